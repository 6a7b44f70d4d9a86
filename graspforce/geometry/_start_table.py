"""A start table for many rays shot at one set: the facets of an inner polytope.

ZC-IE (section 3.4.2) begins with ZC from the origin, which spends about n + 1 support calls and as
many active-set projections to find a first facet that the ray crosses; on the ingot grasp's W_L1
that search is 4.3 of a shot's 11.4 us (docs/design.md, "Start tables"). When many rays are shot at
one set (min_force over many wrenches, a ray_shoot loop), the search can be done once for all:
the support points P_0 of A in the 2n directions +-q_j (q_j a fixed orthonormal basis in general
position) span an inner polytope CH(P_0) in A. When the origin is strictly inside it, its facets
y_f^T x = 1 cover every direction, and the ray R(r) leaves CH(P_0) through the facet of largest
y_f^T r at t_0 r with 1 / t_0 = y_f^T r = sum_j gam_j, r = sum_j gam_j a_j over the facet's
vertices a_j. That facet is IE's start: a facet of points of A that the ray crosses. When the
origin is outside every CH(P_0) tried (a grasp that is not force-closure, such as feet on the
ground), the table keeps the facets whose hyperplane y_f^T x = 1 supports CH(P_0) with the origin
on its inner side: a ray that crosses CH(P_0) leaves it through one of them, the one of largest
y_f^T r, and a ray that does not starts cold.

Nothing of the table is trusted beyond that: t_0 r is the convex combination (gam / sum gam) of
support points of A, so t_0 <= t* whichever facet the lookup picked; IE's steps and stopping rule
are unchanged. The table keeps a copy of the set's parameters and is ignored when they changed
(the growth query rewrites a set's poses in place), and when no facet of the table holds the
ray (some gam_j < 0: a ridge met to rounding, or a facet left out below): ZC then starts from the
origin as usual. A facet of CH(P_0) with more than n points is split by Qhull into simplices that
share its hyperplane; the lookup takes the one of them that holds the ray.

A table costs 2n support calls, a convex hull (scipy's Qhull) and one inverse per facet: ~1 ms
in R^6 (F = 87 facets on the ingot), ~10 ms in R^10 with F ~ 2000, where the lookup's F n
products would cost more than the ZC search they replace; so tables are built for n <= MAX_DIM
only, at a set's second shot (a set shot once never pays for one). The exception: rays that live
in the last k <= MAX_DIM coordinates of a set in up to R^MAX_HULL_DIM (min_force's shots at
W_Linf's lift, graspforce.grasping.wrench_space). Half of P_0 then spans that subspace, and the
table keeps only the facets those rays leave through, found by random rays spread like P_0's points
in that subspace: ~320 of ~530 on the ingot's lift in R^9, where the table cuts ZC's 11 support
calls (~20 us of 53) to none. (Isotropic rays kept 69, and 15% of the benchmark's wrenches found
no facet and started cold, ~9 us slower each.)
"""
import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ._kernel import params_size

MAX_DIM = 8
MAX_HULL_DIM = 9      # rays in a subspace of dimension <= MAX_DIM: Qhull in up to R^9 (W_Linf's
                      # lift for 4 contacts: 16 points, ~530 facets, 2 ms)
SLICE_RAYS = 16384    # random rays that pick the facets kept for rays in a subspace
MAX_ADDED = 8         # support points added to P_0 toward an origin outside CH(P_0)
HEADER = 5            # [facets F, n, witness size, parameters, points]
CONVEX_TOL = 1e-6     # y_f^T p <= 1 + CONVEX_TOL for every point p: y_f supports CH(P_0)
MAX_COND = 1e10       # condition number of a facet's vertex matrix kept in the table
TIE_TOL = 1e-6        # facets whose y_f^T r is within this of the largest: one facet of CH(P_0)
                      # with more than n points, triangulated (all share its hyperplane)

# a set's table state (ConvexSet._start_table): not shot yet, shot once, or no table (not
# applicable: n too large, a flat set, the origin not strictly inside CH(P_0))
UNSEEN = np.empty(0)
SEEN_ONCE = np.empty(0)
NO_TABLE = np.empty(0)


def start_table(A, ray_dims=None):
    """The table to pass with a shot at A (NO_TABLE on its first shot; built at its second).
    ray_dims = k < n: the rays shot at A have zeros but in their last k entries (W_Linf's lift,
    graspforce.grasping.wrench_space)."""
    state = A._start_table
    if state is UNSEEN:
        A._start_table = SEEN_ONCE
        return NO_TABLE
    if state is SEEN_ONCE:
        A._start_table = build_start_table(A, ray_dims)
    return A._start_table


def _directions(n, k):
    """+-q_j for a fixed orthonormal basis q in general position: the coordinate axes of a
    wrench space are special (two contacts' extreme forces along one axis coincide, and CH(P_0)
    then has the origin on its boundary); a seeded random rotation is not. With k < n, q rotates
    the last k coordinates and the first n - k apart: half of P_0 then spans the rays'
    subspace."""
    rng = np.random.default_rng(n)
    if k == n:
        q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    else:
        q = np.zeros((n, n))
        q[n - k:, n - k:] = np.linalg.qr(rng.normal(size=(k, k)))[0]
        q[:n - k, :n - k] = np.linalg.qr(rng.normal(size=(n - k, n - k)))[0]
    return np.vstack((q, -q))


def _spread(points):
    """L^T for the Cholesky factor L of the points' covariance: z L^T ~ N(0, cov) for z ~ N(0, I).
    Random rays spread like the set itself meet its facets in proportion to the rays that real
    problems shoot: isotropic ones, in a wrench space whose torques are 25x smaller than its
    forces (the ingot), missed the facets of 15% of the benchmark's wrenches."""
    k = points.shape[1]
    cov = np.cov(points.T)
    return np.linalg.cholesky(cov + 1e-12 * np.trace(cov) * np.eye(k)).T


def build_start_table(A, ray_dims=None):
    """The start table of A as one float array (layout in `table_start`), or NO_TABLE.

    P_0 from one basis (2n directions) first. While the origin is outside CH(P_0), P_0 takes the
    support point in the outer normal of the facet the origin lies farthest beyond, up to
    MAX_ADDED of them: the ingot's W_Linf needed one, and CH(P_0) then has 104 facets where a
    second basis gave 590 (more directions bring t_0 closer to t* but not IE's steps fewer: 4n
    directions on the ingot's W_L1 gave t_0 / t* = 0.86 against 0.33, the same median of 17
    support calls, and 597 facets to look up against 87). A support value h_A(u) <= 0 in that
    normal u proves the origin is not inside A (a grasp that is not force-closure: feet on the
    ground); the table is then the first CH(P_0)'s facets that rays crossing it leave through."""
    n = A.dim
    k = n if ray_dims is None else ray_dims
    if not 2 <= k <= MAX_DIM or n > (MAX_DIM if k == n else MAX_HULL_DIM):
        return NO_TABLE
    rows = [A._support(u) for u in _directions(n, k)]
    first = None
    for added in range(MAX_ADDED + 1):
        table, toward = _table(A, rows, k)
        if first is None:
            first = table
        if toward is None:
            return table
        if added == MAX_ADDED:
            break
        row = A._support(toward)
        if toward @ row[1] <= CONVEX_TOL * max(np.linalg.norm(r[1]) for r in rows):
            break
        rows.append(row)
    return first


def _table(A, rows, k):
    """(table, toward) of P_0 = the points of the support rows (value, point, witness) `rows`;
    with k < n, the table keeps only the facets that rays in the last k coordinates leave
    through. toward: None when the origin is strictly inside CH(P_0); else the unit outer normal
    of the facet the origin lies farthest beyond, and the table keeps only the facets whose
    hyperplane y_f^T x = 1 supports CH(P_0) (the origin on its inner side), through one of which
    every ray that crosses CH(P_0) leaves it (the lookup's largest y_f^T r); other rays start
    cold. NO_TABLE (and None) for a flat P_0 or no usable facet."""
    points, keep = np.unique(np.array([row[1] for row in rows]), axis=0, return_index=True)
    witnesses = np.array([rows[i][2] for i in keep])
    try:
        # joggled: every facet a simplex of n points (Qhull's triangulation of a merged facet
        # may leave flat ones)
        faces = ConvexHull(points, qhull_options="QJ").simplices
    except QhullError:
        return NO_TABLE, None      # P_0 spans less than R^n: a flat set
    vertices = np.transpose(points[faces], (0, 2, 1))
    # facets whose vertices are nearly dependent (the origin near their hyperplane, or two
    # support points nearly equal) would give inaccurate weights: left out, their rays start cold
    faces = faces[np.linalg.cond(vertices) < MAX_COND]
    if len(faces) == 0:
        return NO_TABLE, None
    # gam = B_f r: B_f inverts the matrix whose columns are the facet's vertices
    inverse = np.linalg.inv(np.transpose(points[faces], (0, 2, 1)))
    normals = inverse.sum(axis=1)         # y_f = B_f^T 1
    supporting = (points @ normals.T).max(axis=0) <= 1.0 + CONVEX_TOL
    toward = None
    if not supporting.all():
        # some y_f^T x = 1 does not support CH(P_0) with the origin inside: the origin is
        # outside CH(P_0), beyond those facets, at 1 / ||y_f|| from their hyperplanes, whose
        # outer normal is -y_f
        facing = normals[~supporting]
        y = facing[np.argmin(np.linalg.norm(facing, axis=1))]
        toward = -y / np.linalg.norm(y)
        if not supporting.any():
            return NO_TABLE, toward
        faces, inverse, normals = faces[supporting], inverse[supporting], normals[supporting]
    n = A.dim
    if k < n:
        # of CH(P_0)'s facets in R^n (~530 for W_Linf's lift on 4 contacts) the rays of the
        # subspace leave through some (~320): those that random rays pick, with the simplices
        # tied with them. A ray whose facet was missed starts cold.
        rays = np.random.default_rng(k).normal(size=(SLICE_RAYS, k)) @ _spread(points[:, n - k:])
        scores = rays @ normals[:, n - k:].T
        tied = scores >= (1.0 - TIE_TOL) * scores.max(axis=1, keepdims=True)
        used = np.flatnonzero(tied.any(axis=0))
        faces, inverse, normals = faces[used], inverse[used], normals[used]
    ints, floats = A.program
    npar = params_size(ints)
    header = [len(faces), A.dim, A.witness_size, npar, len(points)]
    # normals by coordinate, (n, F): see table_start
    table = np.concatenate((header, floats[:npar], normals.T.ravel(), inverse.ravel(),
                            faces.ravel(), points.ravel(), witnesses.ravel())).astype(float)
    return table, toward
