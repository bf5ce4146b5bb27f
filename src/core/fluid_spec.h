// The deck's `fluid:` section as plain located data (issue #18 §5): grid, fluid properties,
// boundaries, formulation, drag law or user-defined drag, fluid time step. Read by
// io/deck_fluid.cpp; made into a coupled fluid by cfdem/fluid_setup.h. docs/deck.md "fluid".
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/vec3.h"

namespace quarry {

enum class FluidBoundaryType { wall, velocity_inlet, pressure_outlet, periodic };
enum class FluidModel { a, b };
enum class FluidAdvection { central, hybrid };

struct FluidFaceSpec {
  Located<FluidBoundaryType> type{FluidBoundaryType::wall};
  Located<Vec3> velocity;               // m/s: a wall's (tangential part), an inlet's
  Located<double> reference_pressure{0.0};  // Pa: a pressure outlet's p_ref
  Located<Vec3> reference_point;        // m: where p = p_ref (hydrostatic outlet)
};

struct FluidDragUdfSpec {
  Located<std::string> library;   // path resolved against the deck's folder
  Located<std::string> function;  // symbol name
};

// A fluid monitor (fluid_monitors.csv, docs/deck.md "fluid"): the pressure drop between two
// planes normal to an axis, the flow rate through a plane, or the particles' mean slip velocity.
enum class FluidMonitorType { pressure_drop, flow_rate, slip_velocity };

struct FluidMonitorSpec {
  SourceLocation where;
  Located<std::string> name;
  Located<FluidMonitorType> type{FluidMonitorType::pressure_drop};
  Located<int> axis{2};       // 0, 1, 2 for x, y, z: the planes' normal
  Located<double> from{0.0};  // m: pressure_drop's upstream plane
  Located<double> to{0.0};    // m: pressure_drop's downstream plane
  Located<double> at{0.0};    // m: flow_rate's plane
};

// A region of the grid with no fluid (docs/deck.md "fluid", `blocked:`): a cell is blocked when its
// centre lies in an axis-aligned box, on the solid side of a plane, or inside a closed surface of
// the deck's `surfaces:` (cfdem/fluid_blocked.h).
enum class FluidBlockedKind { box, half_space, surface };

struct FluidBlockedSpec {
  SourceLocation where;  // the list entry
  Located<FluidBlockedKind> kind{FluidBlockedKind::box};
  Located<Vec3> min, max;           // box: corners (m), max > min in every component
  Located<Vec3> point;              // half_space: a point of its plane (m)
  Located<Vec3> normal{Vec3{0, 0, 1}};  // half_space: outward, from the solid into the fluid
  Located<std::string> surface;     // surface: a name of the deck's surfaces (closed, fixed)
};

struct FluidSpec {
  SourceLocation where;                         // the fluid: section
  Located<double> density{1000.0};              // ρ_f (kg/m³)
  Located<double> viscosity{1e-3};              // μ (Pa·s)
  Located<double> time_step{0.0};               // Δt_f (s): an integer multiple of the DEM step
  Located<Vec3> origin;                         // m, the grid's low corner
  Located<double> cell_size{0.0};               // m, cubic cells
  Located<Vec3> cells{Vec3{1.0, 1.0, 1.0}};     // integers ≥ 1 per axis
  std::array<FluidFaceSpec, 6> faces;           // x_min, x_max, y_min, y_max, z_min, z_max
  Located<FluidModel> model{FluidModel::a};
  Located<FluidAdvection> advection{FluidAdvection::central};  // cfd::Advection
  Located<std::string> drag_law{std::string("stokes")};  // a name of cfd::kDragLawNames
  std::optional<FluidDragUdfSpec> drag_udf;     // replaces drag_law when present
  std::vector<FluidMonitorSpec> monitors;
  std::vector<FluidBlockedSpec> blocked;        // cells without fluid, in deck order
  SourceLocation blocked_where;                 // the blocked: list, for errors about all of it
};

}  // namespace quarry
