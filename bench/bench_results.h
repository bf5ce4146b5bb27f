// Benchmark results of the peer comparisons (bench/run.sh: settled bed, bench/run_flowing.sh:
// a pour, bench/run_scenes.sh: a hopper and a drum): one CSV row per timed run of Quarry, LIGGGHTS or LAMMPS; medians per (size, code,
// threads, skin), the markdown summary with the ratios and the physics check, and the
// throughput plot. Not part of the time step.
#pragma once

#include <string>
#include <vector>

#include "io/png_plot.h"

namespace quarry::bench {

// Which reference problem the runs are of: it decides the physics check of the summary.
enum class BenchKind { settled_bed, pour, scene };

// One timed run. Numbers absent from a code's log are NaN.
struct BenchRun {
  std::string date, machine, size, code;  // code: quarry | liggghts | lmp_granular | lmp_ghh
  int threads = 1;                        // OpenMP threads (Quarry) or MPI ranks (peers)
  int repeat = 1;
  double particles = 0;                   // N
  double steps = 0;                       // timed steps
  double loop_seconds = 0;                // s, wall time of the timed steps
  double particle_steps_per_second = 0;   // 1/s, N · steps / loop_seconds
  double coordination = 0;                // 2 × contacting pairs / N (peers' contact/atom sum / N)
  double neighbor_pairs_per_particle = 0; // half-list pairs / N
  double rebuilds = 0;                    // neighbour-list builds during the timed steps
  double peak_rss_kib = 0;                // KiB, GNU time max RSS of the whole process
  double max_height = 0;                  // m, max z of particle centres after the timed steps
  double mean_height = 0;                 // m, mean z of particle centres
  double floor_force = 0;                 // N, vertical force of the particles on the floor
  double weight = 0;                      // N, Σ m g
  double other_load = 0;                  // cores used by other processes during the run
  // Columns of the flowing benchmarks (NaN when a file has none):
  double skin = 0;                        // m, neighbour skin
  double kinetic_energy = 0;              // J per particle, translation + rotation, at the end
  double neighbor_share = 0;              // neighbour stage / loop time (the code's own timers)
  // Columns of the scenes (bench/run_scenes.sh), means over the run's second half:
  double discharge_rate = 0;              // kg/s out of the hopper (NaN for the drum)
  double rising_fraction = 0;             // the drum's mass on its rising side / all (NaN for the hopper)
};

// The CSV header the harness writes: the settled bed's columns; the pour adds skin, ke_pp and
// neigh_share at the end, the scenes these and discharge_kg_s, rising_fraction.
std::string bench_csv_header(BenchKind kind = BenchKind::settled_bed);
// Parses the CSV text (header line first; columns found by name, so added columns are
// tolerated; the pour's columns may be absent). Throws std::runtime_error naming the line of a malformed row.
std::vector<BenchRun> read_bench_csv(const std::string& text);

// Median of the values that are finite (NaN if none). Even count: mean of the middle two.
double median_of(std::vector<double> values);

// Medians over the repeats of one (size, code, threads).
struct BenchGroup {
  std::string size, code;
  int threads = 1;
  double skin = 0;                                       // m (NaN: not recorded)
  double particles = 0;
  int runs = 0;
  double median_rate = 0, min_rate = 0, max_rate = 0;  // particle-steps/s
  double coordination = 0, neighbor_pairs_per_particle = 0, rebuilds = 0;
  double peak_rss_kib = 0;                               // largest over the runs (KiB)
  double max_height = 0, mean_height = 0, floor_force = 0, weight = 0;  // m, m, N, N
  double other_load = 0;                                 // mean over the runs (cores)
  double kinetic_energy = 0, neighbor_share = 0;         // J per particle, 1
  double discharge_rate = 0, rising_fraction = 0;        // kg/s, 1
};
// Groups sorted by N, then code (quarry, liggghts, lmp_granular, lmp_ghh), then threads, then
// skin.
std::vector<BenchGroup> summarize_runs(const std::vector<BenchRun>& runs);

// Relative difference (a − b) / |b|.
double relative_difference(double a, double b);

// The markdown summary: medians, Quarry/peer ratios, 2-thread speed-up, contacts and memory
// per particle (total and marginal between sizes), and the physics check of Quarry against
// each peer within `tolerance` (default 1 %): the settled bed's packing height and floor
// force, or the pour's mean height (its kinetic energy, top and floor force are reported), or
// the scenes' discharge rate and rising share (within `tolerance`, with the peer's own spread
// between its 1- and 2-rank runs shown beside). The flowing summaries also show the skin, the
// neighbour stage's share and each code's best skin.
std::string bench_markdown(const std::vector<BenchRun>& runs, const std::string& heading,
                           double tolerance = 0.01, BenchKind kind = BenchKind::settled_bed);

// Particle-steps per second (millions) against log10 N, one series per code and thread count;
// against the thread count for one N or for the scenes (a series per scene and code).
PlotSpec throughput_plot(const std::vector<BenchGroup>& groups, const std::string& title,
                         BenchKind kind = BenchKind::settled_bed);

}  // namespace quarry::bench
