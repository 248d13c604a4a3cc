// Analytic tier: free and periodic boundaries agree for a small loaded patch in a large cell.
//
// Analytic answer: the periodic kernel is the exact periodisation of the free one (Poisson
// summation, surface_gf.hpp), so for a self-equilibrated load (zero net force: a net force has
// no static solution in a periodic cell) the two displacement fields near the load differ only
// by a rigid shift plus the field of the periodic images. The images of a force dipole of arm s
// act at distance L with a field ~ s / L^2 relative to the near field ~ 1/s, so the relative
// difference is of order (s / L)^2. Tolerance: 4 (s/L)^2 relative to the largest displacement,
// and the difference must fall at least 3x when L doubles (4x or more expected).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"

using namespace asperity;
using elastic::Components;

namespace {

// Max over a window of radius 8 d around the load of |u_periodic - u_free - shift|, relative to
// max |u_free| there; shift = mean difference over the window.
double difference(int L, Components comps, double nu) {
  const elastic::Material m{.G = 1.0, .nu = nu};
  const Shape2 cell{L, L};
  const int s = 4;  // dipole arm, sites
  const int c0 = L / 2, c1 = L / 2;
  // Enough Poisson images that their truncation (about 6e-5 relative at the default 12, see
  // the unit test ImageSumConverges) stays below the image effect measured here.
  elastic::PeriodicSurfaceGF periodic(m, comps, cell, 1.0, {}, 32);
  // The free block only needs to hold the load and the window.
  const int half = 10;
  const Shape2 block{2 * half + 1, 2 * half + 1};
  elastic::FreeSurfaceGF free_gf(m, comps, block);
  const int nc = periodic.ncomp();
  std::vector<double> fp(periodic.size(), 0.0), up(periodic.size());
  std::vector<double> ff(free_gf.size(), 0.0), uf(free_gf.size());
  // Per component, +F at the centre and -F at (s, s/2) away: zero net force, non-zero moment.
  for (int c = 0; c < nc; ++c) {
    const double F = 1.0 + 0.5 * c;
    fp[c * cell.count() + cell.index(c0, c1)] += F;
    fp[c * cell.count() + cell.index(c0 + s, c1 + s / 2)] -= F;
    ff[c * block.count() + block.index(half, half)] += F;
    ff[c * block.count() + block.index(half + s, half + s / 2)] -= F;
  }
  periodic.apply(fp, up);
  free_gf.apply(ff, uf);
  double worst = 0.0, size = 0.0;
  for (int c = 0; c < nc; ++c) {
    double shift = 0.0;
    int count = 0;
    std::vector<std::pair<double, double>> pairs;
    for (int a = -8; a <= 8; ++a) {
      for (int b = -8; b <= 8; ++b) {
        if (a * a + b * b > 64) continue;
        const double vp = up[c * cell.count() + cell.index(c0 + a, c1 + b)];
        const double vf = uf[c * block.count() + block.index(half + a, half + b)];
        pairs.emplace_back(vp, vf);
        shift += vp - vf;
        ++count;
        size = std::max(size, std::abs(vf));
      }
    }
    shift /= count;
    for (auto [vp, vf] : pairs)
      worst = std::max(worst, std::abs(vp - vf - shift));
  }
  return worst / size;
}

}  // namespace

TEST(PeriodicVsFree, SmallPatchInLargeCell) {
  for (auto [comps, nu] : {std::pair{Components::in_plane, 0.5},
                           {Components::full, 0.3},
                           {Components::normal, 0.25}}) {
    const double d64 = difference(64, comps, nu);
    const double d128 = difference(128, comps, nu);
    std::printf("periodic vs free, %d components, nu=%.2f: L=64 %.2e, L=128 %.2e\n",
                elastic::component_count(comps), nu, d64, d128);
    EXPECT_LT(d128, 4.0 * std::pow(4.0 / 128.0, 2));
    EXPECT_LT(d128, d64 / 3.0);
  }
}
