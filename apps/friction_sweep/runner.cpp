// friction_sweep's point runner (runner.hpp).
#include "runner.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>
#include <optional>
#include <tuple>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/memory.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/apps/common/snapshot_sink.hpp"
#include "report.hpp"

namespace asperity::app {
namespace {

namespace fs = std::filesystem;

// A point's checkpoints in its folder: the latest; the last one between steps while the latest is
// inside a paused slip flow; the one a capped lower bound keeps for a larger limit.
constexpr const char* kCheckpointName = "checkpoint.cbor";
constexpr const char* kStepCheckpointName = "checkpoint.step.cbor";
constexpr const char* kCappedCheckpointName = "checkpoint.capped.cbor";

// "a = 43 d, R = 535 d" and, for a tip out of registry, ", tip 2 deg / m = 0".
std::string describe_point(const SweepPoint& p) {
  char text[160];
  std::snprintf(text, sizeof text, "a = %.4g d, R = %g d", p.a, p.R);
  std::string out = text;
  if (!p.tip.aligned()) {
    std::snprintf(text, sizeof text, ", tip %g deg / m = %g", p.tip.angle, p.tip.mismatch);
    out += text;
  }
  return out;
}

void write_table(const fs::path& csv, const std::vector<std::optional<SweepRow>>& rows) {
  CsvTable table(sweep_columns());
  for (const auto& row : rows) {
    if (row) table.add_row(row->cells);
  }
  table.write(csv);
}

// A point to run: of the explicit model (xpoints, rows_x) or the LFM (points, rows).
struct Job {
  bool x = false;
  std::size_t k = 0;
};

// Where a point's frames go: its snapshots/ as they are made (with --figures), only those of its
// largest slip to largest_slip/ (with --largest-slip), or nowhere: a point holds at most one
// pair, however many slips it takes.
struct PointSinks {
  slide::DiscardFrames none;
  std::optional<SnapshotSink> frames;
  std::optional<LargestSlipSink> largest;
  slide::FrameSink* sink() {
    if (largest) return &*largest;
    if (frames) return &*frames;
    return &none;
  }
};

class SweepRunner {
 public:
  SweepRunner(const SweepScene& s, const SweepRunOptions& o, Ranks& ranks)
      : s_(s),
        o_(o),
        ranks_(ranks),
        points_(sweep_points(s)),  // validates s
        xpoints_(explicit_sweep_points(s)) {}

  // --peek: the states held by each LFM point's checkpoint in the output folder, as NetCDF for
  // track_loops, while the sweep runs (or after it stopped): points/<point>/peek/accepted.nc
  // (the last accepted state), peak.nc and, if a slip flow is paused in it, flow.nc (where the
  // flow stands: slide::paused_slip). A slip through a contact of a million sites flows for
  // hours, and the sweep writes a slip's states (--largest-slip) only once it is through. Reads
  // the checkpoint without the folder's lock: the run replaces it by a rename, so a read sees
  // one whole file. Returns 1 if a point's checkpoint could not be read or does not fit.
  int peek_only() {
    if (!ranks_.leader()) return 0;
    const fs::path out = o_.out;
    int looked = 0, failed = 0;
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const SweepPoint& point = points_[k];
      const fs::path dir = out / "points" / point_folder(point, false);
      std::error_code ec;
      fs::path file = dir / kCheckpointName;
      if (!fs::exists(file, ec)) file = dir / kCappedCheckpointName;
      if (!fs::exists(file, ec)) continue;
      ++looked;
      try {
        peek_point(point, file, dir / "peek");
      } catch (const std::exception& e) {
        ++failed;
        std::fprintf(stderr, "friction_sweep --peek: %s: %s\n", describe_point(point).c_str(),
                     e.what());
      }
    }
    if (looked == 0) {
      std::printf("friction_sweep --peek: no point of this sweep has a checkpoint in %s\n",
                  (out / "points").string().c_str());
    }
    if (!xpoints_.empty()) {
      std::printf(
          "friction_sweep --peek: the explicit model's points are not looked at (their "
          "slides pause no flow; --figures writes their states)\n");
    }
    return failed > 0 ? 1 : 0;
  }

  void peek_point(const SweepPoint& point, const fs::path& file, const fs::path& into) {
    const SlideScene ps = point_scene(point);
    const SlideCheckpoint c = read_checkpoint(file);
    // The checkpoint must be of this point's problem; the build, the slide.*, solver.* and fft.*
    // settings (adoptable) and the outputs (output.*, and snapshots= from --figures) may
    // differ: they do not change what a state is.
    const FingerprintDifference d = fingerprint_difference(c.settings, slide_fingerprint(ps));
    std::string other;
    for (const std::string& item : d.fixed) {
      if (item.rfind("snapshots=", 0) == 0 || item.rfind("output.", 0) == 0) continue;
      other += (other.empty() ? "" : ", ") + item;
    }
    if (!other.empty()) {
      throw std::invalid_argument(file.string() + ": checkpoint of another problem (" + other +
                                  " differ): give the run's scene and point flags");
    }
    const slide::SlideState& st = c.state;
    const nlohmann::json attributes = snapshot_attributes(ps, nullptr);
    ensure_directory(into);
    write_snapshots(into / "accepted.nc", {slide::snapshot_of(ps.contact, st.current, "accepted")},
                    attributes, ps.snapshot_format);
    write_snapshots(into / "peak.nc", {slide::snapshot_of(ps.contact, st.peak, "peak")}, attributes,
                    ps.snapshot_format);
    // A flow.nc of an earlier peek is not this state's.
    std::error_code ec;
    fs::remove(into / "flow.nc", ec);
    std::printf(
        "friction_sweep --peek: %s (%s): %zu steps, %d slip events; accepted state at "
        "Dx = %.4f d, Fx = %.6g, Fx/Fz = %.6g; peak Fx/Fz = %.6g at Dx = %.4f d\n",
        describe_point(point).c_str(), file.filename().string().c_str(), st.partial.trace.size(),
        st.partial.slip_events, st.current.Dx, st.current.Fx, st.current.Fx / st.current.Fz,
        st.peak.Fx / st.peak.Fz, st.peak.Dx);
    if (st.pending) {
      const slide::PausedSlip flow = slide::paused_slip(ps.contact, ps.options, st);
      slide::Snapshot snap = slide::snapshot_of(ps.contact, flow.state, "flow");
      snap.iteration = flow.iteration;
      write_snapshots(into / "flow.nc", {snap}, attributes, ps.snapshot_format);
      // How far from rest the paused state is, against the tolerance that ends the flow: a
      // creeping line is far above it, one being held comes down to it.
      const minimize::MinimizerOptions& slip_solver =
          ps.options.slip_minimizer ? *ps.options.slip_minimizer : ps.options.minimizer;
      std::printf(
          "  slip flow to Dx = %.4f d paused at iteration %d: %d sites slipped since the "
          "accepted state, Fx = %.6g, energy %.10g (accepted: %.10g at its Dx), max |r| = %.3g "
          "G d^2 (the flow ends at %.3g)\n",
          flow.state.Dx, flow.iteration, flow.slipped_sites, flow.state.Fx, flow.state.energy,
          st.current.energy, flow.max_force, slip_solver.force_tolerance);
    } else {
      std::printf("  no slip flow paused in it (taken between steps)\n");
    }
    std::printf("  wrote %s: accepted.nc, peak.nc%s (track_loops reads them)\n",
                into.string().c_str(), st.pending ? ", flow.nc" : "");
  }

  // --plan: the points, with a/b_core^0 and the memory each slide needs, whether an existing
  // table in the output folder holds its row already (it would be kept), and whether it would
  // continue from a checkpoint. Reads, writes nothing, runs nothing.
  int plan_only() {
    if (!ranks_.leader()) return 0;
    const std::string settings = settings_fingerprint(s_.base);
    const std::string settings_x = explicit_settings_fingerprint(s_);
    const fs::path out = o_.out;
    const ResumedRows kept =
        resume_rows(out / "sweep.csv", points_, settings, o_.adopt, extendable(out, false));
    const ResumedRows kept_x = resume_rows(out / "sweep_explicit.csv", xpoints_, settings_x,
                                           o_.adopt, extendable(out, true));
    std::printf("friction_sweep --plan: %zu point%s (model lfm), %zu explicit; output %s\n",
                points_.size(), points_.size() == 1 ? "" : "s", xpoints_.size(),
                out.string().c_str());
    double largest = 0.0;
    std::size_t to_run = 0, in_flight = 0;
    // A point in flight: its checkpoint (or the one between steps beside it) is continued if it
    // fits these settings, which only the run reads (a checkpoint can be hundreds of MB).
    const auto has_checkpoint = [&](const SweepPoint& p, bool x) {
      const fs::path dir = out / "points" / point_folder(p, x);
      std::error_code ec;
      return fs::exists(dir / kCheckpointName, ec) || fs::exists(dir / kStepCheckpointName, ec);
    };
    const auto status = [](bool kept_row, bool extend, bool flight) {
      return kept_row ? "kept from the table"
             : extend ? "to run on from the checkpoint kept at the limit these settings raise (a "
                        "lower bound in the table)"
             : flight ? "to run on from its checkpoint, if it fits these settings"
                      : "to run";
    };
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const auto [c, opt] = point_slide(k);
      const double bytes = slide::estimated_slide_bytes(c, opt);
      largest = std::max(largest, bytes);
      const bool flight = !kept.rows[k] && !kept.extend[k] && has_checkpoint(points_[k], false);
      to_run += kept.rows[k] ? 0 : 1;
      in_flight += flight;
      std::printf("  %s: a/b_core^0 = %.4g, about %.0f MB: %s\n",
                  describe_point(points_[k]).c_str(), c.a_over_bcore0(), bytes / 1e6,
                  status(kept.rows[k].has_value(), kept.extend[k], flight));
    }
    for (std::size_t k = 0; k < xpoints_.size(); ++k) {
      const bool flight = !kept_x.rows[k] && !kept_x.extend[k] && has_checkpoint(xpoints_[k], true);
      to_run += kept_x.rows[k] ? 0 : 1;
      in_flight += flight;
      std::printf("  explicit %s: %s\n", describe_point(xpoints_[k]).c_str(),
                  status(kept_x.rows[k].has_value(), kept_x.extend[k], flight));
    }
    std::printf(
        "to run: %zu (%zu of them continued from a capped checkpoint, %zu from their "
        "checkpoint); kept: %zu; rows of other settings dropped: %zu; largest slide about %.0f "
        "MB\n",
        to_run, kept.to_extend + kept_x.to_extend, in_flight, kept.reused + kept_x.reused,
        kept.other_settings + kept_x.other_settings, largest / 1e6);
    return 0;
  }

  int run() {
    if (o_.plan) return plan_only();
    if (o_.peek) return peek_only();
    // A signal from here on stops the sweep cleanly (points in flight checkpoint, no new ones).
    install_stop_handlers();
    settings_ = settings_fingerprint(s_.base);
    settings_x_ = explicit_settings_fingerprint(s_);
    const auto t0 = std::chrono::steady_clock::now();
    jobs_ = s_.effective_jobs(ranks_.hardware_threads());
    n_jobs_ = jobs_;
    // Over MPI ranks, rank 0 alone locks, resumes, plans and writes the tables; the others only
    // run the points it hands them, each in its point folder.
    std::optional<DirectoryLock> dir_lock;
    ResumedRows resumed, resumed_x;
    dir_ = o_.out;
    if (ranks_.leader()) {
      dir_ = ensure_directory(o_.out);
      // One sweep per output directory: its table and point folders (with their checkpoints)
      // would interleave with another's.
      dir_lock.emplace(dir_);
      if (const std::size_t n = remove_stale_temporaries(dir_)) {
        std::fprintf(stderr, "friction_sweep: removed %zu temporary file%s left by a killed run\n",
                     n, n > 1 ? "s" : "");
      }
      csv_ = dir_ / "sweep.csv";
      csv_x_ = dir_ / "sweep_explicit.csv";
      resumed = resume_rows(csv_, points_, settings_, o_.adopt, extendable(dir_, false));
      resumed_x = resume_rows(csv_x_, xpoints_, settings_x_, o_.adopt, extendable(dir_, true));
      rows_ = std::move(resumed.rows);
      rows_x_ = std::move(resumed_x.rows);
      plan();
      check_resources();
      announce(resumed, resumed_x);
    }
    ranks_.start(settings_ + "\n" + settings_x_ + "\n" + std::to_string(points_.size()) + " " +
                 std::to_string(xpoints_.size()));
    std::vector<std::size_t> ids;
    for (const Job& job : order_)
      ids.push_back(job.x ? points_.size() + job.k : job.k);
    const std::size_t interrupted = ranks_.run_points(
        ids, n_jobs_,
        [&](std::size_t id) -> std::optional<std::string> {
          auto row = run_point(job_of(id));
          if (!row) return std::nullopt;
          return encode_row(*row);
        },
        [&](std::size_t id, std::string_view row, int rank) {
          SweepRow r = decode_row(row);
          r.rank = rank;
          record(job_of(id), std::move(r));
        },
        stop_);
    if (!ranks_.leader()) return 0;
    if (fatal_) std::rethrow_exception(fatal_);
    const auto missing = [](const auto& r) { return !r.has_value(); };
    if (stop_requested() && (std::any_of(rows_.begin(), rows_.end(), missing) ||
                             std::any_of(rows_x_.begin(), rows_x_.end(), missing))) {
      std::fprintf(stderr,
                   "friction_sweep: stopped; %zu point%s finished in this run (kept in %s), %zu "
                   "in flight saved to points/*/checkpoint.cbor\ncontinue with:\n  %s\n",
                   finished_, finished_ == 1 ? "" : "s", csv_.c_str(), interrupted,
                   o_.command_line.c_str());
      return kInterrupted;
    }
    std::vector<SweepRow> done, done_x;
    for (auto& row : rows_)
      done.push_back(std::move(*row));
    for (auto& row : rows_x_)
      done_x.push_back(std::move(*row));
    return finish_sweep(dir_, s_, done, done_x,
                        {.points = points_.size(),
                         .explicit_points = xpoints_.size(),
                         .computed = order_.size(),
                         .reused = resumed.reused + resumed_x.reused,
                         .jobs = jobs_,
                         .ranks = ranks_.size(),
                         .control = o_.control},
                        t0);
  }

 private:
  const SweepPoint& point_of(const Job& j) const { return j.x ? xpoints_[j.k] : points_[j.k]; }
  // A job by the number that ranks send: the LFM's points first, then the explicit model's.
  Job job_of(std::size_t id) const {
    if (id < points_.size()) return {false, id};
    return {true, id - points_.size()};
  }
  // The fingerprint of the table a job's row goes to.
  const std::string& row_settings(const Job& j) const { return j.x ? settings_x_ : settings_; }

  // The points without a row, cheapest first (cost grows as the a^2 contact sites): results
  // start arriving at once.
  void plan() {
    for (std::size_t k = 0; k < points_.size(); ++k) {
      if (!rows_[k]) order_.push_back({false, k});
    }
    for (std::size_t k = 0; k < xpoints_.size(); ++k) {
      if (!rows_x_[k]) order_.push_back({true, k});
    }
    std::stable_sort(order_.begin(), order_.end(),
                     [&](const Job& i, const Job& j) { return point_of(i).a < point_of(j).a; });
    n_jobs_ = std::min(n_jobs_, static_cast<int>(order_.size()));
  }

  // The LFM scene at a point: the sweep's settings with its a, R and tip.
  SlideScene point_scene(const SweepPoint& point) const {
    SlideScene ps = s_.base;
    ps.contact.a = point.a;
    ps.contact.R = point.R;
    ps.contact.tip = point.tip;
    return ps;
  }

  // The contact and slide options of LFM point k, as its memory estimate sees them.
  std::pair<interface::ContactScene, slide::SlideOptions> point_slide(std::size_t k) const {
    const interface::ContactScene c = point_scene(points_[k]).contact;
    slide::SlideOptions opt = s_.base.options;
    if (!o_.figures) opt.path_frame_slips = 0;  // frames discarded: no path is held either
    return {c, opt};
  }

  // The largest contacts still to run, as many at once as run in parallel on this host (over MPI
  // ranks: its ranks' threads), must fit together (explicit points are not estimated: a = 43 d
  // takes 50 MiB, docs/benchmarks.md; a/R < 0.1 does not bound a, so a large explicit sweep is
  // the user's to size); with --figures, every point's snapshots (and a checkpoint) on disk, as
  // contact_slide writes them.
  void check_resources() const {
    std::vector<double> bytes;
    double a_max = 0.0;
    for (const Job& job : order_) {
      if (job.x) continue;
      const auto [c, opt] = point_slide(job.k);
      bytes.push_back(slide::estimated_slide_bytes(c, opt));
      a_max = std::max(a_max, c.a);
    }
    std::sort(bytes.rbegin(), bytes.rend());
    const auto at_once = std::min(
        bytes.size(), static_cast<std::size_t>(std::max(n_jobs_, 1) * ranks_.ranks_on_host()));
    const double total = std::accumulate(bytes.begin(), bytes.begin() + at_once, 0.0);
    char what[160];
    std::snprintf(what, sizeof what,
                  "running the sweep's %zu largest contacts at once (a up to %g d; fewer with "
                  "--jobs)",
                  at_once, a_max);
    check_fits_in_memory(what, total,
                         "estimate: 260 bytes per point of each block's padded FFT grid "
                         "and the minimiser's vectors on the contact");
    if (!o_.figures) return;
    double disk = 0.0;
    for (const Job& job : order_) {
      SlideScene ps = s_.base;
      ps.contact.a = point_of(job).a;
      disk += estimated_snapshot_bytes(ps).run(std::max(10, ps.options.slips_to_stop),
                                               ps.options.path_frame_slips);
    }
    check_fits_on_disk(
        "--figures: the snapshots of the sweep's " + std::to_string(order_.size()) + " points",
        dir_.string(), disk, "estimate for 10 slip events per point, uncompressed");
  }

  // Whether point k (of points_, or xpoints_ with `x`) of the sweep in `out` kept the
  // checkpoint of a capped lower bound (capped_lower_bound): one a larger limit continues.
  [[nodiscard]] std::function<bool(std::size_t)> extendable(const fs::path& out, bool x) const {
    return [this, out, x](std::size_t k) {
      const SweepPoint& p = x ? xpoints_[k] : points_[k];
      std::error_code ec;
      return fs::exists(out / "points" / point_folder(p, x) / kCappedCheckpointName, ec);
    };
  }

  // What the sweep is, what it reused and dropped, what it runs; the tables rewritten to hold
  // exactly the reused rows (points are added as they finish).
  void announce(const ResumedRows& resumed, const ResumedRows& resumed_x) {
    std::fprintf(stderr,
                 "friction_sweep: %zu points (model %s): R = %s d; %s = %s; %s envelope, "
                 "alpha = %g, tau0 = %g G, nu = %g; %s protocol, %s, tolerance %g\n",
                 points_.size() + xpoints_.size(), s_.model.c_str(),
                 describe_list(s_.radii()).c_str(), s_.a ? "a (d)" : "a/b_core^0",
                 describe_list(s_.a ? s_.a->values : s_.a_over_bcore0->values).c_str(),
                 s_.base.contact.envelope.c_str(), s_.base.contact.alpha, s_.base.contact.tau0,
                 s_.base.contact.material.nu, slide::to_string(s_.base.options.protocol).c_str(),
                 minimize::to_string(s_.base.options.minimizer.method).c_str(),
                 s_.base.options.minimizer.force_tolerance);
    if (const auto tips = sweep_tips(s_); tips.size() > 1 || !tips.front().aligned()) {
      std::string list;
      for (const auto& t : tips) {
        char text[64];
        std::snprintf(text, sizeof text, "%s%g deg / m = %g", list.empty() ? "" : ", ", t.angle,
                      t.mismatch);
        list += text;
      }
      std::fprintf(stderr, "friction_sweep: tip lattices (angle / mismatch): %s\n", list.c_str());
    }
    for (const auto& [table, res, n] : {std::tuple{&csv_, &resumed, points_.size()},
                                        std::tuple{&csv_x_, &resumed_x, xpoints_.size()}}) {
      if (!fs::exists(*table)) continue;
      std::fprintf(stderr, "friction_sweep: reused %zu of %zu points from %s", res->reused, n,
                   table->c_str());
      if (res->adopted > 0) {
        std::fprintf(stderr, " (%zu of another build or other numerical settings, --adopt)",
                     res->adopted);
      }
      if (res->to_extend > 0) {
        std::fprintf(stderr,
                     "; %zu lower bound%s at a limit these settings raise continue%s from the "
                     "checkpoint kept at the limit (--adopt)",
                     res->to_extend, res->to_extend > 1 ? "s" : "", res->to_extend > 1 ? "" : "s");
      }
      // Dropped rows leave the table; their point folders stay until the points are run again.
      std::string why;
      for (const auto& [count, reason] : {std::pair{res->other_settings, "with other settings"},
                                          std::pair{res->not_requested, "not in this sweep"},
                                          std::pair{res->failed, "failed, run again"}}) {
        if (count > 0) why += (why.empty() ? "" : ", ") + std::to_string(count) + " " + reason;
      }
      if (!why.empty()) std::fprintf(stderr, "; dropped rows: %s", why.c_str());
      std::fprintf(stderr, "\n");
    }
    if (s_.runs_lfm()) write_table(csv_, rows_);
    if (s_.runs_explicit()) write_table(csv_x_, rows_x_);
    if (!order_.empty()) {
      std::string where;
      if (ranks_.distributed()) where = " on each of " + std::to_string(ranks_.size()) + " ranks";
      std::fprintf(stderr,
                   "friction_sweep: running %zu point%s, %d at once%s, %d FFT thread%s each\n",
                   order_.size(), order_.size() > 1 ? "s" : "", n_jobs_, where.c_str(),
                   s_.base.options.fft.threads, s_.base.options.fft.threads > 1 ? "s" : "");
    }
  }

  // A finished point's row: into the table of its model, which is rewritten.
  void record(const Job& job, SweepRow row) {
    const std::lock_guard lock(table_mutex_);
    ++finished_;
    const std::string where =
        ranks_.distributed() ? " on rank " + std::to_string(row.rank) : std::string();
    std::fprintf(stderr,
                 "friction_sweep: [%zu/%zu] %s%s, a/b_core^0 = %.4g: "
                 "%s = %.5f%s, %.1f s%s%s%s\n",
                 finished_, order_.size(), job.x ? "explicit " : "",
                 describe_point(row.point).c_str(), row.a_over_bcore0,
                 relative_friction_name(row.envelope).c_str(), row.relative_friction,
                 row.mu_is_lower_bound ? " (lower bound)" : "", row.wall_s, where.c_str(),
                 row.failed ? ": FAILED: " : "", row.failed ? row.stop_reason.c_str() : "");
    (job.x ? rows_x_ : rows_)[job.k] = std::move(row);
    try {
      write_table(job.x ? csv_x_ : csv_, job.x ? rows_x_ : rows_);
    } catch (...) {
      if (!fatal_) fatal_ = std::current_exception();
      stop_ = true;
    }
  }

  void say(const SweepPoint& point, const std::string& what) {
    const std::lock_guard lock(table_mutex_);
    std::fprintf(stderr, "friction_sweep: %s: %s\n", describe_point(point).c_str(), what.c_str());
  }

  // The point's checkpoint, if it has one of these settings. A damaged, foreign or unreadable
  // one is kept aside, not overwritten: a checkpoint of another build or scene can hold hours
  // of a long point, and the run that was meant to continue it may simply be using the wrong
  // binary (docs/reliability.md). Moving it back undoes the new start.
  std::optional<SlideCheckpoint> load_checkpoint(const fs::path& point_dir,
                                                 const fs::path& checkpoint_file,
                                                 const std::string& point_settings) {
    if (std::error_code ec; !fs::exists(checkpoint_file, ec)) return std::nullopt;
    try {
      SlideCheckpoint c = read_checkpoint(checkpoint_file);
      if (const auto adoption =
              check_or_adopt_checkpoint(c, point_settings, checkpoint_file, o_.adopt)) {
        const std::string what = record_adoption(checkpoint_file, c, *adoption);
        const std::lock_guard lock(table_mutex_);
        std::fprintf(stderr, "friction_sweep: %s\n", what.c_str());
      }
      return c;
    } catch (const std::exception& e) {
      const fs::path kept = point_dir / "checkpoint.replaced.cbor";
      std::error_code rename_ec;
      fs::rename(checkpoint_file, kept, rename_ec);
      const std::lock_guard lock(table_mutex_);
      std::fprintf(
          stderr, "friction_sweep: starting the point over (%s%s): %s\n",
          rename_ec ? "the old checkpoint could not be kept: " : "the old checkpoint is kept as ",
          rename_ec ? rename_ec.message().c_str() : kept.string().c_str(), e.what());
      return std::nullopt;
    }
  }

  // Large points run for hours, mostly inside a few relaxations (a slip sweeps a contact of a
  // million sites in thousands of iterations): a line now and then says where each is and that
  // it runs.
  slide::SlideProgress progress_of(const Job& job, const SweepPoint& point) {
    if (!(o_.control.progress_every > 0.0)) return {};
    return [this, job, point, lines = ProgressLines(o_.control.progress_every)](
               const slide::SlideProgressInfo& info) mutable {
      if (!lines.due(info)) return;
      const std::lock_guard lock(table_mutex_);
      std::fprintf(stderr, "friction_sweep: %s%s: %s\n", job.x ? "explicit " : "",
                   describe_point(point).c_str(), describe_progress(info).c_str());
    };
  }

  // The point's frame sinks (PointSinks), picked up where a resumed point left them.
  void open_sinks(PointSinks& sinks, const fs::path& point_dir, const SweepPoint& point,
                  const SlideScene& ps, const nlohmann::json& extra,
                  const std::optional<SlideCheckpoint>& start) {
    if (o_.figures) {
      sinks.frames.emplace(point_dir / "snapshots", snapshot_attributes(ps, extra),
                           ps.snapshot_format, &output_mutex_);
      if (const std::string warning =
              sinks.frames->start(start ? std::optional(start->state.current.Dx) : std::nullopt);
          !warning.empty()) {
        say(point, warning);
      }
    }
    if (o_.largest_slip) {
      // Not part of the checkpoint's settings: the sink restarts from the slips of the
      // checkpoint's trace, and says if their largest is not on disk.
      sinks.largest.emplace(point_dir / "largest_slip", snapshot_attributes(ps, extra),
                            ps.snapshot_format, &output_mutex_);
      std::optional<LargestSlipSink::Resume> so_far;
      if (start) {
        so_far.emplace();
        const auto& trace = start->state.partial.trace;
        for (std::size_t i = 0; i < trace.size(); ++i) {
          if (!trace[i].slip) continue;
          so_far->slips.push_back({.Dx = trace[i].Dx,
                                   .slipped_sites = trace[i].slipped_sites,
                                   .Dx_before = i > 0 ? trace[i - 1].Dx : trace[i].Dx,
                                   .replayed = trace[i].replayed});
        }
      }
      if (const std::string warning = sinks.largest->start(so_far); !warning.empty()) {
        say(point, warning);
      }
    }
  }

  // One point, on the rank that took it: its scene, checkpoint, sinks, slide and outputs; its
  // row (failed if anything in it throws: the other points go on), none if it was interrupted.
  std::optional<SweepRow> run_point(const Job& job) {
    const auto started = std::chrono::steady_clock::now();
    const SweepPoint& point = point_of(job);
    SlideScene ps = point_scene(point);
    try {
      return slide_point(job, point, ps);
    } catch (const std::exception& e) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      return error_row(ps, e.what(), seconds, row_settings(job));
    }
  }

  // The slide of a point (`ps`: the LFM scene at the point, replaced by the explicit model's
  // for an explicit point); no row if it was interrupted (the next run continues it).
  std::optional<SweepRow> slide_point(const Job& job, const SweepPoint& point, SlideScene& ps) {
    // The explicit model: its scene, and alpha of the potential at the point's central load.
    const ExplicitSlideScene es = explicit_point_scene(s_, point);
    ExplicitAlpha alpha_x;
    if (job.x) {
      alpha_x = explicit_alpha(es);
      ps = explicit_as_slide_scene(es, alpha_x);  // contact.alpha: of the potential
    }
    const nlohmann::json extra = job.x ? explicit_summary_extra(es, alpha_x) : nullptr;
    // A point in flight saves its slide in its folder every checkpoint_every seconds and when
    // the sweep is stopped (SIGINT, SIGTERM); the next run continues it from there, to the same
    // result bit for bit. A checkpoint of other settings is replaced (and kept aside).
    const fs::path point_dir = dir_ / "points" / point_folder(point, job.x);
    // Held while the point runs: a contact_slide started into this folder is refused, and so is
    // this point (failed, the sweep goes on) if a contact_slide already writes there. The
    // sweep's own lock on dir_ (rank 0's, over MPI ranks) is not in the way.
    const DirectoryLock point_lock(ensure_directory(point_dir), dir_);
    const fs::path checkpoint_file = point_dir / kCheckpointName;
    // A lower bound stopped at a limit keeps its last checkpoint (below); under --adopt a run
    // with other limits continues from it. Without --adopt the point starts over as before, and
    // the kept checkpoint stays for a later --adopt.
    const fs::path capped_file = point_dir / kCappedCheckpointName;
    if (std::error_code ec;
        o_.adopt && !fs::exists(checkpoint_file, ec) && fs::exists(capped_file, ec)) {
      fs::rename(capped_file, checkpoint_file, ec);
      const std::lock_guard lock(table_mutex_);
      std::fprintf(stderr,
                   "friction_sweep: %s%s, a lower bound at its limit, continues from the "
                   "checkpoint kept there if it fits these settings%s%s\n",
                   job.x ? "explicit " : "", describe_point(point).c_str(),
                   ec ? ": could not take it: " : "", ec ? ec.message().c_str() : "");
    }
    // With --figures the point writes snapshots as it goes: a checkpoint of a run without them
    // cannot continue one with them (the frames before it would be missing).
    const std::string point_settings =
        (job.x ? explicit_slide_fingerprint(es, alpha_x) : slide_fingerprint(ps)) +
        (o_.figures ? " snapshots=1" : " snapshots=0");
    // A kill between a checkpoint's steps cannot leave only checkpoint.step.cbor (it is a second
    // name, made before the write), but a file lost otherwise can: then continue from that one.
    const fs::path step_file = point_dir / kStepCheckpointName;
    if (std::error_code ec; !fs::exists(checkpoint_file, ec) && fs::exists(step_file, ec)) {
      fs::rename(step_file, checkpoint_file, ec);
    }
    const std::optional<SlideCheckpoint> start =
        load_checkpoint(point_dir, checkpoint_file, point_settings);
    if (start) {
      const std::lock_guard lock(table_mutex_);
      std::fprintf(stderr, "friction_sweep: resuming %s%s from its checkpoint at Dx = %.4f d\n",
                   job.x ? "explicit " : "", describe_point(point).c_str(),
                   start->state.current.Dx);
    }
    PointSinks sinks;
    open_sinks(sinks, point_dir, point, ps, extra, start);
    auto& frames = sinks.frames;
    // Whether the last checkpoint holds a paused slip flow: such a state continues the step it
    // was in as that step was cut by the limit, and under the reference protocol a larger
    // limit would plan another step than the paused one (a refused start), so it is not the one
    // kept for a larger limit. The last checkpoint between steps is kept beside it instead
    // (checkpoint.step.cbor) until a newer one replaces both; the slide writes one at the top of
    // the step after every paused checkpoint (SlideControl), so that is at most a step old.
    bool last_checkpoint_paused = start && start->state.pending.has_value();
    if (std::error_code ec; !last_checkpoint_paused) fs::remove(step_file, ec);  // not this run's
    const slide::SlideControl control{
        .progress = progress_of(job, point),
        .checkpoint =
            [&](const slide::SlideState& state) {
              ensure_directory(point_dir);
              if (frames) frames->flush();
              const bool paused = state.pending.has_value();
              std::error_code ec;
              if (paused && !last_checkpoint_paused && fs::exists(checkpoint_file, ec)) {
                // The one between steps stays, as a second name of its file: the atomic write
                // below replaces checkpoint.cbor's entry, so no moment is without a checkpoint.
                fs::remove(step_file, ec);
                fs::create_hard_link(checkpoint_file, step_file, ec);
              }
              write_checkpoint(checkpoint_file, {.settings = point_settings, .state = state});
              if (!paused) fs::remove(step_file, ec);
              last_checkpoint_paused = paused;
            },
        .checkpoint_every_s = o_.control.checkpoint_every,
        .stop_requested = stop_requested,
        .start = start ? &start->state : nullptr,
        .frames = sinks.sink()};
    const slide::SlideResult result = job.x ? slide_explicit_scene(es, alpha_x, control)
                                            : slide::slide(ps.contact, ps.options, control);
    if (result.interrupted) {
      if (frames) frames->flush();
      return std::nullopt;  // no row: the next run continues from the checkpoint
    }
    if (frames) frames->finish();
    {
      std::unique_lock lock(output_mutex_, std::defer_lock);
      if (o_.figures) lock.lock();
      SlideOutputOptions oo{.figures = o_.figures};
      if (job.x) oo.summary_extra = extra;
      write_slide_outputs(point_dir, ps, result, oo);
    }
    std::error_code ec;
    const fs::path& between_steps = last_checkpoint_paused ? step_file : checkpoint_file;
    const bool capped = capped_lower_bound(result.mu_is_lower_bound, result.stop_reason);
    if (capped && fs::exists(between_steps, ec)) {
      // A lower bound only because a limit stopped it: its last checkpoint between steps stays,
      // for a larger limit under --adopt. It is from the top of a step before the one that
      // reached the limit (the slide does not checkpoint at the cap), so the continued run takes
      // that step again under the larger limit: the steps of a run with that limit from the
      // start, unless a trial step before the checkpoint was already cut to the cap and slipped
      // (an adaptive bracket ending at the cap), when it continues that bracket
      // (docs/reliability.md).
      fs::rename(between_steps, capped_file, ec);
      {
        const std::lock_guard lock(table_mutex_);
        std::fprintf(
            stderr,
            "friction_sweep: %s%s, a lower bound at its limit, keeps its last checkpoint "
            "between steps%s for a larger limit (--adopt)%s%s\n",
            job.x ? "explicit " : "", describe_point(point).c_str(),
            last_checkpoint_paused ? " (the later one inside a slip's flow is dropped)" : "",
            ec ? ": could not keep it (the files stay as they are): " : "",
            ec ? ec.message().c_str() : "");
      }
      if (ec) return sweep_row(ps, result, row_settings(job));
    } else {
      fs::remove(capped_file, ec);
      if (capped) {
        const std::lock_guard lock(table_mutex_);
        std::fprintf(stderr,
                     "friction_sweep: %s%s, a lower bound at its limit, has no checkpoint "
                     "between steps to keep: a larger limit runs it again\n",
                     job.x ? "explicit " : "", describe_point(point).c_str());
      }
    }
    fs::remove(checkpoint_file, ec);  // the row is final
    fs::remove(step_file, ec);
    return sweep_row(ps, result, row_settings(job));
  }

  const SweepScene& s_;
  const SweepRunOptions& o_;
  Ranks& ranks_;
  const std::vector<SweepPoint> points_, xpoints_;
  std::string settings_, settings_x_;  // the rows' fingerprints
  fs::path dir_, csv_, csv_x_;
  std::vector<std::optional<SweepRow>> rows_, rows_x_;
  std::vector<Job> order_;
  int jobs_ = 1;             // points at once (on each rank), as asked or by default
  int n_jobs_ = 0;           // threads: jobs_, or fewer for fewer points
  std::mutex table_mutex_;   // rows, sweep.csv and the progress lines
  std::mutex output_mutex_;  // the NetCDF library is not thread-safe
  std::atomic<bool> stop_{false};
  std::exception_ptr fatal_;  // failure to write sweep.csv: ends the sweep
  std::size_t finished_ = 0;
};

}  // namespace

int run_sweep(const SweepScene& s, const SweepRunOptions& options, Ranks& ranks) {
  SweepRunner runner(s, options, ranks);
  return runner.run();
}

}  // namespace asperity::app
