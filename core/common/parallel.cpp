// The worker pool of common/parallel.hpp.
#include "asperity/core/common/parallel.hpp"

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace asperity::par {

namespace {

// Set on the threads running a job: a pass started from inside a job runs serially there (the
// caller holds the pool, and a worker cannot wait on its own pool).
thread_local bool inside_job = false;

// Workers wait on a condition variable (they sleep, so FFTW's threads keep the cores between
// passes). One job at a time: a generation counter tells a worker that a new job is posted, and
// the caller waits until every worker taking part in it is done, so no worker can miss the job
// it takes part in.
class Pool {
 public:
  Pool() = default;
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;
  ~Pool() {
    {
      const std::lock_guard lock(m_);
      stop_ = true;
    }
    work_.notify_all();
    for (auto& w : workers_)
      w.join();
  }

  void run(int t, Job job, void* context) noexcept {
    std::unique_lock running(run_mutex_, std::try_to_lock);
    if (!running.owns_lock()) {  // another caller's job is on the workers: do it all here
      serial(t, job, context);
      return;
    }
    try {
      while (static_cast<int>(workers_.size()) < t - 1) {
        const int k = static_cast<int>(workers_.size()) + 1;
        workers_.emplace_back([this, k] { work(k); });
      }
    } catch (const std::exception&) {  // no thread to be had: the same ranges, here
      serial(t, job, context);
      return;
    }
    {
      const std::lock_guard lock(m_);
      job_ = job;
      context_ = context;
      threads_ = t;
      pending_ = t - 1;
      ++generation_;
    }
    work_.notify_all();
    job(context, 0, t);
    std::unique_lock lock(m_);
    done_.wait(lock, [this] { return pending_ == 0; });
  }

  static void serial(int t, Job job, void* context) noexcept {
    for (int k = 0; k < t; ++k)
      job(context, k, t);
  }

 private:
  void work(int k) {
    inside_job = true;
    std::uint64_t seen = 0;
    std::unique_lock lock(m_);
    for (;;) {
      work_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (k >= threads_) continue;  // a job on fewer threads
      const Job job = job_;
      void* const context = context_;
      const int t = threads_;
      lock.unlock();
      job(context, k, t);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::mutex run_mutex_;  // held by the caller whose job is posted
  std::mutex m_;          // guards what follows
  std::condition_variable work_, done_;
  std::vector<std::thread> workers_;  // worker i runs k = i + 1
  Job job_ = nullptr;
  void* context_ = nullptr;
  int threads_ = 0, pending_ = 0;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
};

}  // namespace

void run(int t, Job job, void* context) noexcept {
  static Pool pool;
  if (t <= 1 || inside_job) {
    Pool::serial(t, job, context);
    return;
  }
  inside_job = true;
  pool.run(t, job, context);
  inside_job = false;
}

}  // namespace asperity::par
