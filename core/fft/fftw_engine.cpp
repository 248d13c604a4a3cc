// FFTW3 backend of fft::Engine. The planner is not thread-safe, so planning (and thread
// initialisation) is serialised behind one mutex; executing existing plans on new arrays is
// re-entrant, which convolve() uses to run column blocks on several threads.
//
// convolve() for a support of S of the n0 rows:
//   1. r2c along axis 1 of the S non-zero rows only (FFTW threads);
//   2. per block of B columns of the half-grid, on one of our threads: c2c along axis 0 into a
//      small scratch block (the zero rows S..n0-1 of the Fourier buffer are read, never
//      written), the multiplier, the inverse c2c in place, and rows 0..S-1 copied back;
//   3. c2r of rows 0..S-1 only.
// Against a plain 2D forward/inverse pair this skips half of the row transforms when S = n0/2
// and applies the multiplier while the block is in cache.
#include <fftw3.h>
#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <atomic>
#include <barrier>
#include <cassert>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "asperity/core/fft/fft_engine.hpp"
#include "asperity/core/fft/fftw_common.hpp"

namespace asperity::fft {

namespace {

std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

using detail::as_fftw;

// Columns per block in convolve(): even, so every block starts on the alignment of the buffer
// (plans made for one aligned block run on all); 8 columns of 1024 complex values per field
// stay within L2.
constexpr int block_width = 8;

class FFTWEngine final : public Engine {
 public:
  FFTWEngine(Shape2 shape, int fields, int support, const FFTOptions& options)
      : Engine(shape, fields, support), threads_(options.threads) {
    const Shape2 fs = fourier_shape();
    widths_[0] = std::min(block_width, fs.n1);
    widths_[1] = fs.n1 > block_width ? fs.n1 % block_width : 0;
    blocks_ = (fs.n1 + block_width - 1) / block_width;
    try {
      for (int f = 0; f < fields; ++f) {
        input_.push_back(checked(fftw_alloc_real(shape.count()), shape.count()));
        output_.push_back(checked(fftw_alloc_real(shape.count()), shape.count()));
        fourier_.push_back(reinterpret_cast<std::complex<double>*>(
            checked(fftw_alloc_complex(fs.count()), fs.count())));
      }
      const std::size_t scratch = static_cast<std::size_t>(fields) * fs.n0 * block_width;
      for (int t = 0; t < threads_; ++t) {
        scratch_.push_back(
            reinterpret_cast<std::complex<double>*>(checked(fftw_alloc_complex(scratch), scratch)));
      }
      std::lock_guard<std::mutex> lock(planner_mutex());
      make_plans(options);
    } catch (...) {
      destroy();
      throw;
    }
    if (workers_ > 1) {
      sync_ = std::make_unique<std::barrier<>>(workers_);
      try {
        for (int t = 1; t < workers_; ++t)
          pool_.emplace_back([this, t] { worker(t); });
      } catch (...) {  // e.g. a thread limit: release the started workers, plans and buffers
        stop_workers();
        destroy();
        throw;
      }
    }
    // MEASURE and PATIENT overwrite the arrays while planning: buffers are zeroed after.
    for (int f = 0; f < fields; ++f) {
      std::fill_n(input_[f], shape.count(), 0.0);
      std::fill_n(output_[f], shape.count(), 0.0);
      std::fill_n(fourier_[f], fs.count(), std::complex<double>{});
    }
  }

  ~FFTWEngine() override {
    stop_workers();
    destroy();
  }

  void forward() override {
    for (int f = 0; f < fields(); ++f)
      fftw_execute_dft_r2c(forward_, input_[f], as_fftw(fourier_[f]));
    fourier_rows_clean_ = false;
  }

  void inverse() override {
    for (int f = 0; f < fields(); ++f)
      fftw_execute_dft_c2r(inverse_, as_fftw(fourier_[f]), output_[f]);
    fourier_rows_clean_ = false;
  }

  void convolve(const Multiplier& multiplier) override {
    const Shape2 fs = fourier_shape();
    const int support = support_rows();
    if (!fourier_rows_clean_) {  // rows past the support must read as zero in step 2
      for (int f = 0; f < fields(); ++f) {
        std::fill(fourier_[f] + fs.index(support, 0), fourier_[f] + fs.count(),
                  std::complex<double>{});
      }
      fourier_rows_clean_ = true;
    }
    const int workers = workers_;
    if (workers <= 1) {
      convolve_part(0, 1, multiplier, nullptr);
      return;
    }
    // One parallel region per call on the engine's own workers (started once: spawning threads
    // per call cost more than the transforms of a small grid): rows, then column blocks, then
    // rows again, each phase split over the workers, with a barrier between phases and at the end.
    job_ = &multiplier;
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    convolve_part(0, workers, multiplier, sync_.get());
    sync_->arrive_and_wait();  // the workers are done with the buffers
  }

  [[nodiscard]] std::string backend() const override { return "fftw3"; }

  [[nodiscard]] std::vector<std::size_t> block_order() const override {
    const Shape2 fs = fourier_shape();
    std::vector<std::size_t> order;
    order.reserve(fs.count());
    for (int k1 = 0; k1 < fs.n1; k1 += block_width) {
      const int w = std::min(block_width, fs.n1 - k1);
      for (int k0 = 0; k0 < fs.n0; ++k0) {
        for (int j = 0; j < w; ++j)
          order.push_back(fs.index(k0, k1 + j));
      }
    }
    return order;
  }

 private:
  template <class T>
  static T* checked(T* p, std::size_t count) {
    if (p == nullptr) throw std::runtime_error("fft: cannot allocate transform buffers");
    advise_huge_pages(p, count * sizeof(T));
    return p;
  }

  // The column transforms and the products visit a block of a few columns on every row: on 4 KiB
  // pages each row is a page of its own (in whatever heap the buffer came from: the hint is
  // harmless there), and the TLB misses cost a large part of the column
  // pass on 2048^2 and 4096^2 grids. Transparent huge pages (2 MiB) are asked for where the
  // kernel grants them on request (THP "madvise" mode, Debian's default); a hint only.
  static void advise_huge_pages(void* p, std::size_t bytes) {
#ifdef __linux__
    const long size = sysconf(_SC_PAGESIZE);
    if (size <= 0) return;
    const auto page = static_cast<std::uintptr_t>(size);
    const auto begin = (reinterpret_cast<std::uintptr_t>(p) + page - 1) & ~(page - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(page - 1);
    if (end > begin && bytes >= (std::size_t{4} << 20)) {
      (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
    }
#else
    (void)p, (void)bytes;
#endif
  }

  // Caller holds planner_mutex().
  void make_plans(const FFTOptions& options) {
    static const bool threads_ok = fftw_init_threads() != 0;
    if (!threads_ok && options.threads > 1) {
      throw std::runtime_error("fft: FFTW thread support could not be initialised");
    }
    const unsigned flags = detail::planner_flag(options.planner);
    const Shape2 s = real_shape(), fs = fourier_shape();
    const int n[2] = {s.n0, s.n1};
    fftw_plan_with_nthreads(options.threads);
    forward_ = fftw_plan_dft_r2c(2, n, input_[0], as_fftw(fourier_[0]), flags);
    inverse_ = fftw_plan_dft_c2r(2, n, as_fftw(fourier_[0]), output_[0], flags);
    // The transforms of convolve() run one per thread, so each is single-threaded. Each worker
    // transforms a batch of consecutive rows: batch sizes are floor and ceil of support/workers.
    // A batch that does not start on the buffer's alignment needs an unaligned plan.
    fftw_plan_with_nthreads(1);
    const int support = support_rows();
    workers_ = std::min({threads_, blocks_, support});
    bool rows_aligned = true;
    for (int t = 0; t < workers_; ++t) {
      const std::size_t r0 = batch_start(t);
      rows_aligned =
          rows_aligned && fftw_alignment_of(input_[0] + s.index(static_cast<int>(r0), 0)) == 0 &&
          fftw_alignment_of(
              reinterpret_cast<double*>(fourier_[0] + fs.index(static_cast<int>(r0), 0))) == 0;
    }
    const unsigned row_flags = flags | (rows_aligned ? 0u : static_cast<unsigned>(FFTW_UNALIGNED));
    for (int k = 0; k < 2; ++k) {
      const int batch = support / workers_ + k;
      if (k == 1 && support % workers_ == 0) break;
      rows_forward_[k] = fftw_plan_many_dft_r2c(1, &n[1], batch, input_[0], nullptr, 1, s.n1,
                                                as_fftw(fourier_[0]), nullptr, 1, fs.n1, row_flags);
      rows_inverse_[k] = fftw_plan_many_dft_c2r(1, &n[1], batch, as_fftw(fourier_[0]), nullptr, 1,
                                                fs.n1, output_[0], nullptr, 1, s.n1, row_flags);
      if (rows_forward_[k] == nullptr || rows_inverse_[k] == nullptr) {
        throw std::runtime_error("fft: FFTW could not plan the row transforms");
      }
    }
    for (int k = 0; k < 2; ++k) {
      const int w = widths_[k];
      if (w == 0) continue;
      fftw_complex* scratch = as_fftw(scratch_[0]);
      columns_forward_[k] = fftw_plan_many_dft(1, &n[0], w, as_fftw(fourier_[0]), nullptr, fs.n1, 1,
                                               scratch, nullptr, w, 1, FFTW_FORWARD, flags);
      columns_inverse_[k] = fftw_plan_many_dft(1, &n[0], w, scratch, nullptr, w, 1, scratch,
                                               nullptr, w, 1, FFTW_BACKWARD, flags);
      if (columns_forward_[k] == nullptr || columns_inverse_[k] == nullptr) break;
    }
    const bool columns_ok =
        (columns_forward_[0] != nullptr && columns_inverse_[0] != nullptr) &&
        (widths_[1] == 0 || (columns_forward_[1] != nullptr && columns_inverse_[1] != nullptr));
    if (forward_ == nullptr || inverse_ == nullptr || !columns_ok) {
      throw std::runtime_error("fft: FFTW could not plan the transforms");
    }
  }

  // Worker t > 0: waits (futex, no spinning) for a new convolution, takes its share.
  void worker(int t) {
    unsigned seen = 0;
    for (;;) {
      generation_.wait(seen, std::memory_order_acquire);
      seen = generation_.load(std::memory_order_acquire);
      if (stopping_.load(std::memory_order_acquire)) return;
      convolve_part(t, workers_, *job_, sync_.get());
      sync_->arrive_and_wait();
    }
  }

  void stop_workers() {
    if (pool_.empty()) return;
    stopping_.store(true, std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    pool_.clear();  // joins
  }

  // First row of worker t's batch: batches of floor(S/W) rows, the first S mod W one longer.
  [[nodiscard]] int batch_start(int t) const {
    const int base = support_rows() / workers_, extra = support_rows() % workers_;
    return t * base + std::min(t, extra);
  }

  // Worker t of `workers`: its share of each phase of convolve().
  void convolve_part(int t, int workers, const Multiplier& multiplier, std::barrier<>* sync) {
    const Shape2 s = real_shape(), fs = fourier_shape();
    const int support = support_rows();
    const int r0 = batch_start(t);
    const int kind = t < support % workers ? 1 : 0;
    for (int f = 0; f < fields(); ++f) {
      fftw_execute_dft_r2c(rows_forward_[kind], input_[f] + s.index(r0, 0),
                           as_fftw(fourier_[f] + fs.index(r0, 0)));
    }
    if (sync != nullptr) sync->arrive_and_wait();
    for (int b = t; b < blocks_; b += workers)
      column_block(b, scratch_[t], multiplier);
    if (sync != nullptr) sync->arrive_and_wait();
    for (int f = 0; f < fields(); ++f) {
      fftw_execute_dft_c2r(rows_inverse_[kind], as_fftw(fourier_[f] + fs.index(r0, 0)),
                           output_[f] + s.index(r0, 0));
    }
  }

  void column_block(int b, std::complex<double>* scratch, const Multiplier& multiplier) {
    const Shape2 fs = fourier_shape();
    const int k1 = b * block_width;
    const int kind = k1 + widths_[0] <= fs.n1 ? 0 : 1;
    const int w = widths_[kind];
    // Every block before this one is block_width wide: it starts at k1 * n0 in block_order().
    FourierBlock block{.k1_begin = k1,
                       .width = w,
                       .rows = fs.n0,
                       .offset = static_cast<std::size_t>(k1) * static_cast<std::size_t>(fs.n0)};
    for (int f = 0; f < fields(); ++f) {
      std::complex<double>* t = scratch + static_cast<std::size_t>(f) * fs.n0 * block_width;
      assert(fftw_alignment_of(reinterpret_cast<double*>(fourier_[f] + k1)) ==
             fftw_alignment_of(reinterpret_cast<double*>(fourier_[0])));
      fftw_execute_dft(columns_forward_[kind], as_fftw(fourier_[f] + k1), as_fftw(t));
      block.field[f] = t;
    }
    multiplier(block);
    for (int f = 0; f < fields(); ++f) {
      std::complex<double>* t = block.field[f];
      fftw_execute_dft(columns_inverse_[kind], as_fftw(t), as_fftw(t));
      for (int k0 = 0; k0 < support_rows(); ++k0) {
        std::copy_n(t + static_cast<std::size_t>(k0) * w, w, fourier_[f] + fs.index(k0, k1));
      }
    }
  }

  void destroy() {
    {
      std::lock_guard<std::mutex> lock(planner_mutex());
      for (fftw_plan* p : {&forward_, &inverse_, &rows_forward_[0], &rows_forward_[1],
                           &rows_inverse_[0], &rows_inverse_[1], &columns_forward_[0],
                           &columns_forward_[1], &columns_inverse_[0], &columns_inverse_[1]}) {
        if (*p != nullptr) fftw_destroy_plan(*p);
        *p = nullptr;
      }
    }
    detail::free_buffers(input_);
    detail::free_buffers(output_);
    detail::free_buffers(fourier_);
    detail::free_buffers(scratch_);
  }

  int threads_;
  int widths_[2] = {0, 0};  // full block width, and the width of a last partial block (or 0)
  int blocks_ = 0;
  bool fourier_rows_clean_ = true;
  std::vector<std::complex<double>*> scratch_;  // one per thread: fields x n0 x block_width
  fftw_plan forward_ = nullptr, inverse_ = nullptr;
  int workers_ = 1;  // threads used by convolve()
  std::unique_ptr<std::barrier<>> sync_;
  std::atomic<unsigned> generation_{0};  // bumped once per convolve() to wake the workers
  std::atomic<bool> stopping_{false};
  const Multiplier* job_ = nullptr;
  std::vector<std::jthread> pool_;  // stopped and joined by stop_workers() before destroy()
  fftw_plan rows_forward_[2] = {nullptr, nullptr}, rows_inverse_[2] = {nullptr, nullptr};
  fftw_plan columns_forward_[2] = {nullptr, nullptr}, columns_inverse_[2] = {nullptr, nullptr};
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

const settings::Table<FFTOptions>& FFTOptions::settings() {
  using R = settings::Range;
  static const settings::Table<FFTOptions> table = {
      settings::neutral(settings::integer<FFTOptions>(
          "threads", [](auto& o) -> auto& { return o.threads; }, R::closed(1, 1024), "",
          "FFT threads (also the solvers' vector passes on large contacts)", "--threads")),
      settings::choice<FFTOptions>(
          "planner", [](auto& o) -> auto& { return o.planner; }, {"estimate", "measure", "patient"},
          [](Planner p) { return to_string(p); }, planner_from_string,
          "FFTW planning: estimate (instant, repeats bit for bit) | measure | patient")};
  return table;
}

void FFTOptions::validate() const {
  settings::validate(*this, settings());
}

// The part of the grids this process holds (layout()): every row and column for the serial
// engine, a slab for a distributed one.
std::span<double> Engine::input(int field) {
  const Layout l = layout();
  return {input_.at(field), static_cast<std::size_t>(l.rows) * static_cast<std::size_t>(shape_.n1)};
}
std::span<std::complex<double>> Engine::fourier(int field) {
  const Layout l = layout();
  return {fourier_.at(field),
          static_cast<std::size_t>(shape_.n0) * static_cast<std::size_t>(l.k1_count)};
}
std::span<double> Engine::output(int field) {
  const Layout l = layout();
  return {output_.at(field),
          static_cast<std::size_t>(l.rows) * static_cast<std::size_t>(shape_.n1)};
}

std::unique_ptr<Engine> make_engine(Shape2 shape, int fields, const FFTOptions& options,
                                    int support_rows) {
  detail::check_engine_arguments("fft::make_engine", shape, fields, options, support_rows);
  return std::make_unique<FFTWEngine>(shape, fields, support_rows == 0 ? shape.n0 : support_rows,
                                      options);
}

}  // namespace asperity::fft
