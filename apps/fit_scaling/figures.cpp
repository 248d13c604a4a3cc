// fit_scaling's figures: collapse.png (mu/alpha against a/b_core^0, data and every prediction)
// and regime_map.png (the predicted mu/alpha over (a, R), the regime boundaries and the data in
// their simulated regimes). The numbers are nucleation/'s; this draws them.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "asperity/apps/common/plot.hpp"
#include "fit_io.hpp"

namespace asperity::app::fit_scaling {

namespace fs = std::filesystem;
namespace nuc = asperity::nucleation;

namespace {

// The marker of lower bounds (a slide that reached its cap still rising), in both figures: an
// up-triangle around the point.
app::Series lower_bound_series() {
  return {.title = "lower bound (slide capped while rising)",
          .style = "points pt 8 ps 3 lc 'black'"};
}

// mu/alpha vs a/b_core^0 (log-log): data by model and R, the Regime I line, the fitted Regime II
// law and the nucleation condition, the Regime III predictions per R.
fs::path collapse_figure(const fs::path& dir, const std::vector<DataPoint>& pts,
                         const LawSource& law, const Analysis& an, const Options& o) {
  std::vector<app::Series> s;
  std::map<std::pair<std::string, double>, app::Series> groups;
  const char* markers[] = {"7", "5", "9", "11", "13", "15"};
  for (const auto& p : pts) {
    auto& g = groups[{p.model, p.R}];
    g.x.push_back(p.x);
    g.y.push_back(p.mu);
  }
  // One colour per R (data and its predictions), one marker per model.
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
  std::map<double, std::string> colour_of;
  for (double R : an.Rs)
    colour_of[R] = colours[colour_of.size() % 6];
  std::map<std::string, std::string> marker_of;
  for (auto& [key, g] : groups) {
    if (!marker_of.count(key.first)) marker_of[key.first] = markers[marker_of.size() % 6];
    g.title = key.first + ", R = " + fmt("%g", key.second) + " d";
    g.style =
        "points pt " + marker_of[key.first] + " ps 1.6 lc rgb '" + colour_of[key.second] + "'";
    s.push_back(g);
  }
  app::Series bounds = lower_bound_series();
  for (const auto& p : pts) {
    if (!p.lower_bound) continue;
    bounds.x.push_back(p.x);
    bounds.y.push_back(p.mu);
  }
  if (!bounds.x.empty()) s.push_back(bounds);
  double xmin = pts.front().x, xmax = xmin;
  for (const auto& p : pts) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
  }
  xmin /= 2.0;
  xmax *= 3.0;
  // Far enough to show each R's predicted II -> III crossover.
  for (const auto& cr : an.crossovers) {
    if (cr.crossover.found) xmax = std::max(xmax, 2.0 * cr.crossover.a_over_bcore0);
  }
  app::Series one{.title = "Regime I: mu/alpha = 1", .style = "lines dt 3 lw 2 lc 'gray40'"};
  one.x = {xmin, xmax};
  one.y = {1.0, 1.0};
  s.push_back(one);
  app::Series law_in{.title = "Regime II fit: c0 = " + fmt("%.3f", an.fit.c0) + " +- " +
                              fmt("%.3f", an.fit.c0_error) + " (window " +
                              fmt("%g", an.fit.window_lo) + ".." + fmt("%g", an.fit.window_hi) +
                              ")",
                     .style = "lines lw 2.5 lc 'black'"};
  app::Series law_out{.title = "", .style = "lines dt 2 lw 1 lc 'black'"};
  app::Series cond{.title = "nucleation condition (no expansion), min(1, 3(1 - x*^2))",
                   .style = "lines lw 1.5 lc 'dark-orange'"};
  for (int i = 0; i <= 200; ++i) {
    const double x = xmin * std::pow(xmax / xmin, i / 200.0);
    const double y = nuc::regime_two_law(x, an.fit.c0);
    const bool inside = x >= an.fit.window_lo && x <= an.fit.window_hi;
    law_in.x.push_back(x);
    law_in.y.push_back(inside ? y : NAN);
    law_out.x.push_back(x);
    law_out.y.push_back(y <= 1.5 ? y : NAN);
    cond.x.push_back(x);
    cond.y.push_back(nuc::nucleation_condition(x, an.fit.c0).mu_over_alpha);
  }
  s.push_back(law_out);
  s.push_back(law_in);
  s.push_back(cond);
  for (double R : an.Rs) {
    app::Series r3{.title = "Regime III, integrated f_P tau_P, R = " + fmt("%g", R) + " d",
                   .style = "lines lw 2 dt 4 lc rgb '" + colour_of[R] + "'"};
    app::Series comb{.title = "prediction max(II, III), R = " + fmt("%g", R) + " d",
                     .style = "lines lw 1 dt 1 lc rgb '" + colour_of[R] + "'"};
    for (int i = 0; i <= 200; ++i) {
      const double x = xmin * std::pow(xmax / xmin, i / 200.0);
      const double a = nuc::contact_radius(x, R, an.alpha, an.nu);
      const nuc::Prediction pr = nuc::predict(x, a / x, an.model);
      r3.x.push_back(x);
      r3.y.push_back(pr.integrated > 1e-3 ? pr.integrated : NAN);
      comb.x.push_back(x);
      comb.y.push_back(pr.mu_over_alpha);
    }
    s.push_back(r3);
    s.push_back(comb);
  }
  const fs::path png = dir / "collapse.png";
  app::plot_png(png, s,
                {.title = "Friction collapse: alpha = " + fmt("%g", an.alpha) +
                          ", nu = " + fmt("%g", an.nu) + "; k1 = " + fmt("%.3g", law.law.k1) +
                          ", k2 = " + fmt("%.3g", law.law.k2) + ", f_P = " + fmt("%g", o.f_P),
                 .xlabel = "a / b_core^0",
                 .ylabel = "mu / alpha",
                 .logx = true,
                 .logy = true,
                 .width = 1100,
                 .height = 750,
                 .yrange = std::pair{1e-3, 2.0},
                 .extra_commands = {"set key bottom left font ',9'", "set grid"}});
  return png;
}

// Predicted log10(mu/alpha) over (a/d, R/d) with the regime boundaries, the data points marked by
// their simulated regime and the disagreements circled.
fs::path regime_map_figure(const fs::path& dir, const std::vector<DataPoint>& pts,
                           const LawSource& law, const Analysis& an, const Options& o) {
  const int n = 80;
  std::vector<double> ax, Ry, v;
  std::vector<double> map_a = o.map_a, map_R = o.map_R;
  if (map_a.empty()) {
    double lo = pts.front().a, hi = lo;
    for (const auto& p : pts) {
      lo = std::min(lo, p.a);
      hi = std::max(hi, p.a);
    }
    for (const auto& cr : an.crossovers) {
      if (cr.crossover.found) hi = std::max(hi, 1.5 * cr.crossover.a);
    }
    map_a = {lo / 2.0, 3.0 * hi};
  }
  if (map_R.empty()) map_R = {*an.Rs.begin() / 2.0, *an.Rs.rbegin() * 2.0};
  for (int i = 0; i < n; ++i) {
    ax.push_back(map_a[0] * std::pow(map_a[1] / map_a[0], i / (n - 1.0)));
    Ry.push_back(map_R[0] * std::pow(map_R[1] / map_R[0], i / (n - 1.0)));
  }
  for (double a : ax) {
    for (double R : Ry) {
      const double x = nuc::control_parameter(a, R, an.alpha, an.nu);
      v.push_back(std::log10(nuc::predict(x, a / x, an.model).mu_over_alpha));
    }
  }
  std::vector<app::Series> overlays;
  app::Series b12{.title = "I | II (a/b_core^0 = " + fmt("%.2f", an.x_one_two) + ")",
                  .style = "lines lw 2.5 lc 'black'"};
  app::Series b23{.title = "II | III (prediction)", .style = "lines lw 2.5 lc 'red'"};
  app::Series slope{.title = "a = 0.1 R", .style = "lines dt 2 lw 1.5 lc 'gray70'"};
  for (double R : Ry) {
    b12.x.push_back(nuc::contact_radius(an.x_one_two, R, an.alpha, an.nu));
    b12.y.push_back(R);
    const nuc::Crossover cr = nuc::regime_two_three_crossover(R, an.alpha, an.nu, an.model);
    b23.x.push_back(cr.found ? cr.a : NAN);
    b23.y.push_back(R);
    slope.x.push_back(0.1 * R);
    slope.y.push_back(R);
  }
  overlays.push_back(b12);
  overlays.push_back(b23);
  overlays.push_back(slope);
  if (law.law.b_min > 0.0) {
    // Right of this line the centre's core width is below the Peierls fit window.
    app::Series edge{
        .title = "b_core^0 = " + fmt("%g", law.law.b_min) + " d (right: Peierls law extrapolated)",
        .style = "lines dt 4 lw 2 lc 'white'"};
    for (double R : Ry) {
      edge.x.push_back(nuc::bcore0(law.law.b_min, R, an.alpha, an.nu));
      edge.y.push_back(R);
    }
    overlays.push_back(edge);
  }
  const char* style[] = {"points pt 7 ps 1.6 lc 'orange'", "points pt 5 ps 1.6 lc 'cyan'",
                         "points pt 9 ps 2 lc 'magenta'"};
  for (nuc::Regime r : {nuc::Regime::one, nuc::Regime::two, nuc::Regime::three}) {
    app::Series d{.title = "simulated " + nuc::to_string(r),
                  .style = style[static_cast<int>(r) - 1]};
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (an.comparisons[i].simulated != r) continue;
      d.x.push_back(pts[i].a);
      d.y.push_back(pts[i].R);
    }
    if (!d.x.empty()) overlays.push_back(d);
  }
  // Disagreements: circled where the prediction decides, boxed where it cannot (a point on
  // a boundary within 2 errors of the fits, regime_undetermined).
  app::Series wrong{.title = "predicted regime differs", .style = "points pt 6 ps 3 lc 'black'"};
  app::Series open{.title = "differs, on a boundary within 2 errors or a lower bound",
                   .style = "points pt 4 ps 3 lc 'black'"};
  app::Series bound = lower_bound_series();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const nuc::PointComparison& cmp = an.comparisons[i];
    if (cmp.lower_bound) {
      bound.x.push_back(pts[i].a);
      bound.y.push_back(pts[i].R);
    }
    if (cmp.agrees()) continue;
    app::Series& into = cmp.undetermined || cmp.simulated_undetermined ? open : wrong;
    into.x.push_back(pts[i].a);
    into.y.push_back(pts[i].R);
  }
  for (app::Series* ser : {&wrong, &open, &bound})
    if (!ser->x.empty()) overlays.push_back(*ser);
  const fs::path png = dir / "regime_map.png";
  app::heatmap_png(
      png, ax, Ry, v,
      {.title = "Predicted log10(mu/alpha): c0 = " + fmt("%.3f", an.fit.c0) +
                ", k1 = " + fmt("%.3g", law.law.k1) + ", k2 = " + fmt("%.3g", law.law.k2) +
                ", f_P = " + fmt("%g", o.f_P) + ", alpha = " + fmt("%g", an.alpha),
       .xlabel = "a / d",
       .ylabel = "R / d",
       .logx = true,
       .logy = true,
       .width = 1500,
       .height = 750,
       .extra_commands = {"set rmargin 50", "set key at screen 0.99,0.85 right top font ',9'"}},
      "log10(mu/alpha)", std::nullopt, overlays);
  return png;
}

}  // namespace

fs::path write_adhesive_figure(const fs::path& dir, const std::vector<DataPoint>& pts,
                               const AdhesiveAnalysis& an) {
  std::vector<app::Series> s;
  // One series per tau0 (the collapse: tau_fric/tau0 against a/b_core, whatever tau0).
  std::map<double, app::Series> by_tau0;
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
  std::vector<bool> in_window(pts.size(), false);
  for (std::size_t i : an.fit.used)
    in_window[i] = true;
  app::Series used{.title = "in the fit's window", .style = "points pt 6 ps 2.4 lc 'black'"};
  double xmin = pts.front().x, xmax = xmin, ymin = 1.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    auto& g = by_tau0[p.tau0];
    if (g.title.empty()) {
      g.title = "adhesive, tau0 = " + fmt("%g", p.tau0) +
                " G (b_core = " + fmt("%g", p.G / p.tau0) + " d)";
      g.style =
          "points pt 7 ps 1.6 lc rgb '" + std::string(colours[(by_tau0.size() - 1) % 6]) + "'";
    }
    g.x.push_back(p.x);
    g.y.push_back(p.mu);
    if (in_window[i]) {
      used.x.push_back(p.x);
      used.y.push_back(p.mu);
    }
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.mu);
  }
  for (auto& [tau0, g] : by_tau0)
    s.push_back(std::move(g));
  s.push_back(used);
  xmin /= 2.0;
  xmax *= 2.0;
  app::Series one{.title = "Regime I: tau_fric = tau0", .style = "lines dt 3 lw 2 lc 'gray40'"};
  one.x = {xmin, xmax};
  one.y = {1.0, 1.0};
  s.push_back(one);
  const nuc::RegimeTwoFit& fit = an.fit;
  app::Series law_in{.title = "Regime II: 2 (a/(2 c0 b_core))^(-1/2), c0 = " + fmt("%.3f", fit.c0) +
                              " +- " + fmt("%.3f", fit.c0_error) + " (window " +
                              fmt("%g", fit.window_lo) + ".." + fmt("%g", fit.window_hi) + ")",
                     .style = "lines lw 2.5 lc 'black'"};
  app::Series law_out{.title = "", .style = "lines dt 2 lw 1 lc 'black'"};
  app::Series cond{.title = "nucleation condition min(1, 2 sqrt(q (2 - q))), q = c0 b_core/a",
                   .style = "lines lw 1.5 lc 'dark-orange'"};
  for (int i = 0; i <= 200; ++i) {
    const double x = xmin * std::pow(xmax / xmin, i / 200.0);
    const double y = nuc::regime_two_law(an.law, x, fit.c0);
    const bool inside = x >= fit.window_lo && x <= fit.window_hi;
    law_in.x.push_back(x);
    law_in.y.push_back(inside ? y : NAN);
    law_out.x.push_back(x);
    law_out.y.push_back(y <= 1.5 ? y : NAN);
    cond.x.push_back(x);
    cond.y.push_back(nuc::nucleation_condition(an.law, x, fit.c0).mu_over_alpha);
  }
  s.push_back(law_out);
  s.push_back(law_in);
  s.push_back(cond);
  const fs::path png = dir / "adhesive_collapse.png";
  app::plot_png(
      png, s,
      {.title = "Adhesive contacts (tau_max = tau0, no load): free slope " +
                fmt("%.3f", fit.free_slope) + " +- " + fmt("%.3f", fit.free_slope_error) +
                " over the window (law -1/2, condition " + fmt("%.3f", an.condition_slope) + ")",
       .xlabel = "a / b_core   (b_core = d G / tau0)",
       .ylabel = "tau_fric / tau0   (tau_fric = Fx / A at the peak)",
       .logx = true,
       .logy = true,
       .width = 1000,
       .height = 700,
       .xrange = std::pair{xmin, xmax},
       .yrange = std::pair{ymin / 1.5, 1.5},
       .extra_commands = {"set key bottom left font ',10'", "set grid"}});
  return png;
}

fs::path write_mixed_figure(const fs::path& dir, const std::vector<DataPoint>& pts,
                            const MixedAnalysis& an) {
  // Each mixed point twice: mu/alpha at its Hertz control parameter, against the Hertz law, and
  // tau_fric/tau0 at its adhesive one, against the adhesive law.
  app::Series hz{.title = "mixed: mu/alpha at a/b_core^0 of alpha p alone",
                 .style = "points pt 7 ps 1.6 lc rgb '#1f77b4'"};
  app::Series ad{.title = "mixed: tau_fric/tau0 at a tau0/(d G)",
                 .style = "points pt 5 ps 1.6 lc rgb '#d62728'"};
  double xmin = std::numeric_limits<double>::infinity(), xmax = 0.0, ymin = 1.0, ymax = 1.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const MixedPoint& m = an.points[i];
    hz.x.push_back(m.x_hertz);
    hz.y.push_back(pts[i].mu_over_alpha);
    ad.x.push_back(m.x_adhesive);
    ad.y.push_back(pts[i].tau_fric_over_tau0);
    for (double x : {m.x_hertz, m.x_adhesive}) {
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
    }
    for (double y : {pts[i].mu_over_alpha, pts[i].tau_fric_over_tau0}) {
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  }
  xmin /= 2.0;
  xmax *= 2.0;
  std::vector<app::Series> s{hz, ad};
  app::Series one{.title = "Regime I of either limit", .style = "lines dt 3 lw 2 lc 'gray40'"};
  one.x = {xmin, xmax};
  one.y = {1.0, 1.0};
  s.push_back(one);
  const auto curve = [&](const LimitC0& l, bool hertz) {
    app::Series c{.title = std::string(hertz ? "Hertz" : "adhesive") +
                           " limit (nucleation condition), c0 = " + fmt("%.3f", l.c0),
                  .style = hertz ? "lines lw 2 lc rgb '#1f77b4'" : "lines lw 2 lc rgb '#d62728'"};
    for (int i = 0; i <= 200; ++i) {
      const double x = xmin * std::pow(xmax / xmin, i / 200.0);
      c.x.push_back(x);
      c.y.push_back(hertz ? nuc::nucleation_condition(x, l.c0).mu_over_alpha
                          : nuc::nucleation_condition(nuc::adhesive_law(), x, l.c0).mu_over_alpha);
    }
    return c;
  };
  if (std::isfinite(an.hertz.c0)) s.push_back(curve(an.hertz, true));
  if (std::isfinite(an.adhesive.c0)) s.push_back(curve(an.adhesive, false));
  const fs::path png = dir / "mixed_limits.png";
  app::plot_png(png, s,
                {.title = "Mixed envelope tau0 + alpha p against its two limits",
                 .xlabel = "a / b_core^0 of the limit",
                 .ylabel = "mu / alpha (Hertz limit), tau_fric / tau0 (adhesive limit)",
                 .logx = true,
                 .logy = true,
                 .width = 1000,
                 .height = 700,
                 .xrange = std::pair{xmin, xmax},
                 .yrange = std::pair{ymin / 1.5, ymax * 1.5},
                 .extra_commands = {"set key top right font ',10'", "set grid"}});
  return png;
}

std::vector<fs::path> write_figures(const fs::path& dir, const std::vector<DataPoint>& pts,
                                    const LawSource& law, const Analysis& an, const Options& o) {
  return {collapse_figure(dir, pts, law, an, o), regime_map_figure(dir, pts, law, an, o)};
}

}  // namespace asperity::app::fit_scaling
