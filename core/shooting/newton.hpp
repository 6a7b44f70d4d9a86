#pragma once

#include <optional>

#include "api.hpp"
#include "geometry/piece.hpp"

// A second-order finish for ray shooting: Newton's method on the pieces that form the exit face.
//
// Ray shooting is the convex program t* = min { h_A(u) : u^T r = 1 } (z_A(r) = t* r; IE's facet
// normals are its cutting planes, which is why IE converges only linearly on curved sets). Near
// the answer h_A is the maximum of the supports h_p of a few smooth pieces (piece.hpp) and the
// minimum is the root of the KKT system, in u, the piece weights lam_p, t and tau:
//
//     sum_p lam_p s_p(u) + sum_l T_l y_l = t r,   h_p(u) = tau (each p),   T_l^T u = 0 (each l),
//     sum_p lam_p = 1,   u^T r = 1
//
// (the first line is z_A(r) = t r as the convex combination of eq. 2's support points that Z_A(r)
// holds; the second puts every piece's point on one hyperplane with normal u). A flat leaf l of
// piece p (its whole body is in the face, e.g. a soft finger whose friction is not saturated) adds
// the point T_l x_l, x_l free, through y_l = lam_p x_l, and T_l^T u = 0. The Jacobian needs the
// pieces' curvatures J_p = ds_p/du; Newton converges quadratically from the facet that IE's
// cutting planes have brought close. The pieces are read off the witnesses of the facet's
// vertices (a leaf is flat where ||T^T u|| is tiny); a piece whose weight turns negative leaves
// the system, one that the final check finds sticking out joins it, a smooth leaf that meets its
// kink turns flat, and a flat leaf whose point leaves the body turns smooth.
//
// Nothing of Newton's is trusted: the points s_p(u) are points of A, so their convex combination
// z (weights re-solved by least squares on the final points) is in A and on the ray to rounding
// (Fig. 3b's rule); one call of the full support map at u gives the hyperplane H(u, s_A(u)) that
// bounds z_A(r) from outside. When the bracket is wider than eps, or the system is singular (a
// polytope face with fewer than n vertices, a flat face whose normal sits on a piece's kink), the
// finish fails and IE goes on.

namespace gf {

namespace newton_detail {

// Newton steps of one attempt, over all changes of the piece set
constexpr Int NEWTON_STEPS = 12;
// ||du|| <= STEP_TOL ||u||: one more step leaves an error far below eps
constexpr double STEP_TOL = 1e-7;
// the ellipsoid path tries its certificate once ||du|| <= EARLY_STEP ||u||: the next step's
// error, ~||du||^2, is then far below eps, and a certificate that fails asks for STEP_TOL
constexpr double EARLY_STEP = 1e-5;
// a step longer than DIVERGED times the last (same pieces) ends the ellipsoid path's try (0.5
// ended tries from gap ~5e-3 on soft fingers that went on to converge: 0.9 takes them)
constexpr double DIVERGED = 0.9;
// ||T^T u|| <= FLAT_RHO ||T|| ||u|| on the facet's normal: the leaf is flat,
constexpr double FLAT_RHO = 1e-3;
// or its facet vertices' mean local point is this far inside (squared)
constexpr double FLAT_SPREAD = 0.5;
// a corner finish's rank tolerance, relative to the KKT matrix's largest entry: rounding in u and
// the curvatures of the pieces, amplified where the normal is far from unique
constexpr double CORNER_RANK = 1e-9;
constexpr Int MAX_CHANGES = 6;       // changes of the piece set in one attempt

// (count of flat leaves, entries of y) of `flats`
struct Flats {
    Int nf;
    Int ny;
};

// The flat leaves of the pieces: their piece, node, offset in y and size; T's columns and
// y = lam_p x. count -1 when T has no room for them.
inline Flats flats(IVec ints, Vec f, Mat PW, Vec lam, Int m, Mat T, Vec y, IVec fpiece,
                   IVec fleaf, IVec foff, IVec fq, Mat C, Mat C2) {
    const Int nn = ints[0];
    const Blocks B = blocks(nn);
    Int nf = 0;
    Int ny = 0;
    for (Int p = 0; p < m; ++p) {
        for (Int i = 0; i < nn; ++i) {
            if (ints[B.KIND + i] >= HULL) continue;
            const Int w = ints[B.WSTART + i];
            if (PW(p, w) != piece::FLAT) continue;
            const Int q = piece::flat_columns(ints, f, i, T, ny, C, C2);
            if (q < 0) return {-1, ny};
            for (Int b = 0; b < q; ++b) y[ny + b] = lam[p] * PW(p, w + 1 + b);
            fpiece[nf] = p;
            fleaf[nf] = i;
            foff[nf] = ny;
            fq[nf] = q;
            nf += 1;
            ny += q;
        }
    }
    return {nf, ny};
}

// Turn a leaf of piece p flat with local point x (a disk keeps its side).
inline void mark_flat(IVec ints, Vec f, Mat PW, Int p, Int leaf, Vec x) {
    const Int nn = ints[0];
    const Blocks B = blocks(nn);
    const Int w = ints[B.WSTART + leaf];
    PW(p, w) = piece::FLAT;
    const Int q = piece::local_size(ints[B.KIND + leaf], f, ints[B.PSTART + leaf]);
    for (Int b = 0; b < q; ++b) PW(p, w + 1 + b) = x[b];
}

// Move the basic solution dx of a rank-deficient system (`solve_basic`'s factors in lu, pcol)
// within the system's null space so that u + du is shortest. mats (3 N, N) and vecs (3, N) are
// scratch.
inline void shortest_u(Vec u, Int n, Int N, Int rank, Mat lu, IVec pcol, Vec dx, Mat mats,
                       Mat vecs) {
    const Int Nm = mats.rows / 3;
    const Mat Z = mats.rows_range(0, Nm);
    const Mat D = mats.rows_range(Nm, 2 * Nm);
    const Mat work = mats.rows_range(2 * Nm, 3 * Nm);
    const Vec x = vecs.row(0);
    const Vec rhs = vecs.row(1);
    const Vec wrhs = vecs.row(2);
    const Int q = N - rank;
    basic_null_space(lu, pcol, N, rank, Z, x);
    for (Int i = 0; i < n; ++i) {
        for (Int e = 0; e < q; ++e) D(i, e) = Z(i, e);
        rhs[i] = -(u[i] + dx[i]);
    }
    // false when some null direction leaves u alone (free weights): the basic solution stands
    if (lstsq(D, n, q, rhs, x, 0, work, wrhs)) {
        for (Int i = 0; i < N; ++i)
            for (Int e = 0; e < q; ++e) dx[i] += Z(i, e) * x[e];
    }
}

// One Newton step of the KKT system (header comment) into dx = (du, dlam, dy, dt, dtau), by LU
// with partial pivoting, or a basic solution (complete pivoting) where the weights are not unique
// (two flat leaves that share a direction: two fingers on one face whose friction split is
// free). JJ: the pieces' Jacobians, (m n, n); sm: (m, n) work for the pieces' smooth parts.
// corner: every step by complete pivoting, the shortest u (newton_finish); mats, vecs:
// `shortest_u`'s scratch.
inline bool solve_kkt(Vec r, Vec u, double t, double tau, Vec lam, Mat S, Mat JJ, Int m, Mat T,
                      Vec y, Int nf, Int ny, IVec fpiece, IVec foff, IVec fq, Mat sm, Mat K,
                      Mat lu, IVec prow, IVec pcol, Vec rhs, Vec dx, bool corner, Mat mats,
                      Mat vecs) {
    const Int n = r.n;
    const Int N = n + m + ny + 2;
    const Int it = n + m + ny;
    for (Int i = 0; i < N; ++i) {
        rhs[i] = 0.0;
        for (Int j = 0; j < N; ++j) K(i, j) = 0.0;
    }
    // the smooth part s_p of each piece's point: S_p less its flat leaves' T x
    for (Int p = 0; p < m; ++p)
        for (Int i = 0; i < n; ++i) sm(p, i) = S(p, i);
    for (Int e = 0; e < nf; ++e) {
        const Int p = fpiece[e];
        if (lam[p] != 0.0) {
            for (Int b = 0; b < fq[e]; ++b) {
                const double xb = y[foff[e] + b] / lam[p];
                for (Int i = 0; i < n; ++i) sm(p, i) -= T(i, foff[e] + b) * xb;
            }
        }
    }
    for (Int i = 0; i < n; ++i) {
        double F = -t * r[i];
        for (Int p = 0; p < m; ++p) {
            F += lam[p] * S(p, i);
            for (Int b = 0; b < n; ++b) K(i, b) += lam[p] * JJ(p * n + i, b);
            K(i, n + p) = sm(p, i);
        }
        for (Int c = 0; c < ny; ++c) K(i, n + m + c) = T(i, c);
        K(i, it) = -r[i];
        rhs[i] = -F;
    }
    for (Int p = 0; p < m; ++p) {
        for (Int b = 0; b < n; ++b) K(n + p, b) = sm(p, b);
        K(n + p, it + 1) = -1.0;
        rhs[n + p] = tau - dot(u, sm.row(p));
    }
    Int row = n + m;
    for (Int c = 0; c < ny; ++c) {
        double s = 0.0;
        for (Int b = 0; b < n; ++b) {
            K(row, b) = T(b, c);
            s += T(b, c) * u[b];
        }
        rhs[row] = -s;
        row += 1;
    }
    double total = 0.0;
    for (Int p = 0; p < m; ++p) {
        K(row, n + p) = 1.0;
        total += lam[p];
    }
    rhs[row] = 1.0 - total;
    for (Int b = 0; b < n; ++b) K(row + 1, b) = r[b];
    rhs[row + 1] = 1.0 - dot(u, r);
    if (corner) {
        const Int rank = solve_basic(K, N, lu, prow, pcol, rhs, dx, CORNER_RANK);
        if (rank < N) shortest_u(u, n, N, rank, lu, pcol, dx, mats, vecs);
        return rank > 0;
    }
    if (lu_factor(K, N, lu, prow)) {
        lu_solve(lu, prow, N, rhs, dx);
        return true;
    }
    return solve_basic(K, N, lu, prow, pcol, rhs, dx) > n;
}

// newton_finish's answer when it gives up: the steps and support calls it spent.
inline NewtonOut failed(double t, double t_up, double h, Int steps, Int calls, Array& nrm,
                        Array& S, Array& lm, Array& WS) {
    return {false, t, t_up, h, 0, steps, calls, std::move(nrm), std::move(S), std::move(lm),
            std::move(WS)};
}


// The ellipsoid finish's limits: stack arrays for sets in up to R^FAST_N whose pieces' shapes have
// up to FAST_N columns (W_Linf's lift of 8 contacts is in R^13)
constexpr Int FAST_N = 14;
// the system's unknowns: u, every weight but the last, t; n + m <= 2n (a piece joins only while
// m < n)
constexpr Int FAST_K = 2 * FAST_N;

// Solve K x = b (K (N, N) in FAST_K-strided rows) by LU with partial pivoting; false when a pivot
// is below 1e-14 of K's largest entry (lu_factor's test). Compiled for NN unknowns, with the
// factors in a compact NN x NN array on the stack and every loop unrolled, or for any N when NN
// is 0, factored in lu (FAST_K-strided).
template <int NN = 0>
inline bool small_solve(const double* K, double* lu, const double* b, double* x, Int N_) {
    const Int N = NN > 0 ? NN : N_;
    constexpr Int LD = NN > 0 ? NN : FAST_K;
    double compact[NN > 0 ? NN * NN : 1];
    double* const a = NN > 0 ? compact : lu;
    double scale = 0.0;
#pragma GCC unroll 16
    for (Int i = 0; i < N; ++i) {
        x[i] = b[i];
#pragma GCC unroll 16
        for (Int j = 0; j < N; ++j) {
            a[i * LD + j] = K[i * FAST_K + j];
            scale = std::max(scale, std::abs(K[i * FAST_K + j]));
        }
    }
    if (scale == 0.0) return false;
#pragma GCC unroll 16
    for (Int c = 0; c < N; ++c) {
        Int p = c;
        double best = std::abs(a[c * LD + c]);
#pragma GCC unroll 16
        for (Int i = c + 1; i < N; ++i) {
            if (std::abs(a[i * LD + c]) > best) {
                best = std::abs(a[i * LD + c]);
                p = i;
            }
        }
        if (best <= 1e-14 * scale) return false;
        if (p != c) {
            for (Int j = c; j < N; ++j) std::swap(a[c * LD + j], a[p * LD + j]);
            std::swap(x[c], x[p]);
        }
        const double inv = 1.0 / a[c * LD + c];
#pragma GCC unroll 16
        for (Int i = c + 1; i < N; ++i) {
            const double g = a[i * LD + c] * inv;
            if (g == 0.0) continue;
#pragma GCC unroll 16
            for (Int j = c + 1; j < N; ++j) a[i * LD + j] -= g * a[c * LD + j];
            x[i] -= g * x[c];
        }
    }
#pragma GCC unroll 16
    for (Int i = N - 1; i >= 0; --i) {
        double s = x[i];
#pragma GCC unroll 16
        for (Int j = i + 1; j < N; ++j) s -= a[i * LD + j] * x[j];
        x[i] = s / a[i * LD + i];
    }
    return true;
}

// small_solve for the sizes of systems on sets in R^6: W_L1's n + m = 7..12 unknowns (m = 1..6
// pieces), W_Linf's sum's 7 and its contacts' states' (sum_finish.hpp: 8..16 on 4 or 5 soft
// fingers)
inline bool small_solve_r6(const double* K, double* lu, const double* b, double* x, Int N) {
    switch (N) {
        case 7: return small_solve<7>(K, lu, b, x, N);
        case 8: return small_solve<8>(K, lu, b, x, N);
        case 9: return small_solve<9>(K, lu, b, x, N);
        case 10: return small_solve<10>(K, lu, b, x, N);
        case 11: return small_solve<11>(K, lu, b, x, N);
        case 12: return small_solve<12>(K, lu, b, x, N);
        case 13: return small_solve<13>(K, lu, b, x, N);
        case 14: return small_solve<14>(K, lu, b, x, N);
        case 15: return small_solve<15>(K, lu, b, x, N);
        case 16: return small_solve<16>(K, lu, b, x, N);
        default: return small_solve(K, lu, b, x, N);
    }
}

// The column count shared by the ellipsoid leaves of a smooth hull (piece::SmoothLeaf: a root
// hull of ellipsoid leaves, W_L1 of soft or point contacts, or of ORIGIN_EMBED nodes over one
// each, W_Linf's lift) in up to R^FAST_N, each with up to FAST_N columns (the pieces the
// ellipsoid finish evaluates in closed form): 0 when their counts differ, -1 for any other set.
// embedded: whether some leaf is under an embedding.
inline Int ellipsoid_hull_columns(IVec ints, Vec f, Int n, bool& embedded) {
    const Int nn = ints[0];
    const Blocks B = blocks(nn);
    embedded = false;
    if (n > FAST_N || ints[B.KIND] != HULL) return -1;
    const Int c0 = B.CHILDREN + ints[B.CSTART];
    Int cols = -1;
    for (Int c = 0; c < ints[B.CCOUNT]; ++c) {
        Int leaf = ints[c0 + c];
        if (ints[B.KIND + leaf] == ORIGIN_EMBED) {
            embedded = true;
            leaf = ints[B.CHILDREN + ints[B.CSTART + leaf]];
        }
        if (ints[B.KIND + leaf] != ELLIPSOID) return -1;
        const Int kk = static_cast<Int>(f[ints[B.PSTART + leaf] + 1]);
        if (kk > FAST_N) return -1;
        cols = cols < 0 || cols == kk ? kk : 0;
    }
    return cols;
}

// The point z = t + (0, c + S x), x = S^T u_c / ||S^T u_c||, of the smooth leaf e (its
// parameters (n_c, k, c, S), u_c the last n_c entries of u, t its embedding's offset or 0) in
// direction u, into z (n), x (k) and sx = S x (n_c); returns (h = u^T z, ||S^T u_c||), or rho 0
// at its kink. An embedding's origin is the point t (rho 1, no curvature). Sizes as
// ellipsoid_piece; FN > 0 only for leaves without an embedding.
struct EllipsePoint {
    double h;
    double rho;
};

// The upper triangle of S S^T (n x n, rows ld apart) for S (n, k) by rows: a smooth piece's
// curvature without its point's part
inline void gram_upper(const double* S, Int n, Int k, double* out, Int ld) {
    for (Int a = 0; a < n; ++a)
        for (Int a2 = a; a2 < n; ++a2) {
            double v = 0.0;
            for (Int b = 0; b < k; ++b) v += S[a * k + b] * S[a2 * k + b];
            out[a * ld + a2] = v;
        }
}
template <int FN = 0, int FK = 0>
[[gnu::always_inline]] inline EllipsePoint ellipsoid_at(Vec f, const piece::SmoothLeaf& e,
                                                        const double* u_, Int n_, double* z,
                                                        double* x, double* sx) {
    using piece_detail::KINK_TOL;
    if (FN == 0 && e.pp < 0) {
        double h = 0.0;
        for (Int a = 0; a < n_; ++a) {
            z[a] = f[e.t0 + a];
            h += z[a] * u_[a];
        }
        return {h, 1.0};
    }
    const Int lead = FN > 0 ? 0 : e.lead;
    const Int n = FN > 0 ? FN : n_ - lead;   // the leaf's own dimension n_c
    const Int p = e.pp;
    const Int kk = FK > 0 ? FK : static_cast<Int>(f[p + 1]);
    const Int s0 = p + 2 + n;
    const double* u = u_ + lead;
    double rho2 = 0.0, ss = 0.0, uu = 0.0, cu = 0.0;
    for (Int a = 0; a < n; ++a) {
        uu += u[a] * u[a];
        cu += f[p + 2 + a] * u[a];
    }
    if (FN == 0 && e.t0 >= 0)
        for (Int a = 0; a < n_; ++a) cu += f[e.t0 + a] * u_[a];
    for (Int b = 0; b < kk; ++b) {
        double y = 0.0;
        for (Int a = 0; a < n; ++a) {
            y += f[s0 + a * kk + b] * u[a];
            ss += f[s0 + a * kk + b] * f[s0 + a * kk + b];
        }
        x[b] = y;
        rho2 += y * y;
    }
    if (rho2 <= KINK_TOL * KINK_TOL * ss * uu) return {cu, 0.0};
    const double rho = std::sqrt(rho2);
    const double inv = 1.0 / rho;
    for (Int b = 0; b < kk; ++b) x[b] *= inv;
    for (Int a = 0; a < n; ++a) {
        double s = 0.0;
        for (Int b = 0; b < kk; ++b) s += f[s0 + a * kk + b] * x[b];
        sx[a] = s;
        z[lead + a] = f[p + 2 + a] + s;
    }
    for (Int a = 0; a < lead; ++a) z[a] = 0.0;
    if (FN == 0 && e.t0 >= 0)
        for (Int a = 0; a < n_; ++a) z[a] += f[e.t0 + a];
    return {cu + rho, rho};
}

// One Newton step on a KKT system K (N, N; FAST_K-strided rows) and its right side, on the
// stack (KktWork): dx by LU, or a basic solution where K is singular (not ok when its rank is
// below n), then u += dx[:n]. basic: K was singular; du = max |dx[:n]|, un = max |u| after.
struct KktWork {
    double K[FAST_K * FAST_K];
    double lu[FAST_K * FAST_K];
    double rhs[FAST_K];
    double dx[FAST_K];
    Int prow[FAST_K];
    Int pcol[FAST_K];
};
struct KktStep {
    bool ok;
    bool basic;
    double du;
    double un;
};
inline KktStep kkt_step(KktWork& w, Int N, double* u, Int n, bool r6) {
    double* const dx = w.dx;
    const bool basic = !(r6 ? small_solve_r6(w.K, w.lu, w.rhs, dx, N)
                            : small_solve(w.K, w.lu, w.rhs, dx, N));
    if (basic && solve_basic(Mat{w.K, N, N, FAST_K}, N, Mat{w.lu, N, N, FAST_K},
                             IVec{w.prow, N}, IVec{w.pcol, N}, Vec{w.rhs, N}, Vec{dx, N}) < n)
        return {false, basic, 0.0, 0.0};
    double du = 0.0, un = 0.0;
    for (Int a = 0; a < n; ++a) {
        u[a] += dx[a];
        du = std::max(du, std::abs(dx[a]));
        un = std::max(un, std::abs(u[a]));
    }
    return {true, basic, du, un};
}

// newton_finish's answer when it gives up, for a set in R^n and witnesses of ws entries
inline NewtonOut ellipsoid_failed(double t, double t_up, double h, Int steps, Int calls, Int n,
                                  Int ws) {
    return {false, t, t_up, h, 0, steps, calls, Array(n), Array(n + 1, n), Array(n + 1),
            Array(n + 1, ws)};
}

// newton_finish on a smooth hull (ellipsoid_hull_columns: W_L1 of soft or point contacts, or
// W_Linf's lift) whose exit face's pieces are all smooth: the KKT system of the header comment
// without tau, flat leaves and the tree walk, in the unknowns u, lam, t,
//
//     sum_p lam_p z_p(u) = t r,   h_p(u) = 1 (each p),   sum_p lam_p = 1,
//
// (h_p = 1 fixes u's scale, and u^T r = 1 / t follows), each piece z_p = t_p + (0, c + S x),
// x = S^T u_c / ||S^T u_c|| (ellipsoid_at), with the curvature (S S^T - (S x)(S x)^T) /
// ||S^T u_c|| in its leaf's coordinates, on the stack.
// Pieces drop and join as in the general path, and the answer is certified as there. nullopt
// hands over to the general path: another set, a flat piece (the general path's test) or a piece
// at its kink. Compiled for sizes FN, FK (soft fingers' (6, 3): the loops
// unroll), or for any when they are 0.
template <int FN = 0, int FK = 0>
inline std::optional<NewtonOut> ellipsoid_finish_sized(IVec ints, Vec f, Vec r, double eps,
                                                       Mat Wt, Vec lam, Int k, Vec normal,
                                                       double t) {
    const Int n = FN > 0 ? FN : r.n;
    const Blocks B = blocks(ints[0]);
    const Int ws = Wt.cols;
    piece::SmoothLeaf leaf[FAST_N];
    double lm[FAST_N + 1];
    double xw[FAST_N * FAST_N];   // per piece: the weighted sum of its vertices' x
    double xs[FAST_N * FAST_N];   // and their plain sum
    Int count[FAST_N];
    Int m = 0;
    for (Int j = 0; j < k; ++j) {
        const piece::SmoothLeaf e = piece::smooth_leaf(ints, Wt.row(j));
        const Int l = e.leaf;
        if (l < 0) return std::nullopt;
        Int p = 0;
        while (p < m && leaf[p].leaf != l) ++p;
        const Int kk = e.pp < 0 ? 0 : static_cast<Int>(f[e.pp + 1]);
        if (p == m) {
            if (m == n) return std::nullopt;
            leaf[m] = e;
            lm[m] = 0.0;
            count[m] = 0;
            for (Int b = 0; b < kk; ++b) xw[m * FAST_N + b] = xs[m * FAST_N + b] = 0.0;
            m += 1;
        }
        const Int w = ints[B.WSTART + l];
        lm[p] += lam[j];
        count[p] += 1;
        for (Int b = 0; b < kk; ++b) {
            xw[p * FAST_N + b] += lam[j] * Wt(j, w + 1 + b);
            xs[p * FAST_N + b] += Wt(j, w + 1 + b);
        }
    }
    const double nr = dot(normal, r);
    if (!(nr > 0.0) || !(t > 0.0)) return std::nullopt;
    double u[FAST_N];
    for (Int i = 0; i < n; ++i) u[i] = normal[i] / (t * nr);
    // flat pieces (the general path's test, in the leaf's coordinates; a piece of weight 0 by
    // its vertices' plain mean)
    for (Int p = 0; p < m; ++p) {
        const Int pp = leaf[p].pp;
        if (FN == 0 && pp < 0) continue;   // an origin
        const Int lead = FN > 0 ? 0 : leaf[p].lead;
        const Int nc = n - lead;
        const Int kk = FK > 0 ? FK : static_cast<Int>(f[pp + 1]);
        const Int s0 = pp + 2 + nc;
        double tu = 0.0, tt = 0.0, x2 = 0.0, uu = 0.0;
        for (Int a = lead; a < n; ++a) uu += u[a] * u[a];
        for (Int b = 0; b < kk; ++b) {
            double s = 0.0;
            for (Int a = 0; a < nc; ++a) {
                s += f[s0 + a * kk + b] * u[lead + a];
                tt += f[s0 + a * kk + b] * f[s0 + a * kk + b];
            }
            tu += s * s;
            const double xb = lm[p] > 0.0 ? xw[p * FAST_N + b] / lm[p]
                                          : xs[p * FAST_N + b] / static_cast<double>(count[p]);
            x2 += xb * xb;
        }
        if (tu <= FLAT_RHO * FLAT_RHO * uu * tt || x2 < FLAT_SPREAD) return std::nullopt;
    }
    double Z[FAST_N * FAST_N];    // the pieces' points, by row
    double X[FAST_N * FAST_N];    // their x
    double SX[FAST_N * FAST_N];   // their S x
    double hv[FAST_N];
    double rho[FAST_N];
    // S S^T (nc x nc, upper triangle by rows) of the leaves met in this try, by leaf: the
    // curvature's constant part, computed at a leaf's first step (recomputing it every step was
    // a third of the finish's own instructions on point contacts)
    constexpr Int SSN = FN > 0 ? FN : FAST_N;
    double SS[SSN * SSN * FAST_N];
    Int ss_leaf[FAST_N];
    Int ss_count = 0;
    auto leaf_ss = [&](Int l, Int nc, Int kk, Int s0) -> const double* {
        for (Int q = 0; q < ss_count; ++q)
            if (ss_leaf[q] == l) return SS + q * SSN * SSN;
        // past FAST_N leaves in one try (pieces that drop and join), the last slot is remade
        const Int q = ss_count < FAST_N ? ss_count++ : FAST_N - 1;
        ss_leaf[q] = l;
        double* const out = SS + q * SSN * SSN;
        gram_upper(f.d + s0, nc, kk, out, SSN);
        return out;
    };
    KktWork kw;
    double* const K = kw.K;
    double* const rhs = kw.rhs;
    double* const dx = kw.dx;
    Int steps = 0;
    Int calls = 0;
    Int changes = 0;
    bool converged = false;
    bool precise = false;   // certify only after a step below STEP_TOL, not EARLY_STEP
    double last_du = INF;   // the last step's length, INF after a change of the piece set
    while (steps < NEWTON_STEPS) {
        if (m < 1 || changes > MAX_CHANGES)
            return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        for (Int p = 0; p < m; ++p) {
            const EllipsePoint e = ellipsoid_at<FN, FK>(f, leaf[p], u, n, Z + p * FAST_N,
                                                        X + p * FAST_N, SX + p * FAST_N);
            // a piece at its kink turns flat: the general path's case
            if (e.rho == 0.0) return std::nullopt;
            hv[p] = e.h;
            rho[p] = e.rho;
        }
        if (converged) {
            // certify as the general path: weights re-solved on the points, the full support.
            // A certificate tried early that does not hold asks for the full step test
            auto not_yet = [&]() {
                precise = true;
                converged = false;
            };
            Array S(n + 1, n);
            Array WS(n + 1, ws);
            Array lmA(n + 1);
            Array nrmA(n);
            Array witA(ws);
            const Mat Sm = S.mat();
            const Vec lv = lmA.vec();
            for (Int p = 0; p < m; ++p) {
                // the leaf's slot (an embedding's own slot stays 0: not its origin), or the
                // embedding's for its origin
                const Int w = ints[B.WSTART + leaf[p].leaf];
                for (Int i = 0; i < n; ++i) Sm(p, i) = Z[p * FAST_N + i];
                WS.mat()(p, w) = 1.0;
                if (leaf[p].pp < 0) continue;
                for (Int b = 0; b < static_cast<Int>(f[leaf[p].pp + 1]); ++b)
                    WS.mat()(p, w + 1 + b) = X[p * FAST_N + b];
            }
            double D[FAST_N * (FAST_N + 1)];
            double work[FAST_N * (FAST_N + 1)];
            double wrhs[FAST_N];
            double rhs[FAST_N];
            double point[FAST_N];
            const double tz = weights_on_ray(Sm, m, r, lv, Mat{D, n, m, m}, Mat{work, n, m, m},
                                             Vec{wrhs, n}, Vec{rhs, n});
            for (Int i = 0; i < n; ++i) point[i] = tz * r[i];
            const Vec pv{point, n};
            if (tz <= 0.0 || smallest(lv, m) < -1e-12 || !reproduce(Sm, lv, m, pv)) {
                if (precise) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
                not_yet();
                continue;
            }
            double ur = 0.0, uu = 0.0;
            for (Int i = 0; i < n; ++i) {
                ur += u[i] * r[i];
                uu += u[i] * u[i];
            }
            if (!(ur > 0.0)) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
            const Vec nrm = nrmA.vec();
            const double un = std::sqrt(uu);
            for (Int i = 0; i < n; ++i) nrm[i] = u[i] / un;
            const double h_full = support(ints, f, nrm, pv, witA.vec());
            calls += 1;
            const double t_up = h_full / dot(nrm, r);
            if (t_up - tz <= eps * tz && t_up >= tz * (1.0 - face_rounding(Sm, m, h_full)))
                return NewtonOut{true,  tz,    std::max(t_up, tz), h_full,
                                 m,     steps, calls,              std::move(nrmA),
                                 std::move(S), std::move(lmA),     std::move(WS)};
            // a piece the system did not hold sticks out at u: it joins with weight 0
            const piece::SmoothLeaf e = piece::smooth_leaf(ints, witA.vec());
            const Int l = e.leaf;
            Int p = 0;
            while (p < m && leaf[p].leaf != l) ++p;
            if (p < m && !precise) {
                not_yet();
                continue;
            }
            if (l < 0 || p < m || m == n)
                return ellipsoid_failed(t, t_up, h_full, steps, calls, n, ws);
            for (Int q = 0; q < m; ++q) lm[q] = lv[q];
            last_du = INF;
            leaf[m] = e;
            lm[m] = 0.0;
            m += 1;
            changes += 1;
            converged = false;
            continue;
        }
        // the Newton step: [[sum lam_p H_p, Z^T, -r], [Z, 0, 0], [0, 1^T, 0]] with the last
        // row solved for the last weight's step, dlam_last = e - sum of the others (e = 1 -
        // sum lam): unknowns du, dlam_0 .. dlam_{m-2}, dt
        const Int N = n + m;
        double total = 0.0;
        for (Int p = 0; p < m; ++p) total += lm[p];
        const double e_sum = 1.0 - total;
        const double* zl = Z + (m - 1) * FAST_N;
        for (Int a = 0; a < n; ++a) {
            double F = -t * r[a];
            for (Int p = 0; p < m; ++p) F += lm[p] * Z[p * FAST_N + a];
            rhs[a] = -F - zl[a] * e_sum;
            for (Int a2 = 0; a2 < n; ++a2) K[a * FAST_K + a2] = 0.0;
            for (Int p = 0; p + 1 < m; ++p) K[a * FAST_K + n + p] = Z[p * FAST_N + a] - zl[a];
            K[a * FAST_K + n + m - 1] = -r[a];
        }
        for (Int p = 0; p < m; ++p) {
            // the curvature, in the leaf's coordinates (the last n_c of u); none at an origin
            const Int pp = leaf[p].pp;
            rhs[n + p] = 1.0 - hv[p];
            for (Int a = 0; a < n; ++a) K[(n + p) * FAST_K + a] = Z[p * FAST_N + a];
            for (Int c = n; c < N; ++c) K[(n + p) * FAST_K + c] = 0.0;
            if (FN == 0 && pp < 0) continue;
            const Int lead = FN > 0 ? 0 : leaf[p].lead;
            const Int nc = n - lead;
            const Int kk = FK > 0 ? FK : static_cast<Int>(f[pp + 1]);
            const Int s0 = pp + 2 + nc;
            const double g = lm[p] / rho[p];
            const double* sx = SX + p * FAST_N;
            const double* ss = leaf_ss(leaf[p].leaf, nc, kk, s0);
            for (Int a = 0; a < nc; ++a) {
                double* row = K + (lead + a) * FAST_K + lead;
                for (Int a2 = a; a2 < nc; ++a2) row[a2] += g * (ss[a * SSN + a2] - sx[a] * sx[a2]);
            }
        }
        for (Int a = 0; a < n; ++a)
            for (Int a2 = 0; a2 < a; ++a2) K[a * FAST_K + a2] = K[a2 * FAST_K + a];
        // singular where the face's normal cone is wider than a ray (one soft finger's
        // 3-D ellipsoid in R^6): a basic solution, as the general path's
        const KktStep step = kkt_step(kw, N, u, n, FN == 6);
        if (!step.ok) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        steps += 1;
        const double du = step.du, un = step.un;
        Int worst = -1;
        double rest = e_sum;
        for (Int p = 0; p < m; ++p) {
            const double dl = p + 1 < m ? dx[n + p] : rest;
            rest -= dl;
            lm[p] += dl;
            if (lm[p] <= 0.0 && (worst < 0 || lm[p] < lm[worst])) worst = p;
        }
        t += dx[n + m - 1];
        if (worst >= 0) {
            // not a piece of the exit face: its weight would be negative
            for (Int p = worst; p < m - 1; ++p) {
                leaf[p] = leaf[p + 1];
                lm[p] = lm[p + 1];
            }
            m -= 1;
            changes += 1;
            converged = false;
            last_du = INF;
            continue;
        }
        // Newton's steps shrink quadratically near the answer; one that does not shrink the last
        // by a tenth is a piece set (or a singular system's basic steps) that does not converge
        if (du > DIVERGED * last_du) return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
        last_du = du;
        converged = du <= (precise ? STEP_TOL : EARLY_STEP) * un;
    }
    return ellipsoid_failed(t, INF, 0.0, steps, calls, n, ws);
}

// ellipsoid_finish_sized for the set's sizes (nullopt for a set it does not take)
inline std::optional<NewtonOut> ellipsoid_finish(IVec ints, Vec f, Vec r, double eps, Mat Wt,
                                                 Vec lam, Int k, Vec normal, double t) {
    bool embedded;
    const Int cols = ellipsoid_hull_columns(ints, f, r.n, embedded);
    if (cols < 0) return std::nullopt;
    // W_L1 of soft fingers (6, 3) and of point contacts (6, 2)
    if (!embedded && r.n == 6 && cols == 3)
        return ellipsoid_finish_sized<6, 3>(ints, f, r, eps, Wt, lam, k, normal, t);
    if (!embedded && r.n == 6 && cols == 2)
        return ellipsoid_finish_sized<6, 2>(ints, f, r, eps, Wt, lam, k, normal, t);
    return ellipsoid_finish_sized(ints, f, r, eps, Wt, lam, k, normal, t);
}

}  // namespace newton_detail

// Try to finish a shot from the simplex P[:k] (witnesses Wt, weights lam: t r is their convex
// combination or near it) and the normal of its facet. On ok, z = t r is the convex combination
// `weights` of V[:m] (points of A, witnesses W), within rounding of the ray, and H(normal, h_n)
// supports A with (t_upper - t) <= eps t.
//
// corner: the ray runs along the boundary of CO(A) (ZC stalled, or its cone reproduced b_k only
// to ~1e-8: zc_from), so z_A(r) is a corner whose normals form a cone of more than one ray, the
// KKT system is singular, and the given normal (ZC's, nearly orthogonal to r) is a poor
// certificate. Every step is then a basic solution by complete pivoting, moved within the null
// space so that u (u^T r = 1) stays shortest: the normal that bounds t best. (Two contacts,
// wrenches on the edge of what they resist: the plain steps finish some two-point-contact cases,
// the corner steps the others, and three-term corners where the plain steps fail.)
//
// Plain steps on a hull of ellipsoid leaves whose exit face's pieces are all smooth (soft fingers
// whose friction saturates) take `ellipsoid_finish`: the same answer for half the cost.
NewtonOut newton_finish(IVec ints, Vec f, Vec r, double eps, Mat P, Mat Wt, Vec lam, Int k,
                        Vec normal, double t, bool corner) {
    using namespace newton_detail;
    if (!corner) {
        std::optional<NewtonOut> fast = ellipsoid_finish(ints, f, r, eps, Wt, lam, k, normal, t);
        if (fast) return std::move(*fast);
    }
    const Int n = r.n;
    const Int ws = Wt.cols;
    const Int nn = ints[0];
    const Blocks B = blocks(nn);
    const Int cap = k + 3;
    // what the answer returns, owned apart so that it moves out
    Array S(cap, n);
    Array WS(cap, ws);
    Array lmA(cap);
    Array nrmA(n);
    const auto [size, nmax, qmax] = piece::jacobian_size(ints, f);
    const Int ycap = 2 * n + 2;
    const Int N = n + cap + ycap + 2;
    const Int Nm = corner ? N : 0;
    // the work arrays, one float and one int buffer, each entry written before it is read
    Array fbuf = Array::uninitialized(1, cap * ws + cap * n * n + cap * n + n * ycap + ycap +
                                             2 * nmax * qmax + 2 * N * N + 2 * N + size +
                                             3 * Nm * Nm + 3 * Nm + 2 * n + ws + qmax);
    IArray ibuf = IArray::uninitialized(k + 4 * ycap + 2 * N);
    Int fat = 0;
    auto take_mat = [&](Int rows, Int cols) {
        const Mat M = mat_view(fbuf.vec(), fat, rows, cols);
        fat += rows * cols;
        return M;
    };
    auto take = [&](Int len) {
        const Vec v = fbuf.vec().segment(fat, len);
        fat += len;
        return v;
    };
    Int iat = 0;
    auto take_int = [&](Int len) {
        const IVec v{ibuf.data.data() + iat, len};
        iat += len;
        return v;
    };
    const Mat PW = take_mat(cap, ws);
    const Mat JJ = take_mat(cap * n, n);   // (cap, n, n)
    const Mat sm = take_mat(cap, n);
    const Vec lm = lmA.vec();
    const Mat Sm = S.mat();
    const Mat WSm = WS.mat();
    const IVec group = take_int(k);
    const Mat T = take_mat(n, ycap);
    const Vec y = take(ycap);
    const IVec fpiece = take_int(ycap);
    const IVec fleaf = take_int(ycap);
    const IVec foff = take_int(ycap);
    const IVec fq = take_int(ycap);
    const Mat C = take_mat(nmax, qmax);
    const Mat C2 = take_mat(nmax, qmax);
    const Mat K = take_mat(N, N);
    const Mat lu = take_mat(N, N);
    const IVec prow = take_int(N);
    const IVec pcol = take_int(N);
    const Vec rhs = take(N);
    const Vec dx = take(N);
    const Vec jw = take(size);
    const Mat mats = take_mat(3 * Nm, Nm);   // (3, N, N) when corner
    const Mat vecs = take_mat(3, Nm);
    const Vec u = take(n);
    const Vec point = take(n);
    const Vec wit = take(ws);
    const Vec nrm = nrmA.vec();
    const Vec xbar = take(qmax);
    Int steps = 0;
    Int calls = 0;
    const double nr = dot(normal, r);
    if (nr <= 0.0) return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
    for (Int i = 0; i < n; ++i) u[i] = normal[i] / nr;
    // the pieces of the simplex, each weighted by the sum of its vertices' weights
    Int m = 0;
    for (Int j = 0; j < k; ++j) {
        group[j] = m;
        for (Int p = 0; p < m; ++p) {
            if (piece::same_piece(ints, Wt.row(j), PW.row(p))) {
                group[j] = p;
                break;
            }
        }
        if (group[j] == m) {
            for (Int a = 0; a < ws; ++a) PW(m, a) = Wt(j, a);
            lm[m] = lam[j];
            m += 1;
        } else {
            lm[group[j]] += lam[j];
        }
    }
    // flat leaves: the facet's normal nearly annihilates T, or the facet's vertices spread over
    // the body (a smooth piece's crowd together); x starts at their weighted mean
    double un = std::sqrt(dot(u, u));
    for (Int p = 0; p < m; ++p) {
        for (Int i = 0; i < nn; ++i) {
            const Int kind = ints[B.KIND + i];
            if (kind != ELLIPSOID && kind != TRUNCATED_CONE) continue;
            const Int w = ints[B.WSTART + i];
            if (PW(p, w) == 0.0) continue;
            const Int q = piece::flat_columns(ints, f, i, T, 0, C, C2);
            if (q < 0) continue;
            double tu = 0.0;
            double tt = 0.0;
            for (Int b = 0; b < q; ++b) {
                double s = 0.0;
                for (Int a = 0; a < n; ++a) {
                    s += T(a, b) * u[a];
                    tt += T(a, b) * T(a, b);
                }
                tu += s * s;
            }
            double wsum = 0.0;
            for (Int b = 0; b < q; ++b) xbar[b] = 0.0;
            for (Int j = 0; j < k; ++j) {
                if (group[j] == p) {
                    wsum += lam[j];
                    for (Int b = 0; b < q; ++b) xbar[b] += lam[j] * Wt(j, w + 1 + b);
                }
            }
            for (Int b = 0; b < q; ++b) xbar[b] = wsum > 0.0 ? xbar[b] / wsum : 0.0;
            for (Int b = 0; b < q; ++b) PW(p, w + 1 + b) = xbar[b];
            const double fr = FLAT_RHO * un;
            if (tu <= fr * fr * tt || piece::flat_radius2(ints, f, i, PW.row(p)) < FLAT_SPREAD)
                mark_flat(ints, f, PW, p, i, xbar);
        }
    }
    Flats fl = flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2);
    double tau = t;
    Int changes = 0;
    bool converged = false;
    while (steps < NEWTON_STEPS) {
        if (m < 1 || m > n || fl.nf < 0 || n + m + fl.ny + 2 > N || changes > MAX_CHANGES)
            return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
        bool kinked = false;
        for (Int p = 0; p < m; ++p) {
            const double h = piece::piece_support(ints, f, u, PW.row(p), Sm.row(p), WSm.row(p),
                                                  JJ.rows_range(p * n, (p + 1) * n), jw, nmax);
            if (h != h) {
                // a smooth leaf at its kink: its whole body is in the face, it turns flat
                for (Int i = 0; i < nn; ++i) {
                    if (ints[B.KIND + i] < HULL && WSm(p, ints[B.WSTART + i]) == piece::KINK) {
                        for (Int b = 0; b < qmax; ++b) xbar[b] = 0.0;
                        mark_flat(ints, f, PW, p, i, xbar);
                    }
                }
                kinked = true;
            }
        }
        if (kinked) {
            fl = flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2);
            changes += 1;
            continue;
        }
        if (converged) {
            // a flat leaf in several pieces (a summand's body in more than one piece of the
            // face): the point equation holds only sum_p lam_p x_p, which the basic solution
            // splits freely (one copy just outside the body, another inside: W_Linf of two
            // point contacts at the edge of their cones); each copy takes their weighted mean,
            // and its piece's point is evaluated again
            for (Int e = 0; e < fl.nf; ++e) {
                const Int leaf = fleaf[e];
                const Int w = ints[B.WSTART + leaf];
                Int copies = 0;
                double lsum = 0.0;
                for (Int b = 0; b < fq[e]; ++b) xbar[b] = 0.0;
                for (Int g = 0; g < fl.nf; ++g) {
                    if (fleaf[g] != leaf) continue;
                    copies += 1;
                    lsum += lm[fpiece[g]];
                    for (Int b = 0; b < fq[e]; ++b)
                        xbar[b] += lm[fpiece[g]] * PW(fpiece[g], w + 1 + b);
                }
                if (copies < 2 || !(lsum > 0.0)) continue;
                for (Int g = 0; g < fl.nf; ++g) {
                    if (fleaf[g] != leaf) continue;
                    for (Int b = 0; b < fq[e]; ++b) PW(fpiece[g], w + 1 + b) = xbar[b] / lsum;
                    const Int p = fpiece[g];
                    piece::piece_support(ints, f, u, PW.row(p), Sm.row(p), WSm.row(p),
                                         JJ.rows_range(p * n, (p + 1) * n), jw, nmax);
                }
            }
            // certify: flat points inside their bodies, weights on the ray, the full support
            Int outside = -1;
            for (Int e = 0; e < fl.nf; ++e)
                if (piece::flat_radius2(ints, f, fleaf[e], PW.row(fpiece[e])) > 1.0 + 1e-12)
                    outside = e;
            if (outside >= 0) {
                PW(fpiece[outside], ints[B.WSTART + fleaf[outside]]) = 1.0;
                fl = flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2);
                changes += 1;
                converged = false;
                continue;
            }
            // a flat point outside its body by rounding (<= 1e-12) goes onto its boundary, so
            // that the forces read off it lie in their cones to rounding (a soft finger's x 5e-14
            // outside its unit ball was a force 5e-14 outside its cone); its piece's point is
            // evaluated again, the others are as they were
            for (Int e = 0; e < fl.nf; ++e) {
                const Int p = fpiece[e];
                const double rho2 = piece::flat_radius2(ints, f, fleaf[e], PW.row(p));
                if (rho2 > 1.0) {
                    const Int w = ints[B.WSTART + fleaf[e]];
                    const double inv = 1.0 / std::sqrt(rho2);
                    const Int q = piece::local_size(ints[B.KIND + fleaf[e]], f,
                                                    ints[B.PSTART + fleaf[e]]);
                    for (Int b = 0; b < q; ++b) PW(p, w + 1 + b) *= inv;
                    piece::piece_support(ints, f, u, PW.row(p), Sm.row(p), WSm.row(p),
                                         JJ.rows_range(p * n, (p + 1) * n), jw, nmax);
                }
            }
            const double tz = weights_on_ray(Sm, m, r, lm, K, lu, dx, rhs);
            if (tz <= 0.0 || smallest(lm, m) < -1e-12)
                return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
            for (Int i = 0; i < n; ++i) point[i] = tz * r[i];
            if (!reproduce(Sm, lm, m, point))
                return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
            un = std::sqrt(dot(u, u));
            if (!(dot(u, r) > 0.0)) return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
            for (Int i = 0; i < n; ++i) nrm[i] = u[i] / un;
            const double h_full = support(ints, f, nrm, point, wit);
            calls += 1;
            const double t_up = h_full / dot(nrm, r);
            if (t_up - tz <= eps * tz && t_up >= tz * (1.0 - face_rounding(Sm, m, h_full)))
                return {true, tz, std::max(t_up, tz), h_full, m, steps, calls, std::move(nrmA),
                        std::move(S), std::move(lmA), std::move(WS)};
            // a piece the system did not hold sticks out at u: it joins with weight 0
            for (Int p = 0; p < m; ++p)
                if (piece::same_piece(ints, wit, PW.row(p)))
                    return failed(t, t_up, h_full, steps, calls, nrmA, S, lmA, WS);
            if (m == n) return failed(t, t_up, h_full, steps, calls, nrmA, S, lmA, WS);
            for (Int a = 0; a < ws; ++a) PW(m, a) = wit[a];
            lm[m] = 0.0;
            m += 1;
            changes += 1;
            converged = false;
            continue;
        }
        if (!solve_kkt(r, u, t, tau, lm, Sm, JJ, m, T, y, fl.nf, fl.ny, fpiece, foff, fq, sm, K,
                       lu, prow, pcol, rhs, dx, corner, mats, vecs))
            return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
        steps += 1;
        double du = 0.0;
        for (Int i = 0; i < n; ++i) {
            u[i] += dx[i];
            du = std::max(du, std::abs(dx[i]));
        }
        un = 0.0;
        for (Int i = 0; i < n; ++i) un = std::max(un, std::abs(u[i]));
        Int worst = -1;
        for (Int p = 0; p < m; ++p) {
            lm[p] += dx[n + p];
            if (lm[p] <= 0.0 && (worst < 0 || lm[p] < lm[worst])) worst = p;
        }
        for (Int c = 0; c < fl.ny; ++c) y[c] += dx[n + m + c];
        t += dx[n + m + fl.ny];
        tau += dx[n + m + fl.ny + 1];
        if (worst >= 0) {
            // not a piece of the exit face: its weight would be negative (or is zero: the basic
            // solution left it out) (S's rows shift along: every round evaluates them afresh)
            m = drop_point(Sm, PW, lm, m, worst);
            fl = flats(ints, f, PW, lm, m, T, y, fpiece, fleaf, foff, fq, C, C2);
            changes += 1;
            converged = false;
            continue;
        }
        for (Int e = 0; e < fl.nf; ++e) {
            const Int w = ints[B.WSTART + fleaf[e]];
            for (Int b = 0; b < fq[e]; ++b)
                PW(fpiece[e], w + 1 + b) = y[foff[e] + b] / lm[fpiece[e]];
        }
        converged = du <= STEP_TOL * un;
    }
    return failed(t, INF, 0.0, steps, calls, nrmA, S, lmA, WS);
}

}  // namespace gf
