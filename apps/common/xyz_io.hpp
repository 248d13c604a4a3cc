// Field snapshots (slide::Snapshot) as extended XYZ, the text format that ASE (ase.io.read) and
// OVITO open without a plug-in: OVITO reads NetCDF only in the AMBER convention, which the CF
// snapshots (snapshot_io.hpp) do not follow.
//
// One frame per block of lines: the site count, a comment line of key=value pairs, and a line
// per block site (block-major, i0 * n1 + i1, as the NetCDF fields). Per site:
//   species  "X" (ASE's dummy element: the sites carry no chemistry),
//   pos      X + ux, Y + uy and uz (explicit model) or 0 (the LFM has no normal motion), in d,
//   ux uy sx sy tau_x tau_y tau_max pressure [uz], in_contact: the NetCDF variables, same names
//            and units (snapshot_io.hpp),
//   registry_x registry_y: the registry index round(s / d) along x and y (slider.hpp), whose
//            jumps are the slips and whose steps the dislocation lines bound; under a tip
//            lattice out of registry round(rho) along the tip's axes (tip_lattice.hpp).
// Comment line: Lattice (a box of n0 d x n1 d x 1 d around the block, not periodic: pbc="F F F"),
// Origin (its corner, (origin0 - 1/2, origin1 - 1/2, -1/2) d, which OVITO places the box at;
// ASE keeps it in Atoms.info), Properties, then the frame's label, iteration, Dx, Fx, Fz, energy,
// origin_x, origin_y, the tip's lattice (tip_angle, tip_mismatch) and the file's flat attributes
// (model, a, R, ...; a key holding characters the format cannot carry is left out). ASE moves
// `energy` into a SinglePointCalculator (atoms.get_potential_energy()): every other key stays in
// atoms.info.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/core/slide/frames.hpp"

namespace asperity::app {

// One frame as text. `single_precision`: the values are rounded to float and written with 9
// digits, so that they equal, bit for bit, the float fields of the NetCDF file written with the
// same format; otherwise 17 digits (every double reads back exactly). Throws
// std::invalid_argument if a field's size is not the block's site count.
std::string extended_xyz_frame(const slide::Snapshot& frame, const nlohmann::json& attributes,
                               bool single_precision);

// Writes `frames` as one file, atomically (temporary file renamed onto `xyz`). Throws
// std::invalid_argument as extended_xyz_frame, std::runtime_error naming the file if writing
// fails.
void write_extended_xyz(const std::filesystem::path& xyz,
                        const std::vector<slide::Snapshot>& frames,
                        const nlohmann::json& attributes, bool single_precision);

// Converts a NetCDF snapshot file (write_snapshots or SnapshotAppender) into extended XYZ at
// `xyz`, one frame at a time (a run's paths.nc can hold thousands: memory stays one frame),
// with the file's attributes `attributes`. Atomic like write_extended_xyz. Returns the frames
// written.
std::size_t convert_snapshots_to_xyz(const std::filesystem::path& nc,
                                     const std::filesystem::path& xyz,
                                     const nlohmann::json& attributes, bool single_precision);

}  // namespace asperity::app
