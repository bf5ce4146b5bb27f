// The body of shell_internal_forces_quads (shell_element_batch.h): W quads per instruction, a
// template on W. Included only by shell_element_batch.cpp (W = 4: AVX2 in the release build,
// SSE2 pairs in a baseline x86-64 build) and shell_element_batch_avx512.cpp (W = 8, compiled
// for AVX-512 and called only where the processor has it). Everything here has internal linkage,
// so the two copies, built for different instruction sets, never meet at link time.
//
// Every expression below is the scalar kernel's (shell_element.cpp: element_frame,
// local_geometry, quad_shear_rates, quad_shear, add_quad_edge_forces, shell_internal_forces for
// n = 4 and edge-tied shear), with the same operands in the same order, including the additions
// to zero that start its sums (they decide the sign of a zero); keep the two in step.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "core/vec3.h"
#include "fem/plane_stress_j2.h"
#include "fem/shell_element.h"
#include "fem/shell_element_batch.h"

// The vector types below only cross functions of this header (internal linkage, inlined), so
// the note that their ABI differs without AVX-512 does not concern any caller.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace quarry::fem {
namespace {

// GCC/Clang vector extension: W quads, one per lane; + − × ÷ act lane by lane.
template <int W>
struct Lanes {
  typedef double v __attribute__((vector_size(8 * W)));
};

template <class V>
[[gnu::always_inline]] inline V vsqrt(V a) {
  constexpr int w = sizeof(V) / sizeof(double);
  double lanes[w];
  std::memcpy(lanes, &a, sizeof a);
  for (double& lane : lanes) lane = std::sqrt(lane);  // vectorised: the vector square root
  std::memcpy(&a, lanes, sizeof a);
  return a;
}

// {f(0), f(1), …}: a lane's value from each quad.
template <class V, class F, int... L>
[[gnu::always_inline]] inline V gather(F f, std::integer_sequence<int, L...>) {
  return V{f(L)...};
}

template <class V>
struct Vec3s {
  V x, y, z;
};
template <class V>
[[gnu::always_inline]] inline Vec3s<V> operator+(const Vec3s<V>& a, const Vec3s<V>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class V>
[[gnu::always_inline]] inline Vec3s<V> operator-(const Vec3s<V>& a, const Vec3s<V>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class V>
[[gnu::always_inline]] inline Vec3s<V> operator*(const Vec3s<V>& a, V s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class V>
[[gnu::always_inline]] inline V dot(const Vec3s<V>& a, const Vec3s<V>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class V>
[[gnu::always_inline]] inline Vec3s<V> cross(const Vec3s<V>& a, const Vec3s<V>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// quarry::normalized: a / |a|, the zero vector where |a| = 0.
template <class V>
[[gnu::always_inline]] inline Vec3s<V> normalized(const Vec3s<V>& a) {
  const V n = vsqrt(dot(a, a));
  const auto positive = n > 0.0;
  const V zero{};
  return {positive ? a.x / n : zero, positive ? a.y / n : zero, positive ? a.z / n : zero};
}

using Nodes = std::array<std::array<std::int32_t, 4>, kQuadLanes>;

// Node i of quads first .. first + W − 1.
template <int W>
[[gnu::always_inline]] inline Vec3s<typename Lanes<W>::v> load(const Vec3* field,
                                                               const Nodes& nodes, int first,
                                                               int i) {
  using V = typename Lanes<W>::v;
  const auto lanes = std::make_integer_sequence<int, W>{};
  return {gather<V>([&](int l) { return field[nodes[first + l][i]].x; }, lanes),
          gather<V>([&](int l) { return field[nodes[first + l][i]].y; }, lanes),
          gather<V>([&](int l) { return field[nodes[first + l][i]].z; }, lanes)};
}

// W consecutive doubles of a QuadBatchState (any alignment).
template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::v load(const double* lanes) {
  typename Lanes<W>::v a;
  std::memcpy(&a, lanes, sizeof a);
  return a;
}
template <class V>
[[gnu::always_inline]] inline void store(double* lanes, V a) {
  std::memcpy(lanes, &a, sizeof a);
}

constexpr int kQuadEdges[4][2] = {{0, 1}, {3, 2}, {0, 3}, {1, 2}};

// add_quad_edge_forces. Inlined (GCC kept it a call, 5 % of the samples), so that `local` is
// not passed through memory (with the unsigned gather index of the solver: +5 %, n 36).
template <class V>
[[gnu::always_inline]] inline void add_edge_forces(const V (&x)[4], const V (&y)[4],
                                                   const V (&edge_force)[4], V (&local)[4][6]) {
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const V dx = x[j] - x[i], dy = y[j] - y[i];
    local[j][2] += 0.5 * edge_force[k];
    local[i][2] -= 0.5 * edge_force[k];
    for (const int node : {i, j}) {
      local[node][3] -= 0.25 * edge_force[k] * dy;
      local[node][4] += 0.25 * edge_force[k] * dx;
    }
  }
}

// shell_internal_forces_quads for the batch's quads first .. first + W − 1 (their lanes of the
// interleaved histories and of `out`).
template <int W>
[[gnu::always_inline]] inline void quads(const Vec3* xs, const Vec3* vs, const Vec3* omegas,
                                         const Nodes& nodes, int first, double dt,
                                         const SectionProperties& section,
                                         const QuadBatchState& states, const QuadBatchOutput& out) {
  using V = typename Lanes<W>::v;
  using V3 = Vec3s<V>;
  // This call's lanes first .. first + W − 1 of the batch's interleaved histories.
  const QuadBatchState lanes{states.stress + first, states.plastic_strain + first,
                             states.shear + first, states.hourglass + first};
  const V zero{};
  V3 xn[4];
  for (int i = 0; i < 4; ++i) xn[i] = load<W>(xs, nodes, first, i);

  // element_frame.
  V3 sum{zero, zero, zero};
  for (int i = 0; i < 4; ++i) sum = sum + xn[i];
  const V3 origin{sum.x / 4.0, sum.y / 4.0, sum.z / 4.0};
  const V3 e3 = normalized(cross(xn[2] - xn[0], xn[3] - xn[1]));
  const V3 edge = xn[1] - xn[0];
  const V3 e1 = normalized(edge - e3 * dot(edge, e3));
  const V3 e2 = cross(e3, e1);

  // local_geometry.
  V x[4], y[4], height[4];
  for (int i = 0; i < 4; ++i) {
    const V3 r = xn[i] - origin;
    x[i] = dot(r, e1);
    y[i] = dot(r, e2);
    height[i] = dot(r, e3);
  }
  const V area = 0.5 * ((x[2] - x[0]) * (y[3] - y[1]) + (x[1] - x[3]) * (y[2] - y[0]));
  const V inverse = 1.0 / (2.0 * area);
  const V b1[4] = {(y[1] - y[3]) * inverse, (y[2] - y[0]) * inverse, (y[3] - y[1]) * inverse,
                   (y[0] - y[2]) * inverse};
  const V b2[4] = {(x[3] - x[1]) * inverse, (x[0] - x[2]) * inverse, (x[1] - x[3]) * inverse,
                   (x[2] - x[0]) * inverse};
  const V gxi_x = 0.25 * (-x[0] + x[1] + x[2] - x[3]);
  const V gxi_y = 0.25 * (-y[0] + y[1] + y[2] - y[3]);
  const V geta_x = 0.25 * (-x[0] - x[1] + x[2] + x[3]);
  const V geta_y = 0.25 * (-y[0] - y[1] + y[2] + y[3]);
  const V det = gxi_x * geta_y - gxi_y * geta_x;

  // Nodal velocities and angular velocities in the co-rotational frame.
  V3 vl[4], wl[4];
  for (int i = 0; i < 4; ++i) {
    // Loaded here, not with the positions: not live through the frame (+2 %, n 36).
    const V3 vn = load<W>(vs, nodes, first, i), wn = load<W>(omegas, nodes, first, i);
    vl[i] = {dot(vn, e1), dot(vn, e2), dot(vn, e3)};
    wl[i] = {dot(wn, e1), dot(wn, e2), dot(wn, e3)};
  }
  V membrane[3] = {zero, zero, zero}, curvature[3] = {zero, zero, zero};
  for (int i = 0; i < 4; ++i) {
    membrane[0] += b1[i] * vl[i].x;
    membrane[1] += b2[i] * vl[i].y;
    membrane[2] += b2[i] * vl[i].x + b1[i] * vl[i].y;
    curvature[0] += b1[i] * wl[i].y;
    curvature[1] -= b2[i] * wl[i].x;
    curvature[2] += b2[i] * wl[i].y - b1[i] * wl[i].x;
  }
  for (int k = 0; k < 3; ++k) {
    membrane[k] *= dt;
    curvature[k] *= dt;
  }
  // (The scalar kernel's centre shear rates are not needed with edge-tied shear.)
  // The edge-tied covariant shear strains (quad_shear_rates) and the hourglass rates, used
  // further down, computed here so that vl and wl are dead during the thickness loop
  // (+1-2 %, n 36 and n 100).
  V covariant[4];
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const V dx = x[j] - x[i], dy = y[j] - y[i];
    covariant[k] =
        0.5 * (vl[j].z - vl[i].z) + 0.25 * ((wl[i].y + wl[j].y) * dx - (wl[i].x + wl[j].x) * dy);
  }
  const double h[4] = {1.0, -1.0, 1.0, -1.0};
  V hx = zero, hy = zero, bb = zero;
  for (int i = 0; i < 4; ++i) {
    hx += h[i] * x[i];
    hy += h[i] * y[i];
    bb += b1[i] * b1[i] + b2[i] * b2[i];
  }
  V gamma[4];
  V rate[5] = {zero, zero, zero, zero, zero};
  V hz = zero, spin_x = zero, spin_y = zero;
  V spin_z = zero, in_plane = zero;  // the drilling rate's sums (shell_element.cpp)
  for (int i = 0; i < 4; ++i) {
    spin_z += wl[i].z;
    in_plane += b1[i] * vl[i].y - b2[i] * vl[i].x;
    gamma[i] = h[i] - hx * b1[i] - hy * b2[i];
    rate[0] += gamma[i] * vl[i].x;
    rate[1] += gamma[i] * vl[i].y;
    rate[2] += gamma[i] * vl[i].z;
    rate[3] += gamma[i] * wl[i].x;
    rate[4] += gamma[i] * wl[i].y;
    hz += h[i] * height[i];
    spin_x += wl[i].x;
    spin_y += wl[i].y;
  }
  // The warping correction of the in-plane hourglass rates (shell_element.cpp).
  rate[0] -= 0.25 * hz * spin_y;
  rate[1] += 0.25 * hz * spin_x;

  // Through the thickness: the elastic trial in vector form, the return map per yielding lane.
  const double t = section.thickness;
  const double half = 0.5 * t;
  const PlaneStressMaterial material = section.material;
  const double e = material.youngs_modulus, nu = material.poisson_ratio;
  const double factor = e / (1.0 - nu * nu);
  const double yield0 = material.yield_stress;
  const bool plastic = yield0 > 0.0 && std::isfinite(yield0);
  V force[3] = {zero, zero, zero}, moment[3] = {zero, zero, zero};
  V work = zero;
  for (int p = 0; p < section.points; ++p) {
    const double z = section.coordinate[p] * half;
    const double w = section.weight[p] * half;
    const V increment[3] = {membrane[0] + z * curvature[0], membrane[1] + z * curvature[1],
                            membrane[2] + z * curvature[2]};
    V stress[3];
    for (int k = 0; k < 3; ++k) stress[k] = load<W>(lanes.stress + kQuadLanes * (3 * p + k));
    const V old[3] = {stress[0], stress[1], stress[2]};
    // update_plane_stress: plane_stress_elastic, then the yield test.
    stress[0] = stress[0] + factor * (increment[0] + nu * increment[1]);
    stress[1] = stress[1] + factor * (nu * increment[0] + increment[1]);
    stress[2] = stress[2] + factor * 0.5 * (1.0 - nu) * increment[2];
    if (plastic) {
      const V plastic_strain = load<W>(lanes.plastic_strain + kQuadLanes * p);
      const V xx = stress[0], yy = stress[1], xy = stress[2];
      const V von_mises = vsqrt(xx * xx - xx * yy + yy * yy + 3.0 * xy * xy);
      const auto inside = von_mises <= yield0 + material.hardening_modulus * plastic_strain;
      for (int l = 0; l < W; ++l) {
        if (inside[l]) continue;
        Voigt3 trial{stress[0][l], stress[1][l], stress[2][l]};
        double strain = plastic_strain[l];
        plane_stress_return_map(material, trial, strain);
        stress[0][l] = trial[0];
        stress[1][l] = trial[1];
        stress[2][l] = trial[2];
        lanes.plastic_strain[kQuadLanes * p + l] = strain;
      }
    }
    for (int k = 0; k < 3; ++k) store(lanes.stress + kQuadLanes * (3 * p + k), stress[k]);
    for (int k = 0; k < 3; ++k) {
      work += 0.5 * (old[k] + stress[k]) * increment[k] * w;
      force[k] += stress[k] * w;
      moment[k] += stress[k] * z * w;
    }
  }

  // Transverse shear from the edge-tied covariant strains (quad_shear_rates, quad_shear).
  const double shear_stiffness = section.shear_factor * section.shear_modulus * t;
  V local[4][6];
  for (auto& node : local)
    for (V& value : node) value = zero;
  {
    const V gamma_xi = 0.5 * (covariant[0] + covariant[1]);
    const V gamma_eta = 0.5 * (covariant[2] + covariant[3]);
    const V rate_x = (gamma_xi * geta_y - gamma_eta * gxi_y) / det;
    const V rate_y = (gamma_eta * gxi_x - gamma_xi * geta_x) / det;
    const V increment_x = rate_x * dt;
    const V increment_y = rate_y * dt;
    const V old_x = load<W>(lanes.shear);
    const V old_y = load<W>(lanes.shear + kQuadLanes);
    const V q_x = old_x + shear_stiffness * increment_x;
    const V q_y = old_y + shear_stiffness * increment_y;
    store(lanes.shear, q_x);
    store(lanes.shear + kQuadLanes, q_y);
    const V shear_work =
        area * (0.5 * (old_x + q_x) * increment_x + 0.5 * (old_y + q_y) * increment_y);
    const V force_xi = area * (q_x * geta_y - q_y * geta_x) / det;
    const V force_eta = area * (q_y * gxi_x - q_x * gxi_y) / det;
    add_edge_forces<V>(x, y, {0.5 * force_xi, 0.5 * force_xi, 0.5 * force_eta, 0.5 * force_eta},
                       local);
    work += shear_work / area;
  }
  const V internal_energy = work * area;

  // Nodal forces from the virtual power A (N:δd + M:δκ + Q·δγ).
  const V a = area;
  for (int i = 0; i < 4; ++i) {
    local[i][0] += a * (b1[i] * force[0] + b2[i] * force[2]);
    local[i][1] += a * (b2[i] * force[1] + b1[i] * force[2]);
    local[i][3] += a * (-b2[i] * moment[1] - b1[i] * moment[2]);
    local[i][4] += a * (b1[i] * moment[0] + b2[i] * moment[2]);
  }

  // Hourglass control, the w mode from the edge shears.
  const V along_xi = 0.5 * (hx * geta_y - hy * geta_x) / det;
  const V along_eta = 0.5 * (-hx * gxi_y + hy * gxi_x) / det;
  const V w_weight[4] = {-1.0 - along_xi, 1.0 - along_xi, -1.0 - along_eta, 1.0 - along_eta};
  rate[2] = zero;
  for (int k = 0; k < 4; ++k) rate[2] += w_weight[k] * covariant[k];
  const V membrane_k = section.hourglass_membrane * material.youngs_modulus * t * a * bb / 8.0;
  const V transverse_k = section.hourglass_transverse * section.shear_factor *
                         section.shear_modulus * t * t * t * bb / 12.0;
  const V bending_k =
      section.hourglass_bending * material.youngs_modulus * t * t * t * a * bb / 192.0;
  const V stiffness[5] = {membrane_k, membrane_k, transverse_k, bending_k, bending_k};
  V resultant[5];
  for (int k = 0; k < 5; ++k) resultant[k] = load<W>(lanes.hourglass + kQuadLanes * k);
  V hourglass_work = zero;
  for (int k = 0; k < 5; ++k) {
    const V increment = rate[k] * dt;
    const V old = resultant[k];
    resultant[k] += stiffness[k] * increment;
    hourglass_work += 0.5 * (old + resultant[k]) * increment;
  }
  for (int k = 0; k < 5; ++k) store(lanes.hourglass + kQuadLanes * k, resultant[k]);
  for (int i = 0; i < 4; ++i) {
    local[i][0] += gamma[i] * resultant[0];
    local[i][1] += gamma[i] * resultant[1];
    local[i][3] += gamma[i] * resultant[3] + 0.25 * hz * resultant[1];
    local[i][4] += gamma[i] * resultant[4] - 0.25 * hz * resultant[0];
  }
  const V q = resultant[2];
  add_edge_forces<V>(x, y, {q * w_weight[0], q * w_weight[1], q * w_weight[2], q * w_weight[3]},
                     local);

  // Drilling stiffness (shell_element.cpp), its resultant in the third shear slot.
  if (section.drilling > 0.0) {
    const V increment = (spin_z * 0.25 - 0.5 * in_plane) * dt;
    const V old = load<W>(lanes.shear + 2 * kQuadLanes);
    const V drill = old + section.drilling * section.shear_modulus * t * a * increment;
    store(lanes.shear + 2 * kQuadLanes, drill);
    hourglass_work += 0.5 * (old + drill) * increment;
    for (int i = 0; i < 4; ++i) {
      local[i][0] += 0.5 * b2[i] * drill;
      local[i][1] -= 0.5 * b1[i] * drill;
      local[i][5] += 0.25 * drill;
    }
  }

  // Back to global axes.
  for (int i = 0; i < 4; ++i) {
    const V3 fg = e1 * local[i][0] + e2 * local[i][1] + e3 * local[i][2];
    const V3 mg = e1 * local[i][3] + e2 * local[i][4] + e3 * local[i][5];
    for (int l = 0; l < W; ++l) {
      (*out.nodal[first + l])[i] = {fg.x[l], fg.y[l], fg.z[l], mg.x[l], mg.y[l], mg.z[l]};
    }
  }
  for (int l = 0; l < W; ++l) {
    *out.internal_energy_increment[first + l] = internal_energy[l];
    *out.hourglass_energy_increment[first + l] = hourglass_work[l];
  }
}

}  // namespace
}  // namespace quarry::fem
