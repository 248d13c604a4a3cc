// Quasi-static sliding of the lateral force model; protocols and criteria in slider.hpp.
#include "asperity/core/slide/slider.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "asperity/core/common/validate.hpp"
#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/slide/lfm_problem.hpp"
#include "asperity/core/slide/protocol.hpp"

namespace asperity::slide {

namespace {

// Half-width of the block of unknowns (sites): the contact radius plus two sites of margin.
int block_half(const interface::ContactScene& scene) {
  return static_cast<int>(std::ceil(scene.a / scene.d)) + 2;
}

// The state of the slide: full-block force and displacement fields (component-major) at a
// tip position, with the block offset (in lattice steps) that follows the tip.
using State = SlideFields;

class Slider {
 public:
  Slider(const interface::ContactScene& scene, const SlideOptions& options)
      : scene_(scene),
        options_(options),
        half_(block_half(scene)),
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

  // Called by relax() every 16 minimiser iterations with the iteration (the protocol's progress
  // reports and stop requests); returning true abandons the relaxation (Termination::interrupted,
  // the state half relaxed). Empty: not called.
  std::function<bool(int)> heartbeat;

  State initial() {
    State s;
    s.f.assign(gf_.size(), 0.0);
    s.u.assign(gf_.size(), 0.0);
    return s;
  }

  // Moves `s` to tip position Dx and relaxes it. Path frames go to `frames` if given. With
  // `pausing` (the slip minimiser's flow, protocol.hpp) the flow may pause, and with
  // pausing->from it continues a pause of the same relaxation of the same `s` (its pair replaces
  // the one `s` would start from).
  minimize::MinimizeResult relax(State& s, double Dx, std::vector<PathFrame>* frames,
                                 bool stop_on_slip = false,
                                 const minimize::MinimizerOptions* solver = nullptr,
                                 detail::RelaxPausing* pausing = nullptr) {
    const minimize::FlowPause* from = pausing ? pausing->from : nullptr;
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
    // Continuing a pause, the pair is the pause's and this application was counted before it;
    // it is still made for the displacement off the contact (path frames carry it).
    if (from) ++uncounted_gf_;
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size();
    std::vector<double> u(2 * m), f(2 * m);
    gather(s.u, u);
    gather(s.f, f);
    // A trial step that is to be undone if it slips is stopped as soon as a site has moved by
    // 3/4 d: the slip is certain, and relaxing it fully would be wasted. Not less (the former
    // slip test was d/2): the path of a relaxation may overshoot (seen after a 0.4 d step with
    // the interface filter, which ended without a slip), and a false alarm costs a bisection.
    // A core gliding by a spacing moves no site that far: such a trial is relaxed fully and
    // the slip test on the relaxed state (registry_jumps) catches it.
    const std::vector<double> u_start = u;
    const bool record = frames != nullptr && options_.path_frame_every > 0;
    minimize::Observer observer;
    // A long relaxation keeps at most max_path_frames frames: when full, every other frame is
    // dropped and the interval doubles, so the frames stay evenly spread over the relaxation.
    int own_interval = options_.path_frame_every;
    int& interval = pausing ? pausing->frame_interval : own_interval;
    if (interval <= 0) interval = options_.path_frame_every;
    if (record || stop_on_slip || heartbeat) {
      observer = [&](int it, std::span<const double> uu, std::span<const double> ff) {
        if (heartbeat && it % 16 == 0 && heartbeat(it)) return true;
        if (record && it % interval == 0) {
          if (static_cast<int>(frames->size()) >= options_.max_path_frames) {
            std::size_t keep = 0;
            for (std::size_t k = 1; k < frames->size(); k += 2)
              (*frames)[keep++] = std::move((*frames)[k]);
            frames->resize(keep);
            interval *= 2;
          }
          if (it % interval == 0) {
            // The displacement only (the snapshot follows from it); off the contact it is the
            // start state's.
            PathFrame frame{.iteration = it,
                            .fields = {.Dx = s.Dx, .shift = s.shift, .f = {}, .u = s.u}};
            scatter(uu, frame.fields.u);
            std::vector<double> fint(uu.size());
            const double v = lfm_.energy_and_force(uu, fint);
            double fu = 0.0;
            for (std::size_t j = 0; j < m; ++j)
              frame.fields.Fx += fint[j];
            for (std::size_t j = 0; j < uu.size(); ++j)
              fu += ff[j] * uu[j];
            frame.fields.Fz = lfm_.load();
            frame.fields.area = lfm_.area();
            frame.fields.energy = 0.5 * fu + v;
            frames->push_back(std::move(frame));
          }
        }
        if (!stop_on_slip) return false;
        for (std::size_t j = 0; j < m; ++j) {
          if (std::abs(uu[j] - u_start[j]) > 0.75 * scene_.d) {
            return true;
          }
        }
        return false;
      };
    }
    const auto r = minimize::minimize(problem_, u, f, solver ? *solver : options_.minimizer,
                                      observer, from, pausing ? &pausing->pauses : nullptr);
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
    s.area = lfm_.area();
    double fu = 0.0;
    for (std::size_t j = 0; j < 2 * m; ++j)
      fu += f[j] * u[j];
    s.energy = 0.5 * fu + v;
    return r;
  }

  // Brings a state's fields onto the block alignment of `like` (no GF application: f only).
  void align(State& s, const State& like) const {
    if (s.shift != like.shift) roll_fields(s, like.shift - s.shift);
  }
  // The rest of the model interface of protocol.hpp.
  [[nodiscard]] std::size_t field_size() const { return gf_.size(); }
  [[nodiscard]] std::string check_fields(const State& s) const {
    // |shift| bounded so that rolling a start state cannot overflow the index arithmetic.
    constexpr int kMaxShift = 1 << 20;
    if (s.f.size() == field_size() && s.u.size() == field_size() && std::abs(s.shift) <= kMaxShift)
      return {};
    return std::to_string(field_size()) +
           " (2 per site of this scene's block), |shift| <= " + std::to_string(kMaxShift);
  }
  [[nodiscard]] std::size_t contact_sites() const { return lfm_.contact_sites().size(); }
  [[nodiscard]] std::size_t gf_applications() const { return gf_.applications() - uncounted_gf_; }
  [[nodiscard]] Shape2 block_shape() const { return gf_.region(); }
  [[nodiscard]] Shape2 fft_grid() const { return gf_.fft_shape(); }

  // How far `later` is from `earlier` carried on by whole periods: the largest difference of a
  // block site's force (G d^2), when the tip is k d further on and the block k rows further
  // (the block follows the tip, so site i is at the same place relative to the tip); +inf
  // otherwise. The registry potential has period d and the Hertz envelope moves with the tip
  // (MODEL.md 3), so equal forces mean the same state of the interface one period on (the
  // displacements follow from the forces, u = G f).
  [[nodiscard]] double period_mismatch(const State& later, const State& earlier) const {
    const int k = later.shift - earlier.shift;
    if (k < 1 || later.f.size() != earlier.f.size() ||
        std::abs(later.Dx - earlier.Dx - k * scene_.d) > 1e-9 * scene_.d) {
      return std::numeric_limits<double>::infinity();
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < later.f.size(); ++i)
      worst = std::max(worst, std::abs(later.f[i] - earlier.f[i]));
    return worst;
  }

  // Sites that slipped between `before` and `after` (MODEL.md 5): a site slipped if its
  // registry index (round(s_x / d), round(s_y / d), s = X + u - (Dx, 0)) changed while it was
  // in the contact at both tip positions, by a jump: its displacement changed by at least d/4
  // in that component. An instability takes a site from one well to the next; a gliding core
  // moves its sites across a half-period by less than d/2 (0.3-0.44 d at b_core = 1.87 d, by
  // profile), which the
  // former test (|du| > d/2) missed. The d/4 floor keeps out the smooth crossings that are not
  // instabilities: weakly pinned edge sites creeping over their barriers (measured: up to 54
  // sites moving 0.02-0.03 d per adaptive step before a slip at a = 43 d, R = 535 d) and, in
  // Regime I, the whole contact sliding smoothly over the barrier top. A smooth crossing large
  // enough to pass the floor at a coarse step is undone and bisected by the adaptive protocol;
  // its displacement shrinks with the step, a jump's does not.
  int slipped_sites(const State& before, const State& after) const {
    State b = before;
    const int k = after.shift - b.shift;
    if (k != 0) roll_fields(b, k);
    // Rows that entered the block with the roll have no displacement in `before`.
    const int entered_rows = std::max(k, 0);
    return registry_jumps(scene_, block_at(after.shift), b.Dx, b.u, after.Dx, after.u,
                          entered_rows);
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
    snap.tip = scene_.tip;
    const double k = 2.0 * std::numbers::pi / scene_.d;
    const interface::TipFrame& frame = lfm_.tip_frame();
    for (std::size_t i = 0; i < n; ++i) {
      snap.sx[i] = lfm_.sx(i, snap.ux[i]);
      snap.sy[i] = lfm_.sy(i, snap.uy[i]);
      if (snap.tau_max[i] > 0.0) {
        snap.in_contact[i] = 1;
        if (frame.aligned()) {
          snap.tau_x[i] = -snap.tau_max[i] * std::sin(k * snap.sx[i]);
          snap.tau_y[i] = -snap.tau_max[i] * std::sin(k * snap.sy[i]);
        } else {
          // f / d^2 = -tau_max Q(theta) [sin(2 pi rho1), sin(2 pi rho2)] (tip_lattice.hpp).
          double rho1 = 0.0, rho2 = 0.0;
          frame.registry(snap.sx[i], snap.sy[i], rho1, rho2);
          frame.to_substrate(-snap.tau_max[i] * std::sin(2.0 * std::numbers::pi * rho1),
                             -snap.tau_max[i] * std::sin(2.0 * std::numbers::pi * rho2),
                             snap.tau_x[i], snap.tau_y[i]);
        }
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
  std::size_t uncounted_gf_ = 0;  // GF applications repeated by continued pauses
};
static_assert(detail::SlideModel<Slider>);

}  // namespace

std::string to_string(Protocol p) {
  return p == Protocol::reference ? "reference" : "adaptive";
}

Protocol protocol_from_string(const std::string& name) {
  if (name == "reference") return Protocol::reference;
  if (name == "adaptive") return Protocol::adaptive;
  throw std::invalid_argument("slide protocol: got '" + name + "', allowed: reference, adaptive");
}

minimize::MinimizerOptions slip_minimizer_from(const minimize::MinimizerOptions& base,
                                               minimize::Method method,
                                               minimize::Preconditioner preconditioner) {
  minimize::MinimizerOptions m = base;
  m.method = method;
  m.preconditioner = preconditioner;
  m.max_iterations = std::max(base.max_iterations, 2'000'000);
  return m;
}

minimize::MinimizerOptions slide_minimizer_defaults() {
  minimize::MinimizerOptions m;
  m.force_tolerance = 1e-5;
  m.max_displacement = 0.2;
  return m;
}

const settings::Table<SlideOptions>& SlideOptions::settings() {
  using R = settings::Range;
  using O = SlideOptions;
  static const settings::Table<O> table = [] {
    settings::Table<O> t = {
        settings::choice<O>(
            "slide.protocol", [](auto& o) -> auto& { return o.protocol; },
            {"adaptive", "reference"}, [](Protocol p) { return to_string(p); },
            protocol_from_string, "adaptive | reference (fixed steps)", "--protocol"),
        settings::number<O>(
            "slide.step", [](auto& o) -> auto& { return o.step; }, R::open(0.0, 0.5), "d",
            "reference protocol: tip step"),
        // Half a period or more would alias the registry potential: a step of d/2 lands every
        // atom on the symmetric point of its well, where the forces balance by symmetry.
        settings::number<O>(
            "slide.max_step", [](auto& o) -> auto& { return o.max_step; }, R::open(0.0, 0.5), "d",
            "adaptive protocol: largest step"),
        settings::number<O>(
            "slide.min_step", [](auto& o) -> auto& { return o.min_step; }, R::open_closed(0.0, 0.5),
            "d", "adaptive protocol: instabilities bracketed to this (<= slide.max_step)"),
        settings::number<O>(
            "slide.distance", [](auto& o) -> auto& { return o.distance; }, R::non_negative(), "d",
            "sliding distance; 0: automatic (until the static peak is established)", "--distance"),
        settings::number<O>(
            "slide.max_distance", [](auto& o) -> auto& { return o.max_distance; },
            R::non_negative(), "d", "cap of the automatic distance; 0: 3 d + 3 alpha Fz / k"),
        settings::integer<O>(
            "slide.slips_to_stop", [](auto& o) -> auto& { return o.slips_to_stop; },
            R::closed(1, 1000), "", "automatic distance: slip events after the held peak"),
        settings::integer<O>(
            "slide.max_slips", [](auto& o) -> auto& { return o.max_slips; }, R::closed(0, 1000000),
            "",
            "stop at this slip event whatever the distance, mu then a lower bound (0: no limit)",
            "--max-slips"),
        settings::boolean<O>(
            "slide.extrapolate", [](auto& o) -> auto& { return o.extrapolate; },
            "warm start each step by linear extrapolation along the branch"),
        settings::boolean<O>(
            "slide.replay_cycle", [](auto& o) -> auto& { return o.replay_cycle; },
            "replay the stick-slip cycle once it repeats exactly (adaptive protocol)"),
        // Unbounded, it would take any state for a repeat and replay slides that never repeat.
        settings::number<O>(
            "slide.cycle_tolerance", [](auto& o) -> auto& { return o.cycle_tolerance; },
            R::positive(), "G d^2", "largest force difference of a site for equal states"),
        settings::neutral(settings::integer<O>(
            "slide.path_frame_every", [](auto& o) -> auto& { return o.path_frame_every; },
            R::closed(0, 1000000), "",
            "relaxation-path frames through slip events every N iterations (0: none)")),
        settings::neutral(settings::integer<O>(
            "output.path_frames", [](auto& o) -> auto& { return o.path_frame_slips; },
            R::closed(0, 1000000), "",
            "paths of slip events 1, 1 + N, 1 + 2N, ... are recorded (0: none)")),
        settings::neutral(settings::integer<O>(
            "output.max_path_frames", [](auto& o) -> auto& { return o.max_path_frames; },
            R::closed(2, 100000), "", "frames kept per recorded path"))};
    settings::lift(
        t, minimize::MinimizerOptions::settings(), "solver.",
        [](auto& o) -> auto& { return o.minimizer; });
    settings::lift(
        t, fft::FFTOptions::settings(), "fft.", [](auto& o) -> auto& { return o.fft; });
    return t;
  }();
  return table;
}

void SlideOptions::validate() const {
  settings::validate(*this, settings());
  if (!(min_step <= max_step)) {
    throw std::invalid_argument(
        "slide.min_step = " + settings::format_number(min_step) +
        ": allowed: <= slide.max_step = " + settings::format_number(max_step));
  }
  if (slip_minimizer) slip_minimizer->validate();
}

void SlideControl::validate() const {
  if (!(checkpoint_every_s >= 0.0) || !std::isfinite(checkpoint_every_s)) {
    reject("SlideControl.checkpoint_every_s", std::to_string(checkpoint_every_s),
           "finite and >= 0 (0: after every step)");
  }
}

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
  Slider slider(scene, options);
  // The loading ramp to the Regime I force, F_I / k (alpha Fz / k for the Hertz envelope).
  const double ramp = scene.regime_one_force() / scene.lateral_stiffness();
  const detail::ProtocolParams params{
      .d = scene.d,
      .alpha = scene.alpha,
      .Fz_continuum = scene.load(),
      .default_cap = 3.0 * scene.d + 3.0 * ramp,
      .measure = scene.carries_load() ? FrictionMeasure::load : FrictionMeasure::area};
  return detail::run_protocol(slider, params, options, control, t0);
}

double friction_over_regime_one(const interface::ContactScene& scene, const SlideResult& r) {
  const double Fx = r.measure == FrictionMeasure::load ? r.mu * r.Fz : r.tau_fric * r.area;
  const double capacity = scene.regime_one_force(r.Fz, r.area);
  return capacity > 0.0 ? Fx / capacity : std::numeric_limits<double>::quiet_NaN();
}

int registry_jumps(const interface::ContactScene& scene, const LatticeBlock& block,
                   double Dx_before, std::span<const double> u_before, double Dx_after,
                   std::span<const double> u_after, int entered_rows) {
  const std::size_t n = block.shape.count();
  if (u_before.size() != 2 * n || u_after.size() != 2 * n) {
    throw std::invalid_argument("registry_jumps: fields of " + std::to_string(u_before.size()) +
                                " and " + std::to_string(u_after.size()) + " values for " +
                                std::to_string(2 * n) + " (2 per block site)");
  }
  interface::LateralForceModel at_after(scene, block), at_before = at_after;
  at_after.set_tip(Dx_after);
  at_before.set_tip(Dx_before);
  const double d = scene.d;
  const auto jumped = [&](double s_before, double s_after, double du) {
    return std::lround(s_before / d) != std::lround(s_after / d) && std::abs(du) >= 0.25 * d;
  };
  // Out of registry the index is round(rho) per tip axis (tip_lattice.hpp) and the jump the
  // displacement along that axis.
  const interface::TipFrame& frame = at_after.tip_frame();
  const auto jumped_tip = [&](std::size_t i) {
    double b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0, du1 = 0.0, du2 = 0.0;
    at_before.registry(i, u_before[i], u_before[n + i], b1, b2);
    at_after.registry(i, u_after[i], u_after[n + i], a1, a2);
    frame.to_tip(u_after[i] - u_before[i], u_after[n + i] - u_before[n + i], du1, du2);
    return (std::lround(b1) != std::lround(a1) && std::abs(du1) >= 0.25 * d) ||
           (std::lround(b2) != std::lround(a2) && std::abs(du2) >= 0.25 * d);
  };
  const std::size_t first_new_row =
      static_cast<std::size_t>(block.shape.n0 - std::clamp(entered_rows, 0, block.shape.n0));
  int count = 0;
  for (std::size_t i : at_after.contact_sites()) {
    if (i / static_cast<std::size_t>(block.shape.n1) >= first_new_row) continue;
    if (at_before.tau_max()[i] <= 0.0) continue;  // entered the contact in this step
    if (!frame.aligned()) {
      if (jumped_tip(i)) ++count;
      continue;
    }
    if (jumped(at_before.sx(i, u_before[i]), at_after.sx(i, u_after[i]),
               u_after[i] - u_before[i]) ||
        jumped(at_before.sy(i, u_before[n + i]), at_after.sy(i, u_after[n + i]),
               u_after[n + i] - u_before[n + i])) {
      ++count;
    }
  }
  return count;
}

Snapshot snapshot_of(const interface::ContactScene& scene, const SlideFields& state,
                     std::string label) {
  scene.validate();
  Slider model(scene, SlideOptions{});
  if (const std::string why = model.check_fields(state); !why.empty()) {
    throw std::invalid_argument("snapshot_of: the state's fields do not fit this scene: " +
                                std::to_string(state.u.size()) + " values, allowed: " + why);
  }
  return model.snapshot(state, std::move(label));
}

StepRelaxation relax_step(const interface::ContactScene& scene, const SlideOptions& options,
                          const SlideFields& from, double Dx) {
  scene.validate();
  options.validate();
  Slider model(scene, options);
  if (const std::string why = model.check_fields(from); !why.empty()) {
    throw std::invalid_argument("relax_step: the start state's fields do not fit this scene: " +
                                std::to_string(from.f.size()) + " values, allowed: " + why);
  }
  StepRelaxation out;
  out.state = from;
  const std::size_t gf0 = model.gf_applications();
  const auto t0 = std::chrono::steady_clock::now();
  out.result = model.relax(out.state, Dx, nullptr);
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.result.gf_applications = model.gf_applications() - gf0;
  out.slipped_sites = model.slipped_sites(from, out.state);
  return out;
}

int block_side(const interface::ContactScene& scene) {
  return 2 * block_half(scene) + 1;
}

double estimated_slide_bytes(const interface::ContactScene& scene, const SlideOptions& options) {
  const double n = block_side(scene);
  // Past int range next_fft_size cannot answer; 2n - 1 is then close enough for a refusal.
  const double grid =
      2.0 * n - 1.0 < 1e9 ? next_fft_size(static_cast<int>(2.0 * n - 1.0)) : 2.0 * n - 1.0;
  const double path = options.path_frame_every > 0 && options.path_frame_slips > 0
                          ? options.max_path_frames * 16.0
                          : 0.0;
  // The minimiser's vectors on the contact sites (about pi a^2 of them, 2 values each): the
  // L-BFGS pairs (s, y and the force change) and some 18 working vectors (the point and the
  // line-search trial with their residuals, the direction and its K-image, the two-loop's
  // scratch, the filter's, the CG and FIRE state). Without them the estimate was 22% below
  // the measured peak at a = 430 d, R = 1700 d (2.04 against 2.6 GB).
  const double contact = std::numbers::pi * scene.a * scene.a / (scene.d * scene.d);
  const double minimiser = (3.0 * options.minimizer.memory + 18.0) * 16.0 * contact;
  // A checkpoint inside the slip minimiser's flow (PendingSlip) holds the pair, its velocity
  // and the power vector (5 vectors on the contact sites) and the path frames so far. Besides
  // the live ones, each exists four more times at the worst moment: the vectors in the pause,
  // the state handed over and the tool's encoding of it (its JSON document and CBOR bytes); the
  // frames in the state, the encoding and, in a resumed run, the decoded start state, which is
  // kept for the whole slide.
  const bool pauses =
      options.slip_minimizer && options.slip_minimizer->method == minimize::Method::flow;
  const double pending = pauses ? 4.0 * 5.0 * 16.0 * contact + 4.0 * path * n * n : 0.0;
  // The program and its libraries (36 MB resident before the first relaxation of a = 50 d).
  constexpr double kProcess = 32e6;
  return kProcess + 260.0 * grid * grid + minimiser + pending +
         (2.0 * static_cast<double>(kCycleWindow) * 32.0 + path + 2.0 * 65.0) * n * n;
}

}  // namespace asperity::slide
