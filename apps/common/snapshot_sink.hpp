// The frame sink of the sliding tools (slide::FrameSink): writes each frame of a slide when it is
// made and keeps none, so that the memory of a slide does not grow with its slips (issue 22).
//
// Into <dir> (snapshots/ of a run):
// - <label>.nc, one file per state: "peak", "slip_NNN_before", "slip_NNN_after", "last_good"
//   (each written atomically);
// - paths.nc: the relaxation paths of the slips that record one (SlideOptions::path_frame_slips),
//   every frame of the run in one file with an unlimited frame dimension, labelled
//   "slip_NNN_path". While the run goes on it is paths.nc.partial, closed after each path and at
//   each checkpoint (flush()) and opened again for the next path; finish() renames it. A
//   resumed run keeps the frames up to its checkpoint and appends.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/snapshot_io.hpp"
#include "slide/frames.hpp"

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

}  // namespace asperity::app
