// Scene reading and outputs of the sliding tools; see slide_io.hpp.
#include "asperity/apps/common/slide_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/memory.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/apps/common/snapshot_sink.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "asperity/core/explicit/alpha_path.hpp"
#include "asperity/core/slide/path.hpp"

namespace asperity::app {

namespace {

SlideScene read_slide_keys(SceneReader& r) {
  SlideScene s;
  r.read(SlideScene::settings(), s);
  s.make_slip_minimizer();
  return s;
}

bool path_faithful(minimize::Method m) {
  return m == minimize::Method::flow || m == minimize::Method::fire;
}

}  // namespace

const settings::Table<SlideScene>& SlideScene::settings() {
  using R = settings::Range;
  static const settings::Table<SlideScene> table = [] {
    settings::Table<SlideScene> t;
    settings::lift(
        t, interface::ContactScene::settings(), "", [](auto& s) -> auto& { return s.contact; });
    settings::lift(
        t, slide::SlideOptions::settings(), "", [](auto& s) -> auto& { return s.options; });
    t.push_back(settings::choice<SlideScene>(
        "solver.slip_method", [](auto& s) -> auto& { return s.slip_method; },
        {"flow", "fire", "same"},
        "relax again every slip with this solver: flow (the reference path, MODEL.md 5) | fire "
        "| same (only with solver.method flow or fire)",
        "--slip-solver"));
    t.push_back(settings::choice<SlideScene>(
        "solver.slip_preconditioner", [](auto& s) -> auto& { return s.slip_preconditioner; },
        {"auto", "elastic", "interface"},
        "metric of the slip solver: interface (G with the interface filter) | elastic | auto"));
    t.push_back(settings::neutral(settings::choice<SlideScene>(
        "output.precision", [](auto& s) -> auto& { return s.snapshot_format.single_precision; },
        {"double", "float"}, [](bool single) { return single ? "float" : "double"; },
        [](const std::string& p) { return p == "float"; },
        "precision of the snapshot fields (the checkpoint is always double)")));
    t.push_back(settings::neutral(settings::integer<SlideScene>(
        "output.deflate", [](auto& s) -> auto& { return s.snapshot_format.deflate_level; },
        R::closed(0, 9), "", "NetCDF deflate level of the snapshots (0: none)")));
    t.push_back(settings::neutral(settings::boolean<SlideScene>(
        "output.xyz", [](auto& s) -> auto& { return s.snapshot_format.xyz; },
        "also write every snapshot file as extended XYZ beside it (<label>.xyz, paths.xyz), "
        "for ASE and OVITO (docs/viewers.md)",
        "--xyz")));
    return t;
  }();
  return table;
}

const settings::Table<RunControl>& RunControl::settings() {
  using R = settings::Range;
  static const settings::Table<RunControl> table = {
      settings::neutral(settings::number<RunControl>(
          "run.checkpoint_every", [](auto& r) -> auto& { return r.checkpoint_every; },
          R::non_negative(), "s",
          "run time between checkpoints of a running slide (0: after every step)",
          "--checkpoint-every")),
      settings::neutral(settings::number<RunControl>(
          "run.progress_every", [](auto& r) -> auto& { return r.progress_every; },
          R::non_negative(), "s",
          "run time between progress lines of a running point, also from inside a long "
          "relaxation (0: none)",
          "--progress-every"))};
  return table;
}

void SlideScene::make_slip_minimizer() {
  if (slip_method == "same") {
    options.slip_minimizer.reset();
  } else {
    options.slip_minimizer =
        slide::slip_minimizer_from(options.minimizer, minimize::method_from_string(slip_method),
                                   minimize::preconditioner_from_string(slip_preconditioner));
  }
}

void check_slip_relaxation(const slide::SlideOptions& o, const std::string& slip_source,
                           const std::string& method_source) {
  const auto& slip = o.slip_minimizer;
  if (slip ? !path_faithful(slip->method) : !path_faithful(o.minimizer.method)) {
    throw std::invalid_argument(
        slip_source + " = \"" + (slip ? minimize::to_string(slip->method) : std::string("same")) +
        "\" with " + method_source + " = \"" + minimize::to_string(o.minimizer.method) +
        "\": allowed: slips relaxed by flow or fire (slip_method \"flow\" or \"fire\", or "
        "\"same\" with solver.method \"flow\" or \"fire\"): lbfgs, cg and newton do not end in "
        "the flow's minimum through every slip (docs/solvers.md, \"Path fidelity\")");
  }
}

void apply_slip_flags(SlideScene& scene, const SettingFlags& flags, const std::string& scene_path) {
  const bool slip_solver = flags.given("solver.slip_method");
  const bool solver = flags.given("solver.method");
  scene.make_slip_minimizer();
  check_slip_relaxation(
      scene.options,
      slip_solver ? std::string("--slip-solver") : scene_path + ": solver.slip_method",
      solver        ? std::string("--solver")
      : slip_solver ? scene_path + ": solver.method"
                    : std::string("solver.method"));
}

namespace {

// Constraints between keys; checked after reject_unknown() where possible, so that a misspelled
// key is reported as such rather than through the default that replaced it.
void check_relations(const SlideScene& s, const std::string& path, bool check_slips = true) {
  if (check_slips) check_slip_relaxation(s.options, path + ": solver.slip_method", "solver.method");
  // The structs' own checks (the relations between keys among them: a < R, min_step <=
  // max_step), named by the file.
  try {
    s.contact.validate();
    s.options.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

}  // namespace

namespace {

// A whole document as a slide scene: its keys, nothing else, and their relations.
SlideScene read_whole_slide_scene(SceneReader& reader, bool check_slips) {
  SlideScene s = read_slide_keys(reader);
  reader.reject_unknown();
  check_relations(s, reader.source_name(), check_slips);
  return s;
}

}  // namespace

SlideScene read_slide_scene(const std::string& path, bool check_slips) {
  auto reader = SceneReader::from_file(path);
  return read_whole_slide_scene(reader, check_slips);
}

SlideScene read_slide_scene_text(std::string_view text, const std::string& source) {
  auto reader = SceneReader::from_string(text, source);
  return read_whole_slide_scene(reader, true);
}

SlideScene read_slide_scene(SceneReader& reader, bool check_slips) {
  SlideScene s = read_slide_keys(reader);
  check_relations(s, reader.source_name(), check_slips);
  return s;
}

nlohmann::json slide_summary(const SlideScene& scene, const slide::SlideResult& r) {
  const auto& c = scene.contact;
  const auto& o = scene.options;
  // Undefined values are null, each with its reason nearby (mu_note), never NaN.
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json out = {
      {"model", "lfm"},
      // Every setting as its scene key has it (SlideScene::settings()); the flat entries below
      // repeat a few of them where readers of earlier summaries look for them.
      {"settings", settings_echo(scene, SlideScene::settings())},
      {"a", c.a},
      {"R", c.R},
      {"alpha", c.alpha},
      {"G", c.material.G},
      {"nu", c.material.nu},
      {"a_over_bcore0", c.a_over_bcore0()},
      {"lambda", c.lambda()},
      // The interface envelope (issue 27): its tau0, tau_max and core width at the centre.
      {"envelope", c.envelope},
      {"tau0", c.tau0},
      {"tau_max0", c.tau_max0()},
      {"bcore0", c.bcore0()},
      {"Fz", r.Fz},
      {"Fz_continuum", r.Fz_continuum},
      // What the slide maximised: mu = Fx/Fz, or tau_fric = Fx/A where there is no load.
      {"friction_measure",
       r.measure == slide::FrictionMeasure::load ? "mu = Fx/Fz" : "tau_fric = Fx/A"},
      {"mu", num(r.mu)},
      {"mu_over_alpha", num(r.mu_over_alpha)},
      // Fx at the peak over the contact-site area there (A = N_c d^2, the sites with tau_max >
      // 0), and A beside the continuum pi a^2.
      {"tau_fric", num(r.tau_fric)},
      {"contact_area", r.area},
      {"contact_area_continuum", std::numbers::pi * c.a * c.a},
      // Fx at the peak over its Regime I value alpha Fz + tau0 A: 1 while the contact is rigid.
      {"friction_over_regime_one", num(slide::friction_over_regime_one(c, r))},
      {"mu_is_lower_bound", r.mu_is_lower_bound},
      {"peak_Dx", r.peak_Dx},
      {"peak_precision", r.peak_precision},
      {"kinetic", r.kinetic},
      {"kinetic_over_static", r.kinetic_over_static},
      {"slip_events", r.slip_events},
      {"distance", r.distance},
      {"distance_requested",
       o.distance == 0.0 ? nlohmann::json("automatic") : nlohmann::json(o.distance)},
      {"stop_reason", r.stop_reason},
      {"failed", r.failed},
      {"steps", r.steps},
      // The cycle replay (slider.hpp, SlideOptions::replay_cycle): rows copied from the cycle
      // one period back once the state had repeated, and where and how closely it did.
      {"replayed_steps", r.replayed_steps},
      {"cycle_verified_at",
       r.cycle_verified_at >= 0.0 ? nlohmann::json(r.cycle_verified_at) : nlohmann::json()},
      {"cycle_mismatch",
       r.cycle_mismatch >= 0.0 ? nlohmann::json(r.cycle_mismatch) : nlohmann::json()},
      {"minimizations", r.minimizations},
      {"iterations", r.iterations},
      {"gf_applications", r.gf_applications},
      {"filter_applications", r.filter_applications},
      {"gradient_evaluations", r.gradient_evaluations},
      {"tolerance", o.minimizer.force_tolerance},
      {"solver", minimize::to_string(o.minimizer.method)},
      {"flow_tolerance", o.minimizer.method == minimize::Method::flow
                             ? nlohmann::json(o.minimizer.flow_tolerance)
                             : nlohmann::json()},
      {"slip_solver", o.slip_minimizer ? nlohmann::json(slide::solver_label(*o.slip_minimizer))
                                       : nlohmann::json("same")},
      {"slip_relaxations", r.slip_relaxations},
      {"flow_first_steps", r.flow_first_steps},
      {"flow_first_stable", r.flow_first_stable},
      {"preconditioner", minimize::to_string(o.minimizer.preconditioner)},
      {"interface_filter_used", r.filtered},
      {"stability_check", minimize::to_string(o.minimizer.stability)},
      {"protocol", slide::to_string(o.protocol)},
      {"step", o.protocol == slide::Protocol::reference ? o.step : o.max_step},
      {"min_step", o.protocol == slide::Protocol::reference ? o.step : o.min_step},
      {"grid",
       {{"block", {r.block.n0, r.block.n1}},
        {"fft_grid", {r.fft_grid.n0, r.fft_grid.n1}},
        {"contact_sites", r.contact_sites}}},
      {"threads", o.fft.threads},
      // What differs between runs of the same scene with the same threads: everything outside
      // "run" is bit-identical between such runs (tests/regression/test_slide_resume.cpp).
      {"run",
       {{"wall_s", r.wall_s},
        {"peak_memory_bytes", peak_memory_bytes()},
        {"provenance", provenance_json()}}},
  };
  if (c.uses_tau0() && c.tau0 > 0.0) out["tau_fric_over_tau0"] = num(r.tau_fric / c.tau0);
  if (!c.carries_load()) {
    out["mu_note"] =
        "mu and mu_over_alpha undefined: the adhesive envelope carries no load (Fz = 0); its "
        "friction is tau_fric (tau_fric_over_tau0), and kinetic is a mean of Fx/A";
  }
  return out;
}

namespace {

// trace.png, stress_profiles.png and stress_map.png (peak snapshot) into dir.
void write_figures(const std::filesystem::path& dir, const SlideScene& scene,
                   const slide::SlideResult& r, std::vector<std::filesystem::path>& written) {
  const auto& c = scene.contact;
  // Fx over its Regime I value, alpha Fz + tau0 A per row (ContactScene::regime_one_force): the
  // Hertz envelope's Fx / (alpha Fz) as it always was.
  const char* y_label = !c.uses_tau0()     ? "Fx / (alpha Fz)"
                        : c.carries_load() ? "Fx / (alpha Fz + tau0 A)"
                                           : "Fx / (tau0 A)";
  const auto y_of = [&](const slide::TraceRow& row) {
    return row.Fx / c.regime_one_force(row.Fz, row.area);
  };
  Series fx{.title = y_label, .style = "lines lw 2"};
  Series slips{.title = "slip events", .style = "points pt 7 ps 1.2"};
  // Rows replayed from the repeating cycle (slider.hpp, replay_cycle) are marked as such.
  Series replayed{.title = "replayed from the cycle a period back", .style = "points pt 6 ps 1.0"};
  for (const auto& row : r.trace) {
    fx.x.push_back(row.Dx / c.d);
    fx.y.push_back(y_of(row));
    if (row.replayed) {
      replayed.x.push_back(row.Dx / c.d);
      replayed.y.push_back(y_of(row));
    }
    if (row.slip) {
      slips.x.push_back(row.Dx / c.d);
      slips.y.push_back(y_of(row));
    }
  }
  char title[200];
  const char* bound = r.mu_is_lower_bound ? " (lower bound)" : "";
  if (!c.uses_tau0()) {
    std::snprintf(title, sizeof title,
                  "a = %.0f d, R = %.0f d, alpha = %.2f: a/b_core^0 = %.2f, mu/alpha = %.4f%s", c.a,
                  c.R, c.alpha, c.a_over_bcore0(), r.mu_over_alpha, bound);
  } else if (!c.carries_load()) {
    std::snprintf(title, sizeof title,
                  "adhesive, a = %.0f d, tau0 = %.3g G: a/b_core^0 = %.2f, tau_fric/tau0 = %.4f%s",
                  c.a, c.tau0, c.a_over_bcore0(), r.tau_fric / c.tau0, bound);
  } else {
    std::snprintf(title, sizeof title,
                  "mixed, a = %.0f d, R = %.0f d, alpha = %.2f, tau0 = %.3g G: a/b_core^0 = %.2f, "
                  "mu/alpha = %.4f, tau_fric/tau0 = %.4f%s",
                  c.a, c.R, c.alpha, c.tau0, c.a_over_bcore0(), r.mu_over_alpha,
                  r.tau_fric / c.tau0, bound);
  }
  std::vector<Series> trace_series{fx};
  if (!slips.x.empty()) trace_series.push_back(slips);
  if (!replayed.x.empty()) trace_series.push_back(replayed);
  plot_png(dir / "trace.png", trace_series,
           {.title = title, .xlabel = "Dx / d", .ylabel = y_label});
  written.push_back(dir / "trace.png");

  // Peak snapshot: stress profiles along the axes through the tip centre, and the map.
  const auto& peak = r.peak_snapshot;
  const auto& blk = peak.block;
  // Stresses over tau_max at the centre: alpha p0 (Hertz), tau0 (adhesive) or both (mixed).
  const double p0 = c.carries_load() ? c.hertz().p0 : 0.0;
  const double tau_unit = c.uses_tau0() ? c.tau_max0() : c.alpha * p0;
  const std::string unit_name = !c.uses_tau0()     ? "alpha p0"
                                : c.carries_load() ? "(tau0 + alpha p0)"
                                                   : "tau0";
  Series along_x{.title = "tau_x, y = 0", .style = "points pt 7 ps 0.6"};
  Series along_y{.title = "tau_x, x = Dx", .style = "points pt 6 ps 0.6"};
  Series envelope{.title = !c.uses_tau0()     ? "tau_max = alpha p(r)"
                           : c.carries_load() ? "tau_max = tau0 + alpha p(r)"
                                              : "tau_max = tau0",
                  .style = "lines dt 2"};
  // The stick solution at the peak's force: Cattaneo-Mindlin under the Hertz strength, the
  // bonded rigid disk Fx / (2 pi a^2) (1 - r^2/a^2)^(-1/2) capped at tau0 under the adhesive one
  // (MODEL.md 2; the edge singularity where Regime II nucleates). None for the mixed envelope.
  Series mindlin{
      .title = c.carries_load() ? "Cattaneo-Mindlin" : "bonded rigid disk (capped at tau0)",
      .style = "lines lw 2"};
  // Explicit model (snapshots with u_z): the local pressure per atom on the same axes, against
  // Hertz (the envelope curve is p/p0 of Hertz as well).
  const bool explicit_model = !peak.uz.empty();
  Series pressure_x{.title = "p / p0, y = 0", .style = "points pt 2 ps 0.6"};
  std::vector<double> mx, my, map;
  const int ix_tip = static_cast<int>(std::lround(peak.Dx / c.d)) - blk.origin0;
  for (int i0 = 0; i0 < blk.shape.n0; ++i0)
    mx.push_back(blk.x(i0, c.d));
  for (int i1 = 0; i1 < blk.shape.n1; ++i1)
    my.push_back(blk.y(i1, c.d));
  map.assign(blk.shape.count(), std::nan(""));
  for (int i0 = 0; i0 < blk.shape.n0; ++i0) {
    for (int i1 = 0; i1 < blk.shape.n1; ++i1) {
      const std::size_t i = blk.shape.index(i0, i1);
      if (!peak.in_contact[i]) continue;
      map[i] = peak.tau_x[i] / peak.tau_max[i];
      const double t = peak.tau_x[i] / tau_unit;
      if (blk.y(i1, c.d) == 0.0) {
        along_x.x.push_back((blk.x(i0, c.d) - peak.Dx) / c.a);
        along_x.y.push_back(t);
        pressure_x.x.push_back((blk.x(i0, c.d) - peak.Dx) / c.a);
        pressure_x.y.push_back(peak.pressure[i] / p0);
      }
      if (i0 == ix_tip) {
        along_y.x.push_back(blk.y(i1, c.d) / c.a);
        along_y.y.push_back(t);
      }
    }
  }
  // In the explicit model the envelope is the Hertz pressure the atoms are compared with.
  if (explicit_model) envelope.title = "tau_max = alpha p_H(r); Hertz p_H / p0";
  const auto shape = interface::make_envelope(c);
  for (int k = -200; k <= 200; ++k) {
    const double rho = k / 200.0;
    const double w = std::sqrt(std::max(0.0, 1.0 - rho * rho));
    envelope.x.push_back(rho);
    // The Hertz curve as it always was; the others from the envelope itself (inside the edge).
    envelope.y.push_back(
        !c.uses_tau0() ? w : shape->tau_max(std::min(std::abs(rho), 0.9999) * c.a) / tau_unit);
    if (!c.uses_tau0()) {
      mindlin.x.push_back(rho);
      mindlin.y.push_back(contact::cattaneo_mindlin(std::abs(rho), r.mu_over_alpha));
    } else if (!c.carries_load() && std::abs(rho) < 1.0) {
      mindlin.x.push_back(rho);
      mindlin.y.push_back(
          std::min(1.0, r.tau_fric * r.area / (2.0 * std::numbers::pi * c.a * c.a * c.tau0 * w)));
    }
  }
  std::vector<Series> profiles{along_x, along_y, envelope};
  if (!mindlin.x.empty()) profiles.push_back(mindlin);
  if (explicit_model) profiles.push_back(pressure_x);
  plot_png(dir / "stress_profiles.png", profiles,
           {.title = std::string(explicit_model ? "Shear stress and pressure" : "Shear stress")
                         .append(" at the friction peak (Dx = ")
                         .append(std::to_string(peak.Dx))
                         .append(" d)"),
            .xlabel = "r / a (along x: (x - Dx)/a; along y: y/a)",
            .ylabel = explicit_model ? "tau / (alpha p0), p / p0" : "tau / " + unit_name});
  written.push_back(dir / "stress_profiles.png");
  heatmap_png(
      dir / "stress_map.png", mx, my, map,
      {.title = "tau_x / tau_max at the friction peak (Dx = " + std::to_string(peak.Dx) + " d)",
       .xlabel = "x / d",
       .ylabel = "y / d",
       .extra_commands = {"set size ratio -1"}},
      "tau_x / tau_max", std::pair{-1.0, 1.0});
  written.push_back(dir / "stress_map.png");
}

// The frames a slide collected (no sink), through the sink the tools stream them to.
void write_snapshot_files(const std::filesystem::path& dir, const SlideScene& scene,
                          const slide::SlideResult& r, const nlohmann::json& extra,
                          std::vector<std::filesystem::path>& written) {
  SnapshotSink sink(dir / "snapshots", snapshot_attributes(scene, extra), scene.snapshot_format);
  sink.start(std::nullopt);
  for (const auto& snap : r.snapshots) {
    if (snap.label.ends_with("_path")) {
      sink.path_frame(snap);
    } else {
      sink.state(snap);
    }
  }
  sink.finish();
  written.insert(written.end(), sink.written().begin(), sink.written().end());
}

}  // namespace

nlohmann::json snapshot_attributes(const SlideScene& scene, const nlohmann::json& extra) {
  const auto& c = scene.contact;
  nlohmann::json attributes = {{"model", "lfm"},
                               {"a", c.a},
                               {"R", c.R},
                               {"alpha", c.alpha},
                               {"G", c.material.G},
                               {"nu", c.material.nu},
                               {"a_over_bcore0", c.a_over_bcore0()},
                               {"envelope", c.envelope},
                               {"tau0", c.tau0},
                               {"tolerance", scene.options.minimizer.force_tolerance}};
  if (extra.is_object()) {
    for (const auto& [key, value] : extra.items()) {
      if (!value.is_structured()) attributes[key] = value;
    }
  }
  return attributes;
}

SnapshotBytes estimated_snapshot_bytes(const SlideScene& scene) {
  const double side = slide::block_side(scene.contact);
  // 8 fields and in_contact per site; the NetCDF header and per-frame scalars are small.
  const bool single = scene.snapshot_format.single_precision;
  double per_site = 8.0 * (single ? 4.0 : 8.0) + 1.0;
  // The extended XYZ copies (output.xyz), at most: 3 coordinates of up to 24 characters, 9
  // fields of up to 15 (float) or 24, and the species, in_contact and registry columns.
  if (scene.snapshot_format.xyz) per_site += 72.0 + 9.0 * (single ? 15.0 : 24.0) + 24.0;
  SnapshotBytes b;
  b.frame = per_site * side * side + 4096.0;
  b.slip = 2.0 * b.frame;
  b.path = scene.options.path_frame_every > 0 && scene.options.path_frame_slips > 0
               ? scene.options.max_path_frames * b.frame
               : 0.0;
  // current, previous, earlier, peak, runner-up and the cycle window: force and displacement,
  // 2 components, as 8-byte values (CBOR byte strings), plus the trace (small). Inside a slip
  // relaxation by the flow it also holds the paused flow (5 vectors of 2 values per contact
  // site, bounded here by the block) and the path frames so far (a displacement each).
  b.checkpoint = (5.0 + static_cast<double>(slide::kCycleWindow)) * 32.0 * side * side + 65536.0;
  const auto& slip = scene.options.slip_minimizer;
  if (slip && slip->method == minimize::Method::flow) {
    const double frames = scene.options.path_frame_every > 0 && scene.options.path_frame_slips > 0
                              ? scene.options.max_path_frames
                              : 0.0;
    b.checkpoint += (5.0 + frames) * 16.0 * side * side;
  }
  return b;
}

double SnapshotBytes::run(int slips, int path_frame_slips) const {
  const int paths = path == 0.0 || path_frame_slips <= 0 ? 0 : (slips - 1) / path_frame_slips + 1;
  return 2.0 * frame + slips * slip + paths * path + checkpoint;  // the start and the peak
}

std::string check_output_fits(const SlideScene& scene, const std::string& out) {
  const SnapshotBytes b = estimated_snapshot_bytes(scene);
  const int slips = std::max(10, scene.options.slips_to_stop);
  char how[200];
  std::snprintf(how, sizeof how, "estimate for %d slip events, uncompressed: %.3g MB each%s", slips,
                b.slip / 1e6, b.path > 0.0 ? ", and its path where one is recorded" : "");
  check_fits_on_disk("the snapshots of contact.a = " + std::to_string(scene.contact.a) + " d", out,
                     b.run(slips, scene.options.path_frame_slips), how);
  char line[300];
  if (b.path > 0.0) {
    const int k = scene.options.path_frame_slips;
    std::snprintf(line, sizeof line,
                  "snapshots: at most %.3g MB per slip event, %.3g MB more for a relaxation path "
                  "(slip events 1, %d, %d, ...; uncompressed)",
                  b.slip / 1e6, b.path / 1e6, 1 + k, 1 + 2 * k);
  } else {
    std::snprintf(line, sizeof line, "snapshots: at most %.3g MB per slip event (uncompressed)",
                  b.slip / 1e6);
  }
  return line;
}

std::vector<std::filesystem::path> write_slide_outputs(const std::filesystem::path& dir,
                                                       const SlideScene& scene,
                                                       const slide::SlideResult& r,
                                                       const SlideOutputOptions& options) {
  ensure_directory(dir);
  std::vector<std::filesystem::path> written;
  // Fx_over_Fz is nan where there is no load (the adhesive envelope); area is the contact-site
  // area N_c d^2 and Fx_over_A the friction stress (issue 27).
  CsvTable trace({"Dx", "Fx", "Fz", "Fx_over_Fz", "energy", "iterations", "gf_applications",
                  "max_force", "slip", "slipped_sites", "replayed", "area", "Fx_over_A"});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& row : r.trace) {
    trace.add_row(
        {row.Dx, row.Fx, row.Fz, row.Fz > 0.0 ? row.Fx / row.Fz : nan, row.energy,
         static_cast<long long>(row.iterations), static_cast<long long>(row.gf_applications),
         row.max_force, static_cast<long long>(row.slip), static_cast<long long>(row.slipped_sites),
         static_cast<long long>(row.replayed), row.area, row.area > 0.0 ? row.Fx / row.area : nan});
  }
  if (options.figures) write_figures(dir, scene, r, written);
  if (options.snapshots && !r.snapshots.empty()) {
    write_snapshot_files(dir, scene, r, options.summary_extra, written);
  }
  trace.write(dir / "trace.csv");
  written.push_back(dir / "trace.csv");
  nlohmann::json summary = slide_summary(scene, r);
  if (options.summary_extra.is_object()) summary.update(options.summary_extra);
  write_json(dir / "summary.json", summary);
  written.push_back(dir / "summary.json");
  return written;
}

void check_explicit_envelope(const interface::ContactScene& c, const std::string& source) {
  if (c.envelope != "hertz") {
    throw std::invalid_argument(source + ": contact.envelope = \"" + c.envelope +
                                "\": allowed: \"hertz\" with the explicit model, whose interface "
                                "is its Lennard-Jones tip (MODEL.md 4), not an envelope");
  }
}

ExplicitSlideScene read_explicit_scene(const std::string& path, bool check_slips) {
  auto reader = SceneReader::from_file(path);
  ExplicitSlideScene s;
  s.slide = read_slide_keys(reader);
  auto& m = s.model;
  reader.read(explicit_model::ExplicitScene::settings(), m);
  reader.reject_unknown();
  check_relations(s.slide, path, check_slips);
  check_explicit_envelope(s.slide.contact, path);
  m.R = s.slide.contact.R;
  m.material = s.slide.contact.material;
  m.d = s.slide.contact.d;
  m.tip = s.slide.contact.tip;
  return s;
}

namespace {

// Every setting of an explicit scene, {key: value}: the slide scene's and the potential's, but
// contact.alpha, which the explicit model does not read (its alpha is the potential's, "alpha").
nlohmann::json explicit_settings_echo(const ExplicitSlideScene& scene) {
  nlohmann::json out = settings_echo(scene.slide, SlideScene::settings(), {"contact.alpha"});
  out.update(settings_echo(scene.model, explicit_model::ExplicitScene::settings()));
  return out;
}

}  // namespace

std::vector<std::filesystem::path> write_explicit_load_outputs(const std::filesystem::path& dir,
                                                               const ExplicitSlideScene& scene,
                                                               const explicit_model::LoadResult& r,
                                                               const SlideOutputOptions& options) {
  ensure_directory(dir);
  std::vector<std::filesystem::path> written;
  const auto& st = r.state;
  const auto& hz = r.hertz;
  const auto& m = scene.model;
  const double d = m.d, force_unit = m.force_unit();
  // alpha of the potential at the central atom's load (alpha_path: nearly load independent).
  const double centre_force = hz.p0 * d * d / force_unit;  // eps/sigma
  double alpha = std::nan("");
  try {
    alpha =
        explicit_model::alpha_path({.sigma_over_d = m.sigma_over_d, .normal_force = centre_force})
            .alpha;
  } catch (const std::runtime_error&) {
    // A load the single atom cannot hold: alpha stays NaN (null in the summary).
  }
  const double a_over_bcore0 = alpha * hz.p0 * hz.a / (d * m.material.G);
  CsvTable sites({"x", "y", "r", "ux", "uy", "uz", "fx", "fy", "fz", "p", "active"});
  for (int i0 = 0; i0 < st.block.shape.n0; ++i0) {
    for (int i1 = 0; i1 < st.block.shape.n1; ++i1) {
      const std::size_t i = st.block.shape.index(i0, i1);
      if (!st.active[i] && st.fz[i] == 0.0) continue;
      const double x = st.block.x(i0, d), y = st.block.y(i1, d);
      sites.add_row({x, y, std::hypot(x - st.Dx, y), st.ux[i], st.uy[i], st.uz[i], st.fx[i],
                     st.fy[i], st.fz[i], -st.fz[i] / (d * d),
                     static_cast<long long>(st.active[i])});
    }
  }
  if (options.figures) {
    Series atoms{.title = "atoms (explicit model)", .style = "points pt 7 ps 0.4"};
    Series hertz{.title = "Hertz p0 sqrt(1 - r^2/a^2)", .style = "lines lw 2"};
    Series uz{.title = "u_z, atoms on y = 0 (explicit)", .style = "points pt 7 ps 0.6"};
    Series uz_hertz{.title = "Hertz surface -w(r)", .style = "lines lw 2"};
    std::vector<double> mx, my, map;
    for (int i0 = 0; i0 < st.block.shape.n0; ++i0)
      mx.push_back(st.block.x(i0, d));
    for (int i1 = 0; i1 < st.block.shape.n1; ++i1)
      my.push_back(st.block.y(i1, d));
    map.assign(st.block.shape.count(), std::nan(""));
    for (int i0 = 0; i0 < st.block.shape.n0; ++i0) {
      for (int i1 = 0; i1 < st.block.shape.n1; ++i1) {
        const std::size_t i = st.block.shape.index(i0, i1);
        const double x = st.block.x(i0, d) - st.Dx, y = st.block.y(i1, d);
        const double p = -st.fz[i] / (d * d);
        if (p != 0.0) {
          atoms.x.push_back(std::hypot(x, y) / hz.a);
          atoms.y.push_back(p / hz.p0);
          map[i] = p / hz.p0;
        }
        if (y == 0.0) {
          uz.x.push_back(x / hz.a);
          uz.y.push_back(st.uz[i]);
        }
      }
    }
    for (int k = 0; k <= 400; ++k) {
      const double rho = 1.5 * k / 400.0;
      hertz.x.push_back(rho);
      hertz.y.push_back(hz.pressure(rho * hz.a) / hz.p0);
    }
    for (int k = -400; k <= 400; ++k) {
      const double rho = 2.0 * k / 400.0;
      uz_hertz.x.push_back(rho);
      uz_hertz.y.push_back(-hz.deflection(std::abs(rho) * hz.a));
    }
    char title[240];
    std::snprintf(title, sizeof title,
                  "Explicit model, a_H = %.1f d, R = %.0f d, G = %g eps/sigma^3: a_area %+.2f d, "
                  "delta %+.2f%%",
                  hz.a, hz.R, m.G_eps_sigma3, r.a_area_error, 100.0 * r.delta_error);
    plot_png(dir / "pressure_profile.png", {atoms, hertz},
             {.title = title, .xlabel = "r / a_Hertz", .ylabel = "p / p0"});
    written.push_back(dir / "pressure_profile.png");
    plot_png(dir / "displacement_profile.png", {uz, uz_hertz},
             {.title = "Normal displacement through the apex (y = 0)",
              .xlabel = "x / a_Hertz",
              .ylabel = "u_z / d"});
    written.push_back(dir / "displacement_profile.png");
    heatmap_png(dir / "pressure_map.png", mx, my, map,
                {.title = "Pressure per atom p / p0 (explicit model)",
                 .xlabel = "x / d",
                 .ylabel = "y / d",
                 .extra_commands = {"set size ratio -1"}},
                "p / p0");
    written.push_back(dir / "pressure_map.png");
  }
  sites.write(dir / "sites.csv");
  written.push_back(dir / "sites.csv");
  const auto& c = scene.slide.contact;
  const auto& o = scene.slide.options;
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  write_json(
      dir / "summary.json",
      {{"model", "explicit"},
       {"stage", "normal loading (contact_slide --model explicit --slide then slides at fixed Fz)"},
       {"settings", explicit_settings_echo(scene)},
       {"a", c.a},
       {"R", c.R},
       {"G", c.material.G},
       {"nu", c.material.nu},
       {"G_eps_sigma3", m.G_eps_sigma3},
       {"sigma_over_d", m.sigma_over_d},
       {"eps", m.energy_unit()},
       {"eps_over_sigma", force_unit},
       {"alpha", num(alpha)},
       {"alpha_note", "alpha_path at the central atom's Hertz load p0 d^2"},
       {"a_over_bcore0", num(a_over_bcore0)},
       {"Fz", st.Fz},
       {"Fz_target", r.target},
       {"Fz_eps_over_sigma", st.Fz / force_unit},
       {"centre_atom_load_eps_over_sigma", centre_force},
       {"Fx", st.Fx},
       {"Fy", st.Fy},
       {"h", st.h},
       {"delta", r.delta},
       {"hertz", {{"a", hz.a}, {"delta", hz.approach}, {"p0", hz.p0}, {"estar", hz.estar}}},
       {"delta_error", r.delta_error},
       {"load_error", r.load_error},
       {"a_area", st.a_area},
       {"a_moment", st.a_moment},
       {"a_area_error", r.a_area_error},
       {"a_moment_error", r.a_moment_error},
       {"loaded_sites", st.loaded_sites},
       {"termination", to_string(r.termination)},
       {"message", r.message},
       {"load_steps", r.load_steps},
       {"minimizations", r.minimizations},
       {"growths", r.growths},
       {"iterations", r.iterations},
       {"gf_applications", r.gf_applications},
       {"gradient_evaluations", r.interface_evaluations},
       {"tolerance", o.minimizer.force_tolerance},
       {"solver", minimize::to_string(o.minimizer.method)},
       {"stability_check", minimize::to_string(o.minimizer.stability)},
       {"grid",
        {{"block", {st.block.shape.n0, st.block.shape.n1}},
         {"fft_grid", {r.fft_grid.n0, r.fft_grid.n1}},
         {"active_sites", r.active_sites}}},
       {"threads", o.fft.threads},
       {"run",
        {{"wall_s", r.wall_s},
         {"peak_memory_bytes", peak_memory_bytes()},
         {"provenance", provenance_json()}}}});
  written.push_back(dir / "summary.json");
  return written;
}

ExplicitAlpha explicit_alpha(const ExplicitSlideScene& scene) {
  const auto& m = scene.model;
  const auto hz = contact::Hertz::from_load(m.material, m.R, scene.slide.contact.hertz().load);
  ExplicitAlpha out;
  out.centre_force = hz.p0 * m.d * m.d / m.force_unit();
  out.alpha = out.alpha_force = std::nan("");
  try {
    const auto path = explicit_model::alpha_path(
        {.sigma_over_d = m.sigma_over_d, .normal_force = out.centre_force});
    out.alpha = path.alpha;
    out.alpha_force = path.alpha_force;
  } catch (const std::runtime_error&) {
    // A load the single atom cannot hold: NaN.
  }
  return out;
}

slide::SlideResult slide_explicit_scene(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha,
                                        const slide::SlideControl& control) {
  explicit_model::ExplicitSlideOptions eo;
  eo.load = scene.slide.contact.hertz().load;
  eo.alpha = alpha.alpha;
  return explicit_model::slide_explicit(scene.model, eo, scene.slide.options, control);
}

SlideScene explicit_as_slide_scene(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha) {
  SlideScene s = scene.slide;
  s.contact.alpha = alpha.alpha;
  return s;
}

nlohmann::json explicit_summary_extra(const ExplicitSlideScene& scene, const ExplicitAlpha& alpha) {
  const auto& m = scene.model;
  return {{"model", "explicit"},
          {"G_eps_sigma3", m.G_eps_sigma3},
          {"sigma_over_d", m.sigma_over_d},
          {"alpha_source", "alpha_path at the central Hertz load"},
          {"alpha_force", alpha.alpha_force},
          {"centre_force_eps_sigma", alpha.centre_force},
          {"force_unit", m.force_unit()},
          {"energy_unit", m.energy_unit()}};
}

std::string describe_progress(const slide::SlideProgressInfo& info) {
  using slide::SlidePhase;
  const auto duration = [](double s) {
    char b[32];
    if (s < 120.0) {
      std::snprintf(b, sizeof b, "%.0f s", s);
    } else if (s < 7200.0) {
      std::snprintf(b, sizeof b, "%.1f min", s / 60.0);
    } else {
      std::snprintf(b, sizeof b, "%.2f h", s / 3600.0);
    }
    return std::string(b);
  };
  char buf[320];
  int n =
      std::snprintf(buf, sizeof buf, "Dx = %.4f d of at most %.2f d, %d slip event%s, %d step%s",
                    info.Dx, info.limit, info.slip_events, info.slip_events == 1 ? "" : "s",
                    info.steps, info.steps == 1 ? "" : "s");
  std::string line(buf, static_cast<std::size_t>(std::max(n, 0)));
  if (info.replayed_steps > 0) line += " + " + std::to_string(info.replayed_steps) + " replayed";
  if (std::isfinite(info.friction) && std::isfinite(info.peak_friction)) {
    const bool load = info.measure == slide::FrictionMeasure::load;
    n = std::snprintf(buf, sizeof buf, ", %s %.5g%s (largest %.5g)", load ? "Fx/Fz" : "Fx/area",
                      info.friction, load ? "" : " G", info.peak_friction);
    line.append(buf, static_cast<std::size_t>(std::max(n, 0)));
  }
  line += ", " + std::to_string(info.gf_applications) + " GF, " + duration(info.wall_s);
  const char* what = nullptr;
  switch (info.phase) {
    case SlidePhase::start:
      what = "the first state at";
      break;
    case SlidePhase::accepted:
      break;
    case SlidePhase::step:
      what = "a step to";
      break;
    case SlidePhase::bisection:
      what = "a trial inside the slip's bracket at";
      break;
    case SlidePhase::slip:
      what = "the slip at";
      break;
    case SlidePhase::probe:
      what = "a probe of the repeating cycle at";
      break;
    case SlidePhase::peak:
      what = "a point of the peak refinement at";
      break;
  }
  if (what) {
    n = std::snprintf(buf, sizeof buf, "; relaxing %s Dx = %.4f d", what, info.target_Dx);
    line.append(buf, static_cast<std::size_t>(std::max(n, 0)));
    if (info.iteration > 0) line += ", iteration " + std::to_string(info.iteration);
  }
  return line;
}

bool ProgressLines::due(const slide::SlideProgressInfo& info) {
  const bool slipped = each_slip_ && info.slip_events != last_slips_;
  last_slips_ = info.slip_events;
  if (last_s_ >= 0.0 && info.wall_s - last_s_ < every_s_ && !slipped) return false;
  last_s_ = info.wall_s;
  return true;
}

}  // namespace asperity::app
