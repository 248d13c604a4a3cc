// Path checks against the overdamped flow (path.hpp, MODEL.md 5).
#include "asperity/core/slide/path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

namespace asperity::slide {

Instability bracket_slip(const interface::ContactScene& scene, SlideOptions options, int event) {
  if (event < 1) throw std::invalid_argument("bracket_slip: event must be >= 1");
  options.protocol = Protocol::adaptive;
  options.replay_cycle = false;  // a replayed slip has no bracket
  options.slips_to_stop = std::max(options.slips_to_stop, event);
  // The state at the top of each step before slip `event`: the slipping step starts from the
  // last of them, the bracket's stable end. (Its other end is that step's Dx, at most min_step
  // on: the step to a bisection's closed bracket, or a trial that narrow, which a slide with a
  // slip minimiser hands to it at once, so that no step top shows the closed bracket.)
  // Only the accepted state is kept: the whole SlideState (trace, window, peak, ...) would be
  // copied at every step top (at a = 300 d, R = 800 d about 240 MB, the size of a checkpoint).
  std::optional<SlideFields> top;
  int slips = 0;
  SlideControl control;
  control.checkpoint_every_s = 0.0;  // at every step's top
  control.checkpoint = [&](const SlideState& st) {
    slips = st.partial.slip_events;
    if (st.partial.slip_events == event - 1 && !st.pending) top = st.current;
  };
  control.stop_requested = [&] { return slips >= event; };
  DiscardFrames discard;
  control.frames = &discard;
  SlideResult r = slide(scene, options, control);
  // The trace row of slip `event` (a plain loop: a predicate that counts must not be copied).
  const TraceRow* row = nullptr;
  for (int n = 0; const TraceRow& t : r.trace) {
    if (t.slip && ++n == event) {
      row = &t;
      break;
    }
  }
  if (r.slip_events < event || !top || !row) {
    throw std::runtime_error("bracket_slip: the slide reached " + std::to_string(r.slip_events) +
                             " slip events (" + r.stop_reason + "), not slip " +
                             std::to_string(event));
  }
  const double width = row->Dx - top->Dx;
  if (!(width > 0.0 && options.within_min_step(width))) {
    throw std::logic_error(
        "bracket_slip: slip " + std::to_string(event) + " at Dx = " + std::to_string(row->Dx) +
        " d was taken from the state at " + std::to_string(top->Dx) + " d, not within min_step");
  }
  Instability out;
  out.stable = std::move(*top);
  out.slip_Dx = row->Dx;
  out.event = event;
  out.slide = std::move(r);
  return out;
}

StateComparison compare_states(const interface::ContactScene& scene, const SlideFields& a,
                               const SlideFields& b) {
  const int side = block_side(scene), half = (side - 1) / 2;
  const std::size_t n = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  if (a.shift != b.shift || std::abs(a.Dx - b.Dx) > 1e-12 * scene.d || a.u.size() != 2 * n ||
      b.u.size() != 2 * n) {
    throw std::invalid_argument("compare_states: states at Dx " + std::to_string(a.Dx) + " and " +
                                std::to_string(b.Dx) + " (shifts " + std::to_string(a.shift) +
                                ", " + std::to_string(b.shift) +
                                "): allowed: the same tip position and block of this scene");
  }
  interface::LateralForceModel lfm(scene, LatticeBlock{Shape2{side, side}, a.shift - half, -half});
  lfm.set_tip(a.Dx);
  StateComparison c;
  c.Fx_a = a.Fx;
  c.Fx_b = b.Fx;
  c.relative_Fx = std::abs(a.Fx - b.Fx) / std::max(std::abs(b.Fx), 1e-300);
  const double d = scene.d;
  for (std::size_t i : lfm.contact_sites()) {
    ++c.sites;
    c.max_du = std::max({c.max_du, std::abs(a.u[i] - b.u[i]), std::abs(a.u[n + i] - b.u[n + i])});
    if (!lfm.tip_frame().aligned()) {
      // The registry index of a tip out of registry: round(rho) per tip axis.
      double a1 = 0.0, a2 = 0.0, b1 = 0.0, b2 = 0.0;
      lfm.registry(i, a.u[i], a.u[n + i], a1, a2);
      lfm.registry(i, b.u[i], b.u[n + i], b1, b2);
      if (std::lround(a1) != std::lround(b1) || std::lround(a2) != std::lround(b2))
        ++c.registry_differences;
      continue;
    }
    if (std::lround(lfm.sx(i, a.u[i]) / d) != std::lround(lfm.sx(i, b.u[i]) / d) ||
        std::lround(lfm.sy(i, a.u[n + i]) / d) != std::lround(lfm.sy(i, b.u[n + i]) / d)) {
      ++c.registry_differences;
    }
  }
  return c;
}

std::string solver_label(const minimize::MinimizerOptions& m) {
  std::string s = minimize::to_string(m.method);
  if (m.method == minimize::Method::lbfgs || m.method == minimize::Method::newton ||
      m.method == minimize::Method::flow) {
    s.push_back('/');
    s.append(minimize::to_string(m.preconditioner));
  }
  if (m.curvature_reset) s.append("+reset");
  if (m.method == minimize::Method::flow) {
    char tol[32];
    std::snprintf(tol, sizeof tol, "@%g", m.flow_tolerance);
    s.append(tol);
  }
  return s;
}

namespace {

// A FlowWatch that appends a FlowSample per accepted step to `out`.
FlowWatch sampler(FlowProfile& out, double d) {
  return [&out, d, first = std::vector<double>{},
          last = std::vector<double>{}](const minimize::FlowPause& p) mutable {
    FlowSample s{.iteration = p.iteration,
                 .gf = p.done.gf_applications,
                 .filter = p.done.filter_applications,
                 .step = p.step,
                 .radius = p.radius};
    for (double v : p.velocity_u)
      s.max_speed = std::max(s.max_speed, std::abs(v));
    for (double v : p.velocity_f)
      s.max_residual = std::max(s.max_residual, std::abs(v));
    if (first.empty()) first = p.u, last = p.u;
    for (std::size_t i = 0; i < p.u.size(); ++i) {
      s.max_move = std::max(s.max_move, std::abs(p.u[i] - last[i]));
      if (std::abs(p.u[i] - first[i]) > 0.5 * d) ++s.moved;
    }
    last = p.u;
    out.push_back(s);
  };
}

}  // namespace

PathCheck check_path(const interface::ContactScene& scene, const SlideOptions& options,
                     const Instability& at, const std::vector<minimize::MinimizerOptions>& solvers,
                     int flow_max_iterations, bool halve, bool profile) {
  PathCheck out;
  out.instability = at;
  SlideOptions flow = options;
  flow.minimizer.method = minimize::Method::flow;
  flow.minimizer.preconditioner = minimize::Preconditioner::elastic;  // the reference: G
  flow.minimizer.max_iterations = flow_max_iterations;
  out.flow = relax_step(scene, flow, at.stable, at.slip_Dx,
                        profile ? sampler(out.flow_profile, scene.d) : FlowWatch{});
  if (halve) {
    flow.minimizer.flow_tolerance *= 0.5;
    out.flow_half = relax_step(scene, flow, at.stable, at.slip_Dx);
    out.flow_self = compare_states(scene, out.flow_half.state, out.flow.state);
  }
  for (const auto& m : solvers) {
    SlideOptions o = options;
    o.minimizer = m;
    PathCheckRow row;
    row.solver = solver_label(m);
    const bool watched = profile && m.method == minimize::Method::flow;
    row.step = relax_step(scene, o, at.stable, at.slip_Dx,
                          watched ? sampler(row.profile, scene.d) : FlowWatch{});
    row.slipped = row.step.slipped_sites > 0;
    row.against_flow = compare_states(scene, row.step.state, out.flow.state);
    out.rows.push_back(std::move(row));
  }
  return out;
}

}  // namespace asperity::slide
