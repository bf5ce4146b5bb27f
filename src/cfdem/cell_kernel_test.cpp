// The coupling kernel: partition of unity, continuity, the void fraction's integral and
// Newton's third law of the deposited drag, each to round-off; the same with blocked cells, and
// the nearest fluid cell of each blocked one.
#include "cfdem/cell_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace quarry::cfdem {
namespace {

cfd::FluidGrid test_grid() {
  cfd::FluidGrid grid;
  grid.origin = {-0.01, 0.02, 0.0};
  grid.cell_size = {0.002, 0.0025, 0.003};
  grid.cells = {5, 4, 6};
  return grid;
}

// Particles anywhere in the grid, many in the border half-cells where weights fold or wrap.
std::vector<Vec3> random_positions(const cfd::FluidGrid& grid, int count, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> positions;
  for (int n = 0; n < count; ++n) {
    Vec3 x;
    for (int a = 0; a < 3; ++a)
      x[a] = grid.origin[a] + unit(random) * grid.cells[static_cast<std::size_t>(a)] * grid.cell_size[a];
    positions.push_back(x);
  }
  return positions;
}

TEST(CellKernel, WeightsArePositiveAndSumToOne) {
  const cfd::FluidGrid grid = test_grid();
  for (const PeriodicAxes periodic : {PeriodicAxes{false, false, false}, PeriodicAxes{true, false, true}}) {
    for (const Vec3& x : random_positions(grid, 500, 7)) {
      const CellWeights w = cell_weights(grid, periodic, x);
      double sum = 0.0;
      for (std::size_t c = 0; c < 8; ++c) {
        EXPECT_GE(w.weight[c], 0.0);
        EXPECT_LT(w.cell[c], grid.cell_count());
        sum += w.weight[c];
      }
      EXPECT_NEAR(sum, 1.0, 4e-16);
    }
  }
}

// Along a periodic axis the weights repeat with the period, wherever the position lies: the
// cells and weights at x + m L (m = −3 … 4) are those of the textbook wrap, fmod(s, n) + n
// when negative and (i mod n + n) mod n, to the bit (cell_weights skips the division where
// s is within (−n, 2n); s = position in cell-centre units).
TEST(CellKernel, PeriodicWeightsRepeatWithThePeriodAsTheTextbookWrap) {
  const cfd::FluidGrid grid = test_grid();
  const PeriodicAxes periodic{true, true, true};
  const auto reference = [&](const Vec3& x) {
    std::array<std::array<int, 2>, 3> cell{};
    std::array<double, 3> upper{};
    for (int a = 0; a < 3; ++a) {
      const int n = grid.cells[static_cast<std::size_t>(a)];
      double t = std::fmod((x[a] - grid.origin[a]) / grid.cell_size[a] - 0.5, static_cast<double>(n));
      if (t < 0.0) t += n;
      const double floor_t = std::floor(t);
      const int low = static_cast<int>(floor_t);
      cell[static_cast<std::size_t>(a)] = {((low % n) + n) % n, ((low + 1) % n + n) % n};
      upper[static_cast<std::size_t>(a)] = t - floor_t;
    }
    CellWeights w;
    int corner = 0;
    for (int c = 0; c < 2; ++c)
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a, ++corner) {
          w.cell[static_cast<std::size_t>(corner)] = static_cast<std::uint32_t>(grid.cell_index(cell[0][a], cell[1][b], cell[2][c]));
          w.weight[static_cast<std::size_t>(corner)] = (a ? upper[0] : 1.0 - upper[0]) * (b ? upper[1] : 1.0 - upper[1]) *
                                                       (c ? upper[2] : 1.0 - upper[2]);
        }
    return w;
  };
  const Vec3 period{grid.cells[0] * grid.cell_size.x, grid.cells[1] * grid.cell_size.y, grid.cells[2] * grid.cell_size.z};
  for (const Vec3& inside : random_positions(grid, 300, 11)) {
    for (int m = -3; m <= 4; ++m) {
      const Vec3 x = inside + Vec3{period.x * m, period.y * (m % 3), period.z * -m};
      const CellWeights w = cell_weights(grid, periodic, x), expected = reference(x);
      for (std::size_t c = 0; c < 8; ++c) {
        ASSERT_EQ(w.cell[c], expected.cell[c]) << m;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(w.weight[c]), std::bit_cast<std::uint64_t>(expected.weight[c])) << m;
      }
    }
  }
}

// A particle crossing a cell centre and a cell face: each cell's weight changes by O(step),
// with no jump (the ∂ε/∂t of the fluid stays finite).
TEST(CellKernel, WeightsAreContinuousInPosition) {
  const cfd::FluidGrid grid = test_grid();
  const PeriodicAxes periodic{false, true, false};
  const double step = 1e-7;  // m
  const Vec3 start{-0.0095, 0.0201, 0.0001};  // from the low corner's border half-cell
  std::vector<double> previous;
  for (int n = 0; n <= 40000; ++n) {
    const Vec3 x = start + Vec3{1.0, 0.7, 0.9} * (n * step);
    const CellWeights w = cell_weights(grid, periodic, x);
    std::vector<double> field(grid.cell_count(), 0.0);
    for (std::size_t c = 0; c < 8; ++c) field[w.cell[c]] += w.weight[c];
    if (!previous.empty()) {
      for (std::size_t c = 0; c < field.size(); ++c)
        ASSERT_LT(std::abs(field[c] - previous[c]), 3.0 * step / 0.002) << "cell " << c << " at step " << n;
    }
    previous = field;
  }
}

TEST(CellKernel, VoidFractionIntegratesToParticleVolume) {
  const cfd::FluidGrid grid = test_grid();
  for (const PeriodicAxes periodic : {PeriodicAxes{false, false, false}, PeriodicAxes{true, true, false}}) {
    const std::vector<Vec3> positions = random_positions(grid, 300, 11);
    std::vector<CellWeights> weights;
    std::vector<double> radius;
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> size(1e-4, 4e-4);
    double particle_volume = 0.0;  // m³
    for (const Vec3& x : positions) {
      weights.push_back(cell_weights(grid, periodic, x));
      radius.push_back(size(random));
      particle_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radius.back(), 3);
    }
    std::vector<double> epsilon;
    const double smallest = void_fraction(grid, weights, radius, epsilon);
    ASSERT_EQ(epsilon.size(), grid.cell_count());
    double solid = 0.0;  // m³
    double least = 1.0;
    for (double e : epsilon) solid += (1.0 - e) * grid.cell_volume(), least = std::min(least, e);
    EXPECT_EQ(smallest, least);
    EXPECT_LT(smallest, 1.0);
    // Round-off: 120 cells of |1 − ε| ≤ 1 summed, each to an ulp of 1, times the cell volume.
    EXPECT_NEAR(solid, particle_volume, 1e-13 * grid.cell_volume() * grid.cell_count());
    EXPECT_NEAR(solid / particle_volume, 1.0, 1e-12);
  }
}

// The fluid gets −β_p (u_p − v_p) through β (implicit, times its cell velocity) and β_p v_p
// (explicit), each spread by the weights; with u_p interpolated by the same weights, the sum
// over cells is minus the sum of the particles' drag, whatever the velocity field.
TEST(CellKernel, DepositedDragIsMinusTheParticlesDrag) {
  const cfd::FluidGrid grid = test_grid();
  const PeriodicAxes periodic{true, false, false};
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Vec3> cell_velocity(grid.cell_count());
  for (Vec3& u : cell_velocity) u = {value(random), value(random), value(random)};
  const std::vector<Vec3> positions = random_positions(grid, 200, 13);
  std::vector<CellWeights> weights;
  std::vector<double> coefficient;
  std::vector<Vec3> momentum;
  Vec3 particle_drag;  // N, Σ_p β_p (u_p − v_p)
  for (const Vec3& x : positions) {
    weights.push_back(cell_weights(grid, periodic, x));
    coefficient.push_back(1e-5 * (1.5 + value(random)));  // kg/s
    const Vec3 v{value(random), value(random), value(random)};
    momentum.push_back(v * coefficient.back());
    particle_drag += (interpolate(weights.back(), cell_velocity) - v) * coefficient.back();
  }
  std::vector<double> beta(grid.cell_count(), 0.0);
  std::vector<Vec3> force(grid.cell_count());
  deposit(grid, weights, coefficient, beta);
  deposit(grid, weights, momentum, force);
  Vec3 fluid_drag;  // N, Σ_c V (f_c − β_c u_c)
  for (std::size_t c = 0; c < grid.cell_count(); ++c)
    fluid_drag += (force[c] - cell_velocity[c] * beta[c]) * grid.cell_volume();
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(fluid_drag[a], -particle_drag[a], 1e-14 * 200 * 2.5e-5);
  EXPECT_GT(std::abs(particle_drag.x) + std::abs(particle_drag.y) + std::abs(particle_drag.z), 1e-5);
}

// ---- blocked cells ----

// A random quarter of the cells blocked, plus a solid slab at j = 0 (the particles near it have
// most of their weight there) and a solid block of 3 x 2 x 3 (particles inside it fall back).
std::vector<std::uint8_t> test_mask(const cfd::FluidGrid& grid) {
  std::mt19937_64 random(17);
  std::bernoulli_distribution quarter(0.25);
  std::vector<std::uint8_t> mask(grid.cell_count(), 0);
  for (int k = 0; k < grid.cells[2]; ++k)
    for (int j = 0; j < grid.cells[1]; ++j)
      for (int i = 0; i < grid.cells[0]; ++i)
        mask[grid.cell_index(i, j, k)] = (j == 0 || (i < 3 && j >= 2 && k >= 3) || quarter(random)) ? 1 : 0;
  return mask;
}

TEST(CellKernel, BlockedWeightsStayOnFluidCellsAndSumToOne) {
  const cfd::FluidGrid grid = test_grid();
  const BlockedCells blocked = make_blocked_cells(grid, test_mask(grid));
  ASSERT_GT(blocked.count, grid.cell_count() / 3);
  int untouched = 0, renormalised = 0, moved = 0;
  for (const PeriodicAxes periodic : {PeriodicAxes{false, false, false}, PeriodicAxes{true, false, true}}) {
    for (const Vec3& x : random_positions(grid, 2000, 19)) {
      const CellWeights plain = cell_weights(grid, periodic, x);
      bool to_nearest = false;
      const CellWeights w = cell_weights(grid, periodic, blocked, x, &to_nearest);
      double sum = 0.0;
      bool touches_blocked = false;
      for (std::size_t c = 0; c < 8; ++c) {
        EXPECT_FALSE(blocked.blocked(w.cell[c])) << "an entry on a blocked cell";
        EXPECT_GE(w.weight[c], 0.0);
        sum += w.weight[c];
        touches_blocked |= blocked.blocked(plain.cell[c]);
      }
      EXPECT_NEAR(sum, 1.0, 8e-16);
      if (!touches_blocked) {  // far from blocked cells: the plain weights, bit for bit
        ++untouched;
        for (std::size_t c = 0; c < 8; ++c) {
          EXPECT_EQ(w.weight[c], plain.weight[c]);
          EXPECT_EQ(w.cell[c], plain.cell[c]);
        }
      } else if (to_nearest) {
        ++moved;
        EXPECT_EQ(w.weight[0], 1.0);
      } else {
        ++renormalised;
        // The fluid entries keep their proportions.
        double fluid = 0.0;
        for (std::size_t c = 0; c < 8; ++c) fluid += blocked.blocked(plain.cell[c]) ? 0.0 : plain.weight[c];
        for (std::size_t c = 0; c < 8; ++c) {
          if (!blocked.blocked(plain.cell[c])) {
            EXPECT_NEAR(w.weight[c], plain.weight[c] / fluid, 1e-15);
          }
        }
      }
    }
  }
  std::printf("[ measured ] 4000 particles: %d away from blocked cells, %d renormalised, %d moved whole to the "
              "nearest fluid cell\n",
              untouched, renormalised, moved);
  EXPECT_GT(untouched, 10);
  EXPECT_GT(renormalised, 1000);
  EXPECT_GT(moved, 10);
}

// The nearest fluid cell of every blocked cell, against a search over all fluid cells.
TEST(CellKernel, NearestFluidCellIsTheNearestByCentreDistance) {
  const cfd::FluidGrid grid = test_grid();
  const BlockedCells blocked = make_blocked_cells(grid, test_mask(grid));
  const auto centre = [&](std::size_t c) {
    const auto nx = static_cast<std::size_t>(grid.cells[0]), ny = static_cast<std::size_t>(grid.cells[1]);
    return grid.cell_centre(static_cast<int>(c % nx), static_cast<int>((c / nx) % ny), static_cast<int>(c / (nx * ny)));
  };
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    const std::uint32_t found = blocked.nearest_fluid[c];
    ASSERT_FALSE(blocked.blocked(found));
    if (!blocked.blocked(c)) {
      EXPECT_EQ(found, c);
      continue;
    }
    double best = 1e300;
    for (std::size_t f = 0; f < grid.cell_count(); ++f)
      if (!blocked.blocked(f)) best = std::min(best, norm2(centre(f) - centre(c)));
    EXPECT_NEAR(norm2(centre(found) - centre(c)), best, 1e-12 * best) << "cell " << c;
  }
  EXPECT_THROW(make_blocked_cells(grid, std::vector<std::uint8_t>(grid.cell_count(), 1)), std::invalid_argument);
  EXPECT_THROW(make_blocked_cells(grid, std::vector<std::uint8_t>(3, 0)), std::invalid_argument);
  EXPECT_EQ(make_blocked_cells(grid, std::vector<std::uint8_t>(grid.cell_count(), 0)).count, 0u);
}

// Particles next to blocked cells (and some inside them): Σ_c (1 − ε_c) V_cell is still Σ_p V_p,
// all of it on fluid cells.
TEST(CellKernel, VoidFractionWithBlockedCellsIntegratesToParticleVolume) {
  const cfd::FluidGrid grid = test_grid();
  const BlockedCells blocked = make_blocked_cells(grid, test_mask(grid));
  const std::vector<Vec3> positions = random_positions(grid, 300, 23);
  std::vector<CellWeights> weights;
  std::vector<double> radius;
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> size(1e-4, 4e-4);
  double particle_volume = 0.0;  // m³
  for (const Vec3& x : positions) {
    weights.push_back(cell_weights(grid, PeriodicAxes{false, false, false}, blocked, x));
    radius.push_back(size(random));
    particle_volume += 4.0 / 3.0 * std::numbers::pi * std::pow(radius.back(), 3);
  }
  std::vector<double> epsilon;
  void_fraction(grid, weights, radius, epsilon);
  double solid = 0.0;  // m³
  for (std::size_t c = 0; c < epsilon.size(); ++c) {
    solid += (1.0 - epsilon[c]) * grid.cell_volume();
    if (blocked.blocked(c)) {
      EXPECT_EQ(epsilon[c], 1.0) << "cell " << c;
    }
  }
  EXPECT_NEAR(solid / particle_volume, 1.0, 1e-12);
}

// Newton's third law with blocked cells: the field is NaN in every blocked cell, so a weight
// that read one would poison the particle's drag; the deposits there stay exactly 0.
TEST(CellKernel, DepositedDragWithBlockedCellsIsMinusTheParticlesDrag) {
  const cfd::FluidGrid grid = test_grid();
  const BlockedCells blocked = make_blocked_cells(grid, test_mask(grid));
  const PeriodicAxes periodic{true, false, false};
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Vec3> cell_velocity(grid.cell_count());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t c = 0; c < grid.cell_count(); ++c)
    cell_velocity[c] = blocked.blocked(c) ? Vec3{nan, nan, nan} : Vec3{value(random), value(random), value(random)};
  std::vector<CellWeights> weights;
  std::vector<double> coefficient;
  std::vector<Vec3> momentum;
  Vec3 particle_drag;  // N
  for (const Vec3& x : random_positions(grid, 200, 13)) {
    weights.push_back(cell_weights(grid, periodic, blocked, x));
    coefficient.push_back(1e-5 * (1.5 + value(random)));  // kg/s
    const Vec3 v{value(random), value(random), value(random)};
    momentum.push_back(v * coefficient.back());
    particle_drag += (interpolate(weights.back(), cell_velocity) - v) * coefficient.back();
  }
  ASSERT_TRUE(std::isfinite(particle_drag.x) && std::isfinite(particle_drag.y) && std::isfinite(particle_drag.z));
  std::vector<double> beta(grid.cell_count(), 0.0);
  std::vector<Vec3> force(grid.cell_count());
  deposit(grid, weights, coefficient, beta);
  deposit(grid, weights, momentum, force);
  Vec3 fluid_drag;  // N
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    if (blocked.blocked(c)) {
      EXPECT_EQ(beta[c], 0.0);
      EXPECT_EQ(force[c], Vec3{});
      continue;
    }
    fluid_drag += (force[c] - cell_velocity[c] * beta[c]) * grid.cell_volume();
  }
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(fluid_drag[a], -particle_drag[a], 1e-14 * 200 * 2.5e-5);
}

// Deposits on several threads (order_deposits: the cells cut into ranges, one thread each) give
// the bits of one, for any number of threads, and deposit_drag those of its two deposits: with folded, wrapped (every axis periodic, so some
// particles span the whole flat index) and blocked cells, half the particles crowded into two
// layers of cells so that the cuts are uneven, and more threads than rows of cells.
TEST(CellKernel, DepositsOnThreadsHaveTheBitsOfOneThread) {
  const cfd::FluidGrid grid = test_grid();
  for (const bool with_blocked : {false, true}) {
    const BlockedCells blocked =
        with_blocked ? make_blocked_cells(grid, test_mask(grid)) : BlockedCells{};
    std::vector<Vec3> positions = random_positions(grid, 400, 29);
    for (std::size_t n = 0; n < positions.size(); n += 2) positions[n].z = grid.origin.z + 2.0 * grid.cell_size.z;
    std::vector<CellWeights> weights;
    std::vector<double> radius, coefficient;
    std::vector<Vec3> velocity, momentum;
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (const Vec3& x : positions) {
      weights.push_back(cell_weights(grid, PeriodicAxes{true, true, true}, blocked, x));
      radius.push_back(2e-4 * (1.5 + value(random)));
      coefficient.push_back(1e-5 * (1.5 + value(random)));
      velocity.push_back(Vec3{value(random), value(random), value(random)});
      momentum.push_back(velocity.back() * coefficient.back());
    }
    // Every value as bits, one thread (no order) or `threads` with an order.
    const auto deposits = [&](const DepositOrder* order) {
      std::vector<double> epsilon, beta(grid.cell_count(), 0.0);
      std::vector<Vec3> force(grid.cell_count());
      std::vector<double> fused_beta(grid.cell_count(), 0.0);
      std::vector<Vec3> fused_force(grid.cell_count());
      void_fraction(grid, weights, radius, epsilon, order);
      deposit(grid, weights, coefficient, beta, order);
      deposit(grid, weights, momentum, force, order);
      deposit_drag(grid, weights, coefficient, velocity, fused_beta, fused_force, order);
      std::vector<std::uint64_t> bits;
      for (std::size_t c = 0; c < grid.cell_count(); ++c) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(fused_beta[c]), std::bit_cast<std::uint64_t>(beta[c]));
        for (int a = 0; a < 3; ++a)
          EXPECT_EQ(std::bit_cast<std::uint64_t>(fused_force[c][a]), std::bit_cast<std::uint64_t>(force[c][a]));
        for (const double v : {epsilon[c], beta[c], force[c].x, force[c].y, force[c].z})
          bits.push_back(std::bit_cast<std::uint64_t>(v));
      }
      return bits;
    };
    const std::vector<std::uint64_t> one = deposits(nullptr);
    for (const int threads : {1, 2, 3, 5, 8, 30}) {
      DepositOrder order;
      order_deposits(grid, weights, threads, order);
      ASSERT_EQ(order.particles.size(), static_cast<std::size_t>(threads));
      for (const std::vector<std::uint32_t>& list : order.particles)
        EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
      EXPECT_TRUE(deposits(&order) == one) << threads << " threads, blocked cells " << with_blocked;
    }
  }
}

// Along a blocked slab (j = 0) the share moved off it is the same at every x: the weights stay
// continuous as the particle crosses cell centres and faces beside it.
TEST(CellKernel, BlockedWeightsAreContinuousAlongABlockedWall) {
  const cfd::FluidGrid grid = test_grid();
  std::vector<std::uint8_t> mask(grid.cell_count(), 0);
  for (int k = 0; k < grid.cells[2]; ++k)
    for (int i = 0; i < grid.cells[0]; ++i) mask[grid.cell_index(i, 0, k)] = 1;
  const BlockedCells blocked = make_blocked_cells(grid, mask);
  const double step = 1e-7;                   // m
  const Vec3 start{-0.0095, 0.0231, 0.0001};  // y inside cell row 1, below its centre
  std::vector<double> previous;
  for (int n = 0; n <= 20000; ++n) {
    const Vec3 x = start + Vec3{1.0, 0.0, 0.6} * (n * step);
    const CellWeights w = cell_weights(grid, PeriodicAxes{false, false, false}, blocked, x);
    std::vector<double> field(grid.cell_count(), 0.0);
    for (std::size_t c = 0; c < 8; ++c) field[w.cell[c]] += w.weight[c];
    if (!previous.empty()) {
      for (std::size_t c = 0; c < field.size(); ++c)
        ASSERT_LT(std::abs(field[c] - previous[c]), 3.0 * step / 0.002) << "cell " << c << " at step " << n;
    }
    previous = field;
  }
}

}  // namespace
}  // namespace quarry::cfdem
