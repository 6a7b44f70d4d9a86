"""The shooters' step helpers against closed forms and numpy: ZC-based's warm start (which point
leaves V_k), Bi-GJK's exit from a simplex proved to hold a point of the ray, IE's update of its
facet's inverse, ZC-IE compiled for one dimension against the general version, and IE's secant
query."""
import numpy as np
import pytest
from scipy.optimize import nnls

import graspforce as gf
from graspforce._core import HIT, support
from graspforce._core.testing import (WITH_IE, matvec, pivot, restart, simplex_exit, zc_from,
                                      zc_loop)


def on_ray_simplex(rng, n, k, r):
    """k affinely independent points P (k <= n + 1) and convex weights lam > 0 with
    b = lam @ P on the ray R(r): P is shifted so that b = r."""
    P = rng.standard_normal((k, n))
    lam = rng.uniform(0.2, 1.0, k)
    lam /= lam.sum()
    P += r - lam @ P
    return P, lam


@pytest.mark.parametrize("n, k", [(2, 2), (3, 3), (6, 6), (6, 4), (12, 12)])
def test_restart_keeps_r_along_the_face_in_the_others_cone(n, k):
    """After the drop, the part r_L of r along aff(V_k) is a nonnegative combination of the
    kept points' generators P_l - b (nnls residual zero), so that ZC's first residual is r - r_L,
    normal to aff(V_k). Checked independently: r_L by numpy's least squares, the cone by nnls."""
    rng = np.random.default_rng(10 * n + k)
    for _ in range(20):
        r = rng.standard_normal(n)
        P0, lam0 = on_ray_simplex(rng, n, k, r)
        b = lam0 @ P0
        G = (P0[1:] - P0[0]).T            # directions of aff(V_k)
        r_L = G @ np.linalg.lstsq(G, r, rcond=None)[0]
        P = np.vstack([P0, np.zeros((2, n))])
        Wt = np.zeros((k + 2, 3))
        Wt[:k, 0] = np.arange(k)          # the rows' identities, to see which one went
        lam = np.concatenate([lam0, [0.0, 0.0]])
        kept = restart(P, Wt, lam, k, r)
        assert kept == k - 1
        rows = Wt[:kept, 0].astype(int)
        assert len(set(rows)) == kept and set(rows) <= set(range(k))
        assert np.array_equal(P[:kept], P0[rows])
        _, residual = nnls((P0[rows] - b).T, r_L)
        assert residual <= 1e-9 * np.linalg.norm(r)


def test_restart_drops_negligible_weights_first():
    """A point of weight below NEGLIGIBLE leaves b on the face of the others; it goes, and one
    more by the cone rule."""
    n = 3
    rng = np.random.default_rng(5)
    r = rng.standard_normal(n)
    P0, lam0 = on_ray_simplex(rng, n, n, r)
    lam0 = np.array([lam0[0], lam0[1], 1e-12])
    lam0 /= lam0.sum()
    P = np.vstack([P0, np.zeros((2, n))])
    Wt = np.zeros((n + 2, 1))
    Wt[:n, 0] = np.arange(n)
    lam = np.concatenate([lam0, [0.0, 0.0]])
    kept = restart(P, Wt, lam, n, r)
    assert kept == 1
    assert Wt[0, 0] != 2


@pytest.mark.parametrize("n", [2, 3, 6])
def test_simplex_exit_is_where_a_barycentric_weight_reaches_zero(n):
    """The ray leaves CH(P) (n + 1 points) at the largest t with t r in CH(P), computed as an LP
    by hand: barycentric weights of t r solved by numpy for a fine bracket of t, checked at the
    returned exit (all >= 0, one zero) and just past it (one negative)."""
    rng = np.random.default_rng(n)
    for _ in range(20):
        r = rng.standard_normal(n)
        P0, lam0 = on_ray_simplex(rng, n, n + 1, r)
        t0 = 1.0                          # lam0 @ P0 = r
        A = np.vstack([P0.T, np.ones(n + 1)])
        P = P0.copy()
        Wt = np.zeros((n + 1, 1))
        Wt[:, 0] = np.arange(n + 1)
        lam = lam0.copy()
        M, lu = np.empty((n + 1, n + 1)), np.empty((n + 1, n + 1))
        t, k = simplex_exit(P, Wt, lam, n + 1, r, t0, M, lu, np.empty(n + 1, np.int64),
                            np.empty(n + 1), np.empty(n + 2))
        assert t > t0 and k == n
        weights = np.linalg.solve(A, np.append(t * r, 1.0))
        assert weights.min() >= -1e-12 and np.abs(weights).min() <= 1e-12
        beyond = np.linalg.solve(A, np.append((t + 1e-6 * t) * r, 1.0))
        assert beyond.min() < 0.0
        # the kept points and their weights reproduce the exit point
        rows = Wt[:k, 0].astype(int)
        assert np.allclose(lam[:k] @ P[:k], t * r, atol=1e-12 * (1 + np.abs(t * r).max()))
        assert np.isclose(lam[:k].sum(), 1.0) and lam[:k].min() >= 0.0
        assert np.array_equal(P[:k], P0[rows])


@pytest.mark.parametrize("n", [3, 5, 6, 9, 12])
def test_pivot_keeps_the_facet_inverse(n):
    """IE's revised-simplex step: after column js of the facet is replaced by s (alpha = B s),
    B, y = B^T 1 and gam = B r equal numpy's inverse of the new facet matrix and its solves."""
    rng = np.random.default_rng(n)
    P = rng.standard_normal((n, n)) + 3.0 * np.eye(n)     # the facet's points as rows
    r = rng.standard_normal(n)
    B = np.linalg.inv(P.T)
    y = B.T @ np.ones(n)
    gam = B @ r
    for _ in range(8):
        s = rng.standard_normal(n) + 3.0 * np.eye(n)[rng.integers(n)]
        alpha = np.empty(n)
        matvec(B, n, s, alpha)
        np.testing.assert_allclose(alpha, np.linalg.solve(P.T, s), rtol=1e-10, atol=1e-12)
        js = int(np.argmax(np.abs(alpha)))
        pivot(B, n, alpha, js, y, gam)
        P[js] = s
        inverse = np.linalg.inv(P.T)
        np.testing.assert_allclose(B, inverse, rtol=1e-9, atol=1e-11)
        np.testing.assert_allclose(y, inverse.T @ np.ones(n), rtol=1e-9, atol=1e-11)
        np.testing.assert_allclose(gam, inverse @ r, rtol=1e-9, atol=1e-11)


@pytest.mark.parametrize("n", [3, 6, 9])
def test_zc_ie_compiled_for_its_dimension_agrees_with_the_general_version(n):
    """The versions of zc_from's loop compiled for n = 3, 6, 9 shoot as the general one (0: any
    n) does: both certify t* to eps on the same rays (a sum of an ellipsoid and a polytope,
    curved and flat faces, the origin inside), and their brackets overlap."""
    rng = np.random.default_rng(n)
    L = rng.standard_normal((n, n)) + 2.0 * np.eye(n)
    V = rng.standard_normal((3 * n, n))
    A = gf.minkowski_sum(gf.Ellipsoid(np.zeros(n), L @ L.T + np.eye(n)),
                         gf.Polytope(V - V.mean(axis=0)))      # the origin inside
    ints, floats = A.program
    ws = A.witness_size
    eps = 1e-9
    for _ in range(20):
        r = rng.standard_normal(n)
        shots = []
        for compiled_for in (n, 0):
            out = zc_loop(ints, floats, r, ws, eps, 10000, WITH_IE, compiled_for)
            assert out[0] == HIT
            assert out[2] - out[1] <= eps * out[1]
            shots.append((out[1], out[2]))
        (t_a, up_a), (t_b, up_b) = shots
        assert t_a <= up_b * (1.0 + 1e-12) and t_b <= up_a * (1.0 + 1e-12)


def probe_facet(A, r, spread, rng):
    """IE's start as core/shooting/warm.hpp makes it: the support points P of A in n unit directions
    D around r (a tilted guess, so that the facet is not already at z_A(r)), the weights of the
    ray's crossing t r = lam @ P and t; None when the ray misses the facet."""
    ints, floats = A.program
    n = r.shape[0]
    guess = r / np.linalg.norm(r) + 0.2 * rng.standard_normal(n)
    D = guess + spread * np.linalg.qr(rng.standard_normal((n, n)))[0]
    D /= np.linalg.norm(D, axis=1)[:, None]
    P, Wt = np.empty((n + 2, n)), np.empty((n + 2, A.witness_size))
    for j in range(n):
        support(ints, floats, D[j], P[j], Wt[j])
    if np.linalg.cond(P[:n]) > 1e8:
        return None           # two probes found one vertex of a polytope
    gam = np.linalg.solve(P[:n].T, r)
    if gam.min() <= 0.0:
        return None
    lam = np.zeros(n + 2)
    lam[:n] = gam / gam.sum()
    return P, Wt, lam, 1.0 / gam.sum(), D


def secant_and_plain_shots(A, rng, count=10):
    """(r, with the secant query, with facet normals only) for `count` random rays whose probe
    facet holds them: ZC-IE from the same facet, its directions given or not."""
    ints, floats = A.program
    n = A.dim
    none = np.empty((0, 0))
    shots = 0
    while shots < count:
        r = rng.standard_normal(n)
        facet = probe_facet(A, r, 0.5, rng)
        if facet is None:
            continue
        shots += 1
        P, Wt, lam, t, D = facet
        secant, plain = (zc_from(ints, floats, r, A.witness_size, 1e-9, 1000, WITH_IE, t,
                                 P.copy(), Wt.copy(), lam.copy(), n, 0, 0, none, directions)
                         for directions in (D, none))
        yield r, secant, plain


def assert_certified(out, truth, tol):
    """A hit whose bracket [t, t_upper] holds the truth (to tol) and is at most eps wide."""
    assert out[0] == HIT
    assert out[1] <= truth * (1 + tol) and truth <= out[2] * (1 + tol)
    assert out[2] - out[1] <= 1e-9 * out[1]


@pytest.mark.parametrize("n", [3, 5])
def test_secant_query_reaches_a_ball_in_two_steps(n):
    """On a ball of radius rho every support direction is its point's normal, so the secant
    query sum_j lam_j d_j (normalized) is r's direction: its support point is z = rho r / |r|
    exactly, the next facet crosses the ray there, and the query after certifies. IE's facet
    normals from the same facet take many more steps (the gap shrinks ~2-4x a step)."""
    rho = 1.7
    A = gf.Ball(np.zeros(n), rho)
    for r, secant, plain in secant_and_plain_shots(A, np.random.default_rng(n)):
        for out in (secant, plain):
            assert_certified(out, rho / np.linalg.norm(r), 1e-12)
        assert secant[4] <= 2 < 8 <= plain[4]
        assert secant[5] == secant[4]          # no query fell back to the facet normal


@pytest.mark.parametrize("n", [3, 5])
def test_secant_query_on_flat_faces_falls_back_to_facet_normals(n):
    """On a polytope the support map jumps between vertices, so the secant model is wrong: its
    point is a vertex already in the facet (no new ground), and IE's query follows in the same
    step, or a new vertex that keeps little weight (then SECANT_REST plain steps). The answer
    is the LP's, certified, for at most two support calls more than IE's facet normals alone
    (one, measured on these rays)."""
    from scipy.optimize import linprog
    rng = np.random.default_rng(10 + n)
    V = rng.standard_normal((60, n))
    V -= V.mean(axis=0)
    m = V.shape[0]
    for r, secant, plain in secant_and_plain_shots(gf.Polytope(V), rng):
        # t* = max t s.t. t r = V^T mu, mu >= 0, sum mu = 1
        A_eq = np.zeros((n + 1, m + 1))
        A_eq[:n, :m], A_eq[:n, m], A_eq[n, :m] = V.T, -r, 1.0
        lp = linprog(np.r_[np.zeros(m), -1.0], A_eq=A_eq, b_eq=np.r_[np.zeros(n), 1.0],
                     bounds=[(0, None)] * (m + 1))
        for out in (secant, plain):
            assert_certified(out, lp.x[m], 1e-9)
        assert secant[5] <= plain[5] + 2


@pytest.mark.parametrize("n", [3, 5])
def test_probes_that_miss_the_ray_are_recentred_by_the_secant_model(n):
    """On a ball the secant model through probes that miss the ray extrapolates to r's
    direction exactly (P_j = rho d_j, so r = sum_j gam_j P_j is along sum_j gam_j d_j): the
    second round of probes, centred there at the same spread, holds the ray, and the secant
    query then reaches z_A(r) = rho r / |r| in two steps."""
    from graspforce._core import capacity, shoot_warm
    rng = np.random.default_rng(20 + n)
    rho = 1.3
    A = gf.Ball(np.zeros(n), rho)
    ints, floats = A.program
    packed = np.empty(capacity(n, A.witness_size))
    for _ in range(10):
        r = rng.standard_normal(n)
        # a guessed normal 80 degrees off r: probes at spread 0.05 around it miss the ray
        side = rng.standard_normal(n)
        side -= (side @ r) / (r @ r) * r
        guess = np.cos(np.radians(80)) * r / np.linalg.norm(r) + \
            np.sin(np.radians(80)) * side / np.linalg.norm(side)
        out = shoot_warm(ints, floats, r, A.witness_size, 1e-9, 1000, guess, 0.05, packed, 0)
        assert_certified(out, rho / np.linalg.norm(r), 1e-12)
        assert out[4] <= 2 and out[5] == 2 * n + out[4]
