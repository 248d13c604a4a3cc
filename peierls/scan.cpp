// A Peierls-stress scan's points, results and fits; see scan.hpp.
#include "asperity/peierls/scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace asperity::peierls {

std::vector<Orientation> scan_orientations(int L, std::span<const double> theta_deg,
                                           double tolerance_deg, double min_line_spacing) {
  std::vector<Orientation> out;
  for (double t : theta_deg) {
    const Orientation o = orientation_for_angle(L, t, tolerance_deg, min_line_spacing);
    const bool seen = std::any_of(out.begin(), out.end(),
                                  [&](const auto& x) { return x.mx == o.mx && x.my == o.my; });
    if (!seen) out.push_back(o);
  }
  return out;
}

std::vector<double> scan_core_widths(std::span<const double> b_core) {
  std::vector<double> bs(b_core.begin(), b_core.end());
  std::sort(bs.begin(), bs.end());
  bs.erase(std::unique(bs.begin(), bs.end()), bs.end());
  return bs;
}

std::vector<ScanPoint> scan_points(std::span<const double> b_core,
                                   std::span<const Orientation> orientations) {
  std::vector<ScanPoint> points;
  for (const auto& o : orientations) {
    for (double b : b_core)
      points.push_back({b, o});
  }
  return points;
}

PeierlsOptions point_options(const PeierlsOptions& scan, const ScanPoint& point) {
  PeierlsOptions o = scan;
  o.cell.b_core = point.b_core;
  o.cell.mx = point.orientation.mx;
  o.cell.my = point.orientation.my;
  return o;
}

PointResult point_result(const ScanPoint& point, const CellSizeResult& converged) {
  const PeierlsResult& r = converged.result;
  PointResult p;
  p.point = point;
  p.L = r.L;
  p.L_change = converged.change;
  p.L_converged = converged.converged;
  p.resolved_pos = r.positive.resolved;
  p.resolved_neg = r.negative.resolved;
  p.tau_pos = r.positive.tau_P / r.tau_max;
  p.tau_neg = r.negative.tau_P / r.tau_max;
  p.floor = std::max(r.positive.floor, r.negative.floor) / r.tau_max;
  p.core_width = r.core_width;
  p.core_width_continuum = r.core_width_continuum;
  p.rigid = r.rigid_estimate;
  p.iterations = r.iterations;
  p.transforms = static_cast<long long>(r.transforms);
  p.undetermined = r.positive.undetermined + r.negative.undetermined;
  p.failure = r.failure;
  return p;
}

std::optional<double> peierls_ratio(const PointResult& r) {
  if (!r.failure.empty()) return std::nullopt;
  if (r.resolved_pos && r.resolved_neg) return 0.5 * (r.tau_pos + r.tau_neg);
  if (r.resolved_pos) return r.tau_pos;
  if (r.resolved_neg) return r.tau_neg;
  return std::nullopt;
}

double rigid_profile_k2(const Orientation& o, double nu) {
  return std::hypot(o.mx, o.my) * std::numbers::pi * continuum_core_width(1.0, o.theta_deg, nu);
}

std::vector<OrientationFit> fit_orientations(std::span<const PointResult> results,
                                             std::span<const Orientation> orientations,
                                             double b_min, double b_max, double nu) {
  std::vector<OrientationFit> out;
  for (const auto& o : orientations) {
    std::vector<double> x, y;
    for (const PointResult& r : results) {
      if (r.point.orientation.mx != o.mx || r.point.orientation.my != o.my) continue;
      if (const auto tau = peierls_ratio(r)) {
        x.push_back(r.point.b_core);
        y.push_back(*tau);
      }
    }
    out.push_back({.orientation = o,
                   .fit = fit_exponential(x, y, b_min, b_max),
                   .k2_rigid = rigid_profile_k2(o, nu)});
  }
  return out;
}

slide::Snapshot cell_snapshot(const PeierlsCell& cell, const std::vector<double>& u,
                              const std::string& label, double tau_ext) {
  const int L = cell.options().L;
  const std::vector<double> full = cell.expand(u);
  const std::size_t n = static_cast<std::size_t>(L) * static_cast<std::size_t>(L);
  slide::Snapshot s;
  s.label = label;
  s.Dx = 0.0;
  s.Fx = tau_ext * static_cast<double>(n);  // total applied force on the cell (G d^2)
  s.block.shape = {L, L};
  s.ux.assign(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
  s.uy.assign(full.begin() + static_cast<std::ptrdiff_t>(n), full.end());
  s.sx.resize(n);
  s.sy = s.uy;
  s.tau_x.resize(n);
  s.tau_y.resize(n);
  s.tau_max.assign(n, cell.tau_max());
  s.pressure.assign(n, 0.0);
  s.in_contact.assign(n, 1);
  const double two_pi = 2.0 * std::numbers::pi;
  for (int X = 0; X < L; ++X) {
    for (int Y = 0; Y < L; ++Y) {
      const std::size_t i =
          static_cast<std::size_t>(X) * static_cast<std::size_t>(L) + static_cast<std::size_t>(Y);
      const double w = static_cast<double>(static_cast<long long>(cell.options().mx) * X +
                                           static_cast<long long>(cell.options().my) * Y) /
                       L;
      s.sx[i] = X + s.ux[i] - w;
      s.tau_x[i] = -cell.tau_max() * std::sin(two_pi * (s.ux[i] - w));
      s.tau_y[i] = -cell.tau_max() * std::sin(two_pi * s.sy[i]);
    }
  }
  return s;
}

}  // namespace asperity::peierls
