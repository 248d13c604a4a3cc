# All dependencies are Debian packages (scripts/setup.sh installs them). Config packages
# are preferred; FFTW ships only pkg-config files on Debian 12.
find_package(Eigen3 3.4 REQUIRED CONFIG)
find_package(Boost 1.74 REQUIRED CONFIG COMPONENTS graph)
find_package(SUNDIALS 6.4 REQUIRED CONFIG)
find_package(GTest REQUIRED CONFIG)
find_package(benchmark REQUIRED CONFIG)
find_package(CLI11 REQUIRED CONFIG)
find_package(tomlplusplus REQUIRED CONFIG)
find_package(nlohmann_json 3.10 REQUIRED CONFIG)
find_package(netCDF REQUIRED CONFIG)
find_package(spectra 1.0 REQUIRED CONFIG)
find_package(Threads REQUIRED)

find_package(PkgConfig REQUIRED)
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)
find_library(FFTW3_THREADS_LIBRARY NAMES fftw3_threads REQUIRED
             HINTS ${FFTW3_LIBRARY_DIRS})
add_library(asperity_fftw3 INTERFACE)
target_link_libraries(asperity_fftw3 INTERFACE ${FFTW3_THREADS_LIBRARY} PkgConfig::FFTW3
                                               Threads::Threads)

find_program(GNUPLOT_EXECUTABLE gnuplot REQUIRED)

# MPI and FFTW-MPI (issue 26): the distributed FFT backend (core/fft/fftw_mpi_engine.hpp),
# built where Debian's libopenmpi-dev and libfftw3-mpi-dev are installed (scripts/setup.sh
# installs them); without them the serial toolkit builds as before.
option(ASPERITY_MPI "Build the MPI backends (OpenMPI, FFTW-MPI) where they are found" ON)
set(ASPERITY_HAVE_MPI OFF)
if(ASPERITY_MPI)
  find_package(MPI COMPONENTS CXX)
  find_library(FFTW3_MPI_LIBRARY NAMES fftw3_mpi HINTS ${FFTW3_LIBRARY_DIRS})
  find_path(FFTW3_MPI_INCLUDE_DIR fftw3-mpi.h HINTS ${FFTW3_INCLUDE_DIRS})
  if(MPI_CXX_FOUND AND FFTW3_MPI_LIBRARY AND FFTW3_MPI_INCLUDE_DIR)
    set(ASPERITY_HAVE_MPI ON)
    add_library(asperity_fftw3_mpi INTERFACE)
    target_include_directories(asperity_fftw3_mpi INTERFACE ${FFTW3_MPI_INCLUDE_DIR})
    target_link_libraries(asperity_fftw3_mpi INTERFACE ${FFTW3_MPI_LIBRARY} asperity_fftw3
                                                       MPI::MPI_CXX)
    message(STATUS "asperity: MPI backends on (${MPIEXEC_EXECUTABLE})")
  else()
    message(STATUS "asperity: MPI or FFTW-MPI not found; the MPI backends are not built")
  endif()
endif()
