// The relaxations a slide starts, read from its progress reports (slide::SlideProgress): a
// relaxation reports iteration 0 when it starts and its iteration at every heartbeat after
// (every 16 iterations, where a stop request is polled); an accepted report ends a step. Tests
// of which relaxations a step made (the flow first in creep, stops inside them) share it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "asperity/core/slide/types.hpp"

namespace asperity::test {

struct Relaxation {
  slide::SlidePhase phase;
  double target;         // the Dx it relaxes to (d)
  int iterations = 0;    // the largest iteration reported
  std::size_t step = 0;  // the step it belongs to: accepted reports before it
};

// Whether two relaxations are the same start: phase and target.
inline bool same_start(const Relaxation& a, const Relaxation& b) {
  return a.phase == b.phase && a.target == b.target;
}

// A progress callback that records the relaxations.
class RelaxationLog {
 public:
  void operator()(const slide::SlideProgressInfo& p) {
    if (p.phase == slide::SlidePhase::accepted) {
      ++steps_;
      return;
    }
    if (p.iteration == 0) all_.push_back({p.phase, p.target_Dx, 0, steps_});
    if (!all_.empty()) all_.back().iterations = std::max(all_.back().iterations, p.iteration);
  }
  const std::vector<Relaxation>& all() const { return all_; }
  // The relaxations of each step, one list per step begun (accepted reports + 1).
  std::vector<std::vector<Relaxation>> per_step() const {
    std::vector<std::vector<Relaxation>> steps(steps_ + 1);
    for (const Relaxation& r : all_)
      steps[r.step].push_back(r);
    return steps;
  }

 private:
  std::vector<Relaxation> all_;
  std::size_t steps_ = 0;
};

}  // namespace asperity::test
