// The batch kernels (shell_element_batch.h: four and eight lanes, each where the processor has
// it) against the scalar kernel, bit for bit: on random distorted, warped, rotated quads with
// random velocities and histories, elastic and yielding (lanes of one batch yield at some points
// and not at others), Lobatto and Gauss rules of 2 to 7 points; and the solver with and without
// batches (quads of two sections interleaved, triangles, a quad count that leaves a remainder per
// section) on 1 and 2 threads.
#include "fem/shell_element_batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "fem/shell_element.h"
#include "fem/shell_solver.h"
#include "fem/shell_test_meshes.h"
#include "fem/through_thickness.h"

namespace quarry::fem {
namespace {

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

using testing::History;
using testing::rotate;

// The kernels this processor runs (eight lanes need AVX-512; the test says when it is skipped).
std::vector<QuadKernel> available_kernels() {
  std::vector<QuadKernel> kernels;
  for (const QuadKernel k : {QuadKernel::four_lanes, QuadKernel::eight_lanes})
    if (quad_kernel_available(k)) kernels.push_back(k);
  if (kernels.size() == 1) std::printf("[ skipped  ] eight lanes: this processor has no AVX-512\n");
  return kernels;
}

// A batch's histories interleaved as the solver keeps them (QuadBatchState), from and back to
// element order.
struct InterleavedHistories {
  std::vector<double> stress, plastic, shear, hourglass;
  explicit InterleavedHistories(int points)
      : stress(3 * kQuadLanes * points),
        plastic(kQuadLanes * points),
        shear(3 * kQuadLanes),
        hourglass(5 * kQuadLanes) {}
  QuadBatchState state() { return {stress.data(), plastic.data(), shear.data(), hourglass.data()}; }
  // copy(element-order value, its interleaved copy) for every value of every lane.
  template <class Copy>
  void each_value(std::array<History, kQuadLanes>& histories, Copy copy) {
    for (int l = 0; l < kQuadLanes; ++l) {
      History& h = histories[l];
      for (std::size_t k = 0; k < h.stress.size(); ++k)
        copy(h.stress[k], stress[kQuadLanes * k + l]);
      for (std::size_t k = 0; k < h.plastic.size(); ++k)
        copy(h.plastic[k], plastic[kQuadLanes * k + l]);
      for (std::size_t k = 0; k < 3; ++k) copy(h.shear[k], shear[kQuadLanes * k + l]);
      for (std::size_t k = 0; k < 5; ++k) copy(h.hourglass[k], hourglass[kQuadLanes * k + l]);
    }
  }
};

TEST(ShellElementBatch, EveryKernelEqualsTheScalarKernelBitForBit) {
  for (const QuadKernel kernel : available_kernels()) {
    SCOPED_TRACE(quad_kernel_name(kernel));
    std::mt19937_64 random(20261203);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const PlaneStressMaterial materials[] = {{210e9, 0.3, 0.0, 0.0},     // elastic
                                             {210e9, 0.3, 250e6, 0.0},   // perfectly plastic
                                             {70e9, 0.33, 150e6, 2e9}};  // hardening
    int yielded = 0, elastic_points = 0;
    for (const PlaneStressMaterial& material : materials) {
      for (const ThicknessRule rule : {ThicknessRule::lobatto, ThicknessRule::gauss}) {
        for (const int points : {2, 3, 5, 7}) {
          const ThicknessPoints rule_points = thickness_points(rule, points);
          SectionProperties section;
          section.thickness = 0.002 + 0.004 * (0.5 + 0.5 * unit(random));
          section.points = points;
          section.coordinate = rule_points.coordinate.data();
          section.weight = rule_points.weight.data();
          section.material = material;
          section.shear_modulus = material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio));
          ASSERT_TRUE(batchable(section));
          for (int trial = 0; trial < 20; ++trial) {
            // kQuadLanes quads, nodes 4l..4l+3: a distorted, warped square of side ~L, rotated and
            // moved.
            std::vector<Vec3> x(4 * kQuadLanes), v(4 * kQuadLanes), omega(4 * kQuadLanes);
            std::array<std::array<std::int32_t, 4>, kQuadLanes> nodes;
            std::array<History, kQuadLanes> scalar_history, batch_history, initial;
            const double dt = 1e-7 * (1.0 + 9.0 * (0.5 + 0.5 * unit(random)));
            for (int l = 0; l < kQuadLanes; ++l) {
              const double side = 0.01 + 0.09 * (0.5 + 0.5 * unit(random));
              const Vec3 corners[4] = {{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}};
              Vec3 axis{unit(random), unit(random), unit(random)};
              axis = normalized(axis);
              const double angle = 3.14159 * unit(random);
              const Vec3 shift{unit(random), unit(random), unit(random)};
              for (int i = 0; i < 4; ++i) {
                const Vec3 local =
                    corners[i] + Vec3{0.2 * side * unit(random), 0.2 * side * unit(random),
                                      0.05 * side * unit(random)};
                x[4 * l + i] = rotate(local, axis, angle) + shift;
                v[4 * l + i] = {unit(random), unit(random), unit(random)};
                omega[4 * l + i] = Vec3{unit(random), unit(random), unit(random)} * 30.0;
                nodes[l][i] = 4 * l + i;
              }
              // Histories: stresses up to ~1.6 × the yield stress, so some points yield.
              History h;
              const double scale = 400e6 * (0.5 + 0.5 * unit(random));
              for (int p = 0; p < points; ++p) {
                for (int k = 0; k < 3; ++k)
                  h.stress.push_back(scale * unit(random) * (k == 2 ? 0.5 : 1.0));
                h.plastic.push_back(material.yield_stress > 0.0 ? 0.01 * (0.5 + 0.5 * unit(random))
                                                                : 0.0);
              }
              for (int k = 0; k < 3; ++k) h.shear.push_back(1e4 * unit(random));
              for (int k = 0; k < 5; ++k) h.hourglass.push_back(10.0 * unit(random));
              scalar_history[l] = h;
              batch_history[l] = h;
              initial[l] = h;
            }
            InterleavedHistories interleaved(points);
            interleaved.each_value(batch_history,
                                   [](double& lane, double& packed) { packed = lane; });
            std::array<ElementForces, kQuadLanes> batch;
            QuadBatchOutput out;
            for (int l = 0; l < kQuadLanes; ++l) {
              out.nodal[l] = &batch[l].nodal;
              out.internal_energy_increment[l] = &batch[l].internal_energy_increment;
              out.hourglass_energy_increment[l] = &batch[l].hourglass_energy_increment;
            }
            shell_internal_forces_quads(x.data(), v.data(), omega.data(), nodes, dt, section,
                                        interleaved.state(), out, kernel);
            interleaved.each_value(batch_history,
                                   [](double& lane, double& packed) { lane = packed; });
            for (int l = 0; l < kQuadLanes; ++l) {
              std::array<Vec3, 4> xl, vl, wl;
              for (int i = 0; i < 4; ++i) {
                xl[i] = x[4 * l + i];
                vl[i] = v[4 * l + i];
                wl[i] = omega[4 * l + i];
              }
              const ElementForces scalar =
                  shell_internal_forces(xl, vl, wl, 4, dt, section, scalar_history[l].state());
              SCOPED_TRACE(::testing::Message()
                           << "material " << material.yield_stress << ", " << points
                           << " points, trial " << trial << ", lane " << l);
              EXPECT_TRUE(same_bits(scalar.nodal, batch[l].nodal));
              EXPECT_TRUE(
                  same_bits(scalar.internal_energy_increment, batch[l].internal_energy_increment));
              EXPECT_TRUE(same_bits(scalar.hourglass_energy_increment,
                                    batch[l].hourglass_energy_increment));
              EXPECT_TRUE(same_bits(scalar_history[l].stress, batch_history[l].stress));
              EXPECT_TRUE(same_bits(scalar_history[l].plastic, batch_history[l].plastic));
              EXPECT_TRUE(same_bits(scalar_history[l].shear, batch_history[l].shear));
              EXPECT_TRUE(same_bits(scalar_history[l].hourglass, batch_history[l].hourglass));
            }
            // Points that went through the return map (their ε̄_p grew) and points that did not.
            if (material.yield_stress > 0.0) {
              for (int l = 0; l < kQuadLanes; ++l) {
                for (int p = 0; p < points; ++p) {
                  if (batch_history[l].plastic[p] > initial[l].plastic[p])
                    ++yielded;
                  else
                    ++elastic_points;
                }
              }
            }
          }
        }
      }
    }
    // Both branches of the yield test were taken, within batches.
    EXPECT_GT(yielded, 100);
    EXPECT_GT(elastic_points, 100);
  }
}

// Two sections (thickness, points, rule, material) interleaved, triangles among the quads and a
// quad count per section that is not a multiple of eight: the solver with batches takes the same
// steps, to the bit, as the solver without, on 1 and 2 threads.
TEST(ShellElementBatch, SolverWithBatchesTakesTheScalarSteps) {
  ShellModel model = testing::rectangle(9, 7, 0.27, 0.21, 0.003, testing::MeshKind::quads, 5,
                                        ThicknessRule::lobatto, testing::steel(250e6, 1e9));
  model.sections.push_back({0.004, 4, ThicknessRule::gauss, 1});
  model.materials.push_back({70e9, 0.33, 2700.0, 120e6, 0.0});
  std::vector<ShellElement> elements;
  int index = 0;
  for (const ShellElement& e : model.elements) {
    const int section = index % 3 == 1 ? 1 : 0;
    if (index % 7 == 3) {
      elements.push_back({{e.nodes[0], e.nodes[1], e.nodes[2], 0}, 3, section});
      elements.push_back({{e.nodes[0], e.nodes[2], e.nodes[3], 0}, 3, section});
    } else {
      elements.push_back({e.nodes, 4, section});
    }
    ++index;
  }
  model.elements = elements;
  model.boundary_conditions.push_back(
      {testing::nodes_where(model, [](const Vec3& p) { return testing::near(p.x, 0.0); }),
       dof::all,
       {}});
  auto run = [&model](bool batched, int threads, QuadKernel kernel = QuadKernel::four_lanes) {
    ShellSolverOptions options;
    options.damping = 20.0;
    options.batched_quads = batched;
    options.quad_kernel = kernel;
    options.threading.threads = threads;
    options.threading.threshold = 0;
    ShellSolver solver(model, options);
    std::vector<NodalLoad> loads(model.nodes.size());
    for (std::size_t n = 0; n < loads.size(); ++n) {
      loads[n].force = {30.0 * std::cos(static_cast<double>(n)), 0.0,
                        -400.0 - 200.0 * std::sin(static_cast<double>(n))};
      loads[n].moment = {0.0, 0.5 * std::sin(3.0 * static_cast<double>(n)), 0.0};
    }
    solver.set_loads(loads);
    const double dt = 0.8 * solver.stable_time_step().time_step;
    for (int s = 0; s < 300; ++s) solver.step(dt);
    return solver.state();
  };
  const ShellSolverState reference = run(false, 1);
  double plastic = 0.0;
  for (const double p : reference.plastic) plastic = std::max(plastic, p);
  EXPECT_GT(plastic, 0.0);  // the run reached the return map
  for (const QuadKernel kernel : available_kernels())
    for (const int threads : {1, 2}) {
      const ShellSolverState batched = run(true, threads, kernel);
      SCOPED_TRACE(::testing::Message() << threads << " threads, " << quad_kernel_name(kernel));
      EXPECT_EQ(0, std::memcmp(reference.positions.data(), batched.positions.data(),
                               reference.positions.size() * sizeof(Vec3)));
      EXPECT_EQ(0, std::memcmp(reference.velocities.data(), batched.velocities.data(),
                               reference.velocities.size() * sizeof(Vec3)));
      EXPECT_EQ(0,
                std::memcmp(reference.angular_velocities.data(), batched.angular_velocities.data(),
                            reference.angular_velocities.size() * sizeof(Vec3)));
      EXPECT_TRUE(same_bits(reference.stress, batched.stress));
      EXPECT_TRUE(same_bits(reference.plastic, batched.plastic));
      EXPECT_TRUE(same_bits(reference.shear, batched.shear));
      EXPECT_TRUE(same_bits(reference.hourglass, batched.hourglass));
      EXPECT_TRUE(same_bits(reference.energies.internal, batched.energies.internal));
      EXPECT_TRUE(same_bits(reference.energies.hourglass, batched.energies.hourglass));
      EXPECT_TRUE(same_bits(reference.energies.kinetic, batched.energies.kinetic));
    }
}

}  // namespace
}  // namespace quarry::fem
