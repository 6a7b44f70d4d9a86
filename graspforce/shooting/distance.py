"""gf.closest_point (GJK, section 2.2) and gf.cone_distance (ZC, section 2.3)."""
import numpy as np

from .. import _core as D
from .._validate import finite_array, finite_scalar, positive_int
from ..records.results import ClosestPoint, ConeDistance
from ..geometry.sets import ConvexSet


def _check(A, b, eps, max_iter):
    if not isinstance(A, ConvexSet):
        raise TypeError(f"A: expected a graspforce convex set, got {type(A).__name__}")
    b = finite_array(b, "b", shape=(A.dim,))
    return (b, finite_scalar(eps, "eps", minimum=0.0, exclusive=True),
            positive_int(max_iter, "max_iter"))


def closest_point(A, b, eps=1e-12, max_iter=1000):
    """d_A(b) and v_A(b) of eq. (3) by GJK, with V_A(b) and its convex weights.

    eps is relative to the distance: GJK stops once h_A(n) - n^T v <= eps d, so the distance
    is exact to a factor (1 - eps).
    """
    b, eps, max_iter = _check(A, b, eps, max_iter)
    ints, floats = A.program
    st, d, gap, it, calls, v, V, lam, W = D.closest_point(ints, floats, b, A.witness_size,
                                                               eps, max_iter)
    status = {D.CONVERGED: "converged", D.STALLED: "converged", D.INSIDE: "inside",
              D.MAX_ITER: "max_iter"}[st]
    return ClosestPoint(distance=d, point=b.copy() if st == D.INSIDE else v, vertices=V,
                        weights=lam, witnesses=tuple(A.decode_witness(w) for w in W), gap=gap,
                        status=status, iterations=int(it), support_calls=int(calls))


def cone_distance(A, b, eps=1e-12, max_iter=1000):
    """d_CO(A)(b) and v_CO(A)(b) by the ZC algorithm, with linearly independent generators.

    eps is absolute, in the units of A: ZC stops once h_A(n) <= eps (section 2.3).
    """
    b, eps, max_iter = _check(A, b, eps, max_iter)
    if not np.any(b):
        raise ValueError("b: must be nonzero (its distance to any cone is 0 at the apex)")
    ints, floats = A.program
    st, d, h, it, calls, v, nvec, V, lam, W = D.cone_distance(ints, floats, b,
                                                                   A.witness_size, eps,
                                                                   max_iter)
    status = {D.CONVERGED: "outside", D.STALLED: "outside", D.INSIDE: "inside",
              D.MAX_ITER: "max_iter"}[st]
    return ConeDistance(distance=d, point=b.copy() if st == D.INSIDE else v, vertices=V,
                        coefficients=lam, witnesses=tuple(A.decode_witness(w) for w in W),
                        normal=nvec, support_value=h if st != D.INSIDE else 0.0, status=status,
                        iterations=int(it), support_calls=int(calls))
