// graspforce._core: the compiled core as seen from Python.
//
// Every entry point takes NumPy arrays of exactly the documented kind (C-contiguous float64, or
// int64 for programs) and refuses anything else with a TypeError, without converting: several of
// them write into their arguments (the packed result; the growth query's program), which a
// converted copy would lose. The computation runs with the GIL released, and every entry point but
// the growth query works on its own copy of the set's program (`program_copy`), so threads may
// shoot at one set at the same time.
#include <nanobind/nanobind.h>
#include <nanobind/stl/tuple.h>

#include <tuple>
#include <utility>

#include "python/python.hpp"
#include "python/batch.hpp"
#include "python/min_force_call.hpp"
#include "python/min_force_method.hpp"
#include "python/testing.hpp"
#include "python/timing.hpp"

namespace nb = nanobind;
using namespace nb::literals;
using namespace gf_python;

NB_MODULE(_core, m) {
    if (_import_array() < 0) throw nb::python_error();
    m.doc() = "The compiled core of graspforce: support programs, GJK, ZC and the ray shooters.";

    m.def(
        "support",
        [](InI1 ints, In1 floats, In1 u, F1 point, F1 wit) {
            nb::gil_scoped_release nogil;
            const Program prog = program_copy(ints, floats);
            return gf::support(prog.ints, prog.floats, vec(u), vec(point), vec(wit));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "u"_a.noconvert(),
        "point"_a.noconvert(), "wit"_a.noconvert(),
        "h_A(u) (returned) and s_A(u) (into point) of eq. (2); the witness into wit.");

    m.def(
        "closest_point",
        [](InI1 ints, In1 floats, In1 b, gf::Int ws, double eps, gf::Int max_iter) {
            gf::ClosestOut out;
            {
                nb::gil_scoped_release nogil;
                const Program prog = program_copy(ints, floats);
                out = gf::closest_point(prog.ints, prog.floats, vec(b), ws, eps, max_iter);
            }
            return nb::make_tuple(out.status, out.d, out.gap, out.it, out.calls,
                                  numpy(out.v), numpy(out.V),
                                  numpy(out.lam), numpy(out.W));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "b"_a.noconvert(), "ws"_a, "eps"_a,
        "max_iter"_a,
        "GJK (section 2.2): (status, d, gap, iterations, calls, v, V, weights, witnesses).");

    m.def(
        "cone_distance",
        [](InI1 ints, In1 floats, In1 b, gf::Int ws, double eps, gf::Int max_iter) {
            gf::ConeOut out;
            {
                nb::gil_scoped_release nogil;
                const Program prog = program_copy(ints, floats);
                out = gf::cone_distance(prog.ints, prog.floats, vec(b), ws, eps, max_iter);
            }
            return nb::make_tuple(out.status, out.d, out.h, out.it, out.calls,
                                  numpy(out.v), numpy(out.normal),
                                  numpy(out.V), numpy(out.lam),
                                  numpy(out.W));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "b"_a.noconvert(), "ws"_a, "eps"_a,
        "max_iter"_a,
        "ZC (section 2.3): (status, d, h, iterations, calls, v, normal, V, weights, "
        "witnesses).");

    m.def(
        "shoot",
        [](InI1 ints, In1 floats, In1 r, gf::Int ws, gf::Int method, double eps,
           gf::Int max_iter) {
            gf::Shot out;
            {
                nb::gil_scoped_release nogil;
                const Program prog = program_copy(ints, floats);
                out = gf::shoot(prog.ints, prog.floats, vec(r), ws, method, eps, max_iter);
            }
            return shot_tuple(std::move(out));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "r"_a.noconvert(), "ws"_a, "method"_a,
        "eps"_a, "max_iter"_a,
        "One shot by `method`, without a start table: (status, t, t_upper, h_n, iterations, "
        "calls, normal, V, weights, W, singular).");

    m.def(
        "shoot_packed",
        [](InI1 ints, In1 floats, In1 r, gf::Int ws, gf::Int method, double eps, gf::Int max_iter,
           F1 packed, In1 table) {
            nb::gil_scoped_release nogil;
            const Program prog = program_copy(ints, floats);
            return head_tuple(gf::shoot_packed(prog.ints, prog.floats, vec(r), ws, method, eps,
                                               max_iter, vec(packed), vec(table)));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "r"_a.noconvert(), "ws"_a, "method"_a,
        "eps"_a, "max_iter"_a, "packed"_a.noconvert(), "table"_a.noconvert(),
        "A shot's head; its arrays into `packed` (status BAD_RAY: r not finite or zero).");

    m.def(
        "shoot_and_read_forces",
        [](In1 w_ext, gf::Int method, double eps, gf::Int max_iter, F1 packed, In1 start,
           InI1 ints, In1 floats, In1 reader, In1 span) {
            nb::gil_scoped_release nogil;
            const Program prog = program_copy(ints, floats);
            return head_tuple(gf::shoot_and_read_forces(vec(w_ext), method, eps, max_iter,
                                                        vec(packed), vec(start), prog.ints,
                                                        prog.floats, vec(reader), vec(span)));
        },
        "w_ext"_a.noconvert(), "method"_a, "eps"_a, "max_iter"_a, "packed"_a.noconvert(),
        "start"_a.noconvert(), "ints"_a.noconvert(), "floats"_a.noconvert(),
        "reader"_a.noconvert(), "span"_a.noconvert(),
        "One min_force call: the shot at W along -w_ext and the forces read off Z_W(r).");

    // a capsule, not a class: two builds of the core loaded in one process (benchmarks/ab.py)
    // share nanobind's registry of classes, where the second could not register its own
    m.def(
        "min_force_call",
        [](nb::type_object record_type, nb::tuple names, nb::tuple target, gf::Int method,
           double eps, gf::Int max_iter, gf::Int size, nb::object start, nb::object ints,
           nb::object floats, nb::object reader, nb::object span, double t_scale,
           gf::Int contacts) {
            auto* call = new MinForceCall(record_type, names, target, method, eps, max_iter,
                                          size, start, ints, floats, reader, span, t_scale,
                                          contacts);
            return nb::capsule(call, MinForceCall::NAME, [](void* p) noexcept {
                delete static_cast<MinForceCall*>(p);
            });
        },
        "record_type"_a, "names"_a, "target"_a, "method"_a, "eps"_a, "max_iter"_a, "size"_a,
        "start"_a, "ints"_a, "floats"_a, "reader"_a, "span"_a, "t_scale"_a, "contacts"_a,
        "Grasp.min_force's common call with these constants, for min_force_method.");

    m.def(
        "min_force_compiled",
        [](nb::handle call, nb::handle w_ext) {
            return MinForceCall::of(call)(w_ext);
        },
        // positional and unnamed: nanobind's simple dispatch, without the keyword matching of
        // named arguments
        "The MinForce record of w_ext from min_force_call's capsule (the shot, its forces "
        "and the record in one call), or None where Grasp.min_force's general path answers: "
        "the common call of min_force_method alone (benchmarks/fresh.py times it).");

    m.def("min_force_method", &min_force_method, "cls"_a, "general"_a,
          "A method descriptor of cls for Grasp.min_force: the common call straight to its "
          "compiled call, any other with its own arguments to `general`, the Python method "
          "whose name, signature and docstring it takes.");

    m.def(
        "shoot_warm",
        [](InI1 ints, In1 floats, In1 r, gf::Int ws, double eps, gf::Int max_iter, In1 normal,
           double spread, F1 packed, gf::Int e) {
            nb::gil_scoped_release nogil;
            const Program prog = program_copy(ints, floats);
            return head_tuple(gf::shoot_warm(prog.ints, prog.floats, vec(r), ws, eps, max_iter,
                                             vec(normal), spread, vec(packed), e));
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "r"_a.noconvert(), "ws"_a, "eps"_a,
        "max_iter"_a, "normal"_a.noconvert(), "spread"_a, "packed"_a.noconvert(), "e"_a,
        "ZC-IE from probes around `normal`; the shot's arrays into packed[e:].");

    m.def(
        "growth_query",
        [](I1 ints, F1 floats, In2 R_a, In1 p_a, In2 R_b, In1 p_b, F1 packed) {
            nb::gil_scoped_release nogil;
            const gf::GrowthOut g = gf::growth_query(ivec(ints), vec(floats), mat(R_a),
                                                     vec(p_a), mat(R_b), vec(p_b), vec(packed));
            return std::make_tuple(g.code, g.verdict, g.sigma, g.lower, g.upper, g.iterations,
                                   g.calls);
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "R_a"_a.noconvert(), "p_a"_a.noconvert(),
        "R_b"_a.noconvert(), "p_b"_a.noconvert(), "packed"_a.noconvert(),
        "One growth-distance query (section 4.1): (code, verdict, sigma, sigma_lower, "
        "sigma_upper, iterations, calls).");

    m.def(
        "min_force_rows",
        [](In2 wrenches, gf::Int method, double eps, gf::Int max_iter, gf::Int packed_size,
           In1 start, InI1 ints, In1 floats, In1 reader, In1 span, double t_scale, F1 sigma,
           F1 sigma_lower, I1 status, I1 iterations, F1 forces, gf::Int threads) {
            const gf::Int N = wrenches.rows;
            const gf::Int m = static_cast<gf::Int>(reader.data[3]);
            if (wrenches.cols != 6) throw nb::value_error("wrenches: expected shape (N, 6)");
            if (sigma.rows != N || sigma_lower.rows != N || status.rows != N ||
                iterations.rows != N || (forces.rows != 0 && forces.rows != 4 * m * N))
                throw nb::value_error("min_force_rows: an output array has the wrong length");
            nb::gil_scoped_release nogil;
            gf::min_force_rows(mat(wrenches), method, eps, max_iter, packed_size, vec(start),
                               ivec(ints), vec(floats), vec(reader), vec(span), t_scale,
                               vec(sigma), vec(sigma_lower), ivec(status), ivec(iterations),
                               vec(forces), threads);
        },
        "wrenches"_a.noconvert(), "method"_a, "eps"_a, "max_iter"_a, "packed_size"_a,
        "start"_a.noconvert(), "ints"_a.noconvert(), "floats"_a.noconvert(),
        "reader"_a.noconvert(), "span"_a.noconvert(), "t_scale"_a, "sigma"_a.noconvert(),
        "sigma_lower"_a.noconvert(), "status"_a.noconvert(), "iterations"_a.noconvert(),
        "forces"_a.noconvert(), "threads"_a,
        "min_force for every row of wrenches (N, 6) on `threads` threads (0: all cores); the "
        "outputs are written in place (forces: empty, or (N, m, 4) flattened).");

    m.def(
        "growth_rows",
        [](In2 R_a, In2 p_a, In2 R_b, In2 p_b, InI1 ints, In1 floats, gf::Int packed_size,
           I1 code, I1 verdict, F1 sigma, F1 lower, F1 upper, I1 iterations, gf::Int threads) {
            const gf::Int N = R_a.rows;
            if (R_a.cols != 9 || R_b.cols != 9 || p_a.cols != 3 || p_b.cols != 3 ||
                R_b.rows != N || p_a.rows != N || p_b.rows != N)
                throw nb::value_error("poses: expected R (N, 9) and p (N, 3) for both objects");
            if (code.rows != N || verdict.rows != N || sigma.rows != N || lower.rows != N ||
                upper.rows != N || iterations.rows != N)
                throw nb::value_error("growth_rows: an output array has the wrong length");
            nb::gil_scoped_release nogil;
            gf::growth_rows(mat(R_a), mat(p_a), mat(R_b), mat(p_b), ivec(ints), vec(floats),
                            packed_size, ivec(code), ivec(verdict), vec(sigma), vec(lower),
                            vec(upper), ivec(iterations), threads);
        },
        "R_a"_a.noconvert(), "p_a"_a.noconvert(), "R_b"_a.noconvert(), "p_b"_a.noconvert(),
        "ints"_a.noconvert(), "floats"_a.noconvert(), "packed_size"_a, "code"_a.noconvert(),
        "verdict"_a.noconvert(), "sigma"_a.noconvert(), "lower"_a.noconvert(),
        "upper"_a.noconvert(), "iterations"_a.noconvert(), "threads"_a,
        "growth_query for every row of the poses on `threads` threads (0: all cores).");

    m.def(
        "contact",
        [](nb::handle position, nb::handle normal, double mu, double mu_spin) -> nb::object {
            double p[3], n[3], unit[3], entries[gf::contacts::ENTRIES];
            if (!read_finite3(position.ptr(), p) || !read_finite3(normal.ptr(), n) ||
                !gf::contacts::contact_entries(p, n, mu, mu_spin, numpy_dot3, unit, entries))
                return nb::none();
            // the squared arm, ||p||^2 + mu_s^2, in Python's order of the terms (Grasp's default
            // length sums them)
            const double arm2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + mu_spin * mu_spin;
            return nb::make_tuple(numpy_copy(p, 3), numpy_copy(unit, 3),
                                  numpy_copy(entries, gf::contacts::ENTRIES), arm2);
        },
        "position"_a, "normal"_a, "mu"_a, "mu_spin"_a,
        "(position, unit normal, entries, squared arm ||p||^2 + mu_s^2) of a contact with the "
        "default tangents (graspforce.grasping.contact), or None: position or normal not a "
        "float64 array or list of 3 finite floats, or a normal of length <= 1e-12.");

    m.def(
        "grasp_values",
        [](nb::list entries) {
            const npy_intp m = static_cast<npy_intp>(nb::len(entries));
            constexpr gf::Int G = gf::contacts::G, X = gf::contacts::ENTRIES - G;
            npy_intp size = m * gf::contacts::ENTRIES + 1;
            PyObject* o = PyArray_SimpleNew(1, &size, NPY_FLOAT64);
            if (o == nullptr) throw nb::python_error();
            nb::object values = nb::steal(o);
            double* v = float_data(o);
            for (npy_intp i = 0; i < m; ++i) {
                const In1 e = nb::cast<In1>(entries[i]);
                if (e.rows != gf::contacts::ENTRIES)
                    throw nb::value_error("grasp_values: a contact's entries have the wrong size");
                std::memcpy(v + i * G, e.data, G * sizeof(double));
                std::memcpy(v + m * G + i * X, e.data + G, X * sizeof(double));
            }
            v[size - 1] = 1.0;
            return values;
        },
        "entries"_a,
        "A grasp's values from its contacts' entries: the G_i (m x 24), then per contact (mu, "
        "mu_s, mu_s / mu, (mu / mu_s)^2), then 1.0 "
        "(graspforce.grasping.wrench_space.grasp_values).");

    m.def(
        "template_arrays",
        [](In1 values, InI1 ints, In1 floats, In1 reader, InI1 dst, InI1 src, InI1 scale, In1 add,
           InI1 read_dst, InI1 read_src) {
            nb::object new_ints = numpy_copy(ints.data, ints.rows);
            nb::object new_floats = numpy_copy(floats.data, floats.rows);
            nb::object new_reader = numpy_copy(reader.data, reader.rows);
            gf::contacts::fill_template(vec(values), {float_data(new_floats.ptr()), floats.rows},
                                        ivec(dst), ivec(src), ivec(scale), vec(add),
                                        {float_data(new_reader.ptr()), reader.rows},
                                        ivec(read_dst), ivec(read_src));
            return nb::make_tuple(new_ints, new_floats, new_reader);
        },
        "values"_a.noconvert(), "ints"_a.noconvert(), "floats"_a.noconvert(),
        "reader"_a.noconvert(), "dst"_a.noconvert(), "src"_a.noconvert(), "scale"_a.noconvert(),
        "add"_a.noconvert(), "read_dst"_a.noconvert(), "read_src"_a.noconvert(),
        "(ints, floats, reader): copies of a template's arrays with a grasp's values gathered "
        "in (graspforce.grasping.wrench_space._Template).");

    m.def(
        "ellipsoid_origin",
        [](In1 center, In2 shape) {
            if (center.rows != 3 || shape.rows != 3 || shape.cols < 3)
                throw nb::value_error("ellipsoid_origin: expected center (3,) and shape (3, k), "
                                      "k >= 3");
            return gf::shapes::ellipsoid_origin(center.data, shape.data, shape.cols);
        },
        "center"_a.noconvert(), "shape"_a.noconvert(),
        "Whether {center + shape x : |x| <= 1} in R^3 holds the origin: shapes.INSIDE, OUTSIDE "
        "or UNDECIDED (too close to the boundary or too thin to say in closed form).");

    m.def(
        "delta_arrays",
        [](InI1 ints, In1 floats, gf::Int sa, gf::Int la, nb::tuple pa, gf::Int sb, gf::Int lb,
           nb::tuple pb, nb::tuple settings) {
            // the settings fill the tail from METHOD to TOUCHING_TOL, in that order
            static_assert(gf::growth::MAX_ITER == gf::growth::METHOD + 1 &&
                          gf::growth::WARM_START == gf::growth::METHOD + 2 &&
                          gf::growth::EPS == gf::growth::METHOD + 3 &&
                          gf::growth::TOUCHING_TOL == gf::growth::METHOD + 4);
            constexpr gf::Int ls = gf::growth::TOUCHING_TOL + 1 - gf::growth::METHOD;
            if (sa < 0 || sb < 0 || la < 0 || lb < 0 || sa + la > floats.rows ||
                sb + lb > floats.rows || floats.rows < gf::growth::TAIL)
                throw nb::value_error("delta_arrays: a parameter block outside the floats");
            nb::object new_ints = numpy_copy(ints.data, ints.rows);
            nb::object new_floats = numpy_copy(floats.data, floats.rows);
            double* f = float_data(new_floats.ptr());
            if (write_parts(pa, f + sa, la) != la || write_parts(pb, f + sb, lb) != lb)
                throw nb::value_error(
                    "delta_arrays: a leaf's parameter parts are not its template's block (numbers "
                    "and C-contiguous float64 arrays filling exactly la and lb entries)");
            double* tail = f + floats.rows - gf::growth::TAIL;
            if (write_parts(settings, tail + gf::growth::METHOD, ls) != ls)
                throw nb::value_error("delta_arrays: settings must be the five numbers (method, "
                                      "max_iter, warm_start, eps, touching_tol)");
            return nb::make_tuple(new_ints, new_floats);
        },
        "ints"_a.noconvert(), "floats"_a.noconvert(), "sa"_a, "la"_a, "pa"_a, "sb"_a, "lb"_a,
        "pb"_a, "settings"_a,
        "(ints, floats): copies of a Delta template's program with the two leaves' parameter "
        "parts (a leaf's `_param_parts`) written at sa and sb, filling la and lb entries, and "
        "the solver's settings in the tail from METHOD on (graspforce.growth).");

    m.def(
        "finite_min",
        [](nb::handle a) {
            PyObject* o = a.ptr();
            if (!PyArray_Check(o)) throw nb::type_error("finite_min: expected a numpy array");
            auto* arr = reinterpret_cast<PyArrayObject*>(o);
            if (!c_float64(arr))
                throw nb::type_error("finite_min: expected a C-contiguous float64 array");
            const double* d = static_cast<const double*>(PyArray_DATA(arr));
            const npy_intp n = PyArray_SIZE(arr);
            double low = gf::INF;
            for (npy_intp i = 0; i < n; ++i) {
                if (!std::isfinite(d[i])) return std::numeric_limits<double>::quiet_NaN();
                low = std::min(low, d[i]);
            }
            return low;
        },
        "a"_a,
        "The least entry of a C-contiguous float64 array, NaN if some entry is not finite, inf "
        "if it has none (graspforce._validate.finite_array).");

    m.def(
        "leaf_params",
        [](nb::tuple parts) {
            constexpr gf::Int ANY = std::numeric_limits<gf::Int>::max();
            const gf::Int n = write_parts(parts, nullptr, ANY);
            if (n < 0)
                throw nb::type_error("leaf_params: a part is neither a number nor a C-contiguous "
                                     "float64 array");
            npy_intp size = n;
            PyObject* o = PyArray_SimpleNew(1, &size, NPY_FLOAT64);
            if (o == nullptr) throw nb::python_error();
            nb::object out = nb::steal(o);
            write_parts(parts, float_data(o), n);
            return out;
        },
        "parts"_a, "A leaf's parameter parts (its `_param_parts`) as one float64 array.");

    m.def("capacity", &gf::capacity, "n"_a, "ws"_a,
          "Entries the arrays of a shot in R^n with witnesses of ws entries take when packed.");
    m.def("extra_size", &gf::forces::extra_size, "m"_a,
          "Entries [sigma, forces (m, 4), wrenches (m, 6), resultant] ahead of a min_force "
          "shot's packed arrays.");

    // the codes Python shares with the core
#define GF_EXPORT(name) m.attr(#name) = gf::name
    GF_EXPORT(POLYTOPE); GF_EXPORT(ELLIPSOID); GF_EXPORT(BOX); GF_EXPORT(TRUNCATED_CONE);
    GF_EXPORT(CONE_CAP); GF_EXPORT(HULL); GF_EXPORT(SUM); GF_EXPORT(AFFINE); GF_EXPORT(EMBED);
    GF_EXPORT(ORIGIN_EMBED); GF_EXPORT(GENERAL); GF_EXPORT(ELLIPSOID_HULL);
    GF_EXPORT(ELLIPSE_HULL); GF_EXPORT(POSED_SUM);
    GF_EXPORT(PROJECTED_ELLIPSOID_HULL); GF_EXPORT(PROJECTED_ELLIPSE_HULL);
    GF_EXPORT(ORIGIN_ELLIPSOID_SUM); GF_EXPORT(ORIGIN_ELLIPSE_SUM);
    GF_EXPORT(CONVERGED); GF_EXPORT(INSIDE); GF_EXPORT(STALLED); GF_EXPORT(MAX_ITER);
    GF_EXPORT(HIT); GF_EXPORT(MISS); GF_EXPORT(LIMIT);
    GF_EXPORT(GJK_BASED); GF_EXPORT(IE); GF_EXPORT(ZC_BASED); GF_EXPORT(BI_GJK);
    GF_EXPORT(ZC_IE); GF_EXPORT(ZC_IE_NEWTON); GF_EXPORT(ZC_IE_PAPER); GF_EXPORT(HEAD);
    GF_EXPORT(BAD_RAY); GF_EXPORT(BAD_WRENCH); GF_EXPORT(ZERO_WRENCH); GF_EXPORT(FULL_SET);
#undef GF_EXPORT
    // the growth-distance query's codes and layout, the force reader's and the warm start's
    nb::module_ growth = m.def_submodule("growth", "The growth-distance query's codes and layout.");
    nb::module_ forces = m.def_submodule("forces", "The force reader's layout.");
    nb::module_ warm = m.def_submodule("warm", "The warm start's probe rounds.");
    nb::module_ batch = m.def_submodule("batch", "A batch row's statuses.");
    nb::module_ shapes = m.def_submodule("shapes", "The closed-form origin verdicts' bounds.");
#define GF_EXPORT_FROM(space, name) space.attr(#name) = gf::space::name
    GF_EXPORT_FROM(forces, READER_HEAD); GF_EXPORT_FROM(forces, LENGTH);
    GF_EXPORT_FROM(warm, WIDENINGS);
    GF_EXPORT_FROM(batch, OPTIMAL); GF_EXPORT_FROM(batch, INFEASIBLE);
    GF_EXPORT_FROM(batch, MAX_ITER); GF_EXPORT_FROM(batch, BAD_WRENCH);
    GF_EXPORT_FROM(batch, FULL_SET);
    GF_EXPORT_FROM(shapes, THIN); GF_EXPORT_FROM(shapes, CLEAR_INSIDE);
    GF_EXPORT_FROM(shapes, CLEAR_OUTSIDE); GF_EXPORT_FROM(shapes, INSIDE);
    GF_EXPORT_FROM(shapes, UNDECIDED);
    GF_EXPORT_FROM(growth, OK); GF_EXPORT_FROM(growth, BAD_POSE_A);
    GF_EXPORT_FROM(growth, BAD_POSE_B); GF_EXPORT_FROM(growth, COINCIDENT);
    GF_EXPORT_FROM(growth, SEPARATED); GF_EXPORT_FROM(growth, TOUCHING);
    GF_EXPORT_FROM(growth, PENETRATING); GF_EXPORT_FROM(growth, NOT_CERTIFIED);
    GF_EXPORT_FROM(growth, POSES); GF_EXPORT_FROM(growth, FRAME);
    GF_EXPORT_FROM(growth, MA); GF_EXPORT_FROM(growth, MB); GF_EXPORT_FROM(growth, WS);
    GF_EXPORT_FROM(growth, METHOD); GF_EXPORT_FROM(growth, MAX_ITER);
    GF_EXPORT_FROM(growth, WARM_START); GF_EXPORT_FROM(growth, EPS);
    GF_EXPORT_FROM(growth, TOUCHING_TOL); GF_EXPORT_FROM(growth, WARM);
    GF_EXPORT_FROM(growth, SPREAD); GF_EXPORT_FROM(growth, NORMAL); GF_EXPORT_FROM(growth, TAIL);
    GF_EXPORT_FROM(growth, WARM_SPREAD); GF_EXPORT_FROM(growth, COLD_SPREAD);
#undef GF_EXPORT_FROM

    bind_testing(m);
    bind_timing(m);
}
