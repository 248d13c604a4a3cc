// Quasi-static sliding of the lateral force model; protocols and criteria in slider.hpp.
#include "slide/slider.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include "common/validate.hpp"
#include "elastic/surface_gf.hpp"
#include "slide/lfm_problem.hpp"

namespace asperity::slide {

namespace {

// The state of the slide: full-block force and displacement fields (component-major) at a
// tip position, with the block offset (in lattice steps) that follows the tip.
using State = SlideFields;

class Slider {
 public:
  Slider(const interface::ContactScene& scene, const SlideOptions& options)
      : scene_(scene),
        options_(options),
        half_(static_cast<int>(std::ceil(scene.a / scene.d)) + 2),
        block_shape_{2 * half_ + 1, 2 * half_ + 1},
        gf_(scene.material, elastic::Components::in_plane, block_shape_, scene.d, options.fft),
        lfm_(scene, block_at(0)),
        problem_(gf_, lfm_) {}

  [[nodiscard]] LatticeBlock block_at(int shift) const {
    return LatticeBlock{block_shape_, shift - half_, -half_};
  }
  elastic::FreeSurfaceGF& gf() { return gf_; }
  interface::LateralForceModel& lfm() {
    return lfm_;
  }

  State initial() {
    State s;
    s.f.assign(gf_.size(), 0.0);
    s.u.assign(gf_.size(), 0.0);
    return s;
  }

  // Moves `s` to tip position Dx and relaxes it. Frames go to `frames` if given.
  minimize::MinimizeResult relax(State& s, double Dx, std::vector<Snapshot>* frames,
                                 bool stop_on_slip = false) {
    const int target_shift = static_cast<int>(std::floor(Dx / scene_.d + 0.5));
    // Rolled rows come in without displacements; u = G f below recomputes them.
    if (target_shift != s.shift) roll_fields(s, target_shift - s.shift);
    lfm_ = interface::LateralForceModel(scene_, block_at(s.shift));
    lfm_.set_tip(Dx);
    s.Dx = Dx;
    // Sites that left the contact carry no force; u = G f also refreshes the pair.
    const std::size_t n = block_shape_.count();
    std::vector<std::uint8_t> in(n, 0);
    for (std::size_t i : lfm_.contact_sites())
      in[i] = 1;
    for (std::size_t i = 0; i < n; ++i) {
      if (!in[i]) s.f[i] = s.f[n + i] = 0.0;
    }
    gf_.apply(s.f, s.u);
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size();
    std::vector<double> u(2 * m), f(2 * m);
    gather(s.u, u);
    gather(s.f, f);
    // A trial step that is to be undone if it slips is stopped as soon as a site has moved by
    // d/2: the slip is certain, and relaxing it fully would be wasted.
    const std::vector<double> u_start = u;
    const bool record = frames != nullptr && options_.path_frame_every > 0;
    minimize::Observer observer;
    // A long relaxation keeps at most max_path_frames frames: when full, every other frame is
    // dropped and the interval doubles, so the frames stay evenly spread over the relaxation.
    int interval = options_.path_frame_every;
    if (record || stop_on_slip) {
      observer = [&](int it, std::span<const double> uu, std::span<const double> ff) {
        if (record && it % interval == 0) {
          if (static_cast<int>(frames->size()) >= options_.max_path_frames) {
            std::size_t keep = 0;
            for (std::size_t k = 1; k < frames->size(); k += 2)
              (*frames)[keep++] = std::move((*frames)[k]);
            frames->resize(keep);
            interval *= 2;
          }
          if (it % interval == 0) {
            State frame = s;
            scatter(uu, frame.u);
            scatter(ff, frame.f);
            std::vector<double> fint(uu.size());
            const double v = lfm_.energy_and_force(uu, fint);
            frame.Fx = 0.0;
            double fu = 0.0;
            for (std::size_t j = 0; j < m; ++j)
              frame.Fx += fint[j];
            for (std::size_t j = 0; j < uu.size(); ++j)
              fu += ff[j] * uu[j];
            frame.Fz = lfm_.load();
            frame.energy = 0.5 * fu + v;
            frames->push_back(snapshot(frame, "path", it));
          }
        }
        if (!stop_on_slip) return false;
        for (std::size_t j = 0; j < m; ++j) {
          if (std::abs(uu[j] - u_start[j]) > 0.5 * scene_.d) {
            return true;
          }
        }
        return false;
      };
    }
    const auto r = minimize::minimize(problem_, u, f, options_.minimizer, observer);
    scatter(f, s.f);
    // The displacement off the contact follows from the new forces (slip detection and
    // snapshots compare it between states); on the contact it is the minimiser's.
    gf_.apply(s.f, s.u);
    scatter(u, s.u);
    std::vector<double> fint(2 * m);
    const double v = lfm_.energy_and_force(u, fint);
    s.Fx = 0.0;
    for (std::size_t j = 0; j < m; ++j)
      s.Fx += fint[j];
    s.Fz = lfm_.load();
    double fu = 0.0;
    for (std::size_t j = 0; j < 2 * m; ++j)
      fu += f[j] * u[j];
    s.energy = 0.5 * fu + v;
    return r;
  }

  // Brings a state's fields onto the block alignment `shift` (no GF application: f only).
  void align(State& s, int shift) const { roll_fields(s, shift - s.shift); }

  // Sites of the contact at `after` whose x displacement changed by more than d/2 since
  // `before` (same block alignment after rolling).
  int slipped_sites(const State& before, const State& after) const {
    State b = before;
    const int k = after.shift - b.shift;
    if (k != 0) roll_fields(b, k);
    // Rows that entered the block with the roll have no displacement in `before`.
    const std::size_t first_new_row = static_cast<std::size_t>(block_shape_.n0 - std::max(k, 0));
    int count = 0;
    for (std::size_t i : lfm_.contact_sites()) {
      if (i / static_cast<std::size_t>(block_shape_.n1) >= first_new_row) continue;
      if (std::abs(after.u[i] - b.u[i]) > 0.5 * scene_.d) ++count;
    }
    return count;
  }

  Snapshot snapshot(const State& s, std::string label, int iteration = -1) {
    Snapshot snap;
    snap.label = std::move(label);
    snap.iteration = iteration;
    snap.Dx = s.Dx;
    snap.Fx = s.Fx;
    snap.Fz = s.Fz;
    snap.energy = s.energy;
    snap.block = block_at(s.shift);
    // The LFM must describe this state's tip position and block.
    if (lfm_.tip() != s.Dx || lfm_.block().origin0 != snap.block.origin0) {
      lfm_ = interface::LateralForceModel(scene_, snap.block);
      lfm_.set_tip(s.Dx);
    }
    const std::size_t n = block_shape_.count();
    snap.ux.assign(s.u.begin(), s.u.begin() + static_cast<std::ptrdiff_t>(n));
    snap.uy.assign(s.u.begin() + static_cast<std::ptrdiff_t>(n), s.u.end());
    snap.sx.resize(n);
    snap.sy.resize(n);
    snap.tau_x.assign(n, 0.0);
    snap.tau_y.assign(n, 0.0);
    snap.tau_max = lfm_.tau_max();
    snap.pressure = lfm_.pressure();
    snap.in_contact.assign(n, 0);
    const double k = 2.0 * std::numbers::pi / scene_.d;
    for (std::size_t i = 0; i < n; ++i) {
      snap.sx[i] = lfm_.sx(i, snap.ux[i]);
      snap.sy[i] = lfm_.sy(i, snap.uy[i]);
      if (snap.tau_max[i] > 0.0) {
        snap.in_contact[i] = 1;
        snap.tau_x[i] = -snap.tau_max[i] * std::sin(k * snap.sx[i]);
        snap.tau_y[i] = -snap.tau_max[i] * std::sin(k * snap.sy[i]);
      }
    }
    return snap;
  }

 private:
  void gather(const std::vector<double>& full, std::vector<double>& part) const {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n = block_shape_.count();
    for (std::size_t j = 0; j < m; ++j) {
      part[j] = full[sites[j]];
      part[m + j] = full[n + sites[j]];
    }
  }
  void scatter(std::span<const double> part, std::vector<double>& full) const {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n = block_shape_.count();
    for (std::size_t j = 0; j < m; ++j) {
      full[sites[j]] = part[j];
      full[n + sites[j]] = part[m + j];
    }
  }

  // Shifts the block by k lattice rows along +x: site rows move down by k, new rows are empty.
  void roll_fields(State& s, int k) const {
    const std::size_t n1 = static_cast<std::size_t>(block_shape_.n1);
    const int n0 = block_shape_.n0;
    for (std::vector<double>* field : {&s.f, &s.u}) {
      for (int c = 0; c < 2; ++c) {
        double* base = field->data() + static_cast<std::size_t>(c) * block_shape_.count();
        for (int i0 = 0; i0 < n0; ++i0) {
          const int from = i0 + k;
          double* row = base + static_cast<std::size_t>(i0) * n1;
          if (from >= 0 && from < n0) {
            std::copy_n(base + static_cast<std::size_t>(from) * n1, n1, row);
          } else {
            std::fill_n(row, n1, 0.0);
          }
        }
      }
    }
    s.shift += k;
  }

  interface::ContactScene scene_;
  SlideOptions options_;
  int half_;
  Shape2 block_shape_;
  elastic::FreeSurfaceGF gf_;
  interface::LateralForceModel lfm_;
  LfmProblem problem_;
};

}  // namespace

std::string to_string(Protocol p) {
  return p == Protocol::reference ? "reference" : "adaptive";
}

Protocol protocol_from_string(const std::string& name) {
  if (name == "reference") return Protocol::reference;
  if (name == "adaptive") return Protocol::adaptive;
  throw std::invalid_argument("slide protocol: got '" + name + "', allowed: reference, adaptive");
}

minimize::MinimizerOptions slide_minimizer_defaults() {
  minimize::MinimizerOptions m;
  m.force_tolerance = 1e-5;
  m.max_displacement = 0.2;
  return m;
}

void SlideOptions::validate() const {
  const auto fail = [](const std::string& what, double v, const std::string& allowed) {
    reject("SlideOptions." + what, std::to_string(v), allowed);
  };
  if (!(step > 0.0 && step < 0.5)) fail("step", step, "0 < step < 0.5 d");
  // Half a period or more would alias the registry potential: a step of d/2 lands every atom
  // on the symmetric point of its well, where the forces balance by symmetry.
  if (!(max_step > 0.0 && max_step < 0.5)) fail("max_step", max_step, "0 < max_step < 0.5 d");
  if (!(min_step > 0.0 && min_step <= max_step))
    fail("min_step", min_step, "0 < min_step <= max_step");
  if (!(distance >= 0.0) || !std::isfinite(distance))
    fail("distance", distance, ">= 0 (0: automatic)");
  if (!(max_distance >= 0.0) || !std::isfinite(max_distance)) {
    fail("max_distance", max_distance, ">= 0 (0: automatic)");
  }
  if (slips_to_stop < 1) fail("slips_to_stop", slips_to_stop, ">= 1");
  if (path_frame_every < 0) fail("path_frame_every", path_frame_every, ">= 0");
  if (max_path_frames < 2) fail("max_path_frames", max_path_frames, ">= 2");
  minimizer.validate();
  fft.validate();
}

void SlideControl::validate() const {
  if (!(checkpoint_every_s >= 0.0) || !std::isfinite(checkpoint_every_s)) {
    reject("SlideControl.checkpoint_every_s", std::to_string(checkpoint_every_s),
           "finite and >= 0 (0: after every step)");
  }
}

namespace {

// A start state must come from a slide of the same scene: every field on the same block.
void check_start(const SlideState& st, std::size_t field_size) {
  const auto fields = [&](const SlideFields& f, const char* name) {
    if (f.f.size() != field_size || f.u.size() != field_size) {
      reject(std::string("SlideState.") + name + " fields",
             std::to_string(f.f.size()) + " and " + std::to_string(f.u.size()) + " values",
             std::to_string(field_size) + " (2 per site of this scene's block)");
    }
    if (!std::isfinite(f.Dx) || !(f.Dx >= 0.0)) {
      reject(std::string("SlideState.") + name + ".Dx", std::to_string(f.Dx), "finite and >= 0");
    }
  };
  fields(st.current, "current");
  fields(st.peak, "peak");
  if (st.previous) fields(*st.previous, "previous");
  if (st.earlier) fields(*st.earlier, "earlier");
  if (st.runner_up) fields(*st.runner_up, "runner_up");
  if (st.partial.trace.empty())
    reject("SlideState.partial.trace", "empty", "the first row at least");
}

}  // namespace

SlideResult slide(const interface::ContactScene& scene, const SlideOptions& options,
                  const SlideProgress& progress) {
  return slide(scene, options, SlideControl{.progress = progress});
}

SlideResult slide(const interface::ContactScene& scene, const SlideOptions& options,
                  const SlideControl& control) {
  scene.validate();
  options.validate();
  control.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&t0] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  Slider slider(scene, options);
  SlideResult res;
  // Of the earlier sessions of a resumed slide (counted in the start state).
  std::size_t gf_before = 0;
  double wall_before = 0.0;
  if (control.start) {
    check_start(*control.start, slider.gf().size());
    res = control.start->partial;
    gf_before = res.gf_applications;
    wall_before = res.wall_s;
  }
  res.block = slider.gf().region();
  res.fft_grid = slider.gf().fft_shape();
  res.Fz_continuum = scene.hertz().load;
  const double d = scene.d;
  const bool automatic = options.distance == 0.0;
  const double ramp = scene.alpha * scene.hertz().load / scene.lateral_stiffness();
  const double limit =
      automatic ? (options.max_distance > 0.0 ? options.max_distance : 3.0 * d + 3.0 * ramp)
                : options.distance;

  State state = slider.initial();
  const auto record = [&](const State& s, const minimize::MinimizeResult& r, bool slip, int sites) {
    res.trace.push_back(TraceRow{s.Dx, s.Fx, s.Fz, s.energy, r.iterations, r.gf_applications,
                                 r.max_force, slip, sites});
    res.iterations += r.iterations;
  };
  const auto count = [&](const minimize::MinimizeResult& r) {
    ++res.minimizations;
    res.gradient_evaluations += r.interface_evaluations;
  };
  // Why a relaxation to Dx (from the state at `from`) cannot be accepted: the minimiser did not
  // converge, or the relaxed state has non-finite forces or energy. Empty if it can. The message
  // names the step and the parameters needed to reproduce it.
  const auto failure = [&](const minimize::MinimizeResult& r, const State& s, double Dx,
                           double from) -> std::string {
    const char* what = nullptr;
    if (r.termination != Termination::converged) {
      what = "";
    } else if (!std::isfinite(s.Fx) || !std::isfinite(s.Fz) || !std::isfinite(s.energy)) {
      what = "non-finite force or energy after ";
    } else {
      return {};
    }
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%sminimizer %s at Dx = %.9g d (step %d, from Dx = %.9g d, step size %.3g d; "
                  "%d iterations, max force %.3g, energy %.9g; %s, tolerance %g, max "
                  "iterations %d)",
                  what, to_string(r.termination).c_str(), Dx, res.steps + 1, from, Dx - from,
                  r.iterations, r.max_force, r.energy,
                  minimize::to_string(options.minimizer.method).c_str(),
                  options.minimizer.force_tolerance, options.minimizer.max_iterations);
    return buf;
  };

  std::optional<State> peak, previous, earlier, runner_up;
  double runner_up_ratio = -std::numeric_limits<double>::infinity();
  double best = 0.0;
  double first_max_Dx = -1.0;  // Regime I: first maximum of Fx without a slip
  double slip_at = std::numeric_limits<double>::infinity();
  bool stopped = false;
  if (control.start) {
    const SlideState& st = *control.start;
    state = st.current;
    previous = st.previous;
    earlier = st.earlier;
    peak = st.peak;
    runner_up = st.runner_up;
    best = st.best;
    runner_up_ratio = st.runner_up_ratio;
    first_max_Dx = st.first_max_Dx;
    slip_at = st.slip_at;
    stopped = st.stepping_done;
  } else {
    auto first = slider.relax(state, 0.0, nullptr);
    count(first);
    res.contact_sites = slider.lfm().contact_sites().size();
    record(state, first, false, 0);
    best = state.Fx / state.Fz;
    peak = state;
    if (const std::string why = failure(first, state, 0.0, 0.0); !why.empty()) {
      res.failed = true;  // no good state yet to keep
      res.stop_reason = why;
      stopped = true;
    }
  }

  // The state at the top of the stepping loop (or after it), for checkpoints.
  const auto capture = [&](bool stepping_done) {
    SlideState st{.current = state,
                  .previous = previous,
                  .earlier = earlier,
                  .peak = *peak,
                  .runner_up = runner_up,
                  .best = best,
                  .runner_up_ratio = runner_up_ratio,
                  .first_max_Dx = first_max_Dx,
                  .slip_at = slip_at,
                  .stepping_done = stepping_done,
                  .partial = res};
    st.partial.gf_applications = gf_before + slider.gf().applications();
    st.partial.wall_s = wall_before + elapsed();
    return st;
  };
  // Stop on request: hand the state over and return what is known so far.
  const auto interrupt = [&](const SlideState& st) {
    if (control.checkpoint) control.checkpoint(st);
    SlideResult out = st.partial;
    out.interrupted = true;
    char buf[120];
    std::snprintf(buf, sizeof buf, "interrupted at Dx = %.6g d%s", st.current.Dx,
                  st.stepping_done ? " (refining the peak)" : "");
    out.stop_reason = buf;
    out.mu = st.best;
    out.mu_over_alpha = st.best / scene.alpha;
    out.mu_is_lower_bound = true;  // the static peak is not established yet
    out.peak_Dx = st.peak.Dx;
    out.Fz = st.peak.Fz;
    out.distance = st.current.Dx;
    out.kinetic = out.kinetic_over_static = std::numeric_limits<double>::quiet_NaN();
    return out;
  };
  const auto stop_requested = [&] { return control.stop_requested && control.stop_requested(); };
  auto last_checkpoint = std::chrono::steady_clock::now();

  const double h = options.protocol == Protocol::reference ? options.step : options.max_step;
  while (!stopped) {
    if (stop_requested()) return interrupt(capture(false));
    if (control.checkpoint) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_checkpoint).count() >=
          control.checkpoint_every_s) {
        control.checkpoint(capture(false));
        last_checkpoint = now;
      }
    }
    if (state.Dx >= limit - 1e-12) {
      res.stop_reason = automatic ? "distance cap reached" : "distance reached";
      break;
    }
    // Adaptive: a bracket [state.Dx, slip_at] around a known instability is bisected until it
    // is min_step wide; the slip is then taken from its stable end.
    // Smooth sliding (a maximum without a slip, Regime I): the kinetic friction is the mean of a
    // near-sinusoid over the last period, which the trapezoid rule gets right only from evenly
    // spread samples: eight per period from the first maximum on.
    const double step = options.protocol == Protocol::adaptive && first_max_Dx >= 0.0 &&
                                res.slip_events == 0
                            ? std::min(h, 0.125 * d)
                            : h;
    double Dx = std::min(state.Dx + step, limit);
    bool may_undo = false;
    if (options.protocol == Protocol::adaptive) {
      const double gap = slip_at - state.Dx;
      if (!std::isfinite(slip_at)) {
        may_undo = true;
      } else if (gap > options.min_step * 1.0001) {
        Dx = state.Dx + 0.5 * gap;
        may_undo = true;
      } else {
        Dx = slip_at;
      }
    }
    State trial = state;
    // Warm start on a smooth branch: extrapolate the force field in Dx through the last two or
    // three states of the branch (Lagrange; u follows as G f). After a slip the branch is new.
    const std::size_t rows = res.trace.size();
    const bool on_branch1 = previous && !res.trace.back().slip && state.Dx > previous->Dx;
    const bool on_branch2 = on_branch1 && earlier && rows >= 3 && !res.trace[rows - 2].slip &&
                            previous->Dx > earlier->Dx;
    if (options.extrapolate && on_branch1) {
      State p1 = *previous;
      if (p1.shift != trial.shift) slider.align(p1, trial.shift);
      if (on_branch2) {
        State p2 = *earlier;
        if (p2.shift != trial.shift) slider.align(p2, trial.shift);
        const double x0 = p2.Dx, x1 = p1.Dx, x2 = state.Dx;
        const double l0 = (Dx - x1) * (Dx - x2) / ((x0 - x1) * (x0 - x2));
        const double l1 = (Dx - x0) * (Dx - x2) / ((x1 - x0) * (x1 - x2));
        const double l2 = (Dx - x0) * (Dx - x1) / ((x2 - x0) * (x2 - x1));
        for (std::size_t i = 0; i < trial.f.size(); ++i) {
          trial.f[i] = l0 * p2.f[i] + l1 * p1.f[i] + l2 * state.f[i];
        }
      } else {
        const double w = (Dx - state.Dx) / (state.Dx - p1.Dx);
        for (std::size_t i = 0; i < trial.f.size(); ++i)
          trial.f[i] += w * (state.f[i] - p1.f[i]);
      }
    }
    std::vector<Snapshot> frames;
    const bool want_frames = options.path_frame_every > 0 && !may_undo;
    const auto r = slider.relax(trial, Dx, want_frames ? &frames : nullptr, may_undo);
    count(r);
    if (may_undo && r.termination == Termination::interrupted) {
      slip_at = Dx;  // slipped: bisect towards the instability
      continue;
    }
    if (const std::string why = failure(r, trial, Dx, state.Dx); !why.empty()) {
      // The trial is dropped; the last accepted state is kept as a checkpoint (resumable) and
      // as snapshot "last_good".
      if (control.checkpoint) control.checkpoint(capture(false));
      res.failed = true;
      res.stop_reason = why;
      res.snapshots.push_back(slider.snapshot(state, "last_good"));
      break;
    }
    const int sites = slider.slipped_sites(state, trial);
    const bool slip = sites > 0;
    if (slip && may_undo) {
      slip_at = Dx;
      continue;
    }
    // After a slip the bracket is used up; a stable state at the bracket's end means the
    // instability lies further on (a trial from further back had slipped).
    if (slip || Dx >= slip_at) slip_at = std::numeric_limits<double>::infinity();
    if (slip) {
      ++res.slip_events;
      char label[32];
      std::snprintf(label, sizeof label, "slip_%03d", res.slip_events);
      res.snapshots.push_back(slider.snapshot(state, std::string(label) + "_before"));
      res.snapshots.push_back(slider.snapshot(trial, std::string(label) + "_after"));
      for (auto& frame : frames) {
        frame.label = std::string(label) + "_path";
        res.snapshots.push_back(std::move(frame));
      }
    }
    earlier = std::move(previous);
    previous = std::move(state);
    state = std::move(trial);
    record(state, r, slip, sites);
    ++res.steps;
    // A later maximum replaces the peak only if it is higher beyond the minimiser's noise: in
    // Regime I the trace repeats its first maximum a period later, and the first, which has
    // samples on both sides, is the one to refine.
    const double ratio = state.Fx / state.Fz;
    if (ratio > best + 1e-6 * std::abs(best)) {
      runner_up = std::move(peak);
      runner_up_ratio = best;
      best = ratio;
      peak = state;
    }
    if (control.progress) control.progress(state.Dx, limit, res.slip_events);

    // Regime I: a smooth maximum (rise then fall, no slip yet).
    const std::size_t k = res.trace.size();
    if (first_max_Dx < 0.0 && res.slip_events == 0 && k >= 3 &&
        res.trace[k - 2].Fx > res.trace[k - 3].Fx && res.trace[k - 1].Fx < res.trace[k - 2].Fx) {
      first_max_Dx = res.trace[k - 2].Dx;
    }
    if (automatic && res.slip_events >= options.slips_to_stop) {
      res.stop_reason = "slip events reached";
      break;
    }
    // Adaptive: the even steps start at most one step past the maximum, and the kinetic window
    // (the last period) must lie inside them.
    const double lead = options.protocol == Protocol::adaptive ? h : 0.0;
    if (automatic && res.slip_events == 0 && first_max_Dx >= 0.0 &&
        state.Dx >= first_max_Dx + lead + d - 1e-12) {
      res.stop_reason = "one period past the first maximum (no slip)";
      break;
    }
  }

  // mu and its resolution. Before a slip the peak is the last stable state: the instability
  // lies within one step after it, and mu is resolved to that step times the slope. A smooth
  // maximum (Regime I) is refined, in the adaptive protocol, by parabolic search on Dx in the
  // bracket of its neighbours (each point relaxed from the peak state); the reference protocol
  // keeps the classic sampled maximum, and reports the parabola's excess as its precision.
  // A maximum at the very end of the trace cannot be refined; if it only repeats an earlier one
  // within the minimiser's noise (Regime I a period later; 1e-6 relative is seen), the earlier
  // one, which has samples on both sides, is the peak.
  // (Not when the runner-up is the sample just before: that is a ramp, cut off by the distance.)
  // A stop requested during the refinement below returns this state: a resumed slide redoes
  // the refinement from it.
  // (Without the snapshots, which can be large and which the refinement leaves alone: they are
  // added back if the state is used.)
  std::optional<SlideState> stepping_end;
  if (control.stop_requested) {
    std::vector<Snapshot> snapshots = std::move(res.snapshots);
    res.snapshots.clear();
    stepping_end = capture(true);
    res.snapshots = std::move(snapshots);
  }
  const std::size_t n_rows = res.trace.size();
  if (runner_up && n_rows >= 2 && peak->Dx == res.trace.back().Dx &&
      runner_up->Dx < res.trace[n_rows - 2].Dx && best <= runner_up_ratio * (1.0 + 1e-4)) {
    peak = std::move(runner_up);
    best = runner_up_ratio;
  }
  // Still rising at the last sample (cap or a fixed distance hit on the loading ramp): the
  // static peak lies further on, mu is only a lower bound.
  res.mu_is_lower_bound = peak->Dx == res.trace.back().Dx;
  res.mu = best;
  res.peak_Dx = peak->Dx;
  res.Fz = peak->Fz;
  const auto at_peak = std::find_if(res.trace.begin(), res.trace.end(),
                                    [&](const TraceRow& row) { return row.Dx == peak->Dx; });
  const auto ratio = [](const TraceRow& row) { return row.Fx / row.Fz; };
  if (at_peak != res.trace.begin() && at_peak != res.trace.end() &&
      at_peak + 1 != res.trace.end()) {
    const auto prev = at_peak - 1, next = at_peak + 1;
    if (next->slip) {
      res.peak_precision = (next->Dx - at_peak->Dx) *
                           std::abs((ratio(*at_peak) - ratio(*prev)) / (at_peak->Dx - prev->Dx));
    } else {
      double x0 = prev->Dx, x1 = at_peak->Dx, x2 = next->Dx;
      double y0 = ratio(*prev), y1 = ratio(*at_peak), y2 = ratio(*next);
      const auto vertex = [&](double& yv) {
        const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
        const double curv = (d12 - d01) / (x2 - x0);
        const double xv = 0.5 * (x0 + x1) - d01 / (2.0 * curv);
        yv = y1 + (xv - x1) * (d01 + curv * (xv - x0));  // Newton form through the 3 points
        return curv < 0.0 ? xv : x1;
      };
      double yv = y1;
      double xv = vertex(yv);
      res.peak_precision = std::max(0.0, yv - y1);
      for (int k = 0;
           k < 30 && options.protocol == Protocol::adaptive && x2 - x0 > 2.0 * options.min_step;
           ++k) {
        xv = std::clamp(vertex(yv), x0 + 0.25 * options.min_step, x2 - 0.25 * options.min_step);
        if (std::abs(xv - x1) < 0.25 * options.min_step) {
          xv = x1 + (x2 - x1 > x1 - x0 ? 0.5 : -0.5) * options.min_step;
        }
        if (stop_requested()) {
          stepping_end->partial.snapshots = std::move(res.snapshots);
          return interrupt(*stepping_end);
        }
        State probe = *peak;
        const auto r = slider.relax(probe, xv, nullptr);
        count(r);
        if (const std::string why = failure(r, probe, xv, peak->Dx); !why.empty()) {
          res.failed = true;
          res.stop_reason = "refining the peak: " + why;
          break;
        }
        const bool off_branch = slider.slipped_sites(*peak, probe) > 0;
        const double y =
            off_branch ? -std::numeric_limits<double>::infinity() : probe.Fx / probe.Fz;
        if (y > y1) {
          (xv < x1 ? x2 : x0) = x1;
          (xv < x1 ? y2 : y0) = y1;
          x1 = xv;
          y1 = y;
          peak = probe;
        } else {
          (xv < x1 ? x0 : x2) = xv;
          (xv < x1 ? y0 : y2) = y;
        }
        if (!std::isfinite(y0) || !std::isfinite(y2)) break;
        vertex(yv);
        res.peak_precision = std::max(0.0, yv - y1);
        if (res.peak_precision < 1e-9 * std::abs(y1)) break;
      }
      res.mu = std::max(best, y1);
      res.peak_Dx = x1;
      res.Fz = peak->Fz;
    }
  }
  res.mu_over_alpha = res.mu / scene.alpha;
  res.distance = state.Dx;
  const auto first_slip = std::find_if(res.trace.begin(), res.trace.end(),
                                       [](const TraceRow& row) { return row.slip; });
  // Kinetic friction: the mean of Fx/Fz over Dx (trapezoid: adaptive steps are uneven) after
  // the first slip; without slips (smooth sliding) over the last whole period d.
  auto from = first_slip;
  if (from == res.trace.end() && state.Dx >= d) {
    from = std::find_if(res.trace.begin(), res.trace.end(),
                        [&](const TraceRow& row) { return row.Dx >= state.Dx - d - 1e-12; });
  }
  res.kinetic = res.kinetic_over_static = std::numeric_limits<double>::quiet_NaN();
  if (from != res.trace.end()) {
    double area = 0.0, span = 0.0;
    for (auto a = from; a + 1 != res.trace.end(); ++a) {
      const double w = (a + 1)->Dx - a->Dx;
      area += 0.5 * w * (a->Fx / a->Fz + (a + 1)->Fx / (a + 1)->Fz);
      span += w;
    }
    res.kinetic = span > 0.0 ? area / span : from->Fx / from->Fz;
    res.kinetic_over_static = res.kinetic / res.mu;
  }
  res.snapshots.insert(res.snapshots.begin(), slider.snapshot(*peak, "peak"));
  res.gf_applications = gf_before + slider.gf().applications();
  res.wall_s = wall_before + elapsed();
  return res;
}

}  // namespace asperity::slide
