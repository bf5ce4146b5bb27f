// Bad calls through the C ABI never crash (issue 16 §5): every function with a handle never
// opened and one already closed, then NULL pointers, wrong lengths and calls in the wrong state —
// each answered by its status code and a last-error text that names the call, with nothing changed.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "capi/abi_test_support.h"
#include "quarry/quarry.h"

namespace {

using quarry_test::error_of;

// The shared small simulation with two particles, 0.1 m apart.
quarry_sim started_simulation() {
  quarry_sim sim = quarry_test::started_simulation();
  const double position[6] = {0, 0, 0, 0.1, 0, 0};
  quarry_test::add_particles(sim, position, 2);
  return sim;
}

// Buffers every call below may write into (large enough for the small simulation).
struct Buffers {
  double doubles[4096] = {};
  std::uint64_t ids[64] = {};
  std::uint32_t types[64] = {};
  char text[256] = {};
  quarry_view view{};
  quarry_settings settings = quarry_default_settings();
  quarry_material material{sizeof(quarry_material), "m", 1000.0, 1e7, 0.3};
  quarry_interaction interaction{sizeof(quarry_interaction), "m", "m", 0.5, 0.5, 0.0, 0, 0.0};
  quarry_particle_type type{sizeof(quarry_particle_type), "t", "m", 1e-3, 0.0};
  quarry_particle_data data{};
  quarry_new_particles add{};
  quarry_surface_desc surface{};
  quarry_surface_info surface_info{};
  quarry_surface_loads loads{};
  quarry_advance_result advance{};
  std::uint32_t triangle[3] = {0, 1, 2};
  Buffers() {
    data.struct_size = sizeof data;
    data.capacity = 64;
    add.struct_size = sizeof add;
    surface.struct_size = sizeof surface;
    surface_info.struct_size = sizeof surface_info;
    loads.struct_size = sizeof loads;
    advance.struct_size = sizeof advance;
  }
};

struct Call {
  const char* name;
  std::function<quarry_status(quarry_sim, Buffers&)> run;
};

// Every function of quarry.h that takes a handle, called with plausible arguments.
std::vector<Call> every_call() {
  return {
      {"quarry_close", [](quarry_sim s, Buffers&) { return quarry_close(s); }},
      {"quarry_set_settings", [](quarry_sim s, Buffers& b) { return quarry_set_settings(s, &b.settings); }},
      {"quarry_add_material", [](quarry_sim s, Buffers& b) { return quarry_add_material(s, &b.material, nullptr); }},
      {"quarry_add_interaction", [](quarry_sim s, Buffers& b) { return quarry_add_interaction(s, &b.interaction); }},
      {"quarry_add_particle_type", [](quarry_sim s, Buffers& b) { return quarry_add_particle_type(s, &b.type, nullptr); }},
      {"quarry_start", [](quarry_sim s, Buffers&) { return quarry_start(s); }},
      {"quarry_get_time", [](quarry_sim s, Buffers& b) { return quarry_get_time(s, b.doubles, nullptr, nullptr); }},
      {"quarry_advance", [](quarry_sim s, Buffers& b) { return quarry_advance(s, 1e-4, &b.advance); }},
      {"quarry_step", [](quarry_sim s, Buffers&) { return quarry_step(s, 1); }},
      {"quarry_save_checkpoint", [](quarry_sim s, Buffers&) { return quarry_save_checkpoint(s, "unused.qck"); }},
      {"quarry_save_state", [](quarry_sim s, Buffers&) {
         std::uint64_t needed = 0;
         return quarry_save_state(s, nullptr, 0, &needed);
       }},
      {"quarry_restore_state", [](quarry_sim s, Buffers& b) { return quarry_restore_state(s, b.doubles, 64); }},
      {"quarry_num_types", [](quarry_sim s, Buffers& b) { return quarry_num_types(s, b.types); }},
      {"quarry_type_name", [](quarry_sim s, Buffers& b) { return quarry_type_name(s, 0, b.text, sizeof b.text); }},
      {"quarry_num_particles", [](quarry_sim s, Buffers& b) { return quarry_num_particles(s, -1, b.ids); }},
      {"quarry_epoch", [](quarry_sim s, Buffers& b) { return quarry_epoch(s, b.ids); }},
      {"quarry_get_particles", [](quarry_sim s, Buffers& b) { return quarry_get_particles(s, &b.data); }},
      {"quarry_particle_index", [](quarry_sim s, Buffers& b) { return quarry_particle_index(s, 1, b.ids); }},
      {"quarry_view_particles", [](quarry_sim s, Buffers& b) { return quarry_view_particles(s, QUARRY_FIELD_POSITION, &b.view); }},
      {"quarry_add_particles", [](quarry_sim s, Buffers& b) { return quarry_add_particles(s, &b.add); }},
      {"quarry_remove_particles", [](quarry_sim s, Buffers& b) { return quarry_remove_particles(s, b.ids, 0); }},
      {"quarry_set_external_loads", [](quarry_sim s, Buffers& b) {
         return quarry_set_external_loads(s, b.doubles, nullptr, 2, QUARRY_LOAD_REPLACE, QUARRY_HOLD_NEXT_STEP);
       }},
      {"quarry_set_external_loads_by_id", [](quarry_sim s, Buffers& b) {
         return quarry_set_external_loads_by_id(s, b.ids, 0, b.doubles, nullptr, QUARRY_LOAD_ADD, QUARRY_HOLD_NEXT_STEP);
       }},
      {"quarry_clear_external_loads", [](quarry_sim s, Buffers&) { return quarry_clear_external_loads(s); }},
      {"quarry_view_next_step_loads", [](quarry_sim s, Buffers& b) {
         return quarry_view_next_step_loads(s, QUARRY_FIELD_FORCE, &b.view);
       }},
      {"quarry_register_property", [](quarry_sim s, Buffers& b) {
         return quarry_register_property(s, "p", 1, "", 0.0, b.types);
       }},
      {"quarry_num_properties", [](quarry_sim s, Buffers& b) { return quarry_num_properties(s, b.types); }},
      {"quarry_property_info", [](quarry_sim s, Buffers& b) {
         return quarry_property_info(s, 0, b.text, sizeof b.text, b.types, nullptr, 0);
       }},
      {"quarry_get_property", [](quarry_sim s, Buffers& b) { return quarry_get_property(s, 0, b.doubles, 2); }},
      {"quarry_set_property", [](quarry_sim s, Buffers& b) { return quarry_set_property(s, 0, b.doubles, 2); }},
      {"quarry_view_property", [](quarry_sim s, Buffers& b) { return quarry_view_property(s, 0, &b.view); }},
      {"quarry_sample_points", [](quarry_sim s, Buffers& b) { return quarry_sample_points(s, 0, 10, 1, b.doubles); }},
      {"quarry_sample_point_positions", [](quarry_sim s, Buffers& b) {
         return quarry_sample_point_positions(s, 0, 10, 1, b.doubles, 4096, nullptr);
       }},
      {"quarry_add_surface", [](quarry_sim s, Buffers& b) { return quarry_add_surface(s, &b.surface, nullptr); }},
      {"quarry_num_surfaces", [](quarry_sim s, Buffers& b) { return quarry_num_surfaces(s, b.types); }},
      {"quarry_find_surface", [](quarry_sim s, Buffers& b) { return quarry_find_surface(s, "x", b.types); }},
      {"quarry_get_surface_info", [](quarry_sim s, Buffers& b) { return quarry_get_surface_info(s, 0, &b.surface_info); }},
      {"quarry_set_surface_driver", [](quarry_sim s, Buffers&) { return quarry_set_surface_driver(s, 0, QUARRY_DRIVER_COUPLED); }},
      {"quarry_set_surface_nodes", [](quarry_sim s, Buffers& b) {
         return quarry_set_surface_nodes(s, 0, b.doubles, nullptr, 3);
       }},
      {"quarry_get_surface_nodes", [](quarry_sim s, Buffers& b) {
         return quarry_get_surface_nodes(s, 0, b.doubles, nullptr, 3);
       }},
      {"quarry_get_surface_loads", [](quarry_sim s, Buffers& b) { return quarry_get_surface_loads(s, 0, &b.loads); }},
      {"quarry_set_hook", [](quarry_sim s, Buffers&) { return quarry_set_hook(s, QUARRY_HOOK_POST_FORCE, nullptr, nullptr); }},
      {"quarry_add_hook_forces", [](quarry_sim s, Buffers& b) { return quarry_add_hook_forces(s, b.doubles, nullptr, 2); }},
      {"quarry_last_error", [](quarry_sim s, Buffers& b) { return quarry_last_error(s, b.text, sizeof b.text, nullptr); }},
  };
}

TEST(BadCalls, EveryFunctionRefusesHandlesNeverOpenedOrClosed) {
  const quarry_sim forged{0x0000000700000005ull};
  quarry_sim closed = started_simulation();
  ASSERT_EQ(quarry_close(closed), QUARRY_OK);
  // A new simulation may reuse the closed one's slot: the old handle must still be refused.
  quarry_sim live = started_simulation();
  for (const Call& call : every_call()) {
    for (const quarry_sim bad : {forged, closed}) {
      Buffers buffers;
      EXPECT_EQ(call.run(bad, buffers), QUARRY_ERROR_INVALID_HANDLE) << call.name;
      const std::string text = error_of(QUARRY_NO_SIM);
      EXPECT_NE(text.find(call.name), std::string::npos) << call.name << ": " << text;
    }
  }
  std::uint64_t count = 0;
  EXPECT_EQ(quarry_num_particles(live, -1, &count), QUARRY_OK);
  EXPECT_EQ(count, 2u) << "the live simulation was disturbed";
  EXPECT_EQ(quarry_close(live), QUARRY_OK);
}

TEST(BadCalls, OpenRefusesWhatItCannotUse) {
  quarry_sim sim{};
  EXPECT_EQ(quarry_open(nullptr, &sim), QUARRY_ERROR_NULL_POINTER);
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  EXPECT_EQ(quarry_open(&info, nullptr), QUARRY_ERROR_NULL_POINTER);
  info.abi_version = (QUARRY_ABI_MAJOR + 1u) << 16;
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_ERROR_VERSION);
  EXPECT_NE(error_of(QUARRY_NO_SIM).find("rebuild"), std::string::npos) << error_of(QUARRY_NO_SIM);
  info = QUARRY_OPEN_INFO_INIT;
  info.struct_size = 8;  // a struct from nowhere
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_ERROR_BAD_VALUE);
  info = QUARRY_OPEN_INFO_INIT;
  info.deck_path = "no/such/deck.yaml";
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_ERROR_INPUT);
  EXPECT_NE(error_of(QUARRY_NO_SIM).find("no/such/deck.yaml"), std::string::npos) << error_of(QUARRY_NO_SIM);
  info = QUARRY_OPEN_INFO_INIT;
  info.checkpoint_path = "no/such/checkpoint.qck";
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_ERROR_INPUT);
  info = QUARRY_OPEN_INFO_INIT;
  info.threads = -2;
  EXPECT_EQ(quarry_open(&info, &sim), QUARRY_ERROR_BAD_VALUE);
}

// The per-call refusals of a started simulation: NULL pointers, lengths that are not the
// particle or node count, values out of range, and calls that need another state.
TEST(BadCalls, WrongArgumentsAndStatesAreRefusedAndChangeNothing) {
  quarry_sim sim = started_simulation();
  Buffers b;
  struct Expectation {
    const char* name;
    quarry_status status;
    std::function<quarry_status()> run;
  };
  double state_before[64] = {}, state_after[64] = {};
  quarry_particle_data snapshot{};
  snapshot.struct_size = sizeof snapshot;
  snapshot.capacity = 8;
  snapshot.position = state_before;
  ASSERT_EQ(quarry_get_particles(sim, &snapshot), QUARRY_OK);
  const std::vector<Expectation> table = {
      {"quarry_set_settings", QUARRY_ERROR_WRONG_STATE, [&] { return quarry_set_settings(sim, &b.settings); }},
      {"quarry_add_material", QUARRY_ERROR_WRONG_STATE, [&] { return quarry_add_material(sim, &b.material, nullptr); }},
      {"quarry_start", QUARRY_ERROR_WRONG_STATE, [&] { return quarry_start(sim); }},
      {"quarry_set_settings", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_set_settings(sim, nullptr); }},
      {"quarry_num_types", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_num_types(sim, nullptr); }},
      {"quarry_get_particles", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_get_particles(sim, nullptr); }},
      {"quarry_get_particles", QUARRY_ERROR_BAD_LENGTH, [&] {
         quarry_particle_data small = b.data;
         small.capacity = 1;
         return quarry_get_particles(sim, &small);
       }},
      {"quarry_get_particles", QUARRY_ERROR_BAD_VALUE, [&] {
         quarry_particle_data old = b.data;
         old.struct_size = 16;  // shorter than any version of the struct
         return quarry_get_particles(sim, &old);
       }},
      {"quarry_advance", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_advance(sim, -1.0, nullptr); }},
      {"quarry_advance", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_advance(sim, std::nan(""), nullptr); }},
      {"quarry_set_external_loads", QUARRY_ERROR_BAD_LENGTH, [&] {
         return quarry_set_external_loads(sim, b.doubles, nullptr, 3, QUARRY_LOAD_REPLACE, QUARRY_HOLD_NEXT_STEP);
       }},
      {"quarry_set_external_loads", QUARRY_ERROR_BAD_VALUE, [&] {
         return quarry_set_external_loads(sim, b.doubles, nullptr, 2, 7, QUARRY_HOLD_NEXT_STEP);
       }},
      {"quarry_set_external_loads_by_id", QUARRY_ERROR_NOT_FOUND, [&] {
         const std::uint64_t id = 999;
         return quarry_set_external_loads_by_id(sim, &id, 1, b.doubles, nullptr, QUARRY_LOAD_ADD, QUARRY_HOLD_NEXT_STEP);
       }},
      {"quarry_remove_particles", QUARRY_ERROR_NOT_FOUND, [&] {
         const std::uint64_t ids[2] = {1, 999};  // 1 exists: it must not be removed either
         return quarry_remove_particles(sim, ids, 2);
       }},
      {"quarry_remove_particles", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_remove_particles(sim, nullptr, 1); }},
      {"quarry_particle_index", QUARRY_ERROR_NOT_FOUND, [&] { return quarry_particle_index(sim, 999, b.ids); }},
      {"quarry_add_particles", QUARRY_ERROR_NULL_POINTER, [&] {
         quarry_new_particles add = b.add;
         add.count = 1;  // positions missing
         return quarry_add_particles(sim, &add);
       }},
      {"quarry_add_particles", QUARRY_ERROR_BAD_VALUE, [&] {
         const double outside[3] = {5.0, 0.0, 0.0};
         quarry_new_particles add = b.add;
         add.count = 1;
         add.position = outside;
         return quarry_add_particles(sim, &add);
       }},
      {"quarry_add_particles", QUARRY_ERROR_BAD_VALUE, [&] {
         const double inside[3] = {0.5, 0.5, 0.5};
         quarry_new_particles add = b.add;
         add.count = 1;
         add.position = inside;
         add.type = 3;  // no such type
         return quarry_add_particles(sim, &add);
       }},
      {"quarry_view_particles", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_view_particles(sim, 77, &b.view); }},
      {"quarry_view_next_step_loads", QUARRY_ERROR_BAD_VALUE, [&] {
         return quarry_view_next_step_loads(sim, QUARRY_FIELD_POSITION, &b.view);
       }},
      {"quarry_view_next_step_loads", QUARRY_ERROR_NULL_POINTER, [&] {
         return quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, nullptr);
       }},
      {"quarry_get_property", QUARRY_ERROR_NOT_FOUND, [&] { return quarry_get_property(sim, 5, b.doubles, 2); }},
      {"quarry_register_property", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_register_property(sim, "radius", 1, "m", 0.0, nullptr); }},
      {"quarry_register_property", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_register_property(sim, "zero", 0, "", 0.0, nullptr); }},
      {"quarry_sample_points", QUARRY_ERROR_NOT_FOUND, [&] { return quarry_sample_points(sim, 4, 10, 1, b.doubles); }},
      {"quarry_sample_point_positions", QUARRY_ERROR_BAD_LENGTH, [&] {
         return quarry_sample_point_positions(sim, 0, 10, 1, b.doubles, 5, nullptr);
       }},
      {"quarry_get_surface_info", QUARRY_ERROR_NOT_FOUND, [&] { return quarry_get_surface_info(sim, 0, &b.surface_info); }},
      {"quarry_find_surface", QUARRY_ERROR_NOT_FOUND, [&] { return quarry_find_surface(sim, "none", b.types); }},
      {"quarry_add_surface", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_add_surface(sim, &b.surface, nullptr); }},
      {"quarry_add_surface", QUARRY_ERROR_BAD_VALUE, [&] {
         const double nodes[9] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
         const std::uint32_t bad[3] = {0, 1, 7};  // node 7 does not exist
         quarry_surface_desc d = b.surface;
         d.name = "s";
         d.material = "ore";
         d.node_count = 3;
         d.nodes = nodes;
         d.triangle_count = 1;
         d.triangles = bad;
         return quarry_add_surface(sim, &d, nullptr);
       }},
      {"quarry_add_hook_forces", QUARRY_ERROR_WRONG_STATE, [&] { return quarry_add_hook_forces(sim, b.doubles, nullptr, 2); }},
      {"quarry_set_hook", QUARRY_ERROR_BAD_VALUE, [&] { return quarry_set_hook(sim, 9, nullptr, nullptr); }},
      {"quarry_restore_state", QUARRY_ERROR_INPUT, [&] { return quarry_restore_state(sim, b.doubles, 64); }},
      {"quarry_save_checkpoint", QUARRY_ERROR_NULL_POINTER, [&] { return quarry_save_checkpoint(sim, nullptr); }},
  };
  for (const Expectation& e : table) {
    EXPECT_EQ(e.run(), e.status) << e.name << " should give " << quarry_status_name(e.status) << ": " << error_of(sim);
    const std::string text = error_of(sim);
    EXPECT_NE(text.find(e.name), std::string::npos) << e.name << ": " << text;
  }
  std::uint64_t count = 0;
  ASSERT_EQ(quarry_num_particles(sim, -1, &count), QUARRY_OK);
  EXPECT_EQ(count, 2u) << "a refused call changed the particles";
  snapshot.position = state_after;
  ASSERT_EQ(quarry_get_particles(sim, &snapshot), QUARRY_OK);
  EXPECT_EQ(std::vector<double>(state_before, state_before + 6), std::vector<double>(state_after, state_after + 6));
  EXPECT_EQ(error_of(sim), "") << "a successful call clears the last error";
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

// A state put back by quarry_restore_state makes every earlier view and index stale: the epoch
// moves past the current one and past the saved one, even when the two were equal.
TEST(BadCalls, RestoredStateMovesTheEpochPastBoth) {
  quarry_sim sim = started_simulation();
  std::uint64_t needed = 0, saved_epoch = 0, current = 0, after = 0;
  ASSERT_EQ(quarry_save_state(sim, nullptr, 0, &needed), QUARRY_OK);
  std::vector<char> state(needed);
  ASSERT_EQ(quarry_save_state(sim, state.data(), state.size(), &needed), QUARRY_OK);
  ASSERT_EQ(quarry_epoch(sim, &saved_epoch), QUARRY_OK);
  const double position[3] = {0.2, 0.2, 0.2};
  quarry_test::add_particles(sim, position, 1);  // epoch + 1: the saved one + 1
  ASSERT_EQ(quarry_epoch(sim, &current), QUARRY_OK);
  ASSERT_EQ(quarry_restore_state(sim, state.data(), state.size()), QUARRY_OK) << error_of(sim);
  ASSERT_EQ(quarry_epoch(sim, &after), QUARRY_OK);
  EXPECT_GT(after, current);
  EXPECT_GT(after, saved_epoch);
  std::uint64_t count = 0;
  ASSERT_EQ(quarry_num_particles(sim, -1, &count), QUARRY_OK);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

// A simulation built by calls that lacks what a deck would need is refused at start with what is
// missing; the handle stays usable.
TEST(BadCalls, IncompleteDefinitionIsReportedAtStart) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  quarry_sim sim{};
  ASSERT_EQ(quarry_open(&info, &sim), QUARRY_OK);
  quarry_material a{sizeof(quarry_material), "a", 2500.0, 1e7, 0.3};
  ASSERT_EQ(quarry_add_material(sim, &a, nullptr), QUARRY_OK);
  quarry_particle_type type{sizeof(quarry_particle_type), "grain", "a", 1e-3, 0.0};
  ASSERT_EQ(quarry_add_particle_type(sim, &type, nullptr), QUARRY_OK);
  EXPECT_EQ(quarry_start(sim), QUARRY_ERROR_INPUT);  // no domain, no interaction a–a
  const std::string text = error_of(sim);
  EXPECT_NE(text.find("domain"), std::string::npos) << text;
  EXPECT_NE(text.find("interaction"), std::string::npos) << text;
  std::uint32_t types = 0;
  EXPECT_EQ(quarry_num_types(sim, &types), QUARRY_OK);
  EXPECT_EQ(types, 1u);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

}  // namespace
