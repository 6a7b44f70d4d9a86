"""A run's output as numbered chunk files, each written atomically, then one final file.

A chunk is written to a temporary name in the same folder, fsynced and renamed over its final
name (an atomic replace on POSIX), and the folder is fsynced: after a crash a chunk file is
either whole or absent, so `--resume` skips exactly the finished chunks. The folder
`<out>.parts/` also holds the run's manifest (its inputs and settings): a resume with other
inputs is refused rather than mixed. The final file is assembled from the chunks in order the
same way, and only then are the chunks removed; the same chunks give the same bytes, so an
interrupted and resumed run ends with the file an uninterrupted run writes.
"""
import json
import os
import pathlib
import shutil

FORMATS = {".parquet": "parquet", ".csv": "csv"}


def _pyarrow():
    try:
        import pyarrow
        import pyarrow.csv
        import pyarrow.parquet
    except ImportError:
        raise ImportError("graspforce batch writes files with pyarrow: pip install "
                          "'graspforce[batch]'") from None
    return pyarrow


def output_format(path):
    fmt = FORMATS.get(pathlib.Path(path).suffix.lower())
    if fmt is None:
        raise ValueError(f"out: expected a .parquet or .csv file, got {path}")
    return fmt


def fsync_dir(folder):
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def atomic_write(path, write):
    """write(file) into a temporary file beside path, fsync, rename over path."""
    path = pathlib.Path(path)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        with open(tmp, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    fsync_dir(path.parent)


class ChunkStore:
    """The chunks of a run writing `out`; manifest: the run's inputs and settings (JSON)."""

    def __init__(self, out, manifest, resume):
        self.out = pathlib.Path(out)
        self.format = output_format(out)
        self.pa = _pyarrow()
        self.parts = self.out.with_name(self.out.name + ".parts")
        manifest_path = self.parts / "manifest.json"
        if self.parts.exists():
            if not resume:
                raise ValueError(f"out: {self.parts} holds an unfinished run's chunks: pass "
                                 "--resume to continue it, or delete that folder")
            try:
                old = json.loads(manifest_path.read_text())
            except (OSError, json.JSONDecodeError):
                raise ValueError(f"out: {manifest_path} is missing or unreadable: delete "
                                 f"{self.parts} to start again") from None
            changed = sorted(k for k in set(old) | set(manifest) if old.get(k) != manifest.get(k))
            if changed:
                raise ValueError(f"--resume: this run's {', '.join(changed)} differ from the "
                                 f"interrupted run's ({manifest_path})")
        else:
            self.parts.mkdir(parents=True)
            atomic_write(manifest_path,
                         lambda f: f.write(json.dumps(manifest, indent=1, sort_keys=True).encode()))

    def path(self, i):
        return self.parts / f"chunk-{i:06d}.{self.format}"

    def done(self, i):
        return self.path(i).is_file()

    def write(self, i, columns):
        """Chunk i from {name: array}: a Parquet table, or CSV lines without the header."""
        table = self.pa.table(columns)
        if self.format == "parquet":
            atomic_write(self.path(i), lambda f: self.pa.parquet.write_table(table, f))
        else:
            options = self.pa.csv.WriteOptions(include_header=False)
            atomic_write(self.path(i), lambda f: self.pa.csv.write_csv(table, f, options))

    def read(self, i, schema):
        if self.format == "parquet":
            return self.pa.parquet.read_table(self.path(i))
        options = self.pa.csv.ReadOptions(column_names=schema.names)
        convert = self.pa.csv.ConvertOptions(column_types=dict(zip(schema.names, schema.types)))
        return self.pa.csv.read_csv(self.path(i), read_options=options, convert_options=convert)

    def assemble(self, chunks, schema, keep):
        """The final file from chunks 0..chunks-1 in order; returns {name: array} of the
        columns in `keep`, concatenated (for the summary); then removes the chunks."""
        kept = {name: [] for name in keep}

        def write(f):
            if self.format == "parquet":
                with self.pa.parquet.ParquetWriter(f, schema) as writer:
                    for i in range(chunks):
                        table = self.read(i, schema)
                        writer.write_table(table)
                        for name in keep:
                            kept[name].append(table.column(name).to_numpy())
            else:
                f.write((",".join(schema.names) + "\n").encode())
                for i in range(chunks):
                    with open(self.path(i), "rb") as part:
                        shutil.copyfileobj(part, f)
                    table = self.read(i, schema)
                    for name in keep:
                        kept[name].append(table.column(name).to_numpy())

        atomic_write(self.out, write)
        shutil.rmtree(self.parts)
        import numpy as np
        return {name: np.concatenate(parts) if parts else np.empty(0)
                for name, parts in kept.items()}
