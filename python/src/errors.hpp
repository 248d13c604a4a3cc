// The libraries' std::invalid_argument (bad input, the violated constraint named) as Python's
// ValueError, for every binding (python/src).
#pragma once

#include <pybind11/pybind11.h>

#include <stdexcept>

namespace asperity::python {

template <class F>
auto value_errors(F f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw pybind11::value_error(e.what());
  }
}

}  // namespace asperity::python
