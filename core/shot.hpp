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

// a hit's t_upper = h_A(n) / n^T r below t by at most this (relative) is rounding: the ray left
// through an exact face of A, whose hyperplane is the facet's own, and the bracket closes at t
constexpr double FACE_ROUNDING = 1e-12;

// t_upper as a result reports it: a hit's, below t by at most FACE_ROUNDING, is t.
double reported_upper(Int status, double t, double t_up) {
    if (status == HIT && t * (1.0 - FACE_ROUNDING) <= t_up && t_up < t) return t;
    return t_up;
}

// The result record: copies of normal, P[:k], lam[:k], Wt[:k] (the shooter's arrays die with
// it), t_upper as reported_upper gives it.
Shot make_result(Int status, double t, double t_up, double h_n, Int iters, Int calls,
                 Vec normal, Mat P, Vec lam, Mat Wt, Int k, Int singular) {
    Shot out;
    out.status = status;
    out.t = t;
    out.t_up = reported_upper(status, t, t_up);
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
    for (Int j = 0; j < k; ++j) {
        if (changed < 0 || j == changed) {
            for (Int i = 0; i < P.cols; ++i) Pz(j, i) = P(j, i);
            for (Int i = 0; i < Wt.cols; ++i) Wz(j, i) = Wt(j, i);
        }
        lz[j] = lam[j];
    }
    return k;
}

// Whether lam[:k] are convex weights (>= -tol, summing to 1 within tol) of the rows P[:k] that
// reproduce t r (written to b) to tol relative,
// or to the sum's own rounding, 1e-14 sum_j lam_j ||P_j|| (about 50 unit roundoffs; it matters
// where the origin is near A's boundary and t r is far shorter than the points that make it:
// the paper's sphere at lambda = 1e-5). The point on the ray is then in A to that accuracy.
// Relative, unlike `reproduce`'s floor: A's units do not matter.
bool holds(Mat P, Vec lam, Int k, double t, Vec r, Vec b, double tol) {
    // a convex combination: weights >= 0 summing to 1, to tol
    double total = 0.0;
    for (Int j = 0; j < k; ++j) {
        if (lam[j] < -tol) return false;
        total += lam[j];
    }
    if (!(std::abs(total - 1.0) <= tol)) return false;
    for (Int i = 0; i < r.n; ++i) b[i] = t * r[i];
    const std::pair<double, double> rb = residual2(P, lam, k, b);
    const double res = rb.first, bb = rb.second;
    if (res <= tol * tol * bb) return true;
    double mass = 0.0;
    for (Int j = 0; j < k; ++j) {
        double pp = 0.0;
        for (Int i = 0; i < P.cols; ++i) pp += P(j, i) * P(j, i);
        mass += std::abs(lam[j]) * std::sqrt(pp);
    }
    return res <= 1e-28 * mass * mass;
}

}  // namespace gf
