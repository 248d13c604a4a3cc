// Vector kernels of the minimisers of minimizer.hpp (internal to core/minimize): dot products,
// largest entries and element-wise passes over the pair representation of SOLVERS.md ("Free-
// boundary contact"), the passes on the threads of the problem (common/parallel.hpp: the same
// bits on any number of threads; the sums stay serial).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <span>
#include <vector>

#include "asperity/core/common/comm.hpp"
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

// How the sums of the minimisation running on this thread are made (set by minimize() from the
// problem for its duration, like pass_threads below): over the processes of Problem::comm(),
// and, where the problem has rows (Problem::runs()), row by row: the dot product of each run
// of every block (row-major over runs, then blocks) on its own, the partials then added in that
// order over every process (Comm::ordered_sum). Rows are never split between processes, so the
// sums, and with them the whole minimisation, are the same bits on any number of processes.
// Without runs: one dot product per process, reduced. Serial: the identity.
struct Reduction {
  const par::Comm* comm = nullptr;
  std::vector<std::size_t> runs;  // starts of the runs within a block, then its size
  std::size_t blocks = 1;
};
inline thread_local const Reduction* pass_reduction = nullptr;

inline double reduce_sum(double local) {
  return pass_reduction && pass_reduction->comm ? pass_reduction->comm->sum(local) : local;
}
inline double reduce_max(double local) {
  return pass_reduction && pass_reduction->comm ? pass_reduction->comm->max(local) : local;
}
inline bool reduce_any(bool local) {
  return pass_reduction && pass_reduction->comm ? pass_reduction->comm->any(local) : local;
}

class PassReduction {
 public:
  explicit PassReduction(const Reduction& r) : saved_(pass_reduction) { pass_reduction = &r; }
  ~PassReduction() { pass_reduction = saved_; }
  PassReduction(const PassReduction&) = delete;
  PassReduction& operator=(const PassReduction&) = delete;

 private:
  const Reduction* saved_;
};

inline double dot(std::span<const double> a, std::span<const double> b) {
  const Reduction* r = pass_reduction;
  // A process without rows has runs {0}: no partials, but it takes part in the sum.
  if (r == nullptr || r->runs.empty()) return reduce_sum(view(a).dot(view(b)));
  const std::size_t per = r->runs.back();
  assert(a.size() == r->blocks * per && b.size() == a.size());
  thread_local std::vector<double> partials;
  partials.clear();
  for (std::size_t k = 0; k + 1 < r->runs.size(); ++k) {
    const std::size_t begin = r->runs[k], len = r->runs[k + 1] - begin;
    for (std::size_t c = 0; c < r->blocks; ++c)
      partials.push_back(
          view(a.subspan(c * per + begin, len)).dot(view(b.subspan(c * per + begin, len))));
  }
  return (r->comm ? *r->comm : par::serial()).ordered_sum(partials);
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
  if (a.empty()) return reduce_max(0.0);
  return reduce_max(par::max_over_ranges(a.size(), pass_threads, [&](std::size_t b, std::size_t e) {
    return view(a.subspan(b, e - b)).cwiseAbs().maxCoeff<Eigen::PropagateNaN>();
  }));
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
