// Generates the tipper body of a mining dump truck at model scale (SI metres): floor with a
// rising tail, flared side walls and a forward-leaning front wall. Two outputs of one geometry:
//   generate_truck_bed examples/truck_bed/truck_bed.stl
//       the rigid bed of the flagship: ~25 mm cells, two triangles each, normals into the bed;
//   generate_truck_bed --shells examples/truck_bed_two_way/truck_bed_shells.bdf
//       the steel bed of the two-way flagship as OptiStruct/Nastran bulk data: ~36 mm CQUAD4
//       shells (about a coarse particle's diameter; 50 mm up the walls), a 4 mm floor and 3 mm
//       walls of S355 steel pinned on two chassis rails, coupled through an EDEM card;
//   generate_truck_bed --full-scale bench/truck_bed_full/truck_bed_full.stl
//       the same body at full size (× 4.6: 5.5 m long, 3.2 m floor, 1.6 m walls) in 8,630
//       triangles, about the 8,650 elements of seed 002's bed (issue 21's full-scale benchmark).
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <stdexcept>
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

// Cells per panel. The side-wall rows must land on front-wall rows (side_height / side =
// front_height / front, so side : front = 7 : 9) for the seams to share nodes.
struct Cells {
  int flat_x, tail_x, across, side_height, front_height;
  int along_x() const { return flat_x + tail_x; }
};
constexpr Cells stl_cells{36, 10, 26, 14, 18};  // about 25 mm squares
constexpr Cells shell_cells{26, 7, 19, 7, 9};   // 36.5 / 35.7 / 36.8 mm in plan, 50 mm up the walls
// Full scale: the model's coordinates × 4.6, cells of about 90 mm in plan (115 mm up the walls).
constexpr double full_scale = 4.6;
constexpr Cells full_scale_cells{48, 13, 33, 14, 18};

enum class Panel { floor, wall };

// One cell: corners a, b, c, d around it; `flip`: the order a, d, c, b is the one whose normal
// points into the bed (towards the ore).
struct Quad {
  std::array<Vec3, 4> corners;
  bool flip;
  Panel panel;
};

class BedMesher {
 public:
  explicit BedMesher(const Cells& cells, double scale = 1.0) : cells_(cells), scale_(scale) {}

  std::vector<Quad> quads() const {
    std::vector<Quad> out;
    // Floor: rows follow the side walls' flare so the floor edge lies on the side-wall planes.
    auto floor_node = [this](int i, int k) {
      const double z = floor_z(i);
      return Vec3{node_x(i), (-1.0 + 2.0 * k / cells_.across) * wall_half_width(z), z};
    };
    const Vec3 flat_inward{0, 0, 1};
    const Vec3 tail_inward{-std::sin(tail_rise), 0, std::cos(tail_rise)};
    for (int i = 0; i < cells_.along_x(); ++i)
      for (int k = 0; k < cells_.across; ++k)
        add(out, {floor_node(i, k), floor_node(i + 1, k), floor_node(i + 1, k + 1), floor_node(i, k + 1)},
            i < cells_.flat_x ? flat_inward : tail_inward, Panel::floor);

    // Side walls: planes y = ±wall_half_width(z), from the floor edge up to side_height, from the
    // leaning front wall (x = −z tan(front_lean)) to the open rear (x = 1.2). The front column is
    // sheared onto the front wall and the shear fades out by the start of the tail.
    for (const double side : {-1.0, 1.0}) {
      auto wall_node = [this, side](int i, int j) {
        const double bottom = floor_z(i);
        const double z = bottom + (side_height - bottom) * j / cells_.side_height;
        const double shear = i <= cells_.flat_x ? 1.0 - static_cast<double>(i) / cells_.flat_x : 0.0;
        return Vec3{node_x(i) - z * std::tan(front_lean) * shear, side * wall_half_width(z), z};
      };
      const Vec3 inward{0, -side, std::tan(side_flare)};
      for (int i = 0; i < cells_.along_x(); ++i)
        for (int j = 0; j < cells_.side_height; ++j)
          add(out, {wall_node(i, j), wall_node(i + 1, j), wall_node(i + 1, j + 1), wall_node(i, j + 1)}, inward,
              Panel::wall);
    }

    // Front wall: plane x = −z tan(front_lean), as wide as the flared side walls at each height,
    // rising above them to front_height (a headboard).
    auto front_node = [this](int k, int j) {
      const double z = front_height * j / cells_.front_height;
      return Vec3{-z * std::tan(front_lean), (-1.0 + 2.0 * k / cells_.across) * wall_half_width(z), z};
    };
    const Vec3 front_inward{1, 0, std::tan(front_lean)};
    for (int k = 0; k < cells_.across; ++k)
      for (int j = 0; j < cells_.front_height; ++j)
        add(out, {front_node(k, j), front_node(k + 1, j), front_node(k + 1, j + 1), front_node(k, j + 1)},
            front_inward, Panel::wall);
    return out;
  }

 private:
  double node_x(int i) const {  // m, floor node i along the bed
    return i <= cells_.flat_x ? flat_floor_length * i / cells_.flat_x
                              : flat_floor_length + tail_length * (i - cells_.flat_x) / cells_.tail_x;
  }
  double floor_z(int i) const {  // m, floor height at node i
    return i <= cells_.flat_x ? 0.0 : tail_length * (i - cells_.flat_x) / cells_.tail_x * std::tan(tail_rise);
  }
  static double wall_half_width(double z) { return half_width + z * std::tan(side_flare); }  // m, at height z

  void add(std::vector<Quad>& out, const std::array<Vec3, 4>& q, const Vec3& inward, Panel panel) const {
    out.push_back({{q[0] * scale_, q[1] * scale_, q[2] * scale_, q[3] * scale_},
                   dot(cross(q[1] - q[0], q[2] - q[0]), inward) <= 0.0, panel});
  }

  Cells cells_;
  double scale_;  // multiplies every coordinate (the model's numbers above are at scale 1)
};

// Two triangles per cell, wound into the bed.
std::vector<Vec3> triangle_soup(const std::vector<Quad>& quads) {
  std::vector<Vec3> corners;
  for (const Quad& q : quads) {
    const auto& [a, b, c, d] = q.corners;
    if (q.flip)
      corners.insert(corners.end(), {a, c, b, a, d, c});
    else
      corners.insert(corners.end(), {a, b, c, a, c, d});
  }
  return corners;
}

void write_stl(const std::string& path, const BedMesher& mesher) {
  // Seams computed by different formulas agree to round-off; 0.1 µm welds them for certain
  // before the float32 rounding of the file could separate them.
  const quarry::Surface bed =
      quarry::surface_from_triangle_soup(triangle_soup(mesher.quads()), "truck_bed", 1e-7);
  quarry::write_stl_binary(path, bed);
  std::printf("wrote %s: %zu triangles, %zu vertices\n", path.c_str(), bed.triangle_count(), bed.vertex_count());
}

// The steel of the two-way bed (SI units; the model says so with DTI,UNITS).
constexpr double floor_thickness = 0.004, wall_thickness = 0.003;  // m
constexpr double youngs_modulus = 2.1e11, poisson_ratio = 0.3, density = 7850.0;  // Pa, -, kg/m³
constexpr double yield_stress = 355e6, hardening = 1.0e9;  // Pa: S355, a bilinear hardening slope
// Chassis rails under the flat floor: the floor nodes with 0.14 ≤ |y| ≤ 0.26 m, pinned
// (translations fixed), the supports of the one-way export in examples/truck_bed.
constexpr double rail_inner = 0.14, rail_outer = 0.26;  // m
// Coupling PERIOD (s): about two DEM steps of the flagship (9.37e-5 s), the seed's minimum. The
// staggered exchange lags the bed's loads by a period, which drives the bed's modes of a few
// periods through the ore's contacts; the deck's damping holds it (docs/fem.md "Damping the
// structure").
constexpr double coupling_period = 2.0e-4;

void write_shells(const std::string& path) {
  const std::vector<Quad> quads = BedMesher(shell_cells).quads();
  // The cell's triangles (a, b, c) and (a, c, d), welded: their indices give the quad's nodes.
  std::vector<Vec3> soup;
  for (const Quad& q : quads) soup.insert(soup.end(), {q.corners[0], q.corners[1], q.corners[2], q.corners[0],
                                                       q.corners[2], q.corners[3]});
  const quarry::WeldedMesh mesh = quarry::weld_triangle_soup(soup, 1e-7);

  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw std::runtime_error("cannot write " + path);
  std::fprintf(file,
               "$ The steel tipper body of examples/truck_bed_two_way, written by generate_truck_bed --shells\n"
               "$ (examples/truck_bed/generate_truck_bed.cpp: edit it there, not here). SI units.\n"
               "$ %zu CQUAD4 of about 36 mm (50 mm up the walls): PSHELL 1 the 4 mm floor, PSHELL 2 the\n"
               "$ 3 mm side and front walls; S355 steel (MAT1 + MATS1, bilinear hardening); the floor\n"
               "$ nodes over the two chassis rails (0.14 <= |y| <= 0.26 m) pinned by SPC1 set 1; every\n"
               "$ element on SURF 2, coupled to the particles by the EDEM card (PERIOD 2e-4 s).\n"
               "BEGIN BULK\nDTI,UNITS,1,KG,N,M,S\n",
               quads.size());
  for (std::size_t n = 0; n < mesh.vertices.size(); ++n) {
    const Vec3& x = mesh.vertices[n];
    std::fprintf(file, "GRID,%zu,,%.9g,%.9g,%.9g\n", n + 1, x.x, x.y, x.z);
  }
  for (std::size_t e = 0; e < quads.size(); ++e) {
    const auto& first = mesh.triangles[2 * e];
    std::array<std::uint32_t, 4> nodes{first[0], first[1], first[2], mesh.triangles[2 * e + 1][2]};
    if (quads[e].flip) std::swap(nodes[1], nodes[3]);  // a, d, c, b: normal into the bed
    std::fprintf(file, "CQUAD4,%zu,%d,%u,%u,%u,%u\n", e + 1, quads[e].panel == Panel::floor ? 1 : 2,
                 nodes[0] + 1, nodes[1] + 1, nodes[2] + 1, nodes[3] + 1);
  }
  std::fprintf(file, "PSHELL,1,1,%.9g,1,,1\nPSHELL,2,1,%.9g,1,,1\n", floor_thickness, wall_thickness);
  std::fprintf(file, "MAT1,1,%.9g,,%.9g,%.9g\n", youngs_modulus, poisson_ratio, density);
  std::fprintf(file, "MATS1,1,,PLASTIC,%.9g,1,1,%.9g\n", hardening, yield_stress);
  std::size_t pinned = 0;
  for (std::size_t n = 0; n < mesh.vertices.size(); ++n) {
    const Vec3& x = mesh.vertices[n];
    if (std::abs(x.z) < 1e-9 && std::abs(x.y) >= rail_inner && std::abs(x.y) <= rail_outer) {
      std::fprintf(file, "SPC1,1,123,%zu\n", n + 1);
      ++pinned;
    }
  }
  std::fprintf(file, "SURF,2,ELEM,LIST\n,1,THRU,%zu\n", quads.size());
  std::fprintf(file, "EDEM,100,CONTROL,%.9g,,COUPLING,SURF,2,truck_bed\nENDDATA\n", coupling_period);
  if (std::fclose(file) != 0) throw std::runtime_error("cannot write " + path);
  std::printf("wrote %s: %zu CQUAD4, %zu GRID, %zu pinned on the rails\n", path.c_str(), quads.size(),
              mesh.vertices.size(), pinned);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string first = argc > 1 ? argv[1] : "truck_bed.stl";
    if (first == "--shells")
      write_shells(argc > 2 ? argv[2] : "truck_bed_shells.bdf");
    else if (first == "--full-scale")
      write_stl(argc > 2 ? argv[2] : "truck_bed_full.stl", BedMesher(full_scale_cells, full_scale));
    else
      write_stl(first, BedMesher(stl_cells));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "generate_truck_bed: %s\n", error.what());
    return 1;
  }
  return 0;
}
