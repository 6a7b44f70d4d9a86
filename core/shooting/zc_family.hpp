#pragma once

#include "api.hpp"
#include "shooting/shot.hpp"
#include "geometry/piece.hpp"

// ZC-based ray shooting (section 3.3) and ZC-IE (section 3.4.2), with or without the Newton
// finish (newton.hpp).
//
// From b_k = t_k r in A (the origin first, which decides whether the ray meets A), ZC on
// A - b_k toward r either finds r in the cone CO(V_k - b_k), which moves b_k along the ray to
// b_{k+1} = sum_l lam_l V_l, or a direction n with h_{A - b_k}(n) within eps: z_A(r) = b_k,
// supported by H(n, s_A(n)). ZC-IE takes plain IE steps whenever V_k has n points, a facet the
// ray crosses inside: its hyperplane y^T x = 1 from the facet's inverse (updated by the revised
// simplex method's pivot rule between fresh factorizations), the support point s_A(y), and the
// ratio test for the vertex it replaces. With directions known for the facet's points, IE's
// query may be the secant query, the support map's linear model through the facet. Z_A(r) is
// the simplex kept at the end (Pz, Wz, lz).

namespace gf {
namespace zc_family_detail {

constexpr Int REFACTOR = 64;   // IE steps between fresh factorizations of the facet matrix
// "zc-ie-newton" tries the Newton finish (newton.hpp, docs/core-api.md), and "zc-ie" its smooth
// path alone on the sets it takes (smooth_finish), in up to R^NEWTON_CHEAP
// once an IE step's relative gap is at most NEWTON_GAP; above, where a try is dear (grasps in R^6:
// ~5 us, more than the IE steps it saved when tried early), once the gap is at most
// NEWTON_GAP_DEAR and the last NEWTON_STABLE n IE steps each found their support point on a piece
// of their facet (the exit face's pieces are found); after a failed try, the next waits for the
// gap to shrink by NEWTON_RETRY (1e-2 left ~15 IE steps between the tries). The smooth path's
// try that ends before its first step (a flat piece: a contact whose friction is not saturated,
// or a piece at its kink) is not repeated: the face keeps its pieces as IE closes in (a pinch
// by two soft fingers tried ~6 times a shot, each ~1,800 instructions, and finished 14%)
constexpr Int NEWTON_CHEAP = 3;
constexpr double NEWTON_GAP = 0.1;
constexpr double NEWTON_GAP_DEAR = 1e-2;
constexpr Int NEWTON_STABLE = 2;
constexpr double NEWTON_RETRY = 0.1;
// W_Linf's sum (sum_finish.hpp): tries before IE goes on alone
constexpr Int SUM_TRIES = 2;
// the secant query (ZC-IE from a facet whose points' support directions are known: `zc_from`'s
// `directions`): a secant point must keep at least SECANT_HOLD of the weight of t r in the next
// facet, and its query's gap must be at most SECANT_GAIN times the last query's, else
// SECANT_REST plain IE steps follow before the next try. Measured on the growth protocol and on
// random pairs: 0.9 and 4 (support calls, protocol median 26 -> 19; 0.5 or 1 step of rest tried
// secant queries on flat pieces too often); the gain rule, 0.5, catches secant points that keep
// their weight but not their pace (random pairs' mean 22.2 -> 19.1 calls; 0.25 and 0.1 were
// worse)
constexpr double SECANT_HOLD = 0.9;
constexpr Int SECANT_REST = 4;
constexpr double SECANT_GAIN = 0.5;
// zc_from gives up after this many ZC steps in a row that find b_k inside ZC's cone without
// moving it: a corner its steps never leave (W_Linf's lift of two point contacts at the edge of
// what they resist went on to max_iter, 10000 steps, t unchanged after the 23rd). Not 1: giving
// up at the first such step failed a doubled contact 1e-9 inside its cone's edge (Linf) once
constexpr Int IDLE_STEPS = 100;
constexpr double NEGLIGIBLE = 1e-6;   // restart: a relative weight this small leaves b on the face of the others
// the loop's stop for ZC's point that could not be certified: the Newton finish, else LIMIT
// (besides the statuses HIT, MISS, LIMIT and FACET)
constexpr Int NEWTON_END = 5;

// One ZC-based iteration (section 3.3) from b_k = t r (written to b): ZC on A - b_k toward r.
inline DistOut zc_step(IVec ints, Vec floats, Vec r, double t, Mat P, Mat Wt, Vec lam, Int k,
                       double eps, Int max_iter, Vec nvec, Vec v, Vec point, Vec wit, Vec b,
                       const Scratch& sc) {
    for (Int i = 0; i < r.n; ++i) b[i] = t * r[i];
    // purely relative: an absolute floor would accept h > eps n^T b when n^T r is small
    return zc(ints, floats, b, r, P, Wt, lam, k, eps, 0.0, max_iter, nvec, v, point, wit, sc);
}

// A stalled ZC's normal at the origin, polished toward a miss certificate (written to `m`, with
// h_A(m) returned; NaN when no direction with m^T r > 0 came of it). First made orthogonal to the
// span of its generators P[:k]: they span the face of CO(A) nearest r, whose hyperplane through
// the origin a certificate's is, and rounding in their large weights leaves the normal off it by
// ~1e-16 of their mass (h_A(n) ~1e-11 for two point contacts whose wrench is off their grasp
// map's span, 8e-15 after). Then up to POLISH_STEPS Newton steps on h_A, whose gradient is the
// support point s: m - (1 + POLISH_OVERSHOOT) h_A(m) s / ||s||^2, into the polar cone where a
// curved face of CO(A) left ZC a positive h_A (W_Linf of full magnitude: a face of second-order
// cones, where ZC's steps stop gaining at h_A ~1e-10). `best` is work of n entries; support
// calls are counted in `calls`.
constexpr Int POLISH_STEPS = 4;
constexpr double POLISH_OVERSHOOT = 1e-3;
// Out of line: a rare case, whose code stays out of zc_loop, the IE steps' loop.
[[gnu::noinline]] inline double polish_normal(IVec ints, Vec floats, Vec r, Mat P, Int k,
                                              Vec nvec, Vec m, Vec best, Vec point, Vec wit,
                                              const Scratch& sc, Int& calls) {
    const Int n = r.n;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (Int i = 0; i < n; ++i) m[i] = nvec[i];
    if (k >= 1 && k < n) {
        for (Int i = 0; i < n; ++i)
            for (Int j = 0; j < k; ++j) sc.D(i, j) = P(j, i);
        if (lstsq(sc.D, n, k, nvec, sc.x, 0, sc.work, sc.wrhs)) {
            for (Int i = 0; i < n; ++i) {
                double s = nvec[i];
                for (Int j = 0; j < k; ++j) s -= sc.x[j] * P(j, i);
                m[i] = s;
            }
        }
    }
    double h_best = nan;
    for (Int step = 0; step <= POLISH_STEPS; ++step) {
        const double mm = dot(m, m);
        if (!(mm > 0.0)) break;
        const double inv = 1.0 / std::sqrt(mm);
        for (Int i = 0; i < n; ++i) m[i] *= inv;
        if (!(dot(m, r) > 0.0)) break;
        const double h = support(ints, floats, m, point, wit);
        calls += 1;
        if (!(h >= h_best)) {   // also the first: h_best is NaN
            h_best = h;
            for (Int i = 0; i < n; ++i) best[i] = m[i];
        }
        const double ss = dot(point, point);
        if (!(h > 0.0) || !(ss > 0.0)) break;
        const double c = (1.0 + POLISH_OVERSHOOT) * h / ss;
        for (Int i = 0; i < n; ++i) m[i] -= c * point[i];
    }
    for (Int i = 0; i < n; ++i) m[i] = best[i];
    return h_best;
}

// ZC from the origin ended (CONVERGED or STALLED) short of r: MISS with normal nvec and h_A, or
// LIMIT with the bracket [0, h_A(n) / n^T r] where a stall's normal, polished, is not a
// certificate to rounding (`miss_to_rounding`). nvec is overwritten by the polished normal where
// that is better; m and best are work. Out of line, as polish_normal.
struct OriginVerdict {
    Int code;
    double t_up;
    double h;
    Int calls;
};
[[gnu::noinline]] inline OriginVerdict origin_verdict(IVec ints, Vec floats, Vec r, Int st,
                                                      double h, Mat P, Int k, Vec nvec, Vec m,
                                                      Vec best, Vec point, Vec wit,
                                                      const Scratch& sc) {
    Int calls = 0;
    if (st == STALLED && h > 0.0) {
        const double hm = polish_normal(ints, floats, r, P, k, nvec, m, best, point, wit, sc,
                                        calls);
        if (hm <= h) {
            for (Int i = 0; i < r.n; ++i) nvec[i] = m[i];
            h = hm;
        }
    }
    if (st == CONVERGED || miss_to_rounding(h, P, k)) return {MISS, 0.0, h, calls};
    const double nr = dot(nvec, r);
    return {LIMIT, nr > 0.0 ? h / nr : INF, h, calls};
}

// Whether the support point with witness `wit` lies on a piece (piece.hpp) of one of the facet's
// points Wt[:n].
[[gnu::always_inline]] inline bool on_facet_piece(IVec ints, Mat Wt, Int n, Vec wit) {
    for (Int j = 0; j < n; ++j)
        if (piece::same_piece(ints, wit, Wt.row(j))) return true;
    return false;
}

// on_facet_piece on a smooth hull (smooth_finish's sets), where a piece is an ellipsoid leaf:
// whether a facet point flags the leaf that wit flags (false for an embedding's origin). The
// witnesses' flags alone, not same_piece's walk over every node.
[[gnu::always_inline]] inline bool on_facet_leaf(IVec ints, Mat Wt, Int n, Vec wit) {
    const piece::SmoothLeaf e = piece::smooth_leaf(ints, wit);
    if (e.leaf < 0) return false;
    const Int w = ints[blocks(ints[0]).WSTART + e.leaf];
    for (Int j = 0; j < n; ++j)
        if (Wt(j, w) != 0.0) return true;
    return false;
}

// M = [P_0 .. P_{n-1}]: the facet's points as columns.
[[gnu::always_inline]] inline void facet_matrix(Mat P, Int n, Mat M) {
    for (Int j = 0; j < n; ++j)
        for (Int i = 0; i < n; ++i) M(i, j) = P(j, i);
}

// LU of [P_0 .. P_{n-1}] (facet points as columns) into lu, piv; false when singular.
inline bool factor_facet(Mat P, Int n, Mat M, Mat lu, IVec piv) {
    facet_matrix(P, n, M);
    return lu_factor(M, n, lu, piv);
}

// y (the facet's hyperplane y^T x = 1) and gam (r = sum gam_l P_l) by LU solves on a fresh
// factorization of [P_0 .. P_{n-1}], left in lu, piv; false when singular.
inline bool solve_facet(Mat P, Int n, Vec r, Mat M, Mat lu, IVec piv, Vec ones, Vec y, Vec gam) {
    if (!factor_facet(P, n, M, lu, piv)) return false;
    lu_solve_t(lu, piv, n, ones, y);
    lu_solve(lu, piv, n, r, gam);
    return true;
}

// B = [P_0 .. P_{n-1}]^{-1} (facet points as columns); false when singular. (Python's
// `_invert`, renamed: gf::invert is linalg's.)
inline bool invert_facet(Mat P, Int n, Mat M, IVec piv, Mat B) {
    facet_matrix(P, n, M);
    return invert(M, n, B, piv);
}

// out = B x
[[gnu::always_inline]] inline void matvec(Mat B, Int n, Vec x, Vec out) {
    for (Int i = 0; i < n; ++i) {
        double s = 0.0;
        for (Int j = 0; j < n; ++j) s += B(i, j) * x[j];
        out[i] = s;
    }
}

// out = B^T 1: the facet's hyperplane y^T x = 1.
[[gnu::always_inline]] inline void matvec_t_ones(Mat B, Int n, Vec out) {
    for (Int j = 0; j < n; ++j) out[j] = 0.0;
    for (Int i = 0; i < n; ++i)
        for (Int j = 0; j < n; ++j) out[j] += B(i, j);
}

// Whether row j of P is x, exactly.
[[gnu::always_inline]] inline bool same_point(Mat P, Int j, Vec x) {
    for (Int i = 0; i < x.n; ++i)
        if (P(j, i) != x[i]) return false;
    return true;
}

// Column js of the facet replaced by s, with B s = alpha (Sherman-Morrison, as in the revised
// simplex method): row js of the new inverse is B[js] / alpha_js, and every other row i loses
// alpha_i times it. y = B^T 1 and gam = B r follow in O(n): gam like a column of B, and y gains
// (1 - sum alpha) times the new row js (the column sums of the row operations). No test for
// alpha_i = 0: the loops stay branch-free, which the compiler unrolls for a fixed n.
[[gnu::always_inline]] inline void pivot(Mat B, Int n, Vec alpha, Int js, Vec y, Vec gam) {
    const double inv = 1.0 / alpha[js];
    double asum = 0.0;
    for (Int i = 0; i < n; ++i) asum += alpha[i];
    for (Int j = 0; j < n; ++j) {
        B(js, j) *= inv;
        y[j] += (1.0 - asum) * B(js, j);
    }
    gam[js] *= inv;
    for (Int i = 0; i < n; ++i) {
        if (i != js) {
            const double f = alpha[i];
            gam[i] -= f * gam[js];
            for (Int j = 0; j < n; ++j) B(i, j) -= f * B(js, j);
        }
    }
}

// t of the convex combination gam / sum(gam) of the facet's points that is t r, when every
// weight is >= 0 and the hyperplane n (h = h_A(n), nr = n^T r) closes the bracket on it to eps;
// 0 otherwise. 1 / (y^T r) is the same t in exact arithmetic, but on a nearly degenerate facet y
// carries its conditioning's rounding, and the weights gam / (y^T r) need not sum to 1: a point
// outside A (a growth-distance contact pair at eps = 1e-10 was certified 1.1e-7 off the truth).
inline double certified_t(Vec gam, Int n, double h, double nr, double eps) {
    double gsum = 0.0;
    for (Int j = 0; j < n; ++j) gsum += gam[j];
    if (!(gsum > 0.0 && smallest(gam, n) >= 0.0 && nr > 0.0)) return 0.0;
    const double tz = 1.0 / gsum;
    return h / nr - tz <= eps * tz ? tz : 0.0;
}

// Warm start for the next ZC call (section 3.3) from b = sum_l lam_l P_l, the new point on the
// ray: the generators P_l - b are linearly dependent (sum_l lam_l (P_l - b) = 0), so one point
// must go. Drop the one whose loss leaves r_L, the part of r along aff(P[:k]), inside the cone
// of the others' generators: ZC's first residual is then r - r_L, normal to aff(P[:k]), and its
// first query IE's (the facet's normal when k = n). With r_L = sum_l beta_l (P_l - b)
// (beta_0 = 0, the others by least squares), the others' cone holds r_L iff
// beta - (beta_j / lam_j) lam >= 0: j = argmin_l beta_l / lam_l. (Ingot W_L1, ZC-based: median
// support calls 191 -> 36 against dropping the largest weight, which left ZC to find the
// outward direction by many small steps.) Points of weight below NEGLIGIBLE go first: b lies on
// the face of the others, and the rule applies there (kept, such a point was dropped and found
// again by every ZC call, with no progress: seen on a 6-D ball). Returns the new k.
inline Int restart(Mat P, Mat Wt, Vec lam, Int k, Vec r, const Scratch& sc) {
    double total = 0.0;
    for (Int l = 0; l < k; ++l) total += lam[l];
    const double floor = NEGLIGIBLE * total;
    Int l = k - 1;
    while (l >= 0 && k > 1) {
        if (lam[l] <= floor) {
            total -= lam[l];
            k = drop_point(P, Wt, lam, k, l);
        }
        l -= 1;
    }
    if (k <= 1) return 0;
    const Int n = P.cols;
    const Mat D = sc.D, work = sc.work;
    const Vec rhs = sc.rhs, wrhs = sc.wrhs, x = sc.x;
    for (Int i = 0; i < n; ++i) {
        double b = 0.0;
        for (Int m = 0; m < k; ++m) b += lam[m] * P(m, i);
        b /= total;
        for (Int m = 1; m < k; ++m) D(i, m - 1) = P(m, i) - b;
        rhs[i] = r[i];
    }
    Int j = 0;
    if (lstsq(D, n, k - 1, rhs, x, 1, work, wrhs)) {
        x[0] = 0.0;
        double best = INF;
        for (Int m = 0; m < k; ++m) {
            const double ratio = lam[m] > 0.0 ? x[m] / lam[m] : -INF;
            if (ratio < best) {
                best = ratio;
                j = m;
            }
        }
    } else {
        // no direction space to speak of (the points nearly coincide): keep the spread-out ones
        for (Int m = 1; m < k; ++m)
            if (lam[m] > lam[j]) j = m;
    }
    return drop_point(P, Wt, lam, k, j);
}

// The work arrays of zc_from's loop in R^n, witnesses of ws entries, in one zeroed block: rows
// ((n + 10) x n: the simplex P, then the n-vectors, the normal at n + 2), witnesses
// ((n + 3) x ws), weights (n + 2), four n x n matrices, the subproblem's scratch; and the pivots.
// On the stack up to LOCAL entries (a grasp's wrench sets: ~500 in R^6), else on the heap.
struct LoopWork {
    static constexpr Int LOCAL = 1024, LOCAL_N = 16;
    static Int size(Int n, Int ws) {
        return (n + 10) * n + (n + 3) * ws + n + 2 + 4 * n * n + (2 * n + 5) * (n + 1) + n + 2;
    }
    LocalBlock<double, LOCAL> buf;
    LocalBlock<Int, LOCAL_N> pivot_buf;
    IVec pivots;
    Mat rows, witnesses, M, lu, B, D;
    Vec lam;
    Scratch sc;
    LoopWork(Int n, Int ws)
        : buf(size(n, ws), size(n, ws)), pivot_buf(n, n), pivots{pivot_buf.data, n} {
        const Vec w{buf.data, size(n, ws)};
        const Int a = (n + 10) * n;
        const Int b = a + (n + 3) * ws;
        const Int c = b + n + 2;
        const Int d = c + 4 * n * n;
        const Int e = d + (2 * n + 5) * (n + 1);
        rows = mat_view(w, 0, n + 10, n);
        witnesses = mat_view(w, a, n + 3, ws);
        lam = w.segment(b, n + 2);
        M = mat_view(w, c, n, n);
        lu = mat_view(w, c + n * n, n, n);
        B = mat_view(w, c + 2 * n * n, n, n);
        D = mat_view(w, c + 3 * n * n, n, n);
        sc = scratch_of(mat_view(w, d, 2 * n + 5, n + 1), w.segment(e, n + 2), n);
    }
    LoopWork(const LoopWork&) = delete;
    LoopWork& operator=(const LoopWork&) = delete;
};

// zc_from's loop for one dimension N (every loop over n in it and in the helpers it inlines then
// has a constant bound, which the compiler unrolls) or, for N = 0, any (n = r.n). Its state is
// local; it returns the result record, settling the Newton finish itself. Without fast-math:
// IDLE_STEPS's test `t + 1 / sigma == t` is exact rounding on purpose.
template <int N>
Shot zc_loop(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode,
             double t, Mat Pz, Mat Wz, Vec lz, Int kz, Int it, Int calls, Mat inverse,
             Mat directions, LoopWork& w) {
    const Int n = N > 0 ? N : r.n;
    const Mat rows = w.rows;
    const Mat P = rows.top(n + 2);
    const Vec nvec = rows.row(n + 2), v = rows.row(n + 3), point = rows.row(n + 4),
              ones = rows.row(n + 5), y = rows.row(n + 6), gam = rows.row(n + 7),
              alpha = rows.row(n + 8), b = rows.row(n + 9);
    const Mat Wt = w.witnesses.top(n + 2);
    const Vec wit = w.witnesses.row(n + 2);
    const Vec lam = w.lam;
    const Mat M = w.M, lu = w.lu, B = w.B, D = w.D;
    const IVec piv = w.pivots;
    const Scratch& sc = w.sc;
    const bool use_ie = mode == WITH_IE || mode == WITH_NEWTON || mode == WITH_SMOOTH_NEWTON;

    // the start: from the caller's simplex
    Int singular = 0;
    keep(Pz, Wz, lz, kz, P, Wt, lam);
    Int k;
    if (use_ie && kz == n)
        k = kz;   // a warm-start facet (warm.hpp): IE steps from it at once
    else
        k = kz > 0 ? restart(P, Wt, lam, kz, r, sc) : 0;
    for (Int i = 0; i < n; ++i) ones[i] = 1.0;
    Int age = -1;
    // the secant query needs every facet point's support direction (D's rows): known from the
    // caller's facet, kept by IE steps, lost to any other step
    bool secant =
        (mode == WITH_IE || mode == WITH_SMOOTH_NEWTON) && kz == n && directions.rows >= n;
    if (secant) {
        for (Int j = 0; j < n; ++j)
            for (Int i = 0; i < n; ++i) D(j, i) = directions(j, i);
    }
    Int rest = 0;        // plain IE steps before the next secant query
    double pace = INF;   // the last query's relative gap h_A(n) / (t n^T r) - 1
    Int last = -1;       // the facet row the last secant point went to (-1: none to judge)
    if (use_ie && kz == n && inverse.rows == n) {
        // the table's inverse of its facet: IE's first step factors nothing
        for (Int i = 0; i < n; ++i)
            for (Int j = 0; j < n; ++j) B(i, j) = inverse(i, j);
        matvec_t_ones(B, n, y);
        matvec(B, n, r, gam);
        age = 0;
    }
    // the row of P that the last IE step replaced since Pz last held the facet (-1: unknown)
    Int changed = -1;
    bool fresh_only = false;
    const bool smooth = mode == WITH_SMOOTH_NEWTON && smooth_finish_applies(ints, floats, n);
    // W_Linf's sum: every support point is a point of each contact's, no piece of one leaf; its
    // finish reads the contacts' states off the facet, and waits only for the gap
    const bool sum_set = smooth && ints[blocks(ints[0]).KIND] == SUM;
    Int sum_failures = 0;
    double newton_gap = mode != WITH_NEWTON && !smooth ? -1.0
                        : n <= NEWTON_CHEAP                ? NEWTON_GAP
                                                           : NEWTON_GAP_DEAR;
    Int idle = 0;   // ZC steps in a row that left b_k where it was
    // a Newton try owed: the gap of the IE step that asked for it (0: none). Its simplex is the
    // step's facet, kept in Pz[:n], and the step's support point, P[n]
    double pending = 0.0;
    Int stable = 0;   // IE steps in a row whose support point lies on a piece of their facet
    Int code = LIMIT;
    double t_up = INF;
    double h_n = 0.0;

    // the IE step's facet (Pz[:n]) and its support point (P[n]) as Newton's pieces; when
    // Newton does not finish the shot, the next try waits for the gap to shrink by NEWTON_RETRY
    auto newton_try = [&]() {
        for (Int i = 0; i < n; ++i) Pz(n, i) = P(n, i);
        for (Int i = 0; i < ws; ++i) Wz(n, i) = Wt(n, i);
        lz[n] = 0.0;
        NewtonOut fin =
            smooth ? smooth_finish(ints, floats, r, eps, Wz, lz, n + 1, nvec, t)
                   : newton_finish(ints, floats, r, eps, Pz, Wz, lz, n + 1, nvec, t, false);
        it += fin.steps;
        calls += fin.calls;
        if (!fin.ok) {
            // W_Linf's sum: a try that failed twice is a load whose states the facets do not
            // tell (a long tail of tries on a humanoid's feet); IE finishes alone, as it does
            // after a smooth try that took no step
            const bool last = sum_set ? ++sum_failures >= SUM_TRIES : smooth && fin.steps == 0;
            newton_gap = last ? -1.0 : pending * NEWTON_RETRY;
            pending = 0.0;
        }
        return fin;
    };

    while (it < max_iter) {
        if (pending > 0.0) {
            // the last IE step asked for the Newton finish; when it fails, the loop goes on
            // (its test first: the try's steps count as iterations)
            NewtonOut fin = newton_try();
            if (fin.ok)
                return make_result(HIT, fin.t, fin.t_up, fin.h, it, calls, fin.normal.vec(),
                                   fin.V.mat(), fin.weights.vec(), fin.W.mat(), fin.m, singular);
            continue;
        }
        if (use_ie && k == n) {
            // IE step on the facet CH(V), columns a_l: hyperplane y^T x = 1, r = sum gam_l a_l.
            // y and gam come from B, the facet's inverse, refactored every REFACTOR steps and
            // updated in between by the revised simplex method's pivot rule (O(n^2) a step).
            bool ok;
            if (fresh_only) {
                // LU solves only, no inverse: y, gam here, alpha below
                ok = solve_facet(P, n, r, M, lu, piv, ones, y, gam);
            } else if (age < 0 || age >= REFACTOR) {
                ok = invert_facet(P, n, M, piv, B);
                age = 0;
                if (ok) {
                    matvec_t_ones(B, n, y);
                    matvec(B, n, r, gam);
                }
            } else {
                ok = true;   // y and gam came with the last pivot
            }
            double yr = 0.0;
            if (ok) {
                yr = dot(y, r);
                ok = yr > 0.0 && smallest(gam, n) >= -1e-12 * yr;
            }
            if (!ok && age > 0) {
                age = -1;   // perhaps only drift in the updated inverse: refactor first
                continue;
            }
            if (!ok) {
                // rounding broke the facet: return to the last simplex known to hold b_k
                keep(Pz, Wz, lz, kz, P, Wt, lam);
                k = restart(P, Wt, lam, kz, r, sc);
            } else if (smallest(gam, n) <= 1e-12 * yr) {
                // the ray crosses a lower-dimensional face of the facet: keep that face and
                // continue with ZC-based iterations (section 3.4.2), from the convex
                // combination of its points (certified_t: not 1 / y^T r)
                double gsum = 0.0;
                for (Int j = 0; j < n; ++j) gsum += std::max(gam[j], 0.0);
                t = 1.0 / gsum;
                for (Int j = 0; j < n; ++j) lam[j] = std::max(gam[j], 0.0) * t;
                kz = keep(P, Wt, lam, n, Pz, Wz, lz);
                Int j = n - 1;
                while (j >= 0) {
                    if (lam[j] <= 1e-12) k = drop_point(P, Wt, lam, k, j);
                    j -= 1;
                }
                k = restart(P, Wt, lam, k, r, sc);
                singular += 1;
            } else {
                t = 1.0 / yr;
                const double ny = std::sqrt(dot(y, y));
                // one division, not n: the direction needs to be y's only to rounding
                const double iny = 1.0 / ny;
                bool query_secant = false;
                if (secant) {
                    // the last secant point, judged by its weight in this facet's t r
                    if (last >= 0 && gam[last] * t < SECANT_HOLD) rest = SECANT_REST;
                    last = -1;
                    if (rest > 0)
                        rest -= 1;
                    else
                        query_secant = true;
                }
                double h = 0.0;
                bool closed = false;
                if (query_secant) {
                    // the secant query (docs/core-api.md): the support map's linear model
                    // through the facet, s(d_j) = P_j, puts s(sum_j gam_j d_j) at t r
                    for (Int i = 0; i < n; ++i) v[i] = 0.0;
                    for (Int j = 0; j < n; ++j)
                        for (Int i = 0; i < n; ++i) v[i] += gam[j] * D(j, i);
                    const double nv = std::sqrt(dot(v, v));
                    if (nv > 0.0) {
                        for (Int i = 0; i < n; ++i) nvec[i] = v[i] / nv;
                        h = support(ints, floats, nvec, point, wit);
                        calls += 1;
                        const double nr = dot(nvec, r);
                        closed = nr > 0.0 && h - t * nr <= eps * (t * nr);
                        const double secant_gap = nr > 0.0 ? h / (t * nr) - 1.0 : INF;
                        if (secant_gap > SECANT_GAIN * pace) rest = SECANT_REST;
                        pace = secant_gap;
                    }
                    if (!closed && !(nv > 0.0 && dot(y, point) - 1.0 > eps)) {
                        // neither a bound nor new ground (a flat piece: the model's point is a
                        // vertex): IE's query after all
                        rest = SECANT_REST;
                        query_secant = false;
                    }
                }
                if (!query_secant) {
                    // h_A is positively homogeneous (eq. 2): y itself is queried, so that the
                    // support call waits for no square root and division (IE's gap
                    // h_A(y/|y|) |y| - 1 is h_A(y) - 1); the unit normal is made alongside
                    h = support(ints, floats, y, point, wit);
                    calls += 1;
                    closed = h - 1.0 <= eps;
                    pace = h - 1.0;
                    h *= iny;
                    for (Int i = 0; i < n; ++i) nvec[i] = y[i] * iny;
                }
                it += 1;
                // the certified point tz r whose weights lam holds: the simplex kept, the bracket
                // from h_A at the normal
                auto hit = [&](double tz, double nr) {
                    kz = keep(P, Wt, lam, n, Pz, Wz, lz);
                    code = HIT;
                    t = tz;
                    t_up = h / nr;
                    h_n = h;
                };
                if (closed && fresh_only) {
                    // the fresh LU's weights, as a convex combination (certified_t)
                    const double nr = dot(nvec, r);
                    const double tz = certified_t(gam, n, h, nr, eps);
                    if (tz > 0.0) {
                        for (Int j = 0; j < n; ++j) lam[j] = gam[j] * tz;
                        hit(tz, nr);
                        break;
                    }
                    // not a certified point of A: the step goes on
                } else if (closed) {
                    // certify: the normal and h_A(n) already evaluated bound t from above
                    // whatever n is; from below, t r must be the convex combination
                    // gam / sum(gam) of the facet's points, checked by its residual (the updated
                    // inverse's drift shows there). Failing that, LU solves on a fresh
                    // factorization.
                    const double nr = dot(nvec, r);
                    for (Int refine = 0; refine < 2; ++refine) {
                        if (refine == 1) {
                            // one step of iterative refinement with the updated inverse:
                            // gam += B (r - sum_j gam_j P_j), ~3 n^2 flops where the LU below
                            // costs ~n^3 / 3 + 4 n^2 (taken on 66% of W_Linf's lift's shots on
                            // the ingot, 24% of W_L1's)
                            for (Int i = 0; i < n; ++i) {
                                double e = r[i];
                                for (Int j = 0; j < n; ++j) e -= gam[j] * P(j, i);
                                alpha[i] = e;
                            }
                            matvec(B, n, alpha, v);
                            for (Int j = 0; j < n; ++j) gam[j] += v[j];
                        }
                        const double tz = certified_t(gam, n, h, nr, eps);
                        if (tz == 0.0) break;
                        for (Int j = 0; j < n; ++j) lam[j] = gam[j] * tz;
                        if (holds(P, lam, n, tz, r, b, FACET_HOLDS)) {
                            hit(tz, nr);
                            break;
                        }
                    }
                    if (code == HIT) break;
                    ok = solve_facet(P, n, r, M, lu, piv, ones, y, gam);
                    const double tz = ok ? certified_t(gam, n, h, nr, eps) : 0.0;
                    if (tz > 0.0) {
                        for (Int j = 0; j < n; ++j) lam[j] = gam[j] * tz;
                        hit(tz, nr);
                        break;
                    }
                    // the updated inverse's drift matters at this eps: from here on, LU solves
                    // at every step (the floor of docs/core-api.md, "Numerical floor")
                    fresh_only = true;
                    continue;
                }
                for (Int j = 0; j < n; ++j) lam[j] = gam[j] * t;
                const double gap = h * ny - 1.0;
                kz = keep(P, Wt, lam, n, Pz, Wz, lz, changed);
                if (newton_gap > 0.0 && n > NEWTON_CHEAP && !sum_set)
                    stable = (smooth ? on_facet_leaf(ints, Wt, n, wit)
                                     : on_facet_piece(ints, Wt, n, wit))
                                 ? stable + 1
                                 : 0;
                if (gap <= newton_gap &&
                    (n <= NEWTON_CHEAP || sum_set || stable >= NEWTON_STABLE * n)) {
                    // IE's cutting planes have found the exit face's pieces: Newton on them
                    // (newton.hpp), with the new support point as a candidate piece, tried when
                    // this step is done: its simplex, Pz[:n] and P[n], stays as it is until then
                    set_row(P, Wt, n, point, wit);
                    pending = gap;
                }
                // ratio test: the new facet the ray crosses replaces the vertex j*
                if (fresh_only)
                    lu_solve(lu, piv, n, point, alpha);
                else
                    matvec(B, n, point, alpha);
                // the least gam_j / alpha_j over alpha_j > 0, compared as products: no division
                Int js = -1;
                double amax = 0.0;
                for (Int j = 0; j < n; ++j) {
                    amax = std::max(amax, std::abs(alpha[j]));
                    if (alpha[j] > 0.0 && (js < 0 || gam[j] * alpha[js] < gam[js] * alpha[j]))
                        js = j;
                }
                js = std::max(js, Int(0));
                if (same_point(P, js, point)) {
                    // s is the vertex it would replace: the step cannot move, and the gap was
                    // the updated inverse's drift (a vertex lies on its facet). Fresh factors,
                    // then LU solves; s a vertex even then is rounding at this eps: the bracket
                    // stands (before, the step repeated itself until max_iter: a full-magnitude
                    // lift at eps = 3e-12)
                    if (fresh_only) {
                        code = LIMIT;
                        // the queried normal's bound (the secant direction's, when that was
                        // queried: not y's)
                        t_up = h / dot(nvec, r);
                        h_n = h;
                        break;
                    }
                    if (age > 0)
                        age = -1;
                    else
                        fresh_only = true;
                    continue;
                }
                set_row(P, Wt, js, point, wit);
                changed = js;
                if (secant) {
                    for (Int i = 0; i < n; ++i) D(js, i) = nvec[i];
                    if (query_secant) last = js;
                }
                if (!fresh_only && alpha[js] > 1e-8 * amax) {
                    pivot(B, n, alpha, js, y, gam);
                    age += 1;
                } else {
                    age = -1;
                }
                continue;
            }
        }
        age = -1;
        changed = -1;
        secant = false;
        stable = 0;
        DistOut z = zc_step(ints, floats, r, t, P, Wt, lam, k, eps, max_iter, nvec, v, point,
                            wit, b, sc);
        Int st = z.status;
        k = z.k;
        double h = z.h;
        calls += z.calls;
        if (st == STALLED && t > 0.0) {
            // rounding in the warm-started generators: start ZC afresh from b_k once
            z = zc_step(ints, floats, r, t, P, Wt, lam, 0, eps, max_iter, nvec, v, point, wit, b,
                        sc);
            st = z.status;
            k = z.k;
            h = z.h;
            calls += z.calls;
        }
        it += 1;
        if (st == INSIDE) {
            double sigma = 0.0;
            for (Int j = 0; j < k; ++j) sigma += lam[j];
            idle = t + 1.0 / sigma == t ? idle + 1 : 0;
            if (idle == IDLE_STEPS) break;
            t += 1.0 / sigma;
            for (Int j = 0; j < k; ++j) lam[j] /= sigma;
            kz = keep(P, Wt, lam, k, Pz, Wz, lz);
            if (mode == UNTIL_FACET && k == n) {
                code = FACET;
                singular = 0;
                break;
            }
            if (!(use_ie && k == n)) k = restart(P, Wt, lam, k, r, sc);
            continue;
        }
        if (st == MAX_ITER) break;
        if (t == 0.0) {
            // CONVERGED here means h_A(n) <= 0 < n^T r: a certified miss. STALLED means r lies
            // on the boundary of CO(A) to the cone's rounding: a miss while h_A(n) is rounding
            // (the ray at most grazes A), else no more than the bracket [0, h_A(n) / n^T r]
            kz = 0;
            singular = 0;
            const OriginVerdict o =
                origin_verdict(ints, floats, r, st, h, P, k, nvec, v, alpha, point, wit, sc);
            calls += o.calls;
            code = o.code;
            t_up = o.t_up;
            h_n = o.h;
            break;
        }
        // converged (or stalled): z = b_k, supported by H(n, s_A(n)). A stall certifies nothing
        // by itself: ZC's cone from b_k also loses rank far from z_A(r), on rays near the
        // boundary of a set whose origin is on its boundary (two contacts' wrench set, which is
        // never force-closure: gaps up to 2% were reported as hits). Nor does b_k always lie in
        // A: on a ray along the boundary of CO(A), ZC's INSIDE rule for a cone that lost
        // orthogonality accepts weights that reproduce b_k only to ~1e-8 (two point contacts,
        // wrenches on the edge of what they resist: answers 5e-8 below the true minimum were
        // reported optimal). Newton on the simplex's pieces then finishes the shot exactly
        // where it can (the two-point-contact case); else the bracket stands, with the status
        // of an unfinished shot. Newton's plain steps first: its corner steps (complete
        // pivoting, the shortest normal) lose some two-point-contact cases the plain ones
        // finish.
        h_n = h + t * dot(nvec, r);
        t_up = h_n / dot(nvec, r);
        if ((st == CONVERGED || t_up - t <= std::max(eps, STALL_FLOOR) * t) &&
            holds(Pz, lz, kz, t, r, b, point_holds(eps)))
            code = HIT;
        else
            code = NEWTON_END;
        break;
    }
    if (pending > 0.0) {
        // the loop ended (max_iter, or the bracket stood on a vertex) right after the IE step
        // that asked for the Newton finish: it is tried all the same
        NewtonOut fin = newton_try();
        if (fin.ok)
            return make_result(HIT, fin.t, fin.t_up, fin.h, it, calls, fin.normal.vec(),
                               fin.V.mat(), fin.weights.vec(), fin.W.mat(), fin.m, singular);
    }
    if (code == NEWTON_END) {
        for (Int c = 0; c < 2; ++c) {
            const bool corner = c == 1;   // the plain steps first, then the corner steps
            NewtonOut fin = newton_finish(ints, floats, r, eps, Pz, Wz, lz, kz, nvec, t, corner);
            it += fin.steps;
            calls += fin.calls;
            if (fin.ok)
                return make_result(HIT, fin.t, fin.t_up, fin.h, it, calls, fin.normal.vec(),
                                   fin.V.mat(), fin.weights.vec(), fin.W.mat(), fin.m, singular);
        }
        // t r need not be in A here: an estimate, never above the certified bound
        return make_result(LIMIT, std::min(t, t_up), t_up, h_n, it, calls, nvec, Pz, lz, Wz, kz,
                           singular);
    }
    return make_result(code, t, t_up, h_n, it, calls, nvec, Pz, lz, Wz, kz, singular);
}

}  // namespace zc_family_detail

// ZC-based iterations from b = t r in A, the convex combination lz of Pz[:kz] (t = 0, kz = 0:
// from the origin, which first decides whether the ray meets A; kz = n with WITH_IE: a facet
// the ray crosses, where IE steps start). mode: ZC_ONLY (section 3.3), WITH_IE (ZC-IE, section
// 3.4.2: plain IE steps while V_k is a facet), WITH_NEWTON (ZC-IE with the Newton finish),
// WITH_SMOOTH_NEWTON (ZC-IE with the Newton finish's smooth path, on the sets it takes) or
// UNTIL_FACET (return FACET with V_k as soon as it is a facet: IE's initialization). inverse:
// [Pz_0 .. Pz_{n-1}]^{-1} when it is known (a start table's facet, start_table.hpp), else 0
// rows. directions: with WITH_IE and kz = n, the unit directions whose support points Pz[:kz]
// are (warm.hpp's probes), which turn on the secant query (docs/core-api.md), else 0 rows.
// Pz, Wz, lz have n + 2 rows. Runs the loop compiled for r's dimension (3, 5, 6, 9, else any).
Shot zc_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode,
             double t, Mat Pz, Mat Wz, Vec lz, Int kz, Int it, Int calls, Mat inverse,
             Mat directions) {
    using namespace zc_family_detail;
    const Int n = r.n;
    LoopWork w(n, ws);
    if (n == 6)
        return zc_loop<6>(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it,
                          calls, inverse, directions, w);
    if (n == 3)
        return zc_loop<3>(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it,
                          calls, inverse, directions, w);
    if (n == 9)
        return zc_loop<9>(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it,
                          calls, inverse, directions, w);
    if (n == 5)
        return zc_loop<5>(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it,
                          calls, inverse, directions, w);
    return zc_loop<0>(ints, floats, r, ws, eps, max_iter, mode, t, Pz, Wz, lz, kz, it, calls,
                      inverse, directions, w);
}

// Section 3.3 (ZC-based) and, with mode WITH_IE, section 3.4.2 (ZC-IE): ZC-based iterations,
// and plain IE steps whenever V_k has n points (a facet the ray crosses inside); with mode
// WITH_NEWTON or WITH_SMOOTH_NEWTON, ZC-IE with the Newton finish or its smooth path (newton.hpp).
Shot zc_from_simplex(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode,
                     double t, Mat V, Mat W, Vec lam, Int k, Int it, Int calls) {
    const Int n = r.n;
    Array Pz(n + 2, n), Wz(n + 2, ws), lz(n + 2);
    Mat P = Pz.mat(), Pw = Wz.mat();
    for (Int j = 0; j < k; ++j) {
        for (Int i = 0; i < n; ++i) P(j, i) = V(j, i);
        for (Int i = 0; i < ws; ++i) Pw(j, i) = W(j, i);
        lz.data[j] = lam[j];
    }
    return zc_from(ints, floats, r, ws, eps, max_iter, mode, t, P, Pw, lz.vec(), k, it, calls,
                   Mat{}, Mat{});
}

// IE's initialization, shared with ZC-IE: ZC-based iterations from the origin until V_k is a
// facet crossed by the ray in its interior (status FACET, the facet in V), or the shot's end (a
// flat set never has one: ZC-based then finishes the job)
Shot first_facet(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter) {
    const Int n = r.n;
    Array Pz(n + 2, n), Wz(n + 2, ws), lz(n + 2);
    return zc_from(ints, floats, r, ws, eps, max_iter, UNTIL_FACET, 0.0, Pz.mat(), Wz.mat(),
                   lz.vec(), 0, 0, 0, Mat{}, Mat{});
}

Shot zc_family(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode) {
    const Int n = r.n;
    // Pz (n + 2, n), Wz (n + 2, ws), lz (n + 2)
    Array z((n + 2) * (n + ws + 1));
    const Vec zv = z.vec();
    return zc_from(ints, floats, r, ws, eps, max_iter, mode, 0.0, mat_view(zv, 0, n + 2, n),
                   mat_view(zv, (n + 2) * n, n + 2, ws), zv.segment((n + 2) * (n + ws), n + 2),
                   0, 0, 0, Mat{}, Mat{});
}

}  // namespace gf
