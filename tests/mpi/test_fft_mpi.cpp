// The FFTW-MPI engine against the serial one (issue 26), under mpirun with 1, 2 and 3 ranks
// (tests/mpi/CMakeLists.txt). Every rank builds the same global field (a fixed generator), the
// serial engine transforms all of it on every rank, the distributed engine its slab; the slabs
// must hold the serial numbers. Tolerance: 1e-13 of the field's largest value (Fourier values:
// 1e-13 sqrt(N), their typical size for unit noise) — the two backends
// split the same transforms differently (FFTW-MPI's 1D transforms and transposes against the
// serial 2D plan), so they agree to rounding, not bit for bit.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "asperity/core/fft/fftw_mpi_engine.hpp"

namespace asperity::fft {
namespace {

std::vector<double> global_field(Shape2 s, int seed) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(s.count());
  for (double& x : v)
    x = u(rng);
  return v;
}

// A multiplier that is not symmetric in k0 (a phase), so that a block handed out at the wrong
// wave vector shows.
std::complex<double> kernel(int k0, int k1, Shape2 s) {
  const double q0 = 2.0 * M_PI * std::min(k0, s.n0 - k0) / s.n0, q1 = 2.0 * M_PI * k1 / s.n1;
  return std::exp(-0.7 * (q0 * q0 + q1 * q1)) * std::polar(1.0, 0.3 * k0 - 0.2 * k1);
}

Multiplier multiplier(Shape2 s, int fields) {
  return [s, fields](const FourierBlock& b) {
    for (int k0 = 0; k0 < b.rows; ++k0) {
      for (int j = 0; j < b.width; ++j) {
        const std::complex<double> m = kernel(k0, b.k1_begin + j, s);
        for (int f = 0; f < fields; ++f)
          b.field[f][k0 * b.width + j] *= m;
      }
    }
  };
}

class FftMpi : public ::testing::TestWithParam<Shape2> {};

TEST_P(FftMpi, SlabsHoldTheSerialConvolution) {
  const Shape2 s = GetParam();
  const int fields = 2;
  auto serial = make_engine(s, fields);
  auto dist = make_mpi_engine(MPI_COMM_WORLD, s, fields);
  const Layout l = dist->layout();
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  EXPECT_EQ(l.ranks, ranks);
  EXPECT_TRUE(l.fourier_transposed);
  double scale = 0.0;
  for (int f = 0; f < fields; ++f) {
    const std::vector<double> g = global_field(s, 11 + f);
    scale = std::max(scale, *std::max_element(g.begin(), g.end()));
    std::copy(g.begin(), g.end(), serial->input(f).begin());
    ASSERT_EQ(dist->input(f).size(), static_cast<std::size_t>(l.rows) * s.n1);
    std::copy_n(g.begin() + static_cast<std::ptrdiff_t>(l.row_begin) * s.n1, l.rows * s.n1,
                dist->input(f).begin());
  }
  serial->convolve(multiplier(s, fields));
  dist->convolve(multiplier(s, fields));
  for (int f = 0; f < fields; ++f) {
    for (int r = 0; r < l.rows; ++r) {
      for (int c = 0; c < s.n1; ++c) {
        const double want = serial->output(f)[static_cast<std::size_t>(l.row_begin + r) * s.n1 + c];
        EXPECT_NEAR(dist->output(f)[static_cast<std::size_t>(r) * s.n1 + c], want, 1e-13 * scale)
            << "field " << f << " row " << l.row_begin + r << " column " << c;
      }
    }
  }
  // The rows of every rank together are the grid, once each.
  int rows = l.rows;
  MPI_Allreduce(MPI_IN_PLACE, &rows, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(rows, s.n0);
}

TEST_P(FftMpi, FourierColumnsAreTheSerialOnesTransposed) {
  const Shape2 s = GetParam();
  auto serial = make_engine(s, 1);
  auto dist = make_mpi_engine(MPI_COMM_WORLD, s, 1);
  const Layout l = dist->layout();
  const std::vector<double> g = global_field(s, 5);
  std::copy(g.begin(), g.end(), serial->input(0).begin());
  std::copy_n(g.begin() + static_cast<std::ptrdiff_t>(l.row_begin) * s.n1, l.rows * s.n1,
              dist->input(0).begin());
  serial->forward();
  dist->forward();
  const int h = s.n1 / 2 + 1;
  const std::vector<std::size_t> order = dist->block_order();
  ASSERT_EQ(order.size(), static_cast<std::size_t>(l.k1_count) * s.n0);
  for (int j = 0; j < l.k1_count; ++j) {
    for (int k0 = 0; k0 < s.n0; ++k0) {
      const std::size_t p = static_cast<std::size_t>(j) * s.n0 + k0;
      const std::size_t natural = static_cast<std::size_t>(k0) * h + l.k1_begin + j;
      EXPECT_EQ(order[p], natural);
      EXPECT_LT(std::abs(dist->fourier(0)[p] - serial->fourier(0)[natural]),
                1e-13 * std::sqrt(static_cast<double>(s.count())));
    }
  }
  int columns = l.k1_count;
  MPI_Allreduce(MPI_IN_PLACE, &columns, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(columns, h);
}

TEST_P(FftMpi, ReductionsSpanTheRanks) {
  auto dist = make_mpi_engine(MPI_COMM_WORLD, GetParam(), 1);
  const Layout l = dist->layout();
  EXPECT_EQ(dist->comm().sum(1.0), static_cast<double>(l.ranks));
  EXPECT_EQ(dist->comm().max(static_cast<double>(l.rank)), static_cast<double>(l.ranks - 1));
}

// Even and uneven slabs: 31 rows and 9 Fourier columns over 2 or 3 ranks leave unequal shares.
INSTANTIATE_TEST_SUITE_P(Shapes, FftMpi,
                         ::testing::Values(Shape2{16, 16}, Shape2{31, 17}, Shape2{12, 30}));

TEST(FftMpiInput, BadShapesThrow) {
  EXPECT_THROW(make_mpi_engine(MPI_COMM_WORLD, {0, 8}, 1), std::invalid_argument);
  EXPECT_THROW(make_mpi_engine(MPI_COMM_WORLD, {8, 8}, 4), std::invalid_argument);
}

}  // namespace
}  // namespace asperity::fft
