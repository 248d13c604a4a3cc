// The interface envelope of the lateral force model (MODEL.md 3): the pressure p(r) on a site at
// distance r from the tip centre and the peak shear stress tau_max(r) of its registry
// potential. A plug-in point (issue 24): an envelope is one class and one line in
// make_envelope(); the lateral force model, its filter (through the model's per-site tau_max)
// and the snapshots take whatever envelope the scene names.
//
// - HertzEnvelope (contact.envelope = "hertz"): p(r) = p0 sqrt(1 - r^2/a^2),
//   tau_max = alpha p(r) (MODEL.md 3).
// A constant tau0 inside a given radius (adhesive) or tau0 + alpha p (issue 27) would each be
// one more class here and one more choice of contact.envelope.
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

class HertzEnvelope final : public Envelope {
 public:
  HertzEnvelope(const contact::Hertz& hertz, double alpha) : hertz_(hertz), alpha_(alpha) {}
  [[nodiscard]] double pressure(double r) const override { return hertz_.pressure(r); }
  [[nodiscard]] double tau_max(double r) const override { return alpha_ * hertz_.pressure(r); }

 private:
  contact::Hertz hertz_;
  double alpha_;
};

// The envelopes a scene can name (contact.envelope), in the order of the setting's choices.
const std::vector<std::string>& envelope_names();
// The envelope of a scene (throws std::invalid_argument for an unknown name).
std::unique_ptr<Envelope> make_envelope(const ContactScene& scene);

}  // namespace asperity::interface
