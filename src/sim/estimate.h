// `quarry estimate`: the time step and its limiting particle/material (seed 003), the number of
// steps, and the wall time, from a cost per step calibrated on this machine by a short run of
// the deck's own world timed stage by stage (its hooks, surfaces, factories, neighbour-list
// rebuild rate, output) and by a short run of a dense bed of its particles at rest (the cost per
// particle in contact, which the first steps of a deck still filling or falling cannot show) or,
// where the deck's fluid will carry them, held apart (listed as neighbours, not touching).
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
  int calibration_particles = 0;    // the bed's
  // The deck's fluid carries its particles (fluid_carries_particles): the bed is calibrated
  // held apart, not packed. The inlet's superficial velocity and the largest particles' U_mf.
  bool fluidised = false;
  double inlet_velocity = 0, fluidisation_velocity = 0;  // m/s
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

// The minimum fluidisation velocity (m/s) of spheres of diameter d (m) and density ρ_p in a
// fluid of density ρ_f (kg/m³) and viscosity μ (Pa·s) under gravity g (m/s²), by Wen & Yu
// (1966): Re_mf = √(33.7² + 0.0408 Ar) − 33.7, Ar = ρ_f (ρ_p − ρ_f) g d³ / μ², U_mf =
// Re_mf μ / (ρ_f d). 0 for particles no denser than the fluid.
double minimum_fluidisation_velocity(double fluid_density, double viscosity, double particle_density,
                                     double diameter, double gravity);

// Whether the deck's fluid carries its particles: a velocity inlet whose superficial velocity
// against gravity is above the minimum fluidisation velocity of its hardest particle type to
// lift (the largest U_mf over the types, each at its largest size). Sets `inlet` (the largest
// such inlet velocity, m/s) and `minimum` (that U_mf, m/s).
bool fluid_carries_particles(const SimulationSpec& spec, double& inlet, double& minimum);

// Called on the calibration world before it starts (what `run` attaches beyond build_world:
// the fluid of a fluid: section); what it returns is kept alive while the world runs.
using AttachToWorld = std::function<std::shared_ptr<void>(World&)>;

// Never throws for a deck that `check` accepts: a calibration run that stops on a physics
// error gives the costs of the steps before it.
Estimate estimate_run(const SimulationSpec& spec, const AttachToWorld& attach = {});
std::string format_estimate(const Estimate& e);

}  // namespace quarry::sim
