#pragma once
// `ppohdem simulate --phases A,B,...`: the wall time of each phase of a run, the steps
// (first, A], (A, B], ..., (last mark, end], so that one run reports free fall, impact, settling
// and the settled bed separately (ci/bench-dem.sh --phases; docs/performance.md "Phases").
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "ppohdem/error.hpp"

namespace ppohdem::app {

class PhaseTiming {
 public:
  /// `marks`: step numbers strictly increasing and inside (first_step, last_step).
  PhaseTiming(std::vector<long> marks, long first_step, long last_step) {
    long previous = first_step;
    for (const long mark : marks) {
      if (mark <= previous || mark >= last_step) {
        throw InputError("--phases: expected step numbers increasing strictly between the first step (" +
                         std::to_string(first_step) + ") and the last (" + std::to_string(last_step) + "), got " +
                         std::to_string(mark));
      }
      previous = mark;
    }
    ends_ = std::move(marks);
    ends_.push_back(last_step);
    begin_step_ = first_step;
  }

  /// Called at every step boundary with the number of steps done (run.hpp, at_step_boundary).
  void at_step_boundary(long done) {
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
      started_ = true;
      begin_ = now;
      return;
    }
    if (next_ < ends_.size() && done == ends_[next_]) {
      phases_.push_back({begin_step_, done, std::chrono::duration<double>(now - begin_).count()});
      begin_step_ = done;
      begin_ = std::chrono::steady_clock::now();
      ++next_;
    }
  }

  /// One line per phase: its steps, wall seconds and particle-steps per second.
  void report(std::size_t particles) const {
    for (std::size_t k = 0; k < phases_.size(); ++k) {
      const Phase& p = phases_[k];
      const double steps = static_cast<double>(p.last - p.first);
      std::printf("phase %zu: steps %ld-%ld, wall %.4f s, %.4g particle-steps/s\n", k + 1, p.first, p.last, p.seconds,
                  p.seconds > 0.0 ? steps * static_cast<double>(particles) / p.seconds : 0.0);
    }
  }

 private:
  struct Phase {
    long first, last;
    double seconds;
  };
  std::vector<long> ends_;
  std::vector<Phase> phases_;
  std::size_t next_ = 0;
  long begin_step_ = 0;
  bool started_ = false;
  std::chrono::steady_clock::time_point begin_;
};

}  // namespace ppohdem::app
