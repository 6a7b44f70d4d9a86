#pragma once

#include "api.hpp"
#include "shooting/corral.hpp"

// The distance algorithms of section 2: GJK (point to set) and ZC (point to convex cone).
//
// Both keep a simplex as rows of P (points of A), Wt (their witnesses) and lam (weights), so a
// caller can warm-start them and read Z_A(r) and its witnesses off the final rows.

namespace gf {

namespace distance_detail {

// A least-squares residual below INSIDE_TOL times the target's norm is rounding, not distance.
// The point the callers report then differs from its convex combination by at most this much,
// relative.
constexpr double INSIDE_TOL = 1e-11;
constexpr double ROUNDING = 1e-13;   // about 500 unit roundoffs

}  // namespace distance_detail

// GJK (section 2.2): d_A(b) and v_A(b) from the simplex P[:k] (k = 0: cold start).
//
// Stops when h_A(n_k) - n_k^T v_k <= eps_abs + eps_rel * ref, ref = |n_k^T v_k| (the offset of
// the hyperplane H(n_k, v_k), as the ray shooters need) or d (relative distance error).
// Returns (status, k, d, h_A(n_k), iterations, support_calls); n_k in nvec, v_k in v.
// sc: the work arrays of the active-set subproblem.
DistOut gjk(IVec ints, Vec floats, Vec b, Mat P, Mat Wt, Vec lam, Int k, double eps_rel,
            double eps_abs, bool rel_to_offset, Int max_iter, Vec nvec, Vec v, Vec point,
            Vec wit, const Scratch& sc) {
    using distance_detail::ROUNDING;
    const Int n = b.n;
    const Mat D = sc.D, work = sc.work, house = sc.house;
    const Vec rhs = sc.rhs, wrhs = sc.wrhs, x = sc.x;
    Int calls = 0;
    Int fact = 0;   // corral's factored columns: none yet (`sc` may hold another caller's)
    if (k == 0) {
        for (Int i = 0; i < n; ++i) nvec[i] = b[i];
        if (std::sqrt(dot(b, b)) == 0.0) nvec[0] = 1.0;
        support(ints, floats, nvec, point, wit);
        calls += 1;
        set_row(P, Wt, 0, point, wit);
        lam[0] = 1.0;
        k = 1;
    } else {
        const corral_detail::Corral c = corral_detail::corral(P, Wt, lam, k, b, b, true, D, work,
                                                              rhs, wrhs, x, house, fact);
        k = c.k;
        fact = c.fact;
    }
    const double tiny = ROUNDING * (std::sqrt(dot(b, b)) + std::sqrt(dot(P.row(0), P.row(0))))
                        + 1e-300;
    double d = INF;
    double h = 0.0;
    for (Int it = 0; it < max_iter; ++it) {
        combine(P, lam, k, v);
        d = 0.0;
        for (Int i = 0; i < n; ++i) {
            nvec[i] = b[i] - v[i];
            d += nvec[i] * nvec[i];
        }
        d = std::sqrt(d);
        if (d <= tiny || k == n + 1) {
            // n + 1 affinely independent points: b is reproduced exactly, up to rounding
            return {INSIDE, k, 0.0, h, it, calls};
        }
        for (Int i = 0; i < n; ++i) nvec[i] /= d;
        h = support(ints, floats, nvec, point, wit);
        calls += 1;
        const double offset = dot(nvec, v);
        const double ref = rel_to_offset ? std::abs(offset) : d;
        if (h - offset <= eps_abs + eps_rel * ref) return {CONVERGED, k, d, h, it + 1, calls};
        set_row(P, Wt, k, point, wit);
        lam[k] = 0.0;
        const corral_detail::Corral c = corral_detail::corral(P, Wt, lam, k + 1, b, b, true, D,
                                                              work, rhs, wrhs, x, house, fact);
        k = c.k;
        fact = c.fact;
        if (!c.newest_kept) return {STALLED, k, d, h, it + 1, calls};
    }
    return {MAX_ITER, k, d, h, max_iter, calls};
}

// ZC (section 2.3): distance from `target` to CO(A - shift) with generators P[:k] - shift.
//
// Stops (CONVERGED) when h_{A-shift}(n_k) <= eps_abs + eps_rel * n_k^T shift; INSIDE when the
// target is a positive combination lam[:k] of P[:k] - shift. Returns (status, k, d,
// h_{A-shift}(n_k), iterations, support_calls); n_k in nvec, v_CO in v. sc: the work arrays of
// the active-set subproblem.
DistOut zc(IVec ints, Vec floats, Vec shift, Vec target, Mat P, Mat Wt, Vec lam, Int k,
           double eps_rel, double eps_abs, Int max_iter, Vec nvec, Vec v, Vec point, Vec wit,
           const Scratch& sc) {
    using distance_detail::INSIDE_TOL;
    using distance_detail::ROUNDING;
    const Int n = target.n;
    const Mat D = sc.D, work = sc.work, house = sc.house;
    const Vec rhs = sc.rhs, wrhs = sc.wrhs, x = sc.x;
    Int calls = 0;
    const double tnorm = std::sqrt(dot(target, target));
    if (k == 0) {
        for (Int i = 0; i < n; ++i) nvec[i] = target[i] / tnorm;
        const double h = support(ints, floats, nvec, point, wit) - dot(nvec, shift);
        calls += 1;
        if (h <= eps_abs + eps_rel * dot(nvec, shift)) {
            // the hyperplane through `shift` with normal `target` already supports A (within
            // the same rule as below: shift may sit a rounding error inside a vertex)
            for (Int i = 0; i < v.n; ++i) v[i] = 0.0;
            return {CONVERGED, 0, tnorm, h, 0, calls};
        }
        set_row(P, Wt, 0, point, wit);
        lam[0] = 0.0;
        k = 1;
    } else {
        for (Int j = 0; j < k; ++j) lam[j] = 0.0;
    }
    const corral_detail::Corral c0 = corral_detail::corral(P, Wt, lam, k, target, shift, false,
                                                           D, work, rhs, wrhs, x, house, 0);
    k = c0.k;
    Int fact = c0.fact;
    double h = 0.0;
    double d = tnorm;
    for (Int it = 0; it < max_iter; ++it) {
        for (Int i = 0; i < n; ++i) v[i] = 0.0;
        double mass = 0.0;
        for (Int j = 0; j < k; ++j) {
            double gnorm = 0.0;
            for (Int i = 0; i < n; ++i) {
                const double g = P(j, i) - shift[i];
                v[i] += lam[j] * g;
                gnorm += g * g;
            }
            mass += lam[j] * std::sqrt(gnorm);
        }
        d = 0.0;
        double defect = 0.0;
        for (Int i = 0; i < n; ++i) {
            nvec[i] = target[i] - v[i];
            d += nvec[i] * nvec[i];
            defect += nvec[i] * v[i];
        }
        d = std::sqrt(d);
        if (d <= INSIDE_TOL * tnorm || d <= ROUNDING * mass || std::abs(defect) >= 0.1 * d * d
            || k == n) {
            // The residual is rounding: of the target's size; of the terms lam_j (P_j - shift),
            // which grow like 1/(t_{k+1} - t_k) as b_k nears z_A(r); or of an ill-conditioned
            // cone, seen as lost orthogonality (a true projection has (target - v)^T v = 0).
            // Or n independent generators span R^n. The point the shooters build from lam
            // moves by d / sum(lam), far below INSIDE_TOL relative.
            return {INSIDE, k, 0.0, h, it, calls};
        }
        for (Int i = 0; i < n; ++i) nvec[i] /= d;
        h = support(ints, floats, nvec, point, wit) - dot(nvec, shift);
        calls += 1;
        if (h <= eps_abs + eps_rel * dot(nvec, shift)) return {CONVERGED, k, d, h, it + 1, calls};
        set_row(P, Wt, k, point, wit);
        lam[k] = 0.0;
        const corral_detail::Corral c = corral_detail::corral(
            P, Wt, lam, k + 1, target, shift, false, D, work, rhs, wrhs, x, house, fact);
        k = c.k;
        fact = c.fact;
        if (!c.newest_kept) return {STALLED, k, d, h, it + 1, calls};
    }
    return {MAX_ITER, k, d, h, max_iter, calls};
}

}  // namespace gf
