/* Prints, as JSON, what a C11 compiler makes of include/quarry/quarry.h: every struct's size and
 * every field's offset and size, and every constant. tests/python/test_abi.py compares the
 * Python module's ctypes mirror (python/quarry/_abi.py) with it, so that a field added, moved or
 * retyped in the header cannot go unnoticed by the Python side. */
#include <stddef.h>
#include <stdio.h>

#include "quarry/quarry.h"

static int first = 1;

/* One "key": value line of a flat JSON object. */
static void entry(const char* kind, const char* key, long long value) {
  printf("%s  \"%s:%s\": %lld", first ? "{\n" : ",\n", kind, key, value);
  first = 0;
}

#define SIZE(type) entry("size", #type, (long long)sizeof(type))
#define FIELD(type, field)                                                    \
  do {                                                                        \
    entry("offset", #type "." #field, (long long)offsetof(type, field));      \
    entry("size", #type "." #field, (long long)sizeof(((type*)0)->field));    \
  } while (0)
#define CONSTANT(name) entry("constant", #name, (long long)(name))

int main(void) {
  SIZE(quarry_sim);
  SIZE(quarry_open_info);
  SIZE(quarry_settings);
  SIZE(quarry_material);
  SIZE(quarry_interaction);
  SIZE(quarry_particle_type);
  SIZE(quarry_advance_result);
  SIZE(quarry_particle_data);
  SIZE(quarry_view);
  SIZE(quarry_new_particles);
  SIZE(quarry_surface_desc);
  SIZE(quarry_surface_info);
  SIZE(quarry_surface_loads);
  FIELD(quarry_sim, id);
  FIELD(quarry_open_info, struct_size);
  FIELD(quarry_open_info, abi_version);
  FIELD(quarry_open_info, deck_path);
  FIELD(quarry_open_info, checkpoint_path);
  FIELD(quarry_open_info, output_directory);
  FIELD(quarry_open_info, endpoint);
  FIELD(quarry_open_info, threads);
  FIELD(quarry_open_info, timeout_ms);
  FIELD(quarry_settings, struct_size);
  FIELD(quarry_settings, time_step);
  FIELD(quarry_settings, rayleigh_fraction);
  FIELD(quarry_settings, gravity);
  FIELD(quarry_settings, domain_min);
  FIELD(quarry_settings, domain_max);
  FIELD(quarry_settings, end_time);
  FIELD(quarry_settings, impact_speed);
  FIELD(quarry_settings, skin);
  FIELD(quarry_settings, integrator);
  FIELD(quarry_settings, sort_interval);
  FIELD(quarry_settings, max_overlap_fraction);
  FIELD(quarry_settings, seed);
  FIELD(quarry_settings, periodic);
  FIELD(quarry_material, struct_size);
  FIELD(quarry_material, name);
  FIELD(quarry_material, density);
  FIELD(quarry_material, youngs_modulus);
  FIELD(quarry_material, poisson_ratio);
  FIELD(quarry_interaction, struct_size);
  FIELD(quarry_interaction, material_a);
  FIELD(quarry_interaction, material_b);
  FIELD(quarry_interaction, restitution);
  FIELD(quarry_interaction, static_friction);
  FIELD(quarry_interaction, rolling_friction);
  FIELD(quarry_interaction, rolling_model);
  FIELD(quarry_interaction, cohesion_energy_density);
  FIELD(quarry_particle_type, struct_size);
  FIELD(quarry_particle_type, name);
  FIELD(quarry_particle_type, material);
  FIELD(quarry_particle_type, radius);
  FIELD(quarry_particle_type, max_radius);
  FIELD(quarry_advance_result, struct_size);
  FIELD(quarry_advance_result, steps);
  FIELD(quarry_advance_result, time);
  FIELD(quarry_particle_data, struct_size);
  FIELD(quarry_particle_data, capacity);
  FIELD(quarry_particle_data, id);
  FIELD(quarry_particle_data, type);
  FIELD(quarry_particle_data, position);
  FIELD(quarry_particle_data, velocity);
  FIELD(quarry_particle_data, angular_velocity);
  FIELD(quarry_particle_data, radius);
  FIELD(quarry_particle_data, mass);
  FIELD(quarry_particle_data, volume);
  FIELD(quarry_particle_data, force);
  FIELD(quarry_particle_data, torque);
  FIELD(quarry_particle_data, count);
  FIELD(quarry_particle_data, epoch);
  FIELD(quarry_view, data);
  FIELD(quarry_view, count);
  FIELD(quarry_view, dtype);
  FIELD(quarry_view, components);
  FIELD(quarry_view, stride);
  FIELD(quarry_view, epoch);
  FIELD(quarry_view, writable);
  FIELD(quarry_new_particles, struct_size);
  FIELD(quarry_new_particles, count);
  FIELD(quarry_new_particles, types);
  FIELD(quarry_new_particles, type);
  FIELD(quarry_new_particles, position);
  FIELD(quarry_new_particles, velocity);
  FIELD(quarry_new_particles, angular_velocity);
  FIELD(quarry_new_particles, radius);
  FIELD(quarry_new_particles, ids);
  FIELD(quarry_surface_desc, struct_size);
  FIELD(quarry_surface_desc, name);
  FIELD(quarry_surface_desc, material);
  FIELD(quarry_surface_desc, node_count);
  FIELD(quarry_surface_desc, nodes);
  FIELD(quarry_surface_desc, triangle_count);
  FIELD(quarry_surface_desc, triangles);
  FIELD(quarry_surface_desc, quad_count);
  FIELD(quarry_surface_desc, quads);
  FIELD(quarry_surface_desc, driver);
  FIELD(quarry_surface_info, struct_size);
  FIELD(quarry_surface_info, node_count);
  FIELD(quarry_surface_info, element_count);
  FIELD(quarry_surface_info, triangle_count);
  FIELD(quarry_surface_info, driver);
  FIELD(quarry_surface_loads, struct_size);
  FIELD(quarry_surface_loads, node_count);
  FIELD(quarry_surface_loads, nodal_force);
  FIELD(quarry_surface_loads, element_count);
  FIELD(quarry_surface_loads, pressure);
  FIELD(quarry_surface_loads, shear_stress);
  FIELD(quarry_surface_loads, element_force);
  FIELD(quarry_surface_loads, window);
  FIELD(quarry_surface_loads, time);
  CONSTANT(QUARRY_ABI_MAJOR);
  CONSTANT(QUARRY_ABI_MINOR);
  CONSTANT(QUARRY_OK);
  CONSTANT(QUARRY_ERROR_INVALID_HANDLE);
  CONSTANT(QUARRY_ERROR_NULL_POINTER);
  CONSTANT(QUARRY_ERROR_BAD_LENGTH);
  CONSTANT(QUARRY_ERROR_BAD_VALUE);
  CONSTANT(QUARRY_ERROR_WRONG_STATE);
  CONSTANT(QUARRY_ERROR_NOT_FOUND);
  CONSTANT(QUARRY_ERROR_INPUT);
  CONSTANT(QUARRY_ERROR_PHYSICS);
  CONSTANT(QUARRY_ERROR_IO);
  CONSTANT(QUARRY_ERROR_VERSION);
  CONSTANT(QUARRY_ERROR_TRANSPORT);
  CONSTANT(QUARRY_ERROR_TIMEOUT);
  CONSTANT(QUARRY_ERROR_UNSUPPORTED);
  CONSTANT(QUARRY_ERROR_HOOK);
  CONSTANT(QUARRY_ERROR_INTERNAL);
  CONSTANT(QUARRY_INTEGRATOR_VELOCITY_VERLET);
  CONSTANT(QUARRY_INTEGRATOR_SYMPLECTIC_EULER);
  CONSTANT(QUARRY_ROLLING_NONE);
  CONSTANT(QUARRY_ROLLING_CONSTANT_TORQUE);
  CONSTANT(QUARRY_ROLLING_EPSD);
  CONSTANT(QUARRY_FIELD_ID);
  CONSTANT(QUARRY_FIELD_TYPE);
  CONSTANT(QUARRY_FIELD_POSITION);
  CONSTANT(QUARRY_FIELD_VELOCITY);
  CONSTANT(QUARRY_FIELD_ANGULAR_VELOCITY);
  CONSTANT(QUARRY_FIELD_RADIUS);
  CONSTANT(QUARRY_FIELD_INVERSE_MASS);
  CONSTANT(QUARRY_FIELD_FORCE);
  CONSTANT(QUARRY_FIELD_TORQUE);
  CONSTANT(QUARRY_FIELD_TYPE_ORDER);
  CONSTANT(QUARRY_DTYPE_FLOAT64);
  CONSTANT(QUARRY_DTYPE_UINT64);
  CONSTANT(QUARRY_DTYPE_UINT32);
  CONSTANT(QUARRY_DTYPE_UINT16);
  CONSTANT(QUARRY_DRIVER_FIXED);
  CONSTANT(QUARRY_DRIVER_PRESCRIBED);
  CONSTANT(QUARRY_DRIVER_COUPLED);
  CONSTANT(QUARRY_LOAD_REPLACE);
  CONSTANT(QUARRY_LOAD_ADD);
  CONSTANT(QUARRY_HOLD_NEXT_STEP);
  CONSTANT(QUARRY_HOLD_UNTIL_CHANGED);
  CONSTANT(QUARRY_HOOK_POST_FORCE);
  CONSTANT(QUARRY_HOOK_END_OF_STEP);
  printf("\n}\n");
  return 0;
}
