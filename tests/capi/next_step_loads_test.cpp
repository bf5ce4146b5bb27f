// The writable view of the next step's external loads (quarry_view_next_step_loads, ABI 1.2):
// what a partner writes there in place must act exactly as the same loads copied in with
// quarry_set_external_loads(replace, next step) — the same bits after a step, since both keep the
// loads apart from the stored forces and both half kicks (velocity Verlet, Swope et al. 1982)
// add the same values to the same forces — and everything that reads forces between steps
// (copies, views, saved states) must see them, without changing the step: the force and load
// summed before the kick (F + L, once, in double) are the same bits as summed inside it.
// Through quarry.h and libquarry.so only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "capi/abi_test_support.h"

namespace {

using quarry_test::error_of;

constexpr int kParticles = 8;

// Eight 1 mm grains in a 2 × 2 × 2 cluster, 1.98 mm apart (each presses on its neighbours, so
// contact forces are in every step), resting on nothing: they fall, spread and spin.
quarry_sim cluster() {
  quarry_sim sim = quarry_test::started_simulation(1e-3);
  double positions[3 * kParticles];
  for (int k = 0; k < kParticles; ++k) {
    positions[3 * k] = 1.98e-3 * (k & 1) + 1e-7 * k;
    positions[3 * k + 1] = 1.98e-3 * ((k >> 1) & 1);
    positions[3 * k + 2] = 1.98e-3 * ((k >> 2) & 1);
  }
  quarry_test::add_particles(sim, positions, kParticles);
  return sim;
}

struct State {
  std::vector<double> position, velocity, spin, force, torque;
  explicit State(std::uint64_t n = kParticles)
      : position(3 * n), velocity(3 * n), spin(3 * n), force(3 * n), torque(3 * n) {}
};

State state_of(quarry_sim sim) {
  State s;
  quarry_particle_data d{};
  d.struct_size = sizeof d;
  d.capacity = kParticles;
  d.position = s.position.data();
  d.velocity = s.velocity.data();
  d.angular_velocity = s.spin.data();
  d.force = s.force.data();
  d.torque = s.torque.data();
  EXPECT_EQ(quarry_get_particles(sim, &d), QUARRY_OK) << error_of(sim);
  return s;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Two states the same to the bit, field by field.
void expect_same_bits(const State& a, const State& b) {
  EXPECT_TRUE(same_bits(a.position, b.position));
  EXPECT_TRUE(same_bits(a.velocity, b.velocity));
  EXPECT_TRUE(same_bits(a.spin, b.spin));
  EXPECT_TRUE(same_bits(a.force, b.force));
  EXPECT_TRUE(same_bits(a.torque, b.torque));
}

// The loads a partner would compute from the state: a linear drag on velocity and spin (N, N·m)
// plus a constant push along x, so that every component is non-zero.
void loads_of(const State& s, std::vector<double>& force, std::vector<double>& torque) {
  force.resize(3 * kParticles), torque.resize(3 * kParticles);
  for (int k = 0; k < 3 * kParticles; ++k) {
    force[k] = -2e-4 * s.velocity[k] + (k % 3 == 0 ? 3e-5 : 0.0);
    torque[k] = -1e-10 * s.spin[k] + 1e-11;
  }
}

// The loads written through the views (one particle type: engine order is type order).
void write_through_views(quarry_sim sim, const std::vector<double>& force, const std::vector<double>& torque) {
  for (const auto& [field, values] : {std::pair{QUARRY_FIELD_FORCE, &force}, std::pair{QUARRY_FIELD_TORQUE, &torque}}) {
    quarry_view view{};
    ASSERT_EQ(quarry_view_next_step_loads(sim, field, &view), QUARRY_OK) << error_of(sim);
    ASSERT_EQ(view.writable, 1u);
    ASSERT_EQ(view.count, static_cast<std::uint64_t>(kParticles));
    ASSERT_EQ(view.dtype, static_cast<std::uint32_t>(QUARRY_DTYPE_FLOAT64));
    ASSERT_EQ(view.components, 3u);
    for (int k = 0; k < kParticles; ++k) {
      auto* at = reinterpret_cast<double*>(static_cast<char*>(view.data) + k * view.stride);
      for (int c = 0; c < 3; ++c) at[c] = (*values)[3 * k + c];
    }
  }
}

TEST(NextStepLoads, WrittenInPlaceTheyActAsCopiedOnesBitForBit) {
  quarry_sim copied = cluster(), written = cluster();
  std::vector<double> force, torque;
  for (int step = 0; step < 300; ++step) {
    const State a = state_of(copied), b = state_of(written);
    ASSERT_TRUE(same_bits(a.velocity, b.velocity) && same_bits(a.spin, b.spin)) << "step " << step;
    loads_of(a, force, torque);
    ASSERT_EQ(quarry_set_external_loads(copied, force.data(), torque.data(), kParticles, QUARRY_LOAD_REPLACE,
                                        QUARRY_HOLD_NEXT_STEP),
              QUARRY_OK)
        << error_of(copied);
    write_through_views(written, force, torque);
    if (step % 50 == 0) {
      // The particles' force shows them from the next call that reads it, as the copies' does.
      const State a_loaded = state_of(copied), b_loaded = state_of(written);
      ASSERT_TRUE(same_bits(a_loaded.force, b_loaded.force) && same_bits(a_loaded.torque, b_loaded.torque))
          << "step " << step;
      ASSERT_FALSE(same_bits(a.force, a_loaded.force)) << "the loads did not reach the forces";
    }
    ASSERT_EQ(quarry_step(copied, 1), QUARRY_OK) << error_of(copied);
    ASSERT_EQ(quarry_step(written, 1), QUARRY_OK) << error_of(written);
  }
  expect_same_bits(state_of(copied), state_of(written));
  // After a step the next step's loads are zeros again.
  quarry_view view{};
  ASSERT_EQ(quarry_view_next_step_loads(written, QUARRY_FIELD_FORCE, &view), QUARRY_OK);
  for (int k = 0; k < 3 * kParticles; ++k) EXPECT_EQ(static_cast<const double*>(view.data)[k], 0.0);
  quarry_close(copied);
  quarry_close(written);
}

// Reading the forces between the loads and the step puts the loads into the stored forces (so
// that they show); the step that follows is the same to the bit as one where nothing looked.
TEST(NextStepLoads, ReadingTheForcesBeforeTheStepChangesNothing) {
  quarry_sim looked = cluster(), unread = cluster();
  std::vector<double> force, torque;
  for (int step = 0; step < 300; ++step) {
    const State before = state_of(unread);  // no loads set yet: nothing to put in the forces
    loads_of(before, force, torque);
    write_through_views(looked, force, torque);
    write_through_views(unread, force, torque);
    const State shown = state_of(looked);  // forces and torques with the loads in them
    if (step % 50 == 0) {
      ASSERT_FALSE(same_bits(before.force, shown.force)) << "the loads are not in the forces read";
    }
    ASSERT_EQ(quarry_step(looked, 1), QUARRY_OK) << error_of(looked);
    ASSERT_EQ(quarry_step(unread, 1), QUARRY_OK) << error_of(unread);
  }
  expect_same_bits(state_of(looked), state_of(unread));
  quarry_close(looked);
  quarry_close(unread);
}

// A POST_FORCE hook that reads the forces sees the next-step loads in them, as every read does
// (they are put into the stored forces then). The step's motion keeps its bits (the closing
// kick's F + L is the one stored), and the forces left after it differ from a step where nothing
// looked only by the round-off of taking the loads out again ((F + L) − L).
int read_forces_in_hook(quarry_sim sim, int32_t, void* user_data) {
  *static_cast<State*>(user_data) = state_of(sim);
  return 0;
}

TEST(NextStepLoads, AHookReadingTheForcesSeesThemAndTheMotionKeepsItsBits) {
  quarry_sim looked = cluster(), unread = cluster();
  State seen;
  ASSERT_EQ(quarry_set_hook(looked, QUARRY_HOOK_POST_FORCE, read_forces_in_hook, &seen), QUARRY_OK);
  std::vector<double> force, torque;
  loads_of(state_of(unread), force, torque);
  write_through_views(looked, force, torque);
  write_through_views(unread, force, torque);
  ASSERT_EQ(quarry_step(looked, 1), QUARRY_OK) << error_of(looked);
  ASSERT_EQ(quarry_step(unread, 1), QUARRY_OK) << error_of(unread);
  const State a = state_of(looked), b = state_of(unread);
  EXPECT_TRUE(same_bits(a.position, b.position));
  EXPECT_TRUE(same_bits(a.velocity, b.velocity));
  EXPECT_TRUE(same_bits(a.spin, b.spin));
  for (int k = 0; k < 3 * kParticles; ++k) {
    // In the hook: the new configuration's force (b's, which never held a load) plus the load,
    // summed once in double as the kick would.
    EXPECT_EQ(seen.force[k], b.force[k] + force[k]) << k;
    EXPECT_EQ(seen.torque[k], b.torque[k] + torque[k]) << k;
    // After it: within an ulp of |F + L| ≲ 1e-3 N (2.2e-19 N) of the unread step's force.
    EXPECT_NEAR(a.force[k], b.force[k], 1e-18) << k;
  }
  quarry_close(looked);
  quarry_close(unread);
}

// Loads copied in first show in the view; overwritten there, the copied ones leave the forces
// again: to the bit when nothing had read the forces (the loads were kept apart from them), and
// to round-off when something had ((F + L1) − L1 is F only to within an ulp of F + L1).
TEST(NextStepLoads, TheViewHoldsLoadsCopiedInBeforeAndReplacesThem) {
  for (const bool read_between : {false, true}) {
    quarry_sim direct = cluster(), replaced = cluster();
    const State start = state_of(direct);
    std::vector<double> first(3 * kParticles, 5e-5), second, torque;
    loads_of(start, second, torque);
    ASSERT_EQ(quarry_set_external_loads(replaced, first.data(), nullptr, kParticles, QUARRY_LOAD_REPLACE,
                                        QUARRY_HOLD_NEXT_STEP),
              QUARRY_OK);
    if (read_between) state_of(replaced);  // the first loads go into the forces
    quarry_view view{};
    ASSERT_EQ(quarry_view_next_step_loads(replaced, QUARRY_FIELD_FORCE, &view), QUARRY_OK);
    for (int k = 0; k < 3 * kParticles; ++k) EXPECT_EQ(static_cast<const double*>(view.data)[k], 5e-5);
    std::memcpy(view.data, second.data(), second.size() * sizeof(double));
    ASSERT_EQ(quarry_set_external_loads(direct, second.data(), nullptr, kParticles, QUARRY_LOAD_REPLACE,
                                        QUARRY_HOLD_NEXT_STEP),
              QUARRY_OK);
    ASSERT_EQ(quarry_step(direct, 1), QUARRY_OK);
    ASSERT_EQ(quarry_step(replaced, 1), QUARRY_OK);
    const State a = state_of(direct), b = state_of(replaced);
    if (!read_between) {
      EXPECT_TRUE(same_bits(a.velocity, b.velocity));
    } else {
      // Velocity change per step: dt F / m with m = 2500 · 4/3 π (1 mm)³ ≈ 1.05e-5 kg; the force
      // differs by at most an ulp of |F + L1| ≲ 1e-3 N: 1e-5 s · 2.2e-19 N / 1e-5 kg ≈ 2e-19 m/s.
      for (int k = 0; k < 3 * kParticles; ++k) EXPECT_NEAR(a.velocity[k], b.velocity[k], 1e-17) << k;
    }
    quarry_close(direct);
    quarry_close(replaced);
  }
}

// A saved state holds loads written in place (the save puts them into the forces first): the
// state restored elsewhere steps to the same bits as the original.
TEST(NextStepLoads, ASavedStateHoldsThemAndRestoresBitForBit) {
  quarry_sim original = cluster(), other = cluster();
  std::vector<double> force, torque;
  loads_of(state_of(original), force, torque);
  write_through_views(original, force, torque);
  std::uint64_t needed = 0;
  ASSERT_EQ(quarry_save_state(original, nullptr, 0, &needed), QUARRY_OK);
  std::vector<char> bytes(needed);
  ASSERT_EQ(quarry_save_state(original, bytes.data(), bytes.size(), &needed), QUARRY_OK) << error_of(original);
  ASSERT_EQ(quarry_restore_state(other, bytes.data(), bytes.size()), QUARRY_OK) << error_of(other);
  for (int step = 0; step < 20; ++step) {
    ASSERT_EQ(quarry_step(original, 1), QUARRY_OK);
    ASSERT_EQ(quarry_step(other, 1), QUARRY_OK);
  }
  expect_same_bits(state_of(original), state_of(other));
  quarry_close(original);
  quarry_close(other);
}

TEST(NextStepLoads, ANonFiniteLoadStopsTheNextStepNamingTheParticle) {
  quarry_sim sim = cluster();
  quarry_view view{};
  ASSERT_EQ(quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, &view), QUARRY_OK);
  static_cast<double*>(view.data)[3 * 5 + 1] = std::nan("");
  EXPECT_EQ(quarry_step(sim, 1), QUARRY_ERROR_PHYSICS);
  const std::string text = error_of(sim);
  EXPECT_NE(text.find("non-finite"), std::string::npos) << text;
  EXPECT_NE(text.find("particle id"), std::string::npos) << text;
  quarry_close(sim);
}

int take_view_in_hook(quarry_sim sim, int32_t, void* user_data) {
  quarry_view view{};
  *static_cast<quarry_status*>(user_data) = quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, &view);
  return 0;
}

TEST(NextStepLoads, RefusedInsideAHook) {
  quarry_sim sim = cluster();
  quarry_status inside = QUARRY_OK;
  ASSERT_EQ(quarry_set_hook(sim, QUARRY_HOOK_POST_FORCE, take_view_in_hook, &inside), QUARRY_OK);
  ASSERT_EQ(quarry_step(sim, 1), QUARRY_OK) << error_of(sim);
  EXPECT_EQ(inside, QUARRY_ERROR_WRONG_STATE);
  quarry_close(sim);
}

}  // namespace
