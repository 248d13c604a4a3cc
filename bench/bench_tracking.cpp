// Dislocation-line detection and tracking (tracking/, MODEL.md section 7) on a synthetic
// 2048 x 2048 snapshot: a contact of radius 1000 d with 40 elliptical loops of 5 to 60 d and
// noise. Target (issue 6): one snapshot in under 2 s on 2 cores.
#include <benchmark/benchmark.h>

#include <cmath>

#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/synthetic.hpp"
#include "asperity/tracking/tracker.hpp"

using namespace asperity;
using namespace asperity::tracking;

namespace {

const SyntheticField& field_2048() {
  static const SyntheticField field = [] {
    SyntheticOptions o;
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
  }();
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

}  // namespace

BENCHMARK_MAIN();
