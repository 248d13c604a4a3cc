// Fit of the Peierls stress law of MODEL.md section 6,
//   tau_P / tau_max = k1 exp(-k2 b_core / d),
// which is linear after the transform y = ln(tau_P / tau_max) = ln k1 - k2 b_core: closed-form
// least squares, with standard errors from the residual variance (the scatter of a relaxed
// tau_P about the law is its discreteness, not measurement noise, so the data set the errors).
#pragma once

#include <cstddef>
#include <span>

namespace asperity::peierls {

struct ExponentialFit {
  bool valid = false;  // at least three points and a spread in b_core
  double k1 = 0.0, k1_error = 0.0;
  double k2 = 0.0, k2_error = 0.0;
  // Of the k1 and k2 estimates (from cov(ln k1, k2) = s^2 mean_b / S_bb of the line fit): near +1,
  // since every window lies at b_core > 0. Predictions of the law must use it: treated as
  // independent, k1 and k2 overstate the error of ln tau_P by up to 4x inside the window (5
  // points on 2..6 d: 4.1x at the centre, 1.9x at 2 d).
  double correlation = 0.0;
  double b_min = 0.0, b_max = 0.0;  // fit window (d)
  std::size_t points = 0;
  double rms_log_residual = 0.0;  // rms of ln(tau_P / tau_max) about the fit
};

// b_core (d) and tau_P / tau_max, same length; only points with b_min <= b <= b_max and a
// positive ratio are used.
ExponentialFit fit_exponential(std::span<const double> b_core, std::span<const double> ratio,
                               double b_min, double b_max);

}  // namespace asperity::peierls
