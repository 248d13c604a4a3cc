// Student's t quantiles (Boost.Math) and the bootstrap of a mean; see statistics.hpp.
#include "asperity/nucleation/statistics.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace asperity::nucleation {

double student_t_quantile(double probability, double dof) {
  if (!(dof > 0.0) || !std::isfinite(dof))
    throw std::invalid_argument("student_t_quantile: dof must be finite and > 0");
  if (!(probability > 0.0 && probability < 1.0))
    throw std::invalid_argument("student_t_quantile: probability must be in (0, 1)");
  return boost::math::quantile(boost::math::students_t_distribution<double>(dof), probability);
}

double t_factor(double dof) {
  static const double p2 = boost::math::cdf(boost::math::normal_distribution<double>(), 2.0);
  return student_t_quantile(p2, dof) / 2.0;
}

double bootstrap_se_of_mean(std::span<const double> values, int samples, std::uint64_t seed) {
  if (values.size() < 2) throw std::invalid_argument("bootstrap_se_of_mean: needs >= 2 values");
  if (samples < 2) throw std::invalid_argument("bootstrap_se_of_mean: samples must be >= 2");
  // mt19937_64 and a hand-made index draw: std::uniform_int_distribution differs between
  // standard libraries, and the same seed must give the same error everywhere.
  std::mt19937_64 rng(seed);
  const std::uint64_t n = values.size();
  std::vector<double> means(static_cast<std::size_t>(samples));
  for (double& mean : means) {
    mean = 0.0;
    for (std::uint64_t k = 0; k < n; ++k)
      mean += values[static_cast<std::size_t>(rng() % n)];
    mean /= static_cast<double>(n);
  }
  // Two passes: the spread is small next to the mean (logarithms of similar numbers).
  double m = 0.0;
  for (double v : means)
    m += v;
  m /= samples;
  double var = 0.0;
  for (double v : means)
    var += (v - m) * (v - m);
  return std::sqrt(var / (samples - 1.0));
}

}  // namespace asperity::nucleation
