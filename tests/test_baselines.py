"""The baselines (graspforce.baselines) against closed forms and against each other's guarantees."""
import math
import warnings

import numpy as np
import pytest
from grasps import G_WEIGHT, box_grasp, sphere_grasp, sphere_sigma_l1, two_finger_pinch
from grasps import random_wrenches as wrenches

from graspforce.baselines import clarabel_socp, pyramid


@pytest.mark.parametrize("mu_spin", [0.0, 0.05])
@pytest.mark.parametrize("lam", [1e-1, 1e-2, 1e-3, 1e-4])
@pytest.mark.parametrize("norm, share", [("L1", 1.0), ("Linf", 0.25)])
def test_socp_matches_sphere_closed_form(lam, mu_spin, norm, share):
    grasp = sphere_grasp(lam, mu_spin)
    true = share * sphere_sigma_l1(lam)
    w = [0, 0, -G_WEIGHT, 0, 0, 0]
    # measured: <= 5e-8 at Clarabel's default tolerances (1e-8 gap), <= 5e-10 with tight=True
    for tight, tol in ((False, 1e-6), (True, 1e-8)):
        res = clarabel_socp.min_force(grasp, w, norm, tight=tight)
        assert res.status == "optimal"
        assert abs(res.sigma / true - 1) <= tol
        assert res.sigma_lower <= true * (1 + tol)


@pytest.mark.parametrize("norm", ["L1", "Linf"])
@pytest.mark.parametrize("magnitude", ["normal", "full"])
def test_prepared_update_equals_a_new_solver(norm, magnitude):
    grasp = box_grasp()
    prepared = clarabel_socp.Prepared(grasp, norm, magnitude)
    for w in wrenches(5, 1):
        fast = prepared.solve(w)
        fresh = clarabel_socp.min_force(grasp, w, norm, magnitude)
        assert fast.status == fresh.status == "optimal"
        # same data, same algorithm: only the solver object differs
        assert abs(fast.sigma / fresh.sigma - 1) <= 1e-9


@pytest.mark.parametrize("norm", ["L1", "Linf"])
@pytest.mark.parametrize("magnitude", ["normal", "full"])
def test_socp_forces_are_in_their_cones_and_in_equilibrium(norm, magnitude):
    grasp = box_grasp()
    for w in wrenches(5, 2):
        res = clarabel_socp.min_force(grasp, w, norm, magnitude, tight=True)
        scale = res.forces[:, 0].max()
        for contact, f in zip(grasp.contacts, res.forces):
            # the interior-point solution sits on the cone boundary to the solver's feasibility
            # tolerance (1e-10), measured against the solution's largest normal force
            assert contact.contains(f + np.array([1e-8 * scale, 0, 0, 0]), tol=0.0)
        assert np.linalg.norm(res.resultant + w) <= 1e-8 * np.linalg.norm(w)
        # sigma is the objective of the returned forces, bracketed by the dual bound
        assert res.sigma_lower <= res.sigma * (1 + 1e-8)


@pytest.mark.parametrize("norm", ["L1", "Linf"])
def test_inscribed_pyramid_is_above_the_socp_and_converges(norm):
    grasp = box_grasp()
    w = wrenches(1, 3)[0]
    exact = clarabel_socp.min_force(grasp, w, norm, tight=True).sigma
    gaps = []
    for faces in (4, 16, 64):
        res = pyramid.min_force(grasp, w, norm, solver="clarabel", faces=faces)
        assert res.status == "optimal"
        # inscribed: its forces are feasible for the exact cones (up to Clarabel's 1e-8)
        assert res.sigma >= exact * (1 - 1e-7)
        for contact, f in zip(grasp.contacts, res.forces):
            assert contact.contains(f + np.array([1e-7 * res.forces[:, 0].max(), 0, 0, 0]),
                                    tol=0.0)
        gaps.append(res.sigma / exact - 1)
        assert math.isnan(res.sigma_lower)       # the LP certifies nothing about the exact cones
    assert gaps[0] > gaps[1] > gaps[2] >= -1e-7
    # at 64 faces the soft-finger generators are ~5.6 deg apart in azimuth and 5.3 deg in
    # latitude, so every facet is within cos(4 deg) = 1 - 2.4e-3 of the ellipsoid: the friction
    # lost, and the extra force, is a few 1e-3 (measured 1.1e-3 for L1, 4.8e-4 for Linf)
    assert gaps[2] <= 5e-3


def test_osqp_reports_its_own_status():
    grasp = box_grasp()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # qpsolvers warns when OSQP stops early
        results = [pyramid.min_force(grasp, w, "L1", solver="osqp") for w in wrenches(10, 4)]
    assert all(r.status in ("optimal", "max_iter", "inaccurate") for r in results)
    assert all(r.method == "osqp-pyramid" for r in results)
    for r in results:
        if r.status == "max_iter":
            assert r.iterations >= 4000        # OSQP's default limit, not a silent stop


@pytest.mark.parametrize("solve", [
    lambda g, w: clarabel_socp.min_force(g, w, "L1"),
    lambda g, w: clarabel_socp.min_force(g, w, "Linf", "full"),
    lambda g, w: pyramid.min_force(g, w, "L1", solver="clarabel"),
])
def test_infeasible_wrench(solve):
    # two point contacts cannot resist a torque about the axis through them
    res = solve(two_finger_pinch(), [0, 0, 0, 1.0, 0, 0])
    assert res.status == "infeasible" and not res.feasible
    assert res.sigma == math.inf and not res.forces.any()


def test_bad_input():
    grasp = box_grasp()
    with pytest.raises(ValueError, match="magnitude"):
        pyramid.min_force(grasp, np.ones(6), "L1", "full")
    with pytest.raises(ValueError, match="faces"):
        pyramid.min_force(grasp, np.ones(6), faces=2)
    with pytest.raises(ValueError, match="norm"):
        clarabel_socp.min_force(grasp, np.ones(6), "L2")
    with pytest.raises(ValueError, match="w_ext"):
        clarabel_socp.min_force(grasp, [0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError, match="w_ext"):
        clarabel_socp.Prepared(grasp).solve(np.ones(5))
