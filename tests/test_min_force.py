"""Grasp.min_force on exact friction cones against closed forms and an SOCP (issue 3)."""
import math

import numpy as np
import pytest
from grasps import (
    G_WEIGHT,
    box_grasp,
    random_grasp,
    random_wrenches,
    sphere_grasp,
    sphere_sigma_l1,
    two_finger_pinch,
)

import graspforce as gf
from graspforce.baselines import clarabel_socp

METHODS = list(gf.METHODS)
OBJECTIVES = [("L1", "normal"), ("Linf", "normal"), ("L1", "full"), ("Linf", "full")]


def objective(grasp, forces, norm, magnitude):
    """sigma of eq. (13) or (15), computed here from the returned forces."""
    values = []
    for c, f in zip(grasp.contacts, forces):
        if magnitude == "normal":
            values.append(f[0])
        else:
            spin = (c.mu / c.mu_spin) ** 2 * f[3] ** 2 if c.mu_spin > 0 else 0.0
            values.append(math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2 + spin))
    return sum(values) if norm == "L1" else max(values)


def check_forces(grasp, w, res):
    """The forces lie in their cones and resist w; sigma is their objective."""
    for c, f in zip(grasp.contacts, res.forces):
        # convex combinations of exact cone points, scaled: in the cone to rounding
        assert c.contains(f, tol=1e-9), (c, f)
    assert np.linalg.norm(res.resultant + w) <= 1e-9 * np.linalg.norm(w)
    assert np.allclose(res.wrenches, [c.matrix @ f for c, f in zip(grasp.contacts, res.forces)],
                       rtol=0, atol=1e-12 * np.abs(res.wrenches).max())
    assert np.allclose(res.world_forces, res.wrenches[:, :3])
    assert res.sigma == pytest.approx(objective(grasp, res.forces, res.norm, res.magnitude),
                                      rel=1e-12)


# --- the paper's sphere (section 5.2, tables 3 and 4) --------------------------------------------
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("mu_spin", [0.0, 0.05])
@pytest.mark.parametrize("lam", [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6])
def test_sphere_closed_form(method, mu_spin, lam):
    grasp = sphere_grasp(lam, mu_spin)
    w = np.array([0, 0, -G_WEIGHT, 0, 0, 0])
    # The contacts' coordinates carry rounding u ~ 1.1e-16, which the minimum amplifies by
    # 1 / (mu cos a - sin a) ~ 1 / (lam atan mu): an error ~5.6e-16 / lam is in the problem itself
    # (5.6e-10 at lam = 1e-6); eps = 1e-9 bounds the solver's part. Measured: <= 1.6e-10.
    tol = 1e-9 + 1e-15 / lam
    for norm, share in (("L1", 1.0), ("Linf", 0.25)):
        res = grasp.min_force(w, norm=norm, method=method)
        assert res.status == "optimal" and res.feasible       # never "infeasible" because of eps
        true = share * sphere_sigma_l1(lam)
        assert abs(res.sigma / true - 1) <= tol
        assert res.sigma_lower <= true * (1 + tol) and res.sigma / res.sigma_lower - 1 <= 1e-9
        check_forces(grasp, w, res)


# --- random grasps against the SOCP ----------------------------------------------------------
CASES = [(seed, m) for seed, m in enumerate([2, 3, 3, 4, 4, 4, 5, 6, 7, 8, 3, 4, 6, 8])]


@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
@pytest.mark.parametrize("seed, m", CASES)
def test_random_grasps_match_socp(seed, m, norm, magnitude):
    rng = np.random.default_rng(100 + seed)
    kinds = ("soft", "point", "frictionless") if seed % 3 else ("soft", "point")
    grasp = random_grasp(rng, m, kinds)
    socp = clarabel_socp.Prepared(grasp, norm, magnitude, tight=True)
    methods = ["zc-ie", METHODS[seed % len(METHODS)]]
    for w in random_wrenches(3, seed, force=5.0, torque=0.2):
        truth = socp.solve(w)
        assert truth.status in ("optimal", "infeasible", "inaccurate")
        for method in methods:
            res = grasp.min_force(w, norm, magnitude, method=method)
            assert res.feasible == truth.feasible, (method, res.status, truth.status)
            if not res.feasible:
                assert res.status == "infeasible" and res.sigma == math.inf
                # the certificate: a hyperplane separating the ray from W, to the core's
                # rounding floor (1e-11 of W's size: an Linf set contains 0, so h_W >= 0)
                shot, W = res.shot, grasp.wrench_set(norm, magnitude)
                size = max(abs(W.support(u)[0]) for u in np.vstack((np.eye(6), -np.eye(6))))
                assert shot.support_value <= 1e-11 * size and shot.normal @ (-w) > 0
                continue
            assert res.status == "optimal"
            # Clarabel at tight tolerances is good to ~1e-9; ours is certified to 1e-9
            assert abs(res.sigma / truth.sigma - 1) <= 1e-6
            assert res.sigma_lower <= truth.sigma * (1 + 1e-8)
            assert truth.sigma <= res.sigma * (1 + 1e-8)
            assert res.sigma / res.sigma_lower - 1 <= 1e-9
            check_forces(grasp, w, res)


def test_random_grasps_include_infeasible_cases():
    # the random cases above must exercise both answers, or they prove little
    feasible = set()
    for seed, m in CASES:
        rng = np.random.default_rng(100 + seed)
        grasp = random_grasp(rng, m, ("soft", "point", "frictionless") if seed % 3
                             else ("soft", "point"))
        for w in random_wrenches(3, seed, force=5.0, torque=0.2):
            feasible.add(grasp.min_force(w).feasible)
    assert feasible == {True, False}


# --- the infinity norm: exact set against the literal eq. (14) --------------------------------
def test_linf_exact_set_against_literal_eq14():
    contacts = [gf.Contact([0.05, 0.0, 0.0], [-1, 0, 0], 0.5, 0.01),
                gf.Contact([-0.05, 0.02, 0.0], [1, 0, 0], 0.5, 0.01),
                gf.Contact([0.0, 0.0, -0.04], [0, 0, 1], 0.8, 0.01)]
    grasp = gf.Grasp(contacts)
    w = np.array([0.5, 0.0, -3.0, 0.0, 0.02, 0.0])
    ours = grasp.min_force(w, norm="Linf")
    truth = clarabel_socp.min_force(grasp, w, "Linf", tight=True)
    assert ours.sigma == pytest.approx(truth.sigma, rel=1e-8)
    literal = gf.ray_shoot(gf.minkowski_sum(*grasp.contact_sets()), -w)
    # CH(W_1 + W_2 + W_3) makes every contact push equally hard: here that costs more (or fails)
    assert (not literal.hit) or 1.0 / literal.t >= ours.sigma * 1.05


def test_linf_literal_eq14_is_exact_on_the_symmetric_sphere():
    grasp = sphere_grasp(0.1)
    w = np.array([0, 0, -G_WEIGHT, 0, 0, 0])
    literal = gf.ray_shoot(gf.minkowski_sum(*grasp.contact_sets()), -w)
    assert 1.0 / literal.t == pytest.approx(grasp.min_force(w, norm="Linf").sigma, rel=1e-9)


# --- the full magnitude: support of the cone cut by the unit ball ------------------------------
def projection_norm(y, mu):
    """||Pi_K(y)|| for K = {||y_2:n|| <= mu y_1}, by the textbook three cases."""
    y1, q = y[0], np.linalg.norm(y[1:])
    if q <= mu * y1:
        return np.linalg.norm(y)
    if mu * q <= -y1:
        return 0.0
    return (y1 + mu * q) / math.sqrt(1.0 + mu * mu)


@pytest.mark.parametrize("n", [2, 3, 4, 5])
@pytest.mark.parametrize("mu", [0.0, 0.3, 1.0, 2.5])
def test_cone_cut_by_ball_support_is_projection_norm(n, mu):
    rng = np.random.default_rng(n * 10 + int(mu * 10))
    cut = gf.hull(gf.Polytope(np.zeros((1, n))), gf.ConeCap(mu, n))
    axis = np.eye(n)[0]
    ys = list(rng.normal(size=(40, n))) + [axis, -axis, 3 * axis, np.zeros(n)]
    for y in ys:
        h, point = cut.support(y)
        assert h == pytest.approx(projection_norm(y, mu), rel=1e-12, abs=1e-15)
        # the point is in K and in the unit ball, and attains h
        assert np.linalg.norm(point[1:]) <= mu * point[0] + 1e-15
        assert np.linalg.norm(point) <= 1 + 1e-15
        assert point @ y == pytest.approx(h, rel=1e-12, abs=1e-15)


def test_full_magnitude_contact_set_is_the_d_scaled_cone():
    # support of {G f : f in F, ||f|| <= 1} (eq. 15) against an SOCP solved by Clarabel
    import clarabel
    import scipy.sparse as sp
    contact = gf.Contact([0.02, -0.03, 0.05], [0.2, -0.3, -1.0], 0.6, 0.02)
    W = gf.hull(gf.Polytope(np.zeros((1, 6))), gf.Grasp([contact]).contact_sets("full")[0])
    G = contact.matrix
    k = contact.mu / contact.mu_spin
    rng = np.random.default_rng(5)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-11
    for u in rng.normal(size=(10, 6)):
        # maximize u^T G f over (f_1, f_2/mu, f_3/mu, f_4/mu_s) in SOC, ||D f|| <= 1
        A = -np.vstack([np.diag([1, 1 / contact.mu, 1 / contact.mu, 1 / contact.mu_spin]),
                        np.zeros((1, 4)), np.diag([1, 1, 1, k])])
        b = np.zeros(9)
        b[4] = 1.0
        cones = [clarabel.SecondOrderConeT(4), clarabel.SecondOrderConeT(5)]
        sol = clarabel.DefaultSolver(sp.csc_matrix((4, 4)), -(G.T @ u), sp.csc_matrix(A), b,
                                     cones, settings).solve()
        assert W.support(u)[0] == pytest.approx(-sol.obj_val, rel=1e-8, abs=1e-10)


# --- degenerate and bad input --------------------------------------------------------------------
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_zero_wrench(norm, magnitude):
    res = box_grasp().min_force(np.zeros(6), norm, magnitude)
    assert res.status == "optimal" and res.feasible and res.sigma == 0.0
    assert not res.forces.any() and res.shot is None


def test_coincident_contacts():
    grasp = box_grasp()
    doubled = gf.Grasp(grasp.contacts + grasp.contacts[:1])
    for w in random_wrenches(5, 7):
        # a second copy of a contact can share its load, never lower the total
        one = grasp.min_force(w)
        two = doubled.min_force(w)
        assert two.sigma == pytest.approx(one.sigma, rel=1e-8)
        check_forces(doubled, w, two)


def test_infeasible_pinch_is_certified():
    grasp = two_finger_pinch()
    w = np.array([0, 0, 0, 1.0, 0, 0])         # a torque about the line through the contacts
    for method in METHODS:
        for norm, magnitude in OBJECTIVES:
            res = grasp.min_force(w, norm, magnitude, method=method)
            assert res.status == "infeasible" and res.sigma == math.inf
            assert not res.forces.any()


def test_bad_input():
    grasp = box_grasp()
    for kwargs, field in [({"norm": "L2"}, "norm"), ({"magnitude": "tangential"}, "magnitude"),
                          ({"method": "simplex"}, "method"), ({"eps": 0.0}, "eps"),
                          ({"max_iter": 0}, "max_iter")]:
        with pytest.raises(ValueError, match=field):
            grasp.min_force(np.ones(6), **kwargs)
    for w in ([1, 2, 3], [0, 0, np.nan, 0, 0, 0], [np.inf] + [0] * 5):
        with pytest.raises(ValueError, match="w_ext"):
            grasp.min_force(w)
    with pytest.raises(TypeError, match="contacts"):
        gf.Grasp([grasp.contacts[0], "finger"])
    with pytest.raises(ValueError, match="contacts"):
        gf.Grasp([])


# --- contacts ----------------------------------------------------------------------------------
def test_contact_matrix_is_eq_11():
    p, n = np.array([0.1, -0.2, 0.3]), np.array([0.0, 0.6, -0.8])
    c = gf.Contact(p, n, 0.5, 0.01)
    o, t = c.tangents
    assert np.allclose(np.cross(o, t), n) and abs(o @ n) < 1e-15 and abs(np.linalg.norm(t) - 1) < 1e-15
    expected = np.zeros((6, 4))
    expected[:3, 0], expected[:3, 1], expected[:3, 2] = n, o, t
    expected[3:, 0], expected[3:, 1], expected[3:, 2] = np.cross(p, n), np.cross(p, o), np.cross(p, t)
    expected[3:, 3] = n
    assert np.allclose(c.matrix, expected, atol=1e-15)


def test_contact_kinds_and_cone_membership():
    soft = gf.Contact([0, 0, 0], [0, 0, 2], 0.5, 0.01)
    assert soft.kind == "soft" and np.allclose(soft.normal, [0, 0, 1])
    assert soft.contains([1.0, 0.3, 0.4, 0.0]) and not soft.contains([1.0, 0.3, 0.41, 0.0])
    assert soft.contains([1.0, 0.0, 0.0, 0.01]) and not soft.contains([1.0, 0.3, 0.0, 0.009])
    point = gf.Contact([0, 0, 0], [0, 0, 1], 0.5)
    assert point.kind == "point" and not point.contains([1.0, 0.0, 0.0, 1e-3])
    smooth = gf.Contact([0, 0, 0], [0, 0, 1], 0.0)
    assert smooth.kind == "frictionless" and not smooth.contains([1.0, 1e-3, 0.0, 0.0])
    assert not soft.contains([-1e-3, 0, 0, 0])


@pytest.mark.parametrize("kwargs, field", [
    ({"position": [0, 0]}, "position"), ({"normal": [0, 0, 0]}, "normal"),
    ({"normal": [0, np.nan, 1]}, "normal"), ({"mu": -0.1}, "mu"), ({"mu_spin": -1.0}, "mu_spin"),
    ({"mu": 0.0, "mu_spin": 0.01}, "mu_spin"),
    ({"tangents": [[1, 0, 0], [1, 0, 0]]}, "tangents"),
])
def test_contact_bad_input(kwargs, field):
    args = {"position": [0, 0, 0], "normal": [0, 0, 1], "mu": 0.5, **kwargs}
    with pytest.raises(ValueError, match=field):
        gf.Contact(**args)
