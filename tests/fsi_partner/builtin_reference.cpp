// The built-in path of the external-partner agreement test (partner_agreement_test.sh): the same
// case as shell_partner.cpp, from a deck whose structures: section names the plate, run as
// `quarry run` and quarry_open run it — the world built, the structures attached
// (fsi::CoupledStructures: the coupling surface, the shell solver, the StructureCoupler on the
// world's end-of-step hooks), started, then stepped — in one process, no C ABI. It steps to
// the first exchange at or after the deck's end_time, as the partner does, and writes the same
// report. It also checks that the run means something: every bead reached the plate and the
// plate moved.
// Usage: builtin_reference DECK REPORT. Exit 0: done and the checks hold; 1: a check failed or
// the run could not be made (message on stderr).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/diagnostics.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_coupler.h"
#include "fsi/structure_run.h"
#include "fsi_partner/coupling_report.h"
#include "io/deck.h"
#include "sim/step.h"

namespace {

using namespace quarry;

int run(const std::string& deck, const std::string& report_path) {
  World world = build_world(parse_deck(deck));
  std::ostringstream log;
  fsi::CoupledStructures structures(world, log);
  sim::initialize(world);
  if (structures.size() != 1) throw std::runtime_error("the deck must have one structures: entry");
  const fem::ShellSolver& solver = structures.solver(0);
  const fsi::StructureCoupler& coupler = structures.coupler(0);
  // The plate's initial nodes, for its displacements (the solver's nodes are the model's).
  const fsi::CoupledStructure structure = fsi::read_coupled_structure(world.spec.structures.front().model.value);
  const double end = world.spec.simulation.end_time.value;  // s

  // The beads' downward momentum at the start (N·s).
  const ParticleStore& p = world.particles;
  double momentum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) momentum -= p.velocity[i].z / p.inv_mass[i];

  quarry_partner::CouplingReport report;
  double impulse = 0.0, peak = 0.0;  // N·s downward on the plate, m the largest nodal displacement
  // Step by step, as the run loop does; a step that ends at a sync point has exchanged (the
  // coupler's end-of-step hook), and the run ends at the first exchange at or after `end`.
  while (world.time < end - 1e-6 * world.dt) {
    const std::int64_t syncs = coupler.schedule().synchronisations();
    do {
      sim::step(world);
    } while (coupler.schedule().synchronisations() == syncs);
    quarry_partner::Sync s;
    s.time = world.time;
    Vec3 sum;  // N
    std::uint64_t hash = quarry_partner::kFnvOffset;
    for (const fem::NodalLoad& l : coupler.loads()) {
      sum += l.force;
      hash = quarry_partner::fnv1a(hash, &l, sizeof l);
    }
    s.load = {sum.x, sum.y, sum.z};
    s.loads_hash = hash;
    report.history.push_back(s);
    // Each period's loads act for the structure's next period, whose length is its steps × dt.
    impulse -= sum.z * static_cast<double>(coupler.schedule().steps_to_sync(solver.time(), coupler.structure_step())) *
               coupler.structure_step();
    for (int n = 0; n < solver.node_count(); ++n) {
      const Vec3 u = solver.positions()[static_cast<std::size_t>(n)] - structure.adapted.model.nodes[static_cast<std::size_t>(n)];
      peak = std::max(peak, std::sqrt(dot(u, u)));
    }
  }
  for (int n = 0; n < solver.node_count(); ++n) {
    const Vec3 x = solver.positions()[static_cast<std::size_t>(n)], v = solver.velocities()[static_cast<std::size_t>(n)];
    report.node_position.push_back({x.x, x.y, x.z});
    report.node_velocity.push_back({v.x, v.y, v.z});
  }
  report.structure_steps = coupler.structure_steps();
  double lowest = 1e300;  // m, the lowest bead centre at the end
  for (std::size_t i = 0; i < p.size(); ++i) {
    report.particles.push_back({p.id[i], {p.position[i].x, p.position[i].y, p.position[i].z},
                                {p.velocity[i].x, p.velocity[i].y, p.velocity[i].z}});
    lowest = std::min(lowest, p.position[i].z);
  }
  std::printf("built-in: t %.6g s, %zu syncs, %lld structure steps; %zu beads, initial downward momentum %.6e N s; "
              "impulse on the plate %.6e N s (%.3f of it); largest nodal displacement during the run %.4e m\n",
              world.time, report.history.size(), static_cast<long long>(coupler.structure_steps()), p.size(), momentum,
              impulse, impulse / momentum, peak);
  for (const std::string& line : coupler.messages()) std::printf("coupling: %s\n", line.c_str());
  if (!quarry_partner::write_report(report_path, std::move(report))) {
    std::fprintf(stderr, "builtin_reference: cannot write %s\n", report_path.c_str());
    return 1;
  }
  int failed = 0;
  // Every bead starts at most 20 mm up at 0.5 m/s downward and falls under gravity: it reaches
  // the plate within 30 ms of the 40 ms run, and its rebound only adds to what it gives, so the
  // plate receives at least the beads' initial momentum (walls frictionless: they take none).
  if (p.size() != 40 || !(impulse > momentum)) {
    std::fprintf(stderr, "builtin_reference: %zu beads gave %.6e N s, less than their momentum %.6e N s\n", p.size(),
                 impulse, momentum);
    failed = 1;
  }
  // The plate really moved under them (the clamped plate's static centre deflection under
  // the beads' weight alone, w = 0.0056 P a²/D, is 3.5e-8 m for P = 33 mN).
  if (!(peak > 3e-8)) {
    std::fprintf(stderr, "builtin_reference: the plate hardly moved (%.3e m)\n", peak);
    failed = 1;
  }
  return failed;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: builtin_reference DECK REPORT\n");
    return 1;
  }
  try {
    return run(argv[1], argv[2]);
  } catch (const UserError& e) {
    std::fprintf(stderr, "builtin_reference:\n%s\n", e.diagnostics().format().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "builtin_reference: %s\n", e.what());
  }
  return 1;
}
