"""The subproblem shared by GJK and ZC: the point of a small set's affine-convex hull (GJK) or
convex cone (ZC) closest to a target, with the minimal subset V-hat_k that represents it.

An active-set method on the weights (Wolfe's minimum-norm-point minor cycle for the hull,
Lawson-Hanson for the cone): solve the unconstrained least-squares problem on the current subset;
if a weight is not positive, step back to the boundary and drop that point. Unlike Johnson's
recursion it is exact in any dimension and never enumerates sub-simplices.
"""
import numpy as np

from ._jit import borrowing
from ._linalg import lstsq, lstsq_append


@borrowing(forceinline=True)
def set_row(P, Wt, j, point, wit):
    """Row j of the simplex := (point, witness). Element loops, not slices: in these hot loops
    a slice cost a reference-count round trip (~1.5 us of ZC-IE's 24, before graspforce._jit)."""
    for i in range(P.shape[1]):
        P[j, i] = point[i]
    for i in range(Wt.shape[1]):
        Wt[j, i] = wit[i]


@borrowing(forceinline=True)
def drop_point(P, Wt, lam, k, j):
    """Remove row j of the simplex (points, witnesses, weights); returns the new size."""
    for i in range(j, k - 1):
        for a in range(P.shape[1]):
            P[i, a] = P[i + 1, a]
        for a in range(Wt.shape[1]):
            Wt[i, a] = Wt[i + 1, a]
        lam[i] = lam[i + 1]
    return k - 1


@borrowing(forceinline=True)
def residual2(P, x, k, b):
    """(||sum_j x_j P_j - b||^2, ||b||^2) over the rows P[:k]."""
    res = 0.0
    bn = 0.0
    for i in range(P.shape[1]):
        e = -b[i]
        for j in range(k):
            e += x[j] * P[j, i]
        res += e * e
        bn += b[i] * b[i]
    return res, bn


@borrowing
def reproduce(P, x, k, b):
    """Whether the weights x[:k] of the rows P[:k] reproduce b to 1e-12 (1 + ||b||), the rounding
    floor of Fig. 3b's rule; if so they are clipped at zero and normalized to sum to 1."""
    res, bn = residual2(P, x, k, b)
    if res > (1e-12 * (1.0 + np.sqrt(bn))) ** 2:
        return False
    s = 0.0
    for j in range(k):
        x[j] = max(x[j], 0.0)
        s += x[j]
    for j in range(k):
        x[j] /= s
    return True


@borrowing
def weights_on_ray(S, m, r, x, D, work, wrhs, rhs):
    """Weights x[:m] (summing to 1) and t (returned) of the point of CH(S[:m]) nearest the ray,
    by least squares: S_0 + sum_p x_p (S_p - S_0) = t r. -1 when rank deficient."""
    n = r.shape[0]
    for i in range(n):
        for p in range(1, m):
            D[i, p - 1] = S[p, i] - S[0, i]
        D[i, m - 1] = -r[i]
        rhs[i] = -S[0, i]
    if not lstsq(D, n, m, rhs, x, 1, work, wrhs):
        return -1.0
    t = x[m]
    x[0] = 1.0
    for p in range(1, m):
        x[0] -= x[p]
    return t


@borrowing
def corral(P, Wt, lam, k, target, shift, affine, D, work, rhs, wrhs, x, house, fact):
    """Reduce the simplex P[:k] (the last row just added, weight 0) to the minimal subset whose
    hull (affine=True: convex combinations) or cone (affine=False: nonnegative combinations of
    P_i - shift) holds the point closest to `target`. Writes the positive weights to lam[:k].

    The least squares keep their QR between calls (`lstsq_append`): `fact` columns are factored
    in work and house from the previous call with the same target and shift (0: none). The
    cone's column j is P_j - shift; the hull's column j is P_{j+1} - P_0, so that dropping P_0
    discards them all.

    Returns (k, newest_kept, fact): newest_kept is False when the new point brought no
    improvement or was numerically dependent on the others, which the callers read as "no
    progress"; fact for the next call.
    """
    n = P.shape[1]
    off = 1 if affine else 0     # row j of P is column j - off of D
    newest = k - 1
    while k > 0:
        q = k - off
        for i in range(n):
            base = P[0, i] if affine else shift[i]
            rhs[i] = target[i] - base if affine else target[i]
            for j in range(fact, q):
                D[i, j] = P[j + off, i] - base
        fact = lstsq_append(D, n, q, fact, rhs, x, work, wrhs, house)
        ok = fact >= 0
        fact = max(fact, 0)
        if not ok:
            if newest < 0:
                return k, False, fact
            k = drop_point(P, Wt, lam, k, newest)
            fact = min(fact, max(newest - off, 0))
            newest = -1
            continue
        if affine:
            # x held the weights of P_1..P_{k-1}; P_0 takes the rest
            s = 1.0
            for j in range(q - 1, -1, -1):
                x[j + 1] = x[j]
                s -= x[j]
            x[0] = s
        theta = 1.0
        arg = -1
        for j in range(k):
            if x[j] <= 0.0:
                den = lam[j] - x[j]
                th = lam[j] / den if den > 0.0 else 0.0
                if th < theta or arg < 0:
                    theta = th
                    arg = j
        if arg < 0:
            for j in range(k):
                lam[j] = x[j]
            return k, newest >= 0, fact
        for j in range(k):
            lam[j] += theta * (x[j] - lam[j])
        lam[arg] = 0.0
        j = k - 1
        while j >= 0:
            if lam[j] <= 0.0:
                k = drop_point(P, Wt, lam, k, j)
                fact = min(fact, max(j - off, 0))
                if j == newest:
                    newest = -1
                elif j < newest:
                    newest -= 1
            j -= 1
    return k, False, fact


@borrowing(forceinline=True)
def combine(P, lam, k, out):
    """out = sum_i lam_i P_i."""
    for i in range(P.shape[1]):
        out[i] = 0.0
    for j in range(k):
        for i in range(P.shape[1]):
            out[i] += lam[j] * P[j, i]
