"""The C ABI of include/quarry/quarry.h mirrored in ctypes: every enum, every struct, every
function's prototype, and the loading of libquarry.so with its ABI version check.

Nothing here knows the engine's C++: the module reaches Quarry through the exported quarry_*
functions only. tests/python/test_abi.py compares every struct's size and field offsets and
every constant with the values a C compiler gives for quarry.h (tests/python/abi_layout.c).
"""

import ctypes
import ctypes.util
import enum
import os

# The ABI this module was written for (quarry.h's QUARRY_ABI_MAJOR / QUARRY_ABI_MINOR). A library
# of another major is refused at import; a newer minor only adds calls and trailing fields.
ABI_MAJOR = 1
ABI_MINOR = 2
ABI_VERSION = (ABI_MAJOR << 16) | ABI_MINOR


# ---- enums (each member is its C name without the prefix in ENUM_PREFIXES) ---------------------


class Status(enum.IntEnum):
    """quarry_status codes."""

    OK = 0
    ERROR_INVALID_HANDLE = -1
    ERROR_NULL_POINTER = -2
    ERROR_BAD_LENGTH = -3
    ERROR_BAD_VALUE = -4
    ERROR_WRONG_STATE = -5
    ERROR_NOT_FOUND = -6
    ERROR_INPUT = -7
    ERROR_PHYSICS = -8
    ERROR_IO = -9
    ERROR_VERSION = -10
    ERROR_TRANSPORT = -11
    ERROR_TIMEOUT = -12
    ERROR_UNSUPPORTED = -13
    ERROR_HOOK = -14
    ERROR_INTERNAL = -99


class Integrator(enum.IntEnum):
    VELOCITY_VERLET = 0
    SYMPLECTIC_EULER = 1


class Rolling(enum.IntEnum):
    NONE = 0
    CONSTANT_TORQUE = 1
    EPSD = 2


class Field(enum.IntEnum):
    """Particle arrays that quarry_view_particles shows (engine order)."""

    ID = 1
    TYPE = 2
    POSITION = 3
    VELOCITY = 4
    ANGULAR_VELOCITY = 5
    RADIUS = 6
    INVERSE_MASS = 7
    FORCE = 8
    TORQUE = 9
    TYPE_ORDER = 10


class DType(enum.IntEnum):
    FLOAT64 = 1
    UINT64 = 2
    UINT32 = 3
    UINT16 = 4


class Driver(enum.IntEnum):
    """What moves a surface."""

    FIXED = 0
    PRESCRIBED = 1
    COUPLED = 2


class LoadMode(enum.IntEnum):
    REPLACE = 0
    ADD = 1


class Hold(enum.IntEnum):
    NEXT_STEP = 0
    UNTIL_CHANGED = 1


class HookStage(enum.IntEnum):
    POST_FORCE = 1
    END_OF_STEP = 2


ENUM_PREFIXES = {
    Status: "QUARRY_",
    Integrator: "QUARRY_INTEGRATOR_",
    Rolling: "QUARRY_ROLLING_",
    Field: "QUARRY_FIELD_",
    DType: "QUARRY_DTYPE_",
    Driver: "QUARRY_DRIVER_",
    LoadMode: "QUARRY_LOAD_",
    Hold: "QUARRY_HOLD_",
    HookStage: "QUARRY_HOOK_",
}

# ---- structs --------------------------------------------------------------------------------

c_double_p = ctypes.POINTER(ctypes.c_double)
c_uint64_p = ctypes.POINTER(ctypes.c_uint64)
c_uint32_p = ctypes.POINTER(ctypes.c_uint32)


class quarry_sim(ctypes.Structure):
    _fields_ = [("id", ctypes.c_uint64)]


class quarry_open_info(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("abi_version", ctypes.c_uint32),
        ("deck_path", ctypes.c_char_p),
        ("checkpoint_path", ctypes.c_char_p),
        ("output_directory", ctypes.c_char_p),
        ("endpoint", ctypes.c_char_p),
        ("threads", ctypes.c_int32),
        ("timeout_ms", ctypes.c_int32),
    ]


class quarry_settings(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("time_step", ctypes.c_double),
        ("rayleigh_fraction", ctypes.c_double),
        ("gravity", ctypes.c_double * 3),
        ("domain_min", ctypes.c_double * 3),
        ("domain_max", ctypes.c_double * 3),
        ("end_time", ctypes.c_double),
        ("impact_speed", ctypes.c_double),
        ("skin", ctypes.c_double),
        ("integrator", ctypes.c_int32),
        ("sort_interval", ctypes.c_int32),
        ("max_overlap_fraction", ctypes.c_double),
        ("seed", ctypes.c_uint64),
        ("periodic", ctypes.c_int32 * 3),  # ABI 1.1
    ]


class quarry_material(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("name", ctypes.c_char_p),
        ("density", ctypes.c_double),
        ("youngs_modulus", ctypes.c_double),
        ("poisson_ratio", ctypes.c_double),
    ]


class quarry_interaction(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("material_a", ctypes.c_char_p),
        ("material_b", ctypes.c_char_p),
        ("restitution", ctypes.c_double),
        ("static_friction", ctypes.c_double),
        ("rolling_friction", ctypes.c_double),
        ("rolling_model", ctypes.c_int32),
        ("cohesion_energy_density", ctypes.c_double),
    ]


class quarry_particle_type(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("name", ctypes.c_char_p),
        ("material", ctypes.c_char_p),
        ("radius", ctypes.c_double),
        ("max_radius", ctypes.c_double),
    ]


class quarry_advance_result(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("steps", ctypes.c_uint64),
        ("time", ctypes.c_double),
    ]


class quarry_particle_data(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("capacity", ctypes.c_uint64),
        ("id", c_uint64_p),
        ("type", c_uint32_p),
        ("position", c_double_p),
        ("velocity", c_double_p),
        ("angular_velocity", c_double_p),
        ("radius", c_double_p),
        ("mass", c_double_p),
        ("volume", c_double_p),
        ("force", c_double_p),
        ("torque", c_double_p),
        ("count", ctypes.c_uint64),
        ("epoch", ctypes.c_uint64),
    ]


class quarry_view(ctypes.Structure):
    _fields_ = [
        ("data", ctypes.c_void_p),
        ("count", ctypes.c_uint64),
        ("dtype", ctypes.c_uint32),
        ("components", ctypes.c_uint32),
        ("stride", ctypes.c_int64),
        ("epoch", ctypes.c_uint64),
        ("writable", ctypes.c_uint32),
    ]


class quarry_new_particles(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("count", ctypes.c_uint64),
        ("types", c_uint32_p),
        ("type", ctypes.c_uint32),
        ("position", c_double_p),
        ("velocity", c_double_p),
        ("angular_velocity", c_double_p),
        ("radius", c_double_p),
        ("ids", c_uint64_p),
    ]


class quarry_surface_desc(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("name", ctypes.c_char_p),
        ("material", ctypes.c_char_p),
        ("node_count", ctypes.c_uint64),
        ("nodes", c_double_p),
        ("triangle_count", ctypes.c_uint64),
        ("triangles", c_uint32_p),
        ("quad_count", ctypes.c_uint64),
        ("quads", c_uint32_p),
        ("driver", ctypes.c_int32),
    ]


class quarry_surface_info(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("node_count", ctypes.c_uint64),
        ("element_count", ctypes.c_uint64),
        ("triangle_count", ctypes.c_uint64),
        ("driver", ctypes.c_int32),
    ]


class quarry_surface_loads(ctypes.Structure):
    _fields_ = [
        ("struct_size", ctypes.c_uint32),
        ("node_count", ctypes.c_uint64),
        ("nodal_force", c_double_p),
        ("element_count", ctypes.c_uint64),
        ("pressure", c_double_p),
        ("shear_stress", c_double_p),
        ("element_force", c_double_p),
        ("window", ctypes.c_double),
        ("time", ctypes.c_double),
    ]


STRUCTS = (
    quarry_sim,
    quarry_open_info,
    quarry_settings,
    quarry_material,
    quarry_interaction,
    quarry_particle_type,
    quarry_advance_result,
    quarry_particle_data,
    quarry_view,
    quarry_new_particles,
    quarry_surface_desc,
    quarry_surface_info,
    quarry_surface_loads,
)


def sized(struct_type, **fields):
    """A struct with struct_size = its ctypes size (what sizeof gives in C) and these fields."""
    value = struct_type(**fields)
    value.struct_size = ctypes.sizeof(struct_type)
    return value


# int (*quarry_hook_fn)(quarry_sim sim, int32_t stage, void* user_data)
quarry_hook_fn = ctypes.CFUNCTYPE(ctypes.c_int, quarry_sim, ctypes.c_int32, ctypes.c_void_p)

# ---- functions ------------------------------------------------------------------------------

_S = ctypes.c_int32  # quarry_status
_sim = quarry_sim
_P = ctypes.POINTER
_size = ctypes.c_size_t
_u32, _i32, _u64 = ctypes.c_uint32, ctypes.c_int32, ctypes.c_uint64

# name: (restype, argtypes), in the order of quarry.h.
PROTOTYPES = {
    "quarry_abi_version": (_u32, []),
    "quarry_version_string": (ctypes.c_char_p, []),
    "quarry_status_name": (ctypes.c_char_p, [_S]),
    "quarry_last_error": (_S, [_sim, ctypes.c_char_p, _size, _P(_size)]),
    "quarry_open": (_S, [_P(quarry_open_info), _P(quarry_sim)]),
    "quarry_close": (_S, [_sim]),
    "quarry_default_settings": (quarry_settings, []),
    "quarry_set_settings": (_S, [_sim, _P(quarry_settings)]),
    "quarry_add_material": (_S, [_sim, _P(quarry_material), _P(_u32)]),
    "quarry_add_interaction": (_S, [_sim, _P(quarry_interaction)]),
    "quarry_add_particle_type": (_S, [_sim, _P(quarry_particle_type), _P(_u32)]),
    "quarry_start": (_S, [_sim]),
    "quarry_get_time": (_S, [_sim, c_double_p, c_double_p, c_uint64_p]),
    "quarry_advance": (_S, [_sim, ctypes.c_double, _P(quarry_advance_result)]),
    "quarry_step": (_S, [_sim, _u64]),
    "quarry_save_checkpoint": (_S, [_sim, ctypes.c_char_p]),
    "quarry_save_state": (_S, [_sim, ctypes.c_void_p, _u64, c_uint64_p]),
    "quarry_restore_state": (_S, [_sim, ctypes.c_void_p, _u64]),
    "quarry_num_types": (_S, [_sim, c_uint32_p]),
    "quarry_type_name": (_S, [_sim, _u32, ctypes.c_char_p, _size]),
    "quarry_num_particles": (_S, [_sim, _i32, c_uint64_p]),
    "quarry_epoch": (_S, [_sim, c_uint64_p]),
    "quarry_get_particles": (_S, [_sim, _P(quarry_particle_data)]),
    "quarry_particle_index": (_S, [_sim, _u64, c_uint64_p]),
    "quarry_view_particles": (_S, [_sim, _i32, _P(quarry_view)]),
    "quarry_view_next_step_loads": (_S, [_sim, _i32, _P(quarry_view)]),
    "quarry_add_particles": (_S, [_sim, _P(quarry_new_particles)]),
    "quarry_remove_particles": (_S, [_sim, c_uint64_p, _u64]),
    "quarry_set_external_loads": (_S, [_sim, c_double_p, c_double_p, _u64, _i32, _i32]),
    "quarry_set_external_loads_by_id": (
        _S,
        [_sim, c_uint64_p, _u64, c_double_p, c_double_p, _i32, _i32],
    ),
    "quarry_clear_external_loads": (_S, [_sim]),
    "quarry_register_property": (
        _S,
        [_sim, ctypes.c_char_p, _u32, ctypes.c_char_p, ctypes.c_double, c_uint32_p],
    ),
    "quarry_num_properties": (_S, [_sim, c_uint32_p]),
    "quarry_property_info": (
        _S,
        [_sim, _u32, ctypes.c_char_p, _size, c_uint32_p, ctypes.c_char_p, _size],
    ),
    "quarry_get_property": (_S, [_sim, _u32, c_double_p, _u64]),
    "quarry_set_property": (_S, [_sim, _u32, c_double_p, _u64]),
    "quarry_view_property": (_S, [_sim, _u32, _P(quarry_view)]),
    "quarry_sample_points": (_S, [_sim, _u32, _u32, _u64, c_double_p]),
    "quarry_sample_point_positions": (_S, [_sim, _u32, _u32, _u64, c_double_p, _u64, c_uint64_p]),
    "quarry_add_surface": (_S, [_sim, _P(quarry_surface_desc), c_uint32_p]),
    "quarry_num_surfaces": (_S, [_sim, c_uint32_p]),
    "quarry_find_surface": (_S, [_sim, ctypes.c_char_p, c_uint32_p]),
    "quarry_get_surface_info": (_S, [_sim, _u32, _P(quarry_surface_info)]),
    "quarry_set_surface_driver": (_S, [_sim, _u32, _i32]),
    "quarry_set_surface_nodes": (_S, [_sim, _u32, c_double_p, c_double_p, _u64]),
    "quarry_get_surface_nodes": (_S, [_sim, _u32, c_double_p, c_double_p, _u64]),
    "quarry_get_surface_loads": (_S, [_sim, _u32, _P(quarry_surface_loads)]),
    "quarry_set_hook": (_S, [_sim, _i32, quarry_hook_fn, ctypes.c_void_p]),
    "quarry_add_hook_forces": (_S, [_sim, c_double_p, c_double_p, _u64]),
}

# ---- loading the library --------------------------------------------------------------------


def _candidates():
    """(where, path) pairs to try, in order: QUARRY_LIBRARY alone if it is set; else the build
    or install tree's _library_path.py (written by CMake next to this package); else the
    system loader."""
    explicit = os.environ.get("QUARRY_LIBRARY")
    if explicit:
        return [("QUARRY_LIBRARY", explicit)]
    found = []
    try:
        from . import _library_path  # generated: absent in a bare source tree

        found.append(
            ("the build or install tree (%s)" % _library_path.__file__, _library_path.library())
        )
    except ImportError:
        pass
    system = ctypes.util.find_library("quarry")
    if system:
        found.append(("the system loader (find_library)", system))
    found.append(("the system loader", "libquarry.so.1"))
    return found


def check_abi_version(version):
    """Raises ImportError unless `version` ((major << 16) | minor, from quarry_abi_version) has
    this module's major."""
    major, minor = version >> 16, version & 0xFFFF
    if major != ABI_MAJOR:
        raise ImportError(
            "quarry: libquarry.so has ABI %d.%d, this Python module was written for ABI %d.%d; "
            "use the python/quarry package of the same Quarry build as the library"
            % (major, minor, ABI_MAJOR, ABI_MINOR)
        )


def load():
    """Loads libquarry.so, declares every prototype and checks the ABI major. Returns (the
    ctypes.CDLL, the path it was loaded from)."""
    tried = []
    for where, path in _candidates():
        try:
            library = ctypes.CDLL(path)
        except OSError as error:
            tried.append("  %s: %s (%s)" % (where, path, error))
            continue
        missing = [name for name in PROTOTYPES if not hasattr(library, name)]
        if missing:
            tried.append(
                "  %s: %s lacks %s: not a Quarry library of ABI %d"
                % (where, path, ", ".join(missing[:3]), ABI_MAJOR)
            )
            continue
        for name, (restype, argtypes) in PROTOTYPES.items():
            function = getattr(library, name)
            function.restype = restype
            function.argtypes = argtypes
        check_abi_version(library.quarry_abi_version())
        return library, path
    raise ImportError(
        "quarry: cannot load libquarry.so; tried:\n%s\n"
        "Set QUARRY_LIBRARY to the library (e.g. <build>/src/api/libquarry.so), or put the build's "
        "python folder on PYTHONPATH (docs/python.md)" % "\n".join(tried)
    )
