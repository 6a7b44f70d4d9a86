"""Degenerate geometry and bad input for gf.ray_shoot.

- rays exactly through a vertex, an edge midpoint, the centroid of a lower-dimensional face of a
  cross-polytope or simplex in 3-D..6-D (IE's singular case: the ray meets a ridge or a lower face
  of the inner approximation instead of a facet interior), with support ties (axis-aligned) and
  without (rotated);
- rays along an edge or a face (the ray lies in the boundary);
- flat sets (disks, segments, triangles, a 2-D set embedded in R^4): rays in and across the plane;
- sets not containing the origin; the origin on the boundary;
- invalid input (ValueError) and max_iter = 1 (status "max_iter").

Truth: exact by construction (t = 1 through a boundary point placed on the ray), cross-checked with
the LP / closed form of truth.py.
"""
import itertools

import numpy as np
import pytest

import graspforce as gf
import truth as T
from conftest import METHODS, build, random_rotation, random_ellipsoid


def shoot(A, r, method, **kw):
    return gf.ray_shoot(A, np.asarray(r, dtype=float), method=method, **kw)


# ----------------------------------------------------------------------------------------------
# rays through vertices and lower-dimensional faces
# ----------------------------------------------------------------------------------------------
def cross_polytope(n, rotated, center):
    E = np.vstack([np.eye(n), -np.eye(n)])
    if rotated:
        Q = random_rotation(np.random.default_rng(600 + n), n)
        E = E @ Q.T
    return E + center


def face_targets(V, n, rng):
    """Boundary points of the cross-polytope CH(c + {+-q_i}) on faces of every dimension:
    a vertex, an edge midpoint, the centroid of a k-face for k = 2..n-1 (k = n-2 is a ridge,
    k = n-1 a facet), all built from pairwise non-antipodal vertices (so they are faces)."""
    out = []
    idx = rng.permutation(n)
    signs = rng.integers(0, 2, n)
    verts = [V[i + n * s] for i, s in zip(idx, signs)]   # one of each +-pair: a facet's vertices
    for k in range(1, n + 1):
        out.append((f"{k - 1}-face", np.mean(verts[:k], axis=0)))
    return out


@pytest.mark.parametrize("rotated", [False, True], ids=["axis", "rotated"])
@pytest.mark.parametrize("n", [3, 4, 5, 6])
@pytest.mark.parametrize("method", METHODS)
def test_cross_polytope_faces(method, n, rotated, check_hit):
    """Origin inside (off-centre); the ray through the centroid of a k-face for k = 0..n-1:
    t = 1 exactly. k < n-1 is IE's singular case."""
    rng = np.random.default_rng(700 + n + 10 * rotated)
    center = 0.1 * rng.standard_normal(n) / np.sqrt(n)
    V = cross_polytope(n, rotated, center)
    d = T.poly(V)
    A = build(d)
    for label, p in face_targets(V, n, rng):
        hit, t_lp, _ = T.ray_shoot_lp(V, p)
        assert hit and abs(t_lp - 1.0) <= 1e-12, (label, t_lp)
        res = shoot(A, p, method)
        check_hit(A, d, p, res, 1.0, method, label=label)


@pytest.mark.parametrize("n", [3, 4, 5, 6])
@pytest.mark.parametrize("method", METHODS)
def test_cross_polytope_centered_axis_ties(method, n, check_hit):
    """Origin at the centre of the axis-aligned cross-polytope: r = e_1 + e_2 (+ ...) makes the
    support map tie between vertices and the ray passes through an edge midpoint / face
    centroid at t = 1/k."""
    V = cross_polytope(n, False, np.zeros(n))
    d = T.poly(V)
    A = build(d)
    for k in range(1, n + 1):
        r = np.zeros(n)
        r[:k] = 1.0
        t_true = 1.0 / k
        hit, t_lp, _ = T.ray_shoot_lp(V, r)
        assert hit and abs(t_lp - t_true) <= 1e-12 * t_true
        res = shoot(A, r, method)
        check_hit(A, d, r, res, t_true, method, label=f"k={k}")


@pytest.mark.parametrize("n", [3, 4, 6])
@pytest.mark.parametrize("method", METHODS)
def test_ray_through_inner_ridge(method, n, check_hit):
    """The cross-polytope {+-e_i} plus a vertex p beyond the edge midpoint (e1 + e2)/2: the ray
    r = e1 + e2 first meets the inner approximation spanned by the unit vertices in the
    midpoint of an edge (a ridge or lower face of that simplex), and the set's true boundary
    further out, at p (t = 0.8), or on a facet next to it (tilted p, LP truth)."""
    E = np.vstack([np.eye(n), -np.eye(n)])
    r = np.zeros(n)
    r[:2] = 1.0
    for tilt in (0.0, 0.1):
        p = 0.8 * r.copy()
        p[2] += tilt
        V = np.vstack([E, p])
        d = T.poly(V)
        A = build(d)
        hit, t_lp, _ = T.ray_shoot_lp(V, r)
        assert hit
        if tilt == 0.0:
            assert abs(t_lp - 0.8) <= 1e-12
        res = shoot(A, r, method)
        check_hit(A, d, r, res, 0.8 if tilt == 0.0 else t_lp, method, label=f"tilt={tilt}")


@pytest.mark.parametrize("n", [3, 4, 5, 6])
@pytest.mark.parametrize("method", METHODS)
def test_simplex_vertex_edge_ridge(method, n, check_hit):
    """Random simplex with the origin inside: rays through a vertex, an edge midpoint and a
    ridge centroid (t = 1); and a polytope with extra interior points (not vertices)."""
    rng = np.random.default_rng(800 + n)
    S = rng.standard_normal((n + 1, n))
    S -= S.mean(axis=0)
    inner = 0.8 * rng.dirichlet(np.ones(n + 1), size=5) @ S      # interior points: not vertices
    V = np.vstack([S, inner])
    d = T.poly(V)
    A = build(d)
    targets = [S[0], 0.5 * (S[0] + S[1]), S[:n - 1].mean(axis=0)]
    for p in targets:
        hit, t_lp, _ = T.ray_shoot_lp(V, p)
        assert hit and abs(t_lp - 1.0) <= 1e-12
        res = shoot(A, 2.5 * p, method)
        check_hit(A, d, 2.5 * p, res, 0.4, method)


# ----------------------------------------------------------------------------------------------
# rays along edges and faces
# ----------------------------------------------------------------------------------------------
def unit_box_vertices(n, lo, hi):
    return np.array(list(itertools.product(*[(lo[i], hi[i]) for i in range(n)])), dtype=float)


@pytest.mark.parametrize("n", [2, 3, 4, 5])
@pytest.mark.parametrize("method", METHODS)
def test_ray_along_edge_and_face(method, n, check_hit):
    """Box [1,2] x [0,1]^(n-1), origin outside on the line of an edge:
    r = e_1 runs along the edge {x_2..n = 0} and leaves at the vertex (2, 0, ..): t = 2;
    r = (1, 0.3, 0, ..) runs inside the face {x_3.. = 0} (n >= 3) and leaves through the edge
    {x_1 = 2}: t = 2; also rotated copies (the same t up to rounding)."""
    lo = np.r_[1.0, np.zeros(n - 1)]
    hi = np.r_[2.0, np.ones(n - 1)]
    V0 = unit_box_vertices(n, lo, hi)
    rays = [np.eye(n)[0]]
    r2 = np.zeros(n)
    r2[0], r2[1] = 1.0, 0.3
    rays.append(r2)
    Q = random_rotation(np.random.default_rng(900 + n), n)
    for V, R in ((V0, np.eye(n)), (V0 @ Q.T, Q)):
        d = T.poly(V)
        A = build(d)
        for r in rays:
            rr = R @ r
            hit, t_lp, _ = T.ray_shoot_lp(V, rr)
            assert hit and abs(t_lp - 2.0) <= 1e-9
            res = shoot(A, rr, method)
            check_hit(A, d, rr, res, 2.0, method)


@pytest.mark.parametrize("method", METHODS)
def test_origin_on_boundary(method, check_hit):
    """Origin at a vertex of [0,1]^3 / on a facet of [-1,1] x [0,2] x [-1,1]; rays into the set
    or along its boundary: exact t."""
    cube = unit_box_vertices(3, np.zeros(3), np.ones(3))
    slab = unit_box_vertices(3, np.array([-1.0, 0.0, -1.0]), np.array([1.0, 2.0, 1.0]))
    cases = [
        (cube, [1.0, 1.0, 1.0], 1.0),        # through the opposite vertex
        (cube, [1.0, 0.5, 0.25], 1.0),       # out through the facet x = 1
        (cube, [1.0, 0.0, 0.0], 1.0),        # along an edge
        (cube, [1.0, 1.0, 0.0], 1.0),        # along a facet diagonal
        (slab, [0.0, 1.0, 0.0], 2.0),        # from a facet's centre straight through
        (slab, [1.0, 0.0, 0.0], 1.0),        # along the facet y = 0
        (slab, [0.5, 0.0, 0.5], 2.0),        # along the facet y = 0 to its corner
    ]
    for V, r, t_true in cases:
        hit, t_lp, _ = T.ray_shoot_lp(V, r)
        assert hit and abs(t_lp - t_true) <= 1e-9
        d = T.poly(V)
        A = build(d)
        res = shoot(A, r, method)
        check_hit(A, d, r, res, t_true, method)
    # Ellipsoid with the origin on its boundary: ball of radius 1 centred at e_1.
    d = T.ball([1.0, 0.0, 0.0], 1.0)
    A = build(d)
    for r in ([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.3, -0.2]):
        r = np.asarray(r)
        t_true = 2.0 * r[0] / (r @ r)        # |t r - e1|^2 = 1  <=>  t (t |r|^2 - 2 r_1) = 0
        hit, t_cf = T.ray_shoot_ellipsoid(d[1], d[2], r)
        assert hit and abs(t_cf - t_true) <= 1e-14
        res = shoot(A, r, method)
        check_hit(A, d, r, res, t_true, method)


@pytest.mark.parametrize("method", METHODS)
def test_origin_on_boundary_outward(method):
    """Origin on the boundary, ray pointing out of the set: A meets the ray only at the origin.
    The contract allows either answer, but it must be consistent: a hit at t = 0, or a miss with
    a direction n with h_A(n) <= 0 < n.r. Not an exception, not max_iter."""
    cube = unit_box_vertices(3, np.zeros(3), np.ones(3))
    d = T.poly(cube)
    A = build(d)
    for r in ([-1.0, 0.2, 0.3], [-1.0, -1.0, -1.0]):
        r = np.asarray(r)
        hit, t_lp, _ = T.ray_shoot_lp(cube, r)
        assert hit and abs(t_lp) <= 1e-12
        res = shoot(A, r, method)
        assert res.status in ("hit", "miss"), res.status
        if res.status == "hit":
            assert abs(res.t) <= 1e-12
            assert np.linalg.norm(res.point) <= 1e-12
        else:
            nrm = np.asarray(res.normal)
            assert nrm @ r > 0
            assert T.support(d, nrm) <= 1e-12 * np.linalg.norm(nrm)


# ----------------------------------------------------------------------------------------------
# flat sets
# ----------------------------------------------------------------------------------------------
E2 = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])


def flat_cases():
    """(label, description, r, hit, t) with closed-form truth."""
    out = []
    # disk in z = 0, centre (1,0,0), radius 0.5: origin outside, in the plane
    disk = T.ell([1.0, 0.0, 0.0], 0.5 * E2)
    out.append(("disk in-plane through centre", disk, [1.0, 0.0, 0.0], True, 1.5))
    t_chord = (2.0 + np.sqrt(4.0 - 4 * 1.04 * 0.75)) / (2 * 1.04)   # (t-1)^2 + 0.04 t^2 = 0.25
    out.append(("disk in-plane chord", disk, [1.0, 0.2, 0.0], True, t_chord))
    out.append(("disk in-plane away", disk, [-1.0, 0.0, 0.0], False, 0.0))
    out.append(("disk in-plane beside", disk, [1.0, 0.6, 0.0], False, 0.0))
    out.append(("disk off-plane ray", disk, [1.0, 0.0, 0.1], False, 0.0))
    # disk centred at the origin (origin in its relative interior), ray in its plane
    disk0 = T.ell([0.0, 0.0, 0.0], E2 @ np.diag([1.0, 0.5]))
    t0 = 1.0 / np.sqrt(1.0 + 4.0)                                    # t^2 (1 + 1/0.25) = 1
    out.append(("centred disk in-plane", disk0, [1.0, 1.0, 0.0], True, t0))
    # ellipse in the plane z = 1 (a plane off the origin): rays across it
    disk1 = T.ell([0.0, 0.0, 1.0], E2 @ np.diag([1.0, 0.5]))
    out.append(("disk z=1 hit", disk1, [0.3, 0.2, 1.0], True, 1.0))
    out.append(("disk z=1 hit scaled", disk1, [0.3, 0.2, 2.0], True, 0.5))
    out.append(("disk z=1 miss", disk1, [2.0, 0.0, 1.0], False, 0.0))
    out.append(("disk z=1 parallel", disk1, [1.0, 0.0, 0.0], False, 0.0))
    # segment {(1, s, 0) : |s| <= 1} as a rank-1 ellipsoid
    seg = T.ell([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    out.append(("segment hit", seg, [1.0, 0.5, 0.0], True, 1.0))
    out.append(("segment hit centre", seg, [2.0, 0.0, 0.0], True, 0.5))
    out.append(("segment miss", seg, [1.0, 2.0, 0.0], False, 0.0))
    out.append(("segment miss off-plane", seg, [1.0, 0.5, 0.5], False, 0.0))
    # segment through the origin, ray along it
    seg0 = T.ell([0.5, 0.0, 0.0], [1.0, 0.0, 0.0])
    out.append(("segment along", seg0, [1.0, 0.0, 0.0], True, 1.5))
    # triangle in the plane z = 1 (flat polytope)
    tri = T.poly([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]])
    out.append(("triangle interior", tri, [0.2, 0.3, 1.0], True, 1.0))
    out.append(("triangle vertex", tri, [1.0, 0.0, 1.0], True, 1.0))
    out.append(("triangle edge midpoint", tri, [1.0, 1.0, 2.0], True, 0.5))
    out.append(("triangle miss", tri, [0.8, 0.8, 1.0], False, 0.0))
    # triangle in the plane z = 0 containing the origin as a vertex: ray along the plane
    tri0 = T.poly([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    out.append(("triangle in-plane", tri0, [1.0, 1.0, 0.0], True, 1.0))
    # a 2-D disk embedded in R^4 by an affine map, plane off the origin, ray across it
    M = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    emb = T.affine(M, T.ball([0.0, 0.0], 1.0), t=[0.0, 0.0, 1.0, 2.0])
    out.append(("embedded disk R^4 hit", emb, [0.3, -0.4, 1.0, 2.0], True, 1.0))
    out.append(("embedded disk R^4 miss", emb, [1.0, 1.0, 1.0, 2.0], False, 0.0))
    return out


FLAT = flat_cases()


@pytest.mark.parametrize("case", range(len(FLAT)), ids=[c[0].replace(" ", "-") for c in FLAT])
@pytest.mark.parametrize("method", METHODS)
def test_flat_sets(method, case, check_shot):
    label, d, r, hit, t = FLAT[case]
    r = np.asarray(r, dtype=float)
    # cross-check the hand-derived truth with the general solvers of truth.py
    if d[0] == "ell":
        h2, t2 = T.ray_shoot_ellipsoid(d[1], d[2], r)
    elif d[0] == "poly":
        h2, t2, _ = T.ray_shoot_lp(d[1], r)
    else:
        h2, t2, _ = T.ray_shoot_socp(d, r)
    assert h2 == hit and (not hit or abs(t2 - t) <= 1e-9 * t), (label, h2, t2)
    A = build(d)
    res = shoot(A, r, method)
    check_shot(A, d, r, res, hit, t, method, label=label)


# ----------------------------------------------------------------------------------------------
# sets not containing the origin
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", METHODS)
def test_origin_outside_ball(method, check_shot):
    """Ball of radius 1 at (3, 0, 0): straight at it (t = 4), obliquely (closed form), away,
    and past it (line at distance 3 * 0.5 / sqrt(1.25) > 1 from the centre)."""
    c = np.array([3.0, 0.0, 0.0])
    d = T.ball(c, 1.0)
    A = build(d)
    r_obl = np.array([1.0, 0.2, 0.0])
    rc, rr = r_obl @ c, r_obl @ r_obl
    t_obl = (rc + np.sqrt(rc * rc - rr * (c @ c - 1.0))) / rr
    for r, hit, t in (([1.0, 0.0, 0.0], True, 4.0), (r_obl, True, t_obl),
                      ([-1.0, 0.0, 0.0], False, 0.0), ([1.0, 0.5, 0.0], False, 0.0),
                      ([0.0, 1.0, 0.0], False, 0.0)):
        r = np.asarray(r, dtype=float)
        res = shoot(A, r, method)
        check_shot(A, d, r, res, hit, t, method)


# ----------------------------------------------------------------------------------------------
# invalid input, iteration limit
# ----------------------------------------------------------------------------------------------
def test_bad_rays_raise():
    A = gf.Polytope(np.vstack([np.eye(3), -np.eye(3)]))
    for r in ([0.0, 0.0, 0.0], [np.nan, 1.0, 0.0], [np.inf, 1.0, 0.0], [1.0, 0.0],
              [1.0, 0.0, 0.0, 0.0]):
        for method in METHODS:
            with pytest.raises(ValueError):
                gf.ray_shoot(A, np.asarray(r, dtype=float), method=method)
    with pytest.raises(ValueError):
        gf.ray_shoot(A, np.array([1.0, 0.0, 0.0]), method="simplex")
    with pytest.raises(ValueError):
        gf.ray_shoot(A, np.array([1.0, 0.0, 0.0]), method="GJK2")
    for eps in (0.0, -1e-9):
        with pytest.raises(ValueError):
            gf.ray_shoot(A, np.array([1.0, 0.0, 0.0]), eps=eps)


def test_finite_array_agrees_with_numpy():
    # the compiled check against numpy's isfinite and min, on arrays of every size up to 200,
    # Fortran-ordered ones and 0-d ones, a non-finite entry anywhere
    from graspforce._validate import finite_array
    rng = np.random.default_rng(8)
    for i in range(400):
        shape = [(), (int(rng.integers(0, 200)),), (int(rng.integers(1, 9)), 3)][i % 3]
        a = rng.normal(size=shape)
        if a.size and i % 4:
            a.flat[rng.integers(a.size)] = (np.nan, np.inf, -np.inf)[i % 3]
        if i % 5 == 0 and a.ndim == 2:
            a = np.asfortranarray(a)
        minimum = None if i % 2 else -1.5
        finite = bool(np.isfinite(a).all())
        low_ok = minimum is None or not a.size or (finite and a.min() >= minimum)
        if finite and low_ok:
            out = finite_array(a, "field", minimum=minimum)
            assert out.flags.c_contiguous and np.array_equal(out, a)
        else:
            with pytest.raises(ValueError, match="field: must be"):
                finite_array(a, "field", minimum=minimum)


def test_bad_set_parameters_raise():
    with pytest.raises(ValueError):
        gf.Ellipsoid([np.nan, 0.0, 0.0], np.eye(3))
    with pytest.raises(ValueError):
        gf.Ellipsoid([0.0, 0.0, 0.0], [[1.0, 0.0, 0.0], [0.0, np.inf, 0.0], [0.0, 0.0, 1.0]])
    with pytest.raises(ValueError):
        gf.Polytope([[0.0, 0.0], [1.0, np.nan]])
    with pytest.raises(ValueError):
        gf.Ball([0.0, np.inf], 1.0)
    with pytest.raises(ValueError):
        gf.Ball([0.0, 0.0], np.nan)
    with pytest.raises(ValueError):
        gf.Box([1.0, np.nan, 1.0])
    with pytest.raises(ValueError):
        gf.TruncatedCone(1.0, 0.5, np.nan)
    with pytest.raises(ValueError):
        gf.Capsule(np.inf, 1.0)
    with pytest.raises(ValueError):
        gf.affine(np.array([[1.0, np.nan]]), gf.Ball([0.0, 0.0], 1.0))


@pytest.mark.parametrize("method", METHODS)
def test_max_iter_one(method):
    """A 6-D ellipsoid needs many iterations at eps = 1e-9: max_iter = 1 must stop with status
    "max_iter" (no exception, no hang) and report at most one iteration."""
    rng = np.random.default_rng(31)
    c, S = random_ellipsoid(rng, 6, c_scale=0.1)
    A = gf.Ellipsoid(c, S)
    r = rng.standard_normal(6)
    full = shoot(A, r, method)
    assert full.status == "hit" and full.iterations > 1
    res = shoot(A, r, method, max_iter=1)
    assert res.status == "max_iter"
    assert res.method == method
    assert res.iterations <= 1


# ----------------------------------------------------------------------------------------------
# IE's singular case on random polytopes
# ----------------------------------------------------------------------------------------------
def sphere_polytope(n, seed):
    """3n + 3 points near the unit sphere (all vertices), origin inside but off-centre, and rays
    through a vertex, the midpoint of it and its nearest vertex, and the centroid of it and its
    two nearest vertices (typically an edge and a 2-face). LP truth (truth.ray_shoot_lp)."""
    rng = np.random.default_rng(10000 * n + seed)
    V = rng.standard_normal((3 * n + 3, n))
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    V = V * rng.uniform(0.8, 1.2, (V.shape[0], 1)) + 0.1 * rng.standard_normal(n) / np.sqrt(n)
    nb = np.argsort(np.linalg.norm(V - V[0], axis=1))[1:3]
    rays = [V[0], 0.5 * (V[0] + V[nb[0]]), (V[0] + V[nb[0]] + V[nb[1]]) / 3.0]
    return V, rays


@pytest.mark.parametrize("n", [3, 4, 5, 6])
@pytest.mark.parametrize("method", METHODS)
def test_random_low_dimensional_faces(method, n, check_hit):
    """Rays exactly through vertices, edge midpoints and 2-face centroids of random polytopes.
    For IE these put b_k on faces of dimension < n - 1 of the inner polytope (the singular case
    of section 3.2; if the result reports `singular_steps` (not part of the contract), the test
    also checks that the construction does reach that case)."""
    singular = 0
    for seed in range(12):
        V, rays = sphere_polytope(n, seed)
        d = T.poly(V)
        A = build(d)
        for k, r in enumerate(rays):
            hit, t, _ = T.ray_shoot_lp(V, r)
            assert hit
            res = shoot(A, r, method)
            check_hit(A, d, r, res, t, method, label=f"seed={seed} ray={k}")
            singular += getattr(res, "singular_steps", 0) > 0
    if method == "ie" and hasattr(res, "singular_steps"):
        assert singular >= 3, f"only {singular} cases reached IE's singular case"
