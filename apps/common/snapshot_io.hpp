// Field snapshots of a sliding run (slide::Snapshot) as NetCDF-4 files (classic model), for
// xarray, ParaView and track_loops.
//
// Layout: dimensions frame (unlimited, where a file grows frame by frame: paths.nc; fixed in
// a file written whole: the states), y (n1), x (n0), label_length. Per frame: frame (the frame
// index, axis "T"), label(frame, label_length) (text), iteration, origin_x, origin_y (int), Dx,
// Fx, Fz, energy (double). Fields (frame, y, x), x fastest: ux, uy, sx, sy, tau_x, tau_y,
// tau_max, pressure (double, or float with SnapshotFormat::single_precision), in_contact (byte),
// and uz when the frames carry it (explicit model); each chunked by frame and compressed
// (shuffle + deflate). Coordinates x(x), y(y) in lattice spacings d (units "1": see below) are
// those of the first frame's block; the block may follow the tip, so site (i, j) of frame k is
// at ((origin_x[k] + i) d, (origin_y[k] + j) d). Every variable has `units` (lengths d,
// stresses G, forces G d^2, energy G d^3) and `long_name`; the global attribute field_precision
// says float32 or float64, and tip_angle (degrees) and tip_mismatch give the tip's lattice of
// the frames (slide::Snapshot::tip, alike in every frame of a file; read as 0 where absent).
//
// The layout is the one VTK's CF reader (ParaView's) reads right with its default settings
// (issue 25; tests/regression/test_netcdf_vtk.py): a flat grid with x along VTK's x, one time
// step per frame, every field as point data. Hence the field order, the frame index as the time
// axis, and coordinates without axis "X"/"Y" (longitude/latitude to VTK) or unit "d" (days to
// udunits and VTK). The readers also take the files written before, whose fields are
// (frame, x, y) and which have no frame variable.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/core/slide/frames.hpp"

namespace asperity::app {

// A variable of the snapshot files other than the coordinates and labels: its name, units,
// long_name, and whether it is per site (a field) or per frame. The files' attributes and the
// Python package's xarray Datasets (python/) are made from this one list.
struct SnapshotVariable {
  const char* name;
  const char* units;
  const char* long_name;
  bool per_site;
};
// Fields ux .. pressure, uz, in_contact, then the per-frame Dx, Fx, Fz, energy, iteration,
// origin_x, origin_y.
const std::vector<SnapshotVariable>& snapshot_variables();

// How the per-site fields are stored.
struct SnapshotFormat {
  bool single_precision = false;  // fields as 32-bit floats (7 digits; half the size)
  int deflate_level = 1;          // 0: uncompressed; 1 (fastest) .. 9 (smallest)
  // Also each file as extended XYZ beside it (<label>.xyz, paths.xyz: xyz_io.hpp), for ASE and
  // OVITO, which do not read these CF NetCDF files. Off by default: the text is about 4 times
  // the size of a compressed float file. Honoured by the frame sinks (snapshot_sink.hpp), not by
  // write_snapshots.
  bool xyz = false;

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

// A snapshot file written frame by frame: the relaxation paths of a whole run in one file. The
// file is created at the first frame (whose block shape, label and uz decide its layout), so a
// writer that never gets a frame leaves no file. Not atomic: the caller writes to a temporary
// name and renames it when done. The NetCDF library is not thread-safe: one writer or reader at
// a time in a process.
class SnapshotAppender {
 public:
  // A new file at `nc` (replacing one there): global attributes as in write_snapshots, labels of
  // up to max(label_length, the first frame's) characters. With `frames` > 0 the file holds
  // exactly that many (a fixed frame dimension: its per-frame numbers are stored without
  // chunk indexes, about 20 KiB less per file); 0: it grows frame by frame (unlimited).
  SnapshotAppender(std::filesystem::path nc, nlohmann::json attributes, SnapshotFormat format,
                   std::size_t label_length = 32, std::size_t frames = 0);
  // An existing file written by this class, to append to it. Throws std::runtime_error naming
  // the file if it cannot be opened or lacks a dimension or variable.
  static SnapshotAppender open(const std::filesystem::path& nc);
  SnapshotAppender(SnapshotAppender&& other) noexcept;
  SnapshotAppender& operator=(SnapshotAppender&&) = delete;
  ~SnapshotAppender();  // closes the file (errors then are lost: call close() to see them)

  // Throws std::invalid_argument (frame of another shape, field sizes, label too long) or
  // std::runtime_error naming the file if writing fails.
  void append(const slide::Snapshot& frame);
  [[nodiscard]] slide::Snapshot read(std::size_t k) const;  // frame k, as written
  [[nodiscard]] std::size_t frames() const { return frames_; }
  [[nodiscard]] const std::filesystem::path& path() const { return nc_; }
  void close();  // no more frames; the writer can only be destroyed

 private:
  struct Layout;
  void define(const slide::Snapshot& first);

  std::filesystem::path nc_;
  nlohmann::json attributes_;
  SnapshotFormat format_;
  std::size_t label_length_ = 0;
  std::size_t fixed_frames_ = 0;  // 0: unlimited
  int id_ = -1;
  std::size_t frames_ = 0;
  std::unique_ptr<Layout> layout_;
  interface::TipLattice tip_;  // of the file's frames
};

// Writes `frames` as one file, atomically (temporary file renamed onto `nc`). Global attributes:
// every entry of the flat JSON object `attributes` (numbers as double, strings as text, booleans
// as int 0/1, other values as their JSON text), then title, Conventions, comment, label (the
// first frame's) and field_precision, which replace entries of the same name. Throws
// std::invalid_argument if `frames` is empty, the frames' block shapes differ or are empty, a
// field's size is not the block's site count, or `attributes` is neither null nor an object;
// std::runtime_error naming the file if writing fails.
void write_snapshots(const std::filesystem::path& nc, const std::vector<slide::Snapshot>& frames,
                     const nlohmann::json& attributes, const SnapshotFormat& format = {});

// Reads a file written by write_snapshots or SnapshotAppender: every frame, or with `label` only
// the frames of that label (the path of one slip in a run's paths.nc). Fields stored as float
// come back as double. Throws std::invalid_argument naming the file and the problem if it is
// missing, not a NetCDF file, truncated, or lacks a dimension or variable.
std::vector<slide::Snapshot> read_snapshots(const std::filesystem::path& nc,
                                            const std::string& label = {});

// The checks of read_snapshots that need no field data (the file opens, its dimensions, sizes
// and variables are right, its frames fit in memory); returns the number of frames. For tools
// that read many files: a bad last file stops the run before any work.
std::size_t check_snapshot_file(const std::filesystem::path& nc);

}  // namespace asperity::app
