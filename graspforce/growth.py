"""Growth distance between two convex objects (section 4), with the contact point and normal.

An object is a 3-D convex set A_0 in its local frame, placed by a pose (R_A, p_A):
A = p_A + R_A(A_0) (eq. 7), where the local origin p_A must be an interior point. Its growth
model is A(sigma) = p_A + sigma R_A(A_0) (eq. 8) and the growth distance
    g(A, B) = min {sigma >= 0 : A(sigma) and B(sigma) intersect}              (eq. 9)
is the ray-shooting problem of eq. (10): with Delta = R_A(A_0) - R_B(B_0) and r = p_B - p_A,
g = 1/t for the farthest point z = t r of Delta on R(r). g > 1: separated, g = 1: touching,
g < 1: penetrating.

The contact (the derivation the paper omits). Every support point of the Minkowski sum Delta is
a pair: v = a - b with a a support point of R_A(A_0) and b one of R_B(B_0) in opposite
directions, and the witnesses of each vertex v_k of Z_Delta(r) name both. With the weights
lambda_k of z = sum_k lambda_k v_k, put a = sum_k lambda_k a_k (in R_A(A_0), convex) and
b = sum_k lambda_k b_k (in R_B(B_0)). Then z = a - b = t (p_B - p_A), i.e. with sigma = 1/t
    p_A + sigma a = p_B + sigma b,
a point of A(sigma) and of B(sigma): the contact point (point_a, point_b; equal up to rounding).
The normal n of the hyperplane supporting Delta at z (n^T r > 0) satisfies n^T z = h_Delta(n) =
h_{R_A A_0}(n) + h_{R_B B_0}(-n), and since n^T a <= h_{R_A A_0}(n) and -n^T b <= h_{R_B B_0}(-n)
both must be equalities: A(sigma) lies in {x : n^T x <= n^T point_a} and B(sigma) in
{x : n^T x >= n^T point_b}. So n, normalized, is the contact normal from A to B.
"""
import numpy as np
from numba import njit

from . import _shooters as S
from ._dispatch import shoot
from ._warm import shoot_warm
from ._validate import finite_array
from .quality import facet_expansion
from .ray_shoot import METHODS, check_tolerances
from .results import GrowthDistanceResult
from .sets import Affine, ConvexSet, MinkowskiSum

WARM_SPREAD = 0.05     # warm-start directions: the last normal +- this (a unit vector's tilt)
ORIGIN_TOL = 1e-9      # an origin closer than this fraction of the set's width to its boundary
                        # is not accepted as the interior point p_A of eq. (7)


def growth_distance(A, pose_a, B, pose_b, method="zc-ie", eps=1e-9, max_iter=1000,
                    touching_tol=1e-9):
    """g(A, B) of eq. (9)-(10) for 3-D convex sets A, B given in their local frames (whose
    origins are interior points) and poses as (R, p), 4x4 homogeneous matrices or
    pinocchio.SE3. Returns a GrowthDistanceResult: sigma, status, point_a, point_b, normal.

    For many queries on the same pair, `GrowthDistance(A, B)` compiles Delta once; this
    function keeps the last few pairs compiled.
    """
    key = (id(A), id(B), method, eps, max_iter, touching_tol)
    solver = _RECENT.get(key)
    if solver is None or solver.A is not A or solver.B is not B:
        solver = GrowthDistance(A, B, method, eps, max_iter, touching_tol)
        if len(_RECENT) >= 64:
            _RECENT.pop(next(iter(_RECENT)))
        _RECENT[key] = solver
    return solver(pose_a, pose_b)


_RECENT = {}


class GrowthDistance:
    """g(A, B) for one pair of shapes at many poses: Delta = R_A(A_0) - R_B(B_0) is compiled
    once, and each call writes the two rotations into its support program in place."""

    def __init__(self, A, B, method="zc-ie", eps=1e-9, max_iter=1000, touching_tol=1e-9,
                 warm_start=True):
        for name, X in (("A", A), ("B", B)):
            if not isinstance(X, ConvexSet):
                raise TypeError(f"{name}: expected a graspforce convex set, got "
                                f"{type(X).__name__}")
            if X.dim != 3:
                raise ValueError(f"{name}: must be a 3-D set, got dimension {X.dim}")
            _check_origin_interior(X, name)
        if method not in METHODS:
            raise ValueError(f"method: must be one of {sorted(METHODS)}, got {method!r}")
        self.A, self.B, self.method = A, B, method
        self.eps, self.max_iter = check_tolerances(eps, max_iter)
        if not (isinstance(touching_tol, float) and 0.0 <= touching_tol < 1.0):
            raise ValueError(f"touching_tol: must be a float in [0, 1), got {touching_tol!r}")
        self.touching_tol = touching_tol
        self.delta = MinkowskiSum([Affine(np.eye(3), A), Affine(-np.eye(3), B)])
        ints, floats = self.delta.program
        nn = ints[0]
        pstart, cstart = 1 + 2 * nn, 1 + 3 * nn
        first = ints[1 + 9 * nn + ints[cstart]]            # the root's two children
        second = ints[1 + 9 * nn + ints[cstart] + 1]
        # an Affine node's parameters are [m, n, M (row-major), t]: M starts 2 further
        self._m_a = slice(ints[pstart + first] + 2, ints[pstart + first] + 11)
        self._m_b = slice(ints[pstart + second] + 2, ints[pstart + second] + 11)
        self._code = METHODS[method]
        self._leaves_a = len(A.leaves())
        # time coherence: ZC-IE restarts near the last answer's normal (graspforce._warm)
        self.warm_start = bool(warm_start) and method == "zc-ie"
        self._normal = None

    def __call__(self, pose_a, pose_b):
        """The GrowthDistanceResult at these poses."""
        R_a, p_a = parse_pose(pose_a, "pose_a")
        R_b, p_b = parse_pose(pose_b, "pose_b")
        ints, floats = self.delta.program
        floats[self._m_a] = R_a.ravel()
        floats[self._m_b] = -R_b.ravel()
        r = p_b - p_a
        frame = (R_a, p_a, R_b, p_b, self)
        if not r.any():
            # coincident reference points: A(0) and B(0) are the same point
            return GrowthDistanceResult(0.0, 0.0, "penetrating", self.method, 0, 0, None, frame)
        if self.warm_start and self._normal is not None:
            out = shoot_warm(ints, floats, r, self.delta.witness_size, self.eps, self.max_iter,
                             self._normal, WARM_SPREAD)
        else:
            out = shoot(ints, floats, r, self.delta.witness_size, self._code, self.eps,
                        self.max_iter)
        status, t, t_up = out[0], out[1], out[2]
        self._normal = out[6] if status == S.HIT else None
        # 0 is interior to Delta (both origins are interior points), so the ray always hits
        sigma, lower = 1.0 / t, 1.0 / t_up
        if status != S.HIT:
            verdict = "max_iter"
        elif abs(sigma - 1.0) <= self.touching_tol:
            verdict = "touching"
        else:
            verdict = "separated" if sigma > 1.0 else "penetrating"
        return GrowthDistanceResult(sigma, lower, verdict, self.method, int(out[4]),
                                    int(out[5]), (self.delta, r, out), frame)


def contact_from_shot(result):
    """(point_a, point_b, normal) of a GrowthDistanceResult, by the derivation above."""
    R_a, p_a, R_b, p_b, solver = result.frame
    if result.shot is None:
        return p_a.copy(), p_b.copy(), np.zeros(3)
    shot, sigma = result.shot, result.sigma
    split = solver._leaves_a
    a = np.zeros(3)
    b = np.zeros(3)
    for weight, witness in zip(shot.weights, shot.witnesses):
        a += weight * solver.A.witness_point(tuple((j, x) for j, x in witness if j < split))
        b += weight * solver.B.witness_point(tuple((j - split, x) for j, x in witness
                                                   if j >= split))
    normal = shot.normal / np.linalg.norm(shot.normal)
    return p_a + sigma * (R_a @ a), p_b + sigma * (R_b @ b), normal


def parse_pose(pose, name):
    """(R (3, 3), p (3,)) from (R, p), a 4x4 homogeneous matrix or a pinocchio.SE3."""
    if hasattr(pose, "rotation") and hasattr(pose, "translation"):      # pinocchio.SE3
        R, p = pose.rotation, pose.translation
    elif isinstance(pose, (tuple, list)) and len(pose) == 2:
        R, p = pose
    else:
        M = finite_array(pose, name)
        if M.shape != (4, 4):
            raise ValueError(f"{name}: expected (R, p), a 4x4 matrix or a pinocchio.SE3, got "
                             f"shape {M.shape}")
        if not np.array_equal(M[3], [0.0, 0.0, 0.0, 1.0]):
            raise ValueError(f"{name}: the last row of a homogeneous matrix must be [0, 0, 0, 1]")
        R, p = M[:3, :3], M[:3, 3]
    if not (type(R) is np.ndarray and R.dtype == np.float64 and R.shape == (3, 3)):
        R = finite_array(R, f"{name} rotation", shape=(3, 3))
    if not (type(p) is np.ndarray and p.dtype == np.float64 and p.shape == (3,)):
        p = finite_array(p, f"{name} translation", shape=(3,))
    # one compiled check (~0.3 us) instead of numpy's R^T R and det (~6 us): NaN fails it too
    if not _proper_rotation(R, p):
        finite_array(R, f"{name} rotation")
        finite_array(p, f"{name} translation")
        raise ValueError(f"{name}: the rotation must be proper (R^T R = I to 1e-9, det R = 1)")
    return R, p


@njit(cache=True)
def _proper_rotation(R, p):
    for a in range(3):
        if not np.isfinite(p[a]):
            return False
        for b in range(3):
            s = 0.0
            for c in range(3):
                s += R[c, a] * R[c, b]
            if not abs(s - (1.0 if a == b else 0.0)) <= 1e-9:
                return False
    det = (R[0, 0] * (R[1, 1] * R[2, 2] - R[1, 2] * R[2, 1])
           - R[0, 1] * (R[1, 0] * R[2, 2] - R[1, 2] * R[2, 0])
           + R[0, 2] * (R[1, 0] * R[2, 1] - R[1, 1] * R[2, 0]))
    return det > 0.0


def _check_origin_interior(X, name):
    """The local origin must be interior (eq. 7), certified once per set by facet expansion
    (graspforce.quality): a flat set, or one whose origin lies outside or on its boundary, is
    rejected."""
    verdict = X.__dict__.get("_origin_interior")
    if verdict is None:
        verdict = X._origin_interior = facet_expansion(X, 0.0, ORIGIN_TOL, 500, True)[0]
    if not verdict:
        raise ValueError(f"{name}: the origin of its local frame must be an interior point "
                         "(eq. 7); this set is flat, or its origin is outside or on its boundary")

