// Readers of the cards that define the structure: GRID, CQUAD4, CTRIA3, PSHELL, MAT1, MATS1, SPC
// and PARAM (the id-list cards are in bulk_sets.cpp). Fields as in the MSC Nastran Quick
// Reference Guide and Altair OptiStruct Reference Guide. Values stay in the file's units here;
// bulk_data.cpp converts them to SI once the units are known.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "io/bulk_model.h"

namespace quarry::bulk_detail {

namespace {

// Nastran's plausibility check of MAT1 when E, G and NU are all given (MSC Nastran MAT1
// remark: a warning when |1 − E / (2(1 + NU)G)| > 0.01).
constexpr double kMat1ConsistencyTolerance = 0.01;
// PSHELL defaults (Nastran): 12I/T³ = 1.0, TS/T = 0.833333.
constexpr double kDefaultBendingInertiaRatio = 1.0;
constexpr double kDefaultShearThicknessRatio = 0.833333;

Reference reference(int id, const Field& field, const Card& card, int owner) {
  return Reference{id, field.place, static_card_name(card.name), owner};
}

// A positive real, or reported.
void require_positive(FieldReader& fields, std::size_t index, std::string_view what,
                      const std::optional<double>& value) {
  if (value && !(*value > 0.0))
    fields.error(index, fmt::format("{} {} must be > 0, got {}", fields.card().name, what,
                                    fields.at(index).text));
}

}  // namespace

void read_grid(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "ID");
  const std::optional<std::int64_t> cp = fields.integer(1, "CP");
  if (cp && *cp != 0)
    fields.error(1, "coordinate systems are not supported: GRID CP must be blank or 0",
                 "give the position in the basic (global Cartesian) system");
  Vec3 position;
  const char* const names[] = {"X1", "X2", "X3"};
  for (int axis = 0; axis < 3; ++axis)
    position[axis] = fields.real(static_cast<std::size_t>(2 + axis), names[axis]).value_or(0.0);
  const std::optional<std::int64_t> cd = fields.integer(5, "CD");
  if (cd && *cd != 0)
    fields.error(5, "coordinate systems are not supported: GRID CD must be blank or 0",
                 "constraints and results are in the basic (global Cartesian) system");
  const std::optional<DofSet> permanent = fields.dofs(6, "PS", false, true);
  const std::optional<std::int64_t> superelement = fields.integer(7, "SEID");
  if (superelement && *superelement != 0)
    fields.error(7, "superelements are not supported: GRID SEID must be blank or 0");
  fields.reject_from(8);
  if (!id) return;
  const auto [entry, inserted] = state.model.nodes.try_emplace(*id);
  if (!inserted) {
    fields.error(0, fmt::format("duplicate GRID id {}", *id),
                 state.first_defined(entry->second.where));
    return;
  }
  entry->second.position = position;
  entry->second.permanent_constraints = permanent.value_or(DofSet{});
  entry->second.where = state.location(card.place);
}

void read_shell_element(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const bool quad = card.name == "CQUAD4";
  const int count = quad ? 4 : 3;
  const std::optional<int> id = fields.id(0, "EID");
  // PID defaults to EID (Nastran).
  const std::optional<int> property = fields.blank(1) ? id : fields.id(1, "PID");
  ShellElement element;
  element.shape = quad ? ShellShape::quad4 : ShellShape::tria3;
  bool nodes_valid = true;
  for (int k = 0; k < count; ++k) {
    const std::size_t index = static_cast<std::size_t>(2 + k);
    const std::optional<int> node = fields.id(index, fmt::format("G{}", k + 1));
    if (!node) {
      nodes_valid = false;
      continue;
    }
    for (int previous = 0; previous < k; ++previous) {
      if (element.nodes[static_cast<std::size_t>(previous)] == *node) {
        fields.error(index,
                     fmt::format("{} {} names grid {} twice", card.name, id.value_or(0), *node),
                     quad ? "a quadrilateral with two equal corners is a triangle: write it as "
                            "a CTRIA3"
                          : "a triangle needs three different grid points");
        nodes_valid = false;
      }
    }
    element.nodes[static_cast<std::size_t>(k)] = *node;
  }
  const std::size_t theta = static_cast<std::size_t>(2 + count);
  // THETA/MCID orients the material axes, which an isotropic material does not have: read
  // to check it, not kept.
  if (!fields.blank(theta) && !parse_real(fields.at(theta).text))
    fields.error(theta, fmt::format("{} THETA/MCID must be a real or an integer, got \"{}\"",
                                    card.name, fields.at(theta).text));
  const std::optional<double> offset = fields.real(theta + 1, "ZOFFS");
  if (offset && *offset != 0.0)
    fields.error(theta + 1, fmt::format("{} offsets (ZOFFS) are not supported", card.name),
                 "model the shell at its mid-surface");
  // The continuation line holds TFLAG and corner thicknesses T1-T4.
  for (std::size_t i = theta + 2; i < card.fields.size(); ++i) {
    if (fields.blank(i)) continue;
    if (i >= Card::index(1, 4) && i <= Card::index(1, 4 + count))
      fields.error(
          i,
          fmt::format("{} corner thicknesses (TFLAG, T1-T{}) are not supported", card.name, count),
          "the thickness comes from the PSHELL");
    else
      fields.reject_from(i);
    break;
  }
  if (!id) return;
  const std::size_t index = state.model.shells.size();
  const auto [entry, inserted] = state.element_index.try_emplace(*id, index);
  if (!inserted) {
    fields.error(0, fmt::format("duplicate element id {}", *id),
                 state.first_defined(state.model.shells[entry->second].where));
    return;
  }
  element.id = *id;
  element.property_id = property.value_or(0);
  element.where = state.location(card.place);
  state.model.shells.push_back(element);
  if (property)
    state.property_references.push_back(
        reference(*property, fields.at(fields.blank(1) ? 0 : 1), card, *id));
  if (nodes_valid)
    for (int k = 0; k < count; ++k)
      state.grid_references.push_back(reference(element.nodes[static_cast<std::size_t>(k)],
                                                fields.at(static_cast<std::size_t>(2 + k)), card,
                                                *id));
}

void read_pshell(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "PID");
  ShellProperty property;
  std::optional<int> membrane;
  if (fields.blank(1))
    fields.error(1, "PSHELL MID1 is missing",
                 "a PSHELL without MID1 has no membrane stiffness; Quarry's shells need one");
  else
    membrane = fields.id(1, "MID1");
  const std::optional<double> thickness = fields.real(2, "T", true);
  require_positive(fields, 2, "T", thickness);
  const std::optional<std::int64_t> mid2 = fields.integer(3, "MID2");
  if (mid2 && *mid2 == -1)
    fields.error(3, "PSHELL MID2 = -1 (plane strain) is not supported",
                 "give the bending material, usually MID1");
  else if (mid2)
    property.bending_material_id = fields.id(3, "MID2");
  property.bending_inertia_ratio = fields.real(4, "12I/T**3").value_or(kDefaultBendingInertiaRatio);
  require_positive(fields, 4, "12I/T**3",
                   fields.blank(4) ? std::nullopt : parse_real(fields.at(4).text));
  property.shear_material_id = fields.id(5, "MID3", false);
  property.shear_thickness_ratio = fields.real(6, "TS/T").value_or(kDefaultShearThicknessRatio);
  require_positive(fields, 6, "TS/T",
                   fields.blank(6) ? std::nullopt : parse_real(fields.at(6).text));
  property.nonstructural_mass = fields.real(7, "NSM").value_or(0.0);
  if (property.nonstructural_mass < 0.0)
    fields.error(7, fmt::format("PSHELL NSM must be ≥ 0, got {}", fields.at(7).text));
  const double t = thickness.value_or(0.0);
  property.fiber_bottom = fields.real(Card::index(1, 2), "Z1").value_or(-0.5 * t);
  property.fiber_top = fields.real(Card::index(1, 3), "Z2").value_or(0.5 * t);
  if (!fields.blank(Card::index(1, 4)))
    fields.error(Card::index(1, 4), "PSHELL MID4 (membrane-bending coupling) is not supported",
                 "leave MID4 blank: Quarry's shells are homogeneous through the thickness");
  else
    fields.reject_from(Card::index(1, 5));
  if (!id) return;
  property.id = *id;
  property.thickness = t;
  property.membrane_material_id = membrane.value_or(0);
  property.where = state.location(card.place);
  const auto [entry, inserted] = state.model.properties.try_emplace(*id, property);
  if (!inserted) {
    fields.error(0, fmt::format("duplicate PSHELL id {}", *id),
                 state.first_defined(entry->second.where));
    return;
  }
  if (membrane) state.material_references.push_back(reference(*membrane, fields.at(1), card, *id));
  if (property.bending_material_id)
    state.material_references.push_back(
        reference(*property.bending_material_id, fields.at(3), card, *id));
  if (property.shear_material_id)
    state.material_references.push_back(
        reference(*property.shear_material_id, fields.at(5), card, *id));
}

void read_mat1(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "MID");
  std::optional<double> e = fields.real(1, "E");
  std::optional<double> g = fields.real(2, "G");
  std::optional<double> nu = fields.real(3, "NU");
  const double density = fields.real(4, "RHO").value_or(0.0);
  // A, TREF, GE, ST, SC, SS, MCSID: thermal expansion, damping for frequency response and
  // stress limits, none of which an explicit shell model uses. Checked, not kept.
  for (const auto& [index, what] : {std::pair<std::size_t, const char*>{5, "A"},
                                    {6, "TREF"},
                                    {7, "GE"},
                                    {8, "ST"},
                                    {9, "SC"},
                                    {10, "SS"}})
    fields.real(index, what);
  fields.integer(11, "MCSID");
  fields.reject_from(12);

  // Nastran's rule (MAT1 remarks): E or G must be given; one blank of E, G, NU follows from
  // E = 2(1 + NU)G. Two blanks would be set to 0.0, which leaves a shell without shear or
  // bending stiffness: refused here.
  const int blanks = !e + !g + !nu;
  const bool read_all = fields.ok();
  if (read_all && !e && !g) {
    fields.error(1, "MAT1 needs E or G", "give two of E, G and NU");
  } else if (read_all && blanks == 2) {
    fields.error(
        !e ? 1 : (!g ? 2 : 3),
        fmt::format("MAT1 gives only {}: Nastran would set the other two to 0.0", e ? "E" : "G"),
        "give two of E, G and NU; the third follows from E = 2(1 + NU)G");
  } else if (read_all) {
    if (e && !(*e > 0.0)) fields.error(1, fmt::format("MAT1 E must be > 0, got {}", *e));
    if (g && !(*g > 0.0)) fields.error(2, fmt::format("MAT1 G must be > 0, got {}", *g));
    if (nu && !(*nu > -1.0 && *nu < 0.5))
      fields.error(3, fmt::format("MAT1 NU must be in (-1, 0.5), got {}", *nu));
    if (fields.ok()) {
      if (!e) e = 2.0 * (1.0 + *nu) * *g;
      if (!g) g = *e / (2.0 * (1.0 + *nu));
      if (!nu) {
        nu = *e / (2.0 * *g) - 1.0;
        if (!(*nu > -1.0 && *nu < 0.5))
          fields.error(1,
                       fmt::format("MAT1 E and G give NU = E/(2G) − 1 = {:.4g}, outside "
                                   "(-1, 0.5)",
                                   *nu),
                       "check E and G, or give NU");
      } else if (blanks == 0 &&
                 std::abs(1.0 - *e / (2.0 * (1.0 + *nu) * *g)) > kMat1ConsistencyTolerance) {
        state.problems.warning(
            fields.at(2).place,
            fmt::format("MAT1 E, G and NU do not satisfy E = 2(1 + NU)G (E/(2(1 + NU)G) = "
                        "{:.4g}); shells use E and NU in plane and G for transverse shear",
                        *e / (2.0 * (1.0 + *nu) * *g)),
            "give only two of them unless the difference is meant");
      }
    }
  }
  if (density < 0.0) fields.error(4, fmt::format("MAT1 RHO must be ≥ 0, got {}", density));
  if (!id) return;
  IsotropicMaterial material;
  material.id = *id;
  material.youngs_modulus = e.value_or(0.0);
  material.shear_modulus = g.value_or(0.0);
  material.poisson_ratio = nu.value_or(0.0);
  material.density = density;
  material.where = state.location(card.place);
  const auto [entry, inserted] = state.model.materials.try_emplace(*id, material);
  if (!inserted)
    fields.error(0, fmt::format("duplicate MAT1 id {}", *id),
                 state.first_defined(entry->second.where));
}

void read_mats1(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> id = fields.id(0, "MID");
  const std::optional<std::int64_t> table = fields.integer(1, "TID");
  if (table && *table != 0)
    fields.error(1, "MATS1 stress-strain tables (TID) are not supported",
                 "give the initial yield stress in LIMIT1 and a constant hardening slope in H");
  const std::string type = fields.word(2);
  if (type.empty())
    fields.missing(2, "TYPE");
  else if (type == "NLELAST")
    fields.error(2, "MATS1 TYPE NLELAST (nonlinear elastic) is not supported",
                 "TYPE PLASTIC: J2 plasticity with isotropic hardening");
  else if (type != "PLASTIC")
    fields.error(2, fmt::format("unknown MATS1 TYPE \"{}\"", fields.at(2).text),
                 "TYPE PLASTIC: J2 plasticity with isotropic hardening");
  const std::optional<double> slope = fields.real(3, "H");
  if (!slope && !(table && *table != 0))
    fields.missing(3, "H");
  else if (slope && *slope < 0.0)
    fields.error(3, fmt::format("MATS1 H must be ≥ 0, got {}", fields.at(3).text),
                 "softening is not supported; H = 0.0 is ideally plastic");
  const std::optional<std::int64_t> criterion = fields.integer(4, "YF");
  if (criterion && *criterion != 1)
    fields.error(4, fmt::format("MATS1 YF = {} is not supported", *criterion),
                 "YF = 1 (von Mises) is the only yield function supported");
  // HR may be a real in OptiStruct (mixed hardening); only 1 = isotropic is supported.
  const std::optional<double> rule = fields.real(5, "HR");
  if (rule && *rule != 1.0)
    fields.error(5, fmt::format("MATS1 HR = {} is not supported", fields.at(5).text),
                 "HR = 1 (isotropic hardening) is the only hardening rule supported");
  const std::optional<double> yield = fields.real(6, "LIMIT1", true);
  require_positive(fields, 6, "LIMIT1", yield);
  fields.real(7, "LIMIT2");  // friction angle of Mohr-Coulomb/Drucker-Prager: unused
  for (std::size_t i = Card::index(1, 2); i < card.fields.size(); ++i) {
    if (fields.blank(i)) continue;
    fields.error(i, "MATS1 continuation lines (TYPSTRN, JHCOOK, ...) are not supported",
                 "J2 plasticity with LIMIT1 and H on the first line is what Quarry reads");
    break;
  }
  if (!id) return;
  J2Plasticity plasticity;
  plasticity.initial_yield_stress = yield.value_or(0.0);
  plasticity.hardening_modulus = slope.value_or(0.0);
  plasticity.where = state.location(card.place);
  const auto [entry, inserted] = state.plasticity.try_emplace(*id, plasticity);
  if (!inserted) {
    fields.error(0, fmt::format("a second MATS1 for material {}", *id),
                 state.first_defined(entry->second.where));
    return;
  }
  state.plasticity_references.push_back(reference(*id, fields.at(0), card, *id));
}

void read_spc(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  const std::optional<int> set = fields.id(0, "SID");
  for (int pair = 0; pair < 2; ++pair) {
    const std::size_t g = static_cast<std::size_t>(1 + 3 * pair);
    const std::string suffix = std::to_string(pair + 1);
    if (pair == 1 && fields.blank(g) && fields.blank(g + 1) && fields.blank(g + 2)) break;
    const std::optional<int> node = fields.id(g, "G" + suffix);
    const std::optional<DofSet> dofs = fields.dofs(g + 1, "C" + suffix, true, false);
    const std::optional<double> value = fields.real(g + 2, "D" + suffix);
    if (value && *value != 0.0)
      fields.error(g + 2, "enforced displacements (SPC D ≠ 0) are not supported",
                   "Quarry fixes the listed DOFs; prescribe motion in the deck");
    if (!set || !node || !dofs) continue;
    SinglePointConstraint constraint;
    constraint.set_id = *set;
    constraint.dofs = *dofs;
    constraint.nodes = {*node};
    constraint.where = state.location(card.place);
    state.model.constraints.push_back(std::move(constraint));
    state.grid_references.push_back(reference(*node, fields.at(g), card, *set));
  }
  fields.reject_from(7);
}
void read_param(const Card& card, ModelState& state) {
  FieldReader fields(card, state);
  if (fields.word(0) == "WTMASS") {
    const std::optional<double> factor = fields.real(1, "WTMASS value");
    if (factor && *factor != 1.0) {
      fields.error(1, fmt::format("PARAM,WTMASS = {} scales every mass", fields.at(1).text),
                   "Quarry reads masses in the declared units: remove WTMASS and give "
                   "densities as such (t/mm³ with UNITS = MPA)");
      return;
    }
  }
  state.ignore("PARAM", card.place);
}

}  // namespace quarry::bulk_detail
