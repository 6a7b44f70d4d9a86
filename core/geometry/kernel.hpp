#pragma once

#include "api.hpp"

// The one compiled support kernel.
//
// A convex set compiles to a support program: a tree of nodes stored in pre-order (a parent
// before its children) in flat arrays. `support` evaluates h_A(u) and s_A(u) of eq. (2) for any
// program in four passes: directions flow down the tree (an affine node maps u to M^T u), support
// values flow up (a hull keeps its best child, a sum adds), the leaves that produced the point
// are flagged in the witness vector, and the support point is built up from the flagged nodes
// only. Some program shapes take loops of their own instead of the passes (their plan): the soft
// fingers' wrench sets (ELLIPSOID_HULL), the point contacts' (ELLIPSE_HULL), either's affine
// image (PROJECTED_ELLIPSOID_HULL, PROJECTED_ELLIPSE_HULL) and sums of posed 3-D bodies, growth
// distance's Delta (POSED_SUM).
//
// A program is two arrays: `ints` = [nn, kind, dim, pstart, cstart, ccount, wstart, dstart,
// ostart, choice, active, children, plan] (each block nn long but `children` and the one entry
// `plan`; offsets from `blocks(nn)`), `floats` = [params, scratch]. Node i reads its direction
// at f[dstart[i]:] (its parent's, unless the parent is affine; an embedding's child reads the
// last entries of its parent's), writes its point to f[ostart[i]:ostart[i] + dim[i]] and its
// value to f[ostart[i] + dim[i]]; choice[i] is a hull's best child (an origin embedding's child,
// or -1 for its origin), active[i] whether node i produced the point. Node kinds, their
// parameters and witness slots: codes.hpp.

namespace gf {

namespace kernel {

// (n, mu, y_1, ||y_perp||^2, ||y_perp||, ||y||) of a cone cap's direction y
struct CapDirection {
    Int n;
    double mu;
    double y1;
    double q2;
    double q;
    double ny;
};

// cap_direction's tuple for a cone cap's direction y at f[d:] (its parameters n, mu at f[p:]).
[[gnu::always_inline]] inline CapDirection cap_direction(Vec f, Int p, Int d) {
    const Int n = static_cast<Int>(f[p]);
    const double y1 = f[d];
    double q2 = 0.0;
    for (Int a = 1; a < n; ++a) q2 += f[d + a] * f[d + a];
    return {n, f[p + 1], y1, q2, std::sqrt(q2), std::sqrt(y1 * y1 + q2)};
}

// Support of the unit vectors g of the circular cone K = {||g_2:n|| <= mu g_1}, point to
// f[o:o + n] and witness slot wit[w + 1:]. For y at angle phi from the axis e_1 and the cone's
// half-angle beta = atan(mu), the unit vector of K closest in angle to y is y/||y|| when
// phi <= beta, else the boundary ray b = (cos beta, sin beta y_perp/||y_perp||), so that
// h(y) = ||y|| cos(max(0, phi - beta)) = y_1 cos beta + ||y_perp|| sin beta outside K. This holds
// for every phi up to pi, so the cap's support is negative for y in the polar cone; where
// positive it equals ||Pi_K(y)||, the support of K cut by the unit ball.
inline double cone_cap_support(Vec f, Int p, Int d, Int o, Vec wit, Int w) {
    const CapDirection cd = cap_direction(f, p, d);
    const Int n = cd.n;
    const double mu = cd.mu, y1 = cd.y1, q = cd.q, ny = cd.ny;
    double h;
    if (y1 >= 0.0 && q <= mu * y1) {
        // y in K: the cap's point is y itself, normalized (e_1 for y = 0). The sign test is
        // not redundant: with mu = 0 and q = 0, q <= mu y1 holds for y1 < 0 too (0 <= -0.0)
        if (ny > 0.0) {
            for (Int a = 0; a < n; ++a) f[o + a] = f[d + a] / ny;
        } else {
            f[o] = 1.0;
            for (Int a = 1; a < n; ++a) f[o + a] = 0.0;
        }
        h = ny;
    } else {
        const double cb = 1.0 / std::sqrt(1.0 + mu * mu);
        const double sb = mu * cb;
        f[o] = cb;
        if (q > 0.0) {
            for (Int a = 1; a < n; ++a) f[o + a] = sb * f[d + a] / q;
        } else {
            // y = -|y| e_1: every boundary ray is equally close; take the one along e_2
            for (Int a = 1; a < n; ++a) f[o + a] = 0.0;
            if (n > 1) f[o + 1] = sb;
        }
        h = y1 * cb + q * sb;
    }
    for (Int a = 0; a < n; ++a) wit[w + 1 + a] = f[o + a];
    return h;
}

// The pull of an affine node x -> M x + t, M (m, n) row-major at f[M0:]: the child's direction
// M^T u (to f[dc:]) from the node's (at f[du:]). Compiled for sizes FM, FN (loops of known length
// unroll), or for any when they are 0 (then m, n are given).
template <int FM = 0, int FN = 0>
[[gnu::always_inline]] inline void affine_pull(Vec f, Int M0, Int du, Int dc, Int m_ = FM,
                                               Int n_ = FN) {
    const Int m = FM > 0 ? FM : m_;
    const Int n = FN > 0 ? FN : n_;
    for (Int b = 0; b < n; ++b) {
        double s = 0.0;
        for (Int a = 0; a < m; ++a) s += f[M0 + a * n + b] * f[du + a];
        f[dc + b] = s;
    }
}

}  // namespace kernel

namespace kernel_detail {

// The push of an affine node: its point M x + t (t at f[M0 + m n:]) to f[oi:] from the child's
// at f[oc:]. Sizes as affine_pull.
template <int FM = 0, int FN = 0>
[[gnu::always_inline]] inline void affine_push(Vec f, Int M0, Int oc, Int oi, Int m_ = FM,
                                               Int n_ = FN) {
    const Int m = FM > 0 ? FM : m_;
    const Int n = FN > 0 ? FN : n_;
    for (Int a = 0; a < m; ++a) {
        double s = f[M0 + m * n + a];
        for (Int b = 0; b < n; ++b) s += f[M0 + a * n + b] * f[oc + b];
        f[oi + a] = s;
    }
}

// The value of an ellipsoid leaf {c + S x : ||x|| <= 1} (parameters n, k, c, S at f[p:]):
// h = c^T u + ||S^T u||, leaving S^T u in the witness slot wit[w + 1:]. Compiled for sizes
// FN, FK (the contact wrench sets of eq. (14) and 3-D bodies: loops of known length unroll, about
// four times faster), or for any when they are 0.
template <int FN = 0, int FK = 0>
[[gnu::always_inline]] inline double ellipsoid_value(Vec f, Int p, Int d, Vec wit, Int w,
                                                     Int n_ = FN, Int kk_ = FK) {
    const Int n = FN > 0 ? FN : n_;
    const Int kk = FK > 0 ? FK : kk_;
    const Int s0 = p + 2 + n;
    double nrm2 = 0.0;
    for (Int b = 0; b < kk; ++b) {
        double y = 0.0;
        for (Int a = 0; a < n; ++a) y += f[s0 + a * kk + b] * f[d + a];
        wit[w + 1 + b] = y;
        nrm2 += y * y;
    }
    double h = std::sqrt(nrm2);
    for (Int a = 0; a < n; ++a) h += f[p + 2 + a] * f[d + a];
    return h;
}

// The point of an ellipsoid leaf from what ellipsoid_value left in the witness slot:
// x = S^T u / ||S^T u|| (the pre-image on the unit ball) into the slot, c + S x to f[o:].
template <int FN = 0, int FK = 0>
[[gnu::always_inline]] inline void ellipsoid_point(Vec f, Int p, Int o, Vec wit, Int w,
                                                   Int n_ = FN, Int kk_ = FK) {
    const Int n = FN > 0 ? FN : n_;
    const Int kk = FK > 0 ? FK : kk_;
    const Int s0 = p + 2 + n;
    double nrm2 = 0.0;
    for (Int b = 0; b < kk; ++b) nrm2 += wit[w + 1 + b] * wit[w + 1 + b];
    const double inv = nrm2 > 0.0 ? 1.0 / std::sqrt(nrm2) : 0.0;
    for (Int b = 0; b < kk; ++b) wit[w + 1 + b] *= inv;
    for (Int a = 0; a < n; ++a) {
        double s = f[p + 2 + a];
        for (Int b = 0; b < kk; ++b) s += f[s0 + a * kk + b] * wit[w + 1 + b];
        f[o + a] = s;
    }
}

// (h, x, y, z) of a truncated cone
struct ConeSupport {
    double h;
    double x;
    double y;
    double z;
};

// (h, x, y, z) of a truncated cone (the hull of two coaxial disks; parameters rb, rt, height at
// f[p:]) in direction u, its point written to its witness slot wit[w + 1:].
[[gnu::always_inline]] inline ConeSupport truncated_cone(Vec f, Int p, Int w, Vec wit, double ux,
                                                         double uy, double uz) {
    const double rb = f[p];
    const double rt = f[p + 1];
    const double hz = 0.5 * f[p + 2];
    const double q = std::sqrt(ux * ux + uy * uy);
    const double h_top = hz * uz + rt * q;
    const double h_bot = -hz * uz + rb * q;
    double rad, z, h;
    if (h_top >= h_bot) {
        rad = rt;
        z = hz;
        h = h_top;
    } else {
        rad = rb;
        z = -hz;
        h = h_bot;
    }
    const double x = q > 0.0 ? rad * ux / q : 0.0;
    const double y = q > 0.0 ? rad * uy / q : 0.0;
    wit[w + 1] = x;
    wit[w + 2] = y;
    wit[w + 3] = z;
    return {h, x, y, z};
}

// h of one leaf of kind k: parameters at f[p:], direction at f[d:d + dim]. Writes what the
// leaf's point needs to its witness slot wit[w + 1:] (a polytope's vertex index, an ellipsoid's
// S^T u); the cheap leaves write their point to f[o:o + dim] too.
[[gnu::always_inline]] inline double leaf_value(Int k, Vec f, Int p, Int d, Int o, Vec wit,
                                                Int w) {
    if (k == POLYTOPE) {
        const Int m = static_cast<Int>(f[p]);
        const Int n = static_cast<Int>(f[p + 1]);
        double best = -INF;
        Int arg = 0;
        for (Int j = 0; j < m; ++j) {
            double s = 0.0;
            for (Int a = 0; a < n; ++a) s += f[p + 2 + j * n + a] * f[d + a];
            if (s > best) {
                best = s;
                arg = j;
            }
        }
        wit[w + 1] = static_cast<double>(arg);
        return best;
    }
    if (k == ELLIPSOID) {
        const Int n = static_cast<Int>(f[p]);
        const Int kk = static_cast<Int>(f[p + 1]);
        if (n == 6 && kk == 3) return ellipsoid_value<6, 3>(f, p, d, wit, w);
        if (n == 3 && kk == 3) return ellipsoid_value<3, 3>(f, p, d, wit, w);
        return ellipsoid_value(f, p, d, wit, w, n, kk);
    }
    if (k == BOX) {
        const Int n = static_cast<Int>(f[p]);
        double h = 0.0;
        for (Int a = 0; a < n; ++a) {
            const double half = f[p + 1 + a];
            const double x = f[d + a] >= 0.0 ? half : -half;
            f[o + a] = x;
            h += x * f[d + a];
            wit[w + 1 + a] = x;
        }
        return h;
    }
    if (k == CONE_CAP) return kernel::cone_cap_support(f, p, d, o, wit, w);
    const ConeSupport c = truncated_cone(f, p, w, wit, f[d], f[d + 1], f[d + 2]);
    f[o] = c.x;
    f[o + 1] = c.y;
    f[o + 2] = c.z;
    return c.h;
}

// s of one leaf that produced the support point, from what leaf_value left in its witness slot,
// to f[o:o + dim]. Only the leaves a hull chose get here, so a hull of m ellipsoids pays for one
// point, not m.
[[gnu::always_inline]] inline void leaf_point(Int k, Vec f, Int p, Int o, Vec wit, Int w) {
    if (k == POLYTOPE) {
        const Int n = static_cast<Int>(f[p + 1]);
        const Int v0 = p + 2 + static_cast<Int>(wit[w + 1]) * n;
        for (Int a = 0; a < n; ++a) f[o + a] = f[v0 + a];
    } else if (k == ELLIPSOID) {
        const Int n = static_cast<Int>(f[p]);
        const Int kk = static_cast<Int>(f[p + 1]);
        if (n == 6 && kk == 3)
            ellipsoid_point<6, 3>(f, p, o, wit, w);
        else if (n == 3 && kk == 3)
            ellipsoid_point<3, 3>(f, p, o, wit, w);
        else
            ellipsoid_point(f, p, o, wit, w, n, kk);
    }
}

// `support` for the plans ELLIPSOID_HULL (K = 3: soft fingers) and ELLIPSE_HULL (K = 2: point
// contacts): every child of the root hull is an ellipsoid {c + S x : ||x|| <= 1} in R^6 with S
// (6, K), bare or under an embedding (x -> (0, x) + t; an
// origin embedding's value is t^T u + max(0, h), the origin winning a tie). One loop over the
// children with the direction read from u and the best child's S^T u held in registers, then one
// point: the four passes' value, point and witnesses (the same flags and ties), at 112 ns a call
// on the ingot's W_Linf lift against 189, 89 against 127 on its W_L1. The passes pay for what a
// general tree needs: each node's kind and offsets are read in every pass, and its direction,
// value and point go through the scratch part of `floats`. `root`: the hull's node (1 under a
// projection).
template <int K>
inline double ellipsoid_hull(IVec ints, Vec f, Vec u, Vec point, Vec wit, Int root = 0) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const Int n0 = ints[DIM + root];
    const Int lead = n0 - 6;   // an embedding's leading entries (the lift's contact coordinates)
    const Int first = CHILDREN + ints[CSTART + root];
    double best = -INF;
    Int arg = ints[first];
    bool origin = false;       // the best child is an origin embedding's origin
    double bx[K] = {};
    for (Int c = 0; c < ints[CCOUNT + root]; ++c) {
        const Int i = ints[first + c];
        const Int k = ints[KIND + i];
        const Int leaf = k < HULL ? i : ints[CHILDREN + ints[CSTART + i]];
        const Int p = ints[PSTART + leaf] + 2;   // c (6), then S (6, K) row-major
        double cu = 0.0;
        double x[K] = {};
        for (Int a = 0; a < 6; ++a) {
            const double ua = u[lead + a];
            cu += f[p + a] * ua;
            for (Int b = 0; b < K; ++b) x[b] += f[p + 6 + K * a + b] * ua;
        }
        const Int w = ints[WSTART + leaf];
        wit[w] = 0.0;
        double xx = 0.0;
        for (Int b = 0; b < K; ++b) {
            wit[w + 1 + b] = x[b];
            xx += x[b] * x[b];
        }
        // c^T u apart: the sum waits on the square root once, not six times
        double h = cu + std::sqrt(xx);
        bool at_origin = false;
        if (k >= HULL) {
            const Int p0 = ints[PSTART + i];
            double tu = 0.0;
            for (Int a = 0; a < static_cast<Int>(f[p0 + 2]); ++a) tu += f[p0 + 3 + a] * u[a];
            if (k == ORIGIN_EMBED) {
                const Int wo = ints[WSTART + i];
                wit[wo] = 0.0;
                wit[wo + 1] = 0.0;
                if (!(h > 0.0)) {
                    h = 0.0;
                    at_origin = true;
                }
            }
            h += tu;
        }
        if (h > best) {
            best = h;
            arg = i;
            origin = at_origin;
            for (Int b = 0; b < K; ++b) bx[b] = x[b];
        }
    }
    const Int k = ints[KIND + arg];
    if (k >= HULL) {
        const Int t0 = ints[PSTART + arg] + 3;
        for (Int a = 0; a < n0; ++a) point[a] = f[t0 + a];
    } else {
        for (Int a = 0; a < n0; ++a) point[a] = 0.0;
    }
    if (origin) {
        wit[ints[WSTART + arg]] = 1.0;
        return best;
    }
    double nrm2 = 0.0;
    for (Int b = 0; b < K; ++b) nrm2 += bx[b] * bx[b];
    const double inv = nrm2 > 0.0 ? 1.0 / std::sqrt(nrm2) : 0.0;
    const Int leaf = k < HULL ? arg : ints[CHILDREN + ints[CSTART + arg]];
    const Int w = ints[WSTART + leaf];
    wit[w] = 1.0;
    for (Int b = 0; b < K; ++b) {
        bx[b] *= inv;
        wit[w + 1 + b] = bx[b];
    }
    const Int p = ints[PSTART + leaf] + 2;
    for (Int a = 0; a < 6; ++a) {
        double s = f[p + a];
        for (Int b = 0; b < K; ++b) s += f[p + 6 + K * a + b] * bx[b];
        point[lead + a] += s;
    }
    return best;
}

// `support` for the plans PROJECTED_ELLIPSOID_HULL and PROJECTED_ELLIPSE_HULL: the root maps
// x -> M x + t over node 1, a hull that ellipsoid_hull takes (a rank-deficient grasp's wrench
// set in its span, M = Q^T D). M^T u goes to node 1's direction and its point to node 1's
// point, as in the passes, where an affine node adds no witness: h_A(M^T u) + t^T u and
// M s + t, summed in the passes' order.
template <int K>
inline double projected_ellipsoid_hull(IVec ints, Vec f, Vec u, Vec point, Vec wit) {
    const Blocks B = blocks(ints[0]);
    const Int m = ints[B.DIM];
    const Int nc = ints[B.DIM + 1];
    const Int M0 = ints[B.PSTART] + 2;   // M (m, nc) row-major, then t (m)
    const Vec v = f.segment(ints[B.DSTART + 1], nc);
    const Vec s = f.segment(ints[B.OSTART + 1], nc);
    for (Int b = 0; b < nc; ++b) {
        double x = 0.0;
        for (Int a = 0; a < m; ++a) x += f[M0 + a * nc + b] * u[a];
        v[b] = x;
    }
    double h = ellipsoid_hull<K>(ints, f, v, s, wit, 1);
    const Int t0 = M0 + m * nc;
    for (Int a = 0; a < m; ++a) h += f[t0 + a] * u[a];
    for (Int a = 0; a < m; ++a) {
        double x = f[t0 + a];
        for (Int b = 0; b < nc; ++b) x += f[M0 + a * nc + b] * s[b];
        point[a] = x;
    }
    return h;
}

// `support` for the plans ORIGIN_ELLIPSOID_SUM (K = 3) and ORIGIN_ELLIPSE_SUM (K = 2): W_Linf,
// a root sum of hulls CH({0} U E_i), each hull's children the origin (a polytope of one vertex)
// and then an ellipsoid {c + S x : ||x|| <= 1} in R^6 with S (6, K). A contact adds
// max(0, h_{E_i}(u)) and its point, or nothing (the origin wins a tie, as the hull's first
// child); the same arithmetic, in the same order, as the passes' leaf values and points.
template <int K>
inline double origin_ellipsoid_sum(IVec ints, Vec f, Vec u, Vec point, Vec wit) {
    const Blocks B = blocks(ints[0]);
    const Int first = B.CHILDREN + ints[B.CSTART];
    double h = 0.0;
    double pt[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (Int c = 0; c < ints[B.CCOUNT]; ++c) {
        const Int c0 = B.CHILDREN + ints[B.CSTART + ints[first + c]];
        const Int wo = ints[B.WSTART + ints[c0]];
        const Int e = ints[c0 + 1];
        const Int we = ints[B.WSTART + e];
        const Int p = ints[B.PSTART + e] + 2;   // c (6), then S (6, K) row-major
        double y[K];
        double nrm2 = 0.0;
        for (Int b = 0; b < K; ++b) {
            double s = 0.0;
            for (Int a = 0; a < 6; ++a) s += f[p + 6 + K * a + b] * u[a];
            y[b] = s;
            nrm2 += s * s;
        }
        double he = std::sqrt(nrm2);
        for (Int a = 0; a < 6; ++a) he += f[p + a] * u[a];
        wit[wo + 1] = 0.0;
        if (!(he > 0.0)) {
            wit[wo] = 1.0;
            wit[we] = 0.0;
            for (Int b = 0; b < K; ++b) wit[we + 1 + b] = y[b];
            continue;
        }
        wit[wo] = 0.0;
        wit[we] = 1.0;
        const double inv = nrm2 > 0.0 ? 1.0 / std::sqrt(nrm2) : 0.0;
        for (Int b = 0; b < K; ++b) {
            y[b] *= inv;
            wit[we + 1 + b] = y[b];
        }
        for (Int a = 0; a < 6; ++a) {
            double s = f[p + a];
            for (Int b = 0; b < K; ++b) s += f[p + 6 + K * a + b] * y[b];
            pt[a] += s;
        }
        h += he;
    }
    for (Int a = 0; a < 6; ++a) point[a] = pt[a];
    return h;
}

// `support` for the plan POSED_SUM: the root sums children x -> M x + t in R^3, each over a
// 3-D leaf. One loop over the children with the direction M^T u and the leaf's point in
// registers. Ellipsoids with 3 axes and truncated cones are evaluated in registers; other leaves
// (boxes, polytopes) take the passes' leaf code through the scratch part of `floats`. The
// ellipsoid's arithmetic is ellipsoid_value<3, 3> and ellipsoid_point<3, 3> fused, because every
// leaf of a sum is active: the passes split them so that a hull pays for its chosen child's
// point only.
inline double posed_sum(IVec ints, Vec f, Vec u, Vec point, Vec wit) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const double u0 = u[0];
    const double u1 = u[1];
    const double u2 = u[2];
    const Int first = CHILDREN + ints[CSTART];
    double h = 0.0;
    double p0 = 0.0, p1 = 0.0, p2 = 0.0;
    for (Int c = 0; c < ints[CCOUNT]; ++c) {
        const Int i = ints[first + c];
        const Int M = ints[PSTART + i] + 2;   // M (3, 3) row-major, then t
        const double v0 = f[M] * u0 + f[M + 3] * u1 + f[M + 6] * u2;
        const double v1 = f[M + 1] * u0 + f[M + 4] * u1 + f[M + 7] * u2;
        const double v2 = f[M + 2] * u0 + f[M + 5] * u1 + f[M + 8] * u2;
        const Int leaf = ints[CHILDREN + ints[CSTART + i]];
        const Int k = ints[KIND + leaf];
        const Int p = ints[PSTART + leaf];
        const Int w = ints[WSTART + leaf];
        wit[w] = 1.0;
        double hl, x, y, z;
        if (k == ELLIPSOID && f[p + 1] == 3.0) {
            const Int s = p + 5;   // n, k, c (3), then S (3, 3) row-major
            double y0 = f[s] * v0 + f[s + 3] * v1 + f[s + 6] * v2;
            double y1 = f[s + 1] * v0 + f[s + 4] * v1 + f[s + 7] * v2;
            double y2 = f[s + 2] * v0 + f[s + 5] * v1 + f[s + 8] * v2;
            const double nrm = std::sqrt(y0 * y0 + y1 * y1 + y2 * y2);
            hl = f[p + 2] * v0 + f[p + 3] * v1 + f[p + 4] * v2 + nrm;
            const double inv = nrm > 0.0 ? 1.0 / nrm : 0.0;
            y0 *= inv;
            y1 *= inv;
            y2 *= inv;
            wit[w + 1] = y0;
            wit[w + 2] = y1;
            wit[w + 3] = y2;
            x = f[p + 2] + f[s] * y0 + f[s + 1] * y1 + f[s + 2] * y2;
            y = f[p + 3] + f[s + 3] * y0 + f[s + 4] * y1 + f[s + 5] * y2;
            z = f[p + 4] + f[s + 6] * y0 + f[s + 7] * y1 + f[s + 8] * y2;
        } else if (k == TRUNCATED_CONE) {
            const ConeSupport cs = truncated_cone(f, p, w, wit, v0, v1, v2);
            hl = cs.h;
            x = cs.x;
            y = cs.y;
            z = cs.z;
        } else {
            const Int d = ints[DSTART + leaf];
            const Int o = ints[OSTART + leaf];
            f[d] = v0;
            f[d + 1] = v1;
            f[d + 2] = v2;
            hl = leaf_value(k, f, p, d, o, wit, w);
            leaf_point(k, f, p, o, wit, w);
            x = f[o];
            y = f[o + 1];
            z = f[o + 2];
        }
        const Int t = M + 9;
        h += hl + f[t] * u0 + f[t + 1] * u1 + f[t + 2] * u2;
        p0 += f[t] + f[M] * x + f[M + 1] * y + f[M + 2] * z;
        p1 += f[t + 1] + f[M + 3] * x + f[M + 4] * y + f[M + 5] * z;
        p2 += f[t + 2] + f[M + 6] * x + f[M + 7] * y + f[M + 8] * z;
    }
    point[0] = p0;
    point[1] = p1;
    point[2] = p2;
    return h;
}

}  // namespace kernel_detail

// h_A(u) (returned) and s_A(u) (into point) of eq. (2); the witness goes into wit. Node i reads
// its direction at f[dstart:], writes its point to f[ostart:ostart + dim] and its value to
// f[ostart + dim].
double support(IVec ints, Vec f, Vec u, Vec point, Vec wit) {
    using namespace kernel_detail;
    const Int plan = ints[ints.n - 1];
    if (plan == ELLIPSOID_HULL) return ellipsoid_hull<3>(ints, f, u, point, wit);
    if (plan == ELLIPSE_HULL) return ellipsoid_hull<2>(ints, f, u, point, wit);
    if (plan == PROJECTED_ELLIPSOID_HULL)
        return projected_ellipsoid_hull<3>(ints, f, u, point, wit);
    if (plan == PROJECTED_ELLIPSE_HULL) return projected_ellipsoid_hull<2>(ints, f, u, point, wit);
    if (plan == POSED_SUM) return posed_sum(ints, f, u, point, wit);
    if (plan == ORIGIN_ELLIPSOID_SUM) return origin_ellipsoid_sum<3>(ints, f, u, point, wit);
    if (plan == ORIGIN_ELLIPSE_SUM) return origin_ellipsoid_sum<2>(ints, f, u, point, wit);
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const Int d0 = ints[DSTART];
    const Int n0 = ints[DIM];
    for (Int a = 0; a < n0; ++a) f[d0 + a] = u[a];
    // directions flow down; the children of a hull or a sum read their parent's
    for (Int i = 0; i < nn; ++i) {
        if (ints[KIND + i] != AFFINE) continue;
        const Int di = ints[DSTART + i];
        const Int ni = ints[DIM + i];
        const Int ch = ints[CHILDREN + ints[CSTART + i]];
        const Int dc = ints[DSTART + ch];
        const Int p0 = ints[PSTART + i];
        const Int nc = ints[DIM + ch];
        if (ni == 3 && nc == 3)
            kernel::affine_pull<3, 3>(f, p0 + 2, di, dc);
        else if (ni == 6 && nc == 4)
            kernel::affine_pull<6, 4>(f, p0 + 2, di, dc);
        else
            kernel::affine_pull(f, p0 + 2, di, dc, ni, nc);
    }
    // values flow up: h of every node; a hull keeps its best child
    for (Int i = nn - 1; i >= 0; --i) {
        const Int k = ints[KIND + i];
        const Int oi = ints[OSTART + i];
        const Int ni = ints[DIM + i];
        double h;
        if (k < HULL) {
            h = leaf_value(k, f, ints[PSTART + i], ints[DSTART + i], oi, wit, ints[WSTART + i]);
        } else if (k == HULL) {
            h = -INF;
            Int arg = ints[CHILDREN + ints[CSTART + i]];
            for (Int c = 0; c < ints[CCOUNT + i]; ++c) {
                const Int ch = ints[CHILDREN + ints[CSTART + i] + c];
                const double hc = f[ints[OSTART + ch] + ni];
                if (hc > h) {
                    h = hc;
                    arg = ch;
                }
            }
            ints[CHOICE + i] = arg;
        } else if (k == SUM) {
            h = 0.0;
            for (Int c = 0; c < ints[CCOUNT + i]; ++c)
                h += f[ints[OSTART + ints[CHILDREN + ints[CSTART + i] + c]] + ni];
        } else {
            // h_{MA + t}(u) = h_A(M^T u) + t^T u; an embedding's t follows its span, no M
            const Int ch = ints[CHILDREN + ints[CSTART + i]];
            const Int nc = ints[DIM + ch];
            const Int p0 = ints[PSTART + i];
            Int t0, span;
            if (k == AFFINE) {
                t0 = p0 + 2 + ni * nc;
                span = ni;
            } else {
                t0 = p0 + 3;
                span = static_cast<Int>(f[p0 + 2]);
            }
            const Int di = ints[DSTART + i];
            h = f[ints[OSTART + ch] + nc];
            if (k == ORIGIN_EMBED) {
                // the origin wins a tie, as the first child of the hull it stands for
                if (h > 0.0) {
                    ints[CHOICE + i] = ch;
                } else {
                    h = 0.0;
                    ints[CHOICE + i] = -1;
                }
            }
            for (Int a = 0; a < span; ++a) h += f[t0 + a] * f[di + a];
        }
        f[oi + ni] = h;
    }
    // flag the leaves that produced the point: every child of a sum, the chosen child of a hull
    ints[ACTIVE] = 1;
    for (Int i = 0; i < nn; ++i) {
        const Int k = ints[KIND + i];
        if (k < HULL) {
            wit[ints[WSTART + i]] = static_cast<double>(ints[ACTIVE + i]);
            continue;
        }
        if (k == ORIGIN_EMBED) {
            const Int origin = ints[CHOICE + i] < 0 ? ints[ACTIVE + i] : 0;
            const Int w = ints[WSTART + i];
            wit[w] = static_cast<double>(origin);
            wit[w + 1] = 0.0;
            ints[ACTIVE + ints[CHILDREN + ints[CSTART + i]]] = ints[ACTIVE + i] - origin;
            continue;
        }
        for (Int c = 0; c < ints[CCOUNT + i]; ++c) {
            const Int ch = ints[CHILDREN + ints[CSTART + i] + c];
            ints[ACTIVE + ch] = (k != HULL || ch == ints[CHOICE + i]) ? ints[ACTIVE + i] : 0;
        }
    }
    // points flow up through the flagged nodes only
    for (Int i = nn - 1; i >= 0; --i) {
        if (ints[ACTIVE + i] == 0) continue;
        const Int k = ints[KIND + i];
        const Int oi = ints[OSTART + i];
        const Int ni = ints[DIM + i];
        if (k < HULL) {
            leaf_point(k, f, ints[PSTART + i], oi, wit, ints[WSTART + i]);
        } else if (k == HULL) {
            const Int src = ints[OSTART + ints[CHOICE + i]];
            for (Int a = 0; a < ni; ++a) f[oi + a] = f[src + a];
        } else if (k == SUM) {
            for (Int a = 0; a < ni; ++a) f[oi + a] = 0.0;
            for (Int c = 0; c < ints[CCOUNT + i]; ++c) {
                const Int oc = ints[OSTART + ints[CHILDREN + ints[CSTART + i] + c]];
                for (Int a = 0; a < ni; ++a) f[oi + a] += f[oc + a];
            }
        } else {
            const Int ch = ints[CHILDREN + ints[CSTART + i]];
            const Int oc = ints[OSTART + ch];
            const Int nc = ints[DIM + ch];
            const Int p0 = ints[PSTART + i];
            if (k == EMBED || k == ORIGIN_EMBED) {
                const Int lead = ni - nc;
                for (Int a = 0; a < lead; ++a) f[oi + a] = f[p0 + 3 + a];
                if (ints[CHOICE + i] < 0 && k == ORIGIN_EMBED) {
                    for (Int a = 0; a < nc; ++a) f[oi + lead + a] = f[p0 + 3 + lead + a];
                } else {
                    for (Int a = 0; a < nc; ++a)
                        f[oi + lead + a] = f[oc + a] + f[p0 + 3 + lead + a];
                }
            } else if (ni == 3 && nc == 3) {
                affine_push<3, 3>(f, p0 + 2, oc, oi);
            } else if (ni == 6 && nc == 4) {
                affine_push<6, 4>(f, p0 + 2, oc, oi);
            } else {
                affine_push(f, p0 + 2, oc, oi, ni, nc);
            }
        }
    }
    const Int o0 = ints[OSTART];
    for (Int a = 0; a < n0; ++a) point[a] = f[o0 + a];
    return f[o0 + n0];
}

}  // namespace gf
