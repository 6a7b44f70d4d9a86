#pragma once

#include "shooting/newton.hpp"

// The Newton finish on W_Linf itself, the sum W = sum_i CH({0} U E_i) in R^6 (E_i = G_i F_i, a
// contact's wrenches of unit normal force: an ellipse for a point contact, a 3-D ellipsoid for a
// soft finger; eq. 13's Linf measure).
//
// Ray shooting is t* = min { h_W(u) : u^T r = 1 } with h_W(u) = sum_i max(0, h_i(u)),
// h_i(u) = c_i^T u + ||S_i^T u|| (E_i = {c_i + S_i x : ||x|| <= 1}). At the answer each contact is
// in one of five states, read off IE's last facet (`sum_states`), and its share p_i of
// t r = sum_i p_i is
//
//     off    h_i(u) < 0                  p_i = 0
//     on     h_i(u) > 0                  p_i = z_i(u) = c_i + S_i x_i(u),
//                                                x_i = S_i^T u / ||S_i^T u||
//     kink   h_i(u) = 0                  p_i = lam_i z_i(u), 0 <= lam_i <= 1
//     flat   S_i^T u = 0, c_i^T u > 0    p_i = c_i + S_i v_i, ||v_i|| <= 1 (friction not saturated)
//     kflat  S_i^T u = 0, c_i^T u = 0    p_i = a_i c_i + S_i w_i, ||w_i|| <= a_i <= 1
//
// Newton solves sum_i p_i = t r, u^T r = 1 and each state's equations on u (h_i = 0; S_i^T u = 0;
// c_i^T u = 0 and S_i^T u = 0) in u, t and the states' unknowns: 7 + (1, k, k + 1 a kink, flat,
// kflat) unknowns, with the curvatures (S S^T - (S x)(S x)^T) / ||S^T u|| of the smooth shares.
// States read off a degenerate face whose equations no u solves are demoted first
// (`states_hold`). When a step has converged, a state whose unknowns left their bounds, or whose
// support has the wrong sign at u, changes (kink -> on or off, flat -> on, on -> kink, off ->
// kink, ...) and Newton goes on. Where the system is singular (fingers squeezing), a proximal
// term keeps it regular and the unknowns are moved within their bounds (`sum_least_norm`).
//
// The answer is certified as the other finishes' (newton.hpp): the shares are written as a convex
// combination of at most six points of W (each contact's share split into the origin and points
// of E_i, merged into points of the sum), the weights re-solved on the ray, and one call of the
// full support map at u bounds t from above.

namespace gf {

namespace newton_detail {

constexpr Int SUM_MAX = 16;            // contacts the finish takes
// a state's bound or sign is broken once past CHANGE_TOL (relative), not by rounding
constexpr double CHANGE_TOL = 1e-12;
// Newton steps of one try, over all changes of the states
constexpr Int SUM_STEPS = 20;
// steps after new states before the divergence test (DIVERGED) applies
constexpr Int SETTLE = 2;
// a share whose friction saturates moves u off its flat by this fraction of ||u||
constexpr double LEAVE = 1e-2;
// alternating projections that look for the shares' unknowns within their bounds (those that
// have found none by then mostly never do: the states are wrong)
constexpr Int FEASIBLE_ROUNDS = 8;
// the states' unknowns' proximal weight in the Newton system, relative to its scale (below)
constexpr double PROXIMAL = 1e-10;

enum SumState : int { OFF, ON, KINK, FLAT, KFLAT };

struct SumContact {
    Int leaf;       // the ellipsoid leaf E_i
    Int origin;     // its hull's origin: a polytope of one vertex at 0
    Int pp;         // E_i's parameters: n, k, c (n), S (n, k) by rows
    Int k;
    double scale;   // ||c|| + ||S||_F
    double snorm;   // ||S||_F
    double SS[36];  // S S^T (6, 6)
    int state;
    double a;       // kink: lam; kflat: a
    double v[3];    // flat: v; kflat: w
};

// W_Linf's sum: a root sum in R^6 of hulls of an origin and an ellipsoid leaf (6, 2 or 3) each;
// the contacts into cs (unless null) and their count, or -1 for another set
inline Int sum_contacts(IVec ints, Vec f, SumContact* cs) {
    const Blocks B = blocks(ints[0]);
    if (ints[B.KIND] != SUM || ints[B.DIM] != 6 || ints[B.CCOUNT] > SUM_MAX) return -1;
    const Int m = ints[B.CCOUNT];
    const Int c0 = B.CHILDREN + ints[B.CSTART];
    for (Int i = 0; i < m; ++i) {
        const Int h = ints[c0 + i];
        if (ints[B.KIND + h] != HULL || ints[B.CCOUNT + h] != 2) return -1;
        Int leaf = -1, origin = -1;
        for (Int c = 0; c < 2; ++c) {
            const Int node = ints[B.CHILDREN + ints[B.CSTART + h] + c];
            const Int p = ints[B.PSTART + node];
            if (ints[B.KIND + node] == ELLIPSOID && f[p] == 6.0 &&
                (f[p + 1] == 2.0 || f[p + 1] == 3.0)) {
                leaf = node;
            } else if (ints[B.KIND + node] == POLYTOPE && f[p] == 1.0 && f[p + 1] == 6.0) {
                bool zero = true;
                for (Int a = 0; a < 6; ++a) zero = zero && f[p + 2 + a] == 0.0;
                if (zero) origin = node;
            }
        }
        if (leaf < 0 || origin < 0) return -1;
        if (cs == nullptr) continue;
        SumContact& q = cs[i];
        q.leaf = leaf;
        q.origin = origin;
        q.pp = ints[B.PSTART + leaf];
        q.k = static_cast<Int>(f[q.pp + 1]);
        const double* S = f.d + q.pp + 8;
        gram_upper(S, 6, q.k, q.SS, 6);
        double cc = 0.0, ss = 0.0;   // ||c||^2, and ||S||_F^2 as the trace of S S^T
        for (Int a = 0; a < 6; ++a) {
            cc += f[q.pp + 2 + a] * f[q.pp + 2 + a];
            for (Int a2 = 0; a2 < a; ++a2) q.SS[a * 6 + a2] = q.SS[a2 * 6 + a];
            ss += q.SS[a * 6 + a];
        }
        q.snorm = std::sqrt(ss);
        q.scale = std::sqrt(cc) + q.snorm;
    }
    return m;
}

// Contact q's leaf as newton.hpp's pieces name it (no embedding): ellipsoid_at gives its point
// z(u), x and S x, its support and ||S^T u|| (0 at its kink)
[[gnu::always_inline]] inline piece::SmoothLeaf smooth_of(const SumContact& q) {
    return {q.leaf, q.pp, 0, -1};
}

// c^T u and y = S^T u (k) of contact q; returns ||y||
[[gnu::always_inline]] inline double sum_dirs(Vec f, const SumContact& q, const double* u,
                                              double& cu, double* y) {
    const double* c = f.d + q.pp + 2;
    const double* S = f.d + q.pp + 8;
    cu = 0.0;
    for (Int a = 0; a < 6; ++a) cu += c[a] * u[a];
    double rho2 = 0.0;
    for (Int b = 0; b < q.k; ++b) {
        double s = 0.0;
        for (Int a = 0; a < 6; ++a) s += S[a * q.k + b] * u[a];
        y[b] = s;
        rho2 += s * s;
    }
    return std::sqrt(rho2);
}

// p += c + S x (x of q.k entries)
[[gnu::always_inline]] inline void sum_add_point(Vec f, const SumContact& q, const double* x,
                                                 double* p) {
    const double* c = f.d + q.pp + 2;
    const double* S = f.d + q.pp + 8;
    for (Int a = 0; a < 6; ++a) {
        double s = c[a];
        for (Int b = 0; b < q.k; ++b) s += S[a * q.k + b] * x[b];
        p[a] += s;
    }
}

// Contact q's part of sum_i p_i at u. The columns along which its state's unknowns move it (a
// kink's z(u) for lam; a kflat's c for a, then S for w; a flat's S for v) go to C[:, col:]
// (rows FAST_K apart); what does not move with them (z(u) when on, c when flat) is added to
// fixed; the column after its last is returned. A smooth share's z, S x and support
// (ellipsoid_at) are left in z, sx and e. The state's equations are C_j^T u = 0 for its columns
// j (h_i(u) = z(u)^T u, c^T u, S^T u).
inline Int sum_columns(Vec f, const SumContact& q, const double* u, double* C, Int col,
                       double* fixed, double* z, double* sx, EllipsePoint& e) {
    if (q.state == OFF) return col;
    const double* c = f.d + q.pp + 2;
    const double* S = f.d + q.pp + 8;
    if (q.state == ON || q.state == KINK) {
        double x[3];
        e = ellipsoid_at<6>(f, smooth_of(q), u, 6, z, x, sx);
        for (Int a = 0; a < 6; ++a) {
            if (q.state == ON) fixed[a] += z[a];
            else C[a * FAST_K + col] = z[a];
        }
        return col + (q.state == KINK);
    }
    for (Int a = 0; a < 6; ++a) {
        if (q.state == FLAT) fixed[a] += c[a];
        else C[a * FAST_K + col] = c[a];
    }
    col += q.state == KFLAT;
    for (Int b = 0; b < q.k; ++b, ++col)
        for (Int a = 0; a < 6; ++a) C[a * FAST_K + col] = S[a * q.k + b];
    return col;
}

// Contact q's unknowns in the order of its columns (a kink's or kflat's a, then a flat's or
// kflat's v) as pointers into q; their count
inline Int unknowns_of(SumContact& q, double** x) {
    Int count = 0;
    if (q.state == KINK || q.state == KFLAT) x[count++] = &q.a;
    if (q.state == FLAT || q.state == KFLAT)
        for (Int b = 0; b < q.k; ++b) x[count++] = &q.v[b];
    return count;
}

// Every contact's columns (sum_columns) into C (6 rows, FAST_K apart) and what does not move
// with them into fixed (zeroed first); their count
inline Int all_columns(Vec f, const SumContact* cs, Int m, const double* u, double* C,
                       double* fixed) {
    for (Int a = 0; a < 6; ++a) fixed[a] = 0.0;
    Int E = 0;
    for (Int i = 0; i < m; ++i) {
        double z[6], sx[6];
        EllipsePoint e{0.0, 0.0};
        E = sum_columns(f, cs[i], u, C, E, fixed, z, sx, e);
    }
    return E;
}

// v (len) less its part in the span of the orthonormal rows Q[:rank] (ld apart); ||v||^2 after
inline double less_span(const double* Q, Int rank, Int ld, Int len, double* v) {
    for (Int q = 0; q < rank; ++q) {
        double d = 0.0;
        for (Int a = 0; a < len; ++a) d += Q[q * ld + a] * v[a];
        for (Int a = 0; a < len; ++a) v[a] -= d * Q[q * ld + a];
    }
    double vv = 0.0;
    for (Int a = 0; a < len; ++a) vv += v[a] * v[a];
    return vv;
}

// Gram-Schmidt's step: the row Q[rank] (len entries) less its part in the span of Q[:rank],
// normalized and kept where ||.||^2 after exceeds floor; the rank after
inline Int grow_basis(double* Q, Int rank, Int ld, Int len, double floor) {
    double* const v = Q + rank * ld;
    const double vv = less_span(Q, rank, ld, len, v);
    if (!(vv > floor)) return rank;
    const double inv = 1.0 / std::sqrt(vv);
    for (Int a = 0; a < len; ++a) v[a] *= inv;
    return rank + 1;
}

// A state's unknowns, and its equations on u: 1 a kink (lam), k flat (v), k + 1 a kflat (a, w)
inline Int state_size(const SumContact& q) {
    return q.state == KINK ? 1 : q.state == FLAT ? q.k : q.state == KFLAT ? q.k + 1 : 0;
}

// Whether some u has C^T u = 0 for the states' columns C (sum_columns) and u^T r = 1: r is not in
// the span of C (Gram-Schmidt on C's columns, r's part outside it above 1e-8 of ||r||)
inline bool states_hold(Vec f, const SumContact* cs, Int m, const double* u, Vec r) {
    constexpr Int n = 6;
    double C[n * FAST_K], fixed[n];
    const Int E = all_columns(f, cs, m, u, C, fixed);
    double Q[n * n];
    Int rank = 0;
    for (Int j = 0; j < E && rank < n; ++j) {
        double v0 = 0.0;
        for (Int a = 0; a < n; ++a) {
            Q[rank * n + a] = C[a * FAST_K + j];
            v0 += Q[rank * n + a] * Q[rank * n + a];
        }
        rank = grow_basis(Q, rank, n, n, 1e-20 * v0);
    }
    double w[n], rr = 0.0;
    for (Int a = 0; a < n; ++a) {
        w[a] = r[a];
        rr += r[a] * r[a];
    }
    return less_span(Q, rank, n, n, w) > 1e-16 * rr;
}

// The state of each contact from the facet of IE's last step (its k points' witnesses Wt and
// weights lam, t r = sum_j lam_j P_j): on where every point has the contact's ellipse point, off
// where none has, a kink between, with lam_i the weight of the points that have it; flat (or
// kflat) where ||S_i^T u|| <= FLAT_RHO ||S_i|| ||u|| or the weighted mean v_i of the points'
// x_i lies inside (||v_i||^2 < FLAT_SPREAD: the points spread around E_i, newton.hpp's test).
inline void sum_states(IVec ints, Vec f, SumContact* cs, Int m, const double* u, Vec r, Mat Wt,
                       Vec lam, Int k) {
    const Blocks B = blocks(ints[0]);
    double uu = 0.0, total = 0.0;
    for (Int a = 0; a < 6; ++a) uu += u[a] * u[a];
    for (Int j = 0; j < k; ++j) total += lam[j];
    const double un = std::sqrt(uu);
    for (Int i = 0; i < m; ++i) {
        SumContact& q = cs[i];
        const Int w = ints[B.WSTART + q.leaf];
        Int with = 0;
        double share = 0.0, x[3] = {0.0, 0.0, 0.0};
        for (Int j = 0; j < k; ++j) {
            if (Wt(j, w) == 0.0) continue;
            with += 1;
            share += lam[j];
            for (Int b = 0; b < q.k; ++b) x[b] += lam[j] * Wt(j, w + 1 + b);
        }
        double cu, y[3];
        const double rho = sum_dirs(f, q, u, cu, y);
        double xx = 0.0;
        for (Int b = 0; b < q.k; ++b) xx += x[b] * x[b];
        const bool flat = rho <= FLAT_RHO * q.snorm * un ||
                          (share > 0.0 && xx < FLAT_SPREAD * share * share);
        q.a = total > 0.0 ? std::min(std::max(share / total, 0.0), 1.0) : 0.5;
        for (Int b = 0; b < 3; ++b) q.v[b] = 0.0;
        if (with == 0) {
            q.state = OFF;
        } else if (with == k) {
            q.state = flat ? FLAT : ON;
            if (flat && share > 0.0)
                for (Int b = 0; b < q.k; ++b) q.v[b] = x[b] / share;
        } else {
            q.state = flat ? KFLAT : KINK;
            if (flat && total > 0.0)
                for (Int b = 0; b < q.k; ++b) q.v[b] = x[b] / total;   // w = a v
        }
    }
    // the states' equations C^T u = 0 (their columns, sum_columns) and u^T r = 1 have no
    // solution when r lies in the span of C (a degenerate face read too flat: the feet's corners),
    // which takes more than five of them; the flat state whose ||S_i^T u|| is largest gives up
    // its flatness, then the kink nearest an end, until they have one. Squeezing fingers'
    // dependent equations keep theirs.
    auto equations = [&]() {
        Int e = 0;
        for (Int i = 0; i < m; ++i) e += state_size(cs[i]);
        return e;
    };
    while (equations() > 5 && !states_hold(f, cs, m, u, r)) {
        Int pick = -1;
        double best = -1.0;
        for (Int i = 0; i < m; ++i) {
            SumContact& q = cs[i];
            if (q.state != FLAT && q.state != KFLAT) continue;
            double cu, y[3];
            const double rel = sum_dirs(f, q, u, cu, y) / q.snorm;
            if (rel > best) {
                best = rel;
                pick = i;
            }
        }
        if (pick >= 0) {
            cs[pick].state = cs[pick].state == FLAT ? ON : KINK;
            continue;
        }
        for (Int i = 0; i < m; ++i) {
            if (cs[i].state != KINK) continue;
            const double end = std::abs(cs[i].a - 0.5);
            if (end > best) {
                best = end;
                pick = i;
            }
        }
        if (pick < 0) return;
        cs[pick].state = cs[pick].a >= 0.5 ? ON : OFF;
    }
}

// After a converged step: the state whose unknowns left their bounds, or whose support has the
// wrong sign at u, by the most changes (one at a time: two changed at once sent steps astray);
// true when one did
inline bool sum_change(Vec f, SumContact* cs, Int m, double* u) {
    double uu = 0.0;
    for (Int a = 0; a < 6; ++a) uu += u[a] * u[a];
    const double un = std::sqrt(uu);
    Int worst = -1;
    int to = OFF;
    double most = CHANGE_TOL;
    for (Int i = 0; i < m; ++i) {
        const SumContact& q = cs[i];
        double cu, y[3];
        const double rho = sum_dirs(f, q, u, cu, y);
        const double h = (cu + rho) / (q.scale * un);   // relative support
        const double c = cu / (q.scale * un);
        double vv = 0.0;
        for (Int b = 0; b < q.k; ++b) vv += q.v[b] * q.v[b];
        const double vn = std::sqrt(vv);
        auto consider = [&](double amount, int state) {
            if (amount > most) {
                most = amount;
                worst = i;
                to = state;
            }
        };
        if (q.state == OFF) consider(h, KINK);
        if (q.state == ON) consider(-h, KINK);
        if (q.state == KINK) {
            consider(q.a - 1.0, ON);
            consider(-q.a, OFF);
        }
        if (q.state == FLAT) {
            consider(vn - 1.0, ON);
            consider(-c, KFLAT);
        }
        if (q.state == KFLAT) {
            consider(-q.a, OFF);
            consider(vn - q.a, KINK);
            consider(q.a - 1.0, FLAT);
        }
    }
    if (worst < 0) return false;
    SumContact& q = cs[worst];
    if (to == KINK)
        q.a = q.state == OFF ? 0.0 : q.state == ON ? 1.0 : std::min(std::max(q.a, 0.0), 1.0);
    if (q.state == FLAT && to == KFLAT) q.a = 1.0;
    if (q.state == KFLAT && to == FLAT)
        for (Int b = 0; b < q.k; ++b) q.v[b] /= q.a;
    if ((q.state == FLAT && to == ON) || (q.state == KFLAT && to == KINK)) {
        // friction saturates: u leaves S^T u = 0 along S v (where the force pushed), by LEAVE
        // of its length, so that the smooth share's point and curvature exist
        const double* S = f.d + q.pp + 8;
        double d[6], dd = 0.0;
        for (Int a = 0; a < 6; ++a) {
            double s = 0.0;
            for (Int b = 0; b < q.k; ++b) s += S[a * q.k + b] * q.v[b];
            d[a] = s;
            dd += s * s;
        }
        if (dd > 0.0) {
            const double g = LEAVE * un / std::sqrt(dd);
            for (Int a = 0; a < 6; ++a) u[a] += g * d[a];
        }
    }
    q.state = to;
    return true;
}

// One contact's share as a convex combination of up to three points of CH({0} U E_i): weights
// mu, and x (unit, k entries each) or the origin (flag 0)
struct Share {
    Int count;
    double mu[3];
    bool point[3];
    double x[3][3];
};

inline void sum_share(Vec f, const SumContact& q, const double* u, Share& s) {
    double cu, y[3];
    const double rho = sum_dirs(f, q, u, cu, y);
    s.count = 0;
    auto add = [&](double mu, bool point, const double* x) {
        s.mu[s.count] = mu;
        s.point[s.count] = point;
        for (Int b = 0; b < q.k; ++b) s.x[s.count][b] = point ? x[b] : 0.0;
        s.count += 1;
    };
    double x[3];
    if (q.state == ON || q.state == KINK) {
        for (Int b = 0; b < q.k; ++b) x[b] = rho > 0.0 ? y[b] / rho : 0.0;
        const double lam = q.state == ON ? 1.0 : std::min(std::max(q.a, 0.0), 1.0);
        add(lam, true, x);
        if (lam < 1.0) add(1.0 - lam, false, x);
        return;
    }
    if (q.state == OFF) {
        add(1.0, false, x);
        return;
    }
    // flat: c + S v with v = alpha e + (1 - alpha)(-e), e = v / ||v||, alpha = (1 + ||v||) / 2;
    // kflat: a times that, and the origin
    const double a = q.state == FLAT ? 1.0 : std::min(std::max(q.a, 0.0), 1.0);
    double v[3], vv = 0.0;
    for (Int b = 0; b < q.k; ++b) {
        v[b] = q.state == FLAT ? q.v[b] : (a > 0.0 ? q.v[b] / a : 0.0);
        vv += v[b] * v[b];
    }
    const double vn = std::min(std::sqrt(vv), 1.0);
    for (Int b = 0; b < q.k; ++b) x[b] = vn > 0.0 ? v[b] / std::sqrt(vv) : (b == 0 ? 1.0 : 0.0);
    const double alpha = 0.5 * (1.0 + vn);
    add(a * alpha, true, x);
    for (Int b = 0; b < q.k; ++b) x[b] = -x[b];
    if (alpha < 1.0) add(a * (1.0 - alpha), true, x);
    if (a < 1.0) add(1.0 - a, false, x);
}

// The shares merged into rows of points of W with weights (each row one point of every
// contact's share: the staircase of their cumulative weights), into S (rows, 6), WS (rows, ws)
// and lam; the number of rows, or -1 past max_rows
inline Int sum_rows(IVec ints, Vec f, const SumContact* cs, Int m, const double* u, Mat S,
                    Mat WS, Vec lam, Int max_rows) {
    const Blocks B = blocks(ints[0]);
    Share sh[SUM_MAX];
    Int at[SUM_MAX];
    double rest[SUM_MAX];
    for (Int i = 0; i < m; ++i) {
        sum_share(f, cs[i], u, sh[i]);
        at[i] = 0;
        rest[i] = sh[i].mu[0];
    }
    Int rows = 0;
    for (;;) {
        double step = INF;
        for (Int i = 0; i < m; ++i) step = std::min(step, rest[i]);
        if (step > 1e-15) {
            if (rows == max_rows) return -1;
            for (Int a = 0; a < 6; ++a) S(rows, a) = 0.0;
            for (Int j = 0; j < WS.cols; ++j) WS(rows, j) = 0.0;
            for (Int i = 0; i < m; ++i) {
                const Share& s = sh[i];
                if (s.point[at[i]]) {
                    sum_add_point(f, cs[i], s.x[at[i]], &S(rows, 0));
                    const Int w = ints[B.WSTART + cs[i].leaf];
                    WS(rows, w) = 1.0;
                    for (Int b = 0; b < cs[i].k; ++b) WS(rows, w + 1 + b) = s.x[at[i]][b];
                } else {
                    WS(rows, ints[B.WSTART + cs[i].origin]) = 1.0;
                }
            }
            lam[rows] = step;
            rows += 1;
        }
        bool done = false;
        for (Int i = 0; i < m; ++i) {
            rest[i] -= step;
            if (rest[i] <= 1e-15) {
                at[i] += 1;
                if (at[i] == sh[i].count) done = true;
                else rest[i] += sh[i].mu[at[i]];
            }
        }
        if (done) return rows;
    }
}

// The states' unknowns that give sum_i p_i = t r at u (the system's columns C, the rest b)
// within their bounds. Where the system is singular (two soft fingers squeezing an object:
// their forces trade along the squeeze) Newton's basic steps leave any solution, often one
// outside the friction cones: the least-norm one (x = C^T y, C C^T y = b), then alternating
// projections when that one is outside too.
inline void sum_least_norm(Vec f, SumContact* cs, Int m, const double* u, double t, Vec r) {
    constexpr Int n = 6;
    double C[n * FAST_K], fixed[n];
    const Int E = all_columns(f, cs, m, u, C, fixed);
    if (E == 0) return;
    double b[n];
    for (Int a = 0; a < n; ++a) b[a] = t * r[a] - fixed[a];
    double G[n * n], lu[n * n], y[n];
    Int prow[n], pcol[n];
    for (Int a = 0; a < n; ++a)
        for (Int a2 = 0; a2 < n; ++a2) {
            double s = 0.0;
            for (Int j = 0; j < E; ++j) s += C[a * FAST_K + j] * C[a2 * FAST_K + j];
            G[a * n + a2] = s;
        }
    // x = C^T y, C C^T y = rhs: the least-norm x with C x = rhs (+ the x given)
    double x[FAST_K], res[n];
    for (Int j = 0; j < E; ++j) x[j] = 0.0;
    auto to_plane = [&]() {
        for (Int a = 0; a < n; ++a) {
            double s = b[a];
            for (Int j = 0; j < E; ++j) s -= C[a * FAST_K + j] * x[j];
            res[a] = s;
        }
        if (solve_basic(Mat{G, n, n, n}, n, Mat{lu, n, n, n}, IVec{prow, n}, IVec{pcol, n},
                        Vec{res, n}, Vec{y, n}) == 0)
            return false;
        for (Int j = 0; j < E; ++j)
            for (Int a = 0; a < n; ++a) x[j] += C[a * FAST_K + j] * y[a];
        return true;
    };
    if (!to_plane()) return;
    // where that x leaves a share's bounds (a kink's 0 <= lam <= 1, a flat's ||v|| <= 1, a
    // kflat's ||w|| <= a <= 1), alternate projections onto the bounds and onto C x = rhs: the
    // solutions form a line or more, and one inside the bounds is the answer's. The projection
    // onto C x = rhs is x - Q^T Q (x - x0), Q an orthonormal basis of C's rows (Gram-Schmidt)
    double Q[n * FAST_K], x0[FAST_K];
    double big = 0.0;
    for (Int a = 0; a < n; ++a) {
        double cc = 0.0;
        for (Int j = 0; j < E; ++j) cc += C[a * FAST_K + j] * C[a * FAST_K + j];
        big = std::max(big, cc);
    }
    Int rank = 0;
    for (Int a = 0; a < n; ++a) {
        for (Int j = 0; j < E; ++j) Q[rank * FAST_K + j] = C[a * FAST_K + j];
        rank = grow_basis(Q, rank, FAST_K, E, 1e-20 * big);
    }
    for (Int j = 0; j < E; ++j) x0[j] = x[j];
    for (Int round = 0; round < FEASIBLE_ROUNDS; ++round) {
        bool inside = true;
        Int j = 0;
        for (Int i = 0; i < m; ++i) {
            const SumContact& q = cs[i];
            if (q.state == KINK) {
                const double l = x[j];
                x[j] = std::min(std::max(l, 0.0), 1.0);
                inside = inside && x[j] == l;
                j += 1;
            } else if (q.state == FLAT || q.state == KFLAT) {
                double a = q.state == KFLAT ? x[j] : 1.0;
                double* w = x + j + (q.state == KFLAT);
                double ww = 0.0;
                for (Int bb = 0; bb < q.k; ++bb) ww += w[bb] * w[bb];
                const double wn = std::sqrt(ww);
                if (wn > a * (1.0 + CHANGE_TOL) || a > 1.0 + CHANGE_TOL || a < -CHANGE_TOL) {
                    inside = false;
                    if (q.state == KFLAT && wn > std::abs(a)) {
                        // onto the cone ||w|| <= a: ((a + ||w||) / 2) (1, w / ||w||)
                        a = std::max(0.5 * (a + wn), 0.0);
                        for (Int bb = 0; bb < q.k; ++bb) w[bb] *= wn > 0.0 ? a / wn : 0.0;
                    }
                    a = std::min(std::max(a, 0.0), 1.0);
                    double w2 = 0.0;
                    for (Int bb = 0; bb < q.k; ++bb) w2 += w[bb] * w[bb];
                    if (w2 > a * a)
                        for (Int bb = 0; bb < q.k; ++bb) w[bb] *= a / std::sqrt(w2);
                    if (q.state == KFLAT) x[j] = a;
                }
                j += q.k + (q.state == KFLAT);
            }
        }
        if (inside) break;
        for (Int p = 0; p < rank; ++p) {
            double d = 0.0;
            for (Int j = 0; j < E; ++j) d += Q[p * FAST_K + j] * (x[j] - x0[j]);
            for (Int j = 0; j < E; ++j) x[j] -= d * Q[p * FAST_K + j];
        }
    }
    Int j = 0;
    for (Int i = 0; i < m; ++i) {
        double* mine[4];
        const Int count = unknowns_of(cs[i], mine);
        for (Int jj = 0; jj < count; ++jj) *mine[jj] = x[j++];
    }
}

// newton_finish on W_Linf's sum (header comment), from the facet's normal; nullopt for another
// set
inline std::optional<NewtonOut> sum_finish(IVec ints, Vec f, Vec r, double eps, Mat Wt,
                                           Vec lam, Int k, Vec normal) {
    const Int ws = Wt.cols;
    constexpr Int n = 6;
    SumContact cs[SUM_MAX];
    const Int m = sum_contacts(ints, f, cs);
    if (m < 0 || r.n != n) return std::nullopt;
    const double nr = dot(normal, r);
    if (!(nr > 0.0)) return ellipsoid_failed(0.0, INF, 0.0, 0, 0, n, ws);
    double u[n];
    for (Int a = 0; a < n; ++a) u[a] = normal[a] / nr;
    sum_states(ints, f, cs, m, u, r, Wt, lam, k);
    double t = 0.0;
    for (Int i = 0; i < m; ++i) {
        double cu, y[3];
        const double rho = sum_dirs(f, cs[i], u, cu, y);
        t += std::max(cu + rho, 0.0);
    }
    KktWork kw;
    double* const K = kw.K;
    double* const rhs = kw.rhs;
    double* const dx = kw.dx;
    Int steps = 0, calls = 0, changes = 0;
    bool precise = false;
    double last_du = INF;
    Int fresh = 0;        // steps since the states last changed
    bool basic = false;   // the last step was a basic solution: a singular system
    while (steps < SUM_STEPS) {
        // a smooth share at its kink (S^T u = 0) turns flat: its force inside its cone
        bool turned = false;
        for (Int i = 0; i < m; ++i) {
            SumContact& q = cs[i];
            if (q.state != ON && q.state != KINK) continue;
            double z[n], x[3], sx[n];
            if (ellipsoid_at<n>(f, smooth_of(q), u, n, z, x, sx).rho > 0.0) continue;
            for (Int b = 0; b < q.k; ++b) q.v[b] = 0.0;
            q.state = q.state == ON ? FLAT : KFLAT;
            turned = true;
        }
        if (turned) {
            if (++changes > MAX_CHANGES) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
            last_du = INF;
            fresh = 0;
        }
        // the system: rows 0..5 sum_i p_i = t r, then each state's equations, then u^T r = 1;
        // columns du (0..5), dt (6), then each state's unknowns
        Int N = 7;
        for (Int i = 0; i < m; ++i) N += state_size(cs[i]);
        if (N > FAST_K) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        for (Int i = 0; i < N; ++i)
            for (Int j = 0; j < N; ++j) K[i * FAST_K + j] = 0.0;
        double p[n] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        // each contact's columns, its point (fixed + columns x its unknowns), a smooth share's
        // curvature (S S^T - (S x)(S x)^T) / ||S^T u|| times its weight; each state's
        // equations are its columns' transposes, C_j^T u = 0
        Int col = 7;
        for (Int i = 0; i < m; ++i) {
            SumContact& q = cs[i];
            double z[n], sx[n];
            EllipsePoint e{0.0, 0.0};
            const Int first = col;
            col = sum_columns(f, q, u, K, col, p, z, sx, e);
            double* mine[4];
            const Int count = unknowns_of(q, mine);
            for (Int j = 0; j < count; ++j)
                for (Int a = 0; a < n; ++a) p[a] += K[a * FAST_K + first + j] * *mine[j];
            if (q.state != ON && q.state != KINK) continue;
            const double gr = (q.state == ON ? 1.0 : q.a) / e.rho;
            for (Int a = 0; a < n; ++a)
                for (Int a2 = 0; a2 < n; ++a2)
                    K[a * FAST_K + a2] += gr * (q.SS[a * 6 + a2] - sx[a] * sx[a2]);
        }
        for (Int j = 7; j < N; ++j) {
            double s = 0.0;
            for (Int a = 0; a < n; ++a) {
                K[(j - 1) * FAST_K + a] = K[a * FAST_K + j];
                s += K[a * FAST_K + j] * u[a];
            }
            rhs[j - 1] = -s;
        }
        const Int row = N - 1;
        double ur = 0.0;
        for (Int a = 0; a < n; ++a) {
            K[a * FAST_K + 6] = -r[a];
            rhs[a] = -(p[a] - t * r[a]);
            K[row * FAST_K + a] = r[a];
            ur += u[a] * r[a];
        }
        rhs[row] = 1.0 - ur;
        // the states' unknowns move along C's null space (two fingers squeezing) at a cost
        // PROXIMAL of the system's scale: -delta on their equations' diagonal keeps the system
        // regular, and vanishes with the steps (a converged step solves the exact equations)
        double big = 0.0;
        for (Int a = 0; a < n; ++a)
            for (Int j = 7; j < N; ++j) big = std::max(big, std::abs(K[a * FAST_K + j]));
        for (Int q = 0; q + 7 < N; ++q) K[(6 + q) * FAST_K + 7 + q] = -PROXIMAL * big * big;
        const KktStep step = kkt_step(kw, N, u, n, true);
        if (!step.ok) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        basic = step.basic;
        steps += 1;
        const double du = step.du, un = step.un;
        t += dx[6];
        col = 7;
        for (Int i = 0; i < m; ++i) {
            double* mine[4];
            const Int count = unknowns_of(cs[i], mine);
            for (Int j = 0; j < count; ++j) *mine[j] += dx[col++];
        }
        // the first steps from new states may grow before they shrink quadratically
        if (!std::isfinite(t) || (++fresh > SETTLE && du > DIVERGED * last_du))
            return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        last_du = du;
        if (du > (precise ? STEP_TOL : EARLY_STEP) * un) continue;
        if (basic) sum_least_norm(f, cs, m, u, t, r);
        if (sum_change(f, cs, m, u)) {
            if (++changes > MAX_CHANGES) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
            last_du = INF;
            fresh = 0;
            continue;
        }
        // certify: the shares as rows of points of W, their weights re-solved on the ray, the
        // full support at u
        Array Sa(n + 1, n), WSa(n + 1, ws), lmA(n + 1), nrmA(n), witA(ws);
        const Mat Sm = Sa.mat();
        const Vec lv = lmA.vec();
        const Int rows = sum_rows(ints, f, cs, m, u, Sm, WSa.mat(), lv, n);
        if (rows < 1) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        double D[FAST_N * (FAST_N + 1)];
        double work[FAST_N * (FAST_N + 1)];
        double wrhs[FAST_N];
        double rhs2[FAST_N];
        double point[n];
        const double tz = weights_on_ray(Sm, rows, r, lv, Mat{D, n, rows, rows},
                                         Mat{work, n, rows, rows}, Vec{wrhs, n}, Vec{rhs2, n});
        double uu = 0.0;
        for (Int a = 0; a < n; ++a) uu += u[a] * u[a];
        const double ul = std::sqrt(uu);
        const Vec nrm = nrmA.vec();
        for (Int a = 0; a < n; ++a) nrm[a] = u[a] / ul;
        const Vec pv{point, n};
        for (Int a = 0; a < n; ++a) point[a] = tz * r[a];
        bool holds = tz > 0.0 && smallest(lv, rows) >= -1e-12 && reproduce(Sm, lv, rows, pv);
        double t_up = INF, h_full = 0.0;
        if (holds) {
            h_full = support(ints, f, nrm, pv, witA.vec());
            calls += 1;
            t_up = h_full / dot(nrm, r);
            holds = t_up - tz <= eps * tz && t_up >= tz * (1.0 - face_rounding(Sm, rows, h_full));
        }
        if (holds)
            return NewtonOut{true,          tz,    std::max(t_up, tz), h_full,
                             rows,          steps, calls,              std::move(nrmA),
                             std::move(Sa), std::move(lmA),            std::move(WSa)};
        if (precise) return ellipsoid_failed(t, t_up, h_full, steps, calls, n, ws);
        precise = true;
    }
    return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
}

}  // namespace newton_detail

// Whether smooth_finish can take a shot at this set: a hull of ellipsoid leaves (W_L1 of soft or
// point contacts) or of embeddings of one each with the origin (W_Linf's lift), or W_Linf's sum.
bool smooth_finish_applies(IVec ints, Vec f, Int n) {
    bool embedded;
    return newton_detail::ellipsoid_hull_columns(ints, f, n, embedded) >= 0 ||
           (n == 6 && newton_detail::sum_contacts(ints, f, nullptr) >= 0);
}

// newton_finish's plain steps where every piece of the exit face is smooth (`ellipsoid_finish`),
// or the finish on W_Linf's sum (`sum_finish`); not ok, after no step and with no arrays, where
// a hull's piece is flat or at its kink (most tries on grasps whose friction is not saturated
// end so: ZC-IE reads only ok, steps and calls of it).
NewtonOut smooth_finish(IVec ints, Vec f, Vec r, double eps, Mat Wt, Vec lam, Int k, Vec normal,
                        double t) {
    using namespace newton_detail;
    std::optional<NewtonOut> fast = ints[blocks(ints[0]).KIND] == SUM
                                        ? sum_finish(ints, f, r, eps, Wt, lam, k, normal)
                                        : ellipsoid_finish(ints, f, r, eps, Wt, lam, k, normal, t);
    if (fast) return std::move(*fast);
    return {false, t, INF, 0.0, 0, 0, 0, Array(), Array(), Array(), Array()};
}

}  // namespace gf
