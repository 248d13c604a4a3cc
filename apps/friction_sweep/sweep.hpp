// friction_sweep: the sweep scene, its points, and the results table sweep.csv, which is also
// the record a later run resumes from.
//
// A sweep scene is a slide scene (data/scenes/default.toml documents its keys) plus a [sweep]
// table (data/scenes/sweep_default.toml documents it) and, for the explicit model, an [explicit]
// table (data/scenes/sweep_collapse.toml). contact.a and contact.R are not allowed: the points
// take them from the [sweep] lists.
//
// sweep.model = "lfm" (default) | "explicit" | "both": which models run the points. The
// lateral force model's rows go to sweep.csv, the explicit model's (MODEL.md 4; alpha of the
// potential at each point's central load, contact.alpha unused) to sweep_explicit.csv, in the
// same columns.
//
// contact.envelope (issue 27) chooses the interface: hertz (default), adhesive or mixed; the
// rows carry it with tau0, and a/b_core^0 is the envelope's (ContactScene::a_over_bcore0). An
// adhesive sweep may leave out sweep.R (the adhesive envelope has no sphere: its points carry
// contact.R's default, 535 d, which enters nothing); the explicit model runs the Hertz envelope
// only.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/slide_io.hpp"

namespace asperity::app {

// A list of numbers with its origin, so that errors name what the user wrote.
struct ValueList {
  std::vector<double> values;
  std::string key;  // its setting, "sweep.a"
};

// sweep.tip_angle and sweep.tip_mismatch (issue 27): lists of the tip's lattice rotation and
// mismatch (interface/tip_lattice.hpp); every R and a runs with every angle and mismatch. Absent,
// the scene's contact.tip_angle and contact.tip_mismatch hold for every point (giving both a
// list and the contact value is an error). sweep.csv has the columns tip_angle, tip_mismatch.
struct SweepScene {
  std::string source;                      // scene file
  SlideScene base;                         // settings shared by all points; a and R set per point
  ValueList R{{}, "sweep.R"};              // sphere radii (d)
  std::optional<ValueList> a;              // contact radii (d); exactly one of a, a_over_bcore0
  std::optional<ValueList> a_over_bcore0;  // targets of the control parameter a / b_core^0
  std::optional<ValueList> tip_angle;      // the tip lattice's rotations (degrees); absent:
                                           // base.contact.tip.angle
  std::optional<ValueList> tip_mismatch;   // its mismatches; absent: base.contact.tip.mismatch
  int jobs = 0;  // points run at once (on each rank); 0: max(1, hardware threads / fft.threads)
  std::string model = "lfm";  // lfm | explicit | both
  // The explicit model's potential and substrate: G in eps/sigma^3 and sigma/d ([explicit]);
  // R, material and d are set per point.
  explicit_model::ExplicitScene potential;

  // The [sweep] and [explicit] settings (common/settings.hpp), flags --R, --a, --a-over-bcore0,
  // --jobs; the slide's own are SlideScene::settings().
  static const settings::Table<SweepScene>& settings();
  // The slide-scene keys a sweep scene leaves out: each point sets them from [sweep] (and --a
  // and --R are the sweep's lists).
  static const std::vector<std::string>& point_keys() {
    static const std::vector<std::string> keys{"contact.a", "contact.R"};
    return keys;
  }
  // Every setting but the points' own, {key: value} (summary.json's "settings").
  [[nodiscard]] nlohmann::json settings_echo() const;
  // Throws std::invalid_argument naming the key, value and allowed range: lists non-empty
  // (sweep.R may be empty for the adhesive envelope), values positive and finite, exactly one of
  // a and a_over_bcore0, the explicit model only with the Hertz envelope. The a < R check needs
  // the points: see sweep_points().
  void validate() const;
  // The sphere radii of the points: sweep.R, or for an adhesive sweep without it contact.R's
  // default.
  [[nodiscard]] std::vector<double> radii() const;
  // jobs, or its default for `hardware_threads` (Ranks::hardware_threads(): this machine's, or
  // over MPI ranks its share of its host's).
  [[nodiscard]] int effective_jobs(int hardware_threads) const;
  [[nodiscard]] bool runs_lfm() const { return model != "explicit"; }
  [[nodiscard]] bool runs_explicit() const { return model != "lfm"; }
};

// Reads a sweep scene; unknown keys, wrong types and out-of-range values throw
// std::invalid_argument naming the file, key, value and range.
// check_slips = false leaves check_slip_relaxation to a caller that applies flags first (a flag
// may mend the scene's slip pair, --slip-solver).
SweepScene read_sweep_scene(const std::string& path, bool check_slips = true);

struct SweepPoint {
  double a = 0.0;                // contact radius (d)
  double R = 0.0;                // sphere radius (d)
  interface::TipLattice tip {};  // the tip's lattice (angle in degrees, mismatch)
};

// Contact radius at which a / b_core^0 = target (ContactScene::radius_for): Hertz
// a = sqrt(target R d / (c alpha)), c = 4 / (pi (1 - nu)) (MODEL.md 3); adhesive target d G /
// tau0; mixed the root of target = a tau0 / (d G) + c alpha a^2 / (R d).
double contact_radius_for(const interface::ContactScene& contact, double target);

// Every R with every a (or target) and every tip (sweep_tips()), sorted by tip angle, mismatch,
// R, then a: the order of sweep.csv. Throws
// std::invalid_argument naming the key if a point has a outside [1, 4096] d or a >= R (the
// limits of contact.a), or if two points coincide. Empty if the sweep runs the explicit model
// only.
std::vector<SweepPoint> sweep_points(const SweepScene& scene);

// The tips of a sweep: every sweep.tip_angle with every sweep.tip_mismatch (each absent list
// replaced by the scene's contact value).
std::vector<interface::TipLattice> sweep_tips(const SweepScene& scene);

// The explicit model's points (sweep_explicit.csv), empty unless it runs. A target of
// a/b_core^0 is met with the alpha of the potential at the point's own central load (a fixed
// point: alpha varies by 2% over 100x in load, 3 rounds). Throws std::invalid_argument naming
// the key as sweep_points() does, and for a/R >= 0.1 (small slopes, MODEL.md 4).
std::vector<SweepPoint> explicit_sweep_points(const SweepScene& scene);

// The contact and potential of an explicit point.
ExplicitSlideScene explicit_point_scene(const SweepScene& scene, const SweepPoint& p);

// Point folder below DIR/points: "a<a>_R<R>" with 6 significant digits, followed by
// "_angle<angle>_mismatch<m>" for a tip out of registry; explicit points "explicit_a<a>_R<R>...".
std::string point_folder(const SweepPoint& p, bool explicit_model = false);

// A short string of everything besides a, R and the tip that changes a point's result
// (protocol, steps, distance, solver, tolerance, alpha, G, nu); rows are reused only under the
// same fingerprint.
// FFT threads and planning change only round-off and are left out.
std::string settings_fingerprint(const SlideScene& scene);
// The same for the explicit rows: also G in eps/sigma^3 and sigma/d (alpha is per point).
std::string explicit_settings_fingerprint(const SweepScene& scene);

// Columns of sweep.csv. Every column is a function of the inputs (and the build): the same sweep
// gives a byte-identical table, whether run at once or killed and resumed. Timings go to
// summary.json ("run").
const std::vector<std::string>& sweep_columns();

// One row of sweep.csv, with what the figures, the fit and the summary need.
// Columns of the envelopes (issue 27): G (the unit of stress, which tau0 is in), envelope, tau0;
// tau_fric = Fx / A at the peak (A the
// contact-site area, column area), tau_fric_over_tau0 (nan without tau0: hertz),
// friction_over_regime_one = Fx / (alpha Fz + tau0 A) at the peak (1 in Regime I); mu,
// mu_over_alpha and kinetic_over_alpha are nan for the adhesive envelope (no load: mu undefined),
// whose kinetic_over_static is that of Fx/A.
struct SweepRow {
  SweepPoint point;
  std::string envelope = "hertz";
  double a_over_bcore0 = 0.0;
  double mu_over_alpha = 0.0;
  // Friction over its Regime I value, the quantity of the envelope's scaling law: mu/alpha
  // (hertz), tau_fric/tau0 (adhesive), friction_over_regime_one (mixed).
  double relative_friction = 0.0;
  double kinetic_over_static = 0.0;
  int slip_events = 0;
  bool mu_is_lower_bound = false;
  bool failed = false;
  std::string stop_reason;
  double wall_s = 0.0;  // run time of the point; NaN for a reused row (not in the table)
  int rank = 0;         // the MPI rank that computed it (mpi_points.hpp; not in the table)
  std::vector<CsvTable::Cell> cells;  // the row as written, in sweep_columns() order
};

// A row as bytes, for rank 0 of a sweep over MPI ranks (mpi_points.hpp), and back: every field
// bit for bit, so that rank 0 writes the row as the rank that computed it would.
std::string encode_row(const SweepRow& row);
SweepRow decode_row(std::string_view bytes);

// Row of a finished point.
SweepRow sweep_row(const SlideScene& scene, const slide::SlideResult& result,
                   const std::string& settings);
// Row of a point whose run threw after wall_s seconds: results NaN, stop_reason
// "error: <message>".
SweepRow error_row(const SlideScene& scene, const std::string& message, double wall_s,
                   const std::string& settings);

// Rows of an existing sweep.csv that can stand in for points of this sweep: same a and R to a
// relative 1e-9, the same tip, same settings fingerprint, and not failed (a failed point is run
// again).
struct ResumedRows {
  std::vector<std::optional<SweepRow>> rows;  // per point of `points`
  std::size_t reused = 0;
  std::size_t adopted = 0;  // of the reused: rows of other settings taken under `adopt`
  std::size_t other_settings = 0, not_requested = 0, failed = 0;  // rows dropped, and why
  // Lower bounds stopped at a limit (capped_lower_bound) that these settings raise
  // (slide.max_distance or slide.max_slips) and that `extendable` says can be continued:
  // dropped under `adopt`, so that the point runs on from its kept checkpoint instead of
  // keeping the bound.
  std::size_t to_extend = 0;
  std::vector<bool> extend;  // per point of `points`: one of the to_extend
};
// Whether a finished point's friction is a lower bound only because it reached a limit a
// longer run lifts: the automatic distance's cap (slide.max_distance) or slide.max_slips (the
// stop reasons of slide/protocol.hpp). friction_sweep keeps the last checkpoint of such a
// point (checkpoint.capped.cbor) so that a run with a larger limit and --adopt continues it.
bool capped_lower_bound(bool mu_is_lower_bound, const std::string& stop_reason);
// Throws std::invalid_argument if the file is not a sweep.csv (other columns). A table of an
// earlier layout (without the tip's columns, or with a wall_s column) is accepted and all its
// rows are dropped as other_settings: they came from another build, which the settings
// fingerprint rejects anyway.
// With `adopt` (--adopt), a row whose settings differ from `settings` only in what a
// checkpoint may be adopted across (the build, slide.*, solver.*, fft.*;
// fingerprint_difference()) is reused too, its settings cell unchanged: the table says which
// build and settings made each row.
// With `adopt` and `extendable` (index into `points` -> whether the point keeps a capped
// checkpoint), a capped lower bound of other settings is dropped instead (to_extend).
ResumedRows resume_rows(const std::filesystem::path& csv, const std::vector<SweepPoint>& points,
                        const std::string& settings, bool adopt = false,
                        const std::function<bool(std::size_t)>& extendable = {});

// The quantity a sweep of this envelope plots and fits (SweepRow::relative_friction), e.g.
// "mu/alpha", and the Regime II slope of its law: -2/3 (hertz: MODEL.md 8), -1/2 (adhesive:
// tau_fric/tau0 = 2 (a/(2 c0 b_core))^(-1/2), nucleation/regime_two.hpp); the mixed envelope
// lies between its two limits and has no slope of its own (NaN).
std::string relative_friction_name(const std::string& envelope);
double regime_two_slope(const std::string& envelope);

// Least-squares fit of log(y) = log(prefactor) + slope log(a/b_core^0), y the rows'
// relative_friction (mu/alpha for the Hertz envelope), over the rows with a/b_core^0 in [lo, hi]
// that neither failed nor are lower bounds. Needs 2 distinct a/b_core^0 values; otherwise the
// json says why there is no fit. `envelope` names the quantity and the law's slope.
nlohmann::json fit_slope(const std::vector<SweepRow>& rows, double lo, double hi,
                         const std::string& envelope = "hertz");

// The collapse of the two models (issue 4 acceptance 3): each explicit row against the LFM's
// mu/alpha at the same R and a/b_core^0, interpolated linearly in log-log between the LFM rows
// around it (failed rows and lower bounds left out). Per explicit row: a, R, a_over_bcore0,
// explicit and lfm mu/alpha, ratio (null where the LFM rows do not bracket it); and the
// largest |ratio - 1| over a/b_core^0 in [lo, hi].
nlohmann::json compare_models(const std::vector<SweepRow>& lfm, const std::vector<SweepRow>& expl,
                              double lo, double hi);

}  // namespace asperity::app
