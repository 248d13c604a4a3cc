// gf_validate: runs the analytic checks of the elastic half-space Green's functions
// (MODEL.md section 2) on a scene and writes a summary, tables and figures.
//
//   gf_validate [scene.toml] [--out DIR] [--threads N] [--hertz-a A ...] [--list-settings]
//
// With no scene it runs the default scene data/scenes/gf_validation.toml of the source tree.
// Its settings are one table (Scene::settings()): docs/gf_validation.md lists them.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "asperity/core/validation/gf_checks.hpp"

namespace fs = std::filesystem;
using namespace asperity;

namespace {

// The scene; defaults equal data/scenes/gf_validation.toml.
struct Scene {
  elastic::Material material;
  double hertz_R = 1000.0;  // sphere radius (d)
  double hertz_a = 40.0;    // Hertz contact radius (d)
  contact::NormalContactOptions hertz_solver;
  double disk_a = 40.0;  // bonded disk radius (d)
  contact::BondedOptions disk_solver{.tolerance = 1e-11};
  int far_field_distance = 60;  // (d)
  fft::FFTOptions fft{.threads = 2};

  // Every setting once: the scene file's keys, the flags, their checks, --list-settings and
  // summary.json's "settings" echo.
  static const settings::Table<Scene>& settings();
};

const settings::Table<Scene>& Scene::settings() {
  using R = settings::Range;
  static const settings::Table<Scene> table = [] {
    settings::Table<Scene> t;
    settings::lift(
        t, elastic::Material::settings(), "material.", [](auto& s) -> auto& { return s.material; });
    t.push_back(settings::number<Scene>(
        "hertz.R", [](auto& s) -> auto& { return s.hertz_R; }, R::positive(), "d",
        "radius of the rigid sphere of the Hertz check", "--hertz-R"));
    // Below 2 d the contact holds a handful of sites; above 2000 d the grid outgrows a laptop.
    t.push_back(settings::number<Scene>(
        "hertz.a", [](auto& s) -> auto& { return s.hertz_a; }, R::closed(2.0, 2000.0), "d",
        "Hertz contact radius; sets the load Fz = 4 E* a^3 / (3 R) (below 0.1 hertz.R)",
        "--hertz-a"));
    settings::lift(
        t, contact::NormalContactOptions::settings(), "hertz.",
        [](auto& s) -> auto& { return s.hertz_solver; });
    t.push_back(settings::number<Scene>(
        "bonded_disk.a", [](auto& s) -> auto& { return s.disk_a; }, R::closed(2.0, 2000.0), "d",
        "radius of the bonded rigid disk", "--disk-a"));
    settings::lift(
        t, contact::BondedOptions::settings(), "bonded_disk.",
        [](auto& s) -> auto& { return s.disk_solver; });
    t.push_back(settings::integer<Scene>(
        "far_field.max_distance", [](auto& s) -> auto& { return s.far_field_distance; },
        R::closed(10, 2000), "d",
        "the response of one loaded patch is sampled out to this distance",
        "--far-field-distance"));
    settings::lift(
        t, fft::FFTOptions::settings(), "fft.", [](auto& s) -> auto& { return s.fft; });
    // The checks compare converged solutions with analytic ones; the solvers' own tables allow
    // any relative tolerance below 1.
    for (const char* key : {"hertz.tolerance", "bonded_disk.tolerance"})
      settings::narrow(t, key, R::open(0.0, 1e-2),
                       "below 0.01: the checks compare converged solutions");
    return t;
  }();
  return table;
}

// The check the table cannot make, between two rows: a Hertz contact is small-slope (MODEL.md 4).
// `where`: the scene's path; `hertz_flags`: whether --hertz-a or --hertz-R was given.
void check_scene(const Scene& s, const std::string& where, bool hertz_flags) {
  if (s.hertz_a >= 0.1 * s.hertz_R) {
    throw std::invalid_argument(
        where + (hertz_flags ? " with --hertz-a/--hertz-R" : "") +
        ": hertz.a = " + settings::format_number(s.hertz_a) + ": allowed: < 0.1 hertz.R = " +
        settings::format_number(0.1 * s.hertz_R) + " (small-slope contact)");
  }
}

Scene read_scene(const std::string& path) {
  Scene s;
  auto r = app::SceneReader::from_file(path);
  r.read(Scene::settings(), s);
  r.reject_unknown();
  return s;
}

nlohmann::json grid_json(Shape2 block, Shape2 fft_grid) {
  return {{"block", {block.n0, block.n1}}, {"fft_grid", {fft_grid.n0, fft_grid.n1}}};
}

}  // namespace

namespace {

// The Hertz check's table and figure: p/p0 of the sites and of Hertz against r/a.
void write_hertz(const fs::path& dir, const Scene& s, const validation::HertzCheck& hz) {
  app::CsvTable hz_table({"r_over_a", "p_over_p0", "p_hertz_over_p0"});
  app::Series hz_num{.title = "GF + Polonsky-Keer (sites)", .style = "points pt 7 ps 0.3"};
  for (std::size_t i = 0; i < hz.r.size(); ++i) {
    if (hz.r[i] > 1.2 * s.hertz_a) continue;
    const double rho = hz.r[i] / s.hertz_a;
    hz_table.add_row({rho, hz.pressure[i] / hz.exact.p0, hz.exact.pressure(hz.r[i]) / hz.exact.p0});
    hz_num.x.push_back(rho);
    hz_num.y.push_back(hz.pressure[i] / hz.exact.p0);
  }
  app::Series hz_exact{.title = "Hertz", .style = "lines lw 2"};
  for (int k = 0; k <= 240; ++k) {
    const double rho = 1.2 * k / 240.0;
    hz_exact.x.push_back(rho);
    hz_exact.y.push_back(hz.exact.pressure(rho * s.hertz_a) / hz.exact.p0);
  }
  hz_table.write(dir / "hertz_pressure.csv");
  app::plot_png(dir / "hertz_pressure.png", {hz_num, hz_exact},
                {.title = "Hertz pressure, R = " + std::to_string(int(s.hertz_R)) +
                          " d, a = " + std::to_string(int(s.hertz_a)) + " d",
                 .xlabel = "r / a",
                 .ylabel = "p / p0"});
}

// The bonded disk's ring-averaged shear traction against (1 - r^2/a^2)^(-1/2).
void write_disk(const fs::path& dir, const Scene& s, const validation::BondedDiskCheck& disk) {
  app::CsvTable disk_table({"r_over_a", "tau_over_mean", "tau_exact_over_mean"});
  app::Series disk_num{.title = "GF, ring averages", .style = "points pt 7"};
  app::Series disk_exact{.title = "(1 - r^2/a^2)^(-1/2)", .style = "lines lw 2"};
  for (std::size_t k = 0; k < disk.ring_r.size(); ++k) {
    const double rho = disk.ring_r[k] / disk.radius;
    disk_table.add_row({rho, disk.ring_traction[k], disk.ring_exact[k]});
    disk_num.x.push_back(rho);
    disk_num.y.push_back(disk.ring_traction[k]);
  }
  for (int k = 0; k < 200; ++k) {
    const double rho = 0.98 * k / 199.0;
    disk_exact.x.push_back(rho);
    disk_exact.y.push_back(1.0 / std::sqrt(1.0 - rho * rho));
  }
  disk_table.write(dir / "disk_traction.csv");
  app::plot_png(
      dir / "disk_traction.png", {disk_num, disk_exact},
      {.title = "Bonded rigid disk: shear traction, a = " + std::to_string(int(s.disk_a)) + " d",
       .xlabel = "r / a",
       .ylabel = "tau / (Fx / 2 pi a^2)",
       .yrange = std::pair{0.0, 5.0}});
}

// The far field: the relative difference of a loaded patch and a point force, with d^2/(24 r^2).
void write_far_field(const fs::path& dir, const validation::FarFieldCheck& far) {
  app::CsvTable far_table({"r", "diagonal", "ux_patch", "ux_point", "uz_patch", "uz_point"});
  app::Series fx_err{.title = "u_x per F_x, along x", .style = "linespoints"};
  app::Series fz_err{.title = "u_z per F_z, along x", .style = "linespoints"};
  app::Series fx_diag{.title = "u_x per F_x, diagonal", .style = "linespoints"};
  app::Series guide{.title = "d^2 / (24 r^2)", .style = "lines dt 2"};
  for (const auto& p : far.samples) {
    far_table.add_row(
        {p.r, static_cast<long long>(p.diagonal), p.ux_patch, p.ux_point, p.uz_patch, p.uz_point});
    auto& sx = p.diagonal ? fx_diag : fx_err;
    sx.x.push_back(p.r);
    sx.y.push_back(std::abs(p.ux_patch / p.ux_point - 1.0));
    if (!p.diagonal) {
      fz_err.x.push_back(p.r);
      fz_err.y.push_back(std::abs(p.uz_patch / p.uz_point - 1.0));
      guide.x.push_back(p.r);
      guide.y.push_back(1.0 / (24.0 * p.r * p.r));
    }
  }
  far_table.write(dir / "far_field.csv");
  app::plot_png(dir / "far_field.png", {fx_err, fz_err, fx_diag, guide},
                {.title = "Loaded patch vs point force: relative difference",
                 .xlabel = "r / d",
                 .ylabel = "|u_patch / u_point - 1|",
                 .logx = true,
                 .logy = true});
}

// Pass/fail against the tolerances of the analytic test tier.
struct Verdicts {
  bool hertz, disk, far;
};

nlohmann::json summary_json(const std::string& scene_path, const Scene& s,
                            const validation::HertzCheck& hz,
                            const validation::BondedDiskCheck& disk,
                            const validation::FarFieldCheck& far, const Verdicts& ok) {
  return {
      {"provenance", app::provenance_json()},
      {"scene", scene_path},
      {"settings", app::settings_echo(s, Scene::settings())},
      {"material", {{"G", s.material.G}, {"nu", s.material.nu}}},
      {"fft", {{"threads", s.fft.threads}, {"planner", fft::to_string(s.fft.planner)}}},
      {"hertz",
       {{"R", s.hertz_R},
        {"a", s.hertz_a},
        {"load", hz.exact.load},
        {"p0", hz.exact.p0},
        {"contact_radius", hz.contact_radius},
        {"radius_error", hz.radius_error},
        {"approach", hz.solve.approach},
        {"approach_exact", hz.exact.approach},
        {"approach_error", hz.approach_error},
        {"pressure_error_over_estar", hz.pressure_error / hz.exact.estar},
        {"pressure_error_over_p0", hz.pressure_error / hz.exact.p0},
        {"max_penetration", hz.solve.max_penetration},
        {"tolerance", s.hertz_solver.tolerance},
        {"residual", hz.solve.residual},
        {"iterations", hz.solve.iterations},
        {"gf_applications", hz.solve.gf_applications},
        {"termination", to_string(hz.solve.termination)},
        {"grid", grid_json(hz.block, hz.fft_grid)},
        {"wall_s", hz.wall_s},
        {"pass", ok.hertz}}},
      {"bonded_disk",
       {{"a", s.disk_a},
        {"a_eff", disk.radius},
        {"stiffness", disk.stiffness},
        {"stiffness_exact", disk.stiffness_exact},
        {"stiffness_error", disk.stiffness_error},
        {"traction_error_r_below_0.7a", disk.traction_error},
        {"tolerance", s.disk_solver.tolerance},
        {"residual", disk.solve.residual},
        {"iterations", disk.solve.iterations},
        {"gf_applications", disk.solve.gf_applications},
        {"termination", to_string(disk.solve.termination)},
        {"grid", grid_json(disk.block, disk.fft_grid)},
        {"wall_s", disk.wall_s},
        {"pass", ok.disk}}},
      {"far_field",
       {{"max_distance", s.far_field_distance},
        {"worst_relative_error_times_r2", far.worst_scaled_error},
        {"grid", grid_json(far.block, far.fft_grid)},
        {"wall_s", far.wall_s},
        {"pass", ok.far}}},
  };
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{
        "Analytic checks of the elastic half-space Green's functions (Hertz, bonded "
        "disk, far field)"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/gf_validation.toml";
    std::string out = "results/gf_validation";
    cli.add_option("scene", scene_path, "Scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    // A flag overrides the scene's key.
    app::SettingFlags flags;
    flags.add(cli, Scene::settings());
    app::add_list_settings(cli, Scene::settings(), Scene{}, "docs/gf_validation.md");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    Scene s = read_scene(scene_path);
    flags.apply(Scene::settings(), s);
    check_scene(s, scene_path, flags.given("hertz.a") || flags.given("hertz.R"));
    const fs::path dir = app::ensure_directory(out);

    std::cerr << "gf_validate: Hertz contact (R = " << s.hertz_R << " d, a = " << s.hertz_a
              << " d)\n";
    const auto hz =
        validation::check_hertz(s.material, s.hertz_R, s.hertz_a, s.hertz_solver, s.fft);
    std::cerr << "gf_validate: bonded rigid disk (a = " << s.disk_a << " d)\n";
    const auto disk = validation::check_bonded_disk(s.material, s.disk_a, s.disk_solver, s.fft);
    std::cerr << "gf_validate: far field of one loaded patch\n";
    const auto far = validation::check_far_field(s.material, s.far_field_distance, s.fft);

    write_hertz(dir, s, hz);
    write_disk(dir, s, disk);
    write_far_field(dir, far);
    // Pass/fail against the tolerances of the analytic test tier.
    const bool hz_ok = std::abs(hz.radius_error) < 0.01 && std::abs(hz.approach_error) < 0.01 &&
                       hz.pressure_error < 1e-3 * hz.exact.estar &&
                       hz.solve.termination == Termination::converged;
    const bool disk_ok = std::abs(disk.stiffness_error) < 0.01 && disk.traction_error < 0.02 &&
                         disk.solve.termination == Termination::converged;
    const bool far_ok = far.worst_scaled_error < 0.25;
    app::write_json(dir / "summary.json",
                    summary_json(scene_path, s, hz, disk, far, {hz_ok, disk_ok, far_ok}));

    std::printf(
        "Hertz:       contact radius %+.2e, approach %+.2e, max |p - p_H| = %.2e p0  [%s]\n",
        hz.radius_error, hz.approach_error, hz.pressure_error / hz.exact.p0,
        hz_ok ? "pass" : "FAIL");
    std::printf("Bonded disk: stiffness %+.2e vs 8Ga/(2-nu), traction (r < 0.7a) %.2e  [%s]\n",
                disk.stiffness_error, disk.traction_error, disk_ok ? "pass" : "FAIL");
    std::printf("Far field:   max |u_patch/u_point - 1| r^2/d^2 = %.3f (r >= 5 d)  [%s]\n",
                far.worst_scaled_error, far_ok ? "pass" : "FAIL");
    std::printf("results: %s\nfigures: %s, %s, %s\n", (dir / "summary.json").c_str(),
                (dir / "hertz_pressure.png").c_str(), (dir / "disk_traction.png").c_str(),
                (dir / "far_field.png").c_str());
    return hz_ok && disk_ok && far_ok ? 0 : 1;
  });
}
