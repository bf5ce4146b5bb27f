#include "api/built_in_solvers.h"

#include "cfdem/fluid_setup.h"
#include "fsi/structure_run.h"

namespace quarry::api {

BuiltInSolvers::BuiltInSolvers() = default;
BuiltInSolvers::BuiltInSolvers(BuiltInSolvers&&) noexcept = default;
BuiltInSolvers& BuiltInSolvers::operator=(BuiltInSolvers&&) noexcept = default;
BuiltInSolvers::~BuiltInSolvers() = default;

BuiltInSolvers attach_built_in_solvers(World& world, std::ostream& log) {
  BuiltInSolvers s;
  s.fluid = cfdem::attach_fluid_from_spec(world);
  if (!world.spec.structures.empty())
    s.structures = std::make_unique<fsi::CoupledStructures>(world, log);
  return s;
}

}  // namespace quarry::api
