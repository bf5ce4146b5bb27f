// HookStage::alongside (sim/step.cpp): hooks that run while the step's stages run, on a thread of
// their own when the world's team has one to spare (the stages then use the rest), else in turn
// before the end_of_step hooks; the thread is given back before the end_of_step hooks, and an
// error on either side stops the step with that error.
#include <gtest/gtest.h>

#include <thread>

#include "core/diagnostics.h"
#include "test_support.h"

namespace quarry {
namespace {

using testing_support::deck_path;
using testing_support::start_world;

struct Seen {
  std::thread::id alongside_thread;
  double alongside_time = -1.0;  // s, world.time as the alongside hook saw it
  int alongside_team = 0;        // world.alongside_threading.threads
  int stage_team = 0;            // world.threading.threads in a post_force hook
  int end_team = 0;              // … in an end_of_step hook
  bool alongside_before_end = false;
  bool end_ran = false;
};

void add_probes(World& world, Seen& seen) {
  world.hooks.push_back({HookStage::alongside, "probe", [&seen](World& w) {
                           seen.alongside_thread = std::this_thread::get_id();
                           seen.alongside_time = w.time;
                           seen.alongside_team = w.alongside_threading.threads;
                           seen.alongside_before_end = !seen.end_ran;
                         }});
  world.hooks.push_back({HookStage::post_force, "stage team", [&seen](World& w) {
                           seen.stage_team = w.threading.threads;
                         }});
  world.hooks.push_back({HookStage::end_of_step, "end team", [&seen](World& w) {
                           seen.end_team = w.threading.threads;
                           seen.end_ran = true;
                         }});
}

TEST(AlongsideHooks, OnTwoThreadsTheyRunOnTheirOwnAndTheStagesOnTheOther) {
  World world = start_world(parse_deck(deck_path("tests/decks/minimal.yaml")), 2);
  Seen seen;
  add_probes(world, seen);
  const double end = world.time + world.dt;  // the step's end time, as the step computes it
  sim::step(world);
  EXPECT_NE(seen.alongside_thread, std::this_thread::get_id());
  EXPECT_EQ(seen.alongside_time, end);  // started once the clock had advanced
  EXPECT_EQ(seen.alongside_team, 1);
  EXPECT_EQ(seen.stage_team, 1);  // the stages ran on what was left of the team
  EXPECT_EQ(seen.end_team, 2);    // given back before the end_of_step hooks
  EXPECT_TRUE(seen.alongside_before_end);
  EXPECT_EQ(world.threading.threads, 2);
  ASSERT_EQ(world.alongside_timers.names().size(), 1u);
  EXPECT_EQ(world.alongside_timers.names()[0], "hook probe");
}

TEST(AlongsideHooks, OnOneThreadTheyRunInTurnBeforeTheEndOfStepHooks) {
  World world = start_world(parse_deck(deck_path("tests/decks/minimal.yaml")), 1);
  Seen seen;
  add_probes(world, seen);
  const double end = world.time + world.dt;
  sim::step(world);
  EXPECT_EQ(seen.alongside_thread, std::this_thread::get_id());
  EXPECT_EQ(seen.alongside_time, end);
  EXPECT_EQ(seen.alongside_team, 1);
  EXPECT_EQ(seen.stage_team, 1);
  EXPECT_TRUE(seen.alongside_before_end);
  EXPECT_TRUE(world.alongside_timers.names().empty());
}

TEST(AlongsideHooks, AnErrorOnTheirThreadStopsTheStepWithItAndGivesTheThreadBack) {
  World world = start_world(parse_deck(deck_path("tests/decks/minimal.yaml")), 2);
  bool end_ran = false;
  world.hooks.push_back({HookStage::alongside, "diverging", [](World&) {
                           throw PhysicsError("shell solver: the solution diverged");
                         }});
  world.hooks.push_back({HookStage::end_of_step, "end", [&end_ran](World&) { end_ran = true; }});
  EXPECT_THROW(sim::step(world), PhysicsError);
  EXPECT_FALSE(end_ran);
  EXPECT_EQ(world.threading.threads, 2);
  // A failing stage while they run: the step waits for them, gives the thread back, and the
  // stage's error is the one that comes out.
  world.hooks.clear();
  world.hooks.push_back({HookStage::alongside, "slow", [](World&) {
                           std::this_thread::sleep_for(std::chrono::milliseconds(20));
                         }});
  world.hooks.push_back({HookStage::post_force, "failing stage", [](World&) {
                           throw PhysicsError("a stage failed");
                         }});
  try {
    sim::step(world);
    ADD_FAILURE() << "the failing stage did not stop the step";
  } catch (const PhysicsError& e) {
    EXPECT_STREQ(e.what(), "a stage failed");
  }
  EXPECT_EQ(world.threading.threads, 2);
  world.hooks.clear();
  sim::step(world);  // the worker is free again
}

}  // namespace
}  // namespace quarry
