"""The baselines (graspforce.grasping.baselines) against closed forms, against pyramids from inside
and outside, and against checks that need no solver (cones by Contact.contains and by qhull's
facets, equilibrium residuals)."""
import math

import numpy as np
import pytest
from grasps import (
    G_WEIGHT,
    MU,
    box_grasp,
    random_grasp,
    sphere_grasp,
    sphere_sigma_l1,
    two_finger_pinch,
)
from grasps import random_wrenches as wrenches
from scipy.spatial import ConvexHull

import graspforce as gf
from graspforce.grasping.baselines import clarabel_socp, pyramid

OBJECTIVES = [(n, m) for n in ("L1", "Linf") for m in ("normal", "full")]
# qpsolvers warns on every status but "solved"; the statuses themselves are what we test
pytestmark = pytest.mark.filterwarnings("ignore:.*terminated with status:UserWarning",
                                        "ignore:OSQP exited with status:UserWarning")


def sphere_sigma(lam, norm, magnitude):
    """NOTES.md item 1. By the 4-fold symmetry (and convexity) each contact lifts G/4. Normal:
    sum f_1 = G / (mu cos a - sin a). Full: ||F|| is least on the cone's edge nearest to +z, at
    atan(mu) - a (= lam atan(mu)) below the horizontal, so ||F|| = (G/4) / sin(lam atan mu);
    the spin moment is not needed and would only add to ||f||."""
    l1 = (sphere_sigma_l1(lam) if magnitude == "normal"
          else G_WEIGHT / math.sin(lam * math.atan(MU)))
    return l1 if norm == "L1" else l1 / 4


@pytest.mark.parametrize("mu_spin", [0.0, 0.05])
@pytest.mark.parametrize("lam", [1e-1, 1e-2, 1e-3, 1e-4])
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_socp_matches_sphere_closed_form(lam, mu_spin, norm, magnitude):
    grasp = sphere_grasp(lam, mu_spin)
    true = sphere_sigma(lam, norm, magnitude)
    w = [0, 0, -G_WEIGHT, 0, 0, 0]
    # Clarabel stops at a relative duality gap and feasibility residuals of 1e-8 (default) or
    # 1e-10 (tight); sigma is the objective of the forces it returns, so both errors enter.
    # Measured over this grid: <= 6.2e-8 at the defaults, <= 6.6e-10 tight. Tight, Clarabel
    # sometimes meets only its reduced tolerances (AlmostSolved: "inaccurate", 3 of these 32
    # problems, soft Linf full) though its answer is as accurate. Below lam = 1e-4 the
    # conditioning wins (3.6e-7 default at 1e-5; tight is "inaccurate" at 1e-6).
    for tight, tol, statuses in ((False, 1e-7, {"optimal"}), (True, 1e-9, {"optimal", "inaccurate"})):
        res = clarabel_socp.min_force(grasp, w, norm, magnitude, tight=tight)
        assert res.status in statuses and res.feasible
        assert abs(res.sigma / true - 1) <= tol
        # the dual bound is reported only when Clarabel met its full tolerances
        if res.status == "optimal":
            assert res.sigma_lower <= true * (1 + tol)
        else:
            assert math.isnan(res.sigma_lower)


def lone_contact_problem(kind, inside, seed):
    """One contact at a random pose and the wrench -G f of a known force f, at 0.9 (inside) or
    1.1 times the cone's boundary in the unit coordinates of eq. (12). G_i has full column
    rank, so f is the only force in equilibrium: the minimum of every objective is f's own
    (eq. 13, 15), and outside the cone it is infeasible."""
    rng = np.random.default_rng(seed)
    mu = 0.0 if kind == "frictionless" else 0.6
    mu_spin = 0.02 if kind == "soft" else 0.0
    contact = gf.Contact(rng.normal(0, 0.1, 3), rng.normal(size=3), mu, mu_spin)
    n = 2.5
    if kind == "frictionless":
        f = n * np.array([1.0, 0.0 if inside else 0.1, 0.0, 0.0])
    else:
        u = rng.normal(size=3) * [1.0, 1.0, kind == "soft"]
        u *= (0.9 if inside else 1.1) / np.linalg.norm(u)
        f = n * np.array([1.0, mu * u[0], mu * u[1], mu_spin * u[2]])
    spin_weight = (mu / mu_spin) ** 2 if kind == "soft" else 0.0
    sigma = {"normal": f[0], "full": math.sqrt(f[:3] @ f[:3] + spin_weight * f[3] ** 2)}
    return [contact], -contact.matrix @ f, f, sigma


@pytest.mark.parametrize("kind", ["soft", "point", "frictionless"])
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_lone_contact_forces_are_fixed_by_equilibrium(kind, norm, magnitude):
    for seed in range(3):
        contacts, w, f, sigma = lone_contact_problem(kind, True, seed)
        res = clarabel_socp.min_force(contacts, w, norm, magnitude)
        assert res.status == "optimal"
        # the equality rows alone fix the forces, so only the rounding of Clarabel's linear
        # solves enters, not its tolerances: measured <= 3e-14
        assert abs(res.sigma / sigma[magnitude] - 1) <= 1e-12
        assert np.allclose(res.forces, [f], rtol=0, atol=1e-12 * f[0])
        if magnitude == "normal" and kind != "soft":
            # a point contact's octagon reaches cos(pi/8) = 0.92 > 0.9 of the disc everywhere;
            # a soft finger's polytope does not, so only the exact cone is tested there
            lp = pyramid.min_force(contacts, w, norm, solver="clarabel")
            assert lp.status == "optimal" and abs(lp.sigma / f[0] - 1) <= 1e-12
        outside = lone_contact_problem(kind, False, seed)
        assert clarabel_socp.min_force(outside[0], outside[1], norm, magnitude).status == (
            "infeasible")


@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_prepared_update_equals_a_new_solver(norm, magnitude):
    rng = np.random.default_rng(5)
    grasps = [box_grasp(), random_grasp(rng, 5), random_grasp(rng, 3)]
    statuses = set()
    for grasp in grasps:
        prepared = clarabel_socp.Prepared(grasp, norm, magnitude)
        for w in wrenches(4, 6):
            fast = prepared.solve(w)
            # a plain list of contacts takes the other input path (G_i rebuilt from the contacts)
            fresh = clarabel_socp.min_force(list(grasp.contacts), w, norm, magnitude)
            assert fast.status == fresh.status
            statuses.add(fast.status)
            if fast.feasible:
                # the same problem and algorithm; measured 2e-11 apart (presolve on in one,
                # off in the other, which drops nothing here)
                assert abs(fast.sigma / fresh.sigma - 1) <= 1e-9
    assert statuses == {"optimal", "infeasible"}


def assert_resists(grasp, res, w, outside):
    """Forces in their exact cones (up to `outside` times the largest normal force: an unused
    contact's f_1 ~ 0 makes a per-contact relative test meaningless), the record's wrenches
    recomputed from them, and equilibrium to 1e-8 |w_ext|."""
    scale = res.forces[:, 0].max()
    for contact, f in zip(grasp.contacts, res.forces):
        assert contact.contains(f + np.array([outside * scale, 0, 0, 0]), tol=0.0)
    assert np.allclose(res.wrenches, [c.matrix @ f for c, f in zip(grasp.contacts, res.forces)])
    assert np.allclose(res.world_forces, res.wrenches[:, :3])
    assert np.linalg.norm(res.resultant + w) <= 1e-8 * np.linalg.norm(w)


@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_socp_forces_are_in_their_cones_and_in_equilibrium(norm, magnitude):
    rng = np.random.default_rng(7)
    checked = 0
    for grasp in [box_grasp()] + [random_grasp(rng, m) for m in (3, 4, 6)]:
        for w in wrenches(3, 2):
            res = clarabel_socp.min_force(grasp, w, norm, magnitude, tight=True)
            if res.status == "infeasible":
                continue
            # tight tolerances are sometimes met only to Clarabel's reduced ones ("inaccurate");
            # the forces are checked all the same
            assert res.status in ("optimal", "inaccurate") and res.method == "clarabel-socp"
            assert res.support_calls == 0 and res.shot is None and res.iterations > 0
            # the interior-point solution sits on the cone boundary to tol_feas = 1e-10
            assert_resists(grasp, res, w, outside=1e-8)
            # sigma is the objective of the returned forces, bracketed by the dual bound
            if res.status == "optimal":
                assert res.sigma_lower <= res.sigma * (1 + 1e-8)
            checked += 1
    assert checked >= 6


@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_zero_wrench_needs_no_force(norm, magnitude):
    grasp = box_grasp()
    results = [clarabel_socp.min_force(grasp, np.zeros(6), norm, magnitude)]
    if magnitude == "normal":
        results.append(pyramid.min_force(grasp, np.zeros(6), norm, solver="clarabel"))
    for res in results:
        assert res.status == "optimal"
        # nothing sets a scale but Clarabel's absolute gap tolerance, 1e-8: the interior point
        # it stops at has forces of that order (measured 2.7e-9 for L1 full)
        assert abs(res.sigma) <= 1e-8 and np.abs(res.forces).max() <= 1e-8


def unit_inradius(faces):
    """The inradius of the soft-finger pyramid's cross-section in the unit coordinates
    (f_2/mu, f_3/mu, f_4/mu_s) / f_1, from qhull's facets of its generators."""
    g = pyramid.generators(gf.Contact([0, 0, 0], [0, 0, 1], 1.0, 1.0), faces)
    return -ConvexHull(g[:, 1:]).equations[:, -1].max()


def outer_contacts(grasp, faces):
    """Contacts whose inscribed pyramids circumscribe the original cones: mu and mu_s divided
    by the inradius of the cross-section (cos(pi/k) for a regular k-gon), so that the scaled
    polygon or polytope contains the original disc or ball."""
    out = []
    for c in grasp.contacts:
        r = (1.0 if c.kind == "frictionless" else math.cos(math.pi / faces) if c.kind == "point"
             else unit_inradius(faces))
        out.append(gf.Contact(c.position, c.normal, c.mu / r, c.mu_spin / r, tangents=c.tangents))
    return out


# the LPs are solved by Clarabel to a 1e-8 relative gap: a sandwich violated by less than 1e-7
# relative is solver tolerance, not a wrong bound
SANDWICH = 1e-7


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_socp_lies_between_the_pyramids_from_inside_and_outside(norm):
    rng = np.random.default_rng(11)
    both = 0
    for m in (2, 3, 4, 5, 6):
        grasp = random_grasp(rng, m)
        outer = outer_contacts(grasp, 8)
        for w in wrenches(3, m):
            exact = clarabel_socp.min_force(grasp, w, norm, tight=True)
            inner = pyramid.min_force(grasp, w, norm, solver="clarabel")
            low = pyramid.min_force(outer, w, norm, solver="clarabel")
            # inner cones <= exact cones <= outer cones: feasibility can only be gained outwards
            assert inner.feasible <= exact.feasible <= low.feasible
            if inner.feasible:
                both += 1
                assert low.sigma * (1 - SANDWICH) <= exact.sigma <= inner.sigma * (1 + SANDWICH)
    assert both >= 5


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_pyramids_converge_quadratically(norm):
    grasp = box_grasp()
    w = wrenches(1, 3)[0]
    exact = clarabel_socp.min_force(grasp, w, norm, tight=True).sigma
    widths = []
    for faces in (8, 32):
        inner = pyramid.min_force(grasp, w, norm, solver="clarabel", faces=faces).sigma
        low = pyramid.min_force(outer_contacts(grasp, faces), w, norm, solver="clarabel",
                                faces=faces).sigma
        assert low * (1 - SANDWICH) <= exact <= inner * (1 + SANDWICH)
        widths.append((inner - low) / exact)
    # a facet at angular spacing h lies 1 - cos(h/2) ~ h^2/8 inside the sphere: 4x the faces
    # should shrink the bracket ~16x (measured 11.7 for Linf, 11.9 for L1: at 8 faces the
    # soft-finger polytope is still coarse); demand at least 8
    assert widths[1] <= widths[0] / 8


def inside_pyramid(contact, f, faces, slack):
    """f in the cone over the hull of the contact's generators, by qhull's facet inequalities
    (independent of the LP's representation as weights of generators)."""
    if contact.kind == "frictionless":
        return f[0] >= -slack and np.abs(f[1:]).max() <= slack
    g = pyramid.generators(contact, faces)
    cols = [1, 2, 3] if contact.kind == "soft" else [1, 2]
    equations = ConvexHull(g[:, cols]).equations      # a.x + b <= 0 on the cross-section f_1 = 1
    return bool(np.all(equations[:, :-1] @ f[cols] + equations[:, -1] * f[0] <= slack))


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_pyramid_forces_are_in_the_pyramid_and_in_equilibrium(norm):
    rng = np.random.default_rng(13)
    checked = 0
    for grasp in [box_grasp()] + [random_grasp(rng, m) for m in (4, 6)]:
        for w in wrenches(3, 8):
            res = pyramid.min_force(grasp, w, norm, solver="clarabel", faces=8)
            if res.status == "infeasible":
                continue
            assert res.status == "optimal" and res.method == "clarabel-pyramid"
            assert math.isnan(res.sigma_lower)      # the LP certifies nothing about eq. (12)
            scale = res.forces[:, 0].max()
            for contact, f in zip(grasp.contacts, res.forces):
                assert inside_pyramid(contact, f, 8, 1e-8 * scale)
            assert_resists(grasp, res, w, outside=1e-8)
            checked += 1
    assert checked >= 4


def test_osqp_reports_its_own_status():
    grasp = box_grasp()
    # at OSQP's defaults the soft-finger pyramid often runs to the iteration limit
    results = [pyramid.min_force(grasp, w, "L1", solver="osqp") for w in wrenches(8, 4)]
    assert all(r.method == "osqp-pyramid" for r in results)
    assert {r.status for r in results} <= {"optimal", "max_iter", "inaccurate"}
    assert all(r.iterations == 4000 for r in results if r.status == "max_iter")
    # a limit the solver cannot meet is reported as such, with the iterate it stopped at
    res = pyramid.min_force(grasp, wrenches(1, 4)[0], solver="osqp", max_iter=10)
    assert res.status == "max_iter" and res.iterations == 10 and res.feasible


def test_osqp_solves_an_easy_pinch():
    # push the pinched object along -x: the finger at x = +0.05 pushes back with f_1 = 1
    res = pyramid.min_force(two_finger_pinch(), [1.0, 0, 0, 0, 0, 0], solver="osqp")
    assert res.status == "optimal" and res.iterations > 0
    # OSQP's default tolerances are 1e-3 absolute and relative
    assert abs(res.sigma - 1.0) <= 1e-3


@pytest.mark.parametrize("solve", [
    lambda g, w: clarabel_socp.min_force(g, w, "L1"),
    lambda g, w: clarabel_socp.min_force(g, w, "Linf", "full"),
    lambda g, w: clarabel_socp.Prepared(g, "L1", "full").solve(w),
    lambda g, w: pyramid.min_force(g, w, "L1", solver="clarabel"),
    lambda g, w: pyramid.min_force(g, w, "Linf", solver="osqp"),
])
def test_infeasible_wrench(solve):
    # two point contacts cannot resist a torque about the axis through them
    res = solve(two_finger_pinch(), [0, 0, 0, 1.0, 0, 0])
    assert res.status == "infeasible" and not res.feasible
    assert res.sigma == res.sigma_lower == math.inf and not res.forces.any()


def test_bad_input():
    grasp = box_grasp()
    w = np.ones(6)
    cases = [
        ("magnitude", lambda: pyramid.min_force(grasp, w, "L1", "full")),
        ("magnitude", lambda: clarabel_socp.min_force(grasp, w, "L1", "total")),
        ("faces", lambda: pyramid.min_force(grasp, w, faces=2)),
        ("faces", lambda: pyramid.min_force(grasp, w, faces=8.0)),
        ("solver", lambda: pyramid.min_force(grasp, w, solver="quadprog")),
        ("norm", lambda: clarabel_socp.min_force(grasp, w, "L2")),
        ("norm", lambda: clarabel_socp.Prepared(grasp, "L2")),
        ("w_ext", lambda: clarabel_socp.min_force(grasp, [0, 0, np.nan, 0, 0, 0])),
        ("w_ext", lambda: pyramid.min_force(grasp, np.ones(5))),
        ("w_ext", lambda: clarabel_socp.Prepared(grasp).solve(np.ones(5))),
        ("grasp", lambda: clarabel_socp.min_force([], w)),
        ("grasp", lambda: pyramid.min_force([np.zeros(3)], w)),
        ("tol_gap", lambda: clarabel_socp.min_force(grasp, w, tol_gap=1e-9)),
        ("presolve_enable", lambda: clarabel_socp.Prepared(grasp, presolve_enable=True)),
    ]
    for field, call in cases:
        with pytest.raises(ValueError, match=field):
            call()
