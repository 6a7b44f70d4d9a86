// What the bindings share: NumPy array arguments read without conversion, and the NumPy
// arrays and tuples that carry the core's records back to Python.
#pragma once

#include <nanobind/nanobind.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <cstring>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "all.hpp"

// A NumPy array argument, read straight off the array object: dtype, rank, C order and (for the
// arrays the core writes to) writability are checked, nothing is converted. nanobind's generic
// ndarray caster costs ~150 ns an argument, several times a support call; this one costs a few.
namespace gf_python {

template <class T, int TYPENUM, int NDIM, bool WRITES>
struct NumpyArg {
    T* data = nullptr;
    gf::Int rows = 0;
    gf::Int cols = 0;
};
using F1 = NumpyArg<double, NPY_FLOAT64, 1, true>;         // the core writes to it
using I1 = NumpyArg<std::int64_t, NPY_INT64, 1, true>;     // a program's ints (scratch blocks)
using In1 = NumpyArg<double, NPY_FLOAT64, 1, false>;       // read only
using In2 = NumpyArg<double, NPY_FLOAT64, 2, false>;
using InI1 = NumpyArg<std::int64_t, NPY_INT64, 1, false>;

}  // namespace gf_python

namespace nanobind::detail {
template <class T, int TYPENUM, int NDIM, bool WRITES>
struct type_caster<gf_python::NumpyArg<T, TYPENUM, NDIM, WRITES>> {
    using Arg = gf_python::NumpyArg<T, TYPENUM, NDIM, WRITES>;
    NB_TYPE_CASTER(Arg, const_name("numpy.ndarray"))

    bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
        PyObject* o = src.ptr();
        if (!PyArray_Check(o)) return false;
        auto* a = reinterpret_cast<PyArrayObject*>(o);
        if (PyArray_TYPE(a) != TYPENUM || PyArray_NDIM(a) != NDIM ||
            !PyArray_IS_C_CONTIGUOUS(a) || !PyArray_ISALIGNED(a) || !PyArray_ISNOTSWAPPED(a))
            return false;
        if (WRITES && !PyArray_ISWRITEABLE(a)) return false;
        value.data = static_cast<T*>(PyArray_DATA(a));
        value.rows = static_cast<gf::Int>(PyArray_DIM(a, 0));
        value.cols = NDIM == 2 ? static_cast<gf::Int>(PyArray_DIM(a, 1)) : 0;
        return true;
    }

    static handle from_cpp(const Arg&, rv_policy, cleanup_list*) noexcept {
        return none().release();
    }
};
}  // namespace nanobind::detail

namespace gf_python {

namespace nb = nanobind;


inline gf::Vec vec(const F1& a) { return {a.data, a.rows}; }
inline gf::IVec ivec(const I1& a) { return {a.data, a.rows}; }
// the core takes views of mutable doubles; it does not write to the arrays passed as In1, In2
inline gf::Vec vec(const In1& a) { return {a.data, a.rows}; }
inline gf::IVec ivec(const InI1& a) { return {a.data, a.rows}; }

// A set's program as the core reads it. The support kernel writes its work into the program's
// arrays (the floats after the parameters, the ints' choice and active blocks), so a call works
// on a copy in buffers of its thread: calls from several threads on one set do not race, and
// read-only programs are accepted. A copy costs ~100 ns for the wrench sets of a 4-finger grasp.
struct Program {
    gf::IVec ints;
    gf::Vec floats;
};
inline Program program_copy(const InI1& ints, const In1& floats) {
    thread_local std::vector<gf::Int> ib;
    thread_local std::vector<double> fb;
    ib.assign(ints.data, ints.data + ints.rows);
    fb.assign(floats.data, floats.data + floats.rows);
    return {{ib.data(), ints.rows}, {fb.data(), floats.rows}};
}

inline gf::Mat mat(const In2& a) { return {a.data, a.rows, a.cols, a.cols}; }

// a new NumPy array holding an Array's entries
inline nb::object numpy(const gf::Array& a) {
    npy_intp dims[2] = {static_cast<npy_intp>(a.rows), static_cast<npy_intp>(a.cols)};
    PyObject* o = PyArray_SimpleNew(a.ndim, dims, NPY_FLOAT64);
    if (o == nullptr) throw nb::python_error();
    if (!a.data.empty())
        std::memcpy(PyArray_DATA(reinterpret_cast<PyArrayObject*>(o)), a.data.data(),
                    a.data.size() * sizeof(double));
    return nb::steal(o);
}

using HeadTuple = std::tuple<gf::Int, double, double, double, gf::Int, gf::Int, gf::Int, gf::Int>;

inline HeadTuple head_tuple(const gf::Head& h) {
    return {h.status, h.t, h.t_up, h.h_n, h.iters, h.calls, h.singular, h.k};
}

inline nb::tuple shot_tuple(gf::Shot&& s) {
    return nb::make_tuple(s.status, s.t, s.t_up, s.h_n, s.iters, s.calls,
                          numpy(s.normal), numpy(s.V),
                          numpy(s.lam), numpy(s.W), s.singular);
}

}  // namespace gf_python

namespace gf_python {

// x.x by NumPy's own dot product of float64 (BLAS's, as `ndarray.dot` and np.linalg.norm take
// it): a contact's norms must round as they did when numpy computed them
inline double numpy_dot3(const double* x) {
    static PyArray_DotFunc* const dot =
        PyDataType_GetArrFuncs(PyArray_DescrFromType(NPY_FLOAT64))->dotfunc;
    double out = 0.0;
    char* p = reinterpret_cast<char*>(const_cast<double*>(x));
    dot(p, sizeof(double), p, sizeof(double), reinterpret_cast<char*>(&out), 3, nullptr);
    return out;
}

// three finite floats from a float64 array of 3 entries or a list or tuple of 3 Python floats
// into v; false for anything else (which the Python layer converts or refuses)
inline bool read_finite3(PyObject* o, double* v) {
    if (PyArray_Check(o)) {
        auto* a = reinterpret_cast<PyArrayObject*>(o);
        if (PyArray_TYPE(a) != NPY_FLOAT64 || PyArray_NDIM(a) != 1 || PyArray_DIM(a, 0) != 3 ||
            !PyArray_ISALIGNED(a) || !PyArray_ISNOTSWAPPED(a))
            return false;
        const char* d = static_cast<const char*>(PyArray_DATA(a));
        const npy_intp s = PyArray_STRIDE(a, 0);
        for (int i = 0; i < 3; ++i) std::memcpy(v + i, d + i * s, sizeof(double));
    } else if (PyList_CheckExact(o) || PyTuple_CheckExact(o)) {
        if (PySequence_Fast_GET_SIZE(o) != 3) return false;
        PyObject** items = PySequence_Fast_ITEMS(o);
        for (int i = 0; i < 3; ++i) {
            if (!PyFloat_CheckExact(items[i])) return false;
            v[i] = PyFloat_AS_DOUBLE(items[i]);
        }
    } else {
        return false;
    }
    // finite iff 0 x + 0 y + 0 z is 0 (0 inf is NaN), graspforce._validate.finite_vector3's test
    return 0.0 * v[0] + 0.0 * v[1] + 0.0 * v[2] == 0.0;
}

// Whether a is a float64 array in C order, aligned and in native byte order: entries the core
// reads in place, of any rank
inline bool c_float64(PyArrayObject* a) {
    return PyArray_TYPE(a) == NPY_FLOAT64 && PyArray_IS_C_CONTIGUOUS(a) && PyArray_ISALIGNED(a) &&
           PyArray_ISNOTSWAPPED(a);
}

// Writes a leaf's parameter parts (a tuple of Python ints and floats and C-contiguous float64
// arrays of any rank) one after the other to out (nullptr: counts only); the entries they fill,
// or -1 for a part of another kind or more than n entries.
inline gf::Int write_parts(nb::handle parts, double* out, gf::Int n) {
    const Py_ssize_t count = PyTuple_GET_SIZE(parts.ptr());
    gf::Int k = 0;
    for (Py_ssize_t i = 0; i < count; ++i) {
        PyObject* o = PyTuple_GET_ITEM(parts.ptr(), i);
        if (PyFloat_CheckExact(o) || PyLong_CheckExact(o)) {
            const double v = PyFloat_CheckExact(o) ? PyFloat_AS_DOUBLE(o) : PyLong_AsDouble(o);
            if (v == -1.0 && PyErr_Occurred()) throw nb::python_error();
            if (k >= n) return -1;
            if (out != nullptr) out[k] = v;
            k += 1;
            continue;
        }
        if (!PyArray_Check(o)) return -1;
        auto* a = reinterpret_cast<PyArrayObject*>(o);
        if (!c_float64(a)) return -1;
        const gf::Int size = static_cast<gf::Int>(PyArray_SIZE(a));
        if (size > n - k) return -1;
        if (out != nullptr) std::memcpy(out + k, PyArray_DATA(a), size * sizeof(double));
        k += size;
    }
    return k;
}

// the entries of a float64 array made by numpy_copy or PyArray_SimpleNew
inline double* float_data(PyObject* a) {
    return static_cast<double*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(a)));
}

// a new float64 or int64 array of n entries, copied from data
template <class T>
nb::object numpy_copy(const T* data, npy_intp n) {
    static_assert(std::is_same_v<T, double> || std::is_same_v<T, std::int64_t>);
    constexpr int type = std::is_same_v<T, double> ? NPY_FLOAT64 : NPY_INT64;
    PyObject* o = PyArray_SimpleNew(1, &n, type);
    if (o == nullptr) throw nb::python_error();
    std::memcpy(PyArray_DATA(reinterpret_cast<PyArrayObject*>(o)), data, n * sizeof(T));
    return nb::steal(o);
}

}  // namespace gf_python
