// The deck's structures hooked into a run (structure_run.h).
#include "fsi/structure_run.h"

#include <array>
#include <cmath>
#include <ostream>
#include <string_view>

#include <fmt/format.h>

#include "fsi/structure_vtu.h"
#include "io/atomic_file.h"
#include "io/png_plot.h"
#include "sim/monitors.h"
#include "sim/output.h"

namespace quarry::fsi {

namespace {

// The columns every structure's table has; each support's reaction follows (monitor_columns).
constexpr std::array<std::string_view, 12> kMonitorColumns = {
    "time_s",   "max_displacement_m", "reaction_x_N", "reaction_y_N", "reaction_z_N", "load_x_N",
    "load_y_N", "load_z_N",           "kinetic_J",    "internal_J",   "hourglass_J",  "external_work_J"};

// The index of a column of kMonitorColumns by its name, found when compiling (a name that is not
// there does not compile).
consteval std::size_t column(std::string_view name) {
  for (std::size_t k = 0; k < kMonitorColumns.size(); ++k)
    if (kMonitorColumns[k] == name) return k;
  throw "not a column of kMonitorColumns";
}

// Series of a structure's table for its plots: the component of a vector column triple
// (`first`, +1, +2) along `axis` (unit), against time.
PlotSeries component_series(const std::vector<std::vector<double>>& rows, std::size_t first, const Vec3& axis,
                            const std::string& label) {
  PlotSeries s{label, {}, {}};
  for (const std::vector<double>& r : rows) {
    s.x.push_back(r[column("time_s")]);
    s.y.push_back(dot(Vec3{r[first], r[first + 1], r[first + 2]}, axis));
  }
  return s;
}

// The world's surface that is structure `spec`'s coupling surface, if it has one by that name.
std::optional<std::size_t> surface_named(const World& world, const std::string& name) {
  for (std::size_t k = 0; k < world.surfaces.size(); ++k)
    if (world.surfaces[k].mesh.name == name) return k;
  return std::nullopt;
}

}  // namespace

CoupledStructures::CoupledStructures(World& world, std::ostream& log)
    : world_(world),
      log_(log),
      interval_(world.spec.output.interval.value),
      next_output_(world.time + world.spec.output.interval.value),
      monitor_interval_(world.spec.output.monitor_interval.value),
      next_monitor_(world.time + world.spec.output.monitor_interval.value) {
  const double end_time = world.spec.simulation.end_time.value;  // s
  // A world restored from a checkpoint has the coupling surfaces (its deck lists them) with the
  // state the run left; restore_sections gives the structures theirs.
  const bool restored = world.initialized;
  for (const StructureSpec& spec : world.spec.structures) {
    auto entry = std::make_unique<Entry>();
    entry->name = spec.name.value;
    AdapterOptions adapter;
    if (spec.constraint_set) adapter.constraint_set = spec.constraint_set->value;
    entry->structure =
        spec.mesh ? read_coupled_mesh(spec.model.value, *spec.mesh, adapter)
                  : read_coupled_structure(spec.model.value, adapter,
                                           spec.surface ? std::optional<int>(spec.surface->value)
                                                        : std::nullopt);
    const CoupledStructure& structure = entry->structure;
    entry->supports = fem::support_groups(structure.adapted.model);

    const std::optional<std::size_t> existing = surface_named(world, spec.name.value);
    std::size_t surface = 0;
    if (restored) {
      const bool same = existing && world.surfaces[*existing].driver.kind == SurfaceDriverKind::coupled &&
                        world.surfaces[*existing].mesh.reference_vertices == structure.mesh.vertices;
      if (!same)
        throw UserError(spec.where,
                        fmt::format("structure \"{}\": the checkpoint's world has no coupling surface of that name "
                                    "with the model's {} coupled nodes",
                                    spec.name.value, structure.mesh.vertices.size()),
                        "the model file changed since the checkpoint was written: restore it, or rerun from the deck");
      surface = *existing;
    } else {
      if (existing)
        throw UserError(spec.where,
                        fmt::format("structure \"{}\": the deck has a surface of that name already (a deck written "
                                    "into a checkpoint lists the structures' coupling surfaces)",
                                    spec.name.value),
                        "continue such a run with `quarry restart CHECKPOINT`; in a deck of your own give the "
                        "structure a name no surface has");
      SurfaceSpec surface_spec = coupling_surface_spec(structure.mesh, spec.name.value, spec.material.value);
      surface_spec.export_loads = spec.export_loads;  // the deformed surface in the FEM load export
      surface = add_surface(world, surface_spec);
    }
    fem::ShellSolverOptions options;
    options.mass_scaling_time_step = spec.mass_scaling_time_step.value;
    options.damping = spec.damping.value;
    if (spec.drilling) options.drilling = spec.drilling->value;
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
    entry->coupler = std::make_unique<StructureCoupler>(
        world, surface, *entry->solver, structure.mesh.node_of_vertex,
        CouplerOptions{.schedule = schedule, .resume = restored});
    const fem::StableTimeStep stable = entry->solver->stable_time_step();
    std::string surfaces;  // "SURF 2 (floor), SURF 3 (walls)"
    for (std::size_t k = 0; k < structure.surface_ids.size(); ++k)
      surfaces += fmt::format("{}SURF {} ({})", k == 0 ? "" : ", ", structure.surface_ids[k], structure.labels[k]);
    log << fmt::format(
        "structure \"{}\": {} nodes, {} shells ({} on the coupling surface: {}), mass {:.4g} kg (added {:.4g} kg); "
        "stable step {:.4g} s (element {}), PERIOD {:.4g} s, FILTER {:.4g} s; quad kernel {}\n",
        entry->name, entry->solver->node_count(), entry->solver->element_count(),
        structure.mesh.triangles.size() + structure.mesh.quads.size(), surfaces, entry->solver->total_mass(),
        entry->solver->added_mass(), stable.time_step, structure.adapted.element_id.at(static_cast<std::size_t>(stable.element)),
        schedule.period, schedule.filter, fem::quad_kernel_name(entry->solver->quad_kernel()));
    if (const fem::WarpedQuads warped = fem::warped_quads(structure.adapted.model); warped.count > 0) {
      log << fmt::format(
          "structure \"{}\": warning: {} quads warped by more than {:g}° (largest {:.1f}°, element {}): "
          "a one-point shell works on the quad's projection, which stands for such a quad poorly; "
          "split them into triangles or refine there (docs/fem.md, \"Elements\")\n",
          entry->name, warped.count, fem::kWarpageLimitDegrees, warped.worst_degrees,
          structure.adapted.element_id.at(static_cast<std::size_t>(warped.worst_element)));
    }
    Entry* raw = entry.get();
    // The structure's steps between synchronisations run alongside the DEM's (on a thread of
    // their own when the team has two), the synchronisation at the end of the DEM's step.
    world.hooks.push_back({HookStage::alongside, "structure " + entry->name, [raw](World& w) {
                             raw->coupler->keep_up(w.time, w.dt, w.alongside_threading);
                           }});
    world.hooks.push_back({HookStage::end_of_step, "structure " + entry->name + " sync", [raw, this](World&) {
                             raw->coupler->after_dem_step();
                             const auto& lines = raw->coupler->messages();
                             for (; raw->messages_printed < lines.size(); ++raw->messages_printed)
                               log_ << "structure \"" << raw->name << "\": " << lines[raw->messages_printed] << "\n";
                           }});
    entries_.push_back(std::move(entry));
  }
  // Monitor rows and frames, after every structure has run its part of the step; none while
  // the world has no output (an ABI handle without an output folder, as the fluid's).
  if (entries_.empty()) return;
  world.hooks.push_back({HookStage::end_of_step, "structure output", [this](World& w) {
                           if (!w.output) return;
                           if (output_directory_.empty()) output_directory_ = w.output->directory();
                           const double due = 1e-6 * w.dt;  // s, clock round-off
                           if (monitor_interval_ > 0.0 && w.time >= next_monitor_ - due) {
                             for (auto& entry : entries_) add_monitor_row(*entry);
                             next_monitor_ += monitor_interval_;
                           }
                           if (interval_ > 0.0 && w.time >= next_output_ - due) {
                             for (auto& entry : entries_) {
                               if (monitor_interval_ == 0.0) add_monitor_row(*entry);
                               write_frame(*entry);
                             }
                             next_output_ += interval_;
                           }
                         }});
  world.hooks.push_back({HookStage::end_of_run, "structure output", [this](World&) { finish(log_); }});
  CheckpointSection section;
  section.name = "structures";
  section.save = [this](const World&, BinaryWriter& out) { save_state(out); };
  section.load = [this](World& w, BinaryReader& in) { load_state(in, w); };
  world.checkpoint_sections.push_back(std::move(section));
}

std::vector<std::string> CoupledStructures::monitor_columns(const Entry& entry) {
  std::vector<std::string> columns(kMonitorColumns.begin(), kMonitorColumns.end());
  for (std::size_t k = 1; k <= entry.supports.size(); ++k)
    for (const char* axis : {"x", "y", "z"}) columns.push_back(fmt::format("support_{}_reaction_{}_N", k, axis));
  return columns;
}

std::vector<double> CoupledStructures::monitor_row(const Entry& entry) const {
  const fem::ShellSolver& solver = *entry.solver;
  double largest = 0.0;  // m
  for (int n = 0; n < solver.node_count(); ++n) {
    const auto k = static_cast<std::size_t>(n);
    const Vec3 u = solver.positions()[k] - entry.structure.adapted.model.nodes[k];
    largest = std::max(largest, std::sqrt(dot(u, u)));
  }
  Vec3 reaction, load;  // N
  for (const auto& r : solver.reactions()) reaction += Vec3{r[0], r[1], r[2]};
  for (const fem::NodalLoad& l : entry.coupler->loads()) load += l.force;
  const fem::ShellEnergies& e = solver.energies();
  std::vector<double> row = {solver.time(), largest, reaction.x, reaction.y, reaction.z, load.x,
                             load.y,        load.z,  e.kinetic,  e.internal, e.hourglass, e.external_work};
  for (const std::vector<std::int32_t>& support : entry.supports) {
    Vec3 sum;  // N
    for (const std::int32_t n : support) {
      const auto& r = solver.reactions()[static_cast<std::size_t>(n)];
      sum += Vec3{r[0], r[1], r[2]};
    }
    row.insert(row.end(), {sum.x, sum.y, sum.z});
  }
  return row;
}

// The series and the table in the output folder, with what a checkpoint carried.
void CoupledStructures::open_output(Entry& entry) {
  if (entry.series && entry.monitors) return;
  entry.series.emplace(output_directory_ / ("structure_" + entry.name + ".pvd"));
  entry.series->set_entries(std::move(entry.listed));
  entry.listed.clear();
  entry.monitors.emplace(output_directory_ / ("structure_" + entry.name + ".csv"), monitor_columns(entry));
  for (const std::vector<double>& row : entry.rows) entry.monitors->add_row(row);
  entry.rows.clear();
  if (world_.output) {  // in the folder's manifest, so that --overwrite removes them
    world_.output->wrote("structure_" + entry.name + ".pvd");
    world_.output->wrote("structure_" + entry.name + ".csv");
  }
}

void CoupledStructures::add_monitor_row(Entry& entry) {
  open_output(entry);
  entry.monitors->add_row(monitor_row(entry));
}

// The structure as it is now (its own time, which is within a sync period of the DEM's).
void CoupledStructures::write_frame(Entry& entry) {
  const fem::ShellSolver& solver = *entry.solver;
  if (solver.time() == entry.last_frame_time) return;
  open_output(entry);
  const std::string file = fmt::format("structure_{}_{:04d}.vtu", entry.name, entry.frames++);
  std::filesystem::create_directories(output_directory_);
  if (world_.output) world_.output->wrote(file);
  write_file_atomically(output_directory_ / file,
                        structure_vtu(solver, entry.structure.adapted.model, entry.coupler->loads()));
  entry.series->add(solver.time(), file);
  entry.monitors->flush();
  entry.last_frame_time = solver.time();
}

// Three plots of a structure's table: its largest displacement, the reactions (in total, per
// support) and the coupled load along gravity's opposite (up: what holds the structure; the
// vertical reaction equals the load once the bed has settled on it), and its energies.
void CoupledStructures::write_plots(const Entry& entry) {
  const std::vector<std::vector<double>>& rows = entry.monitors->rows();
  if (rows.empty()) return;
  const Vec3 g = world_.spec.simulation.gravity.value;
  const double g_norm = std::sqrt(dot(g, g));
  const Vec3 up = g_norm > 0.0 ? g * (-1.0 / g_norm) : Vec3{0.0, 0.0, 1.0};  // along z without gravity
  const std::string axis = g_norm > 0.0 ? "up (against gravity)" : "along z";
  PlotSpec displacement{fmt::format("Structure \"{}\": largest displacement", entry.name), "time (s)",
                        "largest displacement (mm)", {sim::column_series(rows, column("max_displacement_m"), "")}};
  for (double& y : displacement.series.front().y) y *= 1000.0;  // m → mm
  PlotSpec reactions{fmt::format("Structure \"{}\": reactions and coupled load, {}", entry.name, axis), "time (s)",
                     "force (N)", {}};
  reactions.series.push_back(component_series(rows, column("reaction_x_N"), up, "reaction, all supports"));
  for (std::size_t k = 0; k < entry.supports.size() && entry.supports.size() > 1; ++k)
    reactions.series.push_back(
        component_series(rows, kMonitorColumns.size() + 3 * k, up, fmt::format("support {}", k + 1)));
  reactions.series.push_back(component_series(rows, column("load_x_N"), up * -1.0, "coupled load (down)"));
  PlotSpec energies{fmt::format("Structure \"{}\": energies", entry.name), "time (s)", "energy (J)",
                    {sim::column_series(rows, column("kinetic_J"), "kinetic"), sim::column_series(rows, column("internal_J"), "internal"),
                     sim::column_series(rows, column("hourglass_J"), "hourglass"),
                     sim::column_series(rows, column("external_work_J"), "external work")}};
  const std::pair<std::string, const PlotSpec*> plots[] = {
      {"structure_" + entry.name + "_displacement.png", &displacement},
      {"structure_" + entry.name + "_reactions.png", &reactions},
      {"structure_" + entry.name + "_energies.png", &energies}};
  for (const auto& [file, spec] : plots) {
    write_line_plot_png(output_directory_ / file, *spec);
    if (world_.output) world_.output->wrote(file);
  }
}

void CoupledStructures::finish(std::ostream& out) {
  for (const auto& entry : entries_) {
    std::vector<double> r = monitor_row(*entry);
    if (!output_directory_.empty()) {
      open_output(*entry);
      const auto& rows = entry->monitors->rows();
      if (rows.empty() || rows.back()[0] != entry->solver->time()) add_monitor_row(*entry);
      write_frame(*entry);
      entry->monitors->flush();
      r = entry->monitors->rows().back();
      if (world_.spec.output.plots.value) write_plots(*entry);
    }
    out << fmt::format(
        "structure \"{}\": t {:.4g} s, {} steps of {:.4g} s, {} syncs; largest displacement {:.4g} m; "
        "reactions [{:.4g}, {:.4g}, {:.4g}] N, coupled load [{:.4g}, {:.4g}, {:.4g}] N; energies (J): kinetic {:.4g}, "
        "internal {:.4g}, hourglass {:.4g}, external work {:.4g}{}\n",
        entry->name, r[0], entry->coupler->structure_steps(), entry->coupler->structure_step(),
        entry->coupler->schedule().synchronisations(), r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11],
        entry->solver->energies().hourglass_warning ? " (hourglass above 5 % of internal)" : "");
  }
}

}  // namespace quarry::fsi
