#pragma once

#include "api.hpp"

// A ray shot's result record and the helpers every shooter shares (section 3).
//
// Every procedure returns a Shot: (status, t, t_upper, h_n, iterations, support_calls, normal,
// V, weights, W, singular) with z = t r a convex combination `weights` of the rows of V (points
// of A, witnesses in W), and the hyperplane {x : normal^T x = h_n} supporting A
// (h_n = h_A(normal)) crossing the ray at t_upper r. `singular` counts the iterations spent on a
// face of dimension < n - 1 (IE's collections, ZC-IE's hand-overs to ZC-based steps). On a miss,
// normal separates: h_A(normal) <= 0 < normal^T r.
//
// Tolerance: every stopping rule is relative, (h_A(n) - n^T z) <= eps * n^T z, i.e.
// (t_upper - t) / t <= eps, so eps bounds the relative error in t whatever the units of A.

namespace gf {

// a ZC stall is a hit when its bracket is within eps or this (below it double precision cannot
// always certify: docs/core-api.md, "Numerical floor")
constexpr double STALL_FLOOR = 1e-11;

// A hit's t_upper = h_A(n) / n^T r below t by at most `face_rounding` (relative) is rounding:
// the ray left through an exact face of A, whose hyperplane is the facet's own, and the bracket
// closes at t.
double reported_upper(Int status, double t, double t_up, double rho) {
    if (status == HIT && t * (1.0 - rho) <= t_up && t_up < t) return t;
    return t_up;
}

// The result record: copies of normal, P[:k], lam[:k], Wt[:k] (the shooter's arrays die with
// it), t_upper as reported_upper gives it.
Shot make_result(Int status, double t, double t_up, double h_n, Int iters, Int calls,
                 Vec normal, Mat P, Vec lam, Mat Wt, Int k, Int singular) {
    Shot out;
    out.status = status;
    out.t = t;
    out.t_up = reported_upper(status, t, t_up, face_rounding(P, k, h_n));
    out.h_n = h_n;
    out.iters = iters;
    out.calls = calls;
    out.normal = Array(normal.n);
    for (Int i = 0; i < normal.n; ++i) out.normal.data[i] = normal[i];
    out.V = Array(k, P.cols);
    out.lam = Array(k);
    out.W = Array(k, Wt.cols);
    for (Int j = 0; j < k; ++j) {
        for (Int i = 0; i < P.cols; ++i) out.V.data[j * P.cols + i] = P(j, i);
        out.lam.data[j] = lam[j];
        for (Int i = 0; i < Wt.cols; ++i) out.W.data[j * Wt.cols + i] = Wt(j, i);
    }
    out.singular = singular;
    return out;
}

// Save the simplex holding the current point on the ray: it becomes Z_A(r) at the end.
// changed >= 0: Pz[:k], Wz[:k] already hold P[:k], Wt[:k] but for that row (an IE step
// replaces one vertex), which alone is copied.
Int keep(Mat P, Mat Wt, Vec lam, Int k, Mat Pz, Mat Wz, Vec lz, Int changed) {
    // the rows to copy as a range, not a test per row: IE keeps its facet at every step
    const Int first = changed < 0 ? 0 : changed, end = changed < 0 ? k : changed + 1;
    for (Int j = first; j < end; ++j) {
        for (Int i = 0; i < P.cols; ++i) Pz(j, i) = P(j, i);
        for (Int i = 0; i < Wt.cols; ++i) Wz(j, i) = Wt(j, i);
    }
    for (Int j = 0; j < k; ++j) lz[j] = lam[j];
    return k;
}

// Whether lam[:k] are convex weights (>= -tol, summing to 1 within tol) of the rows P[:k] that
// reproduce t r (written to b) to tol relative, or to the rounding of their sum (`on_point`).
// The point on the ray is then in A to that accuracy. Relative: A's units do not matter.
bool holds(Mat P, Vec lam, Int k, double t, Vec r, Vec b, double tol) {
    // a convex combination: weights >= 0 summing to 1, to tol
    double total = 0.0;
    for (Int j = 0; j < k; ++j) {
        if (lam[j] < -tol) return false;
        total += lam[j];
    }
    if (!(std::abs(total - 1.0) <= tol)) return false;
    for (Int i = 0; i < r.n; ++i) b[i] = t * r[i];
    return on_point(P, lam, k, b, tol);
}

// Whether the weights lam[:k] of the rows P[:k] reproduce t r to tol relative: `holds` without a
// work array (the check of every shot's record).
inline bool reproduces(Mat P, Vec lam, Int k, double t, Vec r, double tol) {
    double res = 0.0, bb = 0.0;
    for (Int i = 0; i < r.n; ++i) {
        const double b = t * r[i];
        double e = -b;
        for (Int j = 0; j < k; ++j) e += lam[j] * P(j, i);
        res += e * e;
        bb += b * b;
    }
    return res <= tol * tol * bb;
}

// A hit only with its certificate, whatever procedure made it: t r the convex combination of
// the record's points to point_holds(eps) (`holds`; the weights, nonnegative, are scaled to sum to 1:
// an IE facet solved afresh gives t = 1 / y^T r and weights summing to 1 only to the solve's
// accuracy) and its bracket t <= t_upper <= (1 + eps) t, t_upper taken with its rounding
// (`bound_rounding`: a normal 2.6e-9 from orthogonal to r, at a corner of A, left t_upper
// uncertain by 5e-6 where eps was 1e-9). A hit without one is the LIMIT it is, its bracket
// [min(t, t_upper), t_upper].
Shot certify(Shot out, Vec r, double eps) {
    if (out.status != HIT) return out;
    const double tol = point_holds(eps);
    const double t = out.t;
    const double t_up = out.t_up * (1.0 + bound_rounding(out.normal.vec(), r));
    const Vec lam = out.lam.vec();
    double sum = 0.0;
    bool nonnegative = true;
    for (Int j = 0; j < lam.n; ++j) {
        nonnegative = nonnegative && lam[j] >= 0.0;
        sum += lam[j];
    }
    if (nonnegative && std::abs(sum - 1.0) <= tol)
        for (Int j = 0; j < lam.n; ++j) lam[j] /= sum;
    if (t > 0.0 && t <= t_up && t_up - t <= eps * t && nonnegative &&
        std::abs(sum - 1.0) <= tol && reproduces(out.V.mat(), lam, out.k(), t, r, tol))
        return out;
    out.status = LIMIT;
    out.t = std::min(t, out.t_up);
    return out;
}

}  // namespace gf
