// Grid shapes and the lattice patch that carries the unknowns.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace asperity {

// A 2D array shape, axis 0 slow (x), axis 1 fast (y): element (i0, i1) sits at i0 * n1 + i1.
struct Shape2 {
  int n0 = 0;
  int n1 = 0;

  [[nodiscard]] std::size_t count() const {
    return static_cast<std::size_t>(n0) * static_cast<std::size_t>(n1);
  }
  [[nodiscard]] std::size_t index(int i0, int i1) const {
    return static_cast<std::size_t>(i0) * static_cast<std::size_t>(n1) +
           static_cast<std::size_t>(i1);
  }
  bool operator==(const Shape2&) const = default;
};

// A rectangular block of surface lattice sites: site (i0, i1) of the block is the lattice
// site (origin0 + i0, origin1 + i1), i.e. at position ((origin0 + i0) d, (origin1 + i1) d).
struct LatticeBlock {
  Shape2 shape;     // number of sites along x and y
  int origin0 = 0;  // lattice index of the block's first site along x
  int origin1 = 0;  // lattice index of the block's first site along y

  // Smallest block holding every site with |X| <= radius (in units of d), centred on site (0,0).
  static LatticeBlock centred_disk(double radius_over_d);

  [[nodiscard]] double x(int i0, double d) const { return (origin0 + i0) * d; }
  [[nodiscard]] double y(int i1, double d) const { return (origin1 + i1) * d; }
};

// Smallest even n >= minimum whose prime factors are all in {2, 3, 5, 7} (1 for minimum <= 1):
// sizes FFTW handles with its fast codelets. Even, because a real-to-complex transform of odd
// length cannot be done as a complex one of half the length: with ESTIMATE plans (the slides'
// default) a zero-padded convolution costs about 1.5x per grid point at odd 7-smooth sizes
// (docs/benchmarks.md, "Padded grid sizes": 41 against 27 ns on average over 1000-1400), and
// where the least 7-smooth size is odd the least even one has 3% more points on average.
int next_fft_size(int minimum);
// Whether n >= 1 has no prime factor other than 2, 3, 5 and 7.
bool fft_smooth(int n);

}  // namespace asperity
