// LoadWindow: the time mean of a surface's contact loads over an interval — per element force,
// compressive normal stress (pressure) and shear-stress vector, per node the consistent nodal
// force. One type for the output frames, the FEM load export and the coupling interface: each
// owns a window over its own interval, all fed from the per-step loads of Surface.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

// Means over one window. Element e = element e of the input mesh, node n = vertex n.
struct LoadFrame {
  double time = 0.0;                // s, end of the window
  double duration = 0.0;            // s, time the means are taken over
  std::vector<double> pressure;     // Pa, compressive normal stress per element
  std::vector<Vec3> shear_stress;   // Pa, tangential traction per element
  std::vector<Vec3> force;          // N, force of the particles on each element
  std::vector<Vec3> nodal_force;    // N, barycentric (consistent) nodal force per node
};

// Impulses (∫ load dt) since the window started. Means are impulse / duration: the rectangle
// rule with each step's dt, exact for the piecewise-constant forces of an explicit step, so a
// partner that takes the means every window receives exactly the momentum the particles gave.
// Plain data (checkpoints save the arrays as they are).
struct LoadWindow {
  // Element of each triangle of the surface (input order); empty: element = triangle. A quad
  // of the input mesh is two triangles of one element.
  std::vector<std::uint32_t> element_of_triangle;
  std::vector<Vec3> force_impulse;       // N·s per element
  std::vector<double> normal_impulse;    // N·s per element, compressive (along −normal)
  std::vector<Vec3> shear_impulse;       // N·s per element
  std::vector<Vec3> nodal_impulse;       // N·s per node
  double duration = 0.0;                 // s

  LoadWindow() = default;
  // Sized to `surface`'s mesh with `element_count` elements (0: one per triangle), empty.
  // Cost: O(elements + vertices) memory.
  explicit LoadWindow(const Surface& surface, std::vector<std::uint32_t> element_of_triangle = {},
                      std::size_t element_count = 0);

  bool sized() const { return !nodal_impulse.empty() || !force_impulse.empty(); }
  std::size_t element_count() const { return force_impulse.size(); }

  // Adds this step's loads × dt (s): surface.triangle_force and surface.vertex_force as the
  // particle–surface stage filled them, at the triangles and vertices it marked. Pre: the mesh
  // has the sizes given at construction (throws std::logic_error otherwise); its loads are
  // marked (Surface::add_contact_load or mark_step_loads). Cost: O(loaded entries + mesh / 64).
  void accumulate(const Surface& surface, double dt);

  // The means since the window started into `frame` (time = `time`, s), then restarts the
  // window. Element areas are those of `surface` now (sum of an element's triangles). An empty
  // window gives zero loads and duration 0.
  void take_means(const Surface& surface, double time, LoadFrame& frame);
  void clear();
};

}  // namespace quarry
