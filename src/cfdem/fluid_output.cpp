// Fluid fields as VTK XML ImageData (VTK file formats, "ImageData": WholeExtent in points, one
// cell per fluid cell) with a .pvd series, written at the particle frames' interval.
#include "cfdem/fluid_output.h"

#include <fmt/format.h>

#include <cmath>

#include "io/atomic_file.h"
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

// The hook's state: the series and the next frame's time.
struct FluidFrames {
  std::shared_ptr<FluidCoupling> coupling;
  std::unique_ptr<PvdSeries> series;
  std::size_t frame = 0;
  double next_time = 0.0;  // s
};

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
      frames->series = std::make_unique<PvdSeries>(directory / "fluid.pvd");
      w.output->wrote("fluid.pvd");  // in the manifest, so that --overwrite removes the series
    }
    w.output->wrote(fluid_frame_name(frames->frame));  // listed before it is written, as the particles' frames
    write_fluid_frame(*frames->coupling, directory, frames->frame++, w.time, *frames->series);
    frames->next_time += interval;
    while (frames->next_time <= w.time + 0.5 * w.dt) frames->next_time += interval;
  };
  world.hooks.push_back(std::move(hook));
}

}  // namespace quarry::cfdem
