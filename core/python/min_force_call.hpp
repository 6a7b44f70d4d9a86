// Grasp.min_force's common call as one compiled call: the wrench checked, the shot, the forces
// read and the MinForce record made, for a grasp whose wrench set's start table is settled and
// the default tolerances. Around the shot, Python's lookups, its allocation of the packed array,
// the argument conversions and the record's construction cost ~1.5 us; this call, from Python,
// ~0.5 (a zero wrench's whole call). The packed answer and the shot's head go to Python as one
// bytes object, [packed (size), head (HEAD)], that the record decodes when first read
// (graspforce.records.results.MinForce.ray), where a NumPy array and the head's tuple made
// per call cost ~0.2 us (Go1's scenario, 3%).
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/stl/tuple.h>

#include <structmember.h>

#include <algorithm>
#include <cmath>

#include "python/python.hpp"

namespace gf_python {

class MinForceCall {
public:
    // The slots of the record type that a min_force answer sets, in this order
    // (graspforce.records.results.MinForce.from_packed)
    static constexpr const char* SLOTS[] = {"feasible", "status",     "sigma",
                                            "sigma_lower", "norm",    "magnitude",
                                            "method",   "iterations", "support_calls",
                                            "_ray",      "_contacts",  "_forces"};
    static constexpr int NSLOTS = sizeof(SLOTS) / sizeof(SLOTS[0]);
    static constexpr const char* NAME = "graspforce.MinForceCall";

    // the call a capsule of min_force_call holds; a TypeError for any other object
    static const MinForceCall& of(nb::handle capsule) {
        void* p = PyCapsule_IsValid(capsule.ptr(), NAME)
                      ? PyCapsule_GetPointer(capsule.ptr(), NAME)
                      : nullptr;
        if (p == nullptr) throw nb::type_error("call: expected a capsule of min_force_call");
        return *static_cast<const MinForceCall*>(p);
    }

    // record_type: MinForce; names: (norm, magnitude, method, "optimal", "max_iter",
    // "infeasible"); target: (W, extra, wrench space), kept in each record's ray; the arrays and
    // the rest as shoot_and_read_forces takes them, held unchanged for the call's life
    MinForceCall(nb::type_object record_type, nb::tuple names, nb::tuple target, gf::Int method,
                 double eps, gf::Int max_iter, gf::Int size, nb::object start, nb::object ints,
                 nb::object floats, nb::object reader, nb::object span, double t_scale,
                 gf::Int contacts)
        : record_type_(record_type), names_(names), target_(target),
          arrays_(nb::make_tuple(start, ints, floats, reader, span)), method_(method), eps_(eps),
          max_iter_(max_iter), size_(size), t_scale_(t_scale),
          contacts_(nb::steal(PyLong_FromLongLong(contacts))) {
        if (names.size() != 6 || target.size() != 3)
            throw nb::value_error("MinForceCall: names of 6 and a target of 3 expected");
        if (!read(start, start_) || !read(ints, ints_) || !read(floats, floats_) ||
            !read(reader, reader_) || !read(span, span_))
            throw nb::type_error("MinForceCall: the arrays are not of the kind the core reads");
        PyObject* dict = reinterpret_cast<PyTypeObject*>(record_type.ptr())->tp_dict;
        for (int s = 0; s < NSLOTS; ++s) {
            PyObject* d = PyDict_GetItemString(dict, SLOTS[s]);
            if (d == nullptr || !PyObject_TypeCheck(d, &PyMemberDescr_Type))
                throw nb::type_error("MinForceCall: the record type lacks a slot");
            const PyMemberDef* member = reinterpret_cast<PyMemberDescrObject*>(d)->d_member;
            if (member->type != T_OBJECT_EX)
                throw nb::type_error("MinForceCall: a record slot is not an object slot");
            offsets_[s] = member->offset;
        }
    }

    // The MinForce of w_ext, or None where Grasp.min_force's general path answers: w_ext not a
    // C-contiguous float64 array, a refused or zero wrench, a load for the full-dimensional set,
    // or a shot without a point of W on the ray
    nb::object operator()(nb::handle w_ext) const {
        In1 w;
        if (!read(w_ext, w)) return nb::none();
        nb::object packed = nb::steal(PyBytes_FromStringAndSize(
            nullptr, static_cast<Py_ssize_t>((size_ + gf::HEAD) * sizeof(double))));
        if (!packed.is_valid()) throw nb::python_error();
        auto* pk = reinterpret_cast<double*>(PyBytes_AS_STRING(packed.ptr()));
        gf::Head head;
        {
            nb::gil_scoped_release nogil;
            const Program prog = program_copy(ints_, floats_);
            head = gf::shoot_and_read_forces(vec(w), method_, eps_, max_iter_, {pk, size_},
                                             vec(start_), prog.ints, prog.floats, vec(reader_),
                                             vec(span_));
        }
        const double tail[gf::HEAD] = {static_cast<double>(head.status),
                                       head.t,
                                       head.t_up,
                                       head.h_n,
                                       static_cast<double>(head.iters),
                                       static_cast<double>(head.calls),
                                       static_cast<double>(head.singular),
                                       static_cast<double>(head.k)};
        std::copy(tail, tail + gf::HEAD, pk + size_);
        // a miss: no forces, sigma and its bound infinite; a zero wrench: no shot, no forces,
        // sigma 0 (MinForce.without_forces)
        const bool miss = head.status == gf::MISS, zero = head.status == gf::ZERO_WRENCH;
        if ((head.status < 0 && !zero) || (head.status >= 0 && !miss && !(pk[0] < INFINITY)))
            return nb::none();
        auto* type = reinterpret_cast<PyTypeObject*>(record_type_.ptr());
        nb::object record = nb::steal(type->tp_alloc(type, 0));
        if (!record.is_valid()) throw nb::python_error();
        const double sigma = zero ? 0.0 : miss ? INFINITY : pk[0];
        const nb::object values[NSLOTS] = {
            nb::bool_(!miss),
            names_[miss ? 5 : head.status == gf::HIT || zero ? 3 : 4],
            nb::float_(sigma),
            nb::float_(zero || miss ? sigma : 1.0 / (t_scale_ * head.t_up)),
            names_[0],
            names_[1],
            names_[2],
            nb::int_(head.iters),
            nb::int_(head.calls),
            zero ? nb::object(nb::none())
                 : nb::make_tuple(target_[0], w_ext, nb::none(), packed, target_[1],
                                  target_[2]),
            contacts_,
            zero || miss ? nb::none() : nb::object()};
        char* base = reinterpret_cast<char*>(record.ptr());
        for (int s = 0; s < NSLOTS; ++s)
            if (values[s].is_valid())
                *reinterpret_cast<PyObject**>(base + offsets_[s]) = values[s].inc_ref().ptr();
        return record;
    }

private:
    template <class Arg>
    static bool read(nb::handle o, Arg& out) {
        nb::detail::make_caster<Arg> c;
        if (!c.from_python(o, 0, nullptr)) return false;
        out = c.value;
        return true;
    }

    nb::type_object record_type_;
    nb::tuple names_;
    nb::tuple target_;
    nb::tuple arrays_;   // keeps the arrays below alive
    In1 start_, floats_, reader_, span_;
    InI1 ints_;
    gf::Int method_;
    double eps_;
    gf::Int max_iter_;
    gf::Int size_;
    double t_scale_;
    nb::object contacts_;
    Py_ssize_t offsets_[NSLOTS] = {};
};

}  // namespace gf_python
