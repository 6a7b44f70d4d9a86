#pragma once

#include "api.hpp"
#include "shooting/gjk_based.hpp"

// Bi-GJK ray shooting (section 3.4.1): bisection on the ray between a point of A (from ZC, or
// a start table's facet) and a point outside (from supporting hyperplanes H(n, s_A(n))), each
// midpoint tested by GJK for membership in A. The result's z = t r is a convex combination of
// the simplex that last held a point of the ray; its bracket [t, t_upper] closes to eps
// relative.

namespace gf {
namespace bi_gjk_detail {

struct Exit {
    double t;
    Int k;
};

// GJK proved t r inside A with n + 1 points P[:k] (weights lam): the ray stays in their
// simplex up to t + s, where the barycentric weights lam + s mu of (t + s) r (mu: those of r,
// summing to 0) first reach zero. Moves lam there, drops the point whose weight reached zero
// and returns (t + s, k - 1); (t, k) when the simplex is degenerate.
inline Exit simplex_exit(Mat P, Mat Wt, Vec lam, Int k, Vec r, double t, Mat M, Mat lu,
                         IVec piv, Vec rhs, Vec mu) {
    const Int n = P.cols;
    for (Int j = 0; j < k; ++j) {
        for (Int i = 0; i < n; ++i) M(i, j) = P(j, i);
        M(n, j) = 1.0;
    }
    for (Int i = 0; i < n; ++i) rhs[i] = r[i];
    rhs[n] = 0.0;
    if (!lu_factor(M, k, lu, piv)) return {t, k};
    lu_solve(lu, piv, k, rhs, mu);
    double s = INF;
    Int js = -1;
    for (Int j = 0; j < k; ++j) {
        if (mu[j] < 0.0 && lam[j] / -mu[j] < s) {
            s = lam[j] / -mu[j];
            js = j;
        }
    }
    if (js < 0) return {t, k};
    for (Int j = 0; j < k; ++j) lam[j] = std::max(lam[j] + s * mu[j], 0.0);
    lam[js] = 0.0;
    return {t + s, drop_point(P, Wt, lam, k, js)};
}

}  // namespace bi_gjk_detail

// Section 3.4.1: bisection between a point of A on the ray (from ZC) and a point outside
// (from supporting hyperplanes), each midpoint tested by GJK. When GJK proves a midpoint
// inside with a full simplex of n + 1 points, the inner point moves on to where the ray leaves
// that simplex, not just to the midpoint (`simplex_exit`): ingot W_L1, median iterations
// 32 -> 6, support calls 74 -> 72.
Shot bi_gjk(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    using namespace gjk_based_detail;
    const Int n = r.n;
    Array P(n + 2, n), Wt(n + 2, ws), lam(n + 2);
    Start s = start(ints, floats, r, ws, max_iter, P.mat(), Wt.mat(), lam.vec());
    if (s.decided) return std::move(s.shot);
    // ZC's point is the bisection's lower end only where its weights reproduce it; else no
    // point of A is known on the ray, and the walk from outside (section 3.1) finds one
    if (s.kz == 0)
        return walk(ints, floats, r, ws, eps, max_iter, P.mat(), Wt.mat(), lam.vec(), 0, s.t, 1,
                    s.calls);
    return bi_gjk_from(ints, floats, r, ws, eps, max_iter, s.t, P.mat(), Wt.mat(), lam.vec(),
                       s.kz, r, s.calls);
}

// Bi-GJK's bisection from t_lo r = sum lam_l P_l (l < k), a point of A, and the upper
// bound of the supporting hyperplane H(u, s_A(u)) (u = r from ZC's start; a start table's
// facet normal, much nearer the answer's, from start_table.hpp).
Shot bi_gjk_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, double t_lo,
                 Mat P, Mat Wt, Vec lam, Int k, Vec u, Int calls) {
    using gjk_based_detail::finish_inside;
    using gjk_based_detail::on_ray;
    const Int n = r.n;
    const double rr = dot(r, r);
    Array Pz_(n + 2, n);
    Array Wz_(n + 2, ws);
    Array lz_(n + 2);
    const Mat Pz = Pz_.mat();
    const Mat Wz = Wz_.mat();
    const Vec lz = lz_.vec();
    gjk_based_detail::Work w(n, ws);
    const Vec nvec = w.nvec, point = w.point, wit = w.wit, x = w.x;
    const Scratch& sc = w.scratch.sc;
    Array exit_work(2 * (n + 1), n + 1);
    const Mat M = exit_work.mat().rows_range(0, n + 1);
    const Mat lu = exit_work.mat().rows_range(n + 1, 2 * (n + 1));
    IArray piv(n + 1);
    Array rhs(n + 1);
    Int kz = keep(P, Wt, lam, k, Pz, Wz, lz);
    Array vecs(2 * n);   // best_n, b
    const Vec best_n = vecs.vec().segment(0, n);
    const Vec b = vecs.vec().segment(n, n);
    const double unorm = std::sqrt(dot(u, u));
    for (Int i = 0; i < n; ++i) best_n[i] = u[i] / unorm;
    double best_h = support(ints, floats, best_n, point, wit);
    calls += 1;
    double un = dot(best_n, r);
    if (!(un > 0.0 && best_h >= t_lo * un)) {
        // a table's facet normal that rounding left behind t_lo: r's own bound instead
        const double rnorm = std::sqrt(rr);
        for (Int i = 0; i < n; ++i) best_n[i] = r[i] / rnorm;
        best_h = support(ints, floats, best_n, point, wit);
        calls += 1;
        un = std::sqrt(rr);
    }
    double t_hi = best_h / un;
    double t_up = t_hi;
    for (Int it = 0; it < max_iter; ++it) {
        if (t_up - t_lo <= eps * t_lo) {
            if (holds(Pz, lz, kz, t_lo, r, point, point_holds(eps))) {
                // a table's t_lo = 1 / sum(gam) can exceed t_up by an ulp or two where the ray
                // leaves A exactly at a vertex of the table's facet
                return make_result(HIT, std::min(t_lo, t_up), t_up, best_h, it + 1, calls,
                                   best_n, Pz, lz, Wz, kz, 0);
            }
            // ZC's first point reproduced only to ~1e-8 (a ray along the boundary of CO(A):
            // zc_from's end), which zc_from's finish settles
            return finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz,
                                 it + 1, calls);
        }
        if (t_hi - t_lo <= 1e-3 * eps * t_lo) {
            // the bracket closed on points GJK could not certify: its numerical floor
            return finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz,
                                 it + 1, calls);
        }
        const double tm = 0.5 * (t_lo + t_hi);
        for (Int i = 0; i < n; ++i) b[i] = tm * r[i];
        const DistOut g = gjk(ints, floats, b, P, Wt, lam, k, eps, 0.0, true, max_iter, nvec,
                              w.v, point, wit, sc);
        k = g.k;
        const double d = g.d;
        const double h = g.h;
        calls += g.calls;
        if (g.status == MAX_ITER) break;
        if (g.status == INSIDE) {
            // GJK's floor is absolute (A's size): tm r is a point of A on the ray only if the
            // weights reproduce it relative to its own length; else the bisection has reached
            // that floor
            if (!holds(P, lam, k, tm, r, b, POINT_HOLDS))
                return finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz,
                                     it + 1, calls);
            t_lo = tm;
            if (k == n + 1) {
                const bi_gjk_detail::Exit e =
                    bi_gjk_detail::simplex_exit(P, Wt, lam, k, r, tm, M, lu, piv.vec(),
                                                rhs.vec(), x);
                t_lo = e.t;
                k = e.k;
            }
            kz = keep(P, Wt, lam, k, Pz, Wz, lz);
            continue;
        }
        const double rn = dot(r, nvec);
        if (rn > 0.0 && h / rn < t_up) {
            t_up = h / rn;
            for (Int i = 0; i < n; ++i) best_n[i] = nvec[i];
            best_h = h;
        }
        // GJK puts tm r outside A; when its gap is too wide to certify that, the bisection
        // still moves (t_up stays the certified bound)
        t_hi = std::min(tm, t_up);
        if (rn <= 0.0) continue;
        const double t_b = tm - d / rn;
        double t_ray = -1.0;
        if (g.status == CONVERGED && t_b > t_lo) t_ray = on_ray(P, k, r, t_b, eps, x, 1e-12, sc);
        if (t_ray > t_lo) {
            t_lo = t_ray;
            kz = keep(P, Wt, x, k, Pz, Wz, lz);
        }
    }
    return make_result(LIMIT, t_lo, t_up, best_h, max_iter, calls, best_n, Pz, lz, Wz, kz, 0);
}

}  // namespace gf
