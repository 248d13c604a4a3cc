#include "asperity/apps/common/lines_json.hpp"

#include <cmath>

namespace asperity::app {

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json line_json(const tracking::Line& l, int id, const tracking::FrameLines& f,
                         double centre_fraction) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : l.points)
    points.push_back({p.x, p.y});
  const double slipped =
      l.slipped_region >= 0
          ? static_cast<double>(f.regions[static_cast<std::size_t>(l.slipped_region)].size()) *
                f.d * f.d
          : 0.0;
  const tracking::Point b = tracking::burgers_vector(l, f);
  return {{"id", id},
          {"kind", tracking::to_string(l.kind)},
          // b: d_tip along the tip's first axis per unit of burgers (d along x when aligned).
          {"burgers", l.burgers},
          {"burgers_x", b.x},
          {"burgers_y", b.y},
          {"registry_consistency", l.registry_consistency},
          {"interior_ends", l.interior_ends},
          {"pieces", l.pieces},
          {"length", l.length},
          {"area", l.kind == tracking::LineKind::loop ? nlohmann::json(l.area) : nullptr},
          {"centroid", {l.centroid.x, l.centroid.y}},
          {"bbox", {l.x_min, l.y_min, l.x_max, l.y_max}},
          {"x_extent", l.x_max - l.x_min},
          {"y_extent", l.y_max - l.y_min},
          {"aspect_ratio", finite_or_null(l.aspect_ratio)},
          {"screw_fraction", l.screw_fraction},
          {"edge_fraction", l.edge_fraction},
          {"mean_angle_deg", l.mean_angle_deg},
          {"slipped_area", slipped},
          {"location", tracking::location_class(f, l.centroid, centre_fraction)},
          {"points", points},
          {"angle_deg", l.angle_deg}};
}

std::vector<std::pair<std::string, nlohmann::json>> census_fields(const tracking::LineCensus& c) {
  const auto count = [](auto n) { return nlohmann::json(static_cast<long long>(n)); };
  return {{"contact_sites", count(c.contact_sites)},
          {"lines", count(c.lines)},
          {"loops", count(c.loops)},
          {"open_lines", count(c.open_lines)},
          {"wrapping_lines", count(c.wrapping_lines)},
          {"loop_area", c.loop_area},
          {"loop_length", c.loop_length},
          {"open_length", c.open_length},
          {"loop_screw_fraction", c.loop_screw_fraction},
          {"largest_loop_area", c.largest_loop_area},
          {"largest_loop_x_extent", c.largest_loop_x_extent},
          {"largest_loop_y_extent", c.largest_loop_y_extent},
          {"largest_loop_screw_fraction", c.largest_loop_screw_fraction},
          {"largest_loop_cx", c.largest_loop_cx},
          {"largest_loop_cy", c.largest_loop_cy},
          {"slipped_area", c.slipped_area}};
}

}  // namespace asperity::app
