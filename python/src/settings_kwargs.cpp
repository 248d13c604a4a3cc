// Keyword arguments set through a settings table; see settings_kwargs.hpp.
#include "settings_kwargs.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace py = pybind11;

namespace asperity::python {

namespace {

// What a keyword's value is, for the kinds of the settings.
enum class Sort { boolean, integer, real, text, other };

// Python's bool, int, float and str, and NumPy's scalars and 0-d arrays by their dtype's kind
// (np.bool_, whose type name differs between NumPy versions, is kind "b"; np.int64 "i"). A
// NumPy array of more than one value is none of them.
Sort sort_of(const py::object& value) {
  if (py::isinstance<py::bool_>(value)) return Sort::boolean;
  if (py::isinstance<py::int_>(value)) return Sort::integer;
  if (py::isinstance<py::float_>(value)) return Sort::real;
  if (py::isinstance<py::str>(value)) return Sort::text;
  if (py::hasattr(value, "dtype") && py::hasattr(value, "ndim")) {
    if (value.attr("ndim").cast<int>() != 0) return Sort::other;
    const auto kind = value.attr("dtype").attr("kind").cast<std::string>();
    if (kind == "b") return Sort::boolean;
    if (kind == "i" || kind == "u") return Sort::integer;
    if (kind == "f") return Sort::real;
  }
  return Sort::other;
}

// An integer value as long long; ValueError (naming the key) if it does not fit.
long long as_long_long(const settings::Info& info, const py::object& value) {
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0)
    throw py::value_error(info.key + ": " + std::string(py::str(value)) +
                          " is out of the integers' range");
  return n;
}

}  // namespace

settings::Value keyword_value(const settings::Info& info, const py::handle& handle) {
  const auto value = py::reinterpret_borrow<py::object>(handle);
  const Sort sort = sort_of(value);
  const auto wrong = [&](const char* expected) {
    return py::type_error(info.key + ": expected " + expected + ", got " +
                          std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  };
  switch (info.kind) {
    case settings::Kind::boolean:
      if (sort != Sort::boolean) throw wrong("True or False");
      return PyObject_IsTrue(value.ptr()) == 1;
    case settings::Kind::integer:
      if (sort == Sort::integer) return as_long_long(info, value);
      if (sort == Sort::real) {
        // An integral float (2.0); beyond 2^63 it is not one long long can hold.
        const double v = py::float_(value).cast<double>();
        if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9.2e18)
          return static_cast<long long>(v);
      }
      throw wrong("an integer");
    case settings::Kind::number: {
      // An optional number (settings::optional_number) is left out by None; NaN is not a value.
      if (info.optional && value.is_none()) return std::numeric_limits<double>::quiet_NaN();
      if (sort != Sort::integer && sort != Sort::real)
        throw wrong(info.optional ? "a number or None" : "a number");
      const double v = py::float_(value).cast<double>();
      if (info.optional && std::isnan(v))
        throw py::value_error(info.key + " = nan: give a number, or None to leave it out");
      return v;
    }
    case settings::Kind::choice:
      // A sign given as a number (slip_sign=1, np.int64(-1)) or as its name ("+1").
      if (sort == Sort::text) return info.choice_named(value.cast<std::string>());
      if (sort == Sort::integer)
        return info.choice_named(std::to_string(as_long_long(info, value)));
      throw wrong("a str");
    case settings::Kind::numbers:
      if (sort == Sort::text || !py::isinstance<py::sequence>(value))
        throw wrong("a sequence of numbers");
      return value.cast<std::vector<double>>();
  }
  throw wrong("a value");
}

}  // namespace asperity::python
