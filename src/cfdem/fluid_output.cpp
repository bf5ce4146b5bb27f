// Fluid fields as VTK XML ImageData (VTK file formats, "ImageData": WholeExtent in points, one
// cell per fluid cell) with a .pvd series, written at the particle frames' interval.
#include "cfdem/fluid_output.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <stdexcept>

#include "io/atomic_file.h"
#include "sim/binary_stream.h"
#include "sim/output.h"

namespace quarry::cfdem {

std::string fluid_image_text(const FluidCoupling& coupling) {
  const cfd::FluidGrid& g = coupling.options().grid;
  const cfd::FluidSolver& fluid = coupling.fluid();
  const std::vector<double>& void_fraction = coupling.void_fraction();
  std::string text = "<?xml version=\"1.0\"?>\n"
                     "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n";
  text += fmt::format("  <ImageData WholeExtent=\"0 {} 0 {} 0 {}\" Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n",
                      g.cells[0], g.cells[1], g.cells[2], g.origin.x, g.origin.y, g.origin.z,
                      g.cell_size.x, g.cell_size.y, g.cell_size.z);
  text += fmt::format("    <Piece Extent=\"0 {} 0 {} 0 {}\">\n", g.cells[0], g.cells[1], g.cells[2]);
  text += "      <CellData Vectors=\"velocity\" Scalars=\"pressure\">\n";
  const auto each_cell = [&](auto&& write) {
    for (int k = 0; k < g.cells[2]; ++k)
      for (int j = 0; j < g.cells[1]; ++j)
        for (int i = 0; i < g.cells[0]; ++i) write(i, j, k);
  };
  text += "        <DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  each_cell([&](int i, int j, int k) {
    const Vec3 u = fluid.cell_velocity(i, j, k);
    text += fmt::format("{} {} {}\n", u.x, u.y, u.z);
  });
  text += "        </DataArray>\n";
  text += "        <DataArray type=\"Float64\" Name=\"pressure\" format=\"ascii\">\n";
  each_cell([&](int i, int j, int k) { text += fmt::format("{}\n", fluid.pressure(i, j, k)); });
  text += "        </DataArray>\n";
  text += "        <DataArray type=\"Float64\" Name=\"void_fraction\" format=\"ascii\">\n";
  each_cell([&](int i, int j, int k) { text += fmt::format("{}\n", void_fraction[g.cell_index(i, j, k)]); });
  text += "        </DataArray>\n";
  // 1 where the cell holds no fluid (fluid.blocked): threshold it away in ParaView.
  text += "        <DataArray type=\"UInt8\" Name=\"blocked\" format=\"ascii\">\n";
  const BlockedCells& blocked = coupling.blocked_cells();
  each_cell([&](int i, int j, int k) { text += blocked.blocked(g.cell_index(i, j, k)) ? "1\n" : "0\n"; });
  text += "        </DataArray>\n      </CellData>\n    </Piece>\n  </ImageData>\n</VTKFile>\n";
  return text;
}

std::string fluid_frame_name(std::size_t frame) { return fmt::format("fluid_{:06d}.vti", frame); }

void write_fluid_frame(const FluidCoupling& coupling, const std::filesystem::path& directory,
                       std::size_t frame, double time, PvdSeries& series) {
  const std::string name = fluid_frame_name(frame);
  write_file_atomically(directory / name, fluid_image_text(coupling));
  series.add(time, name);
}

namespace {

// The hook's state: the series and the next frame's time (both in the checkpoint's section
// "fluid frames"; a restart keeps the series' entries up to the checkpoint's time).
struct FluidFrames {
  std::shared_ptr<FluidCoupling> coupling;
  std::unique_ptr<PvdSeries> series;
  std::size_t frame = 0;
  double next_time = 0.0;  // s
  std::optional<double> resume_time;  // s: restored from a checkpoint taken then
};

constexpr std::uint32_t kFramesSectionVersion = 1;

}  // namespace

void attach_fluid_output(World& world, std::shared_ptr<FluidCoupling> coupling) {
  const double interval = world.spec.output.interval.value;  // s
  if (!(interval > 0.0)) return;
  auto frames = std::make_shared<FluidFrames>();
  frames->coupling = std::move(coupling);
  frames->next_time = world.time;
  StepHook hook;
  hook.stage = HookStage::end_of_step;
  hook.name = "fluid output";
  hook.run = [frames, interval](World& w) {
    if (!w.output) return;
    // Half a DEM step of slack: frame times land on steps as the particle frames' do.
    if (w.time + 0.5 * w.dt < frames->next_time) return;
    const std::filesystem::path& directory = w.output->directory();
    if (!frames->series) {
      // A restart continues the series: the frames up to the checkpoint stay listed.
      const std::filesystem::path path = directory / "fluid.pvd";
      frames->series = std::make_unique<PvdSeries>(frames->resume_time ? PvdSeries::resume(path, *frames->resume_time)
                                                                        : PvdSeries(path));
      w.output->wrote("fluid.pvd");  // in the manifest, so that --overwrite removes the series
    }
    w.output->wrote(fluid_frame_name(frames->frame));  // listed before it is written, as the particles' frames
    write_fluid_frame(*frames->coupling, directory, frames->frame++, w.time, *frames->series);
    frames->next_time += interval;
    while (frames->next_time <= w.time + 0.5 * w.dt) frames->next_time += interval;
  };
  world.hooks.push_back(std::move(hook));
  CheckpointSection section;
  section.name = "fluid frames";
  section.save = [frames](const World&, BinaryWriter& out) {
    out.value(kFramesSectionVersion);
    out.value(static_cast<std::uint64_t>(frames->frame));
    out.value(frames->next_time);
  };
  section.load = [frames](World& w, BinaryReader& in) {
    const auto version = in.value<std::uint32_t>();
    if (version != kFramesSectionVersion)
      throw std::runtime_error(fmt::format("version {} (this Quarry reads version {})", version, kFramesSectionVersion));
    const auto frame = in.value<std::uint64_t>();
    const auto next_time = in.value<double>();
    if (frame > 1000000000000ull || !std::isfinite(next_time) || next_time < 0.0)
      throw std::runtime_error(fmt::format("the next fluid frame {} at {} s is out of range", frame, next_time));
    frames->frame = static_cast<std::size_t>(frame);
    frames->next_time = next_time;
    frames->resume_time = w.time;
  };
  world.checkpoint_sections.push_back(std::move(section));
}

}  // namespace quarry::cfdem
