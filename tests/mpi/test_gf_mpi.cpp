// The free-surface Green's function on the FFTW-MPI engine (issue 26) against the serial one,
// under mpirun with 1, 2 and 3 ranks: every rank holds an even share of the region rows, in rank
// order (moved to and from the slabs of the padded grid that transform them), and gets
// u = G * f on them. Every rank
// builds the same global force field and applies the serial GF to all of it. Tolerance 1e-13 of
// the largest |u|: the backends split the transforms differently (rounding, not bits).
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fftw_mpi_engine.hpp"

namespace asperity::elastic {
namespace {

struct Case {
  Shape2 region;
  Components components;
  double nu;
};

class GfMpi : public ::testing::TestWithParam<Case> {};

std::vector<double> forces(std::size_t n, int seed) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v)
    x = u(rng);
  return v;
}

TEST_P(GfMpi, LocalRowsHoldTheSerialDisplacements) {
  const Case c = GetParam();
  const Material m{1.0, c.nu};
  FreeSurfaceGF serial(m, c.components, c.region);
  FreeSurfaceGF dist(m, c.components, c.region, 1.0, {}, fft::mpi_engine_factory(MPI_COMM_WORLD));
  const int nc = serial.ncomp();
  const std::size_t n = c.region.count(), n1 = static_cast<std::size_t>(c.region.n1);
  const std::vector<double> f = forces(nc * n, 7);
  std::vector<double> u(nc * n);
  serial.apply(f, u);

  const int begin = dist.local_row_begin(), rows = dist.local_rows();
  const std::size_t local = static_cast<std::size_t>(rows) * n1;
  ASSERT_EQ(dist.size(), nc * local);
  std::vector<double> f_local(nc * local), u_local(nc * local);
  for (int k = 0; k < nc; ++k)
    std::copy_n(f.begin() + static_cast<std::ptrdiff_t>(k * n + begin * n1), local,
                f_local.begin() + static_cast<std::ptrdiff_t>(k * local));
  dist.apply(f_local, u_local);
  const double scale = *std::max_element(
      u.begin(), u.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  for (int k = 0; k < nc; ++k) {
    for (std::size_t i = 0; i < local; ++i) {
      EXPECT_NEAR(u_local[k * local + i], u[k * n + begin * n1 + i], 1e-13 * std::abs(scale))
          << "component " << k << " site " << begin * n1 + i;
    }
  }
  // An even share of the rows, in rank order; every region row is held once.
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  EXPECT_EQ(begin, rank * c.region.n0 / ranks);
  EXPECT_EQ(rows, (rank + 1) * c.region.n0 / ranks - begin);
  int held = rows;
  MPI_Allreduce(MPI_IN_PLACE, &held, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(held, c.region.n0);

  if (c.components != Components::in_plane) return;
  // The site-list form and the filter on the local rows: every other local site.
  std::vector<std::size_t> sites;
  for (std::size_t i = 0; i < local; i += 2)
    sites.push_back(i);
  std::vector<double> fs(nc * sites.size()), us(fs.size()), ws(fs.size());
  std::vector<double> f_sparse(nc * n, 0.0);
  for (int k = 0; k < nc; ++k) {
    for (std::size_t j = 0; j < sites.size(); ++j) {
      fs[k * sites.size() + j] = f_local[k * local + sites[j]];
    }
  }
  dist.apply(sites, fs, us);
  dist.apply_filter(sites, fs, ws, 0.5);
  // The serial answer: the sparse field of every rank together.
  std::vector<double> f_all(nc * n, 0.0);
  for (int k = 0; k < nc; ++k) {
    for (std::size_t j = 0; j < sites.size(); ++j)
      f_all[k * n + begin * n1 + sites[j]] = fs[k * sites.size() + j];
  }
  MPI_Allreduce(MPI_IN_PLACE, f_all.data(), static_cast<int>(f_all.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  std::vector<double> u_all(nc * n), w_all(nc * n);
  serial.apply(f_all, u_all);
  serial.apply_filter(f_all, w_all, 0.5);
  for (int k = 0; k < nc; ++k) {
    for (std::size_t j = 0; j < sites.size(); ++j) {
      const std::size_t g = k * n + begin * n1 + sites[j];
      EXPECT_NEAR(us[k * sites.size() + j], u_all[g], 1e-13 * std::abs(scale));
      EXPECT_NEAR(ws[k * sites.size() + j], w_all[g], 1e-13);
    }
  }
}

// The slides' case (in-plane, nu = 0.5), and the explicit model's (full, nu = 0.3: the
// imaginary normal-lateral coupling); 21 rows (a 42-row padded grid: 14 rows per rank on 3, the
// third holding padding only), 8 rows on 3 ranks.
INSTANTIATE_TEST_SUITE_P(Cases, GfMpi,
                         ::testing::Values(Case{{21, 13}, Components::in_plane, 0.5},
                                           Case{{8, 30}, Components::in_plane, 0.5},
                                           Case{{12, 11}, Components::full, 0.3}));

// The periodic cell's GF (the Peierls cell) on the FFTW-MPI engine: each rank holds the cell
// rows of its slab and gets u = G * f (and f = K * u) on them, against the serial GF on the whole
// cell; tolerance 1e-13 of the largest value, as above. Cells of 24 x 10 (8 rows per rank on 3)
// and 7 x 16 (uneven slabs: 3, 3, 1), both component sets.
TEST(PeriodicGfMpi, LocalRowsHoldTheSerialFields) {
  for (const auto& [cell, components] : {std::pair{Shape2{24, 10}, Components::in_plane},
                                         std::pair{Shape2{7, 16}, Components::full}}) {
    const Material m{1.0, 0.3};
    PeriodicSurfaceGF serial(m, components, cell);
    PeriodicSurfaceGF dist(m, components, cell, 1.0, {}, 12,
                           fft::mpi_engine_factory(MPI_COMM_WORLD));
    const int nc = serial.ncomp();
    const std::size_t n = cell.count(), n1 = static_cast<std::size_t>(cell.n1);
    const std::size_t begin = static_cast<std::size_t>(dist.local_row_begin());
    const std::size_t local = static_cast<std::size_t>(dist.local_rows()) * n1;
    ASSERT_EQ(dist.size(), nc * local);
    const std::vector<double> f = forces(nc * n, 11);
    std::vector<double> u(nc * n), k(nc * n), f_local(nc * local), u_local(nc * local),
        k_local(nc * local);
    serial.apply(f, u);
    serial.apply_stiffness(f, k);
    for (int c = 0; c < nc; ++c)
      std::copy_n(f.begin() + static_cast<std::ptrdiff_t>(c * n + begin * n1), local,
                  f_local.begin() + static_cast<std::ptrdiff_t>(c * local));
    dist.apply(f_local, u_local);
    dist.apply_stiffness(f_local, k_local);
    const auto largest = [](const std::vector<double>& v) {
      double x = 0.0;
      for (double e : v)
        x = std::max(x, std::abs(e));
      return x;
    };
    for (int c = 0; c < nc; ++c) {
      for (std::size_t i = 0; i < local; ++i) {
        EXPECT_NEAR(u_local[c * local + i], u[c * n + begin * n1 + i], 1e-13 * largest(u));
        EXPECT_NEAR(k_local[c * local + i], k[c * n + begin * n1 + i], 1e-13 * largest(k));
      }
    }
    int held = dist.local_rows();
    MPI_Allreduce(MPI_IN_PLACE, &held, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(held, cell.n0);
  }
}

}  // namespace
}  // namespace asperity::elastic
