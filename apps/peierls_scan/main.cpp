// peierls_scan: Peierls stress of the periodic cell (MODEL.md section 6) over a grid of core
// widths and line angles, points in parallel. Reads a scene (default:
// data/scenes/peierls_default.toml), lets flags override it, and writes into the output directory
// - peierls.csv: one row per (b_core, angle), rewritten after every finished point; a later run
//   with the same settings keeps its rows instead of recomputing them (resumable);
// - summary.json: settings, fits of tau_P = k1 tau_max exp(-k2 b_core/d) per angle (standard
//   errors, window), counts; times and provenance under "run";
// - tau_P_vs_b_core.png (log scale, one curve per angle, unresolved points at their floor),
//   tau_P_vs_theta.png (one curve per b_core), core_width.png (against the continuum width);
// - with snapshots on: points/<point>/cell.nc, the relaxed and the last stable loaded state of
//   the whole L x L cell in the contact simulator's snapshot layout (global attribute periodic).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/cli.hpp"
#include "common/cli_checks.hpp"
#include "common/memory.hpp"
#include "common/output_files.hpp"
#include "common/plot.hpp"
#include "common/point_runner.hpp"
#include "common/settings_cli.hpp"
#include "common/snapshot_io.hpp"
#include "common/toml_reader.hpp"
#include "peierls/fit.hpp"
#include "peierls/peierls_stress.hpp"

using namespace asperity;
namespace fs = std::filesystem;

namespace {

struct Scene {
  std::string source;
  std::vector<double> b_core, theta;
  double angle_tolerance = 0.5;
  int jobs = 0;
  bool snapshots = false;
  double min_line_spacing = 16.0;
  peierls::PeierlsOptions options;
  peierls::CellSizeOptions cell_size;
  double fit_b_min = 2.0, fit_b_max = 1e9;
};

// Shortest form that reads back to the same double: fingerprints compare exactly.
using settings::format_number;

// Every setting of a scan scene but its lists (scan.b_core, scan.theta): the cell's, the
// solver's and the cell-size search's (peierls/), and the scan's own.
const settings::Table<Scene>& scene_settings() {
  using R = settings::Range;
  static const settings::Table<Scene> table = [] {
    settings::Table<Scene> t;
    settings::lift(
        t, peierls::PeierlsOptions::settings(), "", [](auto& s) -> auto& { return s.options; });
    settings::lift(
        t, peierls::CellSizeOptions::settings(), "", [](auto& s) -> auto& { return s.cell_size; });
    t.push_back(settings::number<Scene>(
        "scan.angle_tolerance", [](auto& s) -> auto& { return s.angle_tolerance; },
        R::closed(0.0, 45.0), "degrees",
        "largest difference of a cell's line angle from a wanted one"));
    t.push_back(settings::neutral(settings::integer<Scene>(
        "scan.jobs", [](auto& s) -> auto& { return s.jobs; }, R::closed(0, 1024), "",
        "points run at once (0: hardware threads)")));
    t.push_back(settings::neutral(settings::boolean<Scene>(
        "scan.snapshots", [](auto& s) -> auto& { return s.snapshots; },
        "NetCDF snapshots of each point's cell")));
    t.push_back(settings::number<Scene>(
        "cell.min_line_spacing", [](auto& s) -> auto& { return s.min_line_spacing; }, R::positive(),
        "d", "smallest distance between a line and its periodic images"));
    t.push_back(settings::number<Scene>(
        "fit.b_min", [](auto& s) -> auto& { return s.fit_b_min; }, R::non_negative(), "d",
        "fit window of tau_P = k1 tau_max exp(-k2 b_core/d): smallest core width"));
    t.push_back(settings::number<Scene>(
        "fit.b_max", [](auto& s) -> auto& { return s.fit_b_max; }, R::positive(), "d",
        "fit window: largest core width"));
    return t;
  }();
  return table;
}

Scene read_scene(const std::string& path) {
  app::SceneReader r = app::SceneReader::from_file(path);
  using app::Range;
  Scene s;
  s.source = path;
  s.b_core = r.numbers("scan.b_core", {1, 2, 3, 4, 5, 6}, Range::closed(0.1, 1000));
  s.theta = r.numbers("scan.theta", {0, 45, 63.4, 90}, Range::closed(0, 90));
  r.read(scene_settings(), s);
  r.reject_unknown();
  if (s.b_core.empty())
    throw std::invalid_argument(path + ": scan.b_core: empty, give at least one");
  if (s.theta.empty()) throw std::invalid_argument(path + ": scan.theta: empty, give at least one");
  if (s.fit_b_min >= s.fit_b_max) {
    throw std::invalid_argument(path + ": fit.b_min = " + format_number(s.fit_b_min) +
                                " must be below fit.b_max = " + format_number(s.fit_b_max));
  }
  return s;
}

// Everything but the point's own (b_core, orientation) that changes a result: the scene's
// settings that do, exact, and the build (another build may resolve a threshold differently:
// its rows are not reused).
std::string fingerprint(const Scene& s) {
  return settings::fingerprint(
             s, scene_settings(), true,
             {"scan.angle_tolerance", "cell.min_line_spacing", "fit.b_min", "fit.b_max"}) +
         " code=" + app::provenance_token();
}

struct Point {
  double b_core = 0.0;
  peierls::Orientation orientation;
};

struct Row {
  Point point;
  int L = 0;                 // cell size of the result (sites per period)
  double L_change = NAN;     // |tau_P(L)/tau_P(L/2) - 1|; NaN: one cell
  bool L_converged = false;  // L_change <= cell.L_tolerance (or tolerance 0)
  bool resolved_pos = false, resolved_neg = false;
  double tau_pos = NAN, tau_neg = NAN;  // tau_P / tau_max
  double floor = NAN;                   // resolution floor / tau_max
  double core_width = NAN, core_width_continuum = NAN, rigid = NAN;
  long long iterations = 0, transforms = 0;
  // Relaxations that neither converged nor glided (counted unstable: tau_P is bracketed from
  // below by verified equilibria only), over both signs.
  long long undetermined = 0;
  std::string failure;  // numerical failure (non-finite forces); empty: none
  double wall_s = NAN;
  std::string settings;
};

const std::vector<std::string>& columns() {
  static const std::vector<std::string> c = {"b_core",
                                             "theta_deg",
                                             "m_x",
                                             "m_y",
                                             "L",
                                             "L_change",
                                             "L_converged",
                                             "model",
                                             "tau_P_over_tau_max_pos",
                                             "tau_P_over_tau_max_neg",
                                             "resolved_pos",
                                             "resolved_neg",
                                             "floor_over_tau_max",
                                             "core_width",
                                             "core_width_continuum",
                                             "rigid_pn_estimate",
                                             "iterations",
                                             "transforms",
                                             "undetermined",
                                             "failure",
                                             "wall_s",
                                             "settings"};
  return c;
}

std::vector<app::CsvTable::Cell> cells(const Row& r, const Scene& s) {
  // An unresolved threshold is an empty cell, never a number; its floor is in its own column.
  const auto tau = [](bool ok, double v) -> app::CsvTable::Cell {
    return ok ? app::CsvTable::Cell{v} : app::CsvTable::Cell{std::string()};
  };
  return {r.point.b_core,
          r.point.orientation.theta_deg,
          static_cast<long long>(r.point.orientation.mx),
          static_cast<long long>(r.point.orientation.my),
          static_cast<long long>(r.L),
          r.L_change,
          static_cast<long long>(r.L_converged),
          peierls::to_string(s.options.cell.model),
          tau(r.resolved_pos, r.tau_pos),
          tau(r.resolved_neg, r.tau_neg),
          static_cast<long long>(r.resolved_pos),
          static_cast<long long>(r.resolved_neg),
          r.floor,
          r.core_width,
          r.core_width_continuum,
          r.rigid,
          r.iterations,
          r.transforms,
          r.undetermined,
          r.failure,
          r.wall_s,
          r.settings};
}

void write_table(const fs::path& csv, const std::vector<std::optional<Row>>& rows, const Scene& s) {
  app::CsvTable t(columns());
  for (const auto& r : rows) {
    if (r) t.add_row(cells(*r, s));
  }
  t.write(csv);
}

// Rows of an earlier run with the same settings, matched to this scan's points.
std::size_t resume(const fs::path& csv, const std::vector<Point>& points,
                   const std::string& settings, std::vector<std::optional<Row>>& rows) {
  if (!fs::exists(csv)) return 0;
  const app::CsvTable t = app::CsvTable::read(csv);
  // A table of an older version of the tool (other columns) is started over.
  for (const std::string& c : columns()) {
    if (std::find(t.columns().begin(), t.columns().end(), c) == t.columns().end()) {
      std::fprintf(stderr,
                   "peierls_scan: %s has no column '%s' (an older version): starting over\n",
                   csv.c_str(), c.c_str());
      return 0;
    }
  }
  std::size_t reused = 0;
  const auto number_or_nan = [&t](std::size_t i, const char* c) {
    const std::string text = t.text(i, c);
    return text.empty() ? NAN : t.number(i, c);
  };
  for (std::size_t i = 0; i < t.rows(); ++i) {
    // A failed point is computed again (it may have been an interrupted machine's fault).
    if (t.text(i, "settings") != settings || !t.text(i, "failure").empty()) continue;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Point& p = points[k];
      if (rows[k] || t.number(i, "b_core") != p.b_core || t.integer(i, "m_x") != p.orientation.mx ||
          t.integer(i, "m_y") != p.orientation.my)
        continue;
      Row r;
      r.point = p;
      r.L = static_cast<int>(t.integer(i, "L"));
      r.L_change = number_or_nan(i, "L_change");
      r.L_converged = t.integer(i, "L_converged") != 0;
      r.resolved_pos = t.integer(i, "resolved_pos") != 0;
      r.resolved_neg = t.integer(i, "resolved_neg") != 0;
      r.tau_pos = number_or_nan(i, "tau_P_over_tau_max_pos");
      r.tau_neg = number_or_nan(i, "tau_P_over_tau_max_neg");
      r.floor = t.number(i, "floor_over_tau_max");
      r.core_width = t.number(i, "core_width");
      r.core_width_continuum = t.number(i, "core_width_continuum");
      r.rigid = t.number(i, "rigid_pn_estimate");
      r.iterations = t.integer(i, "iterations");
      r.transforms = t.integer(i, "transforms");
      r.undetermined = t.integer(i, "undetermined");
      r.wall_s = t.number(i, "wall_s");
      r.settings = settings;
      rows[k] = r;
      ++reused;
    }
  }
  return reused;
}

std::string point_name(const Point& p) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "b%g_m%d_%d", p.b_core, p.orientation.mx, p.orientation.my);
  return buf;
}

// The whole L x L cell in the snapshot layout of the contact simulator (MODEL.md 5 fields):
// s_x = X + u_x - w(X) with the frustration w = d (m_x X + m_y Y)/L of MODEL.md 6, unwrapped
// inside the cell so that the registry offset s_x - X is continuous there (it winds by m_x, m_y
// across the cell's sides, which track_loops measures), tau = f / d^2, uniform tau_max, no
// pressure.
slide::Snapshot cell_snapshot(const peierls::PeierlsCell& cell, const std::vector<double>& u,
                              const std::string& label, double tau_ext) {
  const int L = cell.options().L;
  const std::vector<double> full = cell.expand(u);
  const std::size_t n = static_cast<std::size_t>(L) * static_cast<std::size_t>(L);
  slide::Snapshot s;
  s.label = label;
  s.Dx = 0.0;
  s.Fx = tau_ext * static_cast<double>(n);  // total applied force on the cell (G d^2)
  s.block.shape = {L, L};
  s.ux.assign(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
  s.uy.assign(full.begin() + static_cast<std::ptrdiff_t>(n), full.end());
  s.sx.resize(n);
  s.sy = s.uy;
  s.tau_x.resize(n);
  s.tau_y.resize(n);
  s.tau_max.assign(n, cell.tau_max());
  s.pressure.assign(n, 0.0);
  s.in_contact.assign(n, 1);
  const double two_pi = 2.0 * std::numbers::pi;
  for (int X = 0; X < L; ++X) {
    for (int Y = 0; Y < L; ++Y) {
      const std::size_t i =
          static_cast<std::size_t>(X) * static_cast<std::size_t>(L) + static_cast<std::size_t>(Y);
      const double w = static_cast<double>(static_cast<long long>(cell.options().mx) * X +
                                           static_cast<long long>(cell.options().my) * Y) /
                       L;
      s.sx[i] = X + s.ux[i] - w;
      s.tau_x[i] = -cell.tau_max() * std::sin(two_pi * (s.ux[i] - w));
      s.tau_y[i] = -cell.tau_max() * std::sin(two_pi * s.sy[i]);
    }
  }
  return s;
}

std::string angle_title(double theta) {
  char buf[48];
  if (theta < 1e-9) return "screw (0 deg)";
  if (std::abs(theta - 90.0) < 1e-9) return "edge (90 deg)";
  std::snprintf(buf, sizeof buf, "%.1f deg", theta);
  return buf;
}

std::string character_name(const peierls::Orientation& o) {
  if (o.mx == 0) return "screw";
  if (o.my == 0) return "edge";
  char buf[48];
  std::snprintf(buf, sizeof buf, "theta_%.1f", o.theta_deg);
  return buf;
}

// tau_P of a row: the mean of the resolved signs (they agree to the bracket precision).
std::optional<double> row_tau(const Row& r) {
  if (!r.failure.empty()) return std::nullopt;  // not a result at all
  if (r.resolved_pos && r.resolved_neg) return 0.5 * (r.tau_pos + r.tau_neg);
  if (r.resolved_pos) return r.tau_pos;
  if (r.resolved_neg) return r.tau_neg;
  return std::nullopt;
}

std::vector<fs::path> write_figures(const fs::path& dir, const Scene& s,
                                    const std::vector<Row>& rows,
                                    const std::map<double, peierls::ExponentialFit>& fits) {
  std::vector<fs::path> written;
  std::map<double, std::vector<const Row*>> by_angle, by_b;
  for (const Row& r : rows) {
    by_angle[r.point.orientation.theta_deg].push_back(&r);
    by_b[r.point.b_core].push_back(&r);
  }
  char title[200];
  std::snprintf(title, sizeof title, "Peierls stress, L >= %d, nu = %g, %s cell, precision %g",
                s.options.cell.L, s.options.cell.material.nu,
                peierls::to_string(s.options.cell.model).c_str(), s.options.precision);

  std::vector<app::Series> vs_b;
  app::Series unresolved{.title = "unresolved: below floor",
                         .style = "points pt 9 ps 1.5 lc 'black'"};
  for (const auto& [theta, list] : by_angle) {
    app::Series line{.title = angle_title(theta), .style = "linespoints pt 7 ps 1.2"};
    for (const Row* r : list) {
      if (const auto tau = row_tau(*r)) {
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
  if (!vs_b.empty()) {
    const fs::path png = dir / "tau_P_vs_b_core.png";
    app::plot_png(png, vs_b,
                  {.title = title,
                   .xlabel = "b_core / d",
                   .ylabel = "tau_P / tau_max",
                   .logy = true,
                   .extra_commands = {"set format y '%.0e'", "set key bottom left"}});
    written.push_back(png);
  }

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
      if (const auto tau = row_tau(*r)) {
        line.x.push_back(r->point.orientation.theta_deg);
        line.y.push_back(*tau);
      }
    }
    if (!line.x.empty()) vs_theta.push_back(line);
  }
  if (!vs_theta.empty()) {
    const fs::path png = dir / "tau_P_vs_theta.png";
    app::plot_png(png, vs_theta,
                  {.title = title,
                   .xlabel = "line angle theta (deg; 0 screw, 90 edge)",
                   .ylabel = "tau_P / tau_max",
                   .logy = true,
                   .xrange = std::pair{-5.0, 95.0},
                   .extra_commands = {"set format y '%.0e'", "set key bottom left"}});
    written.push_back(png);
  }

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
  if (!width.empty()) {
    const fs::path png = dir / "core_width.png";
    app::plot_png(png, width,
                  {.title = "Relaxed core width (registry offset d/4 to 3d/4) vs continuum "
                            "Peierls-Nabarro",
                   .xlabel = "b_core / d",
                   .ylabel = "core width / d"});
    written.push_back(png);
  }
  return written;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Peierls stress of an interfacial dislocation versus core width and line angle"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/peierls_default.toml";
    std::string out = "results/peierls_scan";
    std::vector<double> b_core, theta;
    std::optional<int> jobs;
    bool snapshots = false, list_angles = false;
    cli.add_option("scene", scene_path, "Scan scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    cli.add_option("--b-core", b_core, "Core widths d G / tau_max (d), comma-separated")
        ->delimiter(',')
        ->check(app::finite_number(0.1, 1000));
    cli.add_option("--theta", theta, "Line angles (degrees, 0 screw, 90 edge), comma-separated")
        ->delimiter(',')
        ->check(app::finite_number(0, 90));
    // --L, --L-tolerance, --max-L, --model, --nu, --precision, --tolerance: from the scene's
    // settings table.
    app::SettingFlags flags;
    flags.add(cli, scene_settings());
    cli.add_option("--jobs", jobs, "Points run at once (default: hardware threads)")
        ->check(CLI::Range(1, 1024));
    cli.add_flag("--snapshots", snapshots, "NetCDF snapshots of each point's cell");
    cli.add_flag("--list-angles", list_angles, "Print the angles the cell offers and exit");
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    Scene s = read_scene(scene_path);
    if (!b_core.empty()) s.b_core = b_core;
    if (!theta.empty()) s.theta = theta;
    flags.apply(scene_settings(), s);
    if (jobs) s.jobs = *jobs;
    if (snapshots) s.snapshots = true;
    s.options.validate();
    s.cell_size.validate();
    if (list_angles) {
      std::printf("theta_deg m_x m_y line_spacing_d (L = %d, images >= %g d apart)\n",
                  s.options.cell.L, s.min_line_spacing);
      for (const auto& o : peierls::available_orientations(s.options.cell.L, s.min_line_spacing))
        std::printf("%9.4f %3d %3d %8.2f\n", o.theta_deg, o.mx, o.my, o.line_spacing);
      return 0;
    }

    // Points, validated before any work: every angle must map onto an orientation of the cell.
    std::vector<Point> points;
    std::vector<double> bs = s.b_core;
    std::sort(bs.begin(), bs.end());
    bs.erase(std::unique(bs.begin(), bs.end()), bs.end());
    std::vector<peierls::Orientation> orientations;
    for (double t : s.theta) {
      const peierls::Orientation o = peierls::orientation_for_angle(
          s.options.cell.L, t, s.angle_tolerance, s.min_line_spacing);
      const bool seen = std::any_of(orientations.begin(), orientations.end(),
                                    [&](const auto& x) { return x.mx == o.mx && x.my == o.my; });
      if (!seen) orientations.push_back(o);
    }
    for (const auto& o : orientations) {
      for (double b : bs)
        points.push_back({b, o});
    }
    const std::string settings = fingerprint(s);
    // SIGINT/SIGTERM from here on: no new point starts; the points in flight (seconds each)
    // finish and are kept, and the same command continues with the rest.
    app::install_stop_handlers();
    const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int n_jobs_wanted = s.jobs > 0 ? s.jobs : hardware;

    const auto t0 = std::chrono::steady_clock::now();
    const fs::path dir = app::ensure_directory(out);
    const app::DirectoryLock dir_lock(dir);  // one scan per output directory
    app::remove_stale_temporaries(dir);
    const fs::path csv = dir / "peierls.csv";
    std::vector<std::optional<Row>> rows(points.size());
    const std::size_t reused = resume(csv, points, settings, rows);
    write_table(csv, rows, s);
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < points.size(); ++k) {
      if (!rows[k]) order.push_back(k);
    }
    // Widest cores last: they take the most relaxations.
    std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
      return points[i].b_core < points[j].b_core;
    });
    const int n_jobs = std::max(1, std::min(n_jobs_wanted, static_cast<int>(order.size())));
    if (s.options.cell.model == peierls::CellModel::full) {
      // The full cell holds L^2 sites: fields, L-BFGS pairs and FFT buffers, about 512 bytes a
      // site (the reduced chain holds L). The largest cell the doubling may reach counts.
      const int largest = s.cell_size.tolerance > 0.0
                              ? std::max(s.options.cell.L, s.cell_size.max_L)
                              : s.options.cell.L;
      const double sites = static_cast<double>(largest) * static_cast<double>(largest);
      app::check_fits_in_memory("--L " + std::to_string(s.options.cell.L) + " (max_L " +
                                    std::to_string(s.cell_size.max_L) + ", model full)",
                                512.0 * sites * n_jobs,
                                "estimate: 512 bytes a site of an L x L cell per point at once");
    }
    std::fprintf(stderr,
                 "peierls_scan: %zu points (%zu reused from %s), L = %d (doubled up to %d until "
                 "tau_P changes by less than %g), %s cell, nu = %g, precision %g, tolerance %g x "
                 "tau; %d at once\n",
                 points.size(), reused, csv.c_str(), s.options.cell.L, s.cell_size.max_L,
                 s.cell_size.tolerance, peierls::to_string(s.options.cell.model).c_str(),
                 s.options.cell.material.nu, s.options.precision, s.options.tolerance, n_jobs);
    for (const auto& o : orientations)
      std::fprintf(stderr, "peierls_scan: theta = %.4f deg from (m_x, m_y) = (%d, %d)\n",
                   o.theta_deg, o.mx, o.my);

    std::mutex table_mutex, netcdf_mutex;
    std::exception_ptr fatal;
    std::atomic<bool> stop{false};
    std::size_t finished = 0;
    const auto run_point = [&](std::size_t k) {
      const Point& p = points[k];
      peierls::PeierlsOptions o = s.options;
      o.cell.b_core = p.b_core;
      o.cell.mx = p.orientation.mx;
      o.cell.my = p.orientation.my;
      const auto started = std::chrono::steady_clock::now();
      const peierls::CellSizeResult converged = peierls::peierls_stress_converged(o, s.cell_size);
      const peierls::PeierlsResult& r = converged.result;
      o.cell.L = r.L;
      Row row;
      row.point = p;
      row.L = r.L;
      row.L_change = converged.change;
      row.L_converged = converged.converged;
      row.resolved_pos = r.positive.resolved;
      row.resolved_neg = r.negative.resolved;
      row.tau_pos = r.positive.tau_P / r.tau_max;
      row.tau_neg = r.negative.tau_P / r.tau_max;
      row.floor = std::max(r.positive.floor, r.negative.floor) / r.tau_max;
      row.core_width = r.core_width;
      row.core_width_continuum = r.core_width_continuum;
      row.rigid = r.rigid_estimate;
      row.iterations = r.iterations;
      row.transforms = static_cast<long long>(r.transforms);
      row.undetermined = r.positive.undetermined + r.negative.undetermined;
      row.failure = r.failure;
      row.wall_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      row.settings = settings;
      if (s.snapshots) {
        const peierls::PeierlsCell cell(o.cell);
        std::vector<slide::Snapshot> frames = {cell_snapshot(cell, r.u_zero, "zero_stress", 0.0)};
        if (!r.u_loaded.empty())
          frames.push_back(cell_snapshot(cell, r.u_loaded, "loaded_below_tau_P", r.tau_loaded));
        nlohmann::json attributes = {
            {"tool", "peierls_scan"},  {"periodic", 1},
            {"b_core", p.b_core},      {"theta_deg", p.orientation.theta_deg},
            {"m_x", p.orientation.mx}, {"m_y", p.orientation.my},
            {"L", o.cell.L},           {"nu", o.cell.material.nu},
            {"tau_max", r.tau_max},    {"tau_loaded", r.tau_loaded}};
        const std::lock_guard lock(netcdf_mutex);  // the NetCDF library is not thread-safe
        app::write_snapshots(app::ensure_directory(dir / "points" / point_name(p)) / "cell.nc",
                             frames, attributes);
      }
      const std::lock_guard lock(table_mutex);
      ++finished;
      char tau_text[96];
      if (!row.failure.empty()) {
        std::snprintf(tau_text, sizeof tau_text, "FAILED");
      } else if (const auto tau = row_tau(row)) {
        std::snprintf(tau_text, sizeof tau_text, "tau_P/tau_max = %.5e", *tau);
      } else {
        std::snprintf(tau_text, sizeof tau_text, "unresolved (floor %.1e tau_max)", row.floor);
      }
      std::fprintf(stderr, "peierls_scan: [%zu/%zu] b_core = %g d, theta = %.1f: %s, %.2f s\n",
                   finished, order.size(), p.b_core, p.orientation.theta_deg, tau_text, row.wall_s);
      rows[k] = std::move(row);
      try {
        write_table(csv, rows, s);
      } catch (...) {
        if (!fatal) fatal = std::current_exception();
        stop = true;
      }
    };
    app::run_points(
        order.size(), n_jobs, [&](std::size_t i) { run_point(order[i]); }, stop);
    if (fatal) std::rethrow_exception(fatal);
    if (app::stop_requested() &&
        std::any_of(rows.begin(), rows.end(), [](const auto& r) { return !r.has_value(); })) {
      std::fprintf(stderr,
                   "peierls_scan: stopped; %zu point%s finished in this run (kept in %s)\n"
                   "continue with:\n  %s\n",
                   finished, finished == 1 ? "" : "s", csv.c_str(),
                   app::command_line(argc_, argv_).c_str());
      return app::kInterrupted;
    }

    std::vector<Row> done;
    for (auto& r : rows)
      done.push_back(*r);
    // Fits per angle over the resolved points in the window.
    std::map<double, peierls::ExponentialFit> fits;
    nlohmann::json fit_json = nlohmann::json::object();
    for (const auto& o : orientations) {
      std::vector<double> x, y;
      for (const Row& r : done) {
        if (r.point.orientation.mx != o.mx || r.point.orientation.my != o.my) continue;
        if (const auto tau = row_tau(r)) {
          x.push_back(r.point.b_core);
          y.push_back(*tau);
        }
      }
      const peierls::ExponentialFit f = peierls::fit_exponential(x, y, s.fit_b_min, s.fit_b_max);
      fits[o.theta_deg] = f;
      // The rigid-profile estimate decays as exp(-2 pi zeta |m| / d): its k2 for comparison.
      const double k2_rigid =
          std::hypot(o.mx, o.my) * std::numbers::pi *
          peierls::continuum_core_width(1.0, o.theta_deg, s.options.cell.material.nu);
      nlohmann::json j = {
          {"theta_deg", o.theta_deg}, {"m_x", o.mx},        {"m_y", o.my},
          {"valid", f.valid},         {"points", f.points}, {"k2_rigid_profile", k2_rigid}};
      if (f.valid) {
        j.update({{"k1", f.k1},
                  {"k1_error", f.k1_error},
                  {"k2", f.k2},
                  {"k2_error", f.k2_error},
                  {"k1_k2_correlation", f.correlation},
                  {"window_b_core", {f.b_min, f.b_max}},
                  {"rms_log_residual", f.rms_log_residual}});
      }
      fit_json[character_name(o)] = j;
    }
    const auto figures = write_figures(dir, s, done, fits);
    nlohmann::json figure_names = nlohmann::json::array();
    for (const auto& f : figures)
      figure_names.push_back(f.filename().string());
    std::size_t unresolved = 0;
    double points_wall = 0.0;
    for (const Row& r : done) {
      if (!r.resolved_pos || !r.resolved_neg) ++unresolved;
      points_wall += r.wall_s;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json scene = {
        {"source", s.source},
        {"b_core", bs},
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
        {"settings", settings}};
    app::write_json(dir / "summary.json", {{"tool", "peierls_scan"},
                                           {"scene", scene},
                                           {"points", points.size()},
                                           {"computed", order.size()},
                                           {"reused", reused},
                                           {"unresolved_points", unresolved},
                                           {"fits", fit_json},
                                           {"table", "peierls.csv"},
                                           {"figures", figure_names},
                                           {"run",
                                            {{"wall_s", wall},
                                             {"points_wall_s", points_wall},
                                             {"jobs", n_jobs},
                                             {"provenance", app::provenance_json()}}}});
    std::printf("peierls_scan: %zu points (%zu computed, %zu unresolved) in %.1f s\n",
                points.size(), order.size(), unresolved, wall);
    for (const auto& [name, j] : fit_json.items()) {
      if (j.value("valid", false)) {
        std::printf("  %-12s k1 = %.4g +- %.2g, k2 = %.4g +- %.2g (b_core in [%g, %g] d)\n",
                    name.c_str(), j["k1"].get<double>(), j["k1_error"].get<double>(),
                    j["k2"].get<double>(), j["k2_error"].get<double>(),
                    j["window_b_core"][0].get<double>(), j["window_b_core"][1].get<double>());
      }
    }
    std::printf("results: %s\n", fs::absolute(dir / "summary.json").c_str());
    std::printf("table:   %s\n", fs::absolute(csv).c_str());
    for (const auto& f : figures)
      std::printf("figure:  %s\n", fs::absolute(f).c_str());
    for (const Row& r : done) {
      // Resolved, but its cell did not converge: at max_L, or resolved at one size only.
      if (r.L_converged || !row_tau(r)) continue;
      std::fprintf(stderr,
                   "peierls_scan: warning: b_core = %g d, theta = %.1f deg: tau_P at L = %d is "
                   "not converged in the cell size (last change %.3g; cell.max_L %d)\n",
                   r.point.b_core, r.point.orientation.theta_deg, r.L, r.L_change,
                   s.cell_size.max_L);
    }
    std::size_t failed = 0;
    for (const Row& r : done) {
      if (r.failure.empty()) continue;
      if (failed++ == 0) std::fprintf(stderr, "peierls_scan: numerical failures:\n");
      std::fprintf(stderr, "  b_core = %g d, theta = %.1f deg (L = %d): %s\n", r.point.b_core,
                   r.point.orientation.theta_deg, r.L, r.failure.c_str());
    }
    return failed > 0 ? 1 : 0;
  });
}
