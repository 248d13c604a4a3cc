// peierls_scan's run: the points still to compute, the memory they need, and the pool that
// computes them, records each row and writes each cell's snapshots.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/memory.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "scan_io.hpp"

namespace asperity::app::peierls_scan {

namespace fs = std::filesystem;

std::vector<std::size_t> pending_points(const std::vector<peierls::ScanPoint>& points,
                                        const std::vector<std::optional<Row>>& rows) {
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!rows[k]) order.push_back(k);
  }
  // Widest cores last: they take the most relaxations.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return points[i].b_core < points[j].b_core;
  });
  return order;
}

void check_memory(const Scene& s, int jobs) {
  if (s.options.cell.model != peierls::CellModel::full) return;
  // The full cell holds L^2 sites: fields, L-BFGS pairs and FFT buffers, about 512 bytes a
  // site (the reduced chain holds L). The largest cell the doubling may reach counts.
  const int largest = s.cell_size.tolerance > 0.0 ? std::max(s.options.cell.L, s.cell_size.max_L)
                                                  : s.options.cell.L;
  const double sites = static_cast<double>(largest) * static_cast<double>(largest);
  app::check_fits_in_memory("--L " + std::to_string(s.options.cell.L) + " (max_L " +
                                std::to_string(s.cell_size.max_L) + ", model full)",
                            512.0 * sites * jobs,
                            "estimate: 512 bytes a site of an L x L cell per point at once");
}

namespace {

// The relaxed and the last stable loaded state of a point's whole cell, as cell.nc. The frames
// are made in parallel, the file written under `netcdf`: the NetCDF library is not thread-safe.
void write_cell_snapshots(const ScanRun& run, const peierls::ScanPoint& p,
                          const peierls::CellOptions& cell_options, const peierls::PeierlsResult& r,
                          std::mutex& netcdf) {
  const peierls::PeierlsCell cell(cell_options);
  std::vector<slide::Snapshot> frames = {
      peierls::cell_snapshot(cell, r.u_zero, "zero_stress", 0.0)};
  if (!r.u_loaded.empty())
    frames.push_back(peierls::cell_snapshot(cell, r.u_loaded, "loaded_below_tau_P", r.tau_loaded));
  nlohmann::json attributes = {{"tool", "peierls_scan"},  {"periodic", 1},
                               {"b_core", p.b_core},      {"theta_deg", p.orientation.theta_deg},
                               {"m_x", p.orientation.mx}, {"m_y", p.orientation.my},
                               {"L", cell_options.L},     {"nu", cell_options.material.nu},
                               {"tau_max", r.tau_max},    {"tau_loaded", r.tau_loaded}};
  const std::lock_guard lock(netcdf);
  app::write_snapshots(app::ensure_directory(run.dir / "points" / point_name(p)) / "cell.nc",
                       frames, attributes);
}

// "[k/n] b_core = ..., theta = ...: tau_P/tau_max = ..., t s" on stderr, and " on rank r" if
// `rank` is not -1.
void print_progress(std::size_t finished, std::size_t total, const Row& row, int rank) {
  char tau_text[96];
  if (!row.failure.empty()) {
    std::snprintf(tau_text, sizeof tau_text, "FAILED");
  } else if (const auto tau = peierls::peierls_ratio(row)) {
    std::snprintf(tau_text, sizeof tau_text, "tau_P/tau_max = %.5e", *tau);
  } else {
    std::snprintf(tau_text, sizeof tau_text, "unresolved (floor %.1e tau_max)", row.floor);
  }
  const std::string where = rank >= 0 ? " on rank " + std::to_string(rank) : std::string();
  std::fprintf(stderr, "peierls_scan: [%zu/%zu] b_core = %g d, theta = %.1f: %s, %.2f s%s\n",
               finished, total, row.point.b_core, row.point.orientation.theta_deg, tau_text,
               row.wall_s, where.c_str());
}

}  // namespace

std::size_t run_scan(const ScanRun& run, std::vector<std::optional<Row>>& rows, Ranks& ranks) {
  std::mutex table_mutex, netcdf_mutex;
  std::exception_ptr fatal;
  std::atomic<bool> stop{false};
  std::size_t finished = 0;
  // On the rank that took the point: its result and snapshots.
  const auto run_point = [&](std::size_t k) -> std::optional<std::string> {
    const peierls::ScanPoint& p = run.points[k];
    peierls::PeierlsOptions o = peierls::point_options(run.scene.options, p);
    const auto started = std::chrono::steady_clock::now();
    const peierls::CellSizeResult converged =
        peierls::peierls_stress_converged(o, run.scene.cell_size);
    o.cell.L = converged.result.L;
    Row row;
    static_cast<peierls::PointResult&>(row) = peierls::point_result(p, converged);
    row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    row.settings = run.settings;
    if (run.scene.snapshots) write_cell_snapshots(run, p, o.cell, converged.result, netcdf_mutex);
    return encode_row(row);
  };
  // On rank 0: the row into the table.
  const auto record = [&](std::size_t k, std::string_view bytes, int rank) {
    Row row = decode_row(run.points[k], bytes);
    const std::lock_guard lock(table_mutex);
    print_progress(++finished, run.order.size(), row, ranks.distributed() ? rank : -1);
    rows[k] = std::move(row);
    try {
      write_table(run.csv, rows, run.scene);
    } catch (...) {
      if (!fatal) fatal = std::current_exception();
      stop = true;
    }
  };
  ranks.run_points(run.order, run.jobs, run_point, record, stop);
  if (fatal) std::rethrow_exception(fatal);
  return finished;
}

}  // namespace asperity::app::peierls_scan
