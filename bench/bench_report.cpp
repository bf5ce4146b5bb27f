// quarry_bench_report: turns a peer-comparison CSV written by bench/run.sh (settled bed),
// bench/run_flowing.sh (--pour) or bench/run_scenes.sh (--scene) into the markdown summary (medians, Quarry/peer ratios,
// memory, physics check) and the throughput PNG.
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_results.h"
#include "io/atomic_file.h"

int main(int argc, char** argv) {
  namespace bench = quarry::bench;
  const std::string usage =
      "usage: quarry_bench_report [--pour|--scene] --header\n"
      "       quarry_bench_report [--pour|--scene] RESULTS.csv SUMMARY.md PLOT.png [HEADING]\n";
  std::vector<std::string> args(argv + 1, argv + argc);
  bench::BenchKind kind = bench::BenchKind::settled_bed;
  if (!args.empty() && (args.front() == "--pour" || args.front() == "--scene")) {
    kind = args.front() == "--pour" ? bench::BenchKind::pour : bench::BenchKind::scene;
    args.erase(args.begin());
  }
  if (args.size() == 1 && args[0] == "--header") {
    std::cout << bench::bench_csv_header(kind) << "\n";
    return 0;
  }
  if (args.size() < 3 || args.size() > 4) {
    std::cerr << usage;
    return 2;
  }
  const bool pour = kind == bench::BenchKind::pour;
  const bool scene = kind == bench::BenchKind::scene;
  try {
    std::ifstream in(args[0], std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("cannot open {}", args[0]));
    std::ostringstream text;
    text << in.rdbuf();
    const auto runs = bench::read_bench_csv(text.str());
    if (runs.empty()) throw std::runtime_error(fmt::format("{} holds no runs", args[0]));
    const std::string heading = args.size() == 4 ? args[3]
                                : pour          ? "# Quarry vs. LIGGGHTS and LAMMPS: a pour"
                                : scene         ? "# Quarry vs. LIGGGHTS: a hopper and a drum"
                                                : "# Quarry vs. LIGGGHTS and LAMMPS: settled bed";
    // The scenes' check: a flow's rate within 5 % (the pour's packing height within 1 %).
    quarry::write_file_atomically(args[1], bench::bench_markdown(runs, heading, scene ? 0.05 : 0.01, kind));
    quarry::write_line_plot_png(
        args[2], bench::throughput_plot(bench::summarize_runs(runs),
                                        pour    ? "Pour onto a floor, Hertz-Mindlin with history: throughput"
                                        : scene ? "Hopper and drum, Hertz-Mindlin with history: throughput"
                                             : "Settled bed, Hertz-Mindlin with history: throughput",
                                        kind));
    std::cerr << fmt::format("wrote {} and {} ({} runs)\n", args[1], args[2], runs.size());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "quarry_bench_report: " << e.what() << "\n";
    return 1;
  }
}
