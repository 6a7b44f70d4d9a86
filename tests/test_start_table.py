"""The start table of repeated shots (graspforce.geometry._start_table): its facet is the exit of
the ray from the inner polytope CH(P_0) (LP truth), shots started from it keep the contract, and it
is ignored wherever it would not be sound (changed parameters, flat sets); a set without the origin
keeps the facets that rays crossing CH(P_0) leave through."""
import numpy as np
import pytest
from scipy.spatial import ConvexHull

import graspforce as gf
import graspforce.geometry._start_table as ST
from graspforce._core.testing import table_start
import truth as T
from conftest import build, random_polytope
from benchmarks.grasp_sets import ingot_grasp_sets
from grasps import box_grasp, random_wrenches

# the methods that start from a table's facet
TABLE_METHODS = ("ie", "zc-ie", "zc-ie-newton", "bi-gjk")


def _table_parts(table):
    """(points, witnesses) of a start table."""
    F, n, ws, npar, npts = (int(v) for v in table[:ST.HEADER])
    p0 = ST.HEADER + npar + F * n + F * n * n + F * n
    points = table[p0:p0 + npts * n].reshape(npts, n)
    return points, table[p0 + npts * n:p0 + npts * (n + ws)].reshape(npts, ws)


def _start(A, r):
    """The core's table_start (core/shooting/start_table.hpp) run from Python: (t_0, facet points,
    weights, witness rows), after checking the facet's hyperplane and inverse against the
    points."""
    n = A.dim
    P, Wt, lam = np.empty((n + 2, n)), np.empty((n + 2, A.witness_size)), np.empty(n + 2)
    y, B = np.empty(n), np.empty((n, n))
    t = table_start(A._start_table, A.program[1], np.asarray(r, float), P, Wt, lam, y, B,
                    np.empty(int(A._start_table[0])))
    if t > 0.0:
        # B inverts the matrix whose columns are the facet's points; they lie on y^T x = 1
        assert np.allclose(B @ P[:n].T, np.eye(n), atol=1e-9)
        assert np.allclose(P[:n] @ y, 1.0, atol=1e-9)
    return t, P[:n], lam[:n], Wt[:n]


@pytest.mark.parametrize("n", range(2, 9))
def test_start_is_the_exit_of_the_inner_polytope(n):
    rng = np.random.default_rng(50 + n)
    A = gf.Polytope(random_polytope(rng, n))
    A._start_table = ST.build_start_table(A)
    assert A._start_table.size > 0
    points, witnesses = _table_parts(A._start_table)
    for p, w in zip(points, witnesses):
        # every table point is a support point of A, with its witness (a vertex of V)
        assert np.allclose(A.witness_point(A.decode_witness(w)), p, atol=1e-12)
    for _ in range(20):
        r = rng.standard_normal(n)
        t, P, lam, Wt = _start(A, r)
        hit, t_lp, _ = T.ray_shoot_lp(points, r)
        assert hit
        if t == 0.0:
            continue        # the ray met a ridge of CH(P_0): a cold start, measure zero
        assert abs(t - t_lp) <= 1e-9 * t_lp
        assert lam.min() >= 0.0 and abs(lam.sum() - 1.0) <= 1e-12
        assert np.allclose(lam @ P, t * r, atol=1e-12 * (1 + t * np.linalg.norm(r)))
        for p, w in zip(P, Wt):
            assert np.allclose(A.witness_point(A.decode_witness(w)), p, atol=1e-12)


@pytest.mark.parametrize("n", [7, 9])
def test_table_for_rays_in_a_subspace(n):
    # rays with zeros but in their last k = 6 entries (W_Linf's lift): the table keeps only the
    # facets such rays leave through, and its start is still the exit from CH(P_0) (LP truth) or
    # a cold start; P_0 spans R^n, and a set in R^9 gets a table only for such rays
    k = 6
    rng = np.random.default_rng(90 + n)
    A = gf.Polytope(random_polytope(rng, n))
    assert (ST.build_start_table(A).size > 0) == (n <= ST.MAX_DIM)
    A._start_table = ST.build_start_table(A, k)
    assert A._start_table.size > 0
    points, _ = _table_parts(A._start_table)
    assert int(A._start_table[0]) < len(ConvexHull(points, qhull_options="QJ").simplices)
    warm = 0
    for _ in range(50):
        r = np.concatenate((np.zeros(n - k), rng.standard_normal(k)))
        t, P, lam, _ = _start(A, r)
        hit, t_lp, _ = T.ray_shoot_lp(points, r)
        assert hit
        if t == 0.0:
            continue
        warm += 1
        assert abs(t - t_lp) <= 1e-9 * t_lp
        assert lam.min() >= 0.0 and np.allclose(lam @ P, t * r, atol=1e-12 * (1 + t * np.linalg.norm(r)))
    assert warm >= 45


def test_rays_through_a_split_facet_start_warm():
    # a box's support points in the directions of its corners are its 8 corners: CH(P_0) is the
    # box, each square face split by Qhull into two triangles on one plane; the lookup's best
    # y_f^T r ties between them, and it must take the one holding the ray
    A = gf.Box([1.0, 2.0, 0.5])
    corners = np.array(np.meshgrid(*[[-1.0, 1.0]] * 3)).reshape(3, -1).T
    A._start_table, _ = ST._table(A, [A._support(u) for u in corners], 3)
    points, _ = _table_parts(A._start_table)
    normals = np.round(ConvexHull(points, qhull_options="QJ").equations[:, :3], 6)
    assert len(np.unique(normals, axis=0)) < len(normals)        # some facets are split
    rng = np.random.default_rng(4)
    for _ in range(200):
        r = rng.standard_normal(3)
        t, P, lam, _ = _start(A, r)
        hit, t_lp, _ = T.ray_shoot_lp(points, r)
        assert t > 0.0 and abs(t - t_lp) <= 1e-9 * t_lp
        assert lam.min() >= 0.0 and np.allclose(lam @ P, t * r, atol=1e-12)


def test_points_join_toward_an_origin_outside_the_first_polytope():
    # the ingot's W_Linf holds the origin (a force-closure grasp), but CH(P_0) of one basis
    # does not: P_0 takes support points toward it, not a second basis (590 facets against ~100)
    from benchmarks.grasp_sets import ingot_grasp
    A = ingot_grasp()._space("Linf", "normal").target("zc-ie").set
    assert A.dim == 6
    _, toward = ST._table(A, [A._support(u) for u in ST._directions(6, 6)], 6)
    assert toward is not None
    table = ST.build_start_table(A)
    points, witnesses = _table_parts(table)
    assert 12 < len(points) <= 12 + ST.MAX_ADDED
    for p, w in zip(points, witnesses):
        assert np.allclose(A.witness_point(A.decode_witness(w)), p, atol=1e-12)
    # the origin strictly inside CH(P_0), every facet kept
    hull = ConvexHull(points, qhull_options="QJ")
    assert hull.equations[:, -1].max() < 0.0
    assert int(table[0]) == len(hull.simplices) <= 150


def test_lift_table_serves_the_benchmark_wrenches():
    # W_Linf's lift on the ingot: its table keeps the facets that wrench-like rays leave through
    # (rays drawn spread like P_0, not isotropic: those missed 15% of these wrenches)
    from benchmarks.grasp_sets import ingot_grasp, random_wrenches as ingot_wrenches
    C = ingot_grasp()._space("Linf", "normal").target("ie").set
    C._start_table = ST.build_start_table(C, 6)
    points, _ = _table_parts(C._start_table)
    warm = 0
    wrenches = ingot_wrenches(300, 5)
    for w in wrenches:
        r = np.concatenate((np.zeros(3), -w))
        t, P, lam, _ = _start(C, r)
        if t > 0.0:
            warm += 1
            assert abs(t - T.ray_shoot_lp(points, r)[1]) <= 1e-9 * t
    assert warm >= 0.99 * len(wrenches)


@pytest.mark.parametrize("method", TABLE_METHODS)
@pytest.mark.parametrize("n", range(2, 9))
def test_repeated_shots_use_the_table_and_keep_the_contract(method, n, check_shot):
    rng = np.random.default_rng(70 + n)
    V = random_polytope(rng, n)
    d = T.poly(V)
    A = build(d)
    rays = [rng.standard_normal(n) for _ in range(12)]
    for i, r in enumerate(rays):
        res = gf.ray_shoot(A, r, method=method)
        assert (A._start_table.size > 0) == (i >= 1)
        hit, t, _ = T.ray_shoot_lp(V, r)
        check_shot(A, d, r, res, hit, t, method)


def test_ingot_table_saves_the_search():
    # the ingot grasp's W_L1 (paper section 5.2, benchmarks/grasp_sets.py)
    W, _ = ingot_grasp_sets()
    cold, _ = ingot_grasp_sets()
    cold._start_table = ST.NO_TABLE
    rng = np.random.default_rng(3)
    calls_table, calls_cold = [], []
    for _ in range(200):
        r = rng.standard_normal(6) * np.array([1, 1, 1, 0.05, 0.05, 0.05])
        shot, ref = gf.ray_shoot(W, r), gf.ray_shoot(cold, r)
        assert shot.hit and abs(shot.t - ref.t) <= 2e-9 * ref.t
        calls_table.append(shot.support_calls)
        calls_cold.append(ref.support_calls)
    assert W._start_table.size > 0
    # the table replaces ZC's search for a first facet (~n + 1 support calls), though IE then
    # needs a step or two more on some rays (1000 rays: median saving 5, worse on 20%)
    assert np.median(np.array(calls_cold) - np.array(calls_table)) >= 3


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_min_force_with_table_agrees_with_the_socp(norm):
    from grasp_cases import plain
    # Linf's ZC-IE shoots at the lift in R^9, whose table serves rays in its last 6 coordinates
    grasp = box_grasp()
    for w in random_wrenches(15, 11):
        res = grasp.min_force(w, norm=norm)
        status, truth, _, _ = T.min_force_socp(plain(grasp), w, norm, "normal")
        assert res.status == "optimal" and status == "optimal"
        # the SOCP's value is within ~1e-9 of the minimum (tests/test_grasp_forces.py, SOCP_TOL)
        assert abs(res.sigma - truth) <= 5e-8 * truth
        assert np.allclose(res.resultant, -w, atol=1e-9 * np.abs(w).max())
    assert grasp._space(norm, "normal").target("zc-ie").set._start_table.size > 0


def test_standing_feet_get_a_table_and_keep_their_answers():
    # a humanoid's eight foot corners under its weight (not force-closure: W's inner polytope
    # does not hold the origin): the table keeps the facets its rays leave through, and the
    # answers equal those of shots started cold, within eps, and the SOCP's
    from benchmarks.families import FAMILIES
    from grasp_cases import plain
    grasp, loads = FAMILIES["feet"](np.random.default_rng(4), 16)
    assert not grasp.is_force_closure()
    cold = gf.Grasp(grasp.contacts)
    saved = []
    for w in loads:
        res = grasp.min_force(w)
        cold.reset_start_tables()
        ref = cold.min_force(w)
        saved.append(ref.support_calls - res.support_calls)
        status, truth, _, _ = T.min_force_socp(plain(grasp), w, "L1", "normal")
        assert res.status == ref.status == status == "optimal"
        assert abs(res.sigma - ref.sigma) <= 2e-9 * ref.sigma
        assert abs(res.sigma - truth) <= 5e-8 * truth
        assert np.allclose(res.resultant, -w, atol=1e-9 * np.abs(w).max())
    assert grasp._space("L1", "normal").target("zc-ie").set._start_table.size > 0
    # the loads whose rays cross CH(P_0) skip ZC's search for a first facet; the others start
    # cold, as before
    assert sum(s > 0 for s in saved) >= 5


def test_table_ignored_once_the_parameters_change(check_shot):
    rng = np.random.default_rng(5)
    n = 4
    V = random_polytope(rng, n)
    A = gf.Polytope(V)
    r = rng.standard_normal(n)
    gf.ray_shoot(A, r)
    gf.ray_shoot(A, r)
    assert A._start_table.size > 0
    # shrink the polytope in place, as the growth query (core/growth/growth.hpp) rewrites a pose:
    # the table's points now lie outside A, and a start from them would overshoot z_A(r)
    ints, floats = A.program
    start = gf.geometry._kernel.param_start(ints, 0)
    floats[start + 2:start + 2 + V.size] *= 0.5
    t0, _, _, _ = _start(A, r)
    assert t0 == 0.0
    res = gf.ray_shoot(A, r)
    hit, t, _ = T.ray_shoot_lp(0.5 * V, r)
    check_shot(gf.Polytope(0.5 * V), T.poly(0.5 * V), r, res, hit, t, "zc-ie")


@pytest.mark.parametrize("n", [3, 6])
def test_origin_outside_keeps_the_facets_rays_leave_through(n, check_shot):
    # the origin outside A (a grasp that is not force-closure): the table keeps the facets of
    # CH(P_0) whose hyperplane y^T x = 1 supports it with the origin on its inner side; a ray that
    # crosses CH(P_0) starts at its exit (LP truth), any other cold, and every shot keeps the
    # contract
    rng = np.random.default_rng(60 + n)
    V = random_polytope(rng, n, shift=np.full(n, 4.0))
    A, d = gf.Polytope(V), T.poly(V)
    A._start_table = table = ST.build_start_table(A)
    assert table.size > 0
    points, _ = _table_parts(table)
    F, npar = int(table[0]), int(table[3])
    normals = table[ST.HEADER + npar:ST.HEADER + npar + F * n].reshape(n, F).T
    assert (points @ normals.T).max() <= 1.0 + ST.CONVEX_TOL
    warm = cold = 0
    for i in range(40):
        # toward a point of CH(P_0) (a ray that crosses it), or anywhere
        r = rng.dirichlet(np.ones(len(points))) @ points if i % 2 else rng.standard_normal(n)
        t, P, lam, Wt = _start(A, r)
        crosses, t_exit, _ = T.ray_shoot_lp(points, r)
        if t > 0.0:
            warm += 1
            assert crosses and abs(t - t_exit) <= 1e-9 * t_exit
            assert lam.min() >= 0.0 and np.allclose(lam @ P, t * r, atol=1e-12 * t * np.abs(r).max())
        else:
            cold += 1
        res = gf.ray_shoot(A, r)
        hit, t_true, _ = T.ray_shoot_lp(V, r)
        check_shot(A, d, r, res, hit, t_true, "zc-ie")
    assert warm >= 15 and cold >= 15


def test_no_table_where_it_would_not_be_sound():
    # a flat set: a disk in R^3
    disk = gf.Ellipsoid(np.zeros(3), np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]))
    assert ST.build_start_table(disk) is ST.NO_TABLE
    # dimensions above MAX_DIM
    assert ST.build_start_table(gf.Ball(np.zeros(ST.MAX_DIM + 1), 1.0)) is ST.NO_TABLE


@pytest.mark.parametrize("n", [3, 6])
def test_origin_at_a_vertex(n, check_shot):
    # the facets through the origin are singular and left out of the table; rays into A start
    # from the others or cold, rays out of A miss (t* = 0)
    rng = np.random.default_rng(20 + n)
    V = random_polytope(rng, n)
    V = V - V[0]
    d = T.poly(V)
    A = build(d)
    for _ in range(15):
        r = rng.standard_normal(n)
        hit, t, _ = T.ray_shoot_lp(V, r)
        res = gf.ray_shoot(A, r)
        if hit and t > 1e-12:
            check_shot(A, d, r, res, hit, t, "zc-ie")
        else:
            assert res.t <= 1e-9


def test_first_shot_builds_nothing():
    A = gf.Ball(np.zeros(3), 1.0)
    assert A._start_table is ST.UNSEEN
    gf.ray_shoot(A, [1.0, 0.0, 0.0])
    assert A._start_table is ST.SEEN_ONCE
    gf.ray_shoot(A, [0.0, 1.0, 0.0])
    assert A._start_table.size > 0


def test_sets_and_grasps_pickle_after_use():
    # what a shot leaves on a set or grasp (compiled entry points, start tables) is rebuilt on
    # demand after unpickling: dask ships sets and grasps to its workers
    import pickle
    A = gf.hull(gf.Ball(np.zeros(3), 1.0), gf.Box([0.5, 1.5, 0.7]))
    r = np.array([0.3, -1.0, 2.0])
    for _ in range(3):
        ref = gf.ray_shoot(A, r)
    B = pickle.loads(pickle.dumps(A))
    assert B._start_table is ST.UNSEEN
    for _ in range(3):
        res = gf.ray_shoot(B, r)
    assert abs(res.t - ref.t) <= 1e-9 * ref.t and B._start_table.size > 0
    grasp = box_grasp()
    w = random_wrenches(1, 4)[0]
    for _ in range(3):
        ref = grasp.min_force(w)
    copy = pickle.loads(pickle.dumps(grasp))
    assert abs(copy.min_force(w).sigma - ref.sigma) <= 1e-9 * ref.sigma
    assert grasp.min_force(w).sigma == ref.sigma
