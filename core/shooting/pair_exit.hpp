#pragma once

#include <cmath>

#include "api.hpp"
#include "linalg.hpp"
#include "shooting/shot.hpp"

// The exit of a ray from W_L1 of two soft fingers, in closed form.
//
// W = CH(E_1 U E_2), E_i = {c_i + S_i x : ||x|| <= 1} (6, 3): eq. 13's set for two soft fingers.
// t* = 1 / sigma* with sigma* = min alpha_1 + alpha_2 over
//
//     alpha_1 c_1 + S_1 a + alpha_2 c_2 + S_2 b = r,   ||a|| <= alpha_1,   ||b|| <= alpha_2,
//
// (the contacts' normal forces and friction shares: t* r = sum_i (alpha_i / sigma*) z_i with
// z_i = c_i + S_i x_i, x_1 = a / alpha_1, x_2 = b / alpha_2). The equations leave a plane of
// solutions y = y0 + Z p (8 unknowns, 6 equations), on which each cone constraint is a conic
// region R_i and sigma is linear: a 2-D problem. On the level line sigma = v the points of R_i
// form an interval, found from a quadratic; sigma* is the least v at which the two intervals
// meet. Either one region alone reaches it (its interval shrinks to a point inside the other's:
// that finger's friction saturated, the other's not, a flat piece that IE and the smooth Newton
// path resolve slowly), found from a quadratic in v, or both do (both saturated), found by the
// Illinois method on the gap between the intervals.
//
// Nothing of it is trusted: the points z_i are points of W, and t r their convex combination
// to rounding (`certify`); the normal u of the face comes from the cones' complementarity
// (a saturated finger's S_i^T u along x_i, a flat one's S_i^T u = 0, c_i^T u + ||S_i^T u|| = 1
// for both, by least squares), and one call of the full support map at u bounds t from above:
// the paper's stopping rule, h_W(n) - n^T (t r) <= eps n^T (t r). Where it does not hold (or
// the plane or the regions are degenerate), the shot goes on as before.

namespace gf {

namespace pair_detail {

constexpr Int N = 8;               // unknowns: alpha_1, a (3), alpha_2, b (3)
constexpr Int ALPHA[2] = {0, 4};   // alpha_i's index in y; a finger's share follows it
constexpr Int ILLINOIS_STEPS = 100;
constexpr double PIVOT_TOL = 1e-12;   // of M's largest entry: M's rank below 6
constexpr Int MAX_WITNESS = 16;       // the set's witness entries (two fingers: 8)

struct Finger {
    Int w;             // its witness slot: [active, x (3)]
    const double* c;   // c_i (6)
    const double* S;   // S_i (6, 3) by rows
};

// The two ellipsoid leaves (6, 3) of a root hull in R^6: W_L1 of two soft fingers. False for any
// other set.
inline bool fingers(IVec ints, Vec f, Finger* F) {
    const Blocks B = blocks(ints[0]);
    if (ints[B.KIND] != HULL || ints[B.DIM] != 6 || ints[B.CCOUNT] != 2) return false;
    const Int c0 = B.CHILDREN + ints[B.CSTART];
    for (Int i = 0; i < 2; ++i) {
        const Int node = ints[c0 + i];
        if (ints[B.KIND + node] != ELLIPSOID) return false;
        const Int p = ints[B.PSTART + node];
        if (static_cast<Int>(f[p]) != 6 || static_cast<Int>(f[p + 1]) != 3) return false;
        F[i] = {ints[B.WSTART + node], f.d + p + 2, f.d + p + 8};
    }
    return true;
}

// y0 and Z (N, 2, by rows) with M (y0 + Z p) = r for every p, M = [c_1 S_1 c_2 S_2], by
// Gauss-Jordan elimination with complete pivoting on the 6 x 8 system; false when M's rank is
// below 6. (linalg's solve_basic and basic_null_space on M padded to 8 x 8 give the same y0
// and Z, but took the Panda's pinch 2.48 -> 2.78 us a call.)
inline bool solutions(const Finger* F, Vec r, double* y0, double* Z) {
    double M[6][N + 1];
    for (Int i = 0; i < 6; ++i) {
        for (Int f = 0; f < 2; ++f) {
            M[i][ALPHA[f]] = F[f].c[i];
            for (Int b = 0; b < 3; ++b) M[i][ALPHA[f] + 1 + b] = F[f].S[i * 3 + b];
        }
        M[i][N] = r[i];
    }
    Int col[N];
    for (Int j = 0; j < N; ++j) col[j] = j;
    double scale = 0.0;
    for (Int i = 0; i < 6; ++i)
        for (Int j = 0; j < N; ++j) scale = std::max(scale, std::abs(M[i][j]));
    for (Int k = 0; k < 6; ++k) {
        Int pi = k, pj = k;
        double best = 0.0;
        for (Int i = k; i < 6; ++i)
            for (Int j = k; j < N; ++j)
                if (std::abs(M[i][j]) > best) {
                    best = std::abs(M[i][j]);
                    pi = i;
                    pj = j;
                }
        if (!(best > PIVOT_TOL * scale)) return false;
        for (Int j = 0; j <= N; ++j) std::swap(M[k][j], M[pi][j]);
        for (Int i = 0; i < 6; ++i) std::swap(M[i][k], M[i][pj]);
        std::swap(col[k], col[pj]);
        const double inv = 1.0 / M[k][k];
        for (Int j = k; j <= N; ++j) M[k][j] *= inv;
        for (Int i = 0; i < 6; ++i) {
            if (i == k) continue;
            const double g = M[i][k];
            for (Int j = k; j <= N; ++j) M[i][j] -= g * M[k][j];
        }
    }
    // basic unknowns col[0..5] = M[:, N] - M[:, 6..7] (free unknowns col[6], col[7])
    for (Int i = 0; i < 6; ++i) {
        y0[col[i]] = M[i][N];
        Z[col[i] * 2] = -M[i][6];
        Z[col[i] * 2 + 1] = -M[i][7];
    }
    for (Int q = 0; q < 2; ++q) {
        y0[col[6 + q]] = 0.0;
        Z[col[6 + q] * 2] = q == 0 ? 1.0 : 0.0;
        Z[col[6 + q] * 2 + 1] = q == 1 ? 1.0 : 0.0;
    }
    return true;
}

// Finger i on the level line sigma = v, p = P(v) + s e: alpha_i = m0 + v m1 + s n and its share
// u0 + v u1 + s w.
struct Line {
    double m0, m1, n;
    double u0[3], u1[3], w[3];
};

// {s : m + s n >= 0, ||u + s w|| <= m + s n} at v as [lo, hi] (either end infinite); false when
// empty. The set is convex; |u + s w|^2 - (m + s n)^2 = a2 s^2 + 2 a1 s + a0.
inline bool interval(const Line& L, double v, double& lo, double& hi) {
    double u[3];
    const double m = L.m0 + v * L.m1;
    double ww = 0.0, uw = 0.0, uu = 0.0;
    for (Int b = 0; b < 3; ++b) {
        u[b] = L.u0[b] + v * L.u1[b];
        ww += L.w[b] * L.w[b];
        uw += u[b] * L.w[b];
        uu += u[b] * u[b];
    }
    const double a2 = ww - L.n * L.n, a1 = uw - m * L.n, a0 = uu - m * m;
    const double disc = a1 * a1 - a2 * a0;
    if (a2 > 0.0) {
        if (disc < 0.0) return false;
        const double sq = std::sqrt(disc);
        lo = (-a1 - sq) / a2;
        hi = (-a1 + sq) / a2;
        // the interval lies in one nappe of the cone: the one with m + s n >= 0, or none
        return m + 0.5 * (lo + hi) * L.n >= 0.0;
    }
    if (a2 < 0.0) {
        // the roots exist (the quadratic is >= 0 where m + s n = 0); the nappe m + s n >= 0 is
        // the ray beyond the larger root (n > 0) or below the smaller (n < 0)
        const double sq = std::sqrt(std::max(disc, 0.0));
        const double r1 = (-a1 + sq) / a2, r2 = (-a1 - sq) / a2;
        if (L.n > 0.0) {
            lo = std::max(r1, r2);
            hi = INF;
        } else {
            lo = -INF;
            hi = std::min(r1, r2);
        }
        return true;
    }
    return false;   // a parabola's region: degenerate, left to the general path
}

// max(lo_1, lo_2) - min(hi_1, hi_2) at v (<= 0: the level line meets both regions), INF where
// an interval is empty; the meeting point's s in s_mid.
inline double gap(const Line* L, double v, double& s_mid) {
    double lo1, hi1, lo2, hi2;
    if (!interval(L[0], v, lo1, hi1) || !interval(L[1], v, lo2, hi2)) return INF;
    const double lo = std::max(lo1, lo2), hi = std::min(hi1, hi2);
    s_mid = 0.5 * (lo + hi);
    return lo - hi;
}

// The least v at which finger i's region alone meets the level line, and its point s there
// (the interval shrunk to a point: a quadratic in v); false when the region is unbounded along
// the level lines or never meets them.
inline bool tangency(const Line& L, double& v, double& s) {
    double ww = 0.0, p0 = 0.0, p1 = 0.0, q0 = 0.0, q1 = 0.0, q2 = 0.0;
    for (Int b = 0; b < 3; ++b) {
        ww += L.w[b] * L.w[b];
        p0 += L.u0[b] * L.w[b];
        p1 += L.u1[b] * L.w[b];
        q0 += L.u0[b] * L.u0[b];
        q1 += L.u0[b] * L.u1[b];
        q2 += L.u1[b] * L.u1[b];
    }
    const double a2 = ww - L.n * L.n;
    if (!(a2 > 0.0)) return false;
    p0 -= L.m0 * L.n;
    p1 -= L.m1 * L.n;
    q0 -= L.m0 * L.m0;
    q1 -= L.m0 * L.m1;
    q2 -= L.m1 * L.m1;
    // the discriminant of the interval's quadratic, (p0 + p1 v)^2 - a2 (q0 + 2 q1 v + q2 v^2)
    const double A = p1 * p1 - a2 * q2, B = 2.0 * (p0 * p1 - a2 * q1), C = p0 * p0 - a2 * q0;
    const double disc = B * B - 4.0 * A * C;
    if (!(disc >= 0.0) || A == 0.0) return false;
    const double sq = std::sqrt(disc);
    double roots[2] = {(-B - sq) / (2.0 * A), (-B + sq) / (2.0 * A)};
    if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
    for (double root : roots) {
        const double si = -(p0 + p1 * root) / a2;
        if (L.m0 + root * L.m1 + si * L.n >= 0.0) {
            v = root;
            s = si;
            return true;
        }
    }
    return false;
}

}  // namespace pair_detail

// Whether the set is the hull of two ellipsoids (6, 3) in R^6 (W_L1 of two soft fingers)
inline bool pair_applies(IVec ints, Vec f) {
    pair_detail::Finger F[2];
    return pair_detail::fingers(ints, f, F);
}

// The shot at W_L1 of two soft fingers from sigma_hi = 1 / t_0, a level known to be reached (a
// point t_0 r of W: a start table's, or ZC's first), as a certified hit (`certify`), or status
// LIMIT where the closed form does not apply or its certificate does not hold: the caller's
// shot goes on. Out of line: the callers' code stays as it was for every other set.
[[gnu::noinline]] inline Shot pair_exit(IVec ints, Vec f, Vec r, Int ws, double eps,
                                         double sigma_hi) {
    using namespace pair_detail;
    Shot none;
    none.status = LIMIT;
    Finger F[2];
    double y0[N], Z[2 * N];
    if (!fingers(ints, f, F) || !solutions(F, r, y0, Z)) return none;
    // sigma = s0 + g^T p; level lines p = P(v) + s e, P(v) = (v - s0) g / |g|^2, e normal to g
    const double g0 = Z[ALPHA[0] * 2] + Z[ALPHA[1] * 2];
    const double g1 = Z[ALPHA[0] * 2 + 1] + Z[ALPHA[1] * 2 + 1];
    const double s0 = y0[ALPHA[0]] + y0[ALPHA[1]];
    const double gg = g0 * g0 + g1 * g1;
    if (!(gg > 0.0)) return none;
    const double gn = std::sqrt(gg);
    const double e0 = -g1 / gn, e1 = g0 / gn;
    auto along = [&](Int row, double& c0, double& c1, double& ce) {
        // y[row] = c0 + v c1 + s ce on the level lines
        c1 = (Z[row * 2] * g0 + Z[row * 2 + 1] * g1) / gg;
        c0 = y0[row] - s0 * c1;
        ce = Z[row * 2] * e0 + Z[row * 2 + 1] * e1;
    };
    Line L[2];
    for (Int i = 0; i < 2; ++i) {
        along(ALPHA[i], L[i].m0, L[i].m1, L[i].n);
        for (Int b = 0; b < 3; ++b) along(ALPHA[i] + 1 + b, L[i].u0[b], L[i].u1[b], L[i].w[b]);
    }
    double s_mid = 0.0;
    if (!(gap(L, sigma_hi, s_mid) <= 0.0)) return none;
    // one finger saturated alone: its region's least level, inside the other's region
    bool saturated[2] = {true, true};
    double v = INF, s = 0.0, low = 0.0;
    for (Int i = 0; i < 2; ++i) {
        double vi, si, lo, hi;
        if (!tangency(L[i], vi, si)) continue;
        low = std::max(low, vi);
        if (vi < v && interval(L[1 - i], vi, lo, hi) && lo < si && si < hi) {
            v = vi;
            s = si;
            saturated[1 - i] = false;
            saturated[i] = true;
        }
    }
    Int steps = 0;
    if (v == INF) {
        // both saturated: the least level where the intervals meet, by the Illinois method
        // between the tangencies' largest (below it a region misses the line) and sigma_hi
        double lo = low, hi = sigma_hi, ghi = gap(L, hi, s_mid);
        double glo = gap(L, lo, s_mid);
        Int side = 0;
        while (hi - lo > 4e-16 * hi && steps < ILLINOIS_STEPS) {
            steps += 1;
            double vm = glo < INF ? hi - ghi * (hi - lo) / (ghi - glo) : 0.5 * (lo + hi);
            if (!(vm > lo && vm < hi)) vm = 0.5 * (lo + hi);
            const double gm = gap(L, vm, s_mid);
            if (gm <= 0.0) {
                hi = vm;
                ghi = gm;
                if (side == -1) glo *= 0.5;
                side = -1;
                if (gm == 0.0) break;
            } else {
                lo = vm;
                glo = gm;
                if (side == 1) ghi *= 0.5;
                side = 1;
            }
        }
        if (!(gap(L, hi, s_mid) <= 0.0)) return none;
        v = hi;
        s = s_mid;
    }
    // the forces: y at (v, s); each finger's point z_i = c_i + S_i x_i and weight alpha_i / sigma
    double y[N];
    for (Int j = 0; j < N; ++j) {
        double c0, c1, ce;
        along(j, c0, c1, ce);
        y[j] = c0 + v * c1 + s * ce;
    }
    if (ws > MAX_WITNESS) return none;
    // the face's points, witnesses, weights and the fingers' x, on the stack
    double pbuf[2 * 6], wbuf[2 * MAX_WITNESS] = {}, lbuf[2], xbuf[2 * 3];
    const Mat P{pbuf, 2, 6, 6}, Wt{wbuf, 2, ws, ws}, xs{xbuf, 2, 3, 3};
    const Vec lam{lbuf, 2};
    Int k = 0;
    double sigma = 0.0;
    for (Int i = 0; i < 2; ++i) sigma += std::max(y[ALPHA[i]], 0.0);
    if (!(sigma > 0.0)) return none;
    for (Int i = 0; i < 2; ++i) {
        const double alpha = y[ALPHA[i]];
        if (!(alpha > 0.0)) {
            if (saturated[i]) return none;   // a finger without force: its normal is not unique
            continue;
        }
        double x[3], xx = 0.0;
        for (Int b = 0; b < 3; ++b) {
            x[b] = y[ALPHA[i] + 1 + b] / alpha;
            xx += x[b] * x[b];
        }
        // rounding may leave x a hair outside the unit ball
        const double shrink = xx > 1.0 ? 1.0 / std::sqrt(xx) : 1.0;
        for (Int b = 0; b < 3; ++b) {
            x[b] *= shrink;
            xs(i, b) = x[b];
            Wt(k, F[i].w + 1 + b) = x[b];
        }
        Wt(k, F[i].w) = 1.0;
        for (Int a = 0; a < 6; ++a) {
            double z = F[i].c[a];
            for (Int b = 0; b < 3; ++b) z += F[i].S[a * 3 + b] * x[b];
            P(k, a) = z;
        }
        lam[k] = alpha / sigma;
        k += 1;
    }
    // the face's normal: u with c_i^T u + kappa_i = 1 and S_i^T u = kappa_i x_i for a saturated
    // finger, c_i^T u = 1 and S_i^T u = 0 for a flat one; unknowns u (6) and the kappas
    Int q = 6;
    Int kap[2] = {-1, -1};
    for (Int i = 0; i < 2; ++i)
        if (saturated[i]) kap[i] = q++;
    double dbuf[8 * 8] = {}, workbuf[8 * 8], rbuf[8] = {}, wrbuf[8], sbuf[8];
    const Mat D{dbuf, 8, q, q};
    const Vec rhs{rbuf, 8}, sol{sbuf, q};
    for (Int i = 0; i < 2; ++i) {
        const Int row = 4 * i;
        for (Int b = 0; b < 3; ++b) {
            for (Int a = 0; a < 6; ++a) D(row + b, a) = F[i].S[a * 3 + b];
            if (kap[i] >= 0) D(row + b, kap[i]) = -xs(i, b);
        }
        for (Int a = 0; a < 6; ++a) D(row + 3, a) = F[i].c[a];
        if (kap[i] >= 0) D(row + 3, kap[i]) = 1.0;
        rhs[row + 3] = 1.0;
    }
    if (!lstsq(D, 8, q, rhs, sol, 0, Mat{workbuf, 8, q, q}, Vec{wrbuf, 8})) return none;
    double nbuf[6], ptbuf[6], witbuf[MAX_WITNESS];
    const Vec normal{nbuf, 6};
    double uu = 0.0;
    for (Int a = 0; a < 6; ++a) uu += sol[a] * sol[a];
    if (!(uu > 0.0)) return none;
    const double un = std::sqrt(uu);
    for (Int a = 0; a < 6; ++a) normal[a] = sol[a] / un;
    const double nr = dot(normal, r);
    if (!(nr > 0.0)) return none;
    const double h = support(ints, f, normal, Vec{ptbuf, 6}, Vec{witbuf, ws});
    return certify(
        make_result(HIT, 1.0 / sigma, h / nr, h, 1 + steps, 1, normal, P, lam, Wt, k, 0), r,
        eps);
}

}  // namespace gf
