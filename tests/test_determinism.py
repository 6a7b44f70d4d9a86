"""Identical calls give identical records, bit for bit (graspforce._core).

The compiled core keeps nothing between calls but what its caller hands it (a set's start table,
a solver's warm start), reads no clock and no random source, and computes in IEEE arithmetic as
written (no fast-math, no fused multiply-adds: CMakeLists.txt). So the same calls on the same
state give the same records to the last bit, however often they are repeated and in whichever
process. A difference would show the core reading memory it never wrote (an entry of a work or
result array left unset, an index past an array's end) or state that an earlier call left
behind: what, for the C++ core, stands where Numba's freed-twice or never-freed memory stood.

Each case makes its sets, grasp or solver once, runs its calls once to build what later calls
reuse (start tables, the warm start), then REPEATS times more: every repetition's records equal
the first one's. Another Python process (its own address space and string hashing) makes the
same objects and runs the same calls: its first run and its repetition equal this process's.
"""
import dataclasses
import os
import pickle
import struct
import subprocess
import sys

import numpy as np
import pytest

import graspforce as gf
from conftest import METHODS, random_rotation

REPEATS = 50
CALLS = 10

RAY_FIELDS = ("hit", "status", "t", "t_upper", "support_value", "iterations", "support_calls",
              "singular_steps", "normal", "weights", "vertices", "witness_rows")
FORCE_FIELDS = ("feasible", "status", "sigma", "sigma_lower", "iterations", "support_calls",
                "forces", "world_forces", "wrenches", "resultant")
GROWTH_FIELDS = ("sigma", "sigma_lower", "sigma_upper", "status", "iterations", "support_calls",
                 "point_a", "point_b", "normal")


def bits(x):
    """x with every number and array as its bytes: records compare bit for bit (-0.0 is not
    0.0, a NaN equals itself)."""
    if isinstance(x, np.ndarray):
        return (x.dtype.str, x.shape, x.tobytes())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return struct.pack("<d", float(x))
    if isinstance(x, (tuple, list)):
        return tuple(bits(v) for v in x)
    if x is None or isinstance(x, str):
        return x
    raise TypeError(f"no bits for {type(x).__name__}")


def record(result, fields):
    """The named fields of a result and, where it has one, of its RayShot, as bits."""
    out = [bits(getattr(result, name)) for name in fields]
    if fields is not RAY_FIELDS and hasattr(result, "shot"):
        shot = result.shot
        out.append(None if shot is None else record(shot, RAY_FIELDS))
    return tuple(out)


def dataclass_record(result):
    return tuple(bits(getattr(result, f.name)) for f in dataclasses.fields(result))


def grasp_of(rng):
    """Two opposing pairs of soft fingers, moved a little at random: W_L1 is a hull of four 6x3
    ellipsoids, as the ingot's, with the origin inside."""
    contacts = []
    for side in np.vstack((np.eye(3)[:2], -np.eye(3)[:2])):
        p = 0.1 * side + 0.01 * rng.normal(size=3)
        contacts.append(gf.Contact(p, -p, 0.5, 0.05))
    return gf.Grasp(contacts)


def body(rng):
    """A set in R^3 with flat, curved and conical faces, the origin outside: rays hit or miss,
    points lie in it or not."""
    return gf.hull(gf.Box([0.3, 0.5, 0.2], center=[0.6, 0.1, 0.0],
                          rotation=random_rotation(rng, 3)),
                   gf.pose(gf.TruncatedCone(0.3, 0.1, 0.5), random_rotation(rng, 3),
                           [0.4, -0.3, 0.2]),
                   gf.Ellipsoid([0.5, 0.4, -0.2], np.diag([0.2, 0.3, 0.1])),
                   gf.Polytope(rng.normal(size=(6, 3)) * 0.2 + [0.7, 0.0, 0.1]))


def ray_shoot_calls(method):
    rng = np.random.default_rng(1)
    sets = (grasp_of(rng).wrench_set("L1"), body(rng))
    rays = [rng.normal(size=(CALLS, A.dim)) for A in sets]
    rays[1][::2] += [2.0, 0.0, 0.0]     # toward the body: hits and misses
    return lambda: tuple(record(gf.ray_shoot(A, r, method=method), RAY_FIELDS)
                         for A, R in zip(sets, rays) for r in R)


def min_force_calls(norm, method):
    rng = np.random.default_rng(2)
    grasp = grasp_of(rng)
    wrenches = rng.normal(size=(CALLS, 6))
    wrenches[0] = 0.0                   # the zero wrench: no shot
    return lambda: tuple(record(grasp.min_force(w, norm=norm, method=method), FORCE_FIELDS)
                         for w in wrenches)


def growth_calls(method, start):
    rng = np.random.default_rng(3)
    solver = gf.GrowthDistance(gf.TruncatedCone(0.4, 0.7, 1.2),
                               gf.Ellipsoid(np.zeros(3), np.diag([0.5, 0.8, 1.1])), method,
                               warm_start=start == "warm")
    pose_a = (np.eye(3), np.zeros(3))
    # a pair moving along a path (the warm start's case), and coincident reference points
    poses = [(random_rotation(rng, 3), np.array([2.0 * np.cos(a), 1.5 * np.sin(a), 0.3]))
             for a in np.linspace(0.0, 1.0, CALLS - 1)] + [(np.eye(3), np.zeros(3))]
    return lambda: tuple(record(solver(pose_a, pose_b), GROWTH_FIELDS) for pose_b in poses)


def distance_calls(distance):
    rng = np.random.default_rng(4)
    A = body(rng)
    points = rng.normal(size=(CALLS, 3)) + [0.5, 0.0, 0.0]
    return lambda: tuple(dataclass_record(distance(A, b)) for b in points)


# (entry point, its arguments): every method of each entry point that takes one
CASES = ([("ray_shoot", method) for method in METHODS]
         + [("min_force", norm, method) for norm in ("L1", "Linf") for method in METHODS]
         + [("growth_distance", method, "cold") for method in METHODS]
         + [("growth_distance", "zc-ie", "warm")]
         + [("closest_point",), ("cone_distance",)])

CALLS_OF = {"ray_shoot": ray_shoot_calls, "min_force": min_force_calls,
            "growth_distance": growth_calls,
            "closest_point": lambda: distance_calls(gf.closest_point),
            "cone_distance": lambda: distance_calls(gf.cone_distance)}


def first_and_repeated(case):
    """(the first run's records, the second's) of a case, on objects made afresh."""
    run = CALLS_OF[case[0]](*case[1:])
    return run(), run()


@pytest.fixture(scope="module")
def other_process():
    """first_and_repeated of every case, computed in another Python process."""
    here = os.path.dirname(os.path.abspath(__file__))
    script = ("import pickle, sys\n"
              f"sys.path.insert(0, {here!r})\n"
              "import test_determinism as T\n"
              "sys.stdout.buffer.write(pickle.dumps({c: T.first_and_repeated(c) "
              "for c in T.CASES}))\n")
    env = dict(os.environ, PYTHONHASHSEED="random")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, env=env,
                          cwd=os.path.dirname(here), timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"the other process failed:\n{done.stderr.decode()}")
    return pickle.loads(done.stdout)


@pytest.mark.parametrize("case", CASES, ids="-".join)
def test_identical_calls_give_identical_records(case, other_process):
    run = CALLS_OF[case[0]](*case[1:])
    first = run()               # builds what the later calls reuse
    repeated = run()
    for i in range(REPEATS - 1):
        assert run() == repeated, f"repetition {i + 2} differs from repetition 1"
    theirs_first, theirs_repeated = other_process[case]
    assert theirs_first == first, "the other process's first run differs"
    assert theirs_repeated == repeated, "the other process's repetition differs"
