// track_loops: finds, traces and follows dislocation lines and loops in NetCDF snapshots of the
// contact simulator or of a Peierls cell (MODEL.md section 7; tracking/). Frames of all files,
// in the order given, form one sequence.
//
// Writes into --out: lines.json (every frame and its lines), lines_NNNN.vtk (the lines of frame
// NNNN as VTK polylines, for ParaView: apps/common/vtk_lines.hpp), events.csv (nucleation, growth,
// retreat, arrest, annihilation, merge, split, reconnection), frame_NNNN.png (tau_x / tau_max
// over the contact with the lines drawn on top, coloured by character) and summary.json. With
// --profiles, per plotted frame also the stress along x and along y through the tip centre
// (profile_NNNN.csv, profile_x_NNNN.png, profile_y_NNNN.png: tau_x / (alpha p0) with the bounds
// +-alpha p, the cores where lines cross, and with --peierls the local Peierls stress of the
// edge and screw fits at the local pressure; the seed's Fig. 9). With --front, per plotted
// frame the stress held all along every line (front_NNNN.csv, front_NNNN.png; MODEL.md 6, 7,
// tracking::front_stresses) and where the front moved since the previous one
// (front_moves_NNNN.csv, tracking::front_moves).
#include <netcdf.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/lines_json.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/peierls_summary.hpp"
#include "asperity/apps/common/plot.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/apps/common/vtk_lines.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"
#include "asperity/tracking/tracker.hpp"

using namespace asperity;
namespace fs = std::filesystem;

namespace {

// Global attribute `periodic` (written by peierls_scan for a whole periodic cell); absent: 0.
// read_snapshots() has already checked that the file is readable.
bool periodic_attribute(const fs::path& nc) {
  int id = 0;
  if (nc_open(nc.c_str(), NC_NOWRITE, &id) != NC_NOERR) return false;
  int value = 0;
  nc_type type = NC_NAT;
  std::size_t length = 0;
  bool periodic = false;
  if (nc_inq_att(id, NC_GLOBAL, "periodic", &type, &length) == NC_NOERR && length == 1 &&
      type != NC_CHAR && nc_get_att_int(id, NC_GLOBAL, "periodic", &value) == NC_NOERR) {
    periodic = value != 0;
  }
  nc_close(id);
  return periodic;
}

std::string join_ids(const std::vector<int>& ids) {
  std::string s;
  for (const int id : ids)
    s += (s.empty() ? "" : " ") + std::to_string(id);
  return s;
}

// tau_x / tau_max over the contact with the lines on top: segments split by character into
// screw (< 30 deg from b), mixed and edge (> 60 deg). Under a tip lattice out of registry the
// stress along the tip's first axis, tau_1 = cos theta tau_x + sin theta tau_y, whose sign
// changes the lines are traced on (tracking/lines.hpp).
void plot_frame(const fs::path& png, const slide::Snapshot& s, const tracking::FrameLines& f,
                const std::string& title) {
  const auto& blk = s.block;
  std::vector<double> x, y, map(blk.shape.count(), std::nan(""));
  for (int i0 = 0; i0 < blk.shape.n0; ++i0)
    x.push_back(blk.x(i0, f.d));
  for (int i1 = 0; i1 < blk.shape.n1; ++i1)
    y.push_back(blk.y(i1, f.d));
  const interface::TipFrame frame(s.tip, f.d);
  for (std::size_t i = 0; i < map.size(); ++i) {
    const bool contact = s.in_contact.empty() || s.in_contact[i] != 0;
    double tau1 = s.tau_x[i], tau2 = 0.0;
    if (!frame.aligned()) frame.to_tip(s.tau_x[i], s.tau_y[i], tau1, tau2);
    if (contact && s.tau_max[i] > 0.0) map[i] = tau1 / s.tau_max[i];
  }
  // One series per run of segments of one class: gnuplot's splot joins points across gaps.
  const std::array<std::string, 3> titles = {"screw (< 30 deg)", "mixed", "edge (> 60 deg)"};
  const std::array<std::string, 3> colours = {"#ffffff", "#ff9900", "#ff0000"};
  std::array<bool, 3> titled{};
  std::vector<app::Series> overlays;
  // Lines through the sides of a periodic cell are traced unwrapped; drawn, they are wrapped
  // back into the cell and broken where they cross a side.
  const double x0 = blk.x(0, f.d), y0 = blk.y(0, f.d);
  const double Lx = blk.shape.n0 * f.d, Ly = blk.shape.n1 * f.d;
  const auto wrapped = [&](tracking::Point p) {
    if (f.periodic) {
      p.x = x0 + std::fmod(std::fmod(p.x - x0, Lx) + Lx, Lx);
      p.y = y0 + std::fmod(std::fmod(p.y - y0, Ly) + Ly, Ly);
    }
    return p;
  };
  for (const auto& l : f.lines) {
    const std::size_t m = l.points.size();
    int current = -1;
    for (std::size_t k = 0; k < l.angle_deg.size(); ++k) {
      const int c = l.angle_deg[k] < 30.0 ? 0 : (l.angle_deg[k] > 60.0 ? 2 : 1);
      const auto a = wrapped(l.points[k]);
      const auto b = wrapped(l.points[(k + 1) % m]);
      const bool crosses = std::abs(b.x - a.x) > 0.5 * Lx || std::abs(b.y - a.y) > 0.5 * Ly;
      if (crosses) {
        current = -1;  // the next segment starts a new series on the other side
        continue;
      }
      if (c != current) {
        const auto cc = static_cast<std::size_t>(c);
        overlays.push_back({.x = {a.x},
                            .y = {a.y},
                            .title = titled[cc] ? "" : titles[cc],
                            .style = "lines lw 3 lc rgb '" + colours[cc] + "'"});
        titled[cc] = true;
        current = c;
      }
      overlays.back().x.push_back(b.x);
      overlays.back().y.push_back(b.y);
    }
  }
  // Each line over a black stroke: the screw lines where loops nucleate run along the contact
  // edge, where tau_x / tau_max is near 1 (the palette's yellow), and white alone is lost there.
  std::vector<app::Series> stroked;
  stroked.reserve(2 * overlays.size());
  for (auto& o : overlays) {
    stroked.push_back({.x = o.x, .y = o.y, .title = "", .style = "lines lw 6 lc rgb '#000000'"});
    stroked.push_back(std::move(o));
  }
  // The key above the title, off the map: inside (as gnuplot's splot puts an "outside" key) it
  // hid the top edge, where those lines are. One row: stacked, three entries (edge, mixed,
  // screw) reached down over the title.
  app::heatmap_png(png, x, y, map,
                   {.title = title,
                    .xlabel = "x / d",
                    .ylabel = "y / d",
                    .width = 800,
                    .height = 720,
                    .extra_commands = {"set size ratio -1",
                                       "set key at screen 0.5, 0.965 center horizontal maxrows 1 "
                                       "box opaque fc rgb '#9a9a9a'"}},
                   frame.aligned() ? "tau_x / tau_max" : "tau_1 / tau_max (tip axis)",
                   std::pair{-1.0, 1.0}, stroked);
}

// Local Peierls stress laws drawn beside the profiles (--peierls): the edge and screw fits (the
// seed's Fig. 9), and every angle of the scan (its fit, and its computed values where the
// scan's table is beside the summary), whose least is the weakest straight segment: a curved
// loop is held only where its weakest segments are (at the narrow cores of large contacts the
// high-index directions are several times weaker than edge, and fits on 2-6 d miss them there;
// data/reference/peierls_narrow_cores.md).
struct LocalPeierls {
  std::optional<nucleation::PeierlsLaw> edge, screw;
  std::vector<nucleation::AngleLaw> angles;  // every angle of the scan: fit and table values

  // Whether the weakest curve says more than the edge and screw fits: another angle, or the
  // scan's computed values.
  [[nodiscard]] bool draws_weakest() const {
    return std::any_of(angles.begin(), angles.end(), [](const nucleation::AngleLaw& a) {
      return (a.theta_deg > 0.0 && a.theta_deg < 90.0) || !a.b_core.empty();
    });
  }
};

// The seed's Fig. 9 for one frame: the profiles along x and y through the tip centre, into
// profile_NNNN.csv and two figures; returns the frame's profile record for lines.json.
nlohmann::json write_profiles(const fs::path& dir, int index, const slide::Snapshot& s,
                              const tracking::FrameLines& f, const std::vector<int>& ids,
                              const LocalPeierls& peierls,
                              const tracking::CrossingOptions& crossing, const std::string& title) {
  app::CsvTable table({"axis", "position", "tau_x", "tau_y", "tau_max", "pressure", "in_contact",
                       "tau_P_edge", "tau_P_screw", "tau_P_weakest", "weakest_theta_deg", "offset",
                       "offset_y"});
  // Per core crossing: the stress it holds and the local Peierls stresses (cores_NNNN.csv).
  app::CsvTable cores_table({"axis", "position", "angle_deg", "line_id", "kind", "stress", "slip",
                             "resolved", "half_width", "tau_max", "tau_P_edge", "tau_P_screw",
                             "tau_P_weakest", "weakest_theta_deg"});
  nlohmann::json record = nlohmann::json::object();
  const auto local = [](const std::optional<nucleation::PeierlsLaw>& law, double tau_max) {
    return law ? nucleation::local_peierls_stress(tau_max, *law) : std::nan("");
  };
  char name[48];
  for (const auto axis : {tracking::ProfileAxis::x, tracking::ProfileAxis::y}) {
    const tracking::StressProfile p = tracking::stress_profile(s, axis);
    const double scale = p.tau_max_peak;  // alpha p0, the frame's: the same for both axes
    record["alpha_p0"] = scale;
    std::vector<double> x, tau, bound, edge, screw, weakest;
    for (std::size_t k = 0; k < p.position.size(); ++k) {
      const double tau_p_edge = local(peierls.edge, p.tau_max[k]);
      const double tau_p_screw = local(peierls.screw, p.tau_max[k]);
      const auto [tau_p_weakest, weakest_theta] =
          nucleation::weakest_local_peierls_stress(p.tau_max[k], peierls.angles);
      table.add_row({tracking::to_string(axis), p.position[k], p.tau_x[k], p.tau_y[k], p.tau_max[k],
                     p.pressure[k], static_cast<long long>(p.in_contact[k]), tau_p_edge,
                     tau_p_screw, tau_p_weakest, weakest_theta,
                     p.offset.empty() ? std::nan("") : p.offset[k],
                     p.offset_y.empty() ? std::nan("") : p.offset_y[k]});
      if (!p.in_contact[k] || !(p.tau_max[k] > 0.0)) continue;
      x.push_back(p.position[k]);
      tau.push_back(p.tau_x[k] / scale);
      bound.push_back(p.tau_max[k] / scale);
      edge.push_back(tau_p_edge / scale);
      screw.push_back(tau_p_screw / scale);
      weakest.push_back(tau_p_weakest / scale);
    }
    const std::vector<tracking::CoreCrossing> cores = tracking::core_crossings(f, p);
    // The stress each core holds (its slip-weighted tau_x) beside the local Peierls stresses:
    // at or below them for a held core, at them for one creeping at threshold.
    std::vector<tracking::CrossingStress> held;
    if (!p.offset.empty()) held = tracking::crossing_stresses(p, cores, crossing);
    nlohmann::json cores_json = nlohmann::json::array();
    for (std::size_t j = 0; j < cores.size(); ++j) {
      const tracking::CoreCrossing& c = cores[j];
      nlohmann::json core = {{"position", c.position},
                             {"angle_deg", c.angle_deg},
                             {"line_id", ids.at(c.line)},
                             {"kind", tracking::to_string(c.kind)}};
      if (!held.empty()) {
        const tracking::CrossingStress& h = held[j];
        const double tau_p_edge = local(peierls.edge, h.tau_max);
        const double tau_p_screw = local(peierls.screw, h.tau_max);
        const auto [tau_p_weakest, weakest_theta] =
            nucleation::weakest_local_peierls_stress(h.tau_max, peierls.angles);
        const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; };
        core["stress"] = number(h.stress.tau);
        core["slip"] = h.stress.slip;
        core["resolved"] = h.resolved();
        core["half_width"] = h.half_width;
        core["tau_max"] = h.tau_max;
        core["tau_P_edge"] = number(tau_p_edge);
        core["tau_P_screw"] = number(tau_p_screw);
        core["tau_P_weakest"] = number(tau_p_weakest);
        core["weakest_theta_deg"] = number(weakest_theta);
        cores_table.add_row({tracking::to_string(axis), c.position, c.angle_deg,
                             static_cast<long long>(ids.at(c.line)), tracking::to_string(c.kind),
                             h.stress.tau, h.stress.slip, static_cast<long long>(h.resolved()),
                             h.half_width, h.tau_max, tau_p_edge, tau_p_screw, tau_p_weakest,
                             weakest_theta});
      }
      cores_json.push_back(std::move(core));
    }
    record[tracking::to_string(axis)] = {
        {"through", p.through}, {"centre", p.centre}, {"cores", cores_json}};
    if (x.size() < 2) continue;  // no contact on this row: nothing to draw
    // A bound drawn at +y and -y in one style, titled once.
    std::vector<app::Series> series;
    const auto plus_minus = [&](const std::vector<double>& y, const std::string& legend,
                                const std::string& style) {
      series.push_back({.x = x, .y = y, .title = legend, .style = style});
      std::vector<double> minus = y;
      for (double& v : minus)
        v = -v;
      series.push_back({.x = x, .y = std::move(minus), .style = style});
    };
    plus_minus(bound, "+-alpha p", "lines lw 2 lc rgb '#777777'");
    if (peierls.edge)
      plus_minus(edge, "+-tau_P edge (local p)", "lines lw 2 dt 2 lc rgb '#d62728'");
    if (peierls.screw) {
      plus_minus(screw, "+-tau_P screw (local p)", "lines lw 2 dt 3 lc rgb '#1f77b4'");
    }
    if (peierls.draws_weakest()) {
      plus_minus(weakest, "+-tau_P weakest angle (local p)", "lines lw 2 dt 4 lc rgb '#2ca02c'");
    }
    series.push_back({.x = x, .y = tau, .title = "tau_x", .style = "lines lw 1 lc rgb 'black'"});
    // Cores by character as in the maps (screw < 30 deg < mixed < 60 deg < edge), drawn at the
    // stress they hold (their slip-weighted tau_x), or on the axis where their window does not
    // resolve it (a core cut by the contact's edge).
    const std::array<std::string, 3> titles = {"core: screw (at the stress it holds)",
                                               "core: mixed (at the stress it holds)",
                                               "core: edge (at the stress it holds)"};
    const std::array<std::string, 3> colours = {"#1f77b4", "#ff9900", "#d62728"};
    for (int c = 0; c < 3; ++c) {
      app::Series marks{
          .title = titles[static_cast<std::size_t>(c)],
          .style = "points pt 7 ps 1.6 lc rgb '" + colours[static_cast<std::size_t>(c)] + "'"};
      for (std::size_t j = 0; j < cores.size(); ++j) {
        const tracking::CoreCrossing& core = cores[j];
        const int cc = core.angle_deg < 30.0 ? 0 : (core.angle_deg > 60.0 ? 2 : 1);
        if (cc != c) continue;
        const bool known = !held.empty() && held[j].resolved();
        marks.x.push_back(core.position);
        marks.y.push_back(known ? held[j].stress.tau / scale : 0.0);
      }
      if (!marks.x.empty()) series.push_back(std::move(marks));
    }
    std::snprintf(name, sizeof name, "profile_%s_%04d.png", tracking::to_string(axis).c_str(),
                  index);
    const bool along_x = axis == tracking::ProfileAxis::x;
    char where[96];
    std::snprintf(where, sizeof where, along_x ? "along x through y = 0" : "along y through x = %g",
                  p.through);
    app::plot_png(dir / name, series,
                  {.title = title + ", " + where,
                   .xlabel = along_x ? "(x - Dx) / d" : "y / d",
                   .ylabel = "tau / (alpha p0)",
                   .width = 1000,
                   .height = 560,
                   .extra_commands = {"set key outside right top", "set grid"}});
    record[tracking::to_string(axis)]["figure"] = name;
  }
  std::snprintf(name, sizeof name, "profile_%04d.csv", index);
  table.write(dir / name);
  record["table"] = name;
  if (cores_table.rows() > 0) {
    std::snprintf(name, sizeof name, "cores_%04d.csv", index);
    cores_table.write(dir / name);
    record["cores_table"] = name;
  }
  return record;
}

// The previous plotted frame's front, to find where the front moved since (front_moves): its
// points, and per point what write_front derived from them for its table.
struct FrontPoint {
  long long line_id = 0;
  double polar = 0, tau_P_angle = 0, angle_theta = 0, tau_P_weakest = 0;
};
struct FrontHistory {
  int frame = -1;  // -1: none
  tracking::RegistryIndices indices;
  std::vector<tracking::FrontStress> front;
  std::vector<FrontPoint> points;  // one per point of `front`
};

// front_moves_NNNN.csv: the points of the previous frame's front to which the sites this frame
// moved are given, with the stress they held in it; its record for lines.json.
nlohmann::json write_moves(const fs::path& dir, int index, const slide::Snapshot& s,
                           const FrontHistory& before, app::Series& moved) {
  const tracking::FrontMoves m = tracking::front_moves(before.indices, s, before.front);
  app::CsvTable table({"line_id", "kind", "arc", "x", "y", "polar_deg", "angle_deg", "stress",
                       "resolved", "tau_P_angle", "angle_theta_deg", "tau_P_weakest", "sites"});
  // held / weakest tau_P over the resolved points that moved, mixed and edge apart from near
  // screw (the line's angle below 30 degrees).
  std::array<std::pair<double, double>, 2> range = {
      std::pair{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
      std::pair{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
  int points = 0;
  for (std::size_t k = 0; k < before.front.size(); ++k) {
    if (m.sites[k] == 0) continue;
    const tracking::FrontStress& f = before.front[k];
    const FrontPoint& p = before.points[k];
    ++points;
    table.add_row({p.line_id, tracking::to_string(f.kind), f.arc, f.at.x, f.at.y, p.polar,
                   f.angle_deg, f.held.tau, static_cast<long long>(f.resolved()), p.tau_P_angle,
                   p.angle_theta, p.tau_P_weakest, static_cast<long long>(m.sites[k])});
    const double ratio = std::abs(f.held.tau) / p.tau_P_weakest;
    if (!f.resolved() || !std::isfinite(ratio)) continue;
    if (f.kind == tracking::LineKind::loop) {
      moved.x.push_back(p.polar);
      moved.y.push_back(ratio);
    }
    auto& r = range[f.angle_deg < 30.0 ? 1 : 0];
    r = {std::min(r.first, ratio), std::max(r.second, ratio)};
  }
  char name[48];
  std::snprintf(name, sizeof name, "front_moves_%04d.csv", index);
  table.write(dir / name);
  const auto span = [](const std::pair<double, double>& r) {
    return r.first <= r.second ? nlohmann::json::array({r.first, r.second}) : nlohmann::json();
  };
  return {{"since_frame", before.frame},
          {"table", name},
          {"moved_sites", m.moved},
          {"elsewhere", m.elsewhere},
          {"points", points},
          {"held_over_weakest_mixed_edge", span(range[0])},
          {"held_over_weakest_near_screw", span(range[1])}};
}

// The stress held all along every line (tracking::front_stresses): front_NNNN.csv and, for the
// loops, front_NNNN.png: the stress held around each loop against the local Peierls stress of
// the scanned angle nearest the line's (and of the weakest), which says which parts of the
// front are at threshold; with the previous front in `history`, where it moved since
// (write_moves). Returns the frame's record for lines.json and keeps this front in `history`.
nlohmann::json write_front(const fs::path& dir, int index, const slide::Snapshot& s,
                           const tracking::FrameLines& f, const std::vector<int>& ids,
                           const LocalPeierls& peierls, const tracking::FrontOptions& options,
                           const std::string& title, FrontHistory& history) {
  const std::vector<tracking::FrontStress> front = tracking::front_stresses(s, f, options);
  nlohmann::json record = app::settings_echo(options, tracking::FrontOptions::settings());
  record["points"] = front.size();
  // Where the front moved since the previous frame (plotted, with a front of its own), drawn
  // at what it held there just before against the weakest direction's tau_P.
  app::Series moved{.title = "moved since the previous frame: held / weakest tau_P just before",
                    .style = "points pt 4 ps 1.4 lw 1.5 lc rgb 'black'"};
  if (history.frame >= 0 && s.sx.size() == s.block.shape.count())
    record["moves"] = write_moves(dir, index, s, history, moved);
  history = {};
  if (front.empty()) return record;  // no s_x, a tip out of registry, or no line
  history.frame = index;
  history.indices = tracking::registry_indices(s);
  history.front = front;
  app::CsvTable table({"line_id", "kind", "arc", "span", "x", "y", "polar_deg", "angle_deg",
                       "stress", "slip", "resolved", "half_width", "bend", "tau_max", "tau_P_angle",
                       "angle_theta_deg", "tau_P_weakest", "weakest_theta_deg"});
  const bool laws = !peierls.angles.empty();
  const double pi = std::acos(-1.0);
  const double scale =
      s.tau_max.empty() ? 1.0 : *std::max_element(s.tau_max.begin(), s.tau_max.end());
  // Per line: the ratios of the resolved points (to tau_P at the nearest angle with --peierls).
  std::map<std::size_t, std::vector<double>> ratios, weakest_ratios;
  const std::array<std::string, 3> titles = {"screw (< 30 deg)", "mixed", "edge (> 60 deg)"};
  const std::array<std::string, 3> colours = {"#1f77b4", "#ff9900", "#d62728"};
  std::array<app::Series, 3> marks;
  for (int c = 0; c < 3; ++c) {
    marks[static_cast<std::size_t>(c)] = {
        .title = "held / tau_P at its angle: " + titles[static_cast<std::size_t>(c)],
        .style = "points pt 7 ps 0.8 lc rgb '" + colours[static_cast<std::size_t>(c)] + "'"};
    if (!laws)
      marks[static_cast<std::size_t>(c)].title =
          "held / (alpha p0): " + titles[static_cast<std::size_t>(c)];
  }
  app::Series weakest{.title = "held / tau_P of the weakest angle",
                      .style = "points pt 6 ps 0.6 lc rgb '#777777'"};
  for (const tracking::FrontStress& p : front) {
    const tracking::Line& l = f.lines[p.line];
    const double polar = std::atan2(p.at.y - l.centroid.y, p.at.x - l.centroid.x) * 180.0 / pi;
    const auto at_angle =
        nucleation::nearest_angle_local_peierls_stress(p.tau_max, peierls.angles, p.angle_deg);
    const auto weak = nucleation::weakest_local_peierls_stress(p.tau_max, peierls.angles);
    table.add_row({static_cast<long long>(ids.at(p.line)), tracking::to_string(p.kind), p.arc,
                   p.span, p.at.x, p.at.y, polar, p.angle_deg, p.held.tau, p.held.slip,
                   static_cast<long long>(p.resolved()), p.half_width, p.bend, p.tau_max,
                   at_angle.tau_P, at_angle.theta_deg, weak.tau_P, weak.theta_deg});
    history.points.push_back({.line_id = ids.at(p.line),
                              .polar = polar,
                              .tau_P_angle = at_angle.tau_P,
                              .angle_theta = at_angle.theta_deg,
                              .tau_P_weakest = weak.tau_P});
    if (!p.resolved()) continue;
    // The stress held has tau_x's sign; the Peierls stress bounds its magnitude.
    const double held = std::abs(p.held.tau);
    const double ratio = laws ? held / at_angle.tau_P : held / scale;
    if (std::isfinite(ratio)) ratios[p.line].push_back(ratio);
    if (laws && std::isfinite(held / weak.tau_P))
      weakest_ratios[p.line].push_back(held / weak.tau_P);
    if (l.kind != tracking::LineKind::loop || !std::isfinite(ratio)) continue;
    const int c = p.angle_deg < 30.0 ? 0 : (p.angle_deg > 60.0 ? 2 : 1);
    marks[static_cast<std::size_t>(c)].x.push_back(polar);
    marks[static_cast<std::size_t>(c)].y.push_back(ratio);
    if (laws && std::isfinite(held / weak.tau_P)) {
      weakest.x.push_back(polar);
      weakest.y.push_back(held / weak.tau_P);
    }
  }
  char name[40];
  std::snprintf(name, sizeof name, "front_%04d.csv", index);
  table.write(dir / name);
  record["table"] = name;
  nlohmann::json lines = nlohmann::json::array();
  // Quantiles by nearest rank.
  const auto quantile = [](std::vector<double>& r, double p) {
    std::sort(r.begin(), r.end());
    return r[static_cast<std::size_t>(std::lround(p * static_cast<double>(r.size() - 1)))];
  };
  for (auto& [line, r] : ratios) {
    nlohmann::json summary = {
        {"line_id", ids.at(line)},       {"kind", tracking::to_string(f.lines[line].kind)},
        {"resolved_points", r.size()},   {"ratio_median", quantile(r, 0.5)},
        {"ratio_p90", quantile(r, 0.9)}, {"ratio_max", quantile(r, 1.0)}};
    if (auto w = weakest_ratios.find(line); w != weakest_ratios.end()) {
      summary["weakest_ratio_median"] = quantile(w->second, 0.5);
      summary["weakest_ratio_p90"] = quantile(w->second, 0.9);
      summary["weakest_ratio_max"] = quantile(w->second, 1.0);
    }
    lines.push_back(summary);
  }
  record["ratio_to"] = laws ? "tau_P at the nearest scanned angle" : "alpha p0";
  record["lines"] = lines;
  std::vector<app::Series> series;
  for (auto& m : marks) {
    if (!m.x.empty()) series.push_back(std::move(m));
  }
  if (series.empty()) return record;  // no resolved point on a loop
  if (!weakest.x.empty()) series.push_back(std::move(weakest));
  if (!moved.x.empty() && laws) series.push_back(std::move(moved));
  if (laws)
    series.push_back({.x = {-180.0, 180.0},
                      .y = {1.0, 1.0},
                      .title = "tau_P",
                      .style = "lines lw 1 dt 2 lc rgb 'black'"});
  std::snprintf(name, sizeof name, "front_%04d.png", index);
  app::plot_png(
      dir / name, series,
      {.title = title + ": the stress held around each loop",
       .xlabel = "position around the loop: polar angle about its centroid (deg; 0 = +x)",
       .ylabel = laws ? "|stress held| / local tau_P" : "|stress held| / (alpha p0)",
       .width = 1000,
       .height = 640,
       .xrange = std::pair{-180.0, 180.0},
       .extra_commands = {"set key outside below maxrows 3", "set grid", "set xtics 45"}});
  record["figure"] = name;
  return record;
}

// What the tool does with each frame, besides the options of the libraries.
struct FrameOptions {
  tracking::DetectOptions detect;
  tracking::TrackOptions track;
  int plot_every = 1;
  bool profiles = false;
  bool front = false;
  bool periodic = false;  // every block a whole periodic cell, whatever its file says
  tracking::FrontOptions front_options;
  tracking::CrossingOptions crossing;  // --profiles: the stress each core crossing holds
  LocalPeierls peierls;

  // The tool's settings: the libraries' tables under "lines.", "track.", "profiles.", "front."
  // and the figure's spacing. Flags, checks, the summary's echo and --list-settings come from it.
  static const settings::Table<FrameOptions>& settings() {
    static const settings::Table<FrameOptions> table = [] {
      settings::Table<FrameOptions> t = {settings::neutral(settings::integer<FrameOptions>(
          "plot_every", [](auto& o) -> auto& { return o.plot_every; },
          settings::Range::closed(0, 1000000), "",
          "a figure (and with --profiles, --front their tables) every N frames; 0: none",
          "--plot-every"))};
      // Not neutral: a cell's lines close across its sides.
      t.push_back(settings::boolean<FrameOptions>(
          "periodic", [](auto& o) -> auto& { return o.periodic; },
          "treat every block as a whole periodic cell (default: the file's `periodic` attribute)",
          "--periodic"));
      t.push_back(settings::neutral(settings::boolean<FrameOptions>(
          "profiles", [](auto& o) -> auto& { return o.profiles; },
          "per plotted frame also the stress along x and along y through the tip centre "
          "(profile_NNNN.csv, profile_x/y_NNNN.png): tau_x / (alpha p0), +-alpha p and the "
          "cores (the seed's Fig. 9)",
          "--profiles")));
      t.push_back(settings::neutral(settings::boolean<FrameOptions>(
          "front", [](auto& o) -> auto& { return o.front; },
          "per plotted frame also the stress held all along every line, from stretches of it "
          "(front_NNNN.csv, front_NNNN.png: around each loop, against the local Peierls stress "
          "at its angle with --peierls), and where the front moved since the previous frame, "
          "with what it held there (front_moves_NNNN.csv)",
          "--front")));
      settings::lift(
          t, tracking::DetectOptions::settings(), "lines.",
          [](auto& o) -> auto& { return o.detect; });
      settings::lift(
          t, tracking::TrackOptions::settings(), "track.",
          [](auto& o) -> auto& { return o.track; });
      settings::lift(
          t, tracking::CrossingOptions::settings(), "profiles.",
          [](auto& o) -> auto& { return o.crossing; });
      settings::lift(
          t, tracking::FrontOptions::settings(), "front.",
          [](auto& o) -> auto& { return o.front_options; });
      return t;
    }();
    return table;
  }
};

// Where a frame of the sequence came from (events.csv).
struct FrameInfo {
  std::string file, label;
  int frame_in_file = 0, iteration = -1;
  double Dx = 0.0;
};

// Counts over the sequence (summary.json).
struct Tally {
  std::map<std::string, int> kinds;
  std::size_t max_lines = 0, figures = 0;
  double detect_s = 0.0, detect_max_s = 0.0;
};

static_assert(static_cast<int>(tracking::LineKind::loop) == 0 &&
                  static_cast<int>(tracking::LineKind::open) == 1 &&
                  static_cast<int>(tracking::LineKind::wrapping) == 2,
              "the kind codes of the VTK lines (apps/common/vtk_lines.hpp)");

// lines_NNNN.vtk: the frame's lines as polylines, the same points, ids and angles as lines.json.
void write_vtk(const fs::path& dir, const slide::Snapshot& s, int index,
               const tracking::FrameLines& f, const std::vector<int>& ids) {
  app::VtkLinesFrame v{
      .frame = index, .iteration = s.iteration, .Dx = s.Dx, .title = {}, .lines = {}};
  std::ostringstream title;
  title << "asperity track_loops: frame " << index << ", " << s.label << ", iteration "
        << s.iteration << ", Dx = " << s.Dx << " d: " << f.lines.size() << " line(s)";
  v.title = title.str();
  for (std::size_t j = 0; j < f.lines.size(); ++j) {
    const tracking::Line& l = f.lines[j];
    const tracking::Point b = tracking::burgers_vector(l, f);
    app::VtkPolyline p{.id = ids[j],
                       .kind = static_cast<int>(l.kind),
                       .closed = l.kind == tracking::LineKind::loop,
                       .burgers_x = b.x,
                       .burgers_y = b.y,
                       .length = l.length,
                       .points = {},
                       .angle_deg = l.angle_deg};
    for (const auto& q : l.points)
      p.points.push_back({q.x, q.y});
    v.lines.push_back(std::move(p));
  }
  char name[32];
  std::snprintf(name, sizeof name, "lines_%04d.vtk", index);
  app::write_vtk_lines(dir / name, v);
}

// One frame: its lines found and followed (MODEL.md 7), its figures, and its entry of
// lines.json.
nlohmann::json track_frame(const fs::path& dir, const slide::Snapshot& s, int index,
                           const FrameInfo& where, bool periodic, const FrameOptions& o,
                           tracking::Tracker& tracker, Tally& tally, FrontHistory& history) {
  const auto t0 = std::chrono::steady_clock::now();
  const tracking::FrameLines f = tracking::find_lines(tracking::view_of(s, periodic), o.detect);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  tally.detect_s += dt;
  tally.detect_max_s = std::max(tally.detect_max_s, dt);
  const std::vector<int> ids = tracker.add(f);
  tally.max_lines = std::max(tally.max_lines, f.lines.size());
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t j = 0; j < f.lines.size(); ++j) {
    lines.push_back(app::line_json(f.lines[j], ids[j], f, o.track.centre_fraction));
    ++tally.kinds[tracking::to_string(f.lines[j].kind)];
  }
  write_vtk(dir, s, index, f, ids);
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.png", index);
  const bool plot = o.plot_every > 0 && index % o.plot_every == 0;
  nlohmann::json profile = nullptr, front = nullptr;
  if (plot) {
    std::ostringstream title;
    // A state (not a frame of a relaxation path) has iteration -1: no iteration to name.
    title << s.label << " #" << where.frame_in_file << " (";
    if (s.iteration >= 0) title << "iteration " << s.iteration << ", ";
    title << "Dx = " << s.Dx << " d): " << f.lines.size() << " line(s)";
    plot_frame(dir / name, s, f, title.str());
    ++tally.figures;
    if (o.profiles) {
      std::ostringstream short_title;
      short_title << s.label << " (Dx = " << s.Dx << " d): " << f.lines.size() << " line(s)";
      profile = write_profiles(dir, index, s, f, ids, o.peierls, o.crossing, short_title.str());
    }
    if (o.front) {
      std::ostringstream short_title;
      short_title << s.label << " (Dx = " << s.Dx << " d)";
      front = write_front(dir, index, s, f, ids, o.peierls, o.front_options, short_title.str(),
                          history);
    }
  }
  return {{"frame", index},
          {"file", where.file},
          {"frame_in_file", where.frame_in_file},
          {"label", s.label},
          {"iteration", s.iteration},
          {"Dx", s.Dx},
          {"periodic", periodic},
          {"tip_angle", s.tip.angle},
          {"tip_mismatch", s.tip.mismatch},
          {"contact_sites", f.contact_sites},
          {"contact_centre", {f.contact_centre.x, f.contact_centre.y}},
          {"contact_radius", f.contact_radius},
          {"core_crossings", f.core_crossings},
          {"registry_crossings_rejected", f.registry_crossings},
          {"dropped_short", f.dropped_short},
          {"joined_pieces", f.joined_pieces},
          {"figure", plot ? nlohmann::json(name) : nullptr},
          {"profiles", profile},
          {"front", front},
          {"lines", lines}};
}

// events.csv from the tracker's events; returns their counts by type.
std::map<std::string, int> write_events(const fs::path& csv, const tracking::Tracker& tracker,
                                        const std::vector<FrameInfo>& info) {
  app::CsvTable events({"frame", "file", "label", "iteration", "Dx", "type", "before_ids",
                        "after_ids", "x", "y", "location", "slipped_area_change"});
  std::map<std::string, int> counts;
  for (const auto& e : tracker.events()) {
    const FrameInfo& fi = info[static_cast<std::size_t>(e.frame)];
    events.add_row({static_cast<long long>(e.frame), fi.file, fi.label,
                    static_cast<long long>(fi.iteration), fi.Dx, tracking::to_string(e.type),
                    join_ids(e.before), join_ids(e.after), e.where.x, e.where.y, e.location,
                    e.slipped_area_change});
    ++counts[tracking::to_string(e.type)];
  }
  events.write(csv);
  return counts;
}

}  // namespace

namespace {

// The edge and screw fits of a peierls_scan summary (its file or folder) into `peierls`, and
// what summary.json says of them.
nlohmann::json read_local_peierls(const std::string& path, LocalPeierls& peierls) {
  const app::PeierlsSummaryFit edge = app::read_peierls_fit(path, "edge");
  const app::PeierlsSummaryFit screw = app::read_peierls_fit(path, "screw");
  peierls = {edge.law, screw.law, {}};
  const app::PeierlsAngles all = app::read_peierls_angles(path);
  peierls.angles = all.angles;
  nlohmann::json angles = nlohmann::json::array();
  for (std::size_t i = 0; i < all.angles.size(); ++i) {
    const nucleation::AngleLaw& a = all.angles[i];
    nlohmann::json entry = {{"theta_deg", a.theta_deg}, {"samples_b_core", a.b_core}};
    if (a.law) {
      entry["fit"] = all.fit_keys[i];
      entry["k1"] = a.law->k1;
      entry["k2"] = a.law->k2;
    }
    angles.push_back(std::move(entry));
  }
  return {{"source", edge.file.string()},
          {"edge", {{"k1", edge.law.k1}, {"k2", edge.law.k2}}},
          {"screw", {{"k1", screw.law.k1}, {"k2", screw.law.k2}}},
          {"angles", angles},
          {"table", all.table.string()},
          {"window_b_core", {edge.law.b_min, edge.law.b_max}}};
}

// What to read, in order: every file whole, or the frames of one label from each file, or
// those of a slip event's three labels, label by label. Pairs of file and label ("": all).
std::vector<std::pair<std::string, std::string>> snapshot_reads(
    const std::vector<std::string>& files, const std::string& label, int slip) {
  std::vector<std::pair<std::string, std::string>> reads;
  if (slip > 0) {
    const std::string prefix = slide::slip_label(slip) + "_";
    for (const char* part : {"before", "path", "after"}) {
      for (const auto& file : files)
        reads.emplace_back(file, prefix + part);
    }
  } else {
    for (const auto& file : files)
      reads.emplace_back(file, label);
  }
  return reads;
}

nlohmann::json summary_json(const nlohmann::json& inputs, const FrameOptions& o,
                            const nlohmann::json& peierls_json, std::size_t frames,
                            const Tally& tally, const std::map<std::string, int>& counts,
                            double wall) {
  nlohmann::json options = app::settings_echo(o, FrameOptions::settings());
  options["peierls"] = peierls_json;
  return {{"inputs", inputs},
          {"options", options},
          {"results",
           {{"frames", frames},
            {"max_lines_per_frame", tally.max_lines},
            {"lines_by_kind", tally.kinds},
            {"events_by_type", counts},
            {"figures", tally.figures}}},
          {"run",
           {{"detect_s", tally.detect_s},
            {"detect_max_frame_s", tally.detect_max_s},
            {"wall_s", wall},
            {"provenance", app::provenance_json()}}}};
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Find, trace and follow dislocation lines and loops in NetCDF snapshots"};
    std::vector<std::string> files;
    std::string out = "results/track_loops";
    FrameOptions o;
    cli.add_option("snapshots", files,
                   "NetCDF snapshot files (contact_slide snapshots/*.nc, peierls_scan cells); "
                   "their frames form one sequence in the order given (required, but for "
                   "--list-settings)")
        ->check(CLI::ExistingFile);
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    std::string label;
    auto* label_option = cli.add_option(
        "--label", label,
        "Only the frames with this label, e.g. slip_011_path: one slip's relaxation path out of "
        "a run's paths.nc; files that hold none are skipped");
    int slip = 0;
    cli.add_option("--slip", slip,
                   "Only slip event N: its state before, its relaxation path and its state after "
                   "(slip_NNN_before, slip_NNN_path, slip_NNN_after), in that order whatever the "
                   "order of the files (e.g. snapshots/*.nc)")
        ->check(CLI::Range(1, 999999))
        ->excludes(label_option);
    app::SettingFlags flags;
    const FrameOptions defaults;
    flags.add(cli, FrameOptions::settings(), {}, "summary key", &defaults);
    std::string peierls_path;
    cli.add_option("--peierls", peierls_path,
                   "peierls_scan summary.json or its folder: with --profiles, draw the local "
                   "Peierls stress of its edge and screw fits at the local pressure; with "
                   "--front, compare every point with its angle's")
        ->check(CLI::ExistingPath);
    app::add_list_settings(cli, FrameOptions::settings(), FrameOptions{}, "docs/tracking.md");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    if (files.empty()) throw std::invalid_argument("snapshots: at least one file is required");
    flags.apply(FrameOptions::settings(), o);
    settings::validate(o, FrameOptions::settings());
    nlohmann::json peierls_json = nullptr;
    if (!peierls_path.empty()) {
      if (!o.profiles && !o.front)
        throw std::invalid_argument("--peierls is drawn beside --profiles or --front: add one");
      peierls_json = read_local_peierls(peierls_path, o.peierls);
    }

    const auto start = std::chrono::steady_clock::now();
    const fs::path dir = app::ensure_directory(out);
    // The VTK files of an earlier, longer run in this folder would read as frames of this one
    // (ParaView opens the numbered series whole).
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      // So would an earlier run's front tables, which this run may not write (no --front).
      const bool front =
          name.starts_with("front_") && (name.ends_with(".csv") || name.ends_with(".png"));
      if ((name.starts_with("lines_") && name.ends_with(".vtk")) || front)
        stale.push_back(entry.path());
    }
    for (const auto& file : stale)
      fs::remove(file);
    tracking::Tracker tracker(o.track);
    FrontHistory front_history;  // --front: the previous frame's, for the moves since
    nlohmann::json frames_json = nlohmann::json::array(), inputs = nlohmann::json::array();
    std::vector<FrameInfo> info;
    Tally tally;
    // A bad file anywhere in the list stops the run before any work (fields are read later).
    for (const auto& file : files)
      app::check_snapshot_file(file);
    const auto reads = snapshot_reads(files, label, slip);
    for (const auto& [file, only] : reads) {
      const std::vector<slide::Snapshot> snaps = app::read_snapshots(file, only);
      if (snaps.empty()) continue;  // no frame of the label
      const bool periodic = o.periodic || periodic_attribute(file);
      inputs.push_back({{"file", fs::absolute(file).string()},
                        {"frames", snaps.size()},
                        {"periodic", periodic}});
      for (std::size_t k = 0; k < snaps.size(); ++k) {
        info.push_back({fs::path(file).filename().string(), snaps[k].label, static_cast<int>(k),
                        snaps[k].iteration, snaps[k].Dx});
        frames_json.push_back(track_frame(dir, snaps[k], static_cast<int>(info.size()) - 1,
                                          info.back(), periodic, o, tracker, tally, front_history));
      }
    }
    if (info.empty()) {
      throw std::invalid_argument(
          slip > 0 ? "--slip " + std::to_string(slip) + ": no frame of this slip event in the files"
                   : "--label " + label + ": no frame with this label in the files");
    }

    const std::map<std::string, int> counts = write_events(dir / "events.csv", tracker, info);
    app::write_json(dir / "lines.json",
                    {{"description",
                      "per frame of the sequence: the dislocation lines found (MODEL.md 7); "
                      "lengths in d, areas in d^2, angles in degrees from b = (burgers_x, "
                      "burgers_y) = burgers d_tip along the tip's first axis, (burgers d, 0) for "
                      "the aligned tip (0: screw, 90: edge); ids persist across frames "
                      "(events.csv)"},
                     {"frames", frames_json}});
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    app::write_json(dir / "summary.json",
                    summary_json(inputs, o, peierls_json, info.size(), tally, counts, wall));

    std::printf("%zu frame(s), at most %zu line(s) per frame; events:", info.size(),
                tally.max_lines);
    if (counts.empty()) std::printf(" none");
    for (const auto& [type, count] : counts)
      std::printf(" %s %d", type.c_str(), count);
    std::printf("\nresults: %s, %s, %s (%zu figure(s))\n", (dir / "lines.json").c_str(),
                (dir / "events.csv").c_str(), (dir / "summary.json").c_str(), tally.figures);
    return 0;
  });
}
