"""The exit of a ray from the hull of two 3-D ellipsoids in R^6 in closed form
(core/shooting/pair_exit.hpp): zc-ie's answer on two soft fingers (W_L1 of normal magnitude) once
the set has a start table, and on any such hull. Checked as every answer is: its certificate
recomputed from the returned forces and normal (test_certificates.check_answer), the minimum
against the SOCP's and against the paper's ZC-IE on the same loads; degenerate answers (a finger
without force) are left to ZC-IE, whose answer must be the same."""
import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import build
from grasp_cases import plain, random_grasp, random_wrench
from test_certificates import MARGIN, check_answer

SOCP_TOL = 5e-8        # the SOCP's own accuracy (truth.min_force_socp)
EPS = 1e-9             # min_force's default eps


def pinch(rng):
    """Two soft fingers on opposite faces of a box, normals exactly opposed (a parallel-jaw
    grasp): the optimal face mostly holds one finger's whole ellipsoid."""
    half = rng.uniform(0.01, 0.04)
    mu, mu_s = rng.uniform(0.3, 1.0), rng.uniform(0.002, 0.02)
    center = rng.uniform(-0.1, 0.1, 3)
    return gf.Grasp([gf.Contact(center + [0.0, -half, 0.0], [0.0, 1.0, 0.0], mu, mu_s),
                     gf.Contact(center + [0.0, half, 0.0], [0.0, -1.0, 0.0], mu, mu_s)])


def loads(rng, grasp, k):
    """k loads: two in three resisted by construction (minus the wrench of forces drawn inside
    the fingers' cones, some near the cones' boundary), the others wrenches at random of three
    sizes (resisted or not)."""
    out = []
    for i in range(k):
        if i % 3 == 2:
            out.append(random_wrench(rng, force=rng.choice([0.5, 5.0, 50.0]), torque=0.1))
            continue
        w = np.zeros(6)
        for c in grasp.contacts:
            fn = rng.uniform(0.5, 10.0)
            share = rng.normal(size=3)
            share *= rng.choice([0.3, 0.9, 0.999]) / np.linalg.norm(share)
            f = np.array([fn, c.mu * fn * share[0], c.mu * fn * share[1],
                          c.mu_spin * fn * share[2]])
            w -= c.matrix @ f
        out.append(w)
    return out


@pytest.mark.parametrize("make", [pinch, lambda rng: random_grasp(rng, 2, ("soft",), tilt=0.5)],
                         ids=["pinch", "random"])
@pytest.mark.parametrize("seed", range(6))
def test_two_soft_fingers_exit_in_closed_form(make, seed):
    rng = np.random.default_rng(700 + seed)
    grasp = make(rng)
    P = plain(grasp)
    W = loads(rng, grasp, 40)
    for w in W[:2]:
        grasp.min_force(w)          # the set's start table, from which the exit starts
    optimal = calls = calls_paper = 0
    for i, w in enumerate(W):
        res = grasp.min_force(w)
        margin = T.resist_margin(P, w)
        ctx = (seed, i, margin)
        status = check_answer(grasp, P, w, res, margin, ctx)
        if status != "optimal" or margin < MARGIN:
            continue
        optimal += 1
        socp_status, truth, _, _ = T.min_force_socp(P, w, "L1", "normal")
        assert socp_status == "optimal", ctx
        assert abs(res.sigma - truth) <= SOCP_TOL * truth, (ctx, res.sigma, truth)
        ref = grasp.min_force(w, method="zc-ie-paper")
        assert ref.status == "optimal", ctx
        assert abs(res.sigma - ref.sigma) <= 2 * EPS * ref.sigma, (ctx, res.sigma, ref.sigma)
        # the closed form calls the support map once, for its certificate, after the first point
        # on the ray (a start table's, or ZC's search from the origin: ~7 calls)
        assert res.support_calls <= ref.support_calls, ctx
        calls += res.support_calls
        calls_paper += ref.support_calls
    assert optimal >= 10
    assert calls <= 0.5 * calls_paper, (calls, calls_paper)


def test_a_finger_without_force_is_left_to_zc_ie():
    # a load that one finger resists alone, pushing along its normal: the other finger's force
    # is zero, its region's apex, where the face's normal is not unique. ZC-IE answers.
    rng = np.random.default_rng(3)
    grasp = pinch(rng)
    P = plain(grasp)
    G = grasp.contacts[0].matrix
    for w in loads(rng, grasp, 2):
        grasp.min_force(w)
    for scale in (0.1, 1.0, 10.0):
        w = -scale * G[:, 0]
        res = grasp.min_force(w)
        assert res.status == "optimal"
        check_answer(grasp, P, w, res, T.resist_margin(P, w), scale)
        assert res.sigma == pytest.approx(scale, rel=2 * EPS)
        assert res.support_calls > 1
        forces = np.asarray(res.forces)
        assert abs(forces[1, 0]) <= 1e-9 * scale and forces[0, 0] == pytest.approx(scale)


def test_ray_shoot_at_a_hull_of_two_ellipsoids():
    # the same closed form for any hull of two 3-D ellipsoids in R^6 (the origin inside or not):
    # the hit against the SOCP's truth, certified as every shot (weights reproduce t r, the bound
    # within eps)
    rng = np.random.default_rng(11)
    for trial in range(8):
        d = T.hull(*(T.ell(rng.normal(0.0, 1.0 if trial % 2 else 0.2, 6), rng.normal(size=(6, 3)))
                     for _ in range(2)))
        A = build(d)
        calls = calls_paper = 0
        for i in range(25):
            r = rng.normal(size=6)
            res = gf.ray_shoot(A, r)
            ref = gf.ray_shoot(A, r, method="zc-ie-paper")
            hit, t, t_up = T.ray_shoot_socp(d, r)
            assert res.hit == hit, (trial, i)
            if not hit:
                continue
            assert abs(res.t - t) <= 1e-8 * t, (trial, i, res.t, t)
            assert res.t <= res.t_upper <= res.t * (1 + EPS)
            assert np.linalg.norm(np.asarray(res.weights) @ np.asarray(res.vertices) - res.t * r) \
                <= 1e-9 * res.t * np.linalg.norm(r)
            assert res.t <= t_up * (1 + 1e-9)
            assert abs(res.t - ref.t) <= 2 * EPS * ref.t
            calls += res.support_calls
            calls_paper += ref.support_calls
        assert calls <= 0.5 * calls_paper, (trial, calls, calls_paper)
