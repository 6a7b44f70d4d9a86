// The functions one part of the core calls in another, declared once. Each is defined in the
// header named beside it; all.hpp includes them all, in the order of the layers.
#pragma once

#include <utility>

#include "arrays.hpp"
#include "codes.hpp"

namespace gf {

// ---- kernel.hpp -------------------------------------------------------------------------
// h_A(u) (returned) and s_A(u) (into point) of eq. (2); the witness goes into wit.
double support(IVec ints, Vec f, Vec u, Vec point, Vec wit);

// ---- linalg.hpp -------------------------------------------------------------------------
inline double dot(Vec a, Vec b) {
    double s = 0.0;
    for (Int i = 0; i < a.n; ++i) s += a[i] * b[i];
    return s;
}
inline double smallest(Vec x, Int n) {
    double m = x[0];
    for (Int i = 1; i < n; ++i) m = std::min(m, x[i]);
    return m;
}
bool lstsq(Mat D, Int n, Int q, Vec rhs, Vec x, Int x0, Mat work, Vec wrhs);
Int lstsq_append(Mat D, Int n, Int q, Int fact, Vec rhs, Vec x, Mat work, Vec wrhs, Mat house);
bool lu_factor(Mat M, Int n, Mat lu, IVec piv);
bool invert(Mat M, Int n, Mat B, IVec piv);
void lu_solve(Mat lu, IVec piv, Int n, Vec b, Vec x);
void lu_solve_t(Mat lu, IVec piv, Int n, Vec b, Vec x);
Int solve_basic(Mat M, Int n, Mat lu, IVec prow, IVec pcol, Vec b, Vec x, double tol = 1e-13);
void basic_null_space(Mat lu, IVec pcol, Int n, Int rank, Mat Z, Vec w);

// ---- corral.hpp -------------------------------------------------------------------------
constexpr double FACET_HOLDS = 1e-12;   // on_point: an IE step's facet weights, Fig. 3b's rule
constexpr double POINT_HOLDS = 1e-9;    // on_point: ZC's and Bi-GJK's final point, any hit
inline void set_row(Mat P, Mat Wt, Int j, Vec point, Vec wit) {
    for (Int i = 0; i < P.cols; ++i) P(j, i) = point[i];
    for (Int i = 0; i < Wt.cols; ++i) Wt(j, i) = wit[i];
}
inline Int drop_point(Mat P, Mat Wt, Vec lam, Int k, Int j) {
    for (Int i = j; i < k - 1; ++i) {
        for (Int a = 0; a < P.cols; ++a) P(i, a) = P(i + 1, a);
        for (Int a = 0; a < Wt.cols; ++a) Wt(i, a) = Wt(i + 1, a);
        lam[i] = lam[i + 1];
    }
    return k - 1;
}
// (||sum_j x_j P_j - b||^2, ||b||^2) over the rows P[:k]
inline std::pair<double, double> residual2(Mat P, Vec x, Int k, Vec b) {
    double res = 0.0, bn = 0.0;
    for (Int i = 0; i < P.cols; ++i) {
        double e = -b[i];
        for (Int j = 0; j < k; ++j) e += x[j] * P(j, i);
        res += e * e;
        bn += b[i] * b[i];
    }
    return {res, bn};
}
bool on_point(Mat P, Vec x, Int k, Vec b, double tol);
bool reproduce(Mat P, Vec x, Int k, Vec b);
double weights_on_ray(Mat S, Int m, Vec r, Vec x, Mat D, Mat work, Vec wrhs, Vec rhs);
inline void combine(Mat P, Vec lam, Int k, Vec out) {
    for (Int i = 0; i < P.cols; ++i) out[i] = 0.0;
    for (Int j = 0; j < k; ++j)
        for (Int i = 0; i < P.cols; ++i) out[i] += lam[j] * P(j, i);
}

// ---- distance.hpp -----------------------------------------------------------------------
// the work arrays of the active-set subproblem (Python's `scratch(n)` tuple, in its order)
struct Scratch {
    Mat D;      // (n, n + 1)
    Mat work;   // (n, n + 1)
    Vec rhs;    // (n)
    Vec wrhs;   // (n)
    Vec x;      // (n + 2)
    Mat house;  // (3, n + 1)
};
// Python's scratch_of(rows, x, n): rows (2n + 5, n + 1), x (n + 2)
inline Scratch scratch_of(Mat rows, Vec x, Int n) {
    return {rows.top(n), rows.rows_range(n, 2 * n), rows.row(2 * n + 3).head(n),
            rows.row(2 * n + 4).head(n), x, rows.rows_range(2 * n, 2 * n + 3)};
}
// Python's scratch(n): owns its arrays
struct ScratchArrays {
    Array rows, x;
    Scratch sc;
    explicit ScratchArrays(Int n) : rows(2 * n + 5, n + 1), x(n + 2) {
        sc = scratch_of(rows.mat(), x.vec(), n);
    }
    ScratchArrays(const ScratchArrays&) = delete;
    ScratchArrays& operator=(const ScratchArrays&) = delete;
};
// (status, k, d, h, iterations, support_calls) of gjk and zc
struct DistOut {
    Int status;
    Int k;
    double d;
    double h;
    Int it;
    Int calls;
};
DistOut gjk(IVec ints, Vec floats, Vec b, Mat P, Mat Wt, Vec lam, Int k, double eps_rel,
            double eps_abs, bool rel_to_offset, Int max_iter, Vec nvec, Vec v, Vec point,
            Vec wit, const Scratch& sc);
DistOut zc(IVec ints, Vec floats, Vec shift, Vec target, Mat P, Mat Wt, Vec lam, Int k,
           double eps_rel, double eps_abs, Int max_iter, Vec nvec, Vec v, Vec point, Vec wit,
           const Scratch& sc);

// ---- newton.hpp -------------------------------------------------------------------------
// Python's tuple (ok, t, t_upper, h_n, m, newton_steps, support_calls, normal, V, weights, W);
// V, weights, W hold at least m rows
struct NewtonOut {
    bool ok;
    double t;
    double t_up;
    double h;
    Int m;
    Int steps;
    Int calls;
    Array normal;
    Array V;        // (>= m, n)
    Array weights;  // (>= m)
    Array W;        // (>= m, ws)
};
NewtonOut newton_finish(IVec ints, Vec f, Vec r, double eps, Mat P, Mat Wt, Vec lam, Int k,
                        Vec normal, double t, bool corner);
bool smooth_finish_applies(IVec ints, Vec f, Int n);
NewtonOut smooth_finish(IVec ints, Vec f, Vec r, double eps, Mat Wt, Vec lam, Int k, Vec normal,
                        double t);

// ---- shot.hpp ---------------------------------------------------------------------------
// a shooter's result, Python's 11-tuple of _result:
//   out[0] status, out[1] t, out[2] t_up, out[3] h_n, out[4] iters, out[5] calls,
//   out[6] normal (n), out[7] V (k, n), out[8] lam (k), out[9] W (k, ws), out[10] singular
struct Shot {
    Int status = LIMIT;
    double t = 0.0;
    double t_up = 0.0;
    double h_n = 0.0;
    Int iters = 0;
    Int calls = 0;
    Array normal;
    Array V;
    Array lam;
    Array W;
    Int singular = 0;
    Int k() const { return V.rows; }
};
// A bound t_upper = h / n^T r below the t of points P[:k] by at most this much (relative) is
// rounding: FACE_ROUNDING, or where h is far smaller than the points (a normal nearly orthogonal
// to them and to r), the rounding of h, ~64 ulps of their size, relative to h; never more than
// FACE_ROUNDING_MAX.
constexpr double FACE_ROUNDING = 1e-12;
constexpr double FACE_ROUNDING_MAX = 1e-10;
inline double face_rounding(Mat P, Int k, double h) {
    double vmax = 0.0;
    for (Int j = 0; j < k; ++j) {
        double pp = 0.0;
        for (Int i = 0; i < P.cols; ++i) pp += P(j, i) * P(j, i);
        vmax = std::max(vmax, pp);
    }
    const double rho = 64.0 * 2.220446049250313e-16 * std::sqrt(vmax) / std::abs(h);
    return std::min(std::max(FACE_ROUNDING, rho), FACE_ROUNDING_MAX);
}
// A stalled ZC's h_A(n) >= 0 at the origin is a miss certificate (h_A(n) <= 0 < n^T r) only
// while it is rounding: at most MISS_ROUNDING of the size of its points P[:k] (the rounding a
// stalled cone's normal keeps, ~100 ulps of sums of a few support values).
constexpr double MISS_ROUNDING = 1e-11;
inline bool miss_to_rounding(double h, Mat P, Int k) {
    if (h <= 0.0) return true;
    double vmax = 0.0;
    for (Int j = 0; j < k; ++j) {
        double pp = 0.0;
        for (Int i = 0; i < P.cols; ++i) pp += P(j, i) * P(j, i);
        vmax = std::max(vmax, pp);
    }
    return h <= MISS_ROUNDING * std::sqrt(vmax);
}
// The relative rounding of a bound t_upper = h / n^T r (unit n) for a normal nearly orthogonal
// to r: n^T r, a sum of n products, is rounded by up to n ulps of ||r||, large relative to n^T r
// there. (h's own rounding, relative to A's size, is the problem's conditioning where the origin
// is near A's boundary, the paper's sphere at small lambda, shared by every method and by an
// exact solver.)
inline double bound_rounding(Vec n, Vec r) {
    return static_cast<double>(r.n) * 2.220446049250313e-16 * std::sqrt(dot(r, r)) /
           std::abs(dot(n, r));
}
// a hit's t_upper, below t by at most rho (relative: face_rounding), is t
double reported_upper(Int status, double t, double t_up, double rho);
// Python's _result: copies normal, P[:k], lam[:k], Wt[:k]; t_up through reported_upper
Shot make_result(Int status, double t, double t_up, double h_n, Int iters, Int calls,
                 Vec normal, Mat P, Vec lam, Mat Wt, Int k, Int singular);
// Python's _keep: save the simplex P[:k] (Wt, lam) into Pz, Wz, lz; changed >= 0: only that row
// of P and Wt differs from what Pz, Wz hold. Returns k.
Int keep(Mat P, Mat Wt, Vec lam, Int k, Mat Pz, Mat Wz, Vec lz, Int changed = -1);
// Python's _holds: whether lam[:k] of P[:k] reproduce t r (written to b) to tol relative
bool holds(Mat P, Vec lam, Int k, double t, Vec r, Vec b, double tol);
// the tolerance a final point is held to: POINT_HOLDS, or eps where it is tighter (a point off the
// ray by more than eps t would widen the certified bracket beyond eps), not below FACET_HOLDS
inline double point_holds(double eps) { return std::min(POINT_HOLDS, std::max(eps, FACET_HOLDS)); }
// A hit only with its certificate: t r in A to point_holds(eps) relative and t_upper within eps
Shot certify(Shot out, Vec r, double eps);

// ---- zc_family.hpp ----------------------------------------------------------------------
// Pz, Wz, lz: the caller's, at least n + 2 rows (written to). inverse: (n, n) or 0 rows.
// directions: at least n rows of unit support directions of Pz[:n], or 0 rows.
Shot zc_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode,
             double t, Mat Pz, Mat Wz, Vec lz, Int kz, Int it, Int calls, Mat inverse,
             Mat directions);
Shot zc_family(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode);
// ZC-based iterations from the origin until a facet the ray crosses: status FACET with it in V,
// or the shot as it ended
Shot first_facet(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter);
// zc_from from a record's simplex V[:k] (witnesses W, weights lam), copied into arrays with the
// n + 2 rows zc_from writes to
Shot zc_from_simplex(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Int mode,
                     double t, Mat V, Mat W, Vec lam, Int k, Int it, Int calls);

// ---- gjk_based.hpp, bi_gjk.hpp ------------------------------------------------------------
Shot gjk_based(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter);
Shot bi_gjk(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter);
// P, Wt, lam: at least n + 2 rows
Shot bi_gjk_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, double t_lo,
                 Mat P, Mat Wt, Vec lam, Int k, Vec u, Int calls);

// ---- ie.hpp -----------------------------------------------------------------------------
Shot ie(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter);
Shot ie_from(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Mat V, Mat Wv,
             Int it, Int calls);

// ---- dispatch.hpp -----------------------------------------------------------------------
Shot shoot(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps, Int max_iter);
Shot unstall(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Shot out);

// ---- start_table.hpp --------------------------------------------------------------------
Shot shoot_with_table(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps,
                      Int max_iter, Vec table);

// ---- packed.hpp -------------------------------------------------------------------------
// (status, t, t_upper, h_n, iterations, support_calls, singular_steps, k)
struct Head {
    Int status;
    double t;
    double t_up;
    double h_n;
    Int iters;
    Int calls;
    Int singular;
    Int k;
};
inline Int capacity(Int n, Int ws) { return n + (n + 2) * (1 + n + ws); }
void pack_arrays(Vec normal, Mat V, Vec lam, Mat W, Int k, Vec packed, Int e);
Head pack(const Shot& out, Vec packed, Int e);

// ---- entry points (the bindings call these) -----------------------------------------------
// ray_shoot.py's shoot_packed: status BAD_RAY and no shot when r is not finite or is zero
constexpr Int BAD_RAY = -1;
Head shoot_packed(IVec ints, Vec floats, Vec r, Int ws, Int method, double eps, Int max_iter,
                  Vec packed, Vec table);
// forces.hpp: statuses that say no shot was made
constexpr Int BAD_WRENCH = -1;
constexpr Int ZERO_WRENCH = -2;
// no answer in a rank-deficient grasp's span (forces.hpp): the caller shoots at the full set
constexpr Int FULL_SET = -3;
Head shoot_and_read_forces(Vec w_ext, Int method, double eps, Int max_iter, Vec packed,
                           Vec start, IVec ints, Vec floats, Vec reader, Vec span);
// warm.hpp
Head shoot_warm(IVec ints, Vec floats, Vec r, Int ws, double eps, Int max_iter, Vec normal,
                double spread, Vec packed, Int e);
// growth.hpp: (code, verdict, sigma, sigma_lower, sigma_upper, iterations, support_calls)
struct GrowthOut {
    Int code;
    Int verdict;
    double sigma;
    double lower;
    double upper;
    Int iterations;
    Int calls;
};
GrowthOut growth_query(IVec ints, Vec floats, Mat R_a, Vec p_a, Mat R_b, Vec p_b, Vec packed);
// entry.hpp: gf.closest_point's (st, d, gap, it, calls, v, V, lam, W)
struct ClosestOut {
    Int status;
    double d;
    double gap;
    Int it;
    Int calls;
    Array v;
    Array V;
    Array lam;
    Array W;
};
ClosestOut closest_point(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter);
// gf.cone_distance's (st, d, h, it, calls, v, nvec, V, lam, W)
struct ConeOut {
    Int status;
    double d;
    double h;
    Int it;
    Int calls;
    Array v;
    Array normal;
    Array V;
    Array lam;
    Array W;
};
ConeOut cone_distance(IVec ints, Vec floats, Vec b, Int ws, double eps, Int max_iter);

}  // namespace gf
