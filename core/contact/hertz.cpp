// Hertz relations of MODEL.md section 1; see hertz.hpp.
#include "asperity/core/contact/hertz.hpp"

#include "asperity/core/common/validate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace asperity::contact {

Hertz Hertz::from_radius(const elastic::Material& m, double R, double a) {
  m.validate();
  require_positive("Hertz.R", R);
  require_positive("Hertz.a", a);
  Hertz h;
  h.R = R;
  h.a = a;
  h.estar = m.contact_modulus();
  h.load = 4.0 * h.estar * a * a * a / (3.0 * R);
  h.p0 = 2.0 * a * h.estar / (std::numbers::pi * R);
  h.approach = a * a / R;
  return h;
}

Hertz Hertz::from_load(const elastic::Material& m, double R, double load) {
  require_positive("Hertz.load", load);
  m.validate();
  return from_radius(m, R, std::cbrt(3.0 * load * R / (4.0 * m.contact_modulus())));
}

double Hertz::pressure(double r) const {
  const double s = 1.0 - (r * r) / (a * a);
  return s > 0.0 ? p0 * std::sqrt(s) : 0.0;
}

double Hertz::deflection(double r) const {
  if (r <= a) return approach - r * r / (2.0 * R);
  const double q = a / r;
  return ((2.0 * a * a - r * r) * std::asin(q) + a * r * std::sqrt(1.0 - q * q)) /
         (std::numbers::pi * R);
}

double bcore_factor(double nu) {
  return 4.0 / (std::numbers::pi * (1.0 - nu));
}

double cattaneo_mindlin(double rho, double mu_over_alpha) {
  if (rho >= 1.0) return 0.0;
  const double slip = std::sqrt(1.0 - rho * rho);
  const double c = std::cbrt(std::max(0.0, 1.0 - mu_over_alpha));
  // Johnson's (c/a) p0 sqrt(1 - r^2/c^2), over p0: sqrt(c^2 - rho^2) with c in units of a.
  return rho < c ? slip - std::sqrt(c * c - rho * rho) : slip;
}

}  // namespace asperity::contact
