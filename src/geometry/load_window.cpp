// Window means of the surface loads: time integrals of the per-step forces divided by the
// window length (a rectangle rule with the step's dt, exact for the piecewise-constant forces
// of an explicit DEM step).
#include "geometry/load_window.h"

#include <stdexcept>

namespace quarry {

LoadWindow::LoadWindow(const Surface& surface, std::vector<std::uint32_t> element_of,
                       std::size_t element_count)
    : element_of_triangle(std::move(element_of)) {
  const std::size_t elements = element_count > 0 ? element_count : surface.triangle_count();
  force_impulse.assign(elements, {});
  normal_impulse.assign(elements, 0.0);
  shear_impulse.assign(elements, {});
  nodal_impulse.assign(surface.vertex_count(), {});
}

void LoadWindow::accumulate(const Surface& surface, double dt) {
  const bool mapped = !element_of_triangle.empty();
  if (surface.vertex_force.size() != nodal_impulse.size() ||
      (mapped ? element_of_triangle.size() != surface.triangle_force.size()
              : surface.triangle_force.size() != force_impulse.size()))
    throw std::logic_error("LoadWindow::accumulate: surface '" + surface.name +
                           "' changed size since the window was made");
  // Only the triangles and vertices a contact loaded this step (Surface::loaded_triangles,
  // ascending: an element of two triangles adds them in order). A marked one whose load came
  // to exactly 0 adds nothing either, as an unmarked one: x + 0 = x for every impulse the sums
  // can hold, but −0 + 0 = +0.
  for_each_loaded(surface.loaded_triangles, [&](std::uint32_t t) {
    const Vec3& force = surface.triangle_force[t];
    if (force.x == 0.0 && force.y == 0.0 && force.z == 0.0) return;
    const std::size_t e = mapped ? element_of_triangle[t] : t;
    const Vec3& normal = surface.triangle_normals[t];
    // Particles on the front side push the element along −normal: that part is the pressure,
    // the remainder the shear.
    const double compressive = -dot(force, normal);
    force_impulse[e] += force * dt;
    normal_impulse[e] += compressive * dt;
    shear_impulse[e] += (force + normal * compressive) * dt;
  });
  for_each_loaded(surface.loaded_vertices, [&](std::uint32_t n) {
    const Vec3& force = surface.vertex_force[n];
    if (force.x == 0.0 && force.y == 0.0 && force.z == 0.0) return;
    nodal_impulse[n] += force * dt;
  });
  duration += dt;
}

void LoadWindow::take_means(const Surface& surface, double time, LoadFrame& frame) {
  const std::size_t elements = force_impulse.size();
  frame.time = time;
  frame.duration = duration;
  frame.pressure.assign(elements, 0.0);
  frame.shear_stress.assign(elements, {});
  frame.force.assign(elements, {});
  frame.nodal_force.assign(nodal_impulse.size(), {});
  if (duration > 0.0) {
    std::vector<double> area(elements, 0.0);  // m²
    for (std::size_t t = 0; t < surface.triangle_areas.size(); ++t)
      area[element_of_triangle.empty() ? t : element_of_triangle[t]] += surface.triangle_areas[t];
    for (std::size_t e = 0; e < elements; ++e) {
      frame.force[e] = force_impulse[e] / duration;
      if (area[e] > 0.0) {
        frame.pressure[e] = normal_impulse[e] / duration / area[e];
        frame.shear_stress[e] = shear_impulse[e] / duration / area[e];
      }
    }
    for (std::size_t n = 0; n < nodal_impulse.size(); ++n) frame.nodal_force[n] = nodal_impulse[n] / duration;
  }
  clear();
}

void LoadWindow::clear() {
  for (auto& v : force_impulse) v = {};
  for (auto& v : normal_impulse) v = 0.0;
  for (auto& v : shear_impulse) v = {};
  for (auto& v : nodal_impulse) v = {};
  duration = 0.0;
}

}  // namespace quarry
