// What the FFTW backends share (fftw_engine.cpp, fftw_mpi_engine.cpp); not a public header.
#pragma once

#include <fftw3.h>

#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#include "asperity/core/fft/fft_engine.hpp"

namespace asperity::fft::detail {

inline unsigned planner_flag(Planner p) {
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

// std::complex<double> and fftw_complex share their layout (FFTW's documented guarantee).
inline fftw_complex* as_fftw(std::complex<double>* p) {
  return reinterpret_cast<fftw_complex*>(p);
}

// Frees buffers from fftw_alloc_* and empties the list.
template <class T>
void free_buffers(std::vector<T*>& buffers) {
  for (T* p : buffers)
    fftw_free(p);
  buffers.clear();
}

// The arguments every engine factory takes; throws std::invalid_argument naming `who` and the
// violated constraint.
inline void check_engine_arguments(const char* who, Shape2 shape, int fields,
                                   const FFTOptions& options, int support_rows) {
  options.validate();
  if (shape.n0 < 1 || shape.n1 < 2 || fields < 1 || fields > FourierBlock::max_fields) {
    throw std::invalid_argument(std::string(who) + ": need n0 >= 1, n1 >= 2, 1 to " +
                                std::to_string(FourierBlock::max_fields) + " fields; got " +
                                std::to_string(shape.n0) + " x " + std::to_string(shape.n1) +
                                ", fields " + std::to_string(fields));
  }
  if (support_rows < 0 || support_rows > shape.n0) {
    throw std::invalid_argument(std::string(who) + ": support_rows: got " +
                                std::to_string(support_rows) + ", allowed: 0 to " +
                                std::to_string(shape.n0));
  }
}

}  // namespace asperity::fft::detail
