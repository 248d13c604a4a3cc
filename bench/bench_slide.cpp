// Whole slides of the lateral force model on the default scene (a = 43 d, R = 535 d,
// alpha = 0.7): the default settings against the classic reference protocol (fixed 0.01 d
// steps, Polak-Ribiere CG preconditioned with G, force tolerance 1e-6), with the error of mu
// against a converged reference (adaptive protocol, tolerance 1e-8, min_step 1e-4), the wall
// time and the GF applications. Prints a Markdown table; bench/run_slide.sh records it.
//
//   bench_slide [threads] [a] [R]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "slide/slider.hpp"

using namespace asperity;

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  interface::ContactScene scene {};
  if (argc > 2) scene.a = std::atof(argv[2]);
  if (argc > 3) scene.R = std::atof(argv[3]);

  struct Case {
    std::string name;
    slide::SlideOptions options;
  };
  const auto with = [&](slide::SlideOptions o) {
    o.fft.threads = threads;
    return o;
  };
  slide::SlideOptions converged = with({});
  converged.min_step = 1e-4;
  converged.minimizer.force_tolerance = 1e-8;
  std::vector<Case> cases;
  cases.push_back({"default (adaptive, lbfgs, 1e-6)", with({})});
  {
    auto o = with({});
    o.minimizer.stability = minimize::StabilityCheck::none;
    cases.push_back({"adaptive, lbfgs, no stability check", o});
  }
  {
    auto o = with({});
    o.min_step = 1e-2;
    cases.push_back({"adaptive, min_step 0.01", o});
  }
  for (double p : {1e-3, 1e-4}) {
    auto o = with({});
    o.minimizer.perturbation = p;
    char name[64];
    std::snprintf(name, sizeof name, "adaptive, stability push %g d", p);
    cases.push_back({name, o});
  }
  {
    auto o = with({});
    o.minimizer.force_tolerance = 1e-5;
    o.min_step = 1e-2;
    cases.push_back({"adaptive, tolerance 1e-5, min_step 0.01", o});
  }
  {
    auto o = with({});
    o.minimizer.method = minimize::Method::newton;
    cases.push_back({"adaptive, newton finish", o});
  }
  {
    auto o = with({});
    o.minimizer.method = minimize::Method::cg;
    cases.push_back({"adaptive, cg", o});
  }
  {
    auto o = with({});
    o.minimizer.method = minimize::Method::fire;
    cases.push_back({"adaptive, fire", o});
  }
  {
    auto o = with({.protocol = slide::Protocol::reference});
    cases.push_back({"reference protocol 0.01 d, lbfgs", o});
  }
  {
    auto o = with({.protocol = slide::Protocol::reference});
    o.minimizer.method = minimize::Method::cg;
    cases.push_back({"classic: reference protocol 0.01 d, cg", o});
  }

  const auto ref = slide::slide(scene, converged);
  std::printf(
      "a = %g d, R = %g d, alpha = %g: a/b_core^0 = %.3g; converged mu/alpha = %.7f "
      "(adaptive, tolerance 1e-8, min_step 1e-4: %.1f s); threads %d\n\n",
      scene.a, scene.R, scene.alpha, scene.a_over_bcore0(), ref.mu_over_alpha, ref.wall_s, threads);
  std::printf(
      "| settings | mu/alpha | error | wall (s) | GF applications | gradient evaluations | "
      "steps | slips |\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& c : cases) {
    const auto r = slide::slide(scene, c.options);
    std::printf("| %s | %.6f | %.1e | %.2f | %zu | %zu | %d | %d%s |\n", c.name.c_str(),
                r.mu_over_alpha, std::abs(r.mu / ref.mu - 1.0), r.wall_s, r.gf_applications,
                r.gradient_evaluations, r.steps, r.slip_events, r.failed ? " (failed)" : "");
  }
  return 0;
}
