// Sliding of the explicit model at fixed Fz (MODEL.md 4 and 5): the model side of
// slide/protocol.hpp; design in explicit_slide.hpp.
#include "asperity/core/explicit/explicit_slide.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "asperity/core/common/validate.hpp"
#include "asperity/core/slide/protocol.hpp"

namespace asperity::explicit_model {

void ExplicitSlideOptions::validate() const {
  require_positive("ExplicitSlideOptions.load", load);
  require_positive("ExplicitSlideOptions.load_tolerance", load_tolerance);
  require_at_least("ExplicitSlideOptions.max_load_steps", max_load_steps, 1);
  if (!(margin >= 1.0) || !std::isfinite(margin)) {
    reject("ExplicitSlideOptions.margin", std::to_string(margin), "finite and >= 1 d");
  }
  require_at_least("ExplicitSlideOptions.max_growths", max_growths, 0);
  require_positive("ExplicitSlideOptions.alpha", alpha);
}

namespace {

using State = slide::SlideFields;

// Largest block side a state may have (a start state's check): 16384^2 sites are 800 M
// unknowns, beyond any memory this runs on.
constexpr std::size_t kMaxBlockSide = 1u << 14;
// Largest block shift (lattice steps along x) a start state may have: 1e6 d of sliding, far
// beyond any slide, and far from overflowing the block index arithmetic.
constexpr int kMaxShift = 1 << 20;

// The block a state's fields live on: square, (2 half + 1)^2 sites (3 components), centred on
// the lattice column `shift` along x and on y = 0 (ExplicitContact's blocks).
LatticeBlock block_of(const State& s) {
  const auto side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(s.f.size() / 3))));
  const int half = (side - 1) / 2;
  return LatticeBlock{Shape2{side, side}, s.shift - half, -half};
}

// Copies the `comps`-component field `src` on block `from` onto block `to` by lattice index;
// sites of `to` outside `from` get 0.
std::vector<double> map_field(const LatticeBlock& from, const std::vector<double>& src,
                              const LatticeBlock& to, int comps) {
  const std::size_t nf = from.shape.count(), nt = to.shape.count();
  std::vector<double> dst(static_cast<std::size_t>(comps) * nt, 0.0);
  for (int i0 = 0; i0 < to.shape.n0; ++i0) {
    const int j0 = to.origin0 + i0 - from.origin0;
    if (j0 < 0 || j0 >= from.shape.n0) continue;
    for (int i1 = 0; i1 < to.shape.n1; ++i1) {
      const int j1 = to.origin1 + i1 - from.origin1;
      if (j1 < 0 || j1 >= from.shape.n1) continue;
      const std::size_t a = to.shape.index(i0, i1), b = from.shape.index(j0, j1);
      for (std::size_t c = 0; c < static_cast<std::size_t>(comps); ++c)
        dst[c * nt + a] = src[c * nf + b];
    }
  }
  return dst;
}

class ExplicitSlider {
 public:
  ExplicitSlider(const ExplicitScene& scene, const ExplicitSlideOptions& eo,
                 const slide::SlideOptions& options)
      : scene_(scene),
        eo_(eo),
        options_(options),
        hertz_(contact::Hertz::from_load(scene.material, scene.R, eo.load)),
        contact_(scene, options.fft),
        hertz_slope_(-2.0 * hertz_.a * hertz_.estar),
        snap_half_(static_cast<int>(std::ceil(hertz_.a / scene.d + eo.margin)) + 2) {}

  // The Hertz state at the target load: the first relax() (Dx = 0) brings it to the LJ contact.
  State initial() {
    contact_.set_active_radius(hertz_.a + eo_.margin);
    contact_.start_from_hertz(eo_.load);
    State s;
    capture(s);
    return s;
  }

  minimize::MinimizeResult relax(State& s, double Dx, std::vector<slide::PathFrame>* /*frames*/,
                                 bool stop_on_slip = false,
                                 const minimize::MinimizerOptions* solver = nullptr) {
    const double d = scene_.d;
    // The active disk starts each step at the Hertz radius + margin (the atoms that carry a
    // force stay active anyway): a disk grown by a transient of an earlier step would otherwise
    // stay, and cost, for the rest of the slide.
    contact_.clear_forces();
    contact_.place(Dx, s.h, start_radius(s, Dx));
    contact_.set_forces(map_field(block_of(s), s.f, contact_.block(), 3));
    // Slip watch: x displacement at the start, by lattice index. This only stops a trial early
    // (an atom moved by d/2: a slip is likely, the slip minimiser or the bisection takes it from
    // there); whether a step slipped is slipped_sites()'s verdict on the end state.
    const LatticeBlock start_block = contact_.block();
    const std::vector<double> start_ux(
        contact_.displacements().begin(),
        contact_.displacements().begin() + static_cast<std::ptrdiff_t>(start_block.shape.count()));
    minimize::Observer observer;
    if (stop_on_slip) {
      observer = [&](int, std::span<const double> u, std::span<const double>) {
        const auto& sites = contact_.active_site_list();
        const LatticeBlock& b = contact_.block();
        const auto n1 = static_cast<std::size_t>(b.shape.n1);
        for (std::size_t j = 0; j < sites.size(); ++j) {
          const int j0 = b.origin0 + static_cast<int>(sites[j] / n1) - start_block.origin0;
          const int j1 = b.origin1 + static_cast<int>(sites[j] % n1) - start_block.origin1;
          if (j0 < 0 || j0 >= start_block.shape.n0 || j1 < 0 || j1 >= start_block.shape.n1)
            continue;
          if (std::abs(u[j] - start_ux[start_block.shape.index(j0, j1)]) > 0.5 * d) return true;
        }
        return false;
      };
    }
    minimize::MinimizeResult total;
    const std::size_t gf0 = contact_.gf_applications();
    // Fz(h) falls as the tip rises. Secant steps from the last two heights until the target is
    // bracketed, then regula falsi in the bracket [h_low (Fz above target), h_high (below)]
    // with the Illinois halving: Fz(h) is flat (zero) where the tip has lifted off, which the
    // plain secant cannot leave.
    double h_prev = 0.0, load_prev = 0.0;
    bool have_prev = false;
    double h_low = -std::numeric_limits<double>::infinity(), g_low = 0.0;
    double h_high = std::numeric_limits<double>::infinity(), g_high = 0.0;
    int last_side = 0;
    double lift_step = 0.01 * d;
    // dFz/dh: the last secant of the state's branch, else the Hertz contact stiffness -2 a E*.
    // It travels with the state (not the model), so that a slide resumed from a checkpoint
    // takes the same load steps as the uninterrupted one.
    double slope = s.dFz_dh < 0.0 ? s.dFz_dh : hertz_slope_;
    // The branch of the previous load step (block and x displacements): a relaxation at a new
    // h can end on another branch (an atom moved to the next hollow of the tip). Fz(h) then
    // jumps, and heights and loads seen on the old branch bracket nothing on the new one.
    LatticeBlock branch_block = contact_.block();
    std::vector<double> branch_ux = x_displacements();
    total.termination = Termination::max_iterations;
    for (int step = 0; step < eo_.max_load_steps; ++step) {
      const auto r = contact_.relax(solver ? *solver : options_.minimizer, eo_.margin,
                                    eo_.max_growths, nullptr, observer);
      total.iterations += r.iterations;
      total.interface_evaluations += r.interface_evaluations;
      total.escapes += r.escapes;
      total.energy = r.energy;
      total.max_force = r.max_force;
      total.stability_checked = total.stability_checked || r.stability_checked;
      total.termination = r.termination;
      if (r.termination != Termination::converged) break;
      const double fz = contact_.load(), h = contact_.h();
      const double g = fz - eo_.load;  // > 0: the tip presses too hard
      if (std::abs(g) <= eo_.load_tolerance * eo_.load) break;
      total.termination = Termination::max_iterations;
      if (left_branch(branch_block, branch_ux)) {
        h_low = -std::numeric_limits<double>::infinity();
        h_high = std::numeric_limits<double>::infinity();
        last_side = 0;
        have_prev = false;
      }
      branch_block = contact_.block();
      branch_ux = x_displacements();
      const int side = g > 0.0 ? -1 : 1;
      if (side < 0) {
        h_low = h, g_low = g;
        if (last_side < 0) g_high *= 0.5;  // Illinois
      } else {
        h_high = h, g_high = g;
        if (last_side > 0) g_low *= 0.5;
      }
      last_side = side;
      if (have_prev && fz != load_prev && h != h_prev) {
        const double secant = (fz - load_prev) / (h - h_prev);
        if (secant < 0.0) slope = secant;
      }
      h_prev = h, load_prev = fz, have_prev = true;
      double next = h + std::clamp(-g / slope, -0.25 * d, 0.25 * d);
      if (fz == 0.0) {
        // Lifted off: the slope says nothing; come down by doubling steps.
        next = h - lift_step;
        lift_step *= 2.0;
      }
      if (std::isfinite(h_low) && std::isfinite(h_high)) {
        next = h_low + g_low * (h_high - h_low) / (g_low - g_high);
      }
      contact_.set_tip(Dx, next);
    }
    total.gf_applications = contact_.gf_applications() - gf0;
    capture(s);
    s.dFz_dh = slope;
    return total;
  }

  // Active radius a relaxation from `s` to Dx starts with: the Hertz radius + margin, or, if
  // larger, the farthest atom that carries a force in `s` + d, so that the warm start keeps
  // every force of the state (a function of the state alone: a resumed slide builds the same
  // block). The growth check of relax() adds the margin where it is needed.
  [[nodiscard]] double start_radius(const State& s, double Dx) const {
    double farthest = 0.0;
    const LatticeBlock b = block_of(s);
    const std::size_t n = b.shape.count();
    for (int i0 = 0; i0 < b.shape.n0; ++i0) {
      for (int i1 = 0; i1 < b.shape.n1; ++i1) {
        const std::size_t i = b.shape.index(i0, i1);
        if (s.f[i] == 0.0 && s.f[n + i] == 0.0 && s.f[2 * n + i] == 0.0) continue;
        farthest = std::max(farthest, std::hypot(b.x(i0, scene_.d) - Dx, b.y(i1, scene_.d)));
      }
    }
    return std::max(hertz_.a + eo_.margin, farthest + scene_.d);
  }

  // x displacements of the current block (the first component).
  [[nodiscard]] std::vector<double> x_displacements() const {
    const auto& u = contact_.displacements();
    return {u.begin(), u.begin() + static_cast<std::ptrdiff_t>(contact_.block().shape.count())};
  }

  // Whether an atom of the current state has moved by more than d/2 in x against `ux` on
  // `block` (by lattice index): the state left that branch.
  [[nodiscard]] bool left_branch(const LatticeBlock& block, const std::vector<double>& ux) const {
    const LatticeBlock& b = contact_.block();
    const auto& now = contact_.displacements();  // x components first, on block b
    for (int i0 = 0; i0 < block.shape.n0; ++i0) {
      const int j0 = block.origin0 + i0 - b.origin0;
      if (j0 < 0 || j0 >= b.shape.n0) continue;
      for (int i1 = 0; i1 < block.shape.n1; ++i1) {
        const int j1 = block.origin1 + i1 - b.origin1;
        if (j1 < 0 || j1 >= b.shape.n1) continue;
        if (std::abs(now[b.shape.index(j0, j1)] - ux[block.shape.index(i0, i1)]) > 0.5 * scene_.d)
          return true;
      }
    }
    return false;
  }

  void align(State& s, const State& like) const {
    const LatticeBlock from = block_of(s), to = block_of(like);
    if (from.shape.n0 == to.shape.n0 && from.origin0 == to.origin0) return;
    s.f = map_field(from, s.f, to, 3);
    s.u = map_field(from, s.u, to, 3);
    s.shift = like.shift;
  }

  // Atoms that feel a force in both states whose registry index jumped (registry_slips).
  int slipped_sites(const State& before, const State& after) const {
    const LatticeBlock b = block_of(after);
    const std::vector<double> ub = map_field(block_of(before), before.u, b, 3);
    const std::vector<double> fb = map_field(block_of(before), before.f, b, 3);
    return registry_slips(contact_.tip_frame(), scene_.d, b, before.Dx, ub, fb, after.Dx, after.u,
                          after.f);
  }

  slide::Snapshot snapshot(const State& s, std::string label, int iteration = -1) const {
    slide::Snapshot snap;
    snap.label = std::move(label);
    snap.iteration = iteration;
    snap.Dx = s.Dx, snap.Fx = s.Fx, snap.Fz = s.Fz, snap.energy = s.energy;
    const int side = 2 * snap_half_ + 1;
    snap.block = LatticeBlock{Shape2{side, side}, s.shift - snap_half_, -snap_half_};
    const LatticeBlock from = block_of(s);
    const std::vector<double> u = map_field(from, s.u, snap.block, 3);
    // At a converged state the pair force equals the interface force (to the tolerance).
    const std::vector<double> f = map_field(from, s.f, snap.block, 3);
    const std::size_t n = snap.block.shape.count();
    const double d = scene_.d, area = d * d;
    snap.ux.assign(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(n));
    snap.uy.assign(u.begin() + static_cast<std::ptrdiff_t>(n),
                   u.begin() + static_cast<std::ptrdiff_t>(2 * n));
    snap.uz.assign(u.begin() + static_cast<std::ptrdiff_t>(2 * n), u.end());
    snap.sx.resize(n), snap.sy.resize(n), snap.tau_x.resize(n), snap.tau_y.resize(n);
    snap.tau_max.resize(n), snap.pressure.resize(n), snap.in_contact.assign(n, 0);
    snap.tip = scene_.tip;
    for (int i0 = 0; i0 < side; ++i0) {
      for (int i1 = 0; i1 < side; ++i1) {
        const std::size_t i = snap.block.shape.index(i0, i1);
        snap.sx[i] = snap.block.x(i0, d) + snap.ux[i] - s.Dx;
        snap.sy[i] = snap.block.y(i1, d) + snap.uy[i];
        snap.tau_x[i] = f[i] / area;
        snap.tau_y[i] = f[n + i] / area;
        snap.pressure[i] = std::max(0.0, -f[2 * n + i] / area);
        snap.tau_max[i] = eo_.alpha * snap.pressure[i];
        snap.in_contact[i] = snap.pressure[i] > 0.0 ? 1 : 0;
      }
    }
    return snap;
  }

  [[nodiscard]] std::size_t field_size() const { return contact_.forces().size(); }
  // A state lives on a square block of odd side, 3 components per site, centred on y = 0;
  // blocks grow and move with the tip, so the size is all there is to check.
  [[nodiscard]] std::string check_fields(const State& s) const {
    const std::size_t n = s.f.size() / 3;
    const auto side = static_cast<std::size_t>(std::lround(std::sqrt(static_cast<double>(n))));
    if (s.f.size() == 3 * n && side * side == n && side % 2 == 1 && s.u.size() == s.f.size() &&
        side <= kMaxBlockSide && std::abs(s.shift) <= kMaxShift) {
      return {};
    }
    return "3 per site of a square block of odd side <= " + std::to_string(kMaxBlockSide) +
           ", f and u alike, |shift| <= " + std::to_string(kMaxShift);
  }
  [[nodiscard]] std::size_t contact_sites() const { return contact_.active_sites(); }
  [[nodiscard]] std::size_t gf_applications() const { return contact_.gf_applications(); }
  [[nodiscard]] Shape2 block_shape() const { return contact_.block().shape; }
  [[nodiscard]] Shape2 fft_grid() const { return contact_.fft_grid(); }
  [[nodiscard]] const contact::Hertz& hertz() const { return hertz_; }

 private:
  void capture(State& s) const {
    const LatticeBlock& b = contact_.block();
    s.f = contact_.forces();
    s.u = contact_.displacements();
    // Atoms that feel no interface force carry none: the minimiser leaves round-off forces on
    // unknowns that left the contact, which would keep them active (and their block) for good.
    const std::size_t n = b.shape.count();
    for (std::size_t i = 0; i < n; ++i) {
      const double ui[3] = {s.u[i], s.u[n + i], s.u[2 * n + i]};
      double fi[3];
      contact_.site_interface(i, ui, fi);
      if (fi[0] == 0.0 && fi[1] == 0.0 && fi[2] == 0.0) s.f[i] = s.f[n + i] = s.f[2 * n + i] = 0.0;
    }
    s.shift = b.origin0 + (b.shape.n0 - 1) / 2;
    s.Dx = contact_.Dx();
    s.h = contact_.h();
    const ExplicitState st = contact_.state();
    s.Fx = st.Fx, s.Fz = st.Fz, s.energy = st.energy;
  }

  ExplicitScene scene_;
  ExplicitSlideOptions eo_;
  slide::SlideOptions options_;
  contact::Hertz hertz_;
  ExplicitContact contact_;
  double hertz_slope_;  // dFz/dh of the Hertz contact, -2 a E* (G d)
  int snap_half_;
};
static_assert(slide::detail::SlideModel<ExplicitSlider>);

}  // namespace

int registry_slips(const interface::TipFrame& frame, double d, const LatticeBlock& block,
                   double Dx_before, std::span<const double> u_before,
                   std::span<const double> f_before, double Dx_after,
                   std::span<const double> u_after, std::span<const double> f_after) {
  const std::size_t n = block.shape.count();
  for (const auto field : {u_before, f_before, u_after, f_after}) {
    if (field.size() != 2 * n && field.size() != 3 * n) {
      throw std::invalid_argument("registry_slips: a field of " + std::to_string(field.size()) +
                                  " values for " + std::to_string(n) +
                                  " block sites (2 or 3 components each)");
    }
  }
  const auto loaded = [n](std::span<const double> f, std::size_t i) {
    for (std::size_t c = 0; c < f.size() / n; ++c)
      if (f[c * n + i] != 0.0) return true;
    return false;
  };
  const auto n1 = static_cast<std::size_t>(block.shape.n1);
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!loaded(f_before, i) || !loaded(f_after, i)) continue;
    const double X = block.x(static_cast<int>(i / n1), d), Y = block.y(static_cast<int>(i % n1), d);
    double b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
    frame.registry(X + u_before[i] - Dx_before, Y + u_before[n + i], b1, b2);
    frame.registry(X + u_after[i] - Dx_after, Y + u_after[n + i], a1, a2);
    if (frame.registry_jumped(b1, b2, a1, a2, u_after[i] - u_before[i],
                              u_after[n + i] - u_before[n + i]))
      ++count;
  }
  return count;
}

slide::SlideResult slide_explicit(const ExplicitScene& scene, const ExplicitSlideOptions& eo,
                                  const slide::SlideOptions& options,
                                  const slide::SlideControl& control) {
  scene.validate();
  eo.validate();
  options.validate();
  control.validate();
  if (control.parallel.comm && control.parallel.comm->distributed()) {
    throw std::invalid_argument(
        "explicit slide: the explicit tip runs on one process (SlideControl::parallel over " +
        std::to_string(control.parallel.comm->size()) +
        " processes is for the lateral force model)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  ExplicitSlider model(scene, eo, options);
  require_small_slope(model.hertz().a, scene.R);
  const double k = 8.0 * scene.material.G * model.hertz().a / (2.0 - scene.material.nu);
  const slide::detail::ProtocolParams params{
      .d = scene.d,
      .alpha = eo.alpha,
      .Fz_continuum = eo.load,
      .default_cap = 3.0 * scene.d + 3.0 * eo.alpha * eo.load / k};
  return slide::detail::run_protocol(model, params, options, control, t0);
}

}  // namespace asperity::explicit_model
