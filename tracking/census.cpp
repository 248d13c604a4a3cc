// The census of a frame's lines (census.hpp; MODEL.md sections 7 and 8).
#include "asperity/tracking/census.hpp"

#include <limits>
#include <vector>

namespace asperity::tracking {

LineCensus census(const FrameLines& frame) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  LineCensus c;
  c.contact_sites = frame.contact_sites;
  c.lines = static_cast<int>(frame.lines.size());
  double screw_length = 0.0;
  const Line* largest = nullptr;
  std::vector<bool> counted(frame.regions.size(), false);
  for (const Line& l : frame.lines) {
    if (l.kind == LineKind::loop) {
      ++c.loops;
      c.loop_area += l.area;
      c.loop_length += l.length;
      screw_length += l.screw_fraction * l.length;
      if (largest == nullptr || l.area > largest->area) largest = &l;
    } else {
      (l.kind == LineKind::open ? c.open_lines : c.wrapping_lines) += 1;
      c.open_length += l.length;
    }
    // Several lines can bound one domain (a ring between two loops): it counts once.
    if (l.slipped_region >= 0) {
      const auto r = static_cast<std::size_t>(l.slipped_region);
      if (!counted[r]) {
        counted[r] = true;
        c.slipped_area += static_cast<double>(frame.regions[r].size()) * frame.d * frame.d;
      }
    }
  }
  c.loop_screw_fraction = c.loop_length > 0.0 ? screw_length / c.loop_length : nan;
  if (largest != nullptr) {
    c.largest_loop_area = largest->area;
    c.largest_loop_x_extent = largest->x_max - largest->x_min;
    c.largest_loop_y_extent = largest->y_max - largest->y_min;
    c.largest_loop_screw_fraction = largest->screw_fraction;
    c.largest_loop_cx = largest->centroid.x;
    c.largest_loop_cy = largest->centroid.y;
  } else {
    c.largest_loop_screw_fraction = nan;
    c.largest_loop_cx = c.largest_loop_cy = nan;
  }
  return c;
}

}  // namespace asperity::tracking
