#pragma once

#include "api.hpp"
#include "shooting/pair_exit.hpp"

// A start table for many rays shot at one set: the facets of an inner polytope.
//
// ZC-IE (section 3.4.2) begins with ZC from the origin, which spends about n + 1 support calls
// and as many active-set projections to find a first facet that the ray crosses. When many rays
// are shot at one set, that search is done once for all (in Python, with Qhull): the support
// points P_0 of A in the 2n directions +-q_j span an inner polytope CH(P_0) in A. With the origin
// strictly inside it, its facets y_f^T x = 1 cover every direction, and the ray R(r) leaves
// CH(P_0) through the facet of largest y_f^T r at t_0 r with 1 / t_0 = y_f^T r = sum_j gam_j,
// r = sum_j gam_j a_j over the facet's vertices a_j. That facet is IE's start: a facet of points
// of A that the ray crosses. With the origin outside, the table holds the facets that rays
// crossing CH(P_0) leave through, and the same lookup finds the exit of such a ray.
//
// Nothing of the table is trusted beyond that: t_0 r is a convex combination of support points
// of A, so t_0 <= t* whichever facet the lookup picked; IE's steps and stopping rule are
// unchanged. The table keeps a copy of the set's parameters and is ignored when they changed,
// and when no facet of the table holds the ray (some gam_j < 0): ZC then starts from the origin.
// A facet of CH(P_0) with more than n points is split into simplices that share its hyperplane;
// the lookup takes the one of them that holds the ray.

namespace gf::start_table_detail {

constexpr Int HEADER = 5;        // [facets F, n, witness size, parameters, points]
constexpr double TIE_TOL = 1e-6; // facets whose y_f^T r is within this of the largest: one facet
                                 // of CH(P_0) with more than n points, triangulated

// lam = B_f r, the weights of r on facet f's vertices, and their sum; 0.0 when one is negative
// (the ray does not cross that simplex).
[[gnu::always_inline]] inline double weights(Vec table, Int b0, Int f, Vec r, Vec lam) {
    const Int n = r.n;
    double total = 0.0;
    for (Int j = 0; j < n; ++j) {
        double s = 0.0;
        for (Int a = 0; a < n; ++a) s += table[b0 + (f * n + j) * n + a] * r[a];
        if (s < 0.0) return 0.0;
        lam[j] = s;
        total += s;
    }
    return total;
}

// t_0 > 0 with the facet of the table's CH(P_0) that R(r) leaves through in P[:n], Wt[:n], its
// weights lam[:n] (t_0 r = sum lam_j P_j), its hyperplane y^T x = 1 in y and the inverse of
// [P_0 .. P_{n-1}] in B; 0.0 when the table does not apply. scores: work of F entries.
//
// table = [F, n, ws, npar, npts, the set's parameters (npar), y_f by coordinate (n, F), B_f
// (F, n, n), vertex indices (F, n), points (npts, n), witnesses (npts, ws)].
inline double table_start(Vec table, Vec floats, Vec r, Mat P, Mat Wt, Vec lam, Vec y, Mat B,
                          Vec scores) {
    const Int n = r.n;
    if (table.n == 0 || static_cast<Int>(table[1]) != n) return 0.0;
    const Int F = static_cast<Int>(table[0]);
    const Int ws = static_cast<Int>(table[2]);
    const Int npar = static_cast<Int>(table[3]);
    for (Int i = 0; i < npar; ++i)
        if (floats[i] != table[HEADER + i]) return 0.0;
    const Int y0 = HEADER + npar;
    const Int b0 = y0 + F * n;
    const Int i0 = b0 + F * n * n;
    const Int p0 = i0 + F * n;
    const Int w0 = p0 + static_cast<Int>(table[4]) * n;
    // y_f^T r of all facets a coordinate at a time: the inner loop runs along F and vectorizes
    // (ingot, F = 87: 0.29 -> 0.12 us a lookup), skipping the coordinates where r is 0
    // (W_Linf's lift: the first m - 1). Yt[a, g] = table[y0 + a * F + g].
    const double* Yt = table.d + y0;
    for (Int g = 0; g < F; ++g) scores[g] = 0.0;
    for (Int a = 0; a < n; ++a) {
        const double ra = r[a];
        if (ra == 0.0) continue;
        for (Int g = 0; g < F; ++g) scores[g] += Yt[a * F + g] * ra;
    }
    double best = 0.0;
    Int f = -1;
    for (Int g = 0; g < F; ++g) {
        if (scores[g] > best) {
            best = scores[g];
            f = g;
        }
    }
    if (f < 0) return 0.0;
    double total = weights(table, b0, f, r, lam);
    if (total == 0.0) {
        // the ray's exit facet of CH(P_0) has more than n points, split into simplices that tie
        // in y_f^T r: the one that holds the exit point has lam >= 0
        for (Int g = 0; g < F; ++g) {
            if (g != f && scores[g] >= (1.0 - TIE_TOL) * best) {
                total = weights(table, b0, g, r, lam);
                if (total > 0.0) {
                    f = g;
                    break;
                }
            }
        }
        if (total == 0.0) return 0.0;
    }
    const double t = 1.0 / total;
    for (Int a = 0; a < n; ++a) {
        y[a] = Yt[a * F + f];
        for (Int j = 0; j < n; ++j) B(a, j) = table[b0 + (f * n + a) * n + j];
    }
    for (Int j = 0; j < n; ++j) {
        lam[j] *= t;
        const Int v = static_cast<Int>(table[i0 + f * n + j]);
        for (Int a = 0; a < n; ++a) P(j, a) = table[p0 + v * n + a];
        for (Int a = 0; a < ws; ++a) Wt(j, a) = table[w0 + v * ws + a];
    }
    return t;
}

}  // namespace gf::start_table_detail

namespace gf {

// `shoot` (dispatch.hpp), with IE's and ZC-IE's steps started on the table's facet when the
// table applies, and Bi-GJK's bisection between that facet's point and the bound of its normal;
// the table's own support calls are not counted.
Shot shoot_with_table(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps,
                      Int max_iter, Vec table) {
    if ((method == ZC_IE || method == ZC_IE_NEWTON || method == ZC_IE_PAPER || method == BI_GJK ||
         method == IE) &&
        table.n > 0) {
        const Int n = r.n;
        // P (n + 2, n), B (n, n), y (n), Wt (n + 2, ws), lam (n + 2), zeroed; and the scores
        // (F, which table_start zeroes itself: a lift's table has ~700 facets): one block, on
        // the stack where it fits (a grasp's sets in R^6: ~250 entries)
        const Int F = static_cast<Int>(table[0]);
        const Int zeroed = (2 * n + 3) * n + (n + 2) * ws + n + 2;
        LocalBlock<double, 1024> work(zeroed + F, zeroed);
        const Vec block{work.data, zeroed + F};
        const Mat rows = mat_view(block, 0, 2 * n + 3, n);
        Mat P = rows.rows_range(0, n + 2);
        Mat B = rows.rows_range(n + 2, 2 * n + 2);
        Vec y = rows.row(2 * n + 2);
        Mat Wt = mat_view(block, (2 * n + 3) * n, n + 2, ws);
        Vec lam = block.segment((2 * n + 3) * n + (n + 2) * ws, n + 2);
        const double t = start_table_detail::table_start(table, floats, r, P, Wt, lam, y, B,
                                                         block.segment(zeroed, F));
        if (t > 0.0) {
            Shot out;
            if (method == BI_GJK) {
                out = bi_gjk_from(ints, floats, r, ws, eps, max_iter, t, P, Wt, lam, n, y, 0);
            } else if (method == IE) {
                out = ie_from(ints, floats, r, ws, eps, max_iter, P, Wt, 0, 0);
            } else {
                if (method == ZC_IE && n == 6 && pair_applies(ints, floats)) {
                    // two soft fingers: the exit in closed form from the table's point
                    // (pair_exit.hpp)
                    Shot pair = pair_exit(ints, floats, r, ws, eps, 1.0 / t);
                    if (pair.status == HIT) return pair;
                }
                const Int mode = method == ZC_IE       ? WITH_SMOOTH_NEWTON
                                 : method == ZC_IE_NEWTON ? WITH_NEWTON
                                                          : WITH_IE;
                out = zc_from(ints, floats, r, ws, eps, max_iter, mode, t, P, Wt, lam, n, 0, 0, B,
                              B.top(0));
            }
            return unstall(ints, floats, r, ws, eps, max_iter, certify(std::move(out), r, eps));
        }
    }
    return shoot(ints, floats, r, ws, method, eps, max_iter);
}

}  // namespace gf
