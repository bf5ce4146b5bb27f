// coupling_exchange (issue 16 §6): the cost of one coupling exchange — positions and velocities
// out, external forces in — as a share of one engine step, on the settled-bed lattice at 100k and
// 1M particles (bench/settled_bed_scene.h), through the C ABI: in process with zero-copy views
// and with copies, and through `quarry serve` over ipc:// (arrays in shared memory; copies, and
// views the server writes into segments of their own) and over tcp://127.0.0.1. Medians of interleaved repetitions, printed as a table. Not a test.
#include <fcntl.h>
#include <fmt/chrono.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "bench/settled_bed_scene.h"
#include "quarry/quarry.h"
#include "sim/run.h"

namespace {

namespace fs = std::filesystem;
namespace bench = quarry::bench;
using Clock = std::chrono::steady_clock;

struct Options {
  std::vector<long> sizes{100000, 1000000};
  int repetitions = 9;
  int threads = 1;
  bool tcp = true;  // also through tcp (at 1M it moves some 150 MB of fresh pages a repetition)
  bool remote_steps = true;  // a remote handle steps before its exchange too (as in a coupled run)
  std::string quarry = QUARRY_BIN;
};

void check(quarry_sim sim, quarry_status status, const char* what) {
  if (status == QUARRY_OK) return;
  char text[2048];
  quarry_last_error(sim, text, sizeof text, nullptr);
  throw std::runtime_error(fmt::format("{}: {}: {}", what, quarry_status_name(status), text));
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `quarry serve` for the benchmark: stopped (SIGTERM, then SIGKILL) when it goes, and killed by
// the kernel if the benchmark dies first.
class ServeProcess {
 public:
  ServeProcess(const std::string& quarry, const std::string& endpoint, int threads,
               const fs::path& log) {
    pid_ = ::fork();
    if (pid_ == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1), ::dup2(fd, 2);
      const std::string thread_count = std::to_string(threads);
      ::execl(quarry.c_str(), quarry.c_str(), "serve", "--endpoint", endpoint.c_str(), "--threads",
              thread_count.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    for (int k = 0; k < 400 && endpoint_.empty(); ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      const std::string text = read_file(log);
      const std::size_t at = text.find("listening on ");
      if (at != std::string::npos)
        endpoint_ = text.substr(at + 13, text.find(' ', at + 13) - at - 13);
    }
    if (endpoint_.empty())
      throw std::runtime_error("quarry serve did not start: " + read_file(log));
  }
  ~ServeProcess() {
    ::kill(pid_, SIGTERM);
    for (int k = 0; k < 100; ++k, std::this_thread::sleep_for(std::chrono::milliseconds(20)))
      if (::waitpid(pid_, nullptr, WNOHANG) == pid_) return;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  const std::string& endpoint() const { return endpoint_; }

 private:
  pid_t pid_ = -1;
  std::string endpoint_;
};

// A packed lattice of about n particles (a square base, the height to match): spacing 1.98 mm
// for spheres of 2 mm, so that every particle presses on its six neighbours (overlap 1 % of the
// diameter, jitter ±2 µm) and a step costs what it costs in a settled bed, contacts included.
bench::SettledBedParameters bed_of(long n) {
  bench::SettledBedParameters bed;
  bed.lattice_spacing = 1.98e-3;  // m
  bed.jitter = 2e-6;              // m
  const int side = static_cast<int>(std::lround(std::cbrt(static_cast<double>(n))));
  bed.cells_x = bed.cells_y = side;
  bed.cells_z = static_cast<int>(std::lround(static_cast<double>(n) / (side * side)));
  return bed;
}

// The bed, started (lists built, forces computed), as a checkpoint file both sides can open.
fs::path write_bed(long n, const fs::path& directory) {
  quarry::World world = bench::make_lattice_world(bed_of(n));
  bench::prepare_first_step(world);
  const fs::path path = directory / fmt::format("bed_{}.qck", world.particles.size());
  quarry::sim::write_checkpoint(world, path.string(), 0);
  return path;
}

quarry_sim open(const fs::path& checkpoint, const char* endpoint, int threads) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.checkpoint_path = checkpoint.c_str();
  info.endpoint = endpoint;
  info.threads = threads;
  info.timeout_ms = 600000;  // 1M particles through tcp take a while; slowness is measured here
  quarry_sim sim;
  check(QUARRY_NO_SIM, quarry_open(&info, &sim), "quarry_open");
  return sim;
}

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size() / 2;
  return values.size() % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

// The partner's side: where positions and velocities go, the forces it sets.
struct Partner {
  explicit Partner(std::uint64_t n) : position(3 * n), velocity(3 * n), force(3 * n) {
    for (std::uint64_t k = 0; k < 3 * n; ++k) force[k] = 1e-9 * static_cast<double>(k % 7);  // N
  }
  std::vector<double> position, velocity, force;  // m, m/s, N
};

struct Timing {
  std::vector<double> get, set;  // s
  std::vector<double> write;     // s: the partner's forces written into the load view
  std::vector<double> step;      // s: the in-process step before each exchange of this path
};

// The exchange's second half, the forces copied in, and the times of both halves (the first
// from start to got).
void set_forces(quarry_sim sim, const Partner& partner, std::uint64_t n, Clock::time_point start,
                Clock::time_point got, Timing& timing) {
  check(sim,
        quarry_set_external_loads(sim, partner.force.data(), nullptr, n, QUARRY_LOAD_REPLACE,
                                  QUARRY_HOLD_NEXT_STEP),
        "quarry_set_external_loads");
  timing.get.push_back(std::chrono::duration<double>(got - start).count());
  timing.set.push_back(since(got));
}

// Positions and velocities as copies (quarry_get_particles), then the forces.
void exchange_by_copies(quarry_sim sim, Partner& partner, std::uint64_t n, Timing& timing) {
  quarry_particle_data data = {sizeof data,
                               n,
                               nullptr,
                               nullptr,
                               partner.position.data(),
                               partner.velocity.data(),
                               nullptr,
                               nullptr,
                               nullptr,
                               nullptr,
                               nullptr,
                               nullptr,
                               0,
                               0};
  const auto start = Clock::now();
  check(sim, quarry_get_particles(sim, &data), "quarry_get_particles");
  const auto got = Clock::now();
  set_forces(sim, partner, n, start, got, timing);
}

// Positions and velocities as views of the engine's arrays, then the forces.
void exchange_by_views(quarry_sim sim, Partner& partner, std::uint64_t n, Timing& timing) {
  quarry_view position, velocity;
  const auto start = Clock::now();
  check(sim, quarry_view_particles(sim, QUARRY_FIELD_POSITION, &position), "quarry_view_particles");
  check(sim, quarry_view_particles(sim, QUARRY_FIELD_VELOCITY, &velocity), "quarry_view_particles");
  const auto got = Clock::now();
  if (position.count != n || velocity.count != n)
    throw std::runtime_error("a view of the wrong length");
  set_forces(sim, partner, n, start, got, timing);
}

// Positions and velocities as views, and the forces written in place through the writable view
// of the next step's loads (ABI 1.2). The ABI's part is the three view calls; the writing is the
// partner's own work (it computes its forces there instead of into an array of its own), timed
// apart: here a linear drag from the velocity view. The step that follows adds the loads in its
// kicks and zeroes them: that share is in the step's time (the "all in" column).
// On a remote handle (`flush`) the view is the handle's copy, sent to the server before the next
// call: a call without arrays sends it within the exchange's time.
void exchange_in_place(quarry_sim sim, std::uint64_t n, bool flush, Timing& timing) {
  quarry_view position, velocity, loads;
  const auto start = Clock::now();
  check(sim, quarry_view_particles(sim, QUARRY_FIELD_POSITION, &position), "quarry_view_particles");
  check(sim, quarry_view_particles(sim, QUARRY_FIELD_VELOCITY, &velocity), "quarry_view_particles");
  const auto got = Clock::now();
  check(sim, quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, &loads),
        "quarry_view_next_step_loads");
  const auto viewed = Clock::now();
  if (position.count != n || velocity.count != n || loads.count != n ||
      loads.stride != 3 * sizeof(double))
    throw std::runtime_error("a view of the wrong length");
  // A drag law's worth of work: F = −c v from the velocity view, written in place.
  const auto* v = static_cast<const double*>(velocity.data);
  auto* f = static_cast<double*>(loads.data);
  for (std::uint64_t k = 0; k < 3 * n; ++k) f[k] = -1e-6 * v[k];  // N, c = 1e-6 kg/s
  timing.write.push_back(since(viewed));
  if (flush) {
    const auto written = Clock::now();
    std::uint64_t epoch = 0;
    check(sim, quarry_epoch(sim, &epoch), "quarry_epoch");
    timing.get.push_back(std::chrono::duration<double>(got - start).count());
    timing.set.push_back(std::chrono::duration<double>(viewed - got).count() + since(written));
    return;
  }
  timing.get.push_back(std::chrono::duration<double>(got - start).count());
  timing.set.push_back(std::chrono::duration<double>(viewed - got).count());
}

// One way to do the exchange, and its times.
struct Path {
  std::string name;
  quarry_sim sim;
  bool views = false;  // views for the particle data, else copies
  Timing timing;
  // Measured in a block of its own after the interleaved ones: each tcp exchange of 1M particles
  // has the kernel map and zero ~150 MB of fresh pages in both processes (ZeroMQ allocates every
  // message), which slowed the steps and the ipc exchanges measured after it (by some 30 % and
  // threefold).
  bool apart = false;
  bool in_place = false;  // the forces written through the load view (in process only)
  bool none = false;      // no exchange: the steps after it are the baseline (no external loads)
  bool remote = false;    // a handle of quarry serve
};

void exchange(Path& path, Partner& partner, std::uint64_t n, Timing& timing) {
  if (path.none) {
    timing.get.push_back(0.0), timing.set.push_back(0.0);
  } else if (path.in_place)
    exchange_in_place(path.sim, n, path.remote, timing);
  else if (path.views)
    exchange_by_views(path.sim, partner, n, timing);
  else
    exchange_by_copies(path.sim, partner, n, timing);
}

void run_size(long wanted, const Options& options, const fs::path& directory,
              const ServeProcess& ipc, const ServeProcess* tcp) {
  std::cerr << fmt::format("coupling_exchange: building the lattice of about {} particles\n",
                           wanted);
  const fs::path bed = write_bed(wanted, directory);
  const quarry_sim local = open(bed, nullptr, options.threads);
  const quarry_sim remote = open(bed, ipc.endpoint().c_str(), options.threads);
  std::vector<Path> paths = {{"in process, views", local, true, {}},
                             {"in process, copies", local, false, {}},
                             {"in process, views, forces in place", local, true, {}, false, true},
                             {"in process, no exchange", local, true, {}, false, false, true},
                             {"quarry serve, ipc + shared memory", remote, false, {}},
                             {"quarry serve, ipc, views", remote, true, {}},
                             // (name, handle, views, timing, apart, in_place, none, remote)
                             {"quarry serve, ipc, views, forces in place", remote, true, {}, false,
                              true, false, true}};
  if (tcp)
    paths.push_back({"quarry serve, tcp 127.0.0.1",
                     open(bed, tcp->endpoint().c_str(), options.threads),
                     false,
                     {},
                     true});
  fs::remove(bed);
  std::uint64_t n = 0;
  check(local, quarry_num_particles(local, -1, &n), "quarry_num_particles");
  // Every handle gives the same particles (before any step); then a warm-up of each path (first
  // touches of the segment and of the copies) and the interleaved repetitions.
  Partner partner(n), other(n);
  Timing unused;
  exchange_by_copies(local, partner, n, unused);
  for (std::size_t k = 2; k < paths.size(); ++k) {
    if (paths[k].sim.id == local.id) continue;
    if (paths[k].views) {  // one particle type: engine order is type order
      quarry_view position;
      check(paths[k].sim, quarry_view_particles(paths[k].sim, QUARRY_FIELD_POSITION, &position),
            "quarry_view_particles");
      if (position.count != n ||
          std::memcmp(position.data, partner.position.data(), 3 * n * sizeof(double)) != 0)
        throw std::runtime_error(paths[k].name + ": the view differs from the in-process copy");
      continue;
    }
    exchange_by_copies(paths[k].sim, other, n, unused);
    if (other.position != partner.position || other.velocity != partner.velocity)
      throw std::runtime_error(paths[k].name + ": the copy differs from the in-process one");
  }
  for (Path& path : paths) exchange(path, partner, n, unused);
  // Each exchange follows a step of its own handle, as in a coupled run (step, then exchange):
  // the engine's arrays are then where a step leaves them, in the caches of the core that ran it
  // (the server's core for a remote handle), and the client has waited out the server's step.
  // The in-process steps give the step's time. --no-remote-steps: the server never steps (the
  // method of the results before 2026-12-04).
  // An in-process exchange is followed by a second step, timed for that path (what the loads it
  // set add to the step: the "next step" column), before any other path runs: the steps of the
  // server's handles in between (and what their process does after them) slowed the next local
  // step by up to 10 % in some runs, which must not fall on one path's steps only.
  Timing step;
  const auto timed_step = [&](quarry_sim sim, std::vector<double>& into) {
    const auto start = Clock::now();
    check(sim, quarry_step(sim, 1), "quarry_step");
    into.push_back(since(start));
  };
  const auto step_then_exchange = [&](Path& path) {
    const bool in_process = path.sim.id == local.id;
    std::vector<double> unused_times;
    if (in_process || options.remote_steps) timed_step(path.sim, in_process ? step.get : unused_times);
    exchange(path, partner, n, path.timing);
    if (in_process) timed_step(path.sim, path.timing.step);
  };
  std::vector<std::function<void()>> measurements;
  for (Path& path : paths)
    if (!path.apart) measurements.push_back([&] { step_then_exchange(path); });
  for (int r = 0; r < options.repetitions; ++r)
    for (std::size_t k = 0; k < measurements.size(); ++k)
      measurements[(k + r) % measurements.size()]();
  for (Path& path : paths)
    for (int r = 0; r < options.repetitions && path.apart; ++r) step_then_exchange(path);
  // The fixed cost of a call through the server: one without arrays (quarry_epoch).
  // (Once per server: the views path shares the ipc handle of the copies path.)
  const auto first_of_its_handle = [&](std::size_t k) {
    for (std::size_t j = 0; j < k; ++j)
      if (paths[j].sim.id == paths[k].sim.id) return false;
    return true;
  };
  std::vector<std::vector<double>> round_trips(paths.size());
  for (int r = 0; r < 5 * options.repetitions; ++r)
    for (std::size_t k = 2; k < paths.size(); ++k) {
      if (!first_of_its_handle(k)) continue;
      std::uint64_t epoch = 0;
      const auto start = Clock::now();
      check(paths[k].sim, quarry_epoch(paths[k].sim, &epoch), "quarry_epoch");
      round_trips[k].push_back(since(start));
    }
  for (std::size_t k = 0; k < paths.size(); ++k)
    if (first_of_its_handle(k)) check(paths[k].sim, quarry_close(paths[k].sim), "quarry_close");

  const double step_time = median(step.get);
  const Timing& copies = paths[1].timing;
  const double copy_time = median(copies.get) + median(copies.set);
  std::cout << fmt::format(
      "\n{} particles, {} thread(s): one engine step {:.2f} ms (median of {})\n", n,
      options.threads, 1e3 * step_time, options.repetitions);
  // In process the loads also cost the next step something (both kicks read them, the end of
  // the step zeroes them): "all in" is the exchange plus the median, over the repetitions, of
  // the next step's time less the baseline's (the step after no exchange) in the same
  // repetition. Paired so: the host's speed drifts by more than 1 % within a run.
  const std::vector<double>* baseline_steps = nullptr;
  for (const Path& path : paths)
    if (path.none) baseline_steps = &path.timing.step;
  const double baseline = median(*baseline_steps);  // s
  std::cout << fmt::format(
      "| {:<41} | {:>9} | {:>9} | {:>13} | {:>10} | {:>11} | {:>15} | {:>12} | {:>10} |\n", "path",
      "get (ms)", "set (ms)", "exchange (ms)", "% of step", "× copies", "next step (ms)",
      "all in (ms)", "% of step");
  std::cout << fmt::format("|{:-<43}|{:->11}|{:->11}|{:->15}|{:->12}|{:->13}|{:->17}|{:->14}|{:->12}|\n",
                           "", ":", ":", ":", ":", ":", ":", ":", ":");
  for (const Path& path : paths) {
    const double get = median(path.timing.get), set = median(path.timing.set);
    std::string next, all_in, all_in_share;
    if (!path.timing.step.empty()) {
      std::vector<double> extra;  // s, per repetition
      for (std::size_t r = 0; r < path.timing.step.size(); ++r)
        extra.push_back(path.timing.step[r] - (*baseline_steps)[r]);
      const double after = median(path.timing.step), total = get + set + median(extra);
      next = fmt::format("{:.3f}", 1e3 * after);
      all_in = fmt::format("{:.3f}", 1e3 * total);
      all_in_share = fmt::format("{:.2f}", 100.0 * total / baseline);
    }
    std::cout << fmt::format(
        "| {:<41} | {:>9.3f} | {:>9.3f} | {:>13.3f} | {:>10.2f} | {:>11.2f} | {:>15} | {:>12} | {:>10} |\n",
        path.name, 1e3 * get, 1e3 * set, 1e3 * (get + set), 100.0 * (get + set) / step_time,
        (get + set) / copy_time, next, all_in, all_in_share);
  }
  for (const Path& path : paths)
    if (path.in_place)
      std::cout << fmt::format(
          "{}: the partner's computing its forces into the view (a linear drag from the velocity "
          "view; not counted above) {:.3f} ms\n",
          path.name, 1e3 * median(path.timing.write));
  for (std::size_t k = 2; k < paths.size(); ++k)
    if (first_of_its_handle(k))
      std::cout << fmt::format("a call without arrays (quarry_epoch), {}: {:.3f} ms (median of {})\n",
                             paths[k].name, 1e3 * median(round_trips[k]), round_trips[k].size());
  std::cout << std::flush;
}

// The 1-minute load average (other processes share the machine: it says how quiet it was).
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one;
  in >> one;
  return one.empty() ? "unknown" : one;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"the cost of one coupling exchange as a share of an engine step (issue 16 §6)"};
  app.add_option("--sizes", options.sizes, "particle counts (about: a lattice is made to fit)")
      ->delimiter(',');
  app.add_option("--repetitions", options.repetitions,
                 "interleaved repetitions of each measurement");
  app.add_option("--threads", options.threads, "OpenMP threads of the simulations");
  app.add_option("--quarry", options.quarry, "the quarry executable that serves");
  app.add_flag("!--no-tcp", options.tcp, "leave out the exchange through tcp");
  app.add_flag("!--no-remote-steps", options.remote_steps,
               "the server's simulation does not step before its exchanges");
  CLI11_PARSE(app, argc, argv);
  const fs::path directory =
      fs::temp_directory_path() / fmt::format("quarry-coupling-exchange-{}", ::getpid());
  fs::create_directories(directory);
  int code = 0;
  try {
    const std::time_t now = std::time(nullptr);
    std::cout << fmt::format(
        "coupling exchange: positions and velocities out, forces in; CPU {}, {} hardware "
        "threads; {:%Y-%m-%d}; median of {} interleaved repetitions\n",
        cpu_model(), std::thread::hardware_concurrency(), fmt::localtime(now), options.repetitions);
    const ServeProcess ipc(options.quarry, "ipc://" + (directory / "serve.ipc").string(),
                           options.threads, directory / "serve_ipc.log");
    std::optional<ServeProcess> tcp;
    if (options.tcp)
      tcp.emplace(options.quarry, "tcp://127.0.0.1:0", options.threads,
                  directory / "serve_tcp.log");
    for (const long n : options.sizes) {
      run_size(n, options, directory, ipc, tcp ? &*tcp : nullptr);
      std::cout << fmt::format("load average (1 min) after it: {}\n", load_average());
    }
  } catch (const std::exception& e) {
    std::cerr << "coupling_exchange: " << e.what() << "\n";
    code = 1;
  }
  fs::remove_all(directory);
  return code;
}
