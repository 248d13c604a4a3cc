// friction_sweep's report (report.hpp): once every point is in, the figures (mu/alpha against
// a/b_core^0, kinetic/static, the collapse of the two models), the Regime II slope fit and the
// model comparison (nucleation-free statistics in sweep.cpp), summary.json and the lines
// printed.
#include "report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/core/interface/lfm.hpp"

namespace asperity::app {

namespace fs = std::filesystem;

std::string describe_list(const std::vector<double>& v) {
  std::string out;
  char buf[32];
  for (double x : v) {
    std::snprintf(buf, sizeof buf, "%g", x);
    out += (out.empty() ? "" : ", ") + std::string(buf);
  }
  return out;
}

namespace {

// Window of the Regime II slope fit (MODEL.md 8), and where the slope guide starts: Hertz
// a/b_core^0 in [10, 60] (issue 3); adhesive [4, 60]: the adhesive condition reaches tau_fric =
// tau0 at a/b_core = 7.46 c0 = 1.4 and follows the law within 1.2% from 4 on (c0 = 0.19;
// data/reference/adhesive_tau0p2.csv lies within 3% of the law there, 8% at 2.4). The mixed
// envelope has no law of its own; its slope is fitted over the Hertz window.
struct FitWindow {
  double lo, hi;
};
FitWindow fit_window(const std::string& envelope) {
  if (envelope == "adhesive") return {4.0, 60.0};
  return {10.0, 60.0};
}
// Window of the model comparison (issue 4 acceptance 3).
constexpr double kCompareLo = 0.1, kCompareHi = 10.0;

// The collapse of the two models: mu/alpha of each against a/b_core^0, log-log, per R.
fs::path write_collapse(const fs::path& dir, const std::vector<SweepRow>& lfm,
                        const std::vector<SweepRow>& expl, const nlohmann::json& comparison) {
  std::vector<Series> series;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0, y_lo = 1.0;
  const auto add = [&](const std::vector<SweepRow>& rows, const char* model, const char* style) {
    std::map<double, Series> by_R;
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
  series.push_back(Series{.x = {lo, hi},
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
  plot_png(png, series,
           {.title = title,
            .xlabel = "a / b_core^0 (alpha: LFM scene value; explicit: of the potential)",
            .ylabel = "mu / alpha",
            .logx = true,
            .logy = true,
            .xrange = std::pair{lo, hi},
            .yrange = std::pair{y_lo / 1.5, 1.3}});
  return png;
}

// The sweep's settings for summary.json: every key of the scene but the per-point a and R.
nlohmann::json scene_json(const SweepScene& s, int jobs) {
  const auto& c = s.base.contact;
  const auto& o = s.base.options;
  const auto& m = o.minimizer;
  nlohmann::json j = {
      {"source", s.source},
      {"R", s.radii()},
      {"alpha", c.alpha},
      {"envelope", c.envelope},
      {"tau0", c.tau0},
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
      {"settings", settings_fingerprint(s.base)},
  };
  if (s.a) j["a"] = s.a->values;
  if (s.a_over_bcore0) j["a_over_bcore0"] = s.a_over_bcore0->values;
  nlohmann::json tips = nlohmann::json::array();
  for (const auto& t : sweep_tips(s))
    tips.push_back({{"angle", t.angle}, {"mismatch", t.mismatch}});
  j["tips"] = tips;
  j["model"] = s.model;
  if (s.runs_explicit()) {
    j["explicit"] = {{"G_eps_sigma3", s.potential.G_eps_sigma3},
                     {"sigma_over_d", s.potential.sigma_over_d},
                     {"alpha", "of the potential at each point's central load (alpha_path)"},
                     {"settings", explicit_settings_fingerprint(s)}};
  }
  return j;
}

// The key of a row's series: its tip, then R (the order of sweep.csv).
using SeriesKey = std::tuple<double, double, double>;
SeriesKey series_key(const SweepRow& r) {
  return {r.point.tip.angle, r.point.tip.mismatch, r.point.R};
}

// "R = 535 d" and, for a tip out of registry, "R = 535 d, tip 2 deg, m = 0".
std::string series_title(const SweepPoint& p) {
  char title[96];
  if (p.tip.aligned()) {
    std::snprintf(title, sizeof title, "R = %g d", p.R);
  } else {
    std::snprintf(title, sizeof title, "R = %g d, tip %g deg, m = %g", p.R, p.tip.angle,
                  p.tip.mismatch);
  }
  return title;
}

// Series per tip and R, in the order of sweep.csv; `pick` returns the y value or nothing to
// leave the row out. Adhesive rows have no sphere: one series, named by tau0.
template <class Pick>
std::vector<Series> series_per_R(const std::vector<SweepRow>& rows, Pick pick, double tau0 = 0.0) {
  std::map<SeriesKey, Series> by_R;
  for (const auto& r : rows) {
    const std::optional<double> y = pick(r);
    if (!y) continue;
    auto& s = by_R[series_key(r)];
    if (s.title.empty()) {
      if (r.envelope == "adhesive") {
        char title[48];
        std::snprintf(title, sizeof title, "adhesive, tau0 = %g G", tau0);
        s.title = title;
      } else {
        s.title = series_title(r.point);
      }
      s.style = "linespoints pt 7 ps 1.3";
    }
    s.x.push_back(r.a_over_bcore0);
    s.y.push_back(*y);
  }
  std::vector<Series> out;
  for (auto& [key, s] : by_R)
    out.push_back(std::move(s));
  return out;
}

// The rows of an aligned tip: the scaling laws of MODEL.md 8 (the Regime II fit and guide) are
// theirs.
std::vector<SweepRow> aligned_rows(const std::vector<SweepRow>& rows) {
  std::vector<SweepRow> out;
  for (const auto& r : rows) {
    if (r.point.tip.aligned()) out.push_back(r);
  }
  return out;
}

// The rigid tip's mu/alpha (interface::rigid_tip_friction, the Regime I limit out of registry)
// at every row of a tip out of registry, for the figure and summary.json.
struct RigidRow {
  SweepPoint point;
  double a_over_bcore0 = 0.0, mu_over_alpha = 0.0;
};
std::vector<RigidRow> rigid_rows(const SweepScene& s, const std::vector<SweepRow>& rows) {
  std::vector<RigidRow> out;
  for (const auto& r : rows) {
    if (r.point.tip.aligned()) continue;
    interface::ContactScene c = s.base.contact;
    c.a = r.point.a;
    c.R = r.point.R;
    c.tip = r.point.tip;
    out.push_back({r.point, c.a_over_bcore0(), interface::rigid_tip_friction(c).over_regime_one});
  }
  return out;
}

// mu/alpha against a for the tips out of registry (issue 27): the sweep's points per tip and R,
// and the rigid tip's (u = 0) as dashed lines of the same colour; linear, and with log y, where
// the zeros of the rigid tip's friction and the level friction falls to beyond them show.
std::vector<fs::path> write_tip_figures(const fs::path& dir, const SweepScene& s,
                                        const std::vector<SweepRow>& rows,
                                        const std::vector<RigidRow>& rigid) {
  const auto usable = [](const SweepRow& r) {
    return !r.failed && std::isfinite(r.mu_over_alpha) && r.mu_over_alpha > 0.0;
  };
  std::map<SeriesKey, Series> points, lines;
  std::map<double, int> radii;
  double a_max = 0.0;
  for (const auto& r : rows) {
    if (!usable(r)) continue;
    radii[r.point.R] = 1;
    a_max = std::max(a_max, r.point.a);
  }
  // Titles name R only if the sweep has several.
  const auto title_of = [&](const SweepPoint& p) {
    char t[96];
    if (p.tip.aligned()) {
      std::snprintf(t, sizeof t, "aligned tip");
    } else {
      std::snprintf(t, sizeof t, "%g deg, m = %g", p.tip.angle, p.tip.mismatch);
    }
    std::string title = t;
    if (radii.size() > 1) {
      std::snprintf(t, sizeof t, ", R = %g d", p.R);
      title += t;
    }
    return title;
  };
  for (const auto& r : rows) {
    if (!usable(r)) continue;
    auto& p = points[series_key(r)];
    if (p.title.empty()) p.title = title_of(r.point);
    p.x.push_back(r.point.a);
    p.y.push_back(r.mu_over_alpha);
  }
  if (points.empty()) return {};
  // The rigid tip's curve between the sweep's smallest and largest a of each series, finer
  // than the points (its zeros are narrow): 200 contact radii (a few seconds at a = 500 d).
  for (const auto& r : rigid) {
    auto& l = lines[{r.point.tip.angle, r.point.tip.mismatch, r.point.R}];
    l.x.push_back(r.point.a);
  }
  for (auto& [key, l] : lines) {
    const double lo = *std::min_element(l.x.begin(), l.x.end());
    const double hi = *std::max_element(l.x.begin(), l.x.end());
    l.x.clear();
    interface::ContactScene c = s.base.contact;
    c.tip = {.angle = std::get<0>(key), .mismatch = std::get<1>(key)};
    c.R = std::get<2>(key);
    constexpr int kSamples = 200;
    for (int k = 0; k <= kSamples; ++k) {
      c.a = lo + (hi - lo) * k / kSamples;
      l.x.push_back(c.a);
      l.y.push_back(interface::rigid_tip_friction(c).over_regime_one);
    }
  }
  std::vector<Series> series;
  int colour = 0;
  double y_lo = 1.0;
  for (auto& [key, p] : points) {
    ++colour;
    p.style = "linespoints pt 7 ps 1.3 lw 2 lc " + std::to_string(colour);
    for (double y : p.y)
      y_lo = std::min(y_lo, y);
    if (const auto it = lines.find(key); it != lines.end()) {
      it->second.style = "lines dt 2 lw 1.5 lc " + std::to_string(colour);
      for (double y : it->second.y)
        if (y > 0.0) y_lo = std::min(y_lo, y);
      series.push_back(std::move(it->second));
    }
    series.push_back(std::move(p));
  }
  // The dashes' meaning in the key (a point outside the axes).
  series.push_back({.x = {-1.0},
                    .y = {-1.0},
                    .title = "dashed: rigid substrate (u = 0)",
                    .style = "lines dt 2 lw 1.5 lc 'black'"});
  char title[200];
  std::snprintf(title, sizeof title, "Static friction of tips out of registry: alpha = %g, nu = %g",
                s.base.contact.alpha, s.base.contact.material.nu);
  std::string one_R;
  if (radii.size() == 1) {
    char t[48];
    std::snprintf(t, sizeof t, ", R = %g d", radii.begin()->first);
    one_R = t;
  }
  std::vector<fs::path> written;
  const fs::path png = dir / "mu_vs_a_by_tip.png", log_png = dir / "mu_vs_a_by_tip_log.png";
  plot_png(png, series,
           {.title = title + one_R,
            .xlabel = "a / d",
            .ylabel = "mu / alpha",
            .width = 900,
            .height = 650,
            .xrange = std::pair{0.0, 1.05 * a_max},
            .yrange = std::pair{0.0, 1.1},
            .extra_commands = {"set key inside right top box opaque"}});
  written.push_back(png);
  plot_png(log_png, series,
           {.title = title + one_R,
            .xlabel = "a / d",
            .ylabel = "mu / alpha",
            .logy = true,
            .width = 900,
            .height = 650,
            .xrange = std::pair{0.0, 1.05 * a_max},
            .yrange = std::pair{0.5 * y_lo, 1.5},
            .extra_commands = {"set key inside left bottom box opaque"}});
  written.push_back(log_png);
  return written;
}

// mu/alpha against a/b_core^0, log-log, with the Regime I limit and a Regime II guide. Returns
// the files written.
std::vector<fs::path> write_figures(const fs::path& dir, const SweepScene& s,
                                    const std::vector<SweepRow>& rows) {
  std::vector<fs::path> written;
  const auto& c = s.base.contact;
  const std::string y_name = relative_friction_name(c.envelope);
  const double law_slope = regime_two_slope(c.envelope);
  const double guide_from = fit_window(c.envelope).lo;
  char title[200], envelope[80];
  if (!c.uses_tau0()) {
    std::snprintf(envelope, sizeof envelope, "alpha = %g", c.alpha);
  } else if (!c.carries_load()) {
    std::snprintf(envelope, sizeof envelope, "adhesive, tau0 = %g G", c.tau0);
  } else {
    std::snprintf(envelope, sizeof envelope, "mixed, alpha = %g, tau0 = %g G", c.alpha, c.tau0);
  }
  std::snprintf(title, sizeof title, "Static friction: %s, nu = %g; %s, %s, tol %g", envelope,
                c.material.nu, slide::to_string(s.base.options.protocol).c_str(),
                minimize::to_string(s.base.options.minimizer.method).c_str(),
                s.base.options.minimizer.force_tolerance);

  // log scales: non-positive values cannot be drawn; failed points are not measurements.
  auto mu = series_per_R(
      rows,
      [](const SweepRow& r) -> std::optional<double> {
        if (r.failed || !(r.relative_friction > 0.0)) return std::nullopt;
        return r.relative_friction;
      },
      c.tau0);
  if (mu.empty()) {
    std::fprintf(stderr, "friction_sweep: no finished point: mu_vs_a_over_bcore0.png skipped\n");
  } else {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo = inf, hi = 0.0, log_x = 0.0, log_y = 0.0, guide_lo = inf, guide_hi = 0.0;
    int n_guide = 0;
    Series bounds{.title = "lower bound (no peak within the distance)",
                  .style = "points pt 8 ps 2.5 lc 'black'"};
    for (const auto& r : rows) {
      if (r.failed || !(r.relative_friction > 0.0)) continue;
      lo = std::min(lo, r.a_over_bcore0);
      hi = std::max(hi, r.a_over_bcore0);
      if (r.mu_is_lower_bound) {
        bounds.x.push_back(r.a_over_bcore0);
        bounds.y.push_back(r.relative_friction);
      }
      if (r.a_over_bcore0 >= guide_from && !r.mu_is_lower_bound && r.point.tip.aligned()) {
        log_x += std::log(r.a_over_bcore0);
        log_y += std::log(r.relative_friction);
        guide_lo = std::min(guide_lo, r.a_over_bcore0);
        guide_hi = std::max(guide_hi, r.a_over_bcore0);
        ++n_guide;
      }
    }
    lo /= 1.5;
    hi *= 1.5;
    Series one{.x = {lo, hi},
               .y = {1.0, 1.0},
               .title = y_name + " = 1 (Regime I)",
               .style = "lines dt 2 lw 2 lc 'black'"};
    mu.push_back(one);
    if (!bounds.x.empty()) mu.push_back(bounds);
    if (n_guide > 0 && std::isfinite(law_slope)) {
      // Through the centre of the points on log axes: exp(mean log x), exp(mean log y).
      const double x0 = std::exp(log_x / n_guide), y0 = std::exp(log_y / n_guide);
      Series guide{.title = c.carries_load() ? "slope -2/3 (Regime II)" : "slope -1/2 (Regime II)",
                   .style = "lines dt 3 lw 2 lc 'gray40'"};
      for (double x : {guide_lo / 1.5, guide_hi * 1.5}) {
        guide.x.push_back(x);
        guide.y.push_back(y0 * std::pow(x / x0, law_slope));
      }
      mu.push_back(guide);
    }
    // The file keeps its name for every envelope (tools and docs point to it).
    const fs::path png = dir / "mu_vs_a_over_bcore0.png";
    plot_png(png, mu,
             {.title = title,
              .xlabel = "a / b_core^0",
              .ylabel = y_name,
              .logx = true,
              .logy = true,
              .xrange = std::pair{lo, hi}});
    written.push_back(png);
  }

  // Kinetic friction as the slider defines it: the mean of Fx/Fz after the first slip, or over
  // the last period when nothing slipped (about 0: smooth sliding costs no work).
  auto ratio = series_per_R(
      rows,
      [](const SweepRow& r) -> std::optional<double> {
        if (r.failed || !std::isfinite(r.kinetic_over_static)) return std::nullopt;
        return r.kinetic_over_static;
      },
      c.tau0);
  if (ratio.empty()) {
    std::fprintf(stderr, "friction_sweep: no finished point: kinetic_over_static.png skipped\n");
  } else {
    const fs::path png = dir / "kinetic_over_static.png";
    std::snprintf(title, sizeof title,
                  "Kinetic (mean %s after the first slip, else over the last period) over static "
                  "friction: %s",
                  c.carries_load() ? "Fx/Fz" : "Fx/A", envelope);
    plot_png(
        png, ratio,
        {.title = title, .xlabel = "a / b_core^0", .ylabel = "kinetic / static", .logx = true});
    written.push_back(png);
  }
  return written;
}

}  // namespace

// The end of a sweep whose points are all in: figures, the Regime II slope, the comparison of
// the models, summary.json and the lines printed. Returns the exit status (1 if a point failed).
int finish_sweep(const fs::path& dir, const SweepScene& s, const std::vector<SweepRow>& done,
                 const std::vector<SweepRow>& done_x, const SweepCounts& n,
                 std::chrono::steady_clock::time_point t0) {
  const fs::path csv = dir / "sweep.csv", csv_x = dir / "sweep_explicit.csv";
  auto figure_files = done.empty() ? std::vector<fs::path>{} : write_figures(dir, s, done);
  // Tips out of registry: mu/alpha against a with the rigid tip's limit (issue 27).
  const std::vector<RigidRow> rigid = rigid_rows(s, done);
  if (!rigid.empty()) {
    for (const fs::path& png : write_tip_figures(dir, s, done, rigid))
      figure_files.push_back(png);
  }
  nlohmann::json rigid_json = nlohmann::json::array();
  for (const auto& r : rigid) {
    rigid_json.push_back({{"a", r.point.a},
                          {"R", r.point.R},
                          {"tip_angle", r.point.tip.angle},
                          {"tip_mismatch", r.point.tip.mismatch},
                          {"a_over_bcore0", r.a_over_bcore0},
                          {"rigid_over_regime_one", r.mu_over_alpha}});
  }
  // The Regime II scaling (MODEL.md 8) is the aligned tip's.
  const FitWindow window = fit_window(s.base.contact.envelope);
  const nlohmann::json fit =
      fit_slope(aligned_rows(done), window.lo, window.hi, s.base.contact.envelope);
  nlohmann::json comparison;
  if (s.runs_explicit()) {
    comparison = compare_models(done, done_x, kCompareLo, kCompareHi);
    if (const fs::path png = write_collapse(dir, done, done_x, comparison); !png.empty()) {
      figure_files.insert(figure_files.begin(), png);
    }
  }
  std::vector<std::pair<const SweepRow*, bool>> failed;  // row, explicit
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
                               {"tip_angle", r.point.tip.angle},
                               {"tip_mismatch", r.point.tip.mismatch},
                               {"wall_s", r.wall_s}});
        if (n.ranks > 1) point_times.back()["rank"] = r.rank;
      }
    }
  }
  nlohmann::json failed_json = nlohmann::json::array();
  for (const auto& [r, x] : failed)
    failed_json.push_back({{"model", x ? "explicit" : "lfm"},
                           {"a", r->point.a},
                           {"R", r->point.R},
                           {"tip_angle", r->point.tip.angle},
                           {"tip_mismatch", r->point.tip.mismatch},
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
                            {"scene", scene_json(s, n.jobs)},
                            {"settings", s.settings_echo()},
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
                             {{"provenance", provenance_json()},
                              {"wall_s", wall},
                              {"ranks", n.ranks},
                              {"control", settings_echo(n.control, RunControl::settings())},
                              {"points_wall_s", points_wall},
                              {"point_wall_s", point_times}}}};
  if (s.runs_explicit()) summary["explicit_vs_lfm"] = comparison;
  if (!rigid.empty()) {
    summary["rigid_tip"] = {
        {"quantity",
         "max Fx / F_I of the tip on a rigid substrate (u = 0), F_I = sum_i tau_max(r_i) d^2 "
         "(mu/alpha for the Hertz envelope): the Regime I limit out of registry "
         "(interface::rigid_tip_friction)"},
        {"points", rigid_json}};
  }
  write_json(dir / "summary.json", summary);

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
  const std::string law = s.base.contact.envelope == "mixed"
                              ? std::string("between the limits' -2/3 and -1/2")
                              : std::string(s.base.contact.carries_load() ? "-2/3" : "-1/2");
  if (fit["slope"].is_null()) {
    std::printf("fit over a/b_core^0 in [%g, %g]: none (%zu points; %s)\n", window.lo, window.hi,
                fit["points"].get<std::size_t>(), fit["note"].get<std::string>().c_str());
  } else {
    char error[48] = "";
    if (!fit["slope_stderr"].is_null()) {
      std::snprintf(error, sizeof error, " +- %.4f", fit["slope_stderr"].get<double>());
    }
    std::printf("fit of %s over a/b_core^0 in [%g, %g]: slope %.4f%s (%zu points; Regime II: %s)\n",
                relative_friction_name(s.base.contact.envelope).c_str(), window.lo, window.hi,
                fit["slope"].get<double>(), error, fit["points"].get<std::size_t>(), law.c_str());
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

}  // namespace asperity::app
