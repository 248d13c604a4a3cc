// alpha_path: the local friction coefficient alpha of the explicit model's interface potential
// (MODEL.md section 4). One atom pushed with a fixed normal force Fz onto a rigid (100) square
// lattice through the repulsive Lennard-Jones potential (cut at its minimum) is moved from a
// hollow site over the bridge to the next hollow site; alpha is the largest slope of its height
// profile (core/explicit/alpha_path.hpp). Scans Fz (eps/sigma) and sigma/d.
//
// Outputs in --out: paths.csv (x, height, slope, lateral force, enthalpy per sample, every
// point), alpha.csv (alpha, max Fx/Fz, barrier, heights per point), summary.json (the table, the
// load dependence of alpha per sigma/d, provenance), height.png and slope.png (profiles at
// sigma/d = 2^(-1/6) for every load and at Fz = 1 for every sigma/d), alpha_vs_load.png.
// Its settings are one table (Scan::settings()): docs/explicit.md lists them.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/cli_checks.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/core/explicit/alpha_path.hpp"

using namespace asperity;

namespace {

std::string label(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// What the tool scans: every sigma/d with every Fz, each path sampled as `path` says.
struct Scan {
  std::vector<double> sigma_over_d{0.8, explicit_model::AlphaPathOptions{}.sigma_over_d, 0.95, 1.0};
  std::vector<double> forces{0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0};  // eps/sigma
  explicit_model::AlphaPathOptions path;  // its samples (sigma/d and Fz come from the lists)

  // Every setting once: the flags, their checks, --list-settings, summary.json's "settings".
  static const settings::Table<Scan>& settings();
};

const settings::Table<Scan>& Scan::settings() {
  static const settings::Table<Scan> table = [] {
    const auto& point = explicit_model::AlphaPathOptions::settings();
    const auto row = [&](const char* key) -> const auto& {
      return *settings::find(point, key);
    };
    // sigma/d takes the allowed values of the single point's row.
    settings::Table<Scan> t = {
        settings::numbers<Scan>(
            "scan.sigma_over_d", [](auto& s) -> auto& { return s.sigma_over_d; },
            row("sigma_over_d").range, "d", "Lennard-Jones sigma of the points", "--sigma-over-d"),
        // Beyond 1000 eps/sigma the atom is pressed to ~0.8 sigma, deep inside the repulsive
        // wall (and 1e300 overflows the height search): the scan stops there.
        settings::numbers<Scan>(
            "scan.Fz", [](auto& s) -> auto& { return s.forces; },
            settings::Range::open_closed(0.0, 1000.0), "eps/sigma", "normal forces of the points",
            "--forces")};
    settings::Table<explicit_model::AlphaPathOptions> samples{row("samples")};
    settings::lift(
        t, samples, "path.", [](auto& s) -> auto& { return s.path; });
    return t;
  }();
  return table;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{
        "Local friction coefficient alpha of the repulsive LJ interface: one atom over a rigid "
        "square lattice at fixed normal force (MODEL.md 4)"};
    std::string out = "results/alpha_path";
    app::SettingFlags flags;
    const Scan defaults;
    flags.add(cli, Scan::settings(), {}, "summary key", &defaults);
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    app::add_list_settings(cli, Scan::settings(), Scan{}, "docs/explicit.md");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    Scan scan;
    flags.apply(Scan::settings(), scan);
    for (const auto& [list, flag] :
         {std::pair{&scan.sigma_over_d, "--sigma-over-d"}, std::pair{&scan.forces, "--forces"}}) {
      if (list->empty()) throw std::invalid_argument(std::string(flag) + ": give at least one");
    }
    try {
      scan.path.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--samples: path.") + e.what());
    }
    const double sigma_default = explicit_model::AlphaPathOptions{}.sigma_over_d;
    std::vector<double> sigmas = scan.sigma_over_d, forces = scan.forces;
    const int samples = scan.path.samples;
    std::sort(sigmas.begin(), sigmas.end());
    std::sort(forces.begin(), forces.end());
    const auto start = std::chrono::steady_clock::now();
    const std::filesystem::path dir = app::ensure_directory(out);

    app::CsvTable paths(
        {"sigma_over_d", "Fz", "x", "height", "slope", "Fx", "Fx_over_Fz", "enthalpy"});
    app::CsvTable table({"sigma_over_d", "Fz", "alpha", "x_at_alpha", "alpha_force", "barrier",
                         "height_hollow", "height_bridge", "slope_check"});
    nlohmann::json points = nlohmann::json::array(), dependence = nlohmann::json::array();
    // Profiles for the figures: every load at the default sigma/d, every sigma/d at Fz = 1
    // (or the load nearest to it).
    const double fz_ref = *std::min_element(forces.begin(), forces.end(), [](double a, double b) {
      return std::abs(std::log(a)) < std::abs(std::log(b));
    });
    const double sigma_ref =
        *std::min_element(sigmas.begin(), sigmas.end(), [&](double a, double b) {
          return std::abs(a - sigma_default) < std::abs(b - sigma_default);
        });
    std::vector<app::Series> h_load, s_load, h_sigma, s_sigma, alpha_curves;
    for (double s : sigmas) {
      app::Series curve{.title = label("sigma/d = %.4g", s), .style = "linespoints pt 7"};
      for (double fz : forces) {
        const auto p =
            explicit_model::alpha_path({.sigma_over_d = s, .normal_force = fz, .samples = samples});
        for (std::size_t k = 0; k < p.x.size(); ++k) {
          paths.add_row({s, fz, p.x[k], p.height[k], p.slope[k], p.lateral[k], p.lateral[k] / fz,
                         p.enthalpy[k]});
        }
        table.add_row({s, fz, p.alpha, p.x_at_alpha, p.alpha_force, p.barrier, p.height_hollow,
                       p.height_bridge, p.slope_check});
        points.push_back({{"sigma_over_d", s},
                          {"Fz", fz},
                          {"alpha", p.alpha},
                          {"x_at_alpha", p.x_at_alpha},
                          {"alpha_force", p.alpha_force},
                          {"barrier", p.barrier},
                          {"height_hollow", p.height_hollow},
                          {"height_bridge", p.height_bridge},
                          {"slope_check", p.slope_check}});
        curve.x.push_back(fz);
        curve.y.push_back(p.alpha);
        if (s == sigma_ref) {
          h_load.push_back({.x = p.x, .y = p.height, .title = label("Fz = %g eps/sigma", fz)});
          s_load.push_back({.x = p.x, .y = p.slope, .title = label("Fz = %g eps/sigma", fz)});
        }
        if (fz == fz_ref) {
          h_sigma.push_back({.x = p.x, .y = p.height, .title = label("sigma/d = %.4g", s)});
          s_sigma.push_back({.x = p.x, .y = p.slope, .title = label("sigma/d = %.4g", s)});
        }
      }
      const auto [lo, hi] = std::minmax_element(curve.y.begin(), curve.y.end());
      const double variation = (*hi - *lo) / *lo;
      dependence.push_back({{"sigma_over_d", s},
                            {"alpha_min", *lo},
                            {"alpha_max", *hi},
                            {"Fz_min", forces.front()},
                            {"Fz_max", forces.back()},
                            {"variation", variation}});
      std::printf(
          "sigma/d = %.4f: alpha from %.4f to %.4f over Fz = %g..%g eps/sigma "
          "(variation %.1f%%)\n",
          s, *lo, *hi, forces.front(), forces.back(), 100.0 * variation);
      alpha_curves.push_back(std::move(curve));
    }
    paths.write(dir / "paths.csv");
    table.write(dir / "alpha.csv");

    const std::string xl = "x / d (hollow site at 0 and 1, bridge at 0.5)";
    app::plot_png(dir / "height.png", h_load,
                  {.title = label("Height along the path, sigma/d = %.4g", sigma_ref),
                   .xlabel = xl,
                   .ylabel = "z / d"});
    app::plot_png(
        dir / "slope.png", s_load,
        {.title = label("Slope dz/dx along the path, sigma/d = %.4g (alpha = max)", sigma_ref),
         .xlabel = xl,
         .ylabel = "dz/dx"});
    app::plot_png(dir / "height_sigma.png", h_sigma,
                  {.title = label("Height along the path, Fz = %g eps/sigma", fz_ref),
                   .xlabel = xl,
                   .ylabel = "z / d"});
    app::plot_png(dir / "slope_sigma.png", s_sigma,
                  {.title = label("Slope dz/dx along the path, Fz = %g eps/sigma", fz_ref),
                   .xlabel = xl,
                   .ylabel = "dz/dx"});
    app::plot_png(dir / "alpha_vs_load.png", alpha_curves,
                  {.title = "alpha = max dz/dx versus normal force",
                   .xlabel = "Fz (eps/sigma)",
                   .ylabel = "alpha",
                   .logx = true});
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    app::write_json(dir / "summary.json",
                    {{"tool", "alpha_path"},
                     {"potential", "repulsive Lennard-Jones cut and shifted at 2^(1/6) sigma"},
                     {"path", "hollow (x = 0) -> bridge (x = d/2) -> hollow (x = d), y = d/2"},
                     {"samples", samples},
                     {"settings", app::settings_echo(scan, Scan::settings())},
                     {"points", points},
                     {"load_dependence", dependence},
                     {"run", {{"wall_s", wall}, {"provenance", app::provenance_json()}}}});
    std::printf("results: %s\nfigures: %s %s %s %s %s\n", (dir / "alpha.csv").c_str(),
                (dir / "height.png").c_str(), (dir / "slope.png").c_str(),
                (dir / "height_sigma.png").c_str(), (dir / "slope_sigma.png").c_str(),
                (dir / "alpha_vs_load.png").c_str());
    return 0;
  });
}
