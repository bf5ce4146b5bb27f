// Belytschko–Tsay quadrilateral and C0 triangle, one-point quadrature in the plane, several
// points through the thickness. Kinematics (Belytschko, Lin & Tsay 1984, eqs. 9-16; Belytschko,
// Liu & Moran, "Nonlinear Finite Elements for Continua and Structures", 2000, §9.7): mid-surface
// strain rates d = B v̂, curvature rates κ = B θ̂, transverse shear γ = B ŵ + N θ̂, all in the
// co-rotational frame, where the stresses are stored and need no objective rate.
#include "fem/shell_element.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace quarry::fem {
namespace {

// Local (frame) description of the element at one configuration.
struct LocalGeometry {
  ElementFrame frame;
  std::array<double, 4> x{}, y{};    // in-plane coordinates of the nodes (m)
  std::array<double, 4> z{};         // heights above the frame's plane: a warped quad's (m)
  std::array<double, 4> b1{}, b2{};  // ∂N_I/∂x̂, ∂N_I/∂ŷ at the centre (1/m)
  double area = 0.0;                 // A (m²)
  // Quad: centre Jacobian columns g_ξ = ∂x/∂ξ, g_η = ∂x/∂η (m) and its determinant (m²).
  double gxi_x = 0.0, gxi_y = 0.0, geta_x = 0.0, geta_y = 0.0, jacobian = 0.0;
};

// The frame, the nodes' in-plane coordinates and the area: all the stable step and the masses
// need (element_area); local_geometry adds the derivatives, with the same operations.
LocalGeometry plane_geometry(const std::array<Vec3, 4>& x, int node_count) {
  LocalGeometry g;
  g.frame = element_frame(x, node_count);
  for (int i = 0; i < node_count; ++i) {
    const Vec3 r = x[i] - g.frame.origin;
    g.x[i] = dot(r, g.frame.e1);
    g.y[i] = dot(r, g.frame.e2);
    g.z[i] = dot(r, g.frame.e3);
  }
  if (node_count == 4) {
    // A = ½ (x31 y42 + x24 y31) (Belytschko, Lin & Tsay 1984 eq. 14), 0-based node numbers.
    g.area = 0.5 * ((g.x[2] - g.x[0]) * (g.y[3] - g.y[1]) + (g.x[1] - g.x[3]) * (g.y[2] - g.y[0]));
  } else {
    // Linear triangle: 2A = x21 y31 − x31 y21.
    g.area = 0.5 * ((g.x[1] - g.x[0]) * (g.y[2] - g.y[0]) - (g.x[2] - g.x[0]) * (g.y[1] - g.y[0]));
  }
  return g;
}

LocalGeometry local_geometry(const std::array<Vec3, 4>& x, int node_count) {
  LocalGeometry g = plane_geometry(x, node_count);
  if (node_count == 4) {
    // The centre derivatives of the bilinear functions (Belytschko, Lin & Tsay 1984 eq. 14).
    const double inverse = 1.0 / (2.0 * g.area);
    g.b1 = {(g.y[1] - g.y[3]) * inverse, (g.y[2] - g.y[0]) * inverse,
            (g.y[3] - g.y[1]) * inverse, (g.y[0] - g.y[2]) * inverse};
    g.b2 = {(g.x[3] - g.x[1]) * inverse, (g.x[0] - g.x[2]) * inverse,
            (g.x[1] - g.x[3]) * inverse, (g.x[2] - g.x[0]) * inverse};
    g.gxi_x = 0.25 * (-g.x[0] + g.x[1] + g.x[2] - g.x[3]);
    g.gxi_y = 0.25 * (-g.y[0] + g.y[1] + g.y[2] - g.y[3]);
    g.geta_x = 0.25 * (-g.x[0] - g.x[1] + g.x[2] + g.x[3]);
    g.geta_y = 0.25 * (-g.y[0] - g.y[1] + g.y[2] + g.y[3]);
    g.jacobian = g.gxi_x * g.geta_y - g.gxi_y * g.geta_x;
  } else {
    // ∂N_I/∂x = (y_J − y_K)/2A, ∂N_I/∂y = (x_K − x_J)/2A.
    const double twice_area =
        (g.x[1] - g.x[0]) * (g.y[2] - g.y[0]) - (g.x[2] - g.x[0]) * (g.y[1] - g.y[0]);
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      g.b1[i] = (g.y[j] - g.y[k]) / twice_area;
      g.b2[i] = (g.x[k] - g.x[j]) / twice_area;
    }
  }
  return g;
}

// Triangle transverse shear with edge-tied (assumed) strains, the MITC3 idea (Lee & Bathe 2004,
// Comput. Struct. 82:945): the shear field γ(x) = a + c (−ŷ, x̂) (x̂, ŷ from the centroid) has a
// constant tangential component on each edge, which is tied to the edge's own value
// γ_τ = (w_j − w_i)/L + τ·(θ̄_y, −θ̄_x), θ̄ the mean of the edge's nodal rotations. A linear
// triangle with one-point shear locks in thin plates (four constraints per node); this does not.
// Energy ∫ ½ κGt |γ|² dA = ½ κGt (A |a|² + J c²), J = A (L₁² + L₂² + L₃²)/36 the polar moment.
// Returns the shear work of the step (J) and adds the nodal forces and moments to `local`.
double triangle_shear(const LocalGeometry& g, const std::array<Vec3, 4>& vl,
                      const std::array<Vec3, 4>& wl, double dt, double shear_stiffness,
                      double* resultants, std::array<std::array<double, 6>, 4>& local) {
  std::array<double, 3> length{}, tx{}, ty{};
  double matrix[3][3];
  double length_sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int i = k, j = (k + 1) % 3;
    const double dx = g.x[j] - g.x[i], dy = g.y[j] - g.y[i];
    length[k] = std::sqrt(dx * dx + dy * dy);
    length_sum += dx * dx + dy * dy;
    tx[k] = dx / length[k];
    ty[k] = dy / length[k];
    const double mx = 0.5 * (g.x[i] + g.x[j]), my = 0.5 * (g.y[i] + g.y[j]);
    matrix[k][0] = tx[k];
    matrix[k][1] = ty[k];
    matrix[k][2] = mx * ty[k] - my * tx[k];
  }
  // Inverse of the 3 × 3 tying matrix (adjugate / determinant).
  double inverse[3][3];
  const double det = matrix[0][0] * (matrix[1][1] * matrix[2][2] - matrix[1][2] * matrix[2][1]) -
                     matrix[0][1] * (matrix[1][0] * matrix[2][2] - matrix[1][2] * matrix[2][0]) +
                     matrix[0][2] * (matrix[1][0] * matrix[2][1] - matrix[1][1] * matrix[2][0]);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      inverse[r][c] = (matrix[r1][c1] * matrix[r2][c2] - matrix[r1][c2] * matrix[r2][c1]) / det;
    }
  }
  std::array<double, 3> edge_rate{};
  for (int k = 0; k < 3; ++k) {
    const int i = k, j = (k + 1) % 3;
    edge_rate[k] = (vl[j].z - vl[i].z) / length[k] +
                   0.5 * ((wl[i].y + wl[j].y) * tx[k] - (wl[i].x + wl[j].x) * ty[k]);
  }
  const double polar = g.area * length_sum / 36.0;
  const std::array<double, 3> measure{g.area, g.area, polar};
  double work = 0.0;
  std::array<double, 3> generalized{};
  for (int r = 0; r < 3; ++r) {
    double increment = 0.0;
    for (int k = 0; k < 3; ++k) increment += inverse[r][k] * edge_rate[k];
    increment *= dt;
    const double old = resultants[r];
    resultants[r] += shear_stiffness * increment;
    work += 0.5 * (old + resultants[r]) * increment * measure[r];
    generalized[r] = resultants[r] * measure[r];
  }
  for (int k = 0; k < 3; ++k) {
    double edge_force = 0.0;  // conjugate to the edge shear γ_τ,k (N·m)
    for (int r = 0; r < 3; ++r) edge_force += inverse[r][k] * generalized[r];
    const int i = k, j = (k + 1) % 3;
    local[j][2] += edge_force / length[k];
    local[i][2] -= edge_force / length[k];
    for (const int node : {i, j}) {
      local[node][3] -= 0.5 * edge_force * ty[k];
      local[node][4] += 0.5 * edge_force * tx[k];
    }
  }
  return work;
}

// Quad transverse shear at the centre from edge-tied covariant strains (Bathe & Dvorkin 1985,
// IJNME 21:367, evaluated at the centre as in the one-point element of Belytschko, Wong &
// Chiang 1992, CMAME 96:93): each edge's tangential shear γ_τ = (w_j − w_i)/L + τ·(θ̄_y, −θ̄_x)
// is exact for the fields of constant curvature, so the element passes the Kirchhoff patch
// test on distorted meshes (the plain centre value B·w + N·θ does not). On rectangles it equals
// the Belytschko–Tsay centre value. Edges (0,1) and (3,2) carry γ_ξ, (0,3) and (1,2) γ_η.
// Returns the shear work of the step (J) and adds the nodal forces and moments to `local`.
constexpr int kQuadEdges[4][2] = {{0, 1}, {3, 2}, {0, 3}, {1, 2}};

struct QuadShearRates {
  std::array<double, 4> covariant{};  // c_k = γ_τ L/2 of the edges A, C, D, B (m/s)
  double x = 0.0, y = 0.0;            // γ̇ at the centre (1/s)
};

QuadShearRates quad_shear_rates(const LocalGeometry& g, const std::array<Vec3, 4>& vl,
                                const std::array<Vec3, 4>& wl) {
  QuadShearRates r;
  // Covariant edge shears c = γ_τ L/2 = ½ (w_j − w_i) + ¼ ((θy_i + θy_j) dx − (θx_i + θx_j) dy).
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const double dx = g.x[j] - g.x[i], dy = g.y[j] - g.y[i];
    r.covariant[k] = 0.5 * (vl[j].z - vl[i].z) +
                     0.25 * ((wl[i].y + wl[j].y) * dx - (wl[i].x + wl[j].x) * dy);
  }
  const double gamma_xi = 0.5 * (r.covariant[0] + r.covariant[1]);
  const double gamma_eta = 0.5 * (r.covariant[2] + r.covariant[3]);
  // γ·g_ξ = γ_ξ, γ·g_η = γ_η with the centre Jacobian columns g_ξ, g_η.
  const double gxi_x = g.gxi_x, gxi_y = g.gxi_y, geta_x = g.geta_x, geta_y = g.geta_y;
  const double det = g.jacobian;
  r.x = (gamma_xi * geta_y - gamma_eta * gxi_y) / det;
  r.y = (gamma_eta * gxi_x - gamma_xi * geta_x) / det;
  return r;
}

// Adds the nodal forces and moments of generalized forces F_k conjugate to the covariant edge
// shears c_k: ∂c/∂w_j = ½, ∂c/∂w_i = −½, ∂c/∂θy = ¼ dx, ∂c/∂θx = −¼ dy at both ends.
void add_quad_edge_forces(const LocalGeometry& g, const std::array<double, 4>& edge_force,
                          std::array<std::array<double, 6>, 4>& local) {
  for (int k = 0; k < 4; ++k) {
    const int i = kQuadEdges[k][0], j = kQuadEdges[k][1];
    const double dx = g.x[j] - g.x[i], dy = g.y[j] - g.y[i];
    local[j][2] += 0.5 * edge_force[k];
    local[i][2] -= 0.5 * edge_force[k];
    for (const int node : {i, j}) {
      local[node][3] -= 0.25 * edge_force[k] * dy;
      local[node][4] += 0.25 * edge_force[k] * dx;
    }
  }
}

double quad_shear(const LocalGeometry& g, const QuadShearRates& rates, double dt,
                  double shear_stiffness, double* resultants,
                  std::array<std::array<double, 6>, 4>& local) {
  const double gxi_x = g.gxi_x, gxi_y = g.gxi_y, geta_x = g.geta_x, geta_y = g.geta_y;
  const double det = g.jacobian;
  const double increment_x = rates.x * dt;
  const double increment_y = rates.y * dt;
  const double old_x = resultants[0], old_y = resultants[1];
  resultants[0] += shear_stiffness * increment_x;
  resultants[1] += shear_stiffness * increment_y;
  const double work = g.area * (0.5 * (old_x + resultants[0]) * increment_x +
                                0.5 * (old_y + resultants[1]) * increment_y);
  // Conjugates of γ_ξ and γ_η in the power A Q·γ, shared by their two edges.
  const double force_xi = g.area * (resultants[0] * geta_y - resultants[1] * geta_x) / det;
  const double force_eta = g.area * (resultants[1] * gxi_x - resultants[0] * gxi_y) / det;
  add_quad_edge_forces(g, {0.5 * force_xi, 0.5 * force_xi, 0.5 * force_eta, 0.5 * force_eta},
                       local);
  return work;
}

}  // namespace

ElementFrame element_frame(const std::array<Vec3, 4>& x, int node_count) {
  ElementFrame frame;
  Vec3 sum;
  for (int i = 0; i < node_count; ++i) sum += x[i];
  frame.origin = sum / node_count;
  const Vec3 normal = node_count == 4 ? cross(x[2] - x[0], x[3] - x[1])
                                      : cross(x[1] - x[0], x[2] - x[0]);
  frame.e3 = normalized(normal);
  const Vec3 edge = x[1] - x[0];
  frame.e1 = normalized(edge - dot(edge, frame.e3) * frame.e3);
  frame.e2 = cross(frame.e3, frame.e1);
  return frame;
}

double element_area(const std::array<Vec3, 4>& x, int node_count) {
  return plane_geometry(x, node_count).area;
}

double characteristic_length(const std::array<Vec3, 4>& x, int node_count) {
  double longest = 0.0;
  for (int i = 0; i < node_count; ++i) {
    longest = std::max(longest, norm(x[(i + 1) % node_count] - x[i]));
  }
  const double area = element_area(x, node_count);
  return (node_count == 4 ? 1.0 : 2.0) * area / longest;
}

double quad_warpage_degrees(const std::array<Vec3, 4>& x) {
  const auto angle = [](const Vec3& a, const Vec3& b) {  // between two normals (degrees)
    return std::atan2(norm(cross(a, b)), dot(a, b)) * 180.0 / std::numbers::pi;
  };
  const double along_02 = angle(cross(x[1] - x[0], x[2] - x[0]), cross(x[2] - x[0], x[3] - x[0]));
  const double along_13 = angle(cross(x[2] - x[1], x[3] - x[1]), cross(x[3] - x[1], x[0] - x[1]));
  return std::max(along_02, along_13);
}

ElementForces shell_internal_forces(const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& v,
                                    const std::array<Vec3, 4>& omega, int node_count, double dt,
                                    const SectionProperties& section, ElementState state) {
  const LocalGeometry g = local_geometry(x, node_count);
  const ElementFrame& f = g.frame;
  const int n = node_count;
  // Nodal velocities and angular velocities in the co-rotational frame.
  std::array<Vec3, 4> vl{}, wl{};
  for (int i = 0; i < n; ++i) {
    vl[i] = {dot(v[i], f.e1), dot(v[i], f.e2), dot(v[i], f.e3)};
    wl[i] = {dot(omega[i], f.e1), dot(omega[i], f.e2), dot(omega[i], f.e3)};
  }
  const double shape = 1.0 / n;  // N_I at the centre
  // Strain increments over dt: membrane (xx, yy, γxy), curvature (1/m), transverse shear γ.
  Voigt3 membrane{}, curvature{};
  double shear_x = 0.0, shear_y = 0.0;
  for (int i = 0; i < n; ++i) {
    membrane[0] += g.b1[i] * vl[i].x;
    membrane[1] += g.b2[i] * vl[i].y;
    membrane[2] += g.b2[i] * vl[i].x + g.b1[i] * vl[i].y;
    // u(z) = u + z (θy, −θx): κxx = ∂θy/∂x, κyy = −∂θx/∂y, 2κxy = ∂θy/∂y − ∂θx/∂x.
    curvature[0] += g.b1[i] * wl[i].y;
    curvature[1] -= g.b2[i] * wl[i].x;
    curvature[2] += g.b2[i] * wl[i].y - g.b1[i] * wl[i].x;
    shear_x += g.b1[i] * vl[i].z + shape * wl[i].y;
    shear_y += g.b2[i] * vl[i].z - shape * wl[i].x;
  }
  for (int k = 0; k < 3; ++k) {
    membrane[k] *= dt;
    curvature[k] *= dt;
  }
  shear_x *= dt;
  shear_y *= dt;

  ElementForces out;
  const double t = section.thickness;
  const double half = 0.5 * t;
  // Through the thickness: σ at z = ξ t/2 from Δε = Δε_m + z Δκ; resultants N = ∫σ dz,
  // M = ∫z σ dz (per unit length), stress work ∫ ½(σ_n + σ_n+1)·Δε dz per unit area.
  Voigt3 force{}, moment{};
  double work = 0.0;
  // A local copy: the stores through state.stress below could alias the section's fields as
  // far as the compiler knows, which would make it reload E, ν and recompute E/(1 − ν²) per point.
  const PlaneStressMaterial material = section.material;
  for (int p = 0; p < section.points; ++p) {
    const double z = section.coordinate[p] * half;
    const double w = section.weight[p] * half;
    double* s = state.stress + 3 * p;
    const Voigt3 increment{membrane[0] + z * curvature[0], membrane[1] + z * curvature[1],
                           membrane[2] + z * curvature[2]};
    Voigt3 stress{s[0], s[1], s[2]};
    const Voigt3 old = stress;
    update_plane_stress(material, increment, stress, state.plastic_strain[p]);
    for (int k = 0; k < 3; ++k) {
      s[k] = stress[k];
      work += 0.5 * (old[k] + stress[k]) * increment[k] * w;
      force[k] += stress[k] * w;
      moment[k] += stress[k] * z * w;
    }
  }
  // Transverse shear, elastic: Q = κ G t γ.
  const double shear_stiffness = section.shear_factor * section.shear_modulus * t;
  std::array<std::array<double, 6>, 4> local{};
  // Edge-tied quads: the covariant edge shears, computed once for the shear and the w
  // hourglass mode below (both read the same vl, wl and geometry).
  QuadShearRates edge_shear;
  if (n == 4 && section.quad_shear == QuadShear::centre) {
    // Belytschko–Tsay: γ at the centre, γ = B ŵ + N θ̂, conjugate resultants Q_x, Q_y.
    const double old_qx = state.shear[0], old_qy = state.shear[1];
    state.shear[0] += shear_stiffness * shear_x;
    state.shear[1] += shear_stiffness * shear_y;
    work += 0.5 * (old_qx + state.shear[0]) * shear_x + 0.5 * (old_qy + state.shear[1]) * shear_y;
    for (int i = 0; i < 4; ++i) {
      local[i][2] += g.area * (g.b1[i] * state.shear[0] + g.b2[i] * state.shear[1]);
      local[i][3] -= g.area * shape * state.shear[1];
      local[i][4] += g.area * shape * state.shear[0];
    }
  } else if (n == 4) {
    edge_shear = quad_shear_rates(g, vl, wl);
    work += quad_shear(g, edge_shear, dt, shear_stiffness, state.shear, local) / g.area;
  } else {
    work += triangle_shear(g, vl, wl, dt, shear_stiffness, state.shear, local) / g.area;
  }
  out.internal_energy_increment = work * g.area;

  // Nodal forces from the virtual power A (N:δd + M:δκ + Q·δγ), in the element frame (the
  // shear forces are already in `local`).
  const double a = g.area;
  for (int i = 0; i < n; ++i) {
    local[i][0] += a * (g.b1[i] * force[0] + g.b2[i] * force[2]);
    local[i][1] += a * (g.b2[i] * force[1] + g.b1[i] * force[2]);
    local[i][3] += a * (-g.b2[i] * moment[1] - g.b1[i] * moment[2]);
    local[i][4] += a * (g.b1[i] * moment[0] + g.b2[i] * moment[2]);
  }

  if (n == 4) {
    // Hourglass control (Belytschko & Tsay 1983; Belytschko, Lin & Tsay 1984 eqs. 27-30): the
    // vector γ_I = h_I − (h·x̂) B1_I − (h·ŷ) B2_I, h = (1, −1, 1, −1), is orthogonal to every
    // linear field, so rigid motion and constant strain leave the hourglass resultants alone.
    const std::array<double, 4> h{1.0, -1.0, 1.0, -1.0};
    double hx = 0.0, hy = 0.0, bb = 0.0;
    for (int i = 0; i < 4; ++i) {
      hx += h[i] * g.x[i];
      hy += h[i] * g.y[i];
      bb += g.b1[i] * g.b1[i] + g.b2[i] * g.b2[i];
    }
    std::array<double, 4> gamma{};
    std::array<double, 5> rate{};  // γ·v̂x, γ·v̂y, γ·v̂z, γ·θ̂x, γ·θ̂y
    double hz = 0.0, spin_x = 0.0, spin_y = 0.0;
    for (int i = 0; i < 4; ++i) {
      gamma[i] = h[i] - hx * g.b1[i] - hy * g.b2[i];
      rate[0] += gamma[i] * vl[i].x;
      rate[1] += gamma[i] * vl[i].y;
      rate[2] += gamma[i] * vl[i].z;
      rate[3] += gamma[i] * wl[i].x;
      rate[4] += gamma[i] * wl[i].y;
      hz += h[i] * g.z[i];
      spin_x += wl[i].x;
      spin_y += wl[i].y;
    }
    // Warping correction (Belytschko, Wong & Chiang 1992, CMAME 96:93, eqs. 47-48): a warped
    // quad's nodes sit at heights z_I = ±(h·z)/4 off its plane, so a rigid rotation Ω about an
    // in-plane axis moves them in the plane by Ω × z_I e3, an in-plane hourglass pattern:
    // γ·v̂x = Ω_y (h·z), γ·v̂y = −Ω_x (h·z). Less that rigid part, with Ω the nodes' mean spin,
    // the in-plane hourglass rates vanish in rigid motion, and their forces (with the moments
    // conjugate to the correction, added below) are in moment equilibrium; without it those
    // forces at ±z_I carried a net moment 4 z_I Q that drove a twisted mesh ever further.
    rate[0] -= 0.25 * hz * spin_y;
    rate[1] += 0.25 * hz * spin_x;
    // With edge-tied shear, the w mode is measured from the edge shears, (c_C − c_A) +
    // (c_B − c_D) less its constant-shear part (h·x̂) γ_x + (h·ŷ) γ_y: equal to γ·ŵ when the
    // rotations are zero, but zero for every Kirchhoff field of constant curvature (whose edge
    // shears all vanish), so that the hourglass control does not resist a uniform twist on
    // distorted quads (cf. the physical stabilisation of Belytschko & Leviathan 1994).
    // q_w = Σ α_k c_k with α_k = sign_k − ½ (h·x̂, h·ŷ)·∂γ/∂γ_ξ (A, C) or ·∂γ/∂γ_η (D, B).
    std::array<double, 4> w_weight{};
    const bool edge_tied = section.quad_shear == QuadShear::edge_tied;
    if (edge_tied) {
      const double gxi_x = g.gxi_x, gxi_y = g.gxi_y, geta_x = g.geta_x, geta_y = g.geta_y;
      const double det = g.jacobian;
      const double along_xi = 0.5 * (hx * geta_y - hy * geta_x) / det;
      const double along_eta = 0.5 * (-hx * gxi_y + hy * gxi_x) / det;
      w_weight = {-1.0 - along_xi, 1.0 - along_xi, -1.0 - along_eta, 1.0 - along_eta};
      rate[2] = 0.0;
      for (int k = 0; k < 4; ++k) rate[2] += w_weight[k] * edge_shear.covariant[k];
    }
    const PlaneStressMaterial& m = section.material;
    // Stiffnesses (BLT 1984 eq. 30): r_m E t A B·B/8, r_w κ G t³ B·B/12, r_θ E t³ A B·B/192.
    const double membrane_k = section.hourglass_membrane * m.youngs_modulus * t * a * bb / 8.0;
    const double transverse_k = section.hourglass_transverse * section.shear_factor *
                                section.shear_modulus * t * t * t * bb / 12.0;
    const double bending_k =
        section.hourglass_bending * m.youngs_modulus * t * t * t * a * bb / 192.0;
    const std::array<double, 5> stiffness{membrane_k, membrane_k, transverse_k, bending_k,
                                          bending_k};
    double hourglass_work = 0.0;
    for (int k = 0; k < 5; ++k) {
      const double increment = rate[k] * dt;
      const double old = state.hourglass[k];
      state.hourglass[k] += stiffness[k] * increment;
      hourglass_work += 0.5 * (old + state.hourglass[k]) * increment;
    }
    out.hourglass_energy_increment = hourglass_work;
    for (int i = 0; i < 4; ++i) {
      local[i][0] += gamma[i] * state.hourglass[0];
      local[i][1] += gamma[i] * state.hourglass[1];
      if (!edge_tied) local[i][2] += gamma[i] * state.hourglass[2];
      local[i][3] += gamma[i] * state.hourglass[3] + 0.25 * hz * state.hourglass[1];
      local[i][4] += gamma[i] * state.hourglass[4] - 0.25 * hz * state.hourglass[0];
    }
    if (edge_tied) {
      const double q = state.hourglass[2];
      add_quad_edge_forces(g, {q * w_weight[0], q * w_weight[1], q * w_weight[2], q * w_weight[3]},
                           local);
    }
  }

  // Drilling stiffness (Hughes & Brezzi 1989, CMAME 72:105, with the rotation's in-plane part
  // tied to the element's spin, Kanok-Nukulchai 1979, IJNME 14:179): the nodes' mean spin
  // about the normal, less the in-plane spin of the translations ½(∂v̂y/∂x − ∂v̂x/∂y), drives
  // a resultant M_d of stiffness α G t A (section.drilling = α). A flat mesh never loads it;
  // where neighbouring elements are not coplanar (a twisted or doubly curved wall) a node's
  // spin about one element's normal is a bending rotation of the next one's, and without it a
  // uniform spin about the normals let a twisted strip bend with no element straining (the
  // MacNeal–Harder twisted beam kept deflecting). Zero in rigid motion; its work is counted
  // with the hourglass work (artificial energy). State: a quad's unused third shear slot, a
  // triangle's first hourglass slot (it has no hourglass control).
  if (section.drilling > 0.0) {
    double spin = 0.0, in_plane = 0.0;
    for (int i = 0; i < n; ++i) {
      spin += wl[i].z;
      in_plane += g.b1[i] * vl[i].y - g.b2[i] * vl[i].x;
    }
    const double increment = (spin * shape - 0.5 * in_plane) * dt;
    double& drill = n == 4 ? state.shear[2] : state.hourglass[0];
    const double old = drill;
    drill += section.drilling * section.shear_modulus * t * a * increment;
    out.hourglass_energy_increment += 0.5 * (old + drill) * increment;
    for (int i = 0; i < n; ++i) {
      local[i][0] += 0.5 * g.b2[i] * drill;
      local[i][1] -= 0.5 * g.b1[i] * drill;
      local[i][5] += shape * drill;
    }
  }

  // Back to global axes.
  for (int i = 0; i < n; ++i) {
    const Vec3 fg = local[i][0] * f.e1 + local[i][1] * f.e2 + local[i][2] * f.e3;
    const Vec3 mg = local[i][3] * f.e1 + local[i][4] * f.e2 + local[i][5] * f.e3;
    out.nodal[i] = {fg.x, fg.y, fg.z, mg.x, mg.y, mg.z};
  }
  return out;
}

}  // namespace quarry::fem
