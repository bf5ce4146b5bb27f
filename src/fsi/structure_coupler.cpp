// The two-way DEM ↔ shell coupling loop (structure_coupler.h).
#include "fsi/structure_coupler.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "sim/step.h"

namespace quarry::fsi {

StructureCoupler::StructureCoupler(World& world, std::size_t surface, fem::ShellSolver& solver,
                                   std::vector<std::int32_t> node_of_vertex, CouplerOptions options)
    : world_(world),
      surface_(surface),
      solver_(solver),
      node_of_vertex_(std::move(node_of_vertex)),
      options_(options),
      schedule_(options.schedule),
      filter_(options.schedule.filter) {
  WorldSurface& s = world_.surfaces.at(surface_);
  if (s.driver.kind != SurfaceDriverKind::coupled)
    throw std::invalid_argument("surface '" + s.mesh.name + "' is not coupled");
  if (node_of_vertex_.size() != s.mesh.vertex_count())
    throw std::invalid_argument(fmt::format("surface '{}' has {} vertices, the coupling names {} nodes",
                                            s.mesh.name, s.mesh.vertex_count(), node_of_vertex_.size()));
  for (std::int32_t n : node_of_vertex_)
    if (n < 0 || n >= solver_.node_count())
      throw std::invalid_argument(fmt::format("coupling node {} is not a node of the structure", n));
  pending_impulse_.assign(node_of_vertex_.size(), Vec3{});
  loads_.assign(static_cast<std::size_t>(solver_.node_count()), fem::NodalLoad{});
  if (options_.resume) return;  // the surface as the checkpoint left it; set_state follows
  // The sync at t = 0: the surface where the structure is; its window starts empty.
  std::vector<Vec3> x(node_of_vertex_.size()), v(node_of_vertex_.size());
  for (std::size_t k = 0; k < node_of_vertex_.size(); ++k) {
    x[k] = solver_.positions()[static_cast<std::size_t>(node_of_vertex_[k])];
    v[k] = solver_.velocities()[static_cast<std::size_t>(node_of_vertex_[k])];
  }
  sim::set_surface_vertices(world_, surface_, x, v);
  s.coupling_window = LoadWindow(s.mesh, s.element_of_triangle, s.element_count);
  begin_structure_period();
}

void StructureCoupler::advance_period() {
  do {
    sim::step(world_);
  } while (!after_dem_step());
}

void StructureCoupler::advance_to(double time) {
  while (world_.time < time - 1e-6 * world_.dt) advance_period();
}

bool StructureCoupler::after_dem_step() {
  // 1. The structure up to the DEM's time, not past its sync point.
  while (!structure_at_sync() && solver_.time() < world_.time) step_structure();
  // 2. The DEM at its sync point: the structure finishes its period, then 3. the exchange.
  if (!schedule_.reached(world_.time, world_.dt)) return false;
  while (!structure_at_sync()) step_structure();
  exchange();
  check_period_stability();
  begin_structure_period();
  return true;
}

StepHook StructureCoupler::step_hook() {
  return {HookStage::end_of_step, "structure coupling", [this](World&) { after_dem_step(); }};
}

// A structure period at a constant step, loaded by the previous exchange's impulse J spread
// evenly over it: loads = J / (n·dt) for its n steps, Σ = J.
void StructureCoupler::begin_structure_period() {
  structure_dt_ = options_.structure_step_fraction * solver_.stable_time_step().time_step;
  if (auto line = schedule_.before_structure_cycle(solver_.step_count() + 1, structure_dt_, world_.dt))
    messages_.push_back(*line);
  period_steps_ = schedule_.steps_to_sync(solver_.time(), structure_dt_);
  period_steps_done_ = 0;
  const double period = static_cast<double>(period_steps_) * structure_dt_;  // s
  for (fem::NodalLoad& load : loads_) load = {};
  for (std::size_t k = 0; k < node_of_vertex_.size(); ++k)
    loads_[static_cast<std::size_t>(node_of_vertex_[k])].force += pending_impulse_[k] / period;
  solver_.set_loads(loads_);
}

void StructureCoupler::step_structure() {
  if (period_steps_done_ > 0) {
    // The cycle-2 reset can only fall inside the first period (which starts at cycle 1 and
    // carries no load yet): the request moved, so the steps to it are counted again.
    const double old_request = schedule_.requested();
    if (auto line = schedule_.before_structure_cycle(solver_.step_count() + 1, structure_dt_, world_.dt))
      messages_.push_back(*line);
    if (schedule_.requested() != old_request)
      period_steps_ = period_steps_done_ + schedule_.steps_to_sync(solver_.time(), structure_dt_);
  }
  solver_.step(structure_dt_);
  ++period_steps_done_;
  ++structure_steps_;
  if (structure_at_sync()) std::fill(pending_impulse_.begin(), pending_impulse_.end(), Vec3{});
}

// 3. Exchange at the sync point.
void StructureCoupler::exchange() {
  WorldSurface& s = world_.surfaces[surface_];
  // DEM → structure: this period's nodal impulses (N·s), filtered over FILTER; the next period
  // applies the filtered mean force × this period's length (= the impulse when FILTER = PERIOD).
  LoadWindow& window = s.coupling_window;
  const double duration = window.duration;  // s
  filter_.set_window(schedule_.filter());
  filter_.add(window.nodal_impulse, duration);
  filter_.mean(filtered_force_);
  for (std::size_t k = 0; k < pending_impulse_.size(); ++k) pending_impulse_[k] = filtered_force_[k] * duration;
  window.clear();

  // Structure → DEM: nodal positions at the DEM's time (the structure's sync step may end
  // before or after it: advanced with the nodal velocity, the motion the surface follows anyway).
  const double lag = world_.time - solver_.time();  // s
  std::vector<Vec3> x(node_of_vertex_.size()), v(node_of_vertex_.size());
  for (std::size_t k = 0; k < node_of_vertex_.size(); ++k) {
    const auto n = static_cast<std::size_t>(node_of_vertex_[k]);
    v[k] = solver_.velocities()[n];
    x[k] = solver_.positions()[n] + v[k] * lag;
  }
  sim::set_surface_vertices(world_, surface_, x, v);
  schedule_.synchronised();
}

// Research notes §1.3: a force held for a period P on a particle–node pair (a two-mass spring
// of Hertz tangent stiffness S_n) is stable only for P < 2/ω, ω = √(S_n / m*), 1/m* = 1/m_p +
// 1/m_node. S_n = 2E*√(R δ) (DESIGN §4) at the Hertz impact overlap for the deck's impact speed V
// (1 m/s if not given): δ = (15 m* V² / (16 E* √R))^(2/5) (Johnson, Contact Mechanics, §11.4).
// The smallest particle and the lightest coupled node give the largest ω. Warned once, with the
// research note's margin P ≤ 0.2 · 2/ω.
void StructureCoupler::check_period_stability() {
  if (stability_checked_ || world_.particles.size() == 0) return;
  stability_checked_ = true;
  const ParticleStore& p = world_.particles;
  std::size_t smallest = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (p.radius[i] < p.radius[smallest]) smallest = i;
  double node_mass = 1e300;  // kg
  for (std::int32_t n : node_of_vertex_) node_mass = std::min(node_mass, solver_.nodal_masses()[static_cast<std::size_t>(n)]);
  const MaterialSpec& particle_material = world_.spec.materials.at(p.material[smallest]);
  const MaterialSpec& wall_material = world_.spec.materials.at(world_.surfaces[surface_].mesh.material);
  const auto compliance = [](const MaterialSpec& m) {
    return (1.0 - m.poisson_ratio.value * m.poisson_ratio.value) / m.youngs_modulus.value;
  };
  const double effective_modulus = 1.0 / (compliance(particle_material) + compliance(wall_material));  // Pa
  const double radius = p.radius[smallest];                                                          // m
  const double effective_mass = 1.0 / (p.inv_mass[smallest] + 1.0 / node_mass);                     // kg
  const double speed = world_.spec.simulation.impact_speed ? world_.spec.simulation.impact_speed->value : 1.0;
  const double overlap = std::pow(15.0 * effective_mass * speed * speed / (16.0 * effective_modulus * std::sqrt(radius)), 0.4);
  const double stiffness = 2.0 * effective_modulus * std::sqrt(radius * overlap);  // N/m
  const double limit = 2.0 / std::sqrt(stiffness / effective_mass);                 // s
  if (schedule_.period() > 0.2 * limit)
    messages_.push_back(fmt::format(
        "warning: coupling PERIOD {:.4g} s is long for the contact stiffness: a particle of radius {:.4g} m on "
        "a node of {:.4g} kg (S_n {:.4g} N/m at {:.3g} m/s) is stable only for PERIOD < 2/ω = {:.4g} s; "
        "use PERIOD ≤ {:.4g} s (research notes §1.3)",
        schedule_.period(), radius, node_mass, stiffness, speed, limit, 0.2 * limit));
}

CouplerState StructureCoupler::state() const {
  return {schedule_.state(), filter_.window(),    filter_.periods(),  pending_impulse_,    loads_,
          structure_dt_,     period_steps_,       period_steps_done_, structure_steps_,    stability_checked_,
          messages_};
}

void StructureCoupler::check_state(const CouplerState& s) const {
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

void StructureCoupler::set_state(CouplerState s) {
  check_state(s);
  schedule_.set_state(s.schedule);
  filter_.set_state(s.filter_window, std::move(s.filter_periods));
  pending_impulse_ = std::move(s.pending_impulse);
  loads_ = std::move(s.loads);
  structure_dt_ = s.structure_dt;
  period_steps_ = s.period_steps;
  period_steps_done_ = s.period_steps_done;
  structure_steps_ = s.structure_steps;
  stability_checked_ = s.stability_checked;
  messages_ = std::move(s.messages);
}

Vec3 StructureCoupler::impulse_in_transit() const {
  Vec3 sum;  // N·s
  for (const Vec3& j : pending_impulse_) sum += j;
  for (const Vec3& j : world_.surfaces[surface_].coupling_window.nodal_impulse) sum += j;
  return sum;
}

}  // namespace quarry::fsi
