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
