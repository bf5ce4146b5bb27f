// ThreadGovernor on synthetic step times: it keeps the faster team, follows a change of the
// machine's load, and probes a steady choice ever less often.
#include "sim/thread_governor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace quarry::sim {
namespace {

// Feeds `steps` steps whose wall time depends on the team the governor picks.
template <class Cost>
void feed(ThreadGovernor& governor, int steps, Cost cost) {
  for (int n = 0; n < steps; ++n) governor.step_took(cost(governor.threads()));
}

TEST(ThreadGovernor, OneRequestedThreadNeverChanges) {
  ThreadGovernor governor(1);
  feed(governor, 10000, [](int) { return 1e-3; });
  EXPECT_EQ(governor.threads(), 1);
  EXPECT_EQ(governor.switches(), 0);
}

// A busy machine: two threads take twice as long per step as one (measured on the hopper with
// one busy process beside it). The governor ends on one thread and spends few steps on two.
TEST(ThreadGovernor, TakesOneThreadWhenItIsFaster) {
  ThreadGovernor governor(2);
  feed(governor, 100000, [](int team) { return team == 1 ? 1e-3 : 2e-3; });  // 100 s
  EXPECT_EQ(governor.threads(), 1);
  EXPECT_EQ(governor.switches(), 1);
  // The probes of two threads: windows of 0.1 s after 2, 4, … 60 s periods.
  EXPECT_LT(static_cast<double>(governor.steps_with_all()) / 100000.0, 0.05);
}

// The other process ends: two threads become faster again and the governor returns to them.
TEST(ThreadGovernor, ReturnsToAllThreadsWhenTheMachineIsQuietAgain) {
  ThreadGovernor governor(2);
  feed(governor, 20000, [](int team) { return team == 1 ? 1e-3 : 2e-3; });
  ASSERT_EQ(governor.threads(), 1);
  feed(governor, 200000, [](int team) { return team == 1 ? 1e-3 : 0.55e-3; });
  EXPECT_EQ(governor.threads(), 2);
  EXPECT_EQ(governor.switches(), 2);
}

// A quiet machine where two threads are 1.8x faster: the choice stays, and the probes of one
// thread (0.1 s windows, then periods of 2, 4, 8, … up to 60 s) cost a small share of the run.
TEST(ThreadGovernor, ProbesASteadyChoiceLessAndLessOften) {
  ThreadGovernor governor(2);
  const double slow = 1e-3, fast = slow / 1.8;
  double wall = 0.0;
  for (int n = 0; n < 1000000; ++n) {
    const double t = governor.threads() == 1 ? slow : fast;
    wall += t;
    governor.step_took(t);
  }
  EXPECT_EQ(governor.threads(), 2);
  EXPECT_EQ(governor.switches(), 0);
  EXPECT_LT(wall / (1000000 * fast), 1.01);  // under 1 % lost to probing over ~9 min
}

// The work per step grows (a pour filling up beside a structure that was most of each step):
// one thread was faster, two become faster. The chosen team's time per step moving by more than
// `drift` starts a probe at once, instead of after the period a steady choice had reached.
TEST(ThreadGovernor, ProbesAgainWhenTheStepsCostDrifts) {
  ThreadGovernor governor(2);
  feed(governor, 60000, [](int team) { return team == 1 ? 1.0e-3 : 1.1e-3; });  // 60 s: period 32 s
  ASSERT_EQ(governor.threads(), 1);
  const std::uint64_t before = governor.steps_with_one();
  feed(governor, 20000, [](int team) { return team == 1 ? 2.0e-3 : 1.3e-3; });
  EXPECT_EQ(governor.threads(), 2);
  // One window of 0.1 s to see the drift, a baseline and a probe window: a few hundred steps,
  // not the rest of a 32 s period (~16,000 steps).
  EXPECT_LT(governor.steps_with_one() - before, 400u);
}

// The work per step growing steadily (a pour filling up): each window's steps cost 20 % more
// than the last one's whatever the team, two threads 1.15x faster than one at any moment. The
// probe of two threads comes after the baseline of one, so against that baseline alone two
// threads looked slower (1.2 / 1.15 = 1.04); against the mean of the windows before and after
// the probe (1.2) they are found faster.
TEST(ThreadGovernor, ComparesTheTeamsAcrossASteadyGrowthOfTheWork) {
  ThreadGovernor governor(2);
  feed(governor, 20000, [](int team) { return team == 1 ? 1e-3 : 2e-3; });  // a busy machine
  ASSERT_EQ(governor.threads(), 1);
  const double growth = std::log(1.2) / 0.1;  // 1/s: +20 % per 0.1 s of wall time
  double wall = 0.0;                          // s since the machine became quiet
  std::uint64_t with_all = 0, steps = 0;
  while (wall < 1.5) {
    const int team = governor.threads();
    const double t = 1e-4 * std::exp(growth * wall) / (team == 1 ? 1.0 : 1.15);
    wall += t;
    with_all += team == 2;
    ++steps;
    governor.step_took(t);
  }
  EXPECT_EQ(governor.threads(), 2);
  EXPECT_GT(static_cast<double>(with_all) / static_cast<double>(steps), 0.5);
}

// Differences within the margin do not make it switch back and forth.
TEST(ThreadGovernor, KeepsItsChoiceWhenTheTeamsAreAlike) {
  ThreadGovernor governor(2);
  feed(governor, 100000, [](int team) { return team == 1 ? 1.01e-3 : 1e-3; });
  EXPECT_EQ(governor.threads(), 2);
  EXPECT_EQ(governor.switches(), 0);
}

}  // namespace
}  // namespace quarry::sim
