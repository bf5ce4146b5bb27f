// Drag laws: each per-particle coefficient β_p (kg/s) is written through C_d·Re, which stays
// finite as the slip goes to zero, so zero slip gives the Re → 0 limit and no 0/0.
#include "cfd/drag_laws.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace quarry::cfd {
namespace {

constexpr double kPi = std::numbers::pi;

// Gidaspow's switch between Ergun and Wen-Yu, on ε (Gidaspow 1994).
constexpr double kGidaspowSwitchPorosity = 0.8;
// Schiller-Naumann's switch to the Newton regime, on Re.
constexpr double kNewtonRegimeReynolds = 1000.0;
constexpr double kNewtonDragCoefficient = 0.44;
// Koch-Hill's switch of F0 to Carman-Kozeny, on φ.
constexpr double kKochHillDenseSolidFraction = 0.4;

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

[[noreturn]] void reject(std::string_view what, double value, std::string_view requirement) {
  throw std::invalid_argument(
      fmt::format("drag law: {} must be {}, got {}", what, requirement, value));
}

[[noreturn]] void reject(std::string_view what, const Vec3& value) {
  throw std::invalid_argument(fmt::format("drag law: {} must be finite, got ({}, {}, {})", what,
                                          value.x, value.y, value.z));
}

// C_d·Re of Schiller-Naumann: 24 (1 + 0.15 Re^0.687) below Re = 1000, 0.44 Re from there.
double schiller_naumann_cd_times_re(double reynolds) {
  if (reynolds < kNewtonRegimeReynolds) return 24.0 * (1.0 + 0.15 * std::pow(reynolds, 0.687));
  return kNewtonDragCoefficient * reynolds;
}

// C_d·Re of Dallavalle: (0.63 √Re + 4.8)².
double dallavalle_cd_times_re(double reynolds) {
  const double root = 0.63 * std::sqrt(reynolds) + 4.8;
  return root * root;
}

// Koch-Hill's F0(φ) (Hill, Koch & Ladd 2001; Benyahia et al. 2006).
double koch_hill_f0(double solid_fraction) {
  const double phi = solid_fraction;
  if (phi == 0.0) return 1.0;  // the limit: φ ln φ → 0 (ln 0 would give 0·∞)
  if (phi < kKochHillDenseSolidFraction) {
    const double numerator =
        1.0 + 3.0 * std::sqrt(phi / 2.0) + (135.0 / 64.0) * phi * std::log(phi) + 16.14 * phi;
    const double denominator = 1.0 + 0.681 * phi - 8.48 * phi * phi + 8.16 * phi * phi * phi;
    return numerator / denominator;
  }
  const double porosity = 1.0 - phi;
  return 10.0 * phi / (porosity * porosity * porosity);
}

// Koch-Hill's F3(φ) = 0.0673 + 0.212 φ + 0.0232/ε⁵.
double koch_hill_f3(double solid_fraction) {
  const double porosity = 1.0 - solid_fraction;
  const double porosity2 = porosity * porosity;
  return 0.0673 + 0.212 * solid_fraction + 0.0232 / (porosity2 * porosity2 * porosity);
}

DragResult along_slip(const DragInput& input, double coefficient) {
  return DragResult{coefficient * slip_velocity(input), coefficient};
}

}  // namespace

void check_drag_input(const DragInput& input) {
  if (!(input.diameter > 0.0) || !std::isfinite(input.diameter))
    reject("particle diameter (m)", input.diameter, "finite and > 0");
  if (!(input.porosity > 0.0 && input.porosity <= 1.0))
    reject("porosity (fluid volume fraction)", input.porosity, "in (0, 1]");
  if (!(input.fluid_density > 0.0) || !std::isfinite(input.fluid_density))
    reject("fluid density (kg/m³)", input.fluid_density, "finite and > 0");
  if (!(input.fluid_viscosity > 0.0) || !std::isfinite(input.fluid_viscosity))
    reject("fluid viscosity (Pa·s)", input.fluid_viscosity, "finite and > 0");
  if (!finite(input.particle_velocity)) reject("particle velocity (m/s)", input.particle_velocity);
  if (!finite(input.fluid_velocity)) reject("fluid velocity (m/s)", input.fluid_velocity);
}

Vec3 slip_velocity(const DragInput& input) {
  return input.fluid_velocity - input.particle_velocity;
}

double slip_reynolds_number(const DragInput& input) {
  return input.fluid_density * norm(slip_velocity(input)) * input.diameter / input.fluid_viscosity;
}

double superficial_reynolds_number(const DragInput& input) {
  return input.fluid_density * input.porosity * norm(slip_velocity(input)) * input.diameter /
         input.fluid_viscosity;
}

double particle_volume(const DragInput& input) {
  return kPi / 6.0 * input.diameter * input.diameter * input.diameter;
}

double volumetric_exchange_coefficient(double particle_coefficient, const DragInput& input) {
  return (1.0 - input.porosity) * particle_coefficient / particle_volume(input);
}

double schiller_naumann_drag_coefficient(double reynolds) {
  return schiller_naumann_cd_times_re(reynolds) / reynolds;
}

double dallavalle_drag_coefficient(double reynolds) {
  const double root = 0.63 + 4.8 / std::sqrt(reynolds);
  return root * root;
}

double di_felice_exponent(double reynolds) {
  if (reynolds == 0.0) return 3.7;  // the limit: log10 Re → −∞, the exponential → 0
  const double distance = 1.5 - std::log10(reynolds);
  return 3.7 - 0.65 * std::exp(-distance * distance / 2.0);
}

double koch_hill_dimensionless_drag(double solid_fraction, double reynolds) {
  return koch_hill_f0(solid_fraction) + 0.5 * koch_hill_f3(solid_fraction) * reynolds;
}

double beetstra_dimensionless_drag(double solid_fraction, double reynolds) {
  const double phi = solid_fraction;
  const double porosity = 1.0 - phi;
  const double porosity2 = porosity * porosity;
  // Stokes part (van der Hoef, Beetstra & Kuipers 2005, J. Fluid Mech. 528:233-254).
  const double stokes_part = 10.0 * phi / porosity2 + porosity2 * (1.0 + 1.5 * std::sqrt(phi));
  if (reynolds == 0.0) return stokes_part;  // Re · Re^(−0.343) → 0; the 0·∞ is avoided
  const double inertial_part =
      0.413 * reynolds / (24.0 * porosity2) *
      (1.0 / porosity + 3.0 * porosity * phi + 8.4 * std::pow(reynolds, -0.343)) /
      (1.0 + std::pow(10.0, 3.0 * phi) * std::pow(reynolds, -(1.0 + 4.0 * phi) / 2.0));
  return stokes_part + inertial_part;
}

DragResult stokes_drag(const DragInput& input) {
  check_drag_input(input);
  // β_p = 3π ε d μ (seed 001).
  return along_slip(input, 3.0 * kPi * input.porosity * input.diameter * input.fluid_viscosity);
}

DragResult schiller_naumann_drag(const DragInput& input) {
  check_drag_input(input);
  // β_p = ½ ρ_f C_d (π d²/4) |u − v| = (π/8) μ d (C_d Re), since ρ_f |u − v| d = Re μ.
  const double reynolds = slip_reynolds_number(input);
  return along_slip(input, kPi / 8.0 * input.fluid_viscosity * input.diameter *
                               schiller_naumann_cd_times_re(reynolds));
}

DragResult di_felice_drag(const DragInput& input) {
  check_drag_input(input);
  // β_p = ½ C_d ρ_f (π d²/4) ε^(2−χ) |u − v| = (π/8) μ d ε^(1−χ) (C_d Re_p),
  // since ρ_f |u − v| d = Re_p μ / ε.
  const double reynolds = superficial_reynolds_number(input);
  const double exponent = di_felice_exponent(reynolds);
  return along_slip(input, kPi / 8.0 * input.fluid_viscosity * input.diameter *
                               std::pow(input.porosity, 1.0 - exponent) *
                               dallavalle_cd_times_re(reynolds));
}

DragResult gidaspow_drag(const DragInput& input) {
  check_drag_input(input);
  const double porosity = input.porosity;
  const double viscosity = input.fluid_viscosity;
  const double diameter = input.diameter;
  if (porosity < kGidaspowSwitchPorosity) {
    // Ergun: β_p = β V_p/(1 − ε) = V_p [150 (1 − ε) μ / (ε d²) + 1.75 ρ_f |u − v| / d].
    const double slip = norm(slip_velocity(input));
    const double per_volume =
        150.0 * (1.0 - porosity) * viscosity / (porosity * diameter * diameter) +
        1.75 * input.fluid_density * slip / diameter;
    return along_slip(input, particle_volume(input) * per_volume);
  }
  // Wen-Yu: β_p = ½ C_d ρ_f (π d²/4) ε^(−1.65) |u − v| = (π/8) μ d ε^(−2.65) (C_d Re_p),
  // since ρ_f |u − v| d = Re_p μ / ε.
  const double reynolds = superficial_reynolds_number(input);
  return along_slip(input, kPi / 8.0 * viscosity * diameter * std::pow(porosity, -2.65) *
                               schiller_naumann_cd_times_re(reynolds));
}

DragResult koch_hill_drag(const DragInput& input) {
  check_drag_input(input);
  // β_p = 3π μ d ε² F(φ, Re_p) (Benyahia et al. 2006: β = 18 μ ε² φ F / d², times V_p/φ).
  const double porosity = input.porosity;
  const double dimensionless =
      koch_hill_dimensionless_drag(1.0 - porosity, superficial_reynolds_number(input));
  return along_slip(input, 3.0 * kPi * input.fluid_viscosity * input.diameter * porosity *
                               porosity * dimensionless);
}

DragResult beetstra_drag(const DragInput& input) {
  check_drag_input(input);
  // β_p = 3π μ d ε F(φ, Re_p): Stokes' drag at the superficial slip ε |u − v| times F.
  const double porosity = input.porosity;
  const double dimensionless =
      beetstra_dimensionless_drag(1.0 - porosity, superficial_reynolds_number(input));
  return along_slip(input,
                    3.0 * kPi * input.fluid_viscosity * input.diameter * porosity * dimensionless);
}

std::string_view drag_law_name(DragLaw law) {
  for (const DragLawName& entry : kDragLawNames)
    if (entry.law == law) return entry.name;
  throw std::invalid_argument(
      fmt::format("drag law: no law has the value {}", static_cast<int>(law)));
}

std::optional<DragLaw> drag_law_from_name(std::string_view name) {
  for (const DragLawName& entry : kDragLawNames)
    if (entry.name == name) return entry.law;
  return std::nullopt;
}

DragResult drag_force(DragLaw law, const DragInput& input) {
  switch (law) {
    case DragLaw::stokes:
      return stokes_drag(input);
    case DragLaw::schiller_naumann:
      return schiller_naumann_drag(input);
    case DragLaw::di_felice:
      return di_felice_drag(input);
    case DragLaw::gidaspow:
      return gidaspow_drag(input);
    case DragLaw::koch_hill:
      return koch_hill_drag(input);
    case DragLaw::beetstra:
      return beetstra_drag(input);
  }
  throw std::invalid_argument(
      fmt::format("drag law: no law has the value {}", static_cast<int>(law)));
}

}  // namespace quarry::cfd
