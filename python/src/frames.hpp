// Snapshots to Python (frames.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <vector>

#include "asperity/core/slide/frames.hpp"

namespace asperity::python {

// Each frame as a dict: label, iteration, Dx, Fx, Fz, energy, origin_x, origin_y,
// slipped_sites, tip_angle, tip_mismatch (the tip's lattice), and "fields": name -> (n0, n1) array
// (block-major; in_contact uint8; uz for the explicit model only). The arrays take over the frames'
// vectors, which are left empty.
pybind11::list frames_to_python(std::vector<slide::Snapshot>&& frames);
// app::snapshot_variables() as dicts (name, units, long_name, per_site).
pybind11::list snapshot_variables();

}  // namespace asperity::python
