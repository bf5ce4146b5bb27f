// Micro-benchmarks of the neighbour search (time-step stage 2): pair-list build, the rebuild
// check and the spatial sort, on a jittered lattice bed (~3 pairs per particle, like a settled
// bed). Items processed = particles, so the rate reads as particles per second.
#include <benchmark/benchmark.h>

#include "neighbor/pair_list.h"
#include "neighbor/spatial_sort.h"
#include "neighbor/test_scenes.h"

namespace quarry {
namespace {

constexpr double kSkin = 0.2e-3;  // m, 10 % of the mean diameter

void build_pair_list_on_lattice_bed(benchmark::State& state) {
  ParticleStore bed = test_scenes::lattice_bed(static_cast<std::size_t>(state.range(0)), 1);
  bed.permute(spatial_order(bed, 2.3e-3));
  PairList list;
  build_pair_list(bed, kSkin, list);  // warm the buffers, as in a running simulation
  for (auto _ : state) {
    build_pair_list(bed, kSkin, list);
    benchmark::DoNotOptimize(list.partner.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["pairs_per_particle"] =
      static_cast<double>(list.size()) / static_cast<double>(bed.size());
}
BENCHMARK(build_pair_list_on_lattice_bed)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

void pair_list_needs_rebuild_on_lattice_bed(benchmark::State& state) {
  const ParticleStore bed = test_scenes::lattice_bed(static_cast<std::size_t>(state.range(0)), 1);
  PairList list;
  build_pair_list(bed, kSkin, list);
  for (auto _ : state) benchmark::DoNotOptimize(pair_list_needs_rebuild(bed, list));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(pair_list_needs_rebuild_on_lattice_bed)->Arg(100000)->Unit(benchmark::kMicrosecond);

void spatial_order_on_lattice_bed(benchmark::State& state) {
  const ParticleStore bed = test_scenes::lattice_bed(static_cast<std::size_t>(state.range(0)), 1);
  for (auto _ : state) benchmark::DoNotOptimize(spatial_order(bed, 2.3e-3).data());
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(spatial_order_on_lattice_bed)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace quarry
