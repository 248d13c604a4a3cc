// The worker pool of common/parallel.hpp.
#include "common/parallel.hpp"

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace asperity::par {

namespace {

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

  void run(int t, Job job, void* context) {
    std::unique_lock running(run_mutex_, std::try_to_lock);
    if (!running.owns_lock()) {  // another caller's job is on the workers: do it all here
      for (int k = 0; k < t; ++k)
        job(context, k, t);
      return;
    }
    while (static_cast<int>(workers_.size()) < t - 1) {
      const int k = static_cast<int>(workers_.size()) + 1;
      workers_.emplace_back([this, k] { work(k); });
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

 private:
  void work(int k) {
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

void run(int t, Job job, void* context) {
  static Pool pool;
  if (t <= 1) {
    job(context, 0, 1);
    return;
  }
  pool.run(t, job, context);
}

}  // namespace asperity::par
