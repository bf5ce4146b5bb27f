// The peer-comparison reference problem (issue 3): a jittered cubic lattice of 2 mm spheres in a
// closed box of six plane walls, settled under gravity, then timed. Identical physics to the
// LIGGGHTS/LAMMPS inputs in bench/peers/ (common.in, model_*.lig|lmp).
#pragma once

#include <cstdint>
#include <string>

#include "core/simulation_spec.h"
#include "sim/world.h"

namespace quarry::bench {

struct LammpsData;  // bench/lammps_data.h

// Geometry and numerics of the reference problem; the defaults are the peers' values.
struct SettledBedParameters {
  int cells_x = 20, cells_y = 20, cells_z = 25;  // lattice sites per direction (N = product)
  double lattice_spacing = 2.1e-3;               // m (peers: a)
  double jitter = 4.0e-5;                        // m, uniform ± per coordinate (peers: jit)
  double particle_radius = 1.0e-3;               // m (d = 2 mm)
  double density = 2500.0;                       // kg/m³
  double youngs_modulus = 5.0e6;                 // Pa
  double poisson_ratio = 0.3;                    // 1
  double restitution = 0.5;                      // 1
  double friction = 0.5;                         // 1
  double time_step = 1.0e-5;                     // s
  double skin = 2.0e-4;                          // m (0.1 d)
  std::uint64_t seed = 4711;                     // jitter stream
  double lift = 0.0;  // m, the lattice raised above the floor (> 0: a pour, bench/run_flowing.sh)
  double max_overlap_fraction = 0.1;             // the overlap guard (the peers have none)

  std::size_t particle_count() const {
    return static_cast<std::size_t>(cells_x) * cells_y * cells_z;
  }
  // Box: [0, nx·a] × [0, ny·a] × [0, (nz+2)·a + lift] (m); the top wall 2 spacings above the
  // lattice.
  Vec3 box_max() const {
    return {cells_x * lattice_spacing, cells_y * lattice_spacing, (cells_z + 2) * lattice_spacing + lift};
  }
};

// Surface indices in the world (six planes, walls facing inward), floor first.
enum WallIndex : int { floor_wall = 0, top_wall, x_low_wall, x_high_wall, y_low_wall, y_high_wall };

// The simulation spec of the problem, made in code: one material, Hertz-Mindlin with history,
// no rolling friction, fixed dt, the given skin, six planes of the particle material.
SimulationSpec settled_bed_spec(const SettledBedParameters& parameters);

// Builds the world and places the jittered lattice (particles at rest at (i + ½)·a + jitter,
// raised by `lift` along z, ids 1..N) directly into world.particles; marks the lists stale.
// Deterministic for a seed.
World make_lattice_world(const SettledBedParameters& parameters);

// Replaces the particles of a world fresh from make_lattice_world (before prepare_first_step:
// no lists, no contact history yet) by a LAMMPS data file's, so that Quarry starts from the
// bed the peers start from: same atom-IDs, radius = diameter / 2, mass from the density,
// velocities and angular velocities as written (SI). Throws UserError unless the file holds
// exactly the lattice's particle count, has the same box, one atom type, no sphere larger than
// the spec's (the neighbour grid is sized for it) and every centre inside the box.
void replace_particles(World& world, const SettledBedParameters& parameters, const LammpsData& data);

// The world's particles as a LAMMPS data file's atoms (atom-type 1, box [0, box_max]), for
// lammps_data_text: how the flowing benchmarks give every code the same starting lattice.
LammpsData to_lammps_data(const World& world, const SettledBedParameters& parameters);

// First force evaluation on a freshly placed or loaded state (what sim::run does before its
// loop): rebuilds every list, computes forces. Call before stepping.
void prepare_first_step(World& world);

// Kinetic energy (translational + rotational) per particle (J).
double kinetic_energy_per_particle(const World& world);

// Measurements of the settled state that the peers' logs also report.
struct BedState {
  double max_height = 0.0;         // m, max z of particle centres
  double mean_height = 0.0;        // m, mean z of particle centres
  double floor_force = 0.0;        // N, vertical force the particles exert on the floor (down > 0)
  double all_walls_force_z = 0.0;  // N, vertical force on all six walls together (down > 0)
  double weight = 0.0;             // N, Σ m g
  double contact_pairs = 0.0;      // particle pairs with overlap > 0
  double neighbor_pairs = 0.0;     // pairs in the Verlet list
};
// Reads the state after a force evaluation (the wall totals are those of the last step).
BedState measure_bed(const World& world);

// Peak resident set size of this process so far (bytes).
double peak_rss_bytes();

// The benchmark binaries' result line "QUARRY_BENCH key=value ..." (bench/lib.sh,
// parse_run_log, reads it) for `steps` timed steps on `threads` threads that took
// `loop_seconds` (s) and `rebuilds` list builds: throughput, contacts, memory, the bed's
// measurements, kinetic energy per particle and the neighbour stage's share of the loop.
std::string bench_result_line(const World& world, int threads, long steps, double loop_seconds,
                              std::uint64_t rebuilds);

}  // namespace quarry::bench
