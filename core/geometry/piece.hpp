#pragma once

#include "api.hpp"
#include "geometry/kernel.hpp"

// The support of one smooth piece of a set, with its curvature: what a second-order finish needs.
//
// A support point's witness names the piece of A that produced it: the leaves it flags (the
// chosen child of every hull, every summand of a sum) and, inside a leaf, the part whose support
// is smooth (a polytope's or a box's vertex, a truncated cone's top or bottom disk; an ellipsoid
// or a cone cap is one piece). On a piece P the support map is differentiable:
//
//     h_P(u) = max over P of u^T a,   s_P(u) = grad h_P(u),   J_P(u) = ds_P/du = Hess h_P(u)
//
// (eq. 2 restricted to P). J is symmetric positive semidefinite with J u = 0 (h is
// 1-homogeneous), zero on a vertex, (S S^T - (s - c)(s - c)^T) / ||S^T u|| on an ellipsoid
// {c + S x : ||x|| <= 1}, and it transforms as M J M^T through an affine node, adds through a
// sum, passes through a hull.
//
// A leaf of a piece may also be flat: where S^T u = 0 an ellipsoid's (or a disk's) whole body is
// its face, and the face of A then holds an interior point c + S x of it, x free (a soft finger
// whose friction is not saturated, an ellipsoid resting on a cone's base). A pattern marks such a
// leaf with the flag FLAT instead of 1 and its local point x in the witness slot; the leaf then
// adds the fixed point c + S x and no curvature, and `flat_columns` gives the columns L S (L the
// linear part of the affine maps above the leaf) along which x moves the piece's point.
//
// `piece_support` evaluates h_P, s_P, J_P and the witness of s_P; at a kink of a smooth leaf (the
// direction where it is not smooth: S^T u = 0) it returns NaN and flags that leaf KINK in the
// witness. Adding a leaf kind means adding its piece here, beside its support in kernel.hpp.

namespace gf {

namespace piece {

constexpr double FLAT = 2.0;    // witness flag of a flat leaf (see above)
constexpr double KINK = -1.0;   // witness flag piece_support leaves on the smooth leaf whose kink
                                // it met

// jacobian_size's tuple
struct JacobianSize {
    Int size;   // entries of the work array piece_support keeps one Jacobian per node in, and a
                // product in
    Int nmax;   // the largest dimension of a node
    Int qmax;   // the largest local point of a leaf that can be flat
};

}  // namespace piece

namespace piece_detail {

// ||S^T u|| <= KINK_TOL ||S|| ||u||: the piece's support is not smooth there
constexpr double KINK_TOL = 1e-9;
constexpr double NOT_A_NUMBER = std::numeric_limits<double>::quiet_NaN();

// The piece of an ellipsoid leaf {c + S x : ||x|| <= 1} (parameters n, k, c, S at f[p:],
// direction at f[d:]): h returned (NaN at its kink), its point to f[o:], x to the witness slot
// wit[w + 1:], J to J[j0:]. Compiled for sizes FN, FK (loops of known length unroll), or for any
// when they are 0.
template <int FN = 0, int FK = 0>
[[gnu::always_inline]] inline double ellipsoid_piece(Vec f, Int p, Int d, Int o, Vec wit, Int w,
                                                     Vec J, Int j0, Int n_ = FN, Int kk_ = FK) {
    const Int n = FN > 0 ? FN : n_;
    const Int kk = FK > 0 ? FK : kk_;
    const Int s0 = p + 2 + n;
    double rho2 = 0.0;
    double ss = 0.0;
    double uu = 0.0;
    for (Int a = 0; a < n; ++a) uu += f[d + a] * f[d + a];
    for (Int b = 0; b < kk; ++b) {
        double y = 0.0;
        for (Int a = 0; a < n; ++a) {
            const double sab = f[s0 + a * kk + b];
            y += sab * f[d + a];
            ss += sab * sab;
        }
        wit[w + 1 + b] = y;
        rho2 += y * y;
    }
    if (rho2 <= KINK_TOL * KINK_TOL * ss * uu) return NOT_A_NUMBER;
    const double rho = std::sqrt(rho2);
    const double inv = 1.0 / rho;
    for (Int b = 0; b < kk; ++b) wit[w + 1 + b] *= inv;
    double h = rho;
    for (Int a = 0; a < n; ++a) {
        double sx = 0.0;
        for (Int b = 0; b < kk; ++b) sx += f[s0 + a * kk + b] * wit[w + 1 + b];
        f[o + a] = f[p + 2 + a] + sx;
        h += f[p + 2 + a] * f[d + a];
    }
    // J = (S S^T - (S x)(S x)^T) / rho, S x = s - c
    for (Int a = 0; a < n; ++a) {
        const double sxa = f[o + a] - f[p + 2 + a];
        for (Int a2 = 0; a2 < n; ++a2) {
            double v = -sxa * (f[o + a2] - f[p + 2 + a2]);
            for (Int b = 0; b < kk; ++b) v += f[s0 + a * kk + b] * f[s0 + a2 * kk + b];
            J[j0 + a * n + a2] = v * inv;
        }
    }
    return h;
}

// A truncated cone's point (x, y, z) in its frame, to f[o:o + 3] and its witness slot (as the
// kernel's truncated cone writes it, spelled out there: a call inlined into the kernel's leaf
// code slowed every support call by ~5%).
[[gnu::always_inline]] inline void disk_point(Vec f, Int o, Vec wit, Int w, double x, double y,
                                              double z) {
    f[o] = x;
    f[o + 1] = y;
    f[o + 2] = z;
    wit[w + 1] = x;
    wit[w + 2] = y;
    wit[w + 3] = z;
}

// The top (or bottom) disk of a truncated cone: s = (R u_xy / ||u_xy||, +-height/2).
[[gnu::always_inline]] inline double disk_piece(Vec f, Int p, Int d, Int o, Vec wit, Int w,
                                                Vec J, Int j0, bool top) {
    const double rad = top ? f[p + 1] : f[p];
    const double z = top ? 0.5 * f[p + 2] : -0.5 * f[p + 2];
    const double ux = f[d];
    const double uy = f[d + 1];
    const double uz = f[d + 2];
    const double q = std::sqrt(ux * ux + uy * uy);
    for (Int a = 0; a < 9; ++a) J[j0 + a] = 0.0;
    if (rad > 0.0) {
        if (q <= KINK_TOL * std::sqrt(q * q + uz * uz)) return NOT_A_NUMBER;
        const double px = ux / q;
        const double py = uy / q;
        const double c = rad / q;
        J[j0] = c * (1.0 - px * px);
        J[j0 + 1] = -c * px * py;
        J[j0 + 3] = -c * px * py;
        J[j0 + 4] = c * (1.0 - py * py);
        disk_point(f, o, wit, w, rad * px, rad * py, z);
    } else {
        disk_point(f, o, wit, w, 0.0, 0.0, z);
    }
    return rad * q + z * uz;
}

// Cone cap: its point from the kernel (kernel::cone_cap_support), its curvature here. C^1 across
// the cone's boundary, so one piece; J is that of the side the direction lies on:
// (I - s s^T) / ||y|| inside K (s = y / ||y||), sin(beta) (I - e e^T) / ||y_perp|| on the
// components 2..n outside (e = y_perp / ||y_perp||, the rim's circle).
[[gnu::always_inline]] inline double cap_piece(Vec f, Int p, Int d, Int o, Vec wit, Int w,
                                               Vec J, Int j0) {
    const double h = kernel::cone_cap_support(f, p, d, o, wit, w);
    const kernel::CapDirection cd = kernel::cap_direction(f, p, d);
    const Int n = cd.n;
    const double mu = cd.mu, y1 = cd.y1, q2 = cd.q2, q = cd.q, ny = cd.ny;
    for (Int a = 0; a < n * n; ++a) J[j0 + a] = 0.0;
    if (y1 >= 0.0 && q <= mu * y1) {
        if (ny == 0.0) return NOT_A_NUMBER;
        for (Int a = 0; a < n; ++a)
            for (Int b = 0; b < n; ++b)
                J[j0 + a * n + b] = ((a == b ? 1.0 : 0.0) - f[o + a] * f[o + b]) / ny;
    } else {
        if (q <= KINK_TOL * ny) return NOT_A_NUMBER;
        const double sb = mu / std::sqrt(1.0 + mu * mu);
        for (Int a = 1; a < n; ++a)
            for (Int b = 1; b < n; ++b)
                J[j0 + a * n + b] = sb * ((a == b ? 1.0 : 0.0) - f[d + a] * f[d + b] / q2) / q;
    }
    return h;
}

// A flat leaf's point c + S x (x at pw[w + 1:]) to f[o:], its value u^T (c + S x) returned. A
// disk's x is the point's (x, y) in the cone's frame, on the top disk if pw[w + 3] > 0.
[[gnu::always_inline]] inline double flat_point(Int k, Vec f, Int p, Int d, Int o, Vec pw, Int w,
                                                Int n) {
    if (k == ELLIPSOID) {
        const Int kk = static_cast<Int>(f[p + 1]);
        const Int s0 = p + 2 + n;
        for (Int a = 0; a < n; ++a) {
            double s = f[p + 2 + a];
            for (Int b = 0; b < kk; ++b) s += f[s0 + a * kk + b] * pw[w + 1 + b];
            f[o + a] = s;
        }
    } else {
        f[o] = pw[w + 1];
        f[o + 1] = pw[w + 2];
        f[o + 2] = pw[w + 3] > 0.0 ? 0.5 * f[p + 2] : -0.5 * f[p + 2];
    }
    double h = 0.0;
    for (Int a = 0; a < n; ++a) h += f[o + a] * f[d + a];
    return h;
}

// J = M J_c M^T through an affine node (M (m, n) row-major at f[M0:]; J_c at jw[jc:], J to
// jw[j0:], jw[tmp:] holds J_c M^T). Compiled for sizes FM, FN (the poses of 3-D bodies unroll),
// or for any when they are 0.
template <int FM = 0, int FN = 0>
[[gnu::always_inline]] inline void affine_jacobian(Vec f, Int M0, Vec jw, Int jc, Int j0,
                                                   Int tmp, Int m_ = FM, Int n_ = FN) {
    const Int m = FM > 0 ? FM : m_;
    const Int n = FN > 0 ? FN : n_;
    for (Int b = 0; b < n; ++b)
        for (Int a = 0; a < m; ++a) {
            double s = 0.0;
            for (Int c = 0; c < n; ++c) s += jw[jc + b * n + c] * f[M0 + a * n + c];
            jw[tmp + b * m + a] = s;
        }
    for (Int a = 0; a < m; ++a)
        for (Int a2 = 0; a2 < m; ++a2) {
            double s = 0.0;
            for (Int b = 0; b < n; ++b) s += f[M0 + a * n + b] * jw[tmp + b * m + a2];
            jw[j0 + a * m + a2] = s;
        }
}

}  // namespace piece_detail

namespace piece {

// (entries of the work array piece_support keeps one Jacobian per node in, and a product in, the
// largest dimension of a node, the largest local point of a leaf that can be flat).
inline JacobianSize jacobian_size(IVec ints, Vec f) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    Int nmax = 0;
    Int qmax = 2;
    for (Int i = 0; i < nn; ++i) {
        nmax = std::max(nmax, ints[DIM + i]);
        if (ints[KIND + i] == ELLIPSOID)
            qmax = std::max(qmax, static_cast<Int>(f[ints[PSTART + i] + 1]));
    }
    return {(nn + 1) * nmax * nmax, nmax, qmax};
}

// Whether two witnesses name the same smooth piece (see the header comment).
inline bool same_piece(IVec ints, Vec wa, Vec wb) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    for (Int i = 0; i < nn; ++i) {
        const Int k = ints[KIND + i];
        if (k == ORIGIN_EMBED) {
            const Int w = ints[WSTART + i];
            if ((wa[w] != 0.0) != (wb[w] != 0.0)) return false;
            continue;
        }
        if (k >= HULL) continue;
        const Int w = ints[WSTART + i];
        if ((wa[w] != 0.0) != (wb[w] != 0.0)) return false;
        if (wa[w] == 0.0) continue;
        if (k == POLYTOPE) {
            if (wa[w + 1] != wb[w + 1]) return false;
        } else if (k == BOX) {
            for (Int a = 0; a < ints[DIM + i]; ++a)
                if (wa[w + 1 + a] != wb[w + 1 + a]) return false;
        } else if (k == TRUNCATED_CONE) {   // the disk, by the sign of the point's z
            if ((wa[w + 3] > 0.0) != (wb[w + 3] > 0.0)) return false;
        }
    }
    return true;
}

// A piece of a smooth hull: an ellipsoid leaf of a root hull (W_L1's contacts), or of a root hull
// of ORIGIN_EMBED nodes (W_Linf's lift: {e} x CH({0} U W_i)), or such an embedding's origin: its
// node (the leaf, or the embedding for its origin), the leaf's parameters at f[pp] (n, k, c, S;
// pp -1 for an origin) and, under an embedding, the coordinates before the leaf's (lead) and the
// embedding's offset at f[t0] (the set's n entries; -1: none).
struct SmoothLeaf {
    Int leaf;
    Int pp;
    Int lead;
    Int t0;
};

// The SmoothLeaf whose point the witness w names, leaf -1 when it names none of the root's
// ellipsoid leaves or origins with flag 1 (another kind of set, a flat leaf). Always inlined:
// ZC-IE's piece test calls it at every IE step (1% of a point-contact grasp's instructions).
[[gnu::always_inline]] inline SmoothLeaf smooth_leaf(IVec ints, Vec w) {
    const Blocks B = blocks(ints[0]);
    const Int c0 = B.CHILDREN + ints[B.CSTART];
    for (Int c = 0; c < ints[B.CCOUNT]; ++c) {
        const Int node = ints[c0 + c];
        Int leaf = node, lead = 0, t0 = -1;
        if (ints[B.KIND + node] == ORIGIN_EMBED) {
            leaf = ints[B.CHILDREN + ints[B.CSTART + node]];
            lead = ints[B.DIM + node] - ints[B.DIM + leaf];
            t0 = ints[B.PSTART + node] + 3;
            const double origin = w[ints[B.WSTART + node]];
            if (origin != 0.0)
                return origin == 1.0 ? SmoothLeaf{node, -1, lead, t0} : SmoothLeaf{-1, 0, 0, -1};
        }
        const double flag = w[ints[B.WSTART + leaf]];
        if (flag == 0.0) continue;
        if (flag != 1.0 || ints[B.KIND + leaf] != ELLIPSOID) return {-1, 0, 0, -1};
        return {leaf, ints[B.PSTART + leaf], lead, t0};
    }
    return {-1, 0, 0, -1};
}

// Entries of a flat leaf's local point: an ellipsoid's x (k), a disk's (x, y).
[[gnu::always_inline]] inline Int local_size(Int k, Vec f, Int p) {
    return k == ELLIPSOID ? static_cast<Int>(f[p + 1]) : 2;
}

// ||x||^2 / (its bound)^2 of a flat leaf's local point: <= 1 when the point is in the leaf.
inline double flat_radius2(IVec ints, Vec f, Int leaf, Vec pw) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const Int p = ints[PSTART + leaf];
    const Int w = ints[WSTART + leaf];
    if (ints[KIND + leaf] == ELLIPSOID) {
        double s = 0.0;
        for (Int b = 0; b < static_cast<Int>(f[p + 1]); ++b) s += pw[w + 1 + b] * pw[w + 1 + b];
        return s;
    }
    const double rad = pw[w + 3] > 0.0 ? f[p + 1] : f[p];
    const double s = pw[w + 1] * pw[w + 1] + pw[w + 2] * pw[w + 2];
    return rad > 0.0 ? s / (rad * rad) : (s == 0.0 ? 0.0 : INF);
}

// T[:, off:off + q] = L S for a flat leaf (see the header comment); returns q, or -1 when T has
// not q columns left. C, C2: (nmax, qmax) work (jacobian_size).
inline Int flat_columns(IVec ints, Vec f, Int leaf, Mat T, Int off, Mat C, Mat C2) {
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const Int k = ints[KIND + leaf];
    const Int p = ints[PSTART + leaf];
    const Int nl = ints[DIM + leaf];
    const Int q = local_size(k, f, p);
    if (off + q > T.cols) return -1;
    for (Int a = 0; a < nl; ++a)
        for (Int b = 0; b < q; ++b) {
            if (k == ELLIPSOID)
                C(a, b) = f[p + 2 + nl + a * q + b];
            else
                C(a, b) = a == b ? 1.0 : 0.0;
        }
    Int node = leaf;
    Int rows = nl;
    while (node != 0) {
        Int parent = 0;
        for (Int i = 0; i < nn; ++i) {
            if (ints[KIND + i] >= HULL) {
                const Int c0 = CHILDREN + ints[CSTART + i];
                for (Int c = 0; c < ints[CCOUNT + i]; ++c)
                    if (ints[c0 + c] == node) parent = i;
            }
        }
        if (ints[KIND + parent] == AFFINE) {
            const Int m = ints[DIM + parent];
            const Int M0 = ints[PSTART + parent] + 2;
            for (Int a = 0; a < m; ++a)
                for (Int b = 0; b < q; ++b) {
                    double s = 0.0;
                    for (Int c = 0; c < rows; ++c) s += f[M0 + a * rows + c] * C(c, b);
                    C2(a, b) = s;
                }
            for (Int a = 0; a < m; ++a)
                for (Int b = 0; b < q; ++b) C(a, b) = C2(a, b);
            rows = m;
        } else if (ints[KIND + parent] == EMBED || ints[KIND + parent] == ORIGIN_EMBED) {
            // x -> (0, x) + t: L gains the embedding's leading zero rows
            const Int m = ints[DIM + parent];
            const Int lead = m - rows;
            for (Int a = m - 1; a >= 0; --a)
                for (Int b = 0; b < q; ++b) C(a, b) = a >= lead ? C(a - lead, b) : 0.0;
            rows = m;
        }
        node = parent;
    }
    for (Int a = 0; a < rows; ++a)
        for (Int b = 0; b < q; ++b) T(a, off + b) = C(a, b);
    return q;
}

// h_P(u) (returned; NaN at a kink of the piece), s_P(u) into `point`, its witness into `wit` and
// J_P(u) = ds_P/du into J (n, n), for the piece P named by the witness `pw`. jw: work of
// jacobian_size(ints, f).size entries. Uses the program's scratch like `support`.
inline double piece_support(IVec ints, Vec f, Vec u, Vec pw, Vec point, Vec wit, Mat J, Vec jw,
                            Int nmax) {
    using namespace piece_detail;
    const Int nn = ints[0];
    const auto [KIND, DIM, PSTART, CSTART, CCOUNT, WSTART, DSTART, OSTART, CHOICE, ACTIVE,
                CHILDREN] = blocks(nn);
    const Int nsq = nmax * nmax;
    // the nodes of the piece: the leaves its witness flags and their ancestors
    for (Int i = nn - 1; i >= 0; --i) {
        const Int k = ints[KIND + i];
        if (k < HULL) {
            ints[ACTIVE + i] = pw[ints[WSTART + i]] != 0.0 ? 1 : 0;
            continue;
        }
        Int act = 0;
        for (Int c = 0; c < ints[CCOUNT + i]; ++c) {
            const Int ch = ints[CHILDREN + ints[CSTART + i] + c];
            if (ints[ACTIVE + ch] != 0) {
                act = 1;
                ints[CHOICE + i] = ch;
            }
        }
        if (k == ORIGIN_EMBED && pw[ints[WSTART + i]] != 0.0) {
            act = 1;
            ints[CHOICE + i] = -1;
        }
        ints[ACTIVE + i] = act;
    }
    for (Int i = 0; i < nn; ++i) {
        const Int k = ints[KIND + i];
        if (k < HULL) {
            wit[ints[WSTART + i]] = static_cast<double>(ints[ACTIVE + i]);
        } else if (k == ORIGIN_EMBED) {
            const Int w = ints[WSTART + i];
            wit[w] = ints[ACTIVE + i] != 0 && ints[CHOICE + i] < 0 ? 1.0 : 0.0;
            wit[w + 1] = 0.0;
        }
    }
    const Int n0 = ints[DIM];
    const Int d0 = ints[DSTART];
    for (Int a = 0; a < n0; ++a) f[d0 + a] = u[a];
    for (Int i = 0; i < nn; ++i) {
        if (ints[KIND + i] == AFFINE && ints[ACTIVE + i] != 0) {
            const Int ch = ints[CHILDREN + ints[CSTART + i]];
            kernel::affine_pull(f, ints[PSTART + i] + 2, ints[DSTART + i], ints[DSTART + ch],
                                ints[DIM + i], ints[DIM + ch]);
        }
    }
    for (Int i = nn - 1; i >= 0; --i) {
        if (ints[ACTIVE + i] == 0) continue;
        const Int k = ints[KIND + i];
        const Int oi = ints[OSTART + i];
        const Int ni = ints[DIM + i];
        const Int p = ints[PSTART + i];
        const Int di = ints[DSTART + i];
        const Int j0 = i * nsq;
        double h;
        if (k < HULL) {
            const Int w = ints[WSTART + i];
            if (pw[w] == FLAT) {
                h = flat_point(k, f, p, di, oi, pw, w, ni);
                for (Int a = 0; a < ni * ni; ++a) jw[j0 + a] = 0.0;
                for (Int a = 1; a < local_size(k, f, p) + 1; ++a) wit[w + a] = pw[w + a];
                if (k == TRUNCATED_CONE) wit[w + 3] = f[oi + 2];
            } else if (k == ELLIPSOID) {
                const Int ne = static_cast<Int>(f[p]);
                const Int ke = static_cast<Int>(f[p + 1]);
                if (ne == 6 && ke == 3)
                    h = ellipsoid_piece<6, 3>(f, p, di, oi, wit, w, jw, j0);
                else if (ne == 3 && ke == 3)
                    h = ellipsoid_piece<3, 3>(f, p, di, oi, wit, w, jw, j0);
                else
                    h = ellipsoid_piece(f, p, di, oi, wit, w, jw, j0, ne, ke);
            } else if (k == POLYTOPE || k == BOX) {
                h = 0.0;
                for (Int a = 0; a < ni; ++a) {
                    const double x = k == POLYTOPE
                                         ? f[p + 2 + static_cast<Int>(pw[w + 1]) * ni + a]
                                         : pw[w + 1 + a];
                    f[oi + a] = x;
                    h += x * f[di + a];
                    if (k == BOX) wit[w + 1 + a] = x;
                }
                if (k == POLYTOPE) wit[w + 1] = pw[w + 1];
                for (Int a = 0; a < ni * ni; ++a) jw[j0 + a] = 0.0;
            } else if (k == CONE_CAP) {
                h = cap_piece(f, p, di, oi, wit, w, jw, j0);
            } else {
                h = disk_piece(f, p, di, oi, wit, w, jw, j0, pw[w + 3] > 0.0);
            }
            if (h != h) {
                wit[w] = KINK;
                return NOT_A_NUMBER;
            }
        } else if (k == HULL) {
            const Int ch = ints[CHOICE + i];
            const Int oc = ints[OSTART + ch];
            for (Int a = 0; a < ni + 1; ++a) f[oi + a] = f[oc + a];
            for (Int a = 0; a < ni * ni; ++a) jw[j0 + a] = jw[ch * nsq + a];
            h = f[oi + ni];
        } else if (k == SUM) {
            h = 0.0;
            for (Int a = 0; a < ni; ++a) f[oi + a] = 0.0;
            for (Int a = 0; a < ni * ni; ++a) jw[j0 + a] = 0.0;
            for (Int c = 0; c < ints[CCOUNT + i]; ++c) {
                const Int ch = ints[CHILDREN + ints[CSTART + i] + c];
                const Int oc = ints[OSTART + ch];
                h += f[oc + ni];
                for (Int a = 0; a < ni; ++a) f[oi + a] += f[oc + a];
                for (Int a = 0; a < ni * ni; ++a) jw[j0 + a] += jw[ch * nsq + a];
            }
        } else if (k == EMBED || k == ORIGIN_EMBED) {
            // x -> (0, x) + t: s = (0, s_c) + t, h = h_c + t^T u, J = [[0, 0], [0, J_c]]; an
            // origin embedding's origin: s = t, h = t^T u, J = 0
            const Int ch = ints[CHILDREN + ints[CSTART + i]];
            const Int oc = ints[OSTART + ch];
            const Int nc = ints[DIM + ch];
            const Int lead = ni - nc;
            const bool child = k == EMBED || ints[CHOICE + i] >= 0;
            h = child ? f[oc + nc] : 0.0;
            for (Int a = 0; a < ni; ++a) {
                f[oi + a] = f[p + 3 + a] + ((a >= lead && child) ? f[oc + a - lead] : 0.0);
                h += f[p + 3 + a] * f[di + a];
            }
            for (Int a = 0; a < ni; ++a)
                for (Int a2 = 0; a2 < ni; ++a2)
                    jw[j0 + a * ni + a2] = (a >= lead && a2 >= lead && child)
                                               ? jw[ch * nsq + (a - lead) * nc + a2 - lead]
                                               : 0.0;
        } else {
            // x -> M x + t: s = M s_c + t, h = h_c + t^T u, J = M J_c M^T
            const Int ch = ints[CHILDREN + ints[CSTART + i]];
            const Int oc = ints[OSTART + ch];
            const Int nc = ints[DIM + ch];
            const Int M0 = p + 2;
            const Int t0 = M0 + ni * nc;
            h = f[oc + nc];
            for (Int a = 0; a < ni; ++a) {
                double s = f[t0 + a];
                for (Int b = 0; b < nc; ++b) s += f[M0 + a * nc + b] * f[oc + b];
                f[oi + a] = s;
                h += f[t0 + a] * f[di + a];
            }
            if (ni == 3 && nc == 3)
                affine_jacobian<3, 3>(f, M0, jw, ch * nsq, j0, nn * nsq);
            else
                affine_jacobian(f, M0, jw, ch * nsq, j0, nn * nsq, ni, nc);
        }
        f[oi + ni] = h;
    }
    const Int o0 = ints[OSTART];
    for (Int a = 0; a < n0; ++a) {
        point[a] = f[o0 + a];
        for (Int b = 0; b < n0; ++b) J(a, b) = jw[a * n0 + b];
    }
    return f[o0 + n0];
}

}  // namespace piece

}  // namespace gf
