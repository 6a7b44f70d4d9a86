"""Growth distance against the paper's protocol, closed forms, an SOCP and coal."""
import numpy as np
import pytest
import scipy.sparse as sp

import graspforce as gf
from benchmarks.growth_sets import (
    CASES,
    SCALES,
    protocol_pairs,
    random_rotation,
    scaled_shapes,
)

METHODS = list(gf.METHODS)
PAIRS = protocol_pairs(12, seed=7)           # 4 per case


def shapes(pair, scale):
    axes, (rb, rt, h) = scaled_shapes(pair, scale)
    return gf.Ellipsoid(np.zeros(3), np.diag(axes)), gf.TruncatedCone(rb, rt, h)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("case", list(SCALES))
def test_paper_protocol(method, case):
    scale, truth = SCALES[case]
    for pair in PAIRS:
        E, C = shapes(pair, scale)
        res = gf.growth_distance(E, (pair["R_e"], pair["p_e"]), C, (pair["R_c"], pair["p_c"]),
                                 method=method, eps=1e-10)
        # the bound at eps = 1e-10; the pair's own construction is exact to ~1e-15
        assert abs(res.sigma - truth) <= 1e-8, (pair["case"], res.sigma)
        # the certified bracket holds the truth; sigma is its midpoint
        assert res.sigma_lower <= truth * (1 + 1e-12) and res.sigma_upper >= truth * (1 - 1e-12)
        assert res.sigma_upper / res.sigma_lower - 1 <= 1e-10 * (1 + 1e-6)
        assert res.sigma_lower <= res.sigma <= res.sigma_upper
        assert res.status == {1.0: "touching", 2.0: "separated", 0.5: "penetrating"}[truth]
        # the contact: the grown shapes touch where the pair was built to touch (the ellipsoid
        # is strictly convex, so the point and its normal are unique), scaled about p_e and p_c
        size = max(pair["axes"].max(), pair["h"])
        assert np.linalg.norm(res.point_a - res.point_b) <= 1e-9 * size
        q = pair["p_e"] + (truth * scale) * (pair["point"] - pair["p_e"])
        # a simplex within eps t of a curved surface spreads over a patch of radius
        # ~sqrt(2 rho eps t): the point is good to ~sqrt(eps) size (measured 1.2e-5 on 180 pairs)
        assert np.linalg.norm(res.point_a - q) <= 1e-4 * size
        # from the ellipsoid (A) to the cone (B): the pair's normal points from cone to ellipsoid
        assert res.normal @ -pair["normal"] >= 1 - 1e-8


def test_certified_bracket_holds_the_truth_on_every_protocol_pair():
    # the benchmark's 3000 pairs at eps = 1e-10: a nearly degenerate IE facet once made ZC-IE
    # certify a bracket 1.1e-7 away from the truth (pair 811: weights 1e-11, 1e-13 and 1 whose
    # y^T r disagreed with their sum), so every pair's bracket is checked here, to the rounding
    # of the certificate itself (points of A to 1e-12 relative, on a facet that ill-conditioned)
    for i, pair in enumerate(protocol_pairs(3000, 0)):
        E, C = shapes(pair, 1.0)
        res = gf.growth_distance(E, (pair["R_e"], pair["p_e"]), C, (pair["R_c"], pair["p_c"]),
                                 eps=1e-10)
        assert res.sigma_lower <= 1 + 1e-11 and res.sigma_upper >= 1 - 1e-11, (i, res)


def _support_ellipsoid(axes, R, p, sigma, n):
    # closed form: h(n) = n^T p + sigma ||diag(axes) R^T n||
    return n @ p + sigma * np.linalg.norm(axes * (R.T @ n))


def _support_cone(rb, rt, h, R, p, sigma, n):
    # the hull of two disks: the better of the two rims, h_disk(m) = c^T m + radius ||m_xy||
    m = R.T @ n
    rad = np.hypot(m[0], m[1])
    return n @ p + sigma * max(-0.5 * h * m[2] + rb * rad, 0.5 * h * m[2] + rt * rad)


@pytest.mark.parametrize("case", list(SCALES))
def test_contact_lies_on_both_boundaries(case):
    # independent of the kernel: closed-form supports of the grown shapes. point_a is on the
    # boundary of A(sigma) where the normal supports it, point_b on B(sigma)'s where -normal does
    scale, _truth = SCALES[case]
    for pair in PAIRS:
        axes, (rb, rt, h) = scaled_shapes(pair, scale)
        E, C = shapes(pair, scale)
        res = gf.growth_distance(E, (pair["R_e"], pair["p_e"]), C, (pair["R_c"], pair["p_c"]))
        n, s = res.normal, res.sigma
        size = s * max(axes.max(), rb, rt, h)
        assert abs(np.linalg.norm(n) - 1) <= 1e-12
        assert abs(_support_ellipsoid(axes, pair["R_e"], pair["p_e"], s, n) - n @ res.point_a) \
            <= 1e-8 * size
        assert abs(_support_cone(rb, rt, h, pair["R_c"], pair["p_c"], s, -n) + n @ res.point_b) \
            <= 1e-8 * size
        assert np.linalg.norm(res.point_a - res.point_b) <= 1e-9 * size


def test_touching_status_follows_the_bracket():
    # at a coarse eps the bracket around a touching pair is wide: it contains 1, so "touching";
    # a pair grown by 1e-3 is outside the bracket either way
    pair = PAIRS[0]
    for scale, want in ((1.0, "touching"), (1.001, "penetrating"), (0.999, "separated")):
        E, C = shapes(pair, scale)
        res = gf.growth_distance(E, (pair["R_e"], pair["p_e"]), C, (pair["R_c"], pair["p_c"]),
                                 eps=1e-5, touching_tol=0.0)
        assert res.status == want, (scale, res)
        assert res.sigma_lower <= 1 / scale <= res.sigma_upper * (1 + 1e-12)


def test_iteration_limit_is_a_status_not_nan():
    pair = PAIRS[1]
    E, C = shapes(pair, 1.0)
    for method in METHODS:
        res = gf.growth_distance(E, (pair["R_e"], pair["p_e"]), C, (pair["R_c"], pair["p_c"]),
                                 method=method, eps=1e-12, max_iter=1)
        assert res.status == "max_iter"
        values = [res.sigma, res.sigma_lower, res.sigma_upper, *res.point_a, *res.normal]
        assert not np.isnan(values).any()
        assert res.sigma_lower == 0.0 and res.sigma_upper == np.inf      # nothing certified


def test_result_keeps_its_poses():
    # a caller that reuses its pose arrays must not move an earlier result's contact
    A, B = gf.Ball(np.zeros(3), 1.0), gf.Ball(np.zeros(3), 1.0)
    R, p = np.eye(3), np.array([4.0, 0.0, 0.0])
    res = gf.growth_distance(A, (R, np.zeros(3)), B, (R, p))
    p[:] = [0.0, 8.0, 0.0]
    assert res.sigma == pytest.approx(2.0, rel=1e-9)
    assert np.allclose(res.point_a, [2.0, 0.0, 0.0], atol=1e-6)
    assert np.allclose(res.normal, [1.0, 0.0, 0.0], atol=1e-6)


def test_one_shot_calls_do_not_depend_on_history():
    A, B = gf.Capsule(0.2, 0.5), gf.Box([0.3, 0.1, 0.2])
    rng = np.random.default_rng(9)
    pa, pb = (random_rotation(rng), np.zeros(3)), (random_rotation(rng), np.ones(3))
    first = gf.growth_distance(A, pa, B, pb)
    gf.growth_distance(A, pa, B, (pb[0], np.array([1.0, 1.1, 0.9])))
    assert gf.growth_distance(A, pa, B, pb).sigma == first.sigma


def test_protocol_covers_every_contact_type():
    assert {p["case"] for p in PAIRS} == set(CASES)


def test_spheres_closed_form():
    rng = np.random.default_rng(1)
    for _ in range(20):
        r1, r2 = rng.uniform(0.1, 2.0, 2)
        c1, c2 = rng.normal(size=3), rng.normal(size=3)
        res = gf.growth_distance(gf.Ball(np.zeros(3), r1), (random_rotation(rng), c1),
                                 gf.Ball(np.zeros(3), r2), (random_rotation(rng), c2))
        assert res.sigma == pytest.approx(np.linalg.norm(c2 - c1) / (r1 + r2), rel=1e-9)
        assert np.allclose(res.normal, (c2 - c1) / np.linalg.norm(c2 - c1), atol=1e-6)


def test_boxes_closed_form():
    # equal rotations: Delta is the box with half extents a + b, and g = max_i |(R^T r)_i| / (a+b)_i
    rng = np.random.default_rng(2)
    for _ in range(20):
        a, b = rng.uniform(0.1, 1.0, 3), rng.uniform(0.1, 1.0, 3)
        R = random_rotation(rng)
        pa, pb = rng.normal(size=3), rng.normal(size=3)
        truth = np.max(np.abs(R.T @ (pb - pa)) / (a + b))
        for method in METHODS:
            res = gf.growth_distance(gf.Box(a), (R, pa), gf.Box(b), (R, pb), method=method)
            assert res.sigma == pytest.approx(truth, rel=1e-9)
            assert np.linalg.norm(res.point_a - res.point_b) <= 1e-9 * (1 + truth)


def socp_growth(A_kind, A_data, RA, pA, B_kind, B_data, RB, pB):
    """min sigma s.t. p_A + R_A x_A = p_B + R_B x_B with x_A in sigma A_0, x_B in sigma B_0, for
    ellipsoids {diag(axes) u : ||u|| <= 1} and boxes {|x_i| <= half_i} (Clarabel)."""
    import clarabel
    # variables: sigma, u_A (3), u_B (3); x = diag(axes or half) u
    A_eq = np.zeros((3, 7))
    A_eq[:, 1:4] = RA @ np.diag(A_data)
    A_eq[:, 4:7] = -RB @ np.diag(B_data)
    rows, b, cones = [A_eq], [pB - pA], [clarabel.ZeroConeT(3)]
    for kind, cols in ((A_kind, slice(1, 4)), (B_kind, slice(4, 7))):
        if kind == "ellipsoid":                       # (sigma, u) in SOC
            block = np.zeros((4, 7))
            block[0, 0] = -1.0
            block[1:, cols] = -np.eye(3)
            rows.append(block)
            b.append(np.zeros(4))
            cones.append(clarabel.SecondOrderConeT(4))
        else:                                         # -sigma <= u_i <= sigma
            block = np.zeros((6, 7))
            block[:3, cols], block[:3, 0] = np.eye(3), -1.0
            block[3:, cols], block[3:, 0] = -np.eye(3), -1.0
            rows.append(block)
            b.append(np.zeros(6))
            cones.append(clarabel.NonnegativeConeT(6))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-11
    q = np.zeros(7)
    q[0] = 1.0
    sol = clarabel.DefaultSolver(sp.csc_matrix((7, 7)), q, sp.csc_matrix(np.vstack(rows)),
                                 np.concatenate(b), cones, settings).solve()
    return sol.x[0]


@pytest.mark.parametrize("kinds", [("ellipsoid", "ellipsoid"), ("box", "ellipsoid"),
                                   ("box", "box")])
def test_random_pairs_against_socp(kinds):
    rng = np.random.default_rng(3)
    make = {"ellipsoid": lambda d: gf.Ellipsoid(np.zeros(3), np.diag(d)),
            "box": lambda d: gf.Box(d)}
    for _ in range(10):
        da, db = rng.uniform(0.2, 1.5, 3), rng.uniform(0.2, 1.5, 3)
        RA, RB = random_rotation(rng), random_rotation(rng)
        pA, pB = rng.normal(0, 2, 3), rng.normal(0, 2, 3)
        truth = socp_growth(kinds[0], da, RA, pA, kinds[1], db, RB, pB)
        for method in ("zc-ie", METHODS[rng.integers(len(METHODS))]):
            res = gf.growth_distance(make[kinds[0]](da), (RA, pA), make[kinds[1]](db), (RB, pB),
                                     method=method)
            # Clarabel at 1e-11 tolerances is good to ~1e-9 here
            assert res.sigma == pytest.approx(truth, rel=1e-7)


def _coal_distance(coal, axes, radius, height, pose_a, pose_b, scale):
    """coal's signed distance between the ellipsoid and the cylinder grown by `scale`."""
    e = coal.Ellipsoid(*(axes * scale))
    c = coal.Cylinder(radius * scale, height * scale)
    return coal.distance(e, coal.Transform3s(*pose_a), c, coal.Transform3s(*pose_b),
                         coal.DistanceRequest(), coal.DistanceResult())


def lp_growth(VA, RA, pA, VB, RB, pB):
    """min sigma s.t. p_A + R_A V_A^T alpha = p_B + R_B V_B^T beta, sum alpha = sum beta = sigma,
    alpha, beta >= 0: a point of both grown polytopes (HiGHS)."""
    from scipy.optimize import linprog
    ma, mb = len(VA), len(VB)
    c = np.zeros(1 + ma + mb)
    c[0] = 1.0
    A_eq = np.zeros((5, 1 + ma + mb))
    A_eq[:3, 1:1 + ma] = RA @ VA.T
    A_eq[:3, 1 + ma:] = -RB @ VB.T
    A_eq[3, 0], A_eq[3, 1:1 + ma] = -1.0, 1.0
    A_eq[4, 0], A_eq[4, 1 + ma:] = -1.0, 1.0
    b_eq = np.concatenate([pB - pA, [0.0, 0.0]])
    sol = linprog(c, A_eq=A_eq, b_eq=b_eq, bounds=(0, None), method="highs",
                  options={"primal_feasibility_tolerance": 1e-10,
                           "dual_feasibility_tolerance": 1e-10})
    return sol.x[0]


@pytest.mark.parametrize("method", METHODS)
def test_random_polytopes_against_lp(method):
    # meshes' vertices: the hull of random points around the origin (the origin stays interior)
    rng = np.random.default_rng(10)
    for _ in range(8):
        VA = rng.normal(size=(12, 3)) * rng.uniform(0.2, 1.0, 3)
        VB = rng.normal(size=(20, 3)) * rng.uniform(0.2, 1.0, 3)
        VA -= VA.mean(axis=0)
        VB -= VB.mean(axis=0)
        RA, RB = random_rotation(rng), random_rotation(rng)
        pA, pB = rng.normal(0, 2, 3), rng.normal(0, 2, 3)
        res = gf.growth_distance(gf.Polytope(VA), (RA, pA), gf.Polytope(VB), (RB, pB),
                                 method=method)
        assert res.sigma == pytest.approx(lp_growth(VA, RA, pA, VB, RB, pB), rel=1e-8)
        assert np.linalg.norm(res.point_a - res.point_b) <= 1e-8 * (1 + np.linalg.norm(pB - pA))


def test_coal_agrees_at_the_growth_distance():
    coal = pytest.importorskip("coal")
    rng = np.random.default_rng(4)
    for _ in range(10):
        axes = rng.uniform(0.2, 1.0, 3)
        radius, height = rng.uniform(0.2, 1.0), rng.uniform(0.5, 2.0)
        pose_a = (random_rotation(rng), rng.normal(0, 2, 3))
        pose_b = (random_rotation(rng), rng.normal(0, 2, 3))
        res = gf.growth_distance(gf.Ellipsoid(np.zeros(3), np.diag(axes)), pose_a,
                                 gf.TruncatedCone(radius, radius, height), pose_b)
        s = res.sigma
        size = s * max(axes.max(), radius, height)
        dist = _coal_distance(coal, axes, radius, height, pose_a, pose_b, s)
        assert abs(dist) <= 1e-6 * size                                      # touching at sigma
        # slightly smaller: separated; slightly larger: penetrating
        assert _coal_distance(coal, axes, radius, height, pose_a, pose_b, s * (1 - 1e-4)) > 0
        assert _coal_distance(coal, axes, radius, height, pose_a, pose_b, s * (1 + 1e-4)) < 0


def test_pose_formats_agree():
    pin = pytest.importorskip("pinocchio")
    rng = np.random.default_rng(5)
    A, B = gf.Box([0.3, 0.2, 0.1]), gf.Ellipsoid(np.zeros(3), np.diag([0.2, 0.3, 0.4]))
    RA, RB = random_rotation(rng), random_rotation(rng)
    pA, pB = rng.normal(size=3), rng.normal(size=3)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = RB, pB
    cold = gf.GrowthDistance(A, B, warm_start=False)      # identical inputs, identical answers
    ref = cold((RA, pA), (RB, pB)).sigma
    assert cold(pin.SE3(RA, pA), T).sigma == ref
    assert cold([RA.tolist(), pA.tolist()], pin.SE3(RB, pB)).sigma == ref


def test_pose_arrays_of_any_type_and_layout_agree():
    # the compiled query takes C-contiguous float64 arrays (graspforce._core.growth_query, which
    # refuses anything else); every other array is converted on the way, never a different answer
    from graspforce.growth.growth import query
    rng = np.random.default_rng(15)
    A, B = gf.Capsule(0.2, 0.5), gf.Box([0.3, 0.1, 0.2])
    RA, RB = random_rotation(rng), random_rotation(rng)
    pA, pB = rng.normal(size=3), rng.normal(size=3)
    solver = gf.GrowthDistance(A, B, warm_start=False)
    ref = solver((RA, pA), (RB, pB)).sigma
    frozen = RB.copy()
    frozen.flags.writeable = False
    wide = np.zeros((3, 6))
    wide[:, ::2] = RB
    for pose_b in ((np.asfortranarray(RB), pB), (frozen, pB), (wide[:, ::2], pB),
                   (RB, np.repeat(pB, 2)[::2]), [RB, pB], (RB.tolist(), pB)):
        assert solver((RA, pA), pose_b).sigma == ref
    assert solver((RA, pA), (np.eye(3, dtype=np.int64), pB)).sigma == \
        solver((RA, pA), (np.eye(3), pB)).sigma
    # the compiled query itself takes exactly such arrays (read-only too: it does not write to
    # the poses) and gives the solver's answer; any other pose array raises TypeError,
    # unconverted
    packed = np.empty(solver._size)
    for R in (RB, frozen):
        assert query(solver._ints, solver._floats, RA, pA, R, pB, packed)[2] == ref
    for R, p in ((np.asfortranarray(RB), pB), (wide[:, ::2], pB), (RB.tolist(), pB),
                 (np.eye(3, dtype=np.int64), pB), (RB.astype(np.float32), pB),
                 (RB, np.repeat(pB, 2)[::2]), (RB, pB.tolist()), (RB, pB.reshape(1, 3))):
        with pytest.raises(TypeError):
            query(solver._ints, solver._floats, RA, pA, R, p, packed)
    with pytest.raises(ValueError, match="pose_b rotation: expected shape"):
        solver((RA, pA), (np.eye(4), pB))
    with pytest.raises(ValueError, match="pose_a translation: expected shape"):
        solver((RA, np.zeros(4)), (RB, pB))


def test_reused_solver_matches_one_shot_calls():
    rng = np.random.default_rng(6)
    A, B = gf.Capsule(0.2, 0.5), gf.TruncatedCone(0.4, 0.1, 0.6)
    solver = gf.GrowthDistance(A, B)
    for _ in range(10):
        pa = (random_rotation(rng), rng.normal(size=3))
        pb = (random_rotation(rng), rng.normal(size=3))
        # both certified to eps = 1e-9 relative (one may be warm-started from the other)
        res = solver(pa, pb)
        assert res.sigma == pytest.approx(gf.growth_distance(A, pa, B, pb).sigma, rel=2e-9)


def test_warm_start_on_a_moving_pair():
    A, B = gf.Ellipsoid(np.zeros(3), np.diag([0.3, 0.2, 0.15])), gf.TruncatedCone(0.2, 0.1, 0.4)
    warm, cold = gf.GrowthDistance(A, B), gf.GrowthDistance(A, B, warm_start=False)
    saved = 0
    for k in range(100):
        th = 2 * np.pi * k / 100
        pose_b = (random_rotation(np.random.default_rng(k)) if k % 50 == 0 else
                  _rot_z(th), np.array([0.8 * np.cos(th), 0.6 * np.sin(th), 0.1]))
        w, c = warm((np.eye(3), np.zeros(3)), pose_b), cold((np.eye(3), np.zeros(3)), pose_b)
        # both certified: their brackets overlap
        assert w.sigma_lower <= c.sigma_upper * (1 + 1e-12)
        assert c.sigma_lower <= w.sigma_upper * (1 + 1e-12)
        saved += c.iterations - w.iterations
    assert saved > 0


def test_probes_whose_facet_misses_the_ray_fall_back_to_zc_from_the_origin():
    # "zc-ie" queries, warm and cold, start IE on the facet of support points spread around a
    # guessed normal (core/shooting/warm.hpp). Around -r the ray never crosses that facet (every
    # probe point is behind the origin), so the spread is widened WIDENINGS times and ZC-IE
    # starts from the origin: a plain ZC-IE shot's answer, for the probes' support calls more.
    from graspforce._core import HIT, ZC_IE, capacity, shoot, shoot_warm
    from graspforce._core.warm import WIDENINGS
    pair = PAIRS[0]
    solver = gf.GrowthDistance(*shapes(pair, 1.0), warm_start=False)
    solver((pair["R_e"], pair["p_e"]), (pair["R_c"], pair["p_c"]))  # Delta at these poses
    ints, floats, ws = solver._ints, solver._floats, solver.delta.witness_size
    r = np.ascontiguousarray(pair["p_c"] - pair["p_e"], dtype=float)
    plain = shoot(ints, floats, r, ws, ZC_IE, 1e-9, 1000)
    packed = np.empty(capacity(3, ws))
    probed = shoot_warm(ints, floats, r, ws, 1e-9, 1000, -r / np.linalg.norm(r), 0.05, packed, 0)
    assert plain[0] == probed[0] == HIT
    assert (probed[1], probed[2]) == (plain[1], plain[2])
    assert probed[5] == plain[5] + 3 * WIDENINGS


def _rot_z(th):
    return np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1]])


def test_coincident_reference_points():
    A, B = gf.Ball(np.zeros(3), 1.0), gf.Box([1.0, 2.0, 3.0])
    res = gf.growth_distance(A, (np.eye(3), np.ones(3)), B, (random_rotation(
        np.random.default_rng(0)), np.ones(3)))
    assert res.sigma == 0.0 and res.status == "penetrating"
    assert np.array_equal(res.point_a, np.ones(3)) and not res.normal.any()


def test_coincident_reference_points_still_check_the_rotations():
    A, B = gf.Ball(np.zeros(3), 1.0), gf.Box([1.0, 2.0, 3.0])
    solver = gf.GrowthDistance(A, B)
    reflection = np.diag([1.0, 1.0, -1.0])
    with pytest.raises(ValueError, match="pose_a: the rotation must be proper"):
        solver((reflection, np.ones(3)), (np.eye(3), np.ones(3)))
    with pytest.raises(ValueError, match="pose_b: the rotation must be proper"):
        solver((np.eye(3), np.ones(3)), (2.0 * np.eye(3), np.ones(3)))


def test_identical_shapes():
    A = gf.TruncatedCone(0.5, 0.2, 1.0)
    R = random_rotation(np.random.default_rng(8))
    # the same cone shifted along its own axis by 3: the tops' and bottoms' faces meet at 3 / 2
    res = gf.growth_distance(A, (R, np.zeros(3)), A, (R, 3.0 * R[:, 2]))
    assert res.sigma == pytest.approx(3.0, rel=1e-9) and res.status == "separated"


def test_bad_input():
    box = gf.Box([1.0, 1.0, 1.0])
    I, o = np.eye(3), np.zeros(3)
    with pytest.raises(ValueError, match="A"):
        gf.growth_distance(gf.Ellipsoid(np.zeros(3), np.diag([1.0, 1.0, 0.0])), (I, o), box,
                           (I, o + 3))                                      # flat
    with pytest.raises(ValueError, match="B"):
        gf.growth_distance(box, (I, o), gf.Ball(np.array([2.0, 0, 0]), 1.0), (I, o + 3))
    with pytest.raises(ValueError, match="3-D"):
        gf.growth_distance(gf.Ball(np.zeros(2), 1.0), (I, o), box, (I, o))
    with pytest.raises(ValueError, match="pose_a"):
        gf.growth_distance(box, (2 * I, o), box, (I, o + 3))
    with pytest.raises(ValueError, match="pose_b"):
        gf.growth_distance(box, (I, o), box, (I, [np.nan, 0, 0]))
    with pytest.raises(ValueError, match="pose_b"):
        gf.growth_distance(box, (I, o), box, np.ones((4, 4)))
    with pytest.raises(ValueError, match="method"):
        gf.growth_distance(box, (I, o), box, (I, o + 3), method="newton")


def test_origin_just_outside_or_inside_a_ball_is_decided_exactly():
    # between the closed form's clear margins (CLEAR_INSIDE, CLEAR_OUTSIDE) facet expansion
    # decides: a ball whose centre is 1.05 radii from the origin does not hold it, one at 0.95
    # does; at every scale
    for s in (1e-9, 1.0, 1e9):
        with pytest.raises(ValueError, match="origin"):
            gf.GrowthDistance(gf.Ball(np.array([1.05, 0.0, 0.0]) * s, s), gf.Ball(np.zeros(3), s))
        with pytest.raises(ValueError, match="origin"):
            gf.GrowthDistance(gf.Ball(np.zeros(3), s), gf.Ball(np.array([0.0, -1.1, 0.0]) * s, s))
        inside = gf.Ball(np.array([0.0, 0.0, 0.95]) * s, s)
        res = gf.growth_distance(inside, (np.eye(3), np.zeros(3)), gf.Ball(np.zeros(3), s),
                                 (np.eye(3), np.array([0.0, 0.0, 4.0]) * s))
        # A(sigma) is the ball of radius sigma s about 0.95 sigma s e_z, B(sigma) that about
        # 4 s e_z: they touch where 4 - 0.95 sigma = 2 sigma
        assert res.status == "separated"
        assert res.sigma == pytest.approx(4.0 / 2.95, rel=1e-9)
