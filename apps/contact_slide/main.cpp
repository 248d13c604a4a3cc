// contact_slide: quasi-static sliding of a sphere on a crystalline flat in the lateral force
// model (MODEL.md sections 3 and 5). Reads a scene (default: data/scenes/default.toml), lets
// flags override it, and writes trace.csv, summary.json, figures and NetCDF snapshots.
//
// Checkpoints: the state of the slide goes to <out>/checkpoint.cbor every --checkpoint-every
// seconds, on SIGINT or SIGTERM (then the run exits with status 3 and prints how to resume) and
// on a numerical failure (the last good state). --resume continues from it to the same result,
// bit for bit, as an uninterrupted run; a finished run removes it. Both models.
//
// --model explicit: the explicit atomistic model (MODEL.md 4; core/explicit/; default scene
// data/scenes/explicit_default.toml): normal loading to the Hertz load of contact.a (outputs of
// app::write_explicit_load_outputs); with --slide, then sliding at fixed Fz with the same
// protocols and outputs as the LFM (the loading's outputs then go to <out>/loading).
//
// Over MPI (issue 26): `mpirun -np N contact_slide ...` spreads one LFM contact over N ranks
// (slabs of the FFT grid, each rank the block rows and contact sites of its slab); rank 0 reads
// and writes everything and prints, the other ranks compute their part silently. Checkpoints
// hold every row, so a run resumes on any number of ranks. The explicit model runs on one
// process.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/cli_checks.hpp"
#include "asperity/apps/common/memory.hpp"
#include "asperity/apps/common/mpi_session.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/apps/common/snapshot_sink.hpp"

using namespace asperity;

namespace {

// What a checkpointed slide left: the result, and the checkpoints written.
struct CheckpointedSlide {
  slide::SlideResult result;
  std::filesystem::path checkpoint_file;
  int checkpoints = 0;
  double checkpoint_s = 0.0;  // wall time spent writing them
};

// A slide of either model with checkpoints in <out>/checkpoint.cbor under `settings` (its
// fingerprint), resumed from that file with `resume`, its frames streamed to <out>/snapshots
// (snapshot_sink.hpp) as they are made. Stop handlers must be installed. An interrupted slide
// prints how to continue; a finished one is the caller's to write out (it removes the checkpoint
// after its outputs).
CheckpointedSlide run_checkpointed(
    const std::string& out, const std::string& settings, bool resume, bool adopt,
    double checkpoint_every, app::SnapshotSink& frames,
    const std::function<slide::SlideResult(const slide::SlideControl&)>& run, int argc, char** argv,
    const slide::SlideParallel& parallel = {}) {
  CheckpointedSlide c;
  c.checkpoint_file = std::filesystem::path(out) / "checkpoint.cbor";
  std::optional<app::SlideCheckpoint> start;
  if (resume) {
    if (!std::filesystem::exists(c.checkpoint_file)) {
      throw std::invalid_argument("--resume: no checkpoint " + c.checkpoint_file.string() +
                                  ": nothing to resume (run without --resume to start)");
    }
    start = app::read_checkpoint(c.checkpoint_file);
    if (const auto adoption =
            app::check_or_adopt_checkpoint(*start, settings, c.checkpoint_file, adopt)) {
      std::fprintf(stderr, "contact_slide: %s\n",
                   app::record_adoption(c.checkpoint_file, *start, *adoption).c_str());
    }
  }
  const bool tty = isatty(2) != 0;
  // On a terminal the line is rewritten 5 times a second; in a log (no terminal) a line at each
  // slip event and otherwise every 10 s, also from inside a long relaxation (the automatic
  // distance is capped generously, so fractions of the cap say little).
  const auto progress = [tty, lines = app::ProgressLines(tty ? 0.2 : 10.0, !tty)](
                            const slide::SlideProgressInfo& info) mutable {
    if (!lines.due(info)) return;
    std::fprintf(stderr, tty ? "\r  %s\033[K" : "  %s\n", app::describe_progress(info).c_str());
  };
  app::ensure_directory(out);
  if (const std::size_t n = app::remove_stale_temporaries(out)) {
    std::fprintf(stderr, "contact_slide: removed %zu temporary file%s left by a killed run\n", n,
                 n > 1 ? "s" : "");
  }
  if (const std::string warning =
          frames.start(start ? std::optional(start->state.current.Dx) : std::nullopt);
      !warning.empty()) {
    std::fprintf(stderr, "contact_slide: %s\n", warning.c_str());
  }
  if (start) {
    std::fprintf(stderr, "contact_slide: resuming from %s at Dx = %.4f d (%d steps done)\n",
                 c.checkpoint_file.c_str(), start->state.current.Dx, start->state.partial.steps);
  } else if (std::filesystem::exists(c.checkpoint_file)) {
    std::fprintf(stderr,
                 "contact_slide: starting over; the checkpoint %s of an earlier run will be "
                 "replaced (--resume continues it)\n",
                 c.checkpoint_file.c_str());
  }
  slide::SlideControl control{
      .progress = progress,
      .checkpoint =
          [&](const slide::SlideState& state) {
            const auto t = std::chrono::steady_clock::now();
            frames.flush();  // the checkpoint must not count frames that are not on disk
            app::write_checkpoint(c.checkpoint_file, {.settings = settings, .state = state});
            c.checkpoint_s +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
            ++c.checkpoints;
          },
      .checkpoint_every_s = checkpoint_every,
      .stop_requested = app::stop_requested,
      .start = start ? &start->state : nullptr,
      .frames = &frames,
      .parallel = parallel};
  c.result = run(control);
  if (tty) std::fprintf(stderr, "\n");
  if (c.result.interrupted) {
    frames.flush();  // the partial paths file, for the resumed run
  } else {
    frames.finish();
  }
  if (c.result.interrupted) {
    std::fprintf(stderr,
                 "contact_slide: %s; state saved in %s (%d checkpoint%s, %.2f s)\n"
                 "continue with:\n  %s\n",
                 c.result.stop_reason.c_str(), c.checkpoint_file.c_str(), c.checkpoints,
                 c.checkpoints == 1 ? "" : "s", c.checkpoint_s,
                 app::command_line(argc, argv, "--resume").c_str());
  }
  return c;
}

// After the outputs of a finished slide: nothing is left to resume (a failed one keeps its
// last good state).
void finish_checkpoints(const CheckpointedSlide& c) {
  if (!c.result.failed) {
    std::error_code ec;
    std::filesystem::remove(c.checkpoint_file, ec);
  }
  if (c.checkpoints > 0) {
    std::fprintf(stderr, "contact_slide: %d checkpoint%s written, %.3f s\n", c.checkpoints,
                 c.checkpoints == 1 ? "" : "s", c.checkpoint_s);
  }
}

// The frames of a rank other than the root of a distributed slide: it hands its rows to the
// root inside the slide and keeps nothing, but wants paths exactly when the root's sink does
// (the slide makes path frames collectively).
class FollowerFrames final : public slide::FrameSink {
 public:
  explicit FollowerFrames(bool wants_paths) : wants_paths_(wants_paths) {}
  void state(const slide::Snapshot& /*frame*/) override {}
  void path_frame(const slide::Snapshot& /*frame*/) override {}
  void replayed_path(const std::string& /*source*/, int /*periods*/, double /*period*/,
                     const std::string& /*label*/) override {}
  [[nodiscard]] bool wants_paths() const override { return wants_paths_; }

 private:
  bool wants_paths_;
};

// What every kind of run of contact_slide takes from its command line.
struct Run {
  std::string scene_path, out;
  bool scene_given = false;  // a scene file was named (else the model's default scene)
  bool resume = false;
  bool adopt = false;  // --adopt: the checkpoint may be of another build or numerical settings
  bool plan = false;   // --plan: read, validate and describe the run, then stop
  double checkpoint_every = app::RunControl{}.checkpoint_every;
  const app::SettingFlags* flags = nullptr;
  int argc = 0;
  char** argv = nullptr;
  const app::MpiSession* mpi = nullptr;
};

// The flags over an explicit scene: the tip's radius and lattice and the substrate's Poisson
// ratio are the contact's.
void apply_explicit_flags(const Run& run, app::ExplicitSlideScene& e) {
  run.flags->apply(app::SlideScene::settings(), e.slide);
  if (run.flags->given("contact.R")) e.model.R = e.slide.contact.R;
  if (run.flags->given("material.nu")) e.model.material.nu = e.slide.contact.material.nu;
  e.model.tip = e.slide.contact.tip;  // the scene's, or --tip-angle and --tip-mismatch
}

// The lines that say where a run's results and figures are.
void print_outputs(const std::string& out, const std::vector<std::filesystem::path>& files) {
  std::printf("results: %s\nfigures:", (std::filesystem::path(out) / "summary.json").c_str());
  for (const auto& f : files) {
    if (f.extension() == ".png") std::printf(" %s", f.c_str());
  }
  std::printf("\n");
}

// The scene of an explicit run with the flags over it: the named file, or the explicit model's
// default (which run.scene_path then names, for messages).
app::ExplicitSlideScene explicit_scene(Run& run) {
  if (!run.scene_given) run.scene_path = ASPERITY_DATA_DIR "/scenes/explicit_default.toml";
  app::ExplicitSlideScene e = app::read_explicit_scene(run.scene_path, false);
  apply_explicit_flags(run, e);
  app::check_explicit_envelope(e.slide.contact, "--model explicit");
  return e;
}

// --plan: the scene and flags were read and validated and the run described; nothing ran.
int plan_done(const Run& run) {
  std::printf("contact_slide --plan: the scene and flags are valid; output %s (not written)\n",
              run.out.c_str());
  return 0;
}

// The explicit model's normal loading alone, compared with Hertz (MODEL.md 4).
int explicit_loading(Run run) {
  app::ExplicitSlideScene e = explicit_scene(run);
  auto& c = e.slide.contact;
  c.validate();
  e.model.validate();
  explicit_model::require_small_slope(c.a, c.R);
  const double load = c.hertz().load;
  std::fprintf(stderr,
               "contact_slide: explicit model, Hertz a = %g d (Fz = %g G d^2 = %g eps/sigma), "
               "R = %g d, G = %g eps/sigma^3, sigma/d = %g, nu = %g; normal loading\n",
               c.a, load, load / e.model.force_unit(), c.R, e.model.G_eps_sigma3,
               e.model.sigma_over_d, c.material.nu);
  if (run.plan) return plan_done(run);
  explicit_model::LoadOptions lo{.load = load};
  lo.minimizer = e.slide.options.minimizer;
  lo.fft = e.slide.options.fft;
  const auto r = explicit_model::load_to_force(e.model, lo);
  const auto files = app::write_explicit_load_outputs(run.out, e, r);
  std::printf(
      "Fz = %.6g G d^2 (target %.6g), delta = %.5f d (Hertz %.5f, %+.2f%%; load at delta "
      "%+.2f%%), contact radius %.2f d from the area, %.2f d from <r^2> (Hertz %.2f d)\n",
      r.state.Fz, r.target, r.delta, r.hertz.approach, 100.0 * r.delta_error, 100.0 * r.load_error,
      r.state.a_area, r.state.a_moment, r.hertz.a);
  std::printf("%s: %d load steps, %d minimisations, %d growths, %zu GF applications, %.2f s\n",
              to_string(r.termination).c_str(), r.load_steps, r.minimizations, r.growths,
              r.gf_applications, r.wall_s);
  print_outputs(run.out, files);
  if (r.termination != Termination::converged) {
    std::fprintf(stderr, "contact_slide: FAILED: %s\n", r.message.c_str());
    return 1;
  }
  return 0;
}

// The explicit model loaded to the Hertz load of contact.a, then slid at fixed Fz with the LFM's
// protocols (explicit/explicit_slide.hpp). alpha is a property of the potential.
int explicit_sliding(Run run) {
  app::ExplicitSlideScene e = explicit_scene(run);
  auto& c = e.slide.contact;
  app::apply_slip_flags(e.slide, *run.flags, run.scene_path);
  c.validate();
  e.model.validate();
  e.slide.options.validate();
  explicit_model::require_small_slope(c.a, c.R);
  const double load = c.hertz().load;
  const app::ExplicitAlpha alpha_p = app::explicit_alpha(e);
  std::fprintf(stderr,
               "contact_slide: explicit model, Hertz a = %g d (Fz = %g G d^2 = %g eps/sigma), "
               "R = %g d, G = %g eps/sigma^3, sigma/d = %g, nu = %g; alpha of the potential "
               "%.4f (max Fx/Fz %.4f): a/b_core^0 = %.3g; %s protocol, tolerance %g\n",
               c.a, load, load / e.model.force_unit(), c.R, e.model.G_eps_sigma3,
               e.model.sigma_over_d, c.material.nu, alpha_p.alpha, alpha_p.alpha_force,
               app::explicit_as_slide_scene(e, alpha_p).contact.a_over_bcore0(),
               slide::to_string(e.slide.options.protocol).c_str(),
               e.slide.options.minimizer.force_tolerance);
  if (run.plan) return plan_done(run);
  const std::string settings = app::explicit_slide_fingerprint(e, alpha_p);
  if (run.resume) {
    // A missing or foreign checkpoint is reported before the loading, not after it.
    const auto file = std::filesystem::path(run.out) / "checkpoint.cbor";
    if (!std::filesystem::exists(file)) {
      throw std::invalid_argument("--resume: no checkpoint " + file.string() +
                                  ": nothing to resume (run without --resume to start)");
    }
    app::check_or_adopt_checkpoint(app::read_checkpoint(file), settings, file, run.adopt);
  }
  // Normal loading alone, with its comparison to Hertz, in <out>/loading.
  explicit_model::LoadOptions lo{.load = load};
  lo.minimizer = e.slide.options.minimizer;
  lo.fft = e.slide.options.fft;
  const auto lr = explicit_model::load_to_force(e.model, lo);
  app::write_explicit_load_outputs(std::filesystem::path(run.out) / "loading", e, lr);
  std::printf(
      "loading: Fz = %.6g G d^2, delta = %.5f d (Hertz %.5f, %+.2f%%; load at delta "
      "%+.2f%%), contact radius %.2f d from the area, %.2f d from <r^2> (Hertz %.2f d); "
      "%zu GF applications, %.2f s\n",
      lr.state.Fz, lr.delta, lr.hertz.approach, 100.0 * lr.delta_error, 100.0 * lr.load_error,
      lr.state.a_area, lr.state.a_moment, lr.hertz.a, lr.gf_applications, lr.wall_s);
  if (lr.termination != Termination::converged) {
    std::fprintf(stderr, "contact_slide: loading FAILED: %s\n", lr.message.c_str());
    return 1;
  }
  // A stop asked during the loading (which does not poll) is honoured at the slide's
  // first step, which checkpoints the loaded state: the run resumes from there.
  const app::SlideScene as_slide = app::explicit_as_slide_scene(e, alpha_p);
  app::SnapshotSink frames(
      std::filesystem::path(run.out) / "snapshots",
      app::snapshot_attributes(as_slide, app::explicit_summary_extra(e, alpha_p)),
      e.slide.snapshot_format);
  const CheckpointedSlide slid = run_checkpointed(
      run.out, settings, run.resume, run.adopt, run.checkpoint_every, frames,
      [&](const slide::SlideControl& control) {
        return app::slide_explicit_scene(e, alpha_p, control);
      },
      run.argc, run.argv);
  const slide::SlideResult& r = slid.result;
  if (r.interrupted) return app::kInterrupted;
  const auto files = app::write_slide_outputs(
      run.out, as_slide, r, {.summary_extra = app::explicit_summary_extra(e, alpha_p)});
  finish_checkpoints(slid);
  std::printf(
      "mu = %.6f, mu/alpha = %.5f%s (alpha %.4f, max Fx/Fz of one atom %.4f; peak at Dx = "
      "%.4f d, precision %.1e), kinetic/static = %.3f, slip events %d\n",
      r.mu, r.mu_over_alpha, r.mu_is_lower_bound ? " (lower bound)" : "", alpha_p.alpha,
      alpha_p.alpha_force, r.peak_Dx, r.peak_precision, r.kinetic_over_static, r.slip_events);
  std::printf(
      "stopped: %s at Dx = %.4f d; %d steps, %d minimisations, %zu GF applications, %.2f s\n",
      r.stop_reason.c_str(), r.distance, r.steps, r.minimizations, r.gf_applications, r.wall_s);
  print_outputs(run.out, files);
  if (r.failed) {
    // A failure in the first step leaves no good state to keep.
    std::fprintf(stderr, "contact_slide: FAILED: %s\n", r.stop_reason.c_str());
    if (slid.checkpoints > 0) {
      std::fprintf(stderr, "  the last good state is in %s\n", slid.checkpoint_file.c_str());
    }
  }
  return r.failed ? 1 : 0;
}

// A rank other than the root of a distributed LFM slide: the same slide with the same control
// (every callback set, as on the root: the slide decides stops and checkpoints together), and
// nothing read but the checkpoint to resume from, nothing written.
int follow_lfm_slide(const Run& run, const app::SlideScene& s,
                     const slide::SlideParallel& parallel) {
  std::optional<app::SlideCheckpoint> start;
  if (run.resume) start = app::read_checkpoint(std::filesystem::path(run.out) / "checkpoint.cbor");
  // The root's sink (app::SnapshotSink) wants paths.
  FollowerFrames frames(true);
  const slide::SlideControl control{.progress = [](const slide::SlideProgressInfo&) {},
                                    .checkpoint = [](const slide::SlideState&) {},
                                    .checkpoint_every_s = run.checkpoint_every,
                                    .stop_requested = app::stop_requested,
                                    .start = start ? &start->state : nullptr,
                                    .frames = &frames,
                                    .parallel = parallel};
  const slide::SlideResult r = slide::slide(s.contact, s.options, control);
  return r.interrupted ? app::kInterrupted : r.failed ? 1 : 0;
}

// The lateral force model's slide (MODEL.md 3, 5).
int lfm_sliding(const Run& run) {
  app::SlideScene s = app::read_slide_scene(run.scene_path, false);
  run.flags->apply(app::SlideScene::settings(), s);
  app::apply_slip_flags(s, *run.flags, run.scene_path);
  const auto method = s.options.minimizer.method;
  if (s.options.minimizer.preconditioner == minimize::Preconditioner::interface &&
      (method == minimize::Method::cg || method == minimize::Method::fire)) {
    std::fprintf(stderr,
                 "contact_slide: note: the interface filter is used by lbfgs and newton only; "
                 "%s preconditions with G\n",
                 minimize::to_string(method).c_str());
  }
  s.contact.validate();
  s.options.validate();
  char a_text[64];
  std::snprintf(a_text, sizeof a_text, "contact.a = %g d", s.contact.a);
  const int ranks = run.mpi->size();
  const double memory = slide::estimated_slide_bytes(s.contact, s.options, ranks);
  // The ranks on this machine share its memory.
  app::check_fits_in_memory(a_text, memory * app::launcher_local_ranks(),
                            ranks > 1 ? "estimate per rank times the ranks on this machine: 260 "
                                        "bytes per point of the rank's slab of the padded FFT "
                                        "grid, the minimiser's vectors on its contact sites and "
                                        "the frames of one relaxation path"
                                      : "estimate: 260 bytes per point of the padded FFT grid of "
                                        "the block, the minimiser's vectors on the contact and "
                                        "the frames of one relaxation path");
  const slide::SlideParallel parallel{.engine = run.mpi->engine(), .comm = &run.mpi->comm()};
  if (run.plan && !run.mpi->root()) return 0;
  if (!run.mpi->root()) return follow_lfm_slide(run, s, parallel);
  const std::string output_line = app::check_output_fits(s, run.out);

  std::fprintf(stderr,
               "contact_slide: %s envelope, a = %g d, R = %g d, alpha = %g, tau0 = %g G, nu = %g: "
               "a/b_core^0 = %.3g, lambda = %.3g; %s protocol, %s (preconditioner %s), "
               "tolerance %g\n",
               s.contact.envelope.c_str(), s.contact.a, s.contact.R, s.contact.alpha,
               s.contact.tau0, s.contact.material.nu, s.contact.a_over_bcore0(), s.contact.lambda(),
               slide::to_string(s.options.protocol).c_str(),
               minimize::to_string(s.options.minimizer.method).c_str(),
               minimize::to_string(s.options.minimizer.preconditioner).c_str(),
               s.options.minimizer.force_tolerance);
  if (ranks > 1) {
    std::fprintf(stderr,
                 "contact_slide: over %d MPI ranks: memory about %.3g MB on the fullest rank, "
                 "whatever the number of slips; %s\n",
                 ranks, memory / 1e6, output_line.c_str());
  } else {
    std::fprintf(stderr, "contact_slide: memory about %.3g MB, whatever the number of slips; %s\n",
                 memory / 1e6, output_line.c_str());
  }
  if (run.plan) return plan_done(run);
  app::SnapshotSink frames(std::filesystem::path(run.out) / "snapshots",
                           app::snapshot_attributes(s, nullptr), s.snapshot_format);
  const CheckpointedSlide slid = run_checkpointed(
      run.out, app::slide_fingerprint(s), run.resume, run.adopt, run.checkpoint_every, frames,
      [&](const slide::SlideControl& control) {
        return slide::slide(s.contact, s.options, control);
      },
      run.argc, run.argv, parallel);
  const slide::SlideResult& r = slid.result;
  if (r.interrupted) return app::kInterrupted;
  // The processes the contact was spread over (1: one process).
  const auto files =
      app::write_slide_outputs(run.out, s, r, {.summary_extra = {{"mpi_ranks", ranks}}});
  finish_checkpoints(slid);

  // Friction as the envelope defines it: mu where there is a load, the friction stress where
  // there is none (adhesive: mu undefined), and tau_fric/tau0 where tau0 enters.
  char friction[160];
  if (s.contact.carries_load()) {
    std::snprintf(friction, sizeof friction, "mu = %.6f, mu/alpha = %.5f", r.mu, r.mu_over_alpha);
  } else {
    std::snprintf(friction, sizeof friction, "tau_fric = Fx/A = %.6g G (mu undefined: no load)",
                  r.tau_fric);
  }
  std::string friction_line = friction;
  if (s.contact.uses_tau0() && s.contact.tau0 > 0.0) {
    std::snprintf(friction, sizeof friction, ", tau_fric/tau0 = %.5f (A = %.6g d^2)",
                  r.tau_fric / s.contact.tau0, r.area);
    friction_line += friction;
  }
  std::printf("%s%s (peak at Dx = %.4f d, precision %.1e), kinetic/static = %.3f, slip events %d\n",
              friction_line.c_str(), r.mu_is_lower_bound ? " (lower bound)" : "", r.peak_Dx,
              r.peak_precision, r.kinetic_over_static, r.slip_events);
  std::printf(
      "stopped: %s at Dx = %.4f d; %d steps, %d minimisations, %zu GF applications + %zu "
      "interface filter passes, %.2f s\n",
      r.stop_reason.c_str(), r.distance, r.steps, r.minimizations, r.gf_applications,
      r.filter_applications, r.wall_s);
  if (r.replayed_steps > 0) {
    std::printf(
        "cycle repeated at Dx = %.4f d (largest force difference %.1e G d^2): %d more "
        "rows replayed, not computed\n",
        r.cycle_verified_at, r.cycle_mismatch, r.replayed_steps);
  }
  print_outputs(run.out, files);
  if (r.failed) {
    // A failure in the first minimisation leaves no good state to keep.
    const auto last_good = std::filesystem::path(run.out) / "snapshots" / "last_good.nc";
    std::fprintf(stderr, "contact_slide: FAILED: %s\n", r.stop_reason.c_str());
    if (std::filesystem::exists(last_good)) {
      std::fprintf(stderr, "  the last good state is in %s and %s\n", last_good.c_str(),
                   slid.checkpoint_file.c_str());
    }
  }
  return r.failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<app::MpiSession> mpi;
  const int code = app::run_main(argc, argv, [&mpi](int argc_, char** argv_) {
    mpi = std::make_unique<app::MpiSession>(argc_, argv_);
    CLI::App cli{"Quasi-static sliding of a sphere on a crystalline flat (lateral force model)"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/default.toml";
    std::string out = "results/contact_slide";
    cli.add_option("scene", scene_path, "Scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    // --a, --R, --alpha, --nu, --distance, --protocol, --solver, --slip-solver,
    // --preconditioner, --tolerance, --threads: from the slide scene's settings table.
    app::SettingFlags flags;
    flags.add(cli, app::SlideScene::settings());
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    bool resume = false;
    app::RunControl control;
    auto* resume_opt = cli.add_flag(
        "--resume", resume,
        "Continue the interrupted run whose checkpoint is in the output directory (same "
        "scene and flags)");
    bool plan = false;
    cli.add_flag("--plan", plan,
                 "Only read and validate the scene and flags and say what the run would be (its "
                 "contact, a/b_core^0, memory and output estimates); runs and writes nothing")
        ->excludes(resume_opt);
    bool adopt = false;
    cli.add_flag("--adopt", adopt,
                 "With --resume: continue a checkpoint of another build, or of other slide.*, "
                 "solver.* and fft.* settings of the same problem (a long run carried over to a "
                 "new build, or given a longer distance); recorded in <out>/adopted.json, the "
                 "adopted file kept beside it")
        ->needs(resume_opt);
    // Its progress lines are every 10 s (0.2 s on a terminal), not --progress-every's.
    const app::RunControl control_defaults;
    flags.add(cli, app::RunControl::settings(), {"run.checkpoint_every"}, "setting",
              &control_defaults);
    std::string model = "lfm";
    cli.add_option("--model", model,
                   "lfm (lateral force model) | explicit (LJ atomistic tip, MODEL.md 4)")
        ->check(CLI::IsMember({"lfm", "explicit"}))
        ->capture_default_str();
    bool explicit_slide = false;
    cli.add_flag("--slide", explicit_slide,
                 "--model explicit: after the normal loading, slide at fixed Fz (the LFM's "
                 "protocols and outputs; the loading's outputs go to <out>/loading)");
    app::add_list_settings(cli, app::SlideScene::settings(), app::SlideScene{}, "docs/settings.md",
                           "scene key");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    flags.apply(app::RunControl::settings(), control);
    if (explicit_slide && model != "explicit") {
      throw std::invalid_argument("--slide: only with --model explicit (the LFM always slides)");
    }
    if (mpi->distributed() && model == "explicit") {
      throw std::invalid_argument("--model explicit runs on one process (started on " +
                                  std::to_string(mpi->size()) +
                                  " MPI ranks; the lateral force model runs over ranks)");
    }
    // One run per output directory, for the whole run (its checkpoint is read under the lock);
    // over MPI the root's, which writes.
    std::optional<app::DirectoryLock> dir_lock;
    if (mpi->root() && !plan) dir_lock.emplace(app::ensure_directory(out));
    const Run run{.scene_path = scene_path,
                  .out = out,
                  .scene_given = cli.count("scene") > 0,
                  .resume = resume,
                  .adopt = adopt,
                  .plan = plan,
                  .checkpoint_every = control.checkpoint_every,
                  .flags = &flags,
                  .argc = argc_,
                  .argv = argv_,
                  .mpi = mpi.get()};

    if (model == "explicit" && flags.given("solver.preconditioner")) {
      throw std::invalid_argument(
          "--preconditioner: not available with --model explicit (the interface filter belongs "
          "to the lateral force model; the explicit model preconditions with G)");
    }
    if (model == "explicit" && !explicit_slide) {
      // Normal loading of the explicit model alone (--slide adds the sliding): the flags that
      // only make sense for a slide are rejected rather than ignored.
      for (const auto& [flag, given] :
           {std::pair{"--alpha", flags.given("contact.alpha")},
            std::pair{"--distance", flags.given("slide.distance")},
            std::pair{"--protocol", flags.given("slide.protocol")}, std::pair{"--resume", resume},
            std::pair{"--slip-solver", flags.given("solver.slip_method")}}) {
        if (given) {
          throw std::invalid_argument(
              std::string(flag) +
              ": not available with --model explicit without --slide, which does the normal "
              "loading only (add --slide to slide at fixed Fz; alpha follows from the potential)");
        }
      }
      return explicit_loading(run);
    }
    // From here on a signal only asks the slide to stop (with a checkpoint; inside a relaxation
    // within 16 iterations, else at its next step):
    // installed before a checkpoint is read, so that no signal meets the default action.
    // mpirun kills the ranks a second after SIGINT or SIGTERM, too soon for a checkpoint; it
    // forwards SIGUSR1 to every rank, which then stop together (the slide agrees on stops).
    app::install_stop_handlers();

    if (model == "explicit") {
      // The explicit model: normal loading to the Hertz load of contact.a, then sliding at fixed
      // Fz with the LFM's protocols (explicit/explicit_slide.hpp). alpha is a property of the
      // potential: --alpha is rejected.
      if (flags.given("contact.alpha")) {
        throw std::invalid_argument(
            "--alpha: not available with --model explicit (alpha follows from the potential, "
            "alpha_path at the central load)");
      }
      return explicit_sliding(run);
    }
    return lfm_sliding(run);
  });
  return mpi ? mpi->finish(code) : code;
}
