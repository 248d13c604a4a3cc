// The interface envelope of the lateral force model (MODEL.md 3): the pressure p(r) on a site at
// distance r from the tip centre and the peak shear stress tau_max(r) of its registry
// potential. A plug-in point (issue 24): an envelope is one class and one line in
// make_envelope(); the lateral force model, its filter (through the model's per-site tau_max)
// and the snapshots take whatever envelope the scene names.
//
// - HertzEnvelope (contact.envelope = "hertz"): p(r) = p0 sqrt(1 - r^2/a^2),
//   tau_max = alpha p(r) (MODEL.md 3).
// - AdhesiveEnvelope ("adhesive", issue 27): tau_max = tau0 for r < a, 0 outside; p = 0. The
//   strength of an adhesive contact does not come from the load: a constant interfacial shear
//   strength over a contact of given radius, whose compressive and adhesive tractions balance to
//   a load that may be zero (the JKR contact at zero load). The lateral force model has no
//   normal degree of freedom, so no pressure is modelled: p = 0 and the load Fz = 0, and the
//   friction is reported as a stress, tau_fric = Fx / A (A the contact-site area, lfm.hpp).
// - MixedEnvelope ("mixed", issue 27): tau_max = tau0 + alpha p(r) for r < a, the Hertz p; the
//   form tau_max = tau0 + alpha p of real surfaces. tau0 = 0 is the Hertz envelope bit for bit
//   (0 + x = x exactly; the same sites are in contact).
// All three put the same sites in contact: 1 - r^2/a^2 > 0 (in_contact()).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "asperity/core/contact/hertz.hpp"

namespace asperity::interface {

struct ContactScene;

class Envelope {
 public:
  virtual ~Envelope() = default;
  // Pressure (G) and peak shear stress (G) at distance r (d) from the tip centre; a site is in
  // contact where tau_max > 0.
  [[nodiscard]] virtual double pressure(double r) const = 0;
  [[nodiscard]] virtual double tau_max(double r) const = 0;
};

// Inside the contact circle of radius a: the test of the Hertz pressure (contact::Hertz::
// pressure is > 0 exactly there), so that every envelope has the same contact sites.
inline bool in_contact(double r, double a) {
  return 1.0 - (r * r) / (a * a) > 0.0;
}

class HertzEnvelope final : public Envelope {
 public:
  HertzEnvelope(const contact::Hertz& hertz, double alpha) : hertz_(hertz), alpha_(alpha) {}
  [[nodiscard]] double pressure(double r) const override { return hertz_.pressure(r); }
  [[nodiscard]] double tau_max(double r) const override { return alpha_ * hertz_.pressure(r); }

 private:
  contact::Hertz hertz_;
  double alpha_;
};

class AdhesiveEnvelope final : public Envelope {
 public:
  AdhesiveEnvelope(double a, double tau0) : a_(a), tau0_(tau0) {}
  [[nodiscard]] double pressure(double /*r*/) const override { return 0.0; }
  [[nodiscard]] double tau_max(double r) const override { return in_contact(r, a_) ? tau0_ : 0.0; }

 private:
  double a_, tau0_;
};

class MixedEnvelope final : public Envelope {
 public:
  MixedEnvelope(const contact::Hertz& hertz, double alpha, double tau0)
      : hertz_(hertz), alpha_(alpha), tau0_(tau0) {}
  [[nodiscard]] double pressure(double r) const override { return hertz_.pressure(r); }
  [[nodiscard]] double tau_max(double r) const override {
    return (in_contact(r, hertz_.a) ? tau0_ : 0.0) + alpha_ * hertz_.pressure(r);
  }

 private:
  contact::Hertz hertz_;
  double alpha_, tau0_;
};

// The envelopes a scene can name (contact.envelope), in the order of the setting's choices.
const std::vector<std::string>& envelope_names();
// The envelope of a scene (throws std::invalid_argument for an unknown name).
std::unique_ptr<Envelope> make_envelope(const ContactScene& scene);

}  // namespace asperity::interface
