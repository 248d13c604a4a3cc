// Analytic tier: the sliding protocol (slide/protocol.hpp, MODEL.md section 5) on the
// Prandtl-Tomlinson model, a contact model of one site written against the SlideModel concept
// (a third model is one class, protocol.hpp), relaxed by the library's own minimisers.
//
// The model: one substrate site held by a spring of stiffness k (the elastic body: u = G f with
// G = 1/k) under a registry potential of period d that moves with the tip,
//   Pi(u; Dx) = k/2 u^2 + U0 (1 - cos(2 pi (u - Dx) / d))      (x; y is pinned likewise at 0),
// and the friction is the spring's force Fx = k u over a fixed load Fz. With theta = 2 pi (Dx -
// u) / d, equilibrium is k u = A sin(theta), A = 2 pi U0 / d, and it is stable while
// k + A (2 pi / d) cos(theta) > 0. For eta = 2 pi A / (k d) = 4 pi^2 U0 / (k d^2) > 1 the
// stuck branch ends at a fold:
//   cos(theta*) = -1 / eta,  F* = A sqrt(1 - 1/eta^2),  Dx* = F* / k + (d / 2 pi) theta*.
// The friction Fx = A sin(theta) is largest at theta = pi / 2, where Dx_p = A / k + d / 4, before
// the fold (theta* > pi / 2): mu Fz = A, a smooth maximum, then Fx falls to F* and slips.
// What the protocol must give, exactly (MODEL.md 5):
// - the instability bracketed from its stable end, min_step wide: the last stable row at
//   Dx_s <= Dx*, the slip at Dx_slip in (Dx*, Dx_s + min_step], the stable row's Fx the stuck
//   branch's k u(Dx_s) (solved here);
// - mu = A / Fz from below, within the precision the slide reports, and that precision no worse
//   than a sample within min_step of the maximum: A - Fx <= |d2Fx/dDx2| min_step^2 / 2 with
//   d2Fx/dDx2 = -A (2 pi / d)^2 at Dx_p (dDx/dtheta = d / 2 pi there);
// - the slip goes where the overdamped flow takes it: from the stable state's u, moved to
//   Dx_slip, down Pi in u to the first equilibrium (a 1-D gradient flow cannot pass one), here
//   the next well: one registry change (slipped_sites = 1), Fx = k u_land.
// Tolerances: the minimisers stop at |r| <= 1e-10 G d^2. Near the fold the stiffness
// Pi'' = k + A (2 pi / d) cos(theta) is smallest at the bracket's stable end; at eta = 4 and
// min_step = 0.01 d it is about 0.7 k, so u is within 1e-10 / 0.7k and Fx within 2e-10: 1e-8 is
// a margin of 50, and the flow's end state in the new well (Pi'' about k + A 2 pi / d) the same.
// Also: the fast relaxation of a step that the slip minimiser may take over (it is then thrown
// away) records no relaxation-path frames; the slip minimiser's relaxation of each slip does,
// and they reach the sink as the slip's path.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/minimize/problem.hpp"
#include "asperity/core/slide/protocol.hpp"

using namespace asperity;

namespace {

constexpr double kPi = std::numbers::pi;

struct Tomlinson1 {
  double d = 1.0;    // period (d)
  double k = 1.0;    // spring stiffness (G d)
  double eta = 4.0;  // 4 pi^2 U0 / (k d^2): > 1 for stick-slip
  double Fz = 1.0;   // load (G d^2)
  [[nodiscard]] double U0() const { return eta * k * d * d / (4.0 * kPi * kPi); }
  [[nodiscard]] double A() const { return 2.0 * kPi * U0() / d; }
  [[nodiscard]] double theta_fold() const { return std::acos(-1.0 / eta); }
  [[nodiscard]] double F_fold() const { return A() * std::sqrt(1.0 - 1.0 / (eta * eta)); }
  [[nodiscard]] double Dx_fold() const { return F_fold() / k + d * theta_fold() / (2.0 * kPi); }
  // dPi/du at tip position Dx.
  [[nodiscard]] double slope(double u, double Dx) const {
    return k * u + A() * std::sin(2.0 * kPi * (u - Dx) / d);
  }
  // u on the stuck branch (theta in [0, theta*]), where the slope rises with u: bisection.
  [[nodiscard]] double stuck_u(double Dx) const {
    double lo = Dx - d * theta_fold() / (2.0 * kPi), hi = Dx;  // slope(lo) <= 0 <= slope(hi)
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (slope(mid, Dx) > 0.0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
  // Where the overdamped flow du/dt = -dPi/du from u0 (slope > 0 there) ends: the first zero of
  // the slope below u0.
  [[nodiscard]] double flow_end(double u0, double Dx) const {
    const double h = 1e-4 * d;
    double hi = u0;
    while (slope(hi - h, Dx) > 0.0)
      hi -= h;
    double lo = hi - h;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (slope(mid, Dx) > 0.0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

// Pi in the pair representation (minimize/problem.hpp): G = 1/k, V the registry potential.
class TomlinsonProblem final : public minimize::Problem {
 public:
  explicit TomlinsonProblem(const Tomlinson1& m) : m_(m) {}
  double Dx = 0.0;

  [[nodiscard]] std::size_t size() const override { return 2; }
  void compliance(std::span<const double> f, std::span<double> u) override {
    ++gf_;
    for (std::size_t i = 0; i < 2; ++i)
      u[i] = f[i] / m_.k;
  }
  double interface(std::span<const double> u, std::span<double> f_int) const override {
    const double q = 2.0 * kPi / m_.d;
    f_int[0] = -m_.A() * std::sin(q * (u[0] - Dx));
    f_int[1] = -m_.A() * std::sin(q * u[1]);
    return m_.U0() * (2.0 - std::cos(q * (u[0] - Dx)) - std::cos(q * u[1]));
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    const double q = 2.0 * kPi / m_.d;
    h[0] = m_.A() * q * std::cos(q * (u[0] - Dx));
    h[1] = m_.A() * q * std::cos(q * u[1]);
  }
  [[nodiscard]] std::size_t gf_applications() const override { return gf_; }

 private:
  Tomlinson1 m_;
  std::size_t gf_ = 0;
};

// One relax() call as the protocol made it.
struct RelaxCall {
  double Dx;
  bool stop_on_slip, slip_minimizer, frames;
};

// The Prandtl-Tomlinson contact as a slide::detail::SlideModel.
class TomlinsonModel {
 public:
  using State = slide::SlideFields;
  TomlinsonModel(const Tomlinson1& m, const slide::SlideOptions& o)
      : m_(m), options_(o), problem_(m) {}

  State initial() {
    State s{.Dx = 0.0, .shift = 0, .f = {0.0, 0.0}, .u = {0.0, 0.0}};
    summarise(s);
    return s;
  }
  minimize::MinimizeResult relax(State& s, double Dx, std::vector<slide::PathFrame>* frames,
                                 bool stop_on_slip = false,
                                 const minimize::MinimizerOptions* solver = nullptr) {
    calls.push_back({Dx, stop_on_slip,
                     solver != nullptr && solver->method == minimize::Method::flow,
                     frames != nullptr});
    problem_.Dx = Dx;
    s.Dx = Dx;
    problem_.compliance(s.f, s.u);
    const double u_start = s.u[0];
    const bool record = frames != nullptr && options_.path_frame_every > 0;
    minimize::Observer observer = [&](int it, std::span<const double> u, std::span<const double>) {
      if (record && it % options_.path_frame_every == 0) {
        frames->push_back(
            {.iteration = it, .fields = {.Dx = Dx, .shift = 0, .f = {}, .u = {u[0], u[1]}}});
      }
      return stop_on_slip && std::abs(u[0] - u_start) > 0.75 * m_.d;
    };
    const auto r =
        minimize::minimize(problem_, s.u, s.f, solver ? *solver : options_.minimizer, observer);
    summarise(s);
    return r;
  }
  void align(State&, const State&) {}
  // The registry index of the site: the well of the tip's potential it sits in.
  [[nodiscard]] int registry(const State& s) const {
    return static_cast<int>(std::floor((s.Dx - s.u[0]) / m_.d + 0.5));
  }
  int slipped_sites(const State& before, const State& after) const {
    return registry(before) != registry(after) ? 1 : 0;
  }
  slide::Snapshot snapshot(const State& s, std::string label, int iteration = -1) const {
    return {.label = std::move(label),
            .iteration = iteration,
            .Dx = s.Dx,
            .Fx = s.Fx,
            .Fz = s.Fz,
            .energy = s.energy};
  }
  [[nodiscard]] std::string check_fields(const State& s) const {
    return s.u.size() == 2 && s.f.size() == 2 ? "" : "2 values (one site, x then y)";
  }
  [[nodiscard]] std::size_t field_size() const { return 2; }
  [[nodiscard]] std::size_t contact_sites() const { return 1; }
  [[nodiscard]] std::size_t gf_applications() const { return problem_.gf_applications(); }
  [[nodiscard]] Shape2 block_shape() const { return {1, 1}; }
  [[nodiscard]] Shape2 fft_grid() const { return {1, 1}; }

  std::vector<RelaxCall> calls;

 private:
  void summarise(State& s) const {
    s.Fx = s.f[0];
    s.Fz = m_.Fz;
    s.area = m_.d * m_.d;
    const double q = 2.0 * kPi / m_.d;
    s.energy = 0.5 * m_.k * (s.u[0] * s.u[0] + s.u[1] * s.u[1]) +
               m_.U0() * (2.0 - std::cos(q * (s.u[0] - s.Dx)) - std::cos(q * s.u[1]));
  }

  Tomlinson1 m_;
  const slide::SlideOptions& options_;
  TomlinsonProblem problem_;
};
static_assert(slide::detail::SlideModel<TomlinsonModel>);

slide::SlideOptions tomlinson_options() {
  slide::SlideOptions o;
  o.minimizer.force_tolerance = 1e-10;
  minimize::MinimizerOptions flow = o.minimizer;
  flow.method = minimize::Method::flow;
  o.slip_minimizer = flow;
  o.path_frame_every = 1;
  o.path_frame_slips = 1;
  o.validate();
  return o;
}

struct Slid {
  slide::SlideResult result;
  std::vector<RelaxCall> calls;
};

Slid slide_tomlinson(const Tomlinson1& m, const slide::SlideOptions& o) {
  TomlinsonModel model(m, o);
  const slide::detail::ProtocolParams params{
      .d = m.d, .alpha = 1.0, .Fz_continuum = m.Fz, .default_cap = 3.0 * m.d};
  Slid out;
  out.result = slide::detail::run_protocol(model, params, o, slide::SlideControl{},
                                           std::chrono::steady_clock::now());
  out.calls = model.calls;
  return out;
}

// eta = 4: the weak case, the fold 0.02 d after the maximum. eta = 20: the site has about six
// metastable wells at the fold (k |u - u'| <= 2 A), the flow's is the next one, two wells short
// of the lowest (the spring nearly unstretched), and the maximum lies 0.004 d before the fold.
class ProtocolTomlinsonEta : public ::testing::TestWithParam<double> {};

TEST_P(ProtocolTomlinsonEta, BracketsEachFoldAndFindsTheMaximumBeforeIt) {
  const Tomlinson1 m{.eta = GetParam()};
  slide::SlideOptions o = tomlinson_options();
  o.max_distance = m.Dx_fold() + 3.0 * m.d;  // two periods past the first fold, and a margin
  const Slid s = slide_tomlinson(m, o);
  const auto& trace = s.result.trace;
  // Pi(u; Dx + d) = Pi(u; Dx): the n-th slip (from 0) is the fold of period n, from the same u.
  int n = 0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    if (!trace[i].slip) continue;
    const auto& stable = trace[i - 1];
    const auto& slip = trace[i];
    const double Dx_fold = m.Dx_fold() + n * m.d;
    std::printf("slip %d: fold Dx* = %.9f d; bracket [%.9f, %.9f] d\n", n + 1, Dx_fold, stable.Dx,
                slip.Dx);
    EXPECT_LE(stable.Dx, Dx_fold);
    EXPECT_GT(slip.Dx, Dx_fold);
    EXPECT_TRUE(o.within_min_step(slip.Dx - stable.Dx)) << slip.Dx - stable.Dx;
    const double u_stable = m.stuck_u(stable.Dx - n * m.d);
    EXPECT_NEAR(stable.Fx, m.k * u_stable, 1e-8);
    // Where the flow from the stable state, moved to the slip's Dx, ends: the next well.
    const double u_land = m.flow_end(u_stable, slip.Dx - n * m.d);
    EXPECT_NEAR(slip.Fx, m.k * u_land, 1e-8);
    EXPECT_EQ(slip.slipped_sites, 1);
    ++n;
  }
  EXPECT_EQ(n, s.result.slip_events);
  ASSERT_GE(n, 2);

  // The smooth maximum before the fold, from below, within the reported precision.
  const double mu_exact = m.A() / m.Fz;
  std::printf("mu %.12f at %.9f d, precision %.3g; A / Fz %.12f\n", s.result.mu, s.result.peak_Dx,
              s.result.peak_precision, mu_exact);
  EXPECT_LE(s.result.mu, mu_exact + 1e-8);
  EXPECT_LE(mu_exact - s.result.mu, s.result.peak_precision + 1e-8);
  const double curvature = m.A() * std::pow(2.0 * kPi / m.d, 2);
  EXPECT_LE(s.result.peak_precision, 0.5 * curvature * o.min_step * o.min_step / m.Fz);
  EXPECT_FALSE(s.result.mu_is_lower_bound);
}
INSTANTIATE_TEST_SUITE_P(Eta, ProtocolTomlinsonEta, ::testing::Values(4.0, 20.0));

TEST(ProtocolTomlinson, RecordsPathFramesOnlyOfTheRelaxationThatIsKept) {
  const Tomlinson1 m;
  const Slid s = slide_tomlinson(m, tomlinson_options());
  int fast = 0, flows = 0;
  for (const RelaxCall& c : s.calls) {
    // A step's fast relaxation (stop_on_slip: undone, or handed to the slip minimiser if it
    // slips) is thrown away when it slips, and a step that does not slip shows no path.
    if (c.stop_on_slip) {
      ++fast;
      EXPECT_FALSE(c.frames) << "the fast relaxation to Dx = " << c.Dx << " d records a path";
    }
    if (c.slip_minimizer) {
      ++flows;
      EXPECT_TRUE(c.frames) << "the slip relaxation to Dx = " << c.Dx << " d records no path";
    }
  }
  EXPECT_GT(fast, 0);
  EXPECT_EQ(flows, s.result.slip_events);
  ASSERT_GE(s.result.slip_events, 2);
  // Every slip's path reached the sink (here the result's snapshots), labelled by its slip.
  for (int e = 1; e <= s.result.slip_events; ++e) {
    char label[32];
    std::snprintf(label, sizeof label, "slip_%03d_path", e);
    int n = 0;
    for (const slide::Snapshot& f : s.result.snapshots)
      n += f.label == label;
    EXPECT_GT(n, 0) << label;
  }
}

}  // namespace
