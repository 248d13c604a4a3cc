// Peierls stress by bisection on the applied stress; see peierls_stress.hpp (MODEL.md 6).
#include "asperity/peierls/peierls_stress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

#include "asperity/core/common/validate.hpp"

namespace asperity::peierls {

const settings::Table<PeierlsOptions>& PeierlsOptions::settings() {
  using R = settings::Range;
  using O = PeierlsOptions;
  static const settings::Table<O> table = [] {
    settings::Table<O> t;
    settings::lift(
        t, CellOptions::settings(), "", [](auto& o) -> auto& { return o.cell; });
    t.push_back(settings::number<O>(
        "solver.precision", [](auto& o) -> auto& { return o.precision; }, R::open(0.0, 0.5), "",
        "relative half-width of the final bracket of tau_P", "--precision"));
    t.push_back(settings::number<O>(
        "solver.tolerance", [](auto& o) -> auto& { return o.tolerance; }, R::open_closed(0.0, 0.1),
        "", "force tolerance per site as a fraction of tau d^2", "--tolerance"));
    t.push_back(settings::number<O>(
        "solver.glide_threshold", [](auto& o) -> auto& { return o.glide_threshold; },
        R::closed(0.5, 2.0), "d", "displacement from the zero-stress state that means glide"));
    t.push_back(settings::boolean<O>(
        "solver.both_signs", [](auto& o) -> auto& { return o.both_signs; },
        "also the threshold for negative stress"));
    t.push_back(settings::number<O>(
        "solver.perturbation", [](auto& o) -> auto& { return o.perturbation; }, R::closed(0.0, 0.1),
        "d", "largest random displacement of the full cell's initial state"));
    settings::lift(
        t, minimize::StiffnessOptions::settings(), "solver.",
        [](auto& o) -> auto& { return o.minimizer; });
    return t;
  }();
  return table;
}

void PeierlsOptions::validate() const {
  cell.validate();  // the cell's relations (even L, the point's own b_core and line)
  settings::validate(*this, settings());
  minimizer.validate();
}

namespace {

enum class Outcome { stable, glides, below_resolution, undetermined, failed };

struct Runner {
  PeierlsCell& cell;
  const PeierlsOptions& options;
  const std::vector<double>& u_zero;
  PeierlsResult& result;

  // Relaxes u in place under stress tau (signed, G).
  Outcome relax(std::vector<double>& u, double tau, Threshold& t) {
    std::vector<double> f_ext(cell.size(), 0.0);
    std::fill_n(f_ext.begin(), cell.sites(), tau);  // force tau d^2 along x on every site
    minimize::StiffnessOptions mo = options.minimizer;
    mo.force_tolerance = options.tolerance * std::abs(tau);
    // Just above tau_P the residual first falls towards the ghost of the lost equilibrium, then
    // grows as the line starts to glide: that is motion, not stagnation, so a stall needs the
    // residual to stay near its best (within 10x) over the window. A stall then means the
    // tolerance is below what round-off allows at this stress (or the line creeps too slowly
    // to tell): below resolution.
    mo.stall_band = 10.0;
    const std::size_t n = cell.sites();
    const double threshold = options.glide_threshold;
    // Glide: the line has left its Peierls valley (its d/2 crossing moved by more than one
    // row spacing d/|m| along the normal; in its valley it moves less than half of that before
    // tau_P), or some site moved more than glide_threshold from the zero-stress state.
    const double spacing = 1.0 / std::hypot(cell.options().mx, cell.options().my);
    const auto glide = [&](int, std::span<const double> x) {
      for (std::size_t s = 0; s < n; ++s) {
        if (std::abs(x[s] - u_zero[s]) > threshold) return true;
      }
      const double position =
          core_profile(cell.chain_offset(x), cell.options().mx, cell.options().my).position;
      return !(std::abs(position - result.core_position) <= spacing);
    };
    const minimize::StiffnessResult r = minimize_stiffness(cell, f_ext, u, mo, glide);
    ++t.relaxations;
    t.iterations += r.iterations;
    result.iterations += r.iterations;
    result.transforms += r.stiffness_applications;
    result.interface_evaluations += r.interface_evaluations;
    if (r.termination == Termination::interrupted) return Outcome::glides;
    if (r.termination == Termination::diverged) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "relaxation diverged (non-finite forces) at tau = %.6g G after %d iterations",
                    tau, r.iterations);
      t.failure = buf;
      return Outcome::failed;
    }
    // A converged state must also not have glided on the last step.
    if (r.termination == Termination::converged)
      return glide(0, u) ? Outcome::glides : Outcome::stable;
    ++t.undetermined;
    return r.termination == Termination::stalled ? Outcome::below_resolution
                                                 : Outcome::undetermined;
  }

  Threshold threshold(double sign) {
    Threshold t;
    const double tau_cap = cell.tau_max();  // no equilibrium can hold more than tau_max
    std::vector<double> u_lo = u_zero;
    double lo = 0.0, hi = 0.0;
    // Bracket: from the floor up by factors of 8. Below the first verified equilibrium, a
    // relaxation that cannot reach its tolerance (stalled at round-off) is below resolution,
    // not unstable: go on up, and raise the floor to it.
    double tau = result.floor;
    t.floor = result.floor;
    bool found = false;
    while (true) {
      std::vector<double> u = u_lo;
      const Outcome o = relax(u, sign * tau, t);
      if (o == Outcome::failed) return t;
      if (o == Outcome::stable) {
        lo = tau;
        u_lo = std::move(u);
        if (tau >= tau_cap) break;  // cannot happen physically; guards the loop
        tau = std::min(8.0 * tau, tau_cap);
      } else if (o == Outcome::below_resolution && lo <= 0.0 && tau < tau_cap) {
        t.floor = tau;
        tau = std::min(8.0 * tau, tau_cap);
      } else {
        hi = tau;
        found = true;
        break;
      }
    }
    if (!found) {
      throw std::logic_error(
          "peierls_stress: an equilibrium held at tau_max, which the interface "
          "force cannot balance");
    }
    t.lower = lo;
    t.upper = hi;
    if (lo <= 0.0) {
      // Unstable (or unresolvable) already at the floor: tau_P < upper, not a number.
      t.resolved = false;
      t.floor = std::max(t.floor, hi);
      return t;
    }
    // Geometric bisection: half-width (hi - lo) / (2 tau_P) <= precision.
    while ((hi - lo) / (2.0 * std::sqrt(lo * hi)) > options.precision) {
      const double mid = std::sqrt(lo * hi);
      std::vector<double> u = u_lo;
      const Outcome o = relax(u, sign * mid, t);
      if (o == Outcome::failed) return t;
      if (o == Outcome::stable) {
        lo = mid;
        u_lo = std::move(u);
      } else {
        hi = mid;
      }
    }
    t.lower = lo;
    t.upper = hi;
    t.tau_P = std::sqrt(lo * hi);
    t.resolved = true;
    if (sign > 0) {
      result.u_loaded = u_lo;
      result.tau_loaded = lo;
    }
    return t;
  }
};

}  // namespace

PeierlsResult peierls_stress(const PeierlsOptions& options) {
  options.validate();
  PeierlsCell cell(options.cell);
  PeierlsResult result;
  result.L = options.cell.L;
  result.mx = options.cell.mx;
  result.my = options.cell.my;
  result.theta_deg = line_angle_deg(result.mx, result.my);
  result.b_core = options.cell.b_core;
  result.tau_max = cell.tau_max();
  result.nu = options.cell.material.nu;
  result.model = options.cell.model;
  result.precision = options.precision;
  result.tolerance = options.tolerance;
  result.rigid_estimate = rigid_peierls_estimate(result.b_core, result.mx, result.my, result.nu);

  // Zero stress, relaxed until the residual stops falling: that floor is the resolution limit.
  std::vector<double> u = cell.initial_state();
  if (options.cell.model == CellModel::full && options.perturbation > 0.0) {
    std::mt19937_64 rng(20261122);
    std::uniform_real_distribution<double> push(-options.perturbation, options.perturbation);
    for (double& x : u)
      x += push(rng);
  }
  const std::vector<double> f_zero(cell.size(), 0.0);
  minimize::StiffnessOptions mo = options.minimizer;
  mo.force_tolerance = 0.0;
  const minimize::StiffnessResult r0 = minimize_stiffness(cell, f_zero, u, mo);
  result.zero_stress_termination = r0.termination;
  result.iterations += r0.iterations;
  result.transforms += r0.stiffness_applications;
  result.interface_evaluations += r0.interface_evaluations;
  // A residual that happens to vanish exactly (a symmetric state) says nothing about round-off:
  // keep at least the size of one rounding of the interface force.
  result.noise_force =
      std::max(r0.best_max_force, 16.0 * std::numeric_limits<double>::epsilon() * cell.tau_max());
  result.floor = 2.0 * result.noise_force / options.tolerance;
  result.u_zero = u;

  const CoreProfile core = core_profile(cell.chain_offset(u), result.mx, result.my);
  result.core_width = core.width;
  result.core_position = core.position;
  result.core_width_continuum = continuum_core_width(result.b_core, result.theta_deg, result.nu);

  if (r0.termination == Termination::diverged) {
    result.positive.resolved = result.negative.resolved = false;
    result.failure = "zero-stress relaxation diverged (non-finite forces) after " +
                     std::to_string(r0.iterations) + " iterations";
    return result;
  }
  Runner runner{cell, options, result.u_zero, result};
  result.positive = runner.threshold(+1.0);
  if (options.both_signs) result.negative = runner.threshold(-1.0);
  for (const auto& [name, t] : {std::pair{"+x", &result.positive}, {"-x", &result.negative}}) {
    if (t->failure.empty()) continue;
    if (!result.failure.empty()) result.failure += "; ";
    result.failure += std::string(name) + " stress: " + t->failure;
  }
  return result;
}

const settings::Table<CellSizeOptions>& CellSizeOptions::settings() {
  using R = settings::Range;
  using O = CellSizeOptions;
  static const settings::Table<O> table = {
      settings::number<O>(
          "cell.L_tolerance", [](auto& o) -> auto& { return o.tolerance; },
          R::closed_open(0.0, 1.0), "",
          "relative change of tau_P on doubling L below which the cell is large enough (0: "
          "one cell)",
          "--L-tolerance"),
      settings::integer<O>(
          "cell.max_L", [](auto& o) -> auto& { return o.max_L; }, R::closed(8, 1 << 16), "",
          "largest cell tried when doubling L", "--max-L")};
  return table;
}

void CellSizeOptions::validate() const {
  settings::validate(*this, settings());
}

CellSizeResult peierls_stress_converged(const PeierlsOptions& options,
                                        const CellSizeOptions& cell_size) {
  cell_size.validate();
  PeierlsOptions o = options;
  CellSizeResult out;
  out.result = peierls_stress(o);
  out.change = std::numeric_limits<double>::quiet_NaN();
  out.converged = cell_size.tolerance == 0.0;
  const auto relative_change = [](const Threshold& now, const Threshold& before) {
    if (now.resolved != before.resolved) return std::numeric_limits<double>::quiet_NaN();
    return now.resolved ? std::abs(now.tau_P / before.tau_P - 1.0) : 0.0;
  };
  while (!out.converged && 2 * o.cell.L <= cell_size.max_L) {
    if (!out.result.failure.empty()) break;
    if (!out.result.positive.resolved && !out.result.negative.resolved) break;
    o.cell.L *= 2;
    PeierlsResult next = peierls_stress(o);
    next.iterations += out.result.iterations;
    next.transforms += out.result.transforms;
    next.interface_evaluations += out.result.interface_evaluations;
    const double positive = relative_change(next.positive, out.result.positive);
    const double negative =
        options.both_signs ? relative_change(next.negative, out.result.negative) : 0.0;
    out.change = std::isnan(positive) || std::isnan(negative)
                     ? std::numeric_limits<double>::quiet_NaN()
                     : std::max(positive, negative);
    out.result = std::move(next);
    ++out.cells;
    if (std::isnan(out.change)) break;  // resolved at one size only: no comparison
    out.converged = out.change <= cell_size.tolerance;
  }
  return out;
}

}  // namespace asperity::peierls
