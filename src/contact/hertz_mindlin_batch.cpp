// The batched Hertz–Mindlin kernel (hertz_mindlin_batch.h), compiled once per vector width.
#include "contact/hertz_mindlin_batch.h"

#include <cmath>

namespace quarry {

namespace {

// Contact m of the batch by the scalar law (evaluate_contact), from the lane's inputs: the
// velocities are differences (v_i − v_j as v_i, 0 as v_j), which is all the law uses.
[[gnu::noinline]] void finish_by_scalar_law(const InteractionParameters& parameters, HertzMindlinBatch& b, int m,
                          double dt, double lead_time) {
  const double distance = std::sqrt(b.distance2[m]);  // m
  ContactKinematics kin;
  kin.normal = Vec3{b.dx[m], b.dy[m], b.dz[m]} * (1.0 / distance);
  kin.overlap = (b.radius_i[m] + b.radius_j[m]) - distance;
  kin.radius_i = b.radius_i[m], kin.radius_j = b.radius_j[m];
  kin.inv_mass_i = b.inv_mass_i[m], kin.inv_mass_j = b.inv_mass_j[m];
  kin.velocity_i = {b.vx[m], b.vy[m], b.vz[m]};
  kin.angular_velocity_i = {b.wix[m], b.wiy[m], b.wiz[m]};
  kin.angular_velocity_j = {b.wjx[m], b.wjy[m], b.wjz[m]};
  kin.velocity_lead_i = {b.lvx[m], b.lvy[m], b.lvz[m]};
  kin.angular_velocity_lead_i = {b.lwix[m], b.lwiy[m], b.lwiz[m]};
  kin.angular_velocity_lead_j = {b.lwjx[m], b.lwjy[m], b.lwjz[m]};
  kin.lead_time = lead_time;
  ContactHistory history;
  history.tangential_displacement = {b.hx[m], b.hy[m], b.hz[m]};
  history.normal_force = b.fn[m];
  const ContactResult r = evaluate_contact(parameters, kin, history, dt);
  b.hx[m] = history.tangential_displacement.x, b.hy[m] = history.tangential_displacement.y,
  b.hz[m] = history.tangential_displacement.z;
  b.fn[m] = history.normal_force;
  b.fx[m] = r.force_i.x, b.fy[m] = r.force_i.y, b.fz[m] = r.force_i.z;
  b.tix[m] = r.torque_i.x, b.tiy[m] = r.torque_i.y, b.tiz[m] = r.torque_i.z;
  b.tjx[m] = r.torque_j.x, b.tjy[m] = r.torque_j.y, b.tjz[m] = r.torque_j.z;
}

// The vector loop over lanes [0, padded). kCohesion: SJKR's −k A n on touching pairs;
// kRolling: the constant directional rolling torque on each body (contact_law.h). Both are
// compiled out of the plain law. Returns nonzero if a contact passes the overlap guard.
template <bool kCohesion, bool kRolling>
[[gnu::always_inline]] inline int vector_lanes(const InteractionParameters& parameters,
                                               HertzMindlinBatch& b, int padded, double dt,
                                               double lead_time, double overlap_limit) {
  const double youngs = parameters.effective_youngs_modulus;      // Pa, E*
  const double shear = parameters.effective_shear_modulus;        // Pa, G*
  const double normal_damping_factor = parameters.hertz_normal_damping;
  const double tangential_damping_factor = parameters.hertz_tangential_damping;
  const double friction = parameters.static_friction;             // μs
  const double cohesion_density = parameters.cohesion_energy_density;  // J/m³, k
  const double rolling_friction = parameters.rolling_friction;         // μr
  const int count = b.count;
  int excessive = 0;
#pragma omp simd reduction(| : excessive)
  for (int m = 0; m < padded; ++m) {
    const double distance = std::sqrt(b.distance2[m]);  // m
    const double inverse = 1.0 / distance;
    const double nx = b.dx[m] * inverse, ny = b.dy[m] * inverse, nz = b.dz[m] * inverse;
    const double ri = b.radius_i[m], rj = b.radius_j[m];
    const double overlap = (ri + rj) - distance;                              // m, δ > 0
    const double effective_radius = ri * rj / (ri + rj);                      // m, R*
    // kg, m*; two fixed particles (both 1/m = 0): 0, no damping of a motion neither has.
    const double inverse_sum = b.inv_mass_i[m] + b.inv_mass_j[m];  // 1/kg
    const double effective_mass = inverse_sum > 0.0 ? 1.0 / inverse_sum : 0.0;
    const double lever_i = ri - 0.5 * overlap, lever_j = rj - 0.5 * overlap;  // m
    // The run's overlap guard; the padding lanes are not contacts.
    excessive |= (m < count) & overlap_past_limit(overlap, ri, rj, overlap_limit);
    // Relative velocity at the contact point: (v_i − v_j) − (lever_i ω_i + lever_j ω_j) × n.
    const double sx = lever_i * b.wix[m] + lever_j * b.wjx[m];
    const double sy = lever_i * b.wiy[m] + lever_j * b.wjy[m];
    const double sz = lever_i * b.wiz[m] + lever_j * b.wjz[m];
    const double rx = b.vx[m] - (sy * nz - sz * ny);
    const double ry = b.vy[m] - (sz * nx - sx * nz);
    const double rz = b.vz[m] - (sx * ny - sy * nx);
    const double drift_normal_velocity = rx * nx + ry * ny + rz * nz;  // m/s
    const double tx = rx - drift_normal_velocity * nx, ty = ry - drift_normal_velocity * ny,
                 tz = rz - drift_normal_velocity * nz;  // m/s, tangential velocity (springs)
    // At the force's time (dashpots): plus the leads' share.
    const double lx = lever_i * b.lwix[m] + lever_j * b.lwjx[m];
    const double ly = lever_i * b.lwiy[m] + lever_j * b.lwjy[m];
    const double lz = lever_i * b.lwiz[m] + lever_j * b.lwjz[m];
    const double qx = rx + (b.lvx[m] - (ly * nz - lz * ny));
    const double qy = ry + (b.lvy[m] - (lz * nx - lx * nz));
    const double qz = rz + (b.lvz[m] - (lx * ny - ly * nx));
    const double normal_velocity = qx * nx + qy * ny + qz * nz;  // m/s
    const double dtx = qx - normal_velocity * nx, dty = qy - normal_velocity * ny,
                 dtz = qz - normal_velocity * nz;  // m/s, tangential velocity (dashpot)
    // A contact whose step window matters (or a pair short of contact) is the scalar law's:
    // its lane computes on a harmless overlap and keeps its history for that law.
    const double half_path = 0.5 * dt * std::fabs(normal_velocity);  // m
    const bool scalar = contact::window_matters(overlap, half_path);
    b.scalar_lane[m] = scalar ? 1.0 : 0.0;
    const double lane_overlap = scalar ? 1.0e-6 * ri : overlap;  // m
    // Hertz normal spring, Mindlin tangential stiffness, EDEM dashpots (contact_law.h).
    const double contact_radius = std::sqrt(effective_radius * lane_overlap);  // m, a
    const double elastic_force = 4.0 / 3.0 * youngs * contact_radius * lane_overlap;  // N
    const double tangential_stiffness = 8.0 * shear * contact_radius;     // N/m
    const double root = std::sqrt(contact_radius * effective_mass);
    const double normal_damping = normal_damping_factor * root;  // N·s/m
    // The dashpot's velocity at the force's time, implicit in this contact's force.
    // SJKR (cohesion_sjkr.h): k A, A the lens's circle at this overlap (N, attractive).
    const double cohesion =
        kCohesion ? contact::sjkr_cohesion_force(
                        cohesion_density, contact::sphere_sphere_contact_area(ri, rj, lane_overlap))
                  : 0.0;
    const double damped_normal_velocity = contact::implicit_normal_velocity(
        normal_velocity, kCohesion ? elastic_force - cohesion : elastic_force, b.fn[m],
        normal_damping, lead_time * inverse_sum);
    // N: the load the contact circle carries (Coulomb's and the rolling limit), then with cohesion.
    const double contact_force = elastic_force - normal_damping * damped_normal_velocity;
    const double normal_force = kCohesion ? contact_force - cohesion : contact_force;
    b.fn[m] = scalar ? b.fn[m] : normal_force;
    const double tangential_damping = tangential_damping_factor * root;  // N·s/m
    const double load = std::fabs(contact_force);                         // N, |Fn|
    const double friction_limit = friction * load;                        // N
    // δt rotated into the tangent plane with its length kept, plus vt dt.
    const double hx = b.hx[m], hy = b.hy[m], hz = b.hz[m];
    const double along = hx * nx + hy * ny + hz * nz;
    const double px = hx - along * nx, py = hy - along * ny, pz = hz - along * nz;
    const double projected2 = px * px + py * py + pz * pz;
    // Branch-free (a select of values, so the loop vectorises): the square root and divisions
    // are taken on a safe operand in the lanes whose result is discarded.
    const double safe_projected2 = projected2 > 0.0 ? projected2 : 1.0;
    const double rescale = std::sqrt((hx * hx + hy * hy + hz * hz) / safe_projected2);
    const double scale = projected2 > 0.0 ? rescale : 0.0;
    const double ux = px * scale + tx * dt, uy = py * scale + ty * dt, uz = pz * scale + tz * dt;
    const double ddx = -tangential_damping * dtx, ddy = -tangential_damping * dty,
                 ddz = -tangential_damping * dtz;  // N, dashpot
    const double gx = -tangential_stiffness * ux + ddx, gy = -tangential_stiffness * uy + ddy,
                 gz = -tangential_stiffness * uz + ddz;  // N, spring + dashpot
    const double force2 = gx * gx + gy * gy + gz * gz;
    // Coulomb: cap |Ft| at μs |Fn| and move the spring back to what the capped force implies.
    const bool sliding = force2 > friction_limit * friction_limit;
    const double capped = friction_limit / std::sqrt(sliding ? force2 : 1.0);
    const double cap = sliding ? capped : 1.0;
    const double fx = gx * cap, fy = gy * cap, fz = gz * cap;
    const double positive = tangential_stiffness > 0.0;
    const double inverse_stiffness = positive / (positive > 0.0 ? tangential_stiffness : 1.0);
    b.hx[m] = scalar ? hx : sliding ? -(fx - ddx) * inverse_stiffness : ux;
    b.hy[m] = scalar ? hy : sliding ? -(fy - ddy) * inverse_stiffness : uy;
    b.hz[m] = scalar ? hz : sliding ? -(fz - ddz) * inverse_stiffness : uz;
    b.fx[m] = normal_force * nx + fx;
    b.fy[m] = normal_force * ny + fy;
    b.fz[m] = normal_force * nz + fz;
    // Torques: τi = −lever_i n × Ft, τj = −lever_j n × Ft.
    const double cx = ny * fz - nz * fy, cy = nz * fx - nx * fz, cz = nx * fy - ny * fx;
    b.tix[m] = -lever_i * cx, b.tiy[m] = -lever_i * cy, b.tiz[m] = -lever_i * cz;
    b.tjx[m] = -lever_j * cx, b.tjy[m] = -lever_j * cy, b.tjz[m] = -lever_j * cz;
    if constexpr (kRolling) {
      // τ = −μr |Fn| R ω̂ on each body, ω at the force's time (its lead added); none at rest.
      const double ax = b.wix[m] + b.lwix[m], ay = b.wiy[m] + b.lwiy[m], az = b.wiz[m] + b.lwiz[m];
      const double bx = b.wjx[m] + b.lwjx[m], by = b.wjy[m] + b.lwjy[m], bz = b.wjz[m] + b.lwjz[m];
      // −μr |Fn| R / |ω| (N·m·s), 0 at rest: a select of values, the division on a safe operand.
      const auto rolling_scale = [&](double speed, double radius) {
        const double torque_per_speed = -rolling_friction * load * radius / (speed > 0.0 ? speed : 1.0);
        return speed > 0.0 ? torque_per_speed : 0.0;
      };
      const double scale_i = rolling_scale(std::sqrt(ax * ax + ay * ay + az * az), ri);
      const double scale_j = rolling_scale(std::sqrt(bx * bx + by * by + bz * bz), rj);
      b.tix[m] += ax * scale_i, b.tiy[m] += ay * scale_i, b.tiz[m] += az * scale_i;
      b.tjx[m] += bx * scale_j, b.tjy[m] += by * scale_j, b.tjz[m] += bz * scale_j;
    }
  }
  return excessive;
}

}  // namespace

// GCC function multiversioning: one clone per target, chosen once at load time (ifunc).
__attribute__((target_clones("arch=x86-64-v4", "default")))
bool evaluate_hertz_mindlin_batch(const InteractionParameters& parameters, HertzMindlinBatch& b,
                                  double dt, double lead_time, double overlap_limit) {
  // Pad to whole vectors with a resting contact of unit size: finite, and never read back.
  const int padded = (b.count + HertzMindlinBatch::kLanes - 1) / HertzMindlinBatch::kLanes *
                     HertzMindlinBatch::kLanes;
  for (int m = b.count; m < padded; ++m) {
    b.dx[m] = 1.0, b.dy[m] = b.dz[m] = 0.0, b.distance2[m] = 1.0;
    b.radius_i[m] = b.radius_j[m] = 0.75;
    b.inv_mass_i[m] = b.inv_mass_j[m] = 1.0;
    b.vx[m] = b.vy[m] = b.vz[m] = 0.0;
    b.wix[m] = b.wiy[m] = b.wiz[m] = b.wjx[m] = b.wjy[m] = b.wjz[m] = 0.0;
    b.lvx[m] = b.lvy[m] = b.lvz[m] = 0.0;
    b.lwix[m] = b.lwiy[m] = b.lwiz[m] = b.lwjx[m] = b.lwjy[m] = b.lwjz[m] = 0.0;
    b.hx[m] = b.hy[m] = b.hz[m] = 0.0;
    b.fn[m] = 0.0;
  }
  const bool cohesion = parameters.cohesion_energy_density > 0.0;
  const bool rolling = parameters.rolling_model == RollingModel::constant_torque;
  const int excessive =
      cohesion ? (rolling ? vector_lanes<true, true>(parameters, b, padded, dt, lead_time, overlap_limit)
                          : vector_lanes<true, false>(parameters, b, padded, dt, lead_time, overlap_limit))
               : (rolling ? vector_lanes<false, true>(parameters, b, padded, dt, lead_time, overlap_limit)
                          : vector_lanes<false, false>(parameters, b, padded, dt, lead_time, overlap_limit));
  const int count = b.count;
  for (int m = 0; m < count; ++m)
    if (b.scalar_lane[m] != 0.0) finish_by_scalar_law(parameters, b, m, dt, lead_time);
  return excessive != 0;
}

}  // namespace quarry
