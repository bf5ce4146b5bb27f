// The structure's half of the coupling exchange (structure_side.h).
#include "fsi/structure_side.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace quarry::fsi {

StructureSide::StructureSide(fem::ShellSolver& solver, std::vector<std::int32_t> node_of_vertex, double step_fraction,
                             ScheduleSettings schedule)
    : solver_(solver),
      node_of_vertex_(std::move(node_of_vertex)),
      step_fraction_(step_fraction),
      schedule_(schedule),
      filter_(schedule.filter) {
  for (std::int32_t n : node_of_vertex_)
    if (n < 0 || n >= solver_.node_count())
      throw std::invalid_argument(fmt::format("coupling node {} is not a node of the structure", n));
  pending_impulse_.assign(node_of_vertex_.size(), Vec3{});
  loads_.assign(static_cast<std::size_t>(solver_.node_count()), fem::NodalLoad{});
}

void StructureSide::surface_nodes(double dem_time, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) const {
  const double lag = dem_time - solver_.time();  // s
  positions.resize(node_of_vertex_.size());
  velocities.resize(node_of_vertex_.size());
  for (std::size_t k = 0; k < node_of_vertex_.size(); ++k) {
    const auto n = static_cast<std::size_t>(node_of_vertex_[k]);
    velocities[k] = solver_.velocities()[n];
    positions[k] = solver_.positions()[n] + velocities[k] * lag;
  }
}

void StructureSide::begin_period(double dem_dt) {
  structure_dt_ = step_fraction_ * solver_.stable_time_step().time_step;
  if (auto line = schedule_.before_structure_cycle(solver_.step_count() + 1, structure_dt_, dem_dt))
    messages_.push_back(*line);
  period_steps_ = schedule_.steps_to_sync(solver_.time(), structure_dt_);
  period_steps_done_ = 0;
  const double period = static_cast<double>(period_steps_) * structure_dt_;  // s
  for (fem::NodalLoad& load : loads_) load = {};
  for (std::size_t k = 0; k < node_of_vertex_.size(); ++k)
    loads_[static_cast<std::size_t>(node_of_vertex_[k])].force += pending_impulse_[k] / period;
  solver_.set_loads(loads_);
}

void StructureSide::step(double dem_dt) {
  if (period_steps_done_ > 0) {
    // The cycle-2 reset can only fall inside the first period (which starts at cycle 1 and
    // carries no load yet): the request moved, so the steps to it are counted again.
    const double old_request = schedule_.requested();
    if (auto line = schedule_.before_structure_cycle(solver_.step_count() + 1, structure_dt_, dem_dt))
      messages_.push_back(*line);
    if (schedule_.requested() != old_request)
      period_steps_ = period_steps_done_ + schedule_.steps_to_sync(solver_.time(), structure_dt_);
  }
  solver_.step(structure_dt_);
  ++period_steps_done_;
  ++structure_steps_;
  if (at_sync()) std::fill(pending_impulse_.begin(), pending_impulse_.end(), Vec3{});
}

// Why evenly: on two threads the structure's steps run beside the DEM's stages, and a step costs
// the dearer of the two. Stepped up to the DEM's time instead, the structure reached its sync
// point early in the DEM step that crosses it and then had to wait for the exchange: with a
// PERIOD of 2.13 DEM steps of 16 structure steps each, it ran 2 steps in one DEM step and 30 in
// the next (the flagship). The steps and their loads are the same either way, so are the bits
// at every sync; only where the structure stands between syncs moves (its output rows and
// frames carry its own time).
void StructureSide::keep_up(double dem_time, double dem_dt) {
  if (at_sync() || dem_time <= paced_to_) return;  // one share per DEM step, however often asked
  paced_to_ = dem_time;
  const std::int64_t dem_steps =
      schedule_.reached(dem_time, dem_dt) ? 1 : 1 + schedule_.steps_to_sync(dem_time, dem_dt);
  const std::int64_t left = period_steps_ - period_steps_done_;
  const std::int64_t now = (left + dem_steps - 1) / dem_steps;  // rounded up
  for (std::int64_t k = 0; k < now && !at_sync(); ++k) step(dem_dt);
}

void StructureSide::finish_period(double dem_dt) {
  while (!at_sync()) step(dem_dt);
}

void StructureSide::receive(std::span<const Vec3> mean_force, double window) {
  if (mean_force.size() != node_of_vertex_.size())
    throw std::invalid_argument(fmt::format("{} nodal forces received for {} coupled nodes", mean_force.size(),
                                            node_of_vertex_.size()));
  impulse_.resize(mean_force.size());
  for (std::size_t k = 0; k < mean_force.size(); ++k) impulse_[k] = mean_force[k] * window;  // N·s
  filter_.set_window(schedule_.filter());
  filter_.add(impulse_, window);
  filter_.mean(filtered_force_);
  for (std::size_t k = 0; k < pending_impulse_.size(); ++k) pending_impulse_[k] = filtered_force_[k] * window;
}

Vec3 StructureSide::pending_impulse() const {
  Vec3 sum;  // N·s
  for (const Vec3& j : pending_impulse_) sum += j;
  return sum;
}

CouplerState StructureSide::state() const {
  return {schedule_.state(), filter_.window(),    filter_.periods(),  pending_impulse_, loads_,
          structure_dt_,     period_steps_,       period_steps_done_, structure_steps_, false,
          messages_};
}

void StructureSide::check_state(const CouplerState& s) const {
  const std::size_t vertices = node_of_vertex_.size();
  if (s.pending_impulse.size() != vertices || s.loads.size() != loads_.size())
    throw std::invalid_argument(fmt::format("the coupler holds {} impulses and {} loads for {} vertices and {} nodes",
                                            s.pending_impulse.size(), s.loads.size(), vertices, loads_.size()));
  for (const ForceFilter::Period& p : s.filter_periods)
    if (p.impulse.size() != vertices)
      throw std::invalid_argument(fmt::format("the force filter holds {} impulses for {} vertices", p.impulse.size(), vertices));
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  for (const Vec3& j : s.pending_impulse)
    if (!finite(j)) throw std::invalid_argument("the coupler's pending impulse is not finite");
  for (const fem::NodalLoad& l : s.loads)
    if (!finite(l.force) || !finite(l.moment)) throw std::invalid_argument("the coupler's nodal loads are not finite");
  if (!(s.structure_dt > 0.0) || !std::isfinite(s.structure_dt) || s.period_steps < 1 || s.period_steps_done < 0 ||
      s.period_steps_done > s.period_steps || s.structure_steps < s.period_steps_done)
    throw std::invalid_argument(fmt::format("the coupler's step {} s, period of {} steps ({} done, {} in all) is out of range",
                                            s.structure_dt, s.period_steps, s.period_steps_done, s.structure_steps));
  CouplingSchedule schedule = schedule_;
  schedule.set_state(s.schedule);
  ForceFilter filter(s.filter_window);
  filter.set_state(s.filter_window, {});
  for (const ForceFilter::Period& p : s.filter_periods)
    if (!(p.duration >= 0.0) || !std::isfinite(p.duration) ||
        !std::all_of(p.impulse.begin(), p.impulse.end(), finite))
      throw std::invalid_argument("the force filter holds a period that is not finite or lasts less than 0 s");
}

void StructureSide::set_state(CouplerState s) {
  check_state(s);
  schedule_.set_state(s.schedule);
  filter_.set_state(s.filter_window, std::move(s.filter_periods));
  pending_impulse_ = std::move(s.pending_impulse);
  loads_ = std::move(s.loads);
  structure_dt_ = s.structure_dt;
  period_steps_ = s.period_steps;
  period_steps_done_ = s.period_steps_done;
  structure_steps_ = s.structure_steps;
  messages_ = std::move(s.messages);
  paced_to_ = -INFINITY;
}

}  // namespace quarry::fsi
