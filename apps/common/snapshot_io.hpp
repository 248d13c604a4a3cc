// Field snapshots of a sliding run (slide::Snapshot) as one NetCDF-4 file (classic model), for
// xarray and ParaView.
//
// Layout: dimensions frame, x (n0), y (n1), label_length. Per frame: label(frame,
// label_length) (text), iteration, origin_x, origin_y (int), Dx, Fx, Fz, energy (double).
// Fields (frame, x, y): ux, uy, sx, sy, tau_x, tau_y, tau_max, pressure (double), in_contact
// (byte), and uz (double) when the frames carry it (explicit model). Coordinates x(x), y(y) in
// units of d are those of the first frame's block; the block may follow the tip, so site (i, j) of
// frame k is at ((origin_x[k] + i) d, (origin_y[k] + j) d). Every variable has `units` (lengths d,
// stresses G, forces G d^2, energy G d^3) and `long_name`.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "slide/slider.hpp"

namespace asperity::app {

// Writes atomically (temporary file renamed onto `nc`). Global attributes: every entry of the
// flat JSON object `attributes` (numbers as double, strings as text, booleans as int 0/1, other
// values as their JSON text), then title, Conventions, comment and label (the first frame's),
// which replace entries of the same name. Throws std::invalid_argument if `frames` is empty, the
// frames' block shapes differ or are empty, a field's size is not the block's site count, or
// `attributes` is neither null nor an object; std::runtime_error naming the file if writing fails.
void write_snapshots(const std::filesystem::path& nc, const std::vector<slide::Snapshot>& frames,
                     const nlohmann::json& attributes);

// Reads a file written by write_snapshots. Throws std::invalid_argument naming the file and the
// problem if it is missing, not a NetCDF file, truncated, or lacks a dimension or variable.
std::vector<slide::Snapshot> read_snapshots(const std::filesystem::path& nc);

// The checks of read_snapshots that need no field data (the file opens, its dimensions, sizes
// and variables are right, its frames fit in memory); returns the number of frames. For tools
// that read many files: a bad last file stops the run before any work.
std::size_t check_snapshot_file(const std::filesystem::path& nc);

}  // namespace asperity::app
