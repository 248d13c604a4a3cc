// Discrete surface Green's functions; equations in surface_gf.hpp and influence.hpp
// (MODEL.md section 2).
#include "asperity/core/elastic/surface_gf.hpp"

#include <Eigen/Dense>
#include <cassert>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "asperity/core/elastic/influence.hpp"

namespace asperity::elastic {

namespace {

void check_common(const Material& material, Shape2 shape, double d, const char* what) {
  material.validate();
  if (!std::isfinite(d) || !(d > 0.0)) {
    throw std::invalid_argument(std::string(what) + ": lattice spacing d: got " +
                                std::to_string(d) + ", allowed: finite and > 0");
  }
  if (shape.n0 < 1 || shape.n1 < 1) {
    throw std::invalid_argument(std::string(what) + ": block of " + std::to_string(shape.n0) +
                                " x " + std::to_string(shape.n1) +
                                " sites; allowed: at least 1 x 1");
  }
}

void check_size(std::span<const double> a, std::size_t n, const char* what) {
  if (a.size() != n) {
    throw std::invalid_argument(std::string(what) + ": field has " + std::to_string(a.size()) +
                                " values, expected " + std::to_string(n));
  }
}

// Signed offset held by index k of a wrapped padded axis of length p, for a block of n sites;
// returns false for the indices between +-(n-1) that no pair of block sites reaches.
bool wrapped_offset(int k, int p, int n, int& offset) {
  if (k < n) {
    offset = k;
    return true;
  }
  if (k > p - n) {
    offset = k - p;
    return true;
  }
  return false;
}

double sinc(double x) {
  return std::abs(x) < 1e-8 ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}

// The in-plane product at entry `at` of a block: (x, y) <- [[a, b], [b, c]] (x, y), a real
// symmetric 2 x 2 kernel (the compliance, or the filter's multiplier).
inline void symmetric_product(const fft::FourierBlock& blk, std::size_t at, double a, double b,
                              double c) {
  const std::complex<double> x = blk.field[0][at], y = blk.field[1][at];
  blk.field[0][at] = a * x + b * y;
  blk.field[1][at] = b * x + c * y;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
FreeSurfaceGF::FreeSurfaceGF(const Material& material, Components components, Shape2 region,
                             double d, const fft::FFTOptions& fft, const fft::EngineFactory& engine)
    : material_(material),
      components_(components),
      region_(region),
      local_(region),
      d_(d),
      ncomp_(static_cast<std::size_t>(component_count(components))) {
  check_common(material, region, d, "FreeSurfaceGF");
  const Shape2 padded{next_fft_size(2 * region.n0 - 1),
                      next_fft_size(std::max(2, 2 * region.n1 - 1))};
  engine_ = engine ? engine(padded, ncomp(), fft, region.n0)
                   : fft::make_engine(padded, ncomp(), fft, region.n0);
  threads_ = std::max(1, fft.threads);
  // The region rows of this process's slab of the padded grid (the region starts at its row 0,
  // so the slab's first row is its first region row).
  const fft::Layout layout = engine_->layout();
  slab_begin_ = std::min(layout.row_begin, region.n0);
  slab_rows_ = std::min(layout.row_begin + layout.rows, region.n0) - slab_begin_;
  local_begin_ = slab_begin_;
  local_.n0 = slab_rows_;
  // Over several processes the region fills the first half of the padded rows, so the slabs
  // would give every region row to the first half of the ranks (on 2, all to rank 0). The rows
  // this process holds for its callers are an even share of the region instead, in rank order,
  // moved to and from the slabs around each transform (exchange_rows): the transforms see the
  // same grid, so the results are those of the slabs' own rows, bit for bit.
  if (!layout.whole()) {
    const auto& comm = engine_->comm();
    const long long n0 = region.n0, ranks = comm.size(), rank = comm.rank();
    local_begin_ = static_cast<int>(rank * n0 / ranks);
    local_.n0 = static_cast<int>((rank + 1) * n0 / ranks) - local_begin_;
    const auto begins = comm.all_gather(slab_begin_), counts = comm.all_gather(slab_rows_);
    for (long long r = 0; r < ranks; ++r) {
      const auto q = static_cast<std::size_t>(r);
      slabs_.push_back({static_cast<int>(begins[q]), static_cast<int>(begins[q] + counts[q])});
      shares_.push_back({static_cast<int>(r * n0 / ranks), static_cast<int>((r + 1) * n0 / ranks)});
    }
  }

  // Each kernel entry is the FFT of the wrapped real-space coefficients; even kernels are real,
  // the odd normal-lateral coupling is imaginary. One engine field at a time is enough here.
  // Each process fills its rows and keeps the wave vectors it holds.
  const auto build = [&](int k, int l, bool imaginary) {
    auto in = engine_->input(0);
    for (int r = 0; r < layout.rows; ++r) {
      const int k0 = layout.row_begin + r;
      for (int k1 = 0; k1 < padded.n1; ++k1) {
        int o0 = 0, o1 = 0;
        const bool used = wrapped_offset(k0, padded.n0, region.n0, o0) &&
                          wrapped_offset(k1, padded.n1, region.n1, o1);
        in[padded.index(r, k1)] = used ? coefficient(k, l, o0, o1) : 0.0;
      }
    }
    engine_->forward();
    const auto spectrum = engine_->fourier(0);
    std::vector<double> out(spectrum.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = (imaginary ? spectrum[i].imag() : spectrum[i].real()) * engine_->normalisation();
    }
    return out;
  };
  const bool coupled = components == Components::full && material.nu != 0.5;
  if (components != Components::normal) {
    kxx_ = build(0, 0, false);
    kxy_ = build(0, 1, false);
    kyy_ = build(1, 1, false);
  }
  if (components != Components::in_plane) kzz_ = build(ncomp() - 1, ncomp() - 1, false);
  if (coupled) {
    sx_ = build(0, 2, true);
    sy_ = build(1, 2, true);
  }
  // Into the order in which convolve() visits the wave vectors (fft_engine.hpp): the products
  // then read every kernel contiguously. A distributed engine's columns (transposed out) are
  // in that order already.
  if (!layout.fourier_transposed) {
    const std::vector<std::size_t> order = engine_->block_order();
    for (auto* kernel : {&kxx_, &kxy_, &kyy_, &kzz_, &sx_, &sy_}) {
      if (!kernel->empty()) *kernel = fft::to_block_order(order, *kernel);
    }
  }
  // The input padding must be zero from here on: apply() writes only the region.
  for (int c = 0; c < ncomp(); ++c)
    std::fill(engine_->input(c).begin(), engine_->input(c).end(), 0.0);
}

double FreeSurfaceGF::coefficient(int k, int l, int o0, int o1) const {
  return patch_gf(material_, component_axis(components_, k), component_axis(components_, l),
                  o0 * d_, o1 * d_, d_);
}

// A listed site must lie in the region rows held here (n sites).
void FreeSurfaceGF::check_site(std::size_t site, std::size_t n) {
  if (site >= n) {
    throw std::invalid_argument("FreeSurfaceGF: site " + std::to_string(site) +
                                " outside the region rows held here, " + std::to_string(n) +
                                " sites");
  }
}

// Padded-grid position of each listed region site (row-major region indices). The walk needs
// no division for increasing indices (a contact's site list); any order is accepted.
void FreeSurfaceGF::map_sites(std::span<const std::size_t> sites) {
  const Shape2 padded = engine_->real_shape();
  const std::size_t n1 = static_cast<std::size_t>(local_.n1), n = local_.count();
  positions_.resize(sites.size());
  std::size_t row = 0, row_begin = 0;
  for (std::size_t j = 0; j < sites.size(); ++j) {
    const std::size_t s = sites[j];
    check_site(s, n);
    if (s < row_begin) {  // not increasing: jump to the row
      row = s / n1;
      row_begin = row * n1;
    }
    while (s >= row_begin + n1)
      ++row, row_begin += n1;
    positions_[j] = padded.index(static_cast<int>(row), static_cast<int>(s - row_begin));
  }
}

// The engine's fused transform with per_q on every wave vector it holds. The kernels are in the
// engine's block order: wave vector `at` of a block is kernel entry b.offset + at.
template <class PerQ>
void FreeSurfaceGF::transform(PerQ& per_q) {
  engine_->convolve([&per_q](const fft::FourierBlock& b) {
    const std::size_t count = static_cast<std::size_t>(b.rows) * static_cast<std::size_t>(b.width);
    for (std::size_t at = 0; at < count; ++at)
      per_q(b, b.offset + at, at);
  });
}

// Rows [begin, end) of the region held by each process for its callers and in its slab.
void FreeSurfaceGF::exchange_rows(const std::vector<double>& from, bool to_slabs,
                                  std::vector<double>& to) const {
  const auto& comm = engine_->comm();
  const auto& source = to_slabs ? shares_ : slabs_;
  const auto& target = to_slabs ? slabs_ : shares_;
  const Rows mine_from = source[static_cast<std::size_t>(comm.rank())];
  const Rows mine_to = target[static_cast<std::size_t>(comm.rank())];
  const auto overlap = [](Rows a, Rows b) {
    return std::max(0, std::min(a.end, b.end) - std::max(a.begin, b.begin));
  };
  const std::size_t n1 = static_cast<std::size_t>(region_.n1);
  const int per_row = static_cast<int>(ncomp_ * n1);
  std::vector<int> send_counts(source.size()), recv_counts(source.size());
  // The buffers are the GF's, kept between calls (region-sized, twice per transform).
  std::vector<double>& send = exchange_send_;
  send.clear();
  const std::size_t rows_from = static_cast<std::size_t>(mine_from.end - mine_from.begin);
  // Rows go in rank order of their targets (which is row order), each with its components.
  for (std::size_t q = 0; q < target.size(); ++q) {
    const int rows = overlap(mine_from, target[q]);
    send_counts[q] = rows * per_row;
    recv_counts[q] = overlap(mine_to, source[q]) * per_row;
    for (int g = std::max(mine_from.begin, target[q].begin);
         rows > 0 && g < std::min(mine_from.end, target[q].end); ++g) {
      for (std::size_t c = 0; c < ncomp_; ++c) {
        const auto at = static_cast<std::ptrdiff_t>(
            c * rows_from * n1 + static_cast<std::size_t>(g - mine_from.begin) * n1);
        send.insert(send.end(), from.begin() + at,
                    from.begin() + at + static_cast<std::ptrdiff_t>(n1));
      }
    }
  }
  std::vector<double>& recv = exchange_recv_;
  recv.resize(static_cast<std::size_t>(std::max(0, mine_to.end - mine_to.begin)) * ncomp_ * n1);
  comm.exchange(send, send_counts, recv, recv_counts);
  // Received row by row (every component of a row together): into component-major order.
  const std::size_t rows_to = static_cast<std::size_t>(mine_to.end - mine_to.begin);
  to.resize(recv.size());
  for (std::size_t r = 0; r < rows_to; ++r) {
    for (std::size_t c = 0; c < ncomp_; ++c)
      std::copy_n(recv.begin() + static_cast<std::ptrdiff_t>((r * ncomp_ + c) * n1), n1,
                  to.begin() + static_cast<std::ptrdiff_t>(c * rows_to * n1 + r * n1));
  }
}

// The convolution with the rows held for the callers moved to and from the slabs: the site
// values (or the whole rows) of this process's share become whole rows of the region, which go
// to the slabs holding them, are transformed there and come back.
template <class PerQ>
void FreeSurfaceGF::convolve_shared(const std::span<const std::size_t>* sites,
                                    std::span<const double> in, std::span<double> out, PerQ per_q) {
  const Shape2 padded = engine_->real_shape();
  const std::size_t n = local_.count();
  // This process's rows and its slab's, kept between calls.
  std::vector<double>&rows = shared_rows_, &slab = shared_slab_;
  rows.assign(ncomp_ * n, 0.0);
  if (sites) {
    const std::size_t m = sites->size();
    for (const std::size_t site : *sites)
      check_site(site, n);
    for (std::size_t c = 0; c < ncomp_; ++c) {
      for (std::size_t j = 0; j < m; ++j)
        rows[c * n + (*sites)[j]] = in[c * m + j];
    }
  } else {
    std::copy(in.begin(), in.end(), rows.begin());
  }
  exchange_rows(rows, true, slab);
  const std::size_t slab_n =
      static_cast<std::size_t>(slab_rows_) * static_cast<std::size_t>(region_.n1);
  for (std::size_t c = 0; c < ncomp_; ++c) {
    auto grid = engine_->input(static_cast<int>(c));
    for (int i0 = 0; i0 < slab_rows_; ++i0)
      std::copy_n(slab.begin() + static_cast<std::ptrdiff_t>(
                                     c * slab_n + static_cast<std::size_t>(i0) *
                                                      static_cast<std::size_t>(region_.n1)),
                  region_.n1, grid.data() + padded.index(i0, 0));
  }
  transform(per_q);
  for (std::size_t c = 0; c < ncomp_; ++c) {
    const double* grid = engine_->output(static_cast<int>(c)).data();
    for (int i0 = 0; i0 < slab_rows_; ++i0)
      std::copy_n(grid + padded.index(i0, 0), region_.n1,
                  slab.begin() + static_cast<std::ptrdiff_t>(
                                     c * slab_n + static_cast<std::size_t>(i0) *
                                                      static_cast<std::size_t>(region_.n1)));
  }
  exchange_rows(slab, false, rows);
  if (sites) {
    const std::size_t m = sites->size();
    for (std::size_t c = 0; c < ncomp_; ++c)
      for (std::size_t j = 0; j < m; ++j)
        out[c * m + j] = rows[c * n + (*sites)[j]];
  } else {
    std::copy(rows.begin(), rows.end(), out.begin());
  }
}

// Zero-padded convolution: copy in, per_q(block, q, at) on every wave vector of the fused
// transform (q: the kernels' index, in the engine's block order; at: the entry of the block),
// copy out. On the whole region (sites == nullptr) or on a list of its sites (the rest carry
// no force), whose fields hold the listed sites only. The engine's input is zero outside what
// a call writes: a whole-region call leaves the region dirty, and a list call cleans it once
// and clears its own sites after. Shared by apply() and apply_filter().
template <class PerQ>
void FreeSurfaceGF::convolve(const std::span<const std::size_t>* sites, std::span<const double> in,
                             std::span<double> out, PerQ per_q) {
  if (!shares_.empty()) {
    convolve_shared(sites, in, out, per_q);
    return;
  }
  const Shape2 padded = engine_->real_shape();
  const std::size_t n = sites ? sites->size() : local_.count();
  if (sites) {
    if (region_dirty_) {
      for (std::size_t c = 0; c < ncomp_; ++c) {
        auto grid = engine_->input(static_cast<int>(c));
        for (int i0 = 0; i0 < local_.n0; ++i0)
          std::fill_n(grid.data() + padded.index(i0, 0), local_.n1, 0.0);
      }
      region_dirty_ = false;
    }
    map_sites(*sites);
    region_dirty_ = true;  // until the sites are cleared below (a throw in between leaves it so)
    for (std::size_t c = 0; c < ncomp_; ++c) {
      double* grid = engine_->input(static_cast<int>(c)).data();
      const double* src = in.data() + c * n;
      for (std::size_t j = 0; j < n; ++j)
        grid[positions_[j]] = src[j];
    }
  } else {
    for (std::size_t c = 0; c < ncomp_; ++c) {
      auto grid = engine_->input(static_cast<int>(c));
      for (int i0 = 0; i0 < local_.n0; ++i0) {
        std::copy_n(in.data() + c * n + local_.index(i0, 0), local_.n1,
                    grid.data() + padded.index(i0, 0));
      }
    }
    region_dirty_ = true;
  }
  transform(per_q);
  for (std::size_t c = 0; c < ncomp_; ++c) {
    const double* grid = engine_->output(static_cast<int>(c)).data();
    double* dst = out.data() + c * n;
    if (sites) {
      double* input = engine_->input(static_cast<int>(c)).data();
      for (std::size_t j = 0; j < n; ++j) {
        dst[j] = grid[positions_[j]];
        input[positions_[j]] = 0.0;
      }
    } else {
      for (int i0 = 0; i0 < local_.n0; ++i0)
        std::copy_n(grid + padded.index(i0, 0), local_.n1, dst + local_.index(i0, 0));
    }
  }
  if (sites) region_dirty_ = false;  // every written site is zero again
}

void FreeSurfaceGF::apply(std::span<const double> f, std::span<double> u) {
  check_size(f, size(), "FreeSurfaceGF::apply (forces)");
  check_size(u, size(), "FreeSurfaceGF::apply (displacements)");
  apply_on(nullptr, f, u);
}

void FreeSurfaceGF::apply(std::span<const std::size_t> sites, std::span<const double> f,
                          std::span<double> u) {
  check_size(f, ncomp_ * sites.size(), "FreeSurfaceGF::apply (forces on the sites)");
  check_size(u, ncomp_ * sites.size(), "FreeSurfaceGF::apply (displacements on the sites)");
  apply_on(&sites, f, u);
}

void FreeSurfaceGF::apply_on(const std::span<const std::size_t>* sites, std::span<const double> f,
                             std::span<double> u) {
  if (components_ == Components::in_plane) {  // the slides' case, without multiply()'s branches
    const double *kxx = kxx_.data(), *kxy = kxy_.data(), *kyy = kyy_.data();
    convolve(sites, f, u,
             [kxx, kxy, kyy](const fft::FourierBlock& b, std::size_t q, std::size_t at) {
               symmetric_product(b, at, kxx[q], kxy[q], kyy[q]);
             });
  } else {
    convolve(sites, f, u, [this](const fft::FourierBlock& b, std::size_t q, std::size_t at) {
      multiply(b, q, at);
    });
  }
  ++applications_;
}

void FreeSurfaceGF::apply_filter(std::span<const double> f, std::span<double> w, double c) {
  check_size(f, size(), "FreeSurfaceGF::apply_filter (forces)");
  check_size(w, size(), "FreeSurfaceGF::apply_filter (output)");
  filter_on(nullptr, f, w, c);
}

void FreeSurfaceGF::apply_filter(std::span<const std::size_t> sites, std::span<const double> f,
                                 std::span<double> w, double c) {
  check_size(f, ncomp_ * sites.size(), "FreeSurfaceGF::apply_filter (forces on the sites)");
  check_size(w, ncomp_ * sites.size(), "FreeSurfaceGF::apply_filter (output on the sites)");
  filter_on(&sites, f, w, c);
}

void FreeSurfaceGF::filter_on(const std::span<const std::size_t>* sites, std::span<const double> f,
                              std::span<double> w, double c) {
  if (components_ != Components::in_plane) {
    throw std::invalid_argument("FreeSurfaceGF::apply_filter: in-plane components only");
  }
  if (!(c >= 0.0) || !std::isfinite(c)) {
    throw std::invalid_argument("FreeSurfaceGF::apply_filter: stiffness c = " + std::to_string(c) +
                                ", must be finite and >= 0");
  }
  if (c != filter_c_) {
    // The kernels carry the FFT normalisation s: G(q) = k(q) / s, and the multiplier is
    // s (I + c G(q))^-1 (2 x 2, real symmetric per q). G(q) of the padded grid is the DFT of
    // the truncated real-space kernel. Its eigenvalues are expected to be positive (the unit
    // test sees M's Rayleigh quotients in (0, 1], up to c = 300); a wave vector where the
    // truncation made I + c G indefinite would be passed through unfiltered, which keeps the
    // filter positive definite whatever happens.
    const double s = engine_->normalisation();
    const std::size_t nq = kxx_.size();
    mxx_.resize(nq), mxy_.resize(nq), myy_.resize(nq);
    for (std::size_t q = 0; q < nq; ++q) {
      const double axx = 1.0 + c * kxx_[q] / s, axy = c * kxy_[q] / s, ayy = 1.0 + c * kyy_[q] / s;
      const double det = axx * ayy - axy * axy;
      if (!(axx > 0.0 && det > 0.0)) {
        mxx_[q] = myy_[q] = s;
        mxy_[q] = 0.0;
        continue;
      }
      const double scale = s / det;
      mxx_[q] = scale * ayy;
      mxy_[q] = -scale * axy;
      myy_[q] = scale * axx;
    }
    filter_c_ = c;
  }
  const double *mxx = mxx_.data(), *mxy = mxy_.data(), *myy = myy_.data();
  convolve(sites, f, w, [mxx, mxy, myy](const fft::FourierBlock& b, std::size_t q, std::size_t at) {
    symmetric_product(b, at, mxx[q], mxy[q], myy[q]);
  });
  ++filter_applications_;
}

void FreeSurfaceGF::multiply(const fft::FourierBlock& b, std::size_t q, std::size_t at) const {
  if (components_ == Components::normal) {
    b.field[0][at] *= kzz_[q];
    return;
  }
  const std::complex<double> fx = b.field[0][at], fy = b.field[1][at];
  symmetric_product(b, at, kxx_[q], kxy_[q], kyy_[q]);
  if (components_ == Components::full) {
    const std::complex<double> fz = b.field[2][at];
    b.field[2][at] = kzz_[q] * fz;
    if (!sx_.empty()) {
      const std::complex<double> i{0.0, 1.0};
      b.field[0][at] += i * sx_[q] * fz;
      b.field[1][at] += i * sy_[q] * fz;
      b.field[2][at] -= i * (sx_[q] * fx + sy_[q] * fy);
    }
  }
}

// ---------------------------------------------------------------------------------------------
void periodic_compliance_block(const Material& material, Components components, double q0,
                               double q1, double d, int alias_images,
                               std::span<std::complex<double>> out) {
  const int nc = component_count(components);
  if (out.size() != static_cast<std::size_t>(nc * nc)) {
    throw std::invalid_argument("periodic_compliance_block: output of " +
                                std::to_string(out.size()) + " entries; need " +
                                std::to_string(nc * nc));
  }
  int axis[3] = {0, 0, 0};
  for (int k = 0; k < nc; ++k)
    axis[k] = component_axis(components, k);
  std::fill(out.begin(), out.end(), std::complex<double>{});
  std::complex<double> tensor[3][3];
  const double two_pi = 2.0 * std::numbers::pi;
  // The image sum runs over the 2M+1 Brillouin zones around q = 0 in each direction, with half
  // weight on the zone boundary so that the truncation stays symmetric in q (q = pi/d included).
  const double limit = (2 * alias_images + 1) * std::numbers::pi / d;
  const auto window = [limit](double Q) {
    const double excess = std::abs(Q) - limit;
    if (std::abs(excess) < 1e-9 * limit) return 0.5;
    return excess < 0.0 ? 1.0 : 0.0;
  };
  for (int a = -alias_images - 1; a <= alias_images + 1; ++a) {
    const double Q0 = q0 + two_pi * a / d;
    const double w0 = window(Q0);
    if (w0 == 0.0) continue;
    const double s0 = w0 * sinc(0.5 * Q0 * d);
    for (int b = -alias_images - 1; b <= alias_images + 1; ++b) {
      const double Q1 = q1 + two_pi * b / d;
      const double w1 = window(Q1);
      if (w1 == 0.0) continue;
      const double s = s0 * w1 * sinc(0.5 * Q1 * d) / (d * d);
      fourier_gf_tensor(material, Q0, Q1, tensor);
      for (int k = 0; k < nc; ++k) {
        for (int l = 0; l < nc; ++l)
          out[static_cast<std::size_t>(k * nc + l)] += s * tensor[axis[k]][axis[l]];
      }
    }
  }
}

PeriodicSurfaceGF::PeriodicSurfaceGF(const Material& material, Components components, Shape2 cell,
                                     double d, const fft::FFTOptions& fft, int alias_images,
                                     const fft::EngineFactory& engine)
    : material_(material),
      components_(components),
      cell_(cell),
      local_(cell),
      d_(d),
      ncomp_(static_cast<std::size_t>(component_count(components))) {
  check_common(material, cell, d, "PeriodicSurfaceGF");
  if (cell.n0 < 2 || cell.n1 < 2) {
    throw std::invalid_argument("PeriodicSurfaceGF: cell of " + std::to_string(cell.n0) + " x " +
                                std::to_string(cell.n1) + " sites; allowed: at least 2 x 2");
  }
  if (alias_images < 1 || alias_images > 1000) {
    throw std::invalid_argument("PeriodicSurfaceGF: alias_images: got " +
                                std::to_string(alias_images) + ", allowed: 1 to 1000");
  }
  engine_ = engine ? engine(cell, ncomp(), fft, 0) : fft::make_engine(cell, ncomp(), fft);
  const fft::Layout layout = engine_->layout();
  local_begin_ = layout.row_begin;
  local_.n0 = layout.rows;
  const Shape2 fs = engine_->fourier_shape();
  const std::size_t block = ncomp_ * ncomp_;
  // The wave vectors held here: the whole half-grid, row-major; a distributed engine's columns
  // [k1_begin, k1_begin + k1_count) for every k0, stored k1-major (fft_engine.hpp: Layout),
  // which is also the order its convolve() visits them.
  const std::size_t held =
      static_cast<std::size_t>(fs.n0) * static_cast<std::size_t>(layout.k1_count);
  const auto slot = [&](int k0, int k1) {
    return layout.fourier_transposed
               ? static_cast<std::size_t>(k1 - layout.k1_begin) * static_cast<std::size_t>(fs.n0) +
                     static_cast<std::size_t>(k0)
               : fs.index(k0, k1);
  };
  compliance_.assign(held * block, {});
  stiffness_.assign(held * block, {});
  const double two_pi = 2.0 * std::numbers::pi;
  const double scale = engine_->normalisation();
  using Block = Eigen::Matrix<std::complex<double>, Eigen::Dynamic, Eigen::Dynamic>;
  Block g(ncomp(), ncomp());
  std::vector<std::complex<double>> gq(block);
  for (int k0 = 0; k0 < fs.n0; ++k0) {
    const int m0 = k0 <= cell.n0 / 2 ? k0 : k0 - cell.n0;
    const double q0 = two_pi * m0 / (cell.n0 * d);
    for (int k1 = layout.k1_begin; k1 < layout.k1_begin + layout.k1_count; ++k1) {
      const double q1 = two_pi * k1 / (cell.n1 * d);
      if (k0 == 0 && k1 == 0) continue;  // rigid shift: zero compliance and stiffness blocks
      periodic_compliance_block(material, components, q0, q1, d, alias_images, gq);
      for (std::size_t e = 0; e < block; ++e)
        g(static_cast<Eigen::Index>(e / ncomp_), static_cast<Eigen::Index>(e % ncomp_)) = gq[e];
      const std::size_t at = slot(k0, k1) * block;
      const Block kq = g.inverse();
      for (std::size_t e = 0; e < block; ++e) {
        compliance_[at + e] =
            g(static_cast<Eigen::Index>(e / ncomp_), static_cast<Eigen::Index>(e % ncomp_)) * scale;
        stiffness_[at + e] =
            kq(static_cast<Eigen::Index>(e / ncomp_), static_cast<Eigen::Index>(e % ncomp_)) *
            (engine_->normalisation() * engine_->normalisation() / scale);
      }
    }
  }
  // Read contiguously by convolve()'s blocks (fft::Engine::block_order); a distributed engine's
  // columns are in that order already.
  if (!layout.fourier_transposed) {
    const std::vector<std::size_t> order = engine_->block_order();
    compliance_ = fft::to_block_order(order, compliance_, block);
    stiffness_ = fft::to_block_order(order, stiffness_, block);
  }
}

void PeriodicSurfaceGF::multiply(std::span<const double> in, std::span<double> out,
                                 bool stiffness) {
  check_size(in, size(), "PeriodicSurfaceGF (input field)");
  check_size(out, size(), "PeriodicSurfaceGF (output field)");
  const std::size_t n = local_.count();
  for (std::size_t c = 0; c < ncomp_; ++c) {
    std::copy_n(in.data() + c * n, n, engine_->input(static_cast<int>(c)).data());
  }
  const std::vector<std::complex<double>>& kernel = stiffness ? stiffness_ : compliance_;
  const std::size_t nc = ncomp_;
  engine_->convolve([&kernel, nc](const fft::FourierBlock& b) {
    std::complex<double> v[fft::FourierBlock::max_fields];
    const std::size_t count = static_cast<std::size_t>(b.rows) * static_cast<std::size_t>(b.width);
    for (std::size_t at = 0; at < count; ++at) {
      const std::complex<double>* kq = kernel.data() + (b.offset + at) * nc * nc;  // block order
      for (std::size_t k = 0; k < nc; ++k)
        v[k] = b.field[k][at];
      for (std::size_t k = 0; k < nc; ++k) {
        std::complex<double> acc{};
        for (std::size_t l = 0; l < nc; ++l)
          acc += kq[k * nc + l] * v[l];
        b.field[k][at] = acc;
      }
    }
  });
  for (std::size_t c = 0; c < ncomp_; ++c) {
    std::copy_n(engine_->output(static_cast<int>(c)).data(), n, out.data() + c * n);
  }
  ++applications_;
}

void PeriodicSurfaceGF::apply(std::span<const double> f, std::span<double> u) {
  multiply(f, u, false);
}

void PeriodicSurfaceGF::apply_stiffness(std::span<const double> u, std::span<double> f) {
  multiply(u, f, true);
}

double elastic_energy(std::span<const double> f, std::span<const double> u) {
  assert(f.size() == u.size());
  double e = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
    e += f[i] * u[i];
  return 0.5 * e;
}

}  // namespace asperity::elastic
