// graspforce._core.testing: the core's internal steps, bound for the tests that check them one
// by one (the linear algebra, the pieces and the Newton finish, single ZC-IE steps).
//
// Each function takes the arguments of the core function it binds, in its order, and returns
// what that one returns (a tuple where it returns several values, NumPy arrays for its arrays).
// Arrays the function writes to are taken as they are, never converted (a converted copy would
// lose what is written, which the tests read); their shapes are checked first, so that a wrong
// one raises ValueError instead of writing past the array. Work arrays that no test reads are
// allocated here.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <cstdint>
#include <initializer_list>
#include <tuple>
#include <utility>

#include "python/python.hpp"

namespace gf_testing {

namespace nb = nanobind;

// arrays the core writes to (taken as they are), and arrays it only reads (converted if need be;
// read-only ones accepted)
using F1 = nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using F2 = nb::ndarray<double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using I1 = nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using In1 = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using In2 = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

using gf::Int;

inline Int len(const F1& a) { return static_cast<Int>(a.shape(0)); }
inline Int len(const I1& a) { return static_cast<Int>(a.shape(0)); }
inline Int len(const In1& a) { return static_cast<Int>(a.shape(0)); }
inline Int rows(const F2& a) { return static_cast<Int>(a.shape(0)); }
inline Int rows(const In2& a) { return static_cast<Int>(a.shape(0)); }
inline Int cols(const F2& a) { return static_cast<Int>(a.shape(1)); }
inline Int cols(const In2& a) { return static_cast<Int>(a.shape(1)); }

inline gf::Vec vec(const F1& a) { return {a.data(), len(a)}; }
inline gf::IVec ivec(const I1& a) { return {a.data(), len(a)}; }
inline gf::Mat mat(const F2& a) { return {a.data(), rows(a), cols(a), cols(a)}; }
// the core takes views of mutable doubles; it does not write to the arrays passed as In1, In2
inline gf::Vec vec(const In1& a) { return {const_cast<double*>(a.data()), len(a)}; }
inline gf::Mat mat(const In2& a) {
    return {const_cast<double*>(a.data()), rows(a), cols(a), cols(a)};
}

inline void require(bool ok, const char* what) {
    if (!ok) throw nb::value_error(what);
}

using gf_python::numpy;

using gf_python::shot_tuple;

// The dimension of a program's root node, after checking that `ints` holds a program's blocks:
// ints = [nn, kind (nn), dim (nn), ...].
inline Int root_dim(const I1& ints) {
    require(len(ints) >= 3, "ints: not a support program");
    const Int nn = ints.data()[0];
    require(nn >= 1 && 1 + 11 * nn <= len(ints), "ints: not a support program");
    return ints.data()[1 + nn];
}

// the simplex arrays of a shooter in R^n: P (>= k rows, n), Wt (>= k rows), lam (>= k)
inline void check_simplex(const F2& P, const F2& Wt, const F1& lam, Int k, Int n) {
    require(cols(P) == n, "P: expected n columns");
    require(0 <= k && rows(P) >= k && rows(Wt) >= k && len(lam) >= k,
            "P, Wt, lam: fewer than k rows");
}

// ---- linalg.hpp --------------------------------------------------------------------------

inline Int lstsq_append(In2 D, Int n, Int q, Int fact, In1 rhs, F1 x, F2 work, F1 wrhs,
                        F2 house) {
    require(0 <= q && q <= cols(D) && 0 <= n && n <= rows(D), "D: smaller than (n, q)");
    require(0 <= fact && fact <= q, "fact: expected 0 <= fact <= q");
    require(len(rhs) >= n && len(wrhs) >= n && len(x) >= q, "rhs, wrhs, x: too short");
    require(rows(work) >= n && cols(work) >= q, "work: smaller than (n, q)");
    require(rows(house) >= 3 && cols(house) >= q, "house: smaller than (3, q)");
    return gf::lstsq_append(mat(D), n, q, fact, vec(rhs), vec(x), mat(work), vec(wrhs),
                            mat(house));
}

// n x n square work arrays and vectors of at least n entries
inline void check_square(Int n, std::initializer_list<Int> sides, std::initializer_list<Int> lens,
                         const char* what) {
    require(n >= 0, what);
    for (Int s : sides) require(s >= n, what);
    for (Int l : lens) require(l >= n, what);
}

inline Int solve_basic(In2 M, Int n, F2 lu, I1 prow, I1 pcol, In1 b, F1 x) {
    check_square(n, {rows(M), cols(M), rows(lu), cols(lu)},
                 {len(prow), len(pcol), len(b), len(x)},
                 "M, lu, prow, pcol, b, x: smaller than n");
    return gf::solve_basic(mat(M), n, mat(lu), ivec(prow), ivec(pcol), vec(b), vec(x));
}

inline void basic_null_space(In2 lu, I1 pcol, Int n, Int rank, F2 Z, F1 w) {
    check_square(n, {rows(lu), cols(lu), rows(Z)}, {len(pcol), len(w)},
                 "lu, pcol, Z, w: smaller than n");
    require(0 <= rank && rank <= n && cols(Z) >= n - rank, "Z: fewer than n - rank columns");
    for (Int i = 0; i < n; ++i)
        require(0 <= pcol.data()[i] && pcol.data()[i] < n, "pcol: not a permutation of n");
    gf::basic_null_space(mat(lu), ivec(pcol), n, rank, mat(Z), vec(w));
}

// ---- piece.hpp, newton.hpp ---------------------------------------------------------------

inline std::tuple<Int, Int, Int> jacobian_size(I1 ints, F1 f) {
    root_dim(ints);
    const gf::piece::JacobianSize s = gf::piece::jacobian_size(ivec(ints), vec(f));
    return {s.size, s.nmax, s.qmax};
}

inline bool same_piece(I1 ints, In1 wa, In1 wb) {
    root_dim(ints);
    return gf::piece::same_piece(ivec(ints), vec(wa), vec(wb));
}

inline Int flat_columns(I1 ints, F1 f, Int leaf, F2 T, Int off, F2 C, F2 C2) {
    const Int n = root_dim(ints);
    const Int nn = ints.data()[0];
    require(0 <= leaf && leaf < nn && ints.data()[1 + leaf] < gf::HULL, "leaf: not a leaf node");
    const gf::piece::JacobianSize s = gf::piece::jacobian_size(ivec(ints), vec(f));
    require(rows(T) >= n && off >= 0, "T: fewer rows than the set's dimension");
    for (const F2* W : {&C, &C2})
        require(rows(*W) >= s.nmax && cols(*W) >= s.qmax, "C, C2: smaller than (nmax, qmax)");
    return gf::piece::flat_columns(ivec(ints), vec(f), leaf, mat(T), off, mat(C), mat(C2));
}

inline double piece_support(I1 ints, F1 f, In1 u, In1 pw, F1 point, F1 wit, F2 J, F1 jw,
                            Int nmax) {
    const Int n = root_dim(ints);
    const gf::piece::JacobianSize s = gf::piece::jacobian_size(ivec(ints), vec(f));
    require(len(u) == n && len(point) >= n, "u, point: expected the set's dimension");
    require(rows(J) >= n && cols(J) == n, "J: expected (n, n)");
    require(nmax == s.nmax && len(jw) >= s.size, "jw, nmax: not jacobian_size's");
    require(len(wit) >= len(pw), "wit: shorter than the witness pw");
    return gf::piece::piece_support(ivec(ints), vec(f), vec(u), vec(pw), vec(point), vec(wit),
                                    mat(J), vec(jw), nmax);
}

// (ok, t, t_upper, h_n, m, newton_steps, support_calls, normal, V, weights, W)
inline nb::tuple newton_finish(I1 ints, F1 f, In1 r, double eps, In2 P, In2 Wt, In1 lam, Int k,
                               In1 normal, double t, bool corner) {
    const Int n = root_dim(ints);
    require(len(r) == n && len(normal) == n, "r, normal: expected the set's dimension");
    require(cols(P) == n && rows(P) >= k && rows(Wt) >= k && len(lam) >= k && k >= 0,
            "P, Wt, lam: fewer than k rows");
    gf::NewtonOut o = gf::newton_finish(ivec(ints), vec(f), vec(r), eps, mat(P), mat(Wt),
                                        vec(lam), k, vec(normal), t, corner);
    return nb::make_tuple(o.ok, o.t, o.t_up, o.h, o.m, o.steps, o.calls,
                          numpy(std::move(o.normal)), numpy(std::move(o.V)),
                          numpy(std::move(o.weights)), numpy(std::move(o.W)));
}

// newton_finish's ellipsoid path alone: (taken, then newton_finish's tuple when taken)
inline nb::tuple ellipsoid_finish(I1 ints, F1 f, In1 r, double eps, In2 Wt, In1 lam, Int k,
                                  In1 normal, double t) {
    const Int n = root_dim(ints);
    require(len(r) == n && len(normal) == n, "r, normal: expected the set's dimension");
    require(rows(Wt) >= k && len(lam) >= k && k >= 0, "Wt, lam: fewer than k rows");
    std::optional<gf::NewtonOut> o = gf::newton_detail::ellipsoid_finish(
        ivec(ints), vec(f), vec(r), eps, mat(Wt), vec(lam), k, vec(normal), t);
    if (!o) return nb::make_tuple(false);
    return nb::make_tuple(true, o->ok, o->t, o->t_up, o->h, o->m, o->steps, o->calls,
                          numpy(std::move(o->normal)), numpy(std::move(o->V)),
                          numpy(std::move(o->weights)), numpy(std::move(o->W)));
}

// ---- zc_family.hpp, bi_gjk.hpp: single steps ---------------------------------------------

inline void matvec(In2 B, Int n, In1 x, F1 out) {
    check_square(n, {rows(B), cols(B)}, {len(x), len(out)}, "B, x, out: smaller than n");
    gf::zc_family_detail::matvec(mat(B), n, vec(x), vec(out));
}

inline void pivot(F2 B, Int n, In1 alpha, Int js, F1 y, F1 gam) {
    check_square(n, {rows(B), cols(B)}, {len(alpha), len(y), len(gam)},
                 "B, alpha, y, gam: smaller than n");
    require(0 <= js && js < n, "js: expected 0 <= js < n");
    gf::zc_family_detail::pivot(mat(B), n, vec(alpha), js, vec(y), vec(gam));
}

// the active-set subproblem's scratch (Python's `scratch(n)`) is allocated here
inline Int restart(F2 P, F2 Wt, F1 lam, Int k, In1 r) {
    const Int n = len(r);
    check_simplex(P, Wt, lam, k, n);
    gf::ScratchArrays sc(n);
    return gf::zc_family_detail::restart(mat(P), mat(Wt), vec(lam), k, vec(r), sc.sc);
}

// (t + s, k - 1), or (t, k) for a degenerate simplex
inline std::tuple<double, Int> simplex_exit(F2 P, F2 Wt, F1 lam, Int k, In1 r, double t, F2 M,
                                            F2 lu, I1 piv, F1 rhs, F1 mu) {
    const Int n = len(r);
    check_simplex(P, Wt, lam, k, n);
    require(k <= n + 1, "k: at most n + 1 points");
    require(rows(M) >= n + 1 && cols(M) >= k, "M: smaller than (n + 1, k)");
    require(rows(lu) >= k && cols(lu) >= k && len(piv) >= k && len(mu) >= k,
            "lu, piv, mu: smaller than k");
    require(len(rhs) >= n + 1, "rhs: fewer than n + 1 entries");
    const gf::bi_gjk_detail::Exit e = gf::bi_gjk_detail::simplex_exit(
        mat(P), mat(Wt), vec(lam), k, vec(r), t, mat(M), mat(lu), ivec(piv), vec(rhs), vec(mu));
    return {e.t, e.k};
}

// zc_from's simplex Pz, Wz, lz (n + 2 rows), its facet's inverse and directions (0 rows or n)
inline void check_zc_start(I1 ints, In1 r, Int ws, Int mode, const F2& Pz, const F2& Wz,
                           const F1& lz, Int kz, const In2& inverse, const In2& directions) {
    const Int n = root_dim(ints);
    require(len(r) == n, "r: expected the set's dimension");
    require(gf::ZC_ONLY <= mode && mode <= gf::WITH_SMOOTH_NEWTON,
            "mode: not one of zc_from's modes");
    require(rows(Pz) >= n + 2 && cols(Pz) == n, "Pz: expected (n + 2, n)");
    require(rows(Wz) >= n + 2 && cols(Wz) == ws && len(lz) >= n + 2,
            "Wz, lz: expected (n + 2, ws) and n + 2 weights");
    require(0 <= kz && kz <= n, "kz: expected 0 <= kz <= n");
    require(rows(inverse) == 0 || (rows(inverse) == n && cols(inverse) == n),
            "inverse: expected (n, n) or no rows");
    require(rows(directions) == 0 || (rows(directions) >= n && cols(directions) == n),
            "directions: expected (n, n) or no rows");
}

inline nb::tuple zc_from(I1 ints, F1 floats, In1 r, Int ws, double eps, Int max_iter, Int mode,
                         double t, F2 Pz, F2 Wz, F1 lz, Int kz, Int it, Int calls, In2 inverse,
                         In2 directions) {
    check_zc_start(ints, r, ws, mode, Pz, Wz, lz, kz, inverse, directions);
    return shot_tuple(gf::zc_from(ivec(ints), vec(floats), vec(r), ws, eps, max_iter, mode, t,
                                  mat(Pz), mat(Wz), vec(lz), kz, it, calls, mat(inverse),
                                  mat(directions)));
}

// zc_from's loop as compiled for one dimension (3, 6 or 9: every loop over n has a constant
// bound) or for any (0), run from the origin as zc_family runs it, for the tests that compare
// the versions; the simplex and the loop's work arrays are allocated here
inline nb::tuple zc_loop(I1 ints, F1 floats, In1 r, Int ws, double eps, Int max_iter, Int mode,
                         Int compiled_for) {
    namespace Z = gf::zc_family_detail;
    const Int n = root_dim(ints);
    require(len(r) == n, "r: expected the set's dimension");
    require(gf::ZC_ONLY <= mode && mode <= gf::WITH_SMOOTH_NEWTON,
            "mode: not one of zc_from's modes");
    require(compiled_for == 0 || ((compiled_for == 3 || compiled_for == 6 || compiled_for == 9) &&
                                  compiled_for == n),
            "compiled_for: expected 0 (any n) or r's dimension, one of 3, 6, 9");
    gf::Array z((n + 2) * (n + ws + 1));
    const gf::Vec zv = z.vec();
    const gf::Mat Pz = gf::mat_view(zv, 0, n + 2, n);
    const gf::Mat Wz = gf::mat_view(zv, (n + 2) * n, n + 2, ws);
    const gf::Vec lz = zv.segment((n + 2) * (n + ws), n + 2);
    Z::LoopWork w(n, ws);
    const gf::IVec iv = ivec(ints);
    const gf::Vec fv = vec(floats), rv = vec(r);
    gf::Shot s;
    if (compiled_for == 3)
        s = Z::zc_loop<3>(iv, fv, rv, ws, eps, max_iter, mode, 0.0, Pz, Wz, lz, 0, 0, 0,
                          gf::Mat{}, gf::Mat{}, w);
    else if (compiled_for == 6)
        s = Z::zc_loop<6>(iv, fv, rv, ws, eps, max_iter, mode, 0.0, Pz, Wz, lz, 0, 0, 0,
                          gf::Mat{}, gf::Mat{}, w);
    else if (compiled_for == 9)
        s = Z::zc_loop<9>(iv, fv, rv, ws, eps, max_iter, mode, 0.0, Pz, Wz, lz, 0, 0, 0,
                          gf::Mat{}, gf::Mat{}, w);
    else
        s = Z::zc_loop<0>(iv, fv, rv, ws, eps, max_iter, mode, 0.0, Pz, Wz, lz, 0, 0, 0,
                          gf::Mat{}, gf::Mat{}, w);
    return shot_tuple(std::move(s));
}

// ---- start_table.hpp ---------------------------------------------------------------------

inline double table_start(In1 table, In1 floats, In1 r, F2 P, F2 Wt, F1 lam, F1 y, F2 B,
                          F1 scores) {
    if (len(table) == 0) return 0.0;
    const Int n = len(r);
    require(len(table) >= gf::start_table_detail::HEADER, "table: not a start table");
    const double* h = table.data();
    require(static_cast<Int>(h[3]) <= len(floats), "floats: fewer than the table's parameters");
    if (static_cast<Int>(h[1]) != n) return 0.0;
    require(rows(P) >= n && cols(P) == n, "P: expected (n, n) or more rows");
    require(rows(Wt) >= n && cols(Wt) >= static_cast<Int>(h[2]), "Wt: smaller than (n, ws)");
    require(len(lam) >= n && len(y) >= n, "lam, y: fewer than n entries");
    require(rows(B) >= n && cols(B) == n, "B: expected (n, n)");
    require(len(scores) >= static_cast<Int>(h[0]), "scores: fewer entries than facets");
    return gf::start_table_detail::table_start(vec(table), vec(floats), vec(r), mat(P), mat(Wt),
                                               vec(lam), vec(y), mat(B), vec(scores));
}

}  // namespace gf_testing

inline void bind_testing(nanobind::module_& m) {
    namespace nb = nanobind;
    namespace T = gf_testing;
    using namespace nb::literals;
    nb::module_ t = m.def_submodule("testing", "The core's internal steps, for the tests.");

    t.def("lstsq_append", &T::lstsq_append, "D"_a, "n"_a, "q"_a, "fact"_a, "rhs"_a,
          "x"_a.noconvert(), "work"_a.noconvert(), "wrhs"_a.noconvert(), "house"_a.noconvert(),
          "x[:q] = argmin ||D[:n, :q] x - rhs[:n]||, the QR of D's first `fact` columns reused "
          "from work and house: q, or -1 when D is rank deficient.");
    t.def("solve_basic", &T::solve_basic, "M"_a, "n"_a, "lu"_a.noconvert(), "prow"_a.noconvert(),
          "pcol"_a.noconvert(), "b"_a, "x"_a.noconvert(),
          "A basic solution of M[:n, :n] x = b by LU with complete pivoting: the rank.");
    t.def("basic_null_space", &T::basic_null_space, "lu"_a, "pcol"_a.noconvert(), "n"_a,
          "rank"_a, "Z"_a.noconvert(), "w"_a.noconvert(),
          "Z[:n, :n - rank]: the null space of the matrix solve_basic factored.");

    t.attr("FLAT") = gf::piece::FLAT;
    t.attr("KINK") = gf::piece::KINK;
    t.def("jacobian_size", &T::jacobian_size, "ints"_a.noconvert(), "f"_a.noconvert(),
          "(work entries of piece_support, largest node dimension, largest flat local point).");
    t.def("same_piece", &T::same_piece, "ints"_a.noconvert(), "wa"_a, "wb"_a,
          "Whether two witnesses name the same smooth piece.");
    t.def("flat_columns", &T::flat_columns, "ints"_a.noconvert(), "f"_a.noconvert(), "leaf"_a,
          "T"_a.noconvert(), "off"_a, "C"_a.noconvert(), "C2"_a.noconvert(),
          "T[:, off:off + q] = L S for a flat leaf: q, or -1 when T has no room.");
    t.def("piece_support", &T::piece_support, "ints"_a.noconvert(), "f"_a.noconvert(), "u"_a,
          "pw"_a, "point"_a.noconvert(), "wit"_a.noconvert(), "J"_a.noconvert(),
          "jw"_a.noconvert(), "nmax"_a,
          "h_P(u) of the piece named by pw (NaN at a kink); s_P(u) into point, its witness into "
          "wit, J_P(u) into J.");
    t.def("newton_finish", &T::newton_finish, "ints"_a.noconvert(), "f"_a.noconvert(), "r"_a,
          "eps"_a, "P"_a, "Wt"_a, "lam"_a, "k"_a, "normal"_a, "t"_a, "corner"_a,
          "The Newton finish from the simplex P[:k]: (ok, t, t_upper, h_n, m, newton_steps, "
          "support_calls, normal, V, weights, W).");
    t.def("ellipsoid_finish", &T::ellipsoid_finish, "ints"_a.noconvert(), "f"_a.noconvert(),
          "r"_a, "eps"_a, "Wt"_a, "lam"_a, "k"_a, "normal"_a, "t"_a,
          "newton_finish's path for hulls of smooth ellipsoid pieces: (False,) when it hands "
          "over to the general path, else (True, newton_finish's tuple).");

    t.attr("ZC_ONLY") = gf::ZC_ONLY;
    t.attr("WITH_IE") = gf::WITH_IE;
    t.attr("UNTIL_FACET") = gf::UNTIL_FACET;
    t.attr("WITH_NEWTON") = gf::WITH_NEWTON;
    t.attr("WITH_SMOOTH_NEWTON") = gf::WITH_SMOOTH_NEWTON;
    t.attr("FACET") = gf::FACET;
    t.def("matvec", &T::matvec, "B"_a, "n"_a, "x"_a, "out"_a.noconvert(), "out = B x.");
    t.def("pivot", &T::pivot, "B"_a.noconvert(), "n"_a, "alpha"_a, "js"_a, "y"_a.noconvert(),
          "gam"_a.noconvert(),
          "The facet's inverse B, y = B^T 1 and gam = B r after column js is replaced "
          "(alpha = B s).");
    t.def("restart", &T::restart, "P"_a.noconvert(), "Wt"_a.noconvert(), "lam"_a.noconvert(),
          "k"_a, "r"_a, "ZC-based's warm start: drops one point of P[:k], returns the new k.");
    t.def("simplex_exit", &T::simplex_exit, "P"_a.noconvert(), "Wt"_a.noconvert(),
          "lam"_a.noconvert(), "k"_a, "r"_a, "t"_a, "M"_a.noconvert(), "lu"_a.noconvert(),
          "piv"_a.noconvert(), "rhs"_a.noconvert(), "mu"_a.noconvert(),
          "Where the ray leaves the simplex P[:k] that holds t r: (t + s, k - 1).");
    t.def("zc_from", &T::zc_from, "ints"_a.noconvert(), "floats"_a.noconvert(), "r"_a, "ws"_a,
          "eps"_a, "max_iter"_a, "mode"_a, "t"_a, "Pz"_a.noconvert(), "Wz"_a.noconvert(),
          "lz"_a.noconvert(), "kz"_a, "it"_a, "calls"_a, "inverse"_a, "directions"_a,
          "ZC-based iterations from t r, the combination lz of Pz[:kz]: the shot's tuple.");
    t.def("zc_loop", &T::zc_loop, "ints"_a.noconvert(), "floats"_a.noconvert(), "r"_a, "ws"_a,
          "eps"_a, "max_iter"_a, "mode"_a, "compiled_for"_a,
          "zc_from's loop compiled for n = compiled_for (3, 6, 9) or for any n (0), from the "
          "origin: the shot's tuple.");

    t.def("table_start", &T::table_start, "table"_a, "floats"_a, "r"_a, "P"_a.noconvert(),
          "Wt"_a.noconvert(), "lam"_a.noconvert(), "y"_a.noconvert(), "B"_a.noconvert(),
          "scores"_a.noconvert(),
          "t_0 > 0 with the start table's facet that the ray leaves CH(P_0) through, or 0.0.");
}
