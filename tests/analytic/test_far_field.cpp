// Analytic tier: far field of a loaded patch.
//
// Analytic answer: a force F on one d x d patch gives, at distance r >> d, the point-force
// (Boussinesq-Cerruti) displacement of MODEL.md section 2,
//   u_x = [(1-nu)/r + nu x^2/r^3] Fx/(2 pi G) + nu x y/r^3 Fy/(2 pi G),  u_z = (1-nu) Fz/(2 pi G
//   r), u_x = (1-2nu) x Fz/(4 pi G r^2),  u_z = -(1-2nu) x Fx/(4 pi G r^2).
// Tolerance: averaging the kernel over the patch adds (d^2/24) lap(g) + O(d^4/r^4): a relative
// error of order d^2/(24 r^2) times an angular factor of order one. We allow d^2/(4 r^2),
// and check that the error falls at least as r^-2 (by 2.8x or more when r doubles: 4x expected;
// where the Laplacian term cancels, e.g. nu = 0.5 on the axes, it falls as r^-4).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "asperity/core/elastic/influence.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

using namespace asperity;
using elastic::Components;

TEST(FarField, PatchResponseTendsToPointForce) {
  const int half = 40;
  const Shape2 block{2 * half + 1, 2 * half + 1};
  const std::size_t n = block.count();
  for (double nu : {0.0, 0.25, 0.5}) {
    const elastic::Material m{.G = 1.0, .nu = nu};
    elastic::FreeSurfaceGF gf(m, Components::full, block);
    for (int l = 0; l < 3; ++l) {
      std::vector<double> f(gf.size(), 0.0), u(gf.size());
      f[l * n + block.index(half, half)] = 1.0;  // unit force on the centre patch
      gf.apply(f, u);
      for (auto [dx, dy] : {std::pair{10, 0}, {0, 10}, {7, 7}, {9, -4}, {-6, 8}}) {
        double previous_error = 0.0;
        for (int scale : {1, 2, 4}) {
          const int ox = dx * scale, oy = dy * scale;
          const double r = std::hypot(ox, oy);
          for (int k = 0; k < 3; ++k) {
            const double point = elastic::point_force_gf(m, k, l, ox, oy);
            const double patch = u[k * n + block.index(half + ox, half + oy)];
            // Scale for the relative error: the largest component of the response there.
            const double size = (1.0 - nu) / (2.0 * std::numbers::pi * r);
            const double error = std::abs(patch - point) / size;
            EXPECT_LT(error, 1.0 / (4.0 * r * r))
                << "nu " << nu << " u_" << k << " per F_" << l << " at " << ox << "," << oy;
            if (k == l && scale > 1 && previous_error > 1e-12) {
              EXPECT_GT(previous_error / error, 2.8) << "nu " << nu << " k " << k;
            }
            if (k == l) previous_error = error;
          }
        }
      }
    }
  }
}
