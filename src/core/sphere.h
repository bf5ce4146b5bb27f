// Volume and mass of a sphere, written once (the particles, the factories, the time-step
// choice, the coupled structures' checks, the fluid's void fraction and the ABI all need them).
#pragma once
#include <numbers>

namespace quarry {

// V = 4/3 π r³ (m³) for a radius r (m).
constexpr double sphere_volume(double radius) {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

// m = ρ 4/3 π r³ (kg) for a density ρ (kg/m³), multiplied in this order (the bits the particle
// store has always had; ρ · sphere_volume(r) would round differently).
constexpr double sphere_mass(double density, double radius) {
  return density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

}  // namespace quarry
