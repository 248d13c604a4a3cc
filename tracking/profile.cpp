// Stress profiles through a snapshot and the stress on dislocation fronts (MODEL.md 3, 6 and 7;
// design and the quantities in profile.hpp): tau = f / d^2 along a lattice row or column through
// the tip centre against tau_max = alpha p; the stress a core feels, tau_x weighted by its slip
// density |du_x/dn| (and tau_y by |du_y/dn|), the Peierls-Nabarro force per Burgers vector; the
// local Peierls stress it is compared with comes from the caller (nucleation::).
#include "asperity/tracking/profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace asperity::tracking {

std::string to_string(ProfileAxis axis) {
  return axis == ProfileAxis::x ? "x" : "y";
}

namespace {

// Whether site i is in the contact: the snapshot's flag, or tau_max > 0 without one.
bool in_contact_at(const slide::Snapshot& s, std::size_t i) {
  return s.in_contact.empty() ? s.tau_max[i] > 0.0 : s.in_contact[i] != 0;
}

// u_y at site i of lattice row Y (d): the snapshot's u_y, or s_y - Y (a contact's snapshot has
// both equal; a Peierls cell's keeps s_y = u_y, the same registry, and u_y).
double uy_at(const slide::Snapshot& s, std::size_t i, double Y) {
  return s.uy.size() == s.sx.size() ? s.uy[i] : s.sy[i] - Y;
}

// The profile along `axis` through block index `fixed` (i1 of a row along x, i0 of a column
// along y), which the caller has checked lies inside the block.
StressProfile profile_at(const slide::Snapshot& s, ProfileAxis axis, int fixed) {
  const LatticeBlock& blk = s.block;
  const std::size_t n = blk.shape.count();
  StressProfile p;
  p.axis = axis;
  p.tau_max_peak = n > 0 ? *std::max_element(s.tau_max.begin(), s.tau_max.end()) : 0.0;
  // d = 1: the snapshot's unit of length (slide::Snapshot).
  p.through = axis == ProfileAxis::x ? blk.y(fixed, 1.0) : blk.x(fixed, 1.0);
  p.centre = axis == ProfileAxis::x ? s.Dx : 0.0;
  const int along = axis == ProfileAxis::x ? blk.shape.n0 : blk.shape.n1;
  const bool offsets = s.sx.size() == n && s.tip.aligned();
  // The displacement across b: u_y, which is s_y - Y in a contact's snapshot (a cell's keeps
  // s_y = u_y, the same registry, so s_y - Y would step by d between rows).
  const bool offsets_y = offsets && (s.uy.size() == n || s.sy.size() == n);
  p.position.reserve(static_cast<std::size_t>(along));
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
    if (offsets) p.offset.push_back(s.sx[i] - blk.x(i0, 1.0));
    if (offsets_y) p.offset_y.push_back(uy_at(s, i, blk.y(i1, 1.0)));
    p.in_contact.push_back(static_cast<std::uint8_t>(in_contact_at(s, i)));
  }
  return p;
}

void check_fields(const slide::Snapshot& s, const char* who) {
  const std::size_t n = s.block.shape.count();
  for (const auto* f : {&s.tau_x, &s.tau_y, &s.tau_max, &s.pressure}) {
    if (f->size() != n)
      throw std::invalid_argument(std::string(who) + ": a field's size differs from the block's " +
                                  std::to_string(n) + " sites");
  }
  if (!s.in_contact.empty() && s.in_contact.size() != n)
    throw std::invalid_argument(std::string(who) + ": in_contact's size differs from the block's");
}

}  // namespace

StressProfile stress_profile(const slide::Snapshot& s, ProfileAxis axis) {
  check_fields(s, "stress_profile");
  const LatticeBlock& blk = s.block;
  const int fixed =
      axis == ProfileAxis::x ? -blk.origin1 : static_cast<int>(std::lround(s.Dx)) - blk.origin0;
  const int fixed_size = axis == ProfileAxis::x ? blk.shape.n1 : blk.shape.n0;
  if (fixed < 0 || fixed >= fixed_size) {
    throw std::invalid_argument(
        "stress_profile: the " +
        std::string(axis == ProfileAxis::x ? "row Y = 0" : "column through Dx") +
        " lies outside the snapshot's block");
  }
  return profile_at(s, axis, fixed);
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
  const bool with_y = p.offset_y.size() == p.position.size() && p.tau_y.size() == p.position.size();
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
    const double share = std::min(inside, 1.0);
    const double rho = share * (p.offset[k + 1] - p.offset[k]);
    c.slip += rho;
    weighted += rho * 0.5 * (p.tau_x[k] + p.tau_x[k + 1]);
    if (with_y)
      weighted += share * (p.offset_y[k + 1] - p.offset_y[k]) * 0.5 * (p.tau_y[k] + p.tau_y[k + 1]);
    ++c.bonds;
  }
  c.tau = c.slip != 0.0 ? weighted / c.slip : std::nan("");
  return c;
}

const settings::Table<CrossingOptions>& CrossingOptions::settings() {
  using O = CrossingOptions;
  static const settings::Table<O> table = {settings::number<O>(
      "widths", [](auto& o) -> auto& { return o.widths; }, settings::Range::positive(), "b_core",
      "window around each core crossing of the profiles, in local core widths either side",
      "--profile-widths")};
  return table;
}

void CrossingOptions::validate() const {
  settings::validate(*this, settings());
}

std::vector<CrossingStress> crossing_stresses(const StressProfile& p,
                                              const std::vector<CoreCrossing>& cores,
                                              const CrossingOptions& options) {
  options.validate();
  const double widths = options.widths;
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
    // a hole in it), and so do the profile's ends (the block's: a core near them has no sites
    // on its far side, which would weigh the window as if it held all of it).
    for (std::size_t k = 0; k < p.position.size(); ++k) {
      if (!p.in_contact[k]) h = std::min(h, std::abs(p.position[k] - x));
    }
    if (!p.position.empty()) h = std::min({h, x - p.position.front(), p.position.back() - x});
    h = std::max(h, 0.0);
    c.half_width = h;
    c.cut = !(h >= full);
    c.stress = core_stress(p, x - h, x + h);
    out.push_back(c);
  }
  return out;
}

const settings::Table<FrontOptions>& FrontOptions::settings() {
  using R = settings::Range;
  using O = FrontOptions;
  static const settings::Table<O> table = {
      settings::number<O>(
          "span", [](auto& o) -> auto& { return o.span; }, R::positive(), "d",
          "length of line pooled per point: at least the period |m| d of the "
          "directions m to be measured (docs/tracking.md)",
          "--front-span"),
      // Fewer stretches than 3 fit one parabola to most of a loop.
      settings::number<O>(
          "stretches", [](auto& o) -> auto& { return o.stretches; }, R::at_least(3.0), "",
          "the stretch pooled is at most the line's length over this many (a "
          "small loop is not averaged over a large part of it)",
          "--front-stretches"),
      settings::number<O>(
          "step", [](auto& o) -> auto& { return o.step; }, R::positive(), "d",
          "spacing of the points along each line", "--front-step"),
      settings::number<O>(
          "widths", [](auto& o) -> auto& { return o.widths; }, R::positive(), "b_core",
          "window across the line, in local core widths either side", "--front-widths"),
      settings::number<O>(
          "max_half_width", [](auto& o) -> auto& { return o.max_half_width; }, R::positive(), "d",
          "windows across the line are cut to this", "--front-max-half-width"),
  };
  return table;
}

void FrontOptions::validate() const {
  settings::validate(*this, settings());
}

namespace {

// Solves the 3 x 3 system m[.][0..2] x = m[.][3] by Gaussian elimination with partial pivoting;
// false if it is singular.
bool solve3(double m[3][4], double x[3]) {
  for (int c = 0; c < 3; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 3; ++r) {
      if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
    }
    if (!(std::abs(m[pivot][c]) > 1e-12)) return false;
    for (int k = 0; k < 4; ++k)
      std::swap(m[c][k], m[pivot][k]);
    for (int r = c + 1; r < 3; ++r) {
      const double f = m[r][c] / m[c][c];
      for (int k = c; k < 4; ++k)
        m[r][k] -= f * m[c][k];
    }
  }
  for (int r = 2; r >= 0; --r) {
    double v = m[r][3];
    for (int k = r + 1; k < 3; ++k)
      v -= m[r][k] * x[k];
    x[r] = v / m[r][r];
  }
  return true;
}

// A stretch's mean curve: n = c0 + c1 u + c2 u^2 in the frame of its principal axis t (normal
// n = (-t_y, t_x)) about its centroid, u the coordinate along t over `half` (d).
struct MeanCurve {
  double cx = 0.0, cy = 0.0, tx = 1.0, ty = 0.0, half = 1.0;
  double c[3] = {0.0, 0.0, 0.0};

  [[nodiscard]] double u(double x, double y) const {
    return ((x - cx) * tx + (y - cy) * ty) / half;
  }
  // The coordinate along the normal (d).
  [[nodiscard]] double v(double x, double y) const { return (x - cx) * -ty + (y - cy) * tx; }
  // dn / ds at the point's u.
  [[nodiscard]] double slope(double x, double y) const {
    return (c[1] + 2.0 * c[2] * u(x, y)) / half;
  }
  // Signed distance of (x, y) from the curve (to first order in its slope).
  [[nodiscard]] double across(double x, double y) const {
    const double uu = u(x, y);
    return (v(x, y) - (c[0] + c[1] * uu + c[2] * uu * uu)) / std::hypot(1.0, slope(x, y));
  }
};

// A site's nearest point on the lines of a frame.
// Single precision: one per site of the block (16 bytes, 64 MB at 4 million sites), and what
// it is used for (membership of a window and a bin) needs no more than 1e-3 d at 1e4 d.
struct Nearest {
  float distance = std::numeric_limits<float>::infinity();
  float across = 0.0F;  // signed distance: > 0 on the line's left
  float arc = 0.0F;     // arc length of the nearest point along its line (d)
  std::int32_t line = -1;
};

}  // namespace

std::vector<FrontStress> front_stresses(const slide::Snapshot& s, const FrameLines& f,
                                        const FrontOptions& options) {
  options.validate();
  check_fields(s, "front_stresses");
  std::vector<FrontStress> out;
  const LatticeBlock& blk = s.block;
  const std::size_t n = blk.shape.count();
  if (s.sx.size() != n || !s.tip.aligned() || f.lines.empty()) return out;
  const bool with_y = s.uy.size() == n || s.sy.size() == n;  // as in profile_at
  const auto site = [&](int i0, int i1) {
    return static_cast<std::size_t>(i0) * static_cast<std::size_t>(blk.shape.n1) +
           static_cast<std::size_t>(i1);
  };
  // Arc length to each vertex and each line's whole length (a loop's with its closing segment).
  std::vector<std::vector<double>> arc(f.lines.size());
  std::vector<double> total(f.lines.size(), 0.0);
  for (std::size_t li = 0; li < f.lines.size(); ++li) {
    const Line& l = f.lines[li];
    const auto step = [&](std::size_t a, std::size_t b) {
      return std::hypot(l.points[b].x - l.points[a].x, l.points[b].y - l.points[a].y);
    };
    arc[li].assign(l.points.size(), 0.0);
    for (std::size_t k = 1; k < l.points.size(); ++k)
      arc[li][k] = arc[li][k - 1] + step(k - 1, k);
    total[li] = l.points.empty() ? 0.0 : arc[li].back();
    if (l.kind == LineKind::loop && l.points.size() > 1) total[li] += step(l.points.size() - 1, 0);
  }
  // Every site within reach of a line, with its nearest point on the nearest line: each site
  // belongs to one line's windows (the other lines cut them halfway, as on a profile). A
  // line's reach is its widest window (at its vertex of least tau_max, at most max_half_width)
  // and a site more, so that a window's side can be seen to reach its half-width.
  std::vector<Nearest> nearest(n);
  for (std::size_t li = 0; li < f.lines.size(); ++li) {
    const Line& l = f.lines[li];
    double widest = 0.0;
    for (const Point& q : l.points) {
      const int i0 = static_cast<int>(std::lround(q.x)) - blk.origin0;
      const int i1 = static_cast<int>(std::lround(q.y)) - blk.origin1;
      const double t = i0 >= 0 && i0 < blk.shape.n0 && i1 >= 0 && i1 < blk.shape.n1
                           ? s.tau_max[site(i0, i1)]
                           : 0.0;
      widest = std::max(widest, t > 0.0 ? options.widths / t : options.max_half_width);
    }
    const double reach = std::min(widest, options.max_half_width) + 2.0;
    const std::size_t m = l.points.size();
    const std::size_t segments = l.kind == LineKind::loop ? m : (m > 0 ? m - 1 : 0);
    for (std::size_t k = 0; k < segments; ++k) {
      const Point& a = l.points[k];
      const Point& b = l.points[(k + 1) % m];
      const double ex = b.x - a.x, ey = b.y - a.y, e2 = ex * ex + ey * ey;
      const int x0 =
          std::max(0, static_cast<int>(std::floor(std::min(a.x, b.x) - reach)) - blk.origin0);
      const int x1 = std::min(
          blk.shape.n0 - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + reach)) - blk.origin0);
      const int y0 =
          std::max(0, static_cast<int>(std::floor(std::min(a.y, b.y) - reach)) - blk.origin1);
      const int y1 = std::min(
          blk.shape.n1 - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + reach)) - blk.origin1);
      for (int i0 = x0; i0 <= x1; ++i0) {
        for (int i1 = y0; i1 <= y1; ++i1) {
          const double px = blk.x(i0, 1.0) - a.x, py = blk.y(i1, 1.0) - a.y;
          const double t = e2 > 0.0 ? std::clamp((px * ex + py * ey) / e2, 0.0, 1.0) : 0.0;
          const double qx = px - t * ex, qy = py - t * ey;
          const double dist = std::hypot(qx, qy);
          Nearest& near = nearest[site(i0, i1)];
          if (dist >= near.distance) continue;
          near.distance = static_cast<float>(dist);
          near.across = static_cast<float>((ex * py - ey * px) >= 0.0 ? dist : -dist);
          near.arc = static_cast<float>(arc[li][k] + t * std::sqrt(e2));
          near.line = static_cast<std::int32_t>(li);
        }
      }
    }
  }
  // Sites by line and by arc bin of width `step`, to gather a stretch quickly.
  std::vector<std::vector<std::vector<std::size_t>>> bins(f.lines.size());
  for (std::size_t li = 0; li < f.lines.size(); ++li)
    bins[li].resize(static_cast<std::size_t>(std::floor(total[li] / options.step)) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Nearest& near = nearest[i];
    if (near.line < 0) continue;
    auto& b = bins[static_cast<std::size_t>(near.line)];
    const auto bin = std::min(b.size() - 1, static_cast<std::size_t>(near.arc / options.step));
    b[bin].push_back(i);
  }
  // The point at arc length `at` along line li (a loop's taken around its closure).
  const auto point_at = [&](std::size_t li, double at) {
    const Line& l = f.lines[li];
    const bool closed = l.kind == LineKind::loop;
    if (closed && total[li] > 0.0) at -= std::floor(at / total[li]) * total[li];
    // The segment holding `at`, by bisection (an open line's last point is its last segment's
    // end).
    const std::size_t last_segment = closed ? l.points.size() - 1 : l.points.size() - 2;
    const auto after = std::upper_bound(arc[li].begin(), arc[li].end(), at);
    const std::size_t k = std::min(last_segment, static_cast<std::size_t>(std::max<std::ptrdiff_t>(
                                                     0, after - arc[li].begin() - 1)));
    const Point& a = l.points[k];
    const Point& b = l.points[(k + 1) % l.points.size()];
    const double seg = std::hypot(b.x - a.x, b.y - a.y);
    const double t = seg > 0.0 ? std::clamp((at - arc[li][k]) / seg, 0.0, 1.0) : 0.0;
    return Point{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
  };
  std::vector<Point> fit_points;
  struct Pooled {
    double across, ox, oy, tx, ty;
  };
  std::vector<Pooled> pool;
  std::vector<std::pair<double, double>> whole_bins;  // per bin: farthest sites left and right
  for (std::size_t li = 0; li < f.lines.size(); ++li) {
    const Line& l = f.lines[li];
    if (l.points.size() < 2) continue;  // no stretch to sample
    const bool closed = l.kind == LineKind::loop;
    const double length = total[li];
    const auto count =
        static_cast<std::size_t>(std::floor(length / options.step)) + (closed ? 0 : 1);
    // The stretch: `span`, or a `stretches`-th of a shorter line, so that a small loop is not
    // averaged over a third of its front (at R = 40 d, a = 24 d a loop 100 d round).
    const double span = std::min(options.span, length / options.stretches);
    const auto nbins = static_cast<long long>(bins[li].size());
    const auto reach_bins = static_cast<long long>(std::ceil(0.5 * span / options.step)) + 1;
    for (std::size_t j = 0; j < count; ++j) {
      const double centre = std::min(static_cast<double>(j) * options.step, length);
      // The point of the line at `centre` and its segment.
      FrontStress fs;
      fs.at = point_at(li, centre);
      // The stretch's mean curve: the least-squares parabola through its points (every quarter
      // site along it) in the frame of their principal axis. The window across the line is
      // measured from it (the polyline's vertices zigzag at the grid scale and step at
      // kinks), and its direction at the point is the stretch's character. A parabola, not a
      // line: over 32 d of a loop of radius 160 d a chord is 0.8 d off the line at its middle.
      const double from = closed ? centre - 0.5 * span : std::max(0.0, centre - 0.5 * span);
      const double to = closed ? centre + 0.5 * span : std::min(length, centre + 0.5 * span);
      const int samples = std::max(3, static_cast<int>(std::ceil((to - from) / 0.25)) + 1);
      std::vector<Point>& fit = fit_points;
      fit.clear();
      double cx = 0.0, cy = 0.0;
      for (int q = 0; q < samples; ++q) {
        fit.push_back(point_at(li, from + (to - from) * q / (samples - 1)));
        cx += fit.back().x;
        cy += fit.back().y;
      }
      cx /= samples;
      cy /= samples;
      double sxx = 0.0, sxy = 0.0, syy = 0.0;
      for (const Point& q : fit) {
        sxx += (q.x - cx) * (q.x - cx);
        sxy += (q.x - cx) * (q.y - cy);
        syy += (q.y - cy) * (q.y - cy);
      }
      const double direction = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // principal axis
      const double tx = std::cos(direction), ty = std::sin(direction);
      const double nx = -ty, ny = tx;
      // n = c0 + c1 u + c2 u^2 by least squares (normal equations, u scaled to [-1, 1]).
      MeanCurve curve{.cx = cx, .cy = cy, .tx = tx, .ty = ty, .half = 1.0};
      double half = 0.0;
      for (const Point& q : fit)
        half = std::max(half, std::abs(curve.u(q.x, q.y)));
      curve.half = std::max(half, 1e-9);
      double m[3][4] = {};
      for (const Point& q : fit) {
        const double u = curve.u(q.x, q.y);
        const double v = curve.v(q.x, q.y);
        const double basis[3] = {1.0, u, u * u};
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c)
            m[r][c] += basis[r] * basis[c];
          m[r][3] += basis[r] * v;
        }
      }
      const bool fitted = solve3(m, curve.c);
      if (fitted) {
        for (const Point& q : fit)
          fs.bend = std::max(fs.bend, std::abs(curve.across(q.x, q.y)));
        const double slope = curve.slope(fs.at.x, fs.at.y);
        const double dx = tx + slope * nx, dy = ty + slope * ny;
        fs.angle_deg = std::atan2(std::abs(dy), std::abs(dx)) * 180.0 / std::acos(-1.0);
      } else {
        fs.bend = std::numeric_limits<double>::infinity();  // a degenerate stretch: not resolved
        fs.angle_deg = std::nan("");
      }
      // An open line's stretch cut by its end is not the span asked for.
      const bool clipped = ((to - from) < span * (1.0 - 1e-9) && !closed) || !fitted;
      fs.span = span;
      fs.line = li;
      fs.kind = l.kind;
      fs.arc = centre;
      const int n0 = static_cast<int>(std::lround(fs.at.x)) - blk.origin0;
      const int n1 = static_cast<int>(std::lround(fs.at.y)) - blk.origin1;
      if (n0 >= 0 && n0 < blk.shape.n0 && n1 >= 0 && n1 < blk.shape.n1)
        fs.tau_max = s.tau_max[site(n0, n1)];
      // b_core = d G / tau_max (tau in G, lengths in d).
      const double full =
          fs.tau_max > 0.0 ? options.widths / fs.tau_max : std::numeric_limits<double>::infinity();
      double h = std::min(full, options.max_half_width);
      // The stretch's sites, and how far they reach on either side: a window that does not
      // reach h on a side is cut there (another line's sites, the block's edge).
      pool.clear();
      // How far the sites reach on either side, the least over the stretch's bins that hold
      // any (a side another line or the block's edge takes over along part of the stretch is
      // cut there).
      double reach_left = std::numeric_limits<double>::infinity(), reach_right = reach_left;
      double fallback_left = 0.0, fallback_right = 0.0;
      whole_bins.clear();
      // Whether arc length `a` lies in the stretch (around a loop, cyclically).
      const auto within = [&](double a) {
        double gap = std::abs(a - centre);
        if (closed) gap = std::min(gap, length - gap);
        return gap <= 0.5 * span;
      };
      const auto bin0 = static_cast<long long>(centre / options.step);
      // Each bin once: around a loop shorter than the bins the stretch reaches, all of them.
      const bool all_bins = closed && 2 * reach_bins + 1 >= nbins;
      const long long first_bin = all_bins ? 0 : bin0 - reach_bins;
      const long long last_bin = all_bins ? nbins - 1 : bin0 + reach_bins;
      for (long long bb = first_bin; bb <= last_bin; ++bb) {
        long long wrapped = bb;
        if (closed) {
          wrapped = ((bb % nbins) + nbins) % nbins;
        } else if (bb < 0 || bb >= nbins) {
          continue;
        }
        double bin_left = 0.0, bin_right = 0.0;
        bool bin_used = false;
        for (const std::size_t i : bins[li][static_cast<std::size_t>(wrapped)]) {
          const Nearest& near = nearest[i];
          if (!within(near.arc)) continue;
          bin_used = true;
          const double across = near.across;
          if (across > 0.0) bin_left = std::max(bin_left, across);
          if (across < 0.0) bin_right = std::max(bin_right, -across);
          // A site out of the contact ends the window at its distance (the contact's edge).
          if (!in_contact_at(s, i)) {
            h = std::min(h, static_cast<double>(near.distance));
            continue;
          }
          const double X =
              s.block.x(static_cast<int>(i / static_cast<std::size_t>(blk.shape.n1)), 1.0);
          const double Y =
              s.block.y(static_cast<int>(i % static_cast<std::size_t>(blk.shape.n1)), 1.0);
          const double oy = with_y ? uy_at(s, i, Y) : 0.0;
          pool.push_back(
              {curve.across(X, Y), s.sx[i] - X, oy, s.tau_x[i], with_y ? s.tau_y[i] : 0.0});
        }
        // Only bins the stretch holds whole (or, around a small loop, all): a slice of a bin
        // at the stretch's end holds too few sites to show how far they reach.
        // (Around a loop the bin's own arc range, taken cyclically.)
        const double bin_from = static_cast<double>(all_bins ? wrapped : bb) * options.step;
        const double bin_to = bin_from + options.step;
        const bool whole = all_bins
                               ? within(bin_from) && within(std::min(bin_to, length))
                               : bin_from >= centre - 0.5 * span && bin_to <= centre + 0.5 * span;
        if (bin_used && whole) whole_bins.push_back({bin_left, bin_right});
        if (bin_used) {
          fallback_left = std::max(fallback_left, bin_left);
          fallback_right = std::max(fallback_right, bin_right);
        }
      }
      // The least over pairs of neighbouring whole bins (8 d of line by default) of their
      // farthest sites: on the concave side of a tight loop one bin's wedge can hold no site
      // near the window's edge (a loop of radius 16 d: 2 d wide at 8 d in); a stretch of fewer
      // whole bins takes the farthest sites of the bins it touches.
      if (whole_bins.size() < 2) {
        reach_left = fallback_left, reach_right = fallback_right;
      } else {
        for (std::size_t q = 0; q + 1 < whole_bins.size(); ++q) {
          reach_left = std::min(reach_left, std::max(whole_bins[q].first, whole_bins[q + 1].first));
          reach_right =
              std::min(reach_right, std::max(whole_bins[q].second, whole_bins[q + 1].second));
        }
      }
      // Sites lie every d or closer across the line along a bin of a few d: a side whose
      // farthest site is more than a site short of h is cut there.
      h = std::min({h, reach_left + 1.0, reach_right + 1.0});
      fs.half_width = h;
      fs.cut = !(h >= full) || clipped;
      // The pooled sites in order of their registry offset s_x - X, which falls monotonically
      // across a core: for a straight line that is the order of the chain (tracking/
      // profile.hpp), copies together; where the stretch holds kinks or a piece one row ahead
      // of the rest, each site still sits in order of its place across its own piece of core,
      // which an order by distance from one mean curve mixes (at the edge ends of the held
      // loop at R = 800 d that gave 0.0016 G between neighbours holding 0.0169). Where the
      // offset is flat (far from the core) the order is arbitrary and the steps are ~1e-3 d.
      std::erase_if(pool, [h](const Pooled& q) { return std::abs(q.across) > h; });
      std::sort(pool.begin(), pool.end(),
                [](const Pooled& u, const Pooled& v) { return u.ox < v.ox; });
      double weighted = 0.0;
      for (std::size_t q = 0; q + 1 < pool.size(); ++q) {
        const double rho = pool[q + 1].ox - pool[q].ox;
        fs.held.slip += rho;
        weighted += rho * 0.5 * (pool[q].tx + pool[q + 1].tx) +
                    (pool[q + 1].oy - pool[q].oy) * 0.5 * (pool[q].ty + pool[q + 1].ty);
        ++fs.held.bonds;
      }
      fs.held.tau = fs.held.slip != 0.0 ? weighted / fs.held.slip : std::nan("");
      out.push_back(fs);
    }
  }
  return out;
}

RegistryIndices registry_indices(const slide::Snapshot& s) {
  const std::size_t n = s.block.shape.count();
  if (s.sx.size() != n)
    throw std::invalid_argument("registry_indices: the snapshot has no s_x for its block");
  RegistryIndices r{.block = s.block, .index = {}};
  r.index.reserve(n);
  for (const double v : s.sx)
    r.index.push_back(static_cast<std::int32_t>(std::lround(v)));  // d = 1 (slide::Snapshot)
  return r;
}

FrontMoves front_moves(const RegistryIndices& before, const slide::Snapshot& after,
                       const std::vector<FrontStress>& front) {
  const LatticeBlock& blk = after.block;
  const std::size_t n = blk.shape.count();
  if (after.sx.size() != n)
    throw std::invalid_argument("front_moves: the later snapshot has no s_x for its block");
  if (after.in_contact.empty() ? after.tau_max.size() != n : after.in_contact.size() != n)
    throw std::invalid_argument(
        "front_moves: the later snapshot's in_contact (or tau_max) differs from its block");
  if (before.index.size() != before.block.shape.count())
    throw std::invalid_argument("front_moves: the earlier indices differ from their block");
  FrontMoves out;
  out.sites.assign(front.size(), 0);
  // The points on a grid of cells as wide as the widest reach, so that a site looks at the
  // points of its own cell and the 8 around it only.
  double cell = 1.0;
  for (const FrontStress& p : front)
    cell = std::max(cell, 0.5 * p.span + p.half_width);
  std::map<std::pair<long long, long long>, std::vector<std::size_t>> grid;
  const auto cell_of = [cell](double v) { return static_cast<long long>(std::floor(v / cell)); };
  for (std::size_t k = 0; k < front.size(); ++k)
    grid[{cell_of(front[k].at.x), cell_of(front[k].at.y)}].push_back(k);
  for (int i0 = 0; i0 < blk.shape.n0; ++i0) {
    for (int i1 = 0; i1 < blk.shape.n1; ++i1) {
      const auto i = static_cast<std::size_t>(i0) * static_cast<std::size_t>(blk.shape.n1) +
                     static_cast<std::size_t>(i1);
      if (!in_contact_at(after, i)) continue;
      // The same lattice site in the earlier block.
      const int j0 = blk.origin0 + i0 - before.block.origin0;
      const int j1 = blk.origin1 + i1 - before.block.origin1;
      if (j0 < 0 || j0 >= before.block.shape.n0 || j1 < 0 || j1 >= before.block.shape.n1) continue;
      const auto j =
          static_cast<std::size_t>(j0) * static_cast<std::size_t>(before.block.shape.n1) +
          static_cast<std::size_t>(j1);
      if (static_cast<std::int32_t>(std::lround(after.sx[i])) == before.index[j]) continue;
      ++out.moved;
      const double x = blk.x(i0, 1.0), y = blk.y(i1, 1.0);
      std::size_t best = front.size();
      double best_distance = std::numeric_limits<double>::infinity();
      const long long cx = cell_of(x), cy = cell_of(y);
      for (long long gx = cx - 1; gx <= cx + 1; ++gx) {
        for (long long gy = cy - 1; gy <= cy + 1; ++gy) {
          const auto found = grid.find({gx, gy});
          if (found == grid.end()) continue;
          for (const std::size_t k : found->second) {
            const double dist = std::hypot(front[k].at.x - x, front[k].at.y - y);
            // Ties go to the earlier point, as in order along the lines.
            if ((dist < best_distance || (dist == best_distance && k < best)) &&
                dist <= 0.5 * front[k].span + front[k].half_width) {
              best = k;
              best_distance = dist;
            }
          }
        }
      }
      if (best < front.size()) {
        ++out.sites[best];
      } else {
        ++out.elsewhere;
      }
    }
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
