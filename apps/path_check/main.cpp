// path_check: relaxes one bracketed instability of a slide with every production solver and with
// the reference path, the overdamped flow (MODEL.md 5, core/slide/path.hpp), and says whether
// each ends in the flow's minimum: the same registry index on every contact site and
// |dFx|/Fx <= 1e-4. The flow is also run at half its tolerance (its step control's own check).
// Prints a table and writes <out>/path_check.json.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/cli_checks.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/core/slide/path.hpp"
#include "asperity/tracking/lines.hpp"

using namespace asperity;

namespace {

// "lbfgs/interface", "cg", ... into minimiser options on top of `base`.
minimize::MinimizerOptions parse_solver(const std::string& label,
                                        const minimize::MinimizerOptions& base) {
  minimize::MinimizerOptions m = base;
  const auto at = label.find('@');
  std::string name = label.substr(0, at);
  // "+reset": lbfgs or newton with MinimizerOptions::curvature_reset (experimental).
  if (const auto plus = name.find("+reset"); plus != std::string::npos) {
    m.curvature_reset = true;
    name.erase(plus);
  }
  const auto slash = name.find('/');
  m.method = minimize::method_from_string(name.substr(0, slash));
  m.preconditioner = slash == std::string::npos
                         ? minimize::Preconditioner::automatic
                         : minimize::preconditioner_from_string(name.substr(slash + 1));
  if (at != std::string::npos) {
    std::size_t used = 0;
    const std::string value = label.substr(at + 1);
    m.flow_tolerance = std::stod(value, &used);
    if (used != value.size() || !(m.flow_tolerance > 0.0)) {
      throw std::invalid_argument("--solvers: '" + label + "': the flow tolerance after @");
    }
  }
  return m;
}

nlohmann::json step_json(const slide::StepRelaxation& s) {
  return {{"iterations", s.result.iterations},
          {"gf_applications", s.result.gf_applications},
          {"filter_applications", s.result.filter_applications},
          {"rejected_steps", s.result.rejected_steps},
          {"termination", to_string(s.result.termination)},
          {"max_force", s.result.max_force},
          {"Fx", s.state.Fx},
          {"slipped_sites", s.slipped_sites},
          {"wall_s", s.wall_s}};
}

// Dislocation lines of an end state (MODEL.md 7, tracking/): loops inside the contact and
// lines open at its edge.
struct Loops {
  int loops = 0, open = 0;
  double loop_area = 0.0;  // d^2
};
Loops loops_of(const interface::ContactScene& scene, const slide::SlideFields& state) {
  const auto snap = slide::snapshot_of(scene, state, "end");
  const auto lines = tracking::find_lines(tracking::view_of(snap));
  Loops l;
  for (const auto& line : lines.lines) {
    if (line.kind == tracking::LineKind::loop) {
      ++l.loops;
      l.loop_area += line.area;
    } else if (line.kind == tracking::LineKind::open) {
      ++l.open;
    }
  }
  return l;
}

nlohmann::json loops_json(const Loops& l) {
  return {{"loops", l.loops}, {"loop_area", l.loop_area}, {"open_lines", l.open}};
}

nlohmann::json comparison_json(const slide::StateComparison& c) {
  return {{"sites", c.sites},
          {"registry_differences", c.registry_differences},
          {"relative_Fx", c.relative_Fx},
          {"max_du", c.max_du},
          {"same_minimum", c.same_minimum()}};
}

// One flow relaxation's profile (slide::FlowProfile), a row per accepted step.
std::string profile_csv(const slide::FlowProfile& profile) {
  std::ostringstream o;
  o << "iteration,gf,filter,step,radius,max_speed,max_residual,max_move,moved\n";
  o.precision(6);
  for (const auto& s : profile) {
    o << s.iteration << ',' << s.gf << ',' << s.filter << ',' << s.step << ',' << s.radius << ','
      << s.max_speed << ',' << s.max_residual << ',' << s.max_move << ',' << s.moved << '\n';
  }
  return o.str();
}

// What the check does beyond its slide scene; the solvers compared (--solvers, a list of labels
// with their own grammar, parse_solver()) are not a table row.
struct Check {
  int slip = 1;                       // which slip event of the slide
  int max_iterations = 200000;        // of the solvers compared
  int flow_max_iterations = 2000000;  // of the flow
  bool flow_profile = false;

  static const settings::Table<Check>& settings();
};

const settings::Table<Check>& Check::settings() {
  using R = settings::Range;
  static const settings::Table<Check> table = {
      settings::integer<Check>(
          "check.slip", [](auto& c) -> auto& { return c.slip; }, R::closed(1, 10000), "",
          "which slip event of the slide to check (1: the first)", "--slip"),
      settings::integer<Check>(
          "check.max_iterations", [](auto& c) -> auto& { return c.max_iterations; },
          R::closed(1, 1 << 30), "",
          "iteration budget of the solvers compared (replaces the scene's solver.max_iterations, "
          "which is sized for a slide's steps, not for relaxing a whole slip)",
          "--max-iterations"),
      settings::integer<Check>(
          "check.flow_max_iterations", [](auto& c) -> auto& { return c.flow_max_iterations; },
          R::closed(1, 1 << 30), "", "step budget of the flows", "--flow-max-iterations"),
      settings::neutral(settings::boolean<Check>(
          "check.flow_profile", [](auto& c) -> auto& { return c.flow_profile; },
          "also write each flow's state after every accepted step (GF applications, step, "
          "largest speed and residual, sites moved) to <out>/flow_profile*.csv",
          "--flow-profile"))};
  return table;
}

// The scene's and the check's rows, one listing (--list-settings).
std::string settings_listing() {
  return app::settings_markdown(app::SlideScene{}, app::SlideScene::settings()) +
         app::settings_markdown(Check{}, Check::settings(), {}, false);
}

// "flow/interface@0.01" -> "flow_interface_0.01": a file name.
std::string file_label(std::string label) {
  for (char& c : label) {
    if (c == '/' || c == '@') c = '_';
  }
  return label;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Relax one instability of a slide with every solver and with the reference flow"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/default.toml";
    std::string out = "results/path_check";
    std::vector<std::string> solvers{"lbfgs/auto", "lbfgs/elastic", "cg", "fire", "newton/auto"};
    cli.add_option("scene", scene_path, "Scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    // The slide scene's flags (--a, --R, --alpha, --tolerance, --flow-tolerance, ...), each
    // overriding its key, and the check's own.
    app::SettingFlags flags;
    flags.add(cli, app::SlideScene::settings());
    const Check defaults;
    flags.add(cli, Check::settings(), {}, "summary key", &defaults);
    cli.add_option("--solvers", solvers,
                   "Solvers to compare: method[/preconditioner][@flow tolerance], e.g. "
                   "lbfgs/interface cg flow/interface@1e-2")
        ->capture_default_str();
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    Check check_options;
    app::add_list_settings(cli, settings_listing, "docs/solvers.md", "scene key and setting");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    flags.apply(Check::settings(), check_options);
    const int event = check_options.slip, max_iterations = check_options.max_iterations,
              flow_max_iterations = check_options.flow_max_iterations;
    const bool profile = check_options.flow_profile;
    app::SlideScene s = app::read_slide_scene(scene_path, false);
    flags.apply(app::SlideScene::settings(), s);
    // The bracketing slide relaxes its slips on the flow's path, as every tool's does.
    app::apply_slip_flags(s, flags, scene_path);
    s.options.minimizer.max_iterations = max_iterations;
    s.contact.validate();
    s.options.validate();
    std::vector<minimize::MinimizerOptions> list;
    for (const auto& label : solvers) {
      list.push_back(parse_solver(label, s.options.minimizer));
      if (list.back().method == minimize::Method::flow) {
        list.back().max_iterations = flow_max_iterations;
      }
    }
    app::ensure_directory(out);

    std::fprintf(stderr, "path_check: a = %g d, R = %g d, a/b_core^0 = %.2f; bracketing slip %d\n",
                 s.contact.a, s.contact.R, s.contact.a_over_bcore0(), event);
    const auto at = slide::bracket_slip(s.contact, s.options, event);
    std::fprintf(stderr, "path_check: slip %d bracketed: stable at Dx = %.6f d, slips at %.6f d\n",
                 event, at.stable.Dx, at.slip_Dx);
    const auto check =
        slide::check_path(s.contact, s.options, at, list, flow_max_iterations, true, profile);
    if (profile) {
      app::write_file_atomic(std::filesystem::path(out) / "flow_profile.csv",
                             profile_csv(check.flow_profile));
      for (const auto& row : check.rows) {
        if (row.profile.empty()) continue;
        app::write_file_atomic(
            std::filesystem::path(out) / ("flow_profile_" + file_label(row.solver) + ".csv"),
            profile_csv(row.profile));
      }
    }

    std::printf("%-16s %9s %9s %-10s %8s %9s %12s %9s %6s %s\n", "solver", "iter", "GF+filter",
                "end", "slipped", "reg.diff", "|dFx|/Fx", "max|du|", "same",
                "loops (area d^2), open lines");
    const auto line = [&](const std::string& name, const slide::StepRelaxation& st,
                          const slide::StateComparison* c) {
      const Loops l = loops_of(s.contact, st.state);
      std::printf("%-16s %9d %9zu %-10s %8d %9s %12s %9s %6s %d (%.0f), %d\n", name.c_str(),
                  st.result.iterations, st.result.gf_applications + st.result.filter_applications,
                  to_string(st.result.termination).c_str(), st.slipped_sites,
                  c ? std::to_string(c->registry_differences).c_str() : "-",
                  c ? (std::ostringstream{} << c->relative_Fx).str().c_str() : "-",
                  c ? (std::ostringstream{} << c->max_du).str().c_str() : "-",
                  c ? (c->same_minimum() ? "yes" : "NO") : "ref", l.loops, l.loop_area, l.open);
    };
    line("flow", check.flow, nullptr);
    line("flow (tol/2)", check.flow_half, &check.flow_self);
    for (const auto& row : check.rows)
      line(row.solver, row.step, &row.against_flow);

    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : check.rows) {
      rows.push_back({{"solver", row.solver},
                      {"step", step_json(row.step)},
                      {"lines", loops_json(loops_of(s.contact, row.step.state))},
                      {"against_flow", comparison_json(row.against_flow)}});
    }
    nlohmann::json settings = app::settings_echo(s, app::SlideScene::settings());
    settings.update(app::settings_echo(check_options, Check::settings()));
    settings["check.solvers"] = solvers;
    const nlohmann::json j{{"a", s.contact.a},
                           {"R", s.contact.R},
                           {"alpha", s.contact.alpha},
                           {"a_over_bcore0", s.contact.a_over_bcore0()},
                           {"slip_event", event},
                           {"stable_Dx", at.stable.Dx},
                           {"slip_Dx", at.slip_Dx},
                           {"force_tolerance", s.options.minimizer.force_tolerance},
                           {"flow_tolerance", s.options.minimizer.flow_tolerance},
                           {"flow", step_json(check.flow)},
                           {"flow_lines", loops_json(loops_of(s.contact, check.flow.state))},
                           {"flow_half_tolerance", step_json(check.flow_half)},
                           {"flow_half_against_flow", comparison_json(check.flow_self)},
                           {"solvers", rows},
                           {"settings", settings},
                           {"provenance", app::provenance_json()}};
    const auto path = std::filesystem::path(out) / "path_check.json";
    app::write_json(path, j);
    std::fprintf(stderr, "path_check: wrote %s\n", path.c_str());
    return 0;
  });
}
