// graspforce._core.testing: the core's internal steps, bound for the tests that check them one
// by one (the linear algebra, the pieces and the Newton finish, single ZC-IE steps).
#pragma once

#include <nanobind/nanobind.h>

inline void bind_testing(nanobind::module_& m) {
    nanobind::module_ t = m.def_submodule("testing", "The core's internal steps, for the tests.");
    (void)t;
}
