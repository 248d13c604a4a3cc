// Unit tier: the periodic Peierls cell (peierls/cell.hpp), its minimiser
// (minimize/stiffness_minimizer.hpp), the exponential fit (peierls/fit.hpp) and a scan's points,
// results, fits and snapshots (peierls/scan.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "asperity/core/minimize/stiffness_minimizer.hpp"
#include "asperity/peierls/cell.hpp"
#include "asperity/peierls/fit.hpp"
#include "asperity/peierls/scan.hpp"

using namespace asperity;
using namespace asperity::peierls;

TEST(PeierlsOrientation, AnglesOfTheFrustrationVector) {
  EXPECT_DOUBLE_EQ(line_angle_deg(1, 0), 90.0);  // line along y, b along x: edge
  EXPECT_DOUBLE_EQ(line_angle_deg(0, 1), 0.0);   // line along x: screw
  EXPECT_NEAR(line_angle_deg(1, 1), 45.0, 1e-12);
  EXPECT_NEAR(line_angle_deg(2, 1), 63.4349488, 1e-6);
}

TEST(PeierlsOrientation, OffersCoprimeVectorsAndNamesTheAlternatives) {
  const auto offered = available_orientations(256, 16.0);
  ASSERT_GE(offered.size(), 4u);
  for (const auto& o : offered) {
    EXPECT_EQ(std::gcd(o.mx, o.my), 1);
    EXPECT_GE(o.line_spacing, 16.0);
  }
  const Orientation o = orientation_for_angle(256, 63.4, 0.5, 16.0);
  EXPECT_EQ(o.mx, 2);
  EXPECT_EQ(o.my, 1);
  // A small cell cannot hold dense orientations: the message lists what it offers.
  try {
    orientation_for_angle(16, 63.4, 0.5, 16.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("offered"), std::string::npos) << e.what();
  }
}

TEST(PeierlsCellOptions, ValidateNamesTheConstraint) {
  CellOptions o;
  o.mx = 2;
  o.my = 2;  // two lines per cell
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.L = 255;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.b_core = -1.0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.b_core = NAN;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// The reduced chain is exact: its stiffness applied to a chain field, expanded to the L x L
// cell, equals the full cell's stiffness applied to the expanded field (and likewise for the
// preconditioner), for every orientation class.
TEST(PeierlsCell, ReducedStiffnessEqualsTheFullCellOnLineInvariantFields) {
  for (auto [mx, my] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}, std::pair{2, 1}}) {
    CellOptions o;
    o.L = 32;
    o.mx = mx;
    o.my = my;
    o.b_core = 3.0;
    PeierlsCell reduced(o);
    o.model = CellModel::full;
    PeierlsCell full(o);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::vector<double> u(reduced.size());
    for (double& x : u)
      x = value(rng);
    std::vector<double> Ku(reduced.size()), Pu(reduced.size());
    reduced.stiffness(u, Ku);
    reduced.precondition(u, Pu);
    const std::vector<double> U = reduced.expand(u);
    std::vector<double> KU(full.size()), PU(full.size());
    full.stiffness(U, KU);
    full.precondition(U, PU);
    const std::vector<double> expected_K = reduced.expand(Ku), expected_P = reduced.expand(Pu);
    double scale = 0.0, err_K = 0.0, err_P = 0.0;
    for (std::size_t i = 0; i < KU.size(); ++i) {
      scale = std::max(scale, std::abs(KU[i]));
      err_K = std::max(err_K, std::abs(KU[i] - expected_K[i]));
      err_P = std::max(err_P, std::abs(PU[i] - expected_P[i]));
    }
    EXPECT_LT(err_K, 1e-12 * scale) << "m = (" << mx << ", " << my << ")";
    EXPECT_LT(err_P, 1e-12) << "m = (" << mx << ", " << my << ")";
  }
}

TEST(PeierlsCell, InitialStateHoldsOneLineAndTheInterfaceForceIsTheSineOfTheOffset) {
  CellOptions o;
  o.L = 64;
  o.b_core = 4.0;
  PeierlsCell cell(o);
  const std::vector<double> u = cell.initial_state();
  const std::vector<double> phi = cell.chain_offset(u);
  EXPECT_NEAR(phi.front(), 0.0, 1e-15);
  EXPECT_NEAR(phi.back(), 1.0, 1e-15);
  const CoreProfile core = core_profile(phi, 1, 0);
  EXPECT_NEAR(core.position, 31.5, 0.5);  // the registry jump sits at k = L/2
  // Registry everywhere but site 5, offset by d/4: force -tau_max d^2 there, energy
  // tau_max d^3 / (2 pi) (MODEL.md 3).
  std::vector<double> v(cell.size(), 0.0), f(cell.size());
  for (std::size_t k = 0; k < cell.sites(); ++k)
    v[k] = cell.registry_shift(k);
  v[5] += 0.25;
  cell.interface_force(v, f);
  EXPECT_NEAR(f[5], -cell.tau_max(), 1e-15);
  EXPECT_NEAR(f[6], 0.0, 1e-15);
  EXPECT_NEAR(cell.interface_energy(v), cell.tau_max() / (2.0 * std::acos(-1.0)), 1e-14);
}

// A separable quadratic: K = diag(k), interface force h (u0 - u). Minimum u = h u0 / (k + h).
namespace {
class Quadratic final : public minimize::StiffnessProblem {
 public:
  std::vector<double> k, h, u0;
  [[nodiscard]] std::size_t size() const override { return k.size(); }
  void stiffness(std::span<const double> u, std::span<double> out) override {
    for (std::size_t i = 0; i < u.size(); ++i)
      out[i] = k[i] * u[i];
  }
  void precondition(std::span<const double> r, std::span<double> z) override {
    for (std::size_t i = 0; i < r.size(); ++i)
      z[i] = r[i] / (k[i] + 1.0);
  }
  void interface_force(std::span<const double> u, std::span<double> f) const override {
    for (std::size_t i = 0; i < u.size(); ++i)
      f[i] = h[i] * (u0[i] - u[i]);
  }
  [[nodiscard]] double max_site_norm(std::span<const double> d) const override {
    double m = 0.0;
    for (double x : d)
      m = std::max(m, std::abs(x));
    return m;
  }
};
}  // namespace

TEST(StiffnessMinimizer, ReachesTheMinimumOfAQuadraticToTheTolerance) {
  Quadratic q;
  const std::size_t n = 50;
  for (std::size_t i = 0; i < n; ++i) {
    q.k.push_back(0.01 + static_cast<double>(i));  // condition number ~ 5000
    q.h.push_back(1.0 + 0.1 * static_cast<double>(i % 7));
    q.u0.push_back(std::sin(static_cast<double>(i)));
  }
  std::vector<double> u(n, 0.0), f_ext(n, 0.0);
  minimize::StiffnessOptions o;
  o.force_tolerance = 1e-12;
  o.max_displacement = 1.0;  // at most a period: the test converges without the cap
  const auto r = minimize::minimize_stiffness(q, f_ext, u, o);
  ASSERT_EQ(r.termination, Termination::converged);
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_NEAR(u[i], q.h[i] * q.u0[i] / (q.k[i] + q.h[i]), 1e-11);
  EXPECT_LE(r.max_force, 1e-12);
}

TEST(StiffnessMinimizer, ReportsNonFiniteForcesAsDiverged) {
  Quadratic q;
  q.k = {1.0, 1.0};
  q.h = {1.0, NAN};
  q.u0 = {1.0, 1.0};
  std::vector<double> u(2, 0.0), f_ext(2, 0.0);
  const auto r = minimize::minimize_stiffness(q, f_ext, u, {});
  EXPECT_EQ(r.termination, Termination::diverged);
  EXPECT_EQ(r.iterations, 0);
}

TEST(PeierlsFit, RecoversExactParametersAndHonestErrors) {
  const std::vector<double> b = {2, 3, 4, 5, 6};
  std::vector<double> ratio;
  for (double x : b)
    ratio.push_back(2.5 * std::exp(-1.8 * x));
  const ExponentialFit exact = fit_exponential(b, ratio, 0.0, 100.0);
  ASSERT_TRUE(exact.valid);
  EXPECT_NEAR(exact.k1, 2.5, 1e-12);
  EXPECT_NEAR(exact.k2, 1.8, 1e-12);
  EXPECT_LT(exact.k2_error, 1e-12);
  // Log-normal scatter of 5%: over many seeded trials the true k2 lies within two standard
  // errors about as often as a t distribution with 3 degrees of freedom allows (~86%).
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  int inside = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> noisy;
    for (double x : b)
      noisy.push_back(2.5 * std::exp(-1.8 * x + noise(rng)));
    const ExponentialFit f = fit_exponential(b, noisy, 0.0, 100.0);
    if (std::abs(f.k2 - 1.8) <= 2.0 * f.k2_error) ++inside;
  }
  EXPECT_GT(inside, trials * 78 / 100);
  EXPECT_LT(inside, trials * 94 / 100);
  // Fewer than three points in the window: no fit.
  EXPECT_FALSE(fit_exponential(b, ratio, 5.0, 6.0).valid);
}

// A scan's points: every angle mapped onto an orientation of the cell (each once, in the order
// asked), the core widths sorted and distinct, orientation by orientation.
TEST(PeierlsScan, PointsByOrientationThenCoreWidth) {
  const std::vector<double> theta = {90.0, 0.0, 90.3};
  const auto o = scan_orientations(64, theta, 0.5, 16.0);
  ASSERT_EQ(o.size(), 2u);
  EXPECT_EQ(o[0].mx, 1);  // edge first, as asked
  EXPECT_EQ(o[0].my, 0);
  EXPECT_EQ(o[1].mx, 0);
  const std::vector<double> off = {63.4};
  EXPECT_THROW(scan_orientations(16, off, 0.5, 16.0), std::invalid_argument);
  const std::vector<double> given = {6, 2, 4, 2};
  const auto b = scan_core_widths(given);
  EXPECT_EQ(b, (std::vector<double>{2, 4, 6}));
  const auto p = scan_points(b, o);
  ASSERT_EQ(p.size(), 6u);
  EXPECT_EQ(p[0].b_core, 2.0);
  EXPECT_EQ(p[0].orientation.mx, 1);
  EXPECT_EQ(p[2].b_core, 6.0);
  EXPECT_EQ(p[3].b_core, 2.0);
  EXPECT_EQ(p[3].orientation.mx, 0);
  const PeierlsOptions at = point_options(PeierlsOptions{}, p[4]);
  EXPECT_EQ(at.cell.b_core, 4.0);
  EXPECT_EQ(at.cell.mx, 0);
  EXPECT_EQ(at.cell.my, 1);
}

// A point's result in units of tau_max, and its tau_P: the mean of the resolved signs.
TEST(PeierlsScan, PointResultAndItsPeierlsRatio) {
  CellSizeResult c;
  c.result.L = 256;
  c.result.tau_max = 0.25;
  c.result.positive = {.resolved = true, .tau_P = 0.01, .undetermined = 2, .floor = 1e-6};
  c.result.negative = {.resolved = true, .tau_P = 0.012, .undetermined = 1, .floor = 2e-6};
  c.result.transforms = 77;
  c.change = 0.003;
  c.converged = true;
  const ScanPoint point{.b_core = 3.0, .orientation = {.mx = 1, .my = 0}};
  const PointResult r = point_result(point, c);
  EXPECT_EQ(r.L, 256);
  EXPECT_DOUBLE_EQ(r.tau_pos, 0.04);
  EXPECT_DOUBLE_EQ(r.tau_neg, 0.048);
  EXPECT_DOUBLE_EQ(r.floor, 8e-6);  // the larger of the two floors
  EXPECT_EQ(r.undetermined, 3);
  EXPECT_EQ(r.transforms, 77);
  EXPECT_EQ(r.L_change, 0.003);
  EXPECT_TRUE(r.L_converged);
  ASSERT_TRUE(peierls_ratio(r));
  EXPECT_DOUBLE_EQ(*peierls_ratio(r), 0.044);
  PointResult one = r;
  one.resolved_pos = false;
  EXPECT_DOUBLE_EQ(peierls_ratio(one).value_or(0.0), 0.048);
  one.resolved_neg = false;
  EXPECT_FALSE(peierls_ratio(one));
  PointResult failed = r;
  failed.failure = "diverged";
  EXPECT_FALSE(peierls_ratio(failed));
}

// The rigid-profile k2 is the decay rate of rigid_peierls_estimate beyond its prefactor:
// estimate(b) = A b exp(-k2 b).
TEST(PeierlsScan, RigidProfileK2IsTheDecayOfTheRigidEstimate) {
  for (const auto& [mx, my] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{2, 1}}) {
    const Orientation o{.mx = mx, .my = my, .theta_deg = line_angle_deg(mx, my)};
    const double k2 = rigid_profile_k2(o, 0.3);
    const double b1 = 2.0, b2 = 5.0;
    const double decay = std::log(rigid_peierls_estimate(b2, mx, my, 0.3) /
                                  rigid_peierls_estimate(b1, mx, my, 0.3) / (b2 / b1)) /
                         (b1 - b2);
    EXPECT_NEAR(k2, decay, 1e-9 * k2) << mx << ", " << my;
  }
}

// Fits per orientation take that orientation's resolved results in the window, nothing else.
TEST(PeierlsScan, FitsPerOrientation) {
  const Orientation edge{.mx = 1, .my = 0, .theta_deg = 90},
      screw{.mx = 0, .my = 1, .theta_deg = 0};
  std::vector<PointResult> results;
  for (double b : {1.0, 2.0, 3.0, 4.0, 5.0}) {
    PointResult e{.point = {.b_core = b, .orientation = edge}, .resolved_pos = true};
    e.tau_pos = 2.5 * std::exp(-1.8 * b);
    PointResult s{.point = {.b_core = b, .orientation = screw}, .resolved_neg = true};
    s.tau_neg = 1.4 * std::exp(-0.8 * b);
    results.push_back(e);
    results.push_back(s);
  }
  // Neither resolved, and failed: left out.
  results.push_back({.point = {.b_core = 3.5, .orientation = edge}});
  PointResult failed{.point = {.b_core = 2.5, .orientation = screw}, .resolved_pos = true};
  failed.tau_pos = 1.0;
  failed.failure = "diverged";
  results.push_back(failed);
  const std::vector<Orientation> both = {edge, screw};
  const auto fits = fit_orientations(results, both, 2.0, 1e9, 0.5);
  ASSERT_EQ(fits.size(), 2u);
  EXPECT_EQ(fits[0].orientation.mx, 1);
  ASSERT_TRUE(fits[0].fit.valid);
  EXPECT_EQ(fits[0].fit.points, 4u);  // b = 1 is outside the window
  EXPECT_NEAR(fits[0].fit.k1, 2.5, 1e-12);
  EXPECT_NEAR(fits[0].fit.k2, 1.8, 1e-12);
  ASSERT_TRUE(fits[1].fit.valid);
  EXPECT_EQ(fits[1].fit.points, 4u);
  EXPECT_NEAR(fits[1].fit.k1, 1.4, 1e-12);
  EXPECT_NEAR(fits[1].fit.k2, 0.8, 1e-12);
  EXPECT_EQ(fits[1].k2_rigid, rigid_profile_k2(screw, 0.5));
}

// The snapshot of a cell carries the cell's own interface stress, site for site (X * L + Y),
// for the full cell and for the reduced one expanded to L x L.
TEST(PeierlsScan, CellSnapshotHoldsTheCellsInterfaceStress) {
  for (const CellModel model : {CellModel::full, CellModel::reduced}) {
    CellOptions o;
    o.L = 16;
    o.mx = 2;
    o.my = 1;
    o.model = model;
    const PeierlsCell cell(o);
    std::vector<double> u = cell.initial_state();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    for (double& x : u)
      x += jitter(rng);
    const slide::Snapshot s = cell_snapshot(cell, u, "loaded", 0.02);
    EXPECT_EQ(s.label, "loaded");
    EXPECT_DOUBLE_EQ(s.Fx, 0.02 * 256);
    ASSERT_EQ(s.tau_x.size(), 256u);
    o.model = CellModel::full;
    const PeierlsCell full(o);
    const std::vector<double> expanded = cell.expand(u);
    std::vector<double> f(full.size());
    full.interface_force(expanded, f);
    for (std::size_t i = 0; i < 256; ++i) {
      EXPECT_NEAR(s.tau_x[i], f[i], 1e-12) << i;
      EXPECT_NEAR(s.tau_y[i], f[256 + i], 1e-12) << i;
      EXPECT_EQ(s.ux[i], expanded[i]);
      EXPECT_EQ(s.tau_max[i], cell.tau_max());
    }
    // s_x - X - u_x is minus the unwrapped frustration w = (m_x X + m_y Y) / L.
    EXPECT_NEAR(s.sx[15 * 16 + 15] - 15 - s.ux[15 * 16 + 15], -(2.0 * 15 + 15) / 16, 1e-12);
  }
}
