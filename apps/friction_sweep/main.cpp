// friction_sweep: static friction of the lateral force model (MODEL.md sections 3 and 5), and
// with sweep.model = "explicit" or "both" of the explicit atomistic model (MODEL.md 4), over
// many (a, R) points, run in parallel. Reads a sweep scene (default:
// data/scenes/sweep_default.toml), lets flags override it, and writes into the output directory
// - sweep.csv: one row per point, sorted by R then a, rewritten after every finished point, so
//   that an interrupted sweep loses only the points in flight; a later run with the same
//   settings reuses its rows instead of recomputing them;
// - points/a<a>_R<R>/: summary.json and trace.csv of each point (with --figures, also the
//   figures and snapshots of contact_slide; with --largest-slip, largest_slip/ with the states
//   before and after the point's largest slip and its peak state);
// - summary.json: settings, counts and the log-log slope of mu/alpha in Regime II; wall times
//   and provenance under "run" (the rest is the same for the same sweep);
// - mu_vs_a_over_bcore0.png and kinetic_over_static.png;
// - with the explicit model: sweep_explicit.csv (same columns), points/explicit_a<a>_R<R>/,
//   collapse.png (mu/alpha of both models against a/b_core^0) and, in summary.json,
//   "explicit_vs_lfm" (the ratio at each explicit point, the largest deviation in
//   a/b_core^0 in [0.1, 10]).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "common/cli.hpp"
#include "common/cli_checks.hpp"
#include "common/memory.hpp"
#include "common/output_files.hpp"
#include "common/plot.hpp"
#include "common/point_runner.hpp"
#include "common/slide_checkpoint.hpp"
#include "common/slide_io.hpp"
#include "common/snapshot_sink.hpp"
#include "sweep.hpp"

using namespace asperity;
namespace fs = std::filesystem;

namespace {

// Window of the Regime II slope fit (MODEL.md 8), and where the slope -2/3 guide starts.
constexpr double kFitLo = 10.0, kFitHi = 60.0, kGuideFrom = 10.0;
// Window of the model comparison (issue 4 acceptance 3).
constexpr double kCompareLo = 0.1, kCompareHi = 10.0;

// The collapse of the two models: mu/alpha of each against a/b_core^0, log-log, per R.
fs::path write_collapse(const fs::path& dir, const std::vector<app::SweepRow>& lfm,
                        const std::vector<app::SweepRow>& expl, const nlohmann::json& comparison) {
  std::vector<app::Series> series;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0, y_lo = 1.0;
  const auto add = [&](const std::vector<app::SweepRow>& rows, const char* model,
                       const char* style) {
    std::map<double, app::Series> by_R;
    for (const auto& r : rows) {
      if (r.failed || !(r.mu_over_alpha > 0.0)) continue;
      auto& s = by_R[r.point.R];
      if (s.title.empty()) {
        char title[64];
        std::snprintf(title, sizeof title, "%s, R = %g d", model, r.point.R);
        s.title = title;
        s.style = style;
      }
      s.x.push_back(r.a_over_bcore0);
      s.y.push_back(r.mu_over_alpha);
      lo = std::min(lo, r.a_over_bcore0);
      hi = std::max(hi, r.a_over_bcore0);
      y_lo = std::min(y_lo, r.mu_over_alpha);
    }
    for (auto& [R, s] : by_R)
      series.push_back(std::move(s));
  };
  add(lfm, "LFM", "linespoints pt 7 ps 1.3 lw 2");
  add(expl, "explicit", "linespoints pt 5 ps 1.8 lw 2 dt 2");
  if (series.empty()) return {};
  lo /= 1.5;
  hi *= 1.5;
  series.push_back(app::Series{.x = {lo, hi},
                               .y = {1.0, 1.0},
                               .title = "mu/alpha = 1 (Regime I)",
                               .style = "lines dt 3 lw 1 lc 'black'"});
  char title[200], worst_text[32] = "-";
  if (const auto& worst = comparison["max_deviation_in_window"]; !worst.is_null()) {
    std::snprintf(worst_text, sizeof worst_text, "%.1f%%", 100.0 * worst.get<double>());
  }
  std::snprintf(title, sizeof title,
                "Collapse: mu/alpha of both models; |explicit/LFM - 1| at most %s in "
                "a/b_core^0 [%g, %g]",
                worst_text, kCompareLo, kCompareHi);
  const fs::path png = dir / "collapse.png";
  app::plot_png(png, series,
                {.title = title,
                 .xlabel = "a / b_core^0 (alpha: LFM scene value; explicit: of the potential)",
                 .ylabel = "mu / alpha",
                 .logx = true,
                 .logy = true,
                 .xrange = std::pair{lo, hi},
                 .yrange = std::pair{y_lo / 1.5, 1.3}});
  return png;
}

std::string describe_list(const std::vector<double>& v) {
  std::string out;
  char buf[32];
  for (double x : v) {
    std::snprintf(buf, sizeof buf, "%g", x);
    out += (out.empty() ? "" : ", ") + std::string(buf);
  }
  return out;
}

void write_table(const fs::path& csv, const std::vector<std::optional<app::SweepRow>>& rows) {
  app::CsvTable table(app::sweep_columns());
  for (const auto& row : rows) {
    if (row) table.add_row(row->cells);
  }
  table.write(csv);
}

// The sweep's settings for summary.json: every key of the scene but the per-point a and R.
nlohmann::json scene_json(const app::SweepScene& s, int jobs) {
  const auto& c = s.base.contact;
  const auto& o = s.base.options;
  const auto& m = o.minimizer;
  nlohmann::json j = {
      {"source", s.source},
      {"R", s.R.values},
      {"alpha", c.alpha},
      {"G", c.material.G},
      {"nu", c.material.nu},
      {"d", c.d},
      {"protocol", slide::to_string(o.protocol)},
      {"step", o.step},
      {"max_step", o.max_step},
      {"min_step", o.min_step},
      {"distance", o.distance == 0.0 ? nlohmann::json("automatic") : nlohmann::json(o.distance)},
      {"max_distance", o.max_distance},
      {"slips_to_stop", o.slips_to_stop},
      {"replay_cycle", o.replay_cycle},
      {"solver", minimize::to_string(m.method)},
      {"tolerance", m.force_tolerance},
      {"max_iterations", m.max_iterations},
      {"memory", m.memory},
      {"max_displacement", m.max_displacement},
      {"flow_tolerance", m.flow_tolerance},
      {"preconditioner", minimize::to_string(m.preconditioner)},
      {"fft_threads", o.fft.threads},
      {"fft_planner", fft::to_string(o.fft.planner)},
      {"jobs", jobs},
      {"settings", app::settings_fingerprint(s.base)},
  };
  if (s.a) j["a"] = s.a->values;
  if (s.a_over_bcore0) j["a_over_bcore0"] = s.a_over_bcore0->values;
  j["model"] = s.model;
  if (s.runs_explicit()) {
    j["explicit"] = {{"G_eps_sigma3", s.potential.G_eps_sigma3},
                     {"sigma_over_d", s.potential.sigma_over_d},
                     {"alpha", "of the potential at each point's central load (alpha_path)"},
                     {"settings", app::explicit_settings_fingerprint(s)}};
  }
  return j;
}

// Series per R, in increasing R; `pick` returns the y value or nothing to leave the row out.
template <class Pick>
std::vector<app::Series> series_per_R(const std::vector<app::SweepRow>& rows, Pick pick) {
  std::map<double, app::Series> by_R;
  for (const auto& r : rows) {
    const std::optional<double> y = pick(r);
    if (!y) continue;
    auto& s = by_R[r.point.R];
    if (s.title.empty()) {
      char title[48];
      std::snprintf(title, sizeof title, "R = %g d", r.point.R);
      s.title = title;
      s.style = "linespoints pt 7 ps 1.3";
    }
    s.x.push_back(r.a_over_bcore0);
    s.y.push_back(*y);
  }
  std::vector<app::Series> out;
  for (auto& [R, s] : by_R)
    out.push_back(std::move(s));
  return out;
}

// mu/alpha against a/b_core^0, log-log, with the Regime I limit and a Regime II guide. Returns
// the files written.
std::vector<fs::path> write_figures(const fs::path& dir, const app::SweepScene& s,
                                    const std::vector<app::SweepRow>& rows) {
  std::vector<fs::path> written;
  char title[200];
  std::snprintf(title, sizeof title, "Static friction: alpha = %g, nu = %g; %s, %s, tol %g",
                s.base.contact.alpha, s.base.contact.material.nu,
                slide::to_string(s.base.options.protocol).c_str(),
                minimize::to_string(s.base.options.minimizer.method).c_str(),
                s.base.options.minimizer.force_tolerance);

  // log scales: non-positive values cannot be drawn; failed points are not measurements.
  auto mu = series_per_R(rows, [](const app::SweepRow& r) -> std::optional<double> {
    if (r.failed || !(r.mu_over_alpha > 0.0)) return std::nullopt;
    return r.mu_over_alpha;
  });
  if (mu.empty()) {
    std::fprintf(stderr, "friction_sweep: no finished point: mu_vs_a_over_bcore0.png skipped\n");
  } else {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo = inf, hi = 0.0, log_x = 0.0, log_y = 0.0, guide_lo = inf, guide_hi = 0.0;
    int n_guide = 0;
    app::Series bounds{.title = "lower bound (no peak within the distance)",
                       .style = "points pt 8 ps 2.5 lc 'black'"};
    for (const auto& r : rows) {
      if (r.failed || !(r.mu_over_alpha > 0.0)) continue;
      lo = std::min(lo, r.a_over_bcore0);
      hi = std::max(hi, r.a_over_bcore0);
      if (r.mu_is_lower_bound) {
        bounds.x.push_back(r.a_over_bcore0);
        bounds.y.push_back(r.mu_over_alpha);
      }
      if (r.a_over_bcore0 >= kGuideFrom && !r.mu_is_lower_bound) {
        log_x += std::log(r.a_over_bcore0);
        log_y += std::log(r.mu_over_alpha);
        guide_lo = std::min(guide_lo, r.a_over_bcore0);
        guide_hi = std::max(guide_hi, r.a_over_bcore0);
        ++n_guide;
      }
    }
    lo /= 1.5;
    hi *= 1.5;
    app::Series one{.x = {lo, hi},
                    .y = {1.0, 1.0},
                    .title = "mu/alpha = 1 (Regime I)",
                    .style = "lines dt 2 lw 2 lc 'black'"};
    mu.push_back(one);
    if (!bounds.x.empty()) mu.push_back(bounds);
    if (n_guide > 0) {
      // Through the centre of the points on log axes: exp(mean log x), exp(mean log y).
      const double x0 = std::exp(log_x / n_guide), y0 = std::exp(log_y / n_guide);
      app::Series guide{.title = "slope -2/3 (Regime II)", .style = "lines dt 3 lw 2 lc 'gray40'"};
      for (double x : {guide_lo / 1.5, guide_hi * 1.5}) {
        guide.x.push_back(x);
        guide.y.push_back(y0 * std::pow(x / x0, -2.0 / 3.0));
      }
      mu.push_back(guide);
    }
    const fs::path png = dir / "mu_vs_a_over_bcore0.png";
    app::plot_png(png, mu,
                  {.title = title,
                   .xlabel = "a / b_core^0",
                   .ylabel = "mu / alpha",
                   .logx = true,
                   .logy = true,
                   .xrange = std::pair{lo, hi}});
    written.push_back(png);
  }

  // Kinetic friction as the slider defines it: the mean of Fx/Fz after the first slip, or over
  // the last period when nothing slipped (about 0: smooth sliding costs no work).
  auto ratio = series_per_R(rows, [](const app::SweepRow& r) -> std::optional<double> {
    if (r.failed || !std::isfinite(r.kinetic_over_static)) return std::nullopt;
    return r.kinetic_over_static;
  });
  if (ratio.empty()) {
    std::fprintf(stderr, "friction_sweep: no finished point: kinetic_over_static.png skipped\n");
  } else {
    const fs::path png = dir / "kinetic_over_static.png";
    std::snprintf(
        title, sizeof title,
        "Kinetic (mean Fx/Fz after the first slip, else over the last period) over static "
        "friction: alpha = %g",
        s.base.contact.alpha);
    app::plot_png(
        png, ratio,
        {.title = title, .xlabel = "a / b_core^0", .ylabel = "kinetic / static", .logx = true});
    written.push_back(png);
  }
  return written;
}

// How many points a sweep had, and how many it computed and reused.
struct SweepCounts {
  std::size_t points = 0, explicit_points = 0, computed = 0, reused = 0;
};

// The end of a sweep whose points are all in: figures, the Regime II slope, the comparison of
// the models, summary.json and the lines printed. Returns the exit status (1 if a point failed).
int finish_sweep(const fs::path& dir, const app::SweepScene& s,
                 const std::vector<app::SweepRow>& done, const std::vector<app::SweepRow>& done_x,
                 const SweepCounts& n, std::chrono::steady_clock::time_point t0) {
  const fs::path csv = dir / "sweep.csv", csv_x = dir / "sweep_explicit.csv";
  auto figure_files = done.empty() ? std::vector<fs::path>{} : write_figures(dir, s, done);
  const nlohmann::json fit = app::fit_slope(done, kFitLo, kFitHi);
  nlohmann::json comparison;
  if (s.runs_explicit()) {
    comparison = app::compare_models(done, done_x, kCompareLo, kCompareHi);
    if (const fs::path png = write_collapse(dir, done, done_x, comparison); !png.empty()) {
      figure_files.insert(figure_files.begin(), png);
    }
  }
  std::vector<std::pair<const app::SweepRow*, bool>> failed;  // row, explicit
  double points_wall = 0.0;
  nlohmann::json point_times = nlohmann::json::array();
  for (const auto* list : {&done, &done_x}) {
    const bool x = list == &done_x;
    for (const auto& r : *list) {
      if (r.failed) failed.emplace_back(&r, x);
      // Reused rows carry no time: they were computed by an earlier run.
      if (std::isfinite(r.wall_s)) {
        points_wall += r.wall_s;
        point_times.push_back({{"model", x ? "explicit" : "lfm"},
                               {"a", r.point.a},
                               {"R", r.point.R},
                               {"wall_s", r.wall_s}});
      }
    }
  }
  nlohmann::json failed_json = nlohmann::json::array();
  for (const auto& [r, x] : failed)
    failed_json.push_back({{"model", x ? "explicit" : "lfm"},
                           {"a", r->point.a},
                           {"R", r->point.R},
                           {"stop_reason", r->stop_reason}});
  nlohmann::json figure_names = nlohmann::json::array();
  for (const auto& f : figure_files)
    figure_names.push_back(f.filename().string());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // "run" holds what differs between runs of the same sweep (times, host, date); the rest is
  // a function of the inputs, the build and what was reused.
  nlohmann::json tables = nlohmann::json::array();
  if (s.runs_lfm()) tables.push_back("sweep.csv");
  if (s.runs_explicit()) tables.push_back("sweep_explicit.csv");
  nlohmann::json summary = {{"tool", "friction_sweep"},
                            {"scene", scene_json(s, s.effective_jobs())},
                            {"points", n.points + n.explicit_points},
                            {"explicit_points", n.explicit_points},
                            {"computed", n.computed},
                            {"reused", n.reused},
                            {"failed", failed.size()},
                            {"failed_points", failed_json},
                            {"fit", fit},
                            {"table", s.runs_lfm() ? "sweep.csv" : "sweep_explicit.csv"},
                            {"tables", tables},
                            {"figures", figure_names},
                            {"run",
                             {{"provenance", app::provenance_json()},
                              {"wall_s", wall},
                              {"points_wall_s", points_wall},
                              {"point_wall_s", point_times}}}};
  if (s.runs_explicit()) summary["explicit_vs_lfm"] = comparison;
  app::write_json(dir / "summary.json", summary);

  std::printf("points: %zu (%zu computed, %zu reused, %zu failed), %.1f s\n",
              n.points + n.explicit_points, n.computed, n.reused, failed.size(), wall);
  if (s.runs_explicit()) {
    const auto& worst = comparison["max_deviation_in_window"];
    if (worst.is_null()) {
      std::printf(
          "explicit against LFM: no explicit point with LFM rows around it in "
          "a/b_core^0 [%g, %g]\n",
          kCompareLo, kCompareHi);
    } else {
      std::printf(
          "explicit against LFM: mu/alpha within %.1f%% over %zu points in a/b_core^0 "
          "[%g, %g]\n",
          100.0 * worst.get<double>(), comparison["compared_in_window"].get<std::size_t>(),
          kCompareLo, kCompareHi);
    }
  }
  if (fit["slope"].is_null()) {
    std::printf("fit over a/b_core^0 in [%g, %g]: none (%zu points; %s)\n", kFitLo, kFitHi,
                fit["points"].get<std::size_t>(), fit["note"].get<std::string>().c_str());
  } else {
    std::printf("fit over a/b_core^0 in [%g, %g]: slope %.4f (%zu points; Regime II: -2/3)\n",
                kFitLo, kFitHi, fit["slope"].get<double>(), fit["points"].get<std::size_t>());
  }
  std::printf("results:%s%s %s\n", s.runs_lfm() ? (" " + csv.string()).c_str() : "",
              s.runs_explicit() ? (" " + csv_x.string()).c_str() : "",
              (dir / "summary.json").c_str());
  std::printf("figures:%s", figure_files.empty() ? " none" : "");
  for (const auto& f : figure_files)
    std::printf(" %s", f.c_str());
  std::printf("\n");
  if (!failed.empty()) {
    std::fprintf(stderr, "friction_sweep: %zu point%s failed:\n", failed.size(),
                 failed.size() > 1 ? "s" : "");
    for (const auto& [r, x] : failed)
      std::fprintf(stderr, "  %sa = %g d, R = %g d: %s\n", x ? "explicit " : "", r->point.a,
                   r->point.R, r->stop_reason.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Static friction of the lateral force model over many (a, R) points"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/sweep_default.toml";
    std::string out = "results/friction_sweep";
    std::vector<double> R, a, targets;
    std::optional<int> jobs;
    bool figures = false;
    cli.add_option("scene", scene_path, "Sweep scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    auto* R_opt = cli.add_option("--R", R, "Sphere radii (d), comma-separated")
                      ->delimiter(',')
                      ->check(app::positive());
    auto* a_opt = cli.add_option("--a", a, "Contact radii (d), comma-separated")
                      ->delimiter(',')
                      ->check(app::positive());
    auto* x_opt = cli.add_option("--a-over-bcore0", targets,
                                 "Targets of a/b_core^0, comma-separated (instead of --a)")
                      ->delimiter(',')
                      ->check(app::positive());
    a_opt->excludes(x_opt);
    cli.add_option("--jobs", jobs, "Points run at once (default: hardware threads / fft.threads)")
        ->check(CLI::Range(1, 1024));
    auto* figures_opt = cli.add_flag(
        "--figures", figures, "Per point also the figures and NetCDF snapshots (as contact_slide)");
    bool largest_slip = false;
    cli.add_flag("--largest-slip", largest_slip,
                 "Per point keep the states before and after its largest slip (most slipped "
                 "sites) and the peak state, as NetCDF in points/<point>/largest_slip/ (for "
                 "track_loops): one pair of frames however many slips")
        ->excludes(figures_opt);
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    double checkpoint_every = 300.0;
    cli.add_option("--checkpoint-every", checkpoint_every,
                   "Seconds of run time between checkpoints of each running point (0: every step)")
        ->check(app::non_negative())
        ->capture_default_str();
    double progress_every = 60.0;
    cli.add_option("--progress-every", progress_every,
                   "Seconds of run time between progress lines of each running point, also from "
                   "inside a long relaxation (0: none)")
        ->check(app::non_negative())
        ->capture_default_str();
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    app::SweepScene s = app::read_sweep_scene(scene_path);
    if (R_opt->count() > 0) s.R = {R, "--R"};
    if (a_opt->count() > 0) {
      s.a = app::ValueList{a, "--a"};
      s.a_over_bcore0.reset();
    }
    if (x_opt->count() > 0) {
      s.a_over_bcore0 = app::ValueList{targets, "--a-over-bcore0"};
      s.a.reset();
    }
    if (jobs) s.jobs = *jobs;
    s.base.contact.validate();
    s.base.options.validate();
    const std::vector<app::SweepPoint> points = app::sweep_points(s);  // validates s
    const std::vector<app::SweepPoint> xpoints = app::explicit_sweep_points(s);
    // A signal from here on stops the sweep cleanly (points in flight checkpoint, no new ones).
    app::install_stop_handlers();
    const std::string settings = app::settings_fingerprint(s.base);
    const std::string settings_x = app::explicit_settings_fingerprint(s);

    const auto t0 = std::chrono::steady_clock::now();
    const fs::path dir = app::ensure_directory(out);
    // One sweep per output directory: its table and point folders (with their checkpoints)
    // would interleave with another's.
    const app::DirectoryLock dir_lock(dir);
    if (const std::size_t n = app::remove_stale_temporaries(dir)) {
      std::fprintf(stderr, "friction_sweep: removed %zu temporary file%s left by a killed run\n", n,
                   n > 1 ? "s" : "");
    }
    const fs::path csv = dir / "sweep.csv", csv_x = dir / "sweep_explicit.csv";
    app::ResumedRows resumed = app::resume_rows(csv, points, settings);
    app::ResumedRows resumed_x = app::resume_rows(csv_x, xpoints, settings_x);
    std::vector<std::optional<app::SweepRow>> rows = std::move(resumed.rows);
    std::vector<std::optional<app::SweepRow>> rows_x = std::move(resumed_x.rows);
    // A point to run: of the explicit model (xpoints, rows_x) or the LFM (points, rows).
    struct Job {
      bool x = false;
      std::size_t k = 0;
    };
    const auto point_of = [&](const Job& j) -> const app::SweepPoint& {
      return j.x ? xpoints[j.k] : points[j.k];
    };
    // Cheapest first (cost grows as the a^2 contact sites): results start arriving at once.
    std::vector<Job> order;
    for (std::size_t k = 0; k < points.size(); ++k) {
      if (!rows[k]) order.push_back({false, k});
    }
    for (std::size_t k = 0; k < xpoints.size(); ++k) {
      if (!rows_x[k]) order.push_back({true, k});
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](const Job& i, const Job& j) { return point_of(i).a < point_of(j).a; });
    const int n_jobs = std::min(s.effective_jobs(), static_cast<int>(order.size()));
    {
      // The largest contacts still to run, as many at once as run in parallel, must fit
      // together. (Explicit points are not estimated: a = 43 d takes 50 MiB, docs/benchmarks.md;
      // a/R < 0.1 does not bound a, so a large explicit sweep is the user's to size.)
      std::vector<double> bytes;
      double a_max = 0.0;
      for (const Job& job : order) {
        if (job.x) continue;
        const std::size_t k = job.k;
        interface::ContactScene c = s.base.contact;
        c.a = points[k].a;
        c.R = points[k].R;
        slide::SlideOptions o = s.base.options;
        if (!figures) o.path_frame_slips = 0;  // frames discarded: no path is held either
        bytes.push_back(slide::estimated_slide_bytes(c, o));
        a_max = std::max(a_max, c.a);
      }
      std::sort(bytes.rbegin(), bytes.rend());
      const auto at_once = std::min(bytes.size(), static_cast<std::size_t>(std::max(n_jobs, 1)));
      const double total = std::accumulate(bytes.begin(), bytes.begin() + at_once, 0.0);
      char what[160];
      std::snprintf(what, sizeof what,
                    "running the sweep's %zu largest contacts at once (a up to %g d; fewer with "
                    "--jobs)",
                    at_once, a_max);
      app::check_fits_in_memory(what, total,
                                "estimate: 260 bytes per point of each block's padded FFT grid "
                                "and the minimiser's vectors on the contact");
    }
    if (figures) {
      // Every point writes its snapshots (and a checkpoint) as contact_slide does.
      double disk = 0.0;
      for (const Job& job : order) {
        app::SlideScene ps = s.base;
        ps.contact.a = point_of(job).a;
        disk += app::estimated_snapshot_bytes(ps).run(std::max(10, ps.options.slips_to_stop),
                                                      ps.options.path_frame_slips);
      }
      app::check_fits_on_disk(
          "--figures: the snapshots of the sweep's " + std::to_string(order.size()) + " points",
          dir.string(), disk, "estimate for 10 slip events per point, uncompressed");
    }

    std::fprintf(stderr,
                 "friction_sweep: %zu points (model %s): R = %s d; %s = %s; alpha = %g, nu = %g; "
                 "%s protocol, %s, tolerance %g\n",
                 points.size() + xpoints.size(), s.model.c_str(), describe_list(s.R.values).c_str(),
                 s.a ? "a (d)" : "a/b_core^0",
                 describe_list(s.a ? s.a->values : s.a_over_bcore0->values).c_str(),
                 s.base.contact.alpha, s.base.contact.material.nu,
                 slide::to_string(s.base.options.protocol).c_str(),
                 minimize::to_string(s.base.options.minimizer.method).c_str(),
                 s.base.options.minimizer.force_tolerance);
    for (const auto& [table, res, n] : {std::tuple{&csv, &resumed, points.size()},
                                        std::tuple{&csv_x, &resumed_x, xpoints.size()}}) {
      if (!fs::exists(*table)) continue;
      std::fprintf(stderr, "friction_sweep: reused %zu of %zu points from %s", res->reused, n,
                   table->c_str());
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
    // The tables now hold exactly the reused rows; points are added as they finish.
    if (s.runs_lfm()) write_table(csv, rows);
    if (s.runs_explicit()) write_table(csv_x, rows_x);
    if (!order.empty()) {
      std::fprintf(stderr,
                   "friction_sweep: running %zu point%s, %d at once, %d FFT thread%s each\n",
                   order.size(), order.size() > 1 ? "s" : "", n_jobs, s.base.options.fft.threads,
                   s.base.options.fft.threads > 1 ? "s" : "");
    }

    std::mutex table_mutex;   // rows, sweep.csv and the progress lines
    std::mutex output_mutex;  // the NetCDF library is not thread-safe
    std::atomic<bool> stop{false};
    std::exception_ptr fatal;  // failure to write sweep.csv: ends the sweep
    std::size_t finished = 0;
    std::atomic<std::size_t> interrupted{0};
    // A finished point's row: into the table of its model, which is rewritten.
    const auto record = [&](const Job& job, app::SweepRow row) {
      const std::lock_guard lock(table_mutex);
      ++finished;
      std::fprintf(stderr,
                   "friction_sweep: [%zu/%zu] %sa = %.4g d, R = %g d, a/b_core^0 = %.4g: "
                   "mu/alpha = %.5f%s, %.1f s%s%s\n",
                   finished, order.size(), job.x ? "explicit " : "", row.point.a, row.point.R,
                   row.a_over_bcore0, row.mu_over_alpha,
                   row.mu_is_lower_bound ? " (lower bound)" : "", row.wall_s,
                   row.failed ? ": FAILED: " : "", row.failed ? row.stop_reason.c_str() : "");
      (job.x ? rows_x : rows)[job.k] = std::move(row);
      try {
        write_table(job.x ? csv_x : csv, job.x ? rows_x : rows);
      } catch (...) {
        if (!fatal) fatal = std::current_exception();
        stop = true;
      }
    };
    const auto run_point_inner = [&](const Job& job) {
      const app::SweepPoint& point = point_of(job);
      app::SlideScene ps = s.base;
      ps.contact.a = point.a;
      ps.contact.R = point.R;
      // The explicit model: its scene, and alpha of the potential at the point's central load.
      const app::ExplicitSlideScene es = app::explicit_point_scene(s, point);
      app::ExplicitAlpha alpha_x;
      if (job.x) {
        alpha_x = app::explicit_alpha(es);
        ps = app::explicit_as_slide_scene(es, alpha_x);  // contact.alpha: of the potential
      }
      const auto started = std::chrono::steady_clock::now();
      // A point in flight saves its slide in its folder every checkpoint_every seconds and when
      // the sweep is stopped (SIGINT, SIGTERM); the next run continues it from there, to the same
      // result bit for bit. A checkpoint of other settings is replaced (and kept aside).
      const fs::path point_dir = dir / "points" / app::point_folder(point, job.x);
      // Held while the point runs: a contact_slide started into this folder is refused, and so is
      // this point (failed, the sweep goes on) if a contact_slide already writes there.
      const app::DirectoryLock point_lock(app::ensure_directory(point_dir));
      const fs::path checkpoint_file = point_dir / "checkpoint.cbor";
      // With --figures the point writes snapshots as it goes: a checkpoint of a run without
      // them cannot continue one with them (the frames before it would be missing).
      const std::string point_settings =
          (job.x ? app::explicit_slide_fingerprint(es, alpha_x) : app::slide_fingerprint(ps)) +
          (figures ? " snapshots=1" : " snapshots=0");
      const std::string& row_settings = job.x ? settings_x : settings;
      std::optional<app::SlideCheckpoint> start;
      if (std::error_code ec; fs::exists(checkpoint_file, ec)) {
        try {
          app::SlideCheckpoint c = app::read_checkpoint(checkpoint_file);
          app::check_checkpoint_settings(c, point_settings, checkpoint_file);
          start = std::move(c);
        } catch (const std::exception& e) {  // damaged, foreign or unreadable
          // Kept, not overwritten: a checkpoint of another build or scene can hold hours of a
          // long point, and the run that was meant to continue it may simply be using the
          // wrong binary (docs/reliability.md). Moving it back undoes the new start.
          const fs::path kept = point_dir / "checkpoint.replaced.cbor";
          std::error_code rename_ec;
          fs::rename(checkpoint_file, kept, rename_ec);
          const std::lock_guard lock(table_mutex);
          std::fprintf(stderr, "friction_sweep: starting the point over (%s%s): %s\n",
                       rename_ec ? "the old checkpoint could not be kept: "
                                 : "the old checkpoint is kept as ",
                       rename_ec ? rename_ec.message().c_str() : kept.string().c_str(), e.what());
        }
      }
      app::SweepRow row;
      try {
        if (start) {
          const std::lock_guard lock(table_mutex);
          std::fprintf(stderr,
                       "friction_sweep: resuming %sa = %.4g d, R = %g d from its checkpoint at "
                       "Dx = %.4f d\n",
                       job.x ? "explicit " : "", point.a, point.R, start->state.current.Dx);
        }
        // Large points run for hours, mostly inside a few relaxations (a slip sweeps a contact
        // of a million sites in thousands of iterations): a line now and then says where each
        // is and that it runs.
        slide::SlideProgress progress;
        if (progress_every > 0.0) {
          progress = [&, lines = app::ProgressLines(progress_every)](
                         const slide::SlideProgressInfo& info) mutable {
            if (!lines.due(info)) return;
            const std::lock_guard lock(table_mutex);
            std::fprintf(stderr, "friction_sweep: %sa = %.4g d, R = %g d: %s\n",
                         job.x ? "explicit " : "", point.a, point.R,
                         app::describe_progress(info).c_str());
          };
        }
        // Frames go to the point's snapshots/ as they are made (with --figures), only those of
        // its largest slip to largest_slip/ (with --largest-slip), or nowhere: a point holds
        // at most one pair, however many slips it takes.
        slide::DiscardFrames no_frames;
        std::optional<app::SnapshotSink> frames;
        std::optional<app::LargestSlipSink> largest;
        const auto attributes = [&] {
          return app::snapshot_attributes(
              ps, job.x ? app::explicit_summary_extra(es, alpha_x) : nullptr);
        };
        if (figures) {
          frames.emplace(point_dir / "snapshots", attributes(), ps.snapshot_format, &output_mutex);
          if (const std::string warning =
                  frames->start(start ? std::optional(start->state.current.Dx) : std::nullopt);
              !warning.empty()) {
            const std::lock_guard lock(table_mutex);
            std::fprintf(stderr, "friction_sweep: a = %.4g d, R = %g d: %s\n", point.a, point.R,
                         warning.c_str());
          }
        }
        if (largest_slip) {
          // Not part of the checkpoint's settings: the sink restarts from the slips of the
          // checkpoint's trace, and says if their largest is not on disk.
          largest.emplace(point_dir / "largest_slip", attributes(), ps.snapshot_format,
                          &output_mutex);
          std::optional<int> so_far;
          if (start) {
            so_far = 0;
            for (const slide::TraceRow& r : start->state.partial.trace)
              if (r.slip) so_far = std::max(*so_far, r.slipped_sites);
          }
          if (const std::string warning = largest->start(so_far); !warning.empty()) {
            const std::lock_guard lock(table_mutex);
            std::fprintf(stderr, "friction_sweep: a = %.4g d, R = %g d: %s\n", point.a, point.R,
                         warning.c_str());
          }
        }
        slide::FrameSink* sink = &no_frames;
        if (frames) sink = &*frames;
        if (largest) sink = &*largest;
        const slide::SlideControl control{.progress = progress,
                                          .checkpoint =
                                              [&](const slide::SlideState& state) {
                                                app::ensure_directory(point_dir);
                                                if (frames) frames->flush();
                                                app::write_checkpoint(
                                                    checkpoint_file,
                                                    {.settings = point_settings, .state = state});
                                              },
                                          .checkpoint_every_s = checkpoint_every,
                                          .stop_requested = app::stop_requested,
                                          .start = start ? &start->state : nullptr,
                                          .frames = sink};
        const slide::SlideResult result = job.x ? app::slide_explicit_scene(es, alpha_x, control)
                                                : slide::slide(ps.contact, ps.options, control);
        if (result.interrupted) {
          if (frames) frames->flush();
          ++interrupted;  // no row: the next run continues from the checkpoint
          return;
        }
        if (frames) frames->finish();
        {
          std::unique_lock lock(output_mutex, std::defer_lock);
          if (figures) lock.lock();
          app::SlideOutputOptions oo{.figures = figures};
          if (job.x) oo.summary_extra = app::explicit_summary_extra(es, alpha_x);
          app::write_slide_outputs(point_dir, ps, result, oo);
        }
        std::error_code ec;
        fs::remove(checkpoint_file, ec);  // the row below is final
        row = app::sweep_row(ps, result, row_settings);
      } catch (const std::exception& e) {
        // Recorded as a failed point; the other points go on.
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        row = app::error_row(ps, e.what(), seconds, row_settings);
      }
      record(job, std::move(row));
    };
    // Anything a point throws before its slide (alpha of the potential, its files) fails that
    // point only, as a failure of its slide does: it must not end the sweep from a worker.
    const auto run_point = [&](const Job& job) {
      const auto started = std::chrono::steady_clock::now();
      try {
        run_point_inner(job);
      } catch (const std::exception& e) {
        app::SlideScene ps = s.base;
        ps.contact.a = point_of(job).a;
        ps.contact.R = point_of(job).R;
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        record(job, app::error_row(ps, e.what(), seconds, job.x ? settings_x : settings));
      }
    };
    app::run_points(
        order.size(), n_jobs, [&](std::size_t i) { run_point(order[i]); }, stop);
    if (fatal) std::rethrow_exception(fatal);
    const auto missing = [](const auto& r) { return !r.has_value(); };
    if (app::stop_requested() && (std::any_of(rows.begin(), rows.end(), missing) ||
                                  std::any_of(rows_x.begin(), rows_x.end(), missing))) {
      std::fprintf(stderr,
                   "friction_sweep: stopped; %zu point%s finished in this run (kept in %s), %zu "
                   "in flight saved to points/*/checkpoint.cbor\ncontinue with:\n  %s\n",
                   finished, finished == 1 ? "" : "s", csv.c_str(), interrupted.load(),
                   app::command_line(argc_, argv_).c_str());
      return app::kInterrupted;
    }

    std::vector<app::SweepRow> done, done_x;
    for (auto& row : rows)
      done.push_back(std::move(*row));
    for (auto& row : rows_x)
      done_x.push_back(std::move(*row));
    return finish_sweep(dir, s, done, done_x,
                        {.points = points.size(),
                         .explicit_points = xpoints.size(),
                         .computed = order.size(),
                         .reused = resumed.reused + resumed_x.reused},
                        t0);
  });
}
