"""gf.ray_shoot against independent truth: LP (polytopes), closed forms (ellipsoids of any rank),
Clarabel SOCP (hulls and sums of ellipsoids, polytopes, boxes, cones, capsules, affine images).

Every check of the contract is in conftest._check_hit / _check_miss: hit/miss agreement, relative
error of t <= 1e-9 at the default eps, the bracket t <= t_true <= t_upper, weights, witnesses, and
the supporting hyperplane, certified with an independent support function.
"""
import functools

import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import (METHODS, T_RTOL, build, random_ellipsoid, random_polytope, random_rotation)

DIMS = range(2, 9)


# ----------------------------------------------------------------------------------------------
# 1. random polytopes, LP truth
# ----------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=None)
def polytope_case(n, where, seed=0):
    """A random polytope in R^n with the origin inside or outside, and rays with their LP truth.
    Returns (V, [(r, hit, t)])."""
    rng = np.random.default_rng(1000 * n + (0 if where == "inside" else 1) + 17 * seed)
    if where == "inside":
        V = random_polytope(rng, n)
        assert T.contains_lp(V, np.zeros(n))
        rays = [rng.standard_normal(n) for _ in range(4)]
        # near a vertex (exactly through one is in test_degenerate.py)
        rays.append(0.7 * V[0] + 0.05 * rng.standard_normal(n))
    else:
        g = rng.standard_normal(n)
        g /= np.linalg.norm(g)
        V = random_polytope(rng, n, shift=6.0 * g)
        assert not T.contains_lp(V, np.zeros(n))
        rays = []
        for _ in range(3):                      # through an interior point: hits
            lam = rng.dirichlet(np.ones(V.shape[0]))
            rays.append((lam @ V) * rng.uniform(0.2, 3.0))
        for _ in range(2):                      # away from the polytope: misses
            rays.append(-g + 0.3 * rng.standard_normal(n))
        # sideways: misses (verified by the LP below)
        perp = rng.standard_normal(n)
        perp -= (perp @ g) * g
        rays.append(g + 2.0 * perp / np.linalg.norm(perp))
    out = []
    for r in rays:
        hit, t, _ = T.ray_shoot_lp(V, r)
        out.append((r, hit, t))
    if where == "outside":
        assert [h for _, h, _ in out] == [True] * 3 + [False] * 3, [h for _, h, _ in out]
    else:
        assert all(h for _, h, _ in out)
    return V, out


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("where", ["inside", "outside"])
@pytest.mark.parametrize("n", DIMS)
@pytest.mark.parametrize("method", METHODS)
def test_random_polytope(method, n, where, seed, check_shot):
    V, rays = polytope_case(n, where, seed)
    d = T.poly(V)
    A = build(d)
    for r, hit, t in rays:
        res = gf.ray_shoot(A, r, method=method)
        check_shot(A, d, r, res, hit, t, method)


@pytest.mark.parametrize("scale", [1e-3, 1e3])
@pytest.mark.parametrize("method", METHODS)
def test_scaled_polytope(method, scale, check_shot):
    """eps is relative: the same accuracy whatever the units."""
    rng = np.random.default_rng(7)
    for n in (3, 5):
        V = random_polytope(rng, n) * scale
        V += 0.2 * scale * rng.standard_normal(n) / np.sqrt(n)
        d = T.poly(V)
        A = build(d)
        for _ in range(3):
            r = rng.standard_normal(n) * (1.0 / scale)
            hit, t, _ = T.ray_shoot_lp(V, r)
            assert hit
            res = gf.ray_shoot(A, r, method=method)
            check_shot(A, d, r, res, hit, t, method)


# ----------------------------------------------------------------------------------------------
# 2. ellipsoids, closed form
# ----------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=None)
def ellipsoid_case(n, where):
    rng = np.random.default_rng(2000 * n + (0 if where == "inside" else 1))
    c, S = random_ellipsoid(rng, n, c_scale=0.1)
    if where == "outside":
        g = rng.standard_normal(n)
        g /= np.linalg.norm(g)
        c = c + 4.0 * g                       # singular values <= 2: origin outside
        rays = [c + S @ (0.9 * x / np.linalg.norm(x)) for x in rng.standard_normal((3, n))]
        rays += [-g + 0.2 * rng.standard_normal(n), rng.standard_normal(n) - 3 * g]
    else:
        rays = [rng.standard_normal(n) for _ in range(4)]
    out = []
    for r in rays:
        hit, t = T.ray_shoot_ellipsoid(c, S, r)
        out.append((r, hit, t))
    if where == "outside":
        assert [h for _, h, _ in out] == [True] * 3 + [False] * 2
    else:
        assert all(h for _, h, _ in out)
    return c, S, out


@pytest.mark.parametrize("where", ["inside", "outside"])
@pytest.mark.parametrize("n", DIMS)
@pytest.mark.parametrize("method", METHODS)
def test_ellipsoid(method, n, where, check_shot):
    c, S, rays = ellipsoid_case(n, where)
    d = T.ell(c, S)
    A = build(d)
    for r, hit, t in rays:
        res = gf.ray_shoot(A, r, method=method)
        check_shot(A, d, r, res, hit, t, method)


@pytest.mark.parametrize("method", METHODS)
def test_ball_and_box(method, check_shot):
    """Ball: t = (r.c + sqrt((r.c)^2 - |r|^2 (|c|^2 - R^2))) / |r|^2; Box: LP on its corners."""
    rng = np.random.default_rng(3)
    for n in (2, 3, 6):
        c = 0.3 * rng.standard_normal(n)
        R = 1.5
        d = T.ball(c, R)
        A = gf.Ball(c, R)
        for _ in range(3):
            r = rng.standard_normal(n)
            rc, rr = r @ c, r @ r
            t = (rc + np.sqrt(rc * rc - rr * (c @ c - R * R))) / rr
            res = gf.ray_shoot(A, r, method=method)
            check_shot(A, d, r, res, True, t, method)
    for n in (3, 4):
        half = rng.uniform(0.5, 2.0, n)
        center = 0.2 * rng.standard_normal(n)
        Q = random_rotation(rng, n)
        d = T.box(half, center, Q)
        A = build(d)
        corners = np.array(np.meshgrid(*[[-1.0, 1.0]] * n)).reshape(n, -1).T * half
        Vc = center + corners @ Q.T
        for _ in range(3):
            r = rng.standard_normal(n)
            hit, t, _ = T.ray_shoot_lp(Vc, r)
            res = gf.ray_shoot(A, r, method=method)
            check_shot(A, d, r, res, hit, t, method)


@functools.lru_cache(maxsize=None)
def flat_ellipsoid_case(n, k):
    """Rank-deficient ellipsoids S (n, k), k < n: rays in the plane (the plane through the origin)
    and rays crossing the plane (the plane off the origin). Closed-form truth (truth.py)."""
    rng = np.random.default_rng(3000 + 10 * n + k)
    _, S = random_ellipsoid(rng, n, k)
    out = []
    # (a) plane through the origin, origin inside the flat set: every in-plane ray hits
    c0 = S @ (0.2 * rng.standard_normal(k) / np.sqrt(k))
    for _ in range(2):
        r = S @ rng.standard_normal(k)
        hit, t = T.ray_shoot_ellipsoid(c0, S, r, in_plane=True)
        assert hit
        out.append((c0, r, hit, t))
    # (b) plane through the origin, origin outside the flat set: toward it hits, away misses
    a = rng.standard_normal(k)
    a *= 2.0 / np.linalg.norm(a)
    c1 = S @ a
    for r, expect in ((S @ (a + 0.1 * rng.standard_normal(k)), True), (-c1, False)):
        hit, t = T.ray_shoot_ellipsoid(c1, S, r, in_plane=True)
        assert hit == expect
        out.append((c1, r, hit, t))
    # (c) plane off the origin: the ray crosses it at one point, inside (hit) or outside (miss)
    U = np.linalg.svd(S)[0]
    off = U[:, k:] @ rng.standard_normal(n - k)
    c2 = off + S @ (0.1 * rng.standard_normal(k))
    for radius, expect in ((0.6, True), (1.6, False)):
        x = rng.standard_normal(k)
        x *= radius / np.linalg.norm(x)
        r = (c2 + S @ x) / 1.7
        hit, t = T.ray_shoot_ellipsoid(c2, S, r, in_plane=False)
        assert hit == expect
        if hit:
            assert abs(t - 1.7) <= 1e-12
        out.append((c2, r, hit, t))
    return S, out


@pytest.mark.parametrize("nk", [(2, 1), (3, 1), (3, 2), (5, 3), (6, 2)],
                         ids=lambda nk: f"{nk[0]}x{nk[1]}")
@pytest.mark.parametrize("method", METHODS)
def test_rank_deficient_ellipsoid(method, nk, check_shot):
    S, cases = flat_ellipsoid_case(*nk)
    for c, r, hit, t in cases:
        d = T.ell(c, S)
        A = build(d)
        res = gf.ray_shoot(A, r, method=method)
        check_shot(A, d, r, res, hit, t, method)


def test_rank_deficient_closed_form_matches_socp():
    """Cross-check of the two independent truths on the flat cases."""
    for nk in [(3, 1), (3, 2), (5, 3), (6, 2)]:
        S, cases = flat_ellipsoid_case(*nk)
        for c, r, hit, t in cases:
            hit2, t2, _ = T.ray_shoot_socp(T.ell(c, S), r)
            assert hit2 == hit
            if hit:
                assert abs(t2 - t) <= 1e-7 * t


# ----------------------------------------------------------------------------------------------
# 3. hulls and sums: SOCP truth (Clarabel)
# ----------------------------------------------------------------------------------------------
def _hull_cases():
    cases = {}
    rng = np.random.default_rng(4000)

    def E(n, k=None, c_scale=0.3, shift=None):
        c, S = random_ellipsoid(rng, n, k, c_scale=c_scale)
        if shift is not None:
            c = c + shift
        return T.ell(c, S)

    def P(n, m=None, shift=None, scale=1.0):
        V = random_polytope(rng, n, m=m) * scale
        if shift is not None:
            V = V + shift
        return T.poly(V)

    e3 = np.eye(3)
    cases["hull_3ell_3d"] = (T.hull(E(3), E(3, shift=2 * e3[0]), E(3, shift=-1.5 * e3[1])), "in")
    cases["hull_ell_poly_4d"] = (T.hull(E(4, shift=[0, 0, 0, 1.0]), P(4, 8), E(4, 2)), "in")
    cases["hull_outside_4d"] = (T.hull(E(4, shift=[5.0, 0, 0, 0]), P(4, 7, shift=[4.0, 1.0, 0, 0])),
                                "out")
    cases["sum_ell_poly_3d"] = (T.msum(E(3), P(3, 6, scale=0.5)), "in")
    cases["sum_ell_poly_5d"] = (T.msum(E(5, c_scale=0.0), P(5, 9, scale=0.5), E(5, 2)), "in")
    cases["sum_outside_3d"] = (T.msum(E(3, shift=[3.0, 0, 0]), P(3, 5, scale=0.5)), "out")
    cases["sum_disk_segment_3d"] = (T.msum(E(3, 2, c_scale=0.0), E(3, 1, c_scale=0.0)), "in")
    cases["nested_3d"] = (T.hull(T.msum(E(3), P(3, 5, scale=0.3)), E(3, shift=[0, 0, 2.0]),
                                 T.box([0.5, 1.0, 0.3], [0.0, 1.0, 0.0],
                                       random_rotation(rng, 3))), "in")
    M = rng.standard_normal((3, 5))
    cases["affine_proj_5to3"] = (T.affine(M, T.hull(E(5), P(5, 8)), t=[0.1, -0.2, 0.05]), "in")
    M2 = rng.standard_normal((4, 2))
    cases["affine_embed_2to4_plus_ball"] = (T.msum(T.affine(M2, E(2)), T.ball(np.zeros(4), 0.5)),
                                            "in")
    cases["neg_hull_3d"] = (T.neg(T.hull(E(3, shift=[1.0, 0, 0]), P(3, 6))), "in")
    cases["tcone"] = (T.tcone(1.0, 0.4, 2.0), "in")
    cases["cylinder"] = (T.tcone(0.7, 0.7, 3.0), "in")
    cases["cone"] = (T.tcone(1.0, 0.0, 1.5), "in")
    cases["capsule"] = (T.capsule(0.5, 2.0), "in")
    R = random_rotation(rng, 3)
    cases["pose_tcone"] = (T.affine(R, T.tcone(0.8, 0.3, 1.2), t=[0.2, 0.1, -0.3]), "in")
    cases["pose_capsule_outside"] = (T.affine(R, T.capsule(0.3, 1.0), t=[2.0, 0.5, 0.0]), "out")
    # a 6-D grasp-like set: four contacts, each a flat ellipse (rank 2) around a wrench g_i
    G = rng.standard_normal((4, 6))
    W = [T.ell(G[i], 0.4 * rng.standard_normal((6, 2))) for i in range(4)]
    zero = T.poly(np.zeros((1, 6)))
    cases["grasp_l1_6d"] = (T.hull(*W, T.ball(np.zeros(6), 0.1)), "in")
    cases["grasp_linf_6d"] = (T.msum(*[T.hull(zero, w) for w in W], T.ball(np.zeros(6), 0.1)), "in")
    # R^12
    cases["hull_3ell_12d"] = (T.hull(E(12), E(12, shift=0.5 * np.ones(12)), E(12, 4)), "in")
    return cases


HULL_CASES = _hull_cases()


@functools.lru_cache(maxsize=None)
def hull_truth(name):
    d, where = HULL_CASES[name]
    n = T.dim(d)
    rng = np.random.default_rng(5000 + sorted(HULL_CASES).index(name))
    rays = [rng.standard_normal(n) for _ in range(3)]
    if where == "out":
        # toward a point of the set (hit), and away from it (miss)
        u = rng.standard_normal(n)
        p = _support_point(d, u)
        q = _support_point(d, -u)
        rays = [0.5 * (p + q), 0.3 * p + 0.7 * q, -(p + q)]
    out = []
    for r in rays:
        hit, t, tu = T.ray_shoot_socp(d, r)
        out.append((r, hit, t, tu))
    if where == "out":
        assert [o[1] for o in out] == [True, True, False], name
    else:
        assert all(o[1] for o in out), name
    return out


def _support_point(d, u):
    """A point of the set maximising u (via the SOCP: max u.x)."""
    P = T._Conic()
    n = T.dim(d)
    x = P.new(n)
    P.member(d, x, ({}, 1.0))
    status, sol, _, _ = P.solve(P.lin([(-float(u[a]), x[a]) for a in range(n)]), tol=1e-10)
    assert status == "Solved"
    return np.array(sol[:n])


@pytest.mark.parametrize("name", sorted(HULL_CASES))
@pytest.mark.parametrize("method", METHODS)
def test_hulls_and_sums(method, name, check_shot):
    d, _ = HULL_CASES[name]
    A = build(d)
    assert A.dim == T.dim(d)
    for r, hit, t, tu in hull_truth(name):
        res = gf.ray_shoot(A, r, method=method)
        # conic truth (see conftest): t <= tu exactly, |t - t_true| <= 1e-9 + truth's own gap
        truth_gap = abs(tu - t) / t if hit else 0.0
        check_shot(A, d, r, res, hit, t, method, exact=False, t_rtol=T_RTOL + truth_gap,
                   t_true_upper=tu if hit else None)


# ----------------------------------------------------------------------------------------------
# 8. R^12
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", METHODS)
def test_polytope_12d(method, check_shot):
    rng = np.random.default_rng(12)
    n = 12
    V = random_polytope(rng, n, m=40)
    d = T.poly(V)
    A = build(d)
    for _ in range(3):
        r = rng.standard_normal(n)
        hit, t, _ = T.ray_shoot_lp(V, r)
        assert hit
        res = gf.ray_shoot(A, r, method=method)
        check_shot(A, d, r, res, hit, t, method)


@pytest.mark.parametrize("method", METHODS)
def test_ellipsoid_12d(method, check_shot):
    rng = np.random.default_rng(112)
    c, S = random_ellipsoid(rng, 12, c_scale=0.1)
    d = T.ell(c, S)
    A = build(d)
    for _ in range(3):
        r = rng.standard_normal(12)
        hit, t = T.ray_shoot_ellipsoid(c, S, r)
        res = gf.ray_shoot(A, r, method=method)
        check_shot(A, d, r, res, hit, t, method)


# ----------------------------------------------------------------------------------------------
# eps and the result fields
# ----------------------------------------------------------------------------------------------
def _eps_problem():
    rng = np.random.default_rng(77)
    n = 4
    c, S = random_ellipsoid(rng, n, c_scale=0.1)
    d = T.hull(T.ell(c, S), T.ell(c + [1.0, 0, 0, 0], 0.5 * S))
    rays = []
    for _ in range(3):
        r = rng.standard_normal(n)
        hit, t, tu = T.ray_shoot_socp(d, r)
        assert hit
        rays.append((r, t, tu))
    # a polytope too: exact LP truth
    V = random_polytope(rng, 5)
    prays = []
    for _ in range(3):
        r = rng.standard_normal(5)
        hit, t, _ = T.ray_shoot_lp(V, r)
        assert hit
        prays.append((r, t))
    return d, rays, V, prays


@pytest.mark.parametrize("eps", [1e-3, 1e-6, 1e-10])
@pytest.mark.parametrize("method", METHODS)
def test_eps_is_relative_bound(method, eps, check_hit):
    """(t_upper - t)/t <= eps, and then |t - t_true|/t_true <= eps (certified), for several eps
    above the documented numerical floor (eps ~ 1e-11)."""
    d, rays, V, prays = _eps_problem()
    A = build(d)
    for r, t, tu in rays:
        res = gf.ray_shoot(A, r, method=method, eps=eps)
        # the comparison with the conic truth is limited by the truth's certified gap (tu - t)/t
        check_hit(A, d, r, res, t, method, eps=eps, t_rtol=eps + abs(tu - t) / t, exact=False,
                  t_true_upper=tu)
    dp = T.poly(V)
    P = build(dp)
    for r, t in prays:
        res = gf.ray_shoot(P, r, method=method, eps=eps)
        check_hit(P, dp, r, res, t, method, eps=eps, t_rtol=eps)


@pytest.mark.parametrize("method", METHODS)
def test_eps_below_floor(method, check_hit):
    """eps = 1e-12 is below the documented floor (docs/core-api.md, "Numerical floor": below
    eps ~ 1e-11 the answer is still bracketed, t <= t_true <= t_upper, but t_upper/t - 1 may be
    a few 1e-12). Checked: status hit, the certified bracket, and t_upper/t - 1 <= 1e-11."""
    d, rays, V, prays = _eps_problem()
    A = build(d)
    for r, t, tu in rays:
        res = gf.ray_shoot(A, r, method=method, eps=1e-12)
        check_hit(A, d, r, res, t, method, eps=1e-11, t_rtol=1e-11 + abs(tu - t) / t,
                  exact=False, t_true_upper=tu, label="eps=1e-12")
    dp = T.poly(V)
    P = build(dp)
    for r, t in prays:
        # polytopes: exact LP truth, so the bracket t <= t_true <= t_upper is checked too
        res = gf.ray_shoot(P, r, method=method, eps=1e-12)
        check_hit(P, dp, r, res, t, method, eps=1e-11, t_rtol=1e-11, label="eps=1e-12")


@pytest.mark.parametrize("method", METHODS)
def test_default_method_and_counters(method):
    rng = np.random.default_rng(5)
    V = random_polytope(rng, 3)
    A = gf.Polytope(V)
    r = rng.standard_normal(3)
    res = gf.ray_shoot(A, r, method=method)
    assert res.support_calls >= 1
    assert 0 <= res.iterations <= 1000
    default = gf.ray_shoot(A, r)
    assert default.method == "zc-ie"
    hit, t, _ = T.ray_shoot_lp(V, r)
    assert abs(default.t - t) <= 1e-9 * t


# ----------------------------------------------------------------------------------------------
# the record: one packed array from compiled code, views taken on first read
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", METHODS)
def test_record_matches_the_compiled_result(method):
    """RayShot's fields are exactly the shooter's own result tuple, read through the packed array
    (graspforce.records._packed) that crosses to Python; the views are consistent with each
    other."""
    from graspforce._core import shoot
    from graspforce.shooting.ray_shoot import METHODS as CODES
    rng = np.random.default_rng(5)
    A = gf.hull(gf.Ellipsoid(*random_ellipsoid(rng, 5, k=3)), gf.Polytope(rng.standard_normal((7, 5))))
    r = rng.standard_normal(5)
    res = gf.ray_shoot(A, r, method=method)
    ints, floats = A.program
    out = shoot(ints, floats, r, A.witness_size, CODES[method], 1e-9, 1000)
    assert (res.t, res.t_upper, res.support_value, res.iterations, res.support_calls,
            res.singular_steps) == (out[1], out[2], out[3], out[4], out[5], out[10])
    np.testing.assert_array_equal(res.normal, out[6])
    np.testing.assert_array_equal(res.vertices, out[7])
    np.testing.assert_array_equal(res.weights, out[8])
    np.testing.assert_array_equal(res.witness_rows, out[9])
    np.testing.assert_array_equal(res.point, res.t * r)
    assert res.error_bound == ((res.t_upper - res.t) * np.linalg.norm(r) if res.hit else np.inf)
    for row, witness in zip(res.vertices, res.witnesses):
        np.testing.assert_allclose(A.witness_point(witness), row, atol=1e-12)


def test_rays_of_any_type_and_layout_agree():
    # the compiled call takes a C-contiguous float64 (n,) array (graspforce._core.shoot_packed,
    # which refuses anything else); every other r is converted on the way: never a misread
    # array or a different answer
    from graspforce._core import capacity
    from graspforce.shooting.ray_shoot import METHODS as CODES, shoot_packed
    A = gf.hull(gf.Ball([0.2, 0.0, 0.1], 1.0), gf.Box([0.5, 1.5, 0.7]))
    r = np.array([0.3, -1.0, 2.0])
    gf.ray_shoot(A, r)
    ref = gf.ray_shoot(A, r)        # the second shot and all that follow use the start table
    hit, t, _ = T.ray_shoot_socp(T.hull(T.ball([0.2, 0.0, 0.1], 1.0), T.box([0.5, 1.5, 0.7])), r)
    assert hit and ref.hit and abs(ref.t - t) <= 1e-8 * t
    frozen = r.copy()
    frozen.flags.writeable = False
    for same in (r.tolist(), tuple(r), frozen, np.repeat(r, 2)[::2], r.reshape(1, 3)[0],
                 np.array([3, -10, 20]) / 10.0,
                 np.asfortranarray(r[None, :])[0]):
        res = gf.ray_shoot(A, same)
        assert res.t == ref.t and np.array_equal(res.point, ref.point)
    assert gf.ray_shoot(A, np.array([0, 0, 1])).t == gf.ray_shoot(A, np.array([0.0, 0, 1])).t
    # the compiled entry point itself takes exactly that kind of array (read-only too: it does
    # not write to r) and gives ray_shoot's answer; any other r raises TypeError, unconverted
    ints, floats = A.program
    ws = A.witness_size
    packed = np.empty(capacity(A.dim, ws))

    def compiled(r):
        return shoot_packed(ints, floats, r, ws, CODES["zc-ie"], 1e-9, 10000, packed,
                            A._start_table)

    for exact in (r, frozen, r.reshape(1, 3)[0]):
        assert compiled(exact)[1] == ref.t
    for other in (r.tolist(), tuple(r), r.astype(np.float32), np.array([3, -10, 20]),
                  np.repeat(r, 2)[::2], r.reshape(1, 3), r.reshape(3, 1)):
        with pytest.raises(TypeError):
            compiled(other)
    for bad in (np.array([1.0, 2.0]), np.zeros((3, 1)), np.array([1.0, np.nan, 0.0]),
                np.zeros(3), np.arange(6.0)[::2][:2]):
        with pytest.raises(ValueError, match="r"):
            gf.ray_shoot(A, bad)
