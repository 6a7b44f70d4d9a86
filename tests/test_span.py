"""min_force on grasps whose wrenches do not span R^6 (two point contacts, one contact): shot at
the image of W in the span (graspforce.grasping.wrench_space.wrench_span), the answers are the
full-dimensional set's within eps and the SOCP's, certified in R^6; a load outside the span is
answered on the full-dimensional set; batch rows equal single calls."""
import math

import numpy as np
import pytest
import truth as T
from grasp_cases import plain
from test_certificates import EPS, METHODS, OBJECTIVES, check_answer

import graspforce as gf
from graspforce.grasping import wrench_space as WS
from graspforce.geometry import _kernel as K
from graspforce.geometry.sets import Affine


def tilted(v, rng, degrees):
    """v turned by up to `degrees` about a random axis."""
    axis = np.cross(v, rng.normal(size=3))
    axis /= np.linalg.norm(axis)
    a = np.deg2rad(rng.uniform(0.0, degrees))
    return v * math.cos(a) + np.cross(axis, v) * math.sin(a)


def pinch(seed):
    """Two point contacts facing each other across a 2-8 cm object, normals tilted up to 10
    degrees, the line between them turned at random: rank 5."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=3)
    d /= np.linalg.norm(d)
    half = rng.uniform(0.01, 0.04) * d
    centre = rng.normal(0.0, 0.02, 3)
    return gf.Grasp([gf.Contact(centre + half, tilted(-d, rng, 10.0), rng.uniform(0.3, 1.0)),
                     gf.Contact(centre - half, tilted(d, rng, 10.0), rng.uniform(0.3, 1.0))])


def single(kind):
    mu, mu_s = {"soft": (0.6, 0.02), "point": (0.6, 0.0), "frictionless": (0.0, 0.0)}[kind]
    return gf.Grasp([gf.Contact([0.02, -0.01, 0.03], [0.1, -0.2, -1.0], mu, mu_s)])


# (grasp, k): the rank of the contacts' maps
CASES = ([(pinch(seed), 5) for seed in range(4)]
         + [(single("soft"), 4), (single("point"), 3), (single("frictionless"), 1),
            (gf.Grasp([gf.Contact([0.03, 0, 0], [-1, 0, 0], 0.0),
                       gf.Contact([-0.03, 0, 0], [1, 0.1, 0], 0.0)]), 2)])


def loads(grasp, rng):
    """(w, label): loads the contacts resist (from forces in their cones), in the span but not
    resisted (the span's part of a random wrench), and each moved off the span by 1e-6 of its
    size."""
    span = grasp._space("L1", "normal").span
    out = []
    for _ in range(2):
        f = []
        for c in grasp.contacts:
            t = rng.normal(size=3) * np.array([0.0, c.mu, c.mu]) / math.sqrt(2.0)
            f.append([1.0 + rng.uniform(), *(t[1:] if c.mu > 0 else (0.0, 0.0)),
                      c.mu_spin * rng.uniform(-0.5, 0.5)])
        out.append((-sum(c.matrix @ fi for c, fi in zip(grasp.contacts, f)), "resisted"))
    # the span is in the units (force, torque / L) the sets are shot in (Grasp.length)
    units = np.r_[1.0, 1.0, 1.0, np.full(3, grasp.length)]
    w = np.r_[rng.normal(0.0, 5.0, 3), rng.normal(0.0, 0.3, 3)] / units
    out.append((units * (span.T @ (span @ w)), "span"))
    off = units * np.linalg.svd(span.T)[0][:, -1]          # a direction outside the span
    out += [(w + 1e-6 * np.linalg.norm(w) * off / np.linalg.norm(off), label + " off")
            for w, label in out]
    return out


def full_dimensional(grasp, monkeypatch):
    """A grasp of the same contacts whose min_force shoots at the sets in R^6 (no span)."""
    with monkeypatch.context() as m:
        m.setattr(WS, "wrench_span", lambda kinds, values, length: None)
        other = gf.Grasp(grasp.contacts)
        for norm, magnitude in OBJECTIVES:
            assert other._space(norm, magnitude).span is None
    return other


@pytest.mark.parametrize("case", range(len(CASES)))
def test_rank_deficient_grasps_shoot_in_the_span(case, monkeypatch):
    grasp, k = CASES[case]
    P = plain(grasp)
    full = full_dimensional(grasp, monkeypatch)
    rng = np.random.default_rng(case)
    m = len(grasp)
    for w, label in loads(grasp, rng):
        margin = T.resist_margin(P, w)
        off = label.endswith("off")
        for norm, magnitude in OBJECTIVES:
            status, socp, _, _ = T.min_force_socp(P, w, norm, magnitude)
            for method in METHODS:
                ctx = (case, label, norm, magnitude, method)
                res = grasp.min_force(w, norm, magnitude, method=method)
                ref = full.min_force(w, norm, magnitude, method=method)
                check_answer(grasp, P, w, res, margin, ctx)
                shot = res.shot
                if off:
                    # answered on the full-dimensional set: the same shot, in R^6 (or the lift)
                    assert not isinstance(shot.convex_set, Affine), ctx
                    assert (res.status, res.sigma, res.iterations) == (
                        "infeasible", math.inf, ref.iterations), ctx
                    assert ref.status == "infeasible", ctx
                    continue
                A = shot.convex_set
                lifted = norm == "Linf" and method in WS.LIFTED_METHODS and m > 1
                assert isinstance(A, Affine) and A.dim == k + (m - 1 if lifted else 0), ctx
                if case < 4 and magnitude == "normal" and (norm == "L1" or lifted):
                    # a pinch's ellipses, bare or lifted: their loop under the projection
                    assert A.program[0][-1] == K.PROJECTED_ELLIPSE_HULL, ctx
                r = np.zeros(A.matrix.shape[1])
                r[-6:] = -w
                assert np.allclose(shot.r, A.matrix @ r, rtol=0, atol=1e-15 * np.abs(w).max())
                assert res.status == ref.status or "max_iter" in (res.status, ref.status), \
                    (ctx, res.status, ref.status)
                if res.status == ref.status == "optimal":
                    assert abs(res.sigma / ref.sigma - 1) <= 2 * EPS, (ctx, res.sigma, ref.sigma)
                if res.status == "optimal" and status == "optimal":
                    assert abs(res.sigma / socp - 1) <= 1e-6, (ctx, res.sigma, socp)


def test_the_rule_and_the_rank():
    for grasp, k in CASES:
        assert grasp._space("L1", "normal").span.shape == (k, 6)
    # two point contacts whose normals meet the line between them: rank 5 all the same
    assert gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5),
                     gf.Contact([-0.05, 0, 0], [1, 0, 0], 0.5)])._space("Linf", "full") \
        .span.shape == (5, 6)
    # a soft finger's spin moment makes the torque about the line: R^6
    soft = gf.Grasp([gf.Contact([0.05, 0, 0], [-1, 0, 0], 0.5, 0.01),
                     gf.Contact([-0.05, 0, 0], [1, 0, 0], 0.5)])
    assert soft._space("L1", "normal").span is None
    # more than two contacts with six force components or more are not examined, even when
    # deficient (three point contacts on a line), and are shot in R^6 as before
    line = gf.Grasp([gf.Contact([x, 0, 0], [0, 0, 1], 0.5) for x in (-0.04, 0.0, 0.04)])
    assert line._space("L1", "normal").span is None
    w = np.array([0.0, 0.0, -5.0, 0.0, 0.1, 0.0])
    res = line.min_force(w)
    status, socp, _, _ = T.min_force_socp(plain(line), w, "L1", "normal")
    assert res.status == status == "optimal" and abs(res.sigma / socp - 1) <= 1e-6
    # fewer than six components: examined whatever the number of contacts
    flat = gf.Grasp([gf.Contact(p, [0, 0, 1], 0.0) for p in ([-0.04, 0, 0], [0, 0.03, 0],
                                                             [0.04, 0, 0])])
    assert flat._space("L1", "normal").span.shape == (3, 6)


@pytest.mark.parametrize("norm", ["L1", "Linf"])
@pytest.mark.parametrize("magnitude", ["normal", "full"])
def test_batch_rows_equal_single_calls_in_and_off_the_span(norm, magnitude):
    rng = np.random.default_rng(7)
    for grasp, _ in CASES[:2] + CASES[5:6]:
        wrenches = np.array([w for w, _ in loads(grasp, rng)] + [np.zeros(6)])
        for method in ("zc-ie", "gjk"):
            for w in wrenches[:2]:
                grasp.min_force(w, norm, magnitude, method=method)   # the start table built
            batch = gf.batch.min_force(grasp, wrenches, norm=norm, magnitude=magnitude,
                                       method=method, forces=True, threads=2)
            for i, w in enumerate(wrenches):
                one = grasp.min_force(w, norm, magnitude, method=method)
                assert (batch.sigma[i], batch.sigma_lower[i], batch.status_names[i],
                        batch.iterations[i]) == (one.sigma, one.sigma_lower, one.status,
                                                 one.iterations), (method, i)
                assert np.array_equal(batch.forces[i], one.forces), (method, i)
            grasps = [gf.Grasp(grasp.contacts) for _ in range(2)]
            for w in wrenches:
                many = gf.batch.min_force_grasps(grasps, w, norm=norm, magnitude=magnitude,
                                                 method=method, forces=True)
                first = gf.Grasp(grasp.contacts).min_force(w, norm, magnitude, method=method)
                assert (many.sigma[0], many.status_names[0], many.iterations[0]) == (
                    first.sigma, first.status, first.iterations)
                assert np.array_equal(many.forces[0], first.forces)


def test_projected_templates_are_their_own():
    # a template made from a projected target serves only grasps projected to the same
    # dimension; the same contacts' kinds in R^6 (outside loads) get the template of W
    WS._TEMPLATES.clear()
    a, b = pinch(10), pinch(11)
    w = np.array([0.0, 0.0, -5.0, 0.0, 0.0, 0.0])
    for grasp in (a, b):
        grasp.min_force(w)
        grasp.min_force(w + [0, 0, 0, 1.0, 0.5, 0.2])          # outside the span: R^6
    kinds = ((1, 1), "normal", False, False)
    assert {key for key in WS._TEMPLATES} == {kinds + (5,), kinds + (6,)}
    assert isinstance(b._space("L1", "normal").target("zc-ie").set, WS._ContactsProjection)
    assert isinstance(b._space("L1", "normal").target("zc-ie", True).set, WS._ContactsHull)
