// `quarry estimate`: the time step and its limiting particle/material (seed 003), the number of
// steps, and the wall time, calibrated by a short timed run of a dense bed of the deck's own
// smallest particles on this machine.
#pragma once

#include <string>

#include "core/simulation_spec.h"

namespace quarry::sim {

struct Estimate {
  double rayleigh_time = 0, hertz_time = 0, dt = 0, impact_speed = 0;  // s, s, s, m/s
  std::string rayleigh_limiter, hertz_limiter;
  double steps = 0;                 // to the end time
  double particle_steps = 0;        // Σ over steps of the expected particle count
  double peak_particles = 0;        // expected
  double seconds_per_particle_step = 0;  // s, measured
  int calibration_particles = 0;
  double wall_seconds = 0;          // s, estimate
};

Estimate estimate_run(const SimulationSpec& spec);
std::string format_estimate(const Estimate& e);

}  // namespace quarry::sim
