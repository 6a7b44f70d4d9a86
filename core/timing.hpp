// graspforce._core.timing: loops that time the core's hot calls inside compiled code, for the
// benchmarks (a call from Python costs more than the support map it would time).
#pragma once

#include <nanobind/nanobind.h>

inline void bind_timing(nanobind::module_& m) {
    nanobind::module_ t = m.def_submodule("timing", "Timing loops for the benchmarks.");
    (void)t;
}
