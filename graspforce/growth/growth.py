"""Growth distance between two convex objects (section 4), with the contact point and normal.

An object is a 3-D convex set A_0 in its local frame, placed by a pose (R_A, p_A):
A = p_A + R_A(A_0) (eq. 7), where the local origin p_A must be an interior point. Its growth
model is A(sigma) = p_A + sigma R_A(A_0) (eq. 8) and the growth distance
    g(A, B) = min {sigma >= 0 : A(sigma) and B(sigma) intersect}              (eq. 9)
is the ray-shooting problem of eq. (10): with Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A,
g = 1/t* for the farthest point z_Delta(r) = t* r of Delta on R(r). g > 1: separated, g = 1:
touching, g < 1: penetrating. The shooter brackets t* between t (t r is a convex combination of
support points of Delta) and t_upper (where a supporting hyperplane crosses the ray), with
t_upper / t - 1 <= eps, so g lies in [1/t_upper, 1/t] = [sigma_lower, sigma_upper]; sigma is
their midpoint (error at most half the bracket, eps/2 relative).

The contact (the derivation the paper omits). Every support point of the Minkowski sum Delta is
a pair: v = a - b with a a support point of R_A(A_0) and b one of R_B(B_0) in opposite
directions, and the witnesses of each vertex v_k of Z_Delta(r) name both. With the weights
lambda_k of t r = sum_k lambda_k v_k, put a = sum_k lambda_k a_k (in R_A(A_0), convex) and
b = sum_k lambda_k b_k (in R_B(B_0)). Then a - b = t (p_B - p_A), i.e. with sigma_upper = 1/t
    p_A + sigma_upper a = p_B + sigma_upper b,
a point of A(sigma_upper) and of B(sigma_upper). point_a = p_A + sigma a and
point_b = p_B + sigma b, at the reported sigma, differ by (sigma/sigma_upper - 1) r, at most
eps/2 |r|. The normal n of the hyperplane supporting Delta at z (n^T r > 0) satisfies
n^T z = h_Delta(n) = h_{R_A A_0}(n) + h_{R_B B_0}(-n), and since n^T a <= h_{R_A A_0}(n) and
-n^T b <= h_{R_B B_0}(-n), both are equalities: A(sigma) lies in {x : n^T x <= n^T point_a} and
B(sigma) in {x : n^T x >= n^T point_b}. So n, normalized, is the contact normal from A to B
(exact for the returned hyperplane; z is within eps of the plane, so these hold to eps).
"""
import math
import threading

import numpy as np

from .._core import capacity, delta_arrays, ellipsoid_origin
from .._core import growth_query as query
from .._core.shapes import INSIDE, THIN, UNDECIDED
from .._core.growth import (BAD_POSE_A, COINCIDENT, FRAME, MA, MB, METHOD, NOT_CERTIFIED, OK,
                           PENETRATING, POSES, SEPARATED, SPREAD, TAIL, TOUCHING, TOUCHING_TOL,
                           WARM_SPREAD, WS)
from ..geometry._kernel import children, param_start
from .._validate import check_choice, finite_array
from ..grasping.quality import facet_expansion
from ..shooting.ray_shoot import METHODS, check_tolerances
from ..records.results import GrowthDistanceResult, RayShot
from ..geometry.sets import (Affine, Ball, ConvexSet, Ellipsoid, Leaf, MinkowskiSum, Polytope,
                   TruncatedCone, _AxisBox)

ORIGIN_TOL = 1e-9      # an origin closer than this fraction of the set's width to its boundary
                       # is not accepted as the interior point p_A of eq. (7)
_VERDICTS = {SEPARATED: "separated", TOUCHING: "touching", PENETRATING: "penetrating",
             NOT_CERTIFIED: "max_iter"}
# the defaults, one object each: a call that passes them on is not checked again
DEFAULT_METHOD, DEFAULT_EPS, DEFAULT_MAX_ITER, DEFAULT_TOUCHING = "zc-ie", 1e-9, 10000, 1e-9


def growth_distance(A, pose_a, B, pose_b, method=DEFAULT_METHOD, eps=DEFAULT_EPS,
                    max_iter=DEFAULT_MAX_ITER, touching_tol=DEFAULT_TOUCHING):
    """g(A, B) of eq. (9)-(10) for 3-D convex sets A, B given in their local frames (whose
    origins are interior points) and poses as (R, p), 4x4 homogeneous matrices or
    pinocchio.SE3. Returns a GrowthDistanceResult: sigma with its bracket, status, point_a,
    point_b, normal. eps: relative bracket width (sigma_upper / sigma_lower - 1 <= eps).

    Two primitives (leaves) are set up for each call from a template (~2 us on shapes checked
    before; most such calls come with shapes made for them, and keeping them costs those calls
    more than it saves the others); a pair with a composite set keeps its compiled Delta among
    the last 64 pairs of the calling thread, so repeated calls on those objects cost what
    `GrowthDistance(A, B)(pose_a, pose_b)` costs. No warm start here: the answer depends only on
    the arguments; for many poses of one pair, use GrowthDistance (set up once, warm start).
    """
    if isinstance(A, Leaf) and isinstance(B, Leaf):
        return GrowthDistance(A, B, method, eps, max_iter, touching_tol, False)(pose_a, pose_b)
    key = (id(A), id(B), method, eps, max_iter, touching_tol)
    try:
        recent = _RECENT.solvers
    except AttributeError:
        recent = _RECENT.solvers = {}
    solver = recent.get(key)
    if solver is None or solver.A is not A or solver.B is not B:
        solver = GrowthDistance(A, B, method, eps, max_iter, touching_tol, warm_start=False)
        if len(recent) >= 64:
            recent.pop(next(iter(recent)))
        recent[key] = solver
    return solver(pose_a, pose_b)


# a GrowthDistance writes each query's poses into its program: the recent solvers are kept per
# thread, so that threads calling growth_distance on the same shapes never share one
_RECENT = threading.local()


class GrowthDistance:
    """g(A, B) for one pair of shapes at many poses: Delta = R_A(A_0) - R_B(B_0) is compiled
    once, and each call writes the two rotations into its support program in place.

    warm_start (method "zc-ie" only): each call after a certified one starts IE from support
    points in directions spread around the previous normal (core/shooting/warm.hpp); for a pair that
    moves little between calls (time coherence). Other "zc-ie" calls start from support points
    spread around r (COLD_SPREAD, core/growth/growth.hpp); both instead of ZC from the origin, to
    which they fall back. The compiled query keeps that memory at the end of the program's
    floats (core/growth/growth.hpp).
    """

    def __init__(self, A, B, method=DEFAULT_METHOD, eps=DEFAULT_EPS, max_iter=DEFAULT_MAX_ITER,
                 touching_tol=DEFAULT_TOUCHING, warm_start=True):
        _check_shape(A, "A")
        _check_shape(B, "B")
        if not (method is DEFAULT_METHOD and eps is DEFAULT_EPS and max_iter is DEFAULT_MAX_ITER
                and touching_tol is DEFAULT_TOUCHING):
            check_choice(method, METHODS, "method")
            eps, max_iter = check_tolerances(eps, max_iter)
            if not (type(touching_tol) is float and 0.0 <= touching_tol < 1.0):
                raise ValueError(f"touching_tol: must be a float in [0, 1), got "
                                 f"{touching_tol!r}")
        self._code = METHODS[method]
        self.A, self.B, self.method = A, B, method
        self.eps, self.max_iter, self.touching_tol = eps, max_iter, touching_tol
        self.warm_start = bool(warm_start) and method == "zc-ie"
        # the solver's constants, in the order of the program's tail from METHOD on
        # (core/growth/growth.hpp)
        settings = (self._code, self.max_iter, int(self.warm_start), self.eps, touching_tol)
        self._delta, self._ints, self._floats, self._size = _delta_program(A, B, settings)

    @property
    def delta(self):
        """Delta = R_A(A_0) - R_B(B_0), whose program the queries write their rotations into;
        for two leaves made from a template when first read."""
        delta = self._delta
        if type(delta) is tuple:
            delta = self._delta = _PosedDelta(self.A, self.B, self._ints, self._floats, *delta)
        return delta

    def __call__(self, pose_a, pose_b):
        """The GrowthDistanceResult at these poses."""
        packed = np.empty(self._size)
        try:
            # the common call, (R, p) pairs of float64 arrays, goes straight to the compiled
            # query; anything else fails it with a TypeError (it takes float64 arrays only) or fails
            # to unpack, and is converted below
            (R_a, p_a), (R_b, p_b) = pose_a, pose_b
            res = query(self._ints, self._floats, R_a, p_a, R_b, p_b, packed)
        except (TypeError, ValueError):
            res = None
        # a pose the query refused (or could not take) is converted, checked and named here;
        # coincident reference points are an answer (sigma 0)
        if res is None or (res[0] != OK and res[0] != COINCIDENT):
            R_a, p_a = parse_pose(pose_a, "pose_a")
            R_b, p_b = parse_pose(pose_b, "pose_b")
            res = query(self._ints, self._floats, R_a, p_a, R_b, p_b, packed)
            code = res[0]
            if code != OK and code != COINCIDENT:
                name = "pose_a" if code == BAD_POSE_A else "pose_b"
                raise ValueError(f"{name}: the rotation must be proper (R^T R = I to 1e-9, "
                                 "det R = 1)")
        code, verdict, sigma, lower, upper, iterations, calls = res
        return GrowthDistanceResult(sigma, lower, upper, _VERDICTS[verdict], self.method,
                                    iterations, calls, (self, code, packed))

    def shot_of(self, result):
        """The RayShot on Delta and R(p_B - p_A) behind a GrowthDistanceResult (None if the
        reference points coincide)."""
        _, code, packed = result._raw
        if code == COINCIDENT:
            return None
        status, t, t_upper, h_n, iterations, calls, singular, k = packed[POSES:FRAME].tolist()
        head = (int(status), t, t_upper, h_n, int(iterations), int(calls), int(singular), int(k))
        return RayShot.from_packed(self.delta, packed[21:24] - packed[9:12], self.method, head,
                                   packed, extra=FRAME)

    def contact_of(self, result):
        """(point_a, point_b, normal) of a GrowthDistanceResult, by the derivation above."""
        frame = result._raw[2]
        R_a, p_a = frame[:9].reshape(3, 3), frame[9:12]
        R_b, p_b = frame[12:21].reshape(3, 3), frame[21:24]
        shot = result.shot
        if shot is None or not shot.hit:
            # coincident reference points: sigma = 0 and A(0) = B(0) = {p_A}; or no certified
            # simplex (max_iter): no contact to report
            return p_a.copy(), p_b.copy(), np.zeros(3)
        split = 1 if isinstance(self.A, Leaf) else len(self.A.leaves())
        a = np.zeros(3)
        b = np.zeros(3)
        for weight, witness in zip(shot.weights, shot.witnesses):
            a += weight * self.A.witness_point(tuple((j, x) for j, x in witness if j < split))
            b += weight * self.B.witness_point(tuple((j - split, x) for j, x in witness
                                                     if j >= split))
        normal = shot.normal / np.linalg.norm(shot.normal)
        sigma = result.sigma
        return p_a + sigma * (R_a @ a), p_b + sigma * (R_b @ b), normal


def parse_pose(pose, name):
    """(R (3, 3), p (3,)) as new C-contiguous, writable float64 arrays from (R, p), a 4x4
    homogeneous matrix or a pinocchio.SE3 (anything with .rotation and .translation): the types
    the compiled query takes. The rotation itself is checked in the query."""
    if isinstance(pose, (tuple, list)) and len(pose) == 2:
        R, p = pose
    elif hasattr(pose, "rotation") and hasattr(pose, "translation"):      # pinocchio.SE3
        R, p = pose.rotation, pose.translation
    else:
        M = finite_array(pose, name)
        if M.shape != (4, 4):
            raise ValueError(f"{name}: expected (R, p), a 4x4 matrix or a pinocchio.SE3, got "
                             f"shape {M.shape}")
        if not np.array_equal(M[3], [0.0, 0.0, 0.0, 1.0]):
            raise ValueError(f"{name}: the last row of a homogeneous matrix must be [0, 0, 0, 1]")
        R, p = M[:3, :3], M[:3, 3]
    # finite_array copies, so these are writable
    R = np.ascontiguousarray(finite_array(R, f"{name} rotation", shape=(3, 3)))
    p = np.ascontiguousarray(finite_array(p, f"{name} translation", shape=(3,)))
    return R, p


def _check_shape(X, name):
    """X must be a 3-D graspforce set whose local origin is interior (eq. 7), decided once per
    set: in closed form for the primitives whose origin is clearly inside or clearly not
    (`_origin_verdict`), else certified by facet expansion (graspforce.grasping.quality). A flat
    set, or one whose origin lies outside or on its boundary, is rejected."""
    if not isinstance(X, ConvexSet):
        raise TypeError(f"{name}: expected a graspforce convex set, got {type(X).__name__}")
    if X.dim != 3:
        raise ValueError(f"{name}: must be a 3-D set, got dimension {X.dim}")
    verdict = X.__dict__.get("_origin_interior")
    if verdict is None:
        verdict = _origin_verdict(X)
        if verdict is None:
            verdict = facet_expansion(X, 0.0, ORIGIN_TOL, 500, True)[0]
        X._origin_interior = verdict
    if not verdict:
        raise ValueError(f"{name}: the origin of its local frame must be an interior point "
                         "(eq. 7); this set is flat, or its origin is outside or on its boundary")


# The closed forms decide only where facet expansion's answer is not in doubt: the origin at most
# CLEAR_INSIDE (0.9) of the way from the centre to the boundary (in the set's own scale), or at
# least CLEAR_OUTSIDE (1.1) beyond it, or a set exactly flat; thin sets (an axis below THIN, 1e-3,
# of the largest) and everything between are left to facet expansion, as before. The bounds are
# core/growth/shapes.hpp's, which decides for ellipsoids.


def _origin_verdict(X):
    """True or False when the origin's interiority is known in closed form (Ball, Ellipsoid,
    centred Box, TruncatedCone, Capsule, and these under a zero-offset well-conditioned 3 x 3
    map), else None."""
    if isinstance(X, Ellipsoid):
        # {c + S x : ||x|| <= 1} in R^3 holds the origin strictly iff S S^T = M is nonsingular
        # and c^T M^-1 c < 1 (core/growth/shapes.hpp); rank < 3 is a disk, a segment or a point
        if X.shape.shape[1] < 3:
            return False
        verdict = ellipsoid_origin(X.center, X.shape)
        return None if verdict == UNDECIDED else verdict == INSIDE
    if isinstance(X, _AxisBox):
        half = X.half.tolist()
        if min(half) == 0.0:
            return False
        return True if min(half) >= THIN * max(half) else None
    if isinstance(X, TruncatedCone):
        h, mid = X.height, 0.5 * (X.bottom_radius + X.top_radius)
        if h == 0.0 or mid == 0.0:
            return False
        scale = max(h, X.bottom_radius, X.top_radius)
        return True if min(h, mid) >= THIN * scale else None
    if isinstance(X, MinkowskiSum) and len(X.sets) == 2:
        # a Capsule: the segment from -z to +z swept by a ball at the origin
        segment, ball = X.sets
        if (isinstance(segment, Polytope) and isinstance(ball, Ball)
                and segment.vertices.shape == (2, 3) and not ball.center.any()):
            (x0, y0, z0), (x1, y1, z1) = segment.vertices.tolist()
            if x0 == y0 == x1 == y1 == 0.0 and z0 == -z1:
                if ball.radius == 0.0:
                    return False
                return True if ball.radius >= THIN * abs(z0) else None
        return None
    if isinstance(X, Affine) and X.matrix.shape == (3, 3) and not X.offset.any():
        # a posed primitive about its own origin (a rotated Box): the origin is interior to
        # M X iff to X, for M well-conditioned
        (a, b, c), (d, e, f), (g, h, i) = X.matrix.tolist()
        det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
        lengths = (a * a + d * d + g * g, b * b + e * e + h * h, c * c + f * f + i * i)
        columns = math.sqrt(lengths[0] * lengths[1] * lengths[2])
        # nearly orthogonal columns of comparable lengths: M scales no axis of X to flat
        if (columns > 0.0 and abs(det) >= 0.5 * columns
                and min(lengths) >= THIN * THIN * max(lengths)):
            return _origin_verdict(X.inner)
    return None


class _PosedDelta(MinkowskiSum):
    """Delta = R_A(A_0) - R_B(B_0) for two leaves whose program came from a template
    (`_delta_program`): its tree (two Affine nodes, read by the records' witnesses) is built on
    first read."""

    def __init__(self, A, B, ints, floats, witness_slots, witness_size):
        self.dim = 3
        self._made_of = (A, B)
        self._program = (ints, floats)
        self._witness_slots = witness_slots
        self._witness_size = witness_size

    @property
    def sets(self):
        sets = self.__dict__.get("_sets")
        if sets is None:
            A, B = self._made_of
            sets = self._sets = (Affine(np.eye(3), A), Affine(-np.eye(3), B))
        return sets

    def __repr__(self):
        return f"MinkowskiSum(dim={self.dim})"


_DELTA_TEMPLATES = {}
MAX_TEMPLATES = 256     # pairs of leaf structures kept (polytopes of many vertex counts)


def _delta_program(A, B, settings):
    """(Delta, ints, floats, packed size): Delta's program with the query's tail (TAIL,
    core/growth/growth.hpp) at the end of floats, holding the offsets of R_A and -R_B in floats,
    the witness size, the first spread and the solver's settings (its entries from METHOD on).
    For two leaves, from a template per the leaves' kinds and layouts (their programs' ints
    depend on nothing else), made by the generic compiler at the first such pair: a copy with
    the leaves' parameter parts and the settings written in by one compiled call (~1 us against
    ~20 us for the tree and its compile); Delta is then given as its witness slots and size,
    and made when first read (GrowthDistance.delta)."""
    leaves = isinstance(A, Leaf) and isinstance(B, Leaf)
    if leaves:
        key = (A.kind, A._layout(), B.kind, B._layout())
        template = _DELTA_TEMPLATES.get(key)
        if template is not None:
            ints, floats, (sa, la, sb, lb), witnesses, size = template
            ints, floats = delta_arrays(ints, floats, sa, la, A._param_parts(), sb, lb,
                                        B._param_parts(), settings)
            return witnesses, ints, floats, size
    delta = MinkowskiSum([Affine(np.eye(3), A), Affine(-np.eye(3), B)])
    ints, floats = delta.program
    # the query's constants and memory go at the end of the program's floats: the kernel reads
    # floats at its nodes' offsets only
    floats = np.concatenate((floats, np.zeros(TAIL)))
    delta._program = (ints, floats)
    # an Affine node's parameters are [m, n, M (row-major), t]: M starts 2 further
    affines = children(ints, 0)
    tail = floats[-TAIL:]
    tail[MA], tail[MB] = (param_start(ints, node) + 2 for node in affines)
    tail[WS], tail[SPREAD] = delta.witness_size, WARM_SPREAD
    size = FRAME + capacity(3, delta.witness_size)
    if leaves:
        sa, sb = (param_start(ints, children(ints, node)[0]) for node in affines)
        blocks = (sa, len(A._params()), sb, len(B._params()))
        # copies taken before any query writes the poses and the solver's settings
        if len(_DELTA_TEMPLATES) >= MAX_TEMPLATES:
            _DELTA_TEMPLATES.pop(next(iter(_DELTA_TEMPLATES)), None)
        _DELTA_TEMPLATES[key] = (ints.copy(), floats.copy(), blocks,
                                 (list(delta._witness_slots), delta.witness_size), size)
    tail[METHOD:TOUCHING_TOL + 1] = settings
    return delta, ints, floats, size
