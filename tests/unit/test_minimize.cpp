// Unit tier: the lateral force model's interface physics and the minimisers (MODEL.md 3,
// SOLVERS.md): force and curvature against finite differences, all methods reaching the same
// minimum, a state started exactly on a saddle being left rather than returned, and each method
// run by the class registered for it.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/interface/sincos.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/minimize/relaxation.hpp"
#include "asperity/core/slide/lfm_problem.hpp"

using namespace asperity;

namespace {

// The slider's problem (slide/lfm_problem.hpp) on a block around the tip, with its GF and LFM.
struct Contact {
  Contact(const interface::ContactScene& scene, double Dx)
      : block(LatticeBlock::centred_disk(scene.a + 2.0)),
        gf(scene.material, elastic::Components::in_plane, block.shape),
        lfm(scene, block),
        problem(gf, lfm) {
    lfm.set_tip(Dx);
  }
  LatticeBlock block;
  elastic::FreeSurfaceGF gf;
  interface::LateralForceModel lfm;
  slide::LfmProblem problem;
};

double friction(const Contact& c, const std::vector<double>& u) {
  std::vector<double> f(u.size());
  c.lfm.energy_and_force(u, f);
  double fx = 0.0;
  for (std::size_t j = 0; j < u.size() / 2; ++j)
    fx += f[j];
  return fx;
}

}  // namespace

TEST(LateralForceModel, ForceAndCurvatureAreDerivativesOfTheEnergy) {
  interface::ContactScene scene {
    .a = 6.0, .R = 100.0
  };
  Contact c(scene, 0.37);
  const std::size_t n = c.problem.size();
  std::vector<double> u(n), f(n), f2(n), h(n), h2(n);
  for (std::size_t i = 0; i < n; ++i)
    u[i] = 0.3 * std::sin(1.7 * static_cast<double>(i));
  const double v = c.problem.interface(u, f);
  c.problem.curvature(u, h);
  for (std::size_t i : {std::size_t{0}, n / 3, n / 2 + 1, n - 1}) {
    const double step = 1e-6;
    std::vector<double> up = u, um = u;
    up[i] += step;
    um[i] -= step;
    const double dv = (c.problem.interface(up, f2) - c.problem.interface(um, f2)) / (2 * step);
    EXPECT_NEAR(-dv, f[i], 1e-8) << "site " << i;
    c.problem.interface(up, f2);
    const double df = f2[i];
    c.problem.interface(um, f2);
    EXPECT_NEAR(-(df - f2[i]) / (2 * step), h[i], 1e-7) << "site " << i;
  }
  // Registry everywhere: no energy, no force.
  std::vector<double> zero(n, 0.0);
  Contact at_origin(scene, 0.0);
  EXPECT_NEAR(at_origin.problem.interface(zero, f), 0.0, 1e-14);
  (void)v;
}

TEST(Minimizer, AllMethodsReachTheSameMinimum) {
  // A stuck state of a Regime II contact: tip at Dx = 0.3 d, starting from registry.
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  double reference_fx = 0.0, reference_e = 0.0;
  // The quasi-Newton methods also with the interface filter (forced: this contact is below the
  // automatic threshold, a / b_core^0 = 1.8).
  using P = minimize::Preconditioner;
  const std::pair<minimize::Method, P> cases[] = {
      {minimize::Method::lbfgs, P::automatic}, {minimize::Method::cg, P::automatic},
      {minimize::Method::fire, P::automatic},  {minimize::Method::newton, P::automatic},
      {minimize::Method::lbfgs, P::interface}, {minimize::Method::newton, P::interface},
      {minimize::Method::flow, P::automatic}};
  for (auto [method, precond] : cases) {
    Contact c(scene, 0.3);
    std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
    minimize::MinimizerOptions o{.method = method, .force_tolerance = 1e-9};
    o.preconditioner = precond;
    const auto r = minimize::minimize(c.problem, u, f, o);
    ASSERT_EQ(r.termination, Termination::converged) << to_string(method);
    EXPECT_EQ(r.filtered, precond == P::interface);
    EXPECT_EQ(r.filter_applications > 0, precond == P::interface);
    EXPECT_LE(r.max_force, 1e-9);
    // The pair stays consistent: u = G f.
    std::vector<double> g(u.size());
    c.problem.compliance(f, g);
    for (std::size_t i = 0; i < u.size(); ++i)
      ASSERT_NEAR(g[i], u[i], 1e-9);
    const double fx = friction(c, u);
    if (method == minimize::Method::lbfgs && precond == P::automatic) {
      reference_fx = fx;
      reference_e = r.energy;
    } else {
      EXPECT_NEAR(fx, reference_fx, 1e-7 * std::abs(reference_fx)) << to_string(method);
      EXPECT_NEAR(r.energy, reference_e, 1e-9 * std::abs(reference_e)) << to_string(method);
    }
    std::printf("%s (%s): %d iterations, %zu GF applications, %zu filter passes\n",
                to_string(method).c_str(), to_string(precond).c_str(), r.iterations,
                r.gf_applications, r.filter_applications);
  }
}

TEST(Minimizer, LeavesAStateStartedExactlyOnASaddle) {
  // Tip at Dx = d/2 with u = 0: every site sits on the top of its registry barrier along x and
  // feels no force. With lambda = 2 pi alpha Fz / (d k) > 1 the rigid mode is unstable, so this
  // is a saddle; a minimiser must not return it as converged.
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  ASSERT_GT(scene.lambda(), 1.0);
  for (auto [check, precond] :
       {std::pair{minimize::StabilityCheck::perturb, minimize::Preconditioner::elastic},
        std::pair{minimize::StabilityCheck::lanczos, minimize::Preconditioner::elastic},
        std::pair{minimize::StabilityCheck::perturb, minimize::Preconditioner::interface}}) {
    Contact c(scene, 0.5);
    std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0), fint(c.problem.size());
    const double e0 = c.problem.interface(u, fint);
    minimize::MinimizerOptions o{.stability = check};
    o.preconditioner = precond;
    const auto r = minimize::minimize(c.problem, u, f, o);
    EXPECT_EQ(r.termination, Termination::converged);
    EXPECT_EQ(r.filter_applications > 0, precond == minimize::Preconditioner::interface);
    EXPECT_GE(r.escapes, 1);
    EXPECT_LT(r.energy, e0 - 1e-3 * std::abs(e0));
    // The final state's lowest eigenvalue, where it had to be computed, is not negative.
    if (check == minimize::StabilityCheck::lanczos && !std::isnan(r.lowest_eigenvalue)) {
      EXPECT_GE(r.lowest_eigenvalue, 0.0);
    }
  }
  // Without a check the saddle is (wrongly) accepted: the check is what makes the difference.
  Contact c(scene, 0.5);
  std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
  const auto r = minimize::minimize(c.problem, u, f, {.stability = minimize::StabilityCheck::none});
  EXPECT_EQ(r.iterations, 0);
}

// lowest_mode() (Lanczos through Spectra above 60 unknowns) against the dense eigenproblem of
// the same A = G + G H G, built column by column from the problem's compliance and interface
// Hessian and solved by Eigen: the saddle of the test above (the tip at d/2, u = 0, lambda > 1),
// where the rigid mode is unstable, and the minimum a minimiser reaches from it. Tolerance:
// Spectra stops when the Ritz pair's residual is below 1e-6 of |theta| (SymEigsBase), which
// bounds the eigenvalue's error by about 1e-6 of the larger of |lowest| and the spectrum's
// top; the direction w must be an eigenvector of A to that residual.
TEST(Minimizer, LowestModeIsTheDenseHessiansLowestEigenvalue) {
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  Contact c(scene, 0.5);
  const std::size_t n = c.problem.size();
  ASSERT_GT(n, 60u);  // the Lanczos branch
  const auto dense_hessian = [&](const std::vector<double>& u) {
    minimize::InterfaceHessian h;
    h.at(c.problem, u);
    Eigen::MatrixXd a(n, n);
    std::vector<double> e(n, 0.0), z(n), t(n), y(n);
    for (std::size_t j = 0; j < n; ++j) {
      std::fill(e.begin(), e.end(), 0.0);
      e[j] = 1.0;
      c.problem.compliance(e, z);
      h.apply(z, t);
      c.problem.compliance(t, y);
      for (std::size_t i = 0; i < n; ++i)
        a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = y[i] + z[i];
    }
    return Eigen::MatrixXd(0.5 * (a + a.transpose()));
  };
  std::vector<double> u(n, 0.0), f(n, 0.0);
  for (const bool saddle : {true, false}) {
    if (!saddle) {
      ASSERT_EQ(
          minimize::minimize(c.problem, u, f, {.stability = minimize::StabilityCheck::lanczos})
              .termination,
          Termination::converged);
    }
    const Eigen::MatrixXd a = dense_hessian(u);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(a);
    const double lowest = es.eigenvalues()(0),
                 highest = es.eigenvalues()(static_cast<Eigen::Index>(n) - 1);
    const minimize::Stability s = minimize::lowest_mode(c.problem, u);
    ASSERT_TRUE(s.converged);
    std::printf("%s, %zu unknowns: Lanczos %.9g, dense %.9g (largest %.4g)\n",
                saddle ? "saddle" : "minimum", n, s.lowest, lowest, highest);
    const double scale = std::max(std::abs(lowest), highest);
    EXPECT_NEAR(s.lowest, lowest, 1e-6 * scale) << (saddle ? "saddle" : "minimum");
    EXPECT_EQ(s.lowest < 0.0, saddle);
    EXPECT_EQ(lowest < 0.0, saddle);
    // The direction: its force image w is an eigenvector of the dense A for the lowest value.
    ASSERT_EQ(s.direction_f.size(), n);
    const Eigen::Map<const Eigen::VectorXd> w(s.direction_f.data(), static_cast<Eigen::Index>(n));
    const double residual = (a * w - s.lowest * w).norm() / w.norm();
    std::printf("  |A w - lowest w| / |w| = %.3g\n", residual);
    EXPECT_LE(residual, 1e-5 * scale);
  }
}

TEST(Minimizer, RejectsBadOptions) {
  EXPECT_THROW(minimize::MinimizerOptions{.force_tolerance = 0.0}.validate(),
               std::invalid_argument);
  EXPECT_THROW(minimize::MinimizerOptions{.max_displacement = -1.0}.validate(),
               std::invalid_argument);
  EXPECT_THROW(minimize::method_from_string("steepest"), std::invalid_argument);
  EXPECT_THROW(minimize::preconditioner_from_string("jacobi"), std::invalid_argument);
  for (auto p : {minimize::Preconditioner::elastic, minimize::Preconditioner::interface,
                 minimize::Preconditioner::automatic}) {
    EXPECT_EQ(minimize::preconditioner_from_string(minimize::to_string(p)), p);
  }
}

TEST(LateralForceModel, FastSincosMatchesLibm) {
  // Exact reduction plus Taylor series on |x| <= pi/4: within 4e-16 of libm for arguments a
  // contact produces (positions up to thousands of d) and at the quadrant boundaries.
  double worst = 0.0;
  for (int k = -200000; k <= 200000; ++k) {
    const double s = k * 1.37e-3 + 1e-9 * (k % 7);
    double sn = 0.0, cs = 0.0;
    interface::sincos_2pi(s, sn, cs);
    const double r = s - std::round(s);  // libm on the reduced argument: no 2 pi s error
    worst = std::max(
        {worst, std::abs(sn - std::sin(2.0 * M_PI * r)), std::abs(cs - std::cos(2.0 * M_PI * r))});
  }
  for (double s : {0.125, 0.25, 0.375, 0.5, -0.125, -0.25, -0.5, 1e6 + 0.25}) {
    double sn = 0.0, cs = 0.0;
    interface::sincos_2pi(s, sn, cs);
    const double r = s - std::round(s);
    worst = std::max(
        {worst, std::abs(sn - std::sin(2.0 * M_PI * r)), std::abs(cs - std::cos(2.0 * M_PI * r))});
  }
  EXPECT_LT(worst, 4e-16);
}

TEST(Minimizer, InjectedNanStopsAtOnce) {
  // An interface force that turns NaN (a bug, or a state out of range) is caught at the next
  // iteration and reported as diverged, not iterated on or returned as converged.
  struct Poisoned final : minimize::Problem {
    explicit Poisoned(minimize::Problem& p) : inner(p) {}
    [[nodiscard]] std::size_t size() const override { return inner.size(); }
    void compliance(std::span<const double> f, std::span<double> u) override {
      inner.compliance(f, u);
    }
    double interface(std::span<const double> u, std::span<double> f) const override {
      const double v = inner.interface(u, f);
      if (++calls > 3) f[f.size() / 2] = std::nan("");
      return v;
    }
    void curvature(std::span<const double> u, std::span<double> h) const override {
      inner.curvature(u, h);
    }
    [[nodiscard]] std::size_t gf_applications() const override { return inner.gf_applications(); }
    minimize::Problem& inner;
    mutable int calls = 0;
  };
  Contact c({.a = 10.0, .R = 100.0}, 0.3);
  Poisoned p(c.problem);
  std::vector<double> u(p.size(), 0.0), f(p.size(), 0.0);
  const auto r = minimize::minimize(p, u, f, {});
  EXPECT_EQ(r.termination, Termination::diverged);
  EXPECT_LE(p.calls, 6);
}

namespace {

// One unknown: a site on a spring of compliance g (elastic energy u^2 / (2 g)) in a periodic
// potential V = A (1 - cos 2 pi u), tilted by a constant force F: E = u^2/(2g) + V - F u.
struct Washboard final : minimize::Problem {
  double g = 20.0, A = 0.05, F = 0.0;
  [[nodiscard]] std::size_t size() const override { return 1; }
  void compliance(std::span<const double> f, std::span<double> u) override {
    u[0] = g * f[0];
    ++applications;
  }
  double interface(std::span<const double> u, std::span<double> f) const override {
    f[0] = -2.0 * M_PI * A * std::sin(2.0 * M_PI * u[0]) + F;
    return A * (1.0 - std::cos(2.0 * M_PI * u[0])) - F * u[0];
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    h[0] = 4.0 * M_PI * M_PI * A * std::cos(2.0 * M_PI * u[0]);
  }
  [[nodiscard]] std::size_t gf_applications() const override { return applications; }
  [[nodiscard]] double slope(double u) const {  // dE/du
    return u / g + 2.0 * M_PI * A * std::sin(2.0 * M_PI * u) - F;
  }
  std::size_t applications = 0;
};

}  // namespace

TEST(Minimizer, FlowEndsInTheMinimumOfItsBasin) {
  // Analytic answer: a gradient flow in one dimension never crosses a maximum of E, so from u0
  // it ends at the minimum between the maxima of E on either side of u0 (found here by
  // bisection on the slope to 1e-12). The start sits just past a maximum, on a long steep
  // descent (tilt F) that carries a large step over the next barriers: wells 2 and 3 lie
  // downhill within 2 d. Tolerance on u: the force tolerance 1e-10 over the curvature at the
  // minimum (about 2 + 1/g), 1e-9.
  Washboard p;
  p.F = 0.2;
  const auto root = [&](double lo, double hi) {  // slope changes sign in [lo, hi]
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (lo + hi);
      ((p.slope(lo) < 0.0) == (p.slope(mid) < 0.0) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  // Stationary points on a fine grid; the start lies just past the maximum near u = 0.5.
  std::vector<double> stationary;
  for (double u = -1.0; u < 6.0; u += 1e-3) {
    if ((p.slope(u) < 0.0) != (p.slope(u + 1e-3) < 0.0)) stationary.push_back(root(u, u + 1e-3));
  }
  ASSERT_GE(stationary.size(), 6u);
  std::size_t top = 0;  // first maximum with u > 0: slope goes from + to -
  while (!(stationary[top] > 0.0 && p.slope(stationary[top] - 1e-6) > 0.0))
    ++top;
  const double u0 = stationary[top] + 1e-3, expected = stationary[top + 1];
  for (auto [scheme, tolerance] :
       {std::pair{minimize::FlowScheme::rkc, 1e-3}, std::pair{minimize::FlowScheme::rkc, 1e-4},
        std::pair{minimize::FlowScheme::euler, 1e-3},
        std::pair{minimize::FlowScheme::euler, 1e-4}}) {
    std::vector<double> u{u0}, f{u0 / p.g};
    minimize::MinimizerOptions o{.method = minimize::Method::flow, .force_tolerance = 1e-10};
    o.flow_tolerance = tolerance;
    o.flow_scheme = scheme;
    o.max_iterations = 200000;
    o.max_displacement = 0.5;
    const auto r = minimize::minimize(p, u, f, o);
    ASSERT_EQ(r.termination, Termination::converged);
    EXPECT_NEAR(u[0], expected, 1e-9) << "flow tolerance " << tolerance;
    EXPECT_EQ(r.gf_applications, p.applications);
    p.applications = 0;
    std::printf("flow (%s) tolerance %g: %d steps (%d rejected), %zu GF, u = %.12f\n",
                minimize::to_string(scheme).c_str(), tolerance, r.iterations, r.rejected_steps,
                r.gf_applications, u[0]);
  }
  // An unguarded Euler step of the size of the slope leaves the basin: the control is needed.
  {
    std::vector<double> u{u0}, f{u0 / p.g};
    minimize::MinimizerOptions o{.method = minimize::Method::flow, .force_tolerance = 1e-10};
    o.flow_tolerance = 1.0;  // no error control to speak of
    o.max_displacement = 0.5;
    o.max_iterations = 200000;
    minimize::minimize(p, u, f, o);
    std::printf("flow tolerance 1: u = %.6f (basin minimum %.6f)\n", u[0], expected);
    EXPECT_GT(std::abs(u[0] - expected), 0.5);  // another well: the test above can fail
  }
}

TEST(Minimizer, FlowPausedAnywhereContinuesBitForBit) {
  // A slip relaxation of hours has to survive the end of a run (slide::PendingSlip): a flow
  // paused after any accepted step and continued, on a fresh problem, from the FlowPause alone
  // ends in the same bits, with the same counts, as the flow that never paused. Both schemes,
  // and rkc in the filter's metric (the slip minimiser's), whose spectral radius estimate and
  // power vector carry over (the flow runs past the 25-step re-estimate).
  const interface::ContactScene scene { .a = 6.0, .R = 100.0 };
  using P = minimize::Preconditioner;
  for (auto [scheme, precond] : {std::pair{minimize::FlowScheme::rkc, P::interface},
                                 std::pair{minimize::FlowScheme::rkc, P::elastic},
                                 std::pair{minimize::FlowScheme::euler, P::elastic}}) {
    minimize::MinimizerOptions o{.method = minimize::Method::flow, .force_tolerance = 1e-7};
    o.preconditioner = precond;
    o.flow_scheme = scheme;
    o.refresh_interval = 20;  // the drift refresh falls after some pauses too
    const std::string what = minimize::to_string(scheme) + "/" + minimize::to_string(precond);
    Contact ref(scene, 0.45);
    std::vector<double> u_ref(ref.problem.size(), 0.0), f_ref(ref.problem.size(), 0.0);
    const auto r_ref = minimize::minimize(ref.problem, u_ref, f_ref, o);
    ASSERT_EQ(r_ref.termination, Termination::converged) << what;
    ASSERT_GT(r_ref.iterations, 30) << what;
    std::printf("%s: %d steps (%d rejected), %zu GF applications\n", what.c_str(), r_ref.iterations,
                r_ref.rejected_steps, r_ref.gf_applications);
    // About 20 pause points spread over the flow, the first steps included.
    int pauses_tried = 0;
    const int stride = std::max(1, r_ref.iterations / 12);
    for (int k = 1; k < r_ref.iterations; k += (k < 4 ? 1 : stride)) {
      std::optional<minimize::FlowPause> saved;
      const minimize::FlowPauses at_k{.due = [&](int it) { return it == k; },
                                      .pause =
                                          [&](const minimize::FlowPause& p) {
                                            saved = p;
                                            return true;
                                          }};
      Contact c(scene, 0.45);
      std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
      const auto r1 = minimize::minimize(c.problem, u, f, o, {}, nullptr, &at_k);
      if (!saved) continue;  // k fell on a rejected step's iteration
      ++pauses_tried;
      ASSERT_EQ(r1.termination, Termination::interrupted) << what << " k " << k;
      EXPECT_EQ(saved->iteration, k);
      // Continued on a fresh problem from the pause alone (u and f only give the size).
      Contact again(scene, 0.45);
      std::vector<double> u2(again.problem.size(), 7.0), f2(again.problem.size(), 7.0);
      const auto r2 = minimize::minimize(again.problem, u2, f2, o, {}, &*saved);
      ASSERT_EQ(r2.termination, Termination::converged) << what << " k " << k;
      EXPECT_EQ(u2, u_ref) << what << ": paused at " << k;
      EXPECT_EQ(f2, f_ref) << what << ": paused at " << k;
      EXPECT_EQ(r2.iterations, r_ref.iterations) << what << " k " << k;
      EXPECT_EQ(r2.gf_applications, r_ref.gf_applications) << what << " k " << k;
      EXPECT_EQ(r2.interface_evaluations, r_ref.interface_evaluations) << what << " k " << k;
      EXPECT_EQ(r2.filter_applications, r_ref.filter_applications) << what << " k " << k;
      EXPECT_EQ(r2.rejected_steps, r_ref.rejected_steps) << what << " k " << k;
      EXPECT_EQ(r2.filtered, r_ref.filtered) << what << " k " << k;
      EXPECT_EQ(r2.energy, r_ref.energy) << what << " k " << k;
    }
    EXPECT_GT(pauses_tried, 8) << what;
    // A pause that does not stop the flow changes nothing.
    {
      int seen = 0;
      const minimize::FlowPauses every{.due = [](int) { return true; },
                                       .pause =
                                           [&](const minimize::FlowPause&) {
                                             ++seen;
                                             return false;
                                           }};
      Contact c(scene, 0.45);
      std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
      const auto r = minimize::minimize(c.problem, u, f, o, {}, nullptr, &every);
      EXPECT_EQ(u, u_ref) << what;
      EXPECT_EQ(r.gf_applications, r_ref.gf_applications) << what;
      EXPECT_GT(seen, 10) << what;
    }
  }
  // Only a flow's pause of the same size can be continued.
  Contact c(scene, 0.45);
  std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
  minimize::FlowPause bad{.iteration = 3, .u = u, .f = f};
  EXPECT_THROW(minimize::minimize(c.problem, u, f, {.method = minimize::Method::lbfgs}, {}, &bad),
               std::invalid_argument);
  EXPECT_THROW(minimize::minimize(c.problem, u, f, {.method = minimize::Method::flow}, {}, &bad),
               std::invalid_argument);  // no velocity, no step
  bad.u.pop_back();
  EXPECT_THROW(minimize::minimize(c.problem, u, f, {.method = minimize::Method::flow}, {}, &bad),
               std::invalid_argument);
}

TEST(Minimizer, MaxResidualIsTheNumberMinimizeTests) {
  // max_residual of a converged call's pair is the max_force that call tested against the
  // tolerance, to the bit (the same evaluation, the same passes); of a flow's pause, the
  // distance from rest the flow went on from (above the tolerance); of any pair, the largest
  // |f - f_int(u)| made by hand from the interface.
  const interface::ContactScene scene { .a = 6.0, .R = 100.0 };
  for (const auto method : {minimize::Method::lbfgs, minimize::Method::flow}) {
    Contact c(scene, 0.45);
    std::vector<double> u(c.problem.size(), 0.0), f(c.problem.size(), 0.0);
    const minimize::MinimizerOptions o{.method = method, .force_tolerance = 1e-7};
    const auto r = minimize::minimize(c.problem, u, f, o);
    ASSERT_EQ(r.termination, Termination::converged) << to_string(method);
    EXPECT_EQ(minimize::max_residual(c.problem, u, f), r.max_force) << to_string(method);
    EXPECT_LE(minimize::max_residual(c.problem, u, f), o.force_tolerance);
  }
  Contact c(scene, 0.45);
  const std::size_t n = c.problem.size();
  std::optional<minimize::FlowPause> saved;
  const minimize::FlowPauses at_5{.due = [](int it) { return it == 5; },
                                  .pause =
                                      [&](const minimize::FlowPause& p) {
                                        saved = p;
                                        return true;
                                      }};
  std::vector<double> u(n, 0.0), f(n, 0.0);
  const minimize::MinimizerOptions flow{.method = minimize::Method::flow, .force_tolerance = 1e-7};
  (void)minimize::minimize(c.problem, u, f, flow, {}, nullptr, &at_5);
  ASSERT_TRUE(saved.has_value());
  const double paused = minimize::max_residual(c.problem, saved->u, saved->f);
  EXPECT_GT(paused, flow.force_tolerance);
  std::vector<double> fint(n);
  (void)c.problem.interface(saved->u, fint);
  double by_hand = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    by_hand = std::max(by_hand, std::abs(saved->f[i] - fint[i]));
  EXPECT_EQ(paused, by_hand);
  // A NaN anywhere shows; a pair of the wrong size is refused.
  std::vector<double> bad = saved->f;
  bad[n / 2] = std::nan("");
  EXPECT_TRUE(std::isnan(minimize::max_residual(c.problem, saved->u, bad)));
  bad.pop_back();
  EXPECT_THROW((void)minimize::max_residual(c.problem, saved->u, bad), std::invalid_argument);
}

TEST(Minimizer, FlowRejectsBadTolerance) {
  EXPECT_THROW(minimize::MinimizerOptions{.flow_tolerance = 0.0}.validate(), std::invalid_argument);
  EXPECT_EQ(minimize::method_from_string("flow"), minimize::Method::flow);
  EXPECT_EQ(minimize::to_string(minimize::Method::flow), "flow");
  for (auto scheme : {minimize::FlowScheme::rkc, minimize::FlowScheme::euler})
    EXPECT_EQ(minimize::flow_scheme_from_string(minimize::to_string(scheme)), scheme);
  EXPECT_THROW(minimize::flow_scheme_from_string("rk45"), std::invalid_argument);
}

TEST(Minimizer, EveryMethodIsTheClassRegisteredUnderItsName) {
  // A method is a class plus its row in method_registry() (minimize/relaxation.hpp): every value
  // of minimize::Method has a row, the row's class implements that value (a row that makes
  // another method's class runs the wrong minimiser under the right name), and the names the
  // "method" setting offers are the registry's, each read back to its own value.
  using M = minimize::Method;
  Washboard p;
  const std::vector<double> u{0.1}, f{0.1 / p.g};
  const auto try_method = [&](M m) {
    const minimize::MinimizerOptions o{.method = m};
    minimize::detail::Relaxation run(p, o, u, f, nullptr);
    return minimize::detail::make_method(m, run)->method();
  };
  for (M m : {M::lbfgs, M::cg, M::fire, M::newton, M::flow}) {
    EXPECT_EQ(minimize::detail::registered(m).method, m) << minimize::to_string(m);
    EXPECT_EQ(minimize::to_string(try_method(m)), minimize::to_string(m));
  }
  const auto* row = settings::find(minimize::MinimizerOptions::settings(), "method");
  ASSERT_NE(row, nullptr);
  std::vector<M> seen;
  for (const std::string& name : row->choices) {
    const M m = minimize::method_from_string(name);
    EXPECT_EQ(minimize::to_string(m), name);
    EXPECT_EQ(minimize::to_string(try_method(m)), name);
    seen.push_back(m);
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::unique(seen.begin(), seen.end()), seen.end()) << "two names, one method";
  EXPECT_EQ(seen.size(), minimize::detail::method_registry().size());
  // A value with no row is refused, not run as some other method.
  const auto unknown = static_cast<M>(99);
  EXPECT_THROW(minimize::detail::registered(unknown), std::invalid_argument);
  EXPECT_THROW(try_method(unknown), std::invalid_argument);
  EXPECT_THROW(minimize::MinimizerOptions{.method = unknown}.validate(), std::invalid_argument);
  std::vector<double> u2 = u, f2 = f;
  EXPECT_THROW(minimize::minimize(p, u2, f2, {.method = unknown}), std::invalid_argument);
}
