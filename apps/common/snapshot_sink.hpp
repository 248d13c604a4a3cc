// The frame sink of the sliding tools (slide::FrameSink): writes each frame of a slide when it is
// made and keeps none, so that the memory of a slide does not grow with its slips (issue 22).
//
// Into <dir> (snapshots/ of a run):
// - <label>.nc, one file per state: "start" (before the slide), "peak", "slip_NNN_before",
//   "slip_NNN_after", "last_good"
//   (each written atomically);
// - paths.nc: the relaxation paths of the slips that record one (SlideOptions::path_frame_slips),
//   every frame of the run in one file with an unlimited frame dimension, labelled
//   "slip_NNN_path". While the run goes on it is paths.nc.partial, closed after each path and at
//   each checkpoint (flush()) and opened again for the next path; finish() renames it. A
//   resumed run keeps the frames up to its checkpoint and appends.
// - with SnapshotFormat::xyz, each file also as extended XYZ beside it (<label>.xyz when the
//   state is written, paths.xyz from paths.nc at finish(): xyz_io.hpp), for ASE and OVITO.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/core/slide/frames.hpp"

namespace asperity::app {

class SnapshotSink final : public slide::FrameSink {
 public:
  // `netcdf`: held around every NetCDF call when several slides write at once (friction_sweep's
  // points; the library is not thread-safe). A slide whose frames are not wanted at all takes
  // slide::DiscardFrames instead.
  SnapshotSink(std::filesystem::path dir, nlohmann::json attributes, SnapshotFormat format,
               std::mutex* netcdf = nullptr);
  ~SnapshotSink() override;
  SnapshotSink(const SnapshotSink&) = delete;
  SnapshotSink& operator=(const SnapshotSink&) = delete;

  // A fresh run: removes the paths file of an earlier run in `dir`. A resumed one (checkpoint
  // at tip position Dx): keeps the path frames up to Dx and drops those written after the
  // checkpoint (the resumed slide makes them again). Returns a warning if the partial file of
  // the killed run cannot be read (its paths are then lost; the states are in their own files),
  // else an empty string.
  std::string start(std::optional<double> resume_Dx);

  void state(const slide::Snapshot& frame) override;
  void path_frame(const slide::Snapshot& frame) override;
  void replayed_path(const std::string& source, int periods, double period,
                     const std::string& label) override;

  // Everything handed over so far is on disk (before a checkpoint is written): the partial file
  // is closed, and opened again by the next path frame.
  void flush();
  // The slide has ended: paths.nc.partial becomes paths.nc. An interrupted slide calls flush()
  // instead, and its resumption continues the partial file.
  void finish();

  [[nodiscard]] const std::vector<std::filesystem::path>& written() const { return written_; }
  [[nodiscard]] std::uintmax_t bytes_written() const { return bytes_; }

  [[nodiscard]] std::filesystem::path paths_file() const { return dir_ / "paths.nc"; }
  [[nodiscard]] std::filesystem::path partial_file() const { return dir_ / "paths.nc.partial"; }

 private:
  void open_paths();
  void close_paths();
  void count(const std::filesystem::path& file);

  std::filesystem::path dir_;
  nlohmann::json attributes_;
  SnapshotFormat format_;
  std::mutex* netcdf_;
  std::optional<SnapshotAppender> appender_;  // the partial file, while a path is written
  bool paths_begun_ = false;                  // the partial file exists (this run's, or resumed)
  std::map<std::string, std::vector<std::size_t>> path_frames_;  // label -> frames in the file
  bool dirty_ = false;  // frames appended since the last flush
  std::vector<std::filesystem::path> written_;
  std::uintmax_t bytes_ = 0;
};

// The frame sink of a sweep point that keeps only what tells which loops a slide ends with: the
// states before and after its largest slip (the most slipped sites; the first of equals) and,
// at the end, the peak. Into <dir>: largest_slip_before.nc, largest_slip_after.nc (the frames
// keep their labels, "slip_NNN_before/after"), peak.nc. A larger slip replaces the pair, so
// the disk and memory of a point stay two frame pairs however many slips it takes (a Regime III
// slide takes hundreds); the "before" state of every slip is held until its "after" arrives.
// Also the pair of the latest slip, latest_slip_before.nc and latest_slip_after.nc, replaced at
// every slip: a point that runs for days can be looked at (track_loops) while it runs.
// And slips.csv, a row per slip: where it happened (Dx, Fx before and after, slipped sites),
// the census of the lines its "after" state holds (tracking::census: loops, their area and
// character, the slipped area), the slide's cost so far and, for a slip replayed from the
// repeating cycle, the computed slip it repeats (Snapshot::replay_of), so that how a Regime III
// slide's loops nucleate, creep and are arrested is kept for every slip in a few hundred bytes each
// (the table is rewritten whole at each slip, atomically, like every result file). Beside it two
// figures of the table, redrawn with it: slips.png, the friction before each slip (at the Dx its
// step began from) and after it, with the value before the first slip as a line (does friction
// climb past the first slip's peak while loops are held: Regime III, MODEL.md 8), and
// slips_loops.png, the loops' area, the largest loop's and the slipped area after each slip (does
// the arrested loop hold, creep, or go). A figure on disk is the table's: one that cannot be drawn
// is removed. No relaxation paths. With SnapshotFormat::xyz, each file also as .xyz beside it.
class LargestSlipSink final : public slide::FrameSink {
 public:
  LargestSlipSink(std::filesystem::path dir, nlohmann::json attributes, SnapshotFormat format,
                  std::mutex* netcdf = nullptr);

  // Where a resumed run's checkpoint left the slide: its slip events in order (the trace rows
  // with a slip), each with its Dx and slipped sites.
  struct Resume {
    struct Slip {
      double Dx = 0.0;
      int slipped_sites = 0;
      // Where its step began: the accepted state before it (the trace row above), for the
      // Dx_before cells of rows an earlier build wrote without them. NaN: not known.
      double Dx_before = std::numeric_limits<double>::quiet_NaN();
      // Replayed from the repeating cycle (the trace row's flag), for the replay_of cells of
      // rows an earlier build wrote without them.
      bool replayed = false;
    };
    std::vector<Slip> slips;
    [[nodiscard]] int largest_slipped_sites() const;
  };
  // A fresh run removes the files of an earlier one. A resumed run continues from a checkpoint
  // whose trace has slips of up to largest_slipped_sites(): only a larger slip replaces the
  // pair. slips.csv keeps its rows of the checkpoint's slips, each matched by its number, Dx and
  // slipped sites (later ones are made again); a table of an earlier build whose columns are the
  // first of today's keeps its rows, the newer columns (the cost) empty; a table that is not this
  // slide's, or cannot be read, is set aside as slips.old.csv (or .old.1.csv, ...) and started
  // again. Returns a warning when the checkpoint's slips include one whose states or row are not
  // on disk (the checkpoint was made by a run that did not keep them), else an empty string.
  std::string start(std::optional<Resume> resume);

  void state(const slide::Snapshot& frame) override;
  void path_frame(const slide::Snapshot& /*frame*/) override {}
  void replayed_path(const std::string& /*source*/, int /*periods*/, double /*period*/,
                     const std::string& /*label*/) override {}
  [[nodiscard]] bool wants_paths() const override { return false; }

  [[nodiscard]] int largest_slipped_sites() const { return largest_; }
  [[nodiscard]] std::filesystem::path before_file() const {
    return dir_ / "largest_slip_before.nc";
  }
  [[nodiscard]] std::filesystem::path after_file() const { return dir_ / "largest_slip_after.nc"; }
  [[nodiscard]] std::filesystem::path latest_before_file() const {
    return dir_ / "latest_slip_before.nc";
  }
  [[nodiscard]] std::filesystem::path latest_after_file() const {
    return dir_ / "latest_slip_after.nc";
  }
  [[nodiscard]] std::filesystem::path census_file() const { return dir_ / "slips.csv"; }
  [[nodiscard]] std::filesystem::path friction_figure() const { return dir_ / "slips.png"; }
  [[nodiscard]] std::filesystem::path loops_figure() const { return dir_ / "slips_loops.png"; }
  // The columns of slips.csv, in order.
  static std::vector<std::string> census_columns();

 private:
  std::filesystem::path dir_;
  nlohmann::json attributes_;
  SnapshotFormat format_;
  std::mutex* netcdf_;
  // Never throws for the census itself (a side table must not end a slide of days): a state the
  // tracer rejects gets a row with its place and empty census fields, and a note on stderr.
  void add_census_row(const slide::Snapshot& before, const slide::Snapshot& after);
  void set_census_aside(std::string& warning, const std::string& why);
  // slips.csv and its figures: each figure is drawn from the rows, or removed where it has
  // nothing to show or cannot be drawn (noted on stderr once; the table is the result).
  void write_census();

  bool figure_failed_ = false;
  int largest_ = 0;
  std::optional<slide::Snapshot> before_;  // of the slip whose "after" comes next
  CsvTable census_{census_columns()};      // slips.csv as on disk
};

}  // namespace asperity::app
