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
// The pour's columns (bench/run_flowing.sh), after the settled bed's.
const std::vector<std::string> kPourColumns = {"skin", "ke_pp", "neigh_share"};
// The scenes' columns (bench/run_scenes.sh), after the pour's.
const std::vector<std::string> kSceneColumns = {"discharge_kg_s", "rising_fraction"};

// Skins compare equal when both are unrecorded (NaN) or the same number.
bool same_skin(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }
double skin_key(double skin) { return std::isnan(skin) ? -1.0 : skin; }

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

std::string bench_csv_header(BenchKind kind) {
  std::string header;
  for (const auto& c : kColumns) header += (header.empty() ? "" : ",") + c;
  if (kind != BenchKind::settled_bed)
    for (const auto& c : kPourColumns) header += "," + c;
  if (kind == BenchKind::scene)
    for (const auto& c : kSceneColumns) header += "," + c;
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
    const auto optional = [&](const char* name) { return column.count(name) ? number(name) : kNaN; };
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
    r.skin = optional("skin");
    r.kinetic_energy = optional("ke_pp");
    r.neighbor_share = optional("neigh_share");
    r.discharge_rate = optional("discharge_kg_s");
    r.rising_fraction = optional("rising_fraction");
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
  std::map<std::tuple<double, int, int, double>, std::vector<const BenchRun*>> by_key;
  for (const auto& r : runs) by_key[{r.particles, code_rank(r.code), r.threads, skin_key(r.skin)}].push_back(&r);
  std::vector<BenchGroup> groups;
  for (const auto& [key, members] : by_key) {
    BenchGroup g;
    g.size = members.front()->size;
    g.code = members.front()->code;
    g.threads = members.front()->threads;
    g.skin = members.front()->skin;
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
    g.kinetic_energy = median_of(collect(&BenchRun::kinetic_energy));
    g.neighbor_share = median_of(collect(&BenchRun::neighbor_share));
    g.discharge_rate = median_of(collect(&BenchRun::discharge_rate));
    g.rising_fraction = median_of(collect(&BenchRun::rising_fraction));
    double load = 0;
    for (const BenchRun* r : members) load += std::isfinite(r->other_load) ? r->other_load : 0.0;
    g.other_load = load / static_cast<double>(members.size());
    groups.push_back(g);
  }
  return groups;
}

namespace {

// The group of `code` at `threads` with the N and skin of `like` (nullptr if none was timed).
const BenchGroup* group_like(const std::vector<BenchGroup>& groups, const BenchGroup& like, const std::string& code,
                             int threads) {
  for (const auto& g : groups)
    if (g.particles == like.particles && g.code == code && g.threads == threads && same_skin(g.skin, like.skin))
      return &g;
  return nullptr;
}

// Each of Quarry's groups with each peer's timed at the same N, skin and thread count (with
// `one_thread`, Quarry's 1-thread groups only).
std::vector<std::pair<const BenchGroup*, const BenchGroup*>> quarry_and_peers(const std::vector<BenchGroup>& groups,
                                                                                bool one_thread) {
  std::vector<std::pair<const BenchGroup*, const BenchGroup*>> pairs;
  for (const auto& q : groups) {
    if (q.code != "quarry" || (one_thread && q.threads != 1)) continue;
    for (const char* peer : {"liggghts", "lmp_granular", "lmp_ghh"})
      if (const BenchGroup* p = group_like(groups, q, peer, q.threads)) pairs.emplace_back(&q, p);
  }
  return pairs;
}

// The pour's physics check: Quarry against each peer at the same skin, 1 thread/rank. The
// mean height of the centres is the pile's packing and must agree within the tolerance; the
// kinetic energy left after the impact, the top of the heap and the floor force are reported
// (they hang on a few particles still moving, and on the friction history at the walls).
std::string pour_check(const std::vector<BenchGroup>& groups, double tolerance) {
  std::string md = fmt::format(
      "\n## Pour: Quarry against each peer (after the timed steps, 1 thread/rank, same skin, medians)\n\n"
      "Pass = |Quarry − peer| / peer within {:.0f} % for the mean height of the particle centres. "
      "The kinetic energy left, the top of the heap and the floor force are shown but not judged: "
      "they hang on the last particles still moving and on the friction history at the walls.\n\n"
      "| N | skin mm | peer | z mean Quarry / peer (mm) | Δ | z max Quarry / peer (mm) | Δ | "
      "kinetic energy per particle Quarry / peer (µJ) | Quarry / peer | floor / Σmg Quarry, peer | "
      "coordination Quarry, peer | pass |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      100.0 * tolerance);
  for (const auto& [qp, p] : quarry_and_peers(groups, true)) {
    const BenchGroup& q = *qp;
    const double dm = relative_difference(q.mean_height, p->mean_height);
    const double dz = relative_difference(q.max_height, p->max_height);
    md += fmt::format("| {:.0f} | {} | {} | {} / {} | {} | {} / {} | {} | {} / {} | {} | {}, {} | {}, {} | {} |\n",
                      q.particles, fixed(1e3 * q.skin, 2), code_label(p->code), fixed(1e3 * q.mean_height, 3),
                      fixed(1e3 * p->mean_height, 3), percent(dm), fixed(1e3 * q.max_height, 2),
                      fixed(1e3 * p->max_height, 2), percent(dz), fixed(1e6 * q.kinetic_energy, 4),
                      fixed(1e6 * p->kinetic_energy, 4), fixed(q.kinetic_energy / p->kinetic_energy, 2),
                      fixed(q.floor_force / q.weight, 3), fixed(p->floor_force / p->weight, 3),
                      fixed(q.coordination, 2), fixed(p->coordination, 2),
                      std::isfinite(dm) ? (std::abs(dm) <= tolerance ? "yes" : "**no**") : "n/a");
  }
  return md;
}

// The scenes' physics check: Quarry against each peer at the same skin and thread count. The
// hopper's discharge rate and the drum's share of mass on its rising side, each a mean over
// the run's second half, must agree within the tolerance; a flow is chaotic, so the peer's own
// 1- against 2-rank difference (the same physics, other round-off) is shown beside as the scale
// of what two runs of one code give. The kinetic energy per particle is shown, not judged.
std::string scene_check(const std::vector<BenchGroup>& groups, double tolerance) {
  std::string md = fmt::format(
      "\n## Scenes: Quarry against each peer (means over the run's second half, medians of the repeats)\n\n"
      "Pass = |Quarry − peer| / peer within {:.0f} % for the hopper's discharge rate or the drum's share of "
      "mass on its rising side (x < 0). \"Peer 2 / 1 ranks\" is the peer's own difference between its 1- and "
      "2-rank runs: a flow is chaotic, and that is what round-off alone moves it by. The kinetic energy per "
      "particle is shown, not judged (the hopper's includes the stream below the outlet, which each code "
      "removes at its own moment).\n\n"
      "| scene | threads | skin mm | peer | quantity | Quarry | peer | Δ | peer 2 / 1 ranks | kinetic energy per "
      "particle Quarry / peer (µJ) | pass |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
      100.0 * tolerance);
  for (const auto& [qp, p] : quarry_and_peers(groups, false)) {
    const BenchGroup& q = *qp;
    const bool hopper = std::isfinite(q.discharge_rate);
    const auto value = [&](const BenchGroup& g) { return hopper ? g.discharge_rate : g.rising_fraction; };
    const double delta = relative_difference(value(q), value(*p));
    const BenchGroup* one = group_like(groups, *p, p->code, 1);
    const BenchGroup* two = group_like(groups, *p, p->code, 2);
    const std::string spread = one && two ? percent(relative_difference(value(*two), value(*one))) : "n/a";
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} |\n", q.size, q.threads,
                      fixed(1e3 * q.skin, 2), code_label(p->code),
                      hopper ? "discharge rate (kg/s)" : "rising side's share of the mass", fixed(value(q), 4),
                      fixed(value(*p), 4), percent(delta), spread, fixed(1e6 * q.kinetic_energy, 3),
                      fixed(1e6 * p->kinetic_energy, 3),
                      std::isfinite(delta) ? (std::abs(delta) <= tolerance ? "yes" : "**no**") : "n/a");
  }
  return md;
}

// Each code's best skin (the highest median throughput over the skins timed) and the ratio of
// Quarry's best to each peer's best, per N and thread count.
std::string best_skins(const std::vector<BenchGroup>& groups) {
  std::map<std::tuple<double, int, int>, const BenchGroup*> best;  // (N, code rank, threads)
  for (const auto& g : groups) {
    const BenchGroup*& b = best[{g.particles, code_rank(g.code), g.threads}];
    if (!b || g.median_rate > b->median_rate) b = &g;
  }
  std::string md =
      "\n## Each code at its best skin (of those timed)\n\n| N | threads | code | best skin mm | median | "
      "Quarry best / this |\n|---|---|---|---|---|---|\n";
  for (const auto& [key, g] : best) {
    const auto q = best.find({std::get<0>(key), code_rank("quarry"), std::get<2>(key)});
    const std::string ratio =
        q == best.end() || g->code == "quarry" ? "-" : fmt::format("**{:.2f}**", q->second->median_rate / g->median_rate);
    md += fmt::format("| {:.0f} | {} | {} | {} | {} | {} |\n", g->particles, g->threads, code_label(g->code),
                      fixed(1e3 * g->skin, 2), millions(g->median_rate), ratio);
  }
  return md;
}

}  // namespace

std::string bench_markdown(const std::vector<BenchRun>& runs, const std::string& heading, double tolerance,
                           BenchKind kind) {
  const std::vector<BenchGroup> groups = summarize_runs(runs);
  const bool pour = kind != BenchKind::settled_bed;  // the flowing benchmarks' tables
  // A scene's row names it beside its N.
  const auto n_label = [&](const BenchGroup& g) {
    return kind == BenchKind::scene ? fmt::format("{} {:.0f}", g.size, g.particles) : fmt::format("{:.0f}", g.particles);
  };
  // The memory table takes one skin per code: the smallest timed (memory hardly depends on it).
  double first_skin = kNaN;
  for (const auto& g : groups)
    if (std::isnan(first_skin) || g.skin < first_skin) first_skin = g.skin;
  std::string md = heading + "\n\n";
  md += pour ? "Throughput = N × timed steps / wall time of the timed steps (setup excluded; the flow is timed "
               "from rest; N: the particles at the start), million particle-steps per second, median over the repeats. Threads = OpenMP "
               "threads (Quarry) or MPI ranks (LIGGGHTS, LAMMPS). Neighbour share = the neighbour stage's "
               "share of the loop by each code's own timers (LIGGGHTS and LAMMPS: \"Neigh\"). Other load = "
               "CPU used by other processes during the run (cores, mean).\n\n"
             : "Throughput = N × timed steps / wall time of the timed steps (setup, settling and warm-up "
               "excluded), million particle-steps per second, median over the repeats. Threads = OpenMP "
               "threads (Quarry) or MPI ranks (LIGGGHTS, LAMMPS). Other load = CPU used by other processes "
               "during the run (cores, mean).\n\n";
  if (pour) {
    md += "| N | code | threads | skin mm | runs | median | min .. max | ns per particle-step × threads | "
          "list builds | neighbour share | coordination (2·contacts/N) | neighbour pairs / N | peak RSS MiB | "
          "other load |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& g : groups)
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} .. {} | {:.0f} | {} | {} | {} | {} | {:.0f} | {:.2f} |\n",
                        n_label(g), code_label(g.code), g.threads, fixed(1e3 * g.skin, 2), g.runs,
                        millions(g.median_rate), millions(g.min_rate), millions(g.max_rate),
                        g.threads * 1e9 / g.median_rate, fixed(g.rebuilds, 0),
                        std::isfinite(g.neighbor_share) ? fmt::format("{:.1f} %", 100.0 * g.neighbor_share) : "n/a",
                        fixed(g.coordination, 2), fixed(g.neighbor_pairs_per_particle, 2), g.peak_rss_kib / 1024.0,
                        g.other_load);
  } else {
    md += "| N | code | threads | runs | median | min .. max | ns per particle-step × threads | "
          "coordination (2·contacts/N) | neighbour pairs / N | list builds | peak RSS MiB | other load |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& g : groups)
      md += fmt::format("| {:.0f} | {} | {} | {} | {} | {} .. {} | {:.0f} | {} | {} | {} | {:.0f} | {:.2f} |\n",
                        g.particles, code_label(g.code), g.threads, g.runs, millions(g.median_rate),
                        millions(g.min_rate), millions(g.max_rate), g.threads * 1e9 / g.median_rate,
                        fixed(g.coordination, 2), fixed(g.neighbor_pairs_per_particle, 2), fixed(g.rebuilds, 0),
                        g.peak_rss_kib / 1024.0, g.other_load);
  }

  md += pour ? "\n## Quarry / peer (ratio of medians, same run, same skin)\n\n| N | threads | skin mm | peer | Quarry | "
               "peer median | Quarry / peer |\n|---|---|---|---|---|---|---|\n"
             : "\n## Quarry / peer (ratio of medians, same run)\n\n| N | threads | peer | Quarry | peer median | "
               "Quarry / peer |\n|---|---|---|---|---|---|\n";
  for (const auto& [q, p] : quarry_and_peers(groups, false))
    md += fmt::format("| {} | {} | {}{} | {} | {} | **{:.2f}** |\n", n_label(*q), q->threads,
                      pour ? fixed(1e3 * q->skin, 2) + " | " : "", code_label(p->code), millions(q->median_rate),
                      millions(p->median_rate), q->median_rate / p->median_rate);
  if (pour) md += best_skins(groups);

  md += pour ? "\n## Speed-up of 2 threads/ranks over 1 (medians)\n\n| N | code | skin mm | 2 / 1 |\n|---|---|---|---|\n"
             : "\n## Speed-up of 2 threads/ranks over 1 (medians)\n\n| N | code | 2 / 1 |\n|---|---|---|\n";
  for (const auto& g : groups) {
    if (g.threads != 2) continue;
    if (const BenchGroup* one = group_like(groups, g, g.code, 1))
      md += fmt::format("| {} | {} | {}{:.2f} |\n", n_label(g), code_label(g.code),
                        pour ? fixed(1e3 * g.skin, 2) + " | " : "", g.median_rate / one->median_rate);
  }

  md += "\n## Memory per particle (single thread/rank, whole-process peak RSS)\n\n"
        "| code | N | peak RSS MiB | bytes/particle (total) | bytes/particle (marginal vs. previous N) |\n"
        "|---|---|---|---|---|\n";
  for (const char* code : {"quarry", "liggghts", "lmp_granular", "lmp_ghh"}) {
    const BenchGroup* previous = nullptr;
    for (const auto& g : groups) {
      if (g.code != code || g.threads != 1 || !same_skin(g.skin, first_skin)) continue;
      const double bytes = g.peak_rss_kib * 1024.0;
      const std::string marginal =
          previous ? fmt::format("{:.0f}", (bytes - previous->peak_rss_kib * 1024.0) / (g.particles - previous->particles))
                   : "-";
      md += fmt::format("| {} | {} | {:.0f} | {:.0f} | {} |\n", code_label(code), n_label(g),
                        g.peak_rss_kib / 1024.0, bytes / g.particles, marginal);
      previous = kind == BenchKind::scene ? nullptr : &g;  // two scenes are not two sizes of one
    }
  }
  if (kind == BenchKind::scene) return md + scene_check(groups, tolerance);
  if (pour) return md + pour_check(groups, tolerance);
  md += fmt::format(
      "\n## Settled bed: Quarry against each peer (after the timed steps, 1 thread/rank, medians)\n\n"
      "Pass = |Quarry − peer| / peer within {:.0f} % for the max and mean height of the particle centres "
      "and the vertical force on the floor. The floor carries less than Σ m g because the side walls "
      "hold part of the weight by friction (Janssen effect), so the floor force depends on the "
      "friction history of the packing, not only on the physics.\n\n"
      "| N | peer | z max Quarry / peer (mm) | Δ | z mean Quarry / peer (mm) | Δ | floor force Quarry / peer (N) | Δ | "
      "floor / Σmg Quarry, peer | coordination Quarry, peer | pass |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
      100.0 * tolerance);
  for (const auto& [qp, p] : quarry_and_peers(groups, true)) {
    const BenchGroup& q = *qp;
    const double dz = relative_difference(q.max_height, p->max_height);
    const double dm = relative_difference(q.mean_height, p->mean_height);
    const double df = relative_difference(q.floor_force, p->floor_force);
    const bool pass = std::abs(dz) <= tolerance && std::abs(dm) <= tolerance && std::abs(df) <= tolerance;
    md += fmt::format("| {:.0f} | {} | {} / {} | {} | {} / {} | {} | {} / {} | {} | {}, {} | {}, {} | {} |\n",
                      q.particles, code_label(p->code), fixed(1e3 * q.max_height, 3), fixed(1e3 * p->max_height, 3),
                      percent(dz), fixed(1e3 * q.mean_height, 3), fixed(1e3 * p->mean_height, 3), percent(dm),
                      fixed(q.floor_force, 4), fixed(p->floor_force, 4), percent(df),
                      fixed(q.floor_force / q.weight, 3), fixed(p->floor_force / p->weight, 3),
                      fixed(q.coordination, 2), fixed(p->coordination, 2),
                      std::isfinite(dz + dm + df) ? (pass ? "yes" : "**no**") : "n/a");
  }
  return md;
}

PlotSpec throughput_plot(const std::vector<BenchGroup>& groups, const std::string& title, BenchKind kind) {
  PlotSpec plot;
  plot.title = title;
  plot.y_label = "million particle-steps per second";
  // One N only (a pour of one size) or the scenes: the throughput against the thread count, one
  // line per code, skin (and scene); otherwise against log10 N, one line per code, thread count
  // and skin.
  const bool scenes = kind == BenchKind::scene;
  bool one_size = true;
  for (const auto& g : groups) one_size = one_size && g.particles == groups.front().particles;
  const bool by_threads = one_size || scenes;
  plot.x_label = by_threads ? "threads (Quarry) or MPI ranks (peers)" : "log10 N (particles)";
  std::map<std::tuple<std::string, int, int, double>, PlotSeries> series;  // the skin is named where recorded
  for (const auto& g : groups) {
    const std::string skin = std::isnan(g.skin) ? "" : fmt::format(", skin {:.2f} mm", 1e3 * g.skin);
    PlotSeries& s = series[{scenes ? g.size : "", code_rank(g.code), by_threads ? 0 : g.threads, skin_key(g.skin)}];
    s.label = by_threads ? (scenes ? g.size + ", " : "") + code_label(g.code) + skin
                         : fmt::format("{}, {} {}{}", code_label(g.code), g.threads,
                                       g.code == "quarry" ? (g.threads == 1 ? "thread" : "threads")
                                                          : (g.threads == 1 ? "rank" : "ranks"),
                                       skin);
    s.x.push_back(by_threads ? g.threads : std::log10(g.particles));
    s.y.push_back(g.median_rate / 1e6);
  }
  for (auto& [key, s] : series) plot.series.push_back(std::move(s));
  return plot;
}

}  // namespace quarry::bench
