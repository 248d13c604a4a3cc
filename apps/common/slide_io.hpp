// Scene files and result files of the sliding tools (contact_slide, friction_sweep).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/core/explicit/explicit_contact.hpp"
#include "asperity/core/explicit/explicit_slide.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/slide/slider.hpp"

namespace asperity::app {

class SceneReader;

struct SlideScene {
  interface::ContactScene contact;
  slide::SlideOptions options;
  // [output] precision, deflate. The tools write float fields by default (7 digits; a state
  // file 0.55 of the double one, a path 0.44), as trajectory formats store coordinates (AMBER
  // NetCDF: float): snapshots are for looking and tracking, and a run continues from its
  // checkpoint, which is in double. write_snapshots() itself writes exactly what it is given
  // unless asked otherwise.
  SnapshotFormat snapshot_format{.single_precision = true};
  // solver.slip_method and solver.slip_preconditioner: the slip minimiser (MODEL.md 5; issue
  // 21) is made from them and the final options.minimizer by make_slip_minimizer(), once the
  // scene and the flags are applied. The flow relaxes every slip again: which minimum an
  // instability falls into is the flow's to say (docs/solvers.md "Path fidelity"); lbfgs, cg
  // and newton carry loops past the flow's arrest, so they are not offered ("same" only with a
  // faithful solver.method: check_slip_relaxation).
  std::string slip_method = "flow";
  std::string slip_preconditioner = "interface";

  // Every setting of a slide scene, keyed as in its file (data/scenes/default.toml): the
  // contact's, the slide's (solver.*, fft.*, output.path_frames, ...), output.precision,
  // output.deflate and the two above. The scene reader, contact_slide's flags, fingerprints
  // and the summary echo are made from it.
  static const settings::Table<SlideScene>& settings();
  // options.slip_minimizer from slip_method, slip_preconditioner and options.minimizer.
  void make_slip_minimizer();
};

// The tools relax every slip with a path-faithful solver (MODEL.md 5; issue 21): the slip
// minimiser is the flow or FIRE, or, without one, solver.method is. Throws
// std::invalid_argument otherwise, naming where the slip method and the method came from
// (a scene key or a flag).
void check_slip_relaxation(const slide::SlideOptions& o, const std::string& slip_source,
                           const std::string& method_source);

class SettingFlags;
// The slip minimiser of a scene read without its slip check (read_slide_scene(path, false))
// once the flags are applied: made from the final minimiser (SlideScene::make_slip_minimizer),
// then checked as above, so that a flag (--slip-solver, --solver) can mend a scene's pair; the
// message names whichever of scene (`scene_path`) and flag set each half, the path once.
void apply_slip_flags(SlideScene& scene, const SettingFlags& flags, const std::string& scene_path);

// Reads a scene (data/scenes/default.toml documents every key); unknown keys, wrong types and
// out-of-range values throw std::invalid_argument naming the file, key, value and range.
// check_slips = false leaves check_slip_relaxation to a caller that applies flags first.
SlideScene read_slide_scene(const std::string& path, bool check_slips = true);
// The same from TOML text (the Python package's scenes), `source` naming it in messages.
SlideScene read_slide_scene_text(std::string_view text, const std::string& source);

// Reads the slide-scene keys (contact, material, slide, solver, fft) from `reader` and checks
// their relations, but leaves reject_unknown() to the caller: a tool whose scenes add tables of
// their own (friction_sweep's [sweep]) reads those too before rejecting unknown keys.
SlideScene read_slide_scene(SceneReader& reader, bool check_slips = true);

// The global attributes of a slide's snapshot files: model, a, R, alpha, G, nu, a/b_core^0,
// tolerance, and the flat entries of `extra` (SlideOutputOptions::summary_extra).
nlohmann::json snapshot_attributes(const SlideScene& scene, const nlohmann::json& extra);

// Estimated size of the snapshot files of one slip event (bytes, uncompressed: an upper
// bound): its "before" and "after" states, and, for the slips that record one, its relaxation
// path (at most max_path_frames frames). For the disk check before a run.
struct SnapshotBytes {
  double frame = 0.0;       // one frame of the block
  double slip = 0.0;        // a slip without its path
  double path = 0.0;        // the path of a slip that records one
  double checkpoint = 0.0;  // the checkpoint (the states the slide keeps, no frames)
  // A slide through `slips` slip events: the start and the peak, the slips, the paths of those
  // that record one, and the checkpoint.
  [[nodiscard]] double run(int slips, int path_frame_slips) const;
};
SnapshotBytes estimated_snapshot_bytes(const SlideScene& scene);

// Refuses (std::invalid_argument, naming the estimate) a slide whose outputs would not fit on
// the disk of `out`: the estimate of SnapshotBytes::run for max(10, slips_to_stop) slip events.
// Returns a line that says what a slip event writes.
std::string check_output_fits(const SlideScene& scene, const std::string& out);

// summary.json contents: parameters, results, cost and accuracy (tolerances, steps, grid).
nlohmann::json slide_summary(const SlideScene& scene, const slide::SlideResult& result);

// What write_slide_outputs writes besides trace.csv and summary.json. A sweep of many points
// skips the figures (a gnuplot process each) and the snapshots (megabytes per point) by default.
struct SlideOutputOptions {
  bool figures = true;  // trace.png, stress_profiles.png, stress_map.png
  // snapshots/<label>.nc and snapshots/paths.nc (snapshot_sink.hpp) from the frames the slide
  // collected (SlideResult::snapshots); a slide whose frames went to a SnapshotSink has none,
  // its files are written already.
  bool snapshots = true;
  // Entries added to (or replacing those of) summary.json and the snapshots' attributes: the
  // explicit model's {"model": "explicit", G in eps/sigma^3, ...}. Null: none.
  nlohmann::json summary_extra;
};

// One line on a slide in progress (SlideControl::progress): where it is, its friction now and
// the largest so far, what it has cost and what it relaxes now, e.g. "Dx = 4.6250 d of at most
// 9.12 d, 0 slip events, 25 steps, Fx/Fz 0.03412 (largest 0.03412), 801 GF, 5.3 min; relaxing
// the slip at Dx = 4.6260 d, iteration 3200".
std::string describe_progress(const slide::SlideProgressInfo& info);

// How a long run reports and saves itself: not a result's setting (left out of fingerprints, so
// a run continues its checkpoint whatever they are), one description for contact_slide's and
// friction_sweep's flags (--checkpoint-every, --progress-every).
struct RunControl {
  double checkpoint_every = 300.0;  // s of run time between checkpoints (0: every step)
  double progress_every = 60.0;     // s between progress lines of a running point (0: none)

  static const settings::Table<RunControl>& settings();
};

// Which progress reports get a line: the first, then one when `every_s` seconds of the slide's
// wall time have passed since the last line, and (each_slip) one at every new slip event.
class ProgressLines {
 public:
  explicit ProgressLines(double every_s, bool each_slip = false)
      : every_s_(every_s), each_slip_(each_slip) {}
  bool due(const slide::SlideProgressInfo& info);

 private:
  double every_s_;
  bool each_slip_;
  double last_s_ = -1.0;  // wall time of the last line (s); < 0: none yet
  int last_slips_ = 0;
};

// Writes trace.csv, summary.json and, as `options` asks, the figures and the NetCDF snapshots
// into dir. Returns the list of files written (figures first). The NetCDF library is not
// thread-safe: callers running points in parallel serialise calls that write snapshots.
std::vector<std::filesystem::path> write_slide_outputs(const std::filesystem::path& dir,
                                                       const SlideScene& scene,
                                                       const slide::SlideResult& result,
                                                       const SlideOutputOptions& options = {});

// The explicit atomistic model (MODEL.md 4, contact_slide --model explicit): the slide-scene
// keys, of which contact.a sets the target load (the Hertz load of a, so that the two models
// are compared at the same load) and contact.R the tip radius, plus [explicit] G (substrate shear
// modulus in eps/sigma^3) and sigma_over_d. contact.alpha is not used: alpha is a property of
// the potential (alpha_path). data/scenes/explicit_default.toml documents the keys.
struct ExplicitSlideScene {
  SlideScene slide;
  explicit_model::ExplicitScene model;
};
ExplicitSlideScene read_explicit_scene(const std::string& path, bool check_slips = true);
// The explicit model has its own interface (the tip's potential): throws std::invalid_argument,
// naming `source`, unless contact.envelope is "hertz" (whose load sets the explicit target).
void check_explicit_envelope(const interface::ContactScene& contact, const std::string& source);

// alpha of the potential at the central atom's Hertz load p0 d^2 of contact.a (alpha_path; nearly
// load independent): the alpha that mu/alpha and a/b_core^0 of the explicit model refer to.
// NaN if the single atom cannot hold that load.
struct ExplicitAlpha {
  double alpha = 0.0;         // largest slope of the minimum-energy height profile
  double alpha_force = 0.0;   // largest Fx/Fz along it
  double centre_force = 0.0;  // the load it was computed at (eps/sigma)
};
ExplicitAlpha explicit_alpha(const ExplicitSlideScene& scene);

// Sliding of the explicit model at the Hertz load of contact.a (explicit/explicit_slide.hpp),
// with the scene's slide options; `alpha` from explicit_alpha(); `control` as in slide::slide
// (progress, checkpoints, stop requests, resume).
slide::SlideResult slide_explicit_scene(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha,
                                        const slide::SlideControl& control = {});
// The SlideScene and output options under which write_slide_outputs writes an explicit slide:
// contact.alpha = alpha of the potential, summary_extra naming the model and its parameters.
SlideScene explicit_as_slide_scene(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha);
nlohmann::json explicit_summary_extra(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha);

// Normal loading of the explicit model: summary.json (parameters, load, Hertz comparison,
// alpha of the potential at the central load, cost), sites.csv (per atom: position, displacement,
// force, pressure), pressure_profile.png (p / p0 against r / a with Hertz),
// displacement_profile.png (u_z along x through the apex with the Hertz surface), and
// pressure_map.png. Returns the files written (figures first).
std::vector<std::filesystem::path> write_explicit_load_outputs(
    const std::filesystem::path& dir, const ExplicitSlideScene& scene,
    const explicit_model::LoadResult& result, const SlideOutputOptions& options = {});

}  // namespace asperity::app
