// Closed-form log-linear least squares for tau_P = k1 tau_max exp(-k2 b_core); see fit.hpp.
#include "peierls/fit.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace asperity::peierls {

ExponentialFit fit_exponential(std::span<const double> b_core, std::span<const double> ratio,
                               double b_min, double b_max) {
  if (b_core.size() != ratio.size())
    throw std::invalid_argument("fit_exponential: b_core and ratio differ in length");
  std::vector<double> x, y;
  for (std::size_t i = 0; i < b_core.size(); ++i) {
    if (b_core[i] >= b_min && b_core[i] <= b_max && ratio[i] > 0.0 && std::isfinite(ratio[i])) {
      x.push_back(b_core[i]);
      y.push_back(std::log(ratio[i]));
    }
  }
  ExponentialFit fit;
  fit.points = x.size();
  if (x.size() < 3) return fit;
  const double n = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0.0)) return fit;
  const double slope = sxy / sxx;
  const double intercept = my - slope * mx;
  double ssr = 0.0;
  fit.b_min = x.front();
  fit.b_max = x.front();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (intercept + slope * x[i]);
    ssr += r * r;
    fit.b_min = std::min(fit.b_min, x[i]);
    fit.b_max = std::max(fit.b_max, x[i]);
  }
  const double sigma2 = ssr / (n - 2.0);
  fit.k2 = -slope;
  fit.k2_error = std::sqrt(sigma2 / sxx);
  fit.k1 = std::exp(intercept);
  fit.k1_error = fit.k1 * std::sqrt(sigma2 * (1.0 / n + mx * mx / sxx));
  fit.rms_log_residual = std::sqrt(ssr / n);
  fit.valid = true;
  return fit;
}

}  // namespace asperity::peierls
