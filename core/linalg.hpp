#pragma once

#include "api.hpp"

// Small dense solvers for the distance and ray-shooting algorithms (n <= ~16, no allocation).
//
// Householder QR least squares (conditioning of the data, not of its square, which the 1e-9
// accuracy goal needs), LU with partial pivoting for the square facet systems of IE, the
// Gauss-Jordan inverse that ZC-IE's steps update by pivots, and LU with complete pivoting for
// the basic solutions and null spaces of rank-deficient KKT systems. The small helpers of the
// inner loops are always inlined: a call costs more than their arithmetic.

namespace gf {

namespace linalg_detail {

constexpr double RANK_TOL = 1e-12;

// Apply reflection j of `lstsq_append` (v = [house[0, j], work[j+1:, j]]) to work[:, c].
[[gnu::always_inline]] inline void reflect_column(Mat work, Int n, Mat house, Int j, Int c) {
    const double v0 = house(0, j);
    double d = v0 * work(j, c);
    for (Int i = j + 1; i < n; ++i) d += work(i, j) * work(i, c);
    const double f = house(1, j) * d;
    work(j, c) -= f * v0;
    for (Int i = j + 1; i < n; ++i) work(i, c) -= f * work(i, j);
}

// Apply reflection j of `lstsq_append` to the vector y.
[[gnu::always_inline]] inline void reflect_vector(Mat work, Int n, Mat house, Int j, Vec y) {
    const double v0 = house(0, j);
    double d = v0 * y[j];
    for (Int i = j + 1; i < n; ++i) d += work(i, j) * y[i];
    const double f = house(1, j) * d;
    y[j] -= f * v0;
    for (Int i = j + 1; i < n; ++i) y[i] -= f * work(i, j);
}

// One step of Gaussian elimination on lu[:n, :n] with pivot lu[k, k]: the multipliers into
// column k below it, the Schur complement into the trailing block.
[[gnu::always_inline]] inline void eliminate(Mat lu, Int n, Int k) {
    const double inv = 1.0 / lu(k, k);
    for (Int i = k + 1; i < n; ++i) {
        lu(i, k) *= inv;
        const double f = lu(i, k);
        if (f != 0.0)
            for (Int j = k + 1; j < n; ++j) lu(i, j) -= f * lu(k, j);
    }
}

// A[:n, :n] = M[:n, :n]; returns max |M_ij|, the scale of the singularity test.
[[gnu::always_inline]] inline double copy_scale(Mat M, Int n, Mat A) {
    double scale = 0.0;
    for (Int i = 0; i < n; ++i)
        for (Int j = 0; j < n; ++j) {
            A(i, j) = M(i, j);
            scale = std::max(scale, std::abs(M(i, j)));
        }
    return scale;
}

// Swap into row k the row at or below it with the largest |A_ik| (recorded in piv[k]); false
// when that pivot is below 1e-14 scale: singular to working precision.
[[gnu::always_inline]] inline bool partial_pivot(Mat A, Int n, Int k, IVec piv, double scale) {
    Int p = k;
    double best = std::abs(A(k, k));
    for (Int i = k + 1; i < n; ++i) {
        if (std::abs(A(i, k)) > best) {
            best = std::abs(A(i, k));
            p = i;
        }
    }
    piv[k] = p;
    if (best <= 1e-14 * scale) return false;
    if (p != k) {
        for (Int j = 0; j < n; ++j) {
            const double tmp = A(k, j);
            A(k, j) = A(p, j);
            A(p, j) = tmp;
        }
    }
    return true;
}

// Exchange rows i and j of a[:, :n] and entries i and j of the permutation `order`.
[[gnu::always_inline]] inline void swap(Mat a, IVec order, Int n, Int i, Int j) {
    if (i == j) return;
    for (Int c = 0; c < n; ++c) {
        const double tmp = a(i, c);
        a(i, c) = a(j, c);
        a(j, c) = tmp;
    }
    const Int tmp2 = order[i];
    order[i] = order[j];
    order[j] = tmp2;
}

// Python's swap(a.T, order, n, i, j): exchange columns i and j of a[:n, :] and entries i and j
// of `order`.
[[gnu::always_inline]] inline void swap_columns(Mat a, IVec order, Int n, Int i, Int j) {
    if (i == j) return;
    for (Int c = 0; c < n; ++c) {
        const double tmp = a(c, i);
        a(c, i) = a(c, j);
        a(c, j) = tmp;
    }
    const Int tmp2 = order[i];
    order[i] = order[j];
    order[j] = tmp2;
}


// lstsq for n rows, N of them when N > 0 (the loops over rows then unroll)
template <int N>
bool lstsq_sized(Mat D, Int n_, Int q, Vec rhs, Vec x, Int x0, Mat work, Vec wrhs) {
    const Int n = N > 0 ? N : n_;
    for (Int i = 0; i < n; ++i) {
        wrhs[i] = rhs[i];
        for (Int j = 0; j < q; ++j) work(i, j) = D(i, j);
    }
    double scale = 0.0;
    for (Int j = 0; j < q; ++j) {
        double s = 0.0;
        for (Int i = 0; i < n; ++i) s += work(i, j) * work(i, j);
        scale = std::max(scale, std::sqrt(s));
    }
    if (scale == 0.0) return q == 0;
    for (Int j = 0; j < q; ++j) {
        // Householder reflection zeroing work[j+1:, j]
        double s = 0.0;
        for (Int i = j; i < n; ++i) s += work(i, j) * work(i, j);
        double alpha = std::sqrt(s);
        if (alpha <= RANK_TOL * scale) return false;
        if (work(j, j) > 0.0) alpha = -alpha;
        const double v0 = work(j, j) - alpha;
        const double vnorm2 = s - work(j, j) * work(j, j) + v0 * v0;
        work(j, j) = v0;
        if (vnorm2 > 0.0) {
            for (Int c = j + 1; c < q; ++c) {
                double d = 0.0;
                for (Int i = j; i < n; ++i) d += work(i, j) * work(i, c);
                const double f = 2.0 * d / vnorm2;
                for (Int i = j; i < n; ++i) work(i, c) -= f * work(i, j);
            }
            double d = 0.0;
            for (Int i = j; i < n; ++i) d += work(i, j) * wrhs[i];
            const double f = 2.0 * d / vnorm2;
            for (Int i = j; i < n; ++i) wrhs[i] -= f * work(i, j);
        }
        work(j, j) = alpha;
    }
    for (Int j = q - 1; j >= 0; --j) {
        double s = wrhs[j];
        for (Int c = j + 1; c < q; ++c) s -= work(j, c) * x[x0 + c];
        x[x0 + j] = s / work(j, j);
    }
    return true;
}

}  // namespace linalg_detail

// x[x0:x0 + q] = argmin ||D[:n, :q] x - rhs[:n]||. False when D is (numerically) rank
// deficient. work (n, q) and wrhs (n) are scratch; D and rhs are left untouched. Compiled for
// R^6 apart (the Newton finishes' certificates on grasps: the same operations, unrolled)
bool lstsq(Mat D, Int n, Int q, Vec rhs, Vec x, Int x0, Mat work, Vec wrhs) {
    if (n == 6) return linalg_detail::lstsq_sized<6>(D, n, q, rhs, x, x0, work, wrhs);
    return linalg_detail::lstsq_sized<0>(D, n, q, rhs, x, x0, work, wrhs);
}

// `lstsq` (x at offset 0) when work and house already hold the Householder QR of D's first
// `fact` columns, left by an earlier call on the same columns: only columns fact..q-1 are
// reduced, O(n q) a column instead of O(n q^2). ZC's active set grows a column a step, so each
// of its projections reduces one column (D's first `fact` columns are not read). house: per
// column the reflection's first entry, 2 / ||v||^2 and the column's norm. Returns q, the
// columns now factored, or -1 when D is (numerically) rank deficient: the same test as
// `lstsq`, alpha_j <= RANK_TOL max_j ||D_j||.
Int lstsq_append(Mat D, Int n, Int q, Int fact, Vec rhs, Vec x, Mat work, Vec wrhs, Mat house) {
    using linalg_detail::RANK_TOL;
    // Q^T rhs through the reflections kept, then each new one
    for (Int i = 0; i < n; ++i) wrhs[i] = rhs[i];
    for (Int j = 0; j < q; ++j) {
        if (j >= fact) {
            double norm2 = 0.0;
            for (Int i = 0; i < n; ++i) {
                work(i, j) = D(i, j);
                norm2 += D(i, j) * D(i, j);
            }
            house(2, j) = std::sqrt(norm2);
            for (Int c = 0; c < j; ++c) linalg_detail::reflect_column(work, n, house, c, j);
            double s = 0.0;
            for (Int i = j; i < n; ++i) s += work(i, j) * work(i, j);
            double alpha = std::sqrt(s);
            if (work(j, j) > 0.0) alpha = -alpha;
            const double v0 = work(j, j) - alpha;
            const double vnorm2 = s - work(j, j) * work(j, j) + v0 * v0;
            house(0, j) = v0;
            house(1, j) = vnorm2 > 0.0 ? 2.0 / vnorm2 : 0.0;
            work(j, j) = alpha;
        }
        linalg_detail::reflect_vector(work, n, house, j, wrhs);
    }
    double scale = 0.0;
    for (Int j = 0; j < q; ++j) scale = std::max(scale, house(2, j));
    for (Int j = 0; j < q; ++j)
        if (!(std::abs(work(j, j)) > RANK_TOL * scale)) return -1;
    for (Int j = q - 1; j >= 0; --j) {
        double s = wrhs[j];
        for (Int c = j + 1; c < q; ++c) s -= work(j, c) * x[c];
        x[j] = s / work(j, j);
    }
    return q;
}

// LU with partial pivoting of M[:n, :n] into lu; false when singular to working precision.
bool lu_factor(Mat M, Int n, Mat lu, IVec piv) {
    const double scale = linalg_detail::copy_scale(M, n, lu);
    if (scale == 0.0) return false;
    for (Int k = 0; k < n; ++k) {
        if (!linalg_detail::partial_pivot(lu, n, k, piv, scale)) return false;
        linalg_detail::eliminate(lu, n, k);
    }
    return true;
}

// B[:n, :n] = M[:n, :n]^{-1} by Gauss-Jordan elimination with partial pivoting; false when
// singular to working precision (lu_factor's test: the pivots are the same). One reciprocal a
// column: LU and n solves divide n^2 / 2 times, in a dependent chain (R^6: 550 -> 220 ns).
bool invert(Mat M, Int n, Mat B, IVec piv) {
    const double scale = linalg_detail::copy_scale(M, n, B);
    if (scale == 0.0) return false;
    for (Int k = 0; k < n; ++k) {
        if (!linalg_detail::partial_pivot(B, n, k, piv, scale)) return false;
        const double inv = 1.0 / B(k, k);
        B(k, k) = 1.0;
        for (Int j = 0; j < n; ++j) B(k, j) *= inv;
        for (Int i = 0; i < n; ++i) {
            const double f = B(i, k);
            if (i != k && f != 0.0) {
                B(i, k) = 0.0;
                for (Int j = 0; j < n; ++j) B(i, j) -= f * B(k, j);
            }
        }
    }
    // the row interchanges of M are column interchanges of its inverse, undone in reverse
    for (Int k = n - 1; k >= 0; --k) {
        const Int p = piv[k];
        if (p != k) {
            for (Int i = 0; i < n; ++i) {
                const double tmp = B(i, k);
                B(i, k) = B(i, p);
                B(i, p) = tmp;
            }
        }
    }
    return true;
}

// Solve M x = b from lu_factor(M); x may be b itself.
void lu_solve(Mat lu, IVec piv, Int n, Vec b, Vec x) {
    for (Int i = 0; i < n; ++i) x[i] = b[i];
    for (Int k = 0; k < n; ++k) {
        const Int p = piv[k];
        if (p != k) {
            const double tmp = x[k];
            x[k] = x[p];
            x[p] = tmp;
        }
    }
    for (Int i = 0; i < n; ++i) {
        double s = x[i];
        for (Int j = 0; j < i; ++j) s -= lu(i, j) * x[j];
        x[i] = s;
    }
    for (Int i = n - 1; i >= 0; --i) {
        double s = x[i];
        for (Int j = i + 1; j < n; ++j) s -= lu(i, j) * x[j];
        x[i] = s / lu(i, i);
    }
}

// Solve M^T x = b from lu_factor(M).
void lu_solve_t(Mat lu, IVec piv, Int n, Vec b, Vec x) {
    for (Int i = 0; i < n; ++i) x[i] = b[i];
    for (Int i = 0; i < n; ++i) {
        double s = x[i];
        for (Int j = 0; j < i; ++j) s -= lu(j, i) * x[j];
        x[i] = s / lu(i, i);
    }
    for (Int i = n - 1; i >= 0; --i) {
        double s = x[i];
        for (Int j = i + 1; j < n; ++j) s -= lu(j, i) * x[j];
        x[i] = s;
    }
    for (Int k = n - 1; k >= 0; --k) {
        const Int p = piv[k];
        if (p != k) {
            const double tmp = x[k];
            x[k] = x[p];
            x[p] = tmp;
        }
    }
}

// A basic solution x of M[:n, :n] x = b by LU with complete pivoting: the unknowns past the
// numerical rank are zero and the equations past it are dropped (consistent for the
// rank-deficient systems this serves: KKT systems whose multipliers are not unique). Returns
// the rank. lu (n, n) and prow, pcol (n) are work.
Int solve_basic(Mat M, Int n, Mat lu, IVec prow, IVec pcol, Vec b, Vec x, double tol) {
    double scale = 0.0;
    for (Int i = 0; i < n; ++i) {
        prow[i] = i;
        pcol[i] = i;
        for (Int j = 0; j < n; ++j) {
            lu(i, j) = M(i, j);
            scale = std::max(scale, std::abs(M(i, j)));
        }
    }
    Int rank = 0;
    for (Int k = 0; k < n; ++k) {
        Int bi = k;
        Int bj = k;
        double best = 0.0;
        for (Int i = k; i < n; ++i)
            for (Int j = k; j < n; ++j)
                if (std::abs(lu(i, j)) > best) {
                    best = std::abs(lu(i, j));
                    bi = i;
                    bj = j;
                }
        if (best <= tol * scale) break;
        rank += 1;
        linalg_detail::swap(lu, prow, n, k, bi);
        linalg_detail::swap_columns(lu, pcol, n, k, bj);
        linalg_detail::eliminate(lu, n, k);
    }
    // forward substitution on the first `rank` equations, back substitution, zeros past rank
    for (Int i = 0; i < rank; ++i) {
        double s = b[prow[i]];
        for (Int j = 0; j < i; ++j) s -= lu(i, j) * x[pcol[j]];
        x[pcol[i]] = s;
    }
    for (Int i = rank; i < n; ++i) x[pcol[i]] = 0.0;
    for (Int i = rank - 1; i >= 0; --i) {
        double s = x[pcol[i]];
        for (Int j = i + 1; j < rank; ++j) s -= lu(i, j) * x[pcol[j]];
        x[pcol[i]] = s / lu(i, i);
    }
    return rank;
}

// The columns Z[:n, :n - rank] spanning the null space of the matrix that `solve_basic`
// factored into lu, pcol with this rank: Q [-U11^-1 U12; I] of its complete-pivoting factors.
// w (n) is scratch.
void basic_null_space(Mat lu, IVec pcol, Int n, Int rank, Mat Z, Vec w) {
    for (Int e = 0; e < n - rank; ++e) {
        const Int col = rank + e;
        for (Int i = rank - 1; i >= 0; --i) {
            double s = lu(i, col);
            for (Int j = i + 1; j < rank; ++j) s -= lu(i, j) * w[j];
            w[i] = s / lu(i, i);
        }
        for (Int i = 0; i < n; ++i) Z(i, e) = 0.0;
        Z(pcol[col], e) = 1.0;
        for (Int i = 0; i < rank; ++i) Z(pcol[i], e) = -w[i];
    }
}

}  // namespace gf
