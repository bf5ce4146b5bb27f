// Four Belytschko–Tsay quads per instruction (shell_element_batch.h). Every expression below is
// the scalar kernel's (shell_element.cpp: element_frame, local_geometry, quad_shear_rates,
// quad_shear, add_quad_edge_forces, shell_internal_forces for n = 4 and edge-tied shear), with
// the same operands in the same order, including the additions to zero that start its sums
// (they decide the sign of a zero); keep the two in step.
#include "fem/shell_element_batch.h"

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

// The vector types below only cross functions of this file (internal linkage, inlined), so the
// note that their ABI differs without AVX does not concern any caller.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace quarry::fem {
namespace {

// GCC/Clang vector extension: one quad per lane; + − × ÷ act lane by lane.
typedef double v4d __attribute__((vector_size(8 * kQuadLanes)));

v4d vsqrt(v4d a) {
  double lanes[kQuadLanes];
  std::memcpy(lanes, &a, sizeof a);
  for (double& lane : lanes) lane = std::sqrt(lane);  // vectorised: the vector square root
  std::memcpy(&a, lanes, sizeof a);
  return a;
}

// {f(0), f(1), …}: a lane's value from each quad.
template <class F, int... L>
[[gnu::always_inline]] inline v4d gather(F f, std::integer_sequence<int, L...>) {
  return v4d{f(L)...};
}
template <class F>
[[gnu::always_inline]] inline v4d gather(F f) {
  return gather(f, std::make_integer_sequence<int, kQuadLanes>{});
}

struct V3 {
  v4d x, y, z;
};
V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(const V3& a, v4d s) { return {a.x * s, a.y * s, a.z * s}; }
v4d dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// quarry::normalized: a / |a|, the zero vector where |a| = 0.
V3 normalized(const V3& a) {
  const v4d n = vsqrt(dot(a, a));
  const auto positive = n > 0.0;
  const v4d zero{};
  return {positive ? a.x / n : zero, positive ? a.y / n : zero, positive ? a.z / n : zero};
}

using Nodes = std::array<std::array<std::int32_t, 4>, kQuadLanes>;

[[gnu::always_inline]] inline V3 load(const Vec3* field, const Nodes& nodes, int i) {
  return {gather([&](int l) { return field[nodes[l][i]].x; }),
          gather([&](int l) { return field[nodes[l][i]].y; }),
          gather([&](int l) { return field[nodes[l][i]].z; })};
}

// The four lanes of a QuadBatchState value (consecutive doubles, any alignment).
[[gnu::always_inline]] inline v4d load(const double* lanes) {
  v4d a;
  std::memcpy(&a, lanes, sizeof a);
  return a;
}
[[gnu::always_inline]] inline void store(double* lanes, v4d a) { std::memcpy(lanes, &a, sizeof a); }

constexpr int kQuadEdges[4][2] = {{0, 1}, {3, 2}, {0, 3}, {1, 2}};

// add_quad_edge_forces. Inlined (GCC kept it a call, 5 % of the samples), so that `local` is
// not passed through memory (with the unsigned gather index of the solver: +5 %, n 36).
[[gnu::always_inline]] inline void add_edge_forces(const v4d (&x)[4], const v4d (&y)[4],
                                                   const v4d (&edge_force)[4],
                                                   v4d (&local)[4][6]) {
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const v4d dx = x[j] - x[i], dy = y[j] - y[i];
    local[j][2] += 0.5 * edge_force[k];
    local[i][2] -= 0.5 * edge_force[k];
    for (const int node : {i, j}) {
      local[node][3] -= 0.25 * edge_force[k] * dy;
      local[node][4] += 0.25 * edge_force[k] * dx;
    }
  }
}

}  // namespace

void shell_internal_forces_quads(const Vec3* xs, const Vec3* vs, const Vec3* omegas,
                                 const Nodes& nodes, double dt, const SectionProperties& section,
                                 const QuadBatchState& states, const QuadBatchOutput& out) {
  const v4d zero{};
  V3 xn[4];
  for (int i = 0; i < 4; ++i) xn[i] = load(xs, nodes, i);

  // element_frame.
  V3 sum{zero, zero, zero};
  for (int i = 0; i < 4; ++i) sum = sum + xn[i];
  const V3 origin{sum.x / 4.0, sum.y / 4.0, sum.z / 4.0};
  const V3 e3 = normalized(cross(xn[2] - xn[0], xn[3] - xn[1]));
  const V3 edge = xn[1] - xn[0];
  const V3 e1 = normalized(edge - e3 * dot(edge, e3));
  const V3 e2 = cross(e3, e1);

  // local_geometry.
  v4d x[4], y[4];
  for (int i = 0; i < 4; ++i) {
    const V3 r = xn[i] - origin;
    x[i] = dot(r, e1);
    y[i] = dot(r, e2);
  }
  const v4d area = 0.5 * ((x[2] - x[0]) * (y[3] - y[1]) + (x[1] - x[3]) * (y[2] - y[0]));
  const v4d inverse = 1.0 / (2.0 * area);
  const v4d b1[4] = {(y[1] - y[3]) * inverse, (y[2] - y[0]) * inverse, (y[3] - y[1]) * inverse,
                     (y[0] - y[2]) * inverse};
  const v4d b2[4] = {(x[3] - x[1]) * inverse, (x[0] - x[2]) * inverse, (x[1] - x[3]) * inverse,
                     (x[2] - x[0]) * inverse};
  const v4d gxi_x = 0.25 * (-x[0] + x[1] + x[2] - x[3]);
  const v4d gxi_y = 0.25 * (-y[0] + y[1] + y[2] - y[3]);
  const v4d geta_x = 0.25 * (-x[0] - x[1] + x[2] + x[3]);
  const v4d geta_y = 0.25 * (-y[0] - y[1] + y[2] + y[3]);
  const v4d det = gxi_x * geta_y - gxi_y * geta_x;

  // Nodal velocities and angular velocities in the co-rotational frame.
  V3 vl[4], wl[4];
  for (int i = 0; i < 4; ++i) {
    // Loaded here, not with the positions: not live through the frame (+2 %, n 36).
    const V3 vn = load(vs, nodes, i), wn = load(omegas, nodes, i);
    vl[i] = {dot(vn, e1), dot(vn, e2), dot(vn, e3)};
    wl[i] = {dot(wn, e1), dot(wn, e2), dot(wn, e3)};
  }
  v4d membrane[3] = {zero, zero, zero}, curvature[3] = {zero, zero, zero};
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
  v4d covariant[4];
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const v4d dx = x[j] - x[i], dy = y[j] - y[i];
    covariant[k] = 0.5 * (vl[j].z - vl[i].z) +
                   0.25 * ((wl[i].y + wl[j].y) * dx - (wl[i].x + wl[j].x) * dy);
  }
  const double h[4] = {1.0, -1.0, 1.0, -1.0};
  v4d hx = zero, hy = zero, bb = zero;
  for (int i = 0; i < 4; ++i) {
    hx += h[i] * x[i];
    hy += h[i] * y[i];
    bb += b1[i] * b1[i] + b2[i] * b2[i];
  }
  v4d gamma[4];
  v4d rate[5] = {zero, zero, zero, zero, zero};
  for (int i = 0; i < 4; ++i) {
    gamma[i] = h[i] - hx * b1[i] - hy * b2[i];
    rate[0] += gamma[i] * vl[i].x;
    rate[1] += gamma[i] * vl[i].y;
    rate[2] += gamma[i] * vl[i].z;
    rate[3] += gamma[i] * wl[i].x;
    rate[4] += gamma[i] * wl[i].y;
  }

  // Through the thickness: the elastic trial in vector form, the return map per yielding lane.
  const double t = section.thickness;
  const double half = 0.5 * t;
  const PlaneStressMaterial material = section.material;
  const double e = material.youngs_modulus, nu = material.poisson_ratio;
  const double factor = e / (1.0 - nu * nu);
  const double yield0 = material.yield_stress;
  const bool plastic = yield0 > 0.0 && std::isfinite(yield0);
  v4d force[3] = {zero, zero, zero}, moment[3] = {zero, zero, zero};
  v4d work = zero;
  for (int p = 0; p < section.points; ++p) {
    const double z = section.coordinate[p] * half;
    const double w = section.weight[p] * half;
    const v4d increment[3] = {membrane[0] + z * curvature[0], membrane[1] + z * curvature[1],
                              membrane[2] + z * curvature[2]};
    v4d stress[3];
    for (int k = 0; k < 3; ++k) stress[k] = load(states.stress + kQuadLanes * (3 * p + k));
    const v4d old[3] = {stress[0], stress[1], stress[2]};
    // update_plane_stress: plane_stress_elastic, then the yield test.
    stress[0] = stress[0] + factor * (increment[0] + nu * increment[1]);
    stress[1] = stress[1] + factor * (nu * increment[0] + increment[1]);
    stress[2] = stress[2] + factor * 0.5 * (1.0 - nu) * increment[2];
    if (plastic) {
      const v4d plastic_strain = load(states.plastic_strain + kQuadLanes * p);
      const v4d xx = stress[0], yy = stress[1], xy = stress[2];
      const v4d von_mises = vsqrt(xx * xx - xx * yy + yy * yy + 3.0 * xy * xy);
      const auto inside = von_mises <= yield0 + material.hardening_modulus * plastic_strain;
      for (int l = 0; l < kQuadLanes; ++l) {
        if (inside[l]) continue;
        Voigt3 trial{stress[0][l], stress[1][l], stress[2][l]};
        double strain = plastic_strain[l];
        plane_stress_return_map(material, trial, strain);
        stress[0][l] = trial[0];
        stress[1][l] = trial[1];
        stress[2][l] = trial[2];
        states.plastic_strain[kQuadLanes * p + l] = strain;
      }
    }
    for (int k = 0; k < 3; ++k) store(states.stress + kQuadLanes * (3 * p + k), stress[k]);
    for (int k = 0; k < 3; ++k) {
      work += 0.5 * (old[k] + stress[k]) * increment[k] * w;
      force[k] += stress[k] * w;
      moment[k] += stress[k] * z * w;
    }
  }

  // Transverse shear from the edge-tied covariant strains (quad_shear_rates, quad_shear).
  const double shear_stiffness = section.shear_factor * section.shear_modulus * t;
  v4d local[4][6];
  for (auto& node : local)
    for (v4d& value : node) value = zero;
  {
    const v4d gamma_xi = 0.5 * (covariant[0] + covariant[1]);
    const v4d gamma_eta = 0.5 * (covariant[2] + covariant[3]);
    const v4d rate_x = (gamma_xi * geta_y - gamma_eta * gxi_y) / det;
    const v4d rate_y = (gamma_eta * gxi_x - gamma_xi * geta_x) / det;
    const v4d increment_x = rate_x * dt;
    const v4d increment_y = rate_y * dt;
    const v4d old_x = load(states.shear);
    const v4d old_y = load(states.shear + kQuadLanes);
    const v4d q_x = old_x + shear_stiffness * increment_x;
    const v4d q_y = old_y + shear_stiffness * increment_y;
    store(states.shear, q_x);
    store(states.shear + kQuadLanes, q_y);
    const v4d shear_work =
        area * (0.5 * (old_x + q_x) * increment_x + 0.5 * (old_y + q_y) * increment_y);
    const v4d force_xi = area * (q_x * geta_y - q_y * geta_x) / det;
    const v4d force_eta = area * (q_y * gxi_x - q_x * gxi_y) / det;
    add_edge_forces(x, y, {0.5 * force_xi, 0.5 * force_xi, 0.5 * force_eta, 0.5 * force_eta},
                    local);
    work += shear_work / area;
  }
  const v4d internal_energy = work * area;

  // Nodal forces from the virtual power A (N:δd + M:δκ + Q·δγ).
  const v4d a = area;
  for (int i = 0; i < 4; ++i) {
    local[i][0] += a * (b1[i] * force[0] + b2[i] * force[2]);
    local[i][1] += a * (b2[i] * force[1] + b1[i] * force[2]);
    local[i][3] += a * (-b2[i] * moment[1] - b1[i] * moment[2]);
    local[i][4] += a * (b1[i] * moment[0] + b2[i] * moment[2]);
  }

  // Hourglass control, the w mode from the edge shears.
  const v4d along_xi = 0.5 * (hx * geta_y - hy * geta_x) / det;
  const v4d along_eta = 0.5 * (-hx * gxi_y + hy * gxi_x) / det;
  const v4d w_weight[4] = {-1.0 - along_xi, 1.0 - along_xi, -1.0 - along_eta, 1.0 - along_eta};
  rate[2] = zero;
  for (int k = 0; k < 4; ++k) rate[2] += w_weight[k] * covariant[k];
  const v4d membrane_k = section.hourglass_membrane * material.youngs_modulus * t * a * bb / 8.0;
  const v4d transverse_k = section.hourglass_transverse * section.shear_factor *
                           section.shear_modulus * t * t * t * bb / 12.0;
  const v4d bending_k =
      section.hourglass_bending * material.youngs_modulus * t * t * t * a * bb / 192.0;
  const v4d stiffness[5] = {membrane_k, membrane_k, transverse_k, bending_k, bending_k};
  v4d resultant[5];
  for (int k = 0; k < 5; ++k) resultant[k] = load(states.hourglass + kQuadLanes * k);
  v4d hourglass_work = zero;
  for (int k = 0; k < 5; ++k) {
    const v4d increment = rate[k] * dt;
    const v4d old = resultant[k];
    resultant[k] += stiffness[k] * increment;
    hourglass_work += 0.5 * (old + resultant[k]) * increment;
  }
  for (int k = 0; k < 5; ++k) store(states.hourglass + kQuadLanes * k, resultant[k]);
  for (int i = 0; i < 4; ++i) {
    local[i][0] += gamma[i] * resultant[0];
    local[i][1] += gamma[i] * resultant[1];
    local[i][3] += gamma[i] * resultant[3];
    local[i][4] += gamma[i] * resultant[4];
  }
  const v4d q = resultant[2];
  add_edge_forces(x, y, {q * w_weight[0], q * w_weight[1], q * w_weight[2], q * w_weight[3]},
                  local);

  // Back to global axes (local[i][5], the drilling moment, is zero but is added as there).
  for (int i = 0; i < 4; ++i) {
    const V3 fg = e1 * local[i][0] + e2 * local[i][1] + e3 * local[i][2];
    const V3 mg = e1 * local[i][3] + e2 * local[i][4] + e3 * local[i][5];
    for (int l = 0; l < kQuadLanes; ++l) {
      (*out.nodal[l])[i] = {fg.x[l], fg.y[l], fg.z[l], mg.x[l], mg.y[l], mg.z[l]};
    }
  }
  for (int l = 0; l < kQuadLanes; ++l) {
    *out.internal_energy_increment[l] = internal_energy[l];
    *out.hourglass_energy_increment[l] = hourglass_work[l];
  }
}

void shell_internal_forces_quads(const Vec3* x, const Vec3* v, const Vec3* omega,
                                 const Nodes& nodes, double dt, const SectionProperties& section,
                                 const std::array<ElementState, kQuadLanes>& states,
                                 const QuadBatchOutput& out) {
  // Interleave the four histories, run the kernel, copy back.
  const int points = section.points;
  std::vector<double> stress(3 * kQuadLanes * points), plastic(kQuadLanes * points),
      shear(3 * kQuadLanes), hourglass(5 * kQuadLanes);
  // copy(lane-wise value, its interleaved copy) for every value of every field and lane.
  const auto each_value = [&](auto copy) {
    for (int l = 0; l < kQuadLanes; ++l) {
      const ElementState& s = states[l];
      for (int k = 0; k < 3 * points; ++k) copy(s.stress[k], stress[kQuadLanes * k + l]);
      for (int k = 0; k < points; ++k) copy(s.plastic_strain[k], plastic[kQuadLanes * k + l]);
      for (int k = 0; k < 3; ++k) copy(s.shear[k], shear[kQuadLanes * k + l]);
      for (int k = 0; k < 5; ++k) copy(s.hourglass[k], hourglass[kQuadLanes * k + l]);
    }
  };
  each_value([](double& lane, double& packed) { packed = lane; });
  const QuadBatchState interleaved{stress.data(), plastic.data(), shear.data(), hourglass.data()};
  shell_internal_forces_quads(x, v, omega, nodes, dt, section, interleaved, out);
  each_value([](double& lane, double& packed) { lane = packed; });
}

}  // namespace quarry::fem
