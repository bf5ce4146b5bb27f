// The deck's built-in solvers attached to a world: its `fluid:` section (the fluid's hooks) and
// then its `structures:` (a shell solver and coupler each), in that order. `quarry run`,
// `quarry estimate` (on its calibration world) and the C ABI's in-process backend attach them
// through this one function, so that the three run the same simulation.
#pragma once

#include <memory>
#include <ostream>

#include "sim/world.h"

namespace quarry::cfdem {
class FluidCoupling;
}
namespace quarry::fsi {
class CoupledStructures;
}

namespace quarry::api {

struct BuiltInSolvers {
  BuiltInSolvers();
  BuiltInSolvers(BuiltInSolvers&&) noexcept;
  BuiltInSolvers& operator=(BuiltInSolvers&&) noexcept;
  ~BuiltInSolvers();
  std::shared_ptr<cfdem::FluidCoupling> fluid;         // null without a fluid: section
  std::unique_ptr<fsi::CoupledStructures> structures;  // null without structures:
};

// Keep the result alive while the world runs (its hooks refer to it). The structures print
// their lines (the model, the schedule's notes, the PERIOD warning) to `log`, which must
// outlive the result.
BuiltInSolvers attach_built_in_solvers(World& world, std::ostream& log);

}  // namespace quarry::api
