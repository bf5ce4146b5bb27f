// Sample points: Monte-Carlo points that stand for a particle's volume when it is shared out
// among the cells of a coupled CFD mesh (the EDEM CFD coupling interface's collectSamplePoints,
// "Using Sample Points to Represent Particles": solid volume in cell c = V_p · n_c / N).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"

namespace quarry::coupling {

// `count` points uniformly distributed inside the unit sphere (radius 1, centred at the origin).
// Candidates are drawn uniformly in the bounding cube [-1, 1)³ from Random(seed), x then y then z
// from successive uniform() draws, and those with |p|² ≤ 1 are kept, in order, until `count` are
// kept (acceptance π/6 ≈ 0.52, so about 5.7 draws a point). Only uniform() and exact arithmetic,
// so a seed gives the same points bit for bit on every platform, and the points for a smaller
// count are the first points for a larger one. Throws std::invalid_argument for count = 0.
std::vector<Vec3> sphere_sample_points(std::size_t count, std::uint64_t seed);

// World positions (m) of every particle's points, particle by particle:
//   out[p·N + k] = centres[p] + radii[p]·unit_points[k],  N = unit_points.size(),
// centres and radii in m. Throws std::invalid_argument unless radii.size() == centres.size()
// and out.size() == centres.size()·N.
void place_sample_points(std::span<const Vec3> unit_points, std::span<const Vec3> centres,
                         std::span<const double> radii, std::span<Vec3> out);

// Fraction n_c / N of the points that lie inside `box` (boundary included, as Aabb::contains):
// for one particle's N points, V_p times this is the particle's solid volume in the box (m³).
// Throws std::invalid_argument for no points (the fraction is undefined). Cost: O(N).
double fraction_inside(std::span<const Vec3> points, const Aabb& box);

}  // namespace quarry::coupling
