// Factory: due-amount schedule, radius drawing, placement by random trials against a local
// hashed grid of nearby particles, and checkpoint state.
#include "insert/factory.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>

#include "core/sphere.h"
#include "insert/placement_grid.h"

namespace quarry {

namespace {
constexpr std::uint64_t kStateTag = 0x51494E5346414331ull;  // "QINSFAC1": layout version 1
}  // namespace

Factory::Factory(const FactorySpec& spec, const ParticleTypeInfo& type, std::uint64_t seed)
    : spec_(spec), type_(type), region_(spec.region), sampler_(type.size), random_(seed) {
  assert(type.density > 0.0);
  Diagnostics problems;
  const std::string& name = spec.name.value;
  if (spec.target_count.has_value() == spec.target_mass.has_value())
    problems.error(
        spec.name.where,
        fmt::format("factory '{}' needs exactly one of target_count and target_mass", name));
  if (spec.target_count && !(spec.target_count->value > 0))
    problems.error(spec.target_count->where,
                   fmt::format("factory '{}': target_count must be > 0, got {}", name,
                               spec.target_count->value));
  if (spec.target_mass && !(spec.target_mass->value > 0.0))
    problems.error(spec.target_mass->where,
                   fmt::format("factory '{}': target_mass must be > 0 (kg), got {}", name,
                               spec.target_mass->value));
  if (spec.mass_rate && !(spec.mass_rate->value > 0.0))
    problems.error(spec.mass_rate->where,
                   fmt::format("factory '{}': mass_rate must be > 0 (kg/s), got {}", name,
                               spec.mass_rate->value));
  if (spec.stop_time.value < spec.start_time.value)
    problems.error(spec.stop_time.where,
                   fmt::format("factory '{}': stop_time {} s is before start_time {} s", name,
                               spec.stop_time.value, spec.start_time.value));
  if (spec.max_attempts.value < 1)
    problems.error(spec.max_attempts.where,
                   fmt::format("factory '{}': max_attempts must be ≥ 1, got {}", name,
                               spec.max_attempts.value));
  if (sampler_.max_radius() > region_.inscribed_radius()) {
    const SourceLocation& where = spec.region.kind.value == RegionKind::box
                                      ? spec.region.max.where
                                      : spec.region.radius.where;
    problems.error(
        where,
        fmt::format("factory '{}': the region holds spheres up to radius {} m, but particles "
                    "reach radius {} m",
                    name, region_.inscribed_radius(), sampler_.max_radius()),
        "enlarge the region");
  }
  if (problems.has_errors()) throw UserError(std::move(problems));
  mean_particle_mass_ = sampler_.mean_particle_mass(type.density);
}

double Factory::particle_mass(double radius) const {
  // Same expression as ParticleStore::add, so the factory's mass sums match the store's.
  return sphere_mass(type_.density, radius);
}

void Factory::draw_one() {
  const double radius = sampler_.sample(random_);
  waiting_radii_.push_back(radius);
  drawn_count_ += 1;
  drawn_mass_ += particle_mass(radius);
}

bool Factory::fully_drawn() const {
  if (spec_.target_count) return drawn_count_ >= spec_.target_count->value;
  return drawn_mass_ >= spec_.target_mass->value - 0.5 * mean_particle_mass_;
}

void Factory::draw_due_radii(double time) {
  const double elapsed = time - spec_.start_time.value;     // s
  const double half_mean_mass = 0.5 * mean_particle_mass_;  // kg
  if (spec_.target_count) {
    const std::int64_t target = spec_.target_count->value;
    bool release_all = !spec_.mass_rate;
    if (spec_.mass_rate) {
      const double duration =
          static_cast<double>(target) * mean_particle_mass_ / spec_.mass_rate->value;  // s
      release_all = elapsed >= duration;
      const double due_mass = spec_.mass_rate->value * elapsed;  // kg
      while (!release_all && drawn_count_ < target && drawn_mass_ < due_mass - half_mean_mass)
        draw_one();
    }
    while (release_all && drawn_count_ < target) draw_one();
    return;
  }
  const double target_mass = spec_.target_mass->value;  // kg
  const double due_mass =
      spec_.mass_rate ? std::min(target_mass, spec_.mass_rate->value * elapsed) : target_mass;
  while (drawn_mass_ < due_mass - half_mean_mass) draw_one();
}

InsertionReport Factory::insert_due(double time, ParticleStore& particles, ParticleId& next_id,
                                    const SurfaceOverlapQuery& touches_surface,
                                    const std::function<bool()>& stop_requested) {
  InsertionReport report;
  if (closed_ || time < spec_.start_time.value) return report;
  draw_due_radii(std::min(time, spec_.stop_time.value));
  if (time >= spec_.stop_time.value) closed_ = true;
  if (waiting_radii_.empty()) return report;

  // Existing particles that could touch a new one: those whose sphere reaches into the region's
  // bounds widened by the largest new radius (a conservative box test).
  const double largest_new_radius =
      *std::max_element(waiting_radii_.begin(), waiting_radii_.end());  // m
  const Aabb bounds = region_.bounds();
  // On periodic axes a sphere also reaches in through the opposite face: its images shifted by
  // ±L are tested (and entered in the grid) like spheres of their own.
  const auto for_each_image = [this](const Vec3& x, auto&& visit) {
    const PeriodicBox& box = periodic_;
    for (int sz = box.wraps[2] ? -1 : 0; sz <= (box.wraps[2] ? 1 : 0); ++sz)
      for (int sy = box.wraps[1] ? -1 : 0; sy <= (box.wraps[1] ? 1 : 0); ++sy)
        for (int sx = box.wraps[0] ? -1 : 0; sx <= (box.wraps[0] ? 1 : 0); ++sx)
          visit(x + Vec3{sx * box.period.x, sy * box.period.y, sz * box.period.z});
  };
  std::vector<Vec3> nearby;            // m, centres (and images) that reach into the region
  std::vector<double> nearby_radius;   // m
  double largest_nearby_radius = 0.0;  // m
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double reach = particles.radius[i] + largest_new_radius;  // m
    for_each_image(particles.position[i], [&](const Vec3& x) {
      if (x.x < bounds.lo.x - reach || x.x > bounds.hi.x + reach || x.y < bounds.lo.y - reach ||
          x.y > bounds.hi.y + reach || x.z < bounds.lo.z - reach || x.z > bounds.hi.z + reach)
        return;
      nearby.push_back(x);
      nearby_radius.push_back(particles.radius[i]);
      largest_nearby_radius = std::max(largest_nearby_radius, particles.radius[i]);
    });
  }
  // Any overlapping pair is closer than the sum of its radii, which is at most this cell size.
  const double cell_size =
      largest_new_radius + std::max(largest_new_radius, largest_nearby_radius);  // m
  PlacementGrid grid(cell_size, nearby.size() + waiting_radii_.size());
  for (std::size_t k = 0; k < nearby.size(); ++k) grid.insert(nearby[k], nearby_radius[k]);

  std::vector<double> still_waiting;
  const int attempts = spec_.max_attempts.value;
  for (std::size_t k = 0; k < waiting_radii_.size(); ++k) {
    if (stop_requested && k % 1024 == 0 && k > 0 && stop_requested()) {
      still_waiting.insert(still_waiting.end(),
                           waiting_radii_.begin() + static_cast<std::ptrdiff_t>(k),
                           waiting_radii_.end());
      break;
    }
    const double radius = waiting_radii_[k];
    bool placed = false;
    for (int attempt = 0; attempt < attempts && !placed; ++attempt) {
      const Vec3 centre = region_.sample_point(random_, radius);
      if (grid.overlaps(centre, radius)) continue;
      if (touches_surface && touches_surface(centre, radius)) continue;
      const std::size_t index = particles.add(next_id++, type_.type_index, type_.material_index, centre,
                                              spec_.initial_velocity.value, radius, type_.density, time);
      particles.angular_velocity[index] = spec_.initial_angular_velocity.value;
      if (type_.fixed) particles.make_fixed(index);
      for_each_image(centre, [&](const Vec3& x) { grid.insert(x, radius); });
      const double mass = particle_mass(radius);  // kg
      inserted_count_ += 1;
      inserted_mass_ += mass;
      report.inserted += 1;
      report.inserted_mass += mass;
      placed = true;
    }
    if (!placed) still_waiting.push_back(radius);
  }
  report.failed = static_cast<std::int64_t>(still_waiting.size());
  waiting_radii_ = std::move(still_waiting);
  return report;
}

bool Factory::finished() const {
  return closed_ || (fully_drawn() && waiting_radii_.empty());
}

std::int64_t Factory::shortfall() const {
  std::int64_t not_drawn = 0;
  if (spec_.target_count) {
    not_drawn = std::max<std::int64_t>(0, spec_.target_count->value - drawn_count_);
  } else if (!fully_drawn()) {
    const double missing_mass =
        spec_.target_mass->value - 0.5 * mean_particle_mass_ - drawn_mass_;  // kg
    not_drawn = static_cast<std::int64_t>(std::ceil(missing_mass / mean_particle_mass_));
  }
  return waiting_count() + not_drawn;
}

std::vector<std::uint64_t> Factory::save_state() const {
  std::vector<std::uint64_t> words;
  words.push_back(kStateTag);
  for (std::uint64_t word : random_.state()) words.push_back(word);
  const std::vector<double> sampler_state = sampler_.state();
  words.push_back(sampler_state.size());
  for (double value : sampler_state) words.push_back(std::bit_cast<std::uint64_t>(value));
  words.push_back(static_cast<std::uint64_t>(drawn_count_));
  words.push_back(std::bit_cast<std::uint64_t>(drawn_mass_));
  words.push_back(static_cast<std::uint64_t>(inserted_count_));
  words.push_back(std::bit_cast<std::uint64_t>(inserted_mass_));
  words.push_back(closed_ ? 1 : 0);
  words.push_back(waiting_radii_.size());
  for (double radius : waiting_radii_) words.push_back(std::bit_cast<std::uint64_t>(radius));
  return words;
}

void Factory::load_state(const std::vector<std::uint64_t>& state) {
  const auto malformed = [this](const char* what) {
    return UserError(SourceLocation{},
                     fmt::format("checkpoint: the state of factory '{}' is malformed ({})",
                                 spec_.name.value, what),
                     "the checkpoint is damaged or was written by a different deck");
  };
  std::size_t at = 0;
  const auto take = [&]() {
    if (at >= state.size()) throw malformed("too short");
    return state[at++];
  };
  if (take() != kStateTag) throw malformed("unknown layout tag");
  Random::State generator;
  for (auto& word : generator) word = take();
  if (generator == Random::State{}) throw malformed("all-zero generator state");
  const std::uint64_t sampler_size = take();
  if (sampler_size != sampler_.state().size()) throw malformed("size classes differ from the deck");
  std::vector<double> sampler_state(sampler_size);
  for (auto& value : sampler_state) value = std::bit_cast<double>(take());
  const auto drawn_count = static_cast<std::int64_t>(take());
  const double drawn_mass = std::bit_cast<double>(take());
  const auto inserted_count = static_cast<std::int64_t>(take());
  const double inserted_mass = std::bit_cast<double>(take());
  const std::uint64_t closed = take();
  const std::uint64_t waiting = take();
  if (closed > 1 || waiting != state.size() - at) throw malformed("inconsistent lengths");
  std::vector<double> waiting_radii(waiting);
  for (auto& radius : waiting_radii) radius = std::bit_cast<double>(take());
  // Commit only after the whole state parsed, so a failed load leaves the factory unchanged.
  random_.set_state(generator);
  sampler_.set_state(sampler_state);
  drawn_count_ = drawn_count;
  drawn_mass_ = drawn_mass;
  inserted_count_ = inserted_count;
  inserted_mass_ = inserted_mass;
  closed_ = closed == 1;
  waiting_radii_ = std::move(waiting_radii);
}

}  // namespace quarry
