#pragma once

#include "api.hpp"
#include "shooting/packed.hpp"

// ZC-IE warm-started from a previous answer's normal (time coherence, the paper's future work).
//
// When a query follows a similar one (an object pair that moved a little), the new z_A(r) lies
// near the old supporting hyperplane's touching point. Instead of ZC's search from the origin,
// take n support points in directions spread around the previous normal; if the ray crosses
// their facet (positive conic coordinates), IE steps start right there, with the probes'
// directions for IE's secant query. If it misses, the same secant model says where the normal
// at z_A(r) is: the next probes are centred there.

namespace gf {

namespace warm {

// probe rounds before the cold start; a round that misses the ray recentres the next one (same
// spread) where the secant model through its probes puts the normal at z_A(r), or, when the
// model gives no centre, widens it by 4. Recentring against widening alone, zc-ie growth
// support calls: protocol mean 21.9 -> 21.7, median 21 -> 20; random pairs' mean 21.6 -> 21.5.
// Without the secant query's gain rule the secant query stalled on recentred facets of the
// warm-start benchmark's moving pair (61 support calls against 33); with it, they take 31.3
// against 31.7
constexpr Int WIDENINGS = 3;

}  // namespace warm

namespace warm_detail {

// `warm_shot`'s stop when the ray misses every round of probes
constexpr Int PROBES_MISSED = -1;

// Entries of the probes' arrays (`ProbeArrays`).
inline Int probe_size(Int n, Int ws) {
    return (2 * n + 8) * n + (n + 3) * ws + n + 2 + 2 * n * n;
}

// `probe_facet`'s arrays, in one allocation: rows (the facet P, the n-vectors, the probes'
// directions), witnesses, weights, two n x n matrices; and the pivots
struct ProbeArrays {
    Array work;
    IArray piv;
    Mat rows;       // (2n + 8, n)
    Mat witnesses;  // (n + 3, ws)
    Vec lam;        // (n + 2)
    Mat M;          // (n, n)
    Mat lu;         // (n, n)
    IVec pivots;    // (n)
    ProbeArrays(Int n, Int ws) : work(probe_size(n, ws)), piv(n) {
        const Vec w = work.vec();
        const Int a = 0;
        const Int b = a + (2 * n + 8) * n;
        const Int c = b + (n + 3) * ws;
        const Int d = c + n + 2;
        rows = mat_view(w, a, 2 * n + 8, n);
        witnesses = mat_view(w, b, n + 3, ws);
        lam = w.segment(c, n + 2);
        M = mat_view(w, d, n, n);
        lu = mat_view(w, d + n * n, n, n);
        pivots = piv.vec();
    }
    ProbeArrays(const ProbeArrays&) = delete;
    ProbeArrays& operator=(const ProbeArrays&) = delete;
};

// (t, support calls) of `shoot_warm`'s probe rounds: t > 0 when the ray crosses the facet of the
// probes P = rows[:n] (witnesses[:n], unit directions rows[n + 8:]) at t r = lam @ P, else 0.
inline std::pair<double, Int> probe_facet(IVec ints, Vec floats, Vec r, Int ws, Vec normal,
                                          double spread, ProbeArrays& pa) {
    const Int n = r.n;
    const Mat rows = pa.rows;
    const Mat P = rows.top(n + 2);
    const Vec v = rows.row(n + 2), d = rows.row(n + 3), w = rows.row(n + 4),
              point = rows.row(n + 5), gam = rows.row(n + 6), centre = rows.row(n + 7);
    // the probes' unit directions: with them, IE's steps may take the secant query
    const Mat directions = rows.rows_from(n + 8);
    const Mat Wt = pa.witnesses.top(n + 2);
    const Vec wit = pa.witnesses.row(n + 2);
    const Vec lam = pa.lam;
    const Mat M = pa.M, lu = pa.lu;
    const IVec piv = pa.pivots;
    for (Int a = 0; a < n; ++a) centre[a] = normal[a];
    Int calls = 0;
    for (Int attempt = 0; attempt < warm::WIDENINGS; ++attempt) {
        // Householder reflection taking (1, ..., 1)/sqrt(n) to the centre: it maps the simplex
        // e_j - 1/n, orthogonal to (1, ..., 1), into the centre's orthogonal plane
        double vv = 0.0;
        for (Int a = 0; a < n; ++a) {
            v[a] = 1.0 / std::sqrt(static_cast<double>(n)) - centre[a];
            vv += v[a] * v[a];
        }
        for (Int j = 0; j < n; ++j) {
            for (Int a = 0; a < n; ++a)
                w[a] = (a == j ? 1.0 : 0.0) - 1.0 / static_cast<double>(n);
            if (vv > 1e-30) {
                double vw = 0.0;
                for (Int a = 0; a < n; ++a) vw += v[a] * w[a];
                for (Int a = 0; a < n; ++a) w[a] -= 2.0 * vw / vv * v[a];
            }
            double dd = 0.0;
            for (Int a = 0; a < n; ++a) {
                d[a] = centre[a] + spread * w[a];
                dd += d[a] * d[a];
            }
            support(ints, floats, d, point, wit);
            const double dn = 1.0 / std::sqrt(dd);
            for (Int a = 0; a < n; ++a) {
                P(j, a) = point[a];
                directions(j, a) = d[a] * dn;
            }
            for (Int a = 0; a < ws; ++a) Wt(j, a) = wit[a];
        }
        calls += n;
        // conic coordinates of r in the n points: r = sum gam_j P[j]
        for (Int i = 0; i < n; ++i)
            for (Int j = 0; j < n; ++j) M(i, j) = P(j, i);
        if (lu_factor(M, n, lu, piv)) {
            lu_solve(lu, piv, n, r, gam);
            double gs = 0.0;
            for (Int j = 0; j < n; ++j) gs += gam[j];
            if (smallest(gam, n) > 0.0) {
                const double t = 1.0 / gs;
                for (Int j = 0; j < n; ++j) lam[j] = gam[j] * t;
                return {t, calls};
            }
            // the ray misses the facet. The secant model through the probes (IE's secant
            // query) extrapolates to the normal at z_A(r): sum_j gam_j d_j / sum_j gam_j. The
            // next probes are centred there
            double cr = 0.0;
            for (Int a = 0; a < n; ++a) {
                double s = 0.0;
                for (Int j = 0; j < n; ++j) s += gam[j] * directions(j, a);
                w[a] = s;
                cr += s * r[a];
            }
            // gs > 0: r is beyond the probes' hyperplane, the model's weights are affine ones
            if (gs > 0.0 && cr > 0.0) {
                const double cn = 1.0 / std::sqrt(dot(w, w));
                for (Int a = 0; a < n; ++a) centre[a] = w[a] * cn;
                continue;
            }
        }
        // a wider spread when that fails too: the pose moved more than expected
        spread *= 4.0;
    }
    return {0.0, calls};
}

// shoot_warm's probes and ZC-IE. A finished shot is packed and its head returned; else the
// head's status is PROBES_MISSED, with the probes' support calls.
inline Head warm_shot(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter,
                      Vec normal, double spread, Vec packed, Int e) {
    const Int n = r.n;
    ProbeArrays pa(n, ws);
    const auto [t, calls] = probe_facet(ints, floats, r, ws, normal, spread, pa);
    if (t <= 0.0) return {PROBES_MISSED, 0.0, 0.0, 0.0, 0, calls, 0, 0};
    // ZC-IE's steps from the probes' facet, with their unit directions for IE's secant query;
    // no facet inverse to hand over
    return pack(certify(zc_from(ints, floats, r, ws, eps, max_iter, WITH_IE, t,
                                pa.rows.top(n + 2), pa.witnesses.top(n + 2), pa.lam, n, 0, calls,
                                Mat{}, pa.rows.rows_from(n + 8)),
                        r, eps),
                packed, e);
}

}  // namespace warm_detail

// ZC-IE (section 3.4.2) from the facet of the support points in the directions
// normal + spread w_j (`normal` a unit vector), w_j the vertices of a regular simplex in the
// plane orthogonal to `normal`; while the ray misses that facet, the next probes are centred at
// the secant model's normal sum_j gam_j d_j / sum_j gam_j (r = sum_j gam_j P_j), or widened when
// that points away from r; after WIDENINGS rounds, cold ZC-IE. Writes the shot's arrays to
// packed[e:] and returns its head (status, t, t_upper, h_n, iterations, support_calls,
// singular_steps, k).
Head shoot_warm(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Vec normal,
                double spread, Vec packed, Int e) {
    using namespace warm_detail;
    const Head head = warm_shot(ints, floats, r, ws, eps, max_iter, normal, spread, packed, e);
    if (head.status >= 0) return head;
    // PROBES_MISSED: cold ZC-IE, the probes' support calls counted
    const Int calls = head.calls;
    Head out = pack(certify(zc_family(ints, floats, r, ws, eps, max_iter, WITH_IE), r, eps),
                    packed, e);
    out.calls += calls;
    return out;
}

}  // namespace gf
