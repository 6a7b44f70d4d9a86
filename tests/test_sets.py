"""Convex sets: support functions and support points against closed forms and brute force,
witnesses, leaves, operators (hull, Minkowski sum, affine with non-square M, -A, pose)."""
import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import build, check_witness, random_ellipsoid, random_rotation


def unit_dirs(rng, n, k):
    u = rng.standard_normal((k, n))
    return u / np.linalg.norm(u, axis=1, keepdims=True)


def sphere_samples(rng, k, m):
    x = rng.standard_normal((m, k))
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def check_support(A, d, u, h_exact=None, samples=None, sample_gap=None):
    """h = A.support(u): equal to the closed form, >= every sample, and within sample_gap of the
    best sample; the support point p is a point of A (via its witness) with u.p = h."""
    h, p = A.support(u)
    h2, p2, wit = A.support_witness(u)
    scale = max(1.0, abs(h))
    assert abs(h - h2) <= 1e-15 * scale and np.array_equal(p, p2)
    assert abs(u @ p - h) <= 1e-12 * scale, f"u.s_A(u) = {u @ p!r} != h_A(u) = {h!r}"
    if h_exact is None:
        h_exact = T.support(d, u)
    assert abs(h - h_exact) <= 1e-12 * scale, f"h_A(u) = {h!r}, closed form {h_exact!r}"
    if samples is not None:
        best = np.max(samples @ u)
        assert h >= best - 1e-12 * scale, f"h_A(u) = {h!r} < a sampled point's {best!r}"
        assert h - best <= sample_gap, f"h_A(u) - best sample = {h - best:.3e} > {sample_gap:.1e}"
    check_witness(A, d, p, wit, what=f"support point for u={u.tolist()}")
    return h, p


# ----------------------------------------------------------------------------------------------
# primitives
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [2, 3, 5, 8])
def test_polytope_support_exact(n):
    rng = np.random.default_rng(100 + n)
    V = rng.standard_normal((3 * n + 4, n))
    A = gf.Polytope(V)
    d = T.poly(V)
    assert A.dim == n
    for u in unit_dirs(rng, n, 50):
        h, p = check_support(A, d, u, h_exact=np.max(V @ u))
        assert any(np.array_equal(p, v) for v in V), "support point is not a vertex"
    # the witness local is the vertex index
    h, p, wit = A.support_witness(unit_dirs(rng, n, 1)[0])
    ((leaf, local),) = wit
    assert leaf == 0 and np.array_equal(V[int(local)], p)


@pytest.mark.parametrize("nk", [(2, 2), (3, 3), (3, 2), (3, 1), (4, 2), (6, 3)])  # (3, 3), (6, 3): unrolled
def test_ellipsoid_support_brute_force(nk):
    n, k = nk
    rng = np.random.default_rng(200 + 10 * n + k)
    c, S = random_ellipsoid(rng, n, k)
    A = gf.Ellipsoid(c, S)
    d = T.ell(c, S)
    assert A.dim == n
    X = sphere_samples(rng, k, 20000)
    P = c + X @ S.T
    # 20000 samples of the k-sphere: the largest angular gap is small; the support of an
    # ellipsoid exceeds the best sample by at most ||S^T u|| (1 - cos gap) (<= 2e-2 for k = 3).
    for u in unit_dirs(rng, n, 20):
        gap = np.linalg.norm(S.T @ u) * (2e-2 if k == 3 else 1e-4 if k == 2 else 1e-15)
        h, p = check_support(A, d, u, h_exact=c @ u + np.linalg.norm(S.T @ u), samples=P,
                             sample_gap=gap + 1e-12)


def test_ball():
    rng = np.random.default_rng(3)
    c = rng.standard_normal(4)
    A = gf.Ball(c, 0.7)
    d = T.ball(c, 0.7)
    for u in unit_dirs(rng, 4, 20):
        h, p = check_support(A, d, u, h_exact=c @ u + 0.7)
        assert np.allclose(p, c + 0.7 * u, atol=1e-14)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_box_support_exact(n):
    """Corners enumerated: exact."""
    rng = np.random.default_rng(300 + n)
    half = rng.uniform(0.2, 2.0, n)
    center = rng.standard_normal(n)
    R = random_rotation(rng, n)
    corners = np.array(np.meshgrid(*[[-1.0, 1.0]] * n)).reshape(n, -1).T * half
    for A, d, W in ((gf.Box(half), T.box(half), corners),
                    (gf.Box(half, center=center, rotation=R), T.box(half, center, R),
                     center + corners @ R.T)):
        assert A.dim == n
        for u in unit_dirs(rng, n, 30):
            h, p = check_support(A, d, u, h_exact=np.max(W @ u))
            assert np.min(np.linalg.norm(W - p, axis=1)) <= 1e-12 * max(1, np.abs(W).max())


def rim_samples(rb, rt, h, m):
    th = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    circ = np.column_stack([np.cos(th), np.sin(th)])
    bottom = np.column_stack([rb * circ, np.full(m, -h / 2)])
    top = np.column_stack([rt * circ, np.full(m, h / 2)])
    return np.vstack([bottom, top])


@pytest.mark.parametrize("dims", [(1.0, 0.4, 2.0), (0.7, 0.7, 3.0), (1.0, 0.0, 1.5),
                                  (0.0, 0.8, 1.0), (0.3, 1.2, 0.5)],
                         ids=["truncated", "cylinder", "cone", "inverted-cone", "flared"])
def test_truncated_cone_support(dims):
    """h(u) = max(h/2 u_z + r_t q, -h/2 u_z + r_b q), q = ||(u_x, u_y)||; cylinder:
    |u_z| h/2 + r q; cone (r_t = 0): max(h/2 u_z, -h/2 u_z + r_b q). Brute force: 2 x 10000
    points on the rims (the set is their hull)."""
    rb, rt, hgt = dims
    A = gf.TruncatedCone(rb, rt, hgt)
    d = T.tcone(rb, rt, hgt)
    assert A.dim == 3
    rng = np.random.default_rng(400)
    P = rim_samples(rb, rt, hgt, 10000)
    for u in np.vstack([unit_dirs(rng, 3, 40), np.eye(3), -np.eye(3)]):
        q = np.hypot(u[0], u[1])
        if rb == rt:
            h_cf = abs(u[2]) * hgt / 2 + rb * q
        elif rt == 0.0:
            h_cf = max(hgt / 2 * u[2], -hgt / 2 * u[2] + rb * q)
        else:
            h_cf = max(hgt / 2 * u[2] + rt * q, -hgt / 2 * u[2] + rb * q)
        # rim spacing 2 pi / 10000: gap <= r (1 - cos(pi / 10000)) < 5e-8 r
        check_support(A, d, u, h_exact=h_cf, samples=P, sample_gap=5e-8 * max(rb, rt) + 1e-12)


@pytest.mark.parametrize("radius,length", [(0.5, 2.0), (1.0, 0.0), (0.2, 3.0)])
def test_capsule_support(radius, length):
    """h(u) = |u_z| L/2 + radius ||u||; brute force: two hemispheres' worth of sphere samples
    around both end points."""
    A = gf.Capsule(radius, length)
    d = T.capsule(radius, length)
    assert A.dim == 3
    rng = np.random.default_rng(500)
    X = sphere_samples(rng, 3, 20000) * radius
    P = np.vstack([X + [0, 0, length / 2], X - [0, 0, length / 2]])
    for u in np.vstack([unit_dirs(rng, 3, 30), [[0, 0, 1.0], [0, 0, -1.0]]]):
        u = u * 1.7          # not unit: h is positively homogeneous
        h_cf = abs(u[2]) * length / 2 + radius * np.linalg.norm(u)
        h, p = check_support(A, d, u, h_exact=h_cf, samples=P,
                             sample_gap=2e-2 * radius * np.linalg.norm(u) + 1e-12)
        assert T.capsule_contains(radius, length, p)


def test_support_is_positively_homogeneous_and_zero_direction():
    rng = np.random.default_rng(9)
    c, S = random_ellipsoid(rng, 3)
    A = gf.hull(gf.Ellipsoid(c, S), gf.Polytope(rng.standard_normal((5, 3))))
    u = rng.standard_normal(3)
    h1, _ = A.support(u)
    h2, _ = A.support(3.5 * u)
    assert abs(h2 - 3.5 * h1) <= 1e-12 * abs(h2)


# ----------------------------------------------------------------------------------------------
# operators
# ----------------------------------------------------------------------------------------------
def operator_cases():
    rng = np.random.default_rng(600)
    c3, S3 = random_ellipsoid(rng, 3)
    V3 = rng.standard_normal((6, 3))
    c4, S4 = random_ellipsoid(rng, 4, 2)
    R = random_rotation(rng, 3)
    p = rng.standard_normal(3)
    cases = {
        "hull": T.hull(T.ell(c3, S3), T.poly(V3), T.ball([2.0, 0, 0], 0.3)),
        "sum": T.msum(T.ell(c3, S3), T.poly(V3), T.box([0.1, 0.2, 0.3])),
        "affine_3x4": T.affine(rng.standard_normal((3, 4)), T.ell(c4, S4), t=[1.0, 2.0, 3.0]),
        "affine_2x3": T.affine(rng.standard_normal((2, 3)), T.hull(T.poly(V3), T.ell(c3, S3))),
        "affine_5x3": T.affine(rng.standard_normal((5, 3)), T.poly(V3), t=np.arange(5.0)),
        "neg": T.neg(T.hull(T.ell(c3, S3), T.poly(V3))),
        "pose_tcone": T.affine(R, T.tcone(1.0, 0.5, 2.0), t=p),
        "pose_box": T.affine(R, T.box([0.5, 1.0, 1.5]), t=p),
        "nested": T.hull(T.msum(T.ell(c3, S3), T.neg(T.poly(V3))),
                         T.affine(R, T.tcone(0.3, 0.6, 1.0), t=p), T.poly(V3 + 1.0)),
        "sum_of_hulls": T.msum(T.hull(T.poly(V3), T.ball(np.zeros(3), 1.0)),
                               T.hull(T.ell(c3, S3), T.tcone(0.5, 0.5, 1.0))),
        # [0; I]: the embeddings of min_force's Linf lift, compiled to an offset read
        "embed_5x3": T.affine(np.vstack((np.zeros((2, 3)), np.eye(3))),
                              T.hull(T.ell(c3, S3), T.poly(V3)), t=[1.0, -2.0, 0.5, 0.0, 3.0]),
        "embed_in_hull": T.hull(T.poly(rng.standard_normal((3, 7))),
                                T.affine(np.vstack((np.zeros((1, 6)), np.eye(6))),
                                         T.msum(T.ell(*random_ellipsoid(rng, 6, 3)),
                                                T.box(np.full(6, 0.1))), t=np.arange(7.0)),
                                T.affine(np.vstack((np.zeros((4, 3)), np.eye(3))),
                                         T.affine(R, T.tcone(0.3, 0.6, 1.0), t=p))),
        # [0; I] over CH({0} U X): one kernel node (_kernel.ORIGIN_EMBED); X off the origin, so
        # that some directions choose the origin and some X
        "origin_embed": T.affine(np.vstack((np.zeros((2, 3)), np.eye(3))),
                                 T.hull(T.poly(np.zeros((1, 3))), T.ell(c3 + 2.0, S3)),
                                 t=[1.0, -2.0, 0.0, 0.0, 0.0]),
        "origin_embeds_in_hull": T.hull(*[
            T.affine(np.vstack((np.zeros((1, 6)), np.eye(6))),
                     T.hull(T.poly(np.zeros((1, 6))), T.ell(c + 2.0, S)), t=np.r_[e, np.zeros(6)])
            for e, (c, S) in ((-0.5, random_ellipsoid(rng, 6, 3)),
                              (0.5, random_ellipsoid(rng, 6, 3)))]),
        # 6 x 4: the unrolled product of soft fingers' full-magnitude wrench sets G_i D U_i (6 x 3,
        # point contacts', takes the general loop)
        "affine_6x4": T.affine(rng.standard_normal((6, 4)), T.ell(c4, S4), t=np.arange(6.0)),
        "affine_6x3_in_hull": T.hull(
            T.affine(rng.standard_normal((6, 3)), T.hull(T.poly(V3), T.ell(c3, S3))),
            T.affine(rng.standard_normal((6, 4)), T.poly(rng.standard_normal((5, 4))),
                     t=-np.arange(6.0))),
    }
    return cases


OPS = operator_cases()


def build_op(name, d):
    """Like conftest.build, but -A and pose go through the library's own operators."""
    if name == "neg":
        return -build(d[3])
    if name.startswith("pose"):
        return gf.pose(build(d[3]), d[1], d[2])
    return build(d)


@pytest.mark.parametrize("name", sorted(OPS))
def test_operator_support(name):
    """Support of hull = max, of sum = sum, of M A + t = h_A(M^T u) + t.u (truth.support),
    and every support point maps back through its witness."""
    d = OPS[name]
    A = build_op(name, d)
    n = T.dim(d)
    assert A.dim == n
    rng = np.random.default_rng(700)
    for u in unit_dirs(rng, n, 40):
        check_support(A, d, u)


def test_only_strict_embeddings_compile_to_offset_reads():
    # [0; I] with zero rows is EMBED; a square identity stays AFFINE, because growth distance
    # rewrites its poses' matrices in place (core/growth/growth.hpp), and so does a near-embedding
    from graspforce.geometry import _kernel as K
    inner = gf.Ball(np.zeros(3), 1.0)
    M = np.vstack((np.zeros((2, 3)), np.eye(3)))
    near = M.copy()
    near[0, 1] = 1e-300
    for matrix, kind in ((M, K.EMBED), (np.eye(3), K.AFFINE), (near, K.AFFINE),
                         (np.vstack((np.eye(3), np.zeros((2, 3)))), K.AFFINE)):
        ints, _ = gf.affine(matrix, inner).program
        assert ints[1] == kind


def test_embedded_origin_hulls_compile_to_one_node():
    # an embedding of CH({0} U X) written hull(Polytope([[0, ..]]), X) is one ORIGIN_EMBED node
    # over X; the origin keeps its witness slot. An origin elsewhere, or second, is not fused
    from graspforce.geometry import _kernel as K
    X = gf.Ball(np.full(3, 2.0), 1.0)
    M = np.vstack((np.zeros((2, 3)), np.eye(3)))
    fused = gf.affine(M, gf.hull(gf.Polytope(np.zeros((1, 3))), X))
    ints, _ = fused.program
    assert ints[0] == 2 and list(ints[1:3]) == [K.ORIGIN_EMBED, K.ELLIPSOID]
    assert fused.witness_size == 2 + 4
    # directions that choose the origin, then X: the witness names the origin, then the ball
    h, point, witness = fused.support_witness(np.array([0.0, 0.0, -1.0, -1.0, -1.0]))
    assert h == 0.0 and not point.any() and witness == ((0, 0),)
    h, point, witness = fused.support_witness(np.array([0.0, 0.0, 1.0, 1.0, 1.0]))
    assert witness[0][0] == 1 and h == pytest.approx(6.0 + np.sqrt(3.0), rel=1e-15)
    for origin in (np.ones((1, 3)), np.zeros((2, 3))):
        ints, _ = gf.affine(M, gf.hull(gf.Polytope(origin), X)).program
        assert ints[1] == K.EMBED
    ints, _ = gf.affine(M, gf.hull(X, gf.Polytope(np.zeros((1, 3))))).program
    assert ints[1] == K.EMBED


def _support_by(plan, A, u):
    """(h, point, witness vector) of A in direction u, evaluated by `plan`
    (graspforce.geometry._kernel)."""
    from graspforce.geometry import _kernel as K
    ints, floats = A.program
    ints = ints.copy()
    ints[-1] = plan
    point, wit = np.empty(A.dim), np.empty(A.witness_size)
    h = K.support(ints, floats.copy(), u, point, wit)
    return h, point, wit


def test_ellipsoid_hulls_take_one_loop_that_matches_the_general_passes():
    # the wrench sets of soft fingers (ellipsoids in R^6 with 3 axes: ELLIPSOID_HULL) and of
    # point contacts (2 axes: ELLIPSE_HULL), bare (W_L1) or lifted (W_Linf's lift, the origin
    # winning for directions that all cones oppose), and their affine images (a rank-deficient
    # grasp's sets in its span: PROJECTED_*): the plan's loop gives the four passes' value,
    # point and witnesses; anything else keeps the passes (graspforce.geometry._kernel)
    from graspforce.geometry import _kernel as K
    from graspforce.grasping.wrench_space import lift_rows, lift_summand
    rng = np.random.default_rng(25)
    sets = []
    for axes, plan, projected in ((3, K.ELLIPSOID_HULL, K.PROJECTED_ELLIPSOID_HULL),
                                  (2, K.ELLIPSE_HULL, K.PROJECTED_ELLIPSE_HULL)):
        W = [gf.Ellipsoid(*random_ellipsoid(rng, 6, axes, c_scale=1.0)) for _ in range(4)]
        lift = gf.hull(*[lift_summand(W_i, e) for W_i, e in zip(W, lift_rows(4))])
        # a span's basis Q (6, 5): the lift's image keeps its contact coordinates
        Q = np.linalg.qr(rng.standard_normal((6, 5)))[0]
        lift_map = np.block([[np.eye(3), np.zeros((3, 6))], [np.zeros((5, 3)), Q.T]])
        sets += [(W, plan, gf.hull(*W), None), (W, plan, lift, None),
                 (W, projected, gf.affine(Q.T, gf.hull(*W), rng.standard_normal(5)), Q),
                 (W, projected, gf.affine(lift_map, lift), Q)]
    for W, plan, A, Q in sets:
        assert A.program[0][-1] == plan
        dirs = unit_dirs(rng, A.dim, 200)
        # the lift's origins: the wrench part against the cones (in a span, its coordinates
        # Q^T), the contact coordinates zero or large, which picks one contact's embedding
        against = -np.mean([w.center for w in W], 0)
        if Q is not None:
            against = Q.T @ against
        lead = A.dim - against.size
        ahead = np.vstack((np.zeros(lead), 10.0 * rng.standard_normal((20, lead))))
        dirs = np.vstack((dirs, np.hstack((ahead, np.tile(against, (21, 1))))))
        origins = 0
        for u in dirs:
            h, point, wit = _support_by(plan, A, u)
            h_ref, point_ref, wit_ref = _support_by(K.GENERAL, A, u)
            assert abs(h - h_ref) <= 1e-14 * max(1.0, abs(h_ref))
            assert np.abs(point - point_ref).max() <= 1e-14 * max(1.0, np.abs(point_ref).max())
            flags = wit_ref == np.round(wit_ref)
            assert np.abs(wit - wit_ref).max() <= 1e-14 * max(1.0, np.abs(wit_ref).max())
            assert (wit[flags] == wit_ref[flags]).all()
            # the origin chosen: no ellipsoid's slot (1 + k entries; an origin's has 2) flagged
            origins += not any(wit[start] for start, size in A._witness_slots if size > 2)
        if A.dim > 6:
            assert origins >= 2
    mixed = gf.hull(gf.Ellipsoid(*random_ellipsoid(rng, 6, 3)),
                    gf.Ellipsoid(*random_ellipsoid(rng, 6, 2)))
    with_ball = gf.hull(gf.Ellipsoid(*random_ellipsoid(rng, 6, 3)), gf.Ball(np.zeros(6), 1.0))
    in_3d = gf.hull(gf.Ellipsoid(*random_ellipsoid(rng, 3, 3)), gf.Ball(np.zeros(3), 1.0))
    for A in (mixed, with_ball, in_3d, gf.minkowski_sum(*W)):
        assert A.program[0][-1] == K.GENERAL


def test_linf_sums_take_one_loop_that_matches_the_general_passes():
    # W_Linf itself, a sum of hulls CH({0} U E_i) with the origin first (ORIGIN_ELLIPSOID_SUM
    # for soft fingers, ORIGIN_ELLIPSE_SUM for point contacts): the plan's loop gives the passes'
    # value, point and witnesses bit for bit, including directions where some E_i lie behind the
    # origin and a tie at h_{E_i} = 0; the origin second, or off 0, keeps the passes
    from graspforce.geometry import _kernel as K
    rng = np.random.default_rng(27)
    for axes, plan in ((3, K.ORIGIN_ELLIPSOID_SUM), (2, K.ORIGIN_ELLIPSE_SUM)):
        W = [gf.Ellipsoid(*random_ellipsoid(rng, 6, axes, c_scale=1.0)) for _ in range(5)]
        A = gf.minkowski_sum(*[gf.hull(gf.Polytope(np.zeros((1, 6))), E) for E in W])
        assert A.program[0][-1] == plan
        # a direction where E_0's support is exactly 0 (its centre's part cancels ||S^T u||)
        E = W[0]
        u = rng.standard_normal(6)
        u -= E.center * (E.center @ u + np.linalg.norm(E.shape.T @ u)) / (E.center @ E.center)
        dirs = np.vstack((unit_dirs(rng, 6, 300), [u]))
        chosen = set()
        for u in dirs:
            h, point, wit = _support_by(plan, A, u)
            h_ref, point_ref, wit_ref = _support_by(K.GENERAL, A, u)
            assert h == h_ref and (point == point_ref).all() and (wit == wit_ref).all()
            chosen.add(tuple(wit[start] for start, size in A._witness_slots if size > 2))
        # both the origin and E_i won for every contact over these directions
        assert all(len({c[i] for c in chosen}) == 2 for i in range(len(W)))
    W = [gf.Ellipsoid(*random_ellipsoid(rng, 6, 3)) for _ in range(3)]
    second = gf.minkowski_sum(*[gf.hull(E, gf.Polytope(np.zeros((1, 6)))) for E in W])
    off = gf.minkowski_sum(*[gf.hull(gf.Polytope(np.ones((1, 6))), E) for E in W])
    for A in (second, off):
        assert A.program[0][-1] == K.GENERAL


def test_posed_sums_take_one_loop_that_matches_the_general_passes():
    # growth distance's Delta = R_A(A_0) - R_B(B_0) and any sum of leaves under 3x3 maps: the
    # plan's loop (graspforce.geometry._kernel.POSED_SUM) gives the passes' value, point and
    # witnesses for every leaf, in registers (3-axis ellipsoids, truncated cones) or by the
    # passes' leaf code
    from graspforce.geometry import _kernel as K
    rng = np.random.default_rng(26)
    leaves = [gf.Ellipsoid(*random_ellipsoid(rng, 3, 3)), gf.Ball(np.zeros(3), 0.7),
              gf.TruncatedCone(0.6, 0.2, 1.1), gf.TruncatedCone(0.5, 0.0, 0.8),
              gf.TruncatedCone(0.4, 0.4, 1.5), gf.Box([0.3, 0.5, 0.7]),
              gf.Polytope(rng.standard_normal((12, 3))),
              gf.Ellipsoid(*random_ellipsoid(rng, 3, 2)), gf.ConeCap(0.5, 3)]
    for i, A in enumerate(leaves):
        B = leaves[(i + 2) % len(leaves)]
        R_a, R_b = random_rotation(rng, 3), random_rotation(rng, 3)
        posed = [gf.affine(R_a, A, rng.standard_normal(3)),
                 gf.affine(-R_b, B, rng.standard_normal(3)), gf.affine(R_b, leaves[i - 1])]
        sums = [gf.minkowski_sum(*posed[:2]), gf.minkowski_sum(*posed)]
        for D in sums:
            assert D.program[0][-1] == K.POSED_SUM
            # random directions, and the ones where the leaves' own branches meet: a cone's or
            # a cap's axis, a box's faces and edges (zero entries in its local frame)
            special = [R @ e for R in (R_a, -R_b) for e in np.vstack((np.eye(3), -np.eye(3),
                                                                        [[1, 1, 0], [0, 1, -1]]))]
            dirs = np.vstack((unit_dirs(rng, 3, 200), special, np.zeros((1, 3))))
            for j, u in enumerate(dirs):
                h, point, wit = _support_by(K.POSED_SUM, D, u)
                h_ref, point_ref, wit_ref = _support_by(K.GENERAL, D, u)
                scale = max(1.0, np.abs(point_ref).max())
                assert abs(h - h_ref) <= 1e-14 * scale
                if j < 200:
                    assert np.abs(point - point_ref).max() <= 1e-14 * scale
                    assert np.abs(wit - wit_ref).max() <= 1e-14 * max(1.0, np.abs(wit_ref).max())
                else:
                    # a face's direction: rounding picks one of its points (the cone's rim point
                    # on its axis follows the last bits of (u_x, u_y)); any is right if it is
                    # the point its witness names, and supporting
                    assert abs(u @ point - h) <= 1e-14 * scale
                    named = D.witness_point(D.decode_witness(wit))
                    assert np.abs(named - point).max() <= 1e-14 * scale
    A = gf.Ball(np.zeros(3), 1.0)
    R = random_rotation(rng, 3)
    for D in (gf.minkowski_sum(gf.affine(R, gf.Capsule(0.2, 1.0)), gf.affine(R, A)),
              gf.minkowski_sum(A, gf.affine(R, A)), gf.affine(R, gf.minkowski_sum(A, A)),
              gf.minkowski_sum(*[gf.affine(np.eye(2), gf.Ball(np.zeros(2), 1.0))] * 2),
              gf.minkowski_sum(gf.affine(np.ones((3, 2)), gf.Ball(np.zeros(2), 1.0)), A)):
        assert D.program[0][-1] == K.GENERAL


def test_neg_and_pose_identities():
    rng = np.random.default_rng(11)
    c, S = random_ellipsoid(rng, 3)
    B = gf.hull(gf.Ellipsoid(c, S), gf.TruncatedCone(0.5, 0.2, 1.0))
    R = random_rotation(rng, 3)
    p = rng.standard_normal(3)
    N = -B
    P = gf.pose(B, R, p)
    for u in unit_dirs(rng, 3, 20):
        assert abs(N.support(u)[0] - B.support(-u)[0]) <= 1e-14 * max(1, abs(B.support(-u)[0]))
        hp = B.support(R.T @ u)[0] + p @ u
        assert abs(P.support(u)[0] - hp) <= 1e-12 * max(1.0, abs(hp))


def test_pose_requires_rotation_and_3d():
    B = gf.Ball(np.zeros(3), 1.0)
    with pytest.raises(ValueError):
        gf.pose(gf.Ball(np.zeros(2), 1.0), np.eye(2), np.zeros(2))
    with pytest.raises(ValueError):
        gf.pose(B, 2.0 * np.eye(3), np.zeros(3))


def test_dimension_mismatch_raises():
    with pytest.raises(ValueError):
        gf.hull(gf.Ball(np.zeros(2), 1.0), gf.Ball(np.zeros(3), 1.0))
    with pytest.raises(ValueError):
        gf.minkowski_sum(gf.Ball(np.zeros(2), 1.0), gf.Ball(np.zeros(3), 1.0))
    with pytest.raises(ValueError):
        gf.affine(np.ones((2, 4)), gf.Ball(np.zeros(3), 1.0))


def test_leaf_parameters_follow_the_kernel_layout():
    # core/geometry/kernel.hpp's blocks, written out by hand: [n, k, c, S row-major],
    # [m, n, V row-major], [n, half], [r_bottom, r_top, h], [n, mu]
    c, S = np.array([0.1, -0.2, 0.3]), np.arange(6.0).reshape(3, 2)
    V = np.arange(12.0).reshape(4, 3)
    cases = [(gf.Ellipsoid(c, S), [3, 2, 0.1, -0.2, 0.3, 0, 1, 2, 3, 4, 5]),
             (gf.Polytope(V), [4, 3] + list(range(12))),
             (gf.Box([1.0, 2.0, 3.0]), [3, 1, 2, 3]),
             (gf.TruncatedCone(0.5, 0.25, 2.0), [0.5, 0.25, 2.0]),
             (gf.ConeCap(0.7, 4), [4, 0.7])]
    for leaf, expected in cases:
        params = leaf._params()
        assert params.dtype == np.float64 and params.tolist() == expected, type(leaf)


def test_fortran_ordered_input_is_read_by_rows():
    # a transposed view is Fortran-ordered: the set must be S, not S^T
    rng = np.random.default_rng(5)
    S = rng.normal(size=(3, 3))
    F = np.asfortranarray(S)
    A, B = gf.Ellipsoid(np.zeros(3), F), gf.Ellipsoid(np.zeros(3), S)
    V = rng.normal(size=(3, 5))
    for u in unit_dirs(rng, 3, 5):
        assert A.support(u)[0] == B.support(u)[0] == pytest.approx(np.linalg.norm(S.T @ u))
        assert gf.Polytope(V.T).support(u)[0] == pytest.approx(max(V.T @ u), rel=1e-15)
    pose_a, pose_b = (np.eye(3), np.zeros(3)), (np.eye(3), np.array([1.0, 0.5, 0.2]))
    ball = gf.Ball(np.zeros(3), 0.1)
    assert (gf.growth_distance(A, pose_a, ball, pose_b).sigma
            == gf.growth_distance(B, pose_a, ball, pose_b).sigma)


def test_delta_arrays_refuse_parts_that_are_not_the_block():
    from graspforce._core import delta_arrays, leaf_params
    from graspforce._core.growth import METHOD, TAIL
    ints, floats = np.zeros(4, dtype=np.int64), np.zeros(10 + TAIL)
    good, settings = (1.0, np.ones(3)), (4, 100, 1, 1e-9, 0.5)
    tail = [0.0] * TAIL
    tail[METHOD:METHOD + 5] = settings
    assert (delta_arrays(ints, floats, 0, 4, good, 4, 4, good, settings)[1].tolist()
            == [1, 1, 1, 1] * 2 + [0, 0] + tail)
    for bad in ((1.0, np.ones(2)), (1.0, np.ones(4)), (1.0, np.ones(6)[::2]),
                (1.0, np.ones(3, dtype=np.float32)), ("1", np.ones(3))):
        with pytest.raises(ValueError):
            delta_arrays(ints, floats, 0, 4, bad, 4, 4, good, settings)
    with pytest.raises(ValueError):
        delta_arrays(ints, floats, 0, 4, good, 10 + TAIL, 4, good, settings)  # past the floats
    for bad in (settings[:4], settings + (1.0,), (4, 100, True, 1e-9, 0.5)):
        with pytest.raises(ValueError):
            delta_arrays(ints, floats, 0, 4, good, 4, 4, good, bad)
    with pytest.raises(TypeError):
        leaf_params((1.0, [1.0, 2.0]))


# ----------------------------------------------------------------------------------------------
# leaves and witnesses
# ----------------------------------------------------------------------------------------------
def test_leaves_depth_first_and_witness_structure():
    rng = np.random.default_rng(12)
    P1 = gf.Polytope(rng.standard_normal((5, 3)))
    E1 = gf.Ellipsoid(np.zeros(3), np.eye(3))
    E2 = gf.Ellipsoid(np.ones(3), 0.5 * np.eye(3))
    Bx = gf.Box([1.0, 2.0, 3.0])
    TC = gf.TruncatedCone(1.0, 0.5, 1.0)
    A = gf.minkowski_sum(gf.hull(P1, E1), gf.affine(2 * np.eye(3), gf.hull(E2, Bx)), TC)
    leaves = A.leaves()
    assert [type(x) for x in leaves] == [type(P1), type(E1), type(E2), type(Bx), type(TC)]
    assert leaves[0] is P1 and leaves[1] is E1 and leaves[2] is E2 and leaves[4] is TC
    for u in unit_dirs(rng, 3, 20):
        h, p, wit = A.support_witness(u)
        idx = [li for li, _ in wit]
        # one leaf of each of the three summands: {0|1}, {2|3}, 4
        assert len(idx) == 3 and idx[0] in (0, 1) and idx[1] in (2, 3) and idx[2] == 4, idx
        for li, local in wit:
            if li == 0:
                assert isinstance(local, (int, np.integer))
            elif li in (1, 2):
                assert np.linalg.norm(local) <= 1 + 1e-12
        assert np.allclose(A.witness_point(wit), p, atol=1e-12)
    # under a hull exactly one leaf
    H = gf.hull(P1, E1, E2)
    for u in unit_dirs(rng, 3, 10):
        _, p, wit = H.support_witness(u)
        assert len(wit) == 1
        assert np.allclose(H.witness_point(wit), p, atol=1e-12)


def test_witness_point_is_independent_of_the_kernel():
    """witness_point of a hand-made witness (not from a support call)."""
    V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    A = gf.minkowski_sum(gf.Polytope(V), gf.Ellipsoid([5.0, 5.0], np.diag([2.0, 1.0])))
    x = np.array([0.6, -0.8])
    p = A.witness_point(((0, 2), (1, x)))
    assert np.allclose(p, V[2] + [5.0 + 1.2, 5.0 - 0.8], atol=1e-15)
    B = gf.affine(np.array([[1.0, 2.0], [0.0, 1.0], [1.0, 1.0]]), A, [1.0, 1.0, 1.0])
    q = B.witness_point(((0, 2), (1, x)))
    assert np.allclose(q, np.array([[1.0, 2.0], [0.0, 1.0], [1.0, 1.0]]) @ p + 1.0, atol=1e-14)
