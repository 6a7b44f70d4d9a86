// graspforce._core.timing: loops that time the core's hot calls inside compiled code, for the
// benchmarks (a call from Python costs more than the support map it would time).
//
// Every loop adds up what each call returns and hands the sum back, so that the compiler cannot
// drop a call whose result would otherwise go unused; the arrays the calls write to (a program's
// scratch, a support point, a packed result) are the caller's, as in the core's own entry points.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <tuple>
#include <utility>

#include "python/python.hpp"

namespace gf_timing {

namespace nb = nanobind;

using Clock = std::chrono::steady_clock;

// arrays a loop writes to (taken as they are, never converted: a copy would hide the writes),
// and arrays it only reads
using F1 = nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using I1 = nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using In2 = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using In3 = nb::ndarray<const double, nb::ndim<3>, nb::c_contig, nb::device::cpu>;

inline gf::Vec vec(F1& a) { return {a.data(), static_cast<gf::Int>(a.shape(0))}; }
inline gf::IVec ivec(I1& a) { return {a.data(), static_cast<gf::Int>(a.shape(0))}; }
// row i of a read-only (k, n) array; the core takes views of mutable doubles but does not write
// to the directions, rays and poses it is given
inline gf::Vec row(In2& a, size_t i) {
    const auto n = static_cast<gf::Int>(a.shape(1));
    return {const_cast<double*>(a.data()) + i * a.shape(1), n};
}
// the i-th (3, 3) matrix of a (k, 3, 3) array
inline gf::Mat matrix(In3& a, size_t i) {
    return {const_cast<double*>(a.data()) + 9 * i, 3, 3, 3};
}

inline double ns_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
}

using gf_python::numpy;

// the dimension of a program's root node: ints = [nn, kind (nn), dim (nn), ...]
inline gf::Int root_dim(I1& ints) {
    if (ints.shape(0) < 3) throw nb::value_error("ints: not a support program");
    const std::int64_t nn = ints.data()[0];
    if (nn < 1 || static_cast<size_t>(1 + 11 * nn) > ints.shape(0))
        throw nb::value_error("ints: not a support program");
    return ints.data()[1 + nn];
}

inline void check_positive(std::int64_t x, const char* name) {
    if (x < 1) throw nb::value_error((std::string(name) + ": must be at least 1").c_str());
}

// (ns per support call in each pass (passes,), sum of h over all calls). A pass is `sweeps`
// sweeps over U's rows, timed as one block: a call (tens of ns) is too short to time alone.
inline std::tuple<nb::object, double> support_loop(I1 ints, F1 floats, In2 U, F1 point, F1 wit,
                                                   std::int64_t passes, std::int64_t sweeps) {
    check_positive(passes, "passes");
    check_positive(sweeps, "sweeps");
    const gf::Int n = root_dim(ints);
    if (U.shape(0) < 1 || static_cast<gf::Int>(U.shape(1)) != n)
        throw nb::value_error("U: expected (k >= 1, n) directions, n the program's dimension");
    if (static_cast<gf::Int>(point.shape(0)) < n)
        throw nb::value_error("point: shorter than the program's dimension");
    gf::Array ns(passes);
    double total = 0.0;
    {
        nb::gil_scoped_release nogil;
        const gf::IVec iv = ivec(ints);
        const gf::Vec fv = vec(floats), pv = vec(point), wv = vec(wit);
        const size_t k = U.shape(0);
        const double calls = static_cast<double>(sweeps) * static_cast<double>(k);
        for (std::int64_t p = 0; p < passes; ++p) {
            const Clock::time_point t0 = Clock::now();
            for (std::int64_t s = 0; s < sweeps; ++s)
                for (size_t i = 0; i < k; ++i) total += gf::support(iv, fv, row(U, i), pv, wv);
            ns.data[static_cast<size_t>(p)] = ns_since(t0) / calls;
        }
    }
    return {numpy(std::move(ns)), total};
}

// (ns of each query (passes, k), sum of sigma over all queries): growth queries at the k pairs
// of poses (R_a[i], p_a[i]), (R_b[i], p_b[i]) in turn, each timed alone, `passes` times over.
inline std::tuple<nb::object, double> growth_loop(I1 ints, F1 floats, In3 R_a, In2 p_a,
                                                  In3 R_b, In2 p_b, F1 packed,
                                                  std::int64_t passes) {
    namespace G = gf::growth;
    check_positive(passes, "passes");
    root_dim(ints);
    const size_t k = R_a.shape(0);
    for (In3* R : {&R_a, &R_b})
        if (R->shape(0) != k || R->shape(1) != 3 || R->shape(2) != 3)
            throw nb::value_error("R_a, R_b: expected (k, 3, 3) rotations, k the same");
    for (In2* p : {&p_a, &p_b})
        if (p->shape(0) != k || p->shape(1) != 3)
            throw nb::value_error("p_a, p_b: expected (k, 3) translations, k as the rotations");
    if (k < 1) throw nb::value_error("R_a: no poses");
    if (floats.shape(0) < static_cast<size_t>(G::TAIL))
        throw nb::value_error("floats: not a growth query's program (no tail)");
    const auto ws = static_cast<gf::Int>(floats.data()[floats.shape(0) - G::TAIL + G::WS]);
    if (static_cast<gf::Int>(packed.shape(0)) < G::FRAME + gf::capacity(3, ws))
        throw nb::value_error("packed: shorter than the query's frame and shot");
    gf::Array ns(passes, static_cast<gf::Int>(k));
    double total = 0.0;
    {
        nb::gil_scoped_release nogil;
        const gf::IVec iv = ivec(ints);
        const gf::Vec fv = vec(floats), out = vec(packed);
        const gf::Mat times = ns.mat();
        for (std::int64_t p = 0; p < passes; ++p) {
            for (size_t i = 0; i < k; ++i) {
                const Clock::time_point t0 = Clock::now();
                const gf::GrowthOut g = gf::growth_query(iv, fv, matrix(R_a, i), row(p_a, i),
                                                         matrix(R_b, i), row(p_b, i), out);
                times(p, static_cast<gf::Int>(i)) = ns_since(t0);
                total += g.sigma;
            }
        }
    }
    return {numpy(std::move(ns)), total};
}

// (ns of each shot (passes, k), sum of t over all shots): gf::shoot (no start table) along the
// rays R[i] in turn, each timed alone, `passes` times over.
inline std::tuple<nb::object, double> shoot_loop(I1 ints, F1 floats, In2 R, std::int64_t ws,
                                                 std::int64_t method, double eps,
                                                 std::int64_t max_iter, std::int64_t passes) {
    check_positive(passes, "passes");
    const gf::Int n = root_dim(ints);
    if (R.shape(0) < 1 || static_cast<gf::Int>(R.shape(1)) != n)
        throw nb::value_error("R: expected (k >= 1, n) rays, n the program's dimension");
    if (method < gf::GJK_BASED || method > gf::ZC_IE_PAPER)
        throw nb::value_error("method: not a method code");
    const size_t k = R.shape(0);
    gf::Array ns(passes, static_cast<gf::Int>(k));
    double total = 0.0;
    {
        nb::gil_scoped_release nogil;
        const gf::IVec iv = ivec(ints);
        const gf::Vec fv = vec(floats);
        const gf::Mat times = ns.mat();
        for (std::int64_t p = 0; p < passes; ++p) {
            for (size_t i = 0; i < k; ++i) {
                const Clock::time_point t0 = Clock::now();
                const gf::Shot s = gf::shoot(iv, fv, row(R, i), ws, method, eps, max_iter);
                times(p, static_cast<gf::Int>(i)) = ns_since(t0);
                total += s.t;
            }
        }
    }
    return {numpy(std::move(ns)), total};
}

// (ns per call in each pass (passes,), sum of t over all calls): newton_finish from one simplex,
// `repeats` calls per pass timed as one block. Every call reads the same inputs (newton_finish
// writes only the program's scratch).
inline std::tuple<nb::object, double> newton_loop(I1 ints, F1 floats, F1 r, double eps, F1 P,
                                                  F1 Wt, F1 lam, std::int64_t k, F1 normal,
                                                  double t, bool corner, std::int64_t passes,
                                                  std::int64_t repeats) {
    check_positive(passes, "passes");
    check_positive(repeats, "repeats");
    const gf::Int n = root_dim(ints);
    if (static_cast<gf::Int>(r.shape(0)) != n || static_cast<gf::Int>(normal.shape(0)) != n)
        throw nb::value_error("r, normal: expected the program's dimension");
    if (k < 1 || static_cast<std::int64_t>(lam.shape(0)) < k ||
        static_cast<std::int64_t>(P.shape(0)) < k * n || Wt.shape(0) % k != 0)
        throw nb::value_error("P, Wt, lam: expected k rows each, flattened");
    const auto ws = static_cast<gf::Int>(Wt.shape(0)) / k;
    gf::Array ns(passes);
    double total = 0.0;
    {
        nb::gil_scoped_release nogil;
        const gf::Mat Pm{P.data(), k, n, n};
        const gf::Mat Wm{Wt.data(), k, ws, ws};
        for (std::int64_t p = 0; p < passes; ++p) {
            const Clock::time_point t0 = Clock::now();
            for (std::int64_t i = 0; i < repeats; ++i)
                total += gf::newton_finish(ivec(ints), vec(floats), vec(r), eps, Pm, Wm,
                                           vec(lam), k, vec(normal), t, corner)
                             .t;
            ns.data[static_cast<size_t>(p)] = ns_since(t0) / static_cast<double>(repeats);
        }
    }
    return {numpy(std::move(ns)), total};
}

}  // namespace gf_timing

inline void bind_timing(nanobind::module_& m) {
    namespace nb = nanobind;
    using namespace nb::literals;
    nb::module_ t = m.def_submodule("timing", "Timing loops for the benchmarks.");
    // the compiler and its optimization level, for the benchmarks' environment lines (the
    // predefined macros tell -Os, which nanobind's Release builds use, from the speed levels)
#if defined(__clang__)
    const std::string compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
    const std::string compiler = "GCC " __VERSION__;
#else
    const std::string compiler = "an unknown compiler";
#endif
#if defined(__OPTIMIZE_SIZE__)
    const char* level = "-Os";
#elif defined(__OPTIMIZE__)
    const char* level = "optimized for speed";
#else
    const char* level = "unoptimized";
#endif
    t.attr("compiler") = nb::str((compiler + ", " + level).c_str());
    t.def("support_loop", &gf_timing::support_loop, "ints"_a.noconvert(),
          "floats"_a.noconvert(), "U"_a.noconvert(), "point"_a.noconvert(), "wit"_a.noconvert(),
          "passes"_a, "sweeps"_a = 1,
          "support(ints, floats, U[i], point, wit) for every row of U, `sweeps` times per pass "
          "(wit: the set's witness_size entries): (ns per call in each pass, sum of h).");
    t.def("growth_loop", &gf_timing::growth_loop, "ints"_a.noconvert(), "floats"_a.noconvert(),
          "R_a"_a.noconvert(), "p_a"_a.noconvert(), "R_b"_a.noconvert(), "p_b"_a.noconvert(),
          "packed"_a.noconvert(), "passes"_a,
          "growth_query at each pair of poses (R_a[i], p_a[i]), (R_b[i], p_b[i]), `passes` "
          "times over: (ns of each query (passes, k), sum of sigma).");
    t.def("shoot_loop", &gf_timing::shoot_loop, "ints"_a.noconvert(), "floats"_a.noconvert(),
          "R"_a.noconvert(), "ws"_a, "method"_a, "eps"_a, "max_iter"_a, "passes"_a,
          "shoot (no start table) along each row of R, `passes` times over: (ns of each shot "
          "(passes, k), sum of t).");
    t.def("newton_loop", &gf_timing::newton_loop, "ints"_a.noconvert(),
          "floats"_a.noconvert(), "r"_a.noconvert(), "eps"_a, "P"_a.noconvert(),
          "Wt"_a.noconvert(), "lam"_a.noconvert(), "k"_a, "normal"_a.noconvert(), "t"_a,
          "corner"_a, "passes"_a, "repeats"_a,
          "newton_finish from the simplex P[:k] (P, Wt flattened), `repeats` calls a pass: "
          "(ns per call in each pass, sum of t).");
}
