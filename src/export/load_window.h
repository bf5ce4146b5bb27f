// LoadWindow: per-element and per-node load impulses of one exported surface, accumulated after
// the force stage of every step and turned into the time-averaged LoadFrame of each export
// interval (pressure, shear-stress vector, force vector per element; consistent nodal forces).
#pragma once

#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry::fem_export {

// Means over one export interval. Element e = triangle e of the input mesh, node n = vertex n.
struct LoadFrame {
  double time = 0.0;                // s, end of the interval
  double duration = 0.0;            // s, time the means are taken over
  std::vector<double> pressure;     // Pa, compressive normal stress per element
  std::vector<Vec3> shear_stress;   // Pa, tangential traction per element
  std::vector<Vec3> force;          // N, force of the particles on each element
  std::vector<Vec3> nodal_force;    // N, barycentric (consistent) nodal force per node
};

class LoadWindow {
 public:
  // Sized to `surface`'s mesh, empty. Cost: O(triangles + vertices) memory, nothing else.
  explicit LoadWindow(const Surface& surface);

  // Adds this step's loads × dt: surface.triangle_force and surface.vertex_force as filled by
  // the particle–surface stage. Pre: the mesh has the sizes given at construction; dt > 0 (s).
  // Cost: O(triangles + vertices).
  void accumulate(const Surface& surface, double dt);

  double duration() const { return duration_; }  // s accumulated since the last take
  bool empty() const { return duration_ <= 0.0; }

  // Writes the means since the last take into `frame` (time = `time`, s) and restarts the
  // window. Areas are those of `surface` now. An empty window gives zero loads, duration 0.
  void take_means(const Surface& surface, double time, LoadFrame& frame);

 private:
  std::vector<Vec3> force_impulse_;       // N·s per element
  std::vector<double> normal_impulse_;    // N·s per element, compressive (along −normal)
  std::vector<Vec3> shear_impulse_;       // N·s per element
  std::vector<Vec3> nodal_impulse_;       // N·s per node
  double duration_ = 0.0;                 // s
};

}  // namespace quarry::fem_export
