"""What the command line reads: a grasp (a shipped scenario's name or a grasp JSON file) and
wrenches (.npy, .csv, .parquet)."""
import json
import pathlib

import numpy as np

from ..grasping.contact import Contact
from ..grasping.grasp import Grasp

WRENCH_COLUMNS = ("fx", "fy", "fz", "tx", "ty", "tz")


def read_grasp_json(path):
    """A Grasp from {"contacts": [{"position": [x, y, z], "normal": [..], "mu": .., "mu_spin": ..,
    "tangents": [[..], [..]] (optional)}, ...]}, the object's frame; errors name the field."""
    path = pathlib.Path(path)
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise ValueError(f"{path}: not a readable JSON file ({e})") from None
    contacts = data.get("contacts") if isinstance(data, dict) else None
    if not isinstance(contacts, list) or not contacts:
        raise ValueError(f"{path}: contacts: expected a non-empty list of contacts")
    out = []
    for i, c in enumerate(contacts):
        if not isinstance(c, dict):
            raise ValueError(f"{path}: contacts[{i}]: expected an object")
        unknown = set(c) - {"position", "normal", "mu", "mu_spin", "tangents"}
        if unknown:
            raise ValueError(f"{path}: contacts[{i}]: unknown fields {sorted(unknown)}")
        try:
            out.append(Contact(c.get("position"), c.get("normal"), c.get("mu"),
                               c.get("mu_spin", 0.0), c.get("tangents")))
        except (TypeError, ValueError) as e:
            raise ValueError(f"{path}: contacts[{i}]: {e}") from None
    return Grasp(out)


def load_grasp(source):
    """A shipped scenario's grasp (graspforce.robots, needs the robots extra) or a JSON file's."""
    if str(source).endswith(".json"):
        return read_grasp_json(source)
    from .. import robots
    return robots.load_scenario(source).grasp


def read_wrenches(path):
    """(N, 6) float64 from .npy, .csv (six numeric columns, an optional header line) or .parquet
    (the columns fx..tz if present, else the first six)."""
    path = pathlib.Path(path)
    suffix = path.suffix.lower()
    if not path.is_file():
        raise ValueError(f"wrenches: no such file {path}")
    if suffix == ".npy":
        w = np.load(path, allow_pickle=False)
    elif suffix == ".csv":
        with open(path) as f:
            first = f.readline()
        try:
            [float(x) for x in first.split(",")]
            skip = 0
        except ValueError:
            skip = 1
        w = np.loadtxt(path, delimiter=",", skiprows=skip, ndmin=2)
    elif suffix == ".parquet":
        import pyarrow.parquet as pq
        table = pq.read_table(path)
        names = [c for c in WRENCH_COLUMNS if c in table.column_names]
        columns = names if len(names) == 6 else table.column_names[:6]
        w = np.column_stack([table.column(c).to_numpy() for c in columns])
    else:
        raise ValueError(f"wrenches: expected a .npy, .csv or .parquet file, got {path.name}")
    w = np.asarray(w, dtype=np.float64)
    if w.ndim != 2 or w.shape[1] != 6:
        raise ValueError(f"wrenches: {path.name} holds shape {w.shape}, expected (N, 6)")
    return np.ascontiguousarray(w)
