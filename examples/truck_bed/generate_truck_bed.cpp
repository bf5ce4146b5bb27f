// Generates truck_bed.stl: the tipper body of a mining dump truck at model scale (SI metres),
// floor with a rising tail, flared side walls and a forward-leaning front wall, normals into
// the bed. Run once: generate_truck_bed examples/truck_bed/truck_bed.stl
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

#include "geometry/stl_reader.h"
#include "geometry/vertex_welder.h"

namespace {

using quarry::Vec3;

constexpr double degree = std::numbers::pi / 180.0;  // rad
// Geometry (m, rad); README.md and truck_bed_test.cpp describe the same numbers.
constexpr double flat_floor_length = 0.95;   // m, x from 0
constexpr double tail_length = 0.25;         // m, plan length of the rising tail (x to 1.2)
constexpr double tail_rise = 12.0 * degree;  // rad
constexpr double half_width = 0.35;          // m, floor half-width (y = ±0.35)
constexpr double side_height = 0.35;         // m, top of the side walls above the floor
constexpr double front_height = 0.45;        // m, top of the front wall
constexpr double side_flare = 10.0 * degree;   // rad, side walls lean outwards from vertical
constexpr double front_lean = 15.0 * degree;   // rad, front wall top leans forward (−x)
// Cells: about 25 mm squares; 14 and 18 rows put the side-wall top on a front-wall row.
constexpr int cells_flat_x = 36, cells_tail_x = 10, cells_across = 26;
constexpr int cells_side_height = 14, cells_front_height = 18;
constexpr int cells_along_x = cells_flat_x + cells_tail_x;

double node_x(int i) {  // m, floor node i along the bed
  return i <= cells_flat_x ? flat_floor_length * i / cells_flat_x
                           : flat_floor_length + tail_length * (i - cells_flat_x) / cells_tail_x;
}
double floor_z(int i) {  // m, floor height at node i
  return i <= cells_flat_x ? 0.0 : tail_length * (i - cells_flat_x) / cells_tail_x * std::tan(tail_rise);
}
double wall_half_width(double z) { return half_width + z * std::tan(side_flare); }  // m, at height z

// Appends the quad (a, b, c, d) as two triangles wound so that their normal has a positive
// component along `inward` (towards the ore).
void append_quad(std::vector<Vec3>& corners, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                 const Vec3& inward) {
  if (dot(cross(b - a, c - a), inward) > 0.0)
    corners.insert(corners.end(), {a, b, c, a, c, d});
  else
    corners.insert(corners.end(), {a, c, b, a, d, c});
}

std::vector<Vec3> truck_bed_soup() {
  std::vector<Vec3> corners;
  // Floor: rows follow the side walls' flare so the floor edge lies on the side-wall planes.
  auto floor_node = [](int i, int k) {
    const double z = floor_z(i);
    return Vec3{node_x(i), (-1.0 + 2.0 * k / cells_across) * wall_half_width(z), z};
  };
  const Vec3 flat_inward{0, 0, 1};
  const Vec3 tail_inward{-std::sin(tail_rise), 0, std::cos(tail_rise)};
  for (int i = 0; i < cells_along_x; ++i)
    for (int k = 0; k < cells_across; ++k)
      append_quad(corners, floor_node(i, k), floor_node(i + 1, k), floor_node(i + 1, k + 1), floor_node(i, k + 1),
                  i < cells_flat_x ? flat_inward : tail_inward);

  // Side walls: planes y = ±wall_half_width(z), from the floor edge up to side_height, from the
  // leaning front wall (x = −z tan(front_lean)) to the open rear (x = 1.2). The front column is
  // sheared onto the front wall and the shear fades out by the start of the tail.
  for (const double side : {-1.0, 1.0}) {
    auto wall_node = [side](int i, int j) {
      const double bottom = floor_z(i);
      const double z = bottom + (side_height - bottom) * j / cells_side_height;
      const double shear = i <= cells_flat_x ? 1.0 - static_cast<double>(i) / cells_flat_x : 0.0;
      return Vec3{node_x(i) - z * std::tan(front_lean) * shear, side * wall_half_width(z), z};
    };
    const Vec3 inward{0, -side, std::tan(side_flare)};
    for (int i = 0; i < cells_along_x; ++i)
      for (int j = 0; j < cells_side_height; ++j)
        append_quad(corners, wall_node(i, j), wall_node(i + 1, j), wall_node(i + 1, j + 1), wall_node(i, j + 1), inward);
  }

  // Front wall: plane x = −z tan(front_lean), as wide as the flared side walls at each height,
  // rising above them to front_height (a headboard).
  auto front_node = [](int k, int j) {
    const double z = front_height * j / cells_front_height;
    return Vec3{-z * std::tan(front_lean), (-1.0 + 2.0 * k / cells_across) * wall_half_width(z), z};
  };
  const Vec3 front_inward{1, 0, std::tan(front_lean)};
  for (int k = 0; k < cells_across; ++k)
    for (int j = 0; j < cells_front_height; ++j)
      append_quad(corners, front_node(k, j), front_node(k + 1, j), front_node(k + 1, j + 1), front_node(k, j + 1),
                  front_inward);
  return corners;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "truck_bed.stl";
  try {
    // Seams computed by different formulas agree to round-off; 0.1 µm welds them for certain
    // before the float32 rounding of the file could separate them.
    const quarry::Surface bed = quarry::surface_from_triangle_soup(truck_bed_soup(), "truck_bed", 1e-7);
    quarry::write_stl_binary(path, bed);
    std::printf("wrote %s: %zu triangles, %zu vertices\n", path.c_str(), bed.triangle_count(), bed.vertex_count());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "generate_truck_bed: %s\n", error.what());
    return 1;
  }
  return 0;
}
