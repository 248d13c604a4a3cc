// The explicit atomistic contact (MODEL.md section 4): a rigid tip of atoms, bent onto a sphere,
// pressed on the (100) face of an elastic half-space whose surface atoms carry 3 displacement
// components (GF of MODEL.md 2, Components::full), interacting across the interface only through
// the repulsive Lennard-Jones potential of lennard_jones.hpp.
//
// Geometry (lengths in d, stresses in G, forces in G d^2): substrate atom i at X_i = (I, J) d,
// position X_i + u_i; tip atom (k, l) at (Dx + (k + 1/2) d, (l + 1/2) d, z_kl) with
//   z_kl = h + R - sqrt(R^2 - ((k + 1/2) d)^2 - ((l + 1/2) d)^2)     (hollow-site registry),
// so h is the height of the sphere's apex. Interface energy and force on substrate atom i:
//   V = sum_i sum_k phi(|P_i - T_k|),  f_int,i = -dV/du_i = -sum_k phi'(r)/r (P_i - T_k).
// Neighbours come from lattice indices: substrate atom i only sees the tip atoms whose lateral
// offset is below the cutoff r_c (about 2 x 2 to 3 x 3 of them); there is no all-pairs search.
//
// Unknowns: the displacements of the substrate atoms in an "active" disk around the tip centre,
// inside a square block of sites on which the free-boundary GF acts; the elastic problem is the
// pair representation of SOLVERS.md (minimize/problem.hpp). The contact region is not known in
// advance: after each minimisation the atoms of the block outside the disk (displaced by u = G f)
// are checked, and if any feels a force the disk grows to the farthest such atom plus a margin
// (and the block with it) and the minimisation continues.
//
// Load control (MODEL.md 4: lower the tip to reach the target Fz): an outer loop on h, each step
// a minimisation at fixed h (a stable, displacement-controlled problem), Newton-secant on Fz(h)
// starting from the Hertz contact stiffness dFz/d(delta) = 2 a E*. The start is the Hertz state
// (forces p(r_i) d^2 on the sites, u = G f, delta of Hertz).
//
// Penetration: the apex substrate atom, undisplaced, is first touched by its four tip
// neighbours (lateral offset d/sqrt(2)) when they are r_c away, i.e. at h_touch = g0 -
// (R - sqrt(R^2 - d^2/2)), g0 = sqrt(r_c^2 - d^2/2); delta = h_touch - h is the approach that
// Hertz calls delta = a^2/R. The interface compliance (the LJ pairs compress under load) adds
// to it, by about (g0 - g(p0 d^2)) at the centre.
// A tip lattice out of registry (interface/tip_lattice.hpp; contact.tip_angle,
// contact.tip_mismatch) puts tip atom (k, l) at (Dx, 0) + Q(theta) ((k + 1/2), (l + 1/2)) d_tip,
// d_tip = (1 + m) d, on the same sphere: the pair sums run in the tip's frame (lateral offsets
// Q(-theta)(P_i - (Dx, 0))), the forces are turned back by Q(theta). The apex atom's four tip
// neighbours are then d_tip/sqrt(2) away (h_touch and g0 with d_tip). theta = m = 0 keeps the
// arithmetic above. Contact radius: from the loaded area, a = d sqrt(N/pi) over the atoms that feel
// a force, and from the second moment of the load, a = sqrt(5/2 <r^2>) (<r^2> = 2 a^2/5 for Hertz).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/shape.hpp"
#include "asperity/core/common/termination.hpp"
#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/elastic/material.hpp"
#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/explicit/lennard_jones.hpp"
#include "asperity/core/fft/fft_engine.hpp"
#include "asperity/core/interface/tip_lattice.hpp"
#include "asperity/core/minimize/minimizer.hpp"

namespace asperity::explicit_model {

struct ExplicitScene {
  double R = 535.0;                          // tip (sphere) radius (d)
  double G_eps_sigma3 = 10.0;                // substrate shear modulus in eps/sigma^3
  double sigma_over_d = 0.8908987181403393;  // LJ sigma in d (2^(-1/6): r_c = d)
  elastic::Material material{};              // G = 1 (the stress unit), nu
  double d = 1.0;                            // lattice spacing (unit of length)
  interface::TipLattice tip {};              // the tip's lattice (aligned: hollow sites)

  // Throws std::invalid_argument naming the violated constraint. sigma/d in [0.75, 1.0]: below,
  // the cutoff barely exceeds the hollow-site gap d/sqrt(2) and tip atoms sink into the hollows;
  // above, the neighbour windows grow beyond 3 x 3. The same margin for a tip of another spacing:
  // r_c >= 1.19 d_tip / sqrt(2) (sigma/d = 0.75 gives r_c = 1.1906 d / sqrt(2)).
  void validate() const;
  // The scene's own settings ("explicit.G", "explicit.sigma_over_d"; common/settings.hpp): R,
  // material, d and the tip's lattice come from the contact (ContactScene) and are not repeated.
  static const settings::Table<ExplicitScene>& settings();
  [[nodiscard]] LennardJones potential() const;  // in G and d
  // One eps/sigma in G d^2 (forces) and one eps in G d^3 (energies).
  [[nodiscard]] double force_unit() const;
  [[nodiscard]] double energy_unit() const;
  [[nodiscard]] double tip_spacing() const { return (1.0 + tip.mismatch) * d; }  // d_tip
  // Zero-force gap between the apex substrate atom and the plane of its four tip neighbours.
  [[nodiscard]] double contact_gap() const;
  // Apex height at which the undisplaced apex atom is first touched.
  [[nodiscard]] double touch_height() const;
};

// Throws std::invalid_argument with the small-slope message unless a / R < 0.1 (MODEL.md 4).
void require_small_slope(double a, double R);

struct LoadOptions {
  double load = 0.0;             // target Fz (G d^2); > 0
  double load_tolerance = 1e-5;  // stop when |Fz - target| <= this * target
  int max_load_steps = 40;       // outer (tip height) iterations
  double margin = 3.0;           // active disk beyond the farthest loaded atom (d)
  double initial_radius = 0.0;   // active disk at the start (d); 0: Hertz a + margin; never
                                 // below Hertz a + 1 d, the disk the Hertz start loads
  int max_growths = 50;          // disk growths per minimisation
  minimize::MinimizerOptions minimizer;
  fft::FFTOptions fft;

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

// The state and its measures on the block of sites (block-major i0 * n1 + i1).
struct ExplicitState {
  LatticeBlock block;
  double Dx = 0.0, h = 0.0;
  std::vector<double> ux, uy, uz;       // displacement (d)
  std::vector<double> fx, fy, fz;       // interface force on the substrate atom (G d^2)
  std::vector<std::uint8_t> active;     // unknown of the minimisation
  double Fx = 0.0, Fy = 0.0, Fz = 0.0;  // total force of the tip on the substrate (Fz > 0: load)
  double energy = 0.0;                  // elastic + interface (G d^3)
  std::size_t loaded_sites = 0;         // atoms feeling a force
  double a_area = 0.0, a_moment = 0.0;  // contact radius from the area, from <r^2> (d)
};

struct LoadResult {
  ExplicitState state;
  contact::Hertz hertz;         // Hertz at the target load
  double target = 0.0;          // Fz asked (G d^2)
  double delta = 0.0;           // approach h_touch - h (d)
  double delta_error = 0.0;     // delta / (a_H^2/R) - 1 at the load reached
  double load_error = 0.0;      // Fz / Fz_Hertz(delta) - 1, Fz_H = 4 E* sqrt(R) delta^1.5 / 3
  double a_area_error = 0.0;    // a_area - a_H (d)
  double a_moment_error = 0.0;  // a_moment - a_H (d)
  int load_steps = 0, minimizations = 0, growths = 0;
  long long iterations = 0;
  std::size_t gf_applications = 0, interface_evaluations = 0;
  std::size_t active_sites = 0;
  Shape2 fft_grid;
  Termination termination = Termination::max_iterations;
  std::string message;  // what stopped it, if not converged
  double wall_s = 0.0;
};

// The explicit contact at a tip position: block, GF, active set, state, minimisation with growth.
class ExplicitContact {
 public:
  ExplicitContact(const ExplicitScene& scene, const fft::FFTOptions& fft = {});
  ~ExplicitContact();
  ExplicitContact(const ExplicitContact&) = delete;
  ExplicitContact& operator=(const ExplicitContact&) = delete;

  // Moves the tip (apex at (Dx, 0, h)); the active disk follows Dx, the block is rebuilt
  // (forces kept by lattice index) when the disk leaves it.
  void set_tip(double Dx, double h);
  // Active disk radius (d) around the tip centre; grows the block if needed.
  void set_active_radius(double radius);
  // Zero forces and displacements (no GF application): before set_tip() and set_forces() load
  // another state, so that the block can move without carrying the old one's forces.
  void clear_forces();
  // Tip at (Dx, 0, h) with an active disk of `radius` (d) on the block that set_active_radius
  // would build from scratch for them, whatever block the contact had: the start of a
  // relaxation then does not depend on the ones before it (a resumed slide repeats the
  // uninterrupted one). Forces are kept by lattice index; call clear_forces() first to load
  // another state.
  void place(double Dx, double h, double radius);
  // Forces on the block sites (component-major x, y, z) as a start; u = G f is recomputed.
  void set_forces(const std::vector<double>& f);
  // The Hertz state at `load`: f_z = -p(r_i) d^2, the apex height of the Hertz approach; the
  // active disk is raised to the Hertz radius + 1 d if smaller.
  void start_from_hertz(double load);

  // Minimises at the current tip, growing the active disk until no atom outside feels a force.
  // `observer` sees every iteration of every minimisation (unknowns of active_site_list(),
  // component-major); returning true stops relax() with Termination::interrupted.
  minimize::MinimizeResult relax(const minimize::MinimizerOptions& options, double margin,
                                 int max_growths, int* growths = nullptr,
                                 const minimize::Observer& observer = {});

  [[nodiscard]] ExplicitState state() const;
  [[nodiscard]] const ExplicitScene& scene() const { return scene_; }
  [[nodiscard]] double Dx() const { return Dx_; }
  [[nodiscard]] double h() const { return h_; }
  [[nodiscard]] double active_radius() const { return radius_; }
  [[nodiscard]] std::size_t active_sites() const { return sites_.size(); }
  [[nodiscard]] const LatticeBlock& block() const { return block_; }
  [[nodiscard]] const interface::TipFrame& tip_frame() const { return frame_; }
  // The block fields (component-major x, y, z; G d^2 and d) and the active block sites.
  [[nodiscard]] const std::vector<double>& forces() const { return f_; }
  [[nodiscard]] const std::vector<double>& displacements() const { return u_; }
  [[nodiscard]] const std::vector<std::size_t>& active_site_list() const { return sites_; }
  [[nodiscard]] Shape2 fft_grid() const;
  [[nodiscard]] std::size_t gf_applications() const;
  // Total normal load on the substrate at the current state (G d^2).
  [[nodiscard]] double load() const;
  // Active atoms above the tip's sphere: they went through its single layer of atoms (relax()
  // then reports Termination::diverged).
  [[nodiscard]] std::size_t passed_through() const;

  // Interface energy and force of block site i at displacement (ux, uy, uz); optional diagonal
  // of the interface Hessian. Returns V_i.
  double site_interface(std::size_t i, const double u[3], double f[3], double* h = nullptr) const;

 private:
  class Problem;
  void rebuild(int half_width);  // block of (2 half + 1)^2 sites around the tip's lattice column
  void select_active();
  void refresh_u();  // u = G f on the block
  // site_interface() under a tip lattice out of registry (tip_lattice.hpp).
  double site_interface_tip(double px, double py, double pz, double f[3], double* h) const;

  ExplicitScene scene_;
  LennardJones lj_;
  fft::FFTOptions fft_;
  double Dx_ = 0.0, h_ = 0.0, radius_ = 0.0;
  LatticeBlock block_;
  interface::TipFrame frame_;             // the tip's lattice (explicit_contact.hpp header)
  elastic::FreeSurfaceGF* gf_ = nullptr;  // the GF of block_, from gf_cache_
  // GFs (and their FFT plans) by block half-width: a slide returns to the same few block
  // sizes at every step, and a plan is made once per size.
  std::map<int, std::unique_ptr<elastic::FreeSurfaceGF>> gf_cache_;
  std::size_t gf_apps_ = 0;         // applications of GFs dropped from the cache
  std::vector<double> f_, u_;       // block, component-major
  std::vector<std::size_t> sites_;  // active block sites
};

// Loads the tip to options.load (MODEL.md 4): Hertz start, minimisation with growth at each h,
// Newton-secant on h. Throws std::invalid_argument for bad options or a/R >= 0.1.
LoadResult load_to_force(const ExplicitScene& scene, const LoadOptions& options);

}  // namespace asperity::explicit_model
