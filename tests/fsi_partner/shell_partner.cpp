// A structural partner in the place of an external FEM code (issue #17 §4): Quarry's own shell
// solver, coupled to a DEM simulation that it reaches ONLY through the public C ABI (quarry.h,
// libquarry) — in this process, or in a `quarry serve` process with --endpoint. It runs the
// OptiStruct EDEM card's exchange itself (docs/fem.md, "Coupling an external FEM code"):
//   0. the model's bulk data read and adapted (the EDEM card: the coupling surface, PERIOD,
//      FILTER); the coupling surface added to the DEM as a COUPLED surface, its nodes set to
//      the structure's, the DEM's load window started (an empty first read);
//   1. the structure steps to its sync point (its first step at or after the requested one),
//      loaded by the last exchange's forces;
//   2. the DEM steps to its sync point (quarry_step: its first step at or after the request);
//   3. exchange: quarry_get_surface_loads (window-mean consistent nodal forces and the window's
//      length) → FILTER → the structure's loads for its next period; the nodal positions,
//      advanced by v·(t_DEM − t_structure) to the DEM's time, and velocities →
//      quarry_set_surface_nodes (the DEM surface moves on with them until the next exchange).
// The structure's half of this (periods, FILTER, the nodes sent) is fsi::StructureSide, the
// code the built-in coupler (fsi::StructureCoupler) runs, fed the same numbers: the two paths
// give the same bits (tests/fsi_partner/partner_agreement_test.sh).
// Exit codes: 0 done, 1 the model, the DEM or a call failed (message on stderr), 2 bad usage.
#include <quarry/quarry.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "fem/shell_solver.h"
#include "fsi/coupling_schedule.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_side.h"
#include "fsi_partner/coupling_report.h"

namespace {

using quarry::Vec3;

constexpr const char* kUsage =
    "usage: shell_partner --deck DEM.yaml --model MODEL.bdf --end-time T [options]\n"
    "  --deck PATH             the DEM deck (no structures: section); with --endpoint the server opens it\n"
    "  --model PATH            bulk data with an EDEM card (its COUPLING surface, PERIOD, FILTER)\n"
    "  --end-time T            s, TTERM: the run's end (PERIOD defaults to TTERM/100)\n"
    "  --endpoint EP           ipc://PATH or tcp://HOST:PORT of a `quarry serve` (default: in this process)\n"
    "  --material NAME         the DEM material of the coupling surface (default: steel)\n"
    "  --period S, --filter S  override the card's PERIOD / FILTER (as a deck's structures: entry)\n"
    "  --mass-scaling-step S   shell mass scaling to this step (default 0: none)\n"
    "  --damping ALPHA         1/s, mass-proportional damping (default 0)\n"
    "  --step-fraction F       the structure's step / its stable estimate (default 0.9)\n"
    "  --threads N             DEM threads (default: the deck's or OpenMP's)\n"
    "  --timeout-ms N          remote: the longest wait for an answer (default 60000)\n"
    "  --report PATH           write the load history and the final state (hex floats) there\n";

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "shell_partner: %s\n%s", message.c_str(), kUsage);
  std::exit(2);
}

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "shell_partner: %s\n", message.c_str());
  std::exit(1);
}

// A call that must succeed: otherwise the call's name, its status and the handle's error text
// (QUARRY_NO_SIM: this thread's), and exit 1.
void must(quarry_sim sim, quarry_status status, const char* call) {
  if (status == QUARRY_OK) return;
  char text[4096] = "";
  quarry_last_error(sim, text, sizeof text, nullptr);
  const std::string name(call, std::strcspn(call, "("));
  fail(name + " returned " + quarry_status_name(status) + ": " + text);
}
#define MUST(sim, call) must((sim), (call), #call)

double number(const char* option, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value))
    usage_error(std::string(option) + " takes a number, not \"" + text + "\"");
  return value;
}

struct Options {
  std::string deck, model, material = "steel", report;
  std::optional<std::string> endpoint;
  std::optional<double> end_time, period, filter;
  double mass_scaling_step = 0.0, damping = 0.0, step_fraction = 0.9;  // s, 1/s, 1
  int threads = 0, timeout_ms = 0;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string key = argv[a];
    if (key == "--help" || key == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (a + 1 >= argc) usage_error(key + " needs a value");
    const char* value = argv[++a];
    if (key == "--deck") o.deck = value;
    else if (key == "--model") o.model = value;
    else if (key == "--end-time") o.end_time = number("--end-time", value);
    else if (key == "--endpoint") o.endpoint = value;
    else if (key == "--material") o.material = value;
    else if (key == "--period") o.period = number("--period", value);
    else if (key == "--filter") o.filter = number("--filter", value);
    else if (key == "--mass-scaling-step") o.mass_scaling_step = number("--mass-scaling-step", value);
    else if (key == "--damping") o.damping = number("--damping", value);
    else if (key == "--step-fraction") o.step_fraction = number("--step-fraction", value);
    else if (key == "--threads") o.threads = static_cast<int>(number("--threads", value));
    else if (key == "--timeout-ms") o.timeout_ms = static_cast<int>(number("--timeout-ms", value));
    else if (key == "--report") o.report = value;
    else usage_error("unknown option " + key);
  }
  if (o.deck.empty() || o.model.empty() || !o.end_time) usage_error("--deck, --model and --end-time are required");
  if (!(*o.end_time > 0.0)) usage_error("--end-time must be > 0 s");
  if (o.mass_scaling_step < 0.0 || o.damping < 0.0) usage_error("--mass-scaling-step and --damping must be ≥ 0");
  if (!(o.step_fraction > 0.0 && o.step_fraction <= 1.0)) usage_error("--step-fraction must be in (0, 1]");
  if (o.threads < 0 || o.timeout_ms < 0) usage_error("--threads and --timeout-ms must be ≥ 0");
  if (!o.report.empty()) {  // writable, before a run that would end without it
    std::FILE* f = std::fopen(o.report.c_str(), "w");
    if (!f) fail("cannot write the report " + o.report + ": " + std::strerror(errno));
    std::fclose(f);
  }
  return o;
}

std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const Vec3& x : v) out.insert(out.end(), {x.x, x.y, x.z});
  return out;
}

struct Dem {
  quarry_sim sim{};
  std::uint32_t surface = 0;
  double time = 0.0, dt = 0.0;  // s
  void refresh_time() { MUST(sim, quarry_get_time(sim, &time, &dt, nullptr)); }
};

// Structure → DEM: the coupled nodes at the DEM's time, with their velocities.
void send_nodes(Dem& dem, const quarry::fsi::StructureSide& side) {
  std::vector<Vec3> x, v;
  side.surface_nodes(dem.time, x, v);
  const std::vector<double> xs = flat(x), vs = flat(v);
  MUST(dem.sim, quarry_set_surface_nodes(dem.sim, dem.surface, xs.data(), vs.data(), x.size()));
}

// DEM → structure: the window-mean nodal forces (N) and the window's length (s); the window
// restarts.
double take_loads(Dem& dem, std::size_t nodes, std::vector<Vec3>& mean_force) {
  std::vector<double> force(3 * nodes);
  quarry_surface_loads loads{};
  loads.struct_size = sizeof loads;
  loads.node_count = nodes;
  loads.nodal_force = force.data();
  MUST(dem.sim, quarry_get_surface_loads(dem.sim, dem.surface, &loads));
  mean_force.resize(nodes);
  for (std::size_t k = 0; k < nodes; ++k) mean_force[k] = {force[3 * k], force[3 * k + 1], force[3 * k + 2]};
  return loads.window;
}

quarry_partner::Sync record(double time, const std::vector<quarry::fem::NodalLoad>& loads) {
  quarry_partner::Sync s;
  s.time = time;
  Vec3 sum;  // N
  std::uint64_t hash = quarry_partner::kFnvOffset;
  for (const quarry::fem::NodalLoad& l : loads) {
    sum += l.force;
    hash = quarry_partner::fnv1a(hash, &l, sizeof l);
  }
  s.load = {sum.x, sum.y, sum.z};
  s.loads_hash = hash;
  return s;
}

int run(const Options& o) {
  // The structure, from the model file as `quarry run` reads a structures: entry.
  quarry::fsi::CoupledStructure structure;
  try {
    structure = quarry::fsi::read_coupled_structure(o.model);
  } catch (const quarry::UserError& e) {
    fail("cannot use the model:\n" + e.diagnostics().format());
  } catch (const std::exception& e) {
    fail(std::string("cannot use the model ") + o.model + ": " + e.what());
  }
  // PERIOD and FILTER as a deck's structures: entry resolves them: an option replaces the
  // card's value (a PERIOD of our own drops the card's FILTER, which went with its PERIOD).
  std::optional<double> period = structure.period, filter = structure.filter;
  if (o.period) period = o.period, filter.reset();
  if (o.filter) filter = o.filter;
  quarry::fsi::ScheduleSettings schedule;
  try {
    schedule = quarry::fsi::resolve_schedule(period, filter, *o.end_time);
  } catch (const std::invalid_argument& e) {
    usage_error(e.what());
  }
  quarry::fem::ShellSolverOptions solver_options;
  solver_options.mass_scaling_time_step = o.mass_scaling_step;
  solver_options.damping = o.damping;
  quarry::fem::ShellSolver solver(structure.adapted.model, solver_options);
  const quarry::fsi::CouplingMesh& mesh = structure.mesh;

  // The DEM, through the ABI only.
  if ((quarry_abi_version() >> 16) != QUARRY_ABI_MAJOR)
    fail("libquarry's ABI major " + std::to_string(quarry_abi_version() >> 16) + " is not this program's " +
         std::to_string(QUARRY_ABI_MAJOR));
  Dem dem;
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.deck_path = o.deck.c_str();
  info.endpoint = o.endpoint ? o.endpoint->c_str() : nullptr;
  info.threads = o.threads;
  info.timeout_ms = o.timeout_ms;
  MUST(QUARRY_NO_SIM, quarry_open(&info, &dem.sim));
  std::vector<std::uint32_t> triangles, quads;
  for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
  for (const auto& q : mesh.quads) quads.insert(quads.end(), q.begin(), q.end());
  const std::vector<double> vertices = flat(mesh.vertices);
  quarry_surface_desc desc{};
  desc.struct_size = sizeof desc;
  // The DEM surface is named by the card's COUPLING label (several coupled as one: joined).
  std::string name = structure.labels.front();
  for (std::size_t k = 1; k < structure.labels.size(); ++k) name += "_" + structure.labels[k];
  desc.name = name.c_str();
  desc.material = o.material.c_str();
  desc.node_count = mesh.vertices.size();
  desc.nodes = vertices.data();
  desc.triangle_count = mesh.triangles.size();
  desc.triangles = triangles.data();
  desc.quad_count = mesh.quads.size();
  desc.quads = quads.data();
  desc.driver = QUARRY_DRIVER_COUPLED;
  MUST(dem.sim, quarry_add_surface(dem.sim, &desc, &dem.surface));
  dem.refresh_time();

  // 0. The sync at the start: the surface where the structure is; the first read of the loads
  // starts the DEM's window (empty: nothing has acted yet).
  quarry::fsi::StructureSide side(solver, mesh.node_of_vertex, o.step_fraction, schedule);
  send_nodes(dem, side);
  std::vector<Vec3> mean_force;
  if (take_loads(dem, mesh.vertices.size(), mean_force) != 0.0)
    fail("the coupling surface's load window was not empty at the start");
  side.begin_period(dem.dt);

  quarry_partner::CouplingReport report;
  double impulse_z = 0.0;  // N·s, Σ of the DEM's nodal forces × window, z
  const double end = *o.end_time;
  while (dem.time < end - 1e-6 * dem.dt) {
    // 1. The structure to its sync point.
    side.finish_period(dem.dt);
    // 2. The DEM to its sync point: its first step at or after the request. All but the last
    // two steps in one call (they cannot reach it: steps_to_sync counts to it), then one at a
    // time, checked as the built-in coupler checks after each step.
    const std::int64_t steps = side.schedule().steps_to_sync(dem.time, dem.dt);
    if (steps > 2) MUST(dem.sim, quarry_step(dem.sim, static_cast<std::uint64_t>(steps - 2)));
    dem.refresh_time();
    do {
      MUST(dem.sim, quarry_step(dem.sim, 1));
      dem.refresh_time();
    } while (!side.schedule().reached(dem.time, dem.dt));
    // 3. The exchange.
    const double window = take_loads(dem, mesh.vertices.size(), mean_force);
    for (const Vec3& f : mean_force) impulse_z += f.z * window;
    side.receive(mean_force, window);
    send_nodes(dem, side);
    side.synchronised();
    side.begin_period(dem.dt);
    report.history.push_back(record(dem.time, side.loads()));
  }
  for (const std::string& line : side.messages()) std::printf("coupling: %s\n", line.c_str());

  // The final state: the structure's nodes, the particles by id.
  double largest = 0.0;  // m
  for (int n = 0; n < solver.node_count(); ++n) {
    const auto k = static_cast<std::size_t>(n);
    const Vec3 x = solver.positions()[k], v = solver.velocities()[k];
    const Vec3 u = x - structure.adapted.model.nodes[k];
    largest = std::max(largest, std::sqrt(dot(u, u)));
    report.node_position.push_back({x.x, x.y, x.z});
    report.node_velocity.push_back({v.x, v.y, v.z});
  }
  report.structure_steps = side.structure_steps();
  std::uint64_t count = 0;
  MUST(dem.sim, quarry_num_particles(dem.sim, -1, &count));
  std::vector<std::uint64_t> ids(count);
  std::vector<double> position(3 * count), velocity(3 * count);
  quarry_particle_data data{};
  data.struct_size = sizeof data;
  data.capacity = count;
  data.id = ids.data();
  data.position = position.data();
  data.velocity = velocity.data();
  MUST(dem.sim, quarry_get_particles(dem.sim, &data));
  for (std::uint64_t k = 0; k < data.count; ++k)
    report.particles.push_back({ids[k],
                                {position[3 * k], position[3 * k + 1], position[3 * k + 2]},
                                {velocity[3 * k], velocity[3 * k + 1], velocity[3 * k + 2]}});
  std::printf("shell_partner: t %.6g s, %zu syncs (PERIOD %.6g s, FILTER %.6g s), %lld structure steps of %.4g s; "
              "largest displacement %.4e m; impulse of the particles on the plate (z) %.6e N s; %llu particles%s\n",
              dem.time, report.history.size(), side.schedule().period(), side.schedule().filter(),
              static_cast<long long>(side.structure_steps()), side.structure_step(), largest, impulse_z,
              static_cast<unsigned long long>(data.count), o.endpoint ? " (DEM in quarry serve)" : " (DEM in process)");
  MUST(dem.sim, quarry_close(dem.sim));
  if (!o.report.empty() && !quarry_partner::write_report(o.report, std::move(report)))
    fail("cannot write the report " + o.report);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  try {
    return run(options);
  } catch (const std::exception& e) {
    fail(std::string("internal error: ") + e.what());
  }
}
