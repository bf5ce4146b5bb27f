// Surface bookkeeping: normals, areas, load accumulation and window averages.
#include "geometry/surface.h"

namespace quarry {

void Surface::update_normals_and_areas() {
  triangle_normals.resize(triangles.size());
  triangle_areas.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& a = vertices[triangles[t][0]];
    const Vec3& b = vertices[triangles[t][1]];
    const Vec3& c = vertices[triangles[t][2]];
    const Vec3 n = cross(b - a, c - a);
    const double twice_area = norm(n);
    triangle_areas[t] = 0.5 * twice_area;
    triangle_normals[t] = twice_area > 0.0 ? n / twice_area : Vec3{};
  }
}

void Surface::reset_loads() {
  triangle_force.assign(triangles.size(), {});
  vertex_force.assign(vertices.size(), {});
  window_force_impulse.assign(triangles.size(), {});
  window_normal_impulse.assign(triangles.size(), 0.0);
  window_shear_impulse.assign(triangles.size(), {});
  window_time = 0.0;
  total_force = {};
  total_torque = {};
  if (vertex_velocities.size() != vertices.size()) vertex_velocities.assign(vertices.size(), {});
}

void Surface::clear_step_loads() {
  for (auto& f : triangle_force) f = {};
  for (auto& f : vertex_force) f = {};
  total_force = {};
  total_torque = {};
}

void Surface::accumulate_window(double dt) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& f = triangle_force[t];
    // Particles push the wall along −normal when they sit on its front side; the pressure
    // is the compressive normal component, the shear the remainder.
    const double fn = -dot(f, triangle_normals[t]);
    window_force_impulse[t] += f * dt;
    window_normal_impulse[t] += fn * dt;
    window_shear_impulse[t] += (f + triangle_normals[t] * fn) * dt;
  }
  window_time += dt;
}

void Surface::window_means(std::vector<double>& pressure, std::vector<Vec3>& shear,
                           std::vector<Vec3>& force) const {
  pressure.assign(triangles.size(), 0.0);
  shear.assign(triangles.size(), {});
  force.assign(triangles.size(), {});
  if (window_time <= 0.0) return;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    force[t] = window_force_impulse[t] / window_time;
    if (triangle_areas[t] > 0.0) {
      pressure[t] = window_normal_impulse[t] / window_time / triangle_areas[t];
      shear[t] = window_shear_impulse[t] / window_time / triangle_areas[t];
    }
  }
}

void Surface::clear_window() {
  for (auto& v : window_force_impulse) v = {};
  for (auto& v : window_normal_impulse) v = 0.0;
  for (auto& v : window_shear_impulse) v = {};
  window_time = 0.0;
}

Aabb Surface::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.expand(v);
  return box;
}

}  // namespace quarry
