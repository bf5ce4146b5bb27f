// quarry_bench_report: turns the peer-comparison CSV written by bench/run.sh into the markdown
// summary (medians, Quarry/peer ratios, memory, settled-bed check) and the throughput PNG.
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "bench/bench_results.h"
#include "io/atomic_file.h"

int main(int argc, char** argv) {
  const std::string usage =
      "usage: quarry_bench_report --header\n"
      "       quarry_bench_report RESULTS.csv SUMMARY.md PLOT.png [HEADING]\n";
  if (argc == 2 && std::string(argv[1]) == "--header") {
    std::cout << quarry::bench::bench_csv_header() << "\n";
    return 0;
  }
  if (argc < 4 || argc > 5) {
    std::cerr << usage;
    return 2;
  }
  try {
    std::ifstream in(argv[1], std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("cannot open {}", argv[1]));
    std::ostringstream text;
    text << in.rdbuf();
    const auto runs = quarry::bench::read_bench_csv(text.str());
    if (runs.empty()) throw std::runtime_error(fmt::format("{} holds no runs", argv[1]));
    const std::string heading = argc == 5 ? argv[4] : "# Quarry vs. LIGGGHTS and LAMMPS: settled bed";
    quarry::write_file_atomically(argv[2], quarry::bench::bench_markdown(runs, heading));
    quarry::write_line_plot_png(argv[3], quarry::bench::throughput_plot(quarry::bench::summarize_runs(runs),
                                "Settled bed, Hertz-Mindlin with history: throughput against N"));
    std::cerr << fmt::format("wrote {} and {} ({} runs)\n", argv[2], argv[3], runs.size());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "quarry_bench_report: " << e.what() << "\n";
    return 1;
  }
}
