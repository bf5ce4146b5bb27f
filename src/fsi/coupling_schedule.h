// When the DEM and the structure synchronise, by the OptiStruct EDEM card's rules (seed 000):
// PERIOD = DT_user requests sync points every DT_user (default TTERM/100); each solver syncs at
// its first step that ends at or after the requested point; DT_user is reset once, at the
// structure's cycle 2, to max(DT_user, 2·DT_fem, 2·DT_dem); FILTER (> PERIOD, default PERIOD) is
// the window the imported forces are averaged over (force_filter.h). Pure: no solver in here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace quarry::fsi {

struct ScheduleSettings {
  double period = 0.0;  // DT_user (s)
  double filter = 0.0;  // s, ≥ period
};

// The seed's defaults and checks: period absent = end_time / 100, filter absent = period; a
// given period must be in (0, end_time), a given filter > period. Throws std::invalid_argument
// naming the value otherwise.
ScheduleSettings resolve_schedule(std::optional<double> period, std::optional<double> filter,
                                  double end_time);

// What a schedule holds between calls (checkpoints: structure_checkpoint.cpp).
struct ScheduleState {
  double period = 0.0, filter = 0.0;              // s, DT_user and FILTER now
  double requested = 0.0, previous_request = 0.0;  // s
  bool reset_done = false;                        // the cycle-2 reset has been made
  std::int64_t synchronisations = 0;
};

class CouplingSchedule {
 public:
  // Pre: settings as resolve_schedule gives them. The first requested point is t = period.
  explicit CouplingSchedule(ScheduleSettings settings);

  double period() const { return period_; }   // s, DT_user now (after the reset if any)
  double filter() const { return filter_; }   // s
  double requested() const { return requested_; }  // s, the pending requested sync point
  std::int64_t synchronisations() const { return synchronisations_; }
  bool reset_done() const { return reset_done_; }  // the cycle-2 reset has been made (PERIOD final)
  // DT_user after the cycle-2 reset with these steps (s): max(DT_user, 2·dt_structure, 2·dt_dem),
  // or DT_user once the reset is made.
  double period_after_reset(double dt_structure, double dt_dem) const;

  // To call before the structure's step number `cycle` (1-based) with the step sizes (s) the
  // two solvers use. At cycle 2, once in a run, DT_user becomes max(DT_user, 2·dt_structure,
  // 2·dt_dem) and the pending request moves to the previous one (0 at the start) plus the new
  // DT_user. Returns the line to print when DT_user changed.
  std::optional<std::string> before_structure_cycle(std::int64_t cycle, double dt_structure,
                                                    double dt_dem);

  // Whether a solver whose step has just ended at `time` (s), stepping by `dt` (s), is at its
  // sync point: time ≥ requested. Times within 1e-6·dt below the request count as at it, so
  // that a clock summed step by step syncs at the step that is meant to land on the request.
  bool reached(double time, double dt) const;
  // Steps of `dt` (s) a solver at `time` (s) takes to its sync point: the fewest n ≥ 1 with
  // time + n·dt at or after the request (≥ 1: a request already passed is served at the next
  // step, as the seed says for a DT_user below a solver's step).
  std::int64_t steps_to_sync(double time, double dt) const;

  // Both solvers have synchronised: the next request is this one plus DT_user.
  void synchronised();

  ScheduleState state() const;
  // Throws std::invalid_argument for times that are not finite or out of order (0 < period ≤
  // filter, 0 ≤ previous request < request) or a negative count; changes nothing then.
  void set_state(const ScheduleState& state);

 private:
  double period_ = 0.0, filter_ = 0.0;
  double requested_ = 0.0, previous_request_ = 0.0;
  bool reset_done_ = false;
  std::int64_t synchronisations_ = 0;
};

}  // namespace quarry::fsi
