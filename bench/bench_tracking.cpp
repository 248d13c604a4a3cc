// Dislocation-line detection and tracking (tracking/, MODEL.md section 7) on a synthetic
// 2048 x 2048 snapshot: a contact of radius 1000 d with 40 elliptical loops of 5 to 60 d and
// noise. Target (issue 6): one snapshot in under 2 s on 2 cores. And the stress held along
// the lines (tracking::front_stresses) at spans of 8, 16 and 32 d: its time on that snapshot
// beside its error in loaded Peierls cells of lines from (1, 0) to (8, 1) and (1, 8) (the
// worst resolved point's miss of the load, in units of the cell's tau_P; the analytic test
// holds span 32 to a computed bound).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "asperity/peierls/peierls_stress.hpp"
#include "asperity/peierls/scan.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"
#include "asperity/tracking/synthetic.hpp"
#include "asperity/tracking/tracker.hpp"

using namespace asperity;
using namespace asperity::tracking;

namespace {

// tau_peak: 0.1 G (cores about 10 d wide) for the line benchmarks; the front's uses 0.56 G,
// the centre of the R = 800 d, a = 300 d contact (cores about 1.8 d), where its windows are
// resolved.
SyntheticField make_field_2048(double tau_peak) {
  SyntheticOptions o;
  o.tau_peak = tau_peak;
  o.block = LatticeBlock{.shape = {2048, 2048}, .origin0 = -1024, .origin1 = -1024};
  o.contact_radius = 1000.0;
  o.noise_s = 0.02;
  o.noise_tau = 0.05;
  o.registry_offset = 0.1;
  o.offset_wavelength = 40.0;
  std::vector<Island> islands;
  for (int k = 0; k < 40; ++k) {  // on a spiral, sizes 5..60 d, aspect 1..2
    const double r = 100.0 + 20.0 * k, phi = 2.4 * k;
    const double ay = 5.0 + 55.0 * ((k * 7) % 40) / 39.0;
    islands.push_back({r * std::cos(phi), r * std::sin(phi), ay * (1.0 + (k % 3) * 0.5), ay});
  }
  return synthetic_field(o, islands);
}

const SyntheticField& field_2048() {
  static const SyntheticField field = make_field_2048(0.1);
  return field;
}

void BM_FindLines2048(benchmark::State& state) {
  const FieldView view = field_2048().view();
  std::size_t lines = 0;
  for (auto _ : state) {
    const FrameLines f = find_lines(view);
    lines = f.lines.size();
    benchmark::DoNotOptimize(f);
  }
  state.counters["lines"] = static_cast<double>(lines);
  state.counters["sites"] = static_cast<double>(view.block.shape.count());
}
BENCHMARK(BM_FindLines2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// One frame of a sequence: detection plus matching against the previous (identical) frame.
void BM_FindAndTrack2048(benchmark::State& state) {
  const FieldView view = field_2048().view();
  Tracker tracker;
  tracker.add(find_lines(view));
  for (auto _ : state) {
    const auto ids = tracker.add(find_lines(view));
    benchmark::DoNotOptimize(ids);
  }
}
BENCHMARK(BM_FindAndTrack2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// The 2048 field with narrow cores as a snapshot (tau_y = 0, u_y = 0: the synthetic loops are
// pure x slip).
const SyntheticField& narrow_field_2048() {
  static const SyntheticField field = make_field_2048(0.56);
  return field;
}
const slide::Snapshot& snapshot_2048() {
  static const slide::Snapshot s = [] {
    const SyntheticField& f = narrow_field_2048();
    slide::Snapshot out;
    out.block = f.block;
    out.sx = f.sx;
    out.tau_x = f.tau_x;
    out.tau_max = f.tau_max;
    out.tau_y.assign(f.tau_x.size(), 0.0);
    out.uy.assign(f.tau_x.size(), 0.0);
    out.pressure.assign(f.tau_x.size(), 0.0);
    out.in_contact = f.in_contact;
    return out;
  }();
  return s;
}

// The worst resolved point's |held + load| / tau_P over loaded cells of several directions
// (L = 256, b_core = 2 d), at one span.
double cell_error(double span) {
  struct Cell {
    slide::Snapshot snapshot;
    tracking::FrameLines lines;
    double load = 0.0, tau_P = 0.0;
  };
  static const std::vector<Cell> cells = [] {
    std::vector<Cell> out;
    for (const auto& [mx, my] :
         std::vector<std::pair<int, int>>{{1, 0}, {2, 1}, {4, 1}, {8, 1}, {1, 8}}) {
      peierls::PeierlsOptions o;
      o.cell.L = 256;
      o.cell.b_core = 2.0;
      o.cell.mx = mx;
      o.cell.my = my;
      o.both_signs = false;
      const peierls::PeierlsResult r = peierls::peierls_stress(o);
      const peierls::PeierlsCell cell(o.cell);
      Cell c{.snapshot = peierls::cell_snapshot(cell, r.u_loaded, "cell", r.tau_loaded),
             .lines = {},
             .load = r.tau_loaded,
             .tau_P = r.positive.tau_P};
      c.lines = find_lines(view_of(c.snapshot, true));
      out.push_back(std::move(c));
    }
    return out;
  }();
  double worst = 0.0;
  for (const Cell& c : cells) {
    for (const FrontStress& p : front_stresses(c.snapshot, c.lines, {.span = span})) {
      if (p.resolved()) worst = std::max(worst, std::abs(p.held.tau + c.load) / c.tau_P);
    }
  }
  return worst;
}

void BM_Front2048(benchmark::State& state) {
  const slide::Snapshot& s = snapshot_2048();
  const FrameLines lines = find_lines(narrow_field_2048().view());
  const FrontOptions o{.span = static_cast<double>(state.range(0))};
  std::size_t points = 0, resolved = 0;
  for (auto _ : state) {
    const std::vector<FrontStress> front = front_stresses(s, lines, o);
    points = front.size();
    resolved = static_cast<std::size_t>(std::count_if(
        front.begin(), front.end(), [](const FrontStress& p) { return p.resolved(); }));
    benchmark::DoNotOptimize(front);
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["resolved"] = static_cast<double>(resolved);
  state.counters["cell_error_tau_P"] = cell_error(o.span);
}
BENCHMARK(BM_Front2048)->Arg(8)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
