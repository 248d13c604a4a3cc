// Keyword arguments set through a settings table; see settings_kwargs.hpp.
#include "settings_kwargs.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

namespace py = pybind11;

namespace asperity::python {

settings::Value keyword_value(const settings::Info& info, const py::handle& handle) {
  const auto value = py::reinterpret_borrow<py::object>(handle);
  const auto wrong = [&](const char* expected) {
    return py::type_error(info.key + ": expected " + expected + ", got " +
                          std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  };
  // bool is a subclass of int in Python: a flag passed where a number belongs is refused.
  // NumPy scalars count as what they hold (np.int64 has __index__, np.float32 __float__).
  const bool is_bool = py::isinstance<py::bool_>(value) ||
                       std::string(py::str(py::type::handle_of(value).attr("__name__"))) == "bool_";
  const bool is_int = !is_bool && PyIndex_Check(value.ptr()) != 0;
  const bool is_float =
      !is_bool && !is_int && !py::isinstance<py::str>(value) && PyNumber_Check(value.ptr()) != 0;
  switch (info.kind) {
    case settings::Kind::boolean:
      if (!is_bool) throw wrong("True or False");
      return py::bool_(value).cast<bool>();
    case settings::Kind::integer:
      if (is_int) return py::int_(value).cast<long long>();
      if (is_float) {
        const double v = py::float_(value).cast<double>();
        if (std::isfinite(v) && v == std::floor(v)) return static_cast<long long>(v);
      }
      throw wrong("an integer");
    case settings::Kind::number:
      if (is_int || is_float) return py::float_(value).cast<double>();
      throw wrong("a number");
    case settings::Kind::choice:
      if (py::isinstance<py::str>(value)) return value.cast<std::string>();
      if (is_int) return std::to_string(py::int_(value).cast<long long>());
      throw wrong("a str");
    case settings::Kind::numbers:
      if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value))
        throw wrong("a sequence of numbers");
      return value.cast<std::vector<double>>();
  }
  throw wrong("a value");
}

}  // namespace asperity::python
