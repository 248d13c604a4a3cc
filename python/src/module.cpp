// asperity._asperity: the compiled half of the Python package (issue 25; python/asperity holds
// the Python half). Scenes are read by the tools' own reader from the same keys (one
// description per setting: SlideScene::settings()), slides run through slide::slide with the
// GIL released, and results come back as the tools write them (slide_summary) plus the trace as
// columns. A bad key or value raises ValueError with the reader's message (key, value, allowed
// range); Ctrl-C stops a slide at its next poll and raises KeyboardInterrupt.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <toml++/toml.h>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "analysis.hpp"
#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/slide_io.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "asperity/core/slide/slider.hpp"
#include "errors.hpp"
#include "frames.hpp"
#include "gf.hpp"

namespace py = pybind11;
using namespace asperity;

namespace {

const char* phase_name(slide::SlidePhase p) {
  switch (p) {
    case slide::SlidePhase::start:
      return "start";
    case slide::SlidePhase::accepted:
      return "accepted";
    case slide::SlidePhase::step:
      return "step";
    case slide::SlidePhase::bisection:
      return "bisection";
    case slide::SlidePhase::slip:
      return "slip";
    case slide::SlidePhase::probe:
      return "probe";
    case slide::SlidePhase::peak:
      return "peak";
  }
  return "?";
}

// A Python scalar handed to `take` as the TOML value it reads as (bool, integer, float,
// string); false if it is none of them.
template <class Take>
bool take_scalar(const py::handle& value, Take&& take) {
  if (py::isinstance<py::bool_>(value)) {
    take(value.cast<bool>());
  } else if (py::isinstance<py::int_>(value)) {
    take(value.cast<long long>());
  } else if (py::isinstance<py::float_>(value)) {
    take(value.cast<double>());
  } else if (py::isinstance<py::str>(value)) {
    take(value.cast<std::string>());
  } else {
    return false;
  }
  return true;
}

std::string type_name(const py::handle& value) {
  return py::str(py::type::of(value));
}

// The table `key` of `into`, made if missing.
toml::table& subtable(toml::table& into, const std::string& key) {
  if (!into.contains(key)) into.insert(key, toml::table{});
  toml::table* sub = into[key].as_table();
  if (!sub) throw py::value_error("scene: '" + key + "' is both a value and a table");
  return *sub;
}

// A Python value as TOML: scalars and lists of them; dicts become tables, and a dotted key
// ("contact.a": 30) is the same key as {"contact": {"a": 30}}.
void put(toml::table& into, const std::string& key, const py::handle& value) {
  if (const auto dot = key.find('.'); dot != std::string::npos) {
    put(subtable(into, key.substr(0, dot)), key.substr(dot + 1), value);
    return;
  }
  if (py::isinstance<py::dict>(value)) {
    toml::table& sub = subtable(into, key);
    for (const auto& [k, v] : value.cast<py::dict>())
      put(sub, py::str(k), v);
    return;
  }
  if (take_scalar(value, [&](auto v) { into.insert_or_assign(key, std::move(v)); })) return;
  if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value)) {
    throw py::value_error("scene: key '" + key + "': unsupported value of type " +
                          type_name(value));
  }
  toml::array list;
  for (const py::handle item : value) {
    if (!take_scalar(item, [&](auto v) { list.push_back(std::move(v)); })) {
      throw py::value_error("scene: key '" + key +
                            "': list items must be numbers, booleans or strings, not " +
                            type_name(item));
    }
  }
  into.insert_or_assign(key, std::move(list));
}

// The scene from TOML text, through the tools' reader: same keys, defaults and messages.
app::SlideScene scene_from_toml(const std::string& text, const std::string& source) {
  return python::value_errors([&] { return app::read_slide_scene_text(text, source); });
}

app::SlideScene scene_from_dict(const py::dict& d) {
  toml::table t;
  for (const auto& [k, v] : d)
    put(t, py::str(k), v);
  std::ostringstream text;
  text << t;
  return scene_from_toml(text.str(), "scene");
}

// The trace as columns (NumPy arrays), keyed as trace.csv's columns.
py::dict trace_columns(const std::vector<slide::TraceRow>& trace) {
  const auto column = [&](auto get) {
    using T = decltype(get(trace.front()));
    py::array_t<T> out(static_cast<py::ssize_t>(trace.size()));
    auto m = out.template mutable_unchecked<1>();
    for (std::size_t i = 0; i < trace.size(); ++i)
      m(static_cast<py::ssize_t>(i)) = get(trace[i]);
    return out;
  };
  py::dict c;
  if (trace.empty()) return c;
  c["Dx"] = column([](const slide::TraceRow& r) { return r.Dx; });
  c["Fx"] = column([](const slide::TraceRow& r) { return r.Fx; });
  c["Fz"] = column([](const slide::TraceRow& r) { return r.Fz; });
  // As trace.csv: nan where there is no load (adhesive envelope) or no contact area.
  c["Fx_over_Fz"] = column([](const slide::TraceRow& r) {
    return r.Fz > 0.0 ? r.Fx / r.Fz : std::numeric_limits<double>::quiet_NaN();
  });
  c["energy"] = column([](const slide::TraceRow& r) { return r.energy; });
  c["iterations"] =
      column([](const slide::TraceRow& r) { return static_cast<long long>(r.iterations); });
  c["gf_applications"] =
      column([](const slide::TraceRow& r) { return static_cast<long long>(r.gf_applications); });
  c["max_force"] = column([](const slide::TraceRow& r) { return r.max_force; });
  c["slip"] = column([](const slide::TraceRow& r) { return r.slip; });
  c["slipped_sites"] =
      column([](const slide::TraceRow& r) { return static_cast<long long>(r.slipped_sites); });
  c["replayed"] = column([](const slide::TraceRow& r) { return r.replayed; });
  c["area"] = column([](const slide::TraceRow& r) { return r.area; });
  c["Fx_over_A"] = column([](const slide::TraceRow& r) {
    return r.area > 0.0 ? r.Fx / r.area : std::numeric_limits<double>::quiet_NaN();
  });
  return c;
}

// One slide of `scene`: summary.json's content (as JSON text), the trace's columns and the
// snapshots (frames.hpp; none unless `snapshots`: the states, and the relaxation paths the
// scene's slide.path_frame_every asks for). The GIL is released while it runs; `progress` (or
// None) is called with a dict per report.
py::tuple run_slide(const app::SlideScene& scene, const py::object& progress, bool snapshots) {
  bool interrupted = false;
  slide::SlideControl control;
  if (!progress.is_none()) {
    control.progress = [&](const slide::SlideProgressInfo& info) {
      py::gil_scoped_acquire gil;
      if (interrupted) return;  // a KeyboardInterrupt is pending: no more Python calls
      progress(py::dict(
          py::arg("phase") = phase_name(info.phase), py::arg("Dx") = info.Dx,
          py::arg("target_Dx") = info.target_Dx, py::arg("slip_events") = info.slip_events,
          py::arg("steps") = info.steps, py::arg("gf_applications") = info.gf_applications,
          py::arg("wall_s") = info.wall_s, py::arg("iteration") = info.iteration,
          py::arg("measure") = slide::to_string(info.measure), py::arg("friction") = info.friction,
          py::arg("peak_friction") = info.peak_friction));
    };
  }
  // Ctrl-C: Python's handler runs when polled; the slide then stops where it stands.
  control.stop_requested = [&] {
    py::gil_scoped_acquire gil;
    if (!interrupted && PyErr_CheckSignals() != 0) interrupted = true;
    return interrupted;
  };
  // Without a sink the slide keeps its frames in the result; a sink that drops them spares the
  // slide making them.
  slide::DiscardFrames discard;
  if (!snapshots) control.frames = &discard;
  slide::SlideResult result;
  {
    py::gil_scoped_release release;
    result = slide::slide(scene.contact, scene.options, control);
  }
  if (interrupted) throw py::error_already_set();
  const std::string summary = app::slide_summary(scene, result).dump();
  return py::make_tuple(summary, trace_columns(result.trace),
                        python::frames_to_python(std::move(result.snapshots)));
}

}  // namespace

PYBIND11_MODULE(_asperity, m) {
  m.doc() = "asperity's compiled core: scenes, slides (see the asperity package)";
  py::class_<app::SlideScene>(m, "SlideScene", "A validated slide scene (data/scenes/default.toml)")
      .def(
          "settings_json",
          [](const app::SlideScene& s) {
            return app::settings_echo(s, app::SlideScene::settings()).dump();
          },
          "Every setting of the scene, keyed as in a scene file, as JSON text")
      .def(
          "snapshot_attributes_json",
          [](const app::SlideScene& s) {
            return app::snapshot_attributes(s, nlohmann::json::object()).dump();
          },
          "The global attributes the tools give this scene's snapshot files, as JSON text");
  m.def("scene_from_dict", &scene_from_dict, py::arg("scene"),
        "A slide scene from a dict (nested tables or dotted keys), read as a scene file is");
  m.def("scene_from_toml", &scene_from_toml, py::arg("text"), py::arg("source") = "scene",
        "A slide scene from TOML text, read as a scene file is");
  m.def("slide", &run_slide, py::arg("scene"), py::arg("progress") = py::none(),
        py::arg("snapshots") = true,
        "Runs a slide; returns (summary JSON text, trace columns, snapshot frames)");
  m.def("snapshot_variables", &python::snapshot_variables,
        "The snapshot files' variables: name, units, long_name, per_site");
  python::bind_gf(m);
  python::bind_analysis(m);
  m.def("version", [] { return app::provenance_string(); });
}
