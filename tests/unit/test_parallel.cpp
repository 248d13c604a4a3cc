// Unit tier: the threaded element-wise passes (common/parallel.hpp). Their promise is that the
// number of threads changes nothing: every element is written once, by the same expression, so a
// minimisation is bit for bit the same on one thread or several (its sums stay serial).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

#include "asperity/core/common/parallel.hpp"
#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/slide/lfm_problem.hpp"

using namespace asperity;

TEST(Parallel, RangesCoverEveryElementOnceOnCacheLineBoundaries) {
  for (const std::size_t n :
       {std::size_t{0}, std::size_t{5}, par::min_per_thread * 2 + 3, par::min_per_thread * 7 + 1}) {
    for (const int threads : {1, 2, 3, 8}) {
      std::vector<std::atomic<int>> hits(n);
      std::atomic<int> ranges{0};
      par::for_ranges(n, threads, [&](std::size_t b, std::size_t e) {
        ++ranges;
        if (b % 8 != 0) ADD_FAILURE() << "range starts at " << b;
        for (std::size_t i = b; i < e; ++i)
          ++hits[i];
      });
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(hits[i], 1) << "element " << i << " of " << n << ", " << threads << " threads";
      EXPECT_EQ(ranges, par::threads_for(n, threads)) << n << ", " << threads << " threads";
    }
  }
  // Short passes stay on one thread; long ones use what they are granted.
  EXPECT_EQ(par::threads_for(par::min_per_thread, 2), 1);
  EXPECT_EQ(par::threads_for(2 * par::min_per_thread, 2), 2);
  EXPECT_EQ(par::threads_for(100 * par::min_per_thread, 3), 3);
}

TEST(Parallel, MaximumOverRangesIsTheMaximumAndReportsNaN) {
  const std::size_t n = 5 * par::min_per_thread + 11;
  std::vector<double> a(n);
  for (std::size_t i = 0; i < n; ++i)
    a[i] = std::sin(0.37 * static_cast<double>(i));
  a[n - 2] = 3.5;  // in the last range
  const auto range_max = [&](std::size_t b, std::size_t e) {
    double m = -1e300;
    for (std::size_t i = b; i < e; ++i)
      m = std::max(m, a[i]);
    return m;
  };
  for (const int threads : {1, 2, 4})
    EXPECT_EQ(par::max_over_ranges(n, threads, range_max), 3.5) << threads << " threads";
  a[7] = std::numeric_limits<double>::quiet_NaN();  // in the first range
  const auto range_max_nan = [&](std::size_t b, std::size_t e) {
    double m = -1e300;
    for (std::size_t i = b; i < e; ++i)
      if (a[i] > m || a[i] != a[i]) m = a[i];
    return m;
  };
  EXPECT_TRUE(std::isnan(par::max_over_ranges(n, 4, range_max_nan)));
}

// Several callers at once (minimisations on different threads): one gets the workers, the
// others run their ranges themselves; every result is complete.
TEST(Parallel, ConcurrentCallersEachGetTheirWholePass) {
  const std::size_t n = 4 * par::min_per_thread + 5;
  std::vector<std::thread> callers;
  std::atomic<int> failures{0};
  for (int c = 0; c < 4; ++c) {
    callers.emplace_back([&, c] {
      std::vector<double> x(n, 0.0);
      for (int rep = 0; rep < 50; ++rep) {
        par::for_ranges(n, 3, [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i)
            x[i] += static_cast<double>(c + 1);
        });
      }
      for (std::size_t i = 0; i < n; ++i)
        if (x[i] != 50.0 * (c + 1)) {
          ++failures;
          break;
        }
    });
  }
  for (auto& t : callers)
    t.join();
  EXPECT_EQ(failures, 0);
}

namespace {

// The slider's problem with the threads of its vector passes set apart from its FFT threads
// (those change FFTW's round-off; these must not change anything).
class ThreadedLfm final : public minimize::Problem {
 public:
  ThreadedLfm(slide::LfmProblem& p, const interface::LateralForceModel& lfm, int threads)
      : p_(p), lfm_(lfm), threads_(threads) {}
  [[nodiscard]] std::size_t size() const override { return p_.size(); }
  void compliance(std::span<const double> f, std::span<double> u) override { p_.compliance(f, u); }
  double interface(std::span<const double> u, std::span<double> f_int) const override {
    return lfm_.energy_and_force(u, f_int, threads_);
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    p_.curvature(u, h);
  }
  [[nodiscard]] bool wants_filter(bool automatic) const override {
    return p_.wants_filter(automatic);
  }
  void filter(std::span<const double> r, std::span<double> w) override { p_.filter(r, w); }
  [[nodiscard]] std::size_t gf_applications() const override { return p_.gf_applications(); }
  [[nodiscard]] int threads() const override { return threads_; }

 private:
  slide::LfmProblem& p_;
  const interface::LateralForceModel& lfm_;
  int threads_;
};

}  // namespace

// a = 150 d: 70 700 contact sites, so that the interface's per-site pass splits in two and the
// minimisers' passes over 141 000 unknowns in four, at range edges that are not the x/y
// boundary.
TEST(Parallel, InterfaceTermsAreBitForBitTheSameOnOneThreadOrSeveral) {
  interface::ContactScene scene;
  scene.a = 150.0;
  scene.R = 400.0;
  const LatticeBlock block = LatticeBlock::centred_disk(scene.a + 2.0);
  interface::LateralForceModel lfm(scene, block);
  lfm.set_tip(0.31);
  const std::size_t m = lfm.contact_sites().size();
  ASSERT_GE(par::threads_for(m, 4), 2) << "the contact is too small to test threads";
  std::vector<double> u(2 * m);
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = 0.4 * std::sin(0.0137 * static_cast<double>(i));
  std::vector<double> f1(2 * m), f(2 * m);
  const double v1 = lfm.energy_and_force(u, f1, 1);
  for (const int threads : {2, 4}) {
    const double v = lfm.energy_and_force(u, f, threads);
    EXPECT_EQ(v, v1) << threads << " threads";
    EXPECT_EQ(std::memcmp(f.data(), f1.data(), f.size() * sizeof(double)), 0)
        << threads << " threads";
  }
}

TEST(Parallel, MinimisationsAreBitForBitTheSameOnOneThreadOrSeveral) {
  interface::ContactScene scene;
  scene.a = 150.0;
  scene.R = 400.0;
  const LatticeBlock block = LatticeBlock::centred_disk(scene.a + 2.0);
  elastic::FreeSurfaceGF gf(scene.material, elastic::Components::in_plane, block.shape);
  interface::LateralForceModel lfm(scene, block);
  lfm.set_tip(0.31);
  slide::LfmProblem base(gf, lfm);
  const std::size_t n = base.size();
  ASSERT_EQ(par::threads_for(n, 4), 4) << "the contact is too small to test four threads";
  for (const auto method : {minimize::Method::lbfgs, minimize::Method::cg}) {
    minimize::MinimizerOptions o;
    o.method = method;
    o.max_iterations = 25;
    o.force_tolerance = 1e-12;  // stop on the count: 25 iterations, every pass many times
    o.stability = minimize::StabilityCheck::none;
    std::vector<std::vector<double>> ends;
    std::vector<double> energies;
    for (const int threads : {1, 2, 4}) {
      ThreadedLfm problem(base, lfm, threads);
      std::vector<double> u(n, 0.0), f(n, 0.0);
      const auto res = minimize::minimize(problem, u, f, o);
      EXPECT_EQ(res.iterations, 25);
      ends.push_back(u);
      energies.push_back(res.energy);
    }
    for (std::size_t k = 1; k < ends.size(); ++k) {
      EXPECT_EQ(std::memcmp(ends[0].data(), ends[k].data(), n * sizeof(double)), 0)
          << "method " << static_cast<int>(method) << ", run " << k;
      EXPECT_EQ(energies[0], energies[k]);
    }
  }
}
