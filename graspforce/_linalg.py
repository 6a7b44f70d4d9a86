"""Small dense solvers for the jitted algorithms (n <= ~16, no allocation in the hot loop).

Householder QR least squares (conditioning of the data, not of its square, which the 1e-9
accuracy goal needs), LU with partial pivoting for the square facet systems of IE, and the
Gauss-Jordan inverse that ZC-IE's steps update by pivots.

The small helpers called in the algorithms' inner loops here and in _corral and _shooters are
compiled with forceinline=True (LLVM's alwaysinline): a call passes every array as its seven
fields and costs more than their arithmetic (an IE step's helpers in R^6: 229 ns as calls, 113
ns inlined, 152 ns with Numba's inline='always', which keeps their reference counting). All
of them borrow their arrays (graspforce._jit).
"""
import numpy as np

from ._jit import borrowing

RANK_TOL = 1e-12


@borrowing(forceinline=True)
def dot(a, b):
    """a^T b for 1-D arrays. np.dot calls BLAS: ~25 ns on 3- to 6-vectors against ~1.5 ns for
    this loop, and the hot loops take several per iteration."""
    s = 0.0
    for i in range(a.shape[0]):
        s += a[i] * b[i]
    return s


@borrowing(forceinline=True)
def smallest(x, n):
    """min(x[:n]) for n >= 1, inlined (np.min is a call)."""
    m = x[0]
    for i in range(1, n):
        m = min(m, x[i])
    return m


@borrowing
def lstsq(D, n, q, rhs, x, x0, work, wrhs):
    """x[x0:x0 + q] = argmin ||D[:n, :q] x - rhs[:n]||. False when D is (numerically) rank
    deficient. `work` (n, q) and `wrhs` (n) are scratch; D and rhs are left untouched. (An offset,
    not a view x[x0:]: a view costs a reference-count round trip in the hot loop.)
    """
    for i in range(n):
        wrhs[i] = rhs[i]
        for j in range(q):
            work[i, j] = D[i, j]
    scale = 0.0
    for j in range(q):
        s = 0.0
        for i in range(n):
            s += work[i, j] * work[i, j]
        scale = max(scale, np.sqrt(s))
    if scale == 0.0:
        return q == 0
    for j in range(q):
        # Householder reflection zeroing work[j+1:, j]
        s = 0.0
        for i in range(j, n):
            s += work[i, j] * work[i, j]
        alpha = np.sqrt(s)
        if alpha <= RANK_TOL * scale:
            return False
        if work[j, j] > 0.0:
            alpha = -alpha
        v0 = work[j, j] - alpha
        vnorm2 = s - work[j, j] * work[j, j] + v0 * v0
        work[j, j] = v0
        if vnorm2 > 0.0:
            for c in range(j + 1, q):
                d = 0.0
                for i in range(j, n):
                    d += work[i, j] * work[i, c]
                f = 2.0 * d / vnorm2
                for i in range(j, n):
                    work[i, c] -= f * work[i, j]
            d = 0.0
            for i in range(j, n):
                d += work[i, j] * wrhs[i]
            f = 2.0 * d / vnorm2
            for i in range(j, n):
                wrhs[i] -= f * work[i, j]
        work[j, j] = alpha
    for j in range(q - 1, -1, -1):
        s = wrhs[j]
        for c in range(j + 1, q):
            s -= work[j, c] * x[x0 + c]
        x[x0 + j] = s / work[j, j]
    return True


@borrowing
def lstsq_append(D, n, q, fact, rhs, x, work, wrhs, house):
    """`lstsq` (x at offset 0) when work and house already hold the Householder QR of D's first
    `fact` columns, left by an earlier call on the same columns: only columns fact..q-1 are
    reduced, O(n q) a column instead of O(n q^2) for all. ZC's active set grows a column a
    step, so each of its projections reduces one column (D's first `fact` columns are not
    read). house: per column the reflection's first entry, 2 / ||v||^2 and the column's norm.
    Returns q, the columns now factored, or -1 when D is (numerically) rank deficient: the
    same test as `lstsq`, alpha_j <= RANK_TOL max_j ||D_j||.
    """
    # Q^T rhs through the reflections kept, then each new one
    for i in range(n):
        wrhs[i] = rhs[i]
    for j in range(q):
        if j >= fact:
            norm2 = 0.0
            for i in range(n):
                work[i, j] = D[i, j]
                norm2 += D[i, j] * D[i, j]
            house[2, j] = np.sqrt(norm2)
            for c in range(j):
                _reflect_column(work, n, house, c, j)
            s = 0.0
            for i in range(j, n):
                s += work[i, j] * work[i, j]
            alpha = np.sqrt(s)
            if work[j, j] > 0.0:
                alpha = -alpha
            v0 = work[j, j] - alpha
            vnorm2 = s - work[j, j] * work[j, j] + v0 * v0
            house[0, j] = v0
            house[1, j] = 2.0 / vnorm2 if vnorm2 > 0.0 else 0.0
            work[j, j] = alpha
        _reflect_vector(work, n, house, j, wrhs)
    scale = 0.0
    for j in range(q):
        scale = max(scale, house[2, j])
    for j in range(q):
        if not abs(work[j, j]) > RANK_TOL * scale:
            return -1
    for j in range(q - 1, -1, -1):
        s = wrhs[j]
        for c in range(j + 1, q):
            s -= work[j, c] * x[c]
        x[j] = s / work[j, j]
    return q


@borrowing(forceinline=True)
def _reflect_column(work, n, house, j, c):
    """Apply reflection j of `lstsq_append` (v = [house[0, j], work[j+1:, j]]) to work[:, c]."""
    v0 = house[0, j]
    d = v0 * work[j, c]
    for i in range(j + 1, n):
        d += work[i, j] * work[i, c]
    f = house[1, j] * d
    work[j, c] -= f * v0
    for i in range(j + 1, n):
        work[i, c] -= f * work[i, j]


@borrowing(forceinline=True)
def _reflect_vector(work, n, house, j, y):
    """Apply reflection j of `lstsq_append` to the vector y."""
    v0 = house[0, j]
    d = v0 * y[j]
    for i in range(j + 1, n):
        d += work[i, j] * y[i]
    f = house[1, j] * d
    y[j] -= f * v0
    for i in range(j + 1, n):
        y[i] -= f * work[i, j]


@borrowing(forceinline=True)
def _eliminate(lu, n, k):
    """One step of Gaussian elimination on lu[:n, :n] with pivot lu[k, k]: the multipliers
    into column k below it, the Schur complement into the trailing block."""
    inv = 1.0 / lu[k, k]
    for i in range(k + 1, n):
        lu[i, k] *= inv
        f = lu[i, k]
        if f != 0.0:
            for j in range(k + 1, n):
                lu[i, j] -= f * lu[k, j]


@borrowing(forceinline=True)
def _copy_scale(M, n, A):
    """A[:n, :n] = M[:n, :n]; returns max |M_ij|, the scale of the singularity test."""
    scale = 0.0
    for i in range(n):
        for j in range(n):
            A[i, j] = M[i, j]
            scale = max(scale, abs(M[i, j]))
    return scale


@borrowing(forceinline=True)
def _partial_pivot(A, n, k, piv, scale):
    """Swap into row k the row at or below it with the largest |A_ik| (recorded in piv[k]);
    False when that pivot is below 1e-14 scale: singular to working precision."""
    p = k
    best = abs(A[k, k])
    for i in range(k + 1, n):
        if abs(A[i, k]) > best:
            best = abs(A[i, k])
            p = i
    piv[k] = p
    if best <= 1e-14 * scale:
        return False
    if p != k:
        for j in range(n):
            tmp = A[k, j]
            A[k, j] = A[p, j]
            A[p, j] = tmp
    return True


@borrowing
def lu_factor(M, n, lu, piv):
    """LU with partial pivoting of M[:n, :n] into lu; False when singular to working precision."""
    scale = _copy_scale(M, n, lu)
    if scale == 0.0:
        return False
    for k in range(n):
        if not _partial_pivot(lu, n, k, piv, scale):
            return False
        _eliminate(lu, n, k)
    return True


@borrowing
def invert(M, n, B, piv):
    """B[:n, :n] = M[:n, :n]^{-1} by Gauss-Jordan elimination with partial pivoting; False when
    singular to working precision (lu_factor's test: the pivots are the same). One reciprocal a
    column: LU and n solves divide n^2 / 2 times, in a dependent chain (R^6: 550 -> 220 ns)."""
    scale = _copy_scale(M, n, B)
    if scale == 0.0:
        return False
    for k in range(n):
        if not _partial_pivot(B, n, k, piv, scale):
            return False
        inv = 1.0 / B[k, k]
        B[k, k] = 1.0
        for j in range(n):
            B[k, j] *= inv
        for i in range(n):
            f = B[i, k]
            if i != k and f != 0.0:
                B[i, k] = 0.0
                for j in range(n):
                    B[i, j] -= f * B[k, j]
    # the row interchanges of M are column interchanges of its inverse, undone in reverse
    for k in range(n - 1, -1, -1):
        p = piv[k]
        if p != k:
            for i in range(n):
                tmp = B[i, k]
                B[i, k] = B[i, p]
                B[i, p] = tmp
    return True


@borrowing(forceinline=True)
def lu_solve(lu, piv, n, b, x):
    """Solve M x = b from lu_factor(M); x may be b itself."""
    for i in range(n):
        x[i] = b[i]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = x[k]
            x[k] = x[p]
            x[p] = tmp
    for i in range(n):
        s = x[i]
        for j in range(i):
            s -= lu[i, j] * x[j]
        x[i] = s
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, n):
            s -= lu[i, j] * x[j]
        x[i] = s / lu[i, i]


@borrowing(forceinline=True)
def lu_solve_t(lu, piv, n, b, x):
    """Solve M^T x = b from lu_factor(M)."""
    for i in range(n):
        x[i] = b[i]
    for i in range(n):
        s = x[i]
        for j in range(i):
            s -= lu[j, i] * x[j]
        x[i] = s / lu[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, n):
            s -= lu[j, i] * x[j]
        x[i] = s
    for k in range(n - 1, -1, -1):
        p = piv[k]
        if p != k:
            tmp = x[k]
            x[k] = x[p]
            x[p] = tmp


@borrowing(forceinline=True)
def _swap(a, order, n, i, j):
    """Exchange rows i and j of a[:, :n] and entries i and j of the permutation `order`."""
    if i == j:
        return
    for c in range(n):
        tmp = a[i, c]
        a[i, c] = a[j, c]
        a[j, c] = tmp
    tmp2 = order[i]
    order[i] = order[j]
    order[j] = tmp2


@borrowing
def solve_basic(M, n, lu, prow, pcol, b, x, tol=1e-13):
    """A basic solution x of M[:n, :n] x = b by LU with complete pivoting: the unknowns past the
    numerical rank are zero and the equations past it are dropped (consistent for the
    rank-deficient systems this serves: KKT systems whose multipliers are not unique). Returns
    the rank. lu (n, n) and prow, pcol (n, int) are work."""
    scale = 0.0
    for i in range(n):
        prow[i] = i
        pcol[i] = i
        for j in range(n):
            lu[i, j] = M[i, j]
            scale = max(scale, abs(M[i, j]))
    rank = 0
    for k in range(n):
        bi = k
        bj = k
        best = 0.0
        for i in range(k, n):
            for j in range(k, n):
                if abs(lu[i, j]) > best:
                    best = abs(lu[i, j])
                    bi = i
                    bj = j
        if best <= tol * scale:
            break
        rank += 1
        _swap(lu, prow, n, k, bi)
        _swap(lu.T, pcol, n, k, bj)
        _eliminate(lu, n, k)
    # forward substitution on the first `rank` equations, back substitution, zeros past rank
    for i in range(rank):
        s = b[prow[i]]
        for j in range(i):
            s -= lu[i, j] * x[pcol[j]]
        x[pcol[i]] = s
    for i in range(rank, n):
        x[pcol[i]] = 0.0
    for i in range(rank - 1, -1, -1):
        s = x[pcol[i]]
        for j in range(i + 1, rank):
            s -= lu[i, j] * x[pcol[j]]
        x[pcol[i]] = s / lu[i, i]
    return rank


@borrowing
def basic_null_space(lu, pcol, n, rank, Z, w):
    """The columns Z[:n, :n - rank] spanning the null space of the matrix that `solve_basic`
    factored into lu, pcol with this rank: Q [-U11^-1 U12; I] of its complete-pivoting factors.
    w (n) is scratch."""
    for e in range(n - rank):
        col = rank + e
        for i in range(rank - 1, -1, -1):
            s = lu[i, col]
            for j in range(i + 1, rank):
                s -= lu[i, j] * w[j]
            w[i] = s / lu[i, i]
        for i in range(n):
            Z[i, e] = 0.0
        Z[pcol[col], e] = 1.0
        for i in range(rank):
            Z[pcol[i], e] = -w[i]
