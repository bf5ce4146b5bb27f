// Order of accuracy of the integrators on a harmonic oscillator x'' = −ω² x (closed form
// x = cos ωt): halving dt must divide the error at a quarter period (where x crosses zero, so
// the error is first order in the phase error — at whole periods it would be second order and
// hide the method's order) by 4 for velocity Verlet
// (second order, Swope et al. 1982) and by 2 for symplectic Euler (first order, Hairer, Lubich
// & Wanner, Geometric Numerical Integration, 2006, §I.1). The same kick/drift sequence as
// sim::step is used, with the spring force evaluated where step() evaluates contact forces.
#include "integrate/integrator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace quarry {
namespace {

// Position error at a quarter period, reached in `steps` steps; the particle has m = 1 kg (ρ chosen so).
double period_error(bool verlet, int steps) {
  const double omega = 3.0;                           // rad/s
  const double period = 2.0 * std::numbers::pi / omega;  // s
  const double dt = 0.25 * period / steps;            // s
  ParticleStore p;
  const double radius = 0.1;                          // m
  const double density = 1.0 / (4.0 / 3.0 * std::numbers::pi * radius * radius * radius);  // kg/m³ → m = 1 kg
  p.add(1, 0, 0, {1.0, 0, 0}, {}, radius, density, 0.0);
  auto spring = [&] { p.force[0] = p.position[0] * (-omega * omega / p.inv_mass[0]); };
  spring();
  for (int n = 0; n < steps; ++n) {
    integrate::kick_drift(p, verlet ? 0.5 * dt : dt, dt);
    spring();
    if (verlet) integrate::kick(p, 0.5 * dt);
  }
  return std::abs(p.position[0].x - std::cos(omega * dt * steps));
}

TEST(Integrator, VelocityVerletIsSecondOrder) {
  const double coarse = period_error(true, 200), fine = period_error(true, 400);
  EXPECT_NEAR(std::log2(coarse / fine), 2.0, 0.05);
}

TEST(Integrator, SymplecticEulerIsFirstOrder) {
  const double coarse = period_error(false, 200), fine = period_error(false, 400);
  EXPECT_NEAR(std::log2(coarse / fine), 1.0, 0.15);
}

}  // namespace
}  // namespace quarry
