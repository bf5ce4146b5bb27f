// The EDEM card's synchronisation rules (coupling_schedule.h, seed 000).
#include "fsi/coupling_schedule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace quarry::fsi {

ScheduleSettings resolve_schedule(std::optional<double> period, std::optional<double> filter,
                                  double end_time) {
  ScheduleSettings s;
  if (period && !(*period > 0.0 && *period < end_time))
    throw std::invalid_argument(fmt::format("PERIOD = {} s must be in (0, TTERM = {} s)", *period, end_time));
  if (!period && !(end_time > 0.0))
    throw std::invalid_argument("PERIOD defaults to TTERM/100, and TTERM (the end time) is not positive");
  s.period = period ? *period : end_time / 100.0;  // seed 000: default TTERM/100
  if (filter && !(*filter > s.period))
    throw std::invalid_argument(fmt::format("FILTER = {} s must exceed PERIOD = {} s", *filter, s.period));
  s.filter = filter ? *filter : s.period;  // seed 000: default PERIOD
  return s;
}

CouplingSchedule::CouplingSchedule(ScheduleSettings settings)
    : period_(settings.period), filter_(settings.filter), requested_(settings.period) {}

double CouplingSchedule::period_after_reset(double dt_structure, double dt_dem) const {
  return reset_done_ ? period_ : std::max({period_, 2.0 * dt_structure, 2.0 * dt_dem});
}

std::optional<std::string> CouplingSchedule::before_structure_cycle(std::int64_t cycle,
                                                                    double dt_structure,
                                                                    double dt_dem) {
  if (cycle != 2 || reset_done_) return std::nullopt;
  // Seed 000: "reset by OptiStruct at cycle 2 ... DT_user = max(DT_user, 2*DT_os, 2*DT_edem)",
  // once per run.
  const double reset = period_after_reset(dt_structure, dt_dem);
  reset_done_ = true;
  if (reset == period_) return std::nullopt;
  const double old = period_;
  period_ = reset;
  filter_ = std::max(filter_, period_);  // FILTER ≥ PERIOD still (its default is PERIOD)
  requested_ = previous_request_ + period_;
  return fmt::format(
      "coupling: PERIOD {:.6g} s is below twice a solver's step (structure {:.6g} s, DEM {:.6g} s); "
      "reset at cycle 2 to {:.6g} s (FILTER {:.6g} s)",
      old, dt_structure, dt_dem, period_, filter_);
}

bool CouplingSchedule::reached(double time, double dt) const {
  return time >= requested_ - 1e-6 * dt;
}

std::int64_t CouplingSchedule::steps_to_sync(double time, double dt) const {
  const double steps = std::ceil((requested_ - time) / dt - 1e-6);
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(steps));
}

void CouplingSchedule::synchronised() {
  previous_request_ = requested_;
  requested_ += period_;
  ++synchronisations_;
}

ScheduleState CouplingSchedule::state() const {
  return {period_, filter_, requested_, previous_request_, reset_done_, synchronisations_};
}

void CouplingSchedule::set_state(const ScheduleState& s) {
  const bool finite = std::isfinite(s.period) && std::isfinite(s.filter) && std::isfinite(s.requested) &&
                      std::isfinite(s.previous_request);
  if (!finite || !(s.period > 0.0) || !(s.filter >= s.period) || !(s.previous_request >= 0.0) ||
      !(s.requested > s.previous_request) || s.synchronisations < 0)
    throw std::invalid_argument(fmt::format(
        "the coupling schedule (PERIOD {} s, FILTER {} s, request {} s after {} s, {} syncs) is out of range",
        s.period, s.filter, s.requested, s.previous_request, s.synchronisations));
  period_ = s.period;
  filter_ = s.filter;
  requested_ = s.requested;
  previous_request_ = s.previous_request;
  reset_done_ = s.reset_done;
  synchronisations_ = s.synchronisations;
}

}  // namespace quarry::fsi
