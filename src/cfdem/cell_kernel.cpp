// Trilinear (cloud-in-cell) weights of a particle's centre on the cell centres, and the void
// fraction, deposition and interpolation made from them (Hockney & Eastwood 1988, Computer
// Simulation Using Particles, §5-3: the same assignment both ways conserves momentum). Weights on
// blocked cells are moved onto the particle's fluid cells; the nearest fluid cell of each blocked
// one comes from a Euclidean distance transform (Felzenszwalb & Huttenlocher 2012).
#include "cfdem/cell_kernel.h"
#include "core/sphere.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace quarry::cfdem {

namespace {

// The two cells along one axis and the weight of the upper one; indices folded or wrapped.
struct AxisPair {
  int low = 0, high = 0;
  double upper_weight = 0.0;  // 1
};

AxisPair axis_pair(double coordinate, double origin, double size, int cells, bool periodic) {
  // Position in cell-centre units: cell i's centre is at i.
  double s = (coordinate - origin) / size - 0.5;
  if (periodic) {
    // fmod(s, span), plus span when negative, with the library call only where s lies outside
    // (−span, 2 span): the same values (s − span is exact on [span, 2 span), Sterbenz; fmod is
    // s itself on (−span, 0)). The indices below then need no integer division either.
    const double span = static_cast<double>(cells);
    if (s >= span && s < 2.0 * span) {
      s -= span;
    } else if (!(s > -span && s < span)) {
      s = std::fmod(s, span);
    }
    if (s < 0.0) s += span;
  } else {
    s = std::clamp(s, -0.5, static_cast<double>(cells) - 0.5);
  }
  const double floor_s = std::floor(s);
  AxisPair pair;
  pair.low = static_cast<int>(floor_s);
  pair.high = pair.low + 1;
  pair.upper_weight = s - floor_s;
  if (periodic) {  // s in [0, span]: low in [0, cells], high in [1, cells + 1]
    if (pair.low >= cells) pair.low -= cells;
    if (pair.high >= cells) pair.high -= cells;
  } else {
    pair.low = std::clamp(pair.low, 0, cells - 1);
    pair.high = std::clamp(pair.high, 0, cells - 1);
  }
  return pair;
}

// One line of the distance transform (Felzenszwalb & Huttenlocher 2012, Algorithm 1): the
// squared distance (m²) along the line of `count` cells `spacing` apart, given `distance` (the
// squared distance found along the earlier axes, +∞ where none) at each cell, and the cell it
// belongs to. Both arrays are replaced by the lower envelope of the parabolas
// (x − x_q)² + distance_q. A line without any finite value is left as it is.
void transform_line(std::vector<double>& distance, std::vector<std::uint32_t>& nearest,
                    double spacing, std::vector<int>& vertex, std::vector<double>& boundary,
                    std::vector<double>& out_distance, std::vector<std::uint32_t>& out_nearest) {
  const int count = static_cast<int>(distance.size());
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const auto height = [&](int q) { return distance[static_cast<std::size_t>(q)] + (q * spacing) * (q * spacing); };
  int top = -1;  // the last parabola of the envelope
  for (int q = 0; q < count; ++q) {
    if (!(distance[static_cast<std::size_t>(q)] < kInfinity)) continue;
    if (top < 0) {
      top = 0;
      vertex[0] = q;
      boundary[0] = -kInfinity;
      boundary[1] = kInfinity;
      continue;
    }
    // Where parabola q overtakes the top one; the top is dropped while that lies before its start.
    double crossing = 0.0;
    while (true) {
      const int r = vertex[static_cast<std::size_t>(top)];
      crossing = (height(q) - height(r)) / (2.0 * spacing * (q - r));
      if (crossing > boundary[static_cast<std::size_t>(top)]) break;
      --top;  // boundary[0] is −∞, so top stays ≥ 0
    }
    ++top;
    vertex[static_cast<std::size_t>(top)] = q;
    boundary[static_cast<std::size_t>(top)] = crossing;
    boundary[static_cast<std::size_t>(top) + 1] = kInfinity;
  }
  if (top < 0) return;
  int k = 0;
  for (int q = 0; q < count; ++q) {
    const double x = q * spacing;
    while (boundary[static_cast<std::size_t>(k) + 1] < x) ++k;
    const int r = vertex[static_cast<std::size_t>(k)];
    const double offset = x - r * spacing;
    out_distance[static_cast<std::size_t>(q)] = offset * offset + distance[static_cast<std::size_t>(r)];
    out_nearest[static_cast<std::size_t>(q)] = nearest[static_cast<std::size_t>(r)];
  }
  distance.swap(out_distance);
  nearest.swap(out_nearest);
}

}  // namespace

BlockedCells make_blocked_cells(const cfd::FluidGrid& grid, std::span<const std::uint8_t> mask) {
  const std::size_t cells = grid.cell_count();
  if (mask.size() != cells)
    throw std::invalid_argument(
        fmt::format("blocked cells: the mask has {} values, the fluid grid {} cells", mask.size(), cells));
  BlockedCells result;
  result.count = static_cast<std::size_t>(std::count_if(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }));
  if (result.count == 0) return result;
  if (result.count == cells)
    throw std::invalid_argument(fmt::format("blocked cells: all {} cells of the fluid grid are blocked", cells));
  result.mask.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) result.mask[c] = mask[c] != 0 ? 1 : 0;
  // Squared distance (m²) to the nearest fluid cell centre, and that cell, one axis at a time.
  std::vector<double> distance(cells, std::numeric_limits<double>::infinity());
  result.nearest_fluid.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    result.nearest_fluid[c] = static_cast<std::uint32_t>(c);
    if (!result.mask[c]) distance[c] = 0.0;
  }
  const std::array<std::size_t, 3> stride{1, static_cast<std::size_t>(grid.cells[0]),
                                          static_cast<std::size_t>(grid.cells[0]) * static_cast<std::size_t>(grid.cells[1])};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const auto b = static_cast<std::size_t>((axis + 1) % 3), c = static_cast<std::size_t>((axis + 2) % 3);
    const auto length = static_cast<std::size_t>(grid.cells[a]);
    std::vector<double> line(length), out_line(length), boundary(length + 1);
    std::vector<std::uint32_t> line_nearest(length), out_nearest(length);
    std::vector<int> vertex(length);
    for (int v = 0; v < grid.cells[c]; ++v)
      for (int u = 0; u < grid.cells[b]; ++u) {
        const std::size_t start = static_cast<std::size_t>(u) * stride[b] + static_cast<std::size_t>(v) * stride[c];
        for (std::size_t q = 0; q < length; ++q) {
          line[q] = distance[start + q * stride[a]];
          line_nearest[q] = result.nearest_fluid[start + q * stride[a]];
        }
        transform_line(line, line_nearest, grid.cell_size[axis], vertex, boundary, out_line, out_nearest);
        for (std::size_t q = 0; q < length; ++q) {
          distance[start + q * stride[a]] = line[q];
          result.nearest_fluid[start + q * stride[a]] = line_nearest[q];
        }
      }
  }
  return result;
}

CellWeights cell_weights(const cfd::FluidGrid& grid, const PeriodicAxes& periodic,
                         const BlockedCells& blocked, const Vec3& position, bool* moved_to_nearest) {
  if (moved_to_nearest) *moved_to_nearest = false;
  CellWeights weights = cell_weights(grid, periodic, position);
  if (blocked.count == 0) return weights;
  double fluid_weight = 0.0;  // Σ w over the entries on fluid cells
  std::size_t first_fluid = 8;
  bool any_blocked = false;
  for (std::size_t c = 0; c < 8; ++c) {
    if (blocked.mask[weights.cell[c]]) {
      any_blocked = true;
      continue;
    }
    fluid_weight += weights.weight[c];
    if (first_fluid == 8 && weights.weight[c] > 0.0) first_fluid = c;
  }
  if (!any_blocked) return weights;
  if (fluid_weight > 0.0) {
    for (std::size_t c = 0; c < 8; ++c) {
      if (blocked.mask[weights.cell[c]]) {
        weights.cell[c] = weights.cell[first_fluid];
        weights.weight[c] = 0.0;
      } else {
        weights.weight[c] /= fluid_weight;
      }
    }
    return weights;
  }
  // Every weight on blocked cells: the whole particle onto the fluid cell nearest its own cell.
  std::array<int, 3> at{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const int n = grid.cells[a];
    const double s = std::floor((position[axis] - grid.origin[axis]) / grid.cell_size[axis]);
    if (periodic[a]) {
      const double wrapped = std::fmod(s, static_cast<double>(n));
      at[a] = static_cast<int>(wrapped < 0.0 ? wrapped + n : wrapped);
    } else {
      at[a] = static_cast<int>(std::clamp(s, 0.0, static_cast<double>(n - 1)));
    }
  }
  const std::uint32_t nearest = blocked.nearest_fluid[grid.cell_index(at[0], at[1], at[2])];
  weights.cell.fill(nearest);
  weights.weight.fill(0.0);
  weights.weight[0] = 1.0;
  if (moved_to_nearest) *moved_to_nearest = true;
  return weights;
}

CellWeights cell_weights(const cfd::FluidGrid& grid, const PeriodicAxes& periodic,
                         const Vec3& position) {
  const AxisPair x = axis_pair(position.x, grid.origin.x, grid.cell_size.x, grid.cells[0], periodic[0]);
  const AxisPair y = axis_pair(position.y, grid.origin.y, grid.cell_size.y, grid.cells[1], periodic[1]);
  const AxisPair z = axis_pair(position.z, grid.origin.z, grid.cell_size.z, grid.cells[2], periodic[2]);
  CellWeights result;
  int corner = 0;
  for (int c = 0; c < 2; ++c) {
    const int k = c == 0 ? z.low : z.high;
    const double wz = c == 0 ? 1.0 - z.upper_weight : z.upper_weight;
    for (int b = 0; b < 2; ++b) {
      const int j = b == 0 ? y.low : y.high;
      const double wy = b == 0 ? 1.0 - y.upper_weight : y.upper_weight;
      for (int a = 0; a < 2; ++a, ++corner) {
        const int i = a == 0 ? x.low : x.high;
        const double wx = a == 0 ? 1.0 - x.upper_weight : x.upper_weight;
        result.cell[static_cast<std::size_t>(corner)] =
            static_cast<std::uint32_t>(grid.cell_index(i, j, k));
        result.weight[static_cast<std::size_t>(corner)] = wx * wy * wz;
      }
    }
  }
  return result;
}

void order_deposits(const cfd::FluidGrid& grid, std::span<const CellWeights> weights, int threads,
                    DepositOrder& order) {
  const std::size_t n = weights.size(), cells = grid.cell_count();
  const auto ranges = static_cast<std::size_t>(std::max(threads, 1));
  order.threads = static_cast<int>(ranges);
  order.lowest.resize(n);
  order.highest.resize(n);
#pragma omp parallel for schedule(static) num_threads(order.threads)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n); ++k) {
    const auto p = static_cast<std::size_t>(k);
    const auto [low, high] = std::minmax_element(weights[p].cell.begin(), weights[p].cell.end());
    order.lowest[p] = *low;
    order.highest[p] = *high;
  }
  // Cuts after about n/ranges, 2n/ranges, … particles by their lowest cell.
  std::vector<std::uint32_t>& per_cell = order.per_cell;
  per_cell.assign(cells, 0);
  for (std::size_t p = 0; p < n; ++p) ++per_cell[order.lowest[p]];
  order.first_cell.assign(ranges + 1, cells);
  order.first_cell[0] = 0;
  std::size_t below = 0, r = 1;  // particles in the cells so far; the next cut
  for (std::size_t c = 0; c < cells && r < ranges; ++c) {
    below += per_cell[c];
    while (r < ranges && below * ranges >= r * n) order.first_cell[r++] = c + 1;
  }
  order.particles.resize(ranges);
#pragma omp parallel for schedule(static, 1) num_threads(order.threads)
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(ranges); ++k) {
    const auto range = static_cast<std::size_t>(k);
    const std::size_t first = order.first_cell[range], end = order.first_cell[range + 1];
    std::vector<std::uint32_t>& list = order.particles[range];
    list.clear();
    for (std::size_t p = 0; p < n; ++p)
      if (order.highest[p] >= first && order.lowest[p] < end) list.push_back(static_cast<std::uint32_t>(p));
  }
}

namespace {

// Calls add(p, in) for every particle p, in(cell) telling whether p may add to that cell: in index
// order on this thread, or each range of `order` on its own thread with its own cells (above).
template <class Add>
void scatter(std::span<const CellWeights> weights, std::size_t cells, const DepositOrder* order, Add&& add) {
  if (order == nullptr) {
    const auto in = [](std::uint32_t) { return true; };
    for (std::size_t p = 0; p < weights.size(); ++p) add(p, in);
    return;
  }
  if (order->lowest.size() != weights.size() || order->first_cell.back() != cells)
    throw std::logic_error("deposit: the order was made for other weights or another grid");
  const auto ranges = static_cast<std::ptrdiff_t>(order->particles.size());
#pragma omp parallel for schedule(static, 1) num_threads(order->threads)
  for (std::ptrdiff_t k = 0; k < ranges; ++k) {
    const auto r = static_cast<std::size_t>(k);
    const std::size_t first = order->first_cell[r], count = order->first_cell[r + 1] - first;
    const auto in = [=](std::uint32_t cell) { return cell - first < count; };  // wraps below first
    for (const std::uint32_t p : order->particles[r]) add(std::size_t{p}, in);
  }
}

}  // namespace

double void_fraction(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                     std::span<const double> radius, std::vector<double>& void_fraction,
                     const DepositOrder* order) {
  // The particle volume per cell (m³) is summed in place, then turned into ε.
  std::vector<double>& solid = void_fraction;
  solid.assign(grid.cell_count(), 0.0);
  scatter(weights, solid.size(), order, [&](std::size_t p, auto in) {
    const double volume = sphere_volume(radius[p]);
    for (std::size_t c = 0; c < 8; ++c)
      if (in(weights[p].cell[c])) solid[weights[p].cell[c]] += weights[p].weight[c] * volume;
  });
  const double cell_volume = grid.cell_volume();
  double smallest = 1.0;
  for (double& value : void_fraction) {
    value = 1.0 - value / cell_volume;
    smallest = std::min(smallest, value);
  }
  return smallest;
}

void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const double> value, std::span<double> density, const DepositOrder* order) {
  const double inverse_volume = 1.0 / grid.cell_volume();
  scatter(weights, density.size(), order, [&](std::size_t p, auto in) {
    for (std::size_t c = 0; c < 8; ++c)
      if (in(weights[p].cell[c])) density[weights[p].cell[c]] += weights[p].weight[c] * value[p] * inverse_volume;
  });
}

void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const Vec3> value, std::span<Vec3> density, const DepositOrder* order) {
  const double inverse_volume = 1.0 / grid.cell_volume();
  scatter(weights, density.size(), order, [&](std::size_t p, auto in) {
    for (std::size_t c = 0; c < 8; ++c)
      if (in(weights[p].cell[c])) density[weights[p].cell[c]] += value[p] * (weights[p].weight[c] * inverse_volume);
  });
}

void deposit_drag(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                  std::span<const double> coefficient, std::span<const Vec3> velocity, std::span<double> beta,
                  std::span<Vec3> force, const DepositOrder* order) {
  const double inverse_volume = 1.0 / grid.cell_volume();
  scatter(weights, beta.size(), order, [&](std::size_t p, auto in) {
    const Vec3 momentum = velocity[p] * coefficient[p];  // β_p v_p (N)
    for (std::size_t c = 0; c < 8; ++c) {
      if (!in(weights[p].cell[c])) continue;
      beta[weights[p].cell[c]] += weights[p].weight[c] * coefficient[p] * inverse_volume;
      force[weights[p].cell[c]] += momentum * (weights[p].weight[c] * inverse_volume);
    }
  });
}

double interpolate(const CellWeights& weights, std::span<const double> field) {
  double sum = 0.0;
  for (std::size_t c = 0; c < 8; ++c) sum += weights.weight[c] * field[weights.cell[c]];
  return sum;
}

Vec3 interpolate(const CellWeights& weights, std::span<const Vec3> field) {
  Vec3 sum;
  for (std::size_t c = 0; c < 8; ++c) sum += field[weights.cell[c]] * weights.weight[c];
  return sum;
}

}  // namespace quarry::cfdem
