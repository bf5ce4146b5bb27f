// LoadWindow::accumulate: the impulses are Σ load × dt per element and node, the rectangle rule
// of the explicit step (load_window.h). Checked to the bit against that sum written out, for a
// mesh where most triangles and vertices carry nothing in a step (the window skips them), with
// loads of mixed signs, signed zeros and elements of two triangles.
#include "geometry/load_window.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "geometry/primitives.h"

namespace quarry {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

TEST(LoadWindow, ImpulsesAreTheSumOfLoadTimesStepToTheBit) {
  Surface surface = make_box({0, 0, 0}, {1, 1, 1}, 3);  // 108 triangles
  surface.reset_loads();
  const std::size_t triangles = surface.triangle_count(), vertices = surface.vertex_count();
  std::vector<std::uint32_t> element_of_triangle(triangles);
  for (std::size_t t = 0; t < triangles; ++t) element_of_triangle[t] = static_cast<std::uint32_t>(t / 2);
  LoadWindow window(surface, element_of_triangle, triangles / 2);
  std::vector<Vec3> force(triangles / 2), shear(triangles / 2), nodal(vertices);
  std::vector<double> normal(triangles / 2);
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> load(-3.0, 3.0);  // N
  std::uniform_int_distribution<int> pick(0, 9);
  const auto draw = [&]() -> Vec3 {
    switch (pick(random)) {
      case 0: return {load(random), load(random), load(random)};
      case 1: return {-0.0, 0.0, -0.0};     // touched by nothing, a signed zero
      case 2: return {0.0, load(random), -0.0};  // one component only
      default: return {};
    }
  };
  for (int step = 0; step < 200; ++step) {
    const double dt = 1e-5 * (1.0 + 0.1 * (step % 7));  // s
    for (std::size_t t = 0; t < triangles; ++t) surface.triangle_force[t] = draw();
    for (std::size_t n = 0; n < vertices; ++n) surface.vertex_force[n] = draw();
    surface.mark_step_loads();
    window.accumulate(surface, dt);
    for (std::size_t t = 0; t < triangles; ++t) {  // the sums written out, every triangle
      const Vec3 f = surface.triangle_force[t], n = surface.triangle_normals[t];
      const double compressive = -dot(f, n);
      const std::size_t e = element_of_triangle[t];
      force[e] += f * dt;
      normal[e] += compressive * dt;
      shear[e] += (f + n * compressive) * dt;
    }
    for (std::size_t v = 0; v < vertices; ++v) nodal[v] += surface.vertex_force[v] * dt;
  }
  for (std::size_t e = 0; e < force.size(); ++e) {
    EXPECT_TRUE(same_bits(window.force_impulse[e], force[e])) << "element " << e;
    EXPECT_TRUE(same_bits(window.normal_impulse[e], normal[e])) << "element " << e;
    EXPECT_TRUE(same_bits(window.shear_impulse[e], shear[e])) << "element " << e;
  }
  for (std::size_t v = 0; v < vertices; ++v) EXPECT_TRUE(same_bits(window.nodal_impulse[v], nodal[v])) << "node " << v;
}

// The contact stage's way: contacts added one by one (Surface::add_contact_load, triangles in
// any order and repeated, each marked), the window fed from the marks; the clearing then zeroes
// what was marked. The impulses are those of a window fed from every triangle and vertex
// (mark_step_loads after writing the same loads), to the bit, over steps that load different
// parts of the mesh (an element of two triangles loaded by both, in either order).
TEST(LoadWindow, ContactsMarkedAsAddedGiveTheImpulsesOfTheWholeMesh) {
  Surface marked = make_box({0, 0, 0}, {1, 1, 1}, 3);
  marked.reset_loads();
  Surface whole = marked;
  const std::size_t triangles = marked.triangle_count();
  std::vector<std::uint32_t> element_of_triangle(triangles);
  for (std::size_t t = 0; t < triangles; ++t)
    element_of_triangle[t] = static_cast<std::uint32_t>(t / 2);
  LoadWindow from_marks(marked, element_of_triangle, triangles / 2);
  LoadWindow from_all(whole, element_of_triangle, triangles / 2);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> load(-3.0, 3.0), weight(0.0, 1.0);
  std::uniform_int_distribution<std::uint32_t> triangle(0,
                                                       static_cast<std::uint32_t>(triangles - 1));
  for (int step = 0; step < 50; ++step) {
    marked.clear_step_loads();
    whole.triangle_force.assign(triangles, {});
    whole.vertex_force.assign(whole.vertex_count(), {});
    for (int c = 0; c < 12; ++c) {  // contacts, some on the same triangle or element
      const std::uint32_t t = triangle(random);
      const Vec3 reaction{load(random), load(random), load(random)};  // N
      const double a = weight(random), b = (1.0 - a) * weight(random);
      const std::array<double, 3> w{a, b, 1.0 - a - b};
      const Vec3 point{weight(random), weight(random), weight(random)};  // m
      marked.add_contact_load(t, reaction, w, point);
      whole.triangle_force[t] += reaction;
      for (int k = 0; k < 3; ++k) whole.vertex_force[whole.triangles[t][k]] += reaction * w[k];
    }
    whole.mark_step_loads();
    from_marks.accumulate(marked, 1e-5);
    from_all.accumulate(whole, 1e-5);
  }
  const LoadWindow &a = from_marks, &b = from_all;
  for (std::size_t e = 0; e < triangles / 2; ++e) {
    EXPECT_TRUE(same_bits(a.force_impulse[e], b.force_impulse[e])) << "element " << e;
    EXPECT_TRUE(same_bits(a.normal_impulse[e], b.normal_impulse[e])) << "element " << e;
    EXPECT_TRUE(same_bits(a.shear_impulse[e], b.shear_impulse[e])) << "element " << e;
  }
  for (std::size_t n = 0; n < marked.vertex_count(); ++n)
    EXPECT_TRUE(same_bits(a.nodal_impulse[n], b.nodal_impulse[n])) << "vertex " << n;
  marked.clear_step_loads();
  for (const Vec3& f : marked.triangle_force) EXPECT_EQ(f, Vec3{});
  for (const Vec3& f : marked.vertex_force) EXPECT_EQ(f, Vec3{});
  int marks = 0;
  for_each_loaded(marked.loaded_triangles, [&](std::uint32_t) { ++marks; });
  for_each_loaded(marked.loaded_vertices, [&](std::uint32_t) { ++marks; });
  EXPECT_EQ(marks, 0);
}

}  // namespace
}  // namespace quarry
