// User-defined drag (issue #18 §4): the seed's Stokes UDF (examples/stokes_settling/
// usrStokesDrag.c) built with `quarry udf build` gives the built-in Stokes law's force to
// round-off; every input reaches the UDF where drag_udf.h says; the seed's particle settles at its
// analytic terminal velocity through the UDF. Failures: drag_udf_errors_test.cpp.
#include "cfd/drag_udf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "cfd/drag_laws.h"
#include "core/diagnostics.h"
#include "udf/udf_test_support.h"

namespace quarry::cfd {
namespace {

namespace fs = std::filesystem;
using udf_testing::build_stokes_example;
using udf_testing::build_udf;
using udf_testing::TemporaryFolder;

constexpr double kPi = std::numbers::pi;

// |a − b| within `ulps` units of roundoff of the larger: the same formula evaluated in another
// order, or compiled with other flags, differs by a few ulp at most. 0 and 0 agree.
bool within_roundoff(double a, double b, double ulps = 4.0) {
  return std::abs(a - b) <=
         ulps * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b));
}

DragInput seed_particle_input(const Vec3& particle_velocity) {
  DragInput input;
  input.diameter = 1e-4;  // m (seed 001)
  input.particle_velocity = particle_velocity;
  input.porosity = 1.0;          // a single particle in still water
  input.fluid_density = 1000.0;  // kg/m³
  input.fluid_viscosity = 1e-3;  // Pa·s
  return input;
}

// F = 3π ε d μ (u − v) by the UDF and by cfd::stokes_drag, over a grid of diameters, porosities,
// viscosities and slips (zero, the seed's terminal slip, mixed signs, very unequal components).
// Both evaluate β = ((3π·ε)·d)·μ and β (u_i − v_i) in doubles; only the UDF's compilation differs
// (another compiler invocation, -O2, -ffp-contract=off on both sides), so they agree to a few ulp
// (in practice bit for bit). A UDF that dropped the factor ε, or used the radius for d, would be
// off by 25 % or more on most of this grid.
TEST(DragUdf, StokesExampleGivesTheBuiltInLawToRoundoff) {
  TemporaryFolder folder;
  const std::string library = build_stokes_example(folder.path());
  ASSERT_TRUE(fs::exists(library)) << "quarry udf build writes the library beside the source";
  const DragUdf udf = load_drag_udf(library, "usrStokesDrag");
  EXPECT_EQ(udf.abi_version(), QUARRY_DRAG_UDF_ABI_VERSION);
  EXPECT_EQ(udf.function_name(), "usrStokesDrag");

  std::vector<DragInput> inputs;
  const std::vector<double> diameters = {1e-4, 3.7e-3, 2.5e-6};
  const std::vector<double> porosities = {1.0, 0.8, 0.41, 0.0123};
  const std::vector<double> viscosities = {1e-3, 1.8e-5, 0.93};
  const std::vector<Vec3> slips = {
      {0.0, 0.0, 0.0}, {0.0, 0.0, -0.002725}, {1.3, -2.7, 0.31}, {-1e-9, 5e3, 7.0 / 3.0}};
  for (const double diameter : diameters)
    for (const double porosity : porosities)
      for (const double viscosity : viscosities)
        for (const Vec3& slip : slips) {
          DragInput input;
          input.diameter = diameter;
          input.porosity = porosity;
          input.fluid_viscosity = viscosity;
          input.fluid_density = 998.2;
          input.particle_velocity = Vec3{0.1, -0.2, 1.0 / 3.0};
          input.fluid_velocity = input.particle_velocity + slip;
          inputs.push_back(input);
        }
  int nonzero = 0;
  for (const DragInput& input : inputs) {
    const DragResult expected = stokes_drag(input);
    const DragResult got = udf.evaluate(input);
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE(within_roundoff(got.force[i], expected.force[i]))
          << "component " << i << ": UDF " << got.force[i] << ", built-in " << expected.force[i]
          << " (d " << input.diameter << ", ε " << input.porosity << ", μ " << input.fluid_viscosity
          << ")";
    EXPECT_TRUE(within_roundoff(got.coefficient, expected.coefficient))
        << "UDF " << got.coefficient << ", built-in " << expected.coefficient;
    nonzero += norm(expected.force) > 0.0;
  }
  EXPECT_EQ(inputs.size(), 144u);
  EXPECT_EQ(nonzero, 108);  // all but the zero slips
}

// A UDF that returns, chosen by the particle type, three of its input fields as the force: each
// field of quarry_drag_input arrives as drag_udf.h documents it.
TEST(DragUdf, EveryInputReachesTheUdf) {
  TemporaryFolder folder;
  const std::string library = build_udf(folder.path(), "echo", R"(
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_EXPORT_ABI()
QUARRY_DRAG_UDF_PROTOTYPE(usrEcho);
static void put(quarry_drag_output* out, double x, double y, double z) {
  out->force[0] = x; out->force[1] = y; out->force[2] = z;
}
int usrEcho(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  switch (in->particle_type) {
    case 0: put(out, in->particle_volume, in->particle_diameter, in->porosity); break;
    case 1: put(out, in->particle_velocity[0], in->particle_velocity[1], in->particle_velocity[2]); break;
    case 2: put(out, in->fluid_velocity[0], in->fluid_velocity[1], in->fluid_velocity[2]); break;
    case 3: put(out, in->pressure_gradient[0], in->pressure_gradient[1], in->pressure_gradient[2]); break;
    case 4: put(out, in->fluid_viscosity, in->fluid_density, in->reynolds_number); break;
    case 5: put(out, (double)in->particle_id, in->time, (double)in->struct_size); break;
    case 6: put(out, (double)out->struct_size, user == 0 ? 1.0 : 0.0, out->message[0] == 0 ? 1.0 : 0.0); break;
    default: return quarry_drag_fail(out, "unknown type");
  }
  return 0;
}
)");
  const DragUdf udf = load_drag_udf(library, "usrEcho");
  DragInput input;
  input.diameter = 2e-3;
  input.particle_velocity = {0.25, -0.5, 0.125};
  input.fluid_velocity = {1.0, 2.0, -3.0};
  input.porosity = 0.6;
  input.fluid_viscosity = 1.8e-5;
  input.fluid_density = 1.2;
  DragUdfContext context;
  context.pressure_gradient = {-10.0, 20.0, 9810.0};
  context.particle_id = 123456789012345ULL;
  context.time = 0.0125;
  const auto echo = [&](std::uint32_t type) {
    context.particle_type = type;
    return udf.evaluate(input, context).force;
  };
  // Volume: a sphere's by default.
  EXPECT_EQ(echo(0), (Vec3{kPi / 6.0 * 2e-3 * 2e-3 * 2e-3, 2e-3, 0.6}));
  EXPECT_EQ(echo(1), input.particle_velocity);
  EXPECT_EQ(echo(2), input.fluid_velocity);
  EXPECT_EQ(echo(3), context.pressure_gradient);
  // Re_p on the superficial slip, as superficial_reynolds_number.
  const double slip = norm(input.fluid_velocity - input.particle_velocity);
  const Vec3 properties = echo(4);
  EXPECT_EQ(properties.x, 1.8e-5);
  EXPECT_EQ(properties.y, 1.2);
  EXPECT_EQ(properties.z, superficial_reynolds_number(input));
  EXPECT_NEAR(properties.z, 1.2 * 0.6 * slip * 2e-3 / 1.8e-5, 1e-13 * properties.z);
  EXPECT_EQ(echo(5), (Vec3{123456789012345.0, 0.0125, double(sizeof(quarry_drag_input))}));
  EXPECT_EQ(echo(6), (Vec3{double(sizeof(quarry_drag_output)), 1.0, 1.0}));  // user NULL, zeroed
  // A volume the caller gives (a non-spherical particle) is passed as it is.
  context.particle_volume = 3.5e-9;
  EXPECT_EQ(echo(0).x, 3.5e-9);
}

// Without a drag coefficient the coefficient is the force's projection on the slip,
// F·(u − v)/|u − v|², and 0 at zero slip.
TEST(DragUdf, CoefficientFromTheForceWhenTheUdfGivesNone) {
  TemporaryFolder folder;
  const std::string library = build_udf(folder.path(), "linear", R"(
#include <quarry/drag_udf.h>
QUARRY_DRAG_UDF_EXPORT_ABI()
QUARRY_DRAG_UDF_PROTOTYPE(usrLinear);
int usrLinear(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  for (int i = 0; i < 3; ++i) out->force[i] = 2.5e-6 * (in->fluid_velocity[i] - in->particle_velocity[i]);
  return 0;
}
)");
  const DragUdf udf = load_drag_udf(library, "usrLinear");
  DragInput input = seed_particle_input({0.3, -0.4, 1.2});
  EXPECT_NEAR(udf.evaluate(input).coefficient, 2.5e-6, 1e-15 * 2.5e-6 * 4);
  input.fluid_velocity = input.particle_velocity;
  EXPECT_EQ(udf.evaluate(input).coefficient, 0.0);
  EXPECT_EQ(udf.evaluate(input).force, Vec3{});
}

// The seed's case through the UDF: a 0.1 mm, 1500 kg/m³ sphere released at rest in still water
// (1000 kg/m³, 1e-3 Pa·s), gravity and buoyancy (ρ_p − ρ_f) V g, drag from usrStokesDrag.so,
// forward Euler with dt = τ/100, τ = ρ_p d²/(18 μ) = 8.33e-4 s the particle's relaxation time.
// The drag is linear, F = −β v with m/β = τ, so forward Euler gives v_n = −v_t (1 − (1 − h)^n)
// exactly, h = dt/τ = 0.01: its fixed point is v_t itself, whatever dt < 2τ. After n = 3000
// steps (30 τ) the relative distance to v_t is (1 − h)^n = 8.0e-14, plus rounding (≈ n ulp,
// 7e-13): the bound 1e-11 holds with margin and is far inside the 1 % asked; the
// analytic v_t = (ρ_p − ρ_f) g d²/(18 μ) = 0.002725 m/s (seed 001; EDEM's coupled run gave
// 0.00274). The built-in law integrated alike stays within round-off of it.
TEST(DragUdf, SeedParticleSettlesAtTheStokesTerminalVelocity) {
  TemporaryFolder folder;
  const DragUdf udf = load_drag_udf(build_stokes_example(folder.path()), "usrStokesDrag");
  const double diameter = 1e-4, particle_density = 1500.0, fluid_density = 1000.0;
  const double viscosity = 1e-3, gravity = 9.81;
  const double volume = kPi / 6.0 * diameter * diameter * diameter;  // m³
  const double mass = particle_density * volume;                     // kg
  const double relaxation_time = particle_density * diameter * diameter / (18.0 * viscosity);  // s
  const double terminal = (particle_density - fluid_density) * gravity * diameter * diameter /
                          (18.0 * viscosity);  // m/s
  ASSERT_NEAR(terminal, 0.002725, 1e-15);
  const double dt = relaxation_time / 100.0;
  const Vec3 weight_less_buoyancy{0.0, 0.0,
                                  -(particle_density - fluid_density) * volume * gravity};  // N

  Vec3 velocity, velocity_builtin;  // m/s
  const int steps = 3000;
  for (int n = 1; n <= steps; ++n) {
    DragUdfContext context;
    context.time = n * dt;
    const Vec3 drag = udf.evaluate(seed_particle_input(velocity), context).force;
    const Vec3 drag_builtin = stokes_drag(seed_particle_input(velocity_builtin)).force;
    velocity += dt / mass * (weight_less_buoyancy + drag);
    velocity_builtin += dt / mass * (weight_less_buoyancy + drag_builtin);
    ASSERT_NEAR(velocity.z, velocity_builtin.z, 1e-12 * terminal) << "step " << n;
    if (n == 100) {  // t = τ: forward Euler's exact discrete solution
      const double discrete = -terminal * (1.0 - std::pow(1.0 - dt / relaxation_time, 100));
      EXPECT_NEAR(velocity.z, discrete, 1e-12 * terminal);
      // and 0.29 % (first order in h) from the continuous −v_t (1 − 1/e).
      EXPECT_NEAR(velocity.z / (-terminal * (1.0 - std::exp(-1.0))), 1.0, 0.003);
    }
  }
  EXPECT_EQ(velocity.x, 0.0);
  EXPECT_EQ(velocity.y, 0.0);
  const double residual = std::pow(1.0 - dt / relaxation_time, steps);
  EXPECT_LT(residual, 1e-13);
  EXPECT_NEAR(-velocity.z, 0.002725, 1e-2 * 0.002725);   // the issue's 1 %, on the seed's value
  EXPECT_NEAR(-velocity.z, terminal, 1e-11 * terminal);  // the derived bound
  // Stokes regime: Re_p = ρ_f v_t d / μ = 0.2725 (< 0.3, as the seed says).
  EXPECT_NEAR(superficial_reynolds_number(seed_particle_input(velocity)), 0.2725, 1e-9);
}

// The library stays open while any copy of a DragUdf lives, however the copies are made and
// dropped; dlopen counts references, so each load closes once (ASan/LSan check the handles in
// the debug-asan preset, and a call through a closed library would crash).
TEST(DragUdf, CopiesKeepTheLibraryOpen) {
  TemporaryFolder folder;
  const std::string library = build_stokes_example(folder.path());
  std::vector<DragUdf> loaded;
  for (int i = 0; i < 3; ++i) loaded.push_back(load_drag_udf(library, "usrStokesDrag"));
  const DragInput input = seed_particle_input({0.0, 0.0, -0.001});
  const double expected = stokes_drag(input).force.z;
  DragUdf kept = loaded.front();
  loaded.clear();
  EXPECT_TRUE(within_roundoff(kept.evaluate(input).force.z, expected));
  DragUdf moved = std::move(kept);
  EXPECT_TRUE(within_roundoff(moved.evaluate(input).force.z, expected));
}

}  // namespace
}  // namespace quarry::cfd
