// Micro-benchmark of the alongside hand-over (core/worker_thread.h): each round hands the
// worker a task of range(0) µs of busy work, does range(1) µs of its own, waits for the task,
// then 50 µs alone (a step's serial hooks). The counter `overhead_us` is the round's time beyond
// max(task, own) + 50 µs: what the two hand-overs cost (a sleeping vCPU's wake-up included).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>

#include "core/worker_thread.h"

namespace quarry {
namespace {

using Clock = std::chrono::steady_clock;

double microseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

void busy_for(double microseconds) {
  const auto start = Clock::now();
  while (microseconds_since(start) < microseconds) {
  }
}

void worker_hand_over(benchmark::State& state) {
  const double task = static_cast<double>(state.range(0));  // µs
  const double own = static_cast<double>(state.range(1));   // µs
  constexpr double kSerial = 50.0;                           // µs
  WorkerThread worker;
  const auto start = Clock::now();
  for (auto _ : state) {
    worker.start([task] { busy_for(task); });
    busy_for(own);
    worker.wait();
    busy_for(kSerial);
  }
  const double elapsed = microseconds_since(start);
  const double rounds = static_cast<double>(state.iterations());
  state.counters["overhead_us"] =
      rounds > 0 ? elapsed / rounds - (std::max(task, own) + kSerial) : 0.0;
}
BENCHMARK(worker_hand_over)
    ->Args({2000, 800})
    ->Args({800, 2000})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace
}  // namespace quarry
