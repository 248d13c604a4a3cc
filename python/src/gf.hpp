// The surface Green's functions on NumPy arrays (gf.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace asperity::python {

void bind_gf(pybind11::module_& m);

}  // namespace asperity::python
