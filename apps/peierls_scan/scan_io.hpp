// peierls_scan's pieces (main.cpp wires them): the scan scene, the results table peierls.csv
// (also the record a later run resumes from), the run of the points, the figures, summary.json
// and the report. The physics is peierls/'s (scan.hpp); this is input, running and output.
#pragma once

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/core/common/settings.hpp"
#include "asperity/peierls/scan.hpp"

namespace asperity::app::peierls_scan {

struct Scene {
  std::string source;
  std::vector<double> b_core = {1, 2, 3, 4, 5, 6};  // core widths (d)
  std::vector<double> theta = {0, 45, 63.4, 90};    // line angles (degrees)
  double angle_tolerance = 0.5;
  int jobs = 0;
  bool snapshots = false;
  double min_line_spacing = 16.0;
  peierls::PeierlsOptions options;
  peierls::CellSizeOptions cell_size;
  double fit_b_min = 2.0, fit_b_max = 1e9;
};

// Every setting of a scan scene: the cell's, the solver's and the cell-size search's (peierls/),
// and the scan's own, its lists (scan.b_core, scan.theta) included.
const settings::Table<Scene>& scene_settings();

// Throws std::invalid_argument naming the file, key and constraint.
Scene read_scene(const std::string& path);

// Everything but the point's own (b_core, orientation) that changes a result: the scene's
// settings that do, exact, and the build (another build may resolve a threshold differently:
// its rows are not reused).
std::string fingerprint(const Scene& s);

// One row of peierls.csv: a point's result, its time and the fingerprint it was computed under.
struct Row : peierls::PointResult {
  double wall_s = NAN;
  std::string settings;
};

// peierls.csv with the rows computed so far (in the order of the points).
void write_table(const std::filesystem::path& csv, const std::vector<std::optional<Row>>& rows,
                 const Scene& s);

// Rows of an earlier run with the same settings, matched to this scan's points (into `rows`);
// returns how many. A table of an older version of the tool, or a failed row, is not reused.
std::size_t resume(const std::filesystem::path& csv, const std::vector<peierls::ScanPoint>& points,
                   const std::string& settings, std::vector<std::optional<Row>>& rows);

// Where a point's snapshots go below the output directory: points/<name>/cell.nc.
std::string point_name(const peierls::ScanPoint& p);

// What one run does: the points not yet in the table, widest cores last (they take the most
// relaxations), on `jobs` threads (of each rank, over MPI ranks; order: rank 0's).
struct ScanRun {
  const Scene& scene;
  const std::vector<peierls::ScanPoint>& points;
  std::vector<std::size_t> order;  // indices into points
  int jobs = 1;
  std::string settings;  // fingerprint()
  std::filesystem::path dir, csv;
};

// The points not yet in `rows`, widest cores last.
std::vector<std::size_t> pending_points(const std::vector<peierls::ScanPoint>& points,
                                        const std::vector<std::optional<Row>>& rows);

// Refuses (std::invalid_argument, exit status 2) a full-model scan whose cells would not fit in
// memory with `jobs` points at once.
void check_memory(const Scene& s, int jobs);

// Runs the points of `run` (over MPI ranks: handed out by rank 0, run by every rank,
// mpi_points.hpp), each row into `rows` and the table rewritten after each (on rank 0);
// snapshots if the scene asks (by the rank that runs the point). Stops early on request
// (stop_requested()); a failed table write is rethrown once the points in flight are done.
// Returns the points finished (0 on the other ranks).
std::size_t run_scan(const ScanRun& run, std::vector<std::optional<Row>>& rows, Ranks& ranks);

// A row's results as bytes, for rank 0 (mpi_points.hpp), and back onto the point's row: every
// field bit for bit.
std::string encode_row(const Row& row);
Row decode_row(const peierls::ScanPoint& point, std::string_view bytes);

// tau_P_vs_b_core.png, tau_P_vs_theta.png and core_width.png in `dir` (those with data).
std::vector<std::filesystem::path> write_figures(const std::filesystem::path& dir, const Scene& s,
                                                 const std::vector<Row>& rows,
                                                 const std::vector<peierls::OrientationFit>& fits);

// The angles an L cell offers (--list-angles), on stdout.
void print_angles(const Scene& s);

// What a run is about to do, on stderr: points, reused rows, cell and solver settings, points at
// once (on each of `ranks` MPI ranks), and the orientation each angle maps to.
void print_plan(const Scene& s, std::size_t points, std::size_t reused,
                const std::filesystem::path& csv,
                const std::vector<peierls::Orientation>& orientations, int jobs, int ranks);

// What summary.json and the report say about a finished scan.
struct ScanSummary {
  const Scene& scene;
  std::string settings;
  std::vector<double> b_core;  // distinct, sorted
  std::size_t points = 0, computed = 0, reused = 0;
  int jobs = 1, ranks = 1;  // points at once on each of `ranks` MPI ranks (1: one process)
  std::vector<Row> rows;
  std::vector<peierls::OrientationFit> fits;
  std::vector<std::filesystem::path> figures;
  double wall_s = 0.0;
};

// summary.json: the scene, the fits per orientation (named edge, screw, theta_<angle>), counts,
// times and provenance.
void write_summary(const std::filesystem::path& json, const ScanSummary& summary);

// The results on stdout; cells not converged in size and numerical failures on stderr.
// Returns the number of failed points.
std::size_t print_report(const std::filesystem::path& dir, const std::filesystem::path& csv,
                         const ScanSummary& summary);

}  // namespace asperity::app::peierls_scan
