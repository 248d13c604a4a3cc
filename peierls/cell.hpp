// The periodic Peierls cell (MODEL.md section 6; SOLVERS.md "Periodic Peierls cell").
//
// An L x L periodic patch of the surface under a rigid body whose sites are shifted by
//   w(X) = d (m_x X_x + m_y X_y) / L   along x,
// so that registry fails once along the normal (m_x, m_y) and the cell holds exactly one
// interfacial dislocation, b = d x-hat, with line direction (-m_y, m_x): theta = 0 is screw
// (m = (0, 1)), theta = 90 degrees edge (m = (1, 0)). Uniform tau_max = G d / b_core (no envelope).
// Energy (MODEL.md 3 with s = u - w x-hat, and section 6):
//   Pi = 1/2 u.K u + sum_i (tau_max d^3 / 2 pi) [2 - cos(2 pi s_ix / d) - cos(2 pi s_iy / d)]
//        - tau_ext d^2 sum_i u_ix,
// K the periodic surface stiffness (MODEL.md 2; elastic/surface_gf.hpp), in-plane components.
//
// Two exact representations of the same cell:
// - full: all L^2 sites, 2D FFTs of the L x L grid.
// - reduced (default): w, and so every straight-line state, depends on X only through
//   k = (m . X) mod L (gcd(m_x, m_y) = 1 makes this onto 0..L-1). A field g(k) is a sum of plane
//   waves at the L wave vectors q_n = 2 pi n (m_x, m_y) / (L d), so the cell's stiffness acts on
//   it as the 1D convolution whose Fourier multiplier at n is the periodic kernel K(q_n). The
//   unknowns are the L sites of one chain across the line, spaced d / |m| along the normal: the
//   same answer as the full cell for a straight line, at 1/L of the cost. The tests compare the
//   two; a symmetry-breaking instability (kinks) would show up only in the full cell.
// Lengths are in d, stresses in G (forces per site in G d^2).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/elastic/material.hpp"
#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fft_engine.hpp"
#include "asperity/core/minimize/stiffness_minimizer.hpp"

namespace asperity::peierls {

// A line orientation a cell can hold.
struct Orientation {
  int mx = 1, my = 0;       // frustration integers, gcd(mx, my) = 1
  double theta_deg = 90;    // angle between the line and b = x-hat (0 screw, 90 edge)
  double line_spacing = 0;  // distance between the line's periodic images along the normal (d)
};

// theta of the line perpendicular to (mx, my), folded into [0, 90] degrees.
double line_angle_deg(int mx, int my);

// All orientations with 0 <= mx, my <= max_index, gcd(mx, my) = 1, whose images are at least
// min_line_spacing apart (L / |m|), one per distinct angle (the smallest |m|), by angle.
std::vector<Orientation> available_orientations(int L, double min_line_spacing, int max_index = 8);

// The orientation of available_orientations(L, min_line_spacing) nearest to theta_deg; throws
// std::invalid_argument if none lies within tolerance_deg (the message lists what is offered).
Orientation orientation_for_angle(int L, double theta_deg, double tolerance_deg,
                                  double min_line_spacing);

enum class CellModel { reduced, full };
std::string to_string(CellModel m);
CellModel cell_model_from_string(const std::string& name);  // throws std::invalid_argument

struct CellOptions {
  int L = 256;                           // sites per period along x and y; even, >= 8
  int mx = 1, my = 0;                    // frustration integers (MODEL.md 6); gcd(mx, my) = 1
  double b_core = 4.0;                   // core width d G / tau_max (d); sets tau_max
  elastic::Material material;            // G (unit of stress) and nu
  CellModel model = CellModel::reduced;  // see the header
  int alias_images = elastic::kDefaultAliasImages;  // reciprocal images per direction in the
                                                    // periodic kernel
  int threads = 1;                                  // FFT threads (full model)

  // The settings of a scan's cell (keys "cell.L", "cell.model", "cell.alias_images",
  // "material.G", "material.nu"); b_core and (mx, my) are a point's own, threads the run's.
  static const settings::Table<CellOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

class PeierlsCell final : public minimize::StiffnessProblem {
 public:
  explicit PeierlsCell(const CellOptions& options);

  [[nodiscard]] std::size_t size() const override { return 2 * sites_; }
  void stiffness(std::span<const double> u, std::span<double> Ku) override;
  void precondition(std::span<const double> r, std::span<double> z) override;
  void interface_force(std::span<const double> u, std::span<double> f_int) const override;
  [[nodiscard]] double max_site_norm(std::span<const double> d) const override;

  // Interface energy sum_i V_i (G d^3); for reporting only (solvers use forces).
  [[nodiscard]] double interface_energy(std::span<const double> u) const;

  [[nodiscard]] const CellOptions& options() const { return options_; }
  [[nodiscard]] std::size_t sites() const { return sites_; }
  [[nodiscard]] double tau_max() const { return tau_max_; }
  // Chain index k = (m . X) mod L of a site, and its registry shift w = d k / L (mod d).
  [[nodiscard]] int chain_index(std::size_t site) const { return chain_[site]; }
  [[nodiscard]] double registry_shift(std::size_t site) const;
  // Site (X, Y) of the full cell that a site stands for (reduced: one representative per k).
  void site_position(std::size_t site, int& X, int& Y) const;

  // A state that already holds the line (SOLVERS.md): registry everywhere, u_x = w - d past
  // k = L/2, u_y = 0.
  [[nodiscard]] std::vector<double> initial_state() const;

  // Registry offset phi_k = w_k - u_x (d) along the chain k = 0..L-1 (sites of one k averaged):
  // ~0 before the line, ~d after it.
  [[nodiscard]] std::vector<double> chain_offset(std::span<const double> u) const;

  // A state of the full L x L cell (x then y component, site X * L + Y) from a state of this
  // cell; the identity for the full model.
  [[nodiscard]] std::vector<double> expand(std::span<const double> u) const;

  [[nodiscard]] std::size_t transforms() const { return transforms_; }

 private:
  void multiply(std::span<const double> in, std::span<double> out,
                const std::vector<std::complex<double>>& kernel);

  CellOptions options_;
  std::size_t sites_ = 0;
  double tau_max_ = 0.0;
  std::vector<int> chain_;
  std::unique_ptr<fft::Engine> engine_;
  // 2x2 row-major blocks per Fourier half-grid entry, scaled by the FFT normalisation.
  std::vector<std::complex<double>> stiffness_, preconditioner_;
  std::size_t transforms_ = 0;
};

// Core width from a chain offset: the distance along the normal between the registry offsets
// d/4 and 3d/4 (linear interpolation), with the chain spacing d / |m|; position: where it is
// d/2. NaN if the profile does not cross both levels.
struct CoreProfile {
  double width = 0.0;     // (d)
  double position = 0.0;  // (d), along the normal from k = 0
};
CoreProfile core_profile(std::span<const double> chain_offset, int mx, int my);

// Continuum Peierls-Nabarro core width (b_core of MODEL.md 3) of the cell's line (MODEL.md 6),
// for a half-space against a rigid body:
// the line equation A |q| u = tau_max sin(2 pi s / d) with A = K_xx(q)/|q| has the solution
// u = (d / pi) atan(x / zeta) with zeta = A d / (2 pi tau_max), so the d/4 -> 3d/4 distance is
//   2 zeta = (b_core / pi) (cos^2 theta + sin^2 theta / (1 - nu))
// (u_y held by the interface): b_core / pi for screw, b_core / (pi (1 - nu)) for edge.
double continuum_core_width(double b_core, double theta_deg, double nu);

// Rigid-profile Peierls-Nabarro estimate (the misfit energy of the continuum profile summed over
// the atomic rows, spacing d/|m| along the normal, Poisson summation, lowest harmonic):
//   tau_P / tau_max = (4 pi zeta |m| / d) exp(-2 pi zeta |m| / d),  zeta = width / 2.
double rigid_peierls_estimate(double b_core, int mx, int my, double nu);

}  // namespace asperity::peierls
