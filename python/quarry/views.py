"""quarry.View: a numpy array on one of the engine's per-particle arrays (quarry_view_particles,
quarry_view_property), no copy; re-fetched after a changing call, refused when its particles are
no longer the same ones (their epoch moved)."""

import ctypes

import numpy as np

from ._abi import DType
from .errors import StaleViewError

_VIEW_DTYPES = {
    DType.FLOAT64: (np.float64, ctypes.c_double),
    DType.UINT64: (np.uint64, ctypes.c_uint64),
    DType.UINT32: (np.uint32, ctypes.c_uint32),
    DType.UINT16: (np.uint16, ctypes.c_uint16),
}


def _view_array(view):
    """A numpy array on a quarry_view's memory (no copy): shape (count,) or (count, components);
    read-only (and not to be made writeable) unless the view is writable."""
    np_type, c_type = _VIEW_DTYPES[DType(view.dtype)]
    components = view.components
    shape = (view.count,) if components == 1 else (view.count, components)
    if view.count == 0 or not view.data:
        array = np.empty(shape, dtype=np_type)
        array.flags.writeable = bool(view.writable)
        return array
    itemsize = np.dtype(np_type).itemsize
    if view.stride == components * itemsize:
        array = np.ctypeslib.as_array(ctypes.cast(view.data, ctypes.POINTER(c_type)), shape=shape)
    else:  # padded records: the same memory with the view's stride
        span = view.stride * (view.count - 1) + components * itemsize
        raw = (ctypes.c_char * span).from_address(view.data)
        strides = (view.stride,) if components == 1 else (view.stride, itemsize)
        array = np.ndarray(shape, dtype=np_type, buffer=raw, strides=strides)
    if not view.writable:
        # A read-only buffer under the array: its WRITEABLE flag cannot be set again.
        array = np.frombuffer(memoryview(array).toreadonly(), dtype=np_type).reshape(shape)
    return array


class View:
    """A zero-copy numpy view of one of the engine's per-particle arrays, in ENGINE order.

    `view.array` is a numpy array on the engine's own memory: reading it costs nothing and sees
    the engine's values as they are now. It is read-only except for custom properties and the
    next step's loads (view_next_step_loads), whose writes go straight into the engine (no
    set_property or set_external_loads needed).

    The rule: an array taken from a view is valid until the next call that changes the
    simulation (advance, step, add/remove particles, set loads or properties, restore_state,
    surface changes, close — and, inside a hook, until the hook returns). Keep the View, not the
    array: `view.array` fetches the engine's pointer again after such a call (O(1)), and raises
    StaleViewError when the particles are no longer the same ones (their epoch moved: a re-sort,
    an insertion or a removal, or a restore_state). Then `view.refresh()` (or a new view) accepts
    the new particles. `epoch` is the particles' epoch the view stands for.

    np.asarray(view), len(view), view[k] and (writable views) view[k] = x act on `view.array`.
    """

    def __init__(self, simulation, name, fetch):
        self._simulation = simulation
        self._fetch = fetch  # () -> quarry_view
        self.name = name
        self._array = None
        self._changes = None
        self._restores = None
        self.epoch = None
        self.refresh()

    def refresh(self):
        """Takes the engine's array as it is now (accepting a new epoch). Returns the view."""
        raw = self._fetch()
        self._array = _view_array(raw)
        self.epoch = raw.epoch
        self.address = raw.data or 0
        self.writable = bool(raw.writable)
        self._changes = self._simulation._changes
        self._restores = self._simulation._restores
        return self

    @property
    def array(self):
        """The numpy array (see the class's rule). Raises StaleViewError if the particles'
        epoch moved since the view was taken or refreshed."""
        simulation = self._simulation
        if self._changes != simulation._changes:
            raw = self._fetch()
            if raw.epoch != self.epoch or self._restores != simulation._restores:
                raise StaleViewError(
                    "view of %s: the particles changed (epoch %d, now %d%s): re-sorted, inserted "
                    "or removed, so index k is no longer the same particle; call view.refresh() "
                    "or take a new view"
                    % (
                        self.name,
                        self.epoch,
                        raw.epoch,
                        ", and a restore_state" if self._restores != simulation._restores else "",
                    )
                )
            self._array = _view_array(raw)
            self.address = raw.data or 0
            self._changes = simulation._changes
        return self._array

    @property
    def valid(self):
        """Whether `array` would return without StaleViewError."""
        simulation = self._simulation
        if simulation.closed:
            return False
        if self._changes == simulation._changes:
            return True
        return self._fetch().epoch == self.epoch and self._restores == simulation._restores

    def __array__(self, dtype=None, copy=None):
        array = self.array
        if dtype is not None and np.dtype(dtype) != array.dtype:
            return array.astype(dtype)
        return array.copy() if copy else array

    def __len__(self):
        return len(self.array)

    def __getitem__(self, key):
        return self.array[key]

    def __setitem__(self, key, value):
        self.array[key] = value

    def __repr__(self):
        return "<quarry.View of %s, epoch %s, %s>" % (
            self.name,
            self.epoch,
            "writable" if self.writable else "read-only",
        )
