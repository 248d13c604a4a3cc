// The analyses of snapshots and sweeps from Python: dislocation lines in one frame
// (tracking::find_lines, MODEL.md section 7; records as track_loops' lines.json through
// app::line_json), the stress held along them (tracking::front_stresses) and the scaling laws of
// MODEL.md section 8 (nucleation/: the Regime II law and its fit of c0, the nucleation condition,
// the prediction across regimes). Whole-run pipelines (track_loops over a run, fit_scaling,
// peierls_scan) run as the tools themselves (python/asperity/tools.py).
#include "analysis.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "asperity/apps/common/lines_json.hpp"
#include "asperity/core/elastic/material.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/nucleation/comparison.hpp"
#include "asperity/nucleation/regime_map.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"
#include "asperity/tracking/tracker.hpp"
#include "errors.hpp"
#include "settings_kwargs.hpp"

namespace asperity::python {

namespace py = pybind11;

namespace {

template <class T>
using Array = py::array_t<T, py::array::c_style | py::array::forcecast>;

py::object json_to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// TrackOptions' one row the lines' records use (their location class).
const settings::Table<tracking::TrackOptions>& centre_fraction_table() {
  static const settings::Table<tracking::TrackOptions> table = {
      *settings::find(tracking::TrackOptions::settings(), "centre_fraction")};
  return table;
}

// The lines' options (tracking::DetectOptions' table, and centre_fraction_table() for the
// records' location class) and, with `front`, FrontOptions' from keywords named by their keys
// (as track_loops' lines.*, track.*, front.* settings); others are refused by name.
struct KeywordOptions {
  tracking::DetectOptions detect;
  tracking::TrackOptions track;
  tracking::FrontOptions front;
};

KeywordOptions keyword_options(const char* function, const py::kwargs& kwargs, bool front) {
  KeywordOptions o;
  for (const auto& [key, value] : kwargs) {
    const auto name = key.cast<std::string>();
    if (set_keyword(tracking::DetectOptions::settings(), o.detect, name, value)) continue;
    if (set_keyword(centre_fraction_table(), o.track, name, value)) continue;
    if (front && set_keyword(tracking::FrontOptions::settings(), o.front, name, value)) continue;
    throw py::type_error(std::string(function) + ": unexpected keyword '" + name +
                         "' (options: " + keyword_names(tracking::DetectOptions::settings()) +
                         ", " + keyword_names(centre_fraction_table()) +
                         (front ? ", " + keyword_names(tracking::FrontOptions::settings()) : "") +
                         ")");
  }
  return o;
}

py::dict find_lines(const Array<double>& sx, const Array<double>& tau_x,
                    const Array<double>& tau_max, const py::object& in_contact, int origin_x,
                    int origin_y, double d, bool periodic, const py::object& sy,
                    const py::object& tau_y, double tip_angle, double tip_mismatch,
                    const py::kwargs& kwargs) {
  const KeywordOptions options = keyword_options("find_lines", kwargs, false);
  if (sx.ndim() != 2) throw py::value_error("find_lines: sx must be 2D, (n0, n1) block-major");
  tracking::FieldView view;
  view.block = {{static_cast<int>(sx.shape(0)), static_cast<int>(sx.shape(1))}, origin_x, origin_y};
  view.d = d;
  view.periodic = periodic;
  view.sx = {sx.data(), static_cast<std::size_t>(sx.size())};
  view.tau_x = {tau_x.data(), static_cast<std::size_t>(tau_x.size())};
  view.tau_max = {tau_max.data(), static_cast<std::size_t>(tau_max.size())};
  Array<std::uint8_t> contact;
  if (!in_contact.is_none()) {
    contact = in_contact.cast<Array<std::uint8_t>>();
    view.in_contact = {contact.data(), static_cast<std::size_t>(contact.size())};
  }
  // A tip out of registry: the registry along the tip's first axis needs sy and tau_y too.
  Array<double> sy_values, tau_y_values;
  if (!sy.is_none()) {
    sy_values = sy.cast<Array<double>>();
    view.sy = {sy_values.data(), static_cast<std::size_t>(sy_values.size())};
  }
  if (!tau_y.is_none()) {
    tau_y_values = tau_y.cast<Array<double>>();
    view.tau_y = {tau_y_values.data(), static_cast<std::size_t>(tau_y_values.size())};
  }
  view.tip = {.angle = tip_angle, .mismatch = tip_mismatch};
  const tracking::FrameLines f = value_errors([&] {
    py::gil_scoped_release release;
    return tracking::find_lines(view, options.detect);
  });
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t k = 0; k < f.lines.size(); ++k)
    lines.push_back(
        app::line_json(f.lines[k], static_cast<int>(k), f, options.track.centre_fraction));
  nlohmann::json census = nlohmann::json::object();
  for (const auto& [name, value] : app::census_fields(tracking::census(f)))
    census[name] = value;  // NaN (no loop) becomes None
  return py::dict(
      py::arg("lines") = json_to_python(lines), py::arg("census") = json_to_python(census),
      py::arg("contact_centre") = py::make_tuple(f.contact_centre.x, f.contact_centre.y),
      py::arg("contact_radius") = f.contact_radius, py::arg("contact_sites") = f.contact_sites,
      py::arg("core_crossings") = f.core_crossings,
      py::arg("registry_crossings") = f.registry_crossings,
      py::arg("dropped_short") = f.dropped_short, py::arg("joined_pieces") = f.joined_pieces);
}

// A copy of an optional array (empty for None); the library checks its size against its block.
template <class T>
std::vector<T> copy_of(const py::object& a) {
  if (a.is_none()) return {};
  const auto arr = a.cast<Array<T>>();
  return {arr.data(), arr.data() + arr.size()};
}

// The stress held all along every line of one frame (tracking::front_stresses, as track_loops
// --front): the lines are found as find_lines finds them, then sampled every `step` d.
py::dict front_stresses(const Array<double>& sx, const Array<double>& tau_x,
                        const Array<double>& tau_max, const py::object& in_contact,
                        const py::object& uy, const py::object& tau_y, int origin_x, int origin_y,
                        double Dx, bool periodic, const py::object& later_sx,
                        const py::object& later_tau_max, const py::object& later_in_contact,
                        int later_origin_x, int later_origin_y, const py::kwargs& kwargs) {
  if (sx.ndim() != 2) throw py::value_error("front_stresses: sx must be 2D, (n0, n1) block-major");
  const auto n = static_cast<std::size_t>(sx.size());
  const auto values = [n](const py::object& a, const char* name) {
    std::vector<double> v;
    if (a.is_none()) return v;
    const auto arr = a.cast<Array<double>>();
    if (static_cast<std::size_t>(arr.size()) != n)
      throw py::value_error(std::string("front_stresses: ") + name + "'s size differs from sx's");
    v.assign(arr.data(), arr.data() + arr.size());
    return v;
  };
  slide::Snapshot s;
  s.Dx = Dx;
  s.block = {{static_cast<int>(sx.shape(0)), static_cast<int>(sx.shape(1))}, origin_x, origin_y};
  s.sx = values(sx, "sx");
  s.tau_x = values(tau_x, "tau_x");
  s.tau_max = values(tau_max, "tau_max");
  s.uy = values(uy, "uy");
  s.tau_y = values(tau_y, "tau_y");
  if (s.tau_y.empty()) s.tau_y.assign(n, 0.0);
  s.pressure.assign(n, 0.0);                         // not used by the measure
  s.in_contact = copy_of<std::uint8_t>(in_contact);  // its size: checked by front_stresses
  const KeywordOptions options = keyword_options("front_stresses", kwargs, true);
  const tracking::DetectOptions& o = options.detect;
  const tracking::FrontOptions& fo = options.front;
  const auto [f, front] = value_errors([&] {
    py::gil_scoped_release release;
    tracking::FrameLines lines = tracking::find_lines(tracking::view_of(s, periodic), o);
    std::vector<tracking::FrontStress> points = tracking::front_stresses(s, lines, fo);
    return std::pair{std::move(lines), std::move(points)};
  });
  const auto m = static_cast<py::ssize_t>(front.size());
  Array<double> arc(m), spans(m), x(m), y(m), angle(m), stress(m), slip(m), half(m), bend(m),
      tmax(m);
  Array<long long> line(m);
  Array<bool> resolved(m);
  py::list kind;
  for (py::ssize_t i = 0; i < m; ++i) {
    const tracking::FrontStress& p = front[static_cast<std::size_t>(i)];
    line.mutable_at(i) = static_cast<long long>(p.line);
    kind.append(tracking::to_string(p.kind));
    arc.mutable_at(i) = p.arc;
    spans.mutable_at(i) = p.span;
    x.mutable_at(i) = p.at.x;
    y.mutable_at(i) = p.at.y;
    angle.mutable_at(i) = p.angle_deg;
    stress.mutable_at(i) = p.held.tau;
    slip.mutable_at(i) = p.held.slip;
    resolved.mutable_at(i) = p.resolved();
    half.mutable_at(i) = p.half_width;
    bend.mutable_at(i) = p.bend;
    tmax.mutable_at(i) = p.tau_max;
  }
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t k = 0; k < f.lines.size(); ++k)
    lines.push_back(
        app::line_json(f.lines[k], static_cast<int>(k), f, options.track.centre_fraction));
  py::dict out(py::arg("line") = line, py::arg("kind") = kind, py::arg("arc") = arc,
               py::arg("span") = spans, py::arg("x") = x, py::arg("y") = y,
               py::arg("angle_deg") = angle, py::arg("stress") = stress, py::arg("slip") = slip,
               py::arg("resolved") = resolved, py::arg("half_width") = half, py::arg("bend") = bend,
               py::arg("tau_max") = tmax, py::arg("lines") = json_to_python(lines));
  // Where the front moved by a later state of the same contact (tracking::front_moves).
  if (!later_sx.is_none()) {
    const auto lsx = later_sx.cast<Array<double>>();
    if (lsx.ndim() != 2)
      throw py::value_error("front_stresses: later_sx must be 2D, (n0, n1) block-major");
    slide::Snapshot later;
    later.block = {{static_cast<int>(lsx.shape(0)), static_cast<int>(lsx.shape(1))},
                   later_origin_x,
                   later_origin_y};
    later.sx = copy_of<double>(later_sx);
    // The contact: its flag, else tau_max > 0 (front_moves checks either against the block).
    if (later_in_contact.is_none() && later_tau_max.is_none())
      throw py::value_error("front_stresses: later_sx needs later_in_contact or later_tau_max");
    later.in_contact = copy_of<std::uint8_t>(later_in_contact);
    if (later.in_contact.empty()) later.tau_max = copy_of<double>(later_tau_max);
    const tracking::FrontMoves moves = value_errors(
        [&] { return tracking::front_moves(tracking::registry_indices(s), later, front); });
    Array<long long> sites(m);
    for (py::ssize_t i = 0; i < m; ++i)
      sites.mutable_at(i) = moves.sites[static_cast<std::size_t>(i)];
    out["moved_sites"] = sites;
    out["moved"] = moves.moved;
    out["elsewhere"] = moves.elsewhere;
  }
  return out;
}

nucleation::Model model_of(double c0, double k1, double k2, double f_P, double k1_error,
                           double k2_error, double correlation) {
  nucleation::Model m;
  m.c0 = c0;
  m.law.k1 = k1;
  m.law.k2 = k2;
  m.law.k1_error = k1_error;
  m.law.k2_error = k2_error;
  m.law.correlation = correlation;
  m.f_P = f_P;
  value_errors([&] {
    m.validate();
    return 0;
  });
  return m;
}

py::dict fit_regime_two(const Array<double>& x, const Array<double>& mu, const py::object& a,
                        const py::object& R, const py::object& window, int bootstrap,
                        long long seed, const py::object& lower_bound) {
  if (x.size() != mu.size())
    throw py::value_error("fit_regime_two: a_over_bcore0 and mu_over_alpha differ in length");
  std::vector<nucleation::ScalingPoint> points(static_cast<std::size_t>(x.size()));
  const auto column = [&](const py::object& values, const char* name) {
    std::vector<double> v(points.size(), 0.0);
    if (values.is_none()) return v;
    const auto arr = values.cast<Array<double>>();
    if (static_cast<std::size_t>(arr.size()) != points.size())
      throw py::value_error(std::string("fit_regime_two: ") + name + " differs in length");
    std::copy(arr.data(), arr.data() + arr.size(), v.begin());
    return v;
  };
  const std::vector<double> av = column(a, "a"), Rv = column(R, "R");
  // mu_is_lower_bound of a friction_sweep table: never fitted, and a bound rising past its
  // branch's lowest point ends the automatic window (nucleation::ScalingPoint::lower_bound).
  const std::vector<double> bounds = column(lower_bound, "lower_bound");
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = {.a_over_bcore0 = x.data()[i],
                 .mu_over_alpha = mu.data()[i],
                 .a = av[i],
                 .R = Rv[i],
                 .series = 0,
                 .lower_bound = bounds[i] != 0.0};
  }
  nucleation::RegimeTwoFitOptions o;
  if (!window.is_none()) o.window = window.cast<std::pair<double, double>>();
  o.bootstrap_samples = bootstrap;
  o.seed = static_cast<std::uint64_t>(seed);
  const nucleation::RegimeTwoFit fit = value_errors([&] {
    o.validate();
    return nucleation::fit_regime_two(points, o);
  });
  return py::dict(
      py::arg("valid") = fit.valid, py::arg("reason") = fit.reason, py::arg("c0") = fit.c0,
      py::arg("c0_error") = fit.c0_error, py::arg("c0_se_bootstrap") = fit.c0_se_bootstrap,
      py::arg("c0_lo") = fit.c0_lo, py::arg("c0_hi") = fit.c0_hi,
      py::arg("prefactor") = fit.prefactor, py::arg("prefactor_error") = fit.prefactor_error,
      py::arg("window") = py::make_tuple(fit.window_lo, fit.window_hi),
      py::arg("window_automatic") = fit.window_automatic, py::arg("used") = fit.used,
      py::arg("points") = fit.points, py::arg("trimmed") = fit.trimmed,
      py::arg("max_relative_deviation") = fit.max_relative_deviation,
      py::arg("within_max_deviation") = fit.within_max_deviation,
      py::arg("rms_log_residual") = fit.rms_log_residual, py::arg("free_slope") = fit.free_slope,
      py::arg("free_slope_error") = fit.free_slope_error,
      py::arg("c0_window_spread") = fit.c0_window_spread);
}

}  // namespace

void bind_analysis(py::module_& m) {
  // Static: the docstrings outlive this call whatever the binding does with them.
  static const std::string lines_help =
      "Options as keywords (default, meaning, allowed; the table track_loops lifts under "
      "lines.*):\n" +
      keywords_help(tracking::DetectOptions::settings()) + keywords_help(centre_fraction_table());
  static const std::string find_lines_doc =
      "Dislocation lines in one frame (MODEL.md 7): fields (n0, n1) block-major; a tip out of "
      "registry (tip_angle, tip_mismatch) needs sy and tau_y too; returns the lines as "
      "lines.json records and the frame's counts.\n" +
      lines_help;
  static const std::string front_doc =
      "The stress held all along every line of one frame (tracking::front_stresses, as "
      "track_loops --front): fields (n0, n1) block-major; returns its points as columns "
      "(line: index in lines, kind, arc, span, x, y, angle_deg, stress, slip, resolved, "
      "half_width, bend, tau_max) and the lines as lines.json records; with a later state "
      "(later_sx and its contact) also where the front moved by then (moved_sites per point, "
      "moved, elsewhere).\nThe front's options as keywords (track_loops' front.*):\n" +
      keywords_help(tracking::FrontOptions::settings()) + "and the lines' (find_lines):\n" +
      lines_help.substr(lines_help.find('\n') + 1);
  m.def("find_lines", &find_lines, py::arg("sx"), py::arg("tau_x"), py::arg("tau_max"),
        py::arg("in_contact") = py::none(), py::arg("origin_x") = 0, py::arg("origin_y") = 0,
        py::arg("d") = 1.0, py::arg("periodic") = false, py::arg("sy") = py::none(),
        py::arg("tau_y") = py::none(), py::arg("tip_angle") = 0.0, py::arg("tip_mismatch") = 0.0,
        find_lines_doc.c_str());
  m.def("front_stresses", &front_stresses, py::arg("sx"), py::arg("tau_x"), py::arg("tau_max"),
        py::arg("in_contact") = py::none(), py::arg("uy") = py::none(),
        py::arg("tau_y") = py::none(), py::arg("origin_x") = 0, py::arg("origin_y") = 0,
        py::arg("Dx") = 0.0, py::arg("periodic") = false, py::arg("later_sx") = py::none(),
        py::arg("later_tau_max") = py::none(), py::arg("later_in_contact") = py::none(),
        py::arg("later_origin_x") = 0, py::arg("later_origin_y") = 0, front_doc.c_str());
  m.def("regime_two_law", py::vectorize([](double x, double c0) {
          return value_errors([&] { return nucleation::regime_two_law(x, c0); });
        }),
        py::arg("a_over_bcore0"), py::arg("c0"),
        "mu/alpha = 3 (2 c0)^(2/3) (a/b_core^0)^(-2/3), the Regime II law (MODEL.md 8)");
  m.def(
      "nucleation_condition", py::vectorize([](double x, double c0) {
        return value_errors([&] { return nucleation::nucleation_condition(x, c0).mu_over_alpha; });
      }),
      py::arg("a_over_bcore0"), py::arg("c0"),
      "mu/alpha = min(1, 3 (1 - x*^2)), the nucleation condition without the small-b_core "
      "expansion (Regimes I and II)");
  m.def("control_parameter", py::vectorize([](double a, double R, double alpha, double nu) {
          return value_errors([&] { return nucleation::control_parameter(a, R, alpha, nu); });
        }),
        py::arg("a"), py::arg("R"), py::arg("alpha") = interface::ContactScene{}.alpha,
        py::arg("nu") = elastic::Material{}.nu,
        "a/b_core^0 = c alpha a^2/(R d), c = 4/(pi (1 - nu)) (MODEL.md 3), lengths in d");
  m.def(
      "predict",
      [](double x, double beta, double c0, double k1, double k2, double f_P, double k1_error,
         double k2_error, double correlation) {
        const nucleation::Model model = model_of(c0, k1, k2, f_P, k1_error, k2_error, correlation);
        const nucleation::Prediction p =
            value_errors([&] { return nucleation::predict(x, beta, model); });
        return py::dict(py::arg("nucleation") = p.nucleation, py::arg("law_two") = p.law_two,
                        py::arg("central") = p.central, py::arg("integrated") = p.integrated,
                        py::arg("integrated_log_error") = p.integrated_log_error,
                        py::arg("mu_over_alpha") = p.mu_over_alpha,
                        py::arg("regime") = nucleation::to_string(p.regime));
      },
      py::arg("a_over_bcore0"), py::arg("beta"), py::arg("c0"), py::arg("k1"), py::arg("k2"),
      py::arg("f_P") = nucleation::kDefaultPeierlsFraction, py::arg("k1_error") = 0.0,
      py::arg("k2_error") = 0.0, py::arg("correlation") = 0.0,
      "mu/alpha predicted across Regimes I-III at a/b_core^0 and beta = b_core^0/d, and the "
      "regime (MODEL.md 8; fit_scaling's regime map)");
  m.def(
      "forecast",
      [](double a, double R, double c0, double k1, double k2, double alpha, double nu, double f_P,
         double c0_error, double k1_error, double k2_error, double correlation, double b_min,
         double b_max) {
        nucleation::Model model = model_of(c0, k1, k2, f_P, k1_error, k2_error, correlation);
        model.law.b_min = b_min;
        model.law.b_max = b_max;
        const nucleation::Forecast f =
            value_errors([&] { return nucleation::forecast(a, R, alpha, nu, model, c0_error); });
        const nucleation::Prediction& p = f.prediction;
        return py::dict(py::arg("a") = f.a, py::arg("R") = f.R,
                        py::arg("a_over_bcore0") = f.a_over_bcore0, py::arg("beta") = f.beta,
                        py::arg("nucleation") = p.nucleation, py::arg("integrated") = p.integrated,
                        py::arg("integrated_log_error") = p.integrated_log_error,
                        py::arg("mu_over_alpha") = p.mu_over_alpha,
                        py::arg("mu_over_alpha_error") = f.mu_over_alpha_error,
                        py::arg("error_complete") = f.error_complete,
                        py::arg("log_slope") = f.log_slope,
                        py::arg("regime") = nucleation::to_string(p.regime),
                        py::arg("law_extrapolated") = f.law_extrapolated,
                        py::arg("undetermined") = f.undetermined);
      },
      py::arg("a"), py::arg("R"), py::arg("c0"), py::arg("k1"), py::arg("k2"),
      py::arg("alpha") = interface::ContactScene{}.alpha, py::arg("nu") = elastic::Material{}.nu,
      py::arg("f_P") = nucleation::kDefaultPeierlsFraction, py::arg("c0_error") = 0.0,
      py::arg("k1_error") = 0.0, py::arg("k2_error") = 0.0, py::arg("correlation") = 0.0,
      py::arg("b_min") = 0.0, py::arg("b_max") = 0.0,
      "The prediction at a contact of radius a on a sphere of radius R (d) without data, as "
      "fit_scaling --forecast-R/--forecast-a gives it: mu/alpha, its error from c0's and the "
      "law's (one reported error each, in quadrature), and d ln mu/d ln a (positive: the "
      "predicted Regime III upturn); b_min, b_max: the core widths (d) the law was fitted on, for "
      "law_extrapolated (0: unknown)");
  m.def("fit_regime_two", &fit_regime_two, py::arg("a_over_bcore0"), py::arg("mu_over_alpha"),
        py::arg("a") = py::none(), py::arg("R") = py::none(), py::arg("window") = py::none(),
        py::arg("bootstrap") = nucleation::RegimeTwoFitOptions{}.bootstrap_samples,
        py::arg("seed") = static_cast<long long>(nucleation::RegimeTwoFitOptions{}.seed),
        py::arg("lower_bound") = py::none(),
        "Fit of c0 to the Regime II law over a window (automatic unless given), with its "
        "bootstrap error, as fit_scaling fits it; lower_bound: nonzero where mu_over_alpha is "
        "a lower bound (never fitted)");
}

}  // namespace asperity::python
