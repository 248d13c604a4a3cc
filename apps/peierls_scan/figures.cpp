// peierls_scan's figures: tau_P against b_core (log scale, one curve per angle, unresolved points
// at their floor, the fits and the rigid-profile estimate), against the line angle (one curve per
// b_core), and the relaxed core width against the continuum one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "asperity/apps/common/plot.hpp"
#include "scan_io.hpp"

namespace asperity::app::peierls_scan {

namespace fs = std::filesystem;

namespace {

std::string angle_title(double theta) {
  char buf[48];
  if (theta < 1e-9) return "screw (0 deg)";
  if (std::abs(theta - 90.0) < 1e-9) return "edge (90 deg)";
  std::snprintf(buf, sizeof buf, "%.1f deg", theta);
  return buf;
}

using ByKey = std::map<double, std::vector<const Row*>>;

// tau_P against b_core (log scale): one curve per angle, unresolved points at their floor, the
// edge and screw fits over their windows, and the rigid-profile estimate for the edge line.
std::optional<fs::path> b_core_figure(const fs::path& dir, const Scene& s, const ByKey& by_angle,
                                      const std::map<double, peierls::ExponentialFit>& fits,
                                      const std::string& title) {
  std::vector<app::Series> vs_b;
  app::Series unresolved{.title = "unresolved: below floor",
                         .style = "points pt 9 ps 1.5 lc 'black'"};
  for (const auto& [theta, list] : by_angle) {
    app::Series line{.title = angle_title(theta), .style = "linespoints pt 7 ps 1.2"};
    for (const Row* r : list) {
      if (const auto tau = peierls::peierls_ratio(*r)) {
        line.x.push_back(r->point.b_core);
        line.y.push_back(*tau);
      } else if (r->failure.empty()) {
        unresolved.x.push_back(r->point.b_core);
        unresolved.y.push_back(r->floor);
      }
    }
    if (!line.x.empty()) vs_b.push_back(line);
    const auto fit = fits.find(theta);
    if (fit != fits.end() && fit->second.valid && (theta < 1e-9 || theta > 90 - 1e-9)) {
      char t[96];
      std::snprintf(t, sizeof t, "fit %s: k1 = %.3g, k2 = %.3g", angle_title(theta).c_str(),
                    fit->second.k1, fit->second.k2);
      app::Series f{.title = t, .style = "lines dt 2 lw 1.5"};
      for (double b : {fit->second.b_min, fit->second.b_max}) {
        f.x.push_back(b);
        f.y.push_back(fit->second.k1 * std::exp(-fit->second.k2 * b));
      }
      vs_b.push_back(f);
    }
  }
  if (!unresolved.x.empty()) vs_b.push_back(unresolved);
  // Rigid-profile Peierls-Nabarro estimate for the edge line, for comparison (cell.hpp).
  if (!s.b_core.empty()) {
    app::Series rigid{.title = "edge, rigid-profile PN estimate",
                      .style = "lines dt 3 lw 2 lc 'gray40'"};
    const double lo = *std::min_element(s.b_core.begin(), s.b_core.end());
    const double hi = *std::max_element(s.b_core.begin(), s.b_core.end());
    for (int i = 0; i <= 40; ++i) {
      const double b = lo + (hi - lo) * i / 40.0;
      rigid.x.push_back(b);
      rigid.y.push_back(peierls::rigid_peierls_estimate(b, 1, 0, s.options.cell.material.nu));
    }
    vs_b.push_back(rigid);
  }
  if (vs_b.empty()) return std::nullopt;
  const fs::path png = dir / "tau_P_vs_b_core.png";
  app::plot_png(png, vs_b,
                {.title = title,
                 .xlabel = "b_core / d",
                 .ylabel = "tau_P / tau_max",
                 .logy = true,
                 .extra_commands = {"set format y '%.0e'", "set key bottom left"}});
  return png;
}

// tau_P against the line angle, one curve per b_core.
std::optional<fs::path> theta_figure(const fs::path& dir, const ByKey& by_b,
                                     const std::string& title) {
  std::vector<app::Series> vs_theta;
  for (const auto& [b, list] : by_b) {
    char t[48];
    std::snprintf(t, sizeof t, "b_core = %g d", b);
    app::Series line{.title = t, .style = "linespoints pt 7 ps 1.2"};
    std::vector<const Row*> sorted = list;
    std::sort(sorted.begin(), sorted.end(), [](const Row* x, const Row* y) {
      return x->point.orientation.theta_deg < y->point.orientation.theta_deg;
    });
    for (const Row* r : sorted) {
      if (const auto tau = peierls::peierls_ratio(*r)) {
        line.x.push_back(r->point.orientation.theta_deg);
        line.y.push_back(*tau);
      }
    }
    if (!line.x.empty()) vs_theta.push_back(line);
  }
  if (vs_theta.empty()) return std::nullopt;
  const fs::path png = dir / "tau_P_vs_theta.png";
  app::plot_png(png, vs_theta,
                {.title = title,
                 .xlabel = "line angle theta (deg; 0 screw, 90 edge)",
                 .ylabel = "tau_P / tau_max",
                 .logy = true,
                 .xrange = std::pair{-5.0, 95.0},
                 .extra_commands = {"set format y '%.0e'", "set key bottom left"}});
  return png;
}

// The relaxed core width against the continuum Peierls-Nabarro one, per angle.
std::optional<fs::path> width_figure(const fs::path& dir, const ByKey& by_angle) {
  std::vector<app::Series> width;
  int colour = 0;
  for (const auto& [theta, list] : by_angle) {
    // One colour per angle for its points and its continuum line.
    const std::string lc = " lc " + std::to_string(++colour);
    app::Series measured{.title = angle_title(theta) + ", relaxed",
                         .style = "points pt 7 ps 1.3" + lc};
    app::Series continuum{.title = angle_title(theta) + ", continuum PN",
                          .style = "lines dt 2" + lc};
    for (const Row* r : list) {
      measured.x.push_back(r->point.b_core);
      measured.y.push_back(r->core_width);
      continuum.x.push_back(r->point.b_core);
      continuum.y.push_back(r->core_width_continuum);
    }
    width.push_back(measured);
    width.push_back(continuum);
  }
  if (width.empty()) return std::nullopt;
  const fs::path png = dir / "core_width.png";
  app::plot_png(png, width,
                {.title = "Relaxed core width (registry offset d/4 to 3d/4) vs continuum "
                          "Peierls-Nabarro",
                 .xlabel = "b_core / d",
                 .ylabel = "core width / d"});
  return png;
}

}  // namespace

std::vector<fs::path> write_figures(const fs::path& dir, const Scene& s,
                                    const std::vector<Row>& rows,
                                    const std::vector<peierls::OrientationFit>& orientation_fits) {
  // The fits by line angle, as the figures draw them.
  std::map<double, peierls::ExponentialFit> fits;
  for (const auto& f : orientation_fits)
    fits[f.orientation.theta_deg] = f.fit;
  ByKey by_angle, by_b;
  for (const Row& r : rows) {
    by_angle[r.point.orientation.theta_deg].push_back(&r);
    by_b[r.point.b_core].push_back(&r);
  }
  char title[200];
  std::snprintf(title, sizeof title, "Peierls stress, L >= %d, nu = %g, %s cell, precision %g",
                s.options.cell.L, s.options.cell.material.nu,
                peierls::to_string(s.options.cell.model).c_str(), s.options.precision);
  std::vector<fs::path> written;
  for (const std::optional<fs::path>& png :
       {b_core_figure(dir, s, by_angle, fits, title), theta_figure(dir, by_b, title),
        width_figure(dir, by_angle)}) {
    if (png) written.push_back(*png);
  }
  return written;
}

}  // namespace asperity::app::peierls_scan
