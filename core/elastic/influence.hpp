// Surface Green's functions of an isotropic elastic half-space (MODEL.md section 2).
//
// Equations implemented:
// - Boussinesq-Cerruti point-force solution at the surface, z pointing out of the solid:
//     g_xx = [(1-nu)/r + nu x^2/r^3] / (2 pi G),   g_yy = [(1-nu)/r + nu y^2/r^3] / (2 pi G),
//     g_xy = nu x y / r^3 / (2 pi G),               g_zz = (1-nu) / (2 pi G r),
//     g_xz = -g_zx = (1 - 2 nu) x / (4 pi G r^2),   g_yz = -g_zy = (1 - 2 nu) y / (4 pi G r^2)
//   (g_ij: displacement i at (x, y) per unit force j at the origin; g_xz > 0 because pressing
//   the surface down pulls it inwards, Johnson, Contact Mechanics, eq. 3.19).
// - The same for a force spread uniformly over a d x d patch (the discretisation of MODEL.md 2),
//   in closed form through the corner antiderivatives (Love 1929 for 1/r):
//     int int 1/r     = x ln(y + r) + y ln(x + r),   int int x^2/r^3 = y ln(x + r),
//     int int x y/r^3 = -r,                          int int x/r^2   = y ln r + x atan(y/x).
// - The continuum Fourier transform (convention exp(-i q.x)):
//     G_xx = (1 - nu qx^2/q^2)/(G q), G_xy = -nu qx qy/(G q^3), G_zz = (1-nu)/(G q),
//     G_xz = -G_zx = -i (1 - 2 nu) qx / (2 G q^2).
#pragma once

#include <complex>

#include "asperity/core/elastic/material.hpp"

namespace asperity::elastic {

// Displacement along axis i (0 = x, 1 = y, 2 = z) at (x, y) per unit force along axis j applied
// at the origin. Units: length / force. Singular at the origin.
double point_force_gf(const Material& m, int i, int j, double x, double y);

// Displacement along axis i at (x, y), measured from the centre of a d x d patch that carries a
// unit total force along axis j, spread as a uniform traction. Finite everywhere.
double patch_gf(const Material& m, int i, int j, double x, double y, double d);

// Continuum Fourier-space surface Green's function, u(q) = G(q) f(q), for q != 0.
std::complex<double> fourier_gf(const Material& m, int i, int j, double qx, double qy);

// All of it at once: g[i][j] = G_ij(q). The lattice sums of the periodic GF evaluate it at
// hundreds of images per wave vector.
void fourier_gf_tensor(const Material& m, double qx, double qy, std::complex<double> (&g)[3][3]);

}  // namespace asperity::elastic
