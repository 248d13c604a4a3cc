// One L-BFGS iteration of a large contact spread over MPI ranks (issue 26, item 5): the slide's
// problem (slide/lfm_problem.hpp) on each rank's rows of the block, with the FFTW-MPI engine,
// as a distributed slide builds it. Reported per rank count (JSON line on rank 0): the mean
// time of an iteration (the slowest rank's), the part of it in Green's function applications
// and interface filter passes (the transforms with their all-to-all transposes, the FFT share),
// the part in the solvers' collectives (dot products, maxima: the Comm calls, whose wait also
// absorbs the ranks' imbalance), the all-to-all transposes inside the transforms (timed apart,
// transpose_seconds), each rank's contact sites and peak resident memory. With
// --serial (one process), the serial engine and problem instead, for the same contact.
//
// Usage: bench_iteration_mpi <grid: 1024|2048|4096> [iterations] [threads] [--serial]
// The contact as bench_iteration.cpp's: a = 250, 505, 1015 d, R = 1700 d, alpha = 0.7, tip at
// Dx = 0.3 d, from the flat state, the interface filter on (a / b_core^0 = 65 to 1070).
#include <fftw3-mpi.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fftw_mpi_engine.hpp"
#include "asperity/core/fft/mpi_comm.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/slide/lfm_problem.hpp"

#include "mpi_bench.hpp"

using namespace asperity;
using bench::max_over_ranks;
using bench::peak_rss_mb;

namespace {

using Clock = std::chrono::steady_clock;

// par::MpiComm with the time spent in its calls.
class TimedComm final : public par::Comm {
  template <class F>
  auto timed(F&& f) const {
    const auto t0 = Clock::now();
    auto out = f();
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    return out;
  }

 public:
  explicit TimedComm(MPI_Comm c) : comm_(c) {}
  mutable double seconds = 0.0;
  [[nodiscard]] int rank() const override { return comm_.rank(); }
  [[nodiscard]] int size() const override { return comm_.size(); }
  [[nodiscard]] double sum(double v) const override {
    return timed([&] { return comm_.sum(v); });
  }
  [[nodiscard]] double max(double v) const override {
    return timed([&] { return comm_.max(v); });
  }
  [[nodiscard]] long long sum(long long v) const override {
    return timed([&] { return comm_.sum(v); });
  }
  [[nodiscard]] bool any(bool v) const override {
    return timed([&] { return comm_.any(v); });
  }
  [[nodiscard]] std::vector<long long> all_gather(long long v) const override {
    return timed([&] { return comm_.all_gather(v); });
  }
  [[nodiscard]] std::vector<double> gather(std::span<const double> v, bool all) const override {
    return timed([&] { return comm_.gather(v, all); });
  }
  void exchange(std::span<const double> s, std::span<const int> sc, std::span<double> r,
                std::span<const int> rc) const override {
    timed([&] {
      comm_.exchange(s, sc, r, rc);
      return 0;
    });
  }

 private:
  par::MpiComm comm_;
};

// The problem with the time of its GF applications and filter passes.
class TimedProblem final : public minimize::Problem {
 public:
  explicit TimedProblem(minimize::Problem& p) : p_(p) {}
  double gf_seconds = 0.0;
  [[nodiscard]] std::size_t size() const override { return p_.size(); }
  void compliance(std::span<const double> f, std::span<double> u) override {
    const auto t0 = Clock::now();
    p_.compliance(f, u);
    gf_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  double interface(std::span<const double> u, std::span<double> f) const override {
    return p_.interface(u, f);
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    p_.curvature(u, h);
  }
  [[nodiscard]] bool wants_filter(bool automatic) const override {
    return p_.wants_filter(automatic);
  }
  void filter(std::span<const double> r, std::span<double> w) override {
    const auto t0 = Clock::now();
    p_.filter(r, w);
    gf_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  [[nodiscard]] std::size_t gf_applications() const override { return p_.gf_applications(); }
  [[nodiscard]] int threads() const override { return p_.threads(); }
  [[nodiscard]] const par::Comm& comm() const override { return p_.comm(); }
  [[nodiscard]] minimize::Share share() const override { return p_.share(); }
  [[nodiscard]] std::vector<std::size_t> runs() const override { return p_.runs(); }

 private:
  minimize::Problem& p_;
};

double contact_for(int grid) {
  return grid == 1024 ? 250.0 : grid == 2048 ? 505.0 : 1015.0;
}

// One all-to-all transpose of the complex half-grid of two fields, as the transposed-out r2c
// and transposed-in c2r plans make one per transform (FFTW's own transpose plan, on the same
// slabs): seconds per transpose, the slowest rank's, mean of `reps`. A GF application or filter
// pass (forward and inverse) makes two; an iteration (two of them) four: the communication of
// the transforms, which runs inside them and cannot be timed there.
double transpose_seconds(int n0, int n1, int reps) {
  const ptrdiff_t n[2] = {n0, n1 / 2 + 1}, howmany = 4;  // two complex fields: 4 doubles
  ptrdiff_t l0 = 0, s0 = 0, l1 = 0, s1 = 0;
  const ptrdiff_t alloc = fftw_mpi_local_size_many_transposed(2, n, howmany, FFTW_MPI_DEFAULT_BLOCK,
                                                              FFTW_MPI_DEFAULT_BLOCK,
                                                              MPI_COMM_WORLD, &l0, &s0, &l1, &s1);
  double* a = fftw_alloc_real(static_cast<std::size_t>(std::max<ptrdiff_t>(alloc, 1)));
  std::fill_n(a, std::max<ptrdiff_t>(alloc, 1), 0.0);
  fftw_plan p =
      fftw_mpi_plan_many_transpose(n[0], n[1], howmany, FFTW_MPI_DEFAULT_BLOCK,
                                   FFTW_MPI_DEFAULT_BLOCK, a, a, MPI_COMM_WORLD, FFTW_ESTIMATE);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = Clock::now();
  for (int r = 0; r < reps; ++r)
    fftw_execute(p);
  const double s = std::chrono::duration<double>(Clock::now() - t0).count() / reps;
  fftw_destroy_plan(p);
  fftw_free(a);
  return max_over_ranks(s);
}

}  // namespace

int main(int argc, char** argv) {
  int rank = 0, ranks = 1;
  bench::init_mpi(argc, argv, rank, ranks);
  if (argc < 2) {
    if (rank == 0)
      std::fprintf(stderr, "usage: bench_iteration_mpi grid [iterations] [threads] [--serial]\n");
    MPI_Finalize();
    return 2;
  }
  {
    const int grid = std::atoi(argv[1]);
    const int iterations = argc > 2 ? std::atoi(argv[2]) : 12;
    fft::FFTOptions fo;
    fo.threads = argc > 3 ? std::atoi(argv[3]) : 1;
    const bool serial = argc > 4 && std::strcmp(argv[4], "--serial") == 0;
    interface::ContactScene scene;
    scene.a = contact_for(grid);
    scene.R = 1700.0;
    const int H = static_cast<int>(std::ceil(scene.a)) + 2;
    const Shape2 shape{2 * H + 1, 2 * H + 1};
    TimedComm comm(MPI_COMM_WORLD);
    elastic::FreeSurfaceGF gf(
        scene.material, elastic::Components::in_plane, shape, scene.d, fo,
        serial ? fft::EngineFactory{} : fft::mpi_engine_factory(MPI_COMM_WORLD));
    const LatticeBlock local{Shape2{gf.local_rows(), shape.n1}, -H + gf.local_row_begin(), -H};
    interface::LateralForceModel lfm(scene, local);
    lfm.set_tip(0.3);
    slide::LfmProblem base(gf, lfm, serial ? par::serial() : static_cast<const par::Comm&>(comm));
    base.distribute();
    TimedProblem problem(base);
    minimize::MinimizerOptions o;
    o.force_tolerance = 1e-300;  // never reached: every iteration runs
    o.max_iterations = iterations;
    o.max_displacement = 0.1;
    o.stability = minimize::StabilityCheck::none;
    std::vector<double> u(problem.size(), 0.0), f(problem.size(), 0.0);
    comm.seconds = 0.0;
    const std::size_t gf0 = gf.applications(), filter0 = gf.filter_applications();
    MPI_Barrier(MPI_COMM_WORLD);
    const auto t0 = Clock::now();
    const auto r = minimize::minimize(problem, u, f, o);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const double n = r.iterations;
    const double wall = max_over_ranks(seconds), gf_s = max_over_ranks(problem.gf_seconds);
    const double comm_s = max_over_ranks(comm.seconds);
    const double pairs =
        static_cast<double>(gf.applications() - gf0 + gf.filter_applications() - filter0);
    const double transpose_s =
        serial ? 0.0 : transpose_seconds(gf.fft_shape().n0, gf.fft_shape().n1, 4);
    std::vector<double> rss(static_cast<std::size_t>(ranks)), sites(rss.size());
    const double mine = peak_rss_mb(), my_sites = static_cast<double>(problem.size() / 2);
    MPI_Gather(&mine, 1, MPI_DOUBLE, rss.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    MPI_Gather(&my_sites, 1, MPI_DOUBLE, sites.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank == 0) {
      std::string rs, ss;
      for (std::size_t i = 0; i < rss.size(); ++i) {
        if (i > 0) rs += ',', ss += ',';
        rs += std::to_string(static_cast<long>(rss[i]));
        ss += std::to_string(static_cast<long>(sites[i]));
      }
      std::printf(
          "{\"grid\": %d, \"a\": %g, \"ranks\": %d, \"engine\": \"%s\", \"threads\": %d, "
          "\"iterations\": %d, \"ms_per_iteration\": %.1f, \"gf_ms_per_iteration\": %.1f, "
          "\"collectives_ms_per_iteration\": %.1f, \"transposes_ms_per_iteration\": %.1f, "
          "\"pairs_per_iteration\": %.2f, "
          "\"sites_per_rank\": [%s], \"peak_rss_mb_per_rank\": [%s]}\n",
          gf.fft_shape().n0, scene.a, ranks,
          serial              ? "fftw"
          : gf.fft_shape().n0 ? "fftw-mpi"
                              : "",
          fo.threads, r.iterations, 1e3 * wall / n, 1e3 * gf_s / n, 1e3 * comm_s / n,
          4e3 * transpose_s, pairs / n, ss.c_str(), rs.c_str());
    }
  }
  MPI_Finalize();
  return 0;
}
