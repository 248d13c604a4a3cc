// peierls_scan's summary.json and what it says on the terminal: the angles a cell offers, the
// plan of a run, and the report of a finished scan.
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "scan_io.hpp"

namespace asperity::app::peierls_scan {

namespace fs = std::filesystem;

namespace {

// The key of an orientation's fit in summary.json (track_loops and fit_scaling read "edge" and
// "screw").
std::string character_name(const peierls::Orientation& o) {
  if (o.mx == 0) return "screw";
  if (o.my == 0) return "edge";
  char buf[48];
  std::snprintf(buf, sizeof buf, "theta_%.1f", o.theta_deg);
  return buf;
}

nlohmann::json fits_json(const std::vector<peierls::OrientationFit>& fits) {
  nlohmann::json out = nlohmann::json::object();
  for (const peierls::OrientationFit& of : fits) {
    const peierls::Orientation& o = of.orientation;
    const peierls::ExponentialFit& f = of.fit;
    nlohmann::json j = {
        {"theta_deg", o.theta_deg}, {"m_x", o.mx},        {"m_y", o.my},
        {"valid", f.valid},         {"points", f.points}, {"k2_rigid_profile", of.k2_rigid}};
    if (f.valid) {
      j.update({{"k1", f.k1},
                {"k1_error", f.k1_error},
                {"k2", f.k2},
                {"k2_error", f.k2_error},
                {"k1_k2_correlation", f.correlation},
                {"window_b_core", {f.b_min, f.b_max}},
                {"rms_log_residual", f.rms_log_residual}});
    }
    out[character_name(o)] = j;
  }
  return out;
}

std::size_t unresolved_points(const std::vector<Row>& rows) {
  std::size_t unresolved = 0;
  for (const Row& r : rows) {
    if (!r.resolved_pos || !r.resolved_neg) ++unresolved;
  }
  return unresolved;
}

nlohmann::json scene_json(const ScanSummary& sum) {
  const Scene& s = sum.scene;
  return {{"source", s.source},
          {"b_core", sum.b_core},
          {"theta_requested", s.theta},
          {"L", s.options.cell.L},
          {"L_tolerance", s.cell_size.tolerance},
          {"max_L", s.cell_size.max_L},
          {"model", peierls::to_string(s.options.cell.model)},
          {"G", s.options.cell.material.G},
          {"nu", s.options.cell.material.nu},
          {"loading", "uniform applied shear stress (force tau d^2 per site along x)"},
          {"precision", s.options.precision},
          {"tolerance", s.options.tolerance},
          {"glide_threshold", s.options.glide_threshold},
          {"max_iterations", s.options.minimizer.max_iterations},
          {"alias_images", s.options.cell.alias_images},
          {"fit_window", {s.fit_b_min, s.fit_b_max}},
          {"settings", sum.settings}};
}

}  // namespace

void print_angles(const Scene& s) {
  std::printf("theta_deg m_x m_y line_spacing_d (L = %d, images >= %g d apart)\n", s.options.cell.L,
              s.min_line_spacing);
  for (const auto& o : peierls::available_orientations(s.options.cell.L, s.min_line_spacing))
    std::printf("%9.4f %3d %3d %8.2f\n", o.theta_deg, o.mx, o.my, o.line_spacing);
}

void print_plan(const Scene& s, std::size_t points, std::size_t reused, const fs::path& csv,
                const std::vector<peierls::Orientation>& orientations, int jobs, int ranks) {
  const std::string where = ranks > 1 ? " on each of " + std::to_string(ranks) + " ranks" : "";
  std::fprintf(stderr,
               "peierls_scan: %zu points (%zu reused from %s), L = %d (doubled up to %d until "
               "tau_P changes by less than %g), %s cell, nu = %g, precision %g, tolerance %g x "
               "tau; %d at once%s\n",
               points, reused, csv.c_str(), s.options.cell.L, s.cell_size.max_L,
               s.cell_size.tolerance, peierls::to_string(s.options.cell.model).c_str(),
               s.options.cell.material.nu, s.options.precision, s.options.tolerance, jobs,
               where.c_str());
  for (const auto& o : orientations)
    std::fprintf(stderr, "peierls_scan: theta = %.4f deg from (m_x, m_y) = (%d, %d)\n", o.theta_deg,
                 o.mx, o.my);
}

void write_summary(const fs::path& json, const ScanSummary& sum) {
  nlohmann::json figure_names = nlohmann::json::array();
  for (const auto& f : sum.figures)
    figure_names.push_back(f.filename().string());
  double points_wall = 0.0;
  for (const Row& r : sum.rows)
    points_wall += r.wall_s;
  app::write_json(json, {{"tool", "peierls_scan"},
                         {"scene", scene_json(sum)},
                         {"settings", app::settings_echo(sum.scene, scene_settings())},
                         {"points", sum.points},
                         {"computed", sum.computed},
                         {"reused", sum.reused},
                         {"unresolved_points", unresolved_points(sum.rows)},
                         {"fits", fits_json(sum.fits)},
                         {"table", "peierls.csv"},
                         {"figures", figure_names},
                         {"run",
                          {{"wall_s", sum.wall_s},
                           {"points_wall_s", points_wall},
                           {"jobs", sum.jobs},
                           {"ranks", sum.ranks},
                           {"provenance", app::provenance_json()}}}});
}

std::size_t print_report(const fs::path& dir, const fs::path& csv, const ScanSummary& sum) {
  std::printf("peierls_scan: %zu points (%zu computed, %zu unresolved) in %.1f s\n", sum.points,
              sum.computed, unresolved_points(sum.rows), sum.wall_s);
  // By name, as summary.json lists them.
  const nlohmann::json fits = fits_json(sum.fits);
  for (const auto& [name, j] : fits.items()) {
    if (j.value("valid", false)) {
      std::printf("  %-12s k1 = %.4g +- %.2g, k2 = %.4g +- %.2g (b_core in [%g, %g] d)\n",
                  name.c_str(), j["k1"].get<double>(), j["k1_error"].get<double>(),
                  j["k2"].get<double>(), j["k2_error"].get<double>(),
                  j["window_b_core"][0].get<double>(), j["window_b_core"][1].get<double>());
    }
  }
  std::printf("results: %s\n", fs::absolute(dir / "summary.json").c_str());
  std::printf("table:   %s\n", fs::absolute(csv).c_str());
  for (const auto& f : sum.figures)
    std::printf("figure:  %s\n", fs::absolute(f).c_str());
  for (const Row& r : sum.rows) {
    // Resolved, but its cell did not converge: at max_L, or resolved at one size only.
    if (r.L_converged || !peierls::peierls_ratio(r)) continue;
    std::fprintf(stderr,
                 "peierls_scan: warning: b_core = %g d, theta = %.1f deg: tau_P at L = %d is "
                 "not converged in the cell size (last change %.3g; cell.max_L %d)\n",
                 r.point.b_core, r.point.orientation.theta_deg, r.L, r.L_change,
                 sum.scene.cell_size.max_L);
  }
  std::size_t failed = 0;
  for (const Row& r : sum.rows) {
    if (r.failure.empty()) continue;
    if (failed++ == 0) std::fprintf(stderr, "peierls_scan: numerical failures:\n");
    std::fprintf(stderr, "  b_core = %g d, theta = %.1f deg (L = %d): %s\n", r.point.b_core,
                 r.point.orientation.theta_deg, r.L, r.failure.c_str());
  }
  return failed;
}

}  // namespace asperity::app::peierls_scan
