// Micro-benchmarks of the force stage's kernels (time-step stage 3): the Hertz–Mindlin pair law
// in its batched vector form and in its scalar form, and the sphere–mesh contact search. Items
// processed = contacts (pair law) or spheres (surface search), so the rate reads per item.
// Inputs are the settled bed's: 2 mm glass-like spheres, overlaps of about 1 µm (bench/).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "contact/contact_law.h"
#include "contact/hertz_mindlin_batch.h"
#include "geometry/mesh_topology.h"
#include "geometry/primitives.h"
#include "geometry/surface_contact.h"

namespace quarry {
namespace {

constexpr double kDt = 1e-5;  // s, the reference problem's step

// The issue-3 problem's law; with `cohesive` (a benchmark argument of 1) also the flagship's
// SJKR cohesion (30 kJ/m³) and constant rolling torque (μr = 0.1), which the batch takes too.
InteractionParameters bed_interaction(bool cohesive) {
  const MaterialProperties beads{2500.0, 5.0e6, 0.3};  // kg/m³, Pa, –
  InteractionSpec spec;
  spec.restitution = 0.5;
  spec.static_friction = 0.5;
  spec.rolling_model = cohesive ? RollingModel::constant_torque : RollingModel::none;
  spec.rolling_friction = cohesive ? 0.1 : 0.0;
  spec.cohesion_energy_density = cohesive ? 3.0e4 : 0.0;
  return make_interaction(beads, beads, spec);
}

const char* law_label(benchmark::State& state) { return state.range(0) ? "SJKR + rolling" : "plain"; }

// Random touching pairs of 1 mm spheres: overlaps 0–2 µm, velocities up to 0.2 mm/s
// (a settled bed's: its kinetic energy of 2e-13 J per particle is 0.2 mm/s), spins up to
// 5 rad/s, some with tangential history (as the settled bed has). At these speeds the batched
// kernel takes almost every contact in its vector loop; impacts (a step's overlap path above a tenth of
// the overlap, contact/dashpot_window.h) take its scalar finish, priced by scalar_contact_law.
std::vector<ContactKinematics> random_contacts(int count, std::vector<Vec3>& history) {
  std::mt19937_64 random(2026);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_vec = [&](double scale) { return Vec3{unit(random), unit(random), unit(random)} * scale; };
  const double mass = 2500.0 * 4.0 / 3.0 * std::numbers::pi * 1e-9;  // kg, R = 1 mm
  std::vector<ContactKinematics> contacts;
  history.clear();
  for (int m = 0; m < count; ++m) {
    ContactKinematics k;
    k.normal = normalized(random_vec(1.0));
    k.radius_i = k.radius_j = 1e-3;
    k.overlap = 1e-6 * (1.01 + unit(random));
    k.inv_mass_i = k.inv_mass_j = 1.0 / mass;
    k.velocity_i = random_vec(2e-4);
    k.velocity_j = random_vec(2e-4);
    k.angular_velocity_i = random_vec(5.0);
    k.angular_velocity_j = random_vec(5.0);
    contacts.push_back(k);
    history.push_back(m % 3 == 0 ? Vec3{} : random_vec(1e-8));
  }
  return contacts;
}

// The vector kernel on one full batch (256 contacts), as the pair loop calls it.
void hertz_mindlin_batch_kernel(benchmark::State& state) {
  const InteractionParameters parameters = bed_interaction(state.range(0) != 0);
  state.SetLabel(law_label(state));
  std::vector<Vec3> history;
  const std::vector<ContactKinematics> contacts = random_contacts(HertzMindlinBatch::kCapacity, history);
  auto batch = std::make_unique<HertzMindlinBatch>();
  HertzMindlinBatch& b = *batch;
  for (int m = 0; m < HertzMindlinBatch::kCapacity; ++m) {
    const ContactKinematics& k = contacts[m];
    const Vec3 d = k.normal * ((k.radius_i + k.radius_j) - k.overlap);  // x_i − x_j (m)
    b.dx[m] = d.x, b.dy[m] = d.y, b.dz[m] = d.z, b.distance2[m] = norm2(d);
    b.radius_i[m] = k.radius_i, b.radius_j[m] = k.radius_j;
    b.inv_mass_i[m] = k.inv_mass_i, b.inv_mass_j[m] = k.inv_mass_j;
    const Vec3 v = k.velocity_i - k.velocity_j;
    b.vx[m] = v.x, b.vy[m] = v.y, b.vz[m] = v.z;
    b.wix[m] = k.angular_velocity_i.x, b.wiy[m] = k.angular_velocity_i.y, b.wiz[m] = k.angular_velocity_i.z;
    b.wjx[m] = k.angular_velocity_j.x, b.wjy[m] = k.angular_velocity_j.y, b.wjz[m] = k.angular_velocity_j.z;
    const Vec3 lead = k.velocity_lead_i - k.velocity_lead_j;
    b.lvx[m] = lead.x, b.lvy[m] = lead.y, b.lvz[m] = lead.z;
    b.lwix[m] = k.angular_velocity_lead_i.x, b.lwiy[m] = k.angular_velocity_lead_i.y;
    b.lwiz[m] = k.angular_velocity_lead_i.z;
    b.lwjx[m] = k.angular_velocity_lead_j.x, b.lwjy[m] = k.angular_velocity_lead_j.y;
    b.lwjz[m] = k.angular_velocity_lead_j.z;
  }
  b.count = HertzMindlinBatch::kCapacity;
  for (auto _ : state) {
    state.PauseTiming();  // the same history every pass, as a step would see it
    for (int m = 0; m < b.count; ++m) {
      b.hx[m] = history[m].x, b.hy[m] = history[m].y, b.hz[m] = history[m].z;
      b.fn[m] = 0.0;
    }
    state.ResumeTiming();
    benchmark::DoNotOptimize(evaluate_hertz_mindlin_batch(parameters, b, kDt, 0.5 * kDt, 0.05));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * b.count);
}
BENCHMARK(hertz_mindlin_batch_kernel)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The scalar law, one contact at a time (the path of mixed materials and other models).
void scalar_contact_law(benchmark::State& state) {
  const InteractionParameters parameters = bed_interaction(state.range(0) != 0);
  state.SetLabel(law_label(state));
  std::vector<Vec3> history;
  const std::vector<ContactKinematics> contacts = random_contacts(1024, history);
  for (auto _ : state) {
    for (std::size_t m = 0; m < contacts.size(); ++m) {
      ContactHistory h{history[m], Vec3{}};
      benchmark::DoNotOptimize(evaluate_contact(parameters, contacts[m], h, kDt));
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(contacts.size()));
}
BENCHMARK(scalar_contact_law)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// Spheres of 1 mm radius touching the inside of a drum of 0.1 m radius meshed with
// state.range(0) segments (0.5 µm overlap with a random facet, at a random point of it), each
// tested against the triangles whose bounding box comes within its radius (the candidates the
// neighbour stage hands the force stage).
void surface_contacts_in_drum(benchmark::State& state) {
  const int segments = static_cast<int>(state.range(0));
  const Surface drum = make_cylinder({0, 0, 0}, {0, 0, 1}, 0.1, 0.2, segments, false);
  const MeshTopology topology = build_topology(drum);
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::uint32_t> triangle_of(0, static_cast<std::uint32_t>(drum.triangles.size() - 1));
  std::uniform_real_distribution<double> weight(0.1, 1.0);
  const double radius = 1e-3;  // m
  struct Probe {
    Vec3 centre;
    std::vector<std::uint32_t> candidates;
  };
  std::vector<Probe> probes(1000);
  for (Probe& p : probes) {
    const std::uint32_t f = triangle_of(random);
    const auto& tri = drum.triangles[f];
    double w[3] = {weight(random), weight(random), weight(random)};
    const double sum = w[0] + w[1] + w[2];
    const Vec3 point = (drum.vertices[tri[0]] * w[0] + drum.vertices[tri[1]] * w[1] + drum.vertices[tri[2]] * w[2]) / sum;
    p.centre = point + drum.triangle_normals[f] * (radius - 0.5e-6);  // normals point inwards
    for (std::uint32_t t = 0; t < drum.triangles.size(); ++t) {
      Aabb box;  // the triangle's, widened by the radius: near if it holds the centre
      for (int k = 0; k < 3; ++k) box.expand(drum.vertices[drum.triangles[t][k]]);
      box.lo = box.lo - Vec3{radius, radius, radius};
      box.hi = box.hi + Vec3{radius, radius, radius};
      if (box.contains(p.centre)) p.candidates.push_back(t);
    }
  }
  std::vector<SurfaceContact> contacts;
  std::size_t found = 0;
  for (auto _ : state) {
    found = 0;
    for (const Probe& p : probes) {
      find_surface_contacts(drum, topology, p.centre, radius, p.candidates, contacts);
      found += contacts.size();
    }
    benchmark::DoNotOptimize(found);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(probes.size()));
  state.counters["contacts_per_sphere"] = static_cast<double>(found) / static_cast<double>(probes.size());
}
BENCHMARK(surface_contacts_in_drum)->Arg(64)->Arg(512)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace quarry
