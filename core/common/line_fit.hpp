// Ordinary least-squares straight line y = intercept + slope x, the one the tools' log-log and
// log-linear fits share (friction_sweep's Regime II slope, peierls/ k1 and k2, fit_scaling).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

namespace asperity {

struct LineFit {
  std::size_t n = 0;
  double mean_x = 0.0, mean_y = 0.0;
  double sxx = 0.0;  // sum of (x - mean_x)^2: zero when all x are equal (no slope)
  double slope = std::numeric_limits<double>::quiet_NaN();
  double intercept = std::numeric_limits<double>::quiet_NaN();
  double ssr = 0.0;  // sum of squared residuals about the line

  // Residual variance ssr / (n - 2) over sxx: the slope's squared standard error (n > 2).
  [[nodiscard]] double slope_variance() const { return ssr / (static_cast<double>(n) - 2.0) / sxx; }
};

// x and y of the same length. With sxx == 0 (or fewer than 2 points) slope and intercept stay
// NaN; callers decide what a degenerate set means for them.
inline LineFit fit_line(std::span<const double> x, std::span<const double> y) {
  LineFit f;
  f.n = x.size();
  if (f.n == 0) return f;
  const double n = static_cast<double>(f.n);
  for (std::size_t i = 0; i < f.n; ++i) {
    f.mean_x += x[i] / n;
    f.mean_y += y[i] / n;
  }
  double sxy = 0.0;
  for (std::size_t i = 0; i < f.n; ++i) {
    f.sxx += (x[i] - f.mean_x) * (x[i] - f.mean_x);
    sxy += (x[i] - f.mean_x) * (y[i] - f.mean_y);
  }
  if (f.n < 2 || !(f.sxx > 0.0)) return f;
  f.slope = sxy / f.sxx;
  f.intercept = f.mean_y - f.slope * f.mean_x;
  for (std::size_t i = 0; i < f.n; ++i) {
    const double r = y[i] - (f.intercept + f.slope * x[i]);
    f.ssr += r * r;
  }
  return f;
}

}  // namespace asperity
