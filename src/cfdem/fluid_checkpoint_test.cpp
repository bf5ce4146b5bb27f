// CFD-DEM restarts (issue #18): a run checkpointed inside a coupling interval and restarted goes
// on to the bit as the run that went through — particles, the fluid's u, v, w and p, the whole
// state (the two end states' checkpoints are the same bytes) — and its output files (fluid.pvd,
// the fluid frames and fluid_monitors.csv, as the particles' files) are those of the run that
// went through; a damaged or mismatched fluid section is refused with a message that says what.
#include "cfdem/fluid_coupling.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "cfdem/fluid_setup.h"
#include "io/deck.h"
#include "sim/run.h"
#include "sim/step.h"

namespace quarry::cfdem {
namespace {

namespace fs = std::filesystem;

// 40 beads thrown onto a plate in a column of water fed from below, the fluid step 5 DEM steps,
// 30 beads at the start and 10 more at step 250 (tests/decks/fluid_restart.yaml).
SimulationSpec restart_deck() {
  return parse_deck(std::string(QUARRY_SOURCE_DIR) + "/tests/decks/fluid_restart.yaml");
}

constexpr std::uint64_t kSteps = 400;        // the deck's end
constexpr std::uint64_t kCheckpointStep = 228;  // 228 = 45 · 5 + 3: inside a coupling interval

struct Coupled {
  World world;
  std::shared_ptr<FluidCoupling> coupling;
};

// `threads` on every loop (threshold 0), so that a restart on another count is tested too.
Coupled start(const SimulationSpec& spec, int threads) {
  Coupled run{build_world(spec), nullptr};
  run.world.threading = Threading{threads, 0};
  run.coupling = attach_fluid_from_spec(run.world);
  sim::initialize(run.world);
  return run;
}

// The restored world with the fluid attached again and given its state.
Coupled restore(const std::string& bytes, int threads, const std::vector<sim::SavedSection>* sections = nullptr) {
  sim::RestoredWorld restored = sim::read_checkpoint_bytes(bytes, "fluid.qck");
  Coupled run{std::move(restored.world), nullptr};
  run.world.threading = Threading{threads, 0};
  run.coupling = attach_fluid_from_spec(run.world);
  sim::restore_sections(run.world, sections ? *sections : restored.sections, "fluid.qck");
  return run;
}

// Every value a later step reads or a user sees: particles and the fluid's faces and cells.
std::vector<double> bits_of(const Coupled& run) {
  std::vector<double> bits;
  const ParticleStore& p = run.world.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    bits.push_back(static_cast<double>(p.id[i]));
    for (const Vec3* v : {&p.position[i], &p.velocity[i], &p.angular_velocity[i], &p.force[i], &p.torque[i]})
      bits.insert(bits.end(), {v->x, v->y, v->z});
  }
  const cfd::FluidSolver& fluid = run.coupling->fluid();
  const std::array<int, 3> n = fluid.grid().cells;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < n[2] + (axis == 2); ++k)
      for (int j = 0; j < n[1] + (axis == 1); ++j)
        for (int i = 0; i < n[0] + (axis == 0); ++i) bits.push_back(fluid.face_velocity(axis, i, j, k));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) bits.push_back(fluid.pressure(i, j, k));
  bits.insert(bits.end(), run.coupling->void_fraction().begin(), run.coupling->void_fraction().end());
  return bits;
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < a.size(); ++k) differing += std::memcmp(&a[k], &b[k], sizeof(double)) != 0;
  EXPECT_EQ(differing, 0u) << "of " << a.size() << " values";
}

TEST(FluidCheckpoint, RestartInsideACouplingIntervalIsBitIdentical) {
  const SimulationSpec spec = restart_deck();
  Coupled through = start(spec, 1);
  ASSERT_EQ(through.coupling->options().coupling_steps, 5);
  std::size_t contacts = 0;  // the most at any step: the beads hit the plate and each other
  through.world.hooks.push_back({HookStage::end_of_step, "count contacts", [&contacts](World& w) {
                                   contacts = std::max(contacts, w.pair_contact_count() + w.wall_contact_count());
                                 }});
  sim::advance(through.world, kSteps);

  std::string bytes;
  {
    Coupled first = start(spec, 2);
    sim::advance(first.world, kCheckpointStep);
    ASSERT_NE(first.world.step_count % 5, 0u) << "the checkpoint must fall inside a coupling interval";
    ASSERT_LT(first.world.particles.size(), 40u) << "particles must be added after the checkpoint";
    bytes = sim::checkpoint_bytes(first.world, 0);
  }  // the first run is gone: the restart has only the bytes
  Coupled again = restore(bytes, 1);
  sim::advance(again.world, kSteps - kCheckpointStep);

  EXPECT_EQ(again.world.particles.size(), 40u);
  EXPECT_EQ(sim::state_hash(again.world), sim::state_hash(through.world));
  expect_same_bits(bits_of(again), bits_of(through));
  EXPECT_EQ(again.coupling->exchanges(), through.coupling->exchanges());
  EXPECT_EQ(again.coupling->fluid().last_report().divergence, through.coupling->fluid().last_report().divergence);
  // The whole state, fluid section included: the same bytes.
  EXPECT_TRUE(sim::checkpoint_bytes(again.world, 0) == sim::checkpoint_bytes(through.world, 0));
  // The fluid moved (the test compares something).
  EXPECT_GT(std::abs(through.coupling->fluid().face_velocity(2, 1, 1, 6)), 1e-4);
  EXPECT_GT(contacts, 0u);
}

// The restore of `sections` (into a world restored from `bytes`, the fluid attached) must fail
// with a UserError whose text holds `expected`.
void expect_refused(const std::string& bytes, const std::vector<sim::SavedSection>& sections, const std::string& expected,
                    bool attach = true) {
  sim::RestoredWorld restored = sim::read_checkpoint_bytes(bytes, "fluid.qck");
  if (attach) attach_fluid_from_spec(restored.world);
  try {
    sim::restore_sections(restored.world, sections, "damaged.qck");
    ADD_FAILURE() << expected << ": restored without a word";
  } catch (const UserError& e) {
    const std::string text = e.diagnostics().format();
    EXPECT_NE(text.find("damaged.qck"), std::string::npos) << text;
    EXPECT_NE(text.find("cannot restore checkpoint"), std::string::npos) << text;
    EXPECT_NE(text.find(expected), std::string::npos) << expected << ": " << text;
  }
}

TEST(FluidCheckpoint, DamagedOrMismatchedFluidStateIsRefused) {
  const SimulationSpec spec = restart_deck();
  Coupled run = start(spec, 1);
  sim::advance(run.world, 57);
  const std::string bytes = sim::checkpoint_bytes(run.world, 0);
  const std::vector<sim::SavedSection> intact = sim::read_checkpoint_bytes(bytes, "fluid.qck").sections;
  ASSERT_EQ(intact.size(), 3u);  // the fluid, its frames and its monitors
  const auto fluid = std::find_if(intact.begin(), intact.end(), [](const sim::SavedSection& s) { return s.name == "fluid"; });
  ASSERT_NE(fluid, intact.end());
  const auto index = static_cast<std::size_t>(fluid - intact.begin());
  const auto damaged = [&](const std::function<void(std::string&)>& damage) {
    std::vector<sim::SavedSection> sections = intact;
    damage(sections[index].bytes);
    return sections;
  };
  // The section: version (4 bytes), then u, v, w and p as arrays (a length, then the values).
  std::uint64_t padded = 0;
  std::memcpy(&padded, fluid->bytes.data() + 4, sizeof padded);
  const std::size_t first_pressure = 4 + 3 * (8 + 8 * padded) + 8;
  ASSERT_LT(first_pressure + 8, fluid->bytes.size());

  expect_refused(bytes, damaged([](std::string& b) { b.resize(b.size() / 2); }), "'fluid' section: ");
  expect_refused(bytes, damaged([](std::string& b) { b += 'x'; }), "'fluid' section: bytes remain after its last field");
  expect_refused(bytes, damaged([](std::string& b) { b[0] = 9; }), "'fluid' section: version 9");
  expect_refused(bytes, damaged([&](std::string& b) {
                   const double nan = std::numeric_limits<double>::quiet_NaN();
                   std::memcpy(b.data() + first_pressure, &nan, sizeof nan);
                 }),
                 "the fluid's pressure value 0 is not a finite number");
  // The fluid of a deck with another grid: its sizes are not this deck's.
  SimulationSpec other = spec;
  other.fluid->cells.value[2] = 11;
  Coupled taller = start(other, 1);
  const std::vector<sim::SavedSection> taller_sections =
      sim::read_checkpoint_bytes(sim::checkpoint_bytes(taller.world, 0), "taller.qck").sections;
  expect_refused(bytes, damaged([&](std::string& b) { b = taller_sections[index].bytes; }), "values, the grid");
  // A checkpoint without the fluid for a run with one, and one with it for a restart without.
  std::vector<sim::SavedSection> without = intact;
  without.erase(without.begin() + static_cast<std::ptrdiff_t>(index));
  expect_refused(bytes, without, "it holds no 'fluid' state, which this restart needs");
  expect_refused(bytes, intact, "it holds 'fluid' state that nothing in this restart takes", false);
  // The intact sections restore.
  Coupled again = restore(bytes, 1, &intact);
  EXPECT_EQ(again.coupling->exchanges(), run.coupling->exchanges());
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Through sim::run and sim::restart as the CLI calls them: a run stopped by a signal inside a
// coupling interval (its last monitor row then written at the stop, which the run that went
// through does not have) and restarted writes every file of the run that went through, to the
// byte: the particles' and the fluid's frames and series, monitors.csv, fluid_monitors.csv and
// the last checkpoint.
TEST(FluidCheckpoint, ARunStoppedAndRestartedWritesTheFilesOfTheRunThatWentThrough) {
  const SimulationSpec spec = restart_deck();
  // Named by the process: two checkouts' tests may run at once on one machine.
  const std::string tag = std::to_string(::getpid());
  const fs::path straight = fs::path(::testing::TempDir()) / ("quarry_fluid_restart_straight_" + tag);
  const fs::path split = fs::path(::testing::TempDir()) / ("quarry_fluid_restart_split_" + tag);
  fs::remove_all(straight);
  fs::remove_all(split);
  std::ostringstream log;
  sim::RunOptions options;
  options.quiet = true;
  options.threads = 1;
  options.log = &log;
  const sim::AttachToWorld attach = [](World& world) -> std::shared_ptr<void> { return attach_fluid_from_spec(world); };

  World through = build_world(spec);
  const auto through_fluid = attach(through);
  options.output_directory = straight.string();
  sim::run(through, options);

  World first = build_world(spec);
  const auto first_fluid = attach(first);
  std::atomic<int> stop{0};
  constexpr std::uint64_t kStopStep = 137;  // 27 · 5 + 2; no monitor row (every 20) or frame (every 50) there
  first.hooks.push_back({HookStage::end_of_step, "stop", [&stop](World& w) {
                           if (w.step_count == kStopStep) stop = SIGTERM;
                         }});
  options.output_directory = split.string();
  options.stop = &stop;
  const sim::RunSummary stopped = sim::run(first, options);
  ASSERT_TRUE(stopped.interrupted());
  ASSERT_EQ(first.step_count, kStopStep);
  options.stop = nullptr;
  sim::restart((split / "checkpoint.qck").string(), options, attach);

  std::size_t files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(straight)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(read_text(entry.path()) == read_text(split / name)) << name << " differs after the restart";
    ++files;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(split), fs::directory_iterator{}), static_cast<std::ptrdiff_t>(files));
  EXPECT_GE(files, 20u);
  const std::string rows = read_text(straight / "fluid_monitors.csv");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 1 + 21) << rows;  // header, step 1, every 20 steps
  EXPECT_NE(read_text(straight / "fluid.pvd").find("fluid_000008.vti"), std::string::npos);
  fs::remove_all(straight);
  fs::remove_all(split);
}

}  // namespace
}  // namespace quarry::cfdem
