// One application of the 2x2 free-boundary Green's function (a 512 x 512 loaded block on its
// 1024 x 1024 padded grid) against the bare FFTW transforms it needs: forward and inverse
// transforms of two 1024 x 1024 real fields. Both use the same planner and thread count, so
// the ratio is the overhead of gathering, the 2x2 Fourier-space product and scattering.
// Also: building and applying the periodic GF of a 256 x 256 Peierls cell; and the engine's
// zero-padded convolution at every 7-smooth padded size of 1000-1400 (BM_ConvolvePadded, with
// the slides' ESTIMATE plans, one thread): odd sizes against even ones (next_fft_size,
// bench/run_padded_sizes.sh).
#include <benchmark/benchmark.h>

#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/slide/lfm_problem.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fft_engine.hpp"

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

// One zero-padded convolution of two fields on an n x n grid whose first (n + 1) / 2 rows are
// loaded (FreeSurfaceGF's support for a region of (n + 1) / 2 rows), the 2x2 product replaced
// by a scaling: the transforms and copies of a GF application at padded size n. Arguments:
// n, planner (0 estimate, 1 measure), threads.
void BM_ConvolvePadded(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const fft::Planner planner = state.range(1) == 0 ? fft::Planner::estimate : fft::Planner::measure;
  const int threads = static_cast<int>(state.range(2));
  auto engine = fft::make_engine({n, n}, 2, {.threads = threads, .planner = planner}, (n + 1) / 2);
  for (int c = 0; c < 2; ++c) {
    auto in = engine->input(c);
    std::fill(in.begin(), in.end(), 0.0);
    for (std::size_t i = 0; i < static_cast<std::size_t>((n + 1) / 2) * n; ++i)
      in[i] = std::sin(0.001 * static_cast<double>(i));
  }
  const double scale = engine->normalisation();
  const fft::Multiplier multiplier = [scale](const fft::FourierBlock& block) {
    const std::size_t count = static_cast<std::size_t>(block.width) * block.rows;
    for (int f = 0; f < 2; ++f) {
      for (std::size_t i = 0; i < count; ++i)
        block.field[f][i] *= scale;
    }
  };
  for (auto _ : state) {
    engine->convolve(multiplier);
    benchmark::DoNotOptimize(engine->output(0).data());
  }
  state.counters["padded"] = n;
  state.counters["ns_per_point"] = benchmark::Counter(
      static_cast<double>(n) * n * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Every 7-smooth size (odd and even) in [1000, 1400].
void padded_sizes(benchmark::internal::Benchmark* b) {
  for (int n = 1000; n <= 1400; ++n) {
    if (fft_smooth(n)) b->Args({n, 0, 1});
  }
}

// Threads against grid size: padded grids of the contacts slid here (72^2 at a = 15 d up to
// 2058^2 at a = 510 d), ESTIMATE plans, 1 and 2 threads.
void thread_sizes(benchmark::internal::Benchmark* b) {
  for (int n : {72, 128, 192, 256, 384, 512, 768, 1024, 1250, 2058}) {
    for (int t : {1, 2})
      b->Args({n, 0, t});
  }
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

// The lateral force model on the default scene's block (a = 43 d): interface force and energy,
// and the Hessian diagonal, per evaluation; and one L-BFGS iteration (one GF application, the
// line search, the two-loop recursion), as the mean over a 40-iteration relaxation.
struct LfmBench {
  interface::ContactScene scene {};
  int H = static_cast<int>(std::ceil(scene.a)) + 2;
  LatticeBlock block{{2 * H + 1, 2 * H + 1}, -H, -H};
  interface::LateralForceModel lfm {
    scene, block
  };
  LfmBench() { lfm.set_tip(0.3); }
};

void BM_LfmInterfaceForce(benchmark::State& state) {
  LfmBench b;
  const std::size_t n = 2 * b.lfm.contact_sites().size();
  std::vector<double> u(n), f(n);
  for (std::size_t i = 0; i < n; ++i)
    u[i] = 0.01 * std::sin(0.1 * static_cast<double>(i));
  for (auto _ : state) {
    benchmark::DoNotOptimize(b.lfm.energy_and_force(u, f));
  }
  state.counters["sites"] = static_cast<double>(n / 2);
}

void BM_LfmInterfaceCurvature(benchmark::State& state) {
  LfmBench b;
  const std::size_t n = 2 * b.lfm.contact_sites().size();
  std::vector<double> u(n), h(n);
  for (auto _ : state) {
    b.lfm.curvature(u, h);
    benchmark::DoNotOptimize(h.data());
  }
}

void BM_LbfgsIteration(benchmark::State& state) {
  LfmBench b;
  elastic::FreeSurfaceGF gf(elastic::Material{}, elastic::Components::in_plane, b.block.shape, 1.0,
                            {.planner = fft::Planner::measure});
  slide::LfmProblem problem(gf, b.lfm);
  minimize::MinimizerOptions o;
  o.force_tolerance = 1e-300;  // never reached: every call runs max_iterations
  o.max_iterations = 40;
  o.stability = minimize::StabilityCheck::none;
  long long iterations = 0;
  for (auto _ : state) {
    std::vector<double> u(problem.size(), 0.0), f(problem.size(), 0.0);
    const auto r = minimize::minimize(problem, u, f, o);
    iterations += r.iterations;
  }
  state.counters["iterations_per_call"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations());
}
}  // namespace

BENCHMARK(BM_PeriodicGFBuild)
    ->Arg(256)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2)
    ->UseRealTime();
BENCHMARK(BM_PeriodicGFApply)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FreeGFInPlane)
    ->Args({91, 1})
    ->Args({512, 1})
    ->Args({512, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_BareFFTPair)
    ->Args({512, 1})
    ->Args({512, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ConvolvePadded)->Apply(padded_sizes)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ConvolvePadded)
    ->Name("BM_ConvolveThreads")
    ->Apply(thread_sizes)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_LfmInterfaceForce)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_LfmInterfaceCurvature)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_LbfgsIteration)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
