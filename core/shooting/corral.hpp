#pragma once

#include "api.hpp"

// The subproblem shared by GJK and ZC: the point of a small set's affine-convex hull (GJK) or
// convex cone (ZC) closest to a target, with the minimal subset V-hat_k that represents it.
//
// An active-set method on the weights (Wolfe's minimum-norm-point minor cycle for the hull,
// Lawson-Hanson for the cone): solve the unconstrained least-squares problem on the current
// subset; if a weight is not positive, step back to the boundary and drop that point. Unlike
// Johnson's recursion it is exact in any dimension and never enumerates sub-simplices.

namespace gf {

// Whether the weights x[:k] of the rows P[:k] reproduce b to tol relative, or to the sum's own
// rounding, 1e-14 sum_j |x_j| ||P_j|| (about 50 unit roundoffs; it matters where t r is far
// shorter than the points that make it: the paper's sphere at lambda = 1e-5), but never worse
// than POINT_HOLDS relative: a point within rounding of A's size but far shorter (a ray that
// leaves A at the origin, t r 1e-13 from A) is not a point of A on the ray.
bool on_point(Mat P, Vec x, Int k, Vec b, double tol) {
    const auto [res, bb] = residual2(P, x, k, b);
    if (res <= tol * tol * bb) return true;
    if (res > POINT_HOLDS * POINT_HOLDS * bb) return false;
    double mass = 0.0;
    for (Int j = 0; j < k; ++j) {
        double pp = 0.0;
        for (Int i = 0; i < P.cols; ++i) pp += P(j, i) * P(j, i);
        mass += std::abs(x[j]) * std::sqrt(pp);
    }
    return res <= 1e-28 * mass * mass;
}

// Whether the weights x[:k] of the rows P[:k], clipped at zero and normalized to sum to 1 (as
// they are then left), reproduce b to FACET_HOLDS relative (`on_point`): the rule of Fig. 3b.
bool reproduce(Mat P, Vec x, Int k, Vec b) {
    double s = 0.0;
    for (Int j = 0; j < k; ++j) {
        x[j] = std::max(x[j], 0.0);
        s += x[j];
    }
    if (!(s > 0.0)) return false;
    for (Int j = 0; j < k; ++j) x[j] /= s;
    return on_point(P, x, k, b, FACET_HOLDS);
}

// Weights x[:m] (summing to 1) and t (returned) of the point of CH(S[:m]) nearest the ray, by
// least squares: S_0 + sum_p x_p (S_p - S_0) = t r. -1 when rank deficient.
double weights_on_ray(Mat S, Int m, Vec r, Vec x, Mat D, Mat work, Vec wrhs, Vec rhs) {
    const Int n = r.n;
    for (Int i = 0; i < n; ++i) {
        for (Int p = 1; p < m; ++p) D(i, p - 1) = S(p, i) - S(0, i);
        D(i, m - 1) = -r[i];
        rhs[i] = -S(0, i);
    }
    if (!lstsq(D, n, m, rhs, x, 1, work, wrhs)) return -1.0;
    const double t = x[m];
    x[0] = 1.0;
    for (Int p = 1; p < m; ++p) x[0] -= x[p];
    return t;
}

namespace corral_detail {

// corral's result: the new size, whether the newest point was kept (false: no progress), and
// the columns factored for the next call
struct Corral {
    Int k;
    bool newest_kept;
    Int fact;
};

// Reduce the simplex P[:k] (the last row just added, weight 0) to the minimal subset whose hull
// (affine: convex combinations) or cone (not affine: nonnegative combinations of P_i - shift)
// holds the point closest to `target`. Writes the positive weights to lam[:k].
//
// The least squares keep their QR between calls (`lstsq_append`): `fact` columns are factored
// in work and house from the previous call with the same target and shift (0: none). The
// cone's column j is P_j - shift; the hull's column j is P_{j+1} - P_0, so that dropping P_0
// discards them all. newest_kept is false when the new point brought no improvement or was
// numerically dependent on the others, which the callers read as "no progress".
inline Corral corral(Mat P, Mat Wt, Vec lam, Int k, Vec target, Vec shift, bool affine, Mat D,
                     Mat work, Vec rhs, Vec wrhs, Vec x, Mat house, Int fact) {
    const Int n = P.cols;
    const Int off = affine ? 1 : 0;   // row j of P is column j - off of D
    Int newest = k - 1;
    while (k > 0) {
        const Int q = k - off;
        for (Int i = 0; i < n; ++i) {
            const double base = affine ? P(0, i) : shift[i];
            rhs[i] = affine ? target[i] - base : target[i];
            for (Int j = fact; j < q; ++j) D(i, j) = P(j + off, i) - base;
        }
        fact = lstsq_append(D, n, q, fact, rhs, x, work, wrhs, house);
        const bool ok = fact >= 0;
        fact = std::max(fact, Int{0});
        if (!ok) {
            if (newest < 0) return {k, false, fact};
            k = drop_point(P, Wt, lam, k, newest);
            fact = std::min(fact, std::max(newest - off, Int{0}));
            newest = -1;
            continue;
        }
        if (affine) {
            // x held the weights of P_1..P_{k-1}; P_0 takes the rest
            double s = 1.0;
            for (Int j = q - 1; j >= 0; --j) {
                x[j + 1] = x[j];
                s -= x[j];
            }
            x[0] = s;
        }
        double theta = 1.0;
        Int arg = -1;
        for (Int j = 0; j < k; ++j) {
            if (x[j] <= 0.0) {
                const double den = lam[j] - x[j];
                const double th = den > 0.0 ? lam[j] / den : 0.0;
                if (th < theta || arg < 0) {
                    theta = th;
                    arg = j;
                }
            }
        }
        if (arg < 0) {
            for (Int j = 0; j < k; ++j) lam[j] = x[j];
            return {k, newest >= 0, fact};
        }
        for (Int j = 0; j < k; ++j) lam[j] += theta * (x[j] - lam[j]);
        lam[arg] = 0.0;
        Int j = k - 1;
        while (j >= 0) {
            if (lam[j] <= 0.0) {
                k = drop_point(P, Wt, lam, k, j);
                fact = std::min(fact, std::max(j - off, Int{0}));
                if (j == newest)
                    newest = -1;
                else if (j < newest)
                    newest -= 1;
            }
            j -= 1;
        }
    }
    return {k, false, fact};
}

}  // namespace corral_detail

}  // namespace gf
