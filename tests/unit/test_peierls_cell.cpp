// Unit tier: the periodic Peierls cell (peierls/cell.hpp), its minimiser
// (minimize/stiffness_minimizer.hpp) and the exponential fit (peierls/fit.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "minimize/stiffness_minimizer.hpp"
#include "peierls/cell.hpp"
#include "peierls/fit.hpp"

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
