// FFTW3 backend of fft::Engine. The planner is not thread-safe, so planning (and thread
// initialisation) is serialised behind one mutex; execution of existing plans is re-entrant.
#include <fftw3.h>

#include <algorithm>
#include <mutex>
#include <stdexcept>

#include "fft/fft_engine.hpp"

namespace asperity::fft {

namespace {

std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

unsigned planner_flag(Planner p) {
  switch (p) {
    case Planner::estimate:
      return FFTW_ESTIMATE;
    case Planner::measure:
      return FFTW_MEASURE;
    case Planner::patient:
      return FFTW_PATIENT;
  }
  return FFTW_ESTIMATE;
}

class FFTWEngine final : public Engine {
 public:
  FFTWEngine(Shape2 shape, int fields, const FFTOptions& options) : Engine(shape, fields) {
    const std::size_t nreal = shape.count() * static_cast<std::size_t>(fields);
    const std::size_t ncomplex = fourier_shape().count() * static_cast<std::size_t>(fields);
    input_ = fftw_alloc_real(nreal);
    output_ = fftw_alloc_real(nreal);
    fourier_ = reinterpret_cast<std::complex<double>*>(fftw_alloc_complex(ncomplex));
    if (input_ == nullptr || output_ == nullptr || fourier_ == nullptr) {
      free_buffers();
      throw std::runtime_error("fft: cannot allocate buffers for a " + std::to_string(shape.n0) +
                               " x " + std::to_string(shape.n1) + " grid");
    }
    std::lock_guard<std::mutex> lock(planner_mutex());
    static const bool threads_ok = fftw_init_threads() != 0;
    if (!threads_ok && options.threads > 1) {
      free_buffers();
      throw std::runtime_error("fft: FFTW thread support could not be initialised");
    }
    fftw_plan_with_nthreads(options.threads);
    const int n[2] = {shape.n0, shape.n1};
    const int real_dist = static_cast<int>(shape.count());
    const int complex_dist = static_cast<int>(fourier_shape().count());
    // MEASURE and PATIENT overwrite the arrays while planning: buffers are zeroed after.
    const unsigned flags = planner_flag(options.planner);
    auto* fc = reinterpret_cast<fftw_complex*>(fourier_);
    forward_ = fftw_plan_many_dft_r2c(2, n, fields, input_, nullptr, 1, real_dist, fc, nullptr, 1,
                                      complex_dist, flags);
    inverse_ = fftw_plan_many_dft_c2r(2, n, fields, fc, nullptr, 1, complex_dist, output_, nullptr,
                                      1, real_dist, flags);
    if (forward_ == nullptr || inverse_ == nullptr) {
      destroy_plans();
      free_buffers();
      throw std::runtime_error("fft: FFTW could not plan the transforms");
    }
    std::fill(input_, input_ + nreal, 0.0);
    std::fill(output_, output_ + nreal, 0.0);
    std::fill(fourier_, fourier_ + ncomplex, std::complex<double>{});
  }

  ~FFTWEngine() override {
    {
      std::lock_guard<std::mutex> lock(planner_mutex());
      destroy_plans();
    }
    free_buffers();
  }

  void forward() override { fftw_execute(forward_); }
  void inverse() override { fftw_execute(inverse_); }
  [[nodiscard]] std::string backend() const override { return "fftw3"; }

 private:
  // Caller holds planner_mutex().
  void destroy_plans() {
    if (forward_ != nullptr) fftw_destroy_plan(forward_);
    if (inverse_ != nullptr) fftw_destroy_plan(inverse_);
    forward_ = inverse_ = nullptr;
  }

  void free_buffers() {
    fftw_free(input_);
    fftw_free(output_);
    fftw_free(fourier_);
    input_ = output_ = nullptr;
    fourier_ = nullptr;
  }

  fftw_plan forward_ = nullptr;
  fftw_plan inverse_ = nullptr;
};

}  // namespace

std::string to_string(Planner p) {
  switch (p) {
    case Planner::estimate:
      return "estimate";
    case Planner::measure:
      return "measure";
    case Planner::patient:
      return "patient";
  }
  return "estimate";
}

Planner planner_from_string(const std::string& name) {
  if (name == "estimate") return Planner::estimate;
  if (name == "measure") return Planner::measure;
  if (name == "patient") return Planner::patient;
  throw std::invalid_argument("fft planner: got '" + name +
                              "', allowed: estimate, measure, patient");
}

void FFTOptions::validate() const {
  if (threads < 1 || threads > 1024) {
    throw std::invalid_argument("FFTOptions.threads: got " + std::to_string(threads) +
                                ", allowed: 1 to 1024");
  }
}

std::span<double> Engine::input(int field) {
  return {input_ + static_cast<std::size_t>(field) * shape_.count(), shape_.count()};
}
std::span<std::complex<double>> Engine::fourier(int field) {
  const std::size_t n = fourier_shape().count();
  return {fourier_ + static_cast<std::size_t>(field) * n, n};
}
std::span<double> Engine::output(int field) {
  return {output_ + static_cast<std::size_t>(field) * shape_.count(), shape_.count()};
}

std::unique_ptr<Engine> make_engine(Shape2 shape, int fields, const FFTOptions& options) {
  options.validate();
  if (shape.n0 < 1 || shape.n1 < 2 || fields < 1) {
    throw std::invalid_argument("fft::make_engine: need n0 >= 1, n1 >= 2, fields >= 1; got " +
                                std::to_string(shape.n0) + " x " + std::to_string(shape.n1) +
                                ", fields " + std::to_string(fields));
  }
  return std::make_unique<FFTWEngine>(shape, fields, options);
}

}  // namespace asperity::fft
