// What the dislocation lines of one snapshot add up to (MODEL.md sections 7 and 8): how many
// closed loops are held in the contact and how much area they enclose, how much of the contact
// lies on the slipped side of a line, and the character of the loops' length. One row of these
// per slip (friction_sweep --largest-slip, slips.csv) shows a Regime III slide's loops nucleating,
// creeping and being arrested, which is what makes its friction rise with load.
//
// Only the tracking/ library: FrameLines in (find_lines), a plain struct out.
#pragma once

#include <cstddef>

#include "asperity/tracking/lines.hpp"

namespace asperity::tracking {

struct LineCensus {
  int lines = 0;  // every line kept by find_lines
  int loops = 0, open_lines = 0, wrapping_lines = 0;
  double loop_area = 0.0;  // sum of the loops' enclosed areas (d^2); nested loops both count
  double loop_length = 0.0, open_length = 0.0;  // (d); wrapping lines count as open
  // Length-weighted screw fraction of the loops (Line::screw_fraction); NaN without loops.
  double loop_screw_fraction = 0.0;
  // The loop of the largest enclosed area (the first of equals); zeros and NaN without loops.
  double largest_loop_area = 0.0;                       // d^2
  double largest_loop_x_extent = 0.0;                   // along x, the sliding direction (d)
  double largest_loop_y_extent = 0.0;                   // d
  double largest_loop_screw_fraction = 0.0;             // NaN without loops
  double largest_loop_cx = 0.0, largest_loop_cy = 0.0;  // centroid of its enclosed area (d)
  // The contact sites in the distinct domains on the slipped side of some line
  // (FrameLines::regions referenced by Line::slipped_region), times d^2: after the first slip of
  // a Regime III slide, the ring the nucleated loop swept before it was arrested.
  double slipped_area = 0.0;
  std::size_t contact_sites = 0;
};

LineCensus census(const FrameLines& frame);

}  // namespace asperity::tracking
