// FFTW-MPI backend of fft::Engine (fftw_mpi_engine.hpp). FFTW-MPI's r2c/c2r transforms need
// the real arrays padded to 2 (n1/2 + 1) values per row, out of place too; the engine keeps the
// unpadded rows the interface promises (input(), output(): rows x n1) and copies them into and
// out of padded buffers around the transforms, a pass over the local rows that costs a small
// fraction of the transforms and their all-to-all transposes.
#include "asperity/core/fft/fftw_mpi_engine.hpp"
#include "asperity/core/fft/fftw_common.hpp"
#include "asperity/core/fft/mpi_comm.hpp"

#include <fftw3-mpi.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>

namespace asperity::fft {

namespace {

// fftw_init_threads before fftw_mpi_init, once per process (FFTW's order).
void init_fftw_mpi() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (fftw_init_threads() == 0) throw std::runtime_error("fft: fftw_init_threads failed");
    fftw_mpi_init();
  });
}

template <class T>
T* checked(T* p, std::size_t count) {
  if (p == nullptr && count > 0) throw std::runtime_error("fft: FFTW-MPI allocation failed");
  return p;
}

class FFTWMpiEngine final : public Engine {
 public:
  FFTWMpiEngine(MPI_Comm comm, Shape2 shape, int fields, int support, const FFTOptions& options)
      : Engine(shape, fields, support), comm_(comm) {
    init_fftw_mpi();
    MPI_Comm_size(comm_, &ranks_);
    MPI_Comm_rank(comm_, &rank_);
    const ptrdiff_t n0 = shape.n0, n1 = shape.n1, h = shape.n1 / 2 + 1;
    ptrdiff_t local_n0 = 0, local_0_start = 0, local_n1 = 0, local_1_start = 0;
    const ptrdiff_t alloc = fftw_mpi_local_size_2d_transposed(
        n0, h, comm_, &local_n0, &local_0_start, &local_n1, &local_1_start);
    rows_ = static_cast<int>(local_n0);
    row_begin_ = static_cast<int>(local_0_start);
    k1_count_ = static_cast<int>(local_n1);
    k1_begin_ = static_cast<int>(local_1_start);
    // At least one value each: FFTW's allocator may return null for 0.
    const std::size_t complex_count = static_cast<std::size_t>(std::max<ptrdiff_t>(alloc, 1));
    const std::size_t real_rows =
        std::max<std::size_t>(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(n1), 1);
    try {
      for (int f = 0; f < fields; ++f) {
        input_.push_back(checked(fftw_alloc_real(real_rows), real_rows));
        output_.push_back(checked(fftw_alloc_real(real_rows), real_rows));
        fourier_.push_back(reinterpret_cast<std::complex<double>*>(
            checked(fftw_alloc_complex(complex_count), complex_count)));
        padded_.push_back(checked(fftw_alloc_real(2 * complex_count), 2 * complex_count));
        std::memset(input_.back(), 0, real_rows * sizeof(double));
      }
      // Plans for the first field's buffers, executed on every field's (new-array execute:
      // the buffers come from one allocator and have its alignment).
      fftw_plan_with_nthreads(options.threads);
      const unsigned flags = detail::planner_flag(options.planner);
      r2c_ = fftw_mpi_plan_dft_r2c_2d(n0, n1, padded_[0], detail::as_fftw(fourier_[0]), comm_,
                                      flags | FFTW_MPI_TRANSPOSED_OUT);
      c2r_ = fftw_mpi_plan_dft_c2r_2d(n0, n1, detail::as_fftw(fourier_[0]), padded_[0], comm_,
                                      flags | FFTW_MPI_TRANSPOSED_IN);
      if (r2c_ == nullptr || c2r_ == nullptr)
        throw std::runtime_error("fft: FFTW-MPI could not plan a " + std::to_string(n0) + " x " +
                                 std::to_string(n1) + " transform");
    } catch (...) {
      release();
      throw;
    }
  }
  ~FFTWMpiEngine() override { release(); }

  void forward() override {
    const std::size_t n1 = static_cast<std::size_t>(real_shape().n1), stride = 2 * (n1 / 2 + 1);
    for (int f = 0; f < fields(); ++f) {
      for (int r = 0; r < rows_; ++r)
        std::copy_n(input_[f] + r * n1, n1, padded_[f] + r * stride);
      fftw_mpi_execute_dft_r2c(r2c_, padded_[f], detail::as_fftw(fourier_[f]));
    }
  }

  void inverse() override {
    const std::size_t n1 = static_cast<std::size_t>(real_shape().n1), stride = 2 * (n1 / 2 + 1);
    for (int f = 0; f < fields(); ++f) {
      fftw_mpi_execute_dft_c2r(c2r_, detail::as_fftw(fourier_[f]), padded_[f]);
      for (int r = 0; r < rows_; ++r)
        std::copy_n(padded_[f] + r * stride, n1, output_[f] + r * n1);
    }
  }

  // One block per local Fourier column: its n0 wave vectors are contiguous (k1-major), a block
  // of width 1 in FourierBlock's terms.
  void convolve(const Multiplier& multiplier) override {
    forward();
    const int n0 = real_shape().n0;
    for (int j = 0; j < k1_count_; ++j) {
      FourierBlock b;
      b.k1_begin = k1_begin_ + j;
      b.width = 1;
      b.rows = n0;
      b.offset = static_cast<std::size_t>(j) * static_cast<std::size_t>(n0);
      for (int f = 0; f < fields(); ++f)
        b.field[f] = fourier_[f] + b.offset;
      multiplier(b);
    }
    inverse();
  }

  [[nodiscard]] std::vector<std::size_t> block_order() const override {
    const std::size_t n0 = static_cast<std::size_t>(real_shape().n0);
    const std::size_t h = static_cast<std::size_t>(fourier_shape().n1);
    std::vector<std::size_t> order;
    order.reserve(n0 * static_cast<std::size_t>(k1_count_));
    for (int j = 0; j < k1_count_; ++j) {
      for (std::size_t k0 = 0; k0 < n0; ++k0)
        order.push_back(k0 * h + static_cast<std::size_t>(k1_begin_ + j));
    }
    return order;
  }
  [[nodiscard]] std::string backend() const override {
    return "fftw-mpi (" + std::to_string(ranks_) + " ranks)";
  }
  [[nodiscard]] Layout layout() const override {
    return {.global = real_shape(),
            .ranks = ranks_,
            .rank = rank_,
            .row_begin = row_begin_,
            .rows = rows_,
            .k1_begin = k1_begin_,
            .k1_count = k1_count_,
            .fourier_transposed = true};
  }
  [[nodiscard]] const par::Comm& comm() const override { return procs_; }

 private:
  void release() {
    if (r2c_) fftw_destroy_plan(r2c_);
    if (c2r_) fftw_destroy_plan(c2r_);
    r2c_ = c2r_ = nullptr;
    detail::free_buffers(input_);
    detail::free_buffers(output_);
    detail::free_buffers(padded_);
    detail::free_buffers(fourier_);
  }

  MPI_Comm comm_;
  par::MpiComm procs_{comm_};  // the same processes as a par::Comm
  int ranks_ = 1, rank_ = 0;
  int row_begin_ = 0, rows_ = 0, k1_begin_ = 0, k1_count_ = 0;
  std::vector<double*> padded_;  // per field: the local rows padded to 2 (n1/2 + 1) values
  fftw_plan r2c_ = nullptr, c2r_ = nullptr;
};

}  // namespace

std::unique_ptr<Engine> make_mpi_engine(MPI_Comm comm, Shape2 shape, int fields,
                                        const FFTOptions& options, int support_rows) {
  detail::check_engine_arguments("fft::make_mpi_engine", shape, fields, options, support_rows);
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) throw std::invalid_argument("fft::make_mpi_engine: MPI is not initialised");
  return std::make_unique<FFTWMpiEngine>(comm, shape, fields, shape.n0, options);
}

EngineFactory mpi_engine_factory(MPI_Comm comm) {
  return [comm](Shape2 shape, int fields, const FFTOptions& options, int support_rows) {
    return make_mpi_engine(comm, shape, fields, options, support_rows);
  };
}

}  // namespace asperity::fft
