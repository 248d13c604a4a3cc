// A small real-to-complex 2D FFT interface. Physics code sees only this header; the FFTW
// backend lives in fftw_engine.cpp, and a distributed (MPI) backend can be added behind the
// same interface (cf. muGrid's fft_backend).
//
// Conventions: forward is X(q) = sum_x x(x) exp(-i q.x) (FFTW_FORWARD); inverse is the
// unnormalised sum with exp(+i q.x), so inverse(forward(x)) = normalisation()^-1 x.
// The Fourier half-grid has shape n0 x (n1/2 + 1) (FFTW's r2c layout).
#pragma once

#include <complex>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "asperity/core/common/comm.hpp"
#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/shape.hpp"

namespace asperity::fft {

// measure and patient choose among plans by timing them, so the plan (and the round-off of the
// results) can differ from one run to the next; estimate repeats bit for bit.
enum class Planner {
  estimate,  // heuristic plans: instant, a little slower to execute
  measure,   // time candidate plans once (seconds for large grids), fastest execution
  patient,   // longer search; only worth it for very long runs
};

std::string to_string(Planner p);
Planner planner_from_string(const std::string& name);  // throws std::invalid_argument

struct FFTOptions {
  int threads = 1;                      // threads used inside each transform, 1 to 1024
  Planner planner = Planner::estimate;  // planning effort, see Planner

  // The settings (keys "threads", "planner"): common/settings.hpp.
  static const settings::Table<FFTOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

// A block of columns of the Fourier half-grid, handed to a Fourier-space multiplier during
// Engine::convolve: wave vector (k0, k1_begin + j) of field f is field[f][k0 * width + j],
// for k0 < rows and j < width.
// offset: where the block starts in Engine::block_order(), so that a multiplier whose
// coefficients are stored in that order finds the one of entry (k0, j) at offset + k0 * width + j.
struct FourierBlock {
  static constexpr int max_fields = 3;
  int k1_begin = 0;
  int width = 0;
  int rows = 0;
  std::size_t offset = 0;
  std::complex<double>* field[max_fields] = {};
};
// Multiplies a block in place. It may be called concurrently on different blocks, and must not
// throw (the workers of a convolution wait for each other).
using Multiplier = std::function<void(const FourierBlock&)>;

// Which part of an engine's grids this process holds (issue 24; the distributed backend of
// issue 26 fills it in). The serial engine holds everything. A slab-decomposed engine (FFTW-MPI)
// holds real-space rows [row_begin, row_begin + rows) of the global grid and, with its output
// transposed, Fourier columns [k1_begin, k1_begin + k1_count) of the half-grid for every k0:
// the pointwise multiply of a convolution then needs no transpose back.
struct Layout {
  Shape2 global;  // the real grid of every process together
  int ranks = 1, rank = 0;
  int row_begin = 0, rows = 0;      // real-space rows held here (of global.n0)
  int k1_begin = 0, k1_count = 0;   // Fourier columns held here (of global.n1 / 2 + 1)
  bool fourier_transposed = false;  // Fourier data stored k1-major (FFTW_MPI_TRANSPOSED_OUT)
  [[nodiscard]] bool whole() const { return ranks == 1; }
};

// Batched transforms of `fields` real 2D arrays of one shape. The engine owns three aligned
// buffers per field: an input grid (kept between calls, so zero padding is written once), the
// Fourier half-grid, and an output grid. Plans are made once, in the constructor.
class Engine {
 public:
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  [[nodiscard]] Shape2 real_shape() const { return shape_; }
  [[nodiscard]] Shape2 fourier_shape() const { return Shape2{shape_.n0, shape_.n1 / 2 + 1}; }
  [[nodiscard]] int fields() const { return fields_; }
  [[nodiscard]] double normalisation() const { return 1.0 / static_cast<double>(shape_.count()); }

  std::span<double> input(int field);
  std::span<std::complex<double>> fourier(int field);
  std::span<double> output(int field);

  virtual void forward() = 0;  // input -> fourier, every field
  virtual void inverse() = 0;  // fourier -> output, every field; overwrites fourier

  // output = inverse(M(forward(input))) for every field, for an input that vanishes outside
  // rows [0, support_rows()); only output rows [0, support_rows()) are computed, the rest of
  // the output is unspecified. This is the whole of a zero-padded (Hockney) convolution: the
  // backend may skip the transforms of rows known to be zero or not needed, and apply M to
  // blocks of columns while they are in cache, instead of in a separate pass over memory.
  // Uses (and overwrites) the fourier buffers.
  virtual void convolve(const Multiplier& multiplier) = 0;
  [[nodiscard]] int support_rows() const { return support_rows_; }
  // The order in which convolve() hands out the half-grid: entry p is the row-major index
  // (k0 * (n1/2 + 1) + k1) of the p-th wave vector, block after block, each row by row.
  // Coefficients stored in this order are read contiguously; in row-major order a block's
  // entries lie a whole row apart, each on its own page (on a 2048^2 grid the products then
  // took a fifth of an L-BFGS iteration's CPU time).
  [[nodiscard]] virtual std::vector<std::size_t> block_order() const = 0;
  [[nodiscard]] virtual std::string backend() const = 0;

  // The part of the grids this process holds; the serial engine: all of it.
  [[nodiscard]] virtual Layout layout() const {
    return {.global = shape_,
            .row_begin = 0,
            .rows = shape_.n0,
            .k1_begin = 0,
            .k1_count = shape_.n1 / 2 + 1};
  }
  // The processes holding the parts of the grids (par::Comm: reductions, gathers, exchanges),
  // for the data a distributed engine's users move between them (FreeSurfaceGF's rows).
  // Serial: the one process.
  [[nodiscard]] virtual const par::Comm& comm() const { return par::serial(); }

 protected:
  Engine(Shape2 shape, int fields, int support_rows)
      : shape_(shape), fields_(fields), support_rows_(support_rows) {}
  // One allocation per field, so that every field has the alignment its plans were made for.
  std::vector<double*> input_, output_;
  std::vector<std::complex<double>*> fourier_;

 private:
  Shape2 shape_;
  int fields_;
  int support_rows_;
};

// A Fourier-space kernel with `per_q` values per wave vector, stored row-major over the
// half-grid, rearranged into a block order (entry p's values at p * per_q ...): `order` as
// returned by Engine::block_order(), computed once for all of an engine's kernels.
template <class T>
std::vector<T> to_block_order(const std::vector<std::size_t>& order, const std::vector<T>& natural,
                              std::size_t per_q = 1) {
  if (natural.size() != order.size() * per_q) {
    throw std::invalid_argument("fft::to_block_order: " + std::to_string(natural.size()) +
                                " values for " + std::to_string(order.size()) +
                                " wave vectors of " + std::to_string(per_q));
  }
  std::vector<T> out(natural.size());
  for (std::size_t p = 0; p < order.size(); ++p) {
    for (std::size_t e = 0; e < per_q; ++e)
      out[p * per_q + e] = natural[order[p] * per_q + e];
  }
  return out;
}

// Makes the engine of a Green's function: the plug-in point of the FFT backends. Empty (the
// default wherever one is taken): make_engine, one process. fftw_mpi_engine.hpp's
// mpi_engine_factory(comm) distributes the grid over the ranks of a communicator.
using EngineFactory = std::function<std::unique_ptr<Engine>(
    Shape2 shape, int fields, const FFTOptions& options, int support_rows)>;

// FFTW3 backend (threads as requested). support_rows: rows of the input that may be non-zero
// in convolve() (0: all). At most FourierBlock::max_fields fields. Throws
// std::invalid_argument on a bad shape or options, std::runtime_error if FFTW cannot plan.
std::unique_ptr<Engine> make_engine(Shape2 shape, int fields, const FFTOptions& options = {},
                                    int support_rows = 0);

}  // namespace asperity::fft
