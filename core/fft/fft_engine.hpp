// A small real-to-complex 2D FFT interface. Physics code sees only this header; the FFTW
// backend lives in fftw_engine.cpp, and a distributed (MPI) backend can be added behind the
// same interface (cf. muGrid's fft_backend).
//
// Conventions: forward is X(q) = sum_x x(x) exp(-i q.x) (FFTW_FORWARD); inverse is the
// unnormalised sum with exp(+i q.x), so inverse(forward(x)) = normalisation()^-1 x.
// The Fourier half-grid has shape n0 x (n1/2 + 1) (FFTW's r2c layout).
#pragma once

#include <complex>
#include <memory>
#include <span>
#include <string>

#include "common/shape.hpp"

namespace asperity::fft {

enum class Planner {
  estimate,  // heuristic plans: instant, a little slower to execute
  measure,   // time candidate plans once (seconds for large grids), fastest execution
  patient,   // longer search; only worth it for very long runs
};

std::string to_string(Planner p);
Planner planner_from_string(const std::string& name);  // throws std::invalid_argument

struct FFTOptions {
  int threads = 1;                      // threads used inside each transform, >= 1
  Planner planner = Planner::estimate;  // planning effort, see Planner

  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
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
  [[nodiscard]] virtual std::string backend() const = 0;

 protected:
  Engine(Shape2 shape, int fields) : shape_(shape), fields_(fields) {}
  double* input_ = nullptr;
  std::complex<double>* fourier_ = nullptr;
  double* output_ = nullptr;

 private:
  Shape2 shape_;
  int fields_;
};

// FFTW3 backend (threads as requested). Throws std::invalid_argument on a bad shape or
// options, std::runtime_error if FFTW cannot plan.
std::unique_ptr<Engine> make_engine(Shape2 shape, int fields, const FFTOptions& options = {});

}  // namespace asperity::fft
