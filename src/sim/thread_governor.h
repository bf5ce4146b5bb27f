// ThreadGovernor: how many of the requested threads the run loop uses, chosen by measuring
// (issue #21 §3: two threads must never be slower than one, even on a machine where another
// process is busy). On two cores shared with one busy process, a team of two waits at every
// barrier for the thread the scheduler has set aside: the hopper took 2.0× as long on two
// threads as on one (docs/performance.md "Threads on a busy machine"). The results are
// bit-identical for any thread count, so the team may change between any two steps: the governor
// times a window of steps with the current team, then a window with the other, then one with the
// current team again, and keeps the faster: the probe against the mean of the windows around it,
// so that work growing or shrinking steadily over the windows (a pour filling up) weighs on both
// teams alike. A choice confirmed by a probe is probed again after twice as long (up to a
// minute), so a steady machine pays little for the probing; sooner if the steps' cost drifts.
#pragma once

#include <cstdint>

namespace quarry::sim {

class ThreadGovernor {
 public:
  struct Options {
    bool enabled = true;           // false: always all requested threads (benchmarks)
    double window_seconds = 0.1;   // s of wall time per measured window (at least min_window_steps)
    std::uint64_t min_window_steps = 32;
    double first_period_seconds = 2.0;  // s between a decision and the next probe, doubled when
    double max_period_seconds = 60.0;   // a probe confirms the choice
    double switch_margin = 0.03;        // the other team must be this much faster to switch to it
    // The chosen team's time per step (windows as above) moving by this factor from what it was
    // at the decision starts a probe at once: the work per step changed (a pour filling up, a
    // coupled structure's share of the step shrinking), and so may the faster team.
    double drift = 1.25;
  };

  // `requested` threads (≥ 1); below 2, or not enabled, the governor never changes anything.
  explicit ThreadGovernor(int requested) : ThreadGovernor(requested, Options{}) {}
  ThreadGovernor(int requested, Options options);

  // The team for the next step: 1 or `requested`.
  int threads() const { return current_; }
  // The step just taken with threads() took `seconds` of wall time.
  void step_took(double seconds);

  int requested() const { return requested_; }
  std::uint64_t steps_with_all() const { return steps_with_all_; }  // steps taken on `requested` threads
  std::uint64_t steps_with_one() const { return steps_with_one_; }
  int switches() const { return switches_; }

 private:
  enum class Phase { run, baseline, probe, check };  // check: the chosen team after the probe
  void start_phase(Phase phase);
  int other_team() const { return chosen_ == 1 ? requested_ : 1; }  // the one a probe times

  int requested_ = 1;
  Options options_;
  int current_ = 1;     // team of the next step
  int chosen_ = 1;      // the team the last decision kept
  Phase phase_ = Phase::baseline;
  double phase_seconds_ = 0.0;       // wall time in this phase so far
  std::uint64_t phase_steps_ = 0;
  double baseline_per_step_ = 0.0;   // s per step of the chosen team just before the probe
  double probe_per_step_ = 0.0;      // s per step of the other team in the probe
  double reference_per_step_ = 0.0;  // s per step of the chosen team at the last decision
  double window_seconds_ = 0.0;      // the run phase's current window
  std::uint64_t window_steps_ = 0;
  double period_seconds_ = 0.0;      // current time between probes
  std::uint64_t steps_with_all_ = 0, steps_with_one_ = 0;
  int switches_ = 0;
};

}  // namespace quarry::sim
