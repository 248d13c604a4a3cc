// A scan of the Peierls stress over core widths and line angles (apps/peierls_scan runs it and
// writes its files): the points, one point's result as the scan records it, the law fitted per
// line orientation, and a cell's state as a field snapshot.
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/slide/frames.hpp"
#include "asperity/peierls/cell.hpp"
#include "asperity/peierls/fit.hpp"
#include "asperity/peierls/peierls_stress.hpp"

namespace asperity::peierls {

struct ScanPoint {
  double b_core = 0.0;  // d
  Orientation orientation;
};

// The orientations of an L cell nearest the requested angles, each once, in the order first
// requested. Throws std::invalid_argument (orientation_for_angle) for an angle that no
// orientation lies within tolerance_deg of: every angle is checked before any work.
std::vector<Orientation> scan_orientations(int L, std::span<const double> theta_deg,
                                           double tolerance_deg, double min_line_spacing);

// The core widths sorted, each once.
std::vector<double> scan_core_widths(std::span<const double> b_core);

// Every (b_core, orientation): by orientation, then by b_core in the order given.
std::vector<ScanPoint> scan_points(std::span<const double> b_core,
                                   std::span<const Orientation> orientations);

// The scan's options with the point's core width and orientation.
PeierlsOptions point_options(const PeierlsOptions& scan, const ScanPoint& point);

// One point's result as a scan records it: stresses in units of tau_max.
struct PointResult {
  ScanPoint point;
  int L = 0;                 // cell size of the result (sites per period)
  double L_change = NAN;     // |tau_P(L)/tau_P(L/2) - 1|; NaN: one cell
  bool L_converged = false;  // L_change <= cell.L_tolerance (or tolerance 0)
  bool resolved_pos = false, resolved_neg = false;
  double tau_pos = NAN, tau_neg = NAN;  // tau_P / tau_max
  double floor = NAN;                   // resolution floor / tau_max
  double core_width = NAN, core_width_continuum = NAN, rigid = NAN;
  long long iterations = 0, transforms = 0;
  // Relaxations that neither converged nor glided (counted unstable: tau_P is bracketed from
  // below by verified equilibria only), over both signs.
  long long undetermined = 0;
  std::string failure;  // numerical failure (non-finite forces); empty: none
};
PointResult point_result(const ScanPoint& point, const CellSizeResult& converged);

// tau_P / tau_max of a point: the mean of the resolved signs (they agree to the bracket
// precision). nullopt when neither sign is resolved or the point failed (not a result at all).
std::optional<double> peierls_ratio(const PointResult& r);

// k2 of the rigid-profile Peierls-Nabarro estimate (cell.hpp), which decays as
// exp(-2 pi zeta |m| / d) with zeta proportional to b_core: the decay a fitted k2 compares with.
double rigid_profile_k2(const Orientation& o, double nu);

struct OrientationFit {
  Orientation orientation;
  ExponentialFit fit;
  double k2_rigid = 0.0;  // rigid_profile_k2
};
// Per orientation, in the order given: tau_P / tau_max = k1 exp(-k2 b_core / d) fitted to the
// resolved results of that orientation with b_min <= b_core <= b_max.
std::vector<OrientationFit> fit_orientations(std::span<const PointResult> results,
                                             std::span<const Orientation> orientations,
                                             double b_min, double b_max, double nu);

// The whole L x L cell in the snapshot layout of the contact simulator (MODEL.md 5 fields):
// s_x = X + u_x - w(X) with the frustration w = d (m_x X + m_y Y)/L of MODEL.md 6, unwrapped
// inside the cell so that the registry offset s_x - X is continuous there (it winds by m_x, m_y
// across the cell's sides, which track_loops measures), tau = f / d^2, uniform tau_max, no
// pressure; Fx = tau_ext L^2 d^2, the force the applied stress puts on the cell.
slide::Snapshot cell_snapshot(const PeierlsCell& cell, const std::vector<double>& u,
                              const std::string& label, double tau_ext);

}  // namespace asperity::peierls
