"""W_Linf's lift (graspforce.grasping.wrench_space): the set that min_force's IE and ZC-IE shoot at
for norm "Linf", C = CH(U_i {e_i - c} x CH({0} U W_i)) in R^(m + 5), against W_Linf itself and the
closed-form supports of truth.py."""
import numpy as np
import pytest
import truth as T
from grasp_cases import plain, random_grasp, random_wrench
from grasps import box_grasp

import graspforce as gf
from graspforce.grasping.wrench_space import LIFT_MAX_CONTACTS, LIFTED_METHODS

# truth.min_force_socp's accuracy (tests/test_grasp_forces.py, SOCP_TOL)
SOCP_TOL = 5e-8


def lift(grasp, magnitude):
    """W_Linf's lift of the grasp's contacts in the grasp's own units (min_force shoots it in
    the units (force, torque / L), Grasp.length)."""
    return gf.Grasp(grasp.contacts, length=1.0)._space("Linf", magnitude).target("ie").set


@pytest.mark.parametrize("magnitude", ["normal", "full"])
def test_lift_meets_the_ray_where_the_sum_does(magnitude):
    # m t' on the lift along (0, r) is t on W_Linf along r: both shot to 1e-12, and the lift's
    # support in (mu, u) is max_i (mu . e_i + h_Ai(u)), which truth's closed forms bound
    rng = np.random.default_rng(3)
    hits = 0
    for m in range(2, LIFT_MAX_CONTACTS + 1):
        grasp = random_grasp(rng, m)
        C, W = lift(grasp, magnitude), grasp.wrench_set("Linf", magnitude)
        assert (C.dim, W.dim) == (m + 5, 6)
        for _ in range(5):
            r = -random_wrench(rng)
            on_W = gf.ray_shoot(W, r, method="ie", eps=1e-12)
            on_C = gf.ray_shoot(C, np.concatenate((np.zeros(m - 1), r)), eps=1e-12)
            assert on_W.hit == on_C.hit
            # the truth: an SOCP for the least Linf forces resisting -r (t = 1 / sigma)
            status, truth, _, _ = T.min_force_socp(plain(grasp), -r, "Linf", magnitude)
            assert on_W.hit == (status == "optimal")
            if on_W.hit:
                hits += 1
                assert abs(1.0 / (m * on_C.t) / truth - 1) <= SOCP_TOL
                assert m * on_C.t == pytest.approx(on_W.t, rel=3e-12)
                # the wrench part u of the lift's normal bounds W_Linf from outside: t <= h_W(u)
                # / u.r <= m t'_upper (MinForce.shot)
                u = on_C.normal[-6:]
                bound = T.grasp_support(plain(grasp), u, "Linf", magnitude) / (u @ r)
                assert on_W.t <= bound * (1 + 1e-12)
                assert bound <= m * on_C.t_upper * (1 + 1e-12)
    assert hits >= 5


def test_ie_does_not_repeat_a_vertex_at_the_numerical_floor():
    # full magnitude, 3 contacts, eps at the floor (3e-12): IE's updated inverse drifts, so a
    # support point equal to a vertex of the facet can still look beyond it by ~1e-10; the step
    # then replaced that vertex by itself, forever (max_iter). The step now refactors instead
    # (core/shooting/zc_family.hpp). Rays within 1e-9 of one that did this
    rng = np.random.default_rng(3)
    # the case found: the fifth of five wrenches on the second random grasp (2, then 3 contacts)
    random_grasp(rng, 2)
    for _ in range(5):
        random_wrench(rng)
    grasp = random_grasp(rng, 3)
    for _ in range(4):
        random_wrench(rng)
    r = -random_wrench(rng)
    C = lift(grasp, "full")
    W = grasp.wrench_set("Linf", "full")
    truth = gf.ray_shoot(W, r, method="ie", eps=1e-12)
    status, sigma, _, _ = T.min_force_socp(plain(grasp), -r, "Linf", "full")
    assert status == "optimal" and abs(1.0 / truth.t / sigma - 1) <= SOCP_TOL
    gf.ray_shoot(C, np.concatenate((np.zeros(2), r)))     # the second shot builds the table
    gf.ray_shoot(C, np.concatenate((np.zeros(2), r)))
    for k in range(20):
        r_k = r * (1.0 + 1e-9 * np.random.default_rng(k).normal(size=6))
        shot = gf.ray_shoot(C, np.concatenate((np.zeros(2), r_k)), eps=3e-12, max_iter=3000)
        assert shot.hit, (k, shot)
        assert 3 * shot.t == pytest.approx(truth.t, rel=1e-8)


def test_which_methods_and_grasps_shoot_the_lift():
    four = box_grasp()
    six = gf.Grasp(list(four.contacts) + list(four.contacts[:2]))
    eight = gf.Grasp(list(six.contacts) + list(four.contacts[2:4]))
    nine = gf.Grasp(list(eight.contacts) + [four.contacts[0]])
    for method in gf.METHODS:
        # zc-ie shoots W_Linf itself where every contact has friction, with its finish
        lifted = method in LIFTED_METHODS and method != "zc-ie"
        assert four._space("Linf", "normal").target(method).set.dim == (9 if lifted else 6)
        assert six._space("Linf", "normal").target(method).set.dim == (11 if lifted else 6)
        assert eight._space("Linf", "normal").target(method).set.dim == (13 if lifted else 6)
        assert four._space("L1", "normal").target(method).set.dim == 6
        assert nine._space("Linf", "normal").target(method).set.dim == 6
    # point contacts and two soft fingers too; a frictionless contact, the full magnitude, or
    # a grasp shot in its wrenches' span keeps the lift
    points = gf.Grasp([gf.Contact(c.position, c.normal, c.mu) for c in six.contacts])
    assert points._space("Linf", "normal").target("zc-ie").set.dim == 6
    two = gf.Grasp([gf.Contact([0.05, 0.0, 0.0], [-1.0, 0.0, 0.0], 0.5, 0.01),
                    gf.Contact([-0.05, 0.0, 0.0], [1.0, 0.0, 0.0], 0.5, 0.01)])
    assert two._space("Linf", "normal").span is None          # soft: spin spans the sixth
    assert two._space("Linf", "normal").target("zc-ie").set.dim == 6
    c = six.contacts[0]
    frictionless = gf.Grasp([gf.Contact(c.position, c.normal, 0.0)] + list(six.contacts[1:]))
    assert frictionless._space("Linf", "normal").target("zc-ie").set.dim == 11
    assert six._space("Linf", "full").target("zc-ie").set.dim == 11
    pinch = gf.Grasp([gf.Contact(c.position, c.normal, c.mu) for c in four.contacts[:2]])
    assert pinch._space("Linf", "normal").span.shape == (5, 6)
    assert pinch._space("Linf", "normal").target("zc-ie").set.dim == 5 + 1


def test_lift_halves_ie_steps_on_the_ingot():
    # the reason for the lift (docs/design.md, "W_Linf's lift"): IE's cutting planes model each
    # contact's set, not their sum. Same wrenches, same answers, steps counted by the shooters
    # (the paper's ZC-IE: zc-ie's finish on the sum takes the sum's steps down too)
    from benchmarks.grasp_sets import ingot_grasp, random_wrenches
    grasp = ingot_grasp()
    W = grasp.wrench_set("Linf")
    C = lift(grasp, "normal")
    steps_W, steps_C = [], []
    for w in random_wrenches(40, 2):
        res = grasp.min_force(w, norm="Linf")
        on_W = gf.ray_shoot(W, -w, method="zc-ie-paper")
        assert res.sigma == pytest.approx(1.0 / on_W.t, rel=2e-9)
        status, truth, _, _ = T.min_force_socp(plain(grasp), w, "Linf", "normal")
        assert status == "optimal" and abs(res.sigma / truth - 1) <= SOCP_TOL
        steps_W.append(on_W.iterations)
        steps_C.append(gf.ray_shoot(C, np.concatenate((np.zeros(3), -w)),
                                    method="zc-ie-paper").iterations)
    assert np.median(steps_C) <= 0.6 * np.median(steps_W)


@pytest.mark.parametrize("magnitude", ["normal", "full"])
def test_second_order_finish_on_the_lift(magnitude):
    # the lift's contact sets are embeddings [0; I] of the R^6 ones
    # (graspforce.geometry._kernel.EMBED): ZC-IE-Newton's pieces, curvature and flat leaves pass
    # through them (core/geometry/piece.hpp).
    # Rays towards points of lam_1 W_1 + ... + lam_m W_m (0 < lam_i < 1), inside W_Linf; contacts
    # with friction, at least three (two contacts never hold an object in closure, and rays near
    # the boundary of their wrench cone stall ZC)
    rng = np.random.default_rng(5)
    for m in range(3, LIFT_MAX_CONTACTS + 1):
        grasp = random_grasp(rng, m, kinds=("soft", "point"))
        C = lift(grasp, magnitude)
        W = grasp.wrench_set("Linf", magnitude)
        for _ in range(4):
            r = sum(rng.uniform(0.2, 1.0) * W_i.support(rng.normal(size=6))[1]
                    for W_i in grasp.contact_sets(magnitude))
            on_W = gf.ray_shoot(W, r, method="ie", eps=1e-12)
            on_C = gf.ray_shoot(C, np.concatenate((np.zeros(m - 1), r)), method="zc-ie-newton",
                                eps=1e-12)
            assert on_W.hit and on_C.hit
            assert m * on_C.t == pytest.approx(on_W.t, rel=3e-12)
            status, truth, _, _ = T.min_force_socp(plain(grasp), -r, "Linf", magnitude)
            assert status == "optimal" and abs(1.0 / (m * on_C.t) / truth - 1) <= SOCP_TOL
