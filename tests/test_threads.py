"""Threads share sets and grasps: the compiled core computes with the GIL released, each call on its
own copy of the set's program, so answers computed by many threads at once on one grasp are those
of the same calls made one by one."""
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import graspforce as gf
from grasps import box_grasp, random_wrenches


def _key(res):
    return (res.status, res.sigma, res.sigma_lower, res.forces.tobytes())


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_threads_on_one_grasp_agree_with_one_by_one(norm):
    grasp = box_grasp()
    wrenches = random_wrenches(400, seed=11)
    for w in wrenches[:2]:
        grasp.min_force(w, norm=norm)          # the set's start table: built before the threads
    alone = [_key(grasp.min_force(w, norm=norm)) for w in wrenches]
    with ThreadPoolExecutor(8) as pool:
        together = list(pool.map(lambda w: _key(grasp.min_force(w, norm=norm)), wrenches))
    assert together == alone


def test_threads_on_one_set_agree_with_one_by_one():
    rng = np.random.default_rng(4)
    A = gf.hull(gf.Ellipsoid(np.zeros(4), rng.normal(size=(4, 3))),
                gf.Polytope(rng.normal(size=(6, 4))))
    rays = rng.normal(size=(300, 4))

    def shots(r):
        s = gf.ray_shoot(A, r)
        c = gf.closest_point(A, 3 * r)
        return (s.t, s.t_upper, s.vertices.tobytes(), c.distance, c.point.tobytes(),
                A.support(r)[0])

    for r in rays[:2]:
        shots(r)
    alone = [shots(r) for r in rays]
    with ThreadPoolExecutor(8) as pool:
        assert list(pool.map(shots, rays)) == alone


@pytest.mark.parametrize("composite", [False, True])
def test_growth_distance_from_threads_on_the_same_shapes(composite):
    """gf.growth_distance keeps recent solvers of composite sets, each of which writes its
    query's poses into its program: threads calling it on the same shape objects at once must not
    share one (two primitives get a solver per call)."""
    rng = np.random.default_rng(8)
    A = (gf.Capsule(0.02, 0.04) if composite
         else gf.Ellipsoid(np.zeros(3), np.diag([0.05, 0.03, 0.02])))
    B = gf.TruncatedCone(0.03, 0.01, 0.08)

    def rotation():
        q, r = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.diag(r))
        return q if np.linalg.det(q) > 0 else -q

    poses = [((rotation(), rng.normal(0, 0.05, 3)), (rotation(), rng.normal(0, 0.05, 3) + 0.2))
             for _ in range(3000)]

    def answer(pair):
        res = gf.growth_distance(A, pair[0], B, pair[1])
        return (res.status, res.sigma, res.sigma_lower, res.sigma_upper)

    alone = [answer(p) for p in poses]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(answer, poses, chunksize=1))
    assert together == alone
