#pragma once

#include "api.hpp"

// GJK-based ray shooting (section 3.1): b_k = t_k r outside A walks down the ray to z_A(r),
// each step to where a supporting hyperplane of A crosses it (eq. (4)), stopped by Fig. 3b's
// rule. Every shooter returns a Shot: z = t r a convex combination `lam` of the rows of V
// (points of A, witnesses in W), and the hyperplane {x : normal^T x = h_n} supporting A
// (h_n = h_A(normal)) crossing the ray at t_upper r. On a miss, normal separates:
// h_A(normal) <= 0 < normal^T r. Stopping rules are relative: (t_upper - t) / t <= eps.
// Also the pieces Bi-GJK (bi_gjk.hpp) shares: Fig. 3b's rule, the work arrays and the finish at
// GJK's numerical floor.

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

// The paper's miss tests (section 3.1) turned into the contract's certificate. The hyperplane
// {a^T x = h_a}, h_a = h_A(a), a^T r > 0, bounds any point t r of A from above, t <= t_u =
// h_a / a^T r; one with b^T r < 0 bounds it from below, t >= t_l = h_b / b^T r (the paper's
// floor: b = -r, or a converged GJK direction that points away from r). Where t_l > t_u the ray
// misses A: by subadditivity h_A(a / a^T r + b / |b^T r|) <= t_u - t_l < 0, while the product
// of that direction with r is 0; adding delta r, delta = (t_l - t_u) / (2 h_A(r)), keeps its
// support negative and turns the product positive: m with h_A(m) < 0 < m^T r. It is checked by
// a support call (into `point`, counted in `calls`); false when rounding defeats it.
inline bool crossing_miss(IVec ints, Vec floats, Vec r, Vec a, double h_a, Vec b, double h_b,
                          double h_r, Vec m, Vec point, Vec wit, double& h_m, Int& calls) {
    const double ar = dot(a, r), br = dot(b, r);
    if (!(ar > 0.0 && br < 0.0)) return false;
    const double gap = h_b / br - h_a / ar;
    if (!(gap > 0.0)) return false;
    calls += 1;
    const double delta = h_r > 0.0 ? 0.5 * gap / h_r : 1.0 / dot(r, r);
    double mm = 0.0;
    for (Int i = 0; i < r.n; ++i) {
        m[i] = a[i] / ar - b[i] / br + delta * r[i];
        mm += m[i] * m[i];
    }
    const double inv = 1.0 / std::sqrt(mm);
    for (Int i = 0; i < r.n; ++i) m[i] *= inv;
    h_m = support(ints, floats, m, point, wit);
    return h_m <= 0.0 && dot(m, r) > 0.0;
}

// Section 3.1's walk, from b_0 = h_A(r) r / r^T r down the ray, above the floor t_lo: a point of
// A on the ray, t_lo r = sum lz_j Pz_j (kz > 0, certified by `holds`), or, with kz = 0, the
// paper's floor max(-h_A(-r), 0) / r^T r under which A has no point of the ray.
//
// Eq. (4) steps to the hyperplane H(n_k, v_A(b_k)), which needs d_A(b_k) exactly: GJK run to
// eps at every b_k. The steps converge quadratically where A is curved (the tangent plane at
// v_A(b_k) crosses the ray within O(d^2) of z_A(r)), so an early step needs far less: while the
// last step moved t by a relative `step`, GJK stops at a relative gap of step^2 (the next
// step's expected size) and b_{k+1} is where the supporting hyperplane H(n_k, s_A(n_k))
// crosses the ray, outside A whatever GJK's accuracy. Once that tolerance reaches eps, eq. (4)
// and Fig. 3b's rule as written. (Ingot W_L1, 300 rays: median support calls 168 -> 80;
// INEXACT_GJK 0.1 gave 98, 0.01 106.) A direction from an unconverged GJK may not cut the ray
// below b at all, or even point away from it (n^T r <= 0): GJK then goes on from the same b,
// TIGHTEN times tighter (62 -> 55 calls). GJK's INSIDE is taken for a point of A on the ray
// only when its weights reproduce t r relative to t r (`holds`): its own floor is relative to
// A's size, and a ray that leaves A at the origin comes within it of A at every small t.
// Pz, Wz, lz: n + 2 rows (finish_inside's zc_from works in them). it: iterations so far.
inline Shot walk(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Mat Pz, Mat Wz,
                 Vec lz, Int kz, double t_lo, Int it0, Int calls) {
    const Int n = r.n;
    const double rr = dot(r, r);
    Array P_(n + 2, n), Wt_(n + 2, ws), lam_(n + 2);
    const Mat P = P_.mat(), Wt = Wt_.mat();
    const Vec lam = lam_.vec();
    Work w(n, ws);
    const Vec nvec = w.nvec, point = w.point, wit = w.wit, x = w.x;
    const Scratch& sc = w.scratch.sc;
    Array vecs(3 * n);   // best_n, b, low_n
    const Vec best_n = vecs.vec().segment(0, n);
    const Vec b = vecs.vec().segment(n, n);
    // the best hyperplane that bounds the ray's points of A from below (low_n^T r < 0): the
    // paper's floor, -r, at first
    const Vec low_n = vecs.vec().segment(2 * n, n);
    const double h0 = support(ints, floats, r, point, wit);
    calls += 1;
    double t = h0 / rr;
    double t_up = t;
    const double rnorm = std::sqrt(rr);
    for (Int i = 0; i < n; ++i) best_n[i] = r[i] / rnorm;
    double best_h = h0 / rnorm;
    for (Int i = 0; i < n; ++i) low_n[i] = -r[i] / rnorm;
    double low_h = -t_lo * rnorm;
    // the walk reached its floor: the bracket [t_lo, t_up] closes on the certified point, or is
    // finished from it by zc_from, which certifies its own answer; with no point of A, below
    // the paper's floor the ray misses A
    auto at_floor = [&](Int iters) {
        if (kz == 0) {
            double h_m = 0.0;
            if (crossing_miss(ints, floats, r, best_n, best_h, low_n, low_h, h0, nvec, point,
                              wit, h_m, calls))
                return make_result(MISS, 0.0, 0.0, h_m, iters, calls, nvec, Pz, lz, Wz, 0, 0);
            return make_result(LIMIT, 0.0, t_up, best_h, iters, calls, best_n, Pz, lz, Wz, 0, 0);
        }
        if (t_up - t_lo <= eps * t_lo && holds(Pz, lz, kz, t_lo, r, b, POINT_HOLDS))
            return make_result(HIT, std::min(t_lo, t_up), t_up, best_h, iters, calls, best_n, Pz,
                               lz, Wz, kz, 0);
        return finish_inside(ints, floats, r, ws, eps, max_iter, t_lo, Pz, Wz, lz, kz, iters,
                             calls);
    };
    set_row(P, Wt, 0, point, wit);
    lam[0] = 1.0;
    Int k = 1;
    double eps_gjk = std::max(eps, INEXACT_GJK);
    bool newton_tried = false;
    for (Int it = it0; it < max_iter; ++it) {
        if (t <= t_lo) return at_floor(it);
        for (Int i = 0; i < n; ++i) b[i] = t * r[i];
        const DistOut g = gjk(ints, floats, b, P, Wt, lam, k, eps_gjk, 0.0, true, max_iter,
                              nvec, w.v, point, wit, sc);
        k = g.k;
        const double d = g.d;
        const double h = g.h;
        calls += g.calls;
        if (g.status == INSIDE) {
            // b_k = t r is in A: it met the boundary, or rounding in v_A(b_{k-1}) put it
            // inside; or it lies within GJK's floor of A, which is relative to A's size: a
            // point of A on the ray only if GJK's weights reproduce it relative to its length
            if (!holds(P, lam, k, t, r, b, POINT_HOLDS)) return at_floor(it + 1);
            t_lo = t;
            kz = keep(P, Wt, lam, k, Pz, Wz, lz);
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
            return make_result(LIMIT, t_lo, t_up, best_h, it + 1, calls, best_n, Pz, lz, Wz, kz,
                               0);
        if (g.status == STALLED && eps_gjk <= eps && !newton_tried) {
            // GJK's simplex lost rank at the exit (a corner of A, whose normals form a cone of
            // more than one ray): Newton on its pieces, from the best normal so far (once: a
            // walk stalls again where Newton could not finish)
            newton_tried = true;
            for (Int c = 0; c < 2; ++c) {
                NewtonOut fin =
                    newton_finish(ints, floats, r, eps, P, Wt, lam, k, best_n, t, c == 1);
                calls += fin.calls;
                it += fin.steps;   // each Newton step counts as an iteration, as in zc_from
                if (fin.ok)
                    return make_result(HIT, fin.t, fin.t_up, fin.h, it + 1, calls,
                                       fin.normal.vec(), fin.V.mat(), fin.weights.vec(),
                                       fin.W.mat(), fin.m, 0);
            }
        }
        const double rn = dot(r, nvec);
        const bool exact = eps_gjk <= eps;
        if (!exact && (rn <= 0.0 || h >= t * rn)) {
            // an unconverged direction whose hyperplane does not cut the ray below b tells
            // nothing yet: tighten, same b
            eps_gjk = std::max(eps, TIGHTEN * eps_gjk);
            continue;
        }
        // b outside A and a point of A below put every separating direction's n^T r > 0: a
        // converged one that does not is GJK's rounding there; with no such point, the paper's
        // miss (n^T r <= 0 while d_A(b) > 0), certified at the floor (crossing_miss)
        if (rn <= 0.0) {
            if (kz > 0) return at_floor(it + 1);
            // the paper's miss: every point of A on the ray lies above h / n^T r, which is
            // above b (b is outside A, on the far side of n's hyperplane) and so above t_up
            if (rn < 0.0 && h / rn > low_h / dot(low_n, r)) {
                for (Int i = 0; i < n; ++i) low_n[i] = nvec[i];
                low_h = h;
            }
            return at_floor(it + 1);
        }
        const double t_next = exact ? t - d / rn : std::min(h / rn, t);
        if (h / rn < t_up) {
            t_up = h / rn;
            for (Int i = 0; i < n; ++i) best_n[i] = nvec[i];
            best_h = h;
        }
        const double step = t_next > 0.0 ? (t - t_next) / t_next : 0.0;
        t = t_next;
        if (t <= t_lo) return at_floor(it + 1);
        // Fig. 3b's rule, on GJK's simplex when it converged or stalled (its hull is in A
        // either way): a point of A on the ray, the answer once the bracket closes on it, else
        // the walk's floor
        const double t_ray =
            exact && g.status != MAX_ITER ? on_ray(P, k, r, t, eps, x, 1e-12, sc) : -1.0;
        if (t_ray > t_lo) {
            for (Int j = 0; j < k; ++j) lam[j] = x[j];
            if (t_up - t_ray <= eps * t_ray)
                return make_result(HIT, t_ray, t_up, best_h, it + 1, calls, best_n, P, lam, Wt,
                                   k, 0);
            t_lo = t_ray;
            kz = keep(P, Wt, lam, k, Pz, Wz, lz);
        }
        eps_gjk = std::max(eps, INEXACT_GJK * step * step);
    }
    return make_result(LIMIT, t_lo, t_up, best_h, max_iter, calls, best_n, Pz, lz, Wz, kz, 0);
}

// ZC from the origin (section 3.3), as every procedure starts: r outside CO(A), a miss (or a ray
// that leaves A at the origin) certified by h_A(n) <= 0 < n^T r (to rounding: miss_to_rounding;
// a stalled ZC's normal first made orthogonal to its generators' span, `polish_normal`),
// returned as such (LIMIT when ZC ran out of iterations); else ZC's point t r = sum lz_j Pz_j
// with its t. Where neither is certified, kz = 0 and t = the paper's floor
// max(-h_A(-r), 0) / r^T r, for the walk from outside to decide: ZC stalled short of a
// certificate (r within ~1e-6 of a curved face of CO(A)), or its weights do not reproduce its
// point (r along the boundary of CO(A): ZC's cone loses rank and takes for INSIDE a point it
// reproduces to ~1e-8, 1e-6 off along a ray that grazes A). Pz, Wz, lz: n + 2 rows.
struct Start {
    bool decided;   // `shot` is the answer
    Shot shot;
    Int kz;
    double t;
    Int calls;
};
inline Start start(IVec ints, Vec floats, Vec r, Int ws, Int max_iter, Mat Pz, Mat Wz, Vec lz) {
    const Int n = r.n;
    Work w(n, ws);
    Array zeros(n);
    const DistOut z = zc(ints, floats, zeros.vec(), r, Pz, Wz, lz, 0, 0.0, 0.0, max_iter, w.nvec,
                         w.v, w.point, w.wit, w.scratch.sc);
    Int calls = z.calls;
    if (z.status == MAX_ITER)
        return {true, make_result(LIMIT, 0.0, INF, z.h, 1, calls, w.nvec, Pz, lz, Wz, 0, 0), 0,
                0.0, calls};
    if (z.status != INSIDE) {
        double h = z.h;
        if (z.status == STALLED && h > 0.0) {
            const double hm =
                zc_family_detail::polish_normal(ints, floats, r, Pz, z.k, w.nvec, w.v, zeros.vec(),
                                                w.point, w.wit, w.scratch.sc, calls);
            if (hm <= h) {
                for (Int i = 0; i < n; ++i) w.nvec[i] = w.v[i];
                h = hm;
            }
        }
        if (z.status == CONVERGED || miss_to_rounding(h, Pz, z.k))
            return {true, make_result(MISS, 0.0, 0.0, h, 1, calls, w.nvec, Pz, lz, Wz, 0, 0), 0,
                    0.0, calls};
    } else {
        double sigma = 0.0;
        for (Int j = 0; j < z.k; ++j) sigma += lz[j];
        for (Int j = 0; j < z.k; ++j) lz[j] /= sigma;
        if (holds(Pz, lz, z.k, 1.0 / sigma, r, w.v, POINT_HOLDS))
            return {false, Shot{}, z.k, 1.0 / sigma, calls};
    }
    for (Int i = 0; i < n; ++i) w.nvec[i] = -r[i];
    const double floor = std::max(-support(ints, floats, w.nvec, w.point, w.wit), 0.0) / dot(r, r);
    return {false, Shot{}, 0, floor, calls + 1};
}

}  // namespace gjk_based_detail

// Section 3.1: b_k outside A walks down the ray, stopped by Fig. 3b's rule (`walk`).
//
// Whether the ray meets A beyond the origin is decided first, as every other procedure decides
// it: ZC from the origin (section 3.3, `start`) finds r in CO(A), with a point t_lo r of A
// (t_lo > 0), or a direction n with h_A(n) <= 0 < n^T r, which certifies a miss and a ray that
// leaves A at the origin alike. The paper's own miss tests cannot tell the latter from a hit:
// with the origin in A, max(-h_A(-r), 0) = 0 and eq. (4) walks down to t = 0, where GJK's
// rounding floor, relative to A's size, takes t r for a point of A. The walk stays above t_lo,
// its floor: a crossing below it is rounding, and the bracket [t_lo, t_upper] is finished from
// there.
Shot gjk_based(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    using namespace gjk_based_detail;
    const Int n = r.n;
    Array Pz(n + 2, n), Wz(n + 2, ws), lz(n + 2);
    Start s = start(ints, floats, r, ws, max_iter, Pz.mat(), Wz.mat(), lz.vec());
    if (s.decided) return std::move(s.shot);
    // ZC's call is the first iteration
    return walk(ints, floats, r, ws, eps, max_iter, Pz.mat(), Wz.mat(), lz.vec(), s.kz, s.t, 1,
                s.calls);
}

}  // namespace gf
