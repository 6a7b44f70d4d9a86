"""The contact wrench sets of eq. (14): the support of a friction cone cut by the unit ball (the
full magnitude of eq. 15) and the analytic supports of W_i, W_L1 and W_Linf, against closed forms
and Clarabel SOCPs written here."""
import math

import clarabel
import numpy as np
import pytest
import scipy.sparse as sp
import truth as T
from grasp_cases import plain, random_grasp

import graspforce as gf

# Clarabel's tolerances here; it then reaches ~1e-10 relative on these tiny SOCPs (measured
# worst 2e-10 against the closed form), so 1e-8 compares its value without flakiness.
SOCP_TOL = 1e-8


def socp_max(c, cones_rows):
    """max c.x s.t. each block (A, b, cone) of rows gives b - A x in its cone (Clarabel)."""
    A = sp.csc_matrix(np.vstack([rows for rows, _, _ in cones_rows]))
    b = np.concatenate([rhs for _, rhs, _ in cones_rows])
    st = clarabel.DefaultSettings()
    st.verbose = False
    st.tol_gap_abs = st.tol_gap_rel = st.tol_feas = 1e-11
    sol = clarabel.DefaultSolver(sp.csc_matrix((len(c), len(c))), -np.asarray(c), A, b,
                                 [cone for _, _, cone in cones_rows], st).solve()
    assert str(sol.status) in ("Solved", "AlmostSolved"), sol.status
    return -sol.obj_val, np.array(sol.x)


def cone_ball_socp(y, mu):
    """max y.g over {g in K, ||g|| <= 1}, K = {||g_2:n|| <= mu g_1}."""
    n = len(y)
    blocks = []
    if mu > 0:
        blocks.append((-np.diag([mu] + [1.0] * (n - 1)), np.zeros(n), clarabel.SecondOrderConeT(n)))
    else:
        blocks.append((-np.eye(n)[:1], np.zeros(1), clarabel.NonnegativeConeT(1)))
        if n > 1:
            blocks.append((np.eye(n)[1:], np.zeros(n - 1), clarabel.ZeroConeT(n - 1)))
    ball = np.vstack((np.zeros((1, n)), -np.eye(n)))
    blocks.append((ball, np.r_[1.0, np.zeros(n)], clarabel.SecondOrderConeT(n + 1)))
    return socp_max(y, blocks)[0]


def directions(rng, n, mu):
    """Random y plus the special cases: inside K, inside the polar cone, on the axis (both
    ways), on K's boundary and on the polar cone's boundary, and zero."""
    axis = np.eye(n)[0]
    ys = list(rng.normal(size=(12, n)))
    if n > 1:
        perp = rng.normal(size=n)
        perp[0] = 0.0
        perp /= np.linalg.norm(perp)
        ys += [axis + 0.5 * mu * perp,                       # inside K
               -axis + (0.5 / mu if mu > 0 else 2.0) * perp,  # inside the polar cone
               axis + mu * perp,                             # on K's boundary
               -mu * axis + perp]                            # on the polar cone's boundary
    ys += [axis, -axis, 3.0 * axis, np.zeros(n)]
    return ys


@pytest.mark.parametrize("n", [2, 3, 4, 5])
@pytest.mark.parametrize("mu", [0.0, 0.2, 1.0, 3.0])
def test_cone_cut_by_ball_support_is_projection_norm(n, mu):
    rng = np.random.default_rng(10 * n + int(10 * mu))
    cut = gf.hull(gf.Polytope(np.zeros((1, n))), gf.ConeCap(mu, n))
    for y in directions(rng, n, mu):
        h, point = cut.support(y)
        exact = T.soc_projection_norm(y, mu)
        scale = max(np.linalg.norm(y), 1e-300)
        # closed forms on both sides: a few ulps of ||y||
        assert abs(h - exact) <= 1e-15 * scale, (y, h, exact)
        # the support point is in K and in the unit ball and attains h (rounding of unit vectors)
        assert np.linalg.norm(point[1:]) <= mu * point[0] + 1e-15
        assert np.linalg.norm(point) <= 1 + 1e-15
        assert abs(point @ y - h) <= 1e-15 * scale
        if np.any(y):
            assert abs(cone_ball_socp(y, mu) - exact) <= SOCP_TOL * scale, (y, mu)


def test_cone_cap_polar_side():
    # the cap alone (no origin): h(y) = ||y|| cos(angle(y, K)) < 0 on the polar side, the same
    # as the boundary ray's inner product computed here
    mu = 0.5
    cap = gf.ConeCap(mu, 3)
    y = np.array([-1.0, 0.2, 0.1])
    q = math.hypot(y[1], y[2])
    edge = np.array([1.0, mu * y[1] / q, mu * y[2] / q]) / math.sqrt(1 + mu * mu)
    assert cap.support(y)[0] == pytest.approx(edge @ y, rel=1e-15)
    assert edge @ y < 0


@pytest.mark.parametrize("seed", range(6))
def test_full_contact_set_is_the_d_scaled_cone(seed):
    # h of {G f : f in F (eq. 12), ||f|| <= 1 (eq. 15)} against an SOCP in f itself (no D scaling)
    rng = np.random.default_rng(seed)
    mu = rng.uniform(0.2, 1.0)
    mu_s = (rng.uniform(0.005, 0.05), 0.0)[seed % 2]
    contact = gf.Contact(rng.normal(0, 0.05, 3), rng.normal(size=3), mu, mu_s)
    W = gf.hull(gf.Polytope(np.zeros((1, 6))), gf.Grasp([contact]).contact_sets("full")[0])
    G = plain(gf.Grasp([contact]))[0][0]
    weight = mu / mu_s if mu_s > 0 else 0.0
    blocks = [(-np.diag([1.0, 1 / mu, 1 / mu, 1 / mu_s if mu_s > 0 else 0.0]), np.zeros(4),
               clarabel.SecondOrderConeT(4)),
              (-np.vstack((np.zeros((1, 4)), np.diag([1.0, 1.0, 1.0, weight]))),
               np.r_[1.0, np.zeros(4)], clarabel.SecondOrderConeT(5))]
    if mu_s == 0:
        blocks.append((np.eye(4)[3:], np.zeros(1), clarabel.ZeroConeT(1)))
    for u in rng.normal(size=(10, 6)):
        h = W.support(u)[0]
        socp, _ = socp_max(G.T @ u, blocks)
        scale = np.linalg.norm(G.T @ u)
        assert abs(h - socp) <= SOCP_TOL * scale, (u, h, socp)
        assert abs(h - T.contact_support(G, mu, mu_s, u, "full")) <= 1e-15 * scale


@pytest.mark.parametrize("seed", range(6))
def test_wrench_set_supports(seed):
    # W_L1 = CH(U W_i), W_Linf = sum CH({0} U W_i) (NOTES.md item 2), W_i from item 3; the
    # L1 sets do not contain 0, so truth's max(0, .) form is compared where it is positive
    rng = np.random.default_rng(20 + seed)
    grasp = random_grasp(rng, 2 + seed % 5)
    P = plain(grasp)
    for norm in ("L1", "Linf"):
        for magnitude in ("normal", "full"):
            W = grasp.wrench_set(norm, magnitude)
            for u in rng.normal(size=(20, 6)):
                h = W.support(u)[0]
                mine = T.grasp_support(P, u, norm, magnitude)
                scale = sum(np.linalg.norm(G.T @ u) for G, _, _ in P)
                if norm == "L1" and mine == 0.0:
                    assert h <= 1e-15 * scale
                else:
                    assert abs(h - mine) <= 1e-14 * scale, (norm, magnitude, u)
