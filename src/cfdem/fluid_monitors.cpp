// Fluid monitors: planes through the fluid grid and the particles' slip, one row per monitor row
// of the run in fluid_monitors.csv.
#include "cfdem/fluid_monitors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "io/png_plot.h"
#include "sim/binary_stream.h"
#include "sim/monitors.h"
#include "sim/output.h"

namespace quarry::cfdem {

namespace {

constexpr std::uint32_t kMonitorsSectionVersion = 1;

// Cell (i, j, k) with `along` at position `axis` and (u, v) on the two other axes in order.
std::array<int, 3> cell_of(int axis, int along, int u, int v) {
  std::array<int, 3> c{};
  c[static_cast<std::size_t>(axis)] = along;
  c[static_cast<std::size_t>((axis + 1) % 3)] = u;
  c[static_cast<std::size_t>((axis + 2) % 3)] = v;
  return c;
}

// Calls visit(u, v) for every column of cells along `axis`.
template <class Visit>
void for_each_column(const cfd::FluidGrid& grid, int axis, Visit&& visit) {
  const int nu = grid.cells[static_cast<std::size_t>((axis + 1) % 3)];
  const int nv = grid.cells[static_cast<std::size_t>((axis + 2) % 3)];
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) visit(u, v);
}

double component(const Vec3& x, int axis) { return axis == 0 ? x.x : axis == 1 ? x.y : x.z; }

}  // namespace

double plane_area(const cfd::FluidGrid& grid, int axis) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  return grid.cells[static_cast<std::size_t>(a)] * component(grid.cell_size, a) *
         grid.cells[static_cast<std::size_t>(b)] * component(grid.cell_size, b);
}

double plane_pressure(const cfd::FluidSolver& fluid, int axis, double coordinate) {
  const cfd::FluidGrid& grid = fluid.grid();
  const int n = grid.cells[static_cast<std::size_t>(axis)];
  const double spacing = component(grid.cell_size, axis);
  // Position in cell-centre units: centre k sits at k.
  const double t = (coordinate - component(grid.origin, axis)) / spacing - 0.5;
  const int low = n == 1 ? 0 : std::clamp(static_cast<int>(std::floor(t)), 0, n - 2);
  const double w = n == 1 ? 0.0 : t - low;
  const std::span<const std::uint8_t> blocked = fluid.blocked();
  const auto is_blocked = [&](const std::array<int, 3>& c) { return blocked[grid.cell_index(c[0], c[1], c[2])] != 0; };
  double sum = 0.0;
  std::size_t columns = 0;
  for_each_column(grid, axis, [&](int u, int v) {
    const auto a = cell_of(axis, low, u, v);
    if (is_blocked(a)) return;  // no fluid there: the column does not count
    double p = fluid.pressure(a[0], a[1], a[2]);
    if (n > 1) {
      const auto b = cell_of(axis, low + 1, u, v);
      if (is_blocked(b)) return;
      p = (1.0 - w) * p + w * fluid.pressure(b[0], b[1], b[2]);
    }
    sum += p;
    ++columns;
  });
  return columns == 0 ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(columns);
}

double flow_rate(const cfd::FluidSolver& fluid, const std::vector<double>& void_fraction, int axis,
                 double coordinate) {
  const cfd::FluidGrid& grid = fluid.grid();
  const int n = grid.cells[static_cast<std::size_t>(axis)];
  const int layer = std::clamp(
      static_cast<int>(std::lround((coordinate - component(grid.origin, axis)) / component(grid.cell_size, axis))), 0, n);
  const double face_area = plane_area(grid, axis) / static_cast<double>(grid.cell_count() / static_cast<std::size_t>(n));
  const auto porosity = [&](int along, int u, int v) {
    if (void_fraction.empty()) return 1.0;
    const auto c = cell_of(axis, along, u, v);
    return void_fraction[grid.cell_index(c[0], c[1], c[2])];
  };
  double sum = 0.0;
  for_each_column(grid, axis, [&](int u, int v) {
    const double below = layer > 0 ? porosity(layer - 1, u, v) : porosity(0, u, v);
    const double above = layer < n ? porosity(layer, u, v) : porosity(n - 1, u, v);
    const auto c = cell_of(axis, layer, u, v);
    sum += 0.5 * (below + above) * fluid.face_velocity(axis, c[0], c[1], c[2]) * face_area;
  });
  return sum;
}

Vec3 mean_slip_velocity(const FluidCoupling& coupling, const World& world) {
  const std::vector<FrozenParticle>& frozen = coupling.frozen();
  const std::vector<FrozenForce>& forces = coupling.frozen_forces();
  const std::size_t n = std::min(frozen.size(), world.particles.size());
  Vec3 sum;
  std::size_t counted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (frozen[i].id != world.particles.id[i]) continue;
    sum += forces[i].fluid_velocity - world.particles.velocity[i];
    ++counted;
  }
  return counted == 0 ? Vec3{} : sum / static_cast<double>(counted);
}

std::vector<std::string> FluidMonitors::columns(const std::vector<FluidMonitorSpec>& monitors) {
  std::vector<std::string> names{"time_s"};
  for (const FluidMonitorSpec& m : monitors) {
    const std::string& name = m.name.value;
    switch (m.type.value) {
      case FluidMonitorType::pressure_drop:
        names.push_back(name + "_dp_Pa");
        names.push_back(name + "_dp_dynamic_Pa");
        break;
      case FluidMonitorType::flow_rate:
        names.push_back(name + "_Q_m3_s");
        names.push_back(name + "_U_m_s");
        break;
      case FluidMonitorType::slip_velocity:
        for (const char* axis : {"x", "y", "z"}) names.push_back(fmt::format("{}_slip_{}_m_s", name, axis));
        break;
    }
  }
  return names;
}

std::vector<double> FluidMonitors::row(const std::vector<FluidMonitorSpec>& monitors, const FluidCoupling& coupling,
                                       const World& world) {
  const cfd::FluidSolver& fluid = coupling.fluid();
  const Vec3 gravity = world.spec.simulation.gravity.value;  // m/s²
  const double density = coupling.options().properties.density;  // kg/m³
  std::vector<double> values{world.time};
  for (const FluidMonitorSpec& m : monitors) {
    const int axis = m.axis.value;
    switch (m.type.value) {
      case FluidMonitorType::pressure_drop: {
        const double drop = plane_pressure(fluid, axis, m.from.value) - plane_pressure(fluid, axis, m.to.value);
        // Hydrostatic p = p_ref + ρ_f g·(x − x_ref): its drop from `from` to `to` is ρ_f g_a (from − to).
        const double head = density * component(gravity, axis) * (m.from.value - m.to.value);
        values.push_back(drop);
        values.push_back(drop - head);
        break;
      }
      case FluidMonitorType::flow_rate: {
        const double q = flow_rate(fluid, coupling.void_fraction(), axis, m.at.value);
        values.push_back(q);
        values.push_back(q / plane_area(fluid.grid(), axis));
        break;
      }
      case FluidMonitorType::slip_velocity: {
        const Vec3 slip = mean_slip_velocity(coupling, world);
        values.insert(values.end(), {slip.x, slip.y, slip.z});
        break;
      }
    }
  }
  return values;
}

std::shared_ptr<FluidMonitors> FluidMonitors::attach(World& world, std::shared_ptr<FluidCoupling> coupling,
                                                     std::vector<FluidMonitorSpec> monitors) {
  if (monitors.empty()) return nullptr;
  auto self = std::make_shared<FluidMonitors>();
  self->coupling_ = std::move(coupling);
  self->monitors_ = std::move(monitors);
  StepHook hook;
  hook.stage = HookStage::end_of_step;
  hook.name = "fluid monitors";
  hook.run = [self](World& w) {
    if (!w.output) return;
    if (self->resume_) self->resume_table(w);
    if (!self->table_ || w.step_count % w.output->monitor_every() == 0) self->record(w);
  };
  world.hooks.push_back(std::move(hook));
  StepHook last;
  last.stage = HookStage::end_of_run;
  last.name = "fluid monitors";
  last.run = [self](World& w) { self->finish(w); };
  world.hooks.push_back(std::move(last));
  CheckpointSection section;
  section.name = "fluid monitors";
  section.save = [self](const World&, BinaryWriter& out) {
    if (self->table_) self->table_->flush();  // the rows a restart keeps, on disk
    out.value(kMonitorsSectionVersion);
    out.value(static_cast<std::uint8_t>(self->table_.has_value()));
    out.value(static_cast<std::uint64_t>(self->table_ ? self->table_->rows().size() : 0));
  };
  section.load = [self](World& w, BinaryReader& in) {
    const auto version = in.value<std::uint32_t>();
    if (version != kMonitorsSectionVersion)
      throw std::runtime_error(fmt::format("version {} (this Quarry reads version {})", version, kMonitorsSectionVersion));
    const auto table = in.value<std::uint8_t>();
    const auto rows = in.value<std::uint64_t>();
    if (table > 1) throw std::runtime_error(fmt::format("the table flag holds {}, not 0 or 1", table));
    Resume resume;
    resume.time = w.time;
    if (table) resume.rows = rows;
    self->resume_ = resume;
  };
  world.checkpoint_sections.push_back(std::move(section));
  return self;
}

void FluidMonitors::resume_table(World& world) {
  const Resume resume = *resume_;
  resume_.reset();
  if (!resume.rows) return;  // no row before the checkpoint: this step writes the first
  const std::filesystem::path path = world.output->directory() / "fluid_monitors.csv";
  table_.emplace(path, columns(monitors_));
  world.output->wrote("fluid_monitors.csv");
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return;  // restarted into another folder: a new table
  // The rows of the checkpoint's table: the file may hold later ones (the run went on, or its
  // end wrote a last row), which the run that went on would not have.
  const CsvTable earlier = CsvTable::load(path);
  if (earlier.columns() != table_->columns()) return;  // not this deck's table: replaced
  for (std::size_t k = 0; k < earlier.rows().size() && k < *resume.rows; ++k) {
    if (earlier.rows()[k][0] > resume.time) break;
    table_->add_row(earlier.rows()[k]);
  }
}

void FluidMonitors::record(World& world) {
  if (!table_) {
    table_.emplace(world.output->directory() / "fluid_monitors.csv", columns(monitors_));
    world.output->wrote("fluid_monitors.csv");
  }
  table_->add_row(row(monitors_, *coupling_, world));
  // The table is small (a few columns, ~200 rows): rewriting it keeps the file current for a
  // run that is watched or killed.
  if (table_->rows().size() % 16 == 1) table_->flush();
}

void FluidMonitors::finish(World& world) {
  if (!table_ || !world.output) return;
  if (table_->rows().empty() || table_->rows().back()[0] != world.time)
    table_->add_row(row(monitors_, *coupling_, world));
  table_->flush();
  if (!world.spec.output.plots.value) return;
  const std::vector<std::string>& names = table_->columns();
  const auto series = [&](std::size_t column, const std::string& label) {
    return sim::column_series(table_->rows(), column, label);
  };
  PlotSpec drop{"Fluid pressure drop (less the hydrostatic head)", "time (s)", "pressure drop (Pa)", {}};
  PlotSpec flow{"Superficial fluid velocity", "time (s)", "U (m/s)", {}};
  PlotSpec slip{"Mean slip velocity u - v", "time (s)", "slip (m/s)", {}};
  for (std::size_t k = 1; k < names.size(); ++k) {
    const std::string& c = names[k];
    if (c.ends_with("_dp_dynamic_Pa")) drop.series.push_back(series(k, c.substr(0, c.size() - 14)));
    if (c.ends_with("_U_m_s")) flow.series.push_back(series(k, c.substr(0, c.size() - 6)));
    if (c.find("_slip_") != std::string::npos) slip.series.push_back(series(k, c.substr(0, c.size() - 4)));
  }
  const std::pair<const char*, const PlotSpec*> plots[] = {
      {"fluid_pressure_drop.png", &drop}, {"fluid_flow_rate.png", &flow}, {"fluid_slip_velocity.png", &slip}};
  for (const auto& [file, spec] : plots) {
    if (spec->series.empty()) continue;
    write_line_plot_png(world.output->directory() / file, *spec);
    world.output->wrote(file);
  }
}

}  // namespace quarry::cfdem
