// Closed forms of MODEL.md section 2; see influence.hpp for the equations.
#include "asperity/core/elastic/influence.hpp"

#include <cassert>
#include <cmath>
#include <numbers>

namespace asperity::elastic {

namespace {

// ln(t + r) with r = hypot(t, s), without cancellation for t < 0 (t + r = s^2 / (r - t)).
double log_plus(double t, double s, double r) {
  return t >= 0.0 ? std::log(t + r) : std::log(s * s / (r - t));
}

// Corner antiderivatives F(x, y) whose mixed difference over a rectangle integrates the kernel.
// Terms whose coefficient vanishes are skipped: their logarithm may be singular there.
double anti_inv_r(double x, double y) {
  const double r = std::hypot(x, y);
  double v = 0.0;
  if (x != 0.0) v += x * log_plus(y, x, r);
  if (y != 0.0) v += y * log_plus(x, y, r);
  return v;
}
double anti_xx_r3(double x, double y) {  // x^2 / r^3
  return y != 0.0 ? y * log_plus(x, y, std::hypot(x, y)) : 0.0;
}
double anti_xy_r3(double x, double y) {
  return -std::hypot(x, y);
}  // x y / r^3
double anti_x_r2(double x, double y) {  // x / r^2
  double v = 0.0;
  if (y != 0.0) v += y * std::log(std::hypot(x, y));
  if (x != 0.0) v += x * std::atan(y / x);
  return v;
}

template <class F>
double over_patch(F anti, double x, double y, double h) {
  return anti(x + h, y + h) - anti(x - h, y + h) - anti(x + h, y - h) + anti(x - h, y - h);
}

}  // namespace

double point_force_gf(const Material& m, int i, int j, double x, double y) {
  assert(i >= 0 && i < 3 && j >= 0 && j < 3);
  const double r2 = x * x + y * y;
  const double r = std::sqrt(r2);
  const double c = 1.0 / (2.0 * std::numbers::pi * m.G);
  const double coupling = 0.5 * (1.0 - 2.0 * m.nu) * c / r2;
  if (i == 2 && j == 2) return c * (1.0 - m.nu) / r;
  if (i == 2) return -coupling * (j == 0 ? x : y);
  if (j == 2) return coupling * (i == 0 ? x : y);
  const double xi = i == 0 ? x : y;
  const double xj = j == 0 ? x : y;
  return c * ((i == j ? (1.0 - m.nu) / r : 0.0) + m.nu * xi * xj / (r2 * r));
}

double patch_gf(const Material& m, int i, int j, double x, double y, double d) {
  assert(i >= 0 && i < 3 && j >= 0 && j < 3);
  const double h = 0.5 * d;
  const double c = 1.0 / (2.0 * std::numbers::pi * m.G * d * d);
  const auto swap = [](auto anti) { return [anti](double a, double b) { return anti(b, a); }; };
  if (i == 2 && j == 2) return c * (1.0 - m.nu) * over_patch(anti_inv_r, x, y, h);
  if (i == 2 || j == 2) {
    const int lateral = i == 2 ? j : i;
    const double sign = i == 2 ? -1.0 : 1.0;
    const double q =
        lateral == 0 ? over_patch(anti_x_r2, x, y, h) : over_patch(swap(anti_x_r2), x, y, h);
    return sign * 0.5 * (1.0 - 2.0 * m.nu) * c * q;
  }
  if (i != j) return c * m.nu * over_patch(anti_xy_r3, x, y, h);
  const double aligned =
      i == 0 ? over_patch(anti_xx_r3, x, y, h) : over_patch(swap(anti_xx_r3), x, y, h);
  return c * ((1.0 - m.nu) * over_patch(anti_inv_r, x, y, h) + m.nu * aligned);
}

void fourier_gf_tensor(const Material& m, double qx, double qy, std::complex<double> (&g)[3][3]) {
  const double q2 = qx * qx + qy * qy;
  assert(q2 > 0.0);
  const double q = std::sqrt(q2);
  const double c = 1.0 / (m.G * q);
  const double nu_q2 = m.nu / q2;
  g[0][0] = c * (1.0 - nu_q2 * qx * qx);
  g[1][1] = c * (1.0 - nu_q2 * qy * qy);
  g[0][1] = g[1][0] = -c * nu_q2 * qx * qy;
  g[2][2] = c * (1.0 - m.nu);
  const double s = (1.0 - 2.0 * m.nu) / (2.0 * m.G * q2);
  g[0][2] = {0.0, -s * qx};
  g[1][2] = {0.0, -s * qy};
  g[2][0] = {0.0, s * qx};
  g[2][1] = {0.0, s * qy};
}

std::complex<double> fourier_gf(const Material& m, int i, int j, double qx, double qy) {
  assert(i >= 0 && i < 3 && j >= 0 && j < 3);
  std::complex<double> g[3][3];
  fourier_gf_tensor(m, qx, qy, g);
  return g[i][j];
}

}  // namespace asperity::elastic
