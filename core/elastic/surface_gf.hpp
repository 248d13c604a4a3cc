// Discrete surface Green's functions u = G * f on a block of lattice sites (MODEL.md section 2).
//
// Fields are component-major: component k (see component_axis) of site (i0, i1) of the block
// is element k * count + i0 * n1 + i1. Forces are per atom (units of force), displacements in
// units of length.
//
// FreeSurfaceGF: a finite loaded block on an infinite surface. Exact linear convolution with
// the patch influence coefficients (influence.hpp) by zero padding (Hockney; DC-FFT): the FFT
// grid is the smallest FFT-friendly size >= 2 n - 1 per axis, which is all an exact linear
// convolution of an n-site block needs.
//
// PeriodicSurfaceGF: an L0 x L1 periodic cell. Its kernel is the lattice sum (Poisson
// summation) of the same patch model:
//   G_cell(q) = (1/d^2) sum_K G(q + K) S(q + K),  S(k) = sinc(kx d/2) sinc(ky d/2),
// over reciprocal lattice vectors K = 2 pi (m, n)/d, so it is the exact periodisation of the
// free kernel. The q = 0 mode (rigid shift of the surface) is handled explicitly: a net force
// on a periodic cell has no static response, so apply() leaves it out and returns u with zero
// mean, and apply_stiffness() gives K(0) = 0 (the shift costs no energy).
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/elastic/material.hpp"
#include "asperity/core/fft/fft_engine.hpp"

namespace asperity::elastic {

class FreeSurfaceGF {
 public:
  // region: the block of sites that may carry force and whose displacements are returned.
  // d: lattice spacing (length). Throws std::invalid_argument on bad input.
  // engine: the FFT backend (empty: fft::make_engine, one process). With a distributed one
  // (fft::mpi_engine_factory) each rank holds an even share of the region rows, in rank order
  // (local_rows() from local_row_begin()), and apply() and apply_filter() take and return
  // those rows: size() = ncomp x local rows x n1, site lists index the local rows. The rows
  // travel to and from the slabs of the padded grid that transform them (the region fills the
  // first half of the padded rows, so the slabs alone would leave half of the ranks without
  // rows). Every rank calls them together (collective).
  FreeSurfaceGF(const Material& material, Components components, Shape2 region, double d = 1.0,
                const fft::FFTOptions& fft = {}, const fft::EngineFactory& engine = {});

  // u = G * f over the region; f and u have size() elements and may not alias.
  void apply(std::span<const double> f, std::span<double> u);
  // The same for a force carried by some region sites only (`sites`: row-major region indices,
  // fastest in increasing order): f and u hold, component-major, the values on those sites
  // (ncomp() x sites.size()). Equal to apply() on the scattered field, read back on the sites,
  // without apply()'s passes over the whole region.
  void apply(std::span<const std::size_t> sites, std::span<const double> f, std::span<double> u);

  // w = R (I + c G~)^-1 R^T f: the in-plane force field f on the region, zero-padded, filtered
  // by the Fourier multiplier (I + c G(q))^-1 of the padded grid and restricted to the region
  // again. It approximates (I + c G)^-1 on the region, where c is a uniform interface stiffness
  // (force per length per site): G (I + c G)^-1 = (K + c)^-1 is the compliance of the surface
  // with springs of stiffness c on every site, the preconditioner that SOLVERS.md recommends
  // for the periodic cell, here for the free boundary. Symmetric positive definite for c >= 0
  // (a restriction of an SPD multiplier). One FFT pair, counted by filter_applications(); the
  // kernel is rebuilt only when c changes. In-plane components only.
  void apply_filter(std::span<const double> f, std::span<double> w, double c);
  // The same on a list of region sites, as apply(sites, f, u).
  void apply_filter(std::span<const std::size_t> sites, std::span<const double> f,
                    std::span<double> w, double c);
  [[nodiscard]] std::size_t filter_applications() const { return filter_applications_; }

  // Real-space coefficient: displacement of slot k at offset (o0, o1) sites per unit force of
  // slot l; what apply() convolves with.
  [[nodiscard]] double coefficient(int k, int l, int o0, int o1) const;

  [[nodiscard]] std::size_t size() const { return ncomp_ * local_.count(); }
  // The region rows this process holds: [local_row_begin(), + local_rows()); all of them
  // without a distributed engine.
  [[nodiscard]] int local_row_begin() const { return local_begin_; }
  [[nodiscard]] int local_rows() const { return local_.n0; }
  [[nodiscard]] int ncomp() const { return static_cast<int>(ncomp_); }
  [[nodiscard]] Components components() const { return components_; }
  [[nodiscard]] Shape2 region() const { return region_; }
  [[nodiscard]] Shape2 fft_shape() const { return engine_->real_shape(); }
  [[nodiscard]] const Material& material() const { return material_; }
  [[nodiscard]] double spacing() const { return d_; }
  // Number of apply() calls so far: the unit of cost reported by solvers.
  [[nodiscard]] std::size_t applications() const { return applications_; }
  // Threads of the transforms (FFTOptions::threads), offered to the solvers' vector passes.
  [[nodiscard]] int threads() const { return threads_; }

 private:
  // The Fourier-space product at wave vector q, on entry `at` of a block.
  void multiply(const fft::FourierBlock& b, std::size_t q, std::size_t at) const;
  template <class PerQ>
  void convolve(const std::span<const std::size_t>* sites, std::span<const double> in,
                std::span<double> out, PerQ per_q);
  template <class PerQ>
  void transform(PerQ& per_q);
  template <class PerQ>
  void convolve_shared(const std::span<const std::size_t>* sites, std::span<const double> in,
                       std::span<double> out, PerQ per_q);
  // Moves whole region rows (component-major) from the callers' shares to the slabs (to_slabs)
  // or back.
  void exchange_rows(const std::vector<double>& from, bool to_slabs, std::vector<double>& to) const;
  static void check_site(std::size_t site, std::size_t n);
  void map_sites(std::span<const std::size_t> sites);
  void apply_on(const std::span<const std::size_t>* sites, std::span<const double> f,
                std::span<double> u);
  void filter_on(const std::span<const std::size_t>* sites, std::span<const double> f,
                 std::span<double> w, double c);

  Material material_;
  Components components_;
  Shape2 region_;
  Shape2 local_;         // the region rows held here (all of them for one process)
  int local_begin_ = 0;  // the first of them
  // The region rows of this process's slab of the padded grid; over several processes, every
  // process's slab rows and its share of the region (the rows held for the callers), in rank
  // order (empty on one process, where the two are the same).
  int slab_begin_ = 0, slab_rows_ = 0;
  struct Rows {
    int begin = 0, end = 0;
  };
  std::vector<Rows> slabs_, shares_;
  // Their buffers, kept between calls: the rows of the share and of the slab, and the exchange's.
  std::vector<double> shared_rows_, shared_slab_;
  mutable std::vector<double> exchange_send_, exchange_recv_;
  double d_;
  std::size_t ncomp_;
  std::unique_ptr<fft::Engine> engine_;
  // Fourier kernels scaled by the FFT normalisation. Real parts of xx, xy, yy, zz; imaginary
  // parts s_x, s_y of G_xz = i s_x, G_yz = i s_y (G_zx = -i s_x). Empty where not needed.
  std::vector<double> kxx_, kxy_, kyy_, kzz_, sx_, sy_;
  std::size_t applications_ = 0;
  // The filter's multiplier (I + c G)^-1 times the FFT normalisation, for filter_c_.
  std::vector<double> mxx_, mxy_, myy_;
  double filter_c_ = -1.0;
  std::size_t filter_applications_ = 0;
  int threads_ = 1;
  // Site-list calls: padded-grid position of each listed site; whether a whole-region call
  // left values in the region of the engine's input.
  std::vector<std::size_t> positions_;
  bool region_dirty_ = false;
};

// The periodic cell's compliance block at one wave vector (q0, q1) (1/length), the lattice sum
//   (1/d^2) sum_K G(q + K) S(q + K)
// truncated symmetrically at |m|, |n| <= alias_images, as ncomp x ncomp row-major entries
// (Hermitian). PeriodicSurfaceGF tabulates it on its cell's grid; a problem invariant along a
// lattice direction can sample it on the few wave vectors it needs (peierls/).
void periodic_compliance_block(const Material& material, Components components, double q0,
                               double q1, double d, int alias_images,
                               std::span<std::complex<double>> out);

// Reciprocal images per direction of the periodic lattice sum by default: the kernel's
// truncation error at 12 is below the tolerances the cells are solved to (tested).
inline constexpr int kDefaultAliasImages = 12;

class PeriodicSurfaceGF {
 public:
  // cell: sites per period along x and y. alias_images: reciprocal vectors per direction and
  // sign in the lattice sum (|m|, |n| <= alias_images); its truncation error falls as
  // alias_images^-2 (tested).
  // engine: the FFT backend, as FreeSurfaceGF's (empty: one process). With a distributed one
  // each rank holds the cell rows of its slab (local_rows() from local_row_begin(); the slabs
  // are the cell's own rows, there is no padding) and apply() and apply_stiffness() take and
  // return those rows; every rank calls them together.
  PeriodicSurfaceGF(const Material& material, Components components, Shape2 cell, double d = 1.0,
                    const fft::FFTOptions& fft = {}, int alias_images = kDefaultAliasImages,
                    const fft::EngineFactory& engine = {});

  // u = G * f without the q = 0 mode: the mean force is not transmitted and u has zero mean.
  void apply(std::span<const double> f, std::span<double> u);
  // f = K * u with K = G^-1 for q != 0 and K(0) = 0.
  void apply_stiffness(std::span<const double> u, std::span<double> f);

  [[nodiscard]] std::size_t size() const { return ncomp_ * local_.count(); }
  // The cell rows this process holds: [local_row_begin(), + local_rows()); all on one process.
  [[nodiscard]] int local_row_begin() const { return local_begin_; }
  [[nodiscard]] int local_rows() const { return local_.n0; }
  [[nodiscard]] int ncomp() const { return static_cast<int>(ncomp_); }
  [[nodiscard]] Components components() const { return components_; }
  [[nodiscard]] Shape2 cell() const { return cell_; }
  [[nodiscard]] const Material& material() const { return material_; }
  [[nodiscard]] double spacing() const { return d_; }
  [[nodiscard]] std::size_t applications() const { return applications_; }

 private:
  void multiply(std::span<const double> in, std::span<double> out, bool stiffness);

  Material material_;
  Components components_;
  Shape2 cell_;
  Shape2 local_;         // the cell rows held here (all of them for one process)
  int local_begin_ = 0;  // the first of them
  double d_;
  std::size_t ncomp_;
  std::unique_ptr<fft::Engine> engine_;
  // Hermitian ncomp x ncomp blocks per wave vector, for the compliance G and stiffness K,
  // scaled by the FFT normalisation; row-major ncomp*ncomp entries per q.
  std::vector<std::complex<double>> compliance_, stiffness_;
  std::size_t applications_ = 0;
};

// Elastic energy 1/2 f.u of a force field and the displacement it causes.
double elastic_energy(std::span<const double> f, std::span<const double> u);

}  // namespace asperity::elastic
