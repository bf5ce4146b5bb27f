// Monitor quantities and plots; the typed monitors' measurements are in monitor_sensors.cpp.
#include "sim/monitors.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "insert/region.h"
#include "io/png_plot.h"
#include "sim/monitor_sensors.h"

namespace quarry::sim {

namespace {
bool rotating(const WorldSurface& s) {
  return s.driver.kind == SurfaceDriverKind::prescribed && s.driver.motion.kind.value == MotionKind::rotation;
}

// The memory of the deck's mass-flow monitor number `flow` (in deck order), made at first use.
PlaneCrossingState& flow_state(World& world, std::size_t flow) {
  if (world.plane_crossings.size() <= flow) world.plane_crossings.resize(flow + 1);
  return world.plane_crossings[flow];
}
}  // namespace

double torque_about_axis(const Vec3& torque_about_origin, const Vec3& force, const Vec3& axis_point,
                         const Vec3& axis_direction) {
  const double length = norm(axis_direction);
  if (!(length > 0.0)) return 0.0;
  // T_p = sum (x - p) x f = T_O - p x F; its component along the unit axis.
  return dot(torque_about_origin - cross(axis_point, force), axis_direction / length);
}

std::vector<std::string> monitor_columns(const World& world, std::size_t surface_count) {
  std::vector<std::string> c = {"time_s", "particles", "kinetic_energy_J", "mean_speed_m_s",
                                "mean_vx_m_s", "mean_vy_m_s", "mean_vz_m_s", "contacts",
                                "particle_contacts", "removed_outside"};
  for (std::size_t s = 0; s < surface_count; ++s)
    for (const char* q : {"Fx_N", "Fy_N", "Fz_N", "F_N", "Tx_Nm", "Ty_Nm", "Tz_Nm"})
      c.push_back(world.surfaces[s].mesh.name + "_" + q);
  for (std::size_t s = 0; s < surface_count; ++s)
    if (rotating(world.surfaces[s])) c.push_back(world.surfaces[s].mesh.name + "_T_axis_Nm");
  for (const auto& m : world.spec.monitors)
    for (std::string& column : sensor_columns(m)) c.push_back(std::move(column));
  return c;
}

std::vector<double> monitor_row(World& world, std::size_t surface_count) {
  const ParticleStore& p = world.particles;
  double kinetic = 0.0, speed = 0.0;  // J, m/s
  Vec3 velocity;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed(i)) continue;  // at rest, of infinite mass: no kinetic energy to add
    const double m = 1.0 / p.inv_mass[i];
    kinetic += 0.5 * m * norm2(p.velocity[i]) + 0.5 / p.inv_inertia(i) * norm2(p.angular_velocity[i]);
    speed += norm(p.velocity[i]);
    velocity += p.velocity[i];
  }
  const double n = static_cast<double>(p.size());
  if (n > 0) speed /= n, velocity /= n;
  const auto pairs = static_cast<double>(world.pair_contact_count());
  std::vector<double> row = {world.time, n, kinetic, speed, velocity.x, velocity.y, velocity.z,
                             pairs + static_cast<double>(world.wall_contact_count()), pairs,
                             static_cast<double>(world.removed_outside)};
  for (std::size_t s = 0; s < surface_count; ++s) {
    const Vec3 f = world.surfaces[s].mesh.total_force, t = world.surfaces[s].mesh.total_torque;
    for (double v : {f.x, f.y, f.z, norm(f), t.x, t.y, t.z}) row.push_back(v);
  }
  for (std::size_t s = 0; s < surface_count; ++s) {
    const WorldSurface& surface = world.surfaces[s];
    if (!rotating(surface)) continue;
    const MotionSpec& motion = surface.driver.motion;
    row.push_back(torque_about_axis(surface.mesh.total_torque, surface.mesh.total_force, motion.axis_point.value,
                                    motion.axis_direction.value));
  }
  std::vector<FrameContact> contacts;  // gathered once for the stress monitors, if any
  bool contacts_gathered = false;
  std::size_t flow = 0;  // index of the next mass-flow monitor's state
  for (const auto& m : world.spec.monitors) {
    switch (m.kind.value) {
      case MonitorKind::mass: {
        if (!m.region) break;
        const Region region(*m.region);
        double mass = 0.0;  // kg
        for (std::size_t i = 0; i < p.size(); ++i)
          if (!p.fixed(i) && region.contains(world.pairs.periodic.wrapped(p.position[i])))
            mass += 1.0 / p.inv_mass[i];  // fixed: infinite
        row.push_back(mass);
        break;
      }
      case MonitorKind::particle:
        append_particle_values(world, m, row);
        break;
      case MonitorKind::mass_flow:
        append_mass_flow_values(world, m, flow_state(world, flow++), row);
        break;
      case MonitorKind::stress: {
        if (!m.region) break;  // the deck requires the box; a spec made in code may lack it
        if (!contacts_gathered) contacts = frame_contacts(world), contacts_gathered = true;
        const RegionStress stress = region_stress(world, *m.region, contacts);
        row.insert(row.end(), stress.contact.begin(), stress.contact.end());
        row.insert(row.end(), stress.kinetic.begin(), stress.kinetic.end());
        break;
      }
      case MonitorKind::velocity_profile:
        break;  // a file of its own (Output)
    }
  }
  return row;
}

void count_flow_windows(World& world) {
  std::size_t flow = 0;  // index of the mass-flow monitor's state, as in monitor_row
  for (const MonitorSpec& m : world.spec.monitors) {
    if (m.kind.value != MonitorKind::mass_flow) continue;
    if (m.region) count_window_crossings(world, m, flow_state(world, flow));
    ++flow;
  }
}

PlotSeries column_series(const std::vector<std::vector<double>>& rows, std::size_t k,
                         const std::string& label) {
  PlotSeries s;
  s.label = label;
  for (const auto& r : rows) {
    s.x.push_back(r[0]);
    s.y.push_back(r[k]);
  }
  return s;
}

std::vector<double> outflow_rate(const std::vector<double>& t, const std::vector<double>& m, std::size_t half_window) {
  const std::size_t n = std::min(t.size(), m.size());
  std::vector<double> rate(n, NAN);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k >= half_window ? k - half_window : 0;
    const std::size_t b = std::min(n - 1, k + half_window);
    if (t[b] > t[a]) rate[k] = -(m[b] - m[a]) / (t[b] - t[a]);
  }
  return rate;
}

std::vector<std::string> write_monitor_plots(const std::string& directory, const std::vector<std::string>& columns,
                                             const std::vector<std::vector<double>>& rows, double gravity) {
  namespace fs = std::filesystem;
  std::vector<std::string> written;
  const auto plot = [&](const std::string& file, const PlotSpec& spec) {
    write_line_plot_png(fs::path(directory) / file, spec);
    written.push_back(file);
  };
  const auto index_of = [&](const std::string& name) {
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (columns[k] == name) return k;
    return columns.size();
  };
  PlotSpec forces{"Force on each surface", "time (s)", "|F| (N)", {}};
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k].ends_with("_F_N"))
      forces.series.push_back(column_series(rows, k, columns[k].substr(0, columns[k].size() - 4)));
  // The reference: a bed at rest carries the weight of what lies in it (m g of the monitor
  // region that holds the bed's load); impacts rise above it, arching and walls below it.
  if (!forces.series.empty())
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (columns[k].ends_with("_mass_kg")) {
        PlotSeries weight = column_series(rows, k, "weight m g in " + columns[k].substr(0, columns[k].size() - 8));
        for (double& y : weight.y) y *= gravity;
        forces.series.push_back(weight);
      }
  if (!forces.series.empty()) plot("surface_forces.png", forces);

  PlotSpec torques{"Torque on each rotating surface about its rotation axis", "time (s)", "torque (N m)", {}};
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k].ends_with("_T_axis_Nm"))
      torques.series.push_back(column_series(rows, k, columns[k].substr(0, columns[k].size() - 10) + " about its axis"));
  if (!torques.series.empty()) plot("surface_torques.png", torques);

  PlotSpec speed{"Mean particle speed", "time (s)", "speed (m/s)",
                 {column_series(rows, index_of("mean_speed_m_s"), "mean speed")}};
  plot("mean_speed.png", speed);

  PlotSpec count{"Particles in the simulation", "time (s)", "count",
                 {column_series(rows, index_of("particles"), "particles")}};
  plot("particle_count.png", count);

  PlotSpec energy{"Kinetic energy", "time (s)", "energy (J)",
                  {column_series(rows, index_of("kinetic_energy_J"), "kinetic energy")}};
  plot("kinetic_energy.png", energy);

  PlotSpec masses{"Mass in monitor regions", "time (s)", "mass (kg)", {}};
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k].ends_with("_mass_kg"))
      masses.series.push_back(column_series(rows, k, columns[k].substr(0, columns[k].size() - 8)));
  if (!masses.series.empty()) plot("region_mass.png", masses);

  // The discharge rate of a hopper: -dm/dt of the mass in its region, over +-2 monitor rows.
  PlotSpec flows{"Net outflow from monitor regions (-dm/dt; negative while filling)", "time (s)", "outflow (kg/s)", {}};
  for (PlotSeries m : masses.series) {
    m.y = outflow_rate(m.x, m.y, 2);
    flows.series.push_back(m);
  }
  if (!flows.series.empty() && rows.size() >= 2) plot("region_outflow.png", flows);
  return written;
}

}  // namespace quarry::sim
