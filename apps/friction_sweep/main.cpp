// friction_sweep: static friction of the lateral force model (MODEL.md sections 3 and 5), and
// with sweep.model = "explicit" or "both" of the explicit atomistic model (MODEL.md 4), over
// many (a, R) points, run in parallel. Reads a sweep scene (default:
// data/scenes/sweep_default.toml), lets flags override it, and writes into the output directory
// - sweep.csv: one row per point, sorted by R then a, rewritten after every finished point, so
//   that an interrupted sweep loses only the points in flight; a later run with the same
//   settings reuses its rows instead of recomputing them;
// - points/a<a>_R<R>/: summary.json and trace.csv of each point (with --figures, also the
//   figures and snapshots of contact_slide; with --largest-slip, largest_slip/ with the states
//   before and after the point's largest slip, those of its latest slip, its peak state and
//   slips.csv, the loops after each slip, with its figures slips.png and slips_loops.png; with
//   --peek, run beside or after the sweep, peek/ with the states its checkpoint holds);
// - summary.json: settings, counts and the log-log slope of mu/alpha in Regime II; wall times
//   and provenance under "run" (the rest is the same for the same sweep);
// - mu_vs_a_over_bcore0.png and kinetic_over_static.png;
// - with the explicit model: sweep_explicit.csv (same columns), points/explicit_a<a>_R<R>/,
//   collapse.png (mu/alpha of both models against a/b_core^0) and, in summary.json,
//   "explicit_vs_lfm" (the ratio at each explicit point, the largest deviation in
//   a/b_core^0 in [0.1, 10]).
// Under mpirun the points run over the ranks, one point per rank at a time (or --jobs per rank),
// and rank 0 writes the same files (apps/common/mpi_points.hpp).
// The points run in runner.cpp, the report is written by report.cpp; this file wires the flags.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/cli_checks.hpp"
#include "asperity/apps/common/mpi_points.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "runner.hpp"
#include "sweep.hpp"

using namespace asperity;

namespace {

// The slide-scene keys a sweep scene takes, with their flags: all but the points' own.
std::vector<std::string> sweep_slide_keys() {
  const auto& skip = app::SweepScene::point_keys();
  std::vector<std::string> keys;
  for (const auto& s : app::SlideScene::settings()) {
    if (std::find(skip.begin(), skip.end(), s.key) == skip.end()) keys.push_back(s.key);
  }
  return keys;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main_over_ranks(argc, argv, [](int argc_, char** argv_, app::Ranks& ranks) {
    CLI::App cli{"Static friction of the lateral force model over many (a, R) points"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/sweep_default.toml";
    app::SweepRunOptions o{.out = "results/friction_sweep"};
    std::string out = o.out.string();
    cli.add_option("scene", scene_path, "Sweep scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    // --R, --a, --a-over-bcore0, --jobs: from the sweep's settings table; --alpha, --tolerance,
    // --threads, --distance, ...: from the slide scene's, but for contact.a and contact.R, which
    // the points set.
    app::SettingFlags flags;
    flags.add(cli, app::SweepScene::settings());
    flags.add(cli, app::SlideScene::settings(), sweep_slide_keys());
    auto* figures_opt =
        cli.add_flag("--figures", o.figures,
                     "Per point also the figures and NetCDF snapshots (as contact_slide)");
    cli.add_flag("--largest-slip", o.largest_slip,
                 "Per point keep the states before and after its largest slip (most slipped "
                 "sites), the states around its latest slip (replaced at every slip: a long "
                 "point can be looked at while it runs) and the peak state, as NetCDF in "
                 "points/<point>/largest_slip/ (for track_loops): two pairs of frames however "
                 "many slips; and slips.csv there, a row per slip with the loops its state "
                 "holds (number, area, screw fraction, slipped area) and the slide's cost so far "
                 "(GF applications, wall time), drawn in slips.png (mu/alpha before and after "
                 "each slip, against its value before the first) and slips_loops.png (the "
                 "loops' and the slipped area)")
        ->excludes(figures_opt);
    cli.add_flag("--adopt", o.adopt,
                 "Continue checkpoints and keep finished rows of another build, or of other "
                 "slide.*, solver.* and fft.* settings of the same problem (a long run carried "
                 "over to a new build, or given a longer distance); each adoption is recorded "
                 "in points/<point>/adopted.json and the adopted file kept beside it; a lower "
                 "bound stopped at slide.max_distance or slide.max_slips continues from the "
                 "checkpoint it kept (checkpoint.capped.cbor) when these settings raise the limit");
    cli.add_flag("--plan", o.plan,
                 "Only print what the sweep would do: its points with a/b_core^0 and the memory "
                 "each slide needs, which rows an existing table in --out would keep, and "
                 "which points would continue from a checkpoint; runs and writes nothing");
    auto* peek_opt = cli.add_flag(
        "--peek", o.peek,
        "Only write the states the checkpoints of the points in --out hold, as NetCDF in "
        "points/<point>/peek/ (for track_loops): accepted.nc (the last accepted state), peak.nc "
        "and, inside a slip, flow.nc (where its paused flow stands, with the sites slipped so "
        "far); reads while the sweep runs, runs nothing");
    peek_opt->excludes("--plan");
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    const app::RunControl control_defaults;
    flags.add(cli, app::RunControl::settings(), {}, "setting", &control_defaults);
    // A sweep scene is a slide scene without contact.a and contact.R (its points set them) and
    // the [sweep] and [explicit] tables.
    app::add_list_settings(
        cli,
        [] {
          return app::settings_markdown(app::SlideScene{}, app::SlideScene::settings(),
                                        app::SweepScene::point_keys()) +
                 app::settings_markdown(app::SweepScene{}, app::SweepScene::settings(), {}, false);
        },
        "docs/settings.md", "scene key");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    app::SweepScene s = app::read_sweep_scene(scene_path, false);  // slips checked after flags
    // A list on the command line replaces the scene's, and --a or --a-over-bcore0 the other.
    const bool a_given = flags.given("sweep.a"), x_given = flags.given("sweep.a_over_bcore0");
    if (a_given && x_given) {
      throw std::invalid_argument("--a and --a-over-bcore0: give one of them");
    }
    if (a_given) s.a_over_bcore0.reset();
    if (x_given) s.a.reset();
    // One tip for every point (--tip-angle) replaces the scene's list, and a list (--tip-angles)
    // the scene's one value; both flags at once are refused, as both keys in a scene are.
    for (const auto& [one, list, one_flag, list_flag] :
         {std::tuple{"contact.tip_angle", "sweep.tip_angle", "--tip-angle", "--tip-angles"},
          std::tuple{"contact.tip_mismatch", "sweep.tip_mismatch", "--tip-mismatch",
                     "--tip-mismatches"}}) {
      if (flags.given(one) && flags.given(list)) {
        throw std::invalid_argument(std::string(one_flag) + " and " + list_flag +
                                    ": give one of them (one value for every point, or a list)");
      }
    }
    if (flags.given("contact.tip_angle")) s.tip_angle.reset();
    if (flags.given("contact.tip_mismatch")) s.tip_mismatch.reset();
    flags.apply(app::SweepScene::settings(), s);
    flags.apply(app::RunControl::settings(), o.control);
    flags.apply(app::SlideScene::settings(), s.base);
    app::apply_slip_flags(s.base, flags, scene_path);
    s.base.contact.validate();
    s.base.options.validate();
    s.validate();  // the relations of the sweep with the slide's keys (--envelope, sweep.model)
    o.out = out;
    o.command_line = app::command_line(argc_, argv_);
    if (ranks.distributed()) {
      o.command_line = "mpirun -np " + std::to_string(ranks.size()) + " " + o.command_line;
    }
    return app::run_sweep(s, o, ranks);
  });
}
