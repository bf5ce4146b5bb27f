// Closedness of a triangle mesh (edges counted by corner positions) and the inside test of a box
// lattice by +x rays: Shewchuk's (1997) orientation predicate, exact through expansion arithmetic
// behind a floating-point filter, with Simulation of Simplicity (Edelsbrunner & Mücke 1990) for
// rows through projected edges and vertices.
#include "geometry/closed_mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace quarry {

namespace {

// ---- exact arithmetic (Shewchuk 1997 §2): a + b and a·b as the rounded value plus its error ----

// Knuth's Two-Sum: x + y == a + b exactly, x = fl(a + b) (any order of magnitude).
void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// x + y == a·b exactly, x = fl(a·b) (the fused multiply-add gives the product's round-off).
void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// A nonoverlapping expansion (Shewchuk 1997 §2.3): its components, by increasing magnitude, sum
// exactly to the value; the largest carries its sign.
struct Expansion {
  std::array<double, 24> component{};
  int size = 0;

  // Grow-Expansion with zero elimination (Shewchuk 1997, Theorem 10).
  void add(double b) {
    double q = b;
    int kept = 0;
    for (int i = 0; i < size; ++i) {
      double sum = 0.0, error = 0.0;
      two_sum(q, component[static_cast<std::size_t>(i)], sum, error);
      if (error != 0.0) component[static_cast<std::size_t>(kept++)] = error;
      q = sum;
    }
    if (q != 0.0) component[static_cast<std::size_t>(kept++)] = q;
    size = kept;
  }
  int sign() const {
    if (size == 0) return 0;
    return component[static_cast<std::size_t>(size - 1)] > 0.0 ? 1 : -1;
  }
};

// Adds (x_hi + x_lo)(y_hi + y_lo)·factor (factor ±1) to `sum`, exactly.
void add_product(Expansion& sum, double x_hi, double x_lo, double y_hi, double y_lo, double factor) {
  for (const auto& [p, q] : {std::pair{x_hi, y_hi}, std::pair{x_hi, y_lo}, std::pair{x_lo, y_hi}, std::pair{x_lo, y_lo}}) {
    double product = 0.0, error = 0.0;
    two_product(p, q, product, error);
    sum.add(factor * product);
    sum.add(factor * error);
  }
}

// ---- rays along +x ----

// Sign of the orientation of (a, b, p) in the (y, z) plane with the row moved to (y + ε, z + ε²)
// (Simulation of Simplicity): the exact sign when it is not zero, otherwise that of the terms the
// perturbation adds, −(b_z − a_z) ε + (b_y − a_y) ε². Zero only when a and b project to one point.
int perturbed_sign(double a_y, double a_z, double b_y, double b_z, double p_y, double p_z) {
  const int exact = orientation_sign(a_y, a_z, b_y, b_z, p_y, p_z);
  if (exact != 0) return exact;
  if (b_z != a_z) return b_z < a_z ? 1 : -1;
  if (b_y != a_y) return b_y > a_y ? 1 : -1;
  return 0;
}

// (b − a) × (p − a) in the (y, z) plane, rounded: a barycentric weight of p.
double orientation_value(const Vec3& a, const Vec3& b, double p_y, double p_z) {
  return (b.y - a.y) * (p_z - a.z) - (b.z - a.z) * (p_y - a.y);
}

struct Crossing {
  std::uint32_t row = 0;  // j + ny·k
  double x = 0.0;         // m, where the row meets the triangle's plane
  int sign = 0;           // sign of the triangle's normal along x
};

// The crossings of the rows of `centres` with triangle (v0, v1, v2).
void cross_rows(const CellCentres& centres, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                std::vector<Crossing>& crossings) {
  const int ny = centres.count[1], nz = centres.count[2];
  // Rows whose centre could lie in the projection (one extra either way: the exact test decides).
  const auto row_range = [](double low, double high, double origin, double spacing, int count) {
    const double first = std::floor((low - origin) / spacing - 0.5);
    const double last = std::ceil((high - origin) / spacing - 0.5);
    return std::pair{static_cast<int>(std::clamp(first, 0.0, static_cast<double>(count))),
                     static_cast<int>(std::clamp(last, -1.0, static_cast<double>(count - 1)))};
  };
  const auto [j_first, j_last] = row_range(std::min({v0.y, v1.y, v2.y}), std::max({v0.y, v1.y, v2.y}),
                                           centres.origin.y, centres.spacing.y, ny);
  const auto [k_first, k_last] = row_range(std::min({v0.z, v1.z, v2.z}), std::max({v0.z, v1.z, v2.z}),
                                           centres.origin.z, centres.spacing.z, nz);
  const double x_low = std::min({v0.x, v1.x, v2.x}), x_high = std::max({v0.x, v1.x, v2.x});
  for (int k = k_first; k <= k_last; ++k) {
    const double z = centres.origin.z + (k + 0.5) * centres.spacing.z;
    for (int j = j_first; j <= j_last; ++j) {
      const double y = centres.origin.y + (j + 0.5) * centres.spacing.y;
      const int s0 = perturbed_sign(v0.y, v0.z, v1.y, v1.z, y, z);
      const int s1 = perturbed_sign(v1.y, v1.z, v2.y, v2.z, y, z);
      const int s2 = perturbed_sign(v2.y, v2.z, v0.y, v0.z, y, z);
      if (s0 == 0 || s0 != s1 || s1 != s2) continue;
      // x on the triangle's plane from the barycentric weights (each ∝ the sub-triangle opposite
      // a corner), kept within the triangle's x extent against round-off.
      const double w0 = orientation_value(v1, v2, y, z), w1 = orientation_value(v2, v0, y, z),
                   w2 = orientation_value(v0, v1, y, z);
      const double total = w0 + w1 + w2;
      double x = (w0 * v0.x + w1 * v1.x + w2 * v2.x) / total;
      if (!std::isfinite(x)) x = (v0.x + v1.x + v2.x) / 3.0;
      crossings.push_back({static_cast<std::uint32_t>(j + ny * k), std::clamp(x, x_low, x_high), s0});
    }
  }
}

}  // namespace

int orientation_sign(double a_u, double a_v, double b_u, double b_v, double p_u, double p_v) {
  // Shewchuk's orient2d on (a, b, p): det[a − p, b − p], the same determinant as (b − a) × (p − a).
  const double left = (a_u - p_u) * (b_v - p_v);
  const double right = (a_v - p_v) * (b_u - p_u);
  const double determinant = left - right;
  double magnitude_sum = 0.0;
  if (left > 0.0) {
    if (right <= 0.0) return determinant > 0.0 ? 1 : (determinant < 0.0 ? -1 : 0);
    magnitude_sum = left + right;
  } else if (left < 0.0) {
    if (right >= 0.0) return determinant > 0.0 ? 1 : (determinant < 0.0 ? -1 : 0);
    magnitude_sum = -left - right;
  } else {
    return determinant > 0.0 ? 1 : (determinant < 0.0 ? -1 : 0);
  }
  // Error bound of the rounded determinant (Shewchuk 1997, ccwerrboundA = (3 + 16ε)ε, ε = 2⁻⁵³).
  constexpr double kEpsilon = 0x1p-53;
  constexpr double kBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
  const double bound = kBound * magnitude_sum;
  if (determinant >= bound || -determinant >= bound) return determinant > 0.0 ? 1 : -1;
  // Exact: each difference as a two-term expansion, the products expanded term by term.
  double au_hi = 0.0, au_lo = 0.0, bv_hi = 0.0, bv_lo = 0.0, av_hi = 0.0, av_lo = 0.0, bu_hi = 0.0, bu_lo = 0.0;
  two_sum(a_u, -p_u, au_hi, au_lo);
  two_sum(b_v, -p_v, bv_hi, bv_lo);
  two_sum(a_v, -p_v, av_hi, av_lo);
  two_sum(b_u, -p_u, bu_hi, bu_lo);
  Expansion sum;
  add_product(sum, au_hi, au_lo, bv_hi, bv_lo, 1.0);
  add_product(sum, av_hi, av_lo, bu_hi, bu_lo, -1.0);
  return sum.sign();
}

MeshClosure check_closure(std::span<const Vec3> vertices,
                          std::span<const std::array<std::uint32_t, 3>> triangles) {
  // One id per distinct position, ordered by position (x, then y, then z).
  std::vector<std::uint32_t> order(vertices.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto position_less = [&](std::uint32_t a, std::uint32_t b) {
    return std::tie(vertices[a].x, vertices[a].y, vertices[a].z) <
           std::tie(vertices[b].x, vertices[b].y, vertices[b].z);
  };
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return position_less(a, b) || (!position_less(b, a) && a < b);
  });
  std::vector<std::uint32_t> id(vertices.size());
  std::vector<std::uint32_t> representative;  // a vertex per id
  for (std::size_t n = 0; n < order.size(); ++n) {
    if (n == 0 || position_less(order[n - 1], order[n])) representative.push_back(order[n]);
    id[order[n]] = static_cast<std::uint32_t>(representative.size() - 1);
  }
  struct EdgeUse {
    std::uint32_t low, high;
    int direction;  // +1 used from low to high, −1 from high to low
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * triangles.size());
  for (const auto& triangle : triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = id[triangle[k]], b = id[triangle[(k + 1) % 3]];
      if (a != b) uses.push_back({std::min(a, b), std::max(a, b), a < b ? 1 : -1});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return std::tie(a.low, a.high, a.direction) < std::tie(b.low, b.high, b.direction);
  });
  MeshClosure closure;
  closure.consistently_oriented = true;
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first;
    int direction_sum = 0;
    while (last < uses.size() && uses[last].low == uses[first].low && uses[last].high == uses[first].high)
      direction_sum += uses[last++].direction;
    if ((last - first) % 2 == 1) {
      if (closure.open_edges++ == 0)
        closure.first_open_edge_midpoint =
            (vertices[representative[uses[first].low]] + vertices[representative[uses[first].high]]) * 0.5;
    }
    if (direction_sum != 0) closure.consistently_oriented = false;
    first = last;
  }
  return closure;
}

std::vector<std::uint8_t> mark_centres_inside(const CellCentres& centres,
                                              std::span<const Vec3> vertices,
                                              std::span<const std::array<std::uint32_t, 3>> triangles,
                                              const MeshClosure& closure) {
  const int nx = centres.count[0], ny = centres.count[1], nz = centres.count[2];
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) *
                                       static_cast<std::size_t>(nz),
                                   0);
  std::vector<Crossing> crossings;
  for (const auto& triangle : triangles)
    cross_rows(centres, vertices[triangle[0]], vertices[triangle[1]], vertices[triangle[2]], crossings);
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
    return std::tie(a.row, a.x, a.sign) < std::tie(b.row, b.x, b.sign);
  });
  for (std::size_t first = 0; first < crossings.size();) {
    const std::uint32_t row = crossings[first].row;
    std::size_t next = first;
    int winding = 0;  // Σ of the signs of the crossings before the centre (non-zero rule)
    int parity = 0;   // their count mod 2 (even-odd rule)
    for (int i = 0; i < nx; ++i) {
      const double x = centres.origin.x + (i + 0.5) * centres.spacing.x;
      // Strictly before the centre: a centre on the surface is the point a hair towards −x.
      while (next < crossings.size() && crossings[next].row == row && crossings[next].x < x) {
        winding += crossings[next].sign;
        parity ^= 1;
        ++next;
      }
      const bool solid = closure.consistently_oriented ? winding != 0 : parity == 1;
      if (solid) inside[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * row] = 1;
    }
    while (first < crossings.size() && crossings[first].row == row) ++first;
  }
  return inside;
}

}  // namespace quarry
