"""The `batch` command: a grasp against N wrenches, to a Parquet or CSV file in atomic chunks.

`add_batch_parser(subparsers)` adds it to the `graspforce` command line (graspforce/cli.py);
`run_batch(args)` runs it and returns the exit code.
"""
import hashlib
import json
import pathlib
import sys
import time

import numpy as np

from ..grasping.wrench_space import MAGNITUDES, NORMS
from .distributed import chunk_bounds
from .forces import min_force
from .inputs import WRENCH_COLUMNS, load_grasp, read_wrenches
from .progress import Progress
from .result import STATUSES
from .store import ChunkStore, atomic_write, output_format
from .summary import summarize, text
from .wrenches import ball, gaussian, table5

GENERATED = ("table5", "gaussian", "ball")


def add_batch_parser(subparsers):
    p = subparsers.add_parser(
        "batch", help="minimal contact forces of one grasp against many wrenches, to a file",
        description=__doc__.split("\n")[0])
    p.add_argument("grasp", help="a shipped scenario's name (graspforce.robots) or a grasp "
                                 "JSON file ({\"contacts\": [{position, normal, mu, mu_spin}]})")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--wrenches", help="a file of wrenches, (N, 6): .npy, .csv or .parquet")
    src.add_argument("--generate", choices=GENERATED,
                     help="seeded wrenches: table5 (the paper's protocol: forces N(0, 10 N), "
                          "torques N(0, 0.5 N m)), gaussian (N(0, --scale)), ball (uniform in "
                          "||w / scale|| <= 1)")
    p.add_argument("-n", type=int, default=100_000, help="wrenches to generate (default 1e5)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--scale", type=float, nargs="+", default=[1.0],
                   help="one or six numbers: the std (gaussian) or the ball's axes (ball)")
    p.add_argument("--out", required=True, help="the result file, .parquet or .csv")
    p.add_argument("--norm", choices=NORMS, default="L1")
    p.add_argument("--magnitude", choices=MAGNITUDES, default="normal")
    p.add_argument("--method", default="zc-ie")
    p.add_argument("--eps", type=float, default=1e-9)
    p.add_argument("--max-iter", type=int, default=10000)
    p.add_argument("--forces", action="store_true", help="also write each contact's (f1..f4)")
    p.add_argument("--budget", type=float, help="report the coverage at this force budget")
    p.add_argument("--chunk-size", type=int, default=50_000, help="rows per chunk file")
    p.add_argument("--threads", type=int, help="threads (default: all cores)")
    p.add_argument("--client", help="a Dask scheduler address: chunks go to its workers")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run into the same --out: finished chunks are "
                        "kept, the rest computed")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run_batch)
    return p


def wrenches_of(args):
    """(wrenches (N, 6), a description for the manifest)."""
    if args.wrenches:
        w = read_wrenches(args.wrenches)
        return w, {"file": str(args.wrenches)}
    if args.n is None or args.n < 1:
        raise ValueError(f"-n: must be a positive integer, got {args.n}")
    scale = args.scale[0] if len(args.scale) == 1 else args.scale
    if args.generate == "table5":
        w = table5(args.n, args.seed)
    elif args.generate == "gaussian":
        w = gaussian(args.n, 0.0, scale, args.seed)
    else:
        w = ball(args.n, 1.0, scale, args.seed)
    return w, {"generate": args.generate, "n": args.n, "seed": args.seed, "scale": args.scale}


def columns(rows, result, m):
    """{name: array} of one chunk: the wrench, sigma, its lower bound, status, iterations, and
    with forces each contact's (f1, f2, f3, f4)."""
    out = {name: rows[:, k] for k, name in enumerate(WRENCH_COLUMNS)}
    out |= {"sigma": result.sigma, "sigma_lower": result.sigma_lower,
            "status": np.array(STATUSES)[result.status], "iterations": result.iterations}
    if result.forces is not None:
        for i in range(m):
            for a in range(4):
                out[f"c{i}_f{a + 1}"] = result.forces[:, i, a]
    return out


def schema(pa, m, forces):
    fields = [(name, pa.float64()) for name in WRENCH_COLUMNS]
    fields += [("sigma", pa.float64()), ("sigma_lower", pa.float64()), ("status", pa.string()),
               ("iterations", pa.int32())]
    if forces:
        fields += [(f"c{i}_f{a + 1}", pa.float64()) for i in range(m) for a in range(4)]
    return pa.schema(fields)


def run_batch(args):
    start = time.perf_counter()
    fmt = output_format(args.out)
    out = pathlib.Path(args.out)
    summary_path = out.with_name(out.name + ".summary.json")
    parts = out.with_name(out.name + ".parts")
    grasp = load_grasp(args.grasp)
    wrenches, source = wrenches_of(args)
    if args.chunk_size < 1:
        raise ValueError(f"--chunk-size: must be a positive integer, got {args.chunk_size}")
    manifest = {"grasp": str(args.grasp),
                "grasp_digest": hashlib.sha256(grasp.contact_matrices.tobytes()).hexdigest(),
                "wrenches": source,
                "wrenches_digest": hashlib.sha256(wrenches.tobytes()).hexdigest(),
                "rows": int(wrenches.shape[0]), "chunk_size": args.chunk_size,
                "norm": args.norm, "magnitude": args.magnitude, "method": args.method,
                "eps": args.eps, "max_iter": args.max_iter, "forces": args.forces,
                "format": fmt}
    if args.resume and not parts.exists() and out.exists() and summary_path.exists():
        done = json.loads(summary_path.read_text())
        changed = sorted(k for k in manifest if done.get("manifest", {}).get(k) != manifest[k])
        if changed:
            raise ValueError(f"--resume: {out} is a finished run whose {', '.join(changed)} "
                             "differ from this run's")
        print(f"{out}: already complete", file=sys.stderr)
        print(text(done))
        return 0
    # the settings are checked (by a first row) before any file is written
    min_force(grasp, wrenches[:1], args.norm, args.magnitude, args.method, args.eps,
              args.max_iter, threads=args.threads)
    store = ChunkStore(out, manifest, args.resume)
    bounds = chunk_bounds(wrenches.shape[0], args.chunk_size)
    todo = [i for i in range(len(bounds)) if not store.done(i)]
    finished = wrenches.shape[0] - sum(bounds[i][1] - bounds[i][0] for i in todo)
    progress = Progress(wrenches.shape[0], finished, enabled=not args.quiet)
    m = len(grasp)
    settings = dict(norm=args.norm, magnitude=args.magnitude, method=args.method, eps=args.eps,
                    max_iter=args.max_iter, forces=args.forces)
    if args.client:
        _on_cluster(args.client, grasp, wrenches, bounds, todo, store, progress, settings, m)
    else:
        for i in todo:
            a, b = bounds[i]
            result = min_force(grasp, wrenches[a:b], threads=args.threads, **settings)
            store.write(i, columns(wrenches[a:b], result, m))
            progress.advance(b - a)
    kept = store.assemble(len(bounds), schema(store.pa, m, args.forces), ("sigma", "status"))
    wall = time.perf_counter() - start
    computed = sum(bounds[i][1] - bounds[i][0] for i in todo)
    summary = summarize(kept["sigma"], kept["status"], args.budget, wall_time=wall,
                        computed=computed)
    summary["out"] = str(out)
    summary["manifest"] = manifest
    atomic_write(summary_path, lambda f: f.write(json.dumps(summary, indent=1).encode()))
    print(text(summary))
    return 0


def _on_cluster(address, grasp, wrenches, bounds, todo, store, progress, settings, m):
    """The chunks to do as tasks on a Dask cluster, each written as it arrives."""
    from distributed import Client, as_completed

    from .distributed import _min_force_chunk
    with Client(address) as client:
        g = client.scatter(grasp, broadcast=True, hash=False)
        futures = {client.submit(_min_force_chunk, g, wrenches[bounds[i][0]:bounds[i][1]],
                                 pure=False, **settings): i for i in todo}
        for future in as_completed(futures):
            i = futures[future]
            a, b = bounds[i]
            store.write(i, columns(wrenches[a:b], future.result(), m))
            progress.advance(b - a)
