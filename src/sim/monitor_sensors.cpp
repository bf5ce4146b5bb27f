// Typed monitors: particle, mass flow through a plane, region stress, velocity profile.
#include "sim/monitor_sensors.h"

#include <cmath>
#include <limits>

#include "insert/region.h"

namespace quarry::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kStressComponents[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
constexpr int kRow[6] = {0, 1, 2, 0, 0, 1}, kColumn[6] = {0, 1, 2, 1, 2, 2};

double box_volume(const RegionSpec& box) {
  const Vec3 size = box.max.value - box.min.value;  // m
  return size.x * size.y * size.z;                  // m³
}

}  // namespace

std::vector<std::string> sensor_columns(const MonitorSpec& monitor) {
  const std::string& name = monitor.name.value;
  std::vector<std::string> columns;
  switch (monitor.kind.value) {
    case MonitorKind::mass:
      if (monitor.region) columns.push_back(name + "_mass_kg");
      break;
    case MonitorKind::particle:
      for (const char* q : {"x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s", "wx_rad_s", "wy_rad_s", "wz_rad_s",
                            "Fx_N", "Fy_N", "Fz_N"})
        columns.push_back(name + "_" + q);
      break;
    case MonitorKind::mass_flow:
      columns.push_back(name + "_mass_flow_kg_s");
      columns.push_back(name + "_crossed_mass_kg");
      break;
    case MonitorKind::stress:
      if (!monitor.region) break;  // as monitor_row: no box, no columns
      for (const char* part : {"contact", "kinetic"})
        for (const char* component : kStressComponents)
          columns.push_back(name + "_" + part + "_s" + component + "_Pa");
      break;
    case MonitorKind::velocity_profile:
      break;
  }
  return columns;
}

void append_particle_values(const World& world, const MonitorSpec& monitor, std::vector<double>& row) {
  const ParticleStore& p = world.particles;
  const auto id = static_cast<ParticleId>(monitor.particle_id.value);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] != id) continue;
    for (const Vec3& v : {p.position[i], p.velocity[i], p.angular_velocity[i], p.force[i]})
      row.insert(row.end(), {v.x, v.y, v.z});
    return;
  }
  row.insert(row.end(), 12, kNaN);
}

namespace {

// Which side of a mass-flow plane a particle is on, and whether it crossed since it was last seen.
// A plane perpendicular to a periodic axis (the deck allows no tilted one across it): a particle
// that wraps from max to min has not crossed it, one that moves across it has. The period, seen
// from the plane, is cut in quarters by the phase φ = frac((x − x_plane)/L); the quarter is
// stored as 1, 2 (φ < 1/2) and −2, −1 (φ ≥ 1/2), and only the step from the last quarter to the
// first (+) or back (−) is a crossing: wrapping leaves φ unchanged. Holds while no particle moves
// more than L/4 between two looks. Elsewhere the side is ±1 (+: on the normal's side).
class PlaneSides {
 public:
  PlaneSides(const World& world, const MonitorSpec& monitor)
      : point_(monitor.point.value), normal_(monitor.normal.value), periodic_(world.pairs.periodic) {
    for (int a = 0; a < 3; ++a)
      if (periodic_.wraps[a] && normal_[a] != 0.0) axis_ = a;
    if (axis_ >= 0) direction_ = normal_[axis_] > 0.0 ? 1.0 : -1.0;
  }

  std::int8_t side(const Vec3& x) const {
    if (axis_ < 0) return dot(x - point_, normal_) >= 0.0 ? 1 : -1;
    const double phase = (x[axis_] - point_[axis_]) * periodic_.inverse_period[axis_];  // periods
    const double quarter = std::floor(4.0 * (phase - std::floor(phase)));  // 0..3 (4: rounding)
    return quarter < 1.0 ? 1 : quarter < 2.0 ? 2 : quarter < 3.0 ? -2 : -1;
  }

  // +1 crossed along the normal, −1 against it, 0 not crossed (or not seen before: last 0).
  double crossing(std::int8_t last, std::int8_t side) const {
    if (axis_ < 0) return last != 0 && last != side ? side : 0.0;
    if (last == -1 && side == 1) return direction_;
    if (last == 1 && side == -1) return -direction_;
    return 0.0;
  }

  // The point of the plane nearest x (m): where a particle seen on both sides in consecutive
  // steps crossed it, within one step's travel.
  Vec3 foot(const Vec3& x) const {
    const Vec3 unit = normal_ / std::sqrt(dot(normal_, normal_));
    return x - unit * dot(x - point_, unit);
  }

 private:
  Vec3 point_, normal_;
  const PeriodicBox& periodic_;
  int axis_ = -1;
  double direction_ = 1.0;
};

}  // namespace

void count_window_crossings(const World& world, const MonitorSpec& monitor, PlaneCrossingState& state) {
  const ParticleStore& p = world.particles;
  const PlaneSides plane(world, monitor);
  const Region window(*monitor.region);
  if (state.side_by_id.size() < world.next_id) state.side_by_id.resize(world.next_id, 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::int8_t side = plane.side(p.position[i]);
    std::int8_t& last = state.side_by_id[p.id[i]];
    const double crossed = plane.crossing(last, side);
    if (crossed != 0.0 && window.contains(world.pairs.periodic.wrapped(plane.foot(p.position[i]))))
      state.pending_mass += crossed / p.inv_mass[i];
    last = side;
  }
}

void append_mass_flow_values(const World& world, const MonitorSpec& monitor, PlaneCrossingState& state,
                             std::vector<double>& row) {
  double crossed = 0.0;  // kg, net along the normal since the last row
  if (monitor.region) {  // counted step by step (count_window_crossings)
    crossed = state.pending_mass;
    state.pending_mass = 0.0;
  } else {
    const ParticleStore& p = world.particles;
    const PlaneSides plane(world, monitor);
    if (state.side_by_id.size() < world.next_id) state.side_by_id.resize(world.next_id, 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::int8_t side = plane.side(p.position[i]);
      std::int8_t& last = state.side_by_id[p.id[i]];
      crossed += plane.crossing(last, side) / p.inv_mass[i];
      last = side;
    }
  }
  const double interval = world.time - state.last_time;  // s
  row.push_back(state.started && interval > 0.0 ? crossed / interval : 0.0);
  state.crossed_mass += crossed;
  row.push_back(state.crossed_mass);
  state.last_time = world.time;
  state.started = true;
}

RegionStress region_stress(const World& world, const RegionSpec& box, const std::vector<FrameContact>& contacts) {
  const Region region(box);
  const double volume = box_volume(box);  // m³
  const PeriodicBox& periodic = world.pairs.periodic;
  RegionStress stress;
  for (const FrameContact& c : contacts) {
    // A branch across a periodic face has its midpoint a little outside the period: wrapped in.
    if (!region.contains(periodic.wrapped(0.5 * (c.line.from + c.line.to)))) continue;
    const Vec3 force = c.line.normal_force + c.line.tangential_force;  // N on i
    const Vec3 branch = c.line.from - c.line.to;                        // m, towards i
    for (int k = 0; k < 6; ++k)
      stress.contact[k] += 0.5 * (force[kRow[k]] * branch[kColumn[k]] + force[kColumn[k]] * branch[kRow[k]]);
  }
  const ParticleStore& p = world.particles;
  double mass = 0.0;  // kg
  Vec3 momentum;      // kg·m/s
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed(i) || !region.contains(periodic.wrapped(p.position[i])))
      continue;  // fixed: infinite mass, at rest
    mass += 1.0 / p.inv_mass[i];
    momentum += p.velocity[i] / p.inv_mass[i];
  }
  const Vec3 mean = mass > 0.0 ? momentum / mass : Vec3{};  // m/s
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed(i) || !region.contains(periodic.wrapped(p.position[i])))
      continue;                                     // fixed: infinite mass, at rest
    const Vec3 fluctuation = p.velocity[i] - mean;  // m/s
    for (int k = 0; k < 6; ++k) stress.kinetic[k] += fluctuation[kRow[k]] * fluctuation[kColumn[k]] / p.inv_mass[i];
  }
  for (int k = 0; k < 6; ++k) stress.contact[k] /= volume, stress.kinetic[k] /= volume;
  return stress;
}

std::vector<VelocityBin> velocity_profile(const World& world, const MonitorSpec& monitor) {
  const RegionSpec& box = *monitor.region;
  const Region region(box);
  const PeriodicBox& periodic = world.pairs.periodic;
  const int axis = static_cast<int>(monitor.axis.value);
  const auto bins = static_cast<std::size_t>(monitor.bins.value);
  const double lower = box.min.value[axis], width = (box.max.value[axis] - lower) / static_cast<double>(bins);  // m
  std::vector<VelocityBin> profile(bins);
  std::vector<Vec3> momentum(bins);  // kg·m/s
  for (std::size_t b = 0; b < bins; ++b) profile[b].centre = lower + (static_cast<double>(b) + 0.5) * width;
  const ParticleStore& p = world.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed(i) || !region.contains(periodic.wrapped(p.position[i])))
      continue;  // fixed: infinite mass, at rest
    const double s = std::floor((periodic.wrapped(p.position[i])[axis] - lower) / width);
    const std::size_t b = s < 0.0 ? 0 : std::min(bins - 1, static_cast<std::size_t>(s));
    profile[b].particles += 1;
    profile[b].mass += 1.0 / p.inv_mass[i];
    momentum[b] += p.velocity[i] / p.inv_mass[i];
  }
  for (std::size_t b = 0; b < bins; ++b)
    profile[b].mean_velocity = profile[b].mass > 0.0 ? momentum[b] / profile[b].mass : Vec3{kNaN, kNaN, kNaN};
  return profile;
}

std::vector<std::string> velocity_profile_columns() {
  return {"time_s", "bin", "position_m", "particles", "mass_kg", "mean_vx_m_s", "mean_vy_m_s", "mean_vz_m_s"};
}

}  // namespace quarry::sim
