// `quarry estimate`: the time step and its limiting particle/material (seed 003), the number of
// steps, and the wall time, from a cost per step calibrated on this machine by a short run of
// the deck's own world timed stage by stage (its hooks, surfaces, factories, neighbour-list
// rebuild rate, output) and by a short run of a dense bed of its particles at rest (the cost per
// particle in contact, which the first steps of a deck still filling or falling cannot show).
// Takes about 3-4 s.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/simulation_spec.h"
#include "sim/world.h"

namespace quarry::sim {

struct Estimate {
  double rayleigh_time = 0, hertz_time = 0, dt = 0, impact_speed = 0;  // s, s, s, m/s
  std::string rayleigh_limiter, hertz_limiter;
  double steps = 0;                 // to the end time
  double particle_steps = 0;        // Σ over steps of the expected particle count
  double peak_particles = 0;        // expected
  // Cost per step = seconds_per_step + seconds_per_particle_step × particles (s, measured).
  double seconds_per_step = 0;
  double seconds_per_particle_step = 0;
  double rebuild_fraction = 0;      // of the deck's calibration steps (weighted by particles)
  double deck_steps = 0, deck_particles = 0, deck_seconds = 0;  // the deck's own calibration run
  int calibration_particles = 0;    // the dense bed's
  double insert_seconds = 0;        // s: the factories' insertions after the calibration's start
  double frames = 0;                // frames after the first
  double output_seconds = 0;        // s: frames, the end of the run (export decks, plots)
  int threads = 1;                  // OpenMP threads the calibration ran with
  double wall_seconds = 0;          // s, estimate
};

// Least squares t = a + b n over a calibration's steps (counts n: particles; seconds t: their
// particle stages' time, s): the part a (s per step) that does not grow with the particles (the
// surfaces' loads cleared and summed, the loops' set-up). 0 unless the counts span at least a
// quarter of their largest value over at least 20 steps and the fit gives a ≥ 0, b ≥ 0.
double particle_stage_fit(const std::vector<double>& counts, const std::vector<double>& seconds);

// Called on the calibration world before it starts (what `run` attaches beyond build_world:
// the fluid of a fluid: section); what it returns is kept alive while the world runs.
using AttachToWorld = std::function<std::shared_ptr<void>(World&)>;

// Never throws for a deck that `check` accepts: a calibration run that stops on a physics
// error gives the costs of the steps before it.
Estimate estimate_run(const SimulationSpec& spec, const AttachToWorld& attach = {});
std::string format_estimate(const Estimate& e);

}  // namespace quarry::sim
