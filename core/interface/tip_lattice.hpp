// The tip's lattice out of registry with the substrate's (issue 27): rotated by theta about z and
// scaled to the spacing d_tip = (1 + m) d. MODEL.md 3 writes the registry potential of a tip
// whose lattice is the substrate's; out of registry it is written in the tip's frame:
//   rho_i = Q(-theta) (X_i + u_i - (Dx, 0)) / d_tip        (registry coordinates, tip spacings),
//   V_i   = (tau_max(r_i) d^2 d_tip / (2 pi)) [2 - cos(2 pi rho_i1) - cos(2 pi rho_i2)],
//   f_i   = -dV_i/du_i = -tau_max(r_i) d^2 Q(theta) [sin(2 pi rho_i1), sin(2 pi rho_i2)],
// with Q(theta) the rotation by theta. The amplitude d^2 d_tip (d^3 for the aligned tip) keeps
// tau_max the peak shear stress per site: the force on a site along either tip axis peaks at
// tau_max d^2 whatever theta and m (a site's area is the substrate's d^2). The interface Hessian
// of a site is Q diag(k1, k2) Q^T, k_j = tau_max d^2 (2 pi / d_tip) cos(2 pi rho_ij): it couples
// the two components of a site unless theta = 0. A site's registry index is round(rho) per tip
// axis. theta = m = 0 is MODEL.md 3 exactly; the code keeps its own arithmetic for that case
// (aligned()), so that results stay bit for bit those of an aligned tip.
//
// The envelope (tau_max(r), p(r)) and the contact geometry do not change: only the lattice the
// substrate sites feel. In the explicit model (MODEL.md 4) the tip atoms sit at
// Q(theta) ((k + 1/2), (l + 1/2)) d_tip from the tip centre, on the sphere.
#pragma once

#include <cmath>
#include <numbers>

namespace asperity::interface {

struct TipLattice {
  double angle = 0.0;     // rotation of the tip lattice about z against the substrate's (degrees)
  double mismatch = 0.0;  // m: the tip's lattice spacing is d_tip = (1 + m) d

  [[nodiscard]] bool aligned() const { return angle == 0.0 && mismatch == 0.0; }
  friend bool operator==(const TipLattice&, const TipLattice&) = default;
};

// The change of frame of a TipLattice on a substrate of spacing d.
class TipFrame {
 public:
  TipFrame() = default;
  TipFrame(const TipLattice& tip, double d)
      : aligned_(tip.aligned()),
        d_(d),
        d_tip_((1.0 + tip.mismatch) * d),
        c_(std::cos(tip.angle * std::numbers::pi / 180.0)),
        s_(std::sin(tip.angle * std::numbers::pi / 180.0)) {
    if (tip.angle == 0.0) c_ = 1.0, s_ = 0.0;  // exact, whatever libm gives
  }

  [[nodiscard]] bool aligned() const { return aligned_; }
  [[nodiscard]] double spacing() const { return d_tip_; }  // d_tip
  [[nodiscard]] double cos() const { return c_; }
  [[nodiscard]] double sin() const { return s_; }

  // Registry coordinates (tip spacings) of a relative position s (d): rho = Q(-theta) s / d_tip;
  // s / d for the aligned tip (the arithmetic of MODEL.md 3).
  void registry(double sx, double sy, double& rho1, double& rho2) const {
    if (aligned_) {
      rho1 = sx / d_, rho2 = sy / d_;
      return;
    }
    rho1 = (c_ * sx + s_ * sy) / d_tip_;
    rho2 = (c_ * sy - s_ * sx) / d_tip_;
  }
  // The slip test of both models (MODEL.md 5; slide/slider.cpp says why the floor): a site whose
  // registry coordinates went from (b1, b2) to (a1, a2) (registry() of its relative positions)
  // by the displacement (dux, duy) jumped if round(rho) changed along a tip axis while it moved
  // by d/4 or more along that axis. For the aligned tip rho = s / d and the axes are x and y.
  [[nodiscard]] bool registry_jumped(double b1, double b2, double a1, double a2, double dux,
                                     double duy) const {
    double du1 = 0.0, du2 = 0.0;
    to_tip(dux, duy, du1, du2);
    return (std::lround(b1) != std::lround(a1) && std::abs(du1) >= 0.25 * d_) ||
           (std::lround(b2) != std::lround(a2) && std::abs(du2) >= 0.25 * d_);
  }
  // A vector along the tip's axes, in the substrate's frame: Q(theta) (v1, v2).
  void to_substrate(double v1, double v2, double& vx, double& vy) const {
    if (aligned_) {
      vx = v1, vy = v2;
      return;
    }
    vx = c_ * v1 - s_ * v2;
    vy = s_ * v1 + c_ * v2;
  }
  // A vector of the substrate's frame along the tip's axes: Q(-theta) (vx, vy).
  void to_tip(double vx, double vy, double& v1, double& v2) const {
    if (aligned_) {
      v1 = vx, v2 = vy;
      return;
    }
    v1 = c_ * vx + s_ * vy;
    v2 = c_ * vy - s_ * vx;
  }

 private:
  bool aligned_ = true;
  double d_ = 1.0, d_tip_ = 1.0, c_ = 1.0, s_ = 0.0;
};

}  // namespace asperity::interface
