#include "asperity/apps/common/snapshot_sink.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "asperity/apps/common/lines_json.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/xyz_io.hpp"
#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"

namespace asperity::app {

namespace fs = std::filesystem;

namespace {

// Holds the NetCDF mutex, if there is one, for a scope.
std::unique_lock<std::mutex> hold(std::mutex* m) {
  return m ? std::unique_lock<std::mutex>(*m) : std::unique_lock<std::mutex>();
}

// <label>.xyz beside <label>.nc, from the frame in memory (no NetCDF call: no lock needed).
fs::path xyz_beside(const fs::path& nc) {
  return fs::path(nc).replace_extension(".xyz");
}

void write_xyz_state(const fs::path& nc, const slide::Snapshot& frame,
                     const nlohmann::json& attributes, const SnapshotFormat& format) {
  if (format.xyz) write_extended_xyz(xyz_beside(nc), {frame}, attributes, format.single_precision);
}

}  // namespace

SnapshotSink::SnapshotSink(fs::path dir, nlohmann::json attributes, SnapshotFormat format,
                           std::mutex* netcdf)
    : dir_(std::move(dir)), attributes_(std::move(attributes)), format_(format), netcdf_(netcdf) {
  format_.validate();
}

SnapshotSink::~SnapshotSink() {
  // An interrupted or failed slide leaves the partial file for its resumption, complete up to
  // its last flush; closing it here writes the rest.
  if (appender_) {
    const auto lock = hold(netcdf_);
    appender_.reset();
  }
}

std::string SnapshotSink::start(std::optional<double> resume_Dx) {
  ensure_directory(dir_);
  const auto lock = hold(netcdf_);
  std::error_code ec;
  if (!resume_Dx) {
    for (const char* name :
         {"paths.nc", "paths.nc.partial", "paths.nc.resumed", "paths.nc.copy", "paths.xyz"})
      fs::remove(dir_ / name, ec);
    return {};
  }
  // The frames up to the checkpoint are copied, one at a time, into a new file: those after it
  // belong to steps that the resumed slide repeats. The source is first renamed to
  // paths.nc.resumed, and the copy (paths.nc.copy) becomes the partial file only when it is
  // complete, so that a run killed during the copy leaves the source for the next --resume:
  // an earlier resumption's source, else the interrupted run's partial file, else the paths of
  // a run that ended in a failure and is continued from its last good state.
  const fs::path source = dir_ / "paths.nc.resumed", copy = dir_ / "paths.nc.copy";
  if (!fs::exists(source)) {
    const fs::path found = fs::exists(partial_file()) ? partial_file() : paths_file();
    if (!fs::exists(found)) return {};
    fs::rename(found, source);
  }
  fs::remove(partial_file(), ec);
  std::string warning;
  try {
    {
      SnapshotAppender in = SnapshotAppender::open(source);
      std::optional<SnapshotAppender> out;
      for (std::size_t k = 0; k < in.frames(); ++k) {
        const slide::Snapshot frame = in.read(k);
        if (frame.Dx > *resume_Dx + 1e-9) break;  // frames come in the order of the slide
        if (!out) out.emplace(copy, attributes_, format_);
        out->append(frame);
        path_frames_[frame.label].push_back(out->frames() - 1);
      }
      if (out) out->close();
    }
    if (fs::exists(copy)) {
      fs::rename(copy, partial_file());
      appender_.emplace(SnapshotAppender::open(partial_file()));
      paths_begun_ = true;
    }
  } catch (const std::exception& e) {
    warning = std::string("the relaxation paths written before the interruption are lost (") +
              e.what() + "); the resumed run writes those that follow";
    appender_.reset();
    paths_begun_ = false;
    path_frames_.clear();
    fs::remove(copy, ec);
    fs::remove(partial_file(), ec);
  }
  fs::remove(source, ec);
  return warning;
}

void SnapshotSink::count(const fs::path& file) {
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (!ec) bytes_ += size;
}

void SnapshotSink::state(const slide::Snapshot& frame) {
  const fs::path file = dir_ / (frame.label + ".nc");
  {
    const auto lock = hold(netcdf_);
    write_snapshots(file, {frame}, attributes_, format_);
  }
  count(file);
  written_.push_back(file);
  if (format_.xyz) {
    write_xyz_state(file, frame, attributes_, format_);
    count(xyz_beside(file));
    written_.push_back(xyz_beside(file));
  }
  // A slip's path comes after its "after" state; the next state ends it: on disk now, so that
  // a process killed later leaves it readable.
  if (dirty_) flush();
}

void SnapshotSink::open_paths() {
  if (appender_) return;
  if (paths_begun_) {
    appender_.emplace(SnapshotAppender::open(partial_file()));
    return;
  }
  ensure_directory(dir_);
  appender_.emplace(partial_file(), attributes_, format_);
}

void SnapshotSink::path_frame(const slide::Snapshot& frame) {
  const auto lock = hold(netcdf_);
  open_paths();
  appender_->append(frame);
  paths_begun_ = true;
  path_frames_[frame.label].push_back(appender_->frames() - 1);
  dirty_ = true;
}

void SnapshotSink::replayed_path(const std::string& source, int periods, double period,
                                 const std::string& label) {
  const auto found = path_frames_.find(source);
  if (found == path_frames_.end()) return;
  const std::vector<std::size_t> frames = found->second;  // appending below adds to the map
  const auto lock = hold(netcdf_);
  open_paths();
  for (const std::size_t k : frames) {
    slide::Snapshot moved = appender_->read(k);
    moved.label = label;
    moved.Dx += periods * period;
    moved.block.origin0 += periods;
    appender_->append(moved);
    path_frames_[label].push_back(appender_->frames() - 1);
  }
  dirty_ = true;
}

// Closed, not only synced: HDF5 keeps the metadata of an open file (the chunk indexes of a file
// that grows by a frame at a time) in a cache that grows with its frames, and only closing frees
// it. Measured with a path for every slip, a = 24 d, R = 40 d: a peak of 33 MB at 17 slip events
// and 35 MB at 46 with sync, against 28 MB at both without paths. Reopening costs a few
// milliseconds per path.
void SnapshotSink::flush() {
  if (!appender_ || !dirty_) return;
  close_paths();
  dirty_ = false;
}

// The appender is given up before it closes, so that a failed close leaves the sink to open the
// file again for the next path rather than holding a handle that is gone.
void SnapshotSink::close_paths() {
  if (!appender_) return;
  const auto lock = hold(netcdf_);
  SnapshotAppender closing = std::move(*appender_);
  appender_.reset();
  closing.close();
}

void SnapshotSink::finish() {
  close_paths();
  if (!paths_begun_) return;
  fs::rename(partial_file(), paths_file());
  paths_begun_ = false;  // a second finish() has nothing to rename
  count(paths_file());
  written_.push_back(paths_file());
  dirty_ = false;
  // From the finished file rather than frame by frame as the paths come: a resumed run drops
  // the frames after its checkpoint from the NetCDF file (start()), which a text file appended
  // to would have to mirror; converting once at the end reads one frame at a time.
  if (format_.xyz) {
    const fs::path xyz = xyz_beside(paths_file());
    {
      const auto lock = hold(netcdf_);
      convert_snapshots_to_xyz(paths_file(), xyz, attributes_, format_.single_precision);
    }
    count(xyz);
    written_.push_back(xyz);
  }
}

LargestSlipSink::LargestSlipSink(fs::path dir, nlohmann::json attributes, SnapshotFormat format,
                                 std::mutex* netcdf)
    : dir_(std::move(dir)), attributes_(std::move(attributes)), format_(format), netcdf_(netcdf) {
  format_.validate();
}

namespace {
// slips.csv's last columns, in the order they were added: the slide's cost when it accepted the
// slip (Snapshot), where the slip's step began (the "before" state's Dx), and the slip event a
// replayed slip repeats (0: computed).
// Then what the closed loops hold where they cross the row (x) and column (y) through the tip
// centre (tracking::loop_core_stress): the stress their cores hold and tau_max there (G).
constexpr std::array<const char*, 8> kLastColumns = {
    "gf_applications", "wall_s",         "Dx_before",     "replay_of",
    "loop_stress_x",   "loop_tau_max_x", "loop_stress_y", "loop_tau_max_y"};
}  // namespace

// The slip's place in the slide, then the census (lines_json.hpp, one description with Python),
// then the slide's cost so far and the step's start. New columns go at the end: a table of an
// earlier build is then a prefix of this one and a resumed run keeps its rows (start()).
std::vector<std::string> LargestSlipSink::census_columns() {
  std::vector<std::string> columns = {"slip", "Dx", "Fx_before", "Fx_after", "Fz", "slipped_sites"};
  for (const auto& [name, value] : census_fields({}))
    columns.push_back(name);
  columns.insert(columns.end(), kLastColumns.begin(), kLastColumns.end());
  return columns;
}

int LargestSlipSink::Resume::largest_slipped_sites() const {
  int largest = 0;
  for (const Slip& s : slips)
    largest = std::max(largest, s.slipped_sites);
  return largest;
}

namespace {
void add_warning(std::string& warning, const std::string& w) {
  warning += (warning.empty() ? "" : "; ") + w;
}
}  // namespace

// slips.csv moves to the first free slips.old[.N].csv, so that no earlier table is overwritten.
void LargestSlipSink::set_census_aside(std::string& warning, const std::string& why) {
  fs::path aside = dir_ / "slips.old.csv";
  for (int k = 1; fs::exists(aside); ++k)
    aside = dir_ / ("slips.old." + std::to_string(k) + ".csv");
  std::error_code ec;
  fs::rename(census_file(), aside, ec);
  add_warning(warning, "its slips.csv " + why + ": " +
                           (ec ? "could not be set aside (" + ec.message() + "), replaced"
                               : "set aside as " + aside.filename().string()) +
                           ", and started again");
}

std::string LargestSlipSink::start(std::optional<Resume> resume) {
  ensure_directory(dir_);
  std::error_code ec;
  fs::remove(dir_ / "peak.nc", ec);  // made again at the end
  fs::remove(dir_ / "peak.xyz", ec);
  census_ = CsvTable(census_columns());
  if (!resume) {
    for (const fs::path& f :
         {before_file(), after_file(), latest_before_file(), latest_after_file()}) {
      fs::remove(f, ec);
      fs::remove(xyz_beside(f), ec);
    }
    // A resumed run's figures are drawn again from its kept rows (write_census, below).
    for (const fs::path& f : {census_file(), friction_figure(), loops_figure()})
      fs::remove(f, ec);
    largest_ = 0;
    return {};
  }
  largest_ = resume->largest_slipped_sites();
  std::string warning;
  // Files written after the checkpoint belong to a slip the resumed slide makes again (bit for
  // bit): they are replaced then, since largest_ does not count it yet.
  if (largest_ > 0 && !fs::exists(before_file())) {
    add_warning(warning, "the states of its largest slip before the checkpoint (" +
                             std::to_string(largest_) +
                             " slipped sites) were not kept (a run without --largest-slip made "
                             "the checkpoint); only a larger slip is kept from here on");
  }
  // The rows of the checkpoint's slips, each the slip it says it is (a table left by another
  // slide of this point, say one started again without --largest-slip, is not); later ones are
  // made again. Doubles are written to round-trip, so Dx compares exactly.
  const std::size_t wanted = resume->slips.size();
  std::size_t kept = 0;
  if (fs::exists(census_file())) {
    try {
      const CsvTable old = CsvTable::read(census_file());
      const std::vector<std::string> columns = census_columns();
      // Columns an earlier build did not write are left empty in its rows.
      if (old.columns().size() > columns.size() ||
          !std::equal(old.columns().begin(), old.columns().end(), columns.begin())) {
        set_census_aside(warning, "has other columns (an earlier build)");
      } else {
        bool mismatch = false;
        std::size_t i = 0;
        for (; i < old.rows() && i < wanted && !mismatch; ++i) {
          const Resume::Slip& slip = resume->slips[i];
          mismatch = old.integer(i, "slip") != static_cast<long long>(i + 1) ||
                     old.number(i, "Dx") != slip.Dx ||
                     old.integer(i, "slipped_sites") != slip.slipped_sites;
          if (!mismatch) {
            std::vector<CsvTable::Cell> row;
            for (std::size_t c = 0; c < old.columns().size(); ++c)
              row.push_back(old.cell(i, c));
            row.resize(columns.size(), CsvTable::Cell(std::string()));
            // A cell an earlier build did not write, filled where the checkpoint's trace tells.
            const auto fill = [&](std::string_view column, bool known, CsvTable::Cell value) {
              CsvTable::Cell& cell = row.at(census_.column_index(column));
              if (const auto* text = std::get_if<std::string>(&cell);
                  known && text && text->empty())
                cell = std::move(value);
            };
            fill("Dx_before", std::isfinite(slip.Dx_before), slip.Dx_before);
            // A computed slip repeats none (0); a replayed one's source is not in the trace (-1:
            // replayed, source unknown), so that the row still says it was not computed.
            fill("replay_of", true, slip.replayed ? -1LL : 0LL);
            census_.add_row(std::move(row));
            ++kept;
          }
        }
        if (mismatch) {
          census_ = CsvTable(census_columns());
          kept = 0;
          set_census_aside(warning, "is not of this slide (its row of slip " + std::to_string(i) +
                                        " differs from the checkpoint's in number, Dx or "
                                        "slipped sites)");
        }
      }
    } catch (const std::exception& e) {
      census_ = CsvTable(census_columns());
      kept = 0;
      set_census_aside(warning, std::string("cannot be read (") + e.what() + ")");
    }
  }
  if (kept < wanted) {
    add_warning(warning, "slips.csv has no rows for " + std::to_string(wanted - kept) + " of the " +
                             std::to_string(wanted) +
                             " slips before the checkpoint; it goes on from the next");
  }
  write_census();
  return warning;
}

// A row of slips.csv: the slip's place in the slide and the census of the lines of the state it
// ends in (the stable state the slide continues from).
void LargestSlipSink::add_census_row(const slide::Snapshot& before, const slide::Snapshot& after) {
  // The event number from the label ("slip_012_after": 12), the one place it is spelt; -1 if a
  // label is not of that form (no slide makes one).
  long long slip = -1;
  const std::string_view digits =
      std::string_view(after.label)
          .substr(0, after.label.size() - std::string_view("_after").size());
  if (digits.starts_with("slip_")) {
    const std::string_view n = digits.substr(std::string_view("slip_").size());
    std::from_chars(n.data(), n.data() + n.size(), slip);
  }
  std::vector<CsvTable::Cell> row = {
      slip, after.Dx, before.Fx, after.Fx, after.Fz, static_cast<long long>(after.slipped_sites)};
  std::vector<std::pair<std::string, nlohmann::json>> fields;
  std::array<tracking::LoopCoreStress, 2> held;
  try {
    const tracking::FrameLines lines = tracking::find_lines(tracking::view_of(after));
    fields = census_fields(tracking::census(lines));
    held = tracking::loop_core_stress(after, lines);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "largest_slip: no census of %s (%s): its row in slips.csv is empty\n",
                 after.label.c_str(), e.what());
  }
  for (const auto& [name, value] : fields) {
    if (value.is_number_integer()) {
      row.emplace_back(value.get<long long>());
    } else {
      row.emplace_back(value.get<double>());
    }
  }
  // Empty census fields without a census.
  row.resize(census_.columns().size() - kLastColumns.size(), CsvTable::Cell(std::string()));
  row.emplace_back(static_cast<long long>(after.gf_applications));
  row.emplace_back(after.wall_s);
  row.emplace_back(before.Dx);
  row.emplace_back(static_cast<long long>(after.replay_of));
  for (const tracking::LoopCoreStress& h : held) {
    row.emplace_back(h.stress);
    row.emplace_back(h.tau_max);
  }
  census_.add_row(std::move(row));
  write_census();
}

namespace {

// A cell of slips.csv as a number; NaN where it is empty (a row without its census), which
// leaves a gap in the figure.
double number_or_nan(const CsvTable& t, std::size_t row, std::string_view column) {
  try {
    return t.number(row, column);
  } catch (const std::invalid_argument&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

// "a = 300 d, R = 800 d" from the frames' attributes (the point), or "" if they do not say.
std::string point_title(const nlohmann::json& attributes) {
  if (!attributes.contains("a") || !attributes.contains("R") || !attributes["a"].is_number() ||
      !attributes["R"].is_number())
    return "";
  char buf[96];
  std::snprintf(buf, sizeof buf, "a = %g d, R = %g d: ", attributes["a"].get<double>(),
                attributes["R"].get<double>());
  return buf;
}

}  // namespace

void LargestSlipSink::write_census() {
  census_.write(census_file());
  std::error_code ec;
  try {
    // Friction as mu/alpha where the frames give alpha (the seed's Fig. 4 axis), else Fx/Fz.
    const bool has_alpha = attributes_.contains("alpha") && attributes_["alpha"].is_number() &&
                           attributes_["alpha"].get<double>() > 0.0;
    const double alpha = has_alpha ? attributes_["alpha"].get<double>() : 1.0;
    const std::size_t n = census_.rows();
    Series path{.title = "", .style = "lines lw 1 lc rgb '#999999'"};
    Series before{.title = "before a slip", .style = "points pt 7 ps 0.9 lc rgb '#d62728'"};
    Series after{.title = "after it", .style = "points pt 7 ps 0.9 lc rgb '#1f77b4'"};
    Series loops{.title = "inside the loops", .style = "linespoints pt 7 ps 0.7 lc rgb '#d62728'"};
    Series largest{.title = "inside the largest loop", .style = "lines lw 1 dt 2 lc rgb '#ff9900'"};
    Series slipped{.title = "slipped area", .style = "linespoints pt 7 ps 0.7 lc rgb '#1f77b4'"};
    for (std::size_t i = 0; i < n; ++i) {
      const double Dx = number_or_nan(census_, i, "Dx");
      // The state before the slip is the one its step began from, a step back (rows of an
      // earlier build without Dx_before: drawn at the slip's Dx).
      double Dx0 = number_or_nan(census_, i, "Dx_before");
      if (!std::isfinite(Dx0)) Dx0 = Dx;
      const double Fz = number_or_nan(census_, i, "Fz");
      const double b = number_or_nan(census_, i, "Fx_before") / (alpha * Fz);
      const double a = number_or_nan(census_, i, "Fx_after") / (alpha * Fz);
      // The slide through its slips: the stable state before, the step to the slip's Dx (its
      // loading and the slip), then the loading to the next slip's start.
      path.x.insert(path.x.end(), {Dx0, Dx});
      path.y.insert(path.y.end(), {b, a});
      before.x.push_back(Dx0);
      before.y.push_back(b);
      after.x.push_back(Dx);
      after.y.push_back(a);
      loops.x.push_back(Dx);
      loops.y.push_back(number_or_nan(census_, i, "loop_area"));
      largest.x.push_back(Dx);
      largest.y.push_back(number_or_nan(census_, i, "largest_loop_area"));
      slipped.x.push_back(Dx);
      slipped.y.push_back(number_or_nan(census_, i, "slipped_area"));
    }
    // A figure is drawn once it has a value to show (rows whose census the tracer rejected have
    // none): gnuplot refuses a plot without one. One it does not draw is removed.
    const auto any_finite = [](const std::vector<Series>& s) {
      return std::any_of(s.begin(), s.end(), [](const Series& one) {
        for (std::size_t i = 0; i < one.x.size(); ++i)
          if (std::isfinite(one.x[i]) && std::isfinite(one.y[i])) return true;
        return false;
      });
    };
    std::vector<Series> friction = {path, before, after};
    char buf[96];
    // The value before the first slip: in Regime II the peak each cycle returns to, in Regime
    // III the one friction climbs past while the loops are held.
    if (n > 0 && std::isfinite(before.y.front()) && std::isfinite(after.x.back())) {
      std::snprintf(buf, sizeof buf, "before the first slip: %.5g", before.y.front());
      friction.push_back({.x = {before.x.front(), after.x.back()},
                          .y = {before.y.front(), before.y.front()},
                          .title = buf,
                          .style = "lines lw 1 dt 2 lc rgb 'black'"});
    }
    const std::string point = point_title(attributes_);
    // The slip events by number (a resumed table may lack rows of slips before its checkpoint).
    const double slips = n > 0 ? number_or_nan(census_, n - 1, "slip") : 0.0;
    std::snprintf(buf, sizeof buf, "%g slip%s", slips, slips == 1.0 ? "" : "s");
    if (any_finite(friction)) {
      plot_png(friction_figure(), friction,
               {.title = point + "friction at each slip (" + buf + ")",
                .xlabel = "Dx (d)",
                .ylabel = has_alpha ? "mu / alpha = Fx / (alpha Fz)" : "Fx / Fz",
                .extra_commands = {"set key bottom right", "set grid"}});
    } else {
      fs::remove(friction_figure(), ec);
    }
    const double last_loops =
        n > 0 ? number_or_nan(census_, n - 1, "loops") : std::numeric_limits<double>::quiet_NaN();
    std::snprintf(buf, sizeof buf, " (%g loop%s after the last)", last_loops,
                  last_loops == 1.0 ? "" : "s");
    if (any_finite({loops, largest, slipped})) {
      plot_png(
          loops_figure(), {loops, largest, slipped},
          {.title = point + "the loops after each slip" + (std::isfinite(last_loops) ? buf : ""),
           .xlabel = "Dx at the slip (d)",
           .ylabel = "area (d^2)",
           .extra_commands = {"set key right center", "set grid"}});
    } else {
      fs::remove(loops_figure(), ec);
    }
  } catch (const std::exception& e) {
    // Not left out of date: a figure on disk is the table's.
    fs::remove(friction_figure(), ec);
    fs::remove(loops_figure(), ec);
    if (!figure_failed_) {
      std::fprintf(stderr, "largest_slip: figures of slips.csv not drawn (%s)\n", e.what());
    }
    figure_failed_ = true;
  }
}

void LargestSlipSink::state(const slide::Snapshot& frame) {
  const auto write = [&](const slide::Snapshot& f, const fs::path& file) {
    {
      const auto lock = hold(netcdf_);
      write_snapshots(file, {f}, attributes_, format_);
    }
    write_xyz_state(file, f, attributes_, format_);
  };
  if (frame.label.ends_with("_before")) {
    before_ = frame;
  } else if (frame.label.ends_with("_after")) {
    if (before_) {
      // A run killed between the two writes leaves a newer "before" beside an older "after";
      // their labels tell.
      write(*before_, latest_before_file());
      write(frame, latest_after_file());
      if (frame.slipped_sites > largest_) {
        write(*before_, before_file());
        write(frame, after_file());
        largest_ = frame.slipped_sites;
      }
      add_census_row(*before_, frame);
    }
    before_.reset();
  } else if (frame.label == "peak") {
    write(frame, dir_ / "peak.nc");
  }
}

}  // namespace asperity::app
