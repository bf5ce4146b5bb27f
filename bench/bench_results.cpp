// Peer-comparison results: CSV parsing, medians per group, markdown summary, throughput plot.
#include "bench/bench_results.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace quarry::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<std::string> kColumns = {
    "date", "machine", "size", "n", "code", "threads", "rep", "steps", "loop_s", "pss",
    "coordination", "neigh_pp", "rebuilds", "rss_kib", "zmax", "zmean", "floor_force", "weight",
    "other_load"};

int code_rank(const std::string& code) {
  static const std::vector<std::string> order = {"quarry", "liggghts", "lmp_granular", "lmp_ghh"};
  const auto it = std::find(order.begin(), order.end(), code);
  return static_cast<int>(it - order.begin());
}

std::string code_label(const std::string& code) {
  if (code == "quarry") return "Quarry";
  if (code == "liggghts") return "LIGGGHTS 3.8.0";
  if (code == "lmp_granular") return "LAMMPS granular";
  if (code == "lmp_ghh") return "LAMMPS gran/hertz/history";
  return code;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.emplace_back();
  return fields;
}

double to_number(const std::string& text, std::size_t line) {
  if (text.empty() || text == "nan" || text == "NA") return kNaN;
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size())
    throw std::runtime_error(fmt::format("results CSV line {}: \"{}\" is not a number", line, text));
  return value;
}

std::string millions(double rate) { return std::isfinite(rate) ? fmt::format("{:.2f}", rate / 1e6) : "n/a"; }
std::string fixed(double value, int decimals) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : "n/a";
}
std::string percent(double fraction) {
  return std::isfinite(fraction) ? fmt::format("{:+.2f} %", 100.0 * fraction) : "n/a";
}

}  // namespace

std::string bench_csv_header() {
  std::string header;
  for (const auto& c : kColumns) header += (header.empty() ? "" : ",") + c;
  return header;
}

std::vector<BenchRun> read_bench_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) return {};
  const std::vector<std::string> header = split(line, ',');
  std::map<std::string, std::size_t> column;
  for (std::size_t k = 0; k < header.size(); ++k) column[header[k]] = k;
  for (const auto& c : kColumns)
    if (!column.count(c)) throw std::runtime_error(fmt::format("results CSV: no column \"{}\"", c));
  std::vector<BenchRun> runs;
  std::size_t line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> f = split(line, ',');
    if (f.size() != header.size())
      throw std::runtime_error(fmt::format("results CSV line {}: {} fields, the header has {}", line_number,
                                           f.size(), header.size()));
    const auto number = [&](const char* name) { return to_number(f[column.at(name)], line_number); };
    BenchRun r;
    r.date = f[column.at("date")];
    r.machine = f[column.at("machine")];
    r.size = f[column.at("size")];
    r.code = f[column.at("code")];
    r.threads = static_cast<int>(number("threads"));
    r.repeat = static_cast<int>(number("rep"));
    r.particles = number("n");
    r.steps = number("steps");
    r.loop_seconds = number("loop_s");
    r.particle_steps_per_second = number("pss");
    r.coordination = number("coordination");
    r.neighbor_pairs_per_particle = number("neigh_pp");
    r.rebuilds = number("rebuilds");
    r.peak_rss_kib = number("rss_kib");
    r.max_height = number("zmax");
    r.mean_height = number("zmean");
    r.floor_force = number("floor_force");
    r.weight = number("weight");
    r.other_load = number("other_load");
    runs.push_back(r);
  }
  return runs;
}

double median_of(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
               values.end());
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size() / 2;
  return values.size() % 2 == 1 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

double relative_difference(double a, double b) { return (a - b) / std::abs(b); }

std::vector<BenchGroup> summarize_runs(const std::vector<BenchRun>& runs) {
  std::map<std::tuple<double, int, int>, std::vector<const BenchRun*>> by_key;
  for (const auto& r : runs) by_key[{r.particles, code_rank(r.code), r.threads}].push_back(&r);
  std::vector<BenchGroup> groups;
  for (const auto& [key, members] : by_key) {
    BenchGroup g;
    g.size = members.front()->size;
    g.code = members.front()->code;
    g.threads = members.front()->threads;
    g.particles = members.front()->particles;
    g.runs = static_cast<int>(members.size());
    const auto collect = [&](double BenchRun::*field) {
      std::vector<double> v;
      for (const BenchRun* r : members) v.push_back(r->*field);
      return v;
    };
    const std::vector<double> rates = collect(&BenchRun::particle_steps_per_second);
    g.median_rate = median_of(rates);
    g.min_rate = *std::min_element(rates.begin(), rates.end());
    g.max_rate = *std::max_element(rates.begin(), rates.end());
    g.coordination = median_of(collect(&BenchRun::coordination));
    g.neighbor_pairs_per_particle = median_of(collect(&BenchRun::neighbor_pairs_per_particle));
    g.rebuilds = median_of(collect(&BenchRun::rebuilds));
    const std::vector<double> rss = collect(&BenchRun::peak_rss_kib);
    g.peak_rss_kib = *std::max_element(rss.begin(), rss.end());
    g.max_height = median_of(collect(&BenchRun::max_height));
    g.mean_height = median_of(collect(&BenchRun::mean_height));
    g.floor_force = median_of(collect(&BenchRun::floor_force));
    g.weight = median_of(collect(&BenchRun::weight));
    double load = 0;
    for (const BenchRun* r : members) load += std::isfinite(r->other_load) ? r->other_load : 0.0;
    g.other_load = load / static_cast<double>(members.size());
    groups.push_back(g);
  }
  return groups;
}

std::string bench_markdown(const std::vector<BenchRun>& runs, const std::string& heading, double tolerance) {
  const std::vector<BenchGroup> groups = summarize_runs(runs);
  const auto find = [&](double n, const std::string& code, int threads) -> const BenchGroup* {
    for (const auto& g : groups)
      if (g.particles == n && g.code == code && g.threads == threads) return &g;
    return nullptr;
  };
  std::string md = heading + "\n\n";
  md += "Throughput = N × timed steps / wall time of the timed steps (setup, settling and warm-up "
        "excluded), million particle-steps per second, median over the repeats. Threads = OpenMP "
        "threads (Quarry) or MPI ranks (LIGGGHTS, LAMMPS). Other load = CPU used by other processes "
        "during the run (cores, mean).\n\n";
  md += "| N | code | threads | runs | median | min .. max | ns per particle-step × threads | "
        "coordination (2·contacts/N) | neighbour pairs / N | list builds | peak RSS MiB | other load |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& g : groups)
    md += fmt::format("| {:.0f} | {} | {} | {} | {} | {} .. {} | {:.0f} | {} | {} | {} | {:.0f} | {:.2f} |\n",
                      g.particles, code_label(g.code), g.threads, g.runs, millions(g.median_rate),
                      millions(g.min_rate), millions(g.max_rate), g.threads * 1e9 / g.median_rate,
                      fixed(g.coordination, 2), fixed(g.neighbor_pairs_per_particle, 2), fixed(g.rebuilds, 0),
                      g.peak_rss_kib / 1024.0, g.other_load);

  md += "\n## Quarry / peer (ratio of medians, same run)\n\n| N | threads | peer | Quarry | peer median | Quarry / peer |\n|---|---|---|---|---|---|\n";
  for (const auto& q : groups) {
    if (q.code != "quarry") continue;
    for (const char* peer : {"liggghts", "lmp_granular", "lmp_ghh"}) {
      const BenchGroup* p = find(q.particles, peer, q.threads);
      if (!p) continue;
      md += fmt::format("| {:.0f} | {} | {} | {} | {} | **{:.2f}** |\n", q.particles, q.threads, code_label(peer),
                        millions(q.median_rate), millions(p->median_rate), q.median_rate / p->median_rate);
    }
  }

  md += "\n## Speed-up of 2 threads/ranks over 1 (medians)\n\n| N | code | 2 / 1 |\n|---|---|---|\n";
  for (const auto& g : groups) {
    if (g.threads != 2) continue;
    if (const BenchGroup* one = find(g.particles, g.code, 1))
      md += fmt::format("| {:.0f} | {} | {:.2f} |\n", g.particles, code_label(g.code), g.median_rate / one->median_rate);
  }

  md += "\n## Memory per particle (single thread/rank, whole-process peak RSS)\n\n"
        "| code | N | peak RSS MiB | bytes/particle (total) | bytes/particle (marginal vs. previous N) |\n"
        "|---|---|---|---|---|\n";
  for (const char* code : {"quarry", "liggghts", "lmp_granular", "lmp_ghh"}) {
    const BenchGroup* previous = nullptr;
    for (const auto& g : groups) {
      if (g.code != code || g.threads != 1) continue;
      const double bytes = g.peak_rss_kib * 1024.0;
      const std::string marginal =
          previous ? fmt::format("{:.0f}", (bytes - previous->peak_rss_kib * 1024.0) / (g.particles - previous->particles))
                   : "-";
      md += fmt::format("| {} | {:.0f} | {:.0f} | {:.0f} | {} |\n", code_label(code), g.particles,
                        g.peak_rss_kib / 1024.0, bytes / g.particles, marginal);
      previous = &g;
    }
  }

  md += fmt::format(
      "\n## Settled bed: Quarry against each peer (after the timed steps, 1 thread/rank, medians)\n\n"
      "Pass = |Quarry − peer| / peer within {:.0f} % for the max and mean height of the particle centres "
      "and the vertical force on the floor. The floor carries less than Σ m g because the side walls "
      "hold part of the weight by friction (Janssen effect), so the floor force depends on the "
      "friction history of the packing, not only on the physics.\n\n"
      "| N | peer | z max Quarry / peer (mm) | Δ | z mean Quarry / peer (mm) | Δ | floor force Quarry / peer (N) | Δ | "
      "floor / Σmg Quarry, peer | coordination Quarry, peer | pass |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
      100.0 * tolerance);
  for (const auto& q : groups) {
    if (q.code != "quarry" || q.threads != 1) continue;
    for (const char* peer : {"liggghts", "lmp_granular", "lmp_ghh"}) {
      const BenchGroup* p = find(q.particles, peer, 1);
      if (!p) continue;
      const double dz = relative_difference(q.max_height, p->max_height);
      const double dm = relative_difference(q.mean_height, p->mean_height);
      const double df = relative_difference(q.floor_force, p->floor_force);
      const bool pass = std::abs(dz) <= tolerance && std::abs(dm) <= tolerance && std::abs(df) <= tolerance;
      md += fmt::format("| {:.0f} | {} | {} / {} | {} | {} / {} | {} | {} / {} | {} | {}, {} | {}, {} | {} |\n",
                        q.particles, code_label(peer), fixed(1e3 * q.max_height, 3), fixed(1e3 * p->max_height, 3),
                        percent(dz), fixed(1e3 * q.mean_height, 3), fixed(1e3 * p->mean_height, 3), percent(dm),
                        fixed(q.floor_force, 4), fixed(p->floor_force, 4), percent(df),
                        fixed(q.floor_force / q.weight, 3), fixed(p->floor_force / p->weight, 3),
                        fixed(q.coordination, 2), fixed(p->coordination, 2),
                        std::isfinite(dz + dm + df) ? (pass ? "yes" : "**no**") : "n/a");
    }
  }
  return md;
}

PlotSpec throughput_plot(const std::vector<BenchGroup>& groups, const std::string& title) {
  PlotSpec plot;
  plot.title = title;
  plot.x_label = "log10 N (particles)";
  plot.y_label = "million particle-steps per second";
  std::map<std::pair<int, int>, PlotSeries> series;  // (code rank, threads) -> points by N
  for (const auto& g : groups) {
    PlotSeries& s = series[{code_rank(g.code), g.threads}];
    s.label = fmt::format("{}, {} {}", code_label(g.code), g.threads,
                          g.code == "quarry" ? (g.threads == 1 ? "thread" : "threads") : (g.threads == 1 ? "rank" : "ranks"));
    s.x.push_back(std::log10(g.particles));
    s.y.push_back(g.median_rate / 1e6);
  }
  for (auto& [key, s] : series) plot.series.push_back(std::move(s));
  return plot;
}

}  // namespace quarry::bench
