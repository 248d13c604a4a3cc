// Regime III predictions and the Levenberg-Marquardt fit of k1, k2 (MODEL.md 8); see
// regime_three.hpp.
#include "asperity/nucleation/regime_three.hpp"

#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/elastic/material.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unsupported/Eigen/LevenbergMarquardt>
#include <vector>

#include "asperity/core/common/validate.hpp"
#include "asperity/nucleation/statistics.hpp"

namespace asperity::nucleation {

double exponential_integral_en(int n, double x) {
  if (n < 0) throw std::invalid_argument("exponential_integral_en: n must be >= 0");
  if (!(x > 0.0) || !std::isfinite(x))
    throw std::invalid_argument("exponential_integral_en: x must be finite and > 0");
  constexpr double eps = 1e-16;
  constexpr double euler = 0.57721566490153286061;
  constexpr int max_iterations = 1000;
  if (n == 0) return std::exp(-x) / x;
  const int nm1 = n - 1;
  if (x > 1.0) {
    // Modified Lentz evaluation of the continued fraction (converges fast for x > 1).
    double b = x + n;
    double c = 1.0 / std::numeric_limits<double>::min();
    double d = 1.0 / b;
    double h = d;
    for (int i = 1; i <= max_iterations; ++i) {
      const double an = -static_cast<double>(i) * (nm1 + i);
      b += 2.0;
      d = 1.0 / (an * d + b);
      c = b + an / c;
      const double del = c * d;
      h *= del;
      if (std::abs(del - 1.0) < eps) return h * std::exp(-x);
    }
    throw std::runtime_error("exponential_integral_en: continued fraction did not converge");
  }
  // Power series (x <= 1).
  double ans = nm1 != 0 ? 1.0 / nm1 : -std::log(x) - euler;
  double fact = 1.0;
  for (int i = 1; i <= max_iterations; ++i) {
    fact *= -x / i;
    double del;
    if (i != nm1) {
      del = -fact / (i - nm1);
    } else {
      double psi = -euler;
      for (int k = 1; k <= nm1; ++k)
        psi += 1.0 / k;
      del = fact * (-std::log(x) + psi);
    }
    ans += del;
    if (std::abs(del) < std::abs(ans) * eps) return ans;
  }
  throw std::runtime_error("exponential_integral_en: series did not converge");
}

void PeierlsLaw::validate() const {
  require_positive("PeierlsLaw.k1", k1);
  require_positive("PeierlsLaw.k2", k2);
  for (const auto& [name, v] :
       {std::pair{"PeierlsLaw.k1_error", k1_error}, std::pair{"PeierlsLaw.k2_error", k2_error}}) {
    if (!(v >= 0.0) || !std::isfinite(v)) reject(name, std::to_string(v), "finite and >= 0");
  }
  if (!(correlation >= -1.0 && correlation <= 1.0))
    reject("PeierlsLaw.correlation", std::to_string(correlation), "in [-1, 1]");
}

std::string to_string(RegimeThreeForm form) {
  return form == RegimeThreeForm::central ? "central" : "integrated";
}

void check_contact(const std::string& where, double R, double alpha, double nu) {
  require_positive(where + ".R", R);
  require_positive(where + ".alpha", alpha);
  // nu against the material's own description (elastic::Material::settings()), so that the
  // range is stated once: a ratio the scenes refuse is refused here too.
  const auto* row = settings::find(elastic::Material::settings(), "nu");
  assert(row != nullptr);
  try {
    row->check(settings::Value(nu));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
}

double bcore0(double a, double R, double alpha, double nu) {
  require_positive("bcore0.a", a);
  check_contact("bcore0", R, alpha, nu);
  const double c = contact::bcore_factor(nu);
  return R / (c * alpha * a);
}

double control_parameter(double a, double R, double alpha, double nu) {
  require_positive("control_parameter.a", a);
  check_contact("control_parameter", R, alpha, nu);
  const double c = contact::bcore_factor(nu);
  return c * alpha * a * a / R;
}

double contact_radius(double a_over_bcore0, double R, double alpha, double nu) {
  require_positive("contact_radius.a_over_bcore0", a_over_bcore0);
  check_contact("contact_radius", R, alpha, nu);
  const double c = contact::bcore_factor(nu);
  return std::sqrt(a_over_bcore0 * R / (c * alpha));
}

// The law is capped at tau_P = tau_max: the interface cannot hold more than its ideal strength
// (a fitted k1 > 1 exceeds it below b_core = ln(k1) / k2, 0.47 d for k1 = 2.3, k2 = 1.8).
double regime_three_central(double beta, const PeierlsLaw& law) {
  return std::min(1.0, law.k1 * std::exp(-law.k2 * beta));
}

namespace {

// Capped: tau_P = tau_max where w = p/p0 > w* = beta k2 / ln(k1) (b_core(r) = beta / w below the
// cap's core width). w* if it lies inside the contact (< 1), else none.
std::optional<double> cap_start(double beta, const PeierlsLaw& law) {
  if (!(law.k1 > 1.0)) return std::nullopt;
  const double w_star = law.k2 * beta / std::log(law.k1);
  return w_star < 1.0 ? std::optional(w_star) : std::nullopt;
}

}  // namespace

double local_peierls_stress(double tau_max, const PeierlsLaw& law) {
  if (!(tau_max > 0.0)) return 0.0;
  return tau_max * regime_three_central(1.0 / tau_max, law);
}

void AngleLaw::validate() const {
  const std::string where = "Peierls samples at theta = " + std::to_string(theta_deg) + " deg: ";
  if (b_core.size() != ratio.size()) {
    throw std::invalid_argument(where + std::to_string(b_core.size()) + " core widths and " +
                                std::to_string(ratio.size()) + " values");
  }
  for (std::size_t i = 0; i < b_core.size(); ++i) {
    if (!(std::isfinite(b_core[i]) && b_core[i] > 0.0) || (i > 0 && !(b_core[i] > b_core[i - 1]))) {
      throw std::invalid_argument(where + "b_core[" + std::to_string(i) +
                                  "] = " + std::to_string(b_core[i]) +
                                  ", allowed: finite, positive and ascending");
    }
    if (!(std::isfinite(ratio[i]) && ratio[i] > 0.0)) {
      throw std::invalid_argument(where + "tau_P / tau_max = " + std::to_string(ratio[i]) +
                                  " at b_core = " + std::to_string(b_core[i]) +
                                  " d, allowed: finite and positive");
    }
  }
  if (law) law->validate();
}

double local_peierls_stress(double tau_max, const AngleLaw& angle) {
  if (!(tau_max > 0.0)) return 0.0;
  const double b = 1.0 / tau_max;  // b_core / d = G / tau_max (MODEL.md 3)
  const std::vector<double>& x = angle.b_core;
  if (!x.empty() && b >= x.front() && b <= x.back()) {
    const auto hi = std::lower_bound(x.begin(), x.end(), b);
    const auto k = static_cast<std::size_t>(hi - x.begin());
    if (x[k] == b) return tau_max * std::min(1.0, angle.ratio[k]);
    const double t = (b - x[k - 1]) / (x[k] - x[k - 1]);
    const double r =
        std::exp((1.0 - t) * std::log(angle.ratio[k - 1]) + t * std::log(angle.ratio[k]));
    return tau_max * std::min(1.0, r);
  }
  return angle.law ? local_peierls_stress(tau_max, *angle.law)
                   : std::numeric_limits<double>::quiet_NaN();
}

WeakestSegment weakest_local_peierls_stress(double tau_max, std::span<const AngleLaw> angles) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(tau_max > 0.0)) return {angles.empty() ? nan : 0.0, nan};  // no segment there
  WeakestSegment w{nan, nan};
  for (const AngleLaw& a : angles) {
    const double t = local_peierls_stress(tau_max, a);
    if (std::isnan(t)) continue;                // no value at this core width
    if (!(t >= w.tau_P)) w = {t, a.theta_deg};  // the first value replaces the NaN
  }
  return w;
}

WeakestSegment nearest_angle_local_peierls_stress(double tau_max, std::span<const AngleLaw> angles,
                                                  double theta_deg) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (angles.empty() || !std::isfinite(theta_deg)) return {nan, nan};
  // Folded into [0, 90]: a line and its reverse, and its mirror about b, have one character.
  theta_deg = std::fmod(std::abs(theta_deg), 180.0);
  if (theta_deg > 90.0) theta_deg = 180.0 - theta_deg;
  const AngleLaw* nearest = &angles.front();
  for (const AngleLaw& a : angles) {
    if (std::abs(a.theta_deg - theta_deg) < std::abs(nearest->theta_deg - theta_deg)) nearest = &a;
  }
  // Outside the contact no registry holds a segment (local_peierls_stress gives 0 there).
  return {local_peierls_stress(tau_max, *nearest), nearest->theta_deg};
}

double regime_three_integrated(double beta, const PeierlsLaw& law, double f_P) {
  // With w = w* s on [0, w*]:
  //   int_0^1 w^2 min(1, k1 e^(-k2 beta / w)) dw = k1 w*^3 E_4(ln k1) + (1 - w*^3) / 3.
  if (const auto w_star = cap_start(beta, law)) {
    const double w3 = *w_star * *w_star * *w_star;
    return 3.0 * f_P *
           (law.k1 * w3 * exponential_integral_en(4, std::log(law.k1)) + (1.0 - w3) / 3.0);
  }
  return 3.0 * f_P * law.k1 * exponential_integral_en(4, law.k2 * beta);
}

double regime_three(RegimeThreeForm form, double beta, const PeierlsLaw& law, double f_P) {
  return form == RegimeThreeForm::central ? regime_three_central(beta, law)
                                          : regime_three_integrated(beta, law, f_P);
}

std::array<double, 2> regime_three_log_gradient(RegimeThreeForm form, double beta,
                                                const PeierlsLaw& law) {
  if (form == RegimeThreeForm::central) {
    if (regime_three_central(beta, law) >= 1.0) return {0.0, 0.0};  // capped: tau_P = tau_max
    return {1.0 / law.k1, -beta};
  }
  // With J = int_0^1 w^2 min(1, k1 e^(-k2 beta / w)) dw (mu/alpha = 3 f_P J, so f_P drops out of
  // ln): the integrand is continuous at the cap's w*, so the moving limit adds nothing, and with
  // w = w* s, int_0^1 s^(n-2) e^(-x/s) ds = E_n(x):
  //   dJ/dk1 = w*^3 E_4(ln k1),   dJ/dk2 = -beta k1 w*^2 E_3(ln k1);
  // uncapped (w* >= 1) these are E_4(x) and -beta k1 E_3(x), x = k2 beta.
  if (const auto w_star = cap_start(beta, law)) {
    const double x = std::log(law.k1), w2 = *w_star * *w_star;
    const double J = regime_three_integrated(beta, law, 1.0 / 3.0);
    return {w2 * *w_star * exponential_integral_en(4, x) / J,
            -beta * law.k1 * w2 * exponential_integral_en(3, x) / J};
  }
  const double x = law.k2 * beta;
  return {1.0 / law.k1, -beta * exponential_integral_en(3, x) / exponential_integral_en(4, x)};
}

double regime_three_log_error(RegimeThreeForm form, double beta, const PeierlsLaw& law) {
  const auto [d1, d2] = regime_three_log_gradient(form, beta, law);
  const double a = d1 * law.k1_error;
  const double b = d2 * law.k2_error;
  // Round-off can take a + b with a correlation of 1 a hair below zero.
  return std::sqrt(std::max(0.0, a * a + b * b + 2.0 * law.correlation * a * b));
}

void RegimeThreeFitOptions::validate() const {
  if (!(f_P > 0.0 && f_P <= 1.0))
    reject("RegimeThreeFitOptions.f_P", std::to_string(f_P), "(0, 1]");
  require_at_least("RegimeThreeFitOptions.max_function_evaluations", max_function_evaluations, 10);
}

namespace {

// Residuals ln(mu_i) - ln(model_i(k1, k2)) for Eigen's LM; parameters (k1, k2).
struct Residuals : Eigen::DenseFunctor<double> {
  std::span<const double> beta, mu;
  RegimeThreeForm form;
  double f_P;

  Residuals(std::span<const double> b, std::span<const double> m, RegimeThreeForm fo, double f)
      : Eigen::DenseFunctor<double>(2, static_cast<int>(b.size())),
        beta(b),
        mu(m),
        form(fo),
        f_P(f) {}

  // ln(model) and its gradient in (k1, k2); k2 beta <= 0 (an LM trial step) continues the
  // integrated form by f_P k1 exp(-k2 beta), which matches it at 0 (E_4(0) = 1/3) in value and
  // slope sign.
  [[nodiscard]] double log_model(double k1, double k2, double b) const {
    if (form == RegimeThreeForm::integrated && k2 * b <= 0.0) return std::log(f_P * k1) - k2 * b;
    return std::log(regime_three(form, b, {.k1 = k1, .k2 = k2}, f_P));
  }
  [[nodiscard]] std::array<double, 2> log_model_gradient(double k1, double k2, double b) const {
    if (form == RegimeThreeForm::integrated && k2 * b <= 0.0) return {1.0 / k1, -b};
    return regime_three_log_gradient(form, b, {.k1 = k1, .k2 = k2});
  }

  int operator()(const InputType& p, ValueType& r) const {
    // k1 <= 0 is undefined: a huge residual sends LM back.
    const double k1 = std::max(p(0), 1e-300);
    for (std::size_t i = 0; i < beta.size(); ++i)
      r(static_cast<Eigen::Index>(i)) = std::log(mu[i]) - log_model(k1, p(1), beta[i]);
    return 0;
  }
  int df(const InputType& p, JacobianType& J) const {
    const double k1 = std::max(p(0), 1e-300);
    for (std::size_t i = 0; i < beta.size(); ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      const auto [d1, d2] = log_model_gradient(k1, p(1), beta[i]);
      J(row, 0) = -d1;
      J(row, 1) = -d2;
    }
    return 0;
  }
};

}  // namespace

RegimeThreeFit fit_regime_three(std::span<const double> beta, std::span<const double> mu_over_alpha,
                                const RegimeThreeFitOptions& options) {
  options.validate();
  if (beta.size() != mu_over_alpha.size())
    throw std::invalid_argument("fit_regime_three: beta and mu_over_alpha differ in length");
  for (std::size_t i = 0; i < beta.size(); ++i) {
    require_positive("fit_regime_three.beta[" + std::to_string(i) + "]", beta[i]);
    require_positive("fit_regime_three.mu_over_alpha[" + std::to_string(i) + "]", mu_over_alpha[i]);
  }
  RegimeThreeFit fit;
  fit.points = beta.size();
  if (beta.size() < 3) {
    fit.reason = "fewer than 3 points (2 parameters and a scatter to estimate)";
    return fit;
  }
  // Start: the closed-form log-linear fit of the central form (exact for that form).
  const double n = static_cast<double>(beta.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < beta.size(); ++i) {
    mx += beta[i] / n;
    my += std::log(mu_over_alpha[i]) / n;
  }
  double sxx = 0.0, sxy = 0.0;
  fit.beta_min = fit.beta_max = beta[0];
  for (std::size_t i = 0; i < beta.size(); ++i) {
    sxx += (beta[i] - mx) * (beta[i] - mx);
    sxy += (beta[i] - mx) * (std::log(mu_over_alpha[i]) - my);
    fit.beta_min = std::min(fit.beta_min, beta[i]);
    fit.beta_max = std::max(fit.beta_max, beta[i]);
  }
  if (!(sxx > 1e-12 * mx * mx)) {
    fit.reason = "no spread in b_core^0: k1 and k2 cannot be separated";
    return fit;
  }
  double k2 = -sxy / sxx;
  if (!(k2 > 0.0)) k2 = 1e-3;  // mu falling with b_core^0 is the only physical sign
  double k1 = std::exp(my + k2 * mx);
  if (options.form == RegimeThreeForm::integrated) {
    double shift = 0.0;
    for (std::size_t i = 0; i < beta.size(); ++i)
      shift += (std::log(mu_over_alpha[i]) -
                std::log(regime_three_integrated(beta[i], {.k1 = 1.0, .k2 = k2}, options.f_P))) /
               n;
    k1 = std::exp(shift);
  }
  Residuals functor(beta, mu_over_alpha, options.form, options.f_P);
  Eigen::LevenbergMarquardt<Residuals> lm(functor);
  lm.setMaxfev(options.max_function_evaluations);
  lm.setXtol(1e-14);
  lm.setFtol(1e-14);
  Eigen::VectorXd p(2);
  p << k1, k2;
  const Eigen::LevenbergMarquardtSpace::Status status = lm.minimize(p);
  fit.evaluations = static_cast<int>(lm.nfev());
  if (status == Eigen::LevenbergMarquardtSpace::ImproperInputParameters ||
      status == Eigen::LevenbergMarquardtSpace::TooManyFunctionEvaluation || !(p(0) > 0.0) ||
      !(p(1) > 0.0)) {
    fit.reason = "Levenberg-Marquardt did not converge to k1, k2 > 0 (status " +
                 std::to_string(static_cast<int>(status)) + ")";
    return fit;
  }
  Eigen::VectorXd r(static_cast<Eigen::Index>(beta.size()));
  functor(p, r);
  Eigen::MatrixXd J(static_cast<Eigen::Index>(beta.size()), 2);
  functor.df(p, J);
  const double ssr = r.squaredNorm();
  fit.dof = n - 2.0;
  const double s2 = ssr / fit.dof;
  // The shape of the covariance comes from J alone: its correlation is defined for exact data
  // (s2 = 0) too. A singular J^T J (points all in the capped range, where the law is flat)
  // leaves k1, k2 undetermined.
  const Eigen::Matrix2d shape = (J.transpose() * J).inverse();
  if (!shape.allFinite() || !(shape(0, 0) > 0.0) || !(shape(1, 1) > 0.0)) {
    fit.reason =
        "k1 and k2 are not determined by these points (singular Jacobian): where tau_P is "
        "capped at tau_max at the centre (b_core^0 < ln(k1)/k2) the law depends on one "
        "combination of them; add points of wider cores";
    return fit;
  }
  const Eigen::Matrix2d cov = shape * s2;
  fit.t_factor = t_factor(fit.dof);
  fit.law.k1 = p(0);
  fit.law.k2 = p(1);
  fit.k1_se = std::sqrt(cov(0, 0));
  fit.k2_se = std::sqrt(cov(1, 1));
  fit.law.k1_error = fit.k1_se * fit.t_factor;
  fit.law.k2_error = fit.k2_se * fit.t_factor;
  fit.law.b_min = fit.beta_min;
  fit.law.b_max = fit.beta_max;
  fit.correlation = shape(0, 1) / std::sqrt(shape(0, 0) * shape(1, 1));
  fit.law.correlation = std::clamp(fit.correlation, -1.0, 1.0);
  fit.rms_log_residual = std::sqrt(ssr / n);
  fit.valid = true;
  return fit;
}

}  // namespace asperity::nucleation
