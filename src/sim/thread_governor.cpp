// ThreadGovernor: run → baseline window (chosen team) → probe window (the other team) → check
// window (chosen team) → decide.
#include "sim/thread_governor.h"

#include <algorithm>

namespace quarry::sim {

ThreadGovernor::ThreadGovernor(int requested, Options options)
    : requested_(std::max(1, requested)), options_(options), current_(requested_), chosen_(requested_),
      period_seconds_(options.first_period_seconds) {
  start_phase(Phase::baseline);
}

void ThreadGovernor::start_phase(Phase phase) {
  phase_ = phase;
  phase_seconds_ = 0.0;
  phase_steps_ = 0;
  window_seconds_ = 0.0;
  window_steps_ = 0;
  current_ = phase == Phase::probe ? other_team() : chosen_;
}

void ThreadGovernor::step_took(double seconds) {
  (current_ == 1 ? steps_with_one_ : steps_with_all_) += 1;
  if (requested_ < 2 || !options_.enabled) return;
  phase_seconds_ += seconds;
  phase_steps_ += 1;
  const auto full = [this](std::uint64_t steps, double wall) {
    return steps >= options_.min_window_steps && wall >= options_.window_seconds;
  };
  const bool window_full = full(phase_steps_, phase_seconds_);
  switch (phase_) {
    case Phase::run: {
      if (phase_seconds_ >= period_seconds_) {
        start_phase(Phase::baseline);
        break;
      }
      window_seconds_ += seconds;
      window_steps_ += 1;
      if (!full(window_steps_, window_seconds_)) break;
      const double per_step = window_seconds_ / static_cast<double>(window_steps_);
      window_seconds_ = 0.0;
      window_steps_ = 0;
      if (per_step > options_.drift * reference_per_step_ || per_step * options_.drift < reference_per_step_) {
        period_seconds_ = options_.first_period_seconds;
        start_phase(Phase::baseline);
      }
      break;
    }
    case Phase::baseline:
      if (!window_full) break;
      baseline_per_step_ = phase_seconds_ / static_cast<double>(phase_steps_);
      start_phase(Phase::probe);
      break;
    case Phase::probe:
      if (!window_full) break;
      probe_per_step_ = phase_seconds_ / static_cast<double>(phase_steps_);
      start_phase(Phase::check);
      break;
    case Phase::check: {
      if (!window_full) break;
      const double check_per_step = phase_seconds_ / static_cast<double>(phase_steps_);
      // The chosen team's time at the probe's moment: the mean of the windows before and after.
      const double chosen_per_step = 0.5 * (baseline_per_step_ + check_per_step);
      if (probe_per_step_ < (1.0 - options_.switch_margin) * chosen_per_step) {
        chosen_ = other_team();  // the other team is faster: take it, and look again soon
        ++switches_;
        period_seconds_ = options_.first_period_seconds;
        reference_per_step_ = probe_per_step_;
      } else {
        period_seconds_ = std::min(2.0 * period_seconds_, options_.max_period_seconds);
        reference_per_step_ = check_per_step;
      }
      start_phase(Phase::run);
      break;
    }
  }
}

}  // namespace quarry::sim
