// The distributed FFT backend (issue 26): fft::Engine on FFTW-MPI, slab-decomposed over the
// ranks of a communicator. Built where MPI and FFTW-MPI are found (ASPERITY_HAVE_MPI; target
// asperity::fft_mpi), so the serial toolkit does not depend on MPI.
//
// Layout (fft_engine.hpp): rank r holds real-space rows [row_begin, row_begin + rows) of the
// global grid, row-major with n1 values per row (input() and output() hold those rows only),
// and, the r2c output transposed (FFTW_MPI_TRANSPOSED_OUT), the Fourier columns
// [k1_begin, k1_begin + k1_count) of the half-grid for every k0, stored k1-major: entry
// (k0, k1) at (k1 - k1_begin) * n0 + k0. The pointwise multiply of a convolution works on those
// columns as they are; the inverse takes them transposed (FFTW_MPI_TRANSPOSED_IN), so no
// transpose back is ever made. FFTW decides the slabs (blocks of ceil(n / ranks) rows or
// columns; the last ranks may hold fewer, or none).
//
// FFTW threads run inside each rank (FFTOptions::threads). The caller initialises MPI
// (MPI_Init_thread with MPI_THREAD_FUNNELED or more when threads > 1); every rank of the
// communicator constructs the engine and calls forward/inverse/convolve together (collective),
// and destroys it before MPI_Finalize (its plans hold a duplicate of the communicator).
#pragma once

#include <mpi.h>

#include <memory>

#include "asperity/core/fft/fft_engine.hpp"

namespace asperity::fft {

// Throws std::invalid_argument on a bad shape or options or if MPI is not initialised,
// std::runtime_error if FFTW cannot plan. support_rows is accepted as by make_engine() but not
// used yet: every row is transformed (the serial engine skips the zero rows of a padded grid).
std::unique_ptr<Engine> make_mpi_engine(MPI_Comm comm, Shape2 shape, int fields,
                                        const FFTOptions& options = {}, int support_rows = 0);
// make_mpi_engine on `comm`, as the factory a Green's function takes (elastic/surface_gf.hpp).
EngineFactory mpi_engine_factory(MPI_Comm comm);

}  // namespace asperity::fft
