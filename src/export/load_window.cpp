// Export-interval means of the surface loads: time integrals of the per-step forces divided by
// the interval length (a rectangle rule with the step's dt, exact for the piecewise-constant
// forces of an explicit DEM step).
#include "export/load_window.h"

#include <stdexcept>

namespace quarry::fem_export {

LoadWindow::LoadWindow(const Surface& surface)
    : force_impulse_(surface.triangle_count()),
      normal_impulse_(surface.triangle_count(), 0.0),
      shear_impulse_(surface.triangle_count()),
      nodal_impulse_(surface.vertex_count()) {}

void LoadWindow::accumulate(const Surface& surface, double dt) {
  if (surface.triangle_force.size() != force_impulse_.size() ||
      surface.vertex_force.size() != nodal_impulse_.size())
    throw std::logic_error("LoadWindow::accumulate: surface '" + surface.name +
                           "' changed size since the export started");
  for (std::size_t t = 0; t < force_impulse_.size(); ++t) {
    const Vec3& force = surface.triangle_force[t];
    const Vec3& normal = surface.triangle_normals[t];
    // Particles on the front side push the element along −normal: that part is the pressure,
    // the remainder the shear (same split as Surface::accumulate_window).
    const double compressive = -dot(force, normal);
    force_impulse_[t] += force * dt;
    normal_impulse_[t] += compressive * dt;
    shear_impulse_[t] += (force + normal * compressive) * dt;
  }
  for (std::size_t n = 0; n < nodal_impulse_.size(); ++n)
    nodal_impulse_[n] += surface.vertex_force[n] * dt;
  duration_ += dt;
}

void LoadWindow::take_means(const Surface& surface, double time, LoadFrame& frame) {
  const std::size_t elements = force_impulse_.size();
  frame.time = time;
  frame.duration = duration_;
  frame.pressure.assign(elements, 0.0);
  frame.shear_stress.assign(elements, {});
  frame.force.assign(elements, {});
  frame.nodal_force.assign(nodal_impulse_.size(), {});
  if (duration_ > 0.0) {
    for (std::size_t t = 0; t < elements; ++t) {
      frame.force[t] = force_impulse_[t] / duration_;
      const double area = surface.triangle_areas[t];  // m²
      if (area > 0.0) {
        frame.pressure[t] = normal_impulse_[t] / duration_ / area;
        frame.shear_stress[t] = shear_impulse_[t] / duration_ / area;
      }
    }
    for (std::size_t n = 0; n < nodal_impulse_.size(); ++n)
      frame.nodal_force[n] = nodal_impulse_[n] / duration_;
  }
  for (auto& v : force_impulse_) v = {};
  for (auto& v : normal_impulse_) v = 0.0;
  for (auto& v : shear_impulse_) v = {};
  for (auto& v : nodal_impulse_) v = {};
  duration_ = 0.0;
}

}  // namespace quarry::fem_export
