"""Quarry from Python: a DEM simulation driven through Quarry's C ABI (libquarry.so, by ctypes)
with numpy arrays — copies in particle-type order, or zero-copy views of the engine's arrays.

    import quarry
    with quarry.Simulation.open(deck="drum.yaml") as sim:
        sim.advance(0.1)                       # s
        p = sim.particles(["id", "position"])  # copies, type order
        v = sim.view("velocity")               # zero-copy, engine order; see quarry.View

SI units everywhere (m, s, kg, N, Pa). docs/python.md is the guide; include/quarry/quarry.h and
docs/coupling.md the reference of the calls underneath. The library is found through the
QUARRY_LIBRARY environment variable, else the build or install tree this package sits in, else
the system loader; its ABI major must be this module's (ImportError otherwise).
"""

from ._abi import (
    ABI_MAJOR,
    ABI_MINOR,
    DType,
    Driver,
    Field,
    Hold,
    HookStage,
    Integrator,
    LoadMode,
    Rolling,
    Status,
)
from .errors import (
    BadLengthError,
    BadValueError,
    FileError,
    HookError,
    InputError,
    InternalError,
    InvalidHandleError,
    NotFoundError,
    NullPointerError,
    PhysicsError,
    QuarryError,
    RemoteTimeoutError,
    StaleViewError,
    TransportError,
    UnsupportedError,
    VersionError,
    WrongStateError,
)
from .records import Particles, PropertyInfo, SurfaceInfo, SurfaceLoads
from .simulation import (
    Simulation,
    abi_version,
    default_settings,
    library_path,
    status_name,
    version,
)
from .views import View

__all__ = [
    "ABI_MAJOR",
    "ABI_MINOR",
    "BadLengthError",
    "BadValueError",
    "DType",
    "Driver",
    "Field",
    "FileError",
    "Hold",
    "HookError",
    "HookStage",
    "InputError",
    "Integrator",
    "InternalError",
    "InvalidHandleError",
    "LoadMode",
    "NotFoundError",
    "NullPointerError",
    "Particles",
    "PhysicsError",
    "PropertyInfo",
    "QuarryError",
    "RemoteTimeoutError",
    "Rolling",
    "Simulation",
    "StaleViewError",
    "Status",
    "SurfaceInfo",
    "SurfaceLoads",
    "TransportError",
    "UnsupportedError",
    "VersionError",
    "View",
    "WrongStateError",
    "abi_version",
    "default_settings",
    "library_path",
    "status_name",
    "version",
]
