// ParticleStore operations: add, remove (order-preserving), permute (re-sort), custom props.
#include "core/particle_store.h"
#include "core/sphere.h"

#include <algorithm>
#include <cassert>
#include <stdexcept>

namespace quarry {

namespace {
// Every per-particle array with its values per particle; the optional external loads only
// once they are enabled.
template <class F>
void for_each_array(ParticleStore& s, F&& f) {
  f(s.position, 1); f(s.velocity, 1); f(s.angular_velocity, 1); f(s.force, 1); f(s.torque, 1);
  f(s.radius, 1); f(s.inv_mass, 1); f(s.material, 1);
  f(s.id, 1); f(s.type, 1); f(s.creation_time, 1);
  if (s.has_external_loads()) {
    f(s.external_force, 1); f(s.external_torque, 1);
    f(s.external_force_once, 1); f(s.external_torque_once, 1);
  }
  for (auto& c : s.custom) f(c.values, c.components);
}
}  // namespace

std::size_t ParticleStore::add(ParticleId pid, std::uint16_t type_index,
                               std::uint16_t material_index, const Vec3& x, const Vec3& v,
                               double radius_m, double density, double time) {
  const double mass = sphere_mass(density, radius_m);
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
    external_force_once.push_back({});
    external_torque_once.push_back({});
  }
  for (auto& c : custom) c.values.insert(c.values.end(), c.components, c.initial);
  layout_epoch += 1;
  return position.size() - 1;
}

void ParticleStore::remove_flagged(const std::vector<char>& remove) {
  assert(remove.size() == size());
  // What lies before the first removed particle stays where it is; the kept particles after it
  // move down run by run, one block copy (memmove) per run and array instead of one per value:
  // a hopper's outflow removes a few particles per step from arrays of thousands.
  const std::size_t n = remove.size();
  const std::size_t first = first_removed(remove);
  struct Run {
    std::size_t begin, end;  // kept particles [begin, end)
  };
  std::vector<Run> runs;
  for (std::size_t i = first; i < n;) {
    while (i < n && remove[i]) ++i;
    const std::size_t begin = i;
    while (i < n && !remove[i]) ++i;
    if (i > begin) runs.push_back({begin, i});
  }
  for_each_array(*this, [&](auto& array, std::size_t stride) {
    std::size_t kept = first * stride;
    for (const Run& r : runs) {
      // Down to a lower position: std::copy (a memmove for these types) is defined there.
      std::copy(array.begin() + static_cast<std::ptrdiff_t>(r.begin * stride),
                array.begin() + static_cast<std::ptrdiff_t>(r.end * stride),
                array.begin() + static_cast<std::ptrdiff_t>(kept));
      kept += (r.end - r.begin) * stride;
    }
    array.resize(kept);
  });
  layout_epoch += 1;
}

std::size_t first_removed(const std::vector<char>& removed) {
  return static_cast<std::size_t>(std::find(removed.begin(), removed.end(), 1) - removed.begin());
}

std::vector<std::uint32_t> indices_after_removal(const std::vector<char>& removed) {
  std::vector<std::uint32_t> new_index(removed.size());
  std::uint32_t kept = 0;
  for (std::size_t i = 0; i < removed.size(); ++i) {
    new_index[i] = kept;
    kept += removed[i] ? 0 : 1;
  }
  return new_index;
}

void ParticleStore::permute(const std::vector<std::size_t>& order) {
  assert(order.size() == size());
  for_each_array(*this, [&](auto& array, std::size_t stride) {
    auto copy = array;
    for (std::size_t k = 0; k < order.size(); ++k)
      for (std::size_t c = 0; c < stride; ++c) array[stride * k + c] = copy[stride * order[k] + c];
  });
  layout_epoch += 1;
}

std::size_t ParticleStore::register_custom(const std::string& name, std::uint32_t components,
                                           double initial, const std::string& unit) {
  if (components == 0) throw std::invalid_argument("custom property '" + name + "' needs at least one component");
  const std::size_t existing = find_custom(name);
  if (existing < custom.size()) {
    if (custom[existing].components != components)
      throw std::invalid_argument("custom property '" + name + "' is registered with " +
                                  std::to_string(custom[existing].components) + " components, not " +
                                  std::to_string(components));
    return existing;
  }
  custom.push_back({name, unit, components, initial, std::vector<double>(size() * components, initial)});
  return custom.size() - 1;
}

std::size_t ParticleStore::find_custom(const std::string& name) const {
  for (std::size_t k = 0; k < custom.size(); ++k)
    if (custom[k].name == name) return k;
  return custom.size();
}

void ParticleStore::reserve(std::size_t n) {
  for_each_array(*this, [&](auto& array, std::size_t stride) { array.reserve(n * stride); });
}

void ParticleStore::enable_external_loads() {
  external_loads_enabled = true;
  external_force.resize(size());
  external_torque.resize(size());
  external_force_once.resize(size());
  external_torque_once.resize(size());
}

void ParticleStore::clear() {
  for_each_array(*this, [&](auto& array, std::size_t) { array.clear(); });
  held_loads = once_loads = 0;
  once_in_forces = false;
  layout_epoch += 1;
}

}  // namespace quarry
