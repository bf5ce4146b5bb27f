// StageTimers: wall-clock time spent in each named stage of the time step (s), for the
// per-stage table printed at the end of a run and for profiling.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace quarry {

class StageTimers {
 public:
  // Returns the index of a stage (created on first use, in order of first use).
  int stage(const std::string& name);
  void add(int stage_index, double seconds) { seconds_[stage_index] += seconds; }
  double seconds(int stage_index) const { return seconds_[stage_index]; }
  const std::vector<std::string>& names() const { return names_; }
  double total() const;
  // Table: stage, seconds, percent of total, one line each. With `wall_seconds` (> 0, the
  // run's measured wall time) the shares are of that time, a line "untimed" holds what no stage
  // timed (the loop itself, progress lines) and the total is the wall time.
  std::string table(double wall_seconds = 0.0) const;
  void reset();

 private:
  std::vector<std::string> names_;
  std::vector<double> seconds_;
};

// Times a scope into one stage.
class ScopedStage {
 public:
  ScopedStage(StageTimers& timers, int stage_index)
      : timers_(timers), index_(stage_index), start_(std::chrono::steady_clock::now()) {}
  ~ScopedStage() {
    timers_.add(index_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  StageTimers& timers_;
  int index_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace quarry
