// Closed-form log-linear least squares for tau_P = k1 tau_max exp(-k2 b_core); see fit.hpp.
#include "asperity/peierls/fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "asperity/core/common/line_fit.hpp"

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
  const LineFit line = fit_line(x, y);
  if (!(line.sxx > 0.0)) return fit;
  const double n = static_cast<double>(line.n);
  fit.b_min = *std::min_element(x.begin(), x.end());
  fit.b_max = *std::max_element(x.begin(), x.end());
  const double sigma2 = line.ssr / (n - 2.0);
  fit.k2 = -line.slope;
  fit.k2_error = std::sqrt(sigma2 / line.sxx);
  fit.k1 = std::exp(line.intercept);
  fit.k1_error = fit.k1 * std::sqrt(sigma2 * (1.0 / n + line.mean_x * line.mean_x / line.sxx));
  // cov(ln k1, k2) = -cov(intercept, slope) = sigma2 mean_x / sxx; k1's error is k1 times that
  // of ln k1, so the correlation is the same.
  fit.correlation = line.mean_x / std::sqrt(line.sxx / n + line.mean_x * line.mean_x);
  fit.rms_log_residual = std::sqrt(line.ssr / n);
  fit.valid = true;
  return fit;
}

}  // namespace asperity::peierls
