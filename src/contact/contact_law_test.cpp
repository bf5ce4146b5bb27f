// Contact-law composition: pair parameters from materials (E*, G*, β), user-error checks,
// conservation of momentum and angular momentum at one contact, wall conventions, release.
#include "contact/contact_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "contact/hertz_mindlin_batch.h"

namespace quarry {
namespace {

const MaterialProperties steel{7800.0, 2.0e11, 0.3};
const MaterialProperties glass{2500.0, 7.0e10, 0.25};

TEST(MakeInteraction, EffectiveModuliAndDampingRatioMatchHandComputation) {
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.4;
  spec.rolling_friction = 0.01;
  const InteractionParameters parameters = make_interaction(steel, glass, spec);
  // 1/E* = (1 − 0.09)/2e11 + (1 − 0.0625)/7e10 = 4.55e-12 + 1.3392857e-11 = 1.7942857e-11 1/Pa
  // → E* = 5.5732484e10 Pa (Johnson 1985 eq. 4.22).
  EXPECT_NEAR(parameters.effective_youngs_modulus, 5.5732484e10, 1e3);
  // 1/G* = 2 · 1.7 · 1.3 / 2e11 + 2 · 1.75 · 1.25 / 7e10 = 2.21e-11 + 6.25e-11 = 8.46e-11 1/Pa
  // → G* = 1.1820331e10 Pa (EDEM guide; Mindlin & Deresiewicz 1953).
  EXPECT_NEAR(parameters.effective_shear_modulus, 1.1820331e10, 1e3);
  // β = ln 0.5 / sqrt(ln² 0.5 + π²) = −0.693147 / sqrt(0.480453 + 9.869604)
  //   = −0.693147 / 3.217151 = −0.215454 (EDEM guide; Tsuji et al. 1992).
  EXPECT_NEAR(parameters.damping_ratio_beta, -0.215454, 1e-6);
  EXPECT_EQ(parameters.static_friction, 0.4);
  EXPECT_EQ(parameters.rolling_friction, 0.01);
  EXPECT_EQ(parameters.rolling_model, RollingModel::constant_torque);
  // Order-independent pair.
  const InteractionParameters swapped = make_interaction(glass, steel, spec);
  EXPECT_DOUBLE_EQ(swapped.effective_youngs_modulus, parameters.effective_youngs_modulus);
  EXPECT_DOUBLE_EQ(swapped.effective_shear_modulus, parameters.effective_shear_modulus);
}

// A rigid material (materials[].rigid) adds no compliance: against it E* = E/(1 − ν²) and
// G* = E/(2 (2 − ν)(1 + ν)) of the other material (Johnson 1985 eq. 4.22 with E → ∞).
TEST(MakeInteraction, RigidMaterialAddsNoCompliance) {
  MaterialProperties anvil;
  anvil.density = 7800.0;
  anvil.rigid = true;  // no Young's modulus or Poisson ratio: they are not read
  const InteractionParameters parameters = make_interaction(glass, anvil, InteractionSpec{});
  EXPECT_EQ(parameters.effective_youngs_modulus, 1.0 / ((1.0 - 0.25 * 0.25) / 7.0e10));
  EXPECT_EQ(parameters.effective_shear_modulus, 1.0 / (2.0 * (2.0 - 0.25) * (1.0 + 0.25) / 7.0e10));
  // 7e10 / 0.9375 = 7.4666667e10 Pa: above the glass–glass E* = 3.7333333e10 Pa, twice it.
  EXPECT_NEAR(parameters.effective_youngs_modulus, 7.4666667e10, 1e3);
}

// Two fixed particles (1/m = 0 on both sides) that overlap: m* would be 1/0; the law takes
// m* = 0 (neither can move, there is nothing to damp) and gives the elastic Hertz force alone,
// F = 4/3 E* √R* δ^{3/2} (Johnson 1985 eq. 4.23), finite whatever the velocities.
TEST(EvaluateContact, TwoFixedParticlesFeelTheElasticForceOnly) {
  InteractionSpec spec;
  spec.restitution = 0.3;
  const InteractionParameters parameters = make_interaction(glass, glass, spec);
  ContactKinematics k;
  k.normal = Vec3{0.0, 0.0, 1.0};
  k.overlap = 1e-6;                    // m
  k.radius_i = k.radius_j = 2e-3;      // m
  k.inv_mass_i = k.inv_mass_j = 0.0;   // both fixed
  k.velocity_i = Vec3{0.0, 0.0, -0.5};  // m/s (a fixed particle has none; the law must not care)
  ContactHistory history;
  const ContactResult result = evaluate_contact(parameters, k, history, 1e-6);
  const double elastic = 4.0 / 3.0 * parameters.effective_youngs_modulus * std::sqrt(1e-3) * std::pow(1e-6, 1.5);  // N
  EXPECT_NEAR(result.normal_force, elastic, 1e-12 * elastic);
  EXPECT_TRUE(std::isfinite(result.force_i.x) && std::isfinite(result.force_i.y) && std::isfinite(result.force_i.z));
}

TEST(MakeInteraction, ElasticRestitutionGivesZeroDamping) {
  InteractionSpec spec;
  spec.restitution = 1.0;
  EXPECT_EQ(make_interaction(steel, glass, spec).damping_ratio_beta, 0.0);
}

TEST(MakeInteraction, ReportsEveryBadValueAtItsSourceLocation) {
  InteractionSpec spec;
  spec.material_a = Located<std::string>("rubber", SourceLocation{"deck.yaml", 3, 5});
  spec.material_b = Located<std::string>("glass", SourceLocation{"deck.yaml", 4, 5});
  spec.restitution = Located<double>(1.2, SourceLocation{"deck.yaml", 7, 18});
  spec.static_friction = Located<double>(-0.1, SourceLocation{"deck.yaml", 8, 22});
  spec.normal_model = NormalModel::linear;  // without a stiffness
  const MaterialProperties no_stiffness{1000.0, 0.0, 0.3};
  try {
    make_interaction(no_stiffness, glass, spec);
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    const auto& all = error.diagnostics().all();
    ASSERT_EQ(all.size(), 4u);
    EXPECT_EQ(all[0].where.line, 3);  // Young's modulus of "rubber"
    EXPECT_NE(all[0].message.find("rubber"), std::string::npos);
    EXPECT_EQ(all[1].where.line, 7);  // restitution
    EXPECT_EQ(all[1].where.column, 18);
    EXPECT_EQ(all[2].where.line, 8);  // friction
    EXPECT_NE(all[3].message.find("linear"), std::string::npos);
  }
}

ContactKinematics oblique_pair() {
  ContactKinematics kinematics;
  kinematics.normal = normalized(Vec3{1.0, 2.0, -0.5});
  kinematics.overlap = 3.0e-5;  // m
  kinematics.radius_i = 0.01;   // m
  kinematics.radius_j = 0.015;  // m
  kinematics.inv_mass_i = 1.0 / 0.01;     // 1/kg
  kinematics.inv_mass_j = 1.0 / 0.034;    // 1/kg
  kinematics.velocity_i = Vec3{-0.3, 0.2, 0.1};
  kinematics.velocity_j = Vec3{0.1, -0.1, 0.4};
  kinematics.angular_velocity_i = Vec3{5.0, -3.0, 2.0};
  kinematics.angular_velocity_j = Vec3{-1.0, 4.0, 7.0};
  return kinematics;
}

// Both bodies feel ±F at the same contact point and the rolling couple is ±Mr, so the total
// angular momentum rate about any origin vanishes: xi × F + τi + xj × (−F) + τj = 0.
// Holds for no rolling resistance and for EPSD (the constant torque acts on each body alone).
TEST(EvaluateContact, ConservesAngularMomentumAboutAnyPoint) {
  for (RollingModel model : {RollingModel::none, RollingModel::epsd}) {
    InteractionSpec spec;
    spec.restitution = 0.6;
    spec.static_friction = 0.3;
    spec.rolling_friction = 0.2;
    spec.rolling_model = model;
    const InteractionParameters parameters = make_interaction(steel, glass, spec);
    const ContactKinematics kinematics = oblique_pair();
    ContactHistory history{Vec3{1e-5, -2e-5, 0.0}, Vec3{1e-4, 0.0, 2e-4}};
    const ContactResult result = evaluate_contact(parameters, kinematics, history, 1.0e-6);
    const Vec3 centre_i{0.2, -0.1, 0.3};  // m, arbitrary placement consistent with the normal
    const Vec3 centre_j = centre_i - (0.01 + 0.015 - 3.0e-5) * kinematics.normal;  // m
    const Vec3 total = cross(centre_i, result.force_i) + result.torque_i +
                       cross(centre_j, -result.force_i) + result.torque_j;    // N·m
    const double scale = norm(result.force_i) * 0.3 + norm(result.torque_i);  // N·m
    EXPECT_LT(norm(total), 1e-13 * scale);
    // The tangential part is really there (a Coulomb-capped force at this sliding speed).
    const Vec3 tangential = result.force_i - result.normal_force * kinematics.normal;
    EXPECT_NEAR(norm(tangential), 0.3 * std::fabs(result.normal_force),
                1e-12 * std::fabs(result.normal_force));
  }
}

TEST(EvaluateContact, TangentialForceOpposesSlipOfTheContactPointIncludingSpin) {
  // A sphere spinning in place on a wall: the contact point moves at −(R − δ) ω × n, and the
  // friction pushes the other way; the wall receives no torque.
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.5;
  spec.rolling_model = RollingModel::none;
  const InteractionParameters parameters = make_interaction(steel, glass, spec);
  ContactKinematics kinematics;
  kinematics.normal = Vec3{0.0, 0.0, 1.0};
  kinematics.overlap = 1.0e-6;                           // m
  kinematics.radius_i = 0.01;                            // m
  kinematics.inv_mass_i = 1.0 / 0.01;                              // 1/kg
  kinematics.angular_velocity_i = Vec3{0.0, 10.0, 0.0};  // contact point moves along −x
  ContactHistory history;
  const ContactResult result = evaluate_contact(parameters, kinematics, history, 1.0e-6);
  EXPECT_GT(result.force_i.x, 0.0);
  EXPECT_EQ(result.torque_j, Vec3{});
  // Lever R − δ for a wall: τi = (−(R − δ) n) × Ft.
  EXPECT_NEAR(result.torque_i.y, -(0.01 - 1.0e-6) * result.force_i.x, 1e-18);
  EXPECT_LT(result.torque_i.y, 0.0);  // the spin is braked
}

TEST(EvaluateContact, SeparatedPairGivesNoForceAndReleasesTheSprings) {
  InteractionSpec spec;
  spec.cohesion_energy_density = 1.0e5;  // J/m³: no reach beyond touching (SJKR)
  spec.rolling_model = RollingModel::epsd;
  spec.rolling_friction = 0.1;
  const InteractionParameters parameters = make_interaction(steel, glass, spec);
  ContactKinematics kinematics = oblique_pair();
  kinematics.overlap = -1.0e-6;  // m, a gap
  ContactHistory history{Vec3{1e-7, 0.0, 0.0}, Vec3{0.0, 1e-4, 0.0}};
  const ContactResult result = evaluate_contact(parameters, kinematics, history, 1.0e-6);
  EXPECT_EQ(result.force_i, Vec3{});
  EXPECT_EQ(result.torque_i, Vec3{});
  EXPECT_EQ(result.normal_force, 0.0);
  EXPECT_EQ(history.tangential_displacement, Vec3{});
  EXPECT_EQ(history.rolling_torque, Vec3{});
}

// The force loop's batch kernel must be the same law as evaluate_contact (contact_law.h):
// random touching pairs, sticking and sliding, fresh and carried history, a batch size that is
// not a whole number of vectors. Agreement to round-off (the two forms may fuse multiply-adds
// differently, and the batch multiplies by 1/kt where the law divides). Every law the kernel
// takes (batch_handles): plain Hertz–Mindlin, with SJKR cohesion (k = 3e5 J/m³: about a tenth
// of the elastic force at these overlaps), with the constant directional rolling torque, both.
void expect_batch_kernel_is_the_law(const InteractionParameters& parameters);

TEST(EvaluateContact, HertzMindlinBatchKernelIsTheSameLaw) {
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.5;
  struct Law {
    const char* name;
    double cohesion;  // J/m³
    RollingModel rolling;
  };
  for (const Law law : {Law{"plain", 0.0, RollingModel::none}, Law{"SJKR", 3.0e5, RollingModel::none},
                        Law{"SJKR and rolling", 3.0e5, RollingModel::constant_torque},
                        Law{"rolling", 0.0, RollingModel::constant_torque}}) {
    SCOPED_TRACE(law.name);
    spec.cohesion_energy_density = law.cohesion;
    spec.rolling_model = law.rolling;
    spec.rolling_friction = law.rolling == RollingModel::none ? 0.0 : 0.1;
    const InteractionParameters parameters = make_interaction(steel, glass, spec);
    // The case exercises the law it names, and the batch takes it.
    ASSERT_EQ(parameters.normal_model, NormalModel::hertz_mindlin);
    ASSERT_EQ(parameters.cohesion_energy_density, law.cohesion);
    ASSERT_EQ(parameters.rolling_model, law.rolling);
    ASSERT_FALSE(parameters.surface_energy > 0.0 || parameters.clip_attraction);
    ASSERT_TRUE(batch_handles(parameters));
    expect_batch_kernel_is_the_law(parameters);
  }
  // Laws the kernel leaves to the scalar path.
  spec.rolling_model = RollingModel::epsd;
  EXPECT_FALSE(batch_handles(make_interaction(steel, glass, spec)));
  spec.rolling_model = RollingModel::none;
  spec.cohesion_model = CohesionModel::jkr;
  spec.surface_energy = 0.05;
  EXPECT_FALSE(batch_handles(make_interaction(steel, glass, spec)));
}

void expect_batch_kernel_is_the_law(const InteractionParameters& parameters) {
  std::mt19937_64 random(2026);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_vec = [&](double scale) { return Vec3{unit(random), unit(random), unit(random)} * scale; };
  auto batch = std::make_unique<HertzMindlinBatch>();
  std::vector<ContactKinematics> cases;
  std::vector<Vec3> starts;
  std::vector<double> previous_forces;
  int sliding = 0, touching = 0, vector_lanes = 0, scalar_lanes = 0;
  for (int round = 0; round < 10; ++round) {
    batch->count = 0;
    cases.clear();
    starts.clear();
    previous_forces.clear();
    for (int m = 0; m < 203; ++m) {
      ContactKinematics k;
      k.normal = normalized(random_vec(1.0));
      k.radius_i = 1e-3 * (1.5 + unit(random));  // m
      k.radius_j = 1e-3 * (1.5 + unit(random));
      // m; every 11th short of contact, where only a dashpot window can act.
      k.overlap = m % 11 == 0 ? -0.3e-6 * (1.01 + unit(random)) : 1e-6 * (1.01 + unit(random));
      k.inv_mass_i = 1.0 / (1e-5 * (1.5 + unit(random)));  // 1/kg
      k.inv_mass_j = 1.0 / (1e-5 * (1.5 + unit(random)));
      // Fixed particles (particle_types[].fixed: 1/m = 0) on one side or, m = 0 mod 35, both.
      if (m % 5 == 0) k.inv_mass_i = 0.0;
      if (m % 7 == 0) k.inv_mass_j = 0.0;
      // Slow pairs take the kernel's vector path; fast ones (a half path s = |u| dt/2 above a
      // tenth of δ: impacts) and those short of contact its scalar finish.
      const double speed = m % 4 == 0 ? 1e-3 : 0.1;  // m/s
      k.velocity_i = random_vec(speed);
      k.velocity_j = random_vec(speed);
      k.lead_time = 0.5e-5;  // s, dt/2
      k.angular_velocity_i = random_vec(50.0);
      k.angular_velocity_j = random_vec(50.0);
      k.velocity_lead_i = random_vec(0.01);
      k.velocity_lead_j = random_vec(0.01);
      k.angular_velocity_lead_i = random_vec(5.0);
      k.angular_velocity_lead_j = random_vec(5.0);
      const Vec3 start = m % 3 == 0 ? Vec3{} : random_vec(m % 2 ? 1e-7 : 1e-9);  // m
      const Vec3 d = k.normal * ((k.radius_i + k.radius_j) - k.overlap);  // x_i − x_j
      batch->dx[m] = d.x, batch->dy[m] = d.y, batch->dz[m] = d.z, batch->distance2[m] = norm2(d);
      batch->radius_i[m] = k.radius_i, batch->radius_j[m] = k.radius_j;
      batch->inv_mass_i[m] = k.inv_mass_i, batch->inv_mass_j[m] = k.inv_mass_j;
      const Vec3 v = k.velocity_i - k.velocity_j;
      batch->vx[m] = v.x, batch->vy[m] = v.y, batch->vz[m] = v.z;
      batch->wix[m] = k.angular_velocity_i.x, batch->wiy[m] = k.angular_velocity_i.y, batch->wiz[m] = k.angular_velocity_i.z;
      batch->wjx[m] = k.angular_velocity_j.x, batch->wjy[m] = k.angular_velocity_j.y, batch->wjz[m] = k.angular_velocity_j.z;
      const Vec3 lead = k.velocity_lead_i - k.velocity_lead_j;
      batch->lvx[m] = lead.x, batch->lvy[m] = lead.y, batch->lvz[m] = lead.z;
      const Vec3 li = k.angular_velocity_lead_i, lj = k.angular_velocity_lead_j;
      batch->lwix[m] = li.x, batch->lwiy[m] = li.y, batch->lwiz[m] = li.z;
      batch->lwjx[m] = lj.x, batch->lwjy[m] = lj.y, batch->lwjz[m] = lj.z;
      batch->hx[m] = start.x, batch->hy[m] = start.y, batch->hz[m] = start.z;
      const double previous = 1e-3 * unit(random);  // N, the contact's last normal force
      batch->fn[m] = previous;
      previous_forces.push_back(previous);
      ++batch->count;
      // The kernel derives n and δ from x_i − x_j: give the law the same (rounded) values.
      const double distance = std::sqrt(norm2(d));
      k.normal = d * (1.0 / distance);
      k.overlap = (k.radius_i + k.radius_j) - distance;
      cases.push_back(k);
      starts.push_back(start);
    }
    // The overlap guard: these overlaps (at most 2.01e-6 m on radii of at least 0.5e-3 m) stay
    // below 0.41 % of the smaller radius.
    EXPECT_FALSE(evaluate_hertz_mindlin_batch(parameters, *batch, 1e-5, 0.5e-5, 0.005));
    for (int m = 0; m < batch->count; ++m) {
      ContactHistory history{starts[m], Vec3{}, false, previous_forces[m]};
      (batch->scalar_lane[m] != 0.0 ? scalar_lanes : vector_lanes) += 1;
      const ContactResult expected = evaluate_contact(parameters, cases[m], history, 1e-5);
      const auto close = [](const Vec3& a, const Vec3& b, double scale) { return norm(a - b) <= 1e-12 * scale; };
      const double force_scale = norm(expected.force_i);  // N
      const double lever = 1e-3;                          // m, torque scale per newton
      EXPECT_TRUE(close({batch->fx[m], batch->fy[m], batch->fz[m]}, expected.force_i, force_scale)) << m;
      EXPECT_TRUE(close({batch->tix[m], batch->tiy[m], batch->tiz[m]}, expected.torque_i, lever * force_scale)) << m;
      EXPECT_TRUE(close({batch->tjx[m], batch->tjy[m], batch->tjz[m]}, expected.torque_j, lever * force_scale)) << m;
      EXPECT_TRUE(close({batch->hx[m], batch->hy[m], batch->hz[m]}, history.tangential_displacement,
                        norm(history.tangential_displacement) + 1e-30)) << m;
      EXPECT_NEAR(batch->fn[m], history.normal_force, 1e-12 * force_scale) << m;
      if (!(cases[m].overlap > 0.0)) continue;  // a dashpot window alone: no tangential force
      ++touching;
      const Vec3 shear = expected.force_i - expected.normal_force * cases[m].normal;
      sliding += norm(shear) >= (1.0 - 1e-9) * 0.5 * std::fabs(expected.normal_force);
    }
  }
  EXPECT_GT(sliding, 100);   // both regimes were exercised
  EXPECT_LT(sliding, touching - 20);
  EXPECT_GT(vector_lanes, 300);  // and both paths of the kernel
  EXPECT_GT(scalar_lanes, 300);
}

// The batched kernel's overlap guard flags δ > limit·min(Ri, Rj) exactly as the run's report
// (sim::check_overlaps) measures it, and never for the padding lanes of a part-filled batch.
TEST(EvaluateContact, BatchKernelOverlapGuardFlagsTheContactPastTheLimitAndNotThePadding) {
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.5;
  const InteractionParameters parameters = make_interaction(steel, glass, spec);
  auto batch = std::make_unique<HertzMindlinBatch>();
  const auto one_contact = [&](double overlap, double ri, double rj) {
    batch->count = 1;
    const double distance = (ri + rj) - overlap;  // m, along x
    batch->dx[0] = distance, batch->dy[0] = batch->dz[0] = 0.0, batch->distance2[0] = distance * distance;
    batch->radius_i[0] = ri, batch->radius_j[0] = rj;
    batch->inv_mass_i[0] = batch->inv_mass_j[0] = 1e5;
    batch->vx[0] = batch->vy[0] = batch->vz[0] = 0.0;
    batch->wix[0] = batch->wiy[0] = batch->wiz[0] = batch->wjx[0] = batch->wjy[0] = batch->wjz[0] = 0.0;
    batch->lvx[0] = batch->lvy[0] = batch->lvz[0] = 0.0;
    batch->lwix[0] = batch->lwiy[0] = batch->lwiz[0] = batch->lwjx[0] = batch->lwjy[0] = batch->lwjz[0] = 0.0;
    batch->hx[0] = batch->hy[0] = batch->hz[0] = 0.0;
  };
  // 1e-6 m on a smaller radius of 1e-3 m: 0.1 %. The padding lanes (δ = 0.5 of R = 0.75)
  // would pass a 10 % limit if they were counted.
  one_contact(1e-6, 1e-3, 2e-3);
  EXPECT_FALSE(evaluate_hertz_mindlin_batch(parameters, *batch, 1e-5, 0.0, 0.1));
  one_contact(1e-6, 1e-3, 2e-3);
  EXPECT_FALSE(evaluate_hertz_mindlin_batch(parameters, *batch, 1e-5, 0.0, 0.0011));
  one_contact(1e-6, 1e-3, 2e-3);
  EXPECT_TRUE(evaluate_hertz_mindlin_batch(parameters, *batch, 1e-5, 0.0, 0.0009));
  one_contact(1e-6, 2e-3, 1e-3);  // the smaller radius is j's
  EXPECT_TRUE(evaluate_hertz_mindlin_batch(parameters, *batch, 1e-5, 0.0, 0.0009));
}

}  // namespace
}  // namespace quarry
