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
// Under mpirun the points run over the ranks and rank 0 writes the same files
// (apps/common/mpi_points.hpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/cli_checks.hpp"
#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/peierls/scan.hpp"
#include "scan_io.hpp"

using namespace asperity;
using namespace asperity::app::peierls_scan;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  return app::run_main_over_ranks(argc, argv, [](int argc_, char** argv_, app::Ranks& ranks) {
    CLI::App cli{"Peierls stress of an interfacial dislocation versus core width and line angle"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/peierls_default.toml";
    std::string out = "results/peierls_scan";
    bool list_angles = false;
    cli.add_option("scene", scene_path, "Scan scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    // --b-core, --theta, --L, --L-tolerance, --max-L, --model, --nu, --precision, --tolerance,
    // --jobs, --snapshots: from the scene's settings table.
    app::SettingFlags flags;
    flags.add(cli, scene_settings());
    cli.add_flag("--list-angles", list_angles, "Print the angles the cell offers and exit");
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    app::add_list_settings(cli, scene_settings(), Scene{}, "docs/peierls.md", "scene key");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    Scene s = read_scene(scene_path);
    flags.apply(scene_settings(), s);
    s.options.validate();
    s.cell_size.validate();
    if (list_angles) {
      print_angles(s);
      return 0;
    }

    // Points, validated before any work: every angle must map onto an orientation of the cell.
    const std::vector<peierls::Orientation> orientations = peierls::scan_orientations(
        s.options.cell.L, s.theta, s.angle_tolerance, s.min_line_spacing);
    const std::vector<double> bs = peierls::scan_core_widths(s.b_core);
    const std::vector<peierls::ScanPoint> points = peierls::scan_points(bs, orientations);
    const std::string settings = fingerprint(s);
    // SIGINT/SIGTERM from here on: no new point starts; the points in flight (seconds each)
    // finish and are kept, and the same command continues with the rest.
    app::install_stop_handlers();
    const int n_jobs_wanted = s.jobs > 0 ? s.jobs : std::max(1, ranks.hardware_threads());

    const auto t0 = std::chrono::steady_clock::now();
    // Over MPI ranks, rank 0 alone locks, resumes, plans and writes; every rank runs points.
    fs::path dir = out;
    std::optional<app::DirectoryLock> dir_lock;
    const fs::path csv = dir / "peierls.csv";
    std::vector<std::optional<Row>> rows(points.size());
    std::size_t reused = 0;
    ScanRun run{.scene = s, .points = points, .settings = settings, .dir = dir, .csv = csv};
    run.jobs = n_jobs_wanted;
    if (ranks.leader()) {
      app::ensure_directory(dir);
      dir_lock.emplace(dir);  // one scan per output directory
      app::remove_stale_temporaries(dir);
      reused = resume(csv, points, settings, rows);
      write_table(csv, rows, s);
      run.order = pending_points(points, rows);
      run.jobs = std::max(1, std::min(n_jobs_wanted, static_cast<int>(run.order.size())));
      check_memory(s, run.jobs * ranks.ranks_on_host());
      print_plan(s, points.size(), reused, csv, orientations, run.jobs, ranks.size());
    }
    ranks.start(settings + " " + std::to_string(points.size()));
    const std::size_t finished = run_scan(run, rows, ranks);
    if (!ranks.leader()) return 0;
    if (app::stop_requested() &&
        std::any_of(rows.begin(), rows.end(), [](const auto& r) { return !r.has_value(); })) {
      std::string again = app::command_line(argc_, argv_);
      if (ranks.distributed()) again = "mpirun -np " + std::to_string(ranks.size()) + " " + again;
      std::fprintf(stderr,
                   "peierls_scan: stopped; %zu point%s finished in this run (kept in %s)\n"
                   "continue with:\n  %s\n",
                   finished, finished == 1 ? "" : "s", csv.c_str(), again.c_str());
      return app::kInterrupted;
    }

    ScanSummary sum{.scene = s,
                    .settings = settings,
                    .b_core = bs,
                    .points = points.size(),
                    .computed = run.order.size(),
                    .reused = reused,
                    .jobs = run.jobs,
                    .ranks = ranks.size()};
    for (auto& r : rows)
      sum.rows.push_back(*r);
    // Fits per angle over the resolved points in the window (the rows' results, without the
    // run's columns).
    const std::vector<peierls::PointResult> results(sum.rows.begin(), sum.rows.end());
    sum.fits = peierls::fit_orientations(results, orientations, s.fit_b_min, s.fit_b_max,
                                         s.options.cell.material.nu);
    sum.figures = write_figures(dir, s, sum.rows, sum.fits);
    sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_summary(dir / "summary.json", sum);
    return print_report(dir, csv, sum) > 0 ? 1 : 0;
  });
}
