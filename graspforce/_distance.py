"""Compiled distance algorithms of section 2: GJK (point to set) and ZC (point to convex cone).

Both keep a simplex as rows of P (points of A), Wt (their witnesses) and lam (weights), so a
caller can warm-start them and read Z_A(r) and its witnesses off the final rows.
"""
import numpy as np
from numba import njit
from numba.extending import register_jitable

from ._corral import combine, corral, set_row
from ._jit import borrowing
from ._kernel import support
from ._linalg import dot

CONVERGED = 0   # GJK: h_A(n) - n^T v within tolerance;  ZC: h_{A - shift}(n) within tolerance
INSIDE = 1      # the target is in CH(V) (GJK) or in CO(V - shift) (ZC): distance zero
STALLED = 2     # the new support point brought no decrease: the answer is exact to rounding
MAX_ITER = 3

# A least-squares residual below INSIDE_TOL times the target's norm is rounding, not distance.
# The point the callers report then differs from its convex combination by at most this much,
# relative.
INSIDE_TOL = 1e-11
ROUNDING = 1e-13   # about 500 unit roundoffs


@register_jitable
def scratch_of(rows, x, n):
    """The work arrays of `scratch(n)` as views of rows ((2 n + 5) x (n + 1)) and x (n + 2
    entries): a caller compiled without reference counting (graspforce._jit) lays them out in
    arrays it owns."""
    return (rows[:n], rows[n:2 * n], rows[2 * n + 3, :n], rows[2 * n + 4, :n], x,
            rows[2 * n:2 * n + 3])


@njit(cache=True)
def scratch(n):
    """Work arrays of the active-set subproblem (D, work, rhs, wrhs, x, house; graspforce._corral):
    allocated once by each shooter and passed to every GJK / ZC call, so that the calls of one
    shot allocate nothing. Rows of two allocations, not six: a few-microsecond shot feels each
    allocation (~20 ns with its free)."""
    return scratch_of(np.empty((2 * n + 5, n + 1)), np.empty(n + 2), n)


@borrowing
def gjk(ints, floats, b, P, Wt, lam, k, eps_rel, eps_abs, rel_to_offset, max_iter, nvec, v,
        point, wit, sc):
    """GJK (section 2.2): d_A(b) and v_A(b) from the simplex P[:k] (k = 0: cold start).

    Stops when h_A(n_k) - n_k^T v_k <= eps_abs + eps_rel * ref, ref = |n_k^T v_k| (the offset of
    the hyperplane H(n_k, v_k), as the ray shooters need) or d (relative distance error).
    Returns (status, k, d, h_A(n_k), iterations, support_calls); n_k in nvec, v_k in v.
    sc: the work arrays of `scratch(n)`.
    """
    n = b.shape[0]
    D, work, rhs, wrhs, x, house = sc
    calls = 0
    fact = 0      # corral's factored columns: none yet (`sc` may hold another caller's)
    if k == 0:
        for i in range(n):
            nvec[i] = b[i]
        if np.sqrt(dot(b, b)) == 0.0:
            nvec[0] = 1.0
        support(ints, floats, nvec, point, wit)
        calls += 1
        set_row(P, Wt, 0, point, wit)
        lam[0] = 1.0
        k = 1
    else:
        k, _, fact = corral(P, Wt, lam, k, b, b, True, D, work, rhs, wrhs, x, house, fact)
    tiny = ROUNDING * (np.sqrt(dot(b, b)) + np.sqrt(dot(P[0], P[0]))) + 1e-300
    d = np.inf
    h = 0.0
    for it in range(max_iter):
        combine(P, lam, k, v)
        d = 0.0
        for i in range(n):
            nvec[i] = b[i] - v[i]
            d += nvec[i] * nvec[i]
        d = np.sqrt(d)
        if d <= tiny or k == n + 1:
            # n + 1 affinely independent points: b is reproduced exactly, up to rounding
            return INSIDE, k, 0.0, h, it, calls
        for i in range(n):
            nvec[i] /= d
        h = support(ints, floats, nvec, point, wit)
        calls += 1
        offset = dot(nvec, v)
        ref = abs(offset) if rel_to_offset else d
        if h - offset <= eps_abs + eps_rel * ref:
            return CONVERGED, k, d, h, it + 1, calls
        set_row(P, Wt, k, point, wit)
        lam[k] = 0.0
        k, kept, fact = corral(P, Wt, lam, k + 1, b, b, True, D, work, rhs, wrhs, x, house,
                               fact)
        if not kept:
            return STALLED, k, d, h, it + 1, calls
    return MAX_ITER, k, d, h, max_iter, calls


@borrowing
def zc(ints, floats, shift, target, P, Wt, lam, k, eps_rel, eps_abs, max_iter, nvec, v, point,
       wit, sc):
    """ZC (section 2.3): distance from `target` to CO(A - shift) with generators P[:k] - shift.

    Stops (CONVERGED) when h_{A-shift}(n_k) <= eps_abs + eps_rel * n_k^T shift; INSIDE when the
    target is a positive combination lam[:k] of P[:k] - shift. Returns (status, k, d,
    h_{A-shift}(n_k), iterations, support_calls); n_k in nvec, v_CO in v. sc: the work
    arrays of `scratch(n)`.
    """
    n = target.shape[0]
    D, work, rhs, wrhs, x, house = sc
    calls = 0
    tnorm = np.sqrt(dot(target, target))
    if k == 0:
        for i in range(n):
            nvec[i] = target[i] / tnorm
        h = support(ints, floats, nvec, point, wit) - dot(nvec, shift)
        calls += 1
        if h <= eps_abs + eps_rel * dot(nvec, shift):
            # the hyperplane through `shift` with normal `target` already supports A (within
            # the same rule as below: shift may sit a rounding error inside a vertex)
            v[:] = 0.0
            return CONVERGED, 0, tnorm, h, 0, calls
        set_row(P, Wt, 0, point, wit)
        lam[0] = 0.0
        k = 1
    else:
        for j in range(k):
            lam[j] = 0.0
    k, _, fact = corral(P, Wt, lam, k, target, shift, False, D, work, rhs, wrhs, x, house, 0)
    h = 0.0
    d = tnorm
    for it in range(max_iter):
        for i in range(n):
            v[i] = 0.0
        mass = 0.0
        for j in range(k):
            gnorm = 0.0
            for i in range(n):
                g = P[j, i] - shift[i]
                v[i] += lam[j] * g
                gnorm += g * g
            mass += lam[j] * np.sqrt(gnorm)
        d = 0.0
        defect = 0.0
        for i in range(n):
            nvec[i] = target[i] - v[i]
            d += nvec[i] * nvec[i]
            defect += nvec[i] * v[i]
        d = np.sqrt(d)
        if (d <= INSIDE_TOL * tnorm or d <= ROUNDING * mass or abs(defect) >= 0.1 * d * d
                or k == n):
            # The residual is rounding: of the target's size; of the terms lam_j (P_j - shift),
            # which grow like 1/(t_{k+1} - t_k) as b_k nears z_A(r); or of an ill-conditioned
            # cone, seen as lost orthogonality (a true projection has (target - v) ^T v = 0).
            # Or n independent generators span R^n. The point the shooters build from lam
            # moves by d / sum(lam), far below INSIDE_TOL relative.
            return INSIDE, k, 0.0, h, it, calls
        for i in range(n):
            nvec[i] /= d
        h = support(ints, floats, nvec, point, wit) - dot(nvec, shift)
        calls += 1
        if h <= eps_abs + eps_rel * dot(nvec, shift):
            return CONVERGED, k, d, h, it + 1, calls
        set_row(P, Wt, k, point, wit)
        lam[k] = 0.0
        k, kept, fact = corral(P, Wt, lam, k + 1, target, shift, False, D, work, rhs, wrhs, x,
                               house, fact)
        if not kept:
            return STALLED, k, d, h, it + 1, calls
    return MAX_ITER, k, d, h, max_iter, calls
