// One application of the 2x2 free-boundary Green's function (a 512 x 512 loaded block on its
// 1024 x 1024 padded grid) against the bare FFTW transforms it needs: forward and inverse
// transforms of two 1024 x 1024 real fields. Both use the same planner and thread count, so
// the ratio is the overhead of gathering, the 2x2 Fourier-space product and scattering.
// Also: building and applying the periodic GF of a 256 x 256 Peierls cell.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "elastic/surface_gf.hpp"
#include "fft/fft_engine.hpp"

using namespace asperity;

namespace {

fft::FFTOptions options(const benchmark::State& state) {
  return {.threads = static_cast<int>(state.range(1)), .planner = fft::Planner::measure};
}

void BM_FreeGFInPlane(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  elastic::FreeSurfaceGF gf(elastic::Material{}, elastic::Components::in_plane, {n, n}, 1.0,
                            options(state));
  std::vector<double> f(gf.size()), u(gf.size());
  for (std::size_t i = 0; i < f.size(); ++i)
    f[i] = std::sin(0.001 * static_cast<double>(i));
  for (auto _ : state) {
    gf.apply(f, u);
    benchmark::DoNotOptimize(u.data());
  }
  state.counters["padded"] = gf.fft_shape().n0;
}

void BM_BareFFTPair(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  auto engine = fft::make_engine({2 * n, 2 * n}, 2, options(state));
  for (int c = 0; c < 2; ++c) {
    auto in = engine->input(c);
    for (std::size_t i = 0; i < in.size(); ++i)
      in[i] = std::sin(0.001 * static_cast<double>(i));
  }
  for (auto _ : state) {
    engine->forward();
    engine->inverse();
    benchmark::DoNotOptimize(engine->output(0).data());
  }
  state.counters["padded"] = 2 * n;
}

// The periodic cell of the Peierls problem: building the Poisson-summed kernel (once per cell)
// and one application.
void BM_PeriodicGFBuild(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  for (auto _ : state) {
    elastic::PeriodicSurfaceGF gf(elastic::Material{}, elastic::Components::in_plane, {L, L});
    benchmark::DoNotOptimize(&gf);
  }
}

void BM_PeriodicGFApply(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  elastic::PeriodicSurfaceGF gf(elastic::Material{}, elastic::Components::in_plane, {L, L}, 1.0,
                                {.planner = fft::Planner::measure});
  std::vector<double> f(gf.size()), u(gf.size());
  for (std::size_t i = 0; i < f.size(); ++i)
    f[i] = std::sin(0.01 * static_cast<double>(i));
  for (auto _ : state) {
    gf.apply(f, u);
    benchmark::DoNotOptimize(u.data());
  }
}

}  // namespace

BENCHMARK(BM_PeriodicGFBuild)
    ->Arg(256)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2)
    ->UseRealTime();
BENCHMARK(BM_PeriodicGFApply)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FreeGFInPlane)
    ->Args({512, 1})
    ->Args({512, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_BareFFTPair)
    ->Args({512, 1})
    ->Args({512, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
