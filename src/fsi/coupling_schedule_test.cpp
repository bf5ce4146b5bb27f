// The EDEM card's schedule (seed 000): defaults, sync times as each solver's first step at or
// after the requested point, the one-time reset at cycle 2; and the FILTER window's mean.
#include "fsi/coupling_schedule.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "fsi/force_filter.h"

namespace quarry::fsi {
namespace {

TEST(CouplingSchedule, SeedDefaultsAndChecks) {
  const ScheduleSettings defaults = resolve_schedule(std::nullopt, std::nullopt, 2.0);
  EXPECT_DOUBLE_EQ(defaults.period, 0.02);  // TTERM / 100
  EXPECT_DOUBLE_EQ(defaults.filter, 0.02);  // = PERIOD
  const ScheduleSettings seed = resolve_schedule(0.1, 0.15, 2.0);  // the seed's example line
  EXPECT_DOUBLE_EQ(seed.period, 0.1);
  EXPECT_DOUBLE_EQ(seed.filter, 0.15);
  EXPECT_THROW(resolve_schedule(0.1, 0.1, 2.0), std::invalid_argument);   // FILTER > PERIOD
  EXPECT_THROW(resolve_schedule(0.1, 0.05, 2.0), std::invalid_argument);
  EXPECT_THROW(resolve_schedule(2.0, std::nullopt, 2.0), std::invalid_argument);  // < TTERM
  EXPECT_THROW(resolve_schedule(-1.0, std::nullopt, 2.0), std::invalid_argument);
}

// Runs both solvers' clocks (time summed step by step, as the solvers do) through `syncs`
// synchronisations; returns each solver's step count at each sync.
struct SyncSteps {
  std::vector<std::int64_t> structure, dem;
  std::vector<std::string> lines;
};
SyncSteps run_clocks(CouplingSchedule& schedule, double dt_structure, double dt_dem, int syncs) {
  SyncSteps out;
  double t_structure = 0.0, t_dem = 0.0;  // s
  std::int64_t n_structure = 0, n_dem = 0;
  for (int k = 0; k < syncs; ++k) {
    do {
      if (auto line = schedule.before_structure_cycle(n_structure + 1, dt_structure, dt_dem))
        out.lines.push_back(*line);
      t_structure += dt_structure;
      ++n_structure;
    } while (!schedule.reached(t_structure, dt_structure));
    do {
      t_dem += dt_dem;
      ++n_dem;
    } while (!schedule.reached(t_dem, dt_dem));
    out.structure.push_back(n_structure);
    out.dem.push_back(n_dem);
    schedule.synchronised();
  }
  return out;
}

// PERIOD 10 µs, structure step 1.1 µs, DEM step 3 µs: the k-th request is at 10k µs and each
// solver syncs at its first step at or after it, step ceil(10k / dt) — counted here in integers
// (tenths of µs) so that the expectation owes nothing to floating point.
TEST(CouplingSchedule, EachSolverSyncsAtItsFirstStepAtOrAfterTheRequest) {
  CouplingSchedule schedule({10e-6, 10e-6});
  const SyncSteps steps = run_clocks(schedule, 1.1e-6, 3e-6, 6);
  for (int k = 1; k <= 6; ++k) {
    const std::int64_t request = 100 * k;  // 0.1 µs
    EXPECT_EQ(steps.structure[static_cast<std::size_t>(k - 1)], (request + 10) / 11) << "sync " << k;
    EXPECT_EQ(steps.dem[static_cast<std::size_t>(k - 1)], (request + 29) / 30) << "sync " << k;
  }
  // Requests at exact multiples of the DEM step (30 µs = 10 steps, 60 µs = 20) sync there, not
  // one step later, although the summed clock may fall short by round-off.
  EXPECT_EQ(steps.dem[2], 10);
  EXPECT_EQ(steps.dem[5], 20);
  EXPECT_TRUE(steps.lines.empty());  // 10 µs ≥ 2 × both steps: no reset
}

// PERIOD 1 µs below both steps (1.1 µs, 3 µs): the first sync comes at each solver's first step
// (request 1 µs); at the structure's cycle 2, DT_user = max(1, 2.2, 6) = 6 µs and the next
// requests are 1 + 6 = 7 µs, 13 µs, … (structure steps 7 and 12, DEM steps 3 and 5).
TEST(CouplingSchedule, PeriodResetOnceAtCycleTwo) {
  CouplingSchedule schedule({1e-6, 1e-6});
  const SyncSteps steps = run_clocks(schedule, 1.1e-6, 3e-6, 3);
  EXPECT_EQ(steps.structure, (std::vector<std::int64_t>{1, 7, 12}));
  EXPECT_EQ(steps.dem, (std::vector<std::int64_t>{1, 3, 5}));
  EXPECT_DOUBLE_EQ(schedule.period(), 6e-6);
  EXPECT_DOUBLE_EQ(schedule.filter(), 6e-6);
  ASSERT_EQ(steps.lines.size(), 1u);
  EXPECT_NE(steps.lines[0].find("reset at cycle 2 to 6e-06 s"), std::string::npos) << steps.lines[0];
  // Once per run: a later cycle 2 call changes nothing.
  EXPECT_FALSE(schedule.before_structure_cycle(2, 1e-3, 1e-3));
  EXPECT_DOUBLE_EQ(schedule.period(), 6e-6);
}

// A PERIOD between one and two steps: cycle 2 comes before the first sync, so the first request
// itself moves from 4 µs to 0 + max(4, 2.2, 6) = 6 µs (DEM step 2, structure step 6).
TEST(CouplingSchedule, ResetBeforeTheFirstSyncMovesTheFirstRequest) {
  CouplingSchedule schedule({4e-6, 4e-6});
  const SyncSteps steps = run_clocks(schedule, 1.1e-6, 3e-6, 2);
  EXPECT_EQ(steps.structure, (std::vector<std::int64_t>{6, 11}));
  EXPECT_EQ(steps.dem, (std::vector<std::int64_t>{2, 4}));
  EXPECT_EQ(steps.lines.size(), 1u);
}

TEST(CouplingSchedule, StepsToSync) {
  CouplingSchedule schedule({10e-6, 10e-6});
  EXPECT_EQ(schedule.steps_to_sync(0.0, 1.1e-6), 10);  // 11 µs ≥ 10 µs
  EXPECT_EQ(schedule.steps_to_sync(0.0, 2.5e-6), 4);   // exactly 10 µs
  EXPECT_EQ(schedule.steps_to_sync(12e-6, 1e-6), 1);   // request passed: the next step
}

// FILTER: impulses 1 and 3 N·s over 1 s periods. Window 2 s: (1 + 3) / 2; window 1.5 s: the
// newest whole and half the older, (3 + 0.5) / 1.5; window = period: the last period alone.
TEST(ForceFilter, MeanOverTheWindow) {
  std::vector<Vec3> force;
  ForceFilter filter(2.0);
  filter.mean(force);
  EXPECT_TRUE(force.empty());
  filter.add({Vec3{1, 0, 0}}, 1.0);
  filter.mean(force);
  EXPECT_DOUBLE_EQ(force[0].x, 1.0);  // less time than the window: the mean so far
  filter.add({Vec3{3, 0, 0}}, 1.0);
  filter.mean(force);
  EXPECT_DOUBLE_EQ(force[0].x, 2.0);
  filter.set_window(1.5);
  filter.mean(force);
  EXPECT_DOUBLE_EQ(force[0].x, 3.5 / 1.5);
  filter.set_window(1.0);
  filter.add({Vec3{0, 5, 0}}, 1.0);
  filter.mean(force);
  EXPECT_DOUBLE_EQ(force[0].y, 5.0);
  EXPECT_DOUBLE_EQ(force[0].x, 0.0);
}

}  // namespace
}  // namespace quarry::fsi
