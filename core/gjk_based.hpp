#pragma once

#include "api.hpp"

// GJK-based ray shooting (section 3.1): b_k = t_k r outside A walks down the ray to z_A(r),
// each step to where a supporting hyperplane of A crosses it (eq. (4)), stopped by Fig. 3b's
// rule. Every shooter returns a Shot: z = t r a convex combination `lam` of the rows of V
// (points of A, witnesses in W), and the hyperplane {x : normal^T x = h_n} supporting A
// (h_n = h_A(normal)) crossing the ray at t_upper r. On a miss, normal separates:
// h_A(normal) <= 0 < normal^T r. Stopping rules are relative: (t_upper - t) / t <= eps.
// Also the pieces Bi-GJK (bi_gjk.hpp) shares: the miss certificate, Fig. 3b's rule, the work
// arrays and the finish at GJK's numerical floor.

namespace gf {
namespace gjk_based_detail {

constexpr double INEXACT_GJK = 1.0;   // GJK's tolerance, relative to the last step squared, until eps
constexpr double TIGHTEN = 1e-2;      // GJK's tolerance after an inexact direction that did not cut the ray

// Work arrays of a shooter's GJK and ZC calls: normal, v, point, witness, weights x (n + 2),
// and the subproblem's scratch. Its views point into its own arrays: not copyable.
struct Work {
    Array buf;              // nvec, v, point, wit, x, one after the other
    ScratchArrays scratch;  // scratch(n)
    Vec nvec, v, point, wit, x;
    Work(Int n, Int ws) : buf(4 * n + ws + 2), scratch(n) {
        Vec all = buf.vec();
        nvec = all.segment(0, n);
        v = all.segment(n, n);
        point = all.segment(2 * n, n);
        wit = all.segment(3 * n, ws);
        x = all.segment(3 * n + ws, n + 2);
    }
    Work(const Work&) = delete;
    Work& operator=(const Work&) = delete;
};

// A miss with its certificate: ZC from the origin finds n with h_A(n) < 0 < n^T r; or, when
// ZC finds r in CO(A), the hit that ZC-IE then computes.
inline Shot miss(IVec ints, Vec floats, Vec r, Int ws, double eps, Int iters, Int calls,
                 Int max_iter) {
    const Int n = r.n;
    Array P(n + 1, n);
    Array Wt(n + 1, ws);
    Array lam(n + 1);
    Array zeros(n);
    Work w(n, ws);
    const DistOut z = zc(ints, floats, zeros.vec(), r, P.mat(), Wt.mat(), lam.vec(), 0, 0.0,
                         0.0, max_iter, w.nvec, w.v, w.point, w.wit, w.scratch.sc);
    if (z.status == INSIDE) {
        // r is in CO(A) after all: the caller's miss test was rounding (seen with GJK on a flat
        // A whose affine span holds the ray), and the ray meets A. ZC-IE decides it.
        Shot out = zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE);
        out.iters = out.iters + iters + z.it;
        out.calls = out.calls + calls + z.calls;
        out.singular = out.singular + 1;
        return out;
    }
    const Int status = z.status != MAX_ITER ? MISS : LIMIT;
    return make_result(status, 0.0, 0.0, z.h, iters + z.it, calls + z.calls, w.nvec, P.mat(),
                       lam.vec(), Wt.mat(), 0, 0);
}

// Fig. 3b's improved stopping rule, the ray meets CH(V_A(b_k)): returns where, t' with
// barycentric weights x[:k] of t' r in CH(P[:k]), or -1. t' and the weights are solved
// together, P_0 + sum_j x_j (P_j - P_0) = t' r, so that t' r is in the hull to rounding: eq.
// (4)'s t = t_k - d_A(b_k) / n^T r carries the rounding of d_A(b_k), which put t r 1e-12
// (relative) outside an 8-D facet the least squares then still accepted. A ray along the
// face (the joint system is singular), or a t' more than eps from t, keeps eq. (4)'s t.
inline double on_ray(Mat P, Int k, Vec r, double t, double eps, Vec x, double tol,
                     const Scratch& sc) {
    const Int n = P.cols;
    Mat D = sc.D;
    Mat work = sc.work;
    Vec rhs = sc.rhs;
    Vec wrhs = sc.wrhs;
    double tj = weights_on_ray(P, k, r, x, D, work, wrhs, rhs);
    if (!(tj > 0.0 && std::abs(tj - t) <= eps * t)) {
        tj = t;
        for (Int i = 0; i < n; ++i) {
            rhs[i] = t * r[i] - P(0, i);
            for (Int j = 1; j < k; ++j) D(i, j - 1) = P(j, i) - P(0, i);
        }
        if (!lstsq(D, n, k - 1, rhs, x, 1, work, wrhs)) return -1.0;
        double s = 1.0;
        for (Int j = 1; j < k; ++j) s -= x[j];
        x[0] = s;
    }
    for (Int j = 0; j < k; ++j)
        if (x[j] < -tol) return -1.0;
    for (Int i = 0; i < n; ++i) rhs[i] = tj * r[i];
    return reproduce(P, x, k, rhs) ? tj : -1.0;
}

// GJK-based's and Bi-GJK's finish at GJK's numerical floor, from t r = sum lam_l P_l in A: IE
// steps from the facet P[:k] when k = n (its facets are solved from the origin and stay
// well-conditioned), ZC-based steps from a lower face. (Ingot W_L1: ZC-based steps from the
// facet, the former finish, stalled above eps on 70 of GJK-based's 300 rays, which the
// dispatcher's IE then redid from scratch; Bi-GJK's mean support calls 181 -> 131.)
// P, Wt, lam: the caller's, n + 2 rows (zc_from works in them).
inline Shot finish_inside(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter,
                          double t, Mat P, Mat Wt, Vec lam, Int k, Int it, Int calls) {
    const Int mode = k == r.n ? WITH_IE : ZC_ONLY;
    return zc_from(ints, floats, r, ws, eps, max_iter, mode, t, P, Wt, lam, k, it, calls,
                   Mat{}, Mat{});
}

}  // namespace gjk_based_detail

// Section 3.1: b_k outside A walks down the ray, stopped by Fig. 3b's rule.
//
// Eq. (4) steps to the hyperplane H(n_k, v_A(b_k)), which needs d_A(b_k) exactly: GJK run to
// eps at every b_k. The steps converge quadratically where A is curved (the tangent plane at
// v_A(b_k) crosses the ray within O(d^2) of z_A(r)), so an early step needs far less: while the
// last step moved t by a relative `step`, GJK stops at a relative gap of step^2 (the next
// step's expected size) and b_{k+1} is where the supporting hyperplane H(n_k, s_A(n_k))
// crosses the ray, outside A whatever GJK's accuracy. Once that tolerance reaches eps, eq. (4)
// and Fig. 3b's rule as written. (Ingot W_L1, 300 rays: median support calls 168 -> 80;
// INEXACT_GJK 0.1 gave 98, 0.01 106.) A direction from an unconverged GJK may not cut the ray
// below b at all, or even point away from it (n^T r <= 0, which only a converged GJK turns into
// a miss): GJK then goes on from the same b, TIGHTEN times tighter (62 -> 55 calls; before,
// such a ray fell into the miss test's ZC and was answered by ZC-IE, 59 of 300).
Shot gjk_based(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    using namespace gjk_based_detail;
    const Int n = r.n;
    const double rr = dot(r, r);
    Array P_(n + 2, n);
    Array Wt_(n + 2, ws);
    Array lam_(n + 2);
    const Mat P = P_.mat();
    const Mat Wt = Wt_.mat();
    const Vec lam = lam_.vec();
    Work w(n, ws);
    const Vec nvec = w.nvec, point = w.point, wit = w.wit, x = w.x;
    const Scratch& sc = w.scratch.sc;
    const double h0 = support(ints, floats, r, point, wit);
    Int calls = 1;
    if (h0 <= 0.0) return miss(ints, floats, r, ws, eps, 0, calls, max_iter);
    double t = h0 / rr;
    double t_up = t;
    Array vecs(2 * n);   // best_n, b
    const Vec best_n = vecs.vec().segment(0, n);
    const Vec b = vecs.vec().segment(n, n);
    const double rnorm = std::sqrt(rr);
    for (Int i = 0; i < n; ++i) best_n[i] = r[i] / rnorm;
    double best_h = h0 / std::sqrt(rr);
    set_row(P, Wt, 0, point, wit);
    lam[0] = 1.0;
    Int k = 1;
    double t_floor = -1.0;   // max(-h_A(-r), 0) / r^T r, evaluated when first needed
    double eps_gjk = std::max(eps, INEXACT_GJK);
    for (Int it = 0; it < max_iter; ++it) {
        for (Int i = 0; i < n; ++i) b[i] = t * r[i];
        const DistOut g = gjk(ints, floats, b, P, Wt, lam, k, eps_gjk, 0.0, true, max_iter,
                              nvec, w.v, point, wit, sc);
        k = g.k;
        const double d = g.d;
        const double h = g.h;
        calls += g.calls;
        if (g.status == INSIDE) {
            // b_k = t r is in A: it met the boundary, or rounding in v_A(b_{k-1}) put it inside.
            // Done if the last supporting hyperplane certifies it; else GJK has reached its
            // numerical floor (ingot W_L1: 255 of 300 rays).
            if (t_up - t <= eps * t) {
                // GJK's weights reproduce b only to its distance floor: on a face, solve
                // again with t free, as Fig. 3b's rule does
                const double t_ray = k <= n ? on_ray(P, k, r, t, eps, x, 1e-12, sc) : -1.0;
                if (t_ray > 0.0) {
                    t = t_ray;
                    for (Int j = 0; j < k; ++j) lam[j] = x[j];
                }
                return make_result(HIT, t, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k,
                                   0);
            }
            return finish_inside(ints, floats, r, ws, eps, max_iter, t, P, Wt, lam, k, it + 1,
                                 calls);
        }
        if (g.status == MAX_ITER)
            return make_result(LIMIT, t, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k, 0);
        const double rn = dot(r, nvec);
        const bool exact = eps_gjk <= eps;
        if (!exact && (rn <= 0.0 || h >= t * rn)) {
            // an unconverged direction whose hyperplane does not cut the ray below b tells
            // nothing yet (n^T r <= 0 is no miss before GJK converges): tighten, same b
            eps_gjk = std::max(eps, TIGHTEN * eps_gjk);
            continue;
        }
        if (rn <= 0.0) return miss(ints, floats, r, ws, eps, it + 1, calls, max_iter);
        const double t_next = exact ? t - d / rn : std::min(h / rn, t);
        if (t_floor < 0.0) {
            Array minus_r_(n);
            const Vec minus_r = minus_r_.vec();
            for (Int i = 0; i < n; ++i) minus_r[i] = -r[i];
            t_floor = std::max(-support(ints, floats, minus_r, point, wit), 0.0) / rr;
            calls += 1;
        }
        if (t_next < t_floor) return miss(ints, floats, r, ws, eps, it + 1, calls, max_iter);
        if (h / rn < t_up) {
            t_up = h / rn;
            for (Int i = 0; i < n; ++i) best_n[i] = nvec[i];
            best_h = h;
        }
        const double step = t_next > 0.0 ? (t - t_next) / t_next : 0.0;
        t = t_next;
        const double t_ray =
            exact && g.status == CONVERGED ? on_ray(P, k, r, t, eps, x, 1e-12, sc) : -1.0;
        if (t_ray > 0.0) {
            for (Int j = 0; j < k; ++j) lam[j] = x[j];
            return make_result(HIT, t_ray, t_up, best_h, it + 1, calls, best_n, P, lam, Wt, k,
                               0);
        }
        eps_gjk = std::max(eps, INEXACT_GJK * step * step);
    }
    return make_result(LIMIT, t, t_up, best_h, max_iter, calls, best_n, P, lam, Wt, k, 0);
}

}  // namespace gf
