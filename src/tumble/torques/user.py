"""A torque from a user's function compiled with numba: :class:`UserTorque`."""

from __future__ import annotations

import dis
import inspect
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import torques as kernels
from tumble.errors import InputError, uncoloured
from tumble.torques.model import TorqueModel

__all__ = ["UserTorque"]

Array = NDArray[np.float64]

#: What each argument of a torque function and of a potential stands for
#: (:attr:`tumble.torques.TorqueModel.depends_on`); ``params`` and ``out`` are not
#: counted.
_TORQUE_ARGUMENTS = ("time", "omega", "attitude")
_POTENTIAL_ARGUMENTS = ("time", "attitude")


@dataclass(frozen=True, eq=False, repr=False)
class UserTorque(TorqueModel):
    """A torque computed by ``function``, compiled with ``numba.njit``, optionally
    derived from a ``potential`` energy.

    ``function(t, omega, quaternion, params, out)`` writes the torque on the
    body in body axes (N·m) into ``out`` (3,), given the time ``t`` (s), the
    angular velocity ``omega`` (3,) in body axes (rad/s) and the attitude
    ``quaternion`` (4,), scalar first, body → space. ``params`` (a sequence of
    floats) is passed through unchanged, so one compiled function serves many
    parameter values.

    ``potential(t, quaternion, params) -> float``, also compiled with
    ``numba.njit``, is the potential energy U (J) from which the torque derives,
    with the same ``t``, ``quaternion`` and ``params``:
    :attr:`tumble.Trajectory.energy` adds it to the kinetic energy. tumble does
    not check that the torque is U's gradient: that is the function's to get
    right (for a rotation δθ about a body axis e, U changes by −τ·e δθ).

    Which of ``t``, ``omega`` and ``quaternion`` the functions read is found from
    their code (an argument never used, not even passed on to a helper, is not
    read): that is :attr:`depends_on`. With a potential, neither of which reads
    ``t``, and a function that does not read ``omega``, the model is
    *conservative*: the motion keeps T + U (the drift report lists the energy)
    and ``method="auto"`` takes the symplectic splitting.

    Both functions are called once here on a test state (t = 0, ω = 0, the
    identity attitude), so a wrong signature fails now, not mid-run.

    Parameters
    ----------
    function : the torque, compiled with ``numba.njit``.
    params : floats passed to both functions (SI units are advised).
    potential : None, or U(t, q) in J, compiled with ``numba.njit``.
    actuator : ``"external"`` (the default) or ``"rotors"`` (the body's rotors
        produce the torque: then no energy is conserved).

    Raises
    ------
    InputError
        A function or potential not compiled with numba, one that does not run on
        the test state, a potential that does not return a number.

    Examples
    --------
    >>> import numba
    >>> @numba.njit
    ... def magnetic_damper(t, omega, quaternion, params, out):
    ...     out[0] = -params[0] * omega[0] ** 3
    >>> model = UserTorque(magnetic_damper, [0.01])
    >>> sorted(model.depends_on), model.conservative
    (['omega'], False)

    A torsion spring about body z, τ = −k θ e_z with θ the angle of the rotation
    about z, derives from U = ½ k θ² (k in N·m/rad):

    >>> import math
    >>> @numba.njit
    ... def spring(t, omega, quaternion, params, out):
    ...     out[2] = -params[0] * 2.0 * math.atan2(quaternion[3], quaternion[0])
    >>> @numba.njit
    ... def spring_energy(t, quaternion, params):
    ...     angle = 2.0 * math.atan2(quaternion[3], quaternion[0])
    ...     return 0.5 * params[0] * angle * angle
    >>> UserTorque(spring, [0.5], potential=spring_energy).conservative
    True
    """

    function: Any
    params: Any = ()
    potential: Any = None
    actuator: str = "external"

    name = "user"
    summary = "a torque from a function compiled with numba"
    kernel = staticmethod(kernels.user_torque)
    depends_on = frozenset({"attitude", "time", "omega"})
    in_files = False
    one_per_sum = "compute both torques in one function"
    drives_rotors = True

    def __post_init__(self) -> None:
        super().__post_init__()
        _check_compiled(self.function, "function", "compiled with numba.njit")
        values = np.asarray(self.params, dtype=float).reshape(-1).copy()
        try:
            self.function(0.0, np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), values, np.zeros(3))
        except Exception as exc:  # numba raises its own typing errors
            raise InputError(
                "Expected `function(t, omega, quaternion, params, out)` to run on a test state "
                f"(t = 0, omega = 0, identity attitude), got {_first_line(exc)}"
            ) from None
        reads = _arguments_read(self.function, _TORQUE_ARGUMENTS)
        if self.potential is not None:
            _check_potential(self.potential, values)
            energy_reads = _arguments_read(self.potential, _POTENTIAL_ARGUMENTS)
            # A torque of ω or t, or a potential of t, does work that U does not hold.
            conservative = not ({"time", "omega"} & reads) and "time" not in energy_reads
            object.__setattr__(self, "conservative", conservative)
        object.__setattr__(self, "depends_on", reads)
        values.flags.writeable = False
        object.__setattr__(self, "params", values)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.zeros(0)

    def context(self, body: Any) -> Any:
        callback = _callback(self.function)
        return (
            np.ascontiguousarray(body.axes),
            np.asarray(body.principal_rotation.as_quat(scalar_first=True), dtype=float),
            np.array(self.params, dtype=float),  # writable copy
            np.zeros(3),
            np.zeros(4),
            np.zeros(3),
            callback,
        )

    def potential_energy(self, body: Any, t: Array, quaternion: Array) -> Array | None:
        """``potential(t, q, params)`` at each sample, J, (n,): ``t`` (n,), s, and
        ``quaternion`` (n, 4) ``[w, x, y, z]``, body → space (the body's own axes,
        as ``function`` sees them); None without a potential."""
        if self.potential is None:
            return None
        times = np.ascontiguousarray(t, dtype=float).reshape(-1)
        attitudes = np.ascontiguousarray(quaternion, dtype=float).reshape(-1, 4)
        out = np.empty(times.size)
        _energies(self.potential)(times, attitudes, np.array(self.params, dtype=float), out)
        return out

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset({"energy"}) if self.conservative else frozenset()

    def flat_names(self) -> tuple[str, ...]:
        """``params[0]``, ``params[1]``, ...: the names of :meth:`flat_values`."""
        return tuple(f"params[{k}]" for k in range(len(self.params)))

    def flat_values(self) -> Array:
        """``params`` as a flat array."""
        return np.asarray(self.params, dtype=float).reshape(-1)

    def with_flat_values(self, values: Array) -> TorqueModel:
        """The same functions with ``params`` = ``values``."""
        return replace(self, params=np.array(values, dtype=float))

    def describe(self) -> dict[str, Any]:
        """The functions' names and the params (a file cannot hold the functions)."""
        entry = {
            "type": self.name,
            "function": getattr(self.function, "__name__", "function"),
            "params": np.asarray(self.params).tolist(),
            "potential": None
            if self.potential is None
            else getattr(self.potential, "__name__", "potential"),
        }
        return {**entry, "actuator": self.actuator}

    def __repr__(self) -> str:
        name = getattr(self.function, "__name__", "function")
        energy = (
            ""
            if self.potential is None
            else f", potential={getattr(self.potential, '__name__', 'potential')}"
        )
        through = "" if self.actuator == "external" else f", actuator={self.actuator!r}"
        return f"UserTorque({name}, params={np.asarray(self.params).tolist()}{energy}{through})"


def _check_compiled(function: Any, name: str, expected: str) -> None:
    """Refuse ``function`` unless numba compiled it: ``expected`` says what was wanted."""
    from numba.core.dispatcher import Dispatcher

    if not isinstance(function, Dispatcher):
        what = getattr(function, "__name__", None)
        shown = what if isinstance(what, str) else function
        raise InputError(
            f"Expected `{name}` to be {expected}, got {type(function).__name__} {shown!r}."
        )


def _check_potential(potential: Any, params: Array) -> None:
    """Run ``potential`` on the test state: it must compile, run and return a number."""
    _check_compiled(potential, "potential", "None or a function compiled with numba.njit")
    name = getattr(potential, "__name__", "potential")
    try:
        value = potential(0.0, np.array([1.0, 0.0, 0.0, 0.0]), params)
    except Exception as exc:  # numba raises its own typing errors
        raise InputError(
            f"Expected `potential(t, quaternion, params)` ({name!r}) to compile and run on a "
            f"test state (t = 0, identity attitude), got {_first_line(exc)}"
        ) from None
    if isinstance(value, bool | np.bool_) or not isinstance(
        value, int | float | np.integer | np.floating
    ):
        shown = (
            f"an array of shape {np.shape(value)}"
            if isinstance(value, np.ndarray)
            else f"{type(value).__name__} {value!r}"
        )
        raise InputError(
            f"Expected `potential(t, quaternion, params)` ({name!r}) to return a number (J), "
            f"got {shown} on a test state (t = 0, identity attitude)."
        )


def _first_line(exc: Exception) -> str:
    """``Kind: first line of the message``: numba's typing errors run to pages, and
    their first line only names the compiler's stage ("Failed in nopython mode
    pipeline"), so the line after it says what failed."""
    lines = [line.strip() for line in uncoloured(str(exc)).strip().splitlines() if line.strip()]
    if len(lines) > 1 and lines[0].startswith("Failed in "):
        lines = lines[1:]
    return f"{type(exc).__name__}: {lines[0]}" if lines else type(exc).__name__


def _arguments_read(function: Any, meanings: tuple[str, ...]) -> frozenset[str]:
    """What the leading arguments of ``function`` (a numba dispatcher) stand for,
    among ``meanings``, for those its code reads.

    Read from the bytecode: an argument that no instruction loads (and no inner
    function captures) cannot affect the result. Whatever cannot be told (no
    Python code, ``*args``) counts as read.
    """
    code = getattr(getattr(function, "py_func", function), "__code__", None)
    if code is None or code.co_flags & (inspect.CO_VARARGS | inspect.CO_VARKEYWORDS):
        return frozenset(meanings)
    loaded = set(code.co_cellvars)
    for instruction in dis.get_instructions(code):
        if instruction.opname.startswith("LOAD_FAST"):
            value = instruction.argval
            loaded.update(value if isinstance(value, tuple) else (value,))
    arguments = code.co_varnames[: code.co_argcount]
    return frozenset(
        meaning
        for k, meaning in enumerate(meanings)
        if k >= len(arguments) or arguments[k] in loaded
    )


#: One C callback per user function, and one compiled loop per potential,
#: compiled on first use.
_CALLBACKS: dict[Any, Any] = {}
_ENERGIES: dict[Any, Any] = {}


def _callback(function: Any) -> Any:
    callback = _CALLBACKS.get(function)
    if callback is None:
        callback = _CALLBACKS[function] = kernels.compile_user_torque(function)
    return callback


def _energies(potential: Any) -> Any:
    energies = _ENERGIES.get(potential)
    if energies is None:
        energies = _ENERGIES[potential] = kernels.compile_user_potential(potential)
    return energies
