"""The compiled code's memory stays balanced (graspforce._jit).

The numerics borrow their array arguments without reference counts (`borrowing`). A borrowing
function that returned or stored a view would leave its memory with one reference too few: freed
while still in use, then freed again. Numba's allocation statistics catch that: after any number
of calls, every allocation the compiled code made has been freed once, and the answers do not
change from one repetition to the next.
"""
import gc

import numpy as np
import pytest
from numba.core.runtime import _nrt_python, rtsys

import graspforce as gf
from conftest import METHODS, random_rotation


def _balance():
    gc.collect()
    stats = rtsys.get_allocation_stats()
    return stats.alloc - stats.free, stats.mi_alloc - stats.mi_free


def _ingot_like(rng):
    """A 4-finger W_L1 (hull of four 6x3 ellipsoids) and a random wrench's ray."""
    contacts = []
    for _ in range(4):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        contacts.append(gf.Contact(-n, n, 0.5, 0.05))
    return gf.Grasp(contacts)


@pytest.fixture(scope="module", autouse=True)
def _stats():
    # what NUMBA_NRT_STATS=1 switches on at start-up, switched on for this module only
    _nrt_python.memsys_enable_stats()
    yield
    _nrt_python.memsys_disable_stats()


@pytest.mark.parametrize("method", METHODS)
def test_every_allocation_is_freed_once(method):
    rng = np.random.default_rng(7)
    grasp = _ingot_like(rng)
    W = grasp.wrench_set("L1")
    A = gf.TruncatedCone(0.4, 0.7, 1.2)
    B = gf.Ellipsoid(np.zeros(3), np.diag([0.5, 0.8, 1.1]))
    solver = gf.GrowthDistance(A, B, method, warm_start=False)
    pose_a = (np.eye(3), np.zeros(3))
    rays = rng.normal(size=(20, 6))
    poses = [(random_rotation(rng, 3), rng.normal(size=3) * 2.0) for _ in range(20)]

    def run():
        out = []
        for r in rays:
            shot = gf.ray_shoot(W, r, method=method)
            out.append((shot.t, shot.vertices.sum(), shot.weights.sum(), len(shot.witnesses)))
            res = grasp.min_force(-r, method=method)
            out.append((res.sigma, res.forces.sum()))
        for pose_b in poses:
            g = solver(pose_a, pose_b)
            out.append((g.sigma, g.point_a.sum(), g.normal.sum()))
        return out

    first = run()            # compiles what this method needs
    before = _balance()
    for _ in range(3):
        assert run() == first
    assert _balance() == before
