// Lines in a frame and the scaling laws from Python (analysis.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace asperity::python {

void bind_analysis(pybind11::module_& m);

}  // namespace asperity::python
