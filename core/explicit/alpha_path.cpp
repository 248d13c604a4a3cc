// The minimum-energy path of one atom over a rigid square lattice at fixed normal force,
// MODEL.md section 4; equations in alpha_path.hpp.
#include "asperity/core/explicit/alpha_path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/explicit/lennard_jones.hpp"

namespace asperity::explicit_model {

const settings::Table<AlphaPathOptions>& AlphaPathOptions::settings() {
  using R = settings::Range;
  static const settings::Table<AlphaPathOptions> table = {
      // Below 0.6 the cutoff (1.12 sigma) no longer reaches past the hollow-site gap of the
      // lattice (d/sqrt(2)): the atom would fall through; above 1.5 the sum over neighbours
      // becomes a wall of many atoms, not a lattice.
      settings::number<AlphaPathOptions>(
          "sigma_over_d", [](auto& o) -> auto& { return o.sigma_over_d; }, R::closed(0.6, 1.5), "d",
          "Lennard-Jones sigma (2^(-1/6): cutoff r_c = d)"),
      // No upper bound here: a load the atom cannot hold throws std::runtime_error, which the
      // explicit model's callers turn into alpha = NaN (alpha_path, the tool, caps its scan).
      settings::number<AlphaPathOptions>(
          "normal_force", [](auto& o) -> auto& { return o.normal_force; }, R::positive(),
          "eps/sigma", "normal force Fz pressing the atom onto the lattice"),
      settings::integer<AlphaPathOptions>(
          "samples", [](auto& o) -> auto& { return o.samples; }, R::closed(3, 1000001), "",
          "points along x over one period d (odd: the bridge site is one)", "--samples")};
  return table;
}

void AlphaPathOptions::validate() const {
  settings::validate(*this, settings());
  if (samples % 2 == 0) {
    throw std::invalid_argument("samples = " + std::to_string(samples) +
                                ": allowed: odd (the bridge site must be a sample)");
  }
}

namespace {

// V and its derivatives in x and z at (x, y, z); lengths in d, energies in eps.
struct Local {
  double v = 0.0, vx = 0.0, vz = 0.0, vxz = 0.0, vzz = 0.0;
};

Local evaluate(const LennardJones& lj, double x, double y, double z) {
  Local l;
  const double rc = lj.cutoff();
  const int i_lo = static_cast<int>(std::ceil(x - rc)), i_hi = static_cast<int>(std::floor(x + rc));
  const int j_lo = static_cast<int>(std::ceil(y - rc)), j_hi = static_cast<int>(std::floor(y + rc));
  for (int i = i_lo; i <= i_hi; ++i) {
    for (int j = j_lo; j <= j_hi; ++j) {
      const double dx = x - i, dy = y - j;
      const double r2 = dx * dx + dy * dy + z * z;
      if (r2 >= lj.cutoff2()) continue;
      const PairTerms t = lj.at(r2);
      // Hessian of V(|r|): V'' r_a r_b / r^2 + (V'/r)(delta_ab - r_a r_b / r^2).
      const double c = (t.d2v - t.dv_r) / r2;
      l.v += t.v;
      l.vx += t.dv_r * dx;
      l.vz += t.dv_r * z;
      l.vxz += c * dx * z;
      l.vzz += c * z * z + t.dv_r;
    }
  }
  return l;
}

// Height where the upward force -V_z equals fz (eps/d), on the stable branch (V_zz > 0): the
// force vanishes at the cutoff height and grows as the atom comes down until the neighbours'
// directions turn sideways; march down from the cutoff to the first crossing, then bisect.
double balance_height(const LennardJones& lj, double x, double y, double fz) {
  double hi = lj.cutoff();  // beyond every neighbour's reach at any (x, y)
  const double step = 1e-3;
  double lo = hi - step;
  while (-evaluate(lj, x, y, lo).vz < fz) {
    hi = lo;
    lo -= step;
    if (lo <= 0.0) {
      throw std::runtime_error("alpha_path: the lattice cannot hold Fz = " + std::to_string(fz) +
                               " eps/d at x = " + std::to_string(x) + " d");
    }
  }
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double mid = 0.5 * (lo + hi);
    (-evaluate(lj, x, y, mid).vz < fz ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

AlphaPath alpha_path(const AlphaPathOptions& o) {
  o.validate();
  // Units: d and eps; a force of Fz eps/sigma is Fz / (sigma/d) eps/d.
  const LennardJones lj(1.0, o.sigma_over_d);
  const double fz = o.normal_force / o.sigma_over_d;
  const double y = 0.5;  // the mirror line through the hollow and bridge sites
  struct Point {
    double z, slope, lateral, enthalpy;
  };
  // x from the hollow site, which is at x = 1/2 of the lattice: the path runs from 1/2 to 3/2.
  const auto at = [&](double x) {
    const double z = balance_height(lj, 0.5 + x, y, fz);
    const Local l = evaluate(lj, 0.5 + x, y, z);
    return Point{z, -l.vxz / l.vzz, l.vx * o.sigma_over_d, l.v + fz * z};
  };
  AlphaPath p;
  const auto n = static_cast<std::size_t>(o.samples);
  p.x.resize(n), p.height.resize(n), p.slope.resize(n), p.lateral.resize(n), p.enthalpy.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    p.x[k] = static_cast<double>(k) / static_cast<double>(n - 1);
    const Point q = at(p.x[k]);
    p.height[k] = q.z, p.slope[k] = q.slope, p.lateral[k] = q.lateral, p.enthalpy[k] = q.enthalpy;
  }
  // The slope jumps where a neighbour crosses the cutoff (V'' jumps there): at low loads the
  // atom in the hollow site sits just inside the cutoff of its four neighbours, the two behind
  // it leave range a few hundredths of d along the path, and the largest slope is reached just
  // after. Samples alone resolve it to the sample spacing; a golden-section search between the
  // neighbours of the best sample finds the supremum (the right limit at a jump).
  const auto imax =
      static_cast<std::size_t>(std::max_element(p.slope.begin(), p.slope.end()) - p.slope.begin());
  double lo = p.x[imax > 0 ? imax - 1 : 0], hi = p.x[std::min(imax + 1, n - 1)];
  p.alpha = p.slope[imax];
  p.x_at_alpha = p.x[imax];
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double s1 = at(x1).slope, s2 = at(x2).slope;
  for (int k = 0; k < 60 && hi - lo > 1e-12; ++k) {
    if (s1 > s2) {
      hi = x2, x2 = x1, s2 = s1, x1 = hi - g * (hi - lo), s1 = at(x1).slope;
    } else {
      lo = x1, x1 = x2, s1 = s2, x2 = lo + g * (hi - lo), s2 = at(x2).slope;
    }
    if (std::max(s1, s2) > p.alpha) {
      p.alpha = std::max(s1, s2);
      p.x_at_alpha = s1 > s2 ? x1 : x2;
    }
  }
  p.alpha_force = *std::max_element(p.lateral.begin(), p.lateral.end()) / o.normal_force;
  p.barrier = p.enthalpy[n / 2] - p.enthalpy[0];
  p.height_hollow = p.height[0];
  p.height_bridge = p.height[n / 2];
  // Check of z' = -V_xz/V_zz: its integral from the hollow to the bridge (trapezoids) against
  // the rise of z. Jumps of z' cost O(spacing x jump) here, a pointwise comparison would not
  // tolerate them.
  double rise = 0.0;
  for (std::size_t k = 0; k < n / 2; ++k)
    rise += 0.5 * (p.slope[k] + p.slope[k + 1]) * (p.x[k + 1] - p.x[k]);
  p.slope_check =
      std::abs(rise - (p.height_bridge - p.height_hollow)) / (p.height_bridge - p.height_hollow);
  return p;
}

}  // namespace asperity::explicit_model
