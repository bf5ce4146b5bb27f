// Prescribed surface motion (translation, rotation about an axis, sinusoidal vibration),
// applied in step stage 2 ("move prescribed geometry") from the reference vertices, so that
// positions never accumulate round-off over millions of steps.
#pragma once

#include "core/simulation_spec.h"
#include "geometry/surface.h"

namespace quarry {

// Sets surface.vertices and surface.vertex_velocities for time `time` (s) from
// surface.reference_vertices, then recomputes normals and areas. With τ = clamp(t, start, stop)
// − start: translation x = x0 + v τ; rotation by angle ω τ about the axis through axis_point
// along axis_direction (Rodrigues), velocity ω × r; vibration x = x0 + A sin(2π f τ), velocity
// 2π f A cos(2π f τ). Outside [start, stop] the surface holds the pose of the nearest end with
// zero velocity; MotionKind::none gives the reference pose at rest. Throws UserError (at the
// deck location) for a zero rotation axis or a stop time before the start time. Cost: O(vertices).
void apply_motion(const MotionSpec& motion, double time, Surface& surface);

// Upper bound of any vertex speed over all times (m/s): |v|, |ω|·(largest distance of a reference
// vertex from the axis), or 2π f |A|; 0 for no motion. For neighbour-list rebuild checks.
double max_vertex_speed(const MotionSpec& motion, const Surface& surface);

}  // namespace quarry
