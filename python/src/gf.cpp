// The elastic half-space's surface Green's functions (core/elastic/surface_gf.hpp, MODEL.md
// section 2) on NumPy arrays: u = G * f for a force field f of shape (ncomp, n0, n1) (component
// slots as Components: in_plane (x, y), normal (z), full (x, y, z); site (i0, i1) at
// ((origin + i0) d, (origin + i1) d)), the tools' own FFT plans, the GIL released while the
// transforms run. No copies: a float64 C-contiguous f is read in place and the result is written
// into `out` when given (which must then be float64, C-contiguous and writeable).
#include "gf.hpp"

#include <pybind11/numpy.h>

#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>

#include "asperity/core/elastic/surface_gf.hpp"
#include "errors.hpp"

namespace asperity::python {

namespace py = pybind11;
using Forces = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Out = py::array_t<double, py::array::c_style>;

namespace {

elastic::Components components_of(const std::string& name) {
  if (name == "in_plane") return elastic::Components::in_plane;
  if (name == "normal") return elastic::Components::normal;
  if (name == "full") return elastic::Components::full;
  throw py::value_error("components: got '" + name +
                        "', allowed: 'in_plane' (x, y), 'normal' (z), 'full' (x, y, z)");
}

std::string name_of(elastic::Components c) {
  switch (c) {
    case elastic::Components::in_plane:
      return "in_plane";
    case elastic::Components::normal:
      return "normal";
    case elastic::Components::full:
      return "full";
  }
  return "?";
}

// A GF and the lock that keeps two Python threads (each without the GIL) out of its buffers.
template <class GF>
struct Shared {
  std::unique_ptr<GF> gf;
  std::mutex busy;
};

// Checks f against the GF's (ncomp, n0, n1) and returns `out` (made if None) for the result.
Out result_array(const Forces& f, const py::object& out, int ncomp, Shape2 shape,
                 const char* what) {
  const auto expected = [&] {
    return "(" + std::to_string(ncomp) + ", " + std::to_string(shape.n0) + ", " +
           std::to_string(shape.n1) + ")";
  };
  const auto shape_of = [](const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k)
      s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + ")";
  };
  const auto matches = [&](const py::array& a) {
    return a.ndim() == 3 && a.shape(0) == ncomp && a.shape(1) == shape.n0 && a.shape(2) == shape.n1;
  };
  if (!matches(f)) {
    throw py::value_error(std::string(what) + ": got an array of shape " + shape_of(f) +
                          ", expected " + expected());
  }
  if (out.is_none()) return Out({ncomp, shape.n0, shape.n1});
  if (!Out::check_(out)) {
    throw py::type_error(std::string(what) +
                         ": out must be a C-contiguous float64 NumPy array (it is written in "
                         "place, never copied)");
  }
  Out result = py::reinterpret_borrow<Out>(out);
  if (!matches(result)) {
    throw py::value_error(std::string(what) + ": out has shape " + shape_of(result) +
                          ", expected " + expected());
  }
  if (!result.writeable()) throw py::value_error(std::string(what) + ": out is read-only");
  const double *a = f.data(), *b = result.data();
  if (a < b + result.size() && b < a + f.size())
    throw py::value_error(std::string(what) + ": out may not overlap the input");
  return result;
}

template <class GF, class Apply>
Out run(Shared<GF>& s, const Forces& f, const py::object& out, Shape2 shape, const char* what,
        Apply apply) {
  Out u = result_array(f, out, s.gf->ncomp(), shape, what);
  const std::span<const double> in(f.data(), static_cast<std::size_t>(f.size()));
  const std::span<double> result(u.mutable_data(), static_cast<std::size_t>(u.size()));
  {
    py::gil_scoped_release release;
    const std::lock_guard lock(s.busy);
    apply(*s.gf, in, result);
  }
  return u;
}

fft::FFTOptions fft_options(int threads) {
  fft::FFTOptions o;
  o.threads = threads;
  value_errors([&] {
    o.validate();
    return 0;
  });
  return o;
}

elastic::Material material(double G, double nu) {
  const elastic::Material m{G, nu};
  value_errors([&] {
    m.validate();
    return 0;
  });
  return m;
}

}  // namespace

void bind_gf(py::module_& m) {
  using Free = Shared<elastic::FreeSurfaceGF>;
  py::class_<Free, std::shared_ptr<Free>>(
      m, "FreeSurfaceGF",
      "Surface Green's function of a loaded block of n0 x n1 sites on an infinite elastic "
      "half-space (MODEL.md 2): exact linear convolution with the patch influence "
      "coefficients, by zero-padded FFTs (the tools' own).")
      .def(py::init([](std::pair<int, int> shape, const std::string& components, double G,
                       double nu, double d, int threads) {
             auto s = std::make_shared<Free>();
             s->gf = value_errors([&] {
               return std::make_unique<elastic::FreeSurfaceGF>(
                   material(G, nu), components_of(components), Shape2{shape.first, shape.second}, d,
                   fft_options(threads));
             });
             return s;
           }),
           py::arg("shape"), py::arg("components") = "in_plane",
           py::arg("G") = elastic::Material{}.G, py::arg("nu") = elastic::Material{}.nu,
           py::arg("d") = 1.0, py::arg("threads") = 1,
           "shape: (n0, n1) sites along x and y; components: 'in_plane', 'normal' or 'full'; "
           "G (unit of stress), nu in [0, 0.5]; d the lattice spacing; threads of the FFTs")
      .def(
          "apply",
          [](Free& s, const Forces& f, const py::object& out) {
            return run(s, f, out, s.gf->region(), "FreeSurfaceGF.apply",
                       [](auto& gf, auto in, auto u) { gf.apply(in, u); });
          },
          py::arg("f"), py::arg("out") = py::none(),
          "u = G * f: displacements (units of d) of the forces per site f (units of G d^2), "
          "both of shape (ncomp, n0, n1). A float64 C-contiguous f is not copied; with `out` "
          "the result is written there and returned.")
      .def(
          "coefficient",
          [](const Free& s, int k, int l, int o0, int o1) {
            return s.gf->coefficient(k, l, o0, o1);
          },
          py::arg("k"), py::arg("l"), py::arg("o0"), py::arg("o1"),
          "Displacement of component slot k at offset (o0, o1) sites per unit force of slot l")
      .def_property_readonly(
          "shape",
          [](const Free& s) { return std::pair<int, int>(s.gf->region().n0, s.gf->region().n1); })
      .def_property_readonly("components",
                             [](const Free& s) { return name_of(s.gf->components()); })
      .def_property_readonly("ncomp", [](const Free& s) { return s.gf->ncomp(); })
      .def_property_readonly(
          "fft_shape",
          [](const Free& s) {
            return std::pair<int, int>(s.gf->fft_shape().n0, s.gf->fft_shape().n1);
          },
          "The padded FFT grid (>= 2 n - 1 per axis, FFT-friendly)")
      .def_property_readonly(
          "applications", [](const Free& s) { return s.gf->applications(); },
          "apply() calls so far: the unit of cost the solvers report");

  using Periodic = Shared<elastic::PeriodicSurfaceGF>;
  py::class_<Periodic, std::shared_ptr<Periodic>>(
      m, "PeriodicSurfaceGF",
      "Surface Green's function of an L0 x L1 periodic cell (the Peierls cell, MODEL.md 2 and "
      "6): the lattice sum of the patch model; the q = 0 mode (rigid shift) is left out.")
      .def(py::init([](std::pair<int, int> cell, const std::string& components, double G, double nu,
                       double d, int threads, int alias_images) {
             auto s = std::make_shared<Periodic>();
             s->gf = value_errors([&] {
               return std::make_unique<elastic::PeriodicSurfaceGF>(
                   material(G, nu), components_of(components), Shape2{cell.first, cell.second}, d,
                   fft_options(threads), alias_images);
             });
             return s;
           }),
           py::arg("cell"), py::arg("components") = "in_plane",
           py::arg("G") = elastic::Material{}.G, py::arg("nu") = elastic::Material{}.nu,
           py::arg("d") = 1.0, py::arg("threads") = 1,
           py::arg("alias_images") = elastic::kDefaultAliasImages,
           "cell: (L0, L1) sites per period; alias_images: reciprocal vectors per direction in "
           "the lattice sum (its error falls as alias_images^-2)")
      .def(
          "apply",
          [](Periodic& s, const Forces& f, const py::object& out) {
            return run(s, f, out, s.gf->cell(), "PeriodicSurfaceGF.apply",
                       [](auto& gf, auto in, auto u) { gf.apply(in, u); });
          },
          py::arg("f"), py::arg("out") = py::none(),
          "u = G * f without the q = 0 mode (u has zero mean), shapes (ncomp, L0, L1)")
      .def(
          "apply_stiffness",
          [](Periodic& s, const Forces& u, const py::object& out) {
            return run(s, u, out, s.gf->cell(), "PeriodicSurfaceGF.apply_stiffness",
                       [](auto& gf, auto in, auto f) { gf.apply_stiffness(in, f); });
          },
          py::arg("u"), py::arg("out") = py::none(), "f = K * u, K = G^-1 (K(0) = 0)")
      .def_property_readonly(
          "cell",
          [](const Periodic& s) { return std::pair<int, int>(s.gf->cell().n0, s.gf->cell().n1); })
      .def_property_readonly("ncomp", [](const Periodic& s) { return s.gf->ncomp(); })
      .def_property_readonly("applications",
                             [](const Periodic& s) { return s.gf->applications(); });
}

}  // namespace asperity::python
