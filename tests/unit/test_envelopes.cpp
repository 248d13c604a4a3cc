// The interface envelopes of the lateral force model (issue 27; core/interface/envelope.hpp):
// what each gives per site, the scene's quantities derived from them (b_core^0, the control
// parameter and its inverse, the Regime I force, lambda), the checks naming the violated
// constraint, and the mixed envelope without tau0 sliding as the Hertz one bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/slide/slider.hpp"

using namespace asperity;

namespace {

std::string message_of(const auto& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}

interface::ContactScene with(const std::string& envelope, double tau0, double a = 43.0) {
  interface::ContactScene c;
  c.envelope = envelope;
  c.tau0 = tau0;
  c.a = a;
  return c;
}

}  // namespace

TEST(Envelope, AdhesiveIsTau0InsideTheContactAndCarriesNoLoad) {
  const auto c = with("adhesive", 0.2);
  const auto e = interface::make_envelope(c);
  const auto h = interface::make_envelope(with("hertz", 0.0));
  for (double r : {0.0, 10.0, 42.9, 42.999999, 43.0, 50.0}) {
    EXPECT_EQ(e->pressure(r), 0.0);
    // The same contact sites as the Hertz envelope: tau_max > 0 exactly where p > 0.
    EXPECT_EQ(e->tau_max(r) > 0.0, h->tau_max(r) > 0.0) << "r = " << r;
    EXPECT_EQ(e->tau_max(r), h->tau_max(r) > 0.0 ? 0.2 : 0.0);
  }
}

TEST(Envelope, MixedIsTau0PlusAlphaP) {
  const auto c = with("mixed", 0.05);
  const auto e = interface::make_envelope(c);
  const auto h = c.hertz();
  for (double r : {0.0, 10.0, 42.9}) {
    EXPECT_EQ(e->pressure(r), h.pressure(r));
    EXPECT_DOUBLE_EQ(e->tau_max(r), 0.05 + c.alpha * h.pressure(r));
  }
  EXPECT_EQ(e->tau_max(43.0), 0.0);
  EXPECT_EQ(e->tau_max(60.0), 0.0);
  // Without tau0 it is the Hertz envelope bit for bit.
  const auto m0 = interface::make_envelope(with("mixed", 0.0));
  const auto hz = interface::make_envelope(with("hertz", 0.0));
  for (int k = 0; k <= 5000; ++k) {
    const double r = 45.0 * k / 5000.0;
    EXPECT_EQ(m0->tau_max(r), hz->tau_max(r)) << "r = " << r;
    EXPECT_EQ(m0->pressure(r), hz->pressure(r));
  }
}

TEST(Envelope, CoreWidthControlParameterAndItsInverse) {
  const double pi = std::numbers::pi;
  // Hertz: b_core^0 = d G / (alpha p0), a/b_core^0 = c alpha a^2 / (R d), c = 8/pi at nu = 0.5.
  const auto hz = with("hertz", 0.0);
  EXPECT_NEAR(hz.a_over_bcore0(), 8.0 / pi * 0.7 * 43.0 * 43.0 / 535.0, 1e-12);
  // Adhesive: b_core^0 = d G / tau0 = 5 d at tau0 = 0.2 G; no load; F_I = tau0 pi a^2; lambda =
  // (pi^2 (2 - nu) / 4) a tau0 / (d G).
  const auto ad = with("adhesive", 0.2, 20.0);
  EXPECT_DOUBLE_EQ(ad.bcore0(), 5.0);
  EXPECT_DOUBLE_EQ(ad.a_over_bcore0(), 4.0);
  EXPECT_FALSE(ad.carries_load());
  EXPECT_EQ(ad.load(), 0.0);
  EXPECT_DOUBLE_EQ(ad.regime_one_force(), 0.2 * pi * 400.0);
  EXPECT_NEAR(ad.lambda(), pi * pi * 1.5 / 4.0 * 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(ad.regime_one_force(0.0, 317.0), 0.2 * 317.0);
  // Mixed: tau_max(0) = tau0 + alpha p0, and the two control parameters add.
  const auto mx = with("mixed", 0.05);
  EXPECT_DOUBLE_EQ(mx.tau_max0(), 0.05 + 0.7 * mx.hertz().p0);
  EXPECT_NEAR(mx.a_over_bcore0(), hz.a_over_bcore0() + 43.0 * 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(mx.regime_one_force(), 0.7 * mx.hertz().load + 0.05 * pi * 43.0 * 43.0);
  // The contact radius of a target of the control parameter, in each envelope.
  for (const auto& scene : {hz, ad, mx}) {
    for (double x : {0.1, 1.0, 7.5, 60.0}) {
      interface::ContactScene at = scene;
      at.a = scene.radius_for(x);
      EXPECT_NEAR(at.a_over_bcore0(), x, 1e-12 * x) << scene.envelope;
    }
  }
  // Mixed without tau0 is the Hertz scene in every derived quantity, bit for bit.
  const auto m0 = with("mixed", 0.0);
  EXPECT_EQ(m0.bcore0(), hz.bcore0());
  EXPECT_EQ(m0.lambda(), hz.lambda());
  EXPECT_EQ(m0.regime_one_force(), hz.regime_one_force());
  EXPECT_EQ(m0.radius_for(7.5), hz.radius_for(7.5));
}

TEST(Envelope, ChecksNameTheViolatedConstraint) {
  EXPECT_EQ(message_of([] { with("adhesive", 0.0).validate(); }),
            "contact.tau0 = 0: allowed: > 0 (the contact's whole strength) with contact.envelope "
            "= \"adhesive\"");
  EXPECT_EQ(message_of([] { with("hertz", 0.1).validate(); }),
            "contact.tau0 = 0.1: allowed: 0 (tau0 enters the adhesive and mixed envelopes) with "
            "contact.envelope = \"hertz\"");
  EXPECT_EQ(message_of([] { with("mixed", -0.1).validate(); }),
            "contact.tau0 = -0.1: allowed: >= 0 G");
  EXPECT_NO_THROW(with("mixed", 0.0).validate());
  // No sphere in the adhesive envelope: a may exceed contact.R; not so in the others.
  EXPECT_NO_THROW(with("adhesive", 0.2, 600.0).validate());
  EXPECT_EQ(message_of([] { with("mixed", 0.1, 600.0).validate(); }),
            "contact.a = 600: allowed: < contact.R = 535");
  interface::ContactScene unknown;
  unknown.envelope = "jkr";
  EXPECT_THROW(interface::make_envelope(unknown), std::invalid_argument);
  EXPECT_THROW(unknown.validate(), std::invalid_argument);
}

// The mixed envelope with tau0 = 0 slides as the Hertz one: the same trace and mu to the last
// bit (a Regime II contact with two slips, a = 20 d at R = 100 d: a/b_core^0 = 7.1).
TEST(Envelope, MixedWithoutTau0SlidesAsHertzBitForBit) {
  interface::ContactScene hz {
    .a = 20.0, .R = 100.0
  };
  interface::ContactScene mx = hz;
  mx.envelope = "mixed";
  const auto a = slide::slide(hz, {});
  const auto b = slide::slide(mx, {});
  ASSERT_FALSE(a.failed) << a.stop_reason;
  EXPECT_GE(a.slip_events, 1);
  EXPECT_EQ(a.mu, b.mu);
  EXPECT_EQ(a.mu_over_alpha, b.mu_over_alpha);
  EXPECT_EQ(a.tau_fric, b.tau_fric);
  EXPECT_EQ(a.kinetic, b.kinetic);
  EXPECT_EQ(a.peak_Dx, b.peak_Dx);
  ASSERT_EQ(a.trace.size(), b.trace.size());
  for (std::size_t i = 0; i < a.trace.size(); ++i) {
    EXPECT_EQ(a.trace[i].Dx, b.trace[i].Dx);
    EXPECT_EQ(a.trace[i].Fx, b.trace[i].Fx);
    EXPECT_EQ(a.trace[i].Fz, b.trace[i].Fz);
    EXPECT_EQ(a.trace[i].energy, b.trace[i].energy);
    EXPECT_EQ(a.trace[i].slip, b.trace[i].slip);
  }
  EXPECT_EQ(a.peak_snapshot.ux, b.peak_snapshot.ux);
}

// The adhesive envelope has no load: friction is the stress Fx / A, and mu is undefined.
TEST(Envelope, AdhesiveSlideReportsTheFrictionStress) {
  const auto c = with("adhesive", 0.2, 12.0);
  const auto r = slide::slide(c, {});
  ASSERT_FALSE(r.failed) << r.stop_reason;
  EXPECT_EQ(r.measure, slide::FrictionMeasure::area);
  EXPECT_TRUE(std::isnan(r.mu));
  EXPECT_TRUE(std::isnan(r.mu_over_alpha));
  EXPECT_EQ(r.Fz, 0.0);
  EXPECT_EQ(r.Fz_continuum, 0.0);
  EXPECT_GT(r.tau_fric, 0.0);
  EXPECT_LE(r.tau_fric, c.tau0 * (1.0 + 1e-12));
  // The contact-site area at the peak: whole sites, about pi a^2.
  EXPECT_EQ(r.area, std::round(r.area));
  EXPECT_NEAR(r.area / (std::numbers::pi * 144.0), 1.0, 0.03);
  EXPECT_DOUBLE_EQ(slide::friction_over_regime_one(c, r), r.tau_fric / c.tau0);
  for (const auto& row : r.trace) {
    EXPECT_EQ(row.Fz, 0.0);
    EXPECT_GT(row.area, 0.0);
  }
}
