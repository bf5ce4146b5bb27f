// The deck's structures hooked into a run (structure_run.h).
#include "fsi/structure_run.h"

#include <cmath>
#include <ostream>

#include <fmt/format.h>

#include "fsi/structure_vtu.h"
#include "io/atomic_file.h"

namespace quarry::fsi {

CoupledStructures::CoupledStructures(World& world, std::ostream& log, std::filesystem::path output_directory)
    : output_directory_(std::move(output_directory)),
      interval_(world.spec.output.interval.value),
      next_output_(world.time + world.spec.output.interval.value) {
  const double end_time = world.spec.simulation.end_time.value;  // s
  for (const StructureSpec& spec : world.spec.structures) {
    auto entry = std::make_unique<Entry>();
    entry->name = spec.name.value;
    AdapterOptions adapter;
    if (spec.constraint_set) adapter.constraint_set = spec.constraint_set->value;
    entry->structure = read_coupled_structure(
        spec.model.value, adapter, spec.surface ? std::optional<int>(spec.surface->value) : std::nullopt);
    const CoupledStructure& structure = entry->structure;

    const std::size_t surface = add_surface(world, coupling_surface_spec(structure.mesh, spec.name.value, spec.material.value));
    fem::ShellSolverOptions options;
    options.mass_scaling_time_step = spec.mass_scaling_time_step.value;
    options.damping = spec.damping.value;
    options.threading = world.threading;
    entry->solver = std::make_unique<fem::ShellSolver>(structure.adapted.model, options);

    std::optional<double> period = structure.period, filter = structure.filter;
    if (spec.period) {
      period = spec.period->value;
      filter.reset();  // the card's FILTER went with the card's PERIOD
    }
    if (spec.filter) filter = spec.filter->value;
    ScheduleSettings schedule;
    try {
      schedule = resolve_schedule(period, filter, end_time);
    } catch (const std::invalid_argument& e) {
      throw UserError(spec.where, fmt::format("structure \"{}\": {}", spec.name.value, e.what()),
                      "set period: and filter: in the deck's structures: entry, or the EDEM card's");
    }
    entry->coupler = std::make_unique<StructureCoupler>(world, surface, *entry->solver,
                                                        structure.mesh.node_of_vertex, CouplerOptions{.schedule = schedule});
    const fem::StableTimeStep stable = entry->solver->stable_time_step();
    log << fmt::format(
        "structure \"{}\": {} nodes, {} shells ({} on the coupling surface), mass {:.4g} kg (added {:.4g} kg); "
        "stable step {:.4g} s (element {}), PERIOD {:.4g} s, FILTER {:.4g} s\n",
        entry->name, entry->solver->node_count(), entry->solver->element_count(),
        structure.mesh.triangles.size() + structure.mesh.quads.size(), entry->solver->total_mass(),
        entry->solver->added_mass(), stable.time_step, structure.adapted.element_id.at(static_cast<std::size_t>(stable.element)),
        schedule.period, schedule.filter);
    entry->series.emplace(output_directory_ / ("structure_" + entry->name + ".pvd"));
    Entry* raw = entry.get();
    world.hooks.push_back({HookStage::end_of_step, "structure " + entry->name, [raw, &log](World&) {
                             raw->coupler->after_dem_step();
                             const auto& lines = raw->coupler->messages();
                             for (; raw->messages_printed < lines.size(); ++raw->messages_printed)
                               log << "structure \"" << raw->name << "\": " << lines[raw->messages_printed] << "\n";
                           }});
    entries_.push_back(std::move(entry));
  }
  // Frames at the output interval, after every structure has run its part of the step.
  if (interval_ > 0.0 && !entries_.empty())
    world.hooks.push_back({HookStage::end_of_step, "structure frames", [this](World& w) {
                             if (w.time < next_output_ - 1e-6 * w.dt) return;
                             for (auto& entry : entries_) write_frame(*entry);
                             next_output_ += interval_;
                           }});
}

// The structure as it is now (its own time, which is within a sync period of the DEM's).
void CoupledStructures::write_frame(Entry& entry) {
  const fem::ShellSolver& solver = *entry.solver;
  if (solver.time() == entry.last_frame_time) return;
  const std::string file = fmt::format("structure_{}_{:04d}.vtu", entry.name, entry.frames++);
  std::filesystem::create_directories(output_directory_);
  write_file_atomically(output_directory_ / file,
                        structure_vtu(solver, entry.structure.adapted.model, entry.coupler->loads()));
  entry.series->add(solver.time(), file);
  entry.last_frame_time = solver.time();
}

void CoupledStructures::finish(std::ostream& out) {
  for (const auto& entry : entries_) {
    write_frame(*entry);
    const fem::ShellSolver& solver = *entry->solver;
    double largest = 0.0;  // m
    for (int n = 0; n < solver.node_count(); ++n) {
      const auto k = static_cast<std::size_t>(n);
      const Vec3 u = solver.positions()[k] - entry->structure.adapted.model.nodes[k];
      largest = std::max(largest, std::sqrt(dot(u, u)));
    }
    Vec3 reaction;  // N
    for (const auto& r : solver.reactions()) reaction += Vec3{r[0], r[1], r[2]};
    const fem::ShellEnergies& e = solver.energies();
    out << fmt::format(
        "structure \"{}\": t {:.4g} s, {} steps of {:.4g} s, {} syncs; largest displacement {:.4g} m; "
        "reactions [{:.4g}, {:.4g}, {:.4g}] N; energies (J): kinetic {:.4g}, internal {:.4g}, hourglass {:.4g}, "
        "external work {:.4g}{}\n",
        entry->name, solver.time(), entry->coupler->structure_steps(), entry->coupler->structure_step(),
        entry->coupler->schedule().synchronisations(), largest, reaction.x, reaction.y, reaction.z, e.kinetic,
        e.internal, e.hourglass, e.external_work, e.hourglass_warning ? " (hourglass above 5 % of internal)" : "");
  }
}

}  // namespace quarry::fsi
