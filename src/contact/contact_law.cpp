// make_interaction: turns two materials and the deck's interaction into the per-pair constants
// of the contact law, at setup. User values are checked here, every problem reported at once.
#include "contact/contact_law.h"

#include <fmt/format.h>

#include <string>
#include <utility>

#include "core/diagnostics.h"

namespace quarry {
namespace {

void check_material(const MaterialProperties& material, const Located<std::string>& name,
                    Diagnostics& diagnostics) {
  if (material.rigid) return;  // no elastic constants
  if (!(material.youngs_modulus > 0.0)) {
    diagnostics.error(name.where,
                      fmt::format("material \"{}\" has Young's modulus {} Pa; it must be positive",
                                  name.value, material.youngs_modulus));
  }
  // Isotropic elasticity needs −1 < ν <= 0.5 (positive bulk and shear moduli).
  if (!(material.poisson_ratio > -1.0 && material.poisson_ratio <= 0.5)) {
    diagnostics.error(name.where,
                      fmt::format("material \"{}\" has Poisson ratio {}; it must lie in (-1, 0.5]",
                                  name.value, material.poisson_ratio));
  }
}

void check_non_negative(const Located<double>& value, const char* what, Diagnostics& diagnostics) {
  if (!(value.value >= 0.0)) {
    diagnostics.error(value.where, fmt::format("{} is {}; it must be >= 0", what, value.value));
  }
}

}  // namespace

InteractionParameters make_interaction(const MaterialProperties& a, const MaterialProperties& b,
                                       const InteractionSpec& spec) {
  Diagnostics diagnostics;
  check_material(a, spec.material_a, diagnostics);
  check_material(b, spec.material_b, diagnostics);
  if (!(spec.restitution.value > 0.0 && spec.restitution.value <= 1.0)) {
    diagnostics.error(spec.restitution.where,
                      fmt::format("coefficient of restitution is {}; it must lie in (0, 1]",
                                  spec.restitution.value),
                      "1 is perfectly elastic; a value near 0 is almost fully damped");
  }
  check_non_negative(spec.static_friction, "static friction coefficient", diagnostics);
  check_non_negative(spec.rolling_friction, "rolling friction coefficient", diagnostics);
  check_non_negative(spec.cohesion_energy_density, "cohesion energy density", diagnostics);
  if (spec.normal_model.value == NormalModel::linear) {
    if (!(spec.linear_stiffness.value > 0.0)) {
      diagnostics.error(spec.linear_stiffness.where,
                        fmt::format("linear normal stiffness is {} N/m; the linear contact model "
                                    "needs a positive stiffness",
                                    spec.linear_stiffness.value));
    }
    check_non_negative(spec.linear_tangential_ratio, "linear tangential stiffness ratio",
                       diagnostics);
  }
  if (spec.cohesion_model.value == CohesionModel::jkr) {
    // JKR replaces the Hertz spring by the adhesive one and holds at negative overlap: a linear
    // spring has no contact radius, and clipping the attraction would undo the model.
    if (!(spec.surface_energy.value > 0.0)) {
      diagnostics.error(spec.cohesion_model.where,
                        fmt::format("JKR surface energy is {} J/m²; cohesion_model: jkr needs a "
                                    "positive surface_energy",
                                    spec.surface_energy.value));
    }
    if (spec.normal_model.value == NormalModel::linear) {
      diagnostics.error(spec.cohesion_model.where,
                        "cohesion_model: jkr needs the Hertz-Mindlin contact model",
                        "JKR's force follows from the Hertzian contact radius; remove model: linear");
    }
    if (spec.clip_attraction.value) {
      diagnostics.error(spec.clip_attraction.where,
                        "clip_attraction cannot be used with cohesion_model: jkr",
                        "JKR's adhesion is an attractive normal force; remove clip_attraction");
    }
  }
  if (diagnostics.has_errors()) throw UserError(std::move(diagnostics));

  InteractionParameters parameters;
  parameters.normal_model = spec.normal_model.value;
  parameters.effective_youngs_modulus = contact::effective_youngs_modulus(a, b);
  parameters.effective_shear_modulus = contact::effective_shear_modulus(a, b);
  parameters.restitution = spec.restitution.value;
  parameters.damping_ratio_beta = contact::damping_ratio_from_restitution(spec.restitution.value);
  parameters.static_friction = spec.static_friction.value;
  parameters.rolling_friction = spec.rolling_friction.value;
  // Without rolling friction every rolling model gives zero torque: skip its work per contact.
  parameters.rolling_model =
      spec.rolling_friction.value > 0.0 ? spec.rolling_model.value : RollingModel::none;
  parameters.cohesion_energy_density = spec.cohesion_energy_density.value;
  if (spec.cohesion_model.value == CohesionModel::jkr) {
    parameters.cohesion_energy_density = 0.0;
    parameters.surface_energy = spec.surface_energy.value;
  }
  parameters.linear_normal_stiffness = spec.linear_stiffness.value;
  parameters.linear_tangential_ratio = spec.linear_tangential_ratio.value;
  parameters.clip_attraction = spec.clip_attraction.value;
  // hertz_mindlin_damping_coefficient(β, k, m*) = −2 sqrt(5/6) β sqrt(k m*) with k = 2 E* a
  // (normal) or 8 G* a (tangential): the constant part, so that a contact needs one sqrt(a m*).
  parameters.hertz_normal_damping = contact::hertz_mindlin_damping_coefficient(
      parameters.damping_ratio_beta, 2.0 * parameters.effective_youngs_modulus, 1.0);
  parameters.hertz_tangential_damping = contact::hertz_mindlin_damping_coefficient(
      parameters.damping_ratio_beta, 8.0 * parameters.effective_shear_modulus, 1.0);
  return parameters;
}

}  // namespace quarry
