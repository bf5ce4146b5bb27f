// The CFD-DEM coupling in a checkpoint (its section "fluid", sim/checkpoint.cpp): the fluid
// solver's fields and what the coupling keeps between exchanges — ε, each particle's frozen
// β_p, u_p, ∇p_p, weights and velocity sum, the counters — so that a run restarted inside a
// coupling interval takes the same steps, to the bit, as the run that went on. Read whole and
// checked before anything changes.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cfdem/fluid_coupling.h"
#include "sim/binary_stream.h"

namespace quarry::cfdem {

namespace {

// 1: the first layout. A section of another version is refused (the file's format number says
// the same for the core state).
constexpr std::uint32_t kSectionVersion = 1;

[[noreturn]] void bad(const std::string& what) { throw std::runtime_error(what); }

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::uint8_t read_flag(BinaryReader& in, const char* what) {
  const auto flag = in.value<std::uint8_t>();
  if (flag > 1) bad(fmt::format("{} holds {}, not 0 or 1", what, flag));
  return flag;
}

// Field by field: a struct's padding bytes are not written.
void write_report(BinaryWriter& out, const cfd::SolveReport& report) {
  out.value(report.iterations);
  out.value(report.relative_residual);
  out.value(static_cast<std::uint8_t>(report.converged));
  out.value(report.removed_mean);
}

cfd::SolveReport read_report(BinaryReader& in) {
  cfd::SolveReport report;
  report.iterations = in.value<int>();
  report.relative_residual = in.value<double>();
  report.converged = read_flag(in, "a solve report's flag") != 0;
  report.removed_mean = in.value<double>();
  return report;
}

void write_solver(BinaryWriter& out, const cfd::FluidSolverState& state) {
  for (const std::vector<double>& component : state.velocity) out.vector(component);
  out.vector(state.pressure);
  out.vector(state.void_fraction_old);
  out.vector(state.void_fraction_new);
  out.vector(state.drag_coefficient);
  out.vector(state.force_density);
  out.vector(state.blocked);
  out.value(static_cast<std::uint8_t>(state.void_fraction_started));
  out.value(static_cast<std::int64_t>(state.steps));
  write_report(out, state.last_report.pressure);
  for (const cfd::SolveReport& report : state.last_report.momentum) write_report(out, report);
  out.value(state.last_report.predicted_divergence);
  out.value(state.last_report.divergence);
}

cfd::FluidSolverState read_solver(BinaryReader& in) {
  cfd::FluidSolverState state;
  for (std::vector<double>& component : state.velocity) in.vector(component);
  in.vector(state.pressure);
  in.vector(state.void_fraction_old);
  in.vector(state.void_fraction_new);
  in.vector(state.drag_coefficient);
  in.vector(state.force_density);
  in.vector(state.blocked);
  state.void_fraction_started = read_flag(in, "the fluid's void-fraction flag") != 0;
  state.steps = static_cast<long long>(in.value<std::int64_t>());
  state.last_report.pressure = read_report(in);
  for (cfd::SolveReport& report : state.last_report.momentum) report = read_report(in);
  state.last_report.predicted_divergence = in.value<double>();
  state.last_report.divergence = in.value<double>();
  return state;
}

// One member of every particle's frozen values, as an array (written and read as such).
template <class S, class T>
std::vector<T> column(const std::vector<S>& frozen, T S::*member) {
  std::vector<T> values(frozen.size());
  for (std::size_t i = 0; i < frozen.size(); ++i) values[i] = frozen[i].*member;
  return values;
}

template <class S, class T>
void read_column(BinaryReader& in, std::vector<S>& frozen, T S::*member, const char* what) {
  std::vector<T> values;
  in.vector(values);
  if (values.size() != frozen.size())
    bad(fmt::format("the frozen {} are {} values for {} particles", what, values.size(), frozen.size()));
  for (std::size_t i = 0; i < frozen.size(); ++i) frozen[i].*member = values[i];
}

bool same(const CellWeights& a, const CellWeights& b) { return a.cell == b.cell && a.weight == b.weight; }

void check_weights(const CellWeights& w, std::size_t cells, const char* what, std::size_t i) {
  for (std::size_t k = 0; k < w.cell.size(); ++k) {
    if (w.cell[k] >= cells) bad(fmt::format("{} {} name cell {} of a grid of {}", what, i, w.cell[k], cells));
    if (!(w.weight[k] >= 0.0) || !std::isfinite(w.weight[k]))
      bad(fmt::format("{} {} hold the weight {}", what, i, w.weight[k]));
  }
}

}  // namespace

void FluidCoupling::save_state(BinaryWriter& out) const {
  out.value(kSectionVersion);
  write_solver(out, fluid_->state());
  out.vector(void_fraction_);
  out.vector(weights_);
  out.vector(column(frozen_, &FrozenParticle::id));
  out.vector(column(forces_, &FrozenForce::coefficient));
  out.vector(column(forces_, &FrozenForce::fluid_velocity));
  out.vector(column(frozen_, &FrozenParticle::pressure_gradient));
  out.vector(column(frozen_, &FrozenParticle::volume));
  out.vector(column(frozen_, &FrozenParticle::exchange_velocity));
  out.vector(column(velocity_sums_, &VelocitySum::sum));
  out.vector(column(velocity_sums_, &VelocitySum::samples));
  // The exchange's weights, which version 1 keeps apart from the weights: the same values (the
  // pressure force is not written; it is made again from ∇p_p and V_p).
  out.vector(weights_);
  out.value(layout_epoch_);
  out.value(static_cast<std::uint64_t>(frozen_count_));
  out.value(static_cast<std::int64_t>(exchanges_));
  out.value(last_exchange_step_);
  out.value(coupling_step_);
  out.value(static_cast<std::uint8_t>(relaxation_warned_));
  out.value(static_cast<std::uint8_t>(blocked_warned_));
}

void FluidCoupling::load_state(BinaryReader& in, const World& world) {
  const auto version = in.value<std::uint32_t>();
  if (version != kSectionVersion)
    bad(fmt::format("version {} (this Quarry reads version {})", version, kSectionVersion));
  cfd::FluidSolverState solver = read_solver(in);
  std::vector<double> void_fraction;
  in.vector(void_fraction);
  std::vector<CellWeights> weights;
  in.vector(weights);
  std::vector<ParticleId> ids;
  in.vector(ids);
  std::vector<FrozenParticle> frozen(ids.size());
  std::vector<FrozenForce> forces(ids.size());
  std::vector<VelocitySum> sums(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) frozen[i].id = ids[i];
  read_column(in, forces, &FrozenForce::coefficient, "drag coefficients");
  read_column(in, forces, &FrozenForce::fluid_velocity, "fluid velocities");
  read_column(in, frozen, &FrozenParticle::pressure_gradient, "pressure gradients");
  read_column(in, frozen, &FrozenParticle::volume, "volumes");
  read_column(in, frozen, &FrozenParticle::exchange_velocity, "exchange velocities");
  read_column(in, sums, &VelocitySum::sum, "velocity sums");
  read_column(in, sums, &VelocitySum::samples, "sample counts");
  std::vector<CellWeights> exchange_weights;
  in.vector(exchange_weights);
  const auto layout_epoch = in.value<std::uint64_t>();
  const auto frozen_count = in.value<std::uint64_t>();
  const auto exchanges = in.value<std::int64_t>();
  const auto last_exchange_step = in.value<std::uint64_t>();
  const auto coupling_step = in.value<double>();
  const bool relaxation_warned = read_flag(in, "the relaxation-warning flag") != 0;
  const bool blocked_warned = read_flag(in, "the blocked-cell warning flag") != 0;

  // Checked against the grid of the deck and the restored particles.
  const std::size_t cells = options_.grid.cell_count();
  if (void_fraction.size() != cells)
    bad(fmt::format("the void fraction has {} values, the grid {} cells", void_fraction.size(), cells));
  for (std::size_t c = 0; c < cells; ++c)
    if (!(void_fraction[c] > 0.0 && void_fraction[c] <= 1.0))
      bad(fmt::format("the void fraction of cell {} is {}, not in (0, 1]", c, void_fraction[c]));
  const std::size_t n = frozen.size();
  if (weights.size() != n || exchange_weights.size() != n || frozen_count != n)
    bad(fmt::format("the coupling holds {} particles' weights, {} exchange weights and {} frozen values (count {})",
                    weights.size(), exchange_weights.size(), n, frozen_count));
  const ParticleStore& p = world.particles;
  for (std::size_t i = 0; i < n; ++i) {
    const FrozenParticle& f = frozen[i];
    check_weights(weights[i], cells, "the weights of particle", i);
    check_weights(exchange_weights[i], cells, "the exchange weights of particle", i);
    if (!same(weights[i], exchange_weights[i]))
      bad(fmt::format("the exchange weights of particle {} are not its weights", i));
    if (f.id == 0 || f.id >= world.next_id)
      bad(fmt::format("frozen particle {} has id {} (next id {})", i, f.id, world.next_id));
    const double coefficient = forces[i].coefficient;
    if (!(coefficient >= 0.0) || !std::isfinite(coefficient) || !(f.volume > 0.0) || !std::isfinite(f.volume) ||
        !finite(forces[i].fluid_velocity) || !finite(f.pressure_gradient) || !finite(f.exchange_velocity) ||
        !finite(sums[i].sum) || sums[i].samples < 0)
      bad(fmt::format("the frozen values of particle id {} are not finite or out of range", f.id));
  }
  // Values the coupling takes to be the particles' as they stand (same layout) must be theirs.
  if (layout_epoch == p.layout_epoch && n == p.size())
    for (std::size_t i = 0; i < n; ++i)
      if (frozen[i].id != p.id[i])
        bad(fmt::format("frozen value {} belongs to particle id {}, the particle there has id {}", i, frozen[i].id,
                        p.id[i]));
  if (exchanges < 0) bad(fmt::format("the exchange count {} is negative", exchanges));
  if (last_exchange_step != ~std::uint64_t{0} && last_exchange_step > world.step_count)
    bad(fmt::format("the last exchange at step {} is after the world's step {}", last_exchange_step,
                    world.step_count));
  if (!(coupling_step >= 0.0) || !std::isfinite(coupling_step))
    bad(fmt::format("the coupling step {} s is not a time", coupling_step));

  // The blocked cells come from the deck (the coupling set them when it was built); a
  // checkpoint whose fluid had others belongs to another deck or lost them on the way.
  const std::span<std::uint8_t> blocked = fluid_->blocked();
  if (solver.blocked.size() == blocked.size() &&
      !std::equal(blocked.begin(), blocked.end(), solver.blocked.begin()))
    bad(fmt::format("its blocked fluid cells ({}) are not those of the deck ({})",
                    std::count(solver.blocked.begin(), solver.blocked.end(), std::uint8_t{1}),
                    std::count(blocked.begin(), blocked.end(), std::uint8_t{1})));
  fluid_->set_state(std::move(solver));  // checks its own fields; throws before changing any
  void_fraction_ = std::move(void_fraction);
  weights_ = std::move(weights);
  order_is_current_ = false;
  for (std::size_t i = 0; i < n; ++i) forces[i].pressure_force = pressure_force(frozen[i]);
  frozen_ = std::move(frozen);
  forces_ = std::move(forces);
  velocity_sums_ = std::move(sums);
  layout_epoch_ = layout_epoch;
  frozen_count_ = static_cast<std::size_t>(frozen_count);
  exchanges_ = static_cast<long long>(exchanges);
  last_exchange_step_ = last_exchange_step;
  coupling_step_ = coupling_step;
  relaxation_warned_ = relaxation_warned;
  blocked_warned_ = blocked_warned;
  update_cell_fields();  // u and ∇p per cell: a function of the fluid's fields, as after the exchange
}

}  // namespace quarry::cfdem
