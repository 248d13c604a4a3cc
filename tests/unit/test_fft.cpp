// Unit tier: the FFT layer (round trip, conventions, planning options, sizes).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/fft/fft_engine.hpp"

using asperity::Shape2;
namespace fft = asperity::fft;

TEST(NextFftSize, SmoothNumbers) {
  EXPECT_EQ(asperity::next_fft_size(0), 1);
  EXPECT_EQ(asperity::next_fft_size(1), 1);
  EXPECT_EQ(asperity::next_fft_size(2), 2);
  EXPECT_EQ(asperity::next_fft_size(3), 4);  // 3 is smooth but odd
  EXPECT_EQ(asperity::next_fft_size(11), 12);
  EXPECT_EQ(asperity::next_fft_size(13), 14);
  EXPECT_EQ(asperity::next_fft_size(1023), 1024);
  EXPECT_EQ(asperity::next_fft_size(1025), 1050);  // not 1029 = 3 * 7^3 (odd); 2 * 3 * 5^2 * 7
  EXPECT_EQ(asperity::next_fft_size(1209), 1250);  // not 1215 = 3^5 * 5 (a = 300 d, R = 800 d)
  EXPECT_EQ(asperity::next_fft_size(85), 90);      // 85 = 5 * 17 -> 90 = 2 * 3^2 * 5
  // Every answer is even, 7-smooth and the least such: checked against a brute-force search.
  const auto smooth_even = [](int n) {
    if (n % 2 != 0) return false;
    for (int p : {2, 3, 5, 7}) {
      while (n % p == 0)
        n /= p;
    }
    return n == 1;
  };
  for (int m = 2; m < 5000; ++m) {
    const int n = asperity::next_fft_size(m);
    ASSERT_TRUE(n >= m && smooth_even(n)) << m << " -> " << n;
    for (int k = m; k < n; ++k)
      ASSERT_FALSE(smooth_even(k)) << m << " -> " << n << " skips " << k;
  }
}

TEST(FFTEngine, RoundTripAndConvention) {
  for (int threads : {1, 2}) {
    const Shape2 s{12, 10};
    auto e = fft::make_engine(s, 2, {.threads = threads});
    for (int f = 0; f < 2; ++f) {
      auto in = e->input(f);
      for (std::size_t i = 0; i < in.size(); ++i)
        in[i] = std::sin(0.3 * static_cast<double>(i) + f);
    }
    e->forward();
    // FFTW_FORWARD convention: a pure mode cos(2 pi k1 i1 / n1) has X(0, k1) = n / 2.
    e->inverse();
    for (int f = 0; f < 2; ++f) {
      auto out = e->output(f);
      for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_NEAR(out[i] * e->normalisation(), std::sin(0.3 * static_cast<double>(i) + f), 1e-13);
      }
    }
  }
}

TEST(FFTEngine, ForwardSignConvention) {
  const Shape2 s{4, 8};
  auto e = fft::make_engine(s, 1);
  auto in = e->input(0);
  for (int i0 = 0; i0 < s.n0; ++i0) {
    for (int i1 = 0; i1 < s.n1; ++i1) {
      in[s.index(i0, i1)] = std::sin(2.0 * std::numbers::pi * i1 / s.n1);
    }
  }
  e->forward();
  // sin(q x) = (e^{iqx} - e^{-iqx}) / 2i: with exp(-i q x) the k1 = 1 coefficient is -i n / 2.
  const auto X = e->fourier(0);
  EXPECT_NEAR(X[1].real(), 0.0, 1e-12);
  EXPECT_NEAR(X[1].imag(), -0.5 * static_cast<double>(s.count()), 1e-12);
}

TEST(FFTEngine, MeasurePlannerGivesSameResult) {
  const Shape2 s{16, 18};
  auto a = fft::make_engine(s, 1, {.planner = fft::Planner::estimate});
  auto b = fft::make_engine(s, 1, {.planner = fft::Planner::measure});
  for (std::size_t i = 0; i < s.count(); ++i) {
    a->input(0)[i] = b->input(0)[i] = std::cos(0.17 * static_cast<double>(i * i));
  }
  a->forward();
  b->forward();
  for (std::size_t i = 0; i < a->fourier(0).size(); ++i) {
    EXPECT_NEAR(std::abs(a->fourier(0)[i] - b->fourier(0)[i]), 0.0, 1e-11);
  }
}

// Engine::block_order() is the order in which convolve() hands out the half-grid: a permutation
// of it, and FourierBlock::offset + k0 * width + j is wave vector (k0, k1_begin + j) in it, for
// every block (the free-surface GF stores its kernels in this order). Shapes with one block,
// several, and a partial last one; one and two threads.
TEST(FFTEngine, BlockOrderIsWhatConvolveVisits) {
  for (const Shape2 s : {Shape2{6, 4}, Shape2{12, 30}, Shape2{10, 34}}) {
    for (int threads : {1, 2}) {
      auto e = fft::make_engine(s, 1, {.threads = threads}, s.n0 / 2);
      const Shape2 fs = e->fourier_shape();
      const auto order = e->block_order();
      ASSERT_EQ(order.size(), fs.count());
      std::vector<int> seen(fs.count(), 0);
      for (std::size_t i : order) {
        ASSERT_LT(i, fs.count());
        ++seen[i];
      }
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(fs.count()));
      std::vector<int> visited(fs.count(), 0);
      std::mutex m;
      e->convolve([&](const fft::FourierBlock& b) {
        std::lock_guard<std::mutex> lock(m);
        for (int k0 = 0; k0 < b.rows; ++k0) {
          for (int j = 0; j < b.width; ++j) {
            const std::size_t p = b.offset + static_cast<std::size_t>(k0 * b.width + j);
            if (p < order.size() && order[p] == fs.index(k0, b.k1_begin + j)) ++visited[p];
          }
        }
      });
      EXPECT_EQ(std::count(visited.begin(), visited.end(), 1), static_cast<long>(fs.count()))
          << s.n0 << " x " << s.n1 << ", " << threads << " threads";
    }
  }
}

// convolve() on several threads: the calling thread and the workers claim units (row batches,
// column blocks) from counters, so who runs what changes from call to call. The output must not:
// it is the same bits on every call and for 2 and 3 threads as for 2 threads the first time,
// within round-off of one thread's (whose single row batch FFTW may plan differently), and it
// is the zero-padded convolution (checked against forward() and inverse() of the whole grid).
// 192 x 160 is over min_points_per_worker per thread for 3 threads; 300 calls so that late and
// early workers both happen.
TEST(FFTEngine, ConvolveOnThreadsIsTheSameBitsWhoeverRunsWhat) {
  const Shape2 s{192, 160};
  const int support = 96;
  const auto load = [&](fft::Engine& e) {
    for (int f = 0; f < 2; ++f) {
      auto in = e.input(f);
      std::fill(in.begin(), in.end(), 0.0);
      for (std::size_t i = 0; i < static_cast<std::size_t>(support) * s.n1; ++i)
        in[i] = std::sin(0.013 * static_cast<double>(i) + f) + 0.1 * f;
    }
  };
  // A multiplier that depends on the wave vector and mixes the fields, like the GF's.
  const auto multiplier = [&](double norm) {
    return [norm](const fft::FourierBlock& b) {
      for (int k0 = 0; k0 < b.rows; ++k0) {
        for (int j = 0; j < b.width; ++j) {
          const std::size_t i = static_cast<std::size_t>(k0) * b.width + j;
          const double w = norm / (1.0 + 0.01 * k0 + 0.02 * (b.k1_begin + j));
          const std::complex<double> x = b.field[0][i], y = b.field[1][i];
          b.field[0][i] = w * (x + 0.5 * y);
          b.field[1][i] = w * (0.5 * x - y);
        }
      }
    };
  };
  const auto rows = [&](fft::Engine& e, int f) {
    auto out = e.output(f);
    return std::vector<double>(out.begin(),
                               out.begin() + static_cast<std::ptrdiff_t>(support) * s.n1);
  };
  std::vector<double> first[2];
  for (int threads : {2, 3}) {
    auto e = fft::make_engine(s, 2, {.threads = threads}, support);
    load(*e);
    const fft::Multiplier m = multiplier(e->normalisation());
    for (int call = 0; call < 300; ++call) {
      e->convolve(m);
      for (int f = 0; f < 2; ++f) {
        const auto got = rows(*e, f);
        if (first[f].empty()) first[f] = got;
        ASSERT_TRUE(got == first[f]) << threads << " threads, call " << call << ", field " << f;
      }
    }
  }
  // One thread, and the whole-grid transforms.
  auto one = fft::make_engine(s, 2, {.threads = 1}, support);
  load(*one);
  one->convolve(multiplier(one->normalisation()));
  auto whole = fft::make_engine(s, 2, {.threads = 1});
  load(*whole);
  whole->forward();
  const Shape2 fs = whole->fourier_shape();
  for (int k0 = 0; k0 < fs.n0; ++k0) {
    for (int k1 = 0; k1 < fs.n1; ++k1) {
      const double w = whole->normalisation() / (1.0 + 0.01 * k0 + 0.02 * k1);
      const std::complex<double> x = whole->fourier(0)[fs.index(k0, k1)],
                                 y = whole->fourier(1)[fs.index(k0, k1)];
      whole->fourier(0)[fs.index(k0, k1)] = w * (x + 0.5 * y);
      whole->fourier(1)[fs.index(k0, k1)] = w * (0.5 * x - y);
    }
  }
  whole->inverse();
  for (int f = 0; f < 2; ++f) {
    const auto a = rows(*one, f), b = rows(*whole, f);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_NEAR(first[f][i], a[i], 1e-12) << "field " << f << " at " << i;
      ASSERT_NEAR(a[i], b[i], 1e-12) << "field " << f << " at " << i;
    }
  }
}

TEST(FFTEngine, RejectsBadInput) {
  EXPECT_THROW(fft::make_engine({0, 4}, 1), std::invalid_argument);
  EXPECT_THROW(fft::make_engine({4, 4}, 0), std::invalid_argument);
  EXPECT_THROW(fft::make_engine({4, 4}, 1, {.threads = 0}), std::invalid_argument);
  EXPECT_THROW(fft::planner_from_string("fast"), std::invalid_argument);
  EXPECT_EQ(fft::planner_from_string("measure"), fft::Planner::measure);
}

// The serial engine holds the whole grid (fft::Layout), and its reductions are identities: the
// interface a distributed engine implements (issue 26).
TEST(FFTEngine, SerialLayoutIsTheWholeGrid) {
  const auto e = fft::make_engine({12, 10}, 1);
  const fft::Layout l = e->layout();
  EXPECT_TRUE(l.whole());
  EXPECT_EQ(l.global.n0, 12);
  EXPECT_EQ(l.global.n1, 10);
  EXPECT_EQ(l.row_begin, 0);
  EXPECT_EQ(l.rows, 12);
  EXPECT_EQ(l.k1_begin, 0);
  EXPECT_EQ(l.k1_count, 6);
  EXPECT_FALSE(l.fourier_transposed);
  EXPECT_FALSE(e->comm().distributed());
}
