// Pure functions over a slide's trace (MODEL.md section 5): trace.hpp.
#include "asperity/core/slide/trace.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace asperity::slide {

std::string to_string(FrictionMeasure m) {
  return m == FrictionMeasure::load ? "load" : "area";
}

}  // namespace asperity::slide

namespace asperity::slide::detail {

bool peak_held(std::span<const TraceRow> t, double best, double ratio_now, double Dx_now, double d,
               int slips_to_stop, FrictionMeasure measure) {
  // The slide stops at a slip, and not while Fx is still within reach of the peak (after a
  // small slip in Regime III it can lie just below it and rise past it next).
  if (t.empty() || !t.back().slip) return false;
  const auto y = [&](std::size_t i) { return ratio_of(t[i], measure); };
  const double floor_tie = kPeakTie * std::abs(best);
  double largest_tie = floor_tie;
  std::optional<double> held_Dx;
  std::size_t top = 0;  // highest sample of the current stick segment
  for (std::size_t i = 1; i <= t.size(); ++i) {
    if (i < t.size() && !t[i].slip) {
      if (t[top].slip || y(i) > y(top)) top = i;
      continue;
    }
    if (!t[top].slip) {  // the segment ends
      double tie = floor_tie;
      if (top > 0 && !t[top - 1].slip) tie = std::max(tie, std::abs(y(top) - y(top - 1)));
      if (top + 1 < t.size() && !t[top + 1].slip)
        tie = std::max(tie, std::abs(y(top) - y(top + 1)));
      largest_tie = std::max(largest_tie, tie);
      if (!held_Dx && y(top) + tie >= best) held_Dx = t[top].Dx;
    }
    if (i < t.size()) {
      top = i;
      // A slip row is a sample of its own, exact in Dx (a bracket end). In a Regime III
      // steady state Fx can rise through a run of tiny slips with no stable sample between
      // them and peak on one of them (R = 40 d, a = 36 d: a 2-site slip, the same to 1e-12
      // every period from 11.6 d on); without this such a peak never held and the slide ran
      // to the cap, reporting a lower bound.
      if (!held_Dx && y(i) + floor_tie >= best) held_Dx = t[i].Dx;
    }
  }
  if (!held_Dx || ratio_now >= best - largest_tie) return false;
  if (Dx_now < *held_Dx + d - 1e-9 * d) return false;
  return std::count_if(t.begin(), t.end(), [&](const TraceRow& row) {
           return row.slip && row.Dx > *held_Dx;
         }) >= slips_to_stop;
}

double kinetic_friction(std::span<const TraceRow> t, double Dx_end, double d,
                        FrictionMeasure measure) {
  auto from = std::find_if(t.begin(), t.end(), [](const TraceRow& row) { return row.slip; });
  if (from == t.end() && Dx_end >= d) {
    from = std::find_if(t.begin(), t.end(),
                        [&](const TraceRow& row) { return row.Dx >= Dx_end - d - 1e-12; });
  }
  if (from == t.end()) return std::numeric_limits<double>::quiet_NaN();
  double area = 0.0, span = 0.0;
  for (auto a = from; a + 1 != t.end(); ++a) {
    const double w = (a + 1)->Dx - a->Dx;
    area += 0.5 * w * (ratio_of(*a, measure) + ratio_of(*(a + 1), measure));
    span += w;
  }
  return span > 0.0 ? area / span : ratio_of(*from, measure);
}

double PeakBracket::vertex(double& y_vertex) const {
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double curv = (d12 - d01) / (x2 - x0);
  const double xv = 0.5 * (x0 + x1) - d01 / (2.0 * curv);
  y_vertex = y1 + (xv - x1) * (d01 + curv * (xv - x0));  // Newton form through the 3 points
  return curv < 0.0 ? xv : x1;
}

double peak_precision_before_slip(const TraceRow& prev, const TraceRow& peak, const TraceRow& next,
                                  FrictionMeasure measure) {
  const auto ratio = [&](const TraceRow& row) { return ratio_of(row, measure); };
  return (next.Dx - peak.Dx) * std::abs((ratio(peak) - ratio(prev)) / (peak.Dx - prev.Dx));
}

}  // namespace asperity::slide::detail
