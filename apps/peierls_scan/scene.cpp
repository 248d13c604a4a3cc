// peierls_scan's scene: its settings table, the scene file and the rows' fingerprint.
#include <stdexcept>
#include <string>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/toml_reader.hpp"
#include "scan_io.hpp"

namespace asperity::app::peierls_scan {

// Shortest form that reads back to the same double: fingerprints compare exactly.
using settings::format_number;

const settings::Table<Scene>& scene_settings() {
  using R = settings::Range;
  static const settings::Table<Scene> table = [] {
    settings::Table<Scene> t;
    settings::lift(
        t, peierls::PeierlsOptions::settings(), "", [](auto& s) -> auto& { return s.options; });
    settings::lift(
        t, peierls::CellSizeOptions::settings(), "", [](auto& s) -> auto& { return s.cell_size; });
    t.push_back(settings::numbers<Scene>(
        "scan.b_core", [](auto& s) -> auto& { return s.b_core; }, R::closed(0.1, 1000.0), "d",
        "core widths d G / tau_max of the points", "--b-core"));
    t.push_back(settings::numbers<Scene>(
        "scan.theta", [](auto& s) -> auto& { return s.theta; }, R::closed(0.0, 90.0), "degrees",
        "line angles of the points (0 screw, 90 edge)", "--theta"));
    t.push_back(settings::number<Scene>(
        "scan.angle_tolerance", [](auto& s) -> auto& { return s.angle_tolerance; },
        R::closed(0.0, 45.0), "degrees",
        "largest difference of a cell's line angle from a wanted one"));
    t.push_back(settings::neutral(settings::integer<Scene>(
        "scan.jobs", [](auto& s) -> auto& { return s.jobs; }, R::closed(0, 1024), "",
        "points run at once, on each MPI rank (0: hardware threads, a host's shared among its "
        "ranks)",
        "--jobs")));
    t.push_back(settings::neutral(settings::boolean<Scene>(
        "scan.snapshots", [](auto& s) -> auto& { return s.snapshots; },
        "NetCDF snapshots of each point's cell", "--snapshots")));
    t.push_back(settings::number<Scene>(
        "cell.min_line_spacing", [](auto& s) -> auto& { return s.min_line_spacing; }, R::positive(),
        "d", "smallest distance between a line and its periodic images"));
    t.push_back(settings::number<Scene>(
        "fit.b_min", [](auto& s) -> auto& { return s.fit_b_min; }, R::non_negative(), "d",
        "fit window of tau_P = k1 tau_max exp(-k2 b_core/d): smallest core width"));
    t.push_back(settings::number<Scene>(
        "fit.b_max", [](auto& s) -> auto& { return s.fit_b_max; }, R::positive(), "d",
        "fit window: largest core width"));
    return t;
  }();
  return table;
}

Scene read_scene(const std::string& path) {
  app::SceneReader r = app::SceneReader::from_file(path);
  using app::Range;
  Scene s;
  s.source = path;
  r.read(scene_settings(), s);
  r.reject_unknown();
  if (s.b_core.empty())
    throw std::invalid_argument(path + ": scan.b_core: empty, give at least one");
  if (s.theta.empty()) throw std::invalid_argument(path + ": scan.theta: empty, give at least one");
  if (s.fit_b_min >= s.fit_b_max) {
    throw std::invalid_argument(path + ": fit.b_min = " + format_number(s.fit_b_min) +
                                " must be below fit.b_max = " + format_number(s.fit_b_max));
  }
  return s;
}

std::string fingerprint(const Scene& s) {
  return settings::fingerprint(
             s, scene_settings(), true,
             // A row carries its own b_core and angle: the lists only say which rows to make.
             {"scan.b_core", "scan.theta", "scan.angle_tolerance", "cell.min_line_spacing",
              "fit.b_min", "fit.b_max"}) +
         " code=" + app::provenance_token();
}

}  // namespace asperity::app::peierls_scan
