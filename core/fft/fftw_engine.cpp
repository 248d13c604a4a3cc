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
//
// On several threads each phase is a list of units (batches of rows, column blocks) that the
// calling thread and the workers claim from a counter, and a phase ends when all its units are
// done. The caller never waits for a worker to start: on a machine with more runnable threads
// than cores a woken worker can wait milliseconds for a core, and with a fixed share per thread
// and barriers between the phases a convolution of a 72^2 grid took 10x, a small slide 17x,
// the time of one thread (docs/benchmarks.md, "Threads on a busy machine"). A unit's result does
// not depend on the thread that runs it (a batch always gets the plan of its index), so the
// output is the same bits whoever claims what.
#include <fftw3.h>
#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <atomic>
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

// Real grid points per thread of convolve() (docs/benchmarks.md, "Threads on a busy machine"):
// 128^2 runs on two threads (1.3x faster on an idle machine), 72^2 on one.
constexpr std::size_t min_points_per_worker = 8192;

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
    if (workers_ <= 1) {
      for (int p = 0; p < phases; ++p) {
        for (int k = 0; k < units(p); ++k)
          run_unit(p, k, 0, multiplier);
      }
      return;
    }
    // A new call: its counters are reset before the workers can see its number (a worker still
    // in an earlier call finds its number gone and claims nothing).
    const std::uint32_t g = ++calls_;
    for (int p = 0; p < phases; ++p) {
      next_[p].store(std::uint64_t{g} << 32, std::memory_order_relaxed);
      done_[p].store(0, std::memory_order_relaxed);
    }
    job_ = &multiplier;
    generation_.store(g, std::memory_order_release);
    generation_.notify_all();
    participate(g, 0);  // returns when every unit of the last phase is done
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
    // A grid under min_points_per_worker points per worker stays on one thread: at 72^2 a
    // second thread gained nothing on an idle machine and cost 1.7x on a busy one.
    const auto by_size = static_cast<int>(s.count() / min_points_per_worker);
    workers_ = std::max(1, std::min({threads_, blocks_, support, by_size}));
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

  // Worker t > 0: waits (futex, no spinning) for a new convolution and helps with it.
  void worker(int t) {
    std::uint32_t seen = 0;
    for (;;) {
      generation_.wait(seen, std::memory_order_acquire);
      seen = generation_.load(std::memory_order_acquire);
      if (stopping_.load(std::memory_order_acquire)) return;
      participate(seen, t);
    }
  }

  void stop_workers() {
    if (pool_.empty()) return;
    stopping_.store(true, std::memory_order_release);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    for (auto& d : done_)
      d.notify_all();  // a worker waiting for a phase to end
    pool_.clear();     // joins
  }

  // First row of batch k: batches of floor(S/W) rows, the first S mod W one longer.
  [[nodiscard]] int batch_start(int k) const {
    const int base = support_rows() / workers_, extra = support_rows() % workers_;
    return k * base + std::min(k, extra);
  }

  // The phases of convolve(): row transforms, column blocks, inverse row transforms.
  static constexpr int phases = 3;
  [[nodiscard]] int units(int phase) const {
    return phase == 1 ? blocks_ : workers_;
  }

  // Unit k of a phase, on participant t (its scratch block).
  void run_unit(int phase, int k, int t, const Multiplier& multiplier) {
    if (phase == 1) {
      column_block(k, scratch_[t], multiplier);
      return;
    }
    const Shape2 s = real_shape(), fs = fourier_shape();
    const int r0 = batch_start(k);
    const int kind = k < support_rows() % workers_ ? 1 : 0;
    for (int f = 0; f < fields(); ++f) {
      if (phase == 0) {
        fftw_execute_dft_r2c(rows_forward_[kind], input_[f] + s.index(r0, 0),
                             as_fftw(fourier_[f] + fs.index(r0, 0)));
      } else {
        fftw_execute_dft_c2r(rows_inverse_[kind], as_fftw(fourier_[f] + fs.index(r0, 0)),
                             output_[f] + s.index(r0, 0));
      }
    }
  }

  // Call g's units, claimed one at a time, phase after phase; between phases, waits until every
  // unit of the phase is done (only for units another thread claimed and is running). Returns
  // at once if call g is over (a worker that woke late).
  void participate(std::uint32_t g, int t) {
    for (int p = 0; p < phases; ++p) {
      const auto total = static_cast<std::uint32_t>(units(p));
      for (;;) {
        std::uint64_t v = next_[p].load(std::memory_order_acquire);
        bool claimed = false;
        while ((v >> 32) == g && (v & 0xffffffffU) < total) {
          if (next_[p].compare_exchange_weak(v, v + 1, std::memory_order_acq_rel,
                                             std::memory_order_acquire)) {
            claimed = true;
            break;
          }
        }
        if ((v >> 32) != g) return;  // another call's counters
        if (!claimed) break;         // the phase's units are all taken
        run_unit(p, static_cast<int>(v & 0xffffffffU), t, *job_);
        if (done_[p].fetch_add(1, std::memory_order_acq_rel) + 1 == total) done_[p].notify_all();
      }
      for (;;) {
        const std::uint32_t d = done_[p].load(std::memory_order_acquire);
        if (d == total) break;
        if (stopping_.load(std::memory_order_acquire) ||
            (next_[p].load(std::memory_order_acquire) >> 32) != g) {
          return;
        }
        done_[p].wait(d, std::memory_order_acquire);
      }
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
  // Per convolve() on several threads: its number (calls_, published in generation_ to wake the
  // workers), and per phase the next unit to claim (the call's number in the high 32 bits, so
  // that a late worker cannot claim a unit of a later call) and the units done.
  std::uint32_t calls_ = 0;
  std::atomic<std::uint32_t> generation_{0};
  std::atomic<std::uint64_t> next_[phases] = {};
  std::atomic<std::uint32_t> done_[phases] = {};
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
