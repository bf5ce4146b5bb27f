// The fluid's fields for ParaView (issue #18 §5): cell-centred velocity (m/s), pressure (Pa),
// void fraction and the blocked-cell flag as VTK image data (.vti, one file per frame) listed with their times in a .pvd
// series, beside the particles' particles.pvd.
#pragma once

#include <filesystem>
#include <string>

#include "cfdem/fluid_coupling.h"
#include "io/pvd_series.h"

namespace quarry::cfdem {

// The VTK XML ImageData text of the coupling's fluid now: the grid's origin and spacing, one
// cell per fluid cell, CellData "velocity" (3 components), "pressure", "void_fraction" in ASCII
// with round-trip precision, and "blocked" (UInt8, 1 where the cell holds no fluid). Cost: O(cells).
std::string fluid_image_text(const FluidCoupling& coupling);

// The file name of fluid frame `frame`: fluid_NNNNNN.vti.
std::string fluid_frame_name(std::size_t frame);

// Writes fluid_frame_name(frame) into `directory` and adds it at `time` (s) to `series` (directory/
// fluid.pvd), both atomically. Throws std::runtime_error if a file cannot be written.
void write_fluid_frame(const FluidCoupling& coupling, const std::filesystem::path& directory,
                       std::size_t frame, double time, PvdSeries& series);

// Adds an end-of-step hook that writes a fluid frame at the start of the run and every
// spec.output.interval (s) of simulated time after it, into the run's output folder (nothing
// when the world has no output, or the interval is 0). The hook shares `coupling`. Its frame
// number and next frame time are the checkpoint section "fluid frames": restored, the series
// keeps the frames up to the checkpoint's time and goes on (as particles.pvd does).
void attach_fluid_output(World& world, std::shared_ptr<FluidCoupling> coupling);

}  // namespace quarry::cfdem
