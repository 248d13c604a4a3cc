// Snapshots (slide::Snapshot) handed to Python as dicts of NumPy arrays; python/asperity builds
// xarray Datasets from them in the NetCDF files' layout (apps/common/snapshot_io.hpp). The
// per-site arrays are the slide's own vectors, moved into the arrays (no copy), shaped (n0, n1)
// block-major as the tools hold them; the Python side takes the transposed view (y, x).
#include "frames.hpp"

#include <pybind11/numpy.h>

#include <memory>
#include <utility>

#include "asperity/apps/common/snapshot_io.hpp"

namespace asperity::python {

namespace py = pybind11;

namespace {

// A vector's storage as an (n0, n1) array that owns it.
template <class T>
py::array_t<T> adopt(std::vector<T>&& values, const Shape2& shape) {
  if (values.empty()) return py::array_t<T>();
  auto* owned = new std::vector<T>(std::move(values));
  const py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(shape.n0), static_cast<py::ssize_t>(shape.n1)},
                        owned->data(), free);
}

}  // namespace

py::list frames_to_python(std::vector<slide::Snapshot>&& frames) {
  py::list out;
  for (slide::Snapshot& f : frames) {
    const Shape2 shape = f.block.shape;
    py::dict fields;
    fields["ux"] = adopt(std::move(f.ux), shape);
    fields["uy"] = adopt(std::move(f.uy), shape);
    fields["sx"] = adopt(std::move(f.sx), shape);
    fields["sy"] = adopt(std::move(f.sy), shape);
    fields["tau_x"] = adopt(std::move(f.tau_x), shape);
    fields["tau_y"] = adopt(std::move(f.tau_y), shape);
    fields["tau_max"] = adopt(std::move(f.tau_max), shape);
    fields["pressure"] = adopt(std::move(f.pressure), shape);
    if (!f.uz.empty()) fields["uz"] = adopt(std::move(f.uz), shape);
    fields["in_contact"] = adopt(std::move(f.in_contact), shape);
    out.append(py::dict(
        py::arg("label") = f.label, py::arg("iteration") = f.iteration, py::arg("Dx") = f.Dx,
        py::arg("Fx") = f.Fx, py::arg("Fz") = f.Fz, py::arg("energy") = f.energy,
        py::arg("origin_x") = f.block.origin0, py::arg("origin_y") = f.block.origin1,
        py::arg("slipped_sites") = f.slipped_sites, py::arg("tip_angle") = f.tip.angle,
        py::arg("tip_mismatch") = f.tip.mismatch, py::arg("fields") = fields));
  }
  frames.clear();
  return out;
}

py::list snapshot_variables() {
  py::list out;
  for (const app::SnapshotVariable& v : app::snapshot_variables()) {
    out.append(py::dict(py::arg("name") = v.name, py::arg("units") = v.units,
                        py::arg("long_name") = v.long_name, py::arg("per_site") = v.per_site));
  }
  return out;
}

}  // namespace asperity::python
