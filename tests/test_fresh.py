"""A grasp or a pair of shapes made per query: the programs built from templates and closed forms
equal the generic compiler's, array for array, and the contacts' frames are numpy's."""
import math
import pickle

import numpy as np
import pytest
from grasp_cases import random_grasp, random_wrench

import graspforce as gf
from graspforce.grasping import wrench_space as WS
from graspforce.geometry.sets import _compile

OBJECTIVES = [(norm, magnitude) for norm in ("L1", "Linf") for magnitude in ("normal", "full")]


def same_bits(a, b):
    """Equal arrays, zeros' signs included."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(
        a.view(np.int64), b.view(np.int64))


def reference_matrix(c):
    """G_i as the contact made it with numpy before (argmin, np.linalg.norm, np.cross)."""
    n = c.normal
    axis = np.zeros(3)
    axis[np.argmin(np.abs(n))] = 1.0
    o = axis - (axis @ n) * n
    o /= np.linalg.norm(o)
    R = np.column_stack((n, o, np.cross(n, o)))
    G = np.zeros((6, 4))
    G[:3, :3] = R
    G[3:, :3] = np.cross(c.position, R.T).T
    G[3:, 3] = n
    return G


def test_contact_frames_are_numpys_bit_for_bit():
    rng = np.random.default_rng(5)
    for i in range(3000):
        p = rng.normal(size=3) * 10.0 ** rng.uniform(-3, 1)
        n = rng.normal(size=3) * 10.0 ** rng.uniform(-3, 3)
        if i % 4 == 0:
            n[rng.integers(3)] = (0.0, -0.0)[i % 8 // 4]       # ties and signed zeros
        if i % 5 == 0:
            n[1] = n[0]
        if i % 9 == 0:
            p[:] = 0.0
        c = gf.Contact(p, n, 0.5, 0.01)
        assert same_bits(c.normal, n / np.linalg.norm(n))
        assert same_bits(c.matrix, reference_matrix(c)), (p, n)
        assert same_bits(c.frame, c.matrix[:3, :3])
        assert same_bits(c.tangents[0], c.matrix[:3, 1])
        assert same_bits(c.tangents[1], c.matrix[:3, 2])


def seeded_grasp(seed, m):
    return random_grasp(np.random.default_rng(seed), m, kinds=("soft", "point", "frictionless"))


def same_kinds(grasp, seed):
    """Another grasp whose contacts have the kinds of `grasp`'s, in order, and other values."""
    rng = np.random.default_rng(seed)
    contacts = []
    for c in grasp.contacts:
        mu = 0.0 if c.mu == 0.0 else rng.uniform(0.2, 1.0)
        mu_s = rng.uniform(0.005, 0.05) if c.mu_spin > 0.0 else 0.0
        contacts.append(gf.Contact(rng.normal(0, 0.05, 3), rng.normal(size=3), mu, mu_s))
    return gf.Grasp(contacts)


def check_same_target(fast, generic):
    fi, ff = fast.set.program
    gi, gfl = generic.set.program
    assert isinstance(fast.set, WS._ContactsRoot) and not isinstance(generic.set, WS._ContactsRoot)
    assert same_bits(fi, gi)
    assert same_bits(ff, gfl)
    assert same_bits(fast.compiled_args[2], generic.compiled_args[2])    # the force reader
    assert same_bits(fast.compiled_args[3], generic.compiled_args[3])    # the span
    assert fast.ray_dims == generic.ray_dims
    assert fast.compiled_args[0] is fi and fast.compiled_args[1] is ff
    assert list(fast.set._witness_slots) == list(generic.set._witness_slots)
    assert fast.set.witness_size == generic.set.witness_size
    assert (fast.set.dim, fast.t_scale, fast.extra, fast.packed_size) == (
        generic.set.dim, generic.t_scale, generic.extra, generic.packed_size)
    # the template's set, whose tree is built when read, compiles to the same program
    ti, tf = _compile(fast.set)[0]
    assert same_bits(ti, gi) and same_bits(tf, gfl)
    assert len(fast.set.leaves()) == len(generic.set.leaves())


@pytest.mark.parametrize("m", range(1, 9))
@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_template_targets_equal_the_generic_compile(m, norm, magnitude):
    WS._TEMPLATES.clear()
    for seed in range(6):
        grasp = seeded_grasp(100 * m + seed, m)
        # the template comes from another grasp of the same kinds
        # (a rank-deficient grasp's: in the span of its wrenches, and in R^6 for loads outside)
        seed_space = same_kinds(grasp, seed + 1)._space(norm, magnitude)
        for method in ("zc-ie", "gjk"):
            for full in (False, True):
                seed_space.target(method, full)
        for method in ("zc-ie", "gjk"):
            for full in (False, True):
                space = grasp._space(norm, magnitude)
                fast = space.target(method, full)
                lifted = fast.t_scale != 1
                span = None if full else space.span
                generic = WS.generic_target(grasp.contacts, norm, magnitude,
                                            grasp.contact_matrices, space.spin_weight, lifted,
                                            grasp.length, span)
                check_same_target(fast, generic)


@pytest.mark.parametrize("norm, magnitude", OBJECTIVES)
def test_template_grasps_answer_as_generic_ones(norm, magnitude):
    rng = np.random.default_rng(11)
    for seed in range(8):
        grasp = seeded_grasp(seed, 1 + seed % 5)
        w = random_wrench(rng)
        same_kinds(grasp, seed)._space(norm, magnitude).target("zc-ie")      # the template
        fast = grasp.min_force(w, norm, magnitude)
        WS._TEMPLATES.clear()
        again = gf.Grasp(grasp.contacts)
        generic = again.min_force(w, norm, magnitude)        # a new structure: the generic path
        assert (fast.status, fast.iterations) == (generic.status, generic.iterations)
        assert fast.sigma == generic.sigma or (math.isinf(fast.sigma) and
                                               math.isinf(generic.sigma))
        assert same_bits(fast.forces, generic.forces)
        assert repr(fast.shot.witnesses) == repr(generic.shot.witnesses)


def test_template_sets_pickle_and_read_as_trees():
    grasp = seeded_grasp(3, 4)
    same_kinds(grasp, 9).wrench_set("Linf", "normal")
    W = grasp.wrench_set("Linf", "normal")
    assert repr(W) == "MinkowskiSum(dim=6)"
    copy = pickle.loads(pickle.dumps(W))
    u = np.arange(1.0, 7.0)
    assert copy.support(u)[0] == W.support(u)[0]
    h, s, witness = W.support_witness(u)
    assert np.allclose(W.witness_point(witness), s, rtol=0, atol=1e-15)


def random_primitive(rng, kind):
    if kind == "ball":
        return gf.Ball(rng.normal(0, 0.01, 3), rng.uniform(0.05, 0.2))
    if kind == "ellipsoid":
        Q = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        return gf.Ellipsoid(rng.normal(0, 0.01, 3), Q @ np.diag(rng.uniform(0.05, 0.3, 3)))
    if kind == "box":
        return gf.Box(rng.uniform(0.05, 0.3, 3))
    if kind == "cone":
        return gf.TruncatedCone(rng.uniform(0.0, 0.2), rng.uniform(0.05, 0.2),
                                rng.uniform(0.05, 0.4))
    if kind == "polytope":
        V = rng.normal(size=(8, 3)) * 0.1
        return gf.Polytope(V - V.mean(axis=0))             # the centroid is interior
    return gf.Capsule(rng.uniform(0.02, 0.1), rng.uniform(0.0, 0.3))


KINDS = ("ball", "ellipsoid", "box", "cone", "polytope", "capsule")


@pytest.mark.parametrize("kind_a", KINDS)
@pytest.mark.parametrize("kind_b", KINDS)
def test_delta_templates_equal_the_generic_compile(kind_a, kind_b):
    from graspforce.growth import growth as GR
    rng = np.random.default_rng(KINDS.index(kind_a) * 10 + KINDS.index(kind_b))
    GR._DELTA_TEMPLATES.clear()
    # the default settings, then others (every entry of the tail's settings different)
    settings = [dict(warm_start=False), dict(method="ie", eps=1e-6, max_iter=77,
                                             touching_tol=1e-4, warm_start=True),
                dict(method="zc-ie", eps=3e-8, max_iter=500, touching_tol=0.0, warm_start=True)]
    for i in range(4):
        A, B = random_primitive(rng, kind_a), random_primitive(rng, kind_b)
        if i == 0:
            gf.GrowthDistance(A, B)          # the template, from another pair
            continue
        solver = gf.GrowthDistance(A, B, **settings[i - 1])
        ints, floats = solver._ints, solver._floats
        generic = gf.minkowski_sum(gf.affine(np.eye(3), A), gf.affine(-np.eye(3), B))
        gi, gfl = generic.program
        assert same_bits(ints, gi)
        assert same_bits(floats[:len(gfl)], gfl)
        delta = solver.delta                            # made when read
        assert delta._program[1] is floats
        assert list(delta._witness_slots) == list(generic._witness_slots)
        assert delta.witness_size == generic.witness_size
        ci, cf = _compile(delta)[0]                     # its tree, built when read
        assert same_bits(ci, gi) and same_bits(cf, gfl)
        assert same_bits(floats[len(gfl):], np.concatenate((
            [GR.param_start(gi, 1) + 2, GR.param_start(gi, GR.children(gi, 0)[1]) + 2,
             generic.witness_size, GR.METHODS[solver.method], solver.max_iter,
             float(solver.warm_start), solver.eps, solver.touching_tol, 0.0, GR.WARM_SPREAD],
            np.zeros(3))))
        assert solver._size == GR.FRAME + GR.capacity(3, generic.witness_size)


def test_closed_form_origin_verdicts_agree_with_facet_expansion():
    from graspforce.growth import growth as GR
    from graspforce.grasping.quality import facet_expansion
    rng = np.random.default_rng(2)
    decided = 0
    shift = lambda X, t: gf.affine(np.eye(3), X, t)       # noqa: E731
    for i in range(300):
        kind = KINDS[i % len(KINDS)]
        X = random_primitive(rng, kind)
        if kind in ("ball", "ellipsoid") and i % 3 == 0:
            X = gf.Ellipsoid(rng.normal(0, 0.2, 3), X.shape)      # the origin anywhere
        if i % 7 == 0:
            X = gf.Ellipsoid(np.zeros(3), rng.normal(size=(3, 2)))     # flat
        if i % 11 == 0:
            Q = np.linalg.qr(rng.normal(size=(3, 3)))[0]
            Q *= np.sign(np.linalg.det(Q))
            X = gf.affine(Q, X)
        if i % 13 == 0:
            X = shift(X, rng.normal(0, 0.3, 3))          # not closed form: left to expansion
        verdict = GR._origin_verdict(X)
        if verdict is not None:
            decided += 1
            assert verdict == facet_expansion(X, 0.0, GR.ORIGIN_TOL, 500, True)[0], X
    assert decided > 150


def test_growth_distance_keeps_composite_pairs_and_sets_up_primitives_per_call():
    rng = np.random.default_rng(5)
    pose_a = (np.eye(3), np.zeros(3))
    pose_b = (np.linalg.qr(rng.normal(size=(3, 3)))[0], np.array([0.0, 0.0, 0.3]))
    pose_b[0][:] *= np.sign(np.linalg.det(pose_b[0]))
    cone = gf.TruncatedCone(0.03, 0.01, 0.08)
    for A, kept in ((gf.Ellipsoid(np.zeros(3), np.diag([0.05, 0.03, 0.02])), False),
                    (gf.Capsule(0.02, 0.04), True)):
        first, again = (gf.growth_distance(A, pose_a, cone, pose_b) for _ in range(2))
        assert (first._raw[0] is again._raw[0]) == kept
        alone = gf.GrowthDistance(A, cone, warm_start=False)(pose_a, pose_b)
        assert (first.sigma, first.sigma_lower, first.sigma_upper, first.status) == (
            alone.sigma, alone.sigma_lower, alone.sigma_upper, alone.status) == (
            again.sigma, again.sigma_lower, again.sigma_upper, again.status)
