"""Grasp.min_force against independent truth: the closed form of the paper's sphere
(NOTES.md item 1), a Clarabel SOCP written in truth.py, and certificates evaluated with the
closed-form support functions of truth.py (never graspforce's own)."""
import math

import numpy as np
import pytest
import truth as T
from grasp_cases import plain, random_grasp, random_wrench
from grasps import G_WEIGHT, MU, sphere_grasp

import graspforce as gf

METHODS = list(gf.METHODS)
OTHERS = [m for m in METHODS if m != "zc-ie"]
OBJECTIVES = [("L1", "normal"), ("Linf", "normal"), ("L1", "full"), ("Linf", "full")]
U = 2.0 ** -53                                  # unit roundoff
EPS = 1e-9                                      # min_force's default eps

# Every returned force is a nonnegative combination of at most 7 support points, each on its
# cone's boundary to a few ulps: 1e-14 relative to f_1 is ~50 ulps (measured <= 4.5e-16).
CONE_TOL = 1e-14
# The resultant cancels wrenches of size sum_i ||G_i f_i|| down to -w_ext, with forces read off
# barycentric weights of at most 7 vertices solved in double precision: its residual is rounding
# of that size times the small system's conditioning (<= 1e3 here). Measured <= 1.5e-13.
RESIDUAL_TOL = 1e-12
# Clarabel's value is off the true minimum by up to ~1e-9 at tol 1e-11, and its fallbacks on
# nearly infeasible grasps (truth.min_force_socp) go down to tol 1e-8: measured worst 8.5e-9
# outside [sigma_lower, sigma] on 300 random grasps. 5e-8 is that fallback accuracy with margin.
SOCP_TOL = 5e-8


def check_forces(grasp, w, res, residual_vs_w=True, residual_tol=RESIDUAL_TOL):
    """Forces in their cones, in equilibrium with w to residual_tol (relative to the sum of
    their wrenches' norms), and sigma their objective."""
    P = plain(grasp)
    for c, f in zip(grasp.contacts, res.forces):
        assert T.cone_excess(c, f) <= CONE_TOL, (c, f)
        assert c.contains(f, tol=CONE_TOL), (c, f)
    wrenches = np.array([G @ f for (G, _, _), f in zip(P, res.forces)])
    scale = np.linalg.norm(wrenches, axis=1).sum()
    mine = wrenches.sum(axis=0)
    assert np.linalg.norm(mine + w) <= residual_tol * scale
    # the library's own resultant and wrenches are the same sums (rounding of 4-term dots)
    assert np.linalg.norm(res.resultant - mine) <= 1e-14 * scale
    assert np.abs(res.wrenches - wrenches).max() <= 1e-14 * scale
    assert np.array_equal(res.world_forces, res.wrenches[:, :3])
    if residual_vs_w:
        # the requirement, meaningful where the forces are of the size of w
        assert np.linalg.norm(res.resultant + w) <= 1e-9 * np.linalg.norm(w)
    # sigma is the objective of these forces: a sum or max of <= 8 terms
    assert res.sigma == pytest.approx(T.contact_objective(res.forces, P, res.norm, res.magnitude),
                                      rel=1e-14)


def wrench_normal(res):
    """The normal of W in R^6 that min_force's shot holds: its normal's wrench part (for Linf the
    shot is on W_Linf's lift), after P^T when the shot is on the image P A of a rank-deficient
    grasp's set in its span (MinForce.shot)."""
    shot = res.shot
    n = np.asarray(shot.normal)
    if isinstance(shot.convex_set, gf.geometry.sets.Affine):
        n = shot.convex_set.matrix.T @ n
    return n[-6:]


def certified_gap(grasp, w, res):
    """(sigma - n.r / h_W(n)) / sigma with the library's normal n and truth's support: an upper
    bound of sigma's relative error that does not trust graspforce's support functions
    (`wrench_normal`)."""
    n = wrench_normal(res)
    r = -np.asarray(w, dtype=float)
    assert n @ r > 0
    lower = (n @ r) / T.grasp_support(plain(grasp), n, res.norm, res.magnitude)
    return (res.sigma - lower) / res.sigma


# --- the paper's sphere (section 5.2, tables 3 and 4) --------------------------------------------
LAMBDAS = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
sphere = sphere_grasp


def sphere_truth(lam, norm, magnitude):
    """NOTES.md item 1: G / (mu cos a - sin a) (L1) and a quarter of it (Linf), with
    mu cos a - sin a = sqrt(1 + mu^2) sin(lam atan mu) (no cancellation). For the full magnitude
    each contact pushes along its cone's upper edge, whose unit vector lifts by
    (mu cos a - sin a) / sqrt(1 + mu^2): ||f|| = sqrt(1 + mu^2) f_1 (symmetry and convexity make
    the equal-share solution optimal; spin moments only cost)."""
    d = math.sqrt(1.0 + MU * MU) * math.sin(lam * math.atan(MU))
    value = G_WEIGHT / d * (0.25 if norm == "Linf" else 1.0)
    return value * (math.sqrt(1.0 + MU * MU) if magnitude == "full" else 1.0), d


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("mu_spin", [0.0, 0.05])
@pytest.mark.parametrize("lam", LAMBDAS)
def test_sphere_closed_form(lam, mu_spin, method):
    grasp = sphere(lam, mu_spin)
    w = np.array([0.0, 0.0, -G_WEIGHT, 0.0, 0.0, 0.0])
    for norm, magnitude in OBJECTIVES:
        true, d = sphere_truth(lam, norm, magnitude)
        # The contacts' coordinates (sin, cos, the normalization) are rounded to ~u each, which
        # moves the denominator d = mu cos a - sin a by up to ~2u: the problem itself is
        # uncertain to 2u/d relative (1.1e-9 at lam = 1e-6), on top of eps.
        # Measured: <= 0.3 u/d (1.6e-10 at lam = 1e-6).
        tol = EPS + 2 * U / d
        res = grasp.min_force(w, norm, magnitude, method=method)
        assert res.status == "optimal" and res.feasible        # never "infeasible" by eps
        assert abs(res.sigma / true - 1) <= tol, (norm, magnitude, res.sigma, true)
        assert res.sigma_lower <= true * (1 + tol)
        assert res.sigma / res.sigma_lower - 1 <= EPS + 1e-15
        # forces are ~1/d times w here: the residual is judged against the forces' size
        check_forces(grasp, w, res, residual_vs_w=False)


@pytest.mark.parametrize("method", METHODS)
def test_sphere_at_the_papers_eps(method):
    # the paper's termination tolerance 1e-5 reported "infeasible" at lambda <= 1e-5
    w = np.array([0.0, 0.0, -G_WEIGHT, 0.0, 0.0, 0.0])
    for lam in LAMBDAS:
        grasp = sphere(lam, 0.0)
        for norm in ("L1", "Linf"):
            true, d = sphere_truth(lam, norm, "normal")
            res = grasp.min_force(w, norm, method=method, eps=1e-5)
            assert res.status == "optimal"
            assert abs(res.sigma / true - 1) <= 1e-5 + 2 * U / d


# --- random grasps against the SOCP
# ----------------------------------------------------------------
CASES = list(range(28))


def case(seed):
    rng = np.random.default_rng(1000 + seed)
    m = 2 + seed % 7
    kinds = ("soft", "point", "frictionless") if seed % 3 else ("soft", "point")
    return rng, random_grasp(rng, m, kinds)


@pytest.mark.parametrize("seed", CASES)
def test_random_grasps_against_socp(seed):
    rng, grasp = case(seed)
    P = plain(grasp)
    methods = ("zc-ie", OTHERS[seed % len(OTHERS)])
    for _ in range(2):
        w = random_wrench(rng)
        for norm, magnitude in OBJECTIVES:
            status, socp, _, u = T.min_force_socp(P, w, norm, magnitude)
            for method in methods:
                res = grasp.min_force(w, norm, magnitude, method=method)
                ctx = (seed, norm, magnitude, method, res.status, status)
                assert res.feasible == (status == "optimal"), ctx
                if not res.feasible:
                    check_infeasible(grasp, w, res)
                    continue
                assert res.status == "optimal", ctx
                assert abs(res.sigma / socp - 1) <= 1e-6, ctx         # the bound
                assert res.sigma_lower <= socp * (1 + SOCP_TOL), ctx
                assert socp <= res.sigma * (1 + SOCP_TOL), ctx
                assert res.sigma / res.sigma_lower - 1 <= EPS + 1e-15, ctx
                check_forces(grasp, w, res)
                # independent certificates: the forces are feasible (checked above), so the
                # true minimum is <= sigma; with the SOCP's dual direction and truth's support,
                # it is >= u.r / h_W(u): sigma may not lie below that; and the library's own
                # supporting normal, re-evaluated with truth's support, brackets sigma to eps
                # (the support values' rounding adds ~1e-16)
                # (weak duality holds exactly for the wrench these forces resist, which differs
                # from w by the residual allowed above; hence r = their resultant)
                r_actual = sum(G @ f for (G, _, _), f in zip(P, res.forces))
                if u @ r_actual > 0:
                    dual_lower = (u @ r_actual) / T.grasp_support(P, u, norm, magnitude)
                    assert dual_lower <= res.sigma * (1 + 1e-13), ctx
                assert certified_gap(grasp, w, res) <= EPS * (1 + 1e-6) + 1e-13, ctx


def check_infeasible(grasp, w, res):
    assert res.status == "infeasible" and res.sigma == math.inf and res.sigma_lower == math.inf
    assert not res.forces.any() and not res.resultant.any()
    m = len(grasp.contacts)
    assert (res.forces.shape, res.world_forces.shape, res.wrenches.shape, res.resultant.shape) \
        == ((m, 4), (m, 3), (m, 6), (6,))
    # the certificate: a direction n with n.r > 0 in which W does not extend (to rounding of
    # W's size: 1e-11 is ~100 ulps of sums of up to 8 support values)
    n = wrench_normal(res)
    P = plain(grasp)
    size = max(T.grasp_support(P, e, res.norm, res.magnitude)
               for e in np.vstack((np.eye(6), -np.eye(6))))
    assert n @ (-w) > 0
    assert T.grasp_support(P, n, res.norm, res.magnitude) <= 1e-11 * size * np.linalg.norm(n)


def test_random_cases_exercise_both_verdicts():
    verdicts = []
    for seed in CASES:
        rng, grasp = case(seed)
        for _ in range(2):
            w = random_wrench(rng)
            verdicts.append(T.min_force_socp(plain(grasp), w, "L1", "normal")[0])
    assert 0.2 <= verdicts.count("infeasible") / len(verdicts) <= 0.8


def two_point_pinch(mu_spin=0.0):
    return gf.Grasp([gf.Contact([0.04, 0.01, 0.02], [-1, 0, 0], 0.5, mu_spin),
                     gf.Contact([-0.04, 0.01, 0.02], [1, 0, 0], 0.5, mu_spin)])


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_pinch_cannot_resist_torque_about_its_axis(norm, magnitude, method):
    # point contacts on the line y = 0.01, z = 0.02 transmit no torque about it
    w = np.array([0.0, 0.3, 0.0, 0.02, 0.0, 0.0])
    w[4:] = np.cross([0.0, 0.01, 0.02], [0.02, 0.0, 0.0])[1:]     # torque about that line
    w[:3] = 0.0
    w[3] = 0.02
    grasp = two_point_pinch()
    assert T.min_force_socp(plain(grasp), w, norm, magnitude)[0] == "infeasible"
    check_infeasible(grasp, w, grasp.min_force(w, norm, magnitude, method=method))
    # soft fingers resist it by spin moments: mu_s f_1 each, so L1 sigma = |tau| / mu_s
    soft = two_point_pinch(0.02)
    res = soft.min_force(w, norm, magnitude, method=method)
    status, socp, _, _ = T.min_force_socp(plain(soft), w, norm, magnitude)
    assert status == "optimal" and res.status == "optimal"
    assert abs(res.sigma / socp - 1) <= 1e-6
    check_forces(soft, w, res)


# --- Linf: the exact set against the literal CH(W_1 + ... + W_m) of eq. (14)
# ------------------------
def asymmetric_grasp():
    # a box held by three soft fingers at different heights and a point contact below
    return gf.Grasp([gf.Contact([0.05, 0.01, 0.02], [-1, 0, 0], 0.6, 0.01),
                     gf.Contact([-0.05, -0.02, -0.01], [1, 0, 0], 0.4, 0.02),
                     gf.Contact([0.0, 0.03, 0.03], [0, -1, 0], 0.8, 0.01),
                     gf.Contact([0.01, 0.0, -0.04], [0, 0, 1], 0.3)])


def opposing_grasp():
    # two opposing pairs, different frictions and offsets
    return gf.Grasp([gf.Contact([0.05, 0.01, 0.02], [-1, 0, 0], 0.6, 0.01),
                     gf.Contact([-0.05, -0.02, -0.01], [1, 0, 0], 0.4, 0.02),
                     gf.Contact([0.01, 0.04, 0.0], [0, -1, 0], 0.8),
                     gf.Contact([-0.02, -0.04, 0.01], [0, 1, 0], 0.3, 0.01)])


@pytest.mark.parametrize("method", METHODS)
def test_linf_exact_set_against_literal_eq14(method):
    # opposing pairs: equal normal forces are possible, but cost 60 % more than the minimum
    grasp = opposing_grasp()
    P = plain(grasp)
    w = np.array([-7.0, -0.65, -3.75, -0.037, -0.027, -0.016])
    _, socp, socp_forces, _ = T.min_force_socp(P, w, "Linf", "normal")
    status, literal, _, _ = T.min_force_socp(P, w, "Linf", "normal", equal=True)
    ours = grasp.min_force(w, norm="Linf", method=method)
    assert abs(ours.sigma / socp - 1) <= 1e-6
    check_forces(grasp, w, ours)
    shot = gf.ray_shoot(gf.minkowski_sum(*grasp.contact_sets()), -w, method=method)
    assert status == "optimal" and shot.hit
    assert abs(1.0 / shot.t / literal - 1) <= 1e-6
    assert literal >= 1.5 * socp
    # the minimum leaves a contact idle (SOCP to its accuracy, ~1e-9 of sigma)
    assert socp_forces[:, 0].min() <= 1e-6 * socp
    # a contact that can only push against the others cannot match them: the literal set
    # misses the ray altogether, the exact one does not
    grasp = asymmetric_grasp()
    P = plain(grasp)
    w = np.array([0.4, -0.2, -6.0, 0.05, 0.08, -0.01])
    _, socp, _, _ = T.min_force_socp(P, w, "Linf", "normal")
    assert T.min_force_socp(P, w, "Linf", "normal", equal=True)[0] == "infeasible"
    assert not gf.ray_shoot(gf.minkowski_sum(*grasp.contact_sets()), -w, method=method).hit
    ours = grasp.min_force(w, norm="Linf", method=method)
    assert ours.status == "optimal" and abs(ours.sigma / socp - 1) <= 1e-6


@pytest.mark.parametrize("seed", range(6))
def test_linf_literal_is_never_better(seed):
    # CH({0} U W_i) contains W_i, so the exact set contains the literal one: its minimum is
    # never larger (eps-certified both, so up to 2 eps)
    rng = np.random.default_rng(50 + seed)
    grasp = random_grasp(rng, 3 + seed % 3, ("soft", "point"))
    literal_set = gf.minkowski_sum(*grasp.contact_sets())
    for _ in range(4):
        w = random_wrench(rng)
        ours = grasp.min_force(w, norm="Linf")
        shot = gf.ray_shoot(literal_set, -w)
        # every wrench decided against the SOCP: the literal set against its own (equal=True)
        P = plain(grasp)
        status, truth, _, _ = T.min_force_socp(P, w, "Linf", "normal")
        assert ours.feasible == (status == "optimal")
        if ours.feasible:
            assert ours.status == "optimal"
            assert abs(ours.sigma / truth - 1) <= SOCP_TOL
        literal, literal_truth, _, _ = T.min_force_socp(P, w, "Linf", "normal", equal=True)
        assert shot.hit == (literal == "optimal")
        if shot.hit:
            assert ours.feasible and ours.sigma <= (1.0 / shot.t) * (1 + 2 * EPS)
            assert abs(1.0 / shot.t / literal_truth - 1) <= SOCP_TOL


def test_linf_literal_is_exact_on_the_symmetric_sphere():
    w = np.array([0.0, 0.0, -G_WEIGHT, 0.0, 0.0, 0.0])
    for lam in (1e-1, 1e-3):
        grasp = sphere(lam, 0.0)
        true, d = sphere_truth(lam, "Linf", "normal")
        shot = gf.ray_shoot(gf.minkowski_sum(*grasp.contact_sets()), -w)
        assert abs(1.0 / shot.t / true - 1) <= EPS + 2 * U / d
        assert abs(grasp.min_force(w, norm="Linf").sigma / true - 1) <= EPS + 2 * U / d


# --- degenerate input: zero wrench, one contact, coincident contacts
# --------------------------------
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_zero_wrench(norm, magnitude, method):
    grasp = asymmetric_grasp()
    res = grasp.min_force(np.zeros(6), norm, magnitude, method=method)
    assert res.status == "optimal" and res.feasible
    assert res.sigma == 0.0 and res.sigma_lower == 0.0
    assert not res.forces.any() and not res.resultant.any() and not res.wrenches.any()
    m = len(grasp.contacts)
    assert (res.forces.shape, res.world_forces.shape, res.wrenches.shape, res.resultant.shape) \
        == ((m, 4), (m, 3), (m, 6), (6,))


SINGLE = [  # (mu, mu_spin, local force f inside the cone)
    (0.5, 0.02, [2.0, 0.3, -0.4, 0.01]),
    # 1e-6 and 1e-9 inside the boundary |f_t| = mu f_1: still far above rounding (exactly on
    # the boundary the rounding of w would decide feasibility)
    (0.5, 0.02, [2.0, 0.6 * (1 - 1e-6), -0.8 * (1 - 1e-6), 0.0]),
    (0.5, 0.02, [2.0, 0.6 * (1 - 1e-9), -0.8 * (1 - 1e-9), 0.0]),
    (0.7, 0.0, [1.5, 0.84 * (1 - 1e-9), -0.63 * (1 - 1e-9), 0.0]),
    (0.7, 0.0, [1.5, -0.2, 0.5, 0.0]),
    (0.0, 0.0, [3.0, 0.0, 0.0, 0.0]),
]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("mu, mu_spin, f", SINGLE)
def test_single_and_doubled_contact_closed_form(mu, mu_spin, f, method):
    # G_i is injective on the contact's components, so w = -G f has the unique answer f: sigma
    # is f_1 (normal) or ||f|| (full). Two copies of the contact share it: Linf halves it.
    f = np.array(f)
    contact = gf.Contact([0.03, -0.02, 0.05], [0.2, -0.3, -1.0], mu, mu_spin)
    w = -(contact.matrix @ f)
    spin = (mu / mu_spin) ** 2 * f[3] ** 2 if mu_spin > 0 else 0.0
    full = math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2 + spin)
    for grasp, copies in ((gf.Grasp([contact]), 1), (gf.Grasp([contact, contact]), 2)):
        for norm, magnitude in OBJECTIVES:
            true = f[0] if magnitude == "normal" else full
            if norm == "Linf":
                true /= copies
            res = grasp.min_force(w, norm, magnitude, method=method)
            assert res.status == "optimal", (copies, norm, magnitude)
            # eps plus the rounding of w = -G f (a few ulps, well conditioned)
            assert abs(res.sigma / true - 1) <= EPS + 1e-14, (copies, norm, magnitude)
            check_forces(grasp, w, res)
            assert np.allclose(res.forces.sum(axis=0), f, rtol=0, atol=1e-8 * true)


@pytest.mark.parametrize("method", gf.METHODS)
def test_every_method_leaves_the_lift_of_a_doubled_point_contact(method):
    # W_Linf's lift of two copies of one point contact is a 3-D set in R^7 (the lift's segment
    # times the contact's disk of unit-normal forces) and r lies in its span: with the force
    # 1e-9 inside the cone, z_W(r) is 1e-9 from the disk's rim, where ZC's cone from b_k loses
    # rank. Every ZC-type method stalled there on an AMD EPYC (the test above, Linf with IE and
    # ZC-IE); GJK-based steps finish it (`unstall`, core/shooting/dispatch.hpp). Closed form:
    # each copy carries f / 2, so t = 1 / (m sigma) = 1 / f_1 on the lift.
    f = np.array([1.5, 0.84 * (1 - 1e-9), -0.63 * (1 - 1e-9), 0.0])
    contact = gf.Contact([0.03, -0.02, 0.05], [0.2, -0.3, -1.0], 0.7, 0.0)
    w = -(contact.matrix @ f)
    lift = gf.Grasp([contact, contact], length=1.0)._space("Linf", "normal").target(
        "ie", full=True).set
    assert lift.dim == 7
    res = gf.ray_shoot(lift, np.r_[0.0, -w], method=method)
    assert res.status == "hit"
    assert res.t <= 1 / f[0] * (1 + 1e-14) <= res.t_upper * (1 + 1e-14)
    assert res.t_upper / res.t - 1 <= EPS


@pytest.mark.parametrize("seed", range(4))
def test_coincident_contacts(seed):
    rng = np.random.default_rng(70 + seed)
    grasp = random_grasp(rng, 4, ("soft", "point"))
    doubled = gf.Grasp(grasp.contacts + grasp.contacts[:2])
    P2 = plain(doubled)
    for _ in range(3):
        w = random_wrench(rng)
        for norm, magnitude in OBJECTIVES:
            one = grasp.min_force(w, norm, magnitude)
            two = doubled.min_force(w, norm, magnitude, method=OTHERS[seed])
            status, socp, _, _ = T.min_force_socp(P2, w, norm, magnitude)
            assert two.feasible == one.feasible == (status == "optimal")
            if not two.feasible:
                continue
            assert abs(two.sigma / socp - 1) <= 1e-6
            check_forces(doubled, w, two)
            if norm == "L1":
                # CH(W_1 U W_1 U ...) is the same set: the same minimum (both to eps)
                assert abs(two.sigma / one.sigma - 1) <= 2 * EPS
            else:
                assert two.sigma <= one.sigma * (1 + 2 * EPS)


@pytest.mark.parametrize("method", METHODS)
def test_ray_leaving_at_the_origin_is_infeasible(method):
    # Two point contacts that cannot resist w (SOCP: infeasible; the other methods find the
    # separating direction). The ray leaves W_Linf (which contains 0) at the origin; a t of
    # rounding size (1e-16) must not be read as a hit: forces scaled by 1/t do not resist w.
    grasp = gf.Grasp([
        gf.Contact([-0.08017769346895402, 0.06026971127964663, -0.01976788405342593],
                   [0.833020429253081, -0.5368404879975505, -0.1337133310241159],
                   0.7013337389032768),
        gf.Contact([0.0035572796019098796, 0.040710299980057936, 0.03340639882198933],
                   [-0.3796944586474776, -0.06622477080093674, -0.9227385316571334],
                   0.40341684336952083)])
    w = np.array([0.1255525340769874, 5.164618149344074, -3.2016635464404652,
                  0.10575860034111352, 0.013002326481180855, -0.4953534537939611])
    for norm, magnitude in OBJECTIVES:
        assert T.min_force_socp(plain(grasp), w, norm, magnitude)[0] == "infeasible"
        res = grasp.min_force(w, norm, magnitude, method=method)
        assert not res.feasible, (norm, magnitude, res.status, res.sigma, res.sigma_lower)
        check_infeasible(grasp, w, res)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_frictionless_contact_cannot_pull(norm, magnitude, method):
    # lifting the object off a frictionless support needs f_1 < 0: infeasible for every measure
    grasp = gf.Grasp([gf.Contact([0.0, 0.0, -0.05], [0, 0, 1], 0.0)])
    w = np.array([0.0, 0.0, 3.0, 0.0, 0.0, 0.0])
    assert T.min_force_socp(plain(grasp), w, norm, magnitude)[0] == "infeasible"
    res = grasp.min_force(w, norm, magnitude, method=method)
    assert not res.feasible, (res.status, res.sigma, res.forces)
    check_infeasible(grasp, w, res)


# --- bad input ----------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, field", [
    ({"w_ext": np.zeros(5)}, "w_ext"),
    ({"w_ext": np.zeros((6, 1))}, "w_ext"),
    ({"w_ext": [0, 0, np.nan, 0, 0, 0]}, "w_ext"),
    ({"w_ext": [0, 0, np.inf, 0, 0, 0]}, "w_ext"),
    ({"w_ext": np.ones(6), "norm": "L2"}, "norm"),
    ({"w_ext": np.ones(6), "magnitude": "tangential"}, "magnitude"),
    ({"w_ext": np.ones(6), "method": "simplex"}, "method"),
    ({"w_ext": np.ones(6), "eps": 0.0}, "eps"),
    ({"w_ext": np.ones(6), "eps": np.nan}, "eps"),
    ({"w_ext": np.ones(6), "max_iter": 0}, "max_iter"),
])
def test_min_force_bad_input_names_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        asymmetric_grasp().min_force(**kwargs)


def test_wrenches_of_any_type_and_layout_agree():
    # the compiled call takes a C-contiguous float64 (6,) array
    # (graspforce._core.shoot_and_read_forces, which refuses anything else); every other wrench
    # is converted on the way, never a different answer
    grasp = asymmetric_grasp()
    w = np.array([0.3, -1.0, 2.0, 0.05, -0.1, 0.02])
    # the second shot builds the set's start table, which every call below then starts from
    # (graspforce.geometry._start_table)
    grasp.min_force(w)
    ref = grasp.min_force(w)
    frozen = w.copy()
    frozen.flags.writeable = False
    for same in (w.tolist(), tuple(w), frozen, np.repeat(w, 2)[::2], w.reshape(1, 6)[0]):
        res = grasp.min_force(same)
        assert res.sigma == ref.sigma and np.array_equal(res.forces, ref.forces)
    assert grasp.min_force(np.array([0, 0, 1, 0, 0, 0])).sigma == \
        grasp.min_force(np.array([0.0, 0, 1, 0, 0, 0])).sigma
    # the compiled call itself takes exactly that kind of array (read-only too: it does not
    # write to the wrench) and gives min_force's sigma; any other wrench raises TypeError,
    # unconverted
    from graspforce._core import HIT, shoot_and_read_forces
    from graspforce.geometry._start_table import start_table
    _, code, shoot, args, A, size, _, _, _ = grasp._call("L1", "normal", "zc-ie")
    assert shoot is shoot_and_read_forces
    packed = np.empty(size)

    def compiled(w_ext):
        return shoot(w_ext, code, 1e-9, 10000, packed, start_table(A, 6), *args)

    for exact in (w, frozen, w.reshape(1, 6)[0]):
        assert compiled(exact)[0] == HIT and packed.item(0) == ref.sigma
    for other in (w.tolist(), tuple(w), w.astype(np.float32), np.array([0, 0, 1, 0, 0, 0]),
                  np.repeat(w, 2)[::2], w.reshape(1, 6), w.reshape(6, 1)):
        with pytest.raises(TypeError):
            compiled(other)
    with pytest.raises(ValueError, match="w_ext"), np.errstate(over="ignore"):
        grasp.min_force(np.full(6, 1e200))                  # x.x overflows


def test_min_force_arrays_are_read_only_views():
    res = asymmetric_grasp().min_force(np.array([0.3, -1.0, 2.0, 0.05, -0.1, 0.02]))
    assert np.array_equal(res.world_forces, res.wrenches[:, :3])
    with pytest.raises(ValueError):
        res.forces[0, 0] = 1.0


def test_grasp_bad_input():
    c = gf.Contact([0, 0, 0], [0, 0, 1], 0.5)
    with pytest.raises(TypeError, match="contacts"):
        gf.Grasp([c, "finger"])
    with pytest.raises(TypeError, match="contacts"):
        gf.Grasp([c, np.array([0.0, 0.0, 1.0])])
    with pytest.raises(ValueError, match="contacts"):
        gf.Grasp([])
    grasp = gf.Grasp([c])
    with pytest.raises(ValueError, match="norm"):
        grasp.wrench_set(norm="l1")
    with pytest.raises(ValueError, match="magnitude"):
        grasp.contact_sets("Full")
    with pytest.raises(ValueError, match="norm"):
        grasp.quality(norm="L2")


def edge_of_cone_cases(count, weights_first):
    """(trial, grasp, lams, w, two_points) for `count` random two- and three-contact grasps and
    w = -(sum_i lam_i s_i), s_i a support point of W_i in a random direction, lam_i in
    [0.2, 1]. The two draw orders give different cases: each contact's weight then direction,
    or all weights first. two_points: two point contacts, whose minimum is sum(lam) (L1) or
    max(lam) (Linf) exactly."""
    rng = np.random.default_rng(5)
    for trial in range(count):
        grasp = random_grasp(rng, 2 + trial % 2, kinds=("soft", "point"))
        sets = grasp.contact_sets()
        lams = [rng.uniform(0.2, 1.0) for _ in sets] if weights_first else []
        w = np.zeros(6)
        for i, W_i in enumerate(sets):
            if not weights_first:
                lams.append(rng.uniform(0.2, 1.0))
            w -= lams[i] * W_i.support(rng.normal(size=6))[1]
        two_points = len(grasp) == 2 and all(c.mu_spin == 0.0 for c in grasp.contacts)
        yield trial, grasp, lams, w, two_points


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_answers_on_grasps_that_are_not_closure_certify_or_say_so(norm):
    # Two or three contacts with friction, wrenches w = -(sum_i lam_i s_i) with s_i a support
    # point of W_i (unit normal force, on its friction cone's edge): resistible, and on or near
    # the boundary of the cone of wrenches the grasp resists, where z_W(r) is a corner of W and
    # ZC's normal is nearly orthogonal to r (docs/core-api.md, "Rays along the boundary of
    # CO(A)"). With two point contacts the grasp map is invertible, the forces are unique and
    # the minimum is sum(lam) (L1) or max(lam) (Linf) exactly; elsewhere the tight SOCP is the
    # yardstick. ZC once accepted a point that its weights reproduced to ~1e-8 ("optimal"
    # answers 5e-8 below the exact minimum) and 10 of 60 shots stalled; every answer is now
    # checked on the ray and Newton finishes the corners. Every lower bound
    # stays below the truth; every "optimal" answer is certified by a bound recomputed here,
    # matches the truth, and its forces lie in their cones and resist w to 1e-9. "max_iter"
    # remains on corners that neither Newton nor GJK-based steps finish (measured with "zc-ie":
    # 3 of 60 wrenches for L1, 3 for Linf, none of them two point contacts; before the hand-over
    # to GJK-based, 4 for L1, and on an AMD EPYC one of them two point contacts).
    open_answers = 0
    for trial, grasp, lams, w, two_points in edge_of_cone_cases(60, weights_first=False):
        if two_points:
            truth, tol = (sum(lams) if norm == "L1" else max(lams)), 2e-9
        else:
            status, truth, _, _ = T.min_force_socp(plain(grasp), w, norm, "normal")
            assert status == "optimal"
            tol = 1e-8
        for method in ("zc-ie", "ie", "gjk", "bi-gjk"):
            res = grasp.min_force(w, norm=norm, method=method)
            assert res.feasible and res.status in ("optimal", "max_iter")
            # sigma is the forces' objective, rounded apart from 1 / t_upper by an ulp or two
            assert res.sigma_lower <= truth * (1 + tol)
            assert res.sigma >= res.sigma_lower * (1 - 1e-15)
            if res.status == "optimal":
                assert abs(res.sigma / truth - 1) <= tol, (trial, method, res.sigma, truth)
                assert certified_gap(grasp, w, res) <= 2e-9
                # the bound (POINT_HOLDS, core/api.hpp), not the 1e-12 that
                # force-closure grasps meet
                check_forces(grasp, w, res, residual_tol=1e-9)
            elif method == "zc-ie":
                open_answers += 1
                assert not two_points, (trial, res.sigma, truth)
    assert open_answers <= {"L1": 3, "Linf": 3}[norm]


def test_corners_that_no_step_leaves_end_early():
    # Wrenches on the edge of what two contacts resist, drawn as in the test above but with the
    # weights first: on two of them ZC-IE and IE on W_Linf's lift found b_k inside ZC's cone
    # again and again without moving it, and went on to max_iter (10000 steps, no upper bound).
    # Such a shot now stops after 100 idle steps (IDLE_STEPS, core/shooting/zc_family.hpp):
    # "max_iter" with its honest (infinite) bracket.
    for _, grasp, lams, w, two_points in edge_of_cone_cases(40, weights_first=True):
        for method in ("zc-ie", "ie"):
            res = grasp.min_force(w, norm="Linf", method=method)
            assert res.status in ("optimal", "max_iter") and res.iterations < 1000
            assert res.feasible
            if two_points:
                assert res.sigma_lower <= max(lams) * (1 + 2e-9)
                if res.status == "optimal":
                    assert res.sigma == pytest.approx(max(lams), rel=2e-9)
            else:
                # the other runs against the SOCP: a lower bound below it, an "optimal" answer
                # on it and certified, its forces in their cones
                status, truth, _, _ = T.min_force_socp(plain(grasp), w, "Linf", "normal")
                assert status == "optimal"
                assert res.sigma_lower <= truth * (1 + SOCP_TOL)
                if res.status == "optimal":
                    assert abs(res.sigma / truth - 1) <= SOCP_TOL
                    assert certified_gap(grasp, w, res) <= 2e-9
                    check_forces(grasp, w, res, residual_tol=1e-9)
