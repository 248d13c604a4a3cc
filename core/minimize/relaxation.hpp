// The plug-in point of the minimisers of minimizer.hpp (internal to core/minimize; issue 24): one
// minimisation in progress in the pair representation of SOLVERS.md ("Free-boundary contact"),
// shared by every method (Relaxation), and the interface a method implements (MinimizerMethod).
//
// minimize() (minimizer.cpp) owns the loop: it stops on a non-finite state, tests convergence,
// checks a converged state's stability and escapes from an unstable one (stability.cpp), calls
// the observer after every accepted step and lets a method pause (the flow). A method only
// makes iterations: lbfgs and newton (lbfgs.cpp), cg (cg.cpp), fire (fire.cpp), flow (flow.cpp).
// Adding one: a class derived from MinimizerMethod, its value in minimize::Method and a row in
// method_registry() (minimizer.cpp), which names it for scenes, flags and messages.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "asperity/core/minimize/minimizer.hpp"

namespace asperity::minimize::detail {

// Energy and gradient at a pair, with the bookkeeping of evaluations.
class Evaluator {
 public:
  explicit Evaluator(Problem& p) : p_(p), fint_(p.size()) {}

  // Pi = 1/2 f.u + V(u) at the pair (u, f); writes r = f - f_int(u).
  double operator()(std::span<const double> u, std::span<const double> f, std::span<double> r);

  std::size_t evaluations = 0;

 private:
  Problem& p_;
  std::vector<double> fint_;
};

// Energies of a whole contact are resolved only to round-off: a rise below this is noise, and
// the derivative conditions decide (SOLVERS.md: slopes, not energy differences).
double energy_slack(double e);

// A pair (u, f) with u = G f, its residual r and energy e.
struct Point {
  std::vector<double> u, f, r;
  double e = 0.0;
};

// One minimisation: the problem and options, the current pair x and a trial pair (scratch at the
// start of every iteration), the result so far. The constructor evaluates the start, the pair
// (u, f) or, with `resume`, the paused flow's pair, whose counts it then continues.
struct Relaxation {
  Relaxation(Problem& problem, const MinimizerOptions& options, const std::vector<double>& u,
             const std::vector<double>& f, const FlowPause* resume);

  // u = G f again every refresh_interval iterations, against the drift of the pair (the line
  // searches and steps update u and f separately); true if it did (x has new values).
  bool refresh(int iteration);
  // w = M r with the problem's interface filter M (one FFT pair), counted in the result.
  void filter(std::span<const double> r, std::span<double> w);
  // The result after `iterations` with the counts of the work, and the pair into (u, f).
  MinimizeResult finish(int iterations, std::vector<double>& u, std::vector<double>& f);

  Problem& problem;
  const MinimizerOptions& options;
  const FlowPause* resume;  // the flow's pause this minimisation continues, or nullptr
  std::size_t n;            // unknowns
  // problem.gf_applications() at the start, less the applications before a pause.
  std::size_t gf0;
  MinimizeResult result;
  Evaluator eval;
  Point x, trial;
};

// How an iteration of a method ended.
enum class Step {
  accepted,   // a new state in x: observed, and the next iteration goes on from it
  again,      // x unchanged or restarted (a rejected step, a retry): the next iteration
  converged,  // nowhere left to go: r is numerically zero in the method's metric
  diverged,   // no step possible at this precision, or a fault of the problem
};

// A minimiser method: what one iteration does from run.x, and what it learnt on the way. A
// method is made for one minimisation (method_registry()) and sizes its state from the run.
class MinimizerMethod {
 public:
  explicit MinimizerMethod(Relaxation& run) : run_(run) {}
  virtual ~MinimizerMethod() = default;
  MinimizerMethod(const MinimizerMethod&) = delete;
  MinimizerMethod& operator=(const MinimizerMethod&) = delete;

  // The method this class implements (its registration: the registry's row must agree).
  [[nodiscard]] virtual Method method() const = 0;
  // One iteration from run.x (iteration: the count so far), into run.x if it steps.
  virtual Step iterate(int iteration) = 0;
  // The state was pushed off an unstable point: what was learnt about the landscape before it
  // (curvature pairs, velocities, a stale force image) no longer holds.
  virtual void forget() = 0;
  // After an accepted step that the observer let go on (iterations: the count with it): a method
  // that can be continued from a pause (the flow) offers it to `pauses`; true stops the
  // minimisation there.
  virtual bool pause(int iterations, const FlowPauses& pauses) {
    (void)iterations, (void)pauses;
    return false;
  }

 protected:
  Relaxation& run_;
};

// The methods, one row each, in the order of the setting's choices ("method"): the value, its
// name in scenes, flags and messages, and the class that runs it.
struct MethodEntry {
  Method method;
  std::string_view name;
  std::unique_ptr<MinimizerMethod> (*make)(Relaxation& run);
};
std::span<const MethodEntry> method_registry();
// The registry's row of m; throws std::invalid_argument for a value with none.
const MethodEntry& registered(Method m);
// Method m made for the run (throws as registered()).
std::unique_ptr<MinimizerMethod> make_method(Method m, Relaxation& run);

// The classes (each in its own file), as the registry makes them.
std::unique_ptr<MinimizerMethod> make_lbfgs(Relaxation& run);
std::unique_ptr<MinimizerMethod> make_newton(Relaxation& run);
std::unique_ptr<MinimizerMethod> make_cg(Relaxation& run);
std::unique_ptr<MinimizerMethod> make_fire(Relaxation& run);
std::unique_ptr<MinimizerMethod> make_flow(Relaxation& run);

// The stability check of a converged state (stability.cpp, minimizer.hpp): a minimum, or an
// unstable state that was left (run.x is then elsewhere and every method must forget), or one
// left once too often (max_escapes). The perturb check's relaxation counts into `iteration`.
enum class Verdict { minimum, escaped, unstable };
Verdict check_minimum(Relaxation& run, int& iteration);

}  // namespace asperity::minimize::detail
