// Choice of the time step (DESIGN §4, seed 003): Rayleigh time step of the smallest particle of
// each type, dt = fraction × min T_R (or the deck's fixed dt), and the check that the Hertz
// contact time at the expected impact speed spans ≥ 10 steps (error below 6).
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/simulation_spec.h"

namespace quarry {

struct TimeStepChoice {
  double rayleigh_time = 0.0;         // s, smallest over particle types (T_R)
  std::string rayleigh_limiter;       // "type 'fine' (material 'ore', R = 2 mm)"
  double hertz_time = 0.0;            // s, shortest contact time at the impact speed (T_h)
  std::string hertz_limiter;          // "ore–steel wall, R = 2 mm"
  double impact_speed = 0.0;          // m/s used for T_h
  double dt = 0.0;                    // s
  bool fixed = false;                 // dt given in the deck
  double steps_per_contact = 0.0;     // T_h / dt
  // Hertz peak overlap of the softest impact at impact_speed, over the smaller radius (1), and
  // the contact it is for; compared with simulation.max_overlap_fraction (a warning above it).
  double peak_overlap_fraction = 0.0;
  std::string peak_overlap_limiter;
  // Hertz static overlap over the radius (1) of the largest moving particle at rest under its
  // weight, on a surface or on another of its kind (the worst), and that contact; an error at
  // simulation.gravity above the overlap guard. Zero without surfaces.
  double resting_overlap_fraction = 0.0;
  std::string resting_overlap_limiter;
  // The heaviest particle the deck's moving types can hold (kg; its largest radius) and its
  // type: the overlap guard asks whether it could have pressed a pair as far as it finds it.
  double heaviest_mass = 0.0;
  std::string heaviest_type;
  std::vector<Diagnostic> problems;   // warnings (< 10 steps) and errors (< 6 steps)
};

// The fastest vertex of the deck's prescribed surface motions (max_vertex_speed over the
// surfaces) and its surface: a wall moving at V meets a particle falling at v at up to v + V.
struct FastestSurface {
  double speed = 0.0;  // m/s
  std::string name;
};

// Computes the choice; problems are returned, not thrown (check prints them, run throws).
// Without a deck impact_speed the expected one is estimated, `fastest`'s speed added (it is
// known once the surfaces are built: World::fastest_surface). The step does not depend on it.
TimeStepChoice choose_time_step(const SimulationSpec& spec, const FastestSurface& fastest = {});

// The choice's problems of one severity at their deck locations (`check` prints the warnings).
Diagnostics problems_of(const TimeStepChoice& choice, Severity severity);
// Throws the choice's errors together as one UserError; nothing if it has none.
void throw_time_step_errors(const TimeStepChoice& choice);

}  // namespace quarry
