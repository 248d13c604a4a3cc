// Small-sample statistics shared by the fits of MODEL.md section 8.
//
// How errors are reported. A fit with n points and p parameters estimates its scatter from the
// data (n - p degrees of freedom), so parameter / standard error follows Student's t, not the
// normal law. With the 4 to 8 points a sweep puts into a window, +-2 plain standard errors cover
// the true value only 86-91% of the time (t with 3-7 degrees of freedom). Every `*_error` of this
// module is therefore the standard error multiplied by t_factor(dof) = t_dof(Phi(2)) / 2, so that
// +-2 reported errors is the exact two-sided 95.45% interval of the Gaussian linear model (the
// normal +-2 sigma interval in the large-sample limit). The plain standard errors are reported
// alongside.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace asperity::nucleation {

// Quantile of Student's t distribution with `dof` > 0 degrees of freedom.
double student_t_quantile(double probability, double dof);

// t_dof(Phi(2)) / 2: the factor that turns a standard error into the reported error. 1 in the
// limit dof -> infinity; 6.98 at dof = 1, 1.65 at 3, 1.14 at 10.
double t_factor(double dof);

// Bootstrap over points of the mean of `values`: `samples` resamples with replacement drawn from
// a generator seeded with `seed` (the same call gives the same answer). Returns the standard
// deviation of the resampled means (the plain bootstrap standard error, which is smaller than the
// classical s / sqrt(n) by sqrt((n - 1) / n) on average). Needs at least two values.
double bootstrap_se_of_mean(std::span<const double> values, int samples, std::uint64_t seed);

}  // namespace asperity::nucleation
