"""quarry.Simulation: one Quarry DEM simulation, driven through the C ABI (include/quarry/quarry.h)
with numpy arrays — copies in type order, or zero-copy views of the engine's own arrays.

Units are SI everywhere: m, s, kg, N, Pa, rad/s. Vectors are rows of 3 (x, y, z): an array of n
vectors has shape (n, 3). "Type order" (every copy, every array given to the engine): all particles
of type 0, then of type 1, ...; within a type in the engine's order, which changes on re-sorts,
insertions and removals — follow a particle by its id. Views are in *engine* order (the same as
type order with one particle type; the "type_order" view maps the two).
"""

import ctypes
import difflib
import os
import weakref

import numpy as np

from . import _abi
from ._abi import Driver, Field, Hold, HookStage, Integrator, LoadMode, Rolling, Status
from .errors import HookError, error_for, python_error
from .records import Particles, PropertyInfo, SurfaceInfo, SurfaceLoads
from .views import View

_lib, library_path = _abi.load()

_NO_SIM = _abi.quarry_sim(0)


def abi_version():
    """The library's ABI version as (major, minor)."""
    version = _lib.quarry_abi_version()
    return version >> 16, version & 0xFFFF


def version():
    """The library's version text, e.g. "0.2.0"."""
    return _lib.quarry_version_string().decode()


def status_name(status):
    """The C name of a status code, e.g. "QUARRY_ERROR_BAD_LENGTH"."""
    return _lib.quarry_status_name(int(status)).decode()


def default_settings():
    """Every setting's default as a dict (quarry_default_settings; the domain is empty)."""
    return _settings_dict(_default_settings())


def _default_settings():
    """quarry_default_settings as this module's struct: a library older than ABI 1.1 fills only
    the fields of its own, shorter struct; the later ones get their defaults here."""
    settings = _lib.quarry_default_settings()
    if abi_version() < (1, 1):
        settings.periodic[:] = [0, 0, 0]
    return settings


# ---- helpers --------------------------------------------------------------------------------


def _last_error(sim):
    """The handle's last-error text (with _NO_SIM: the calling thread's, of a call that had no
    valid handle)."""
    length = ctypes.c_size_t(0)
    size = 1024
    while True:
        buffer = ctypes.create_string_buffer(size)
        if _lib.quarry_last_error(sim, buffer, size, ctypes.byref(length)) != Status.OK:
            return "(the error text could not be read)"
        if length.value < size:
            return buffer.value.decode("utf-8", "replace")
        size = length.value + 1


def _raise_for(status, sim):
    name = status_name(status)
    text = _last_error(_NO_SIM if status == Status.ERROR_INVALID_HANDLE or sim is None else sim)
    raise error_for(status, name, text)


def _hint(word, choices):
    close = difflib.get_close_matches(word, choices, n=1)
    return '; did you mean "%s"?' % close[0] if close else "; one of: %s" % ", ".join(choices)


def _enum(enum_type, value, what):
    """An enum member from a member, its value or its name in any case ("coupled")."""
    if isinstance(value, str):
        key = value.upper()
        if key in enum_type.__members__:
            return enum_type[key]
        names = [name.lower() for name in enum_type.__members__]
        raise python_error(
            Status.ERROR_BAD_VALUE,
            '%s: "%s" is not a value%s' % (what, value, _hint(value.lower(), names)),
        )
    try:
        return enum_type(value)
    except ValueError:
        raise python_error(
            Status.ERROR_BAD_VALUE,
            "%s: %r is not a value (%s)"
            % (what, value, ", ".join(n.lower() for n in enum_type.__members__)),
        ) from None


def _path(value):
    return None if value is None else os.fsencode(value)


def _text(value):
    return value.encode() if isinstance(value, str) else value


def _doubles(values, what, per_entry=3):
    """values as a C-contiguous float64 array and its entry count (values / per_entry)."""
    array = np.ascontiguousarray(values, dtype=np.float64)
    if array.size % per_entry:
        raise python_error(
            Status.ERROR_BAD_LENGTH,
            "%s: %d values are not %d per entry (an (n, %d) array)"
            % (what, array.size, per_entry, per_entry),
        )
    return array, array.size // per_entry


def _indices(values, what, dtype=np.uint32):
    """Non-negative integers as a C-contiguous array of `dtype`."""
    array = np.asarray(values)
    if array.size and not np.issubdtype(array.dtype, np.integer):
        if not np.all(np.equal(np.mod(array, 1), 0)):
            raise python_error(
                Status.ERROR_BAD_VALUE, "%s: the entries must be whole numbers" % what
            )
    if array.size and array.min() < 0:
        raise python_error(
            Status.ERROR_BAD_VALUE, "%s: entry %d is negative" % (what, int(np.argmin(array)))
        )
    return np.ascontiguousarray(array, dtype=dtype)


def _pointer(array, c_type=ctypes.c_double):
    return None if array is None else array.ctypes.data_as(ctypes.POINTER(c_type))


_SETTINGS_VECTORS = ("gravity", "domain_min", "domain_max")
_SETTINGS_NAMES = [name for name, _ in _abi.quarry_settings._fields_ if name != "struct_size"]
_AXES = ("x", "y", "z")


def _settings_dict(settings):
    out = {}
    for name in _SETTINGS_NAMES:
        value = getattr(settings, name)
        out[name] = tuple(value) if name in _SETTINGS_VECTORS else value
    out["integrator"] = Integrator(out["integrator"])
    out["periodic"] = tuple(axis for axis, flag in zip(_AXES, settings.periodic) if flag)
    return out


def _periodic_flags(value):
    """quarry_settings.periodic (1 per periodic axis) from axis names as a deck lists them
    (("x", "y"), or "xy"), or from three flags ((True, True, False)); None or () for none."""
    what = "set_settings: periodic"
    try:
        items = [] if value is None else list(value)
    except TypeError:  # a single number or flag: not a list of axes
        items = [None]
    if all(isinstance(item, str) for item in items):
        flags = [0, 0, 0]
        for name in items:
            axis = name.lower()
            if axis not in _AXES:
                raise python_error(
                    Status.ERROR_BAD_VALUE,
                    '%s: "%s" is not an axis%s' % (what, name, _hint(axis, list(_AXES))),
                )
            if flags[_AXES.index(axis)]:
                raise python_error(
                    Status.ERROR_BAD_VALUE,
                    '%s: axis "%s" is named twice; name each periodic axis once, e.g. ("x", "y")'
                    % (what, axis),
                )
            flags[_AXES.index(axis)] = 1
        return flags
    if len(items) == 3 and all(
        isinstance(item, (bool, int, np.integer, np.bool_)) and item in (0, 1) for item in items
    ):
        return [int(item) for item in items]
    raise python_error(
        Status.ERROR_BAD_VALUE,
        '%s: %r is neither axis names (("x", "y") or "xy") nor three flags for x, y, z '
        "((True, True, False))" % (what, value),
    )


# Fields of quarry_particle_data: (numpy dtype, components, ctypes element type).
_PARTICLE_FIELDS = {
    "id": (np.uint64, 1, ctypes.c_uint64),
    "type": (np.uint32, 1, ctypes.c_uint32),
    "position": (np.float64, 3, ctypes.c_double),
    "velocity": (np.float64, 3, ctypes.c_double),
    "angular_velocity": (np.float64, 3, ctypes.c_double),
    "radius": (np.float64, 1, ctypes.c_double),
    "mass": (np.float64, 1, ctypes.c_double),
    "volume": (np.float64, 1, ctypes.c_double),
    "force": (np.float64, 3, ctypes.c_double),
    "torque": (np.float64, 3, ctypes.c_double),
}

# ---- the simulation ---------------------------------------------------------------------------


class Simulation:
    """One Quarry simulation (a quarry_sim handle). Make one with Simulation.open(...) (a deck,
    a checkpoint, or a server's simulation) or Simulation.empty() (built by calls, then
    start()); close it with close() or a `with` block.

    Every failed call raises a quarry.QuarryError subclass naming the status and carrying the
    engine's message. Calls on one simulation may come from any thread (the engine serialises
    them); views and hooks belong to the thread that uses them.
    """

    def __init__(self, handle, remote):
        # Private: use Simulation.open() or Simulation.empty().
        self._sim = handle
        self.remote = remote
        self._changes = 0  # bumped by every call that may change the simulation (views re-fetch)
        self._restores = 0  # restore_state calls: every view's particles are other ones after one
        self._hooks = {}  # stage -> the ctypes callback (kept alive while the engine holds it)
        self._hook_exception = None
        self._settings = _default_settings()
        self._finalizer = weakref.finalize(self, _lib.quarry_close, _abi.quarry_sim(handle.id))

    # ---- opening and closing ----

    @classmethod
    def open(
        cls,
        deck=None,
        checkpoint=None,
        output_directory=None,
        endpoint=None,
        threads=0,
        timeout_ms=0,
    ):
        """Opens a simulation (quarry_open).

        deck: a YAML deck (docs/deck.md) — the simulation starts at once (the factories due at
        t = 0 inserted, forces computed). checkpoint: a checkpoint file to restore instead.
        Neither: an empty simulation (as Simulation.empty()). output_directory: where the deck's
        outputs go (frames, monitors, load export, checkpoints); None writes nothing.
        endpoint: "ipc:///path" or "tcp://host:port" of a `quarry serve` (paths are then the
        server's); None runs in this process. threads: OpenMP threads (0: the deck's or the
        default). timeout_ms: remote only, the longest wait for an answer (0: 60 s).
        Raises InputError (deck's file:line:col), FileError, VersionError, TransportError.
        Cost: the deck's build (meshes, neighbour lists).
        """
        info = _abi.sized(
            _abi.quarry_open_info,
            abi_version=_abi.ABI_VERSION,
            deck_path=_path(deck),
            checkpoint_path=_path(checkpoint),
            output_directory=_path(output_directory),
            endpoint=_text(endpoint),
            threads=threads,
            timeout_ms=timeout_ms,
        )
        handle = _abi.quarry_sim(0)
        status = _lib.quarry_open(ctypes.byref(info), ctypes.byref(handle))
        if status != Status.OK:
            _raise_for(status, None)
        return cls(handle, endpoint is not None)

    @classmethod
    def empty(cls, output_directory=None, endpoint=None, threads=0, timeout_ms=0):
        """An empty simulation to build with set_settings, add_material, add_interaction,
        add_particle_type (and add_surface), then start()."""
        return cls.open(
            output_directory=output_directory,
            endpoint=endpoint,
            threads=threads,
            timeout_ms=timeout_ms,
        )

    def close(self):
        """Closes the simulation (outputs finished). Views and the handle are dead after it;
        closing twice does nothing. Also done by `with` and when the object is collected."""
        if self._sim is None:
            return
        handle, self._sim = self._sim, None
        self._finalizer.detach()
        self._changes += 1
        status = _lib.quarry_close(handle)
        self._hooks.clear()  # the engine no longer calls them
        if status != Status.OK:
            _raise_for(status, None)  # the handle is gone: its last word is the thread's error

    @property
    def closed(self):
        return self._sim is None

    def __enter__(self):
        return self

    def __exit__(self, *exception):
        self.close()

    def __repr__(self):
        if self._sim is None:
            return "<quarry.Simulation (closed)>"
        return "<quarry.Simulation %#x%s>" % (self._sim.id, " (remote)" if self.remote else "")

    # ---- calling the engine ----

    def _handle(self):
        if self._sim is None:
            raise python_error(Status.ERROR_INVALID_HANDLE, "the simulation is closed")
        return self._sim

    def _call(self, name, *args):
        status = getattr(_lib, name)(self._handle(), *args)
        if status != Status.OK:
            self._raise(status)

    def _change(self, name, *args):
        """A call that may change the simulation: views fetch their pointer again after it."""
        try:
            self._call(name, *args)
        finally:
            self._changes += 1

    def _raise(self, status):
        exception, self._hook_exception = self._hook_exception, None
        if (
            status == Status.ERROR_HOOK
            and exception is not None
            and not isinstance(exception, Exception)
        ):
            raise exception  # KeyboardInterrupt, SystemExit: as they were
        try:
            _raise_for(status, self._sim)
        except HookError as error:
            if exception is None:
                raise
            raise error from exception

    # ---- building without a deck (before start) ----

    def set_settings(self, domain=None, **settings):
        """Sets the simulation's settings (before start): any of time_step (s; 0: from the
        Rayleigh time step), rayleigh_fraction, gravity (m/s², 3), domain_min, domain_max (m, 3;
        or domain=(min, max)), end_time (s), impact_speed (m/s; 0: 1 m/s), skin (m; < 0: chosen
        at every list build, the default), integrator ("velocity_verlet" or "symplectic_euler"),
        sort_interval (steps; 0: never), max_overlap_fraction, seed, periodic (the axes along
        which the domain repeats, as a deck's `periodic: [x, y]`: ("x", "y"), "xy" or
        (True, True, False); () for none, the default). Keys not given keep their earlier value
        (at first the defaults, quarry.default_settings())."""
        values = _abi.quarry_settings.from_buffer_copy(self._settings)
        if domain is not None:
            settings.setdefault("domain_min", domain[0])
            settings.setdefault("domain_max", domain[1])
        for key, value in settings.items():
            if key not in _SETTINGS_NAMES:
                raise TypeError(
                    "set_settings: unknown setting %r%s" % (key, _hint(key, _SETTINGS_NAMES))
                )
            if key in _SETTINGS_VECTORS:
                vector, count = _doubles(value, "set_settings: " + key)
                if count != 1:
                    raise python_error(
                        Status.ERROR_BAD_LENGTH, "set_settings: %s takes 3 values (x, y, z)" % key
                    )
                getattr(values, key)[:] = vector.tolist()
            elif key == "integrator":
                values.integrator = _enum(Integrator, value, "set_settings: integrator")
            elif key == "periodic":
                flags = _periodic_flags(value)
                if any(flags) and abi_version() < (1, 1):
                    # An older library would read a 1.0 struct and drop the axes without a word.
                    raise python_error(
                        Status.ERROR_UNSUPPORTED,
                        "set_settings: periodic axes need libquarry of ABI 1.1 or later, %s is "
                        "%d.%d" % ((library_path,) + abi_version()),
                    )
                values.periodic[:] = flags
            else:
                setattr(values, key, value)
        values.struct_size = ctypes.sizeof(values)
        self._change("quarry_set_settings", ctypes.byref(values))
        self._settings = values

    @property
    def settings(self):
        """The settings given through set_settings (with the defaults), as a dict."""
        return _settings_dict(self._settings)

    def add_material(self, name, density, youngs_modulus, poisson_ratio):
        """Adds a material (before start): density (kg/m³), Young's modulus (Pa), Poisson's
        ratio (in (−1, 0.5)). Returns its index."""
        material = _abi.sized(
            _abi.quarry_material,
            name=_text(name),
            density=density,
            youngs_modulus=youngs_modulus,
            poisson_ratio=poisson_ratio,
        )
        index = ctypes.c_uint32()
        self._change("quarry_add_material", ctypes.byref(material), ctypes.byref(index))
        return index.value

    def add_interaction(
        self,
        material_a,
        material_b,
        restitution=0.5,
        static_friction=0.5,
        rolling_friction=0.0,
        rolling_model="constant_torque",
        cohesion_energy_density=0.0,
    ):
        """Hertz–Mindlin contact between two materials (before start); the defaults are the
        deck's (docs/deck.md): restitution in (0, 1], friction coefficients ≥ 0, rolling_model
        "none", "constant_torque" or "epsd", cohesion energy density (J/m³, SJKR)."""
        interaction = _abi.sized(
            _abi.quarry_interaction,
            material_a=_text(material_a),
            material_b=_text(material_b),
            restitution=restitution,
            static_friction=static_friction,
            rolling_friction=rolling_friction,
            rolling_model=_enum(Rolling, rolling_model, "add_interaction: rolling_model"),
            cohesion_energy_density=cohesion_energy_density,
        )
        self._change("quarry_add_interaction", ctypes.byref(interaction))

    def add_particle_type(self, name, material, radius, max_radius=0.0):
        """Adds a particle type (before start): every particle of radius `radius` (m), or radii
        uniform in [radius, max_radius] when max_radius > 0. Returns its index."""
        particle_type = _abi.sized(
            _abi.quarry_particle_type,
            name=_text(name),
            material=_text(material),
            radius=radius,
            max_radius=max_radius,
        )
        index = ctypes.c_uint32()
        self._change("quarry_add_particle_type", ctypes.byref(particle_type), ctypes.byref(index))
        return index.value

    def start(self):
        """Builds the simulation from what was added and brings it to t = 0. Raises InputError
        naming what is missing or wrong (e.g. an interaction never given)."""
        self._change("quarry_start")

    # ---- time ----

    def _time(self):
        time, time_step, steps = ctypes.c_double(), ctypes.c_double(), ctypes.c_uint64()
        self._call(
            "quarry_get_time", ctypes.byref(time), ctypes.byref(time_step), ctypes.byref(steps)
        )
        return time.value, time_step.value, steps.value

    @property
    def time(self):
        """The simulation's time (s)."""
        return self._time()[0]

    @property
    def time_step(self):
        """Its own stable time step (s)."""
        return self._time()[1]

    @property
    def steps(self):
        """Steps taken so far."""
        return self._time()[2]

    def advance(self, duration):
        """Advances by `duration` (s) in whole steps of the simulation's time step, never past
        time + duration (a remainder under one step is left for the next call). Returns the
        steps taken. After it the state is complete (positions, velocities, forces and loads of
        the new time). Raises PhysicsError (stopped at the step named), HookError.
        Cost: the steps."""
        result = _abi.sized(_abi.quarry_advance_result)
        self._change("quarry_advance", float(duration), ctypes.byref(result))
        return result.steps

    def step(self, steps=1):
        """Exactly `steps` steps."""
        self._change("quarry_step", int(steps))

    # ---- checkpoints ----

    def save_checkpoint(self, path):
        """Writes a checkpoint file: the whole state, the effective deck and every surface's
        mesh; Simulation.open(checkpoint=path) restores it bit-exactly."""
        self._call("quarry_save_checkpoint", _path(path))

    def save_state(self):
        """The same as bytes in memory (e.g. for implicit coupling iterations). Cost: a copy of
        the whole state."""
        needed = ctypes.c_uint64()
        self._call("quarry_save_state", None, 0, ctypes.byref(needed))
        buffer = ctypes.create_string_buffer(needed.value)
        self._call("quarry_save_state", buffer, needed.value, ctypes.byref(needed))
        return buffer.raw[: needed.value]

    def restore_state(self, state):
        """Puts the simulation back into a state from save_state (hooks and outputs kept).
        Every view is stale after it."""
        data = np.frombuffer(state, dtype=np.uint8)
        self._change("quarry_restore_state", ctypes.c_void_p(data.ctypes.data), data.size)
        self._restores += 1  # (a refused state changed nothing)

    # ---- particles ----

    @property
    def type_names(self):
        """The particle types' names, by index."""
        count = ctypes.c_uint32()
        self._call("quarry_num_types", ctypes.byref(count))
        names = []
        for index in range(count.value):
            buffer = ctypes.create_string_buffer(256)
            self._call("quarry_type_name", index, buffer, 256)
            names.append(buffer.value.decode())
        return names

    def _type_index(self, particle_type):
        if isinstance(particle_type, str):
            names = self.type_names
            if particle_type not in names:
                raise python_error(
                    Status.ERROR_NOT_FOUND,
                    'no particle type is named "%s"%s'
                    % (particle_type, _hint(particle_type, names)),
                )
            return names.index(particle_type)
        return int(particle_type)

    def num_particles(self, particle_type=None):
        """Particles of one type (an index or a name), or of all types."""
        count = ctypes.c_uint64()
        index = -1 if particle_type is None else self._type_index(particle_type)
        self._call("quarry_num_particles", index, ctypes.byref(count))
        return count.value

    def __len__(self):
        """len(simulation): its number of particles."""
        return self.num_particles()

    def __bool__(self):
        return True  # a simulation without particles is still a simulation

    @property
    def epoch(self):
        """Bumped whenever particles are re-sorted, inserted or removed."""
        epoch = ctypes.c_uint64()
        self._call("quarry_epoch", ctypes.byref(epoch))
        return epoch.value

    def particles(self, fields=None):
        """Copies of the particles' arrays in TYPE order: a Particles record with the fields
        asked for (all by default): id (uint64), type (uint32), position (m), velocity (m/s),
        angular_velocity (rad/s), force (N, the step's total), torque (N·m) as (n, 3) arrays,
        radius (m), mass (kg), volume (m³) as (n,) arrays; record.epoch their epoch.
        Cost: O(n) per field (a copy)."""
        if fields is None:
            names = list(_PARTICLE_FIELDS)
        else:
            names = [fields] if isinstance(fields, str) else list(fields)
        for name in names:
            if name not in _PARTICLE_FIELDS:
                raise python_error(
                    Status.ERROR_BAD_VALUE,
                    'particles: no field "%s"%s' % (name, _hint(name, list(_PARTICLE_FIELDS))),
                )
        count = self.num_particles()
        data = _abi.sized(_abi.quarry_particle_data, capacity=count)
        arrays = {}
        for name in names:
            dtype, components, c_type = _PARTICLE_FIELDS[name]
            arrays[name] = np.empty(
                (count, components) if components > 1 else (count,), dtype=dtype
            )
            setattr(data, name, _pointer(arrays[name], c_type))
        self._call("quarry_get_particles", ctypes.byref(data))
        return Particles(arrays, data.epoch, data.count)

    def particle_index(self, particle_id):
        """The type-order index of the particle with this id (NotFoundError if none). O(1)
        after the first call of an epoch (O(n) then)."""
        index = ctypes.c_uint64()
        self._call("quarry_particle_index", int(particle_id), ctypes.byref(index))
        return index.value

    def view(self, field):
        """A zero-copy View of an engine array, in ENGINE order (see View for the rule): "id",
        "type", "position", "velocity", "angular_velocity", "radius", "inverse_mass", "force",
        "torque", or "type_order" (order[k] = the engine index of the k-th particle in type
        order, so that view("position").array[order] is in type order). Read-only.
        Cost: O(1) (on a remote handle a copy held by the handle)."""
        key = _enum(Field, field, "view")
        name = key.name.lower()

        def fetch():
            raw = _abi.quarry_view()
            self._call("quarry_view_particles", int(key), ctypes.byref(raw))
            return raw

        return View(self, name, fetch)

    def view_next_step_loads(self, field="force"):
        """A WRITABLE zero-copy View of the next step's external loads, "force" (N) or "torque"
        (N·m), (n, 3) in ENGINE order: what is left in its array acts in the next step as
        set_external_loads(..., mode="replace", hold="next_step") with those values would (the
        same bits after a step). It holds the loads set so far for the next step (zeros after
        a step; view.array fetches them again then). Values are not checked: a non-finite one
        stops the next step. On a remote handle the array is the handle's copy, sent to the
        server before the next call. Cost: O(1) in process."""
        key = _enum(Field, field, "view_next_step_loads")
        if key not in (Field.FORCE, Field.TORQUE):
            raise ValueError('view_next_step_loads: field must be "force" or "torque", not %r' % (field,))

        def fetch():
            raw = _abi.quarry_view()
            self._call("quarry_view_next_step_loads", int(key), ctypes.byref(raw))
            return raw

        return View(self, "next-step " + key.name.lower(), fetch)

    def add_particles(
        self, position, velocity=None, angular_velocity=None, radius=None, particle_type=0
    ):
        """Adds particles between steps: position (m, (n, 3)), velocity (m/s; None: at rest),
        angular_velocity (rad/s; None: not spinning), radius (m, (n,); None or an entry ≤ 0:
        drawn from the type's sizes), particle_type (one index or name for all, or n indices).
        Returns their ids (uint64, in the order given). They are in contact from the next
        step's force stage on. Cost: O(n added) and a neighbour-list rebuild."""
        position, count = _doubles(position, "add_particles: position")
        description = _abi.sized(
            _abi.quarry_new_particles, count=count, position=_pointer(position)
        )
        keep = [position]
        for name, values in (("velocity", velocity), ("angular_velocity", angular_velocity)):
            if values is not None:
                array, entries = _doubles(values, "add_particles: " + name)
                if entries != count:
                    raise python_error(
                        Status.ERROR_BAD_LENGTH,
                        "add_particles: %d %s entries for %d positions" % (entries, name, count),
                    )
                setattr(description, name, _pointer(array))
                keep.append(array)
        if radius is not None:
            radii = np.ascontiguousarray(radius, dtype=np.float64).reshape(-1)
            if radii.size != count:
                raise python_error(
                    Status.ERROR_BAD_LENGTH,
                    "add_particles: %d radii for %d positions" % (radii.size, count),
                )
            description.radius = _pointer(radii)
            keep.append(radii)
        if isinstance(particle_type, (str, int, np.integer)):
            description.type = self._type_index(particle_type)
        else:
            types = np.asarray(particle_type)
            if types.dtype.kind not in "iu":  # names
                types = [self._type_index(t) for t in types.tolist()]
            types = _indices(types, "add_particles: particle_type").reshape(-1)
            if types.size != count:
                raise python_error(
                    Status.ERROR_BAD_LENGTH,
                    "add_particles: %d types for %d positions" % (types.size, count),
                )
            description.types = _pointer(types, ctypes.c_uint32)
            keep.append(types)
        ids = np.zeros(count, dtype=np.uint64)
        description.ids = _pointer(ids, ctypes.c_uint64)
        self._change("quarry_add_particles", ctypes.byref(description))
        return ids

    def remove_particles(self, ids):
        """Removes the particles with these ids (NotFoundError naming the first unknown id:
        then none is removed). Cost: O(n)."""
        ids = _indices(ids, "remove_particles: ids", np.uint64).reshape(-1)
        self._change("quarry_remove_particles", _pointer(ids, ctypes.c_uint64), ids.size)

    # ---- external force and torque ----

    def set_external_loads(
        self, force=None, torque=None, mode="replace", hold="next_step", ids=None
    ):
        """External force (N) and torque (N·m) per particle, (n, 3) arrays in TYPE order for
        every particle — or, with ids, entry k for the particle ids[k]. Either may be None (left
        as it is). mode: "replace" or "add" (to the particle's load of that hold); hold:
        "next_step" (acts in the next step only) or "until_changed". The loads act from the next
        step on (both of its half kicks) and show in the particles' force at once.
        Cost: O(entries)."""
        mode = _enum(LoadMode, mode, "set_external_loads: mode")
        hold = _enum(Hold, hold, "set_external_loads: hold")
        arrays = []
        counts = []
        for name, values in (("force", force), ("torque", torque)):
            if values is None:
                arrays.append(None)
            else:
                array, count = _doubles(values, "set_external_loads: " + name)
                arrays.append(array)
                counts.append(count)
        if ids is not None:
            ids = _indices(ids, "set_external_loads: ids", np.uint64).reshape(-1)
            counts.append(ids.size)
        if len(set(counts)) > 1:
            raise python_error(
                Status.ERROR_BAD_LENGTH,
                "set_external_loads: force, torque and ids differ in length (%s entries)"
                % ", ".join(map(str, counts)),
            )
        count = counts[0] if counts else 0
        force_array, torque_array = arrays
        if ids is None:
            self._change(
                "quarry_set_external_loads",
                _pointer(force_array),
                _pointer(torque_array),
                count,
                mode,
                hold,
            )
        else:
            self._change(
                "quarry_set_external_loads_by_id",
                _pointer(ids, ctypes.c_uint64),
                count,
                _pointer(force_array),
                _pointer(torque_array),
                mode,
                hold,
            )

    def clear_external_loads(self):
        """Every external load (of both holds) back to zero."""
        self._change("quarry_clear_external_loads")

    # ---- custom particle properties ----

    def register_property(self, name, components=1, unit="", initial=0.0):
        """Registers a per-particle property (components values per particle, unit text such as
        "K", every particle starting at `initial`); it follows its particles through re-sorts,
        is checkpointed and written to the VTU frames. Registering a name again returns its
        index (BadValueError if the components differ)."""
        index = ctypes.c_uint32()
        self._change(
            "quarry_register_property",
            _text(name),
            int(components),
            _text(unit),
            float(initial),
            ctypes.byref(index),
        )
        return index.value

    @property
    def properties(self):
        """Every registered property as PropertyInfo(index, name, components, unit)."""
        count = ctypes.c_uint32()
        self._call("quarry_num_properties", ctypes.byref(count))
        out = []
        for index in range(count.value):
            name, unit, components = (
                ctypes.create_string_buffer(256),
                ctypes.create_string_buffer(64),
                ctypes.c_uint32(),
            )
            self._call("quarry_property_info", index, name, 256, ctypes.byref(components), unit, 64)
            out.append(
                PropertyInfo(index, name.value.decode(), components.value, unit.value.decode())
            )
        return out

    def _property(self, prop):
        """PropertyInfo of a property given by name or index."""
        infos = self.properties
        if isinstance(prop, str):
            for info in infos:
                if info.name == prop:
                    return info
            names = [info.name for info in infos]
            raise python_error(
                Status.ERROR_NOT_FOUND,
                'no custom property is named "%s"%s'
                % (prop, _hint(prop, names) if names else " (none registered)"),
            )
        index = int(prop)
        if not 0 <= index < len(infos):
            # The engine's own message for an index it does not know.
            self._call("quarry_property_info", index, None, 0, None, None, 0)
        return infos[index]

    def get_property(self, prop):
        """A property's values in TYPE order (a copy): shape (n,) for one component, else
        (n, components). prop: its name or index."""
        info = self._property(prop)
        count = self.num_particles()
        values = np.empty(
            (count, info.components) if info.components > 1 else (count,), dtype=np.float64
        )
        self._call("quarry_get_property", info.index, _pointer(values), values.size)
        return values

    def set_property(self, prop, values):
        """Sets a property's values (TYPE order, n × components)."""
        info = self._property(prop)
        values = np.ascontiguousarray(values, dtype=np.float64)
        self._change("quarry_set_property", info.index, _pointer(values), values.size)

    def view_property(self, prop):
        """A WRITABLE zero-copy View of a property in ENGINE order: writes through its array go
        straight into the engine (see View for the rule)."""
        info = self._property(prop)

        def fetch():
            raw = _abi.quarry_view()
            self._call("quarry_view_property", info.index, ctypes.byref(raw))
            return raw

        return View(self, "property " + info.name, fetch)

    # ---- sample points ----

    def sample_points(self, particle_type, points, seed=12345):
        """`points` Monte-Carlo points inside the unit particle of the type (centre 0, radius 1),
        uniform in its volume and reproducible for a seed: a (points, 3) array."""
        out = np.empty((int(points), 3), dtype=np.float64)
        self._call(
            "quarry_sample_points",
            self._type_index(particle_type),
            int(points),
            int(seed),
            _pointer(out),
        )
        return out

    def sample_point_positions(self, particle_type, points, seed=12345):
        """The same points placed in every particle of the type, in type order: a (particles,
        points, 3) array (m). A particle's solid volume in a cell is V_p × (its points in the
        cell) / points. Cost: O(particles × points)."""
        index = self._type_index(particle_type)
        count = self.num_particles(index)
        out = np.empty((count, int(points), 3), dtype=np.float64)
        placed = ctypes.c_uint64()
        self._call(
            "quarry_sample_point_positions",
            index,
            int(points),
            int(seed),
            _pointer(out),
            out.size,
            ctypes.byref(placed),
        )
        return out[: placed.value]

    # ---- surfaces ----

    def _surface_index(self, surface):
        return self.find_surface(surface) if isinstance(surface, str) else int(surface)

    def add_surface(self, name, material, nodes, triangles=None, quads=None, coupled=False):
        """A surface from nodes (m, (N, 3)) and triangles ((T, 3)) and/or quads ((Q, 4)) of
        0-based node indices; elements are numbered triangles first, then quads (each quad is
        one element of two triangles). coupled: its nodes are then set by the partner
        (set_surface_nodes); else it is fixed. Allowed before and after start. Returns its
        index."""
        nodes, node_count = _doubles(nodes, "add_surface: nodes")
        description = _abi.sized(
            _abi.quarry_surface_desc,
            name=_text(name),
            material=_text(material),
            node_count=node_count,
            nodes=_pointer(nodes),
            driver=Driver.COUPLED if coupled else Driver.FIXED,
        )
        keep = [nodes]
        for field, values, corners in (("triangles", triangles, 3), ("quads", quads, 4)):
            if values is None:
                continue
            array = _indices(values, "add_surface: " + field).reshape(-1)
            if array.size % corners:
                raise python_error(
                    Status.ERROR_BAD_LENGTH,
                    "add_surface: %s needs %d node indices per element" % (field, corners),
                )
            setattr(description, field, _pointer(array, ctypes.c_uint32))
            setattr(description, field[:-1] + "_count", array.size // corners)
            keep.append(array)
        index = ctypes.c_uint32()
        self._change("quarry_add_surface", ctypes.byref(description), ctypes.byref(index))
        return index.value

    @property
    def num_surfaces(self):
        count = ctypes.c_uint32()
        self._call("quarry_num_surfaces", ctypes.byref(count))
        return count.value

    def find_surface(self, name):
        """The index of the surface with this name (the deck's or add_surface's)."""
        index = ctypes.c_uint32()
        self._call("quarry_find_surface", _text(name), ctypes.byref(index))
        return index.value

    def surface_info(self, surface):
        """SurfaceInfo(node_count, element_count, triangle_count, driver) of a surface (index
        or name)."""
        info = _abi.sized(_abi.quarry_surface_info)
        self._call("quarry_get_surface_info", self._surface_index(surface), ctypes.byref(info))
        return SurfaceInfo(
            info.node_count, info.element_count, info.triangle_count, Driver(info.driver)
        )

    def set_surface_driver(self, surface, driver):
        """Makes a fixed surface "coupled" or a coupled one "fixed" (a prescribed one cannot
        change: WrongStateError)."""
        self._change(
            "quarry_set_surface_driver",
            self._surface_index(surface),
            _enum(Driver, driver, "set_surface_driver"),
        )

    def set_surface_nodes(self, surface, positions, velocities=None):
        """A coupled surface's nodes now: positions (m, (N, 3)) and velocities (m/s; None: at
        rest). Until the next call it moves on with these velocities, x(t) = x + v (t − t_set);
        the neighbour lists are rebuilt when a node has moved more than half the skin."""
        positions, count = _doubles(positions, "set_surface_nodes: positions")
        velocity_array = None
        if velocities is not None:
            velocity_array, entries = _doubles(velocities, "set_surface_nodes: velocities")
            if entries != count:
                raise python_error(
                    Status.ERROR_BAD_LENGTH,
                    "set_surface_nodes: %d velocities for %d positions" % (entries, count),
                )
        self._change(
            "quarry_set_surface_nodes",
            self._surface_index(surface),
            _pointer(positions),
            _pointer(velocity_array),
            count,
        )

    def surface_nodes(self, surface):
        """(positions (m), velocities (m/s)) of the surface's nodes now, (N, 3) arrays."""
        index = self._surface_index(surface)
        count = self.surface_info(index).node_count
        positions = np.empty((count, 3), dtype=np.float64)
        velocities = np.empty((count, 3), dtype=np.float64)
        self._call(
            "quarry_get_surface_nodes", index, _pointer(positions), _pointer(velocities), count
        )
        return positions, velocities

    def surface_loads(self, surface):
        """The loads the particles put on the surface as time means over the window since the
        last call for it (or since it was first asked for: the first call reads an empty window
        and starts it): impulse / window, so a partner that syncs every period receives exactly
        the momentum transferred. The window then restarts. A SurfaceLoads record (nodal_force,
        pressure, shear_stress, element_force; .window and .time in s)."""
        index = self._surface_index(surface)
        info = self.surface_info(index)
        arrays = {
            "nodal_force": np.zeros((info.node_count, 3)),
            "pressure": np.zeros(info.element_count),
            "shear_stress": np.zeros((info.element_count, 3)),
            "element_force": np.zeros((info.element_count, 3)),
        }
        loads = _abi.sized(
            _abi.quarry_surface_loads, node_count=info.node_count, element_count=info.element_count
        )
        for name, array in arrays.items():
            setattr(loads, name, _pointer(array))
        self._change("quarry_get_surface_loads", index, ctypes.byref(loads))
        return SurfaceLoads(arrays, loads.window, loads.time)

    # ---- step hooks (in-process only) ----

    def set_hook(self, stage, function):
        """Calls function(simulation) inside every step: at "post_force" (after the forces of
        the new positions, before the closing half kick: positions x(t + dt), velocities the
        half-step v(t + dt/2) — the place for velocity-dependent forces, added with
        add_hook_forces) or at "end_of_step". function None removes the hook. Inside it the
        simulation may be read (particles, views) and, at post_force, given forces; other
        changing calls raise WrongStateError. Return None to go on; an exception (or a true
        return value) stops the step: advance/step then raise HookError with the exception as
        its __cause__. Cost: a Python call per step."""
        stage = _enum(HookStage, stage, "set_hook: stage")
        if function is None:
            self._call("quarry_set_hook", stage, _abi.quarry_hook_fn(), None)
            self._hooks.pop(stage, None)
            return
        simulation = weakref.ref(self)  # no cycle through the engine's callback

        def trampoline(handle, stage_value, user_data):
            owner = simulation()
            if owner is None:
                return 1
            owner._changes += 1  # views taken in a hook are for this call of it only
            try:
                result = function(owner)
            except BaseException as exception:  # noqa: B036 - carried to the caller of step()
                owner._hook_exception = exception
                return 1
            finally:
                owner._changes += 1
            if not result:
                return 0
            return int(result) if isinstance(result, int) else 1

        callback = _abi.quarry_hook_fn(trampoline)
        self._call("quarry_set_hook", stage, callback, None)
        self._hooks[stage] = callback

    def add_hook_forces(self, force=None, torque=None):
        """Inside a post_force hook only: adds force (N) and torque (N·m), (n, 3) in TYPE order,
        to this step's forces."""
        arrays, counts = [], []
        for name, values in (("force", force), ("torque", torque)):
            if values is None:
                arrays.append(None)
            else:
                array, count = _doubles(values, "add_hook_forces: " + name)
                arrays.append(array)
                counts.append(count)
        if len(set(counts)) > 1:
            raise python_error(
                Status.ERROR_BAD_LENGTH, "add_hook_forces: %d forces and %d torques" % tuple(counts)
            )
        self._change(
            "quarry_add_hook_forces",
            _pointer(arrays[0]),
            _pointer(arrays[1]),
            counts[0] if counts else 0,
        )
