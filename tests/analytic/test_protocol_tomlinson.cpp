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
// - mu = A / Fz from below, within the precision the slide reports, and that precision below
//   the shortfall of a sample min_step from a parabolic maximum, |d2Fx/dDx2| min_step^2 / 2 with
//   d2Fx/dDx2 = -A (2 pi / d)^2 at Dx_p (dDx/dtheta = d / 2 pi there). This is the parabola's
//   bound, a leading-order one: towards the fold Fx falls faster (at +0.01 d, 1.7e-3 against
//   1.3e-3 A for eta = 4). The reported precision (the parabola's excess over the best sample,
//   or, for a peak just before a slip, the gap times the secant slope) was 4.4e-5 and 2.0e-3
//   against bounds of 1.3e-3 and 6.3e-3 at eta = 4 and 20.
// - the slip goes where the overdamped flow takes it: from the stable state's u, moved to
//   Dx_slip, down Pi in u to the first equilibrium (a 1-D gradient flow cannot pass one), here
//   the next well: the registry index round((Dx - u) / d) one up, Fx = k u_land.
// Tolerances: the minimisers stop at |r| <= tol = 1e-10 G d^2, so a state is within tol / Pi''
// of the equilibrium in u and Fx = k u within k tol / Pi'', Pi'' = k + A (2 pi / d) cos(theta)
// the stiffness there. It vanishes at the fold: at the bracket's stable end, delta before it,
// Pi'' = sqrt(2 k delta (2 pi / d)^2 F*) to leading order (0.13 k at eta = 4, where the bracket
// ends 4e-4 d before the fold; 1.2 k at eta = 20), so each state is compared to 10 k tol / Pi''
// at its own stiffness (the factor 10: the stopping test is on the largest of two components,
// and round-off in the sums).
// Also: the fast relaxation of a step that the slip minimiser may take over (it is then thrown
// away) records no relaxation-path frames; the slip minimiser's relaxation of each slip does,
// and they reach the sink as the slip's path. And the model can pause its slip flows (as the
// lateral force model does), so that a slide checkpointed at every chance, or stopped at any of
// its polls and resumed from the checkpoint (paused inside a slip's flow, or between steps, or
// from an abandoned relaxation), is the uninterrupted slide bit for bit, at the same cost (GF
// applications, iterations, relaxations). Measured: 171 checkpoints (151 inside flows), every
// other one resumed (86), and 59 stops (30 inside flows).
// Creep (flow_first_after; eta = 20, step growth 2, flow_first_after = 1): the flow taken first,
// and a fast minimiser made to overshoot into the next well where that flow found the step
// stable (no slide of the lateral force model in the suite reaches that branch), against the
// slide without flow_first_after: the same rows. And that slide stopped at every other poll (592
// stops of 1 183), resumed from every 15th of its 922 checkpoints, and stopped again and again in
// sessions of k polls (a stop inside a flow that an earlier stop paused): the same rows and costs.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/minimize/problem.hpp"
#include "asperity/core/slide/protocol.hpp"
#include "common/results.hpp"

using namespace asperity;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kForceTolerance = 1e-10;  // of both minimisers (G d^2)

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
  // The well of the tip's potential the site sits in.
  [[nodiscard]] int registry(double u, double Dx) const {
    return static_cast<int>(std::floor((Dx - u) / d + 0.5));
  }
  // d2Pi/du2 at tip position Dx.
  [[nodiscard]] double stiffness(double u, double Dx) const {
    return k + A() * (2.0 * kPi / d) * std::cos(2.0 * kPi * (u - Dx) / d);
  }
  // How far Fx of a state the minimisers leave at u may lie from the equilibrium's (the
  // tolerances in the header).
  [[nodiscard]] double accuracy(double u, double Dx) const {
    return 10.0 * k * kForceTolerance / stiffness(u, Dx);
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

// A fast minimiser that lands in another minimum, for the creep tests: its relaxations to the tip
// positions `at` (d) that converge go on from their end state moved one period down, into the
// next well (eta = 20 has several). With `stops`, a relaxation asked to stop at a certain slip
// (stop_on_slip) then stops as the lateral force model's does, once the site has moved by 3/4 d
// (Termination::interrupted); otherwise, or without `stops`, it converges in that well (a
// converged state with its registry changed). A list of positions rather than a rule over the
// slide's history, so that a slide resumed from a checkpoint, with a new model, meets the same
// minimiser.
struct Overshoot {
  std::vector<double> at;
  bool stops = true;
};

// One relax() call as the protocol made it.
struct RelaxCall {
  double Dx;
  bool stop_on_slip, slip_minimizer, frames;
  Termination termination = Termination::max_iterations;  // how it ended
};

// The Prandtl-Tomlinson contact as a slide::detail::SlideModel.
class TomlinsonModel {
 public:
  using State = slide::SlideFields;
  TomlinsonModel(const Tomlinson1& m, const slide::SlideOptions& o)
      : m_(m), options_(o), problem_(m) {}

  State initial() {
    State s{.Dx = 0.0, .shift = 0, .f = {0.0, 0.0}, .u = {0.0, 0.0}};
    problem_.Dx = s.Dx;
    summarise(s);
    return s;
  }
  // With `pausing` (the slip minimiser's flow) the relaxation may pause for a checkpoint or a
  // stop, and with pausing->from it continues such a pause (its pair replaces s's), as the
  // lateral force model's does: that makes the toy a model the protocol can pause
  // (ProtocolRun::pausable). The heartbeat, if the protocol installed one, is asked at every
  // iteration (the lateral force model: every 16th) and abandons a relaxation when it says so.
  minimize::MinimizeResult relax(State& s, double Dx, std::vector<slide::PathFrame>* frames,
                                 bool stop_on_slip = false,
                                 const minimize::MinimizerOptions* solver = nullptr,
                                 slide::detail::RelaxPausing* pausing = nullptr) {
    calls.push_back({Dx, stop_on_slip,
                     solver != nullptr && solver->method == minimize::Method::flow,
                     frames != nullptr});
    problem_.Dx = Dx;
    s.Dx = Dx;
    problem_.compliance(s.f, s.u);
    // Continuing a pause, the pair is the pause's and this application was counted before it
    // (as the lateral force model does, slider.cpp), so that a resumed slide's count is the
    // uninterrupted one's.
    if (pausing && pausing->from) ++uncounted_gf_;
    const double u_start = s.u[0];
    const bool record = frames != nullptr && options_.path_frame_every > 0;
    int own_interval = options_.path_frame_every;
    int& interval = pausing ? pausing->frame_interval : own_interval;
    if (interval <= 0) interval = options_.path_frame_every;
    bool watch_slip = stop_on_slip;
    minimize::Observer observer = [&](int it, std::span<const double> u, std::span<const double>) {
      if (heartbeat && heartbeat(it)) return true;
      if (record && it % interval == 0) {
        frames->push_back(
            {.iteration = it, .fields = {.Dx = Dx, .shift = 0, .f = {}, .u = {u[0], u[1]}}});
      }
      return watch_slip && std::abs(u[0] - u_start) > 0.75 * m_.d;
    };
    auto r =
        minimize::minimize(problem_, s.u, s.f, solver ? *solver : options_.minimizer, observer,
                           pausing ? pausing->from : nullptr, pausing ? &pausing->pauses : nullptr);
    const bool fast = !(solver != nullptr && solver->method == minimize::Method::flow);
    if (fast && r.termination == Termination::converged &&
        std::find(overshoot.at.begin(), overshoot.at.end(), Dx) != overshoot.at.end()) {
      watch_slip = stop_on_slip && overshoot.stops;
      go_on_one_well_down(s, r, observer);
    }
    calls.back().termination = r.termination;
    summarise(s);
    return r;
  }

  // A fast minimiser that lands in another minimum (docs/solvers.md, path fidelity: L-BFGS
  // extrapolates a loop past its arrest): see Overshoot.
  Overshoot overshoot;
  int overshoots = 0;

  void align(State&, const State&) {}
  // Sites whose registry index changed (of one site: 0 or 1, however far it went).
  int slipped_sites(const State& before, const State& after) const {
    return m_.registry(before.u[0], before.Dx) != m_.registry(after.u[0], after.Dx) ? 1 : 0;
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
  [[nodiscard]] std::size_t gf_applications() const {
    return problem_.gf_applications() - uncounted_gf_;
  }
  [[nodiscard]] Shape2 block_shape() const { return {1, 1}; }
  [[nodiscard]] Shape2 fft_grid() const { return {1, 1}; }

  std::vector<RelaxCall> calls;
  std::function<bool(int)> heartbeat;  // installed by the protocol (progress, stop requests)

 private:
  // Of a state the problem describes (its Dx): Pi = 1/2 f.u + V(u) in the pair representation.
  void summarise(State& s) const {
    s.Fx = s.f[0];
    s.Fz = m_.Fz;
    s.area = m_.d * m_.d;
    std::vector<double> f_int(2);
    s.energy = 0.5 * (s.f[0] * s.u[0] + s.f[1] * s.u[1]) + problem_.interface(s.u, f_int);
  }

  // The fast minimiser's converged relaxation r to s goes on from s moved one period down (the
  // registry index one up), observed as before (heartbeat, frames, and the slip watch as set).
  void go_on_one_well_down(State& s, minimize::MinimizeResult& r,
                           const minimize::Observer& observer) {
    s.f[0] -= m_.k * m_.d;
    problem_.compliance(s.f, s.u);
    const minimize::MinimizeResult more =
        minimize::minimize(problem_, s.u, s.f, options_.minimizer, observer);
    r.termination = more.termination;
    r.iterations += more.iterations;
    r.gf_applications += more.gf_applications;
    r.interface_evaluations += more.interface_evaluations;
    r.filter_applications += more.filter_applications;
    r.energy = more.energy;
    r.max_force = more.max_force;
    ++overshoots;
  }

  Tomlinson1 m_;
  const slide::SlideOptions& options_;
  TomlinsonProblem problem_;
  std::size_t uncounted_gf_ = 0;
};
static_assert(slide::detail::SlideModel<TomlinsonModel>);

slide::SlideOptions tomlinson_options() {
  slide::SlideOptions o;
  o.minimizer.force_tolerance = kForceTolerance;
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
  int overshoots = 0;  // TomlinsonModel::overshoots
};

Slid slide_tomlinson(const Tomlinson1& m, const slide::SlideOptions& o,
                     const slide::SlideControl& control = {}, const Overshoot& overshoot = {}) {
  TomlinsonModel model(m, o);
  model.overshoot = overshoot;
  const slide::detail::ProtocolParams params{
      .d = m.d, .alpha = 1.0, .Fz_continuum = m.Fz, .default_cap = 3.0 * m.d};
  Slid out;
  out.result =
      slide::detail::run_protocol(model, params, o, control, std::chrono::steady_clock::now());
  out.calls = model.calls;
  out.overshoots = model.overshoots;
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
    EXPECT_NEAR(stable.Fx, m.k * u_stable, m.accuracy(u_stable, stable.Dx));
    // Where the flow from the stable state, moved to the slip's Dx, ends: the next well.
    const double u_land = m.flow_end(u_stable, slip.Dx - n * m.d);
    EXPECT_NEAR(slip.Fx, m.k * u_land, m.accuracy(u_land, slip.Dx));
    EXPECT_EQ(m.registry(slip.Fx / m.k, slip.Dx), m.registry(stable.Fx / m.k, stable.Dx) + 1);
    EXPECT_EQ(slip.slipped_sites, 1);  // one site, whose registry changed
    ++n;
  }
  EXPECT_EQ(n, s.result.slip_events);
  ASSERT_GE(n, 2);

  // The smooth maximum before the fold, from below, within the reported precision.
  const double mu_exact = m.A() / m.Fz;
  std::printf("mu %.12f at %.9f d, precision %.3g; A / Fz %.12f\n", s.result.mu, s.result.peak_Dx,
              s.result.peak_precision, mu_exact);
  const double noise = 10.0 * kForceTolerance / m.Fz;  // Pi'' = k at the maximum
  EXPECT_LE(s.result.mu, mu_exact + noise);
  EXPECT_LE(mu_exact - s.result.mu, s.result.peak_precision + noise);
  const double curvature = m.A() * std::pow(2.0 * kPi / m.d, 2);
  EXPECT_LE(s.result.peak_precision, 0.5 * curvature * o.min_step * o.min_step / m.Fz);
  EXPECT_FALSE(s.result.mu_is_lower_bound);
}
INSTANTIATE_TEST_SUITE_P(Eta, ProtocolTomlinsonEta, ::testing::Values(4.0, 20.0));

TEST(ProtocolTomlinson, RecordsPathFramesOnlyOfTheRelaxationThatIsKept) {
  const Tomlinson1 m;
  const Slid s = slide_tomlinson(m, tomlinson_options());
  ASSERT_GE(s.result.slip_events, 2);
  // Only the slip minimiser's relaxations record a path: a step's fast relaxation is undone
  // (a trial of the bisection), or thrown away for the flow if it slips, or shows no path.
  for (const RelaxCall& c : s.calls) {
    EXPECT_TRUE(!c.frames || c.slip_minimizer) << "a fast relaxation to Dx = " << c.Dx << " d";
  }
  // Each slip: the step that closes the bracket, relaxed by the fast minimiser until it slips
  // (without frames), then by the flow from the stable state, with them.
  int handed_over = 0;
  for (std::size_t i = 0; i < s.calls.size(); ++i) {
    if (!s.calls[i].slip_minimizer) continue;
    EXPECT_TRUE(s.calls[i].frames) << "the slip relaxation to Dx = " << s.calls[i].Dx << " d";
    ASSERT_GT(i, 0u);
    const RelaxCall& fast = s.calls[i - 1];
    EXPECT_TRUE(fast.stop_on_slip && !fast.slip_minimizer && fast.Dx == s.calls[i].Dx)
        << "the flow to Dx = " << s.calls[i].Dx << " d follows no fast relaxation of its step";
    handed_over += fast.stop_on_slip && !fast.frames;
  }
  EXPECT_EQ(handed_over, s.result.slip_events);
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

// Pauses and stops. A slide that checkpoints, or is stopped and resumed from its checkpoint, must
// go exactly where the uninterrupted one goes (MODEL.md 5: the path is the result): every trace
// row, mu, the slips and the frames handed over, bit for bit. The flow relaxing a slip is paused
// rather than abandoned (SlideState::pending: its pair, velocity, step and path so far), the
// other relaxations are abandoned and made again; both are exercised here, on the model whose
// slips the tests above check against the closed forms (test::expect_same_result).

// A slide of the pause-and-stop tests: the model, its settings and the fast minimiser's
// overshoots.
struct PauseCase {
  std::string name;
  Tomlinson1 m;
  slide::SlideOptions o;
  Overshoot overshoot;
};

// What the stopped or checkpointed slides paused in: a flow after the fast minimiser saw the step
// slip, or a flow taken first in creep (no fast result).
struct PauseKinds {
  int after_fast = 0, flow_first = 0, elsewhere = 0;
  void count(const slide::SlideState& st) {
    (!st.pending ? elsewhere : st.pending->fast ? after_fast : flow_first) += 1;
  }
};

// How often the slide asks whether to stop (between steps, and through the heartbeat in its
// relaxations), and that asking changes nothing (`plain`: the slide without the asking).
int count_polls(const PauseCase& c, const slide::SlideResult& plain) {
  int polls = 0;
  slide::SlideControl counting;
  counting.stop_requested = [&] {
    ++polls;
    return false;
  };
  test::expect_same_result(plain, slide_tomlinson(c.m, c.o, counting, c.overshoot).result,
                           c.name + ", polled");
  return polls;
}

// Checkpoints at every chance: between steps, and after every accepted step of each slip's flow
// (which pauses for it and goes on). Taking them changes nothing, and the slide resumed from each
// (every k-th, so that about 60 to 120 are) is the same slide.
PauseKinds check_resumed_from_checkpoints(const PauseCase& c) {
  const Slid plain = slide_tomlinson(c.m, c.o, {}, c.overshoot);
  EXPECT_GE(plain.result.slip_events, 2) << c.name;
  std::vector<slide::SlideState> saved;
  slide::SlideControl control;
  control.checkpoint = [&](const slide::SlideState& st) { saved.push_back(st); };
  control.checkpoint_every_s = 1e-12;
  test::expect_same_result(plain.result, slide_tomlinson(c.m, c.o, control, c.overshoot).result,
                           c.name + ", checkpointed");
  PauseKinds taken, resumed;
  for (const auto& st : saved)
    taken.count(st);
  std::printf(
      "%s: %zu checkpoints, %d inside a flow after the fast minimiser, %d inside a flow "
      "taken first\n",
      c.name.c_str(), saved.size(), taken.after_fast, taken.flow_first);
  const std::size_t stride = std::max<std::size_t>(1, saved.size() / 60);
  for (std::size_t k = 0; k < saved.size(); k += stride) {
    slide::SlideControl r;
    r.start = &saved[k];
    resumed.count(saved[k]);
    test::expect_same_result(plain.result, slide_tomlinson(c.m, c.o, r, c.overshoot).result,
                             c.name + ", resumed from checkpoint " + std::to_string(k) +
                                 (saved[k].pending ? " (paused in a flow)" : ""));
  }
  EXPECT_GT(resumed.elsewhere, 0) << c.name;
  return resumed;
}

// The slide (from `start`, if given) stopped at the n-th time it asks whether to stop, and the
// state its stop handed over (none if it ended first).
struct Stopped {
  Slid slid;
  std::optional<slide::SlideState> state;
};
Stopped stop_at_poll(const PauseCase& c, int n, const slide::SlideState* start = nullptr) {
  int asked = 0;
  Stopped out;
  slide::SlideControl control;
  control.stop_requested = [&] { return ++asked == n; };
  control.checkpoint = [&](const slide::SlideState& st) { out.state = st; };
  control.checkpoint_every_s = 1e6;  // only the stop's
  control.start = start;
  out.slid = slide_tomlinson(c.m, c.o, control, c.overshoot);
  return out;
}

// Stopped at the n-th time the slide asks whether to stop (between steps, and through the
// heartbeat in its relaxations), for n = 1, 1 + s, 1 + 2 s, ... up to the last poll (s: the
// stride that makes about max_stops stops), and resumed from the stop's checkpoint: the same
// slide. Every poll can stop it (the first relaxation, which cannot, asks none). Returns where
// the stops paused.
PauseKinds check_stopped_anywhere(const PauseCase& c, int max_stops) {
  const Slid plain = slide_tomlinson(c.m, c.o, {}, c.overshoot);
  const int polls = count_polls(c, plain.result);
  EXPECT_GT(polls, 20) << c.name;

  PauseKinds stops;
  int not_stopped = 0;
  for (int n = 1; n <= polls; n += std::max(1, polls / max_stops)) {
    const auto [stopped, last] = stop_at_poll(c, n);
    if (!stopped.result.interrupted) {
      ++not_stopped;
      continue;
    }
    EXPECT_TRUE(last) << c.name << ": a stop without a checkpoint, at poll " << n;
    if (!last) continue;
    stops.count(*last);
    slide::SlideControl r;
    r.start = &*last;
    test::expect_same_result(plain.result, slide_tomlinson(c.m, c.o, r, c.overshoot).result,
                             c.name + ", stopped at poll " + std::to_string(n) +
                                 (last->pending ? " (inside a slip's flow)" : ""));
  }
  std::printf(
      "%s: %d polls; stopped %d times inside a flow after the fast minimiser, %d inside "
      "a flow taken first, %d elsewhere\n",
      c.name.c_str(), polls, stops.after_fast, stops.flow_first, stops.elsewhere);
  EXPECT_GT(stops.elsewhere, 0) << c.name;
  EXPECT_EQ(not_stopped, 0) << c.name << ": stop requests the slide did not act on";
  return stops;
}

// Stopped again and again: each session resumes from the last one's stop and is stopped at its
// k-th poll, until the slide ends. A stop can then fall into a flow that an earlier stop paused
// (re-paused; a single stop does not reach that). The end is the uninterrupted slide, rows and
// costs. A session makes progress only if it outlasts the relaxation it resumes in when that is
// abandoned rather than paused (docs/reliability.md), so the chain is bounded by four times the
// sessions a chain without that would take.
struct Chain {
  int sessions = 0;
  int repaused = 0, repaused_flow_first = 0;  // stops inside a flow the session had resumed
};
Chain check_stopped_in_a_chain(const PauseCase& c, int k) {
  const Slid plain = slide_tomlinson(c.m, c.o, {}, c.overshoot);
  const int polls = count_polls(c, plain.result);
  const int max_sessions = 4 * (polls / k + 1);
  const std::string what = c.name + ", sessions of " + std::to_string(k) + " polls";
  Chain chain;
  std::optional<slide::SlideState> from;
  for (chain.sessions = 1; chain.sessions <= max_sessions; ++chain.sessions) {
    auto [s, last] = stop_at_poll(c, k, from ? &*from : nullptr);
    if (!s.result.interrupted) {
      test::expect_same_result(plain.result, s.result, what);
      return chain;
    }
    if (!last) {
      ADD_FAILURE() << what << ": a stop without a checkpoint in session " << chain.sessions;
      return chain;
    }
    if (from && from->pending && last->pending && last->pending->Dx == from->pending->Dx) {
      ++chain.repaused;
      chain.repaused_flow_first += !last->pending->fast.has_value();
    }
    from = std::move(last);
  }
  ADD_FAILURE() << what << ": not finished after " << max_sessions << " sessions";
  return chain;
}

PauseCase default_case() {
  return {.name = "eta = 4", .m = {}, .o = tomlinson_options()};
}

TEST(ProtocolTomlinson, ResumesFromEveryKindOfCheckpointToTheSameSlide) {
  const PauseKinds k = check_resumed_from_checkpoints(default_case());
  EXPECT_GT(k.after_fast, 0);
}

TEST(ProtocolTomlinson, StoppedAnywhereAndResumedItIsTheSameSlide) {
  const PauseKinds k = check_stopped_anywhere(default_case(), 50);
  EXPECT_GT(k.after_fast, 0);
}

// Creep on the site: eta = 20 (several wells), step growth 2 (the step after a slip is min_step
// wide), five slips; flow_first_after = 1 makes every step after a slip creep's.
slide::SlideOptions creep_options(const Tomlinson1& m, int flow_first_after) {
  slide::SlideOptions o = tomlinson_options();
  o.step_growth = 2.0;
  o.slips_to_stop = 5;
  o.max_distance = m.Dx_fold() + 6.0 * m.d;
  o.flow_first_after = flow_first_after;
  o.validate();
  return o;
}

// The tip positions of the steps that follow a slip.
std::vector<double> steps_after_slips(const slide::SlideResult& r) {
  std::vector<double> Dx;
  for (std::size_t i = 1; i < r.trace.size(); ++i)
    if (r.trace[i - 1].slip) Dx.push_back(r.trace[i].Dx);
  return Dx;
}

// Creep: the flow first (SlideOptions::flow_first_after; protocol.hpp, take_fast_after_flow).
// After flow_first_after slips in a row the next step, min_step wide, goes to the flow first; if
// the flow finds it stable, the fast minimiser relaxes it as it would have without
// flow_first_after, and where the fast minimiser then calls it a slip, the flow's stable state
// stands (MODEL.md 5: the flow says where the state goes). In the slides of the suite the fast
// minimiser never disagreed with a stable flow (83 such steps, docs/solvers.md), so here it is
// made to (Overshoot): at the step after each slip, where the flow finds the site deep in the
// well it slipped into, the fast minimiser lands one well down, stopping there as at a certain
// slip (`stops`, as the lateral force model's trial does at 3/4 d) or converging there. With
// creep_options():
// - Without flow_first_after, the overshooting fast minimiser's slip goes to the flow, which
//   finds the step stable: every row has the slip flag, Dx and registry of the slide without the
//   overshoot, and its Fx within the minimisers' accuracy (the header's 10 k tol / Pi'').
// - With it, the flow goes first, the fast minimiser overshoots after it, and the slide is the
//   one without flow_first_after bit for bit (rows, mu, frames), with the same relaxations (the
//   flow's and the fast one, swapped) and costs.
// - With it and without the overshoot (stable by both), the slide is the plain one bit for bit.
void check_flow_overrules_an_overshoot(bool stops) {
  const Tomlinson1 m{.eta = 20.0};
  const slide::SlideOptions never = creep_options(m, 0), first = creep_options(m, 1);
  const Slid plain = slide_tomlinson(m, never);
  const Overshoot overshoot{.at = steps_after_slips(plain.result), .stops = stops};
  const Slid over = slide_tomlinson(m, never, {}, overshoot);
  const Slid over_first = slide_tomlinson(m, first, {}, overshoot);
  const Slid plain_first = slide_tomlinson(m, first);
  ASSERT_GE(plain.result.slip_events, 5);
  ASSERT_FALSE(over.result.failed) << over.result.stop_reason;
  ASSERT_FALSE(over_first.result.failed) << over_first.result.stop_reason;

  // The fast minimiser overshot once at each step after a slip, ending as asked, and each time
  // the flow relaxed that step again and found it stable.
  const auto& rows = plain.result.trace;
  EXPECT_EQ(over.overshoots, static_cast<int>(overshoot.at.size()));
  const Termination landed = stops ? Termination::interrupted : Termination::converged;
  int fast_landed = 0, flows_of_stable_steps = 0;
  for (const RelaxCall& c : over.calls) {
    const bool listed =
        std::find(overshoot.at.begin(), overshoot.at.end(), c.Dx) != overshoot.at.end();
    fast_landed += listed && !c.slip_minimizer && c.stop_on_slip && c.termination == landed;
    if (!c.slip_minimizer) continue;
    const auto row = std::find_if(rows.begin(), rows.end(),
                                  [&](const slide::TraceRow& t) { return t.Dx == c.Dx; });
    flows_of_stable_steps += row != rows.end() && !row->slip;
  }
  EXPECT_EQ(fast_landed, over.overshoots);
  EXPECT_EQ(flows_of_stable_steps, over.overshoots);
  EXPECT_EQ(over.result.slip_relaxations, plain.result.slip_relaxations + over.overshoots);

  // The overshoot changed no verdict: the same rows, each state within the accuracy of the
  // plain slide's (the flow's end state against the fast minimiser's, in the same well).
  ASSERT_EQ(over.result.trace.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto &a = rows[i], &b = over.result.trace[i];
    EXPECT_EQ(b.Dx, a.Dx) << "row " << i;
    EXPECT_EQ(b.slip, a.slip) << "row " << i << " at Dx " << a.Dx;
    EXPECT_EQ(b.slipped_sites, a.slipped_sites) << "row " << i;
    EXPECT_EQ(m.registry(b.Fx / m.k, b.Dx), m.registry(a.Fx / m.k, a.Dx)) << "row " << i;
    EXPECT_NEAR(b.Fx, a.Fx, 2.0 * m.accuracy(a.Fx / m.k, a.Dx)) << "row " << i;
  }
  EXPECT_EQ(over.result.slip_events, plain.result.slip_events);

  // The flow first: its stable verdict stands, and the slide is the one without it.
  EXPECT_EQ(over_first.overshoots, over.overshoots);
  EXPECT_EQ(over_first.result.flow_first_steps, over.overshoots);
  EXPECT_EQ(over_first.result.flow_first_stable, over_first.result.flow_first_steps);
  test::expect_same_path(over.result, over_first.result,
                         "flow first, the fast minimiser overshooting");
  EXPECT_EQ(over_first.result.minimizations, over.result.minimizations);
  EXPECT_EQ(over_first.result.slip_relaxations, over.result.slip_relaxations);
  EXPECT_EQ(over_first.result.gf_applications, over.result.gf_applications);
  EXPECT_EQ(over_first.result.iterations, over.result.iterations);
  // At each such step: the flow, then the fast minimiser (asked to stop at a certain slip).
  int flow_then_fast = 0;
  for (std::size_t i = 0; i + 1 < over_first.calls.size(); ++i) {
    const RelaxCall &a = over_first.calls[i], &b = over_first.calls[i + 1];
    flow_then_fast += a.slip_minimizer && !b.slip_minimizer && a.Dx == b.Dx && b.stop_on_slip &&
                      b.termination == landed;
  }
  EXPECT_EQ(flow_then_fast, over.overshoots);

  // Stable by both: one relaxation more each time, the same slide.
  EXPECT_EQ(plain_first.result.flow_first_stable, plain_first.result.flow_first_steps);
  EXPECT_GT(plain_first.result.flow_first_steps, 0);
  test::expect_same_path(plain.result, plain_first.result, "flow first, stable by both");
  EXPECT_EQ(plain_first.result.minimizations,
            plain.result.minimizations + plain_first.result.flow_first_steps);
  std::printf(
      "eta = 20, the fast minimiser %s: %d slips; it overshot %d times; flow first at %d steps "
      "(%d stable); GF applications: plain %zu, overshooting %zu, and with the flow first %zu\n",
      stops ? "stopping at the slip" : "converging", plain.result.slip_events, over.overshoots,
      over_first.result.flow_first_steps, over_first.result.flow_first_stable,
      plain.result.gf_applications, over.result.gf_applications, over_first.result.gf_applications);
}

TEST(ProtocolTomlinson, InCreepTheFlowsStableVerdictStandsWhereTheFastMinimiserStopsAtASlip) {
  check_flow_overrules_an_overshoot(true);
}

TEST(ProtocolTomlinson, InCreepTheFlowsStableVerdictStandsWhereTheFastMinimiserLandsElsewhere) {
  check_flow_overrules_an_overshoot(false);
}

// The pauses and stops of creep: a flow taken first, paused for a checkpoint or a stop, holds no
// fast result and is resumed as a flow-first step; the fast relaxation after a stable flow asks
// for no stop (it is not abandoned), so a stop falls at the next step; and the overshooting fast
// minimiser is overruled by the flow's stable verdict after each pause too.
PauseCase creep_case() {
  const Tomlinson1 m{.eta = 20.0};
  return {.name = "creep, eta = 20",
          .m = m,
          .o = creep_options(m, 1),
          .overshoot = {.at = steps_after_slips(slide_tomlinson(m, creep_options(m, 0)).result)}};
}

TEST(ProtocolTomlinson, InCreepResumesFromEveryKindOfCheckpointToTheSameSlide) {
  const PauseKinds k = check_resumed_from_checkpoints(creep_case());
  EXPECT_GT(k.after_fast, 0);
  EXPECT_GT(k.flow_first, 0);
}

TEST(ProtocolTomlinson, InCreepStoppedAnywhereAndResumedItIsTheSameSlide) {
  const PauseKinds k = check_stopped_anywhere(creep_case(), 400);
  EXPECT_GT(k.after_fast, 0);
  EXPECT_GT(k.flow_first, 0);
}

TEST(ProtocolTomlinson, InCreepStoppedAgainAndAgainItIsTheSameSlide) {
  int repaused = 0, repaused_flow_first = 0;
  for (int k : {13, 21, 34, 55, 89}) {
    const Chain chain = check_stopped_in_a_chain(creep_case(), k);
    repaused += chain.repaused;
    repaused_flow_first += chain.repaused_flow_first;
    std::printf(
        "sessions of %d polls: %d sessions, %d stops inside a flow the session resumed (%d "
        "taken first)\n",
        k, chain.sessions, chain.repaused, chain.repaused_flow_first);
  }
  EXPECT_GT(repaused, 0);
  EXPECT_GT(repaused_flow_first, 0);
}

}  // namespace
