// Grasp.min_force as a method written in C (a method descriptor of the class): the common call
// (the default tolerances, and a (norm, magnitude, method) whose compiled call the grasp holds,
// min_force_call.hpp) goes from the caller straight to that compiled call, without a Python
// frame; every other call, and every call the compiled one declines, goes with its own
// arguments to the Python method it stands for, which answers and checks it as before. The
// Python method's frame, key tuple and lookups cost ~0.2 us of a ~7 us call (docs/design.md,
// "A reused grasp's min_force").
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>

#include <array>
#include <string>
#include <vector>

#include "python/min_force_call.hpp"

namespace gf_python {

namespace min_force_method_detail {

// The parameters after (self, w_ext), as the Python method names them, and their defaults
constexpr int PARAMS = 5;
constexpr int NORM = 0, MAGNITUDE = 1, METHOD = 2, EPS = 3, MAX_ITER = 4;

// One class's method: the Python method it stands for, its parameters, and the PyMethodDef its
// descriptor points to (kept for the process's life: the registry below never moves)
struct Method {
    PyTypeObject* cls = nullptr;
    PyObject* general = nullptr;
    std::array<PyObject*, PARAMS> names{};
    std::array<PyObject*, PARAMS> defaults{};
    PyObject* compiled_attr = nullptr;
    std::string name;
    std::string doc;
    PyMethodDef def{};
};

// a class registered again (its module reloaded) takes its old slot
constexpr int SLOTS = 8;
inline std::array<Method, SLOTS>& registry() {
    static std::array<Method, SLOTS> methods;
    return methods;
}

// the default's value: the object itself, or an exact float or int of its value
inline bool is_default(PyObject* given, PyObject* value) {
    if (given == nullptr || given == value) return true;
    if (PyFloat_CheckExact(value))
        return PyFloat_CheckExact(given) && PyFloat_AS_DOUBLE(given) == PyFloat_AS_DOUBLE(value);
    return PyLong_CheckExact(value) && PyLong_CheckExact(given) &&
           PyObject_RichCompareBool(given, value, Py_EQ) == 1;
}

// The compiled call's record, or nullptr (no Python error set) where the Python method answers
inline PyObject* common_call(const Method& m, PyObject* self, PyObject* const* args,
                             Py_ssize_t nargs, PyObject* kwnames) {
    if (nargs < 1 || nargs > 1 + PARAMS) return nullptr;
    std::array<PyObject*, PARAMS> given{};
    for (Py_ssize_t i = 1; i < nargs; ++i) given[i - 1] = args[i];
    const Py_ssize_t nkw = kwnames == nullptr ? 0 : PyTuple_GET_SIZE(kwnames);
    for (Py_ssize_t k = 0; k < nkw; ++k) {
        // keywords by identity: a call's names are interned; any other is the Python method's
        PyObject* name = PyTuple_GET_ITEM(kwnames, k);
        int p = 0;
        while (p < PARAMS && m.names[p] != name) ++p;
        if (p == PARAMS || given[p] != nullptr) return nullptr;
        given[p] = args[nargs + k];
    }
    if (!is_default(given[EPS], m.defaults[EPS]) ||
        !is_default(given[MAX_ITER], m.defaults[MAX_ITER]))
        return nullptr;
    for (int p = NORM; p <= METHOD; ++p)
        if (given[p] == nullptr) given[p] = m.defaults[p];
    PyObject* compiled = PyObject_GetAttr(self, m.compiled_attr);
    // none made yet (a new grasp's first calls): no key to build
    if (compiled == nullptr || !PyDict_CheckExact(compiled) || PyDict_GET_SIZE(compiled) == 0) {
        Py_XDECREF(compiled);
        PyErr_Clear();
        return nullptr;
    }
    PyObject* key = PyTuple_Pack(3, given[NORM], given[MAGNITUDE], given[METHOD]);
    nb::object call =
        nb::borrow(key == nullptr ? nullptr : PyDict_GetItemWithError(compiled, key));
    Py_XDECREF(key);
    Py_DECREF(compiled);
    if (!call.is_valid()) {
        PyErr_Clear();   // an unhashable argument: the Python method names it
        return nullptr;
    }
    nb::object record = MinForceCall::of(call)(args[0]);
    return record.is_none() ? nullptr : record.release().ptr();
}

inline PyObject* call(PyObject* self, PyTypeObject* cls, PyObject* const* args, size_t nargsf,
                      PyObject* kwnames) {
    Method* m = nullptr;
    for (Method& e : registry())
        if (e.cls == cls) m = &e;
    if (m == nullptr) {
        PyErr_SetString(PyExc_RuntimeError, "min_force_method: the class is not registered");
        return nullptr;
    }
    const Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    try {
        if (PyObject* record = common_call(*m, self, args, nargs, kwnames)) return record;
    } catch (nb::python_error& e) {
        e.restore();
        return nullptr;
    } catch (const nb::builtin_exception& e) {
        // the compiled call's TypeError and ValueError as nanobind's bindings raise them
        PyErr_SetString(e.type() == nb::exception_type::type_error    ? PyExc_TypeError
                        : e.type() == nb::exception_type::value_error ? PyExc_ValueError
                                                                      : PyExc_RuntimeError,
                        e.what());
        return nullptr;
    } catch (const std::exception& e) {
        PyErr_SetString(PyExc_RuntimeError, e.what());
        return nullptr;
    }
    // the Python method with self and the call's own arguments
    const Py_ssize_t total = nargs + (kwnames == nullptr ? 0 : PyTuple_GET_SIZE(kwnames));
    std::array<PyObject*, 16> small;
    std::vector<PyObject*> large;
    PyObject** stack = small.data();
    if (total + 1 > static_cast<Py_ssize_t>(small.size())) {
        large.resize(static_cast<size_t>(total + 1));
        stack = large.data();
    }
    stack[0] = self;
    for (Py_ssize_t i = 0; i < total; ++i) stack[i + 1] = args[i];
    return PyObject_Vectorcall(m->general, stack, nargs + 1, kwnames);
}

}  // namespace min_force_method_detail

// A method descriptor for cls that stands for `general`, a Python method (self, w_ext, norm,
// magnitude, method, eps, max_iter) with those five defaults, under its name, signature and
// docstring
inline nb::object min_force_method(nb::type_object cls, nb::object general) {
    using namespace min_force_method_detail;
    nb::object code = general.attr("__code__");
    nb::tuple varnames = nb::borrow<nb::tuple>(code.attr("co_varnames"));
    nb::object defaults = general.attr("__defaults__");
    if (nb::cast<int>(code.attr("co_argcount")) != 2 + PARAMS || defaults.is_none() ||
        nb::len(defaults) != PARAMS)
        throw nb::type_error("min_force_method: expected f(self, w_ext, five parameters with "
                             "defaults)");
    auto* type = reinterpret_cast<PyTypeObject*>(cls.ptr());
    Method* m = nullptr;
    for (Method& e : registry())
        if (m == nullptr && (e.cls == type || e.cls == nullptr)) m = &e;
    if (m == nullptr) throw nb::value_error("min_force_method: too many classes");
    // the slot's old references (a reloaded module) stay alive: a descriptor made before may
    // still be called
    m->cls = type;
    m->general = general.inc_ref().ptr();
    std::string signature = "($self, " + nb::cast<std::string>(varnames[1]);
    for (int p = 0; p < PARAMS; ++p) {
        nb::str name = nb::borrow<nb::str>(varnames[2 + p]);
        PyObject* interned = name.inc_ref().ptr();
        PyUnicode_InternInPlace(&interned);
        m->names[p] = interned;
        m->defaults[p] = nb::borrow(defaults[p]).inc_ref().ptr();
        signature += ", " + nb::cast<std::string>(name) + "=" +
                     nb::cast<std::string>(nb::repr(defaults[p]));
    }
    PyObject* attr = PyUnicode_InternFromString("_compiled");
    if (attr == nullptr) throw nb::python_error();
    m->compiled_attr = attr;
    nb::object doc = general.attr("__doc__");
    // the signature line that inspect.signature and help read off a builtin's docstring
    m->name = nb::cast<std::string>(general.attr("__name__"));
    m->doc = m->name + signature + ")\n--\n\n" +
             (doc.is_none() ? std::string() : nb::cast<std::string>(doc));
    m->def.ml_name = m->name.c_str();
    m->def.ml_meth = reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&call));
    m->def.ml_flags = METH_METHOD | METH_FASTCALL | METH_KEYWORDS;
    m->def.ml_doc = m->doc.c_str();
    PyObject* descr = PyDescr_NewMethod(type, &m->def);
    if (descr == nullptr) throw nb::python_error();
    return nb::steal(descr);
}

}  // namespace gf_python
