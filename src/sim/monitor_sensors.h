// The typed monitors (deck `monitors:` with `type:`), measured once per monitor row, never per
// step: one particle's state, the mass flow through a plane, a box's coarse-grained stress
// (Love–Weber contact sum plus the kinetic part) and a box's binned velocity profile. Each is
// O(particles) or O(contacts) per row.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "sim/frame_contacts.h"
#include "sim/world.h"

namespace quarry::sim {

// Column names of a monitor in monitors.csv (none for a velocity profile, which has a file of
// its own, nor for a mass monitor without a region).
std::vector<std::string> sensor_columns(const MonitorSpec& monitor);

// particle: position (m), velocity (m/s), angular velocity (rad/s) and force (N) of the particle
// with the monitor's id, 12 values; NaN while no particle has that id. Cost: O(n).
void append_particle_values(const World& world, const MonitorSpec& monitor, std::vector<double>& row);

// mass_flow: the net mass (kg) that crossed the plane along its normal since the last row, per
// second of the interval, then the net mass crossed since the start (kg). A particle counts when
// it is on the other side of the plane than at the last row (so a particle that enters and
// leaves the world between two rows is not seen, and one inserted since the last row counts
// from the next). With a `region` (a window: an outlet, one chute of several) the crossings
// were counted step by step (count_window_crossings), which this takes and clears. The first
// row gives 0. Updates `state`. Cost: O(n), O(1) with a window.
void append_mass_flow_values(const World& world, const MonitorSpec& monitor, PlaneCrossingState& state,
                             std::vector<double>& row);

// mass_flow with a `region`: after a step, the particles on the other side of the plane than
// after the step before, counted (kg, ± along the normal, into state.pending_mass) where the
// point of the plane nearest the particle — where it crossed, within one step's travel — lies
// in the region. Pre: monitor.region. Cost: O(n) every step.
void count_window_crossings(const World& world, const MonitorSpec& monitor, PlaneCrossingState& state);

// Coarse-grained stress of a box of volume V (Pa), compression positive, components xx, yy,
// zz, xy, xz, yz (symmetric part). Contact part, Love (1927)–Weber (1966):
//   σc_ab = (1/V) Σ_c f_a l_b  over contacts whose branch midpoint lies in the box,
// f the force on particle i, l the branch vector from j's centre (or the surface contact
// point) to i's centre. Kinetic part (e.g. Weinhart et al., Granular Matter 14 (2012) 289):
//   σk_ab = (1/V) Σ_i m_i v'_a v'_b  over particles whose centre lies in the box,
// v' = v − v̄ the fluctuation about the box's mass-weighted mean velocity v̄.
struct RegionStress {
  std::array<double, 6> contact{}, kinetic{};  // Pa
};
RegionStress region_stress(const World& world, const RegionSpec& box, const std::vector<FrameContact>& contacts);

// velocity_profile: `bins` equal slabs of the box along the axis; per bin the particles whose
// centre lies in it, their mass (kg) and mass-weighted mean velocity (m/s, NaN when empty).
struct VelocityBin {
  double centre = 0.0;  // m: the slab's mid coordinate along the axis
  std::size_t particles = 0;
  double mass = 0.0;    // kg
  Vec3 mean_velocity;   // m/s
};
std::vector<VelocityBin> velocity_profile(const World& world, const MonitorSpec& monitor);
// Columns of a profile file: time_s, bin, position_m, particles, mass_kg, mean_v{x,y,z}_m_s.
std::vector<std::string> velocity_profile_columns();

}  // namespace quarry::sim
