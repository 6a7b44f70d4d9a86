"""gf.closest_point (GJK, section 2.2) against independent truth:

- polytopes: Clarabel SOCP (min s, ||V^T lam - b|| <= s, lam in the simplex), polished to machine
  precision on the optimal face (exact projection onto the affine hull of the active vertices,
  verified by KKT) — truth.closest_point_polytope;
- full-rank ellipsoids: the trust-region secular equation solved by brentq (exact);
- hulls and sums: Clarabel SOCP (measured accuracy ~1e-12 relative on this suite's problems, so
  compared at 1e-9), plus the exact certificate: the independent support function gives
  d_true >= d - (h(n) - n.v) and the independently evaluated witnesses give d_true <= d.
"""
import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import build, check_witness, random_ellipsoid, random_polytope, random_rotation

EPS = 1e-12   # the default eps of closest_point


def check_outside(A, d, b, res, d_true, v_true, exact=True, label=""):
    b = np.asarray(b, dtype=float)
    n = b.size
    R = max(1.0, T.scale_of(d), np.linalg.norm(b))
    ctx = f"[{label}] b={b.tolist()} d_true={d_true!r}"
    assert res.status == "converged", f"{ctx}: status {res.status!r}"
    dist = float(res.distance)
    v = np.asarray(res.point, dtype=float)
    assert v.shape == (n,)
    assert abs(dist - np.linalg.norm(b - v)) <= 1e-14 * R, ctx
    # v is a point of A: vertices from witnesses, convex weights
    V = np.asarray(res.vertices, dtype=float)
    w = np.asarray(res.weights, dtype=float)
    assert V.ndim == 2 and V.shape[1] == n and 1 <= V.shape[0] <= n, f"{ctx}: vertices {V.shape}"
    assert w.shape == (V.shape[0],)
    assert np.all(w >= -1e-14), f"{ctx}: weights {w}"
    assert abs(w.sum() - 1.0) <= 1e-12, ctx
    assert np.linalg.norm(w @ V - v) <= 1e-10 * max(1.0, np.linalg.norm(v)), ctx
    assert np.linalg.matrix_rank(np.hstack([V, np.ones((V.shape[0], 1))])) == V.shape[0], ctx
    assert len(res.witnesses) == V.shape[0]
    for i, (x, wit) in enumerate(zip(V, res.witnesses)):
        check_witness(A, d, x, wit, what=f"{ctx} vertex {i}")
    # gap, independently: n = (b - v)/d, h_A(n) - n.v bounds the distance error
    nrm = (b - v) / dist
    h = T.support(d, nrm)
    gap = h - nrm @ v
    assert abs(res.gap - gap) <= 1e-12 * max(1.0, abs(h)), f"{ctx}: gap {res.gap!r} vs {gap!r}"
    assert gap <= EPS * max(dist, 1e-3 * R) * (1 + 1e-6) + 1e-15 * R, \
        f"{ctx}: certified gap {gap:.3e} > eps max(d, 1e-3 scale)"
    # against the truth
    tol = EPS * max(d_true, 1e-3 * R) + 1e-14 * R if exact else 1e-9 * d_true
    assert abs(dist - d_true) <= tol, \
        f"{ctx}: distance {dist!r} vs truth {d_true!r} (diff {dist - d_true:.3e} > {tol:.1e})"
    if v_true is not None:
        # projection inequality: ||v - v*||^2 <= ||v - b||^2 - d*^2 for v in A
        bound = np.sqrt(max(dist ** 2 - d_true ** 2, 0.0)) + 1e-12 * R
        assert np.linalg.norm(v - v_true) <= bound, \
            f"{ctx}: point {v} vs truth {v_true} (diff {np.linalg.norm(v - v_true):.3e})"


def check_inside(A, d, b, res, label=""):
    b = np.asarray(b, dtype=float)
    ctx = f"[{label}] b={b.tolist()} (inside)"
    assert res.status == "inside", f"{ctx}: status {res.status!r}, distance {res.distance!r}"
    assert res.distance == 0.0 or abs(res.distance) <= 1e-12 * max(1.0, np.linalg.norm(b)), ctx
    assert np.linalg.norm(np.asarray(res.point) - b) <= 1e-12 * max(1.0, np.linalg.norm(b)), ctx
    V = np.asarray(res.vertices, dtype=float)
    w = np.asarray(res.weights, dtype=float)
    assert 1 <= V.shape[0] <= b.size + 1
    assert np.all(w >= -1e-14) and abs(w.sum() - 1.0) <= 1e-12, ctx
    assert np.linalg.norm(w @ V - b) <= 1e-10 * max(1.0, np.linalg.norm(b)), \
        f"{ctx}: weights @ vertices = {w @ V}"
    for x, wit in zip(V, res.witnesses):
        check_witness(A, d, x, wit, what=ctx)


@pytest.mark.parametrize("n", range(2, 9))
def test_polytope(n):
    rng = np.random.default_rng(1100 + n)
    V = random_polytope(rng, n)
    d = T.poly(V)
    A = build(d)
    checked = 0
    for _ in range(4):
        b = 3.0 * rng.standard_normal(n)
        if T.contains_lp(V, b):
            continue
        d_true, v_true = T.closest_point_polytope(V, b)
        res = gf.closest_point(A, b)
        check_outside(A, d, b, res, d_true, v_true, label=f"polytope n={n}")
        checked += 1
    assert checked >= 2
    for _ in range(2):
        lam = rng.dirichlet(np.ones(V.shape[0]))
        b = lam @ V
        res = gf.closest_point(A, b)
        check_inside(A, d, b, res, label=f"polytope n={n}")


@pytest.mark.parametrize("n", range(2, 9))
def test_ellipsoid(n):
    rng = np.random.default_rng(1200 + n)
    c, S = random_ellipsoid(rng, n)
    d = T.ell(c, S)
    A = build(d)
    for _ in range(3):
        b = c + 4.0 * rng.standard_normal(n)
        d_true, v_true = T.closest_point_ellipsoid(c, S, b)
        assert d_true > 0
        res = gf.closest_point(A, b)
        check_outside(A, d, b, res, d_true, v_true, label=f"ellipsoid n={n}")
    b = c + S @ (0.5 * rng.standard_normal(n) / np.sqrt(n))
    check_inside(A, d, b, gf.closest_point(A, b), label=f"ellipsoid n={n}")


def test_exact_cases():
    """Closed forms: square [0,1]^2 from (2, 0.5) -> (1, 0.5), d = 1 (an edge); from (2, 3) ->
    the vertex (1, 1), d = sqrt(5); unit ball from (3, 4, 0) -> (0.6, 0.8, 0), d = 4; a segment
    (rank-1 ellipsoid) and a flat ellipse (rank 2 in R^3)."""
    sq = T.poly([[0, 0], [1, 0], [0, 1], [1, 1]])
    A = build(sq)
    check_outside(A, sq, [2.0, 0.5], gf.closest_point(A, [2.0, 0.5]), 1.0, np.array([1.0, 0.5]),
                  label="square edge")
    check_outside(A, sq, [2.0, 3.0], gf.closest_point(A, [2.0, 3.0]), np.sqrt(5.0),
                  np.array([1.0, 1.0]), label="square vertex")
    ball = T.ball([0.0, 0.0, 0.0], 1.0)
    A = build(ball)
    check_outside(A, ball, [3.0, 4.0, 0.0], gf.closest_point(A, [3.0, 4.0, 0.0]), 4.0,
                  np.array([0.6, 0.8, 0.0]), label="ball")
    seg = T.ell([0.0, 0.0, 0.0], [0.0, 1.0, 0.0])        # {(0, s, 0) : |s| <= 1}
    A = build(seg)
    b = np.array([0.5, 2.0, 1.0])
    check_outside(A, seg, b, gf.closest_point(A, b), np.sqrt(0.25 + 1.0 + 1.0),
                  np.array([0.0, 1.0, 0.0]), label="segment end")
    b = np.array([0.5, 0.3, 1.0])
    check_outside(A, seg, b, gf.closest_point(A, b), np.sqrt(0.25 + 1.0),
                  np.array([0.0, 0.3, 0.0]), label="segment interior")
    disk = T.ell([0.0, 0.0, 1.0], [[2.0, 0.0], [0.0, 1.0], [0.0, 0.0]])   # flat ellipse at z = 1
    A = build(disk)
    b = np.array([0.5, 0.2, 3.0])
    check_outside(A, disk, b, gf.closest_point(A, b), 2.0, np.array([0.5, 0.2, 1.0]),
                  label="flat ellipse above")


def hull_cases():
    rng = np.random.default_rng(1300)
    c3, S3 = random_ellipsoid(rng, 3)
    c5, S5 = random_ellipsoid(rng, 5)
    c12, S12 = random_ellipsoid(rng, 12)
    return {
        "hull_3d": T.hull(T.ell(c3, S3), T.poly(random_polytope(rng, 3, 6) + 1.0),
                          T.ball([0, 0, 2.0], 0.5)),
        "sum_3d": T.msum(T.ell(c3, S3), T.poly(0.5 * random_polytope(rng, 3, 5))),
        "sum_5d": T.msum(T.ell(c5, S5), T.ell(np.zeros(5), rng.standard_normal((5, 2))),
                         T.poly(0.3 * random_polytope(rng, 5, 8))),
        "tcone_pose": T.affine(random_rotation(rng, 3), T.tcone(1.0, 0.4, 2.0), t=[0.5, 0.0, 0.0]),
        "capsule": T.capsule(0.5, 2.0),
        "hull_12d": T.hull(T.ell(c12, S12), T.ell(c12 + 1.0, 0.5 * S12),
                           T.poly(random_polytope(rng, 12, 30))),
    }


HULLS = hull_cases()


@pytest.mark.parametrize("name", sorted(HULLS))
def test_hulls_and_sums(name):
    d = HULLS[name]
    n = T.dim(d)
    A = build(d)
    rng = np.random.default_rng(1400 + sorted(HULLS).index(name))
    checked = 0
    for _ in range(3):
        b = 4.0 * rng.standard_normal(n)
        d_true, v_true = T.closest_point_socp(d, b)
        if d_true <= 1e-6:
            continue
        checked += 1
        res = gf.closest_point(A, b)
        # conic truth: accurate to ~1e-12 relative here; compared at 1e-9 (the exact
        # certificate inside check_outside pins the distance to eps)
        check_outside(A, d, b, res, d_true, None, exact=False, label=name)
    assert checked >= 2


def test_max_iter_one():
    rng = np.random.default_rng(1500)
    c, S = random_ellipsoid(rng, 6)
    A = gf.Ellipsoid(c, S)
    b = c + 5.0 * rng.standard_normal(6)
    assert gf.closest_point(A, b).iterations > 1
    res = gf.closest_point(A, b, max_iter=1)
    assert res.status == "max_iter"
    assert res.iterations <= 1


def test_bad_input():
    A = gf.Ball(np.zeros(3), 1.0)
    for b in ([np.nan, 0.0, 0.0], [1.0, 2.0], [np.inf, 0.0, 0.0]):
        with pytest.raises(ValueError):
            gf.closest_point(A, np.asarray(b))
    with pytest.raises(ValueError):
        gf.closest_point(A, np.ones(3), eps=0.0)
