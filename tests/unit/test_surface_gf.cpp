// Unit tier: the discrete surface Green's functions (MODEL.md section 2). Checks the FFT
// convolution against the direct sum, reciprocity, positivity, the closed-form patch
// coefficients against quadrature, and the periodic compliance/stiffness pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "asperity/core/elastic/influence.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

using namespace asperity;
using elastic::Components;
using elastic::Material;

namespace {

std::vector<double> random_field(std::size_t n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v)
    x = dist(gen);
  return v;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    s += a[i] * b[i];
  return s;
}

// Gauss-Legendre quadrature of the point-force solution over a d x d patch.
double patch_by_quadrature(const Material& m, int i, int j, double x, double y, double d) {
  static const double node[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
  static const double weight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                   0.4786286704993665, 0.2369268850561891};
  const int sub = 8;  // sub-squares per side, 5x5 points each
  double s = 0.0;
  for (int a = 0; a < sub; ++a) {
    for (int b = 0; b < sub; ++b) {
      for (int p = 0; p < 5; ++p) {
        for (int q = 0; q < 5; ++q) {
          const double xs = d * (-0.5 + (a + 0.5 + 0.5 * node[p]) / sub);
          const double ys = d * (-0.5 + (b + 0.5 + 0.5 * node[q]) / sub);
          s += weight[p] * weight[q] * elastic::point_force_gf(m, i, j, x - xs, y - ys);
        }
      }
    }
  }
  return s / (4.0 * sub * sub);
}

}  // namespace

TEST(PatchCoefficients, SelfTermsMatchClosedForm) {
  const Material m{.G = 2.0, .nu = 0.3};
  const double d = 1.5;
  // int int_{[-h,h]^2} dA / r = 8 h asinh(1): the self compliance of a uniformly loaded square.
  const double mean_inv_r = 4.0 * std::asinh(1.0) / d;
  const double c = 1.0 / (2.0 * std::numbers::pi * m.G);
  EXPECT_NEAR(elastic::patch_gf(m, 2, 2, 0, 0, d), c * (1.0 - m.nu) * mean_inv_r, 1e-14);
  // x^2/r^3 averages to half of 1/r over a square, by symmetry.
  EXPECT_NEAR(elastic::patch_gf(m, 0, 0, 0, 0, d), c * (1.0 - 0.5 * m.nu) * mean_inv_r, 1e-14);
  EXPECT_NEAR(elastic::patch_gf(m, 0, 1, 0, 0, d), 0.0, 1e-15);
  EXPECT_NEAR(elastic::patch_gf(m, 0, 2, 0, 0, d), 0.0, 1e-15);
}

TEST(PatchCoefficients, ClosedFormsMatchQuadrature) {
  const Material m{.G = 1.0, .nu = 0.27};
  for (auto [x, y] : {std::pair{2.0, 0.0}, {1.0, 2.0}, {-3.0, 1.0}, {2.0, -2.0}, {0.0, -3.0}}) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const double exact = elastic::patch_gf(m, i, j, x, y, 1.0);
        const double quad = patch_by_quadrature(m, i, j, x, y, 1.0);
        EXPECT_NEAR(exact, quad, 1e-9) << "component " << i << j << " at " << x << "," << y;
      }
    }
  }
}

TEST(FreeSurfaceGF, FFTConvolutionEqualsDirectSum) {
  // Small and larger blocks (several column blocks in the engine's fused convolution, a partial
  // last one), one and two threads.
  for (auto [region, threads] : {std::pair{Shape2{7, 5}, 1}, {Shape2{20, 23}, 2}}) {
    for (Components comps : {Components::in_plane, Components::normal, Components::full}) {
      const Material m{.G = 1.3, .nu = 0.3};
      elastic::FreeSurfaceGF gf(m, comps, region, 0.8, {.threads = threads});
      const auto f = random_field(gf.size(), 1);
      std::vector<double> u(gf.size());
      gf.apply(f, u);
      const std::size_t n = region.count();
      for (int k = 0; k < gf.ncomp(); ++k) {
        for (int a0 = 0; a0 < region.n0; ++a0) {
          for (int a1 = 0; a1 < region.n1; ++a1) {
            double direct = 0.0;
            for (int l = 0; l < gf.ncomp(); ++l) {
              for (int b0 = 0; b0 < region.n0; ++b0) {
                for (int b1 = 0; b1 < region.n1; ++b1) {
                  direct +=
                      gf.coefficient(k, l, a0 - b0, a1 - b1) * f[l * n + region.index(b0, b1)];
                }
              }
            }
            EXPECT_NEAR(u[k * n + region.index(a0, a1)], direct, 1e-13);
          }
        }
      }
    }
  }
  EXPECT_EQ(elastic::FreeSurfaceGF(Material{}, Components::in_plane, {512, 512}).fft_shape(),
            (Shape2{1024, 1024}));
}

TEST(FreeSurfaceGF, SymmetricAndPositiveDefinite) {
  const Material m{.G = 1.0, .nu = 0.2};
  elastic::FreeSurfaceGF gf(m, Components::full, {16, 11});
  const auto f1 = random_field(gf.size(), 2);
  const auto f2 = random_field(gf.size(), 3);
  std::vector<double> u1(gf.size()), u2(gf.size());
  gf.apply(f1, u1);
  gf.apply(f2, u2);
  EXPECT_NEAR(dot(f1, u2), dot(f2, u1), 1e-12 * std::abs(dot(f1, u2)) + 1e-13);
  EXPECT_GT(elastic::elastic_energy(f1, u1), 0.0);
  EXPECT_EQ(gf.applications(), 2u);
}

// The interface filter M = R (I + c G~)^-1 R^T (apply_filter): identity at c = 0; first-order
// consistency, (M f - f) / c -> -G f as c -> 0 (which checks the kernel's FFT normalisation
// and the 2 x 2 inverse); symmetric; eigenvalues in (0, 1] (G positive semi-definite), seen
// through Rayleigh quotients of random fields, also at c large enough that the high-q part
// of G~ decides; kernels rebuilt when c changes; bad c and components rejected.
TEST(FreeSurfaceGF, InterfaceFilter) {
  const Material m{.G = 1.0, .nu = 0.5};
  elastic::FreeSurfaceGF gf(m, Components::in_plane, {21, 17}, 1.0, {.threads = 2});
  const auto f = random_field(gf.size(), 4), g = random_field(gf.size(), 5);
  std::vector<double> w(gf.size()), v(gf.size()), u(gf.size());
  gf.apply_filter(f, w, 0.0);
  for (std::size_t i = 0; i < f.size(); ++i)
    EXPECT_NEAR(w[i], f[i], 1e-14);

  // (M f - f)/eps = -G f + O(eps |G|^2), about 1e-7 relative here; a wrong normalisation or
  // inverse would be off by O(1).
  const double eps = 1e-7;
  gf.apply_filter(f, w, eps);
  gf.apply(f, u);
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    worst = std::max(worst, std::abs((w[i] - f[i]) / eps + u[i]));
    scale = std::max(scale, std::abs(u[i]));
  }
  EXPECT_LT(worst, 1e-5 * scale);

  for (double c : {0.3, 3.0, 300.0}) {
    gf.apply_filter(f, w, c);
    gf.apply_filter(g, v, c);
    EXPECT_NEAR(dot(f, v), dot(g, w), 1e-12 * dot(f, f));
    for (unsigned seed = 10; seed < 20; ++seed) {
      const auto x = random_field(gf.size(), seed);
      std::vector<double> mx(gf.size());
      gf.apply_filter(x, mx, c);
      const double q = dot(x, mx) / dot(x, x);
      EXPECT_GT(q, 0.0) << "c = " << c;
      EXPECT_LE(q, 1.0 + 1e-12) << "c = " << c;
    }
  }
  // A stiffer interface filters more: the Rayleigh quotient falls with c.
  gf.apply_filter(f, w, 0.3);
  const double q_soft = dot(f, w);
  gf.apply_filter(f, w, 3.0);
  EXPECT_LT(dot(f, w), q_soft);
  EXPECT_EQ(gf.applications(), 1u);          // the filter is not a GF application
  EXPECT_EQ(gf.filter_applications(), 40u);  // 1 + 1 + 3 x (2 + 10) + 2

  EXPECT_THROW(gf.apply_filter(f, w, -1.0), std::invalid_argument);
  EXPECT_THROW(gf.apply_filter(f, w, std::nan("")), std::invalid_argument);
  elastic::FreeSurfaceGF full(m, Components::full, {4, 4});
  std::vector<double> ff(full.size()), fw(full.size());
  EXPECT_THROW(full.apply_filter(ff, fw, 1.0), std::invalid_argument);
}

// apply(sites, ...) and apply_filter(sites, ...) (the slides' calls, on the contact sites only):
// equal to the whole-region calls on the scattered field, read back on the sites, bit for bit
// (the same transforms and products; only the copies differ). Interleaved with whole-region
// calls, which leave values in the engine's input that a site call must clear first; site
// calls in a row whose list shrinks, where the first call's sites must be cleared after it;
// sites in increasing and in scrambled order; bad sizes and indices rejected.
TEST(FreeSurfaceGF, SiteListCallsEqualWholeRegionCalls) {
  const Shape2 region{23, 19};
  for (Components comps : {Components::in_plane, Components::full}) {
    elastic::FreeSurfaceGF gf(Material{.G = 1.0, .nu = 0.3}, comps, region, 1.0, {.threads = 2});
    const std::size_t n = region.count(), nc = static_cast<std::size_t>(gf.ncomp());
    std::vector<std::size_t> sites;
    for (std::size_t i = 0; i < n; ++i) {
      if ((i * 7) % 5 != 0) sites.push_back(i);  // about four in five, gaps in every row
    }
    std::vector<std::size_t> scrambled = sites;
    std::reverse(scrambled.begin(), scrambled.end());
    std::swap(scrambled[3], scrambled[100]);
    for (const auto* list : {&sites, &scrambled}) {
      const std::size_t m = list->size();
      for (unsigned seed = 1; seed <= 3; ++seed) {
        const auto fs = random_field(nc * m, seed);
        std::vector<double> full(gf.size(), 0.0), out_full(gf.size()), out(nc * m);
        for (std::size_t c = 0; c < nc; ++c) {
          for (std::size_t j = 0; j < m; ++j)
            full[c * n + (*list)[j]] = fs[c * m + j];
        }
        // A whole-region call with another field first: the site call must not see it.
        const auto other = random_field(gf.size(), 50 + seed);
        gf.apply(other, out_full);
        gf.apply(*list, fs, out);
        gf.apply(full, out_full);
        for (std::size_t c = 0; c < nc; ++c) {
          for (std::size_t j = 0; j < m; ++j)
            ASSERT_EQ(out[c * m + j], out_full[c * n + (*list)[j]]) << "apply, site " << j;
        }
        if (comps == Components::in_plane) {
          gf.apply_filter(other, out_full, 2.0);
          gf.apply_filter(*list, fs, out, 2.0);
          gf.apply_filter(full, out_full, 2.0);
          for (std::size_t c = 0; c < nc; ++c) {
            for (std::size_t j = 0; j < m; ++j)
              ASSERT_EQ(out[c * m + j], out_full[c * n + (*list)[j]]) << "filter, site " << j;
          }
        }
        // Site calls in a row with a shrinking list (a contact that loses sites), no
        // whole-region call in between: the first must leave nothing behind on the sites the
        // second no longer lists. The reference comes first, so that its whole-region call
        // cleans nothing for the site calls after it.
        std::vector<std::size_t> fewer;
        for (std::size_t j = 0; j < m; j += 3)
          fewer.push_back((*list)[j]);
        const std::size_t k = fewer.size();
        const auto fk = random_field(nc * k, 70 + seed);
        std::vector<double> scattered(gf.size(), 0.0), reference(gf.size());
        for (std::size_t c = 0; c < nc; ++c) {
          for (std::size_t j = 0; j < k; ++j)
            scattered[c * n + fewer[j]] = fk[c * k + j];
        }
        gf.apply(scattered, reference);
        if (comps == Components::in_plane) {
          std::vector<double> filtered(gf.size()), wk(nc * k);
          gf.apply_filter(scattered, filtered, 2.0);
          gf.apply_filter(*list, fs, out, 2.0);
          gf.apply_filter(fewer, fk, wk, 2.0);
          for (std::size_t c = 0; c < nc; ++c) {
            for (std::size_t j = 0; j < k; ++j)
              ASSERT_EQ(wk[c * k + j], filtered[c * n + fewer[j]]) << "fewer, filter " << j;
          }
        }
        std::vector<double> uk(nc * k);
        gf.apply(*list, fs, out);
        gf.apply(fewer, fk, uk);
        for (std::size_t c = 0; c < nc; ++c) {
          for (std::size_t j = 0; j < k; ++j)
            ASSERT_EQ(uk[c * k + j], reference[c * n + fewer[j]]) << "fewer, site " << j;
        }
      }
    }
    std::vector<std::size_t> outside{0, n};
    std::vector<double> f2(nc * 2), u2(nc * 2), u3(nc * 3);
    EXPECT_THROW(gf.apply(outside, f2, u2), std::invalid_argument);
    EXPECT_THROW(gf.apply(std::vector<std::size_t>{0, 1}, f2, u3), std::invalid_argument);
    if (comps == Components::in_plane) {
      EXPECT_THROW(gf.apply_filter(outside, f2, u2, 1.0), std::invalid_argument);
      EXPECT_THROW(gf.apply_filter(std::vector<std::size_t>{0, 1}, f2, u3, 1.0),
                   std::invalid_argument);
    }
  }
}

TEST(FreeSurfaceGF, RejectsBadInput) {
  EXPECT_THROW(elastic::FreeSurfaceGF(Material{.G = -1.0}, Components::normal, {4, 4}),
               std::invalid_argument);
  EXPECT_THROW(elastic::FreeSurfaceGF(Material{.nu = 0.6}, Components::normal, {4, 4}),
               std::invalid_argument);
  EXPECT_THROW(elastic::FreeSurfaceGF(Material{}, Components::normal, {0, 4}),
               std::invalid_argument);
  EXPECT_THROW(elastic::FreeSurfaceGF(Material{}, Components::normal, {4, 4}, 0.0),
               std::invalid_argument);
  elastic::FreeSurfaceGF gf(Material{}, Components::in_plane, {4, 4});
  std::vector<double> f(gf.size() - 1), u(gf.size());
  EXPECT_THROW(gf.apply(f, u), std::invalid_argument);
}

TEST(PeriodicSurfaceGF, StiffnessInvertsComplianceOnZeroMeanFields) {
  for (Components comps : {Components::in_plane, Components::full}) {
    elastic::PeriodicSurfaceGF gf(Material{.G = 1.0, .nu = 0.25}, comps, {16, 12});
    auto f = random_field(gf.size(), 4);
    const std::size_t n = gf.cell().count();
    for (int c = 0; c < gf.ncomp(); ++c) {  // remove the mean force: no static response to it
      double mean = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        mean += f[c * n + i];
      mean /= static_cast<double>(n);
      for (std::size_t i = 0; i < n; ++i)
        f[c * n + i] -= mean;
    }
    std::vector<double> u(gf.size()), back(gf.size()), f2 = random_field(gf.size(), 5),
                                                       u2(gf.size());
    gf.apply(f, u);
    gf.apply_stiffness(u, back);
    for (std::size_t i = 0; i < f.size(); ++i)
      EXPECT_NEAR(back[i], f[i], 1e-12);
    for (int c = 0; c < gf.ncomp(); ++c) {
      double mean = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        mean += u[c * n + i];
      EXPECT_NEAR(mean, 0.0, 1e-12);
    }
    gf.apply(f2, u2);
    EXPECT_NEAR(dot(f, u2), dot(f2, u), 1e-12);
  }
}

TEST(PeriodicSurfaceGF, ImageSumConverges) {
  // The truncated Poisson sum differs from a 4x longer one by O(M^-2): checked on the
  // response to a random zero-mean force field, relative to its size.
  const Material m{.G = 1.0, .nu = 0.3};
  const Shape2 cell{16, 16};
  auto f = random_field(2 * cell.count(), 6);
  std::vector<double> coarse(f.size()), fine(f.size()), finest(f.size());
  elastic::PeriodicSurfaceGF(m, Components::in_plane, cell, 1.0, {}, 3).apply(f, coarse);
  elastic::PeriodicSurfaceGF(m, Components::in_plane, cell, 1.0, {}, 12).apply(f, fine);
  elastic::PeriodicSurfaceGF(m, Components::in_plane, cell, 1.0, {}, 48).apply(f, finest);
  double e_coarse = 0.0, e_fine = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    e_coarse = std::max(e_coarse, std::abs(coarse[i] - finest[i]));
    e_fine = std::max(e_fine, std::abs(fine[i] - finest[i]));
    norm = std::max(norm, std::abs(finest[i]));
  }
  EXPECT_LT(e_fine / norm, 1e-4);
  EXPECT_LT(e_fine, e_coarse / 8.0);  // (12/3)^2 = 16 expected; 8 leaves room
}
