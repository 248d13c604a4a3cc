// The minimisers of SOLVERS.md ("Free-boundary contact") in the pair representation, see
// minimizer.hpp for the methods: their names and settings, the registry of the classes that
// implement them (relaxation.hpp), what every minimisation shares (Relaxation) and minimize(),
// the loop around a method's iterations.
#include "asperity/core/minimize/minimizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize {

namespace detail {

// A method's registration: its row here (relaxation.hpp, MethodEntry), the class in its file.
std::span<const MethodEntry> method_registry() {
  static constexpr MethodEntry registry[] = {
      {Method::lbfgs, "lbfgs", make_lbfgs},     // lbfgs.cpp
      {Method::cg, "cg", make_cg},              // cg.cpp
      {Method::fire, "fire", make_fire},        // fire.cpp
      {Method::newton, "newton", make_newton},  // lbfgs.cpp
      {Method::flow, "flow", make_flow},        // flow.cpp
  };
  return registry;
}

const MethodEntry& registered(Method m) {
  for (const MethodEntry& e : method_registry()) {
    if (e.method == m) return e;
  }
  throw std::invalid_argument("minimize: method " + std::to_string(static_cast<int>(m)) +
                              " has no class registered (method_registry)");
}

std::unique_ptr<MinimizerMethod> make_method(Method m, Relaxation& run) {
  return registered(m).make(run);
}

double Evaluator::operator()(std::span<const double> u, std::span<const double> f,
                             std::span<double> r) {
  const double v = p_.interface(u, fint_);
  each(r.size(), [&](std::size_t i) { r[i] = f[i] - fint_[i]; });
  ++evaluations;
  return 0.5 * dot(f, u) + v;
}

double energy_slack(double e) {
  return 1e-12 * std::max(1.0, std::abs(e));
}

Relaxation::Relaxation(Problem& p, const MinimizerOptions& o, const std::vector<double>& u,
                       const std::vector<double>& f, const FlowPause* pause)
    : problem(p),
      options(o),
      resume(pause),
      n(p.size()),
      gf0(p.gf_applications()),
      eval(p),
      x{pause ? pause->u : u, pause ? pause->f : f, std::vector<double>(n), 0.0},
      trial{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), 0.0} {
  result.lowest_eigenvalue = std::numeric_limits<double>::quiet_NaN();
  // The energy and residual of the pair are those the paused run had (the same evaluation);
  // on resume they are not counted again.
  x.e = eval(x.u, x.f, x.r);
  if (pause) {
    result = pause->done;
    eval.evaluations = pause->done.interface_evaluations;
    gf0 -= pause->done.gf_applications;  // the work before the pause counts
  }
}

bool Relaxation::refresh(int iteration) {
  if (!(iteration > 0 && iteration % options.refresh_interval == 0)) return false;
  problem.compliance(x.f, x.u);
  x.e = eval(x.u, x.f, x.r);
  return true;
}

void Relaxation::filter(std::span<const double> r, std::span<double> w) {
  problem.filter(r, w);
  ++result.filter_applications;
}

MinimizeResult Relaxation::finish(int iterations, std::vector<double>& u, std::vector<double>& f) {
  result.iterations = iterations;
  result.energy = x.e;
  result.max_force = max_abs(x.r);
  u = std::move(x.u);
  f = std::move(x.f);
  result.gf_applications = problem.gf_applications() - gf0;
  result.interface_evaluations = eval.evaluations;
  return result;
}

}  // namespace detail

namespace {

// The passes and sums of a minimisation of `problem` on this thread, for the scope's duration:
// its threads for the element-wise passes and its reduction for the dot products and maxima
// (kernels.hpp). minimize() and max_residual() both set them through this one scope, so the
// number max_residual() reports is the one minimize() tests.
class ProblemPasses {
 public:
  explicit ProblemPasses(const Problem& problem)
      : threads_(problem.threads()),
        reduction_{
            .comm = &problem.comm(), .runs = problem.runs(), .blocks = problem.share().blocks},
        pass_reduction_(reduction_) {}

 private:
  detail::PassThreads threads_;
  detail::Reduction reduction_;  // before pass_reduction_, which points at it
  detail::PassReduction pass_reduction_;
};

// The setting's choices: the registered methods' names, in the registry's order.
std::vector<std::string> method_names() {
  std::vector<std::string> names;
  for (const detail::MethodEntry& e : detail::method_registry())
    names.emplace_back(e.name);
  return names;
}

}  // namespace

std::string to_string(Method m) {
  for (const detail::MethodEntry& e : detail::method_registry()) {
    if (e.method == m) return std::string(e.name);
  }
  return "unregistered " + std::to_string(static_cast<int>(m));  // which validate() rejects
}

std::string to_string(FlowScheme s) {
  return s == FlowScheme::euler ? "euler" : "rkc";
}

FlowScheme flow_scheme_from_string(const std::string& name) {
  if (name == "rkc") return FlowScheme::rkc;
  if (name == "euler") return FlowScheme::euler;
  throw std::invalid_argument("flow scheme: got '" + name + "', allowed: rkc, euler");
}

std::string to_string(StabilityCheck c) {
  switch (c) {
    case StabilityCheck::none:
      return "none";
    case StabilityCheck::perturb:
      return "perturb";
    case StabilityCheck::lanczos:
      return "lanczos";
  }
  return "perturb";
}

StabilityCheck stability_from_string(const std::string& name) {
  if (name == "none") return StabilityCheck::none;
  if (name == "perturb") return StabilityCheck::perturb;
  if (name == "lanczos") return StabilityCheck::lanczos;
  throw std::invalid_argument("stability check: got '" + name +
                              "', allowed: none, perturb, lanczos");
}

std::string to_string(Preconditioner p) {
  switch (p) {
    case Preconditioner::elastic:
      return "elastic";
    case Preconditioner::interface:
      return "interface";
    case Preconditioner::automatic:
      return "auto";
  }
  return "auto";
}

Preconditioner preconditioner_from_string(const std::string& name) {
  if (name == "elastic") return Preconditioner::elastic;
  if (name == "interface") return Preconditioner::interface;
  if (name == "auto") return Preconditioner::automatic;
  throw std::invalid_argument("preconditioner: got '" + name +
                              "', allowed: auto, elastic, interface");
}

Method method_from_string(const std::string& name) {
  std::string allowed;
  for (const detail::MethodEntry& e : detail::method_registry()) {
    if (e.name == name) return e.method;
    allowed.append(allowed.empty() ? "" : ", ").append(e.name);
  }
  throw std::invalid_argument("minimizer method: got '" + name + "', allowed: " + allowed);
}

const settings::Table<MinimizerOptions>& MinimizerOptions::settings() {
  using R = settings::Range;
  using O = MinimizerOptions;
  static const settings::Table<O> table = {
      settings::choice<O>(
          "method", [](auto& o) -> auto& { return o.method; }, method_names(),
          [](Method m) { return to_string(m); }, method_from_string,
          "lbfgs | cg (reference) | fire | newton (lbfgs + Newton-Krylov finish) | flow (the "
          "overdamped path: slow, faithful)",
          "--solver"),
      settings::number<O>(
          "tolerance", [](auto& o) -> auto& { return o.force_tolerance; }, R::open(0.0, 1.0),
          "G d^2", "largest residual force per site at convergence", "--tolerance"),
      settings::integer<O>(
          "max_iterations", [](auto& o) -> auto& { return o.max_iterations; }, R::at_least(1), "",
          "iterations per minimisation, escapes included"),
      settings::integer<O>(
          "memory", [](auto& o) -> auto& { return o.memory; }, R::closed(1, 100), "",
          "L-BFGS pairs kept"),
      settings::number<O>(
          "newton_start", [](auto& o) -> auto& { return o.newton_start; }, R::positive(), "G d^2",
          "newton: switch to Newton-Krylov below this residual"),
      settings::number<O>(
          "max_displacement", [](auto& o) -> auto& { return o.max_displacement; },
          R::open_closed(0.0, 0.5), "d",
          "largest displacement of a site in one iteration (half a period at most)"),
      settings::choice<O>(
          "preconditioner", [](auto& o) -> auto& { return o.preconditioner; },
          {"auto", "elastic", "interface"}, [](Preconditioner p) { return to_string(p); },
          preconditioner_from_string,
          "lbfgs, newton: auto (interface from a/b_core^0 = 10) | elastic (G) | interface (G "
          "with the interface filter)",
          "--preconditioner"),
      settings::integer<O>(
          "refresh_interval", [](auto& o) -> auto& { return o.refresh_interval; }, R::at_least(1),
          "", "recompute u = G f every this many iterations (drift)"),
      settings::choice<O>(
          "stability", [](auto& o) -> auto& { return o.stability; }, {"perturb", "lanczos", "none"},
          [](StabilityCheck c) { return to_string(c); }, stability_from_string,
          "check of converged states: perturb (push and relax) | lanczos | none"),
      settings::integer<O>(
          "max_escapes", [](auto& o) -> auto& { return o.max_escapes; }, R::at_least(0), "",
          "escapes from unstable states per minimisation"),
      settings::number<O>(
          "escape_displacement", [](auto& o) -> auto& { return o.escape_displacement; },
          R::positive(), "d", "largest displacement of the push off an unstable state"),
      settings::number<O>(
          "perturbation", [](auto& o) -> auto& { return o.perturbation; }, R::positive(), "d",
          "largest displacement of the random push of the perturb check"),
      settings::number<O>(
          "flow_tolerance", [](auto& o) -> auto& { return o.flow_tolerance; },
          R::open_closed(0.0, 1.0), "d",
          "flow: largest local error of one step, as a displacement of a site", "--flow-tolerance"),
      settings::choice<O>(
          "flow_scheme", [](auto& o) -> auto& { return o.flow_scheme; }, {"rkc", "euler"},
          [](FlowScheme f) { return to_string(f); }, flow_scheme_from_string,
          "flow: the integrator, rkc (stabilised Runge-Kutta-Chebyshev) | euler"),
      settings::boolean<O>(
          "curvature_reset", [](auto& o) -> auto& { return o.curvature_reset; },
          "lbfgs, newton: clear the pairs whenever a site changes the half of its well "
          "(experimental)")};
  return table;
}

void MinimizerOptions::validate() const {
  settings::validate(*this, settings());
}

double max_residual(Problem& problem, std::span<const double> u, std::span<const double> f) {
  const std::size_t n = problem.size();
  if (u.size() != n || f.size() != n) {
    throw std::invalid_argument("max_residual: the pair has " + std::to_string(u.size()) + " and " +
                                std::to_string(f.size()) + " values for " + std::to_string(n) +
                                " unknowns");
  }
  const ProblemPasses passes(problem);
  detail::Evaluator eval(problem);
  std::vector<double> r(n);
  (void)eval(u, f, r);
  return detail::max_abs(r);
}

MinimizeResult minimize(Problem& problem, std::vector<double>& u, std::vector<double>& f,
                        const MinimizerOptions& options, const Observer& observer,
                        const FlowPause* resume, const FlowPauses* pauses) {
  options.validate();
  const std::size_t n = problem.size();
  if (u.size() != n || f.size() != n) {
    throw std::invalid_argument("minimize: the pair has " + std::to_string(u.size()) + " and " +
                                std::to_string(f.size()) + " values for " + std::to_string(n) +
                                " unknowns");
  }
  if (resume && (options.method != Method::flow || resume->u.size() != n || resume->f.size() != n ||
                 resume->iteration < 0 || resume->iteration > options.max_iterations)) {
    throw std::invalid_argument("minimize: a pause can only continue a flow relaxation (method " +
                                to_string(options.method) + ") of " + std::to_string(n) +
                                " unknowns within " + std::to_string(options.max_iterations) +
                                " iterations; it has " + std::to_string(resume->u.size()) +
                                " at iteration " + std::to_string(resume->iteration));
  }
  const ProblemPasses passes(problem);
  // Newton's KINSOL vectors and the Lanczos check's eigensolver are serial (their own dot
  // products); the other methods reduce theirs over the processes (kernels.hpp).
  if (problem.comm().distributed() &&
      (options.method == Method::newton || options.stability == StabilityCheck::lanczos)) {
    throw std::invalid_argument(
        "minimize: method newton and the lanczos stability check run on one process only; "
        "over " +
        std::to_string(problem.comm().size()) +
        " processes use lbfgs, cg, fire or flow with the perturb check");
  }
  detail::Relaxation run(problem, options, u, f, resume);
  const std::unique_ptr<detail::MinimizerMethod> method = detail::make_method(options.method, run);
  MinimizeResult& res = run.result;
  int it = resume ? resume->iteration : 0;
  // Every exit from the loop sets its termination; running out of iterations leaves this one.
  // Of every process (a process may hold no unknowns of a distributed problem, and still takes
  // part in every reduction).
  const std::size_t n_all = problem.share().global_size();
  res.termination = n_all == 0 ? Termination::converged : Termination::max_iterations;
  for (; n_all > 0 && it < options.max_iterations; ++it) {
    const auto finite = [](double v) { return std::isfinite(v); };
    if (!std::isfinite(run.x.e) ||
        detail::reduce_any(!std::all_of(run.x.r.begin(), run.x.r.end(), finite))) {
      res.termination = Termination::diverged;
      break;
    }
    res.max_force = detail::max_abs(run.x.r);
    if (res.max_force <= options.force_tolerance) {
      // Converged: a minimum, or a state left (the method forgets what it learnt before).
      const detail::Verdict verdict = detail::check_minimum(run, it);
      if (verdict == detail::Verdict::escaped) {
        method->forget();
        continue;
      }
      res.termination =
          verdict == detail::Verdict::minimum ? Termination::converged : Termination::unstable;
      break;
    }
    const detail::Step step = method->iterate(it);
    if (step == detail::Step::again) continue;
    if (step != detail::Step::accepted) {
      res.termination =
          step == detail::Step::converged ? Termination::converged : Termination::diverged;
      break;
    }
    // A new state: the observer's (path frames, early stops), then a pause if the method has one.
    if ((observer && observer(it + 1, run.x.u, run.x.f)) ||
        (pauses && method->pause(it + 1, *pauses))) {
      res.termination = Termination::interrupted;
      ++it;  // the step made counts
      break;
    }
  }
  return run.finish(it, u, f);
}

}  // namespace asperity::minimize
