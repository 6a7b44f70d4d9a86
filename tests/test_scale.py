"""Units do not change answers: the same problems with lengths and forces scaled by 1e-9 and 1e9
give answers scaled accordingly. Force closure is invariant (scaling lengths scales W's torque
coordinates, an invertible linear map of R^6); the quality of a uniformly scaled W scales with
it; min_force's sigma scales with the forces; the growth distance is scale-free. Tolerances
inside the library must be relative to the problem's own size for any of this to hold."""
import math

import numpy as np
import pytest
import truth as T
from grasp_cases import plain, random_grasp, random_wrench
from grasps import box_grasp, two_finger_pinch

import graspforce as gf
from graspforce.grasping.quality import grasp_quality

SCALES = [1e-9, 1e9]
OBJECTIVES = [("L1", "normal"), ("Linf", "normal"), ("L1", "full"), ("Linf", "full")]


def scaled_grasp(grasp, s):
    """The grasp with every length (positions, the spin coefficient mu_s, in metres) times s."""
    return gf.Grasp([gf.Contact(np.asarray(c.position) * s, c.normal, c.mu, c.mu_spin * s)
                     for c in grasp.contacts])


def scaled_wrench(w, length, force):
    """A wrench in units scaled by `length` and `force`: forces times force, torques times both."""
    w = np.asarray(w, dtype=float)
    return np.concatenate((w[:3] * force, w[3:] * (length * force)))


def closure_cases():
    rng = np.random.default_rng(31)
    grasps = [box_grasp(), two_finger_pinch()]
    grasps += [random_grasp(rng, m, ("soft", "point")) for m in (2, 3, 3, 4, 4, 5, 6)]
    return grasps


@pytest.mark.parametrize("s", SCALES)
def test_force_closure_does_not_depend_on_the_unit_of_length(s):
    answers = []
    for grasp in closure_cases():
        base = grasp.is_force_closure()
        assert scaled_grasp(grasp, s).is_force_closure() == base, (s, grasp.contacts)
        answers.append(base)
    # the cases hold both answers
    assert any(answers) and not all(answers)


@pytest.mark.parametrize("s", SCALES)
def test_quality_of_a_uniformly_scaled_wrench_set_scales_with_it(s):
    # W scaled by s in every coordinate (the grasp map of contacts at lengths s, measured in
    # units of s): the largest ball in s W has radius s Q, and facet expansion's bracket follows
    for grasp in closure_cases()[:5]:
        for norm, magnitude in (("L1", "normal"), ("Linf", "full")):
            W = grasp.wrench_set(norm, magnitude)
            sW = gf.affine(s * np.eye(6), W)
            base = grasp_quality(W, norm, magnitude, 1e-3, 1e-9, 300)
            big = grasp_quality(sW, norm, magnitude, 1e-3, 1e-9, 300)
            assert big.force_closure == base.force_closure
            if base.force_closure:
                assert big.lower == pytest.approx(s * base.lower, rel=1e-9)
                assert big.upper == pytest.approx(s * base.upper, rel=1e-9)
                assert big.iterations == base.iterations
            else:
                assert big.value == base.value == 0.0


@pytest.mark.parametrize("s", SCALES)
def test_grasp_quality_at_any_unit_of_length_is_certified(s):
    # lengths alone scaled: W's torques scale by s, so Q changes, but the answer stays a
    # certified bracket: upper = h_W(u) for its direction, recomputed with truth's support, and
    # lower <= upper; closure as at unit scale
    for grasp in closure_cases()[:5]:
        base = grasp.quality()
        g = scaled_grasp(grasp, s)
        q = g.quality()
        assert q.force_closure == base.force_closure
        if q.force_closure:
            h = T.grasp_support(plain(g), q.direction, "L1", "normal")
            assert q.upper == pytest.approx(h, rel=1e-12)
            assert 0.0 < q.lower <= q.upper and q.upper - q.lower <= 1e-3 * q.upper
        else:
            assert q.value == 0.0


@pytest.mark.parametrize("s", SCALES)
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_min_force_scales_with_the_forces(norm, magnitude, s):
    # the load in units of force times s: sigma, sigma_lower and the forces scale by s, the
    # status does not change; every method. (Lengths are not scaled here: that maps W by
    # diag(1, 1, 1, s, s, s), and a ray shot to a Euclidean eps in coordinates 1e9 apart is a
    # different numerical problem; closure and quality above are checked under it.)
    rng = np.random.default_rng(7)
    grasps = [box_grasp(), random_grasp(rng, 3, ("soft", "point")),
              random_grasp(rng, 4, ("soft", "point"))]
    statuses = set()
    for grasp in grasps:
        for _ in range(3):
            w = random_wrench(rng, force=2.0, torque=0.1)
            ws = scaled_wrench(w, 1.0, s)
            for method in gf.METHODS:
                base = grasp.min_force(w, norm, magnitude, method=method)
                res = grasp.min_force(ws, norm, magnitude, method=method)
                assert res.status == base.status, (method, base.sigma, res.sigma)
                statuses.add(res.status)
                if base.status != "optimal":
                    assert res.sigma == base.sigma == math.inf
                    continue
                # both brackets hold the same minimum (times s) and are eps wide (the start
                # table and rounding take the two shots along different paths); each is
                # certified to the rounding of its points (FACET_HOLDS, 1e-12 relative), so two
                # may miss each other by that much, not more
                assert res.sigma_lower <= s * base.sigma * (1 + 1e-12)
                assert s * base.sigma_lower <= res.sigma * (1 + 1e-12)
                assert res.sigma == pytest.approx(s * base.sigma, rel=2e-9)
                assert np.linalg.norm(res.resultant + ws) <= 1e-9 * np.linalg.norm(ws)
                assert np.abs(res.forces).max() <= 10 * res.sigma
    assert statuses == {"optimal", "infeasible"}


def length_cases():
    """(grasp, wrenches): soft and point contacts, force-closure or not (the pinch resists no
    torque about the line through its contacts: its last wrench is infeasible)."""
    rng = np.random.default_rng(17)
    grasps = [box_grasp(), two_finger_pinch(), random_grasp(rng, 3, ("soft", "point")),
              random_grasp(rng, 4, ("soft", "point")), random_grasp(rng, 2, ("point",))]
    cases = []
    for grasp in grasps:
        wrenches = [random_wrench(rng, force=2.0, torque=0.1) for _ in range(3)]
        if len(grasp) == 2:
            wrenches.append(np.array([0.0, 0.0, -1.0, 0.05, 0.0, 0.0]))
        cases.append((grasp, wrenches))
    return cases


def units(length):
    """The diagonal of the map (force, torque) -> (force, torque / length)."""
    return np.r_[1.0, 1.0, 1.0, np.full(3, 1.0 / length)]


# (length, force) scales: lengths alone, and lengths with forces
LENGTH_FORCE = [(1e-9, 1.0), (1e9, 1.0), (1e-9, 1e-9), (1e9, 1e9), (1e-9, 1e9)]


@pytest.mark.parametrize("length, force", LENGTH_FORCE)
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_min_force_with_lengths_scaled(norm, magnitude, length, force):
    # positions and mu_s times `length`, the load's forces times `force` and its torques times
    # both: the grasp's length L follows (a power of two within a factor 2 of the scaled one), so
    # the shot is the same problem in the units (force, torque / L). Sigma scales with the
    # forces, the status does not change, and so do the forces (the spin moment f_4 with
    # length too); each answer carries its certificate in those units (docs/grasp-api.md)
    statuses = set()
    for grasp, wrenches in length_cases():
        g = scaled_grasp(grasp, length)
        assert 0.5 * length <= g.length / grasp.length <= 2.0 * length
        for w in wrenches:
            ws = scaled_wrench(w, length, force)
            for method in gf.METHODS:
                ctx = (method, len(grasp), w)
                base = grasp.min_force(w, norm, magnitude, method=method)
                res = g.min_force(ws, norm, magnitude, method=method)
                assert res.status == base.status, ctx
                statuses.add(res.status)
                if base.status != "optimal":
                    assert res.sigma == base.sigma == math.inf, ctx
                    continue
                assert res.sigma == pytest.approx(force * base.sigma, rel=2e-9), ctx
                assert res.sigma_lower <= res.sigma * (1 + 1e-9), ctx
                assert res.sigma / res.sigma_lower - 1 <= 1e-9 + 1e-15, ctx
                # forces in their cones that resist the load to 1e-9 in the units (force,
                # torque / L)
                for c, f in zip(g.contacts, res.forces):
                    assert T.cone_excess(c, f) <= 1e-12, (ctx, f)
                resultant = sum(G @ f for (G, _, _), f in zip(plain(g), res.forces))
                D = units(g.length)
                assert np.linalg.norm(D * (resultant + ws)) <= 1e-9 * np.linalg.norm(D * ws), ctx
                # the forces in the unscaled units are an answer to the unscaled problem: in
                # equilibrium with w and of objective base.sigma; where the minimum is unique (two
                # point contacts, docs/grasp-api.md) they are the unscaled answer's
                back = res.forces / (np.r_[1.0, 1.0, 1.0, length] * force)
                resultant = sum(G @ f for (G, _, _), f in zip(plain(grasp), back))
                D = units(grasp.length)
                assert np.linalg.norm(D * (resultant + w)) <= 2e-9 * np.linalg.norm(D * w), ctx
                assert T.contact_objective(back, plain(grasp), norm, magnitude) == \
                    pytest.approx(base.sigma, rel=2e-9), ctx
                if len(grasp) == 2 and all(c.kind == "point" for c in grasp.contacts):
                    assert np.abs(back - base.forces).max() <= 1e-6 * base.sigma, (ctx, back)
    assert statuses == {"optimal", "infeasible"}


@pytest.mark.parametrize("length, force", LENGTH_FORCE)
def test_min_force_with_lengths_scaled_agrees_with_an_socp(length, force):
    # an independent check: Clarabel on the scaled problem written in the units (force / F,
    # torque / (F L)) and with the spin moment f_4 / L for f_4 (its cone's mu_s / L for mu_s),
    # where it is as well conditioned as the unscaled one (in the grasp's own units it is not:
    # torque rows 1e18 apart from force rows; and Clarabel's tolerances are absolute). Not on
    # two contacts: their loads lie on or off the boundary of the cone of wrenches they resist,
    # where Clarabel stops short of a verdict at any scale
    for grasp, wrenches in length_cases():
        if len(grasp) == 2:
            continue
        g = scaled_grasp(grasp, length)
        L = g.length
        D = units(L)
        P = [(D[:, None] * G * np.r_[1.0, 1.0, 1.0, L], mu, mu_s / L) for G, mu, mu_s in plain(g)]
        for w in wrenches:
            ws = scaled_wrench(w, length, force)
            for norm, magnitude in OBJECTIVES:
                res = g.min_force(ws, norm, magnitude)
                status, sigma, _, _ = T.min_force_socp(P, D * ws / force, norm, magnitude)
                assert res.status == status, (norm, magnitude, w)
                if status == "optimal":
                    assert res.sigma == pytest.approx(force * sigma, rel=5e-8), \
                        (norm, magnitude, w)


def test_grasp_length_default_and_given():
    grasp = box_grasp()
    # the RMS lever arm sqrt(|p_i|^2 + mu_si^2) is 0.0524 m here: 2 x 0.0524 -> 0.125
    assert grasp.length == 0.125
    assert scaled_grasp(grasp, 2.0 ** 30).length == 2.0 ** 27
    assert gf.Grasp([gf.Contact(np.zeros(3), [0, 0, 1], 0.5)]).length == 1.0
    given = gf.Grasp(grasp.contacts, length=0.3)
    assert given.length == 0.3
    w = np.array([0.3, -1.0, 2.0, 0.05, -0.1, 0.02])
    assert given.min_force(w).sigma == pytest.approx(grasp.min_force(w).sigma, rel=2e-9)
    for bad in (0.0, -1.0, math.inf, math.nan, 5e-324, 1e-300, 0.125e-6 / 1.01, 0.125e6 * 1.01,
                1e300):
        with pytest.raises(ValueError, match="length"):
            gf.Grasp(grasp.contacts, length=bad)
    for good in (0.125e-6, 0.125e6):
        assert gf.Grasp(grasp.contacts, length=good).length == good


def growth_pairs():
    """(A, B, pose_a, pose_b) built by a function of the scale s: balls, a ball and a box, a
    polytope whose origin facet expansion decides, an off-centre ellipsoid and a capsule."""
    rng = np.random.default_rng(3)
    V = rng.normal(size=(12, 3))
    V -= V.mean(axis=0)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    S = np.diag([1.0, 0.5, 0.3])

    def make(s):
        I = np.eye(3)
        return [
            (gf.Ball(np.zeros(3), 1e-10 * s), gf.Ball(np.zeros(3), 1e-10 * s),
             (I, np.zeros(3)), (I, np.array([4e-10, 0.0, 0.0]) * s)),
            (gf.Ball(np.zeros(3), s), gf.Box(np.array([0.5, 0.3, 0.2]) * s),
             (I, np.zeros(3)), (Q, np.array([2.0, 1.0, -0.5]) * s)),
            (gf.Polytope(V * s), gf.Ellipsoid(np.array([0.9, 0.0, 0.0]) * s, S * s),
             (Q, np.array([0.3, 0.2, 0.1]) * s), (I, np.array([-4.0, 1.0, 2.0]) * s)),
            (gf.Capsule(0.2 * s, 1.0 * s), gf.Polytope(V * s),
             (I, np.zeros(3)), (Q.T, np.array([0.5, 0.2, 0.3]) * s)),
        ]
    return make


@pytest.mark.parametrize("s", [1e-9, 1e-3, 1e9])
def test_growth_distance_is_scale_free(s):
    make = growth_pairs()
    for (A, B, pa, pb), (sA, sB, spa, spb) in zip(make(1.0), make(s)):
        for method in gf.METHODS:
            base = gf.growth_distance(A, pa, B, pb, method=method)
            res = gf.growth_distance(sA, spa, sB, spb, method=method)
            assert res.status == base.status
            assert res.sigma == pytest.approx(base.sigma, rel=2e-9)
            assert res.sigma_lower <= res.sigma <= res.sigma_upper
    # two balls of radius 1e-10 (at this s too) 4e-10 apart, centre to centre: g = 2
    A, B, pa, pb = make(s)[0]
    assert gf.growth_distance(A, pa, B, pb).sigma == pytest.approx(2.0, rel=1e-9)
    assert math.isfinite(gf.growth_distance(A, pa, B, pb).sigma)
