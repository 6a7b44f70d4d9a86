"""gf.ray_shoot: z_A(r), Z_A(r) and a supporting hyperplane by the five procedures of section 3."""
import math

import numpy as np

from .. import _core as S
from .._core import BAD_RAY, capacity, shoot_packed
from ..geometry._start_table import start_table
from .._validate import check_choice, finite_scalar, finite_vector, is_vector, positive_int
from ..records.results import RayShot
from ..geometry.sets import ConvexSet

METHODS = {"gjk": S.GJK_BASED, "ie": S.IE, "zc": S.ZC_BASED, "bi-gjk": S.BI_GJK,
           "zc-ie": S.ZC_IE, "zc-ie-paper": S.ZC_IE_PAPER, "zc-ie-newton": S.ZC_IE_NEWTON}


def check_ray(r, n):
    """r as a finite, nonzero float64 vector of n entries, or the error that names the rule."""
    r, rr = finite_vector(r, "r", n)
    if rr == 0.0:
        raise ValueError("r: the ray direction must be nonzero")
    return r


def check_tolerances(eps, max_iter):
    # exact type tests first: the common call passes a float and an int and pays ~100 ns
    if type(eps) is not float or not 0.0 < eps < math.inf:
        eps = finite_scalar(eps, "eps", minimum=0.0, exclusive=True)
    if type(max_iter) is not int or max_iter < 1:
        max_iter = positive_int(max_iter, "max_iter")
    return eps, max_iter


def ray_shoot(A, r, method="zc-ie", eps=1e-9, max_iter=10000):
    """Farthest point z_A(r) of A on the ray R(r) = {lambda r : lambda >= 0} (section 2.1).

    method: "gjk" (3.1), "ie" (3.2), "zc" (3.3), "bi-gjk" (3.4.1), "zc-ie-paper" (3.4.2, as
    the paper states it), "zc-ie" (the default: ZC-IE with a Newton finish on a hull of
    ellipsoid pieces whose exit face is smooth, such as W_L1 of contacts whose friction
    saturates; elsewhere the same steps as "zc-ie-paper"), or "zc-ie-newton" (ZC-IE with the
    Newton finish on the exit face's pieces of any set). The Newton finishes
    (core/shooting/newton.hpp) take fewer iterations where the exit face is curved, and their
    answers are certified by the same stopping rule.
    eps: relative tolerance; every method stops once (h_A(n) - n^T z) <= eps n^T z, which
    bounds the relative error in t by eps (t_upper / t - 1 <= eps).
    max_iter: iteration limit; reaching it is the status "max_iter", never an exception. IE-type
    steps (IE, ZC-IE, ZC-based) converge linearly on curved sets, slower as n grows: a hull of
    three ellipsoids in R^12 takes IE ~900 and ZC-based ~1200 of them at eps = 1e-9.
    """
    code = METHODS.get(method)
    if code is None:
        check_choice(method, METHODS, "method")
    layout = getattr(A, "_shot_layout", None)
    if layout is None:
        layout = shot_layout(A)
    ints, floats, ws, size, compiled = layout
    eps, max_iter = check_tolerances(eps, max_iter)
    table = start_table(A)
    packed = np.empty(size)
    # the common call, a float64 (n,) array, goes straight to the compiled code, which checks
    # that it is finite and nonzero; anything else, or a refused r, is checked here
    head = None
    if is_vector(r) and r.shape[0] == A.dim:
        head = compiled(ints, floats, r, ws, code, eps, max_iter, packed, table)
    if head is None or head[0] == BAD_RAY:
        r = np.ascontiguousarray(check_ray(r, A.dim))
        head = compiled(ints, floats, r, ws, code, eps, max_iter, packed, table)
    return RayShot.from_packed(A, r, method, head, packed)


def shot_layout(A):
    """(ints, floats, witness size, entries of the packed result, compiled shoot_packed) of every
    shot on A, kept on A: read there, they cost one attribute lookup instead of ~0.6 us of
    properties per call."""
    if not isinstance(A, ConvexSet):
        raise TypeError(f"A: expected a graspforce convex set, got {type(A).__name__}")
    ints, floats = A.program
    ws = A.witness_size
    A._shot_layout = (ints, floats, ws, capacity(A.dim, ws), shoot_packed)
    return A._shot_layout

