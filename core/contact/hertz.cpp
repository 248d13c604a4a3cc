// Hertz relations of MODEL.md section 1; see hertz.hpp.
#include "contact/hertz.hpp"

#include "common/validate.hpp"

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

}  // namespace asperity::contact
