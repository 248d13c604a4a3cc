// Pure functions over a slide's trace (MODEL.md section 5): the stop rule of the automatic
// distance (when the static peak has held), kinetic friction, and the parabola through three
// samples that refines a smooth maximum and measures mu's resolution. The protocol
// (protocol.hpp) calls them; they hold no state of a slide and are tested on hand-made traces
// (tests/unit/test_peak_rule.cpp).
#pragma once

#include <span>

#include "asperity/core/slide/types.hpp"

namespace asperity::slide::detail {

// The static peak is established once it has held over a whole period d of sliding with
// slips_to_stop slip events after it. In Regime II the stick-slip cycle repeats with period
// d, so this is the slips_to_stop-th slip itself; in Regime III arrested loops pile up and
// Fx keeps rising through many small slips (R = 100 d, a = 70 d: mu/alpha 0.091 at the
// second slip, 0.129 and still rising 2.5 d later), and a count of slips alone would report
// the first one as mu.
// A repeated cycle reaches its maximum again only to within the sampling of the trace (a
// bracket of min_step before a slip; a smooth maximum between coarse steps, which can be
// missed altogether: the explicit model's first cycle, sampled every 0.4 d, shows 0.392
// where the second shows 0.423), and that must not count as a new peak. So each stick
// segment (the stable samples between slips) carries the uncertainty of its highest sample,
// the steps to its stable neighbours, at least kPeakTie (a fifth of the 0.5% to which mu is
// converged, docs/benchmarks.md); the peak held from the first segment whose highest sample
// reaches the maximum within its own uncertainty, or the first slip row that does within
// kPeakTie.
//
// t: the trace so far; best: the largest Fx/Fz of it; ratio_now, Dx_now: the current state (the
// last row); d: the period; slips_to_stop: the slip events wanted after the peak.
// Here and below "Fx/Fz" is the slide's friction ratio (types.hpp, FrictionMeasure): Fx / Fz,
// or Fx / A for FrictionMeasure::area.
inline constexpr double kPeakTie = 1e-3;
bool peak_held(std::span<const TraceRow> t, double best, double ratio_now, double Dx_now, double d,
               int slips_to_stop, FrictionMeasure measure = FrictionMeasure::load);

// The friction ratio of a row.
inline double ratio_of(const TraceRow& row, FrictionMeasure measure) {
  return friction_ratio(row.Fx, row.Fz, row.area, measure);
}

// Kinetic friction of a trace (ours: MODEL.md 1 defines only the static mu; this is the
// sliding average of the stick-slip of MODEL.md 5): the mean of Fx/Fz over Dx (trapezoid: adaptive
// steps are uneven) after the first slip; without slips (smooth sliding) over the last whole
// period d before Dx_end. NaN if neither exists (no slip, slide shorter than d).
double kinetic_friction(std::span<const TraceRow> t, double Dx_end, double d,
                        FrictionMeasure measure = FrictionMeasure::load);

// Three samples (x0 < x1 < x2, y1 the highest) of Fx/Fz around a smooth maximum. vertex() is the
// top of the parabola through them (Newton form) and its height, or x1 itself when they are not
// concave; the adaptive protocol refines the peak with it (a Brent-like search, protocol.hpp),
// and y_vertex - y1 is mu's resolution from the sampling.
struct PeakBracket {
  double x0, x1, x2;
  double y0, y1, y2;
  double vertex(double& y_vertex) const;
};

// mu's resolution when the peak is the last stable sample before a slip (`next` the slip row,
// `prev` the sample before the peak): the instability lies within the step after the peak,
// which the slope before it turns into a difference of Fx/Fz.
double peak_precision_before_slip(const TraceRow& prev, const TraceRow& peak, const TraceRow& next,
                                  FrictionMeasure measure = FrictionMeasure::load);

}  // namespace asperity::slide::detail
