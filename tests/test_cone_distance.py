"""gf.cone_distance (ZC, section 2.3) against independent truth:

- polytopes: scipy.optimize.nnls on the generators (distance from b to the cone of the vertices);
- balls: the cone of B(c, rho) (|c| > rho) is circular with half-angle asin(rho/|c|): closed form;
- hulls and sums: Clarabel SOCP (min ||x - b||, x in th A, th >= 0).
"""
import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import build, check_witness, random_ellipsoid, random_polytope

EPS = 1e-12   # the default eps of cone_distance (absolute, units of A: h_A(n) <= eps)
# Distances are compared at 1e-10 relative to max(1, |b|): ZC's stopping rule h_A(n) <= eps
# bounds the error by eps times the size of the cone coefficients (O(1) for this suite's data).
D_TOL = 1e-10


def check_cone_result(A, d, b, res, d_true, v_true, tol=D_TOL, label=""):
    b = np.asarray(b, dtype=float)
    n = b.size
    scale = max(1.0, np.linalg.norm(b))
    ctx = f"[{label}] b={b.tolist()} d_true={d_true!r}"
    V = np.asarray(res.vertices, dtype=float).reshape(-1, n)
    c = np.asarray(res.coefficients, dtype=float).reshape(-1)
    v = np.asarray(res.point, dtype=float)
    nrm = np.asarray(res.normal, dtype=float)
    assert V.shape[0] == c.size <= n, f"{ctx}: {V.shape[0]} vertices, {c.size} coefficients"
    assert len(res.witnesses) == V.shape[0]
    assert np.all(c > 0), f"{ctx}: coefficients {c}"
    if V.shape[0]:
        assert np.linalg.matrix_rank(V) == V.shape[0], f"{ctx}: dependent generators\n{V}"
    assert np.linalg.norm(c @ V - v) <= 1e-10 * max(1.0, np.linalg.norm(v)), \
        f"{ctx}: coefficients @ vertices {c @ V} != point {v}"
    for i, (x, wit) in enumerate(zip(V, res.witnesses)):
        check_witness(A, d, x, wit, what=f"{ctx} generator {i}")
    if d_true == 0.0:
        assert res.status == "inside", f"{ctx}: status {res.status!r}, distance {res.distance!r}"
        assert abs(res.distance) <= 1e-12 * scale, ctx
        assert np.linalg.norm(v - b) <= 1e-10 * scale, f"{ctx}: point {v} != b"
        assert not nrm.any(), f"{ctx}: normal {nrm} should be zeros inside"
        return
    assert res.status == "outside", f"{ctx}: status {res.status!r}"
    dist = float(res.distance)
    assert abs(dist - np.linalg.norm(b - v)) <= 1e-14 * scale, ctx
    assert abs(dist - d_true) <= tol * scale, \
        f"{ctx}: distance {dist!r} vs truth {d_true!r} (diff {dist - d_true:.3e})"
    if v_true is not None:
        # projection inequality for the convex cone: ||v - v*||^2 <= ||v - b||^2 - d*^2
        bound = np.sqrt(max(dist ** 2 - d_true ** 2, 0.0)) + tol * scale
        assert np.linalg.norm(v - v_true) <= bound, \
            f"{ctx}: point {v} vs truth {v_true} " \
            f"(diff {np.linalg.norm(v - v_true):.3e} > {bound:.1e})"
    # the normal: unit, from v to b, and (nearly) separating: h_A(n) <= eps
    assert abs(np.linalg.norm(nrm) - 1.0) <= 1e-12, ctx
    assert np.linalg.norm(nrm - (b - v) / dist) <= 1e-10, f"{ctx}: normal {nrm}"
    h = T.support(d, nrm)
    assert abs(res.support_value - h) <= 1e-12 * max(1.0, abs(h)), ctx
    assert h <= EPS * (1 + 1e-6) + 1e-15 * max(1.0, T.scale_of(d)), \
        f"{ctx}: h_A(normal) = {h:.3e} > eps: ZC stopped early"


@pytest.mark.parametrize("n", range(2, 9))
def test_polytope(n):
    """Polytope off the origin: b outside (NNLS residual > 0) and inside (b a positive
    combination of vertices) its cone."""
    rng = np.random.default_rng(2100 + n)
    g = rng.standard_normal(n)
    g /= np.linalg.norm(g)
    V = random_polytope(rng, n, m=n + 4, shift=5.0 * g)
    d = T.poly(V)
    A = build(d)
    outside = 0
    for _ in range(4):
        b = 3.0 * rng.standard_normal(n)
        d_true, v_true, _ = T.cone_distance_nnls(V, b)
        if d_true <= 1e-6:
            continue
        outside += 1
        check_cone_result(A, d, b, gf.cone_distance(A, b), d_true, v_true, label=f"n={n}")
    assert outside >= 2
    for k in (1, 2, min(n, 3)):
        idx = rng.choice(V.shape[0], size=k, replace=False)
        b = rng.uniform(0.5, 2.0, k) @ V[idx]
        d_true, v_true, _ = T.cone_distance_nnls(V, b)
        assert d_true <= 1e-12 * np.linalg.norm(b)
        check_cone_result(A, d, b, gf.cone_distance(A, b), 0.0, b, label=f"n={n} inside k={k}")


@pytest.mark.parametrize("n", [2, 3, 6])
def test_origin_inside_polytope_cone_is_everything(n):
    rng = np.random.default_rng(2200 + n)
    V = random_polytope(rng, n)
    assert T.contains_lp(V, np.zeros(n))
    d = T.poly(V)
    A = build(d)
    for _ in range(3):
        b = rng.standard_normal(n)
        check_cone_result(A, d, b, gf.cone_distance(A, b), 0.0, b, label="origin inside")


def ball_cone_distance(c, rho, b):
    """Distance from b to the cone of the ball B(c, rho), |c| > rho: a circular cone with axis c
    and half-angle alpha = asin(rho / |c|)."""
    c = np.asarray(c, dtype=float)
    b = np.asarray(b, dtype=float)
    alpha = np.arcsin(rho / np.linalg.norm(c))
    nb = np.linalg.norm(b)
    beta = np.arccos(np.clip(b @ c / (nb * np.linalg.norm(c)), -1.0, 1.0))
    if beta <= alpha:
        return 0.0, b.copy()
    if beta >= alpha + np.pi / 2:
        return nb, np.zeros_like(b)
    ax = c / np.linalg.norm(c)
    perp = b - (b @ ax) * ax
    perp /= np.linalg.norm(perp)
    gen = np.cos(alpha) * ax + np.sin(alpha) * perp           # unit generator toward b
    return nb * np.sin(beta - alpha), nb * np.cos(beta - alpha) * gen


@pytest.mark.parametrize("n", [2, 3, 5])
def test_ball_cone_closed_form(n):
    rng = np.random.default_rng(2300 + n)
    c = 3.0 * np.eye(n)[0]
    rho = 1.2
    d = T.ball(c, rho)
    A = build(d)
    ax = np.eye(n)[0]
    cases = []
    for ang in (0.2, 0.6, 1.0, 1.5):                       # alpha = asin(0.4) = 0.41
        p = rng.standard_normal(n)
        p -= (p @ ax) * ax
        p /= np.linalg.norm(p)
        cases.append(2.0 * (np.cos(ang) * ax + np.sin(ang) * p))
    for b in cases:
        d_true, v_true = ball_cone_distance(c, rho, b)
        # cross-check the closed form with the conic program
        ds, _ = T.cone_distance_socp(d, b)
        assert abs(ds - d_true) <= 1e-8 * max(1.0, np.linalg.norm(b))
        check_cone_result(A, d, b, gf.cone_distance(A, b), d_true, v_true, label=f"ball n={n}")


def cone_hull_cases():
    rng = np.random.default_rng(2400)
    c3, S3 = random_ellipsoid(rng, 3, c_scale=0.0)
    c4, S4 = random_ellipsoid(rng, 4, 2, c_scale=0.0)
    return {
        "hull_ell_poly_3d": T.hull(T.ell(c3 + [4.0, 0, 0], S3),
                                   T.poly(random_polytope(rng, 3, 5) + [4.0, 2.0, 0])),
        "sum_ell_poly_4d": T.msum(T.ell(c4 + [5.0, 0, 0, 0], S4),
                                  T.poly(0.5 * random_polytope(rng, 4, 6))),
        "flat_disks_3d": T.hull(T.ell([2.0, 0, 0], [[0, 0], [1.0, 0], [0, 1.0]]),
                                T.ell([2.0, 2.0, 0], [[0, 0], [0.5, 0], [0, 0.5]])),
    }


CONE_HULLS = cone_hull_cases()


@pytest.mark.parametrize("name", sorted(CONE_HULLS))
def test_hulls_and_sums(name):
    """Conic truth (Clarabel): ~1e-11 absolute on these problems (measured), compared at
    D_TOL = 1e-10 relative to max(1, |b|)."""
    d = CONE_HULLS[name]
    n = T.dim(d)
    A = build(d)
    rng = np.random.default_rng(2500 + sorted(CONE_HULLS).index(name))
    outside = 0
    for _ in range(4):
        b = 3.0 * rng.standard_normal(n)
        d_true, _ = T.cone_distance_socp(d, b)
        if d_true <= 1e-6:
            continue
        outside += 1
        # the SOCP's primal point is only accurate to ~sqrt(tol): only its distance is compared
        check_cone_result(A, d, b, gf.cone_distance(A, b), d_true, None, label=name)
    assert outside >= 2


def test_max_iter_one():
    c = np.array([3.0, 0.5, -0.2, 0.1])
    A = gf.Ellipsoid(c, np.diag([1.0, 0.7, 0.5, 0.9]))
    b = np.array([0.0, 1.0, 1.0, 0.3])
    assert gf.cone_distance(A, b).iterations > 1
    res = gf.cone_distance(A, b, max_iter=1)
    assert res.status == "max_iter"
    assert res.iterations <= 1


def test_bad_input():
    A = gf.Ball(np.array([3.0, 0.0, 0.0]), 1.0)
    for b in ([np.nan, 0.0, 0.0], [1.0, 2.0], [np.inf, 0.0, 0.0]):
        with pytest.raises(ValueError):
            gf.cone_distance(A, np.asarray(b))
