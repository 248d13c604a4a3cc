#include "asperity/tracking/profile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace asperity::tracking {

std::string to_string(ProfileAxis axis) {
  return axis == ProfileAxis::x ? "x" : "y";
}

StressProfile stress_profile(const slide::Snapshot& s, ProfileAxis axis) {
  const LatticeBlock& blk = s.block;
  const std::size_t n = blk.shape.count();
  for (const auto* f : {&s.tau_x, &s.tau_y, &s.tau_max, &s.pressure}) {
    if (f->size() != n)
      throw std::invalid_argument("stress_profile: a field's size differs from the block's " +
                                  std::to_string(n) + " sites");
  }
  if (!s.in_contact.empty() && s.in_contact.size() != n)
    throw std::invalid_argument("stress_profile: in_contact's size differs from the block's");
  StressProfile p;
  p.axis = axis;
  p.tau_max_peak = n > 0 ? *std::max_element(s.tau_max.begin(), s.tau_max.end()) : 0.0;
  // d = 1: the snapshot's unit of length (slide::Snapshot).
  const int fixed =
      axis == ProfileAxis::x ? -blk.origin1 : static_cast<int>(std::lround(s.Dx)) - blk.origin0;
  const int fixed_size = axis == ProfileAxis::x ? blk.shape.n1 : blk.shape.n0;
  if (fixed < 0 || fixed >= fixed_size) {
    throw std::invalid_argument(
        "stress_profile: the " +
        std::string(axis == ProfileAxis::x ? "row Y = 0" : "column through Dx") +
        " lies outside the snapshot's block");
  }
  p.through = axis == ProfileAxis::x ? 0.0 : blk.x(fixed, 1.0);
  p.centre = axis == ProfileAxis::x ? s.Dx : 0.0;
  const int along = axis == ProfileAxis::x ? blk.shape.n0 : blk.shape.n1;
  for (int k = 0; k < along; ++k) {
    const int i0 = axis == ProfileAxis::x ? k : fixed;
    const int i1 = axis == ProfileAxis::x ? fixed : k;
    const auto i = static_cast<std::size_t>(i0) * static_cast<std::size_t>(blk.shape.n1) +
                   static_cast<std::size_t>(i1);
    p.position.push_back((axis == ProfileAxis::x ? blk.x(i0, 1.0) : blk.y(i1, 1.0)) - p.centre);
    p.tau_x.push_back(s.tau_x[i]);
    p.tau_y.push_back(s.tau_y[i]);
    p.tau_max.push_back(s.tau_max[i]);
    p.pressure.push_back(s.pressure[i]);
    // Under a tip out of registry the registry runs along the tip's axis, not s_x: no offset.
    if (s.sx.size() == n && s.tip.aligned()) p.offset.push_back(s.sx[i] - blk.x(i0, 1.0));
    p.in_contact.push_back(s.in_contact.empty() ? std::uint8_t(s.tau_max[i] > 0.0)
                                                : s.in_contact[i]);
  }
  return p;
}

std::vector<CoreCrossing> core_crossings(const FrameLines& f, const StressProfile& p) {
  std::vector<CoreCrossing> out;
  const bool along_x = p.axis == ProfileAxis::x;
  // Coordinates across the profile (the one that is fixed) and along it.
  const auto across = [&](const Point& q) { return along_x ? q.y : q.x; };
  const auto along = [&](const Point& q) { return along_x ? q.x : q.y; };
  for (std::size_t li = 0; li < f.lines.size(); ++li) {
    const Line& l = f.lines[li];
    const std::size_t m = l.points.size();
    const std::size_t segments = l.kind == LineKind::open ? (m > 0 ? m - 1 : 0) : m;
    for (std::size_t k = 0; k < segments && k < l.angle_deg.size(); ++k) {
      const Point& a = l.points[k];
      const Point& b = l.points[(k + 1) % m];
      const double ca = across(a) - p.through, cb = across(b) - p.through;
      // Half-open: a segment counts if one end lies strictly above the row and the other on or
      // below it, so that a vertex on the row belongs to one segment only. An open line's end
      // on the row has one segment, which counts whichever side it comes from.
      const bool crosses = (ca <= 0.0 && cb > 0.0) || (cb <= 0.0 && ca > 0.0);
      const bool open_end =
          l.kind == LineKind::open &&
          ((k == 0 && ca == 0.0 && cb < 0.0) || (k + 1 == segments && cb == 0.0 && ca < 0.0));
      if (!crosses && !open_end) continue;
      const double t = ca / (ca - cb);
      out.push_back({.position = along(a) + t * (along(b) - along(a)) - p.centre,
                     .angle_deg = l.angle_deg[k],
                     .line = li,
                     .kind = l.kind});
    }
  }
  std::sort(out.begin(), out.end(),
            [](const CoreCrossing& u, const CoreCrossing& v) { return u.position < v.position; });
  return out;
}

CoreStress core_stress(const StressProfile& p, double from, double to) {
  if (p.offset.size() != p.position.size())
    throw std::invalid_argument("core_stress: the profile has no registry offset (s_x)");
  if (!(from <= to))
    throw std::invalid_argument("core_stress: the window's ends are out of order (from > to)");
  CoreStress c;
  double weighted = 0.0;
  for (std::size_t k = 0; k + 1 < p.position.size(); ++k) {
    // Positions grow with k, so rho keeps one sign across a core. A bond cut by the window's
    // end counts by the fraction of it inside, so that the window is where it is said to be,
    // not rounded to whole bonds (up to d/2 off-centre, which weighs one side of the core's
    // swing more).
    const double a = p.position[k], b = p.position[k + 1];
    const double inside = (std::min(b, to) - std::max(a, from)) / (b - a);
    if (!(inside > 0.0)) continue;
    if (!p.in_contact[k] || !p.in_contact[k + 1]) continue;
    const double rho = std::min(inside, 1.0) * (p.offset[k + 1] - p.offset[k]);
    c.slip += rho;
    weighted += rho * 0.5 * (p.tau_x[k] + p.tau_x[k + 1]);
    ++c.bonds;
  }
  c.tau = c.slip != 0.0 ? weighted / c.slip : std::nan("");
  return c;
}

std::vector<CrossingStress> crossing_stresses(const StressProfile& p,
                                              const std::vector<CoreCrossing>& cores,
                                              double widths) {
  if (!(widths > 0.0))
    throw std::invalid_argument("crossing_stresses: widths must be > 0 (core widths either side)");
  std::vector<CrossingStress> out;
  out.reserve(cores.size());
  for (std::size_t j = 0; j < cores.size(); ++j) {
    const double x = cores[j].position;
    CrossingStress c;
    if (!p.position.empty()) {
      const auto nearest =
          std::min_element(p.position.begin(), p.position.end(),
                           [x](double a, double b) { return std::abs(a - x) < std::abs(b - x); });
      c.tau_max = p.tau_max[static_cast<std::size_t>(nearest - p.position.begin())];
    }
    // b_core = d G / tau_max with tau in G and lengths in d; no envelope, no core width.
    const double full = c.tau_max > 0.0 ? widths / c.tau_max : 0.0;
    double h = full;
    if (j > 0) h = std::min(h, 0.5 * (x - cores[j - 1].position));
    if (j + 1 < cores.size()) h = std::min(h, 0.5 * (cores[j + 1].position - x));
    // The first site out of the contact on either side ends the window (the contact's edge, or
    // a hole in it).
    for (std::size_t k = 0; k < p.position.size(); ++k) {
      if (!p.in_contact[k]) h = std::min(h, std::abs(p.position[k] - x));
    }
    c.half_width = h;
    c.cut = !(h >= full);
    c.stress = core_stress(p, x - h, x + h);
    out.push_back(c);
  }
  return out;
}

std::array<LoopCoreStress, 2> loop_core_stress(const slide::Snapshot& snapshot,
                                               const FrameLines& lines) {
  std::array<LoopCoreStress, 2> out;
  for (const ProfileAxis axis : {ProfileAxis::x, ProfileAxis::y}) {
    StressProfile p;
    try {
      p = stress_profile(snapshot, axis);
    } catch (const std::invalid_argument&) {
      continue;  // the row or column lies outside the block: no crossing
    }
    if (p.offset.empty()) continue;  // no s_x, or a tip out of registry (stress_profile)
    const std::vector<CoreCrossing> cores = core_crossings(lines, p);
    const std::vector<CrossingStress> held = crossing_stresses(p, cores);
    LoopCoreStress& o = out[axis == ProfileAxis::x ? 0 : 1];
    double stress = 0.0, tau_max = 0.0;
    for (std::size_t j = 0; j < cores.size(); ++j) {
      if (cores[j].kind != LineKind::loop || !held[j].resolved()) continue;
      stress += held[j].stress.tau;
      tau_max += held[j].tau_max;
      ++o.crossings;
    }
    if (o.crossings > 0) {
      o.stress = stress / o.crossings;
      o.tau_max = tau_max / o.crossings;
    }
  }
  return out;
}

}  // namespace asperity::tracking
