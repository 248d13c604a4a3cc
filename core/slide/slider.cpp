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
  Slider(const interface::ContactScene& scene, const SlideOptions& options,
         const SlideParallel& parallel = {})
      : scene_(scene),
        options_(options),
        comm_(parallel.comm ? *parallel.comm : par::serial()),
        half_(block_half(scene)),
        block_shape_{2 * half_ + 1, 2 * half_ + 1},
        gf_(scene.material, elastic::Components::in_plane, block_shape_, scene.d, options.fft,
            parallel.engine),
        row0_(gf_.local_row_begin()),
        rows_(gf_.local_rows()),
        lfm_(scene, local_block_at(0)),
        problem_(gf_, lfm_, comm_) {
    // Every process's rows, for the rolls and gathers of fields across processes; they follow
    // each other in rank order (the slabs of the padded grid do).
    const auto begins = comm_.all_gather(row0_), counts = comm_.all_gather(rows_);
    int next = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      rank_rows_.push_back(static_cast<int>(counts[r]));
      if (counts[r] > 0 && begins[r] != next) break;
      next += static_cast<int>(counts[r]);
    }
    if (next != block_shape_.n0 || rank_rows_.size() != counts.size()) {
      throw std::invalid_argument(
          "slide: the Green's function's rows are not spread over the " +
          std::to_string(comm_.size()) +
          " processes of SlideParallel::comm in rank order (the engine and comm must be over "
          "the same processes)");
    }
  }

  // The whole block at a block offset, and this process's rows of it.
  [[nodiscard]] LatticeBlock block_at(int shift) const {
    return LatticeBlock{block_shape_, shift - half_, -half_};
  }
  [[nodiscard]] LatticeBlock local_block_at(int shift) const {
    return LatticeBlock{Shape2{rows_, block_shape_.n1}, shift - half_ + row0_, -half_};
  }
  [[nodiscard]] const par::Comm& comm() const { return comm_; }
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
    move_to(s, Dx);
    // Sites that left the contact carry no force; u = G f also refreshes the pair.
    const std::size_t n = local_count();
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
            summarise(uu, ff, frame.fields);
            frames->push_back(std::move(frame));
          }
        }
        if (!stop_on_slip) return false;
        bool moved = false;
        for (std::size_t j = 0; j < m && !moved; ++j)
          moved = std::abs(uu[j] - u_start[j]) > 0.75 * scene_.d;
        return comm_.any(moved);
      };
    }
    const auto r = minimize::minimize(problem_, u, f, solver ? *solver : options_.minimizer,
                                      observer, from, pausing ? &pausing->pauses : nullptr);
    take_pair(u, f, s);
    return r;
  }

  // The block of `s` aligned to tip position Dx (the block follows the tip) and the model moved
  // there. Rolled rows come in without displacements; the caller's u = G f recomputes them.
  void move_to(State& s, double Dx) {
    const int target_shift = static_cast<int>(std::floor(Dx / scene_.d + 0.5));
    if (target_shift != s.shift) roll_fields(s, target_shift - s.shift);
    lfm_ = interface::LateralForceModel(scene_, local_block_at(s.shift));
    lfm_.set_tip(Dx);
    problem_.distribute();
    s.Dx = Dx;
  }

  // The pair (u, f) on the contact sites into `s`, whose forces off the contact are zero. The
  // displacement off the contact follows from the forces (slip detection and snapshots compare
  // it between states); on the contact it is the minimiser's.
  void take_pair(std::span<const double> u, std::span<const double> f, State& s) {
    scatter(f, s.f);
    gf_.apply(s.f, s.u);
    scatter(u, s.u);
    summarise(u, f, s);
  }

  // The state a paused slip flow stands at (PendingSlip): `from` (the last accepted state)
  // moved to the step's tip position, with the pause's pair on the contact sites and, off the
  // contact, the displacement its forces make (u = G f), as relax() leaves a state when a flow
  // ends there. Only the block's alignment is taken from `from`: every force of the state is the
  // pause's (relax() zeroes those off the contact). Throws std::invalid_argument if the pair
  // does not hold two values per contact site at that position.
  State paused_state(const State& from, double Dx, const minimize::FlowPause& pause) {
    State s = from;
    move_to(s, Dx);
    const std::size_t m = lfm_.contact_sites().size();
    if (pause.u.size() != 2 * m || pause.f.size() != 2 * m) {
      throw std::invalid_argument(
          "paused_slip: the paused flow holds " + std::to_string(pause.u.size()) + " and " +
          std::to_string(pause.f.size()) + " values, allowed: " + std::to_string(2 * m) +
          " (2 per contact site at Dx = " + std::to_string(Dx) + " d)");
    }
    std::fill(s.f.begin(), s.f.end(), 0.0);
    take_pair(pause.u, pause.f, s);
    return s;
  }

  // max |r_i| of the pair (u, f) on the contact sites at the model's tip position, as the
  // minimisers test it (minimize::max_residual): one interface evaluation, no GF application.
  [[nodiscard]] double residual(std::span<const double> u, std::span<const double> f) {
    return minimize::max_residual(problem_, u, f);
  }

  // Fx, Fz, the contact-site area and the energy of the pair (u, f) on the contact sites, into
  // `s`: sums over the sites of every process, made row by row and added in row order
  // (Comm::ordered_sum), the same bits on any number of processes.
  void summarise(std::span<const double> u, std::span<const double> f, SlideFields& s) const {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n1 = static_cast<std::size_t>(block_shape_.n1);
    const auto rows = static_cast<std::size_t>(rows_);
    std::vector<double> fint(2 * m), energy(rows), fx(rows, 0.0), fu(rows, 0.0), load(rows, 0.0);
    lfm_.energy_and_force_rows(u, fint, energy);
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t r = sites[j] / n1;
      fx[r] += fint[j];
      fu[r] += f[j] * u[j] + f[m + j] * u[m + j];
    }
    const double d2 = scene_.d * scene_.d;
    const std::vector<double>& p = lfm_.pressure();
    for (std::size_t i = 0; i < p.size(); ++i)
      load[i / n1] += p[i] * d2;
    for (std::size_t r = 0; r < rows; ++r)
      energy[r] += 0.5 * fu[r];
    s.Fx = comm_.ordered_sum(fx);
    s.Fz = comm_.ordered_sum(load);
    s.area = static_cast<double>(comm_.sum(static_cast<long long>(m))) * d2;
    s.energy = comm_.ordered_sum(energy);
  }

  // Brings a state's fields onto the block alignment of `like` (no GF application: f only).
  void align(State& s, const State& like) const {
    if (s.shift != like.shift) roll_fields(s, like.shift - s.shift);
  }
  // The rest of the model interface of protocol.hpp. field_size() and check_fields() describe
  // whole states (every row: start states and checkpoints); a process holds its rows.
  [[nodiscard]] std::size_t field_size() const { return 2 * block_shape_.count(); }
  [[nodiscard]] std::string check_fields(const State& s) const {
    // |shift| bounded so that rolling a start state cannot overflow the index arithmetic.
    constexpr int kMaxShift = 1 << 20;
    if (s.f.size() == field_size() && s.u.size() == field_size() && std::abs(s.shift) <= kMaxShift)
      return {};
    return std::to_string(field_size()) +
           " (2 per site of this scene's block), |shift| <= " + std::to_string(kMaxShift);
  }
  [[nodiscard]] std::size_t contact_sites() const {
    return static_cast<std::size_t>(comm_.sum(static_cast<long long>(lfm_.contact_sites().size())));
  }
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
    return comm_.max(worst);
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
    // Rows that entered the block with the roll have no displacement in `before`: the last k
    // of the block, which are the last of this process's rows that lie among them.
    const int entered = std::clamp(row0_ + rows_ - (block_shape_.n0 - std::max(k, 0)), 0, rows_);
    return static_cast<int>(comm_.sum(static_cast<long long>(registry_jumps(
        scene_, local_block_at(after.shift), b.Dx, b.u, after.Dx, after.u, entered))));
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
    // The LFM must describe this state's tip position and block (this process's rows of it).
    const LatticeBlock local = local_block_at(s.shift);
    if (lfm_.tip() != s.Dx || lfm_.block().origin0 != local.origin0) {
      lfm_ = interface::LateralForceModel(scene_, local);
      lfm_.set_tip(s.Dx);
      problem_.distribute();
    }
    const std::size_t n = local_count();
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
    if (comm_.distributed()) gather_snapshot(snap);
    return snap;
  }

  // Every row of a state, on the root process (the others keep no field values): what
  // checkpoints hold, so that they resume on any number of processes. Every process calls it.
  void globalize(SlideState& st) const {
    if (!comm_.distributed()) return;
    for_each_fields(st, [&](SlideFields& f) { whole_rows(f); });
    if (st.pending) {
      const Cut cut = cut_at(st.pending->Dx);
      minimize::FlowPause& p = st.pending->flow;
      for (std::vector<double>* v : {&p.u, &p.f, &p.velocity_u, &p.velocity_f, &p.power})
        *v = whole_sites(*v, cut);
    }
  }
  // This process's rows of a whole state (a start state): the inverse of globalize().
  void localize(SlideState& st) const {
    if (!comm_.distributed()) return;
    for_each_fields(st, [&](SlideFields& f) { own_rows(f); });
    if (st.pending) {
      const Cut cut = cut_at(st.pending->Dx);
      minimize::FlowPause& p = st.pending->flow;
      for (std::vector<double>* v : {&p.u, &p.f, &p.velocity_u, &p.velocity_f, &p.power})
        *v = own_sites(*v, cut);
    }
  }

 private:
  // Sites of this process's rows of the block.
  [[nodiscard]] std::size_t local_count() const {
    return static_cast<std::size_t>(rows_) * static_cast<std::size_t>(block_shape_.n1);
  }

  void gather(const std::vector<double>& full, std::vector<double>& part) const {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n = local_count();
    for (std::size_t j = 0; j < m; ++j) {
      part[j] = full[sites[j]];
      part[m + j] = full[n + sites[j]];
    }
  }
  void scatter(std::span<const double> part, std::vector<double>& full) const {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n = local_count();
    for (std::size_t j = 0; j < m; ++j) {
      full[sites[j]] = part[j];
      full[n + sites[j]] = part[m + j];
    }
  }

  // Shifts the block by k lattice rows along +x: site rows move down by k, new rows are empty.
  // Over several processes the rows that cross to another process's part are exchanged.
  void roll_fields(State& s, int k) const {
    if (comm_.distributed()) {
      roll_across(s, k);
      s.shift += k;
      return;
    }
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

  // The process holding block row i0.
  [[nodiscard]] int owner(int i0) const {
    int begin = 0;
    for (std::size_t r = 0; r < rank_rows_.size(); ++r) {
      if (i0 < begin + rank_rows_[r]) return static_cast<int>(r);
      begin += rank_rows_[r];
    }
    return static_cast<int>(rank_rows_.size()) - 1;
  }

  // roll_fields over processes: global row i0 takes row i0 + k; each row travels as its four
  // pieces (f and u, x and y), to the process that holds its new place.
  void roll_across(State& s, int k) const {
    const int n0 = block_shape_.n0;
    const std::size_t n1 = static_cast<std::size_t>(block_shape_.n1), n = local_count();
    const auto ranks = static_cast<std::size_t>(comm_.size());
    const int per_row = 4 * block_shape_.n1;
    std::vector<int> send_counts(ranks, 0), recv_counts(ranks, 0);
    std::vector<double> send, recv;
    for (int g = row0_; g < row0_ + rows_; ++g) {  // rows leaving: to the holder of g - k
      if (g - k < 0 || g - k >= n0) continue;
      send_counts[static_cast<std::size_t>(owner(g - k))] += per_row;
      const std::size_t at = static_cast<std::size_t>(g - row0_) * n1;
      for (const std::vector<double>* field : {&s.f, &s.u}) {
        for (std::size_t c = 0; c < 2; ++c)
          send.insert(send.end(), field->begin() + static_cast<std::ptrdiff_t>(c * n + at),
                      field->begin() + static_cast<std::ptrdiff_t>(c * n + at + n1));
      }
    }
    for (int d = row0_; d < row0_ + rows_; ++d) {  // rows arriving: from the holder of d + k
      if (d + k >= 0 && d + k < n0) recv_counts[static_cast<std::size_t>(owner(d + k))] += per_row;
    }
    std::size_t total = 0;
    for (int c : recv_counts)
      total += static_cast<std::size_t>(c);
    recv.resize(total);
    comm_.exchange(send, send_counts, recv, recv_counts);
    // Received in rank order, which is row order: the arriving rows in increasing d.
    std::size_t next = 0;
    for (int d = row0_; d < row0_ + rows_; ++d) {
      const std::size_t at = static_cast<std::size_t>(d - row0_) * n1;
      const bool arrives = d + k >= 0 && d + k < n0;
      for (std::vector<double>* field : {&s.f, &s.u}) {
        for (std::size_t c = 0; c < 2; ++c) {
          double* row = field->data() + c * n + at;
          if (arrives) {
            std::copy_n(recv.data() + next, n1, row);
            next += n1;
          } else {
            std::fill_n(row, n1, 0.0);
          }
        }
      }
    }
  }

  // A snapshot of this process's rows made whole on the root.
  void gather_snapshot(Snapshot& snap) const {
    for (std::vector<double>* v : {&snap.ux, &snap.uy, &snap.sx, &snap.sy, &snap.tau_x, &snap.tau_y,
                                   &snap.tau_max, &snap.pressure})
      *v = comm_.gather(*v);
    const std::vector<double> in(snap.in_contact.begin(), snap.in_contact.end());
    const std::vector<double> all = comm_.gather(in);
    snap.in_contact.assign(all.size(), 0);
    for (std::size_t i = 0; i < all.size(); ++i)
      snap.in_contact[i] = all[i] != 0.0 ? 1 : 0;
  }

  template <class F>
  static void for_each_fields(SlideState& st, F&& f) {
    f(st.current);
    f(st.peak);
    for (std::optional<SlideFields>* o : {&st.previous, &st.earlier, &st.runner_up})
      if (*o) f(**o);
    for (SlideFields& w : st.window)
      f(w);
    if (st.pending) {
      for (PathFrame& frame : st.pending->frames)
        f(frame.fields);
    }
  }
  // A field of this process's rows (x then y) made whole on the root, and the reverse.
  void whole_rows(SlideFields& fields) const {
    const std::size_t n = local_count();
    for (std::vector<double>* v : {&fields.f, &fields.u}) {
      // Path frames carry no force (a process without rows holds no values either way).
      if (!comm_.any(!v->empty())) continue;
      std::vector<double> whole;
      for (std::size_t c = 0; c < 2; ++c) {
        const std::vector<double> part =
            comm_.gather(std::span<const double>(v->data() + c * n, n));
        whole.insert(whole.end(), part.begin(), part.end());
      }
      *v = std::move(whole);
    }
  }
  void own_rows(SlideFields& fields) const {
    const std::size_t n = local_count(), all = block_shape_.count();
    const std::size_t begin = static_cast<std::size_t>(row0_) * block_shape_.n1;
    for (std::vector<double>* v : {&fields.f, &fields.u}) {
      if (v->empty()) continue;
      std::vector<double> part(2 * n);
      for (std::size_t c = 0; c < 2; ++c)
        std::copy_n(v->begin() + static_cast<std::ptrdiff_t>(c * all + begin), n,
                    part.begin() + static_cast<std::ptrdiff_t>(c * n));
      *v = std::move(part);
    }
  }

  // Where this process's contact sites sit among every process's at tip position Dx (the
  // block there): their count, the count before them and the total.
  struct Cut {
    std::size_t m = 0, offset = 0, total = 0;
  };
  [[nodiscard]] Cut cut_at(double Dx) const {
    const int shift = static_cast<int>(std::floor(Dx / scene_.d + 0.5));
    interface::LateralForceModel at(scene_, local_block_at(shift));
    at.set_tip(Dx);
    Cut cut{.m = at.contact_sites().size()};
    const auto counts = comm_.all_gather(static_cast<long long>(cut.m));
    for (std::size_t r = 0; r < counts.size(); ++r) {
      if (static_cast<int>(r) < comm_.rank()) cut.offset += static_cast<std::size_t>(counts[r]);
      cut.total += static_cast<std::size_t>(counts[r]);
    }
    return cut;
  }
  // A vector on the contact sites (x of each, then y; empty stays empty) made whole on the
  // root, and the reverse.
  [[nodiscard]] std::vector<double> whole_sites(const std::vector<double>& v, Cut cut) const {
    // Present on every process or on none (a process without contact sites holds none of it).
    if (!comm_.any(!v.empty())) return {};
    std::vector<double> whole;
    for (std::size_t c = 0; c < 2; ++c) {
      const std::vector<double> part =
          comm_.gather(std::span<const double>(v).subspan(c * cut.m, cut.m));
      whole.insert(whole.end(), part.begin(), part.end());
    }
    return whole;
  }
  [[nodiscard]] std::vector<double> own_sites(const std::vector<double>& v, Cut cut) const {
    if (v.empty()) return {};
    if (v.size() != 2 * cut.total) {
      throw std::invalid_argument("slide: the start state's paused flow has " +
                                  std::to_string(v.size()) + " values for " +
                                  std::to_string(2 * cut.total) + " (2 per contact site)");
    }
    std::vector<double> part(2 * cut.m);
    for (std::size_t c = 0; c < 2; ++c)
      std::copy_n(v.begin() + static_cast<std::ptrdiff_t>(c * cut.total + cut.offset), cut.m,
                  part.begin() + static_cast<std::ptrdiff_t>(c * cut.m));
    return part;
  }

  interface::ContactScene scene_;
  SlideOptions options_;
  const par::Comm& comm_;
  int half_;
  Shape2 block_shape_;
  elastic::FreeSurfaceGF gf_;
  int row0_, rows_;             // this process's rows of the block: [row0_, row0_ + rows_)
  std::vector<int> rank_rows_;  // every process's count of rows, in rank order
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
            "slide.step_growth", [](auto& o) -> auto& { return o.step_growth; },
            R::closed(0.0, 16.0), "",
            "adaptive protocol: after a slip the step restarts at slide.min_step and grows by this "
            "factor per accepted step up to slide.max_step (0: off; else > 1)",
            "--step-growth"),
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
        settings::integer<O>(
            "slide.flow_first_after", [](auto& o) -> auto& { return o.flow_first_after; },
            R::closed(0, 1000000), "",
            "after this many slip steps in a row, a min_step step goes to the slip minimiser first "
            "and to the fast one only if stable: the same path, less cost (0: never)"),
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
  if (step_growth != 0.0 && !(step_growth > 1.0)) {
    throw std::invalid_argument("slide.step_growth = " + settings::format_number(step_growth) +
                                ": allowed: 0 (off) or > 1");
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
  Slider slider(scene, options, control.parallel);
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
  // The index is round(rho) per tip axis (round(s / d) for the aligned tip) and the jump the
  // displacement along that axis (TipFrame::registry_jumped).
  const interface::TipFrame& frame = at_after.tip_frame();
  const std::size_t first_new_row =
      static_cast<std::size_t>(block.shape.n0 - std::clamp(entered_rows, 0, block.shape.n0));
  int count = 0;
  for (std::size_t i : at_after.contact_sites()) {
    if (i / static_cast<std::size_t>(block.shape.n1) >= first_new_row) continue;
    if (at_before.tau_max()[i] <= 0.0) continue;  // entered the contact in this step
    double b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
    at_before.registry(i, u_before[i], u_before[n + i], b1, b2);
    at_after.registry(i, u_after[i], u_after[n + i], a1, a2);
    if (frame.registry_jumped(b1, b2, a1, a2, u_after[i] - u_before[i],
                              u_after[n + i] - u_before[n + i]))
      ++count;
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

PausedSlip paused_slip(const interface::ContactScene& scene, const SlideOptions& options,
                       const SlideState& state) {
  scene.validate();
  options.validate();
  if (!state.pending) {
    throw std::invalid_argument(
        "paused_slip: the state holds no paused slip flow (SlideState::pending is empty: it was "
        "taken between steps)");
  }
  // As the slide checks a start state (protocol.hpp): a damaged file must not reach the block
  // arithmetic.
  if (!std::isfinite(state.pending->Dx) || !(state.pending->Dx > state.current.Dx) ||
      std::abs(state.pending->Dx - state.current.Dx) > 1e6 * scene.d) {
    throw std::invalid_argument(
        "paused_slip: SlideState.pending.Dx = " + std::to_string(state.pending->Dx) +
        " d, allowed: finite and beyond the last accepted state's Dx = " +
        std::to_string(state.current.Dx) + " d");
  }
  Slider model(scene, options);
  if (const std::string why = model.check_fields(state.current); !why.empty()) {
    throw std::invalid_argument("paused_slip: the state's fields do not fit this scene: " +
                                std::to_string(state.current.u.size()) +
                                " values, allowed: " + why);
  }
  PausedSlip out;
  out.iteration = state.pending->flow.iteration;
  out.state = model.paused_state(state.current, state.pending->Dx, state.pending->flow);
  out.slipped_sites = model.slipped_sites(state.current, out.state);
  // The model stands at the step's tip position (paused_state moved it there).
  out.max_force = model.residual(state.pending->flow.u, state.pending->flow.f);
  return out;
}

StepRelaxation relax_step(const interface::ContactScene& scene, const SlideOptions& options,
                          const SlideFields& from, double Dx, const FlowWatch& watch) {
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
  detail::RelaxPausing watching;
  if (watch) {
    watching.pauses.due = [](int) { return true; };
    watching.pauses.pause = [&](const minimize::FlowPause& p) {
      watch(p);
      return false;  // seen, not paused
    };
  }
  out.result = model.relax(out.state, Dx, nullptr, false, nullptr, watch ? &watching : nullptr);
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.result.gf_applications = model.gf_applications() - gf0;
  out.slipped_sites = model.slipped_sites(from, out.state);
  return out;
}

int block_side(const interface::ContactScene& scene) {
  return 2 * block_half(scene) + 1;
}

double estimated_slide_bytes(const interface::ContactScene& scene, const SlideOptions& options,
                             int ranks) {
  if (ranks < 1)
    throw std::invalid_argument("estimated_slide_bytes: ranks " + std::to_string(ranks));
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
  // The root's slab of the grid and its share of the block's rows (1 on one process).
  const double slab = std::ceil(grid / ranks);
  const double share = std::min(1.0, slab / n);
  const double window = static_cast<double>(kCycleWindow) * 32.0 * n * n;
  const double live = 260.0 * grid * slab + share * (minimiser + window + path * n * n);
  // Copies made whole on the root: a checkpoint's (the window again, the pending flow), two
  // snapshots in flight.
  return kProcess + live + window + pending + 2.0 * 65.0 * n * n;
}

}  // namespace asperity::slide
