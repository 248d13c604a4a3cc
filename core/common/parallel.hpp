// Element-wise passes over long vectors on several threads.
//
// Only for work whose every element is computed by the same expression whatever the split:
// each thread takes one contiguous range, so the result is bit for bit that of one thread.
// Sums whose order sets their rounding (dot products, energies) stay serial with their callers:
// a changed order moves a minimiser's stopping point by the force tolerance, not by round-off
// (docs/benchmarks.md, "One iteration against the FFT floor").
//
// The threads are a small pool of workers that block between passes. OpenMP's default
// (workers spin for a while after a region) was measured first: the spinning worker competed
// with FFTW's threads for the two cores, and a 2048^2 iteration took 176.5 ms against 168 ms
// with OMP_WAIT_POLICY=passive, which a library cannot set (docs/benchmarks.md).
#pragma once

#include <algorithm>
#include <cstddef>

namespace asperity::par {

// Below this many elements per thread a pass stays on one thread: waking a worker costs some
// microseconds, a pass over 32 768 doubles about ten.
inline constexpr std::size_t min_per_thread = std::size_t{1} << 15;
inline constexpr int max_threads = 256;

// Threads a pass over n elements uses when `threads` are granted.
[[nodiscard]] inline int threads_for(std::size_t n, int threads) {
  const auto most = static_cast<int>(std::min<std::size_t>(n / min_per_thread, max_threads));
  return std::max(1, std::min(threads, most));
}

// job(context, k, t) for k = 0 .. t-1, k = 0 on the calling thread and the others on workers
// of the pool, returning when all are done. If the pool is running another caller's job, or
// this is called from inside a job, this caller runs every k itself (same ranges, same
// results). job must not throw (a throw terminates).
using Job = void (*)(void* context, int k, int t);
void run(int t, Job job, void* context) noexcept;

// Start of range k of t over [0, n): multiples of 8 elements (a cache line of doubles on
// 64-byte aligned data; at worst the lines at the edges are shared, which costs time, not
// correctness).
[[nodiscard]] inline std::size_t range_start(std::size_t n, int k, int t) {
  return k >= t ? n : (n * static_cast<std::size_t>(k) / static_cast<std::size_t>(t)) / 8 * 8;
}

// f(k, begin, end) for the ranges k = 0 .. t-1 of [0, n), on t threads.
template <class F>
void run_ranges(std::size_t n, int t, F&& f) {
  auto body = [&](int k) noexcept { f(k, range_start(n, k, t), range_start(n, k + 1, t)); };
  run(
      t, [](void* c, int k, int) { (*static_cast<decltype(body)*>(c))(k); }, &body);
}

// f(begin, end) on contiguous ranges that cover [0, n), one per thread. f must not throw.
template <class F>
void for_ranges(std::size_t n, int threads, F&& f) {
  const int t = threads_for(n, threads);
  if (t <= 1) {
    f(std::size_t{0}, n);
    return;
  }
  run_ranges(n, t, [&](int, std::size_t b, std::size_t e) { f(b, e); });
}

// Largest value of g(begin, end) over the ranges of for_ranges (g returns its range's maximum):
// a maximum is exact whatever the order in which it is taken. A NaN anywhere is returned.
template <class G>
[[nodiscard]] double max_over_ranges(std::size_t n, int threads, G&& g) {
  const int t = threads_for(n, threads);
  if (t <= 1) return g(std::size_t{0}, n);
  double best[max_threads];
  run_ranges(n, t, [&](int k, std::size_t b, std::size_t e) { best[k] = g(b, e); });
  double m = best[0];
  for (int k = 1; k < t; ++k)
    if (best[k] > m || best[k] != best[k]) m = best[k];
  return m;
}

}  // namespace asperity::par
