// The deck's structures in a checkpoint (the section "structures", sim/checkpoint.cpp): per
// structure the shell solver's state (nodal positions, velocities, rotations, loads, internal
// forces and reactions, stresses and plastic strains per point, resultants per element, time,
// steps, energies), the coupler's (schedule, force filter, impulse in transit, the period under
// way) and the output's (frame number, the series' entries, the monitor rows), then the next
// output and monitor times: a run restarted from it takes the same steps, to the bit, and
// writes the same files as the run that went on. Read whole and checked before anything
// changes.
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "fsi/structure_run.h"
#include "io/deck.h"

namespace quarry::fsi {

namespace {

// 2: the monitor rows carry each support's reaction after the totals (1: the totals alone;
// written before the elements moved to the mid-step configuration, so its state would not
// continue the run it came from either). A section of another version is refused.
constexpr std::uint32_t kSectionVersion = 2;
constexpr std::uint64_t kMostItems = std::uint64_t{1} << 32;  // counts beyond are damage

[[noreturn]] void bad(const std::string& what) { throw std::runtime_error(what); }

std::uint64_t read_count(BinaryReader& in, const char* what) {
  const auto n = in.value<std::uint64_t>();
  if (n > kMostItems) bad(fmt::format("the count of {} ({}) is implausible", what, n));
  return n;
}

bool read_flag(BinaryReader& in, const char* what) {
  const auto flag = in.value<std::uint8_t>();
  if (flag > 1) bad(fmt::format("{} holds {}, not 0 or 1", what, flag));
  return flag != 0;
}

// Field by field: a struct's padding bytes are not written.
void write_energies(BinaryWriter& out, const fem::ShellEnergies& e) {
  for (const double v : {e.kinetic, e.internal, e.hourglass, e.damping, e.external_work, e.constraint_work}) out.value(v);
  out.value(static_cast<std::uint8_t>(e.hourglass_warning));
}

fem::ShellEnergies read_energies(BinaryReader& in) {
  fem::ShellEnergies e;
  for (double* v : {&e.kinetic, &e.internal, &e.hourglass, &e.damping, &e.external_work, &e.constraint_work})
    *v = in.value<double>();
  e.hourglass_warning = read_flag(in, "the hourglass warning flag");
  return e;
}

void write_solver(BinaryWriter& out, const fem::ShellSolverState& s) {
  for (const auto* v : {&s.positions, &s.velocities, &s.angular_velocities, &s.rotations}) out.vector(*v);
  out.vector(s.loads);
  for (const auto* v : {&s.internal_force, &s.reactions, &s.previous_reactions, &s.prescribed_velocity}) out.vector(*v);
  for (const auto* v : {&s.stress, &s.plastic, &s.shear, &s.hourglass}) out.vector(*v);
  out.value(s.damping);
  out.value(s.time);
  out.value(s.steps);
  write_energies(out, s.energies);
}

fem::ShellSolverState read_solver(BinaryReader& in) {
  fem::ShellSolverState s;
  for (auto* v : {&s.positions, &s.velocities, &s.angular_velocities, &s.rotations}) in.vector(*v);
  in.vector(s.loads);
  for (auto* v : {&s.internal_force, &s.reactions, &s.previous_reactions, &s.prescribed_velocity}) in.vector(*v);
  for (auto* v : {&s.stress, &s.plastic, &s.shear, &s.hourglass}) in.vector(*v);
  s.damping = in.value<double>();
  s.time = in.value<double>();
  s.steps = in.value<std::int64_t>();
  s.energies = read_energies(in);
  return s;
}

void write_coupler(BinaryWriter& out, const CouplerState& s) {
  const ScheduleState& q = s.schedule;
  for (const double v : {q.period, q.filter, q.requested, q.previous_request}) out.value(v);
  out.value(static_cast<std::uint8_t>(q.reset_done));
  out.value(q.synchronisations);
  out.value(s.filter_window);
  out.value(static_cast<std::uint64_t>(s.filter_periods.size()));
  for (const ForceFilter::Period& p : s.filter_periods) {
    out.vector(p.impulse);
    out.value(p.duration);
  }
  out.vector(s.pending_impulse);
  out.vector(s.loads);
  out.value(s.structure_dt);
  for (const std::int64_t v : {s.period_steps, s.period_steps_done, s.structure_steps}) out.value(v);
  out.value(static_cast<std::uint8_t>(s.stability_checked));
  out.value(static_cast<std::uint64_t>(s.messages.size()));
  for (const std::string& line : s.messages) out.string(line);
}

CouplerState read_coupler(BinaryReader& in) {
  CouplerState s;
  ScheduleState& q = s.schedule;
  for (double* v : {&q.period, &q.filter, &q.requested, &q.previous_request}) *v = in.value<double>();
  q.reset_done = read_flag(in, "the cycle-2 reset flag");
  q.synchronisations = in.value<std::int64_t>();
  s.filter_window = in.value<double>();
  s.filter_periods.resize(read_count(in, "force filter periods"));
  for (ForceFilter::Period& p : s.filter_periods) {
    in.vector(p.impulse);
    p.duration = in.value<double>();
  }
  in.vector(s.pending_impulse);
  in.vector(s.loads);
  s.structure_dt = in.value<double>();
  for (std::int64_t* v : {&s.period_steps, &s.period_steps_done, &s.structure_steps}) *v = in.value<std::int64_t>();
  s.stability_checked = read_flag(in, "the stability-check flag");
  s.messages.resize(read_count(in, "coupling messages"));
  for (std::string& line : s.messages) line = in.string();
  return s;
}

}  // namespace

void CoupledStructures::save_state(BinaryWriter& out) const {
  out.value(kSectionVersion);
  out.value(static_cast<std::uint64_t>(entries_.size()));
  for (const auto& entry : entries_) {
    out.string(entry->name);
    out.value(static_cast<std::uint64_t>(entry->coupler->surface()));
    write_solver(out, entry->solver->state());
    write_coupler(out, entry->coupler->state());
    out.value(static_cast<std::uint64_t>(entry->messages_printed));
    out.value(entry->frames);
    out.value(entry->last_frame_time);
    // The series and table as they stand (or as a checkpoint gave them and no step used yet).
    const std::vector<PvdEntry>& listed = entry->series ? entry->series->entries() : entry->listed;
    out.value(static_cast<std::uint64_t>(listed.size()));
    for (const PvdEntry& e : listed) {
      out.value(e.time);
      out.string(e.file);
    }
    const std::vector<std::vector<double>>& rows = entry->monitors ? entry->monitors->rows() : entry->rows;
    out.value(static_cast<std::uint64_t>(rows.size()));
    for (const std::vector<double>& row : rows) out.vector(row);
  }
  out.value(next_output_);
  out.value(next_monitor_);
}

void CoupledStructures::load_state(BinaryReader& in, const World& world) {
  const auto version = in.value<std::uint32_t>();
  if (version != kSectionVersion)
    bad(fmt::format("version {} (this Quarry reads version {}); rerun from the deck", version, kSectionVersion));
  const std::uint64_t count = read_count(in, "structures");
  if (count != entries_.size())
    bad(fmt::format("it holds {} structures, the deck has {}", count, entries_.size()));
  struct Saved {
    fem::ShellSolverState solver;
    CouplerState coupler;
    std::uint64_t messages_printed = 0;
    std::int64_t frames = 0;
    double last_frame_time = 0.0;
    std::vector<PvdEntry> listed;
    std::vector<std::vector<double>> rows;
  };
  std::vector<Saved> saved(entries_.size());
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const Entry& entry = *entries_[k];
    Saved& s = saved[k];
    const std::string name = in.string();
    if (name != entry.name) bad(fmt::format("structure {} is \"{}\", the deck's is \"{}\"", k, name, entry.name));
    const auto surface = in.value<std::uint64_t>();
    const std::size_t ours = entry.coupler->surface();
    if (surface != ours || ours >= world.surfaces.size() || world.surfaces[ours].mesh.name != entry.name ||
        world.surfaces[ours].driver.kind != SurfaceDriverKind::coupled)
      bad(fmt::format("structure \"{}\" was coupled to surface {}, here it is surface {} of {} (another deck)", name,
                      surface, ours, world.surfaces.size()));
    s.solver = read_solver(in);
    s.coupler = read_coupler(in);
    s.messages_printed = in.value<std::uint64_t>();
    s.frames = in.value<std::int64_t>();
    s.last_frame_time = in.value<double>();
    s.listed.resize(read_count(in, "series entries"));
    for (PvdEntry& e : s.listed) {
      e.time = in.value<double>();
      e.file = in.string();
      if (!std::isfinite(e.time) || !usable_in_file_names(e.file))
        bad(fmt::format("structure \"{}\": a series entry names \"{}\" at {} s", name, e.file, e.time));
    }
    s.rows.resize(read_count(in, "monitor rows"));
    const std::size_t columns = monitor_columns(entry).size();
    for (std::vector<double>& row : s.rows) {
      in.vector(row);
      if (row.size() != columns)
        bad(fmt::format("structure \"{}\": a monitor row has {} values, not {}", name, row.size(), columns));
    }
    if (s.messages_printed > s.coupler.messages.size() || s.frames < 0 || !std::isfinite(s.last_frame_time) ||
        s.listed.size() > static_cast<std::uint64_t>(s.frames))
      bad(fmt::format("structure \"{}\": {} of {} messages printed, frame {}, {} series entries, last frame at {} s", name,
                      s.messages_printed, s.coupler.messages.size(), s.frames, s.listed.size(), s.last_frame_time));
  }
  const auto next_output = in.value<double>();
  const auto next_monitor = in.value<double>();
  if (!std::isfinite(next_output) || !std::isfinite(next_monitor) || next_output < 0.0 || next_monitor < 0.0)
    bad(fmt::format("the next structure output at {} s or monitor row at {} s is not a time", next_output, next_monitor));

  // Every part checked before any changes, so that a refused section changes nothing.
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    entries_[k]->solver->check_state(saved[k].solver);
    entries_[k]->coupler->check_state(saved[k].coupler);
  }
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    Entry& entry = *entries_[k];
    Saved& s = saved[k];
    entry.solver->set_state(std::move(s.solver));
    entry.coupler->set_state(std::move(s.coupler));
    entry.messages_printed = static_cast<std::size_t>(s.messages_printed);
    entry.frames = s.frames;
    entry.last_frame_time = s.last_frame_time;
    entry.listed = std::move(s.listed);
    entry.rows = std::move(s.rows);
    entry.series.reset();  // made again, in this run's output folder, at the next use
    entry.monitors.reset();
  }
  next_output_ = next_output;
  next_monitor_ = next_monitor;
}

}  // namespace quarry::fsi
