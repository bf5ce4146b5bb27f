"""Exceptions: every status other than QUARRY_OK becomes a QuarryError of the code's class,
carrying the code, its name and the engine's last-error text (what and where)."""

from ._abi import Status


class QuarryError(Exception):
    """A Quarry call failed. `status` is the quarry_status code (a quarry.Status), `status_name`
    its C name (e.g. "QUARRY_ERROR_BAD_LENGTH") and `message` the engine's text."""

    status = Status.ERROR_INTERNAL

    def __init__(self, status, status_name, message):
        super().__init__("%s: %s" % (status_name, message))
        self.status = Status(status) if status in Status._value2member_map_ else status
        self.status_name = status_name
        self.message = message


class InvalidHandleError(QuarryError):
    """The simulation is closed (or the handle was never opened)."""


class NullPointerError(QuarryError):
    """A required array was missing."""


class BadLengthError(QuarryError, ValueError):
    """An array's length is not the one the call needs (e.g. not one entry per particle)."""


class BadValueError(QuarryError, ValueError):
    """A value out of range, not finite, an unknown name or enum."""


class WrongStateError(QuarryError):
    """Not allowed now (e.g. adding a material after start, or a call inside a hook)."""


class StaleViewError(WrongStateError):
    """A View's particles changed (re-sorted, inserted, removed or restored) since it was taken:
    refresh it (or take a new one) to accept the new particles. Raised by the Python module."""

    def __init__(self, message):
        super().__init__(Status.ERROR_WRONG_STATE, "QUARRY_ERROR_WRONG_STATE", message)


class NotFoundError(QuarryError, LookupError):
    """A particle id, type, surface or property that does not exist."""


class InputError(QuarryError):
    """A deck, mesh or checkpoint is wrong (file:line:col in the message)."""


class PhysicsError(QuarryError):
    """The simulation went unstable (step, particle and a hint in the message)."""


class FileError(QuarryError):
    """A file could not be read or written (QUARRY_ERROR_IO)."""


class VersionError(QuarryError):
    """The ABI majors of the caller and the library (or server) differ."""


class TransportError(QuarryError):
    """Remote: the server is gone, unreachable, or answered garbage."""


class RemoteTimeoutError(QuarryError):
    """Remote: no answer within the open's timeout."""


class UnsupportedError(QuarryError):
    """Not available on this handle (e.g. hooks on a remote one)."""


class HookError(QuarryError):
    """A step hook stopped the step. When the hook was a Python function that raised, the
    exception it raised is this one's __cause__."""


class InternalError(QuarryError):
    """A bug in Quarry: please report it with the message."""


ERROR_CLASSES = {
    Status.ERROR_INVALID_HANDLE: InvalidHandleError,
    Status.ERROR_NULL_POINTER: NullPointerError,
    Status.ERROR_BAD_LENGTH: BadLengthError,
    Status.ERROR_BAD_VALUE: BadValueError,
    Status.ERROR_WRONG_STATE: WrongStateError,
    Status.ERROR_NOT_FOUND: NotFoundError,
    Status.ERROR_INPUT: InputError,
    Status.ERROR_PHYSICS: PhysicsError,
    Status.ERROR_IO: FileError,
    Status.ERROR_VERSION: VersionError,
    Status.ERROR_TRANSPORT: TransportError,
    Status.ERROR_TIMEOUT: RemoteTimeoutError,
    Status.ERROR_UNSUPPORTED: UnsupportedError,
    Status.ERROR_HOOK: HookError,
    Status.ERROR_INTERNAL: InternalError,
}


def error_for(status, status_name, message):
    """The exception of a status code (QuarryError for a code this module does not know)."""
    return ERROR_CLASSES.get(status, QuarryError)(status, status_name, message)


def python_error(status, message):
    """An error found on the Python side before calling the engine, in the engine's classes."""
    return error_for(status, "QUARRY_" + Status(status).name, message)
