// Shell solver throughput (issue 17, "Performance"): a clamped square steel plate under uniform
// pressure, n × n Belytschko–Tsay quads (5 Lobatto points through the thickness), stepped at 0.9
// of the stable step. Prints element-steps per second for each thread count, runs interleaved
// (t1, t2, t1, t2, …) so that a busy machine biases neither, and the median of the repeats;
// --kernels 4 8 interleaves the four- and eight-lane batch kernels the same way (same bits).
// --ccx-input writes the same plate as a CalculiX explicit-dynamics deck (S4 shells, which ccx
// expands to one layer of solids) with the same number of steps, for timing `ccx` beside it.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "fem/shell_solver.h"

namespace {

using quarry::Vec3;
using namespace quarry::fem;

constexpr double kSide = 1.0;         // m
constexpr double kThickness = 0.005;  // m
constexpr double kPressure = 1e4;     // Pa
constexpr double kStepFraction = 0.9;

ShellModel plate(int n) {
  ShellModel model;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) model.nodes.push_back({kSide * i / n, kSide * j / n, 0.0});
  const auto id = [n](int i, int j) { return static_cast<std::int32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      model.elements.push_back({{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)}, 4, 0});
  model.sections.push_back({kThickness, 5, ThicknessRule::lobatto, 0});
  model.materials.push_back({210e9, 0.3, 7850.0, 0.0, 0.0});
  BoundaryCondition clamped;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (i == 0 || j == 0 || i == n || j == n) clamped.nodes.push_back(id(i, j));
  clamped.dofs = dof::all;
  model.boundary_conditions.push_back(clamped);
  return model;
}

// FNV-1a over the bytes of the solver's whole state (nodal fields, stresses, resultants, and
// with `energies` the energy sums): equal hashes prove that two builds or thread counts took
// bit-identical steps. Without the energies, the motion alone (a change in how the energies are
// summed changes the first hash, not this one).
std::uint64_t state_hash(const ShellSolverState& s, bool energies = true) {
  std::uint64_t h = 1469598103934665603ull;
  const auto add = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ p[k]) * 1099511628211ull;
  };
  const auto add_vector = [&add](const auto& v) { add(v.data(), v.size() * sizeof(v[0])); };
  add_vector(s.positions), add_vector(s.velocities), add_vector(s.angular_velocities),
      add_vector(s.rotations);
  add_vector(s.internal_force), add_vector(s.reactions), add_vector(s.stress),
      add_vector(s.plastic);
  add_vector(s.shear), add_vector(s.hourglass);
  if (!energies) return h;
  const double sums[] = {s.energies.kinetic,
                             s.energies.internal,
                             s.energies.hourglass,
                             s.energies.damping,
                             s.energies.external_work,
                             s.energies.constraint_work,
                             s.time};
  add(sums, sizeof sums);
  return h;
}

// Seconds for `steps` steps on `threads` threads (the set-up is not timed); `hash` the final
// state's, `motion_hash` the same without the energies.
double time_steps(int n, int steps, int threads, QuadKernel kernel, double& dt,
                  std::uint64_t& hash, std::uint64_t& motion_hash) {
  ShellSolverOptions options;
  options.threading.threads = threads;
  options.quad_kernel = kernel;
  ShellSolver solver(plate(n), options);
  std::vector<NodalLoad> loads(static_cast<std::size_t>(solver.node_count()));
  const double tributary = (kSide / n) * (kSide / n);  // m² per interior node
  for (auto& load : loads) load.force = Vec3{0, 0, -kPressure * tributary};
  solver.set_loads(loads);
  dt = kStepFraction * solver.stable_time_step().time_step;
  solver.step(dt);  // first touch of every array
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) solver.step(dt);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const ShellSolverState state = solver.state();
  hash = state_hash(state);
  motion_hash = state_hash(state, false);
  return seconds;
}

void write_ccx_deck(const std::string& path, int n, int steps, double dt) {
  std::ofstream out(path);
  out << "** Clamped square steel plate under uniform pressure: the shell_plate benchmark's "
         "problem\n"
      << "*NODE, NSET=NALL\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      out << fmt::format("{}, {:.9g}, {:.9g}, 0\n", j * (n + 1) + i + 1, kSide * i / n,
                         kSide * j / n);
  out << "*ELEMENT, TYPE=S4R, ELSET=EALL\n";
  const auto id = [n](int i, int j) { return j * (n + 1) + i + 1; };
  int e = 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      out << fmt::format("{}, {}, {}, {}, {}\n", e++, id(i, j), id(i + 1, j), id(i + 1, j + 1),
                         id(i, j + 1));
  out << "*NSET, NSET=EDGE\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (i == 0 || j == 0 || i == n || j == n) out << id(i, j) << ",\n";
  out << "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850\n"
      << fmt::format("*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL\n{}\n", kThickness)
      << "*BOUNDARY\nEDGE, 1, 6\n"
      << fmt::format("*STEP, INC={}\n*DYNAMIC, EXPLICIT, DIRECT\n{:.9g}, {:.9g}\n", steps + 10, dt,
                     dt * steps)
      << fmt::format("*DLOAD\nEALL, P, {}\n", kPressure)
      << "*NODE PRINT, NSET=NALL, FREQUENCY=100000\nU\n*END STEP\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Shell solver throughput: element-steps per second on a clamped plate"};
  int n = 100, steps = 200, repeats = 3;
  std::vector<int> threads{1, 2};
  std::string ccx_input;
  app.add_option("--n", n, "elements per side (n² quads)")->check(CLI::PositiveNumber);
  app.add_option("--steps", steps, "timed steps per run")->check(CLI::PositiveNumber);
  app.add_option("--repeats", repeats, "runs per thread count (interleaved)")
      ->check(CLI::PositiveNumber);
  app.add_option("--threads", threads, "thread counts");
  std::vector<int> kernel_lanes{fastest_quad_kernel() == QuadKernel::eight_lanes ? 8 : 4};
  app.add_option("--kernels", kernel_lanes,
                 "batch kernels by lanes: 4 (AVX2), 8 (AVX-512); default the fastest here")
      ->check(CLI::IsMember({4, 8}));
  app.add_option("--ccx-input", ccx_input, "also write the same plate as a CalculiX explicit deck");
  CLI11_PARSE(app, argc, argv);
  // Each (kernel, thread count) in turn, repeat after repeat.
  struct Config {
    QuadKernel kernel;
    int threads;
  };
  std::vector<Config> configs;
  for (const int lanes : kernel_lanes) {
    const QuadKernel kernel = lanes == 8 ? QuadKernel::eight_lanes : QuadKernel::four_lanes;
    if (!quad_kernel_available(kernel)) {
      std::printf("QUARRY_SHELL kernel=%d lanes: not available on this processor\n", lanes);
      continue;
    }
    for (const int t : threads) configs.push_back({kernel, t});
  }
  std::vector<std::vector<double>> rates(configs.size());
  std::vector<std::uint64_t> hashes(configs.size()), motion_hashes(configs.size());
  bool repeatable = true;  // every run of a configuration ended in the same state
  double dt = 0.0;
  for (int r = 0; r < repeats; ++r)
    for (std::size_t c = 0; c < configs.size(); ++c) {
      std::uint64_t hash = 0, motion_hash = 0;
      const double seconds =
          time_steps(n, steps, configs[c].threads, configs[c].kernel, dt, hash, motion_hash);
      rates[c].push_back(static_cast<double>(n) * n * steps / seconds);
      if (r > 0 && hash != hashes[c]) repeatable = false;
      hashes[c] = hash;
      motion_hashes[c] = motion_hash;
    }
  for (std::size_t c = 0; c < configs.size(); ++c) {
    std::vector<double> v = rates[c];
    std::sort(v.begin(), v.end());
    std::printf(
        "QUARRY_SHELL elements=%d threads=%d kernel=%d steps=%d dt=%.4g "
        "median_element_steps_per_s=%.4g "
        "min=%.4g max=%.4g state_hash=%016llx motion_hash=%016llx%s\n",
        n * n, configs[c].threads, configs[c].kernel == QuadKernel::eight_lanes ? 8 : 4, steps, dt,
        v[v.size() / 2], v.front(), v.back(), static_cast<unsigned long long>(hashes[c]),
        static_cast<unsigned long long>(motion_hashes[c]), repeatable ? "" : " NOT_REPEATABLE");
  }
  if (!ccx_input.empty()) write_ccx_deck(ccx_input, n, steps, dt);
  return 0;
}
