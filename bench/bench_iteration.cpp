// One minimiser iteration of a large contact against the FFT floor (issue 22, item 3).
//
// Contacts whose padded grids are 1024^2, 2048^2 and 4096^2 (a = 250, 505, 1015 d; R = 1700 d,
// alpha = 0.7: a / b_core^0 = 65 to 1070, so L-BFGS runs with the interface filter, as in a
// slide): the mean time of an L-BFGS iteration over a relaxation of 24 iterations from a
// loaded flat state, and the time of the FFT transforms the iteration needs, on the same grid,
// planner and threads: per GF application and per filter pass, forward and inverse transforms of
// two real fields (BM_BareFFTPair). The counter `over_floor` is the iteration's time over
// (GF applications + filter passes per iteration) x one bare pair: 1 means nothing but FFTs;
// `over_gf` is the iteration's time over one GF application and one filter pass as the GF
// makes them (its transforms pruned to the non-zero rows of the padded grid).
// Run with bench/run_iteration.sh, which records the figures in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fft_engine.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/slide/lfm_problem.hpp"

using namespace asperity;

namespace {

// Third argument of the benchmarks: 0 FFTW_ESTIMATE (the slides' default), 1 FFTW_MEASURE.
fft::FFTOptions fft_options(int threads, std::int64_t planner) {
  return {.threads = threads,
          .planner = planner == 1 ? fft::Planner::measure : fft::Planner::estimate};
}

// The contact radius whose block's padded grid is `grid` (4 (ceil(a) + 2) + 1 <= grid, and no
// smaller 7-smooth size fits).
double contact_for(int grid) {
  switch (grid) {
    case 1024:
      return 250.0;
    case 2048:
      return 505.0;
    default:
      return 1015.0;
  }
}

// Seconds of one bare pair (forward and inverse transforms of two real fields) per grid and
// thread count, measured once per process for the ratio below.
std::map<std::array<std::int64_t, 3>, double>& bare_pair_seconds() {
  static std::map<std::array<std::int64_t, 3>, double> seconds;
  return seconds;
}

void BM_BareFFTPair(benchmark::State& state) {
  const int grid = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  auto engine = fft::make_engine({grid, grid}, 2, fft_options(threads, state.range(2)));
  for (int c = 0; c < 2; ++c) {
    auto in = engine->input(c);
    for (std::size_t i = 0; i < in.size(); ++i)
      in[i] = std::sin(0.001 * static_cast<double>(i));
  }
  double total = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    engine->forward();
    engine->inverse();
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    benchmark::DoNotOptimize(engine->output(0).data());
  }
  bare_pair_seconds()[{grid, threads, state.range(2)}] =
      total / static_cast<double>(state.iterations());
  state.counters["grid"] = grid;
}

// Seconds of one GF application plus one filter pass on the contact's block (the transforms an
// iteration makes, as the GF makes them: pruned to the non-zero rows of the padded grid, with
// the Fourier-space products and the copies in and out), per grid, threads and planner.
std::map<std::array<std::int64_t, 3>, double>& gf_pair_seconds() {
  static std::map<std::array<std::int64_t, 3>, double> seconds;
  return seconds;
}

void BM_GFApplyAndFilter(benchmark::State& state) {
  const int grid = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  const int H = static_cast<int>(std::ceil(contact_for(grid))) + 2;
  elastic::FreeSurfaceGF gf(elastic::Material{}, elastic::Components::in_plane,
                            {2 * H + 1, 2 * H + 1}, 1.0, fft_options(threads, state.range(2)));
  std::vector<double> f(gf.size()), u(gf.size()), w(gf.size());
  for (std::size_t i = 0; i < f.size(); ++i)
    f[i] = std::sin(0.001 * static_cast<double>(i));
  double total = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    gf.apply_filter(f, w, 0.5);
    gf.apply(w, u);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    benchmark::DoNotOptimize(u.data());
  }
  gf_pair_seconds()[{grid, threads, state.range(2)}] =
      total / static_cast<double>(state.iterations());
  state.counters["grid"] = gf.fft_shape().n0;
}

void BM_LbfgsIterationLarge(benchmark::State& state) {
  const int grid = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  interface::ContactScene scene;
  scene.a = contact_for(grid);
  scene.R = 1700.0;
  const int H = static_cast<int>(std::ceil(scene.a)) + 2;
  const LatticeBlock block{{2 * H + 1, 2 * H + 1}, -H, -H};
  interface::LateralForceModel lfm(scene, block);
  lfm.set_tip(0.3);
  elastic::FreeSurfaceGF gf(scene.material, elastic::Components::in_plane, block.shape, scene.d,
                            fft_options(threads, state.range(2)));
  slide::LfmProblem problem(gf, lfm);
  minimize::MinimizerOptions o;
  o.force_tolerance = 1e-300;  // never reached: every call runs max_iterations
  o.max_iterations = 24;
  o.max_displacement = 0.1;
  o.stability = minimize::StabilityCheck::none;
  long long iterations = 0;
  std::size_t pairs = 0, evaluations = 0;
  double seconds = 0.0;
  for (auto _ : state) {
    std::vector<double> u(problem.size(), 0.0), f(problem.size(), 0.0);
    const std::size_t gf0 = gf.applications(), filter0 = gf.filter_applications();
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = minimize::minimize(problem, u, f, o);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    iterations += r.iterations;
    evaluations += r.interface_evaluations;
    pairs += gf.applications() - gf0 + gf.filter_applications() - filter0;
  }
  const double per_iteration = seconds / static_cast<double>(iterations);
  const double pairs_per_iteration = static_cast<double>(pairs) / static_cast<double>(iterations);
  state.counters["grid"] = gf.fft_shape().n0;
  state.counters["sites"] = static_cast<double>(problem.size() / 2);
  state.counters["ms_per_iteration"] = 1e3 * per_iteration;
  state.counters["pairs_per_iteration"] = pairs_per_iteration;
  state.counters["evaluations_per_iteration"] =
      static_cast<double>(evaluations) / static_cast<double>(iterations);
  if (const auto bare = bare_pair_seconds().find({grid, threads, state.range(2)});
      bare != bare_pair_seconds().end()) {
    state.counters["ms_bare_pair"] = 1e3 * bare->second;
    state.counters["over_floor"] = per_iteration / (pairs_per_iteration * bare->second);
  }
  if (const auto gfs = gf_pair_seconds().find({grid, threads, state.range(2)});
      gfs != gf_pair_seconds().end()) {
    state.counters["ms_gf_and_filter"] = 1e3 * gfs->second;
    state.counters["over_gf"] = per_iteration / gfs->second;
  }
}

// The memory bandwidth that bounds the vector work: x = a + t b over vectors of the size of the
// 2048^2 contact's unknowns (2 x 801 000 doubles, 13 MB each), as the minimiser's axpy_into does.
// An L-BFGS iteration with 8 pairs streams each pair's s, y and the force change once or twice
// and the working vectors a few times: about 150 such vectors per iteration.
void BM_VectorTriad(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  std::vector<double> x(n), a(n, 1.0), b(n, 2.0);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i)
      x[i] = a[i] + 0.5 * b[i];
    benchmark::DoNotOptimize(x.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(3 * n * sizeof(double)));
}

}  // namespace

BENCHMARK(BM_VectorTriad)->Arg(1602000)->Unit(benchmark::kMillisecond)->UseRealTime();
// The bare pair first: the iteration's ratio divides by it.
BENCHMARK(BM_BareFFTPair)
    ->ArgsProduct({{1024, 2048, 4096}, {2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_GFApplyAndFilter)
    ->ArgsProduct({{1024, 2048, 4096}, {2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_LbfgsIterationLarge)
    ->ArgsProduct({{1024, 2048, 4096}, {2}, {0, 1}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
