// Polonsky & Keer constrained conjugate gradients, load-controlled; see normal_contact.hpp.
#include "asperity/core/contact/normal_contact.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity::contact {

const settings::Table<NormalContactOptions>& NormalContactOptions::settings() {
  using R = settings::Range;
  // A relative change of the forces: 1 or more stops at once.
  static const settings::Table<NormalContactOptions> table = {
      settings::number<NormalContactOptions>(
          "tolerance", [](auto& o) -> auto& { return o.tolerance; }, R::open(0.0, 1.0), "",
          "Polonsky-Keer stop: sum |P_new - P_old| / load per iteration"),
      settings::integer<NormalContactOptions>(
          "max_iterations", [](auto& o) -> auto& { return o.max_iterations; }, R::closed(1, 1e9),
          "", "Polonsky-Keer iteration cap (one GF application each)")};
  return table;
}

void NormalContactOptions::validate() const {
  settings::validate(*this, settings());
}

NormalContactResult solve_normal_contact(elastic::FreeSurfaceGF& gf,
                                         std::span<const double> heights, double load,
                                         const NormalContactOptions& options) {
  options.validate();
  if (gf.components() != elastic::Components::normal) {
    throw std::invalid_argument("solve_normal_contact: the Green's function must be normal-only");
  }
  const std::size_t n = gf.size();
  if (heights.size() != n) {
    throw std::invalid_argument("solve_normal_contact: " + std::to_string(heights.size()) +
                                " heights for " + std::to_string(n) + " sites");
  }
  if (!(load > 0.0) || !std::isfinite(load)) {
    throw std::invalid_argument("solve_normal_contact: load: got " + std::to_string(load) +
                                ", allowed: finite and > 0");
  }
  const std::size_t applications_before = gf.applications();
  NormalContactResult res;
  std::vector<double>& P = res.force;
  P.assign(n, load / static_cast<double>(n));
  std::vector<double> w(n), g(n), t(n, 0.0), r(n), P_old(n);
  bool conjugate = false;
  double g_old = 1.0;

  for (int it = 1; it <= options.max_iterations; ++it) {
    res.iterations = it;
    gf.apply(P, w);
    // Gap up to the unknown approach: its mean over the contact set plays the role of delta.
    double g_mean = 0.0;
    std::size_t in_contact = 0;
    for (std::size_t i = 0; i < n; ++i) {
      g[i] = heights[i] + w[i];
      if (P[i] > 0.0) {
        g_mean += g[i];
        ++in_contact;
      }
    }
    if (in_contact == 0) {
      res.termination = Termination::diverged;
      break;
    }
    g_mean /= static_cast<double>(in_contact);
    double g_norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      g[i] -= g_mean;
      if (P[i] > 0.0) g_norm += g[i] * g[i];
    }
    const double beta = conjugate ? g_norm / g_old : 0.0;
    for (std::size_t i = 0; i < n; ++i)
      t[i] = P[i] > 0.0 ? g[i] + beta * t[i] : 0.0;
    g_old = g_norm;

    gf.apply(t, r);
    double r_mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (P[i] > 0.0) r_mean += r[i];
    }
    r_mean /= static_cast<double>(in_contact);
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (P[i] > 0.0) {
        num += g[i] * t[i];
        den += (r[i] - r_mean) * t[i];
      }
    }
    const double tau = den > 0.0 ? num / den : 0.0;

    P_old = P;
    bool overlap = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (P[i] > 0.0) P[i] = std::max(0.0, P[i] - tau * t[i]);
    }
    // Sites out of contact that interpenetrate enter the contact set; CG restarts.
    for (std::size_t i = 0; i < n; ++i) {
      if (P[i] == 0.0 && P_old[i] == 0.0 && g[i] < 0.0) {
        P[i] = -tau * g[i];
        overlap = true;
      }
    }
    conjugate = !overlap;
    double total = 0.0;
    for (double p : P)
      total += p;
    if (!(total > 0.0) || !std::isfinite(total)) {
      res.termination = Termination::diverged;
      break;
    }
    double change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      P[i] *= load / total;
      change += std::abs(P[i] - P_old[i]);
    }
    res.residual = change / load;
    if (res.residual < options.tolerance) {
      res.termination = Termination::converged;
      break;
    }
  }

  gf.apply(P, w);
  double delta = 0.0;
  res.contact_sites = 0;
  res.load = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    res.load += P[i];
    if (P[i] > 0.0) {
      delta += heights[i] + w[i];
      ++res.contact_sites;
    }
  }
  res.approach = res.contact_sites > 0 ? delta / static_cast<double>(res.contact_sites) : 0.0;
  res.gap.resize(n);
  res.max_penetration = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    res.gap[i] = heights[i] + w[i] - res.approach;
    res.max_penetration = std::max(res.max_penetration, -res.gap[i]);
  }
  res.deflection = std::move(w);
  res.gf_applications = gf.applications() - applications_before;
  return res;
}

}  // namespace asperity::contact
