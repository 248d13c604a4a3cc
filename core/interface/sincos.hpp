// sin(2 pi s) and cos(2 pi s) for a position s in units of the lattice spacing: the registry
// potential of MODEL.md 3 needs both for every contact site at every energy evaluation, and
// libm's sincos was a quarter of a large slide's time.
//
// The reduction is exact: r = s - round(s) and t = r - q/4 (q = round(4 r)) are computed without
// rounding error for |s| < 2^50, so, unlike sin(2 pi s) through libm, no error from the product
// 2 pi s is amplified by a large argument. On |2 pi t| <= pi/4 the Taylor series to x^15 (sin)
// and x^16 (cos) are accurate to below 1e-16; tested against libm to 4e-16.
#pragma once

namespace asperity::interface {

inline void sincos_2pi(double s, double& sine, double& cosine) {
  // round() by the 1.5 * 2^52 trick: exact, branch-free and vectorisable.
  constexpr double shifter = 6755399441055744.0;
  const double r = s - ((s + shifter) - shifter);                       // |r| <= 1/2
  const double qd = ((4.0 * r + shifter) - shifter);                    // quadrant, -2 .. 2
  const double x = 6.283185307179586476925286766559 * (r - 0.25 * qd);  // |x| <= pi/4
  const double x2 = x * x;
  const double sn =
      x * (1.0 + x2 * (-1.0 / 6 +
                       x2 * (1.0 / 120 + x2 * (-1.0 / 5040 +
                                               x2 * (1.0 / 362880 +
                                                     x2 * (-1.0 / 39916800 +
                                                           x2 * (1.0 / 6227020800 +
                                                                 x2 * (-1.0 / 1307674368000))))))));
  const double cs =
      1.0 +
      x2 * (-0.5 +
            x2 * (1.0 / 24 +
                  x2 * (-1.0 / 720 +
                        x2 * (1.0 / 40320 +
                              x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600 +
                                                           x2 * (-1.0 / 87178291200 +
                                                                 x2 * (1.0 / 20922789888000))))))));
  // Quadrant q: rotate by q quarter turns, as selects rather than branches (the quadrants of
  // neighbouring sites are random during a slip, and mispredicted branches cost more than this).
  const int q = static_cast<int>(qd) & 3;  // -2 -> 2, -1 -> 3
  const double a = (q & 1) != 0 ? cs : sn;
  const double b = (q & 1) != 0 ? sn : cs;
  sine = (q & 2) != 0 ? -a : a;
  cosine = ((q + 1) & 2) != 0 ? -b : b;
}

}  // namespace asperity::interface
