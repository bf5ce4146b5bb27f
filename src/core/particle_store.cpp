// ParticleStore operations: add, remove (order-preserving), permute (re-sort), custom props.
#include "core/particle_store.h"

#include <cassert>
#include <numbers>

namespace quarry {

namespace {
// Every per-particle array; the optional external loads only once they are enabled.
template <class F>
void for_each_array(ParticleStore& s, F&& f) {
  f(s.position); f(s.velocity); f(s.angular_velocity); f(s.force); f(s.torque);
  f(s.radius); f(s.inv_mass); f(s.material);
  f(s.id); f(s.type); f(s.creation_time);
  if (s.has_external_loads()) { f(s.external_force); f(s.external_torque); }
  for (auto& c : s.custom_values) f(c);
}
}  // namespace

std::size_t ParticleStore::add(ParticleId pid, std::uint16_t type_index,
                               std::uint16_t material_index, const Vec3& x, const Vec3& v,
                               double radius_m, double density, double time) {
  const double mass = density * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
  position.push_back(x);
  velocity.push_back(v);
  angular_velocity.push_back({});
  force.push_back({});
  torque.push_back({});
  radius.push_back(radius_m);
  inv_mass.push_back(1.0 / mass);
  material.push_back(material_index);
  id.push_back(pid);
  type.push_back(type_index);
  creation_time.push_back(time);
  if (has_external_loads()) {
    external_force.push_back({});
    external_torque.push_back({});
  }
  for (auto& c : custom_values) c.push_back(0.0);
  return position.size() - 1;
}

void ParticleStore::remove_flagged(const std::vector<char>& remove) {
  assert(remove.size() == size());
  for_each_array(*this, [&](auto& array) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < array.size(); ++i)
      if (!remove[i]) array[out++] = array[i];
    array.resize(out);
  });
}

void ParticleStore::permute(const std::vector<std::size_t>& order) {
  assert(order.size() == size());
  for_each_array(*this, [&](auto& array) {
    auto copy = array;
    for (std::size_t k = 0; k < order.size(); ++k) array[k] = copy[order[k]];
  });
}

std::size_t ParticleStore::register_custom(const std::string& name, double initial) {
  for (std::size_t k = 0; k < custom_names.size(); ++k)
    if (custom_names[k] == name) return k;
  custom_names.push_back(name);
  custom_values.emplace_back(size(), initial);
  return custom_names.size() - 1;
}

void ParticleStore::reserve(std::size_t n) {
  for_each_array(*this, [&](auto& array) { array.reserve(n); });
}

void ParticleStore::enable_external_loads() {
  external_loads_enabled = true;
  external_force.resize(size());
  external_torque.resize(size());
}

void ParticleStore::clear() {
  for_each_array(*this, [&](auto& array) { array.clear(); });
}

}  // namespace quarry
