// Vector kernels of the minimisers of minimizer.hpp (internal to core/minimize): dot products,
// largest entries and element-wise passes over the pair representation of SOLVERS.md ("Free-
// boundary contact"), the passes on the threads of the problem (common/parallel.hpp: the same
// bits on any number of threads; the sums stay serial).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <span>

#include "asperity/core/common/parallel.hpp"

namespace asperity::minimize::detail {

// Vector kernels through Eigen maps: its reductions are vectorised and unrolled, which plain
// loops are not without reassociation (these passes are a fifth of a large slide's time).
inline Eigen::Map<const Eigen::VectorXd> view(std::span<const double> a) {
  return {a.data(), static_cast<Eigen::Index>(a.size())};
}
inline Eigen::Map<Eigen::VectorXd> view(std::span<double> a) {
  return {a.data(), static_cast<Eigen::Index>(a.size())};
}

inline double dot(std::span<const double> a, std::span<const double> b) {
  return view(a).dot(view(b));
}

// Threads for the element-wise passes of the minimisation running on this thread: set by
// minimize() from Problem::threads() for its duration (a thread of its own per caller, so
// minimisations on different threads do not share it). Dot products stay serial (par::).
inline thread_local int pass_threads = 1;

class PassThreads {
 public:
  explicit PassThreads(int threads) : saved_(pass_threads) { pass_threads = std::max(1, threads); }
  ~PassThreads() { pass_threads = saved_; }
  PassThreads(const PassThreads&) = delete;
  PassThreads& operator=(const PassThreads&) = delete;

 private:
  int saved_;
};

// f(i) for every i in [0, n), on the pass threads.
template <class F>
void each(std::size_t n, F&& f) {
  par::for_ranges(n, pass_threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      f(i);
  });
}

// Largest |a_i|; a NaN anywhere is returned (Eigen's default maximum keeps whichever operand
// its comparison favours, so a NaN would show or not depending on where the ranges split).
inline double max_abs(std::span<const double> a) {
  if (a.empty()) return 0.0;
  return par::max_over_ranges(a.size(), pass_threads, [&](std::size_t b, std::size_t e) {
    return view(a.subspan(b, e - b)).cwiseAbs().maxCoeff<Eigen::PropagateNaN>();
  });
}

// x = a + t b
inline void axpy_into(std::span<double> x, std::span<const double> a, double t,
                      std::span<const double> b) {
  par::for_ranges(x.size(), pass_threads, [&](std::size_t i, std::size_t e) {
    view(x.subspan(i, e - i)) = view(a.subspan(i, e - i)) + t * view(b.subspan(i, e - i));
  });
}

// x += t b
inline void axpy(std::span<double> x, double t, std::span<const double> b) {
  par::for_ranges(x.size(), pass_threads, [&](std::size_t i, std::size_t e) {
    view(x.subspan(i, e - i)) += t * view(b.subspan(i, e - i));
  });
}

// x *= t
inline void scale(std::span<double> x, double t) {
  par::for_ranges(x.size(), pass_threads,
                  [&](std::size_t i, std::size_t e) { view(x.subspan(i, e - i)) *= t; });
}

}  // namespace asperity::minimize::detail
