"""Force closure and the Ferrari-Canny quality of a grasp, on the exact wrench set W of eq. (14).

The grasp is force-closure iff the origin is interior to W, and its quality is the radius of the
largest origin-centred ball inside W,
    Q = min_{||u|| = 1} h_W(u),
the largest wrench (in any direction) that unit contact forces are guaranteed to resist.

Both are computed by facet expansion, the idea behind IE (section 3.2) applied to every direction
at once: keep a polytope P of support points of W (so P is inside W), take the facet of P nearest
to the origin, with outward unit normal u, and add s_W(u). Every step certifies a bracket:
    lower = the distance from the origin to P's nearest facet <= Q  (P inside W),
    upper = the least h_W(u) seen so far >= Q                       (the ball fits under every
                                                                      supporting hyperplane).
While the origin is outside P, the facet it violates most is pushed instead; a normal u with
h_W(u) <= tol proves the origin is not interior (up to tol): W lies in {x : u^T x <= tol}, so the
wrench -u cannot be resisted (or only at an unbounded force). The polytope is kept by Qhull
(scipy.spatial.ConvexHull, incremental). This is not a hot path: a few hundred steps in Python.
"""
import math

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..records.results import GraspQuality

FLAT = 1e-13       # W's extent along a normal below this fraction of its largest width is rounding


def facet_expansion(W, eps, tol, max_iter, stop_at_closure):
    """(force_closure, lower, upper, direction, iterations, support_calls) for the set W."""
    n = W.dim
    points = []
    upper = math.inf
    direction = np.zeros(n)
    for axis in np.vstack((np.eye(n), -np.eye(n))):
        h, s = W.support(axis)
        points.append(s)
        if h < upper:
            upper, direction = h, axis
    calls = 2 * n
    widths = np.ptp(np.asarray(points), axis=0)
    # tol is relative to W's extent along each normal, |widths * u|: the answer then does not
    # change when W is scaled, as a whole or per coordinate (a grasp's torques scale with its
    # lengths, its forces do not); the floor keeps a W that is flat up to rounding flat
    floor = FLAT * max(widths.max(), 1e-300)

    def tol_along(u):
        return tol * max(math.sqrt(float(np.dot(widths * u, widths * u))), floor)

    if upper <= tol_along(direction):
        return False, 0.0, 0.0, direction, 0, calls
    inner, flat, calls = _initial_polytope(W, points, widths, calls, tol_along)
    if inner is None:
        return False, 0.0, 0.0, flat, 0, calls
    lower = -math.inf
    inside = False
    for iteration in range(1, max_iter + 1):
        normals, offsets = inner.facets()
        nearest = int(np.argmin(offsets))           # the facet nearest the origin
        u = normals[nearest]
        lower = offsets[nearest]                    # P only grows, so this never decreases
        inside = lower > tol_along(u)
        if inside and stop_at_closure:
            return True, lower, upper, direction, iteration, calls
        h, s = W.support(u)
        calls += 1
        if h < upper:
            upper, direction = h, u.copy()
        if h <= tol_along(u) or upper <= tol_along(direction):
            return False, 0.0, 0.0, direction, iteration, calls
        if inside and upper - lower <= eps * upper:
            return True, lower, upper, direction, iteration, calls
        inner.add(s)
    return inside, max(lower, 0.0), upper, direction, max_iter, calls


class _InnerPolytope:
    """P = CH(support points of W), kept by Qhull in coordinates scaled to unit widths: Qhull's
    precision is relative to the coordinate range, and a wrench mixes newtons with newton-metres
    (a 10 cm object's torques are 20 times smaller than its forces)."""

    def __init__(self, points, widths):
        self.scale = 1.0 / np.where(widths > 0.0, widths, 1.0)
        self.points = [p * self.scale for p in points]
        self.hull = ConvexHull(np.asarray(self.points), incremental=True)

    def facets(self):
        """(unit outward normals, distances from the origin) of P's facets, a^T x <= d inside."""
        eq = self.hull.equations                    # a'^T x' + b' <= 0 inside, x' = scale x
        a = eq[:, :-1] * self.scale
        length = np.linalg.norm(a, axis=1)
        return a / length[:, None], -eq[:, -1] / length

    def add(self, point):
        self.points.append(point * self.scale)
        try:
            self.hull.add_points(self.points[-1][None, :])
        except QhullError:
            # nearly coplanar facets Qhull refuses to merge incrementally: rebuild, allowing
            # wide merges (Q12); the facets stay those of the same point set
            self.hull = ConvexHull(np.asarray(self.points), incremental=True,
                                   qhull_options="Qt Qx Q12")


def _initial_polytope(W, points, widths, calls, tol_along):
    """(P, None, calls), or (None, u, calls) with h_W(u) + h_W(-u) <= tol when W is flat.

    The axis supports can span less than R^n although W does not (coincident support points);
    the normal v of their affine span then either has a width h_W(v) + h_W(-v) > tol, and its two
    support points extend the span, or W is flat along v and the origin cannot be interior."""
    n = W.dim
    # the span is judged in coordinates scaled to unit widths, as Qhull sees the points
    scale = 1.0 / np.where(widths > 0.0, widths, 1.0)
    while True:
        arr = np.asarray(points) * scale
        _, sv, vt = np.linalg.svd(arr - arr.mean(axis=0))
        if len(sv) >= n and sv[n - 1] > 1e-9 * max(sv[0], 1e-300):
            try:
                return _InnerPolytope(points, widths), None, calls
            except QhullError:
                pass                        # nearly flat for Qhull: widen along the thinnest axis
        v = (vt[-1] if len(sv) < n else vt[n - 1]) * scale     # the span's normal, unscaled
        v = v / np.linalg.norm(v)
        h_plus, s_plus = W.support(v)
        h_minus, s_minus = W.support(-v)
        calls += 2
        if h_plus + h_minus <= tol_along(v):
            return None, v if h_plus <= h_minus else -v, calls
        points.extend((s_plus, s_minus))


def grasp_quality(W, norm, magnitude, eps, tol, max_iter):
    closure, lower, upper, direction, iterations, calls = facet_expansion(
        W, eps, tol, max_iter, stop_at_closure=False)
    if not closure:
        lower = upper = 0.0
    return GraspQuality(force_closure=bool(closure), value=float(0.5 * (lower + upper)),
                        lower=float(lower), upper=float(upper), direction=direction, norm=norm,
                        magnitude=magnitude, iterations=iterations, support_calls=calls)
