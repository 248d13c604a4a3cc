#include "asperity/apps/common/point_runner.hpp"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "asperity/apps/common/cli.hpp"

namespace asperity::app {

void run_points(std::size_t count, int jobs, const std::function<void(std::size_t)>& run,
                std::atomic<bool>& stop) {
  std::atomic<std::size_t> next{0};
  std::mutex failure_mutex;
  std::exception_ptr failure;
  {
    std::vector<std::jthread> pool;
    for (int j = 0; j < std::max(jobs, 1); ++j) {
      pool.emplace_back([&] {
        while (!stop && !stop_requested()) {
          const std::size_t i = next++;
          if (i >= count) break;
          try {
            run(i);
          } catch (...) {
            const std::lock_guard lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            stop = true;
          }
        }
      });
    }
  }  // joins
  if (failure) std::rethrow_exception(failure);
}

}  // namespace asperity::app
