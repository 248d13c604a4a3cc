// Path tier (MODEL.md 5, core/slide/path.hpp): a bracketed instability of a slide is relaxed from
// one and the same stable state by the reference path, the overdamped flow du/dt = -G r, and by
// the solvers the slides use; each must end in the flow's minimum: the same registry index on
// every contact site and |dFx|/Fx <= 1e-4 (the slide's force tolerance, 1e-5 G d^2 per site,
// moves Fx by about 1e-6 relative).
//
// What each case asserts:
// - the flow's step control: halving its tolerance leaves the end state in the same minimum
//   (not in the crossover case, whose halving and FIRE are in bench/run_path_tier.sh's table);
// - the fold: the trial step that the slide's solver (L-BFGS, the default) called a slip is a
//   slip for the flow too;
// - the path-faithful solvers (`faithful` below), which are what the tools relax slips with,
//   end in the flow's minimum.
// And the slides as the tools run them (PathTierSlides): every step solver the tools offer
// (lbfgs with either preconditioner, cg, newton), with the slips relaxed by the flow in the
// interface filter's metric, follows the reference slide, whose every step is the flow in the
// G metric without warm starts, through slip N: the same bracket, the same stable state before
// it and the same minimum after it. lbfgs, cg and newton alone carry loops past the flow's arrest
// near the II/III crossover (issue 21; bench/run_path_tier.sh): the tools do not offer them for
// slips (apps/common/slide_io.cpp, check_slip_relaxation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "asperity/core/slide/path.hpp"

using namespace asperity;

namespace {

struct Case {
  const char* name;
  double a, R;
  int event;         // slip event of the default slide to check
  bool full = true;  // also the flow at half its tolerance, and FIRE (the default suite's
                     // crossover case leaves them to the other cases and to bench/: under the
                     // sanitizers it took nine minutes)
};
// Test names, not bytes, in CTest's listing.
[[maybe_unused]] void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

minimize::MinimizerOptions solver(minimize::Method method, minimize::Preconditioner p) {
  minimize::MinimizerOptions m = slide::slide_minimizer_defaults();
  m.method = method;
  m.preconditioner = p;
  m.max_iterations = 2'000'000;
  return m;
}

using M = minimize::Method;
using P = minimize::Preconditioner;

void print(const slide::PathCheck& c) {
  const auto line = [](const std::string& name, const slide::StepRelaxation& s,
                       const slide::StateComparison* cmp) {
    std::printf("  %-16s %8d iterations %9zu GF %9zu filter  %6d slipped", name.c_str(),
                s.result.iterations, s.result.gf_applications, s.result.filter_applications,
                s.slipped_sites);
    if (cmp) {
      std::printf("  %5d registry differences  |dFx|/Fx %.2e", cmp->registry_differences,
                  cmp->relative_Fx);
    }
    std::printf("\n");
  };
  std::printf("  slip %d: stable at Dx = %.6f d, slips at %.6f d\n", c.instability.event,
              c.instability.stable.Dx, c.instability.slip_Dx);
  line("flow/elastic", c.flow, nullptr);
  if (c.flow_half.result.iterations > 0) line("flow tol/2", c.flow_half, &c.flow_self);
  for (const auto& r : c.rows)
    line(r.solver, r.step, &r.against_flow);
}

void check(const Case& k, std::vector<minimize::MinimizerOptions> solvers, bool expect_same) {
  if (!k.full) std::erase_if(solvers, [](const auto& m) { return m.method == M::fire; });
  const interface::ContactScene scene { .a = k.a, .R = k.R };
  std::printf("%s: a = %g d, R = %g d, a/b_core^0 = %.1f\n", k.name, k.a, k.R,
              scene.a_over_bcore0());
  const slide::SlideOptions options;
  const auto at = slide::bracket_slip(scene, options, k.event);
  const auto c = slide::check_path(scene, options, at, solvers, 2'000'000, k.full);
  print(c);
  ASSERT_EQ(c.flow.result.termination, Termination::converged);
  if (k.full) {
    ASSERT_EQ(c.flow_half.result.termination, Termination::converged);
    EXPECT_TRUE(c.flow_self.same_minimum()) << "the flow's end state depends on its tolerance";
  }
  EXPECT_GT(c.flow.slipped_sites, 0) << "the default solver slipped where the flow does not";
  for (const auto& r : c.rows) {
    EXPECT_EQ(r.step.result.termination, Termination::converged) << r.solver;
    if (expect_same) {
      EXPECT_TRUE(r.against_flow.same_minimum())
          << r.solver << ": " << r.against_flow.registry_differences
          << " sites in another well than the flow's, |dFx|/Fx = " << r.against_flow.relative_Fx;
    }
  }
}

// The path-faithful solvers: the flow in the interface filter's metric (the slide's
// slip_minimizer) and FIRE.
const std::vector<minimize::MinimizerOptions> faithful{solver(M::flow, P::interface),
                                                       solver(M::fire, P::elastic)};
// The step solvers the tools offer (solver.method; each with the flow relaxing its slips).
const std::vector<minimize::MinimizerOptions> step_solvers{
    solver(M::lbfgs, P::automatic), solver(M::lbfgs, P::elastic), solver(M::cg, P::elastic),
    solver(M::newton, P::automatic)};

// The states of the tier; crossover_full: the crossover case with its halving and FIRE too.
std::vector<Case> cases(bool crossover_full) {
  return {Case{"RegimeII_a43_R535", 43.0, 535.0, 1}, Case{"RegimeIII_a28_R40_first", 28.0, 40.0, 1},
          Case{"RegimeIII_a28_R40_third", 28.0, 40.0, 3},
          Case{"Crossover_a46_R100", 46.0, 100.0, 1, crossover_full}};
}

std::string case_name(const ::testing::TestParamInfo<Case>& p) {
  return p.param.name;
}

}  // namespace

class PathTier : public ::testing::TestWithParam<Case> {};

TEST_P(PathTier, FaithfulSolversEndInTheFlowsMinimum) {
  check(GetParam(), faithful, true);
}

INSTANTIATE_TEST_SUITE_P(Cases, PathTier, ::testing::ValuesIn(cases(false)), case_name);

// A slide as the tools run it: `step` for the steps, the flow in the interface filter's metric
// for the slips (solver.slip_method = "flow").
slide::SlideOptions tool_slide(const minimize::MinimizerOptions& step) {
  slide::SlideOptions o;
  o.minimizer = step;
  o.minimizer.max_iterations = slide::slide_minimizer_defaults().max_iterations;
  o.slip_minimizer = slide::slip_minimizer_from(o.minimizer, M::flow, P::interface);
  return o;
}

// The reference slide: every step relaxed by the flow in the G metric, from the state moved to
// the new Dx (no extrapolated warm start), so that the stable states, the folds and the minima
// after the slips are the reference path's own.
slide::SlideOptions reference_slide() {
  slide::SlideOptions o;
  o.minimizer = solver(M::flow, P::elastic);
  o.extrapolate = false;
  return o;
}

void check_slides(const Case& k, const std::vector<minimize::MinimizerOptions>& steps) {
  const interface::ContactScene scene { .a = k.a, .R = k.R };
  std::printf("%s: a = %g d, R = %g d, slip %d\n", k.name, k.a, k.R, k.event);
  const auto ref = slide::bracket_slip(scene, reference_slide(), k.event);
  const auto ref_after = slide::relax_step(scene, reference_slide(), ref.stable, ref.slip_Dx);
  std::printf("  %-16s stable at Dx = %.6f d, slips at %.6f d: %6d slipped, %9zu GF\n", "reference",
              ref.stable.Dx, ref.slip_Dx, ref_after.slipped_sites, ref.slide.gf_applications);
  ASSERT_EQ(ref_after.result.termination, Termination::converged);
  ASSERT_GT(ref_after.slipped_sites, 0);
  for (const auto& step : steps) {
    const std::string name = slide::solver_label(step);
    const auto options = tool_slide(step);
    const auto at = slide::bracket_slip(scene, options, k.event);
    // The fold where the reference's is: the bisection visits the same trial positions, so the
    // brackets are equal to the bit when the verdicts agree.
    EXPECT_EQ(at.stable.Dx, ref.stable.Dx) << name;
    EXPECT_EQ(at.slip_Dx, ref.slip_Dx) << name;
    if (at.stable.Dx != ref.stable.Dx || at.slip_Dx != ref.slip_Dx) continue;
    const auto before = slide::compare_states(scene, at.stable, ref.stable);
    // The slide's own relaxation of the slipping step: its slip minimiser from its state.
    slide::SlideOptions slip = options;
    slip.minimizer = *options.slip_minimizer;
    const auto after = slide::relax_step(scene, slip, at.stable, at.slip_Dx);
    const auto against = slide::compare_states(scene, after.state, ref_after.state);
    std::printf(
        "  %-16s before: %5d registry differences |dFx|/Fx %.2e; after: %6d slipped, %5d "
        "registry differences |dFx|/Fx %.2e; %9zu GF\n",
        name.c_str(), before.registry_differences, before.relative_Fx, after.slipped_sites,
        against.registry_differences, against.relative_Fx, at.slide.gf_applications);
    EXPECT_TRUE(before.same_minimum())
        << name << ": the stable state before the slip is another minimum than the reference's ("
        << before.registry_differences << " sites, |dFx|/Fx = " << before.relative_Fx << ")";
    EXPECT_EQ(after.result.termination, Termination::converged) << name;
    EXPECT_GT(after.slipped_sites, 0) << name << ": the slide's slip minimiser found no slip";
    EXPECT_TRUE(against.same_minimum())
        << name << ": after the slip, " << against.registry_differences
        << " sites in another well than the reference's, |dFx|/Fx = " << against.relative_Fx;
  }
}

// The default suite: the default step solver on the Regime II and first Regime III states (about
// a minute); every step solver on every state under `slow`.
class PathTierSlides : public ::testing::TestWithParam<Case> {};

TEST_P(PathTierSlides, ToolSlidesFollowTheReferenceSlide) {
  check_slides(GetParam(), {step_solvers.front()});
}

INSTANTIATE_TEST_SUITE_P(Cases, PathTierSlides, ::testing::Values(cases(false)[0], cases(false)[1]),
                         case_name);

class PathTierSlidesAllSolvers : public ::testing::TestWithParam<Case> {};

TEST_P(PathTierSlidesAllSolvers, ToolSlidesFollowTheReferenceSlide) {
  check_slides(GetParam(), step_solvers);
}

INSTANTIATE_TEST_SUITE_P(Cases, PathTierSlidesAllSolvers, ::testing::ValuesIn(cases(true)),
                         case_name);

// SlideOptions::slip_minimizer in a slide: the first slip the slide accepts ends where the slip
// minimiser, relaxing the same bracketed step on its own, ends (the protocol takes its end state,
// not the default solver's, which differs here by 20 sites: Regime III, a = 28 d, R = 40 d).
TEST(SlipMinimizer, TheSlideTakesTheFaithfulEndState) {
  const interface::ContactScene scene { .a = 28.0, .R = 40.0 };
  slide::SlideOptions options;
  options.slip_minimizer = solver(M::flow, P::interface);
  int slips = 0;
  slide::SlideControl control;
  control.progress = [&](const slide::SlideProgressInfo& p) { slips = p.slip_events; };
  control.stop_requested = [&] { return slips >= 1; };
  const auto r = slide::slide(scene, options, control);
  ASSERT_GE(r.slip_events, 1);
  EXPECT_GE(r.slip_relaxations, 1);
  const slide::Snapshot* after = nullptr;
  for (const auto& s : r.snapshots) {
    if (s.label == "slip_001_after") after = &s;
  }
  ASSERT_NE(after, nullptr);
  // The same bracket, found by the default solver's bisection, relaxed by the slip minimiser.
  const auto at = slide::bracket_slip(scene, slide::SlideOptions{}, 1);
  ASSERT_DOUBLE_EQ(at.slip_Dx, after->Dx);
  slide::SlideOptions faithful;
  faithful.minimizer = *options.slip_minimizer;
  const auto alone = slide::relax_step(scene, faithful, at.stable, at.slip_Dx);
  slide::SlideFields in_slide = alone.state;
  std::copy(after->ux.begin(), after->ux.end(), in_slide.u.begin());
  std::copy(after->uy.begin(), after->uy.end(),
            in_slide.u.begin() + static_cast<std::ptrdiff_t>(after->ux.size()));
  in_slide.Fx = after->Fx;
  const auto c = slide::compare_states(scene, in_slide, alone.state);
  EXPECT_EQ(c.registry_differences, 0);
  EXPECT_LE(c.relative_Fx, 1e-9);
  // And the default solver's own end state is another minimum: the test can tell them apart.
  const auto fast = slide::relax_step(scene, slide::SlideOptions{}, at.stable, at.slip_Dx);
  EXPECT_GT(slide::compare_states(scene, fast.state, alone.state).registry_differences, 0);
  // The default solver hands the step to the slip minimiser as soon as it sees the slip for
  // certain (a site moved by 3/4 d), instead of relaxing the slip to its own end first: the slip
  // row's iterations are the flow's and fewer than the default solver's whole relaxation.
  const auto row =
      std::find_if(r.trace.begin(), r.trace.end(), [](const slide::TraceRow& t) { return t.slip; });
  ASSERT_NE(row, r.trace.end());
  const int before_flow = row->iterations - alone.result.iterations;
  std::printf("slip row: %d iterations, the flow's %d, the default solver's whole relaxation %d\n",
              row->iterations, alone.result.iterations, fast.result.iterations);
  EXPECT_GT(before_flow, 0);
  EXPECT_LT(before_flow, fast.result.iterations / 2);
}

// path_check --flow-profile (slide::FlowProfile): one sample after every accepted step of each
// flow, with the counts so far, and watching does not change the relaxation (the same bits).
// The state: slip 3 of a = 28 d, R = 40 d (Regime III) with the library's default scene and
// slide (docs/solvers.md profiles the same slip of path_check's default scene).
TEST(FlowProfile, SamplesEveryAcceptedStepAndChangesNothing) {
  const interface::ContactScene scene { .a = 28.0, .R = 40.0 };
  const slide::SlideOptions options;
  const auto at = slide::bracket_slip(scene, options, 3);
  const std::vector<minimize::MinimizerOptions> flows{solver(M::flow, P::interface)};
  const auto plain = slide::check_path(scene, options, at, flows, 2'000'000, false, false);
  const auto watched = slide::check_path(scene, options, at, flows, 2'000'000, false, true);
  EXPECT_TRUE(plain.flow_profile.empty());
  EXPECT_TRUE(plain.rows.at(0).profile.empty());
  EXPECT_EQ(watched.flow.state.Fx, plain.flow.state.Fx);
  EXPECT_EQ(watched.flow.result.iterations, plain.flow.result.iterations);
  EXPECT_EQ(watched.rows.at(0).step.state.Fx, plain.rows.at(0).step.state.Fx);
  EXPECT_EQ(watched.rows.at(0).step.result.gf_applications,
            plain.rows.at(0).step.result.gf_applications);

  const auto check = [&](const slide::FlowProfile& p, const slide::StepRelaxation& s,
                         bool filtered) {
    ASSERT_EQ(s.result.termination, Termination::converged);
    // One sample per accepted step; the stability check's push and relaxation at the end
    // (solver.stability = perturb, when negative curvature is left) makes steps it does not see.
    const auto accepted = static_cast<std::size_t>(s.result.iterations - s.result.rejected_steps);
    if (s.result.stability_checked) {
      EXPECT_LT(p.size(), accepted);
      EXPECT_LT(p.back().gf, s.result.gf_applications);
    } else {
      EXPECT_EQ(p.size(), accepted);
      // The relaxation's count also holds bringing the state to Dx and the end's u = G f.
      EXPECT_LE(p.back().gf, s.result.gf_applications);
      EXPECT_GE(p.back().gf + 4, s.result.gf_applications);
    }
    for (std::size_t k = 1; k < p.size(); ++k) {
      EXPECT_GT(p[k].iteration, p[k - 1].iteration);
      EXPECT_GT(p[k].gf, p[k - 1].gf);  // every step applies the mobility at least once
      EXPECT_GT(p[k].step, 0.0);
    }
    EXPECT_EQ(p.back().filter > 0, filtered);
    // The last sample is the converged state (before the check): its residual is within the
    // force tolerance, and the slip's residual was far above it on the way (G metric: P r = r).
    std::printf("  %s: %zu samples, %d iterations, %d rejected, stability checked: %d\n",
                filtered ? "flow/interface" : "flow/elastic", p.size(), s.result.iterations,
                s.result.rejected_steps, s.result.stability_checked ? 1 : 0);
    if (!filtered) {
      EXPECT_LE(p.back().max_residual, options.minimizer.force_tolerance);
      const auto peak = std::max_element(p.begin(), p.end(), [](const auto& a, const auto& b) {
        return a.max_residual < b.max_residual;
      });
      EXPECT_GT(peak->max_residual, 1e3 * options.minimizer.force_tolerance);
    }
  };
  check(watched.flow_profile, watched.flow, false);
  check(watched.rows.at(0).profile, watched.rows.at(0).step, true);
}
