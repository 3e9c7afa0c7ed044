"""Simulation of a rigid body's rotation: :func:`simulate` and :class:`Trajectory`.

The body turns freely about its centre of mass, or about a ``pivot`` (a body
point held fixed in space) under ``gravity``, with optional torque models from
:mod:`tumble.torques`. Inside, the state is integrated in the principal frame of
the inertia (about the centre of mass, or about the pivot) by compiled kernels
(:mod:`tumble.core.rigid`); results are reported in the user's body axes.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.core.rigid import FINITE, N_TORQUE_PARAMS, rk4_batch, rk4_run, rk4_run_hooked
from tumble.core.splitting import splitting_batch
from tumble.errors import InputError
from tumble.massprops import MassProperties, principal_decomposition
from tumble.torques import TorqueModel
from tumble.units import to_si, vector_to_si

__all__ = [
    "BatchResult",
    "CoarseStepWarning",
    "IntegrationError",
    "Trajectory",
    "simulate",
    "simulate_batch",
]

Array = NDArray[np.float64]

#: Fewer integration steps than this per turn of the fastest rotation trigger a
#: :class:`CoarseStepWarning`: RK4's phase error per turn grows as (2π/n)⁴/120 and
#: passes 1e-4 below about 20 steps a turn.
MIN_STEPS_PER_TURN = 20

#: Steps per turn of the fastest rotation when ``dt`` is not given: RK4 then
#: keeps ω to about 1e-10 relative per turn.
DEFAULT_STEPS_PER_TURN = 200

#: Steps per call of the compiled kernel between progress reports.
PROGRESS_CHUNK = 1 << 17

METHODS = ("auto", "exact", "splitting", "strang", "rk4", "adaptive")
BATCH_METHODS = ("rk4", "splitting", "strang")


class CoarseStepWarning(UserWarning):
    """The time step is too coarse for the fastest rotation of the body."""


class IntegrationError(InputError):
    """The integration produced NaN or infinity (usually: ``dt`` far too large)."""


# --------------------------------------------------------------- quaternions
def _compose(quaternions: Array, rotation: Rotation) -> Array:
    """Scalar-first quaternions of ``R(q) · rotation``: a compiled loop for one
    rotation (the samples of a trajectory), scipy for one rotation per row."""
    if rotation.single:
        from tumble.core.quaternion import multiply_right

        stack = np.ascontiguousarray(np.atleast_2d(quaternions), dtype=float)
        r = np.asarray(rotation.as_quat(scalar_first=True), dtype=float)
        out = multiply_right(stack, r)
        return np.asarray(out[0] if np.ndim(quaternions) == 1 else out)
    return np.asarray(
        (Rotation.from_quat(quaternions, scalar_first=True) * rotation).as_quat(scalar_first=True)
    )


def _attitude(attitude0: Any) -> Array:
    """A unit quaternion from None, a quaternion (4,) or a scipy Rotation."""
    if attitude0 is None:
        return np.array([1.0, 0.0, 0.0, 0.0])
    if isinstance(attitude0, Rotation):
        if not attitude0.single:
            raise InputError(f"Expected `attitude0` to be a single rotation, got {len(attitude0)}.")
        return np.asarray(attitude0.as_quat(scalar_first=True), dtype=float)
    q = vector_to_si(attitude0, "dimensionless", "attitude0", (4,))
    norm = float(np.linalg.norm(q))
    if norm < 1e-12:
        raise InputError(
            f"Expected `attitude0` to be a non-zero quaternion [w, x, y, z], got {q.tolist()}."
        )
    return q / norm


# ------------------------------------------------------------------ simulate
def simulate(
    mp: MassProperties,
    omega0: Any,
    *,
    attitude0: Any = None,
    duration: Any,
    dt: Any = None,
    pivot: Any = None,
    gravity: Any = None,
    torque: TorqueModel | None = None,
    method: str = "auto",
    record_every: int = 1,
    progress: Callable[[int, int], object] | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> Trajectory:
    """Simulate the rotation of a rigid body under Euler's equations.

    Parameters
    ----------
    mp : the body's mass properties.
    omega0 : (3,) initial angular velocity in body coordinates, rad/s (or quantities).
    attitude0 : initial attitude, a unit quaternion ``[w, x, y, z]`` rotating
        body coordinates into space coordinates (normalised here), or a scipy
        ``Rotation``; default the identity.
    duration : simulated time, s, > 0.
    dt : integration step (rk4, strang, splitting) or sampling interval (exact,
        adaptive), s, > 0. Default: 1/200 of a turn of the fastest rotation (see
        ``DEFAULT_STEPS_PER_TURN``). It is shortened slightly so a whole number
        of steps spans ``duration``.
    pivot : None for a free body (rotation about the centre of mass), or a body
        point (3,), m, held fixed in space; then the dynamics use the inertia
        about the pivot and gravity acts at the centre of mass.
    gravity : (3,) gravitational acceleration in space coordinates, m/s², e.g.
        ``[0, 0, -9.81]``. Required with a pivot (pass zeros to mean none); on a
        free body it exerts no torque about the centre of mass.
    torque : a torque model from :mod:`tumble.torques`, or a sum of them.
    method :
        * ``"exact"``: torque-free bodies (free, or on a pivot without gravity):
          the closed-form solution, sampled every ``dt``; no stepping error.
        * ``"splitting"``: fourth-order symplectic splitting (Yoshida's
          composition of ``"strang"``): exact rotations of the free motion
          composed with torque kicks (:mod:`tumble.core.splitting`); |L| kept
          to round-off when torque-free, bounded energy error under gravity;
          exact free motion for a symmetric body.
        * ``"strang"``: the same splitting at second order.
        * ``"rk4"``: classical Runge–Kutta, fixed step, quaternion renormalised.
        * ``"adaptive"``: Dormand–Prince 5(4) with step-size control to
          ``rtol``/``atol`` and dense output at every ``dt``.
        * ``"auto"``: exact when torque-free, splitting when the only torque
          is gravity about a pivot (conservative), adaptive otherwise.
        ``Trajectory.reason`` says which ran and why.
    record_every : keep every k-th step (the final state is always kept).
    progress : None or a callable ``progress(done, total)`` (steps, or samples
        for the adaptive method).
    rtol, atol : tolerances of the adaptive method: each step's local error in
        each component of ω (rad/s) and of the quaternion is kept below
        ``atol + rtol · |value|`` (root-mean-square over the components).

    Returns
    -------
    Trajectory

    Raises
    ------
    InputError
        Bad values (see the messages), a body with a zero principal moment, an
        unknown method.
    IntegrationError
        The state became NaN or infinite; the message names the step and time.

    Warns
    -----
    CoarseStepWarning
        When ``dt`` gives fewer than ``MIN_STEPS_PER_TURN`` steps per turn of
        the fastest rotation.
    """
    if not isinstance(mp, MassProperties):
        raise InputError(f"Expected `mp` to be a MassProperties, got {type(mp).__name__}.")
    if torque is not None and isinstance(torque, TorqueModel) and torque.per_body:
        raise InputError(
            f"Expected one torque for one body, got per-body values ({torque!r}): those are "
            "for simulate_batch."
        )
    if method not in METHODS:
        raise InputError(f"Expected `method` to be one of {', '.join(METHODS)}, got {method!r}.")
    if torque is not None and not isinstance(torque, TorqueModel):
        raise InputError(
            f"Expected `torque` to be a model from tumble.torques, got {type(torque).__name__}."
        )
    if (
        isinstance(record_every, bool)
        or not isinstance(record_every, int | np.integer)
        or record_every < 1
    ):
        raise InputError(f"Expected `record_every` to be an integer >= 1, got {record_every!r}.")
    omega = vector_to_si(omega0, "angular_velocity", "omega0")
    q0 = _attitude(attitude0)
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    g = np.zeros(3) if gravity is None else vector_to_si(gravity, "acceleration", "gravity")
    model = (
        torque if torque is not None else TorqueModel(np.zeros(3), np.zeros(3), np.zeros(3), 0.0)
    )
    g = g + model.gravity
    if pivot is not None and gravity is None and not np.any(model.gravity):
        raise InputError(
            "Expected `gravity` with `pivot`, got none (a pivot without gravity is a free "
            "rotation about that point: pass gravity=[0, 0, 0] to mean it)."
        )
    point = mp.center_of_mass if pivot is None else vector_to_si(pivot, "length", "pivot")
    inertia = mp.inertia if pivot is None else mp.inertia_about(point)
    moments, axes = principal_decomposition(inertia)
    if moments[0] <= 1e-12 * moments[2]:
        raise InputError(
            f"Expected a body with no zero principal moment to simulate, got moments "
            f"{moments.tolist()} kg·m² (an idealised rod or point masses on a line: give the "
            "body some thickness)."
        )

    lever = mp.center_of_mass - point  # body axes; zero for a free body
    params = np.zeros(N_TORQUE_PARAMS)
    params[0:3] = axes.T @ model.body
    params[3:6] = model.space
    if pivot is not None:
        params[6:9] = axes.T @ lever
        params[9:12] = mp.mass * g
    params[12] = model.damping

    torque_free = model.conservative and (pivot is None or not np.any(g))
    conservative = model.conservative
    if method == "exact" and not torque_free:
        raise InputError(
            "Expected a torque-free body for method 'exact' (no torque model other than "
            "gravity, and no gravity with a pivot), got "
            + ("gravity about a pivot." if conservative else f"{model!r}.")
        )
    if method == "auto":
        if torque_free:
            chosen = "exact"
            reason = "auto: torque-free, so the exact solution (Jacobi elliptic functions)"
        elif conservative:
            chosen = "splitting"
            reason = (
                "auto: gravity about a pivot is conservative, so the symplectic splitting "
                "(bounded energy error)"
            )
        else:
            chosen = "adaptive"
            reason = (
                "auto: non-conservative torques, so the adaptive Dormand–Prince 5(4) "
                f"(rtol {rtol:g}, atol {atol:g})"
            )
    else:
        chosen, reason = method, "requested"
    if chosen == "adaptive":
        for name, value in (("rtol", rtol), ("atol", atol)):
            if not (isinstance(value, float | int) and math.isfinite(value) and value > 0):
                raise InputError(f"Expected `{name}` > 0, got {value!r}.")
        if rtol < 1e-15:
            raise InputError(f"Expected `rtol` >= 1e-15 (round-off), got {rtol!r}.")
    fastest = _fastest_rate(
        moments,
        axes.T @ omega,
        mp.mass * float(np.linalg.norm(g)),
        lever,
        pivot,
        exact_spin=chosen in ("splitting", "strang"),
    )
    per_turn = math.inf
    if dt is None:
        step = 2 * math.pi / fastest / DEFAULT_STEPS_PER_TURN if fastest > 0 else total_time
    else:
        step = to_si(dt, "time", "dt")
        if step <= 0:
            raise InputError(f"Expected `dt` > 0 s, got {step!r}.")
        per_turn = 2 * math.pi / (fastest * step) if fastest > 0 else math.inf
    n_steps = max(1, math.ceil(total_time / step * (1 - 1e-12)))
    step = total_time / n_steps

    stepping = chosen in ("rk4", "strang", "splitting")
    if stepping and per_turn < MIN_STEPS_PER_TURN:
        warnings.warn(
            f"dt = {step:.3g} s gives {per_turn:.1f} steps per turn of the fastest rotation "
            f"({fastest:.3g} rad/s); below {MIN_STEPS_PER_TURN} the result is inaccurate.",
            CoarseStepWarning,
            stacklevel=2,
        )

    n_rows = n_steps // record_every + 1
    tail = n_steps % record_every != 0
    times = np.asarray(np.arange(n_rows) * (record_every * step), dtype=np.float64)
    if tail:
        times = np.append(times, total_time)
    w = axes.T @ omega
    principal_axes = Rotation.from_matrix(axes)
    q = _compose(q0, principal_axes)  # principal → body → space
    hook = _user_hook(model, axes, principal_axes)
    steps_taken = 0
    if chosen == "exact":
        out_w, out_q = _exact_principal(moments, w, q, times)
        if progress is not None:
            progress(n_steps, n_steps)
    elif chosen == "adaptive":
        out_w, out_q, steps_taken = _adaptive(
            moments, params, hook, w, q, times, rtol, atol, progress
        )
    else:
        out_w = np.empty((n_rows + tail, 3))
        out_q = np.empty((n_rows + tail, 4))
        out_w[0], out_q[0] = w, q
        step_in_chunks(
            lambda done, count: _fixed_steps(
                chosen, moments, params, hook, w, q, step, count, done, record_every, out_w, out_q
            ),
            n_steps,
            step,
            progress,
        )
        if tail:
            out_w[-1], out_q[-1] = w, q
        steps_taken = n_steps
    return Trajectory(
        t=times,
        omega=out_w @ axes.T,
        quaternion=_compose(out_q, principal_axes.inv()),
        mass_properties=mp,
        pivot=None if pivot is None else point,
        gravity=g,
        method=chosen,
        reason=reason,
        dt=step,
        steps=steps_taken,
    )


def step_in_chunks(
    run: Callable[[int, int], int],
    n_steps: int,
    step: float,
    progress: Callable[[int, int], object] | None,
) -> None:
    """Call ``run(done, count)`` (a compiled kernel's status: ``FINITE`` or the
    number of the first non-finite step) over chunks of ``PROGRESS_CHUNK``
    steps, reporting ``progress(done, n_steps)`` after each.

    Raises
    ------
    IntegrationError
        When a chunk reports a non-finite step; the message names it and its time.
    """
    done = 0
    while done < n_steps:
        count = min(PROGRESS_CHUNK, n_steps - done)
        status = int(run(done, count))
        if status != FINITE:
            raise IntegrationError(
                f"Expected the integration to stay finite, got NaN or inf at step {status} "
                f"(t = {status * step:.6g} s) with dt = {step:.3g} s: reduce dt."
            )
        done += count
        if progress is not None:
            progress(done, n_steps)


#: Samples per call of the adaptive kernel between progress reports.
ADAPTIVE_CHUNK = 4096


def _user_hook(model: TorqueModel, axes: Array, principal_axes: Rotation) -> Any:
    """The kernels' context for a model with a user function, else None."""
    if model.function is None:
        return None
    from tumble.core.rigid import compile_user_torque

    callback = _CALLBACKS.get(model.function)
    if callback is None:
        callback = _CALLBACKS[model.function] = compile_user_torque(model.function)
    return (
        np.ascontiguousarray(axes),
        np.asarray(principal_axes.as_quat(scalar_first=True), dtype=float),
        np.array(model.function_params, dtype=float),  # writable copy
        np.zeros(3),
        np.zeros(4),
        np.zeros(3),
        callback,
    )


#: One C callback per user function, compiled on first use.
_CALLBACKS: dict[Any, Any] = {}


def _fixed_steps(
    method: str,
    moments: Array,
    params: Array,
    hook: Any,
    w: Array,
    q: Array,
    step: float,
    count: int,
    done: int,
    record_every: int,
    out_w: Array,
    out_q: Array,
) -> int:
    """Run ``count`` steps of a fixed-step method; the kernel's status."""
    from tumble.core import splitting

    args = (w, q, moments, params, step, count, done, record_every, out_w, out_q)
    if method == "rk4":
        if hook is None:
            return int(rk4_run(*args))
        return int(rk4_run_hooked(*args, hook))
    order = 4 if method == "splitting" else 2
    if hook is None:
        return int(splitting.splitting_run(*args, order))
    return int(splitting.splitting_run_hooked(*args, order, hook))


def _adaptive(
    moments: Array,
    params: Array,
    hook: Any,
    w: Array,
    q: Array,
    times: Array,
    rtol: float,
    atol: float,
    progress: Callable[[int, int], object] | None,
) -> tuple[Array, Array, int]:
    """The adaptive method sampled at ``times`` (times[0] = 0): (ω, q, steps)."""
    from tumble.core import adaptive

    out_w = np.empty((times.size, 3))
    out_q = np.empty((times.size, 4))
    out_w[0], out_q[0] = w, q
    control = np.array([0.0, rtol, atol, 0.0, 0.0, 0.0])
    total = times.size - 1
    for first in range(1, times.size, ADAPTIVE_CHUNK):
        last = min(first + ADAPTIVE_CHUNK, times.size)
        samples = times[first:last]
        args = (w, q, moments, params, times[first - 1], times[last - 1], control, samples,
                out_w[first:last], out_q[first:last])  # fmt: skip
        if hook is None:
            status = adaptive.adaptive_run(*args)
        else:
            status = adaptive.adaptive_run_hooked(*args, hook)
        if status != FINITE:
            raise IntegrationError(
                "Expected the integration to stay finite, got a step size below round-off at "
                f"t = {control[adaptive.FAILED_AT]:.6g} s (the state became NaN or infinite, "
                "or the torque is singular there)."
            )
        if progress is not None:
            progress(last - 1, total)
    return out_w, out_q, int(control[adaptive.ACCEPTED])


def exact_solution(
    mp: MassProperties, omega0: Array, attitude0: Array, times: Array
) -> tuple[Array, Array]:
    """Exact torque-free (ω in body axes, q body → space) of ``mp`` at ``times``
    from ω0 (body axes, rad/s) and the unit quaternion ``attitude0``."""
    moments, axes = principal_decomposition(mp.inertia)
    if moments[0] <= 1e-12 * moments[2]:
        raise InputError(
            f"Expected a body with no zero principal moment, got moments {moments.tolist()} kg·m²."
        )
    principal_axes = Rotation.from_matrix(axes)
    w, q = _exact_principal(moments, axes.T @ omega0, _compose(attitude0, principal_axes), times)
    return w @ axes.T, _compose(q, principal_axes.inv())


def _exact_principal(moments: Array, w0: Array, q0: Array, times: Array) -> tuple[Array, Array]:
    """Exact torque-free ω (principal frame) and attitude (principal → space) at ``times``.

    ω from Jacobi elliptic functions (:func:`tumble.core.freebody.free_omega`).
    The attitude is written with z-x-z Euler angles about the fixed L
    (Landau & Lifshitz §37): with L along the Z axis of a space frame R_L,
    ``A = R_L Rz(φ) Rx(θ) Rz(ψ)``, where ``cos θ = L3/L`` and ``tan ψ = L1/L2``
    follow from ω, and φ is the integral of
    ``φ̇ = L (I1 ω1² + I2 ω2²)/(I1² ω1² + I2² ω2²)``
    (:func:`tumble.core.freebody.free_precession_angle`).
    """
    from tumble.core.freebody import free_attitude

    start = Rotation.from_quat(q0, scalar_first=True)
    on_axis = np.count_nonzero(w0 == 0.0) >= 2 or moments[0] == moments[2]
    if on_axis:
        # Steady rotation about a principal axis, or any rotation of a sphere.
        attitude = start * Rotation.from_rotvec(np.outer(times, w0))
        return np.tile(w0, (times.size, 1)), attitude.as_quat(scalar_first=True)
    l0 = moments * w0
    initial = Rotation.from_euler(
        "ZXZ", [0.0, np.arctan2(np.hypot(l0[0], l0[1]), l0[2]), np.arctan2(l0[0], l0[1])]
    )
    frame = (start * initial.inv()).as_quat(scalar_first=True)  # R_L: its z axis along L
    w, q = free_attitude(moments, w0, np.asarray(frame, dtype=float), times)
    return w, q


def _fastest_rate(
    moments: Array, w: Array, weight: float, lever: Array, pivot: Any, exact_spin: bool = False
) -> float:
    """An upper estimate of the fastest angular rate a step must resolve, rad/s.

    Torque-free, |ω| never exceeds |L| / I1. A heavy top adds the pendulum rate
    √(m g l / I1) and nutation at up to about I3 ω / I1. With ``exact_spin``
    (the splitting methods), a symmetric body's free motion is exact, so its
    spin about the symmetry axis needs no resolving: the rate is |L| / I⊥, that
    of the precession of the axis about L (and of nutation).
    """
    momentum = float(np.linalg.norm(moments * w))
    rate = momentum / moments[0]
    if exact_spin:
        close = 1e-12 * moments[2]
        if abs(moments[1] - moments[0]) <= close:  # oblate: symmetry axis 3
            rate = momentum / moments[0]
        elif abs(moments[2] - moments[1]) <= close:  # prolate: symmetry axis 1
            rate = momentum / moments[1]
    if pivot is not None:
        rate += math.sqrt(weight * float(np.linalg.norm(lever)) / moments[0])
    return rate


# ---------------------------------------------------------------- trajectory
@dataclass(frozen=True, eq=False)
class Trajectory:
    """A simulated rotation, sampled at times ``t``.

    Attributes
    ----------
    t : (n,) s.
    omega : (n, 3) angular velocity in body coordinates, rad/s.
    quaternion : (n, 4) unit quaternions ``[w, x, y, z]``, body → space.
    mass_properties : the body.
    pivot : None (free body) or the fixed body point, m.
    gravity : (3,) gravitational acceleration in space coordinates, m/s².
    method : the integrator that ran; ``reason``: why it was chosen.
    dt : the integration step used (fixed-step methods) or the sampling
        interval (exact, adaptive), s.
    steps : integration steps taken (accepted steps for the adaptive method;
        0 for the exact solution).
    """

    t: Array
    omega: Array
    quaternion: Array
    mass_properties: MassProperties
    pivot: Array | None
    gravity: Array
    method: str
    reason: str
    dt: float
    steps: int = 0

    @cached_property
    def rotation(self) -> Any:
        """The attitudes as one scipy ``Rotation`` (n rotations), body → space."""
        return Rotation.from_quat(self.quaternion, scalar_first=True)

    @cached_property
    def _matrices(self) -> Array:
        return np.asarray(self.rotation.as_matrix())

    @cached_property
    def _inertia(self) -> Array:
        mp = self.mass_properties
        return mp.inertia if self.pivot is None else mp.inertia_about(self.pivot)

    @cached_property
    def omega_space(self) -> Array:
        """(n, 3) angular velocity in space coordinates, rad/s."""
        return np.einsum("nij,nj->ni", self._matrices, self.omega)

    @cached_property
    def angular_momentum(self) -> Array:
        """(n, 3) angular momentum in space coordinates, kg·m²/s, about the centre
        of mass (free body) or about the pivot."""
        return np.einsum("nij,nj->ni", self._matrices, self.omega @ self._inertia.T)

    @cached_property
    def energy(self) -> Array:
        """(n,) total energy, J: rotational kinetic energy (about the centre of mass,
        or about the pivot), plus the potential energy of gravity about the pivot."""
        kinetic = 0.5 * np.einsum("ni,ij,nj->n", self.omega, self._inertia, self.omega)
        if self.pivot is None:
            return kinetic
        lever = self.mass_properties.center_of_mass - self.pivot
        height = np.einsum("nij,j->ni", self._matrices, lever)  # COM position from the pivot
        return kinetic - self.mass_properties.mass * (height @ self.gravity)

    @cached_property
    def drift(self) -> dict[str, float]:
        """Largest relative change from the initial value over the trajectory of the
        energy, of |L| and of the space-frame vector L (both conserved when
        torque-free; energy also under gravity about a pivot)."""
        energy = self.energy
        scale = max(abs(energy[0]), float(np.max(np.abs(energy))), np.finfo(float).tiny)
        momentum = self.angular_momentum
        size = max(float(np.linalg.norm(momentum[0])), np.finfo(float).tiny)
        norms = np.linalg.norm(momentum, axis=1)
        return {
            "energy": float(np.max(np.abs(energy - energy[0])) / scale),
            "angular_momentum_norm": float(np.max(np.abs(norms - norms[0])) / size),
            "angular_momentum_vector": float(
                np.max(np.linalg.norm(momentum - momentum[0], axis=1)) / size
            ),
        }

    def __repr__(self) -> str:
        drift = self.drift
        kind = "free body" if self.pivot is None else f"pivot at {self.pivot.tolist()} m"
        return (
            f"Trajectory({len(self.t)} samples over {self.t[-1]:.6g} s, {kind}, "
            f"method {self.method} (dt = {self.dt:.3g} s, {self.steps} steps; {self.reason}); "
            "relative drift: "
            f"energy {drift['energy']:.2e}, |L| {drift['angular_momentum_norm']:.2e}, "
            f"L vector {drift['angular_momentum_vector']:.2e})"
        )

    # ------------------------------------------------------------- Parquet
    def to_parquet(self, path: str | os.PathLike[str]) -> None:
        """Write the samples and the run's description to a Parquet file.

        Columns ``t, omega_x, omega_y, omega_z, q_w, q_x, q_y, q_z`` (SI, body
        axes, scalar-first body → space); the body, pivot, gravity, method and
        step go in the file's metadata. Written to a temporary name and renamed,
        so the file is never half-written.
        """
        import pyarrow as pa
        import pyarrow.parquet as pq

        from tumble import __version__

        columns = {"t": self.t}
        for k, axis in enumerate("xyz"):
            columns[f"omega_{axis}"] = self.omega[:, k]
        for k, part in enumerate("wxyz"):
            columns[f"q_{part}"] = self.quaternion[:, k]
        mp = self.mass_properties
        meta = {
            "tumble_version": __version__,
            "mass": mp.mass,
            "center_of_mass": mp.center_of_mass.tolist(),
            "inertia": mp.inertia.tolist(),
            "pivot": None if self.pivot is None else self.pivot.tolist(),
            "gravity": self.gravity.tolist(),
            "method": self.method,
            "reason": self.reason,
            "dt": self.dt,
            "steps": self.steps,
            "units": "SI: s, rad/s, kg, m, kg*m^2; quaternion [w, x, y, z] body -> space",
        }
        table = pa.table(columns).replace_schema_metadata({"tumble": json.dumps(meta)})
        target = Path(path)
        temporary = target.with_name(f".{target.name}.partial")
        pq.write_table(table, temporary)
        os.replace(temporary, target)

    @classmethod
    def read_parquet(cls, path: str | os.PathLike[str]) -> Trajectory:
        """Read a file written by :meth:`to_parquet`."""
        import pyarrow.parquet as pq

        try:
            table = pq.read_table(path)
        except (OSError, ValueError) as exc:
            raise InputError(
                f"Expected a Parquet file written by tumble, got {str(path)!r}: {exc}"
            ) from None
        raw = (table.schema.metadata or {}).get(b"tumble")
        if raw is None:
            raise InputError(
                f"Expected a Parquet file written by tumble, got {str(path)!r} "
                "(no tumble metadata)."
            )
        meta = json.loads(raw)
        data = {name: table.column(name).to_numpy() for name in table.column_names}
        return cls(
            t=data["t"],
            omega=np.column_stack([data[f"omega_{a}"] for a in "xyz"]),
            quaternion=np.column_stack([data[f"q_{p}"] for p in "wxyz"]),
            mass_properties=MassProperties(meta["mass"], meta["center_of_mass"], meta["inertia"]),
            pivot=None if meta["pivot"] is None else np.asarray(meta["pivot"], dtype=float),
            gravity=np.asarray(meta["gravity"], dtype=float),
            method=meta["method"],
            reason=meta["reason"],
            dt=float(meta["dt"]),
            steps=int(meta.get("steps", 0)),
        )

    # ------------------------------------------------------------ notebooks
    def _repr_html_(self) -> str:
        from tumble.report.html import trajectory_html

        return trajectory_html(self)

    def plot(self) -> dict[str, Any]:
        """Matplotlib figures by name: ``omega`` (ω(t), body axes), ``angular_momentum``
        (L(t), space axes), ``drift`` (energy and |L|) and ``polhode`` (L in principal
        axes on the energy ellipsoid). See :mod:`tumble.report.plots`."""
        from tumble.report import figures

        return figures(self)

    def view(self, frames: int = 300) -> Any:
        """The interactive 3D viewer (the body as an ellipsoid of equal inertia, its
        principal axes, ω and L, play / pause and a time slider): shown inline in a
        notebook, ``.save(path)`` writes a self-contained HTML file."""
        from tumble.report import view

        return view(self, frames=frames)


# -------------------------------------------------------------------- batches
@dataclass(frozen=True, eq=False)
class BatchResult:
    """Final states of a batch of bodies (and every k-th state if asked).

    Attributes
    ----------
    omega : (N, 3) final angular velocities in each body's axes, rad/s.
    quaternion : (N, 4) final attitudes ``[w, x, y, z]``, body → space.
    t : (n,) times of the recorded states, s (only the final time when no
        history was asked for).
    omega_history, quaternion_history : (n, N, 3) and (n, N, 4), or None.
    dt : the integration step used, s; ``method``: the integrator.
    """

    omega: Array
    quaternion: Array
    t: Array
    omega_history: Array | None
    quaternion_history: Array | None
    dt: float
    method: str


def simulate_batch(
    inertia: Any,
    omega0: Any,
    *,
    attitude0: Any = None,
    duration: Any,
    dt: Any,
    method: str = "rk4",
    torque: TorqueModel | None = None,
    record_every: int | None = None,
) -> BatchResult:
    """Simulate N free bodies at once, in parallel.

    Parameters
    ----------
    inertia : (N, 3) principal moments (the body axes are principal axes) or
        (N, 3, 3) inertia tensors about the centres of mass, kg·m².
    omega0 : (N, 3) initial angular velocities in body coordinates, rad/s.
    attitude0 : None (identity) or (N, 4) quaternions ``[w, x, y, z]``, body → space.
    duration, dt : s, > 0; dt is shortened slightly so whole steps span duration.
    method : ``"rk4"`` (vectorised across bodies: the fastest per step),
        ``"splitting"`` or ``"strang"`` (as in :func:`simulate`).
    torque : a torque model from :mod:`tumble.torques`: constant body and space
        torques and linear damping, each either one value for all bodies or one
        per body (``ConstantBodyTorque(array (N, 3))``, ``LinearDamping(array
        (N,))``). Gravity needs a pivot and is refused here; so are user
        functions (use :func:`simulate`).
    record_every : None to keep only the final states (memory stays O(N)), or k
        to also keep every k-th state.

    Returns
    -------
    BatchResult — the same states as N separate :func:`simulate` calls with
    the same method and ``dt``, to round-off.
    """
    if method not in BATCH_METHODS:
        raise InputError(
            f"Expected `method` to be one of {', '.join(BATCH_METHODS)}, got {method!r}."
        )
    moments_in = vector_to_si(
        inertia, "inertia", "inertia", (-1, 3) if np.ndim(inertia) == 2 else (-1, 3, 3)
    )
    n = moments_in.shape[0]
    omega = vector_to_si(omega0, "angular_velocity", "omega0", (n, 3))
    if attitude0 is None:
        q0 = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    else:
        q0 = vector_to_si(attitude0, "dimensionless", "attitude0", (n, 4))
        norms = np.linalg.norm(q0, axis=1)
        if np.any(norms < 1e-12):
            k = int(np.argmin(norms))
            raise InputError(
                f"Expected `attitude0` to hold non-zero quaternions, got attitude0[{k}] = "
                f"{q0[k].tolist()}."
            )
        q0 = q0 / norms[:, None]
    if moments_in.ndim == 2:
        moments, axes = moments_in, None
    else:
        tensors = 0.5 * (moments_in + np.swapaxes(moments_in, 1, 2))
        moments, axes = np.linalg.eigh(tensors)
        flip = np.linalg.det(axes) < 0
        axes[flip, :, 2] *= -1  # proper rotations
    low = np.min(moments, axis=1)
    high = np.max(moments, axis=1)
    bad = np.flatnonzero(~(low > 1e-12 * high))
    if bad.size:
        k = int(bad[0])
        raise InputError(
            f"Expected every body to have positive principal moments, got body {k} with "
            f"{moments[k].tolist()} kg·m²."
        )
    ordered = np.sort(moments, axis=1)
    broken = np.flatnonzero(ordered[:, 0] + ordered[:, 1] < ordered[:, 2] * (1 - 1e-9))
    if broken.size:
        k = int(broken[0])
        raise InputError(
            f"Expected principal moments satisfying I1 + I2 >= I3, got body {k} with "
            f"{moments[k].tolist()} kg·m²."
        )
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    step = to_si(dt, "time", "dt")
    if step <= 0:
        raise InputError(f"Expected `dt` > 0 s, got {step!r}.")
    model = (
        torque if torque is not None else TorqueModel(np.zeros(3), np.zeros(3), np.zeros(3), 0.0)
    )
    if not isinstance(model, TorqueModel):
        raise InputError(
            f"Expected `torque` to be a model from tumble.torques, got {type(torque).__name__}."
        )
    if np.any(model.gravity):
        raise InputError(
            "Expected `torque` without gravity: a free body feels no torque from gravity, and "
            "batches have no pivot (use simulate for a top on a pivot)."
        )
    if model.function is not None:
        raise InputError(
            "Expected `torque` without a UserTorque in a batch, got "
            f"{model!r} (use simulate for user torque functions)."
        )
    for name, value, shape in (
        ("ConstantBodyTorque", model.body, (n, 3)),
        ("ConstantSpaceTorque", model.space, (n, 3)),
        ("LinearDamping", model.damping, (n,)),
    ):
        if np.ndim(value) == len(shape) and np.shape(value) != shape:
            raise InputError(
                f"Expected per-body {name} values of shape {shape} for {n} bodies, got "
                f"{np.shape(value)}."
            )
    if record_every is not None and (isinstance(record_every, bool) or record_every < 1):
        raise InputError(
            f"Expected `record_every` to be None or an integer >= 1, got {record_every!r}."
        )
    n_steps = max(1, math.ceil(total_time / step * (1 - 1e-12)))
    step = total_time / n_steps

    # Principal frame: ω_p = Rᵀ ω, q_p = q ⊗ q(R); a body torque turns with each
    # body's principal axes, so with tensors it becomes one value per body.
    if axes is None:
        w = np.ascontiguousarray(omega.T)
        principal_axes = None
        q = np.ascontiguousarray(q0.T)
    else:
        w = np.ascontiguousarray(np.einsum("nji,nj->in", axes, omega))
        principal_axes = Rotation.from_matrix(axes)
        q = np.ascontiguousarray(_compose(q0, principal_axes).T)
    body_torque = np.asarray(model.body, dtype=float)
    if axes is not None and np.any(body_torque):
        body_torque = np.einsum("nji,nj->ni", axes, np.broadcast_to(body_torque, (n, 3)))
    per_body = body_torque.ndim == 2 or model.per_body
    params = np.zeros((N_TORQUE_PARAMS, n if per_body else 1))
    params[0:3] = np.broadcast_to(body_torque, (params.shape[1], 3)).T
    params[3:6] = np.broadcast_to(model.space, (params.shape[1], 3)).T
    params[12] = model.damping
    inertia_soa = np.ascontiguousarray(moments.T)
    status = np.full(n, FINITE, dtype=np.int64)

    chunk = n_steps if record_every is None else record_every
    history_w, history_q, times = [], [], [0.0]
    if record_every is not None:
        history_w.append(w.T.copy())
        history_q.append(q.T.copy())
    done = 0
    while done < n_steps:
        count = min(chunk, n_steps - done)
        if method == "rk4":
            rk4_batch(w, q, inertia_soa, params, step, count)
        else:
            splitting_batch(
                w, q, inertia_soa, params, step, count, 4 if method == "splitting" else 2, status
            )
            if np.any(status != FINITE):
                break
        done += count
        times.append(done * step)
        if record_every is not None:
            history_w.append(w.T.copy())
            history_q.append(q.T.copy())
    diverged = ~(np.isfinite(w).all(axis=0) & np.isfinite(q).all(axis=0)) | (status != FINITE)
    if np.any(diverged):
        k = int(np.flatnonzero(diverged)[0])
        raise IntegrationError(
            f"Expected the integration to stay finite, got NaN or inf for "
            f"{int(diverged.sum())} bodies (first: body {k}) with dt = {step:.3g} s: reduce dt."
        )

    def to_body(ws: Array, qs: Array) -> tuple[Array, Array]:
        if axes is None or principal_axes is None:
            return ws, qs
        return np.einsum("nij,nj->ni", axes, ws), _compose(qs, principal_axes.inv())

    final_w, final_q = to_body(w.T.copy(), q.T.copy())
    if record_every is None:
        return BatchResult(final_w, final_q, np.array([total_time]), None, None, step, method)
    pairs = [to_body(a, b) for a, b in zip(history_w, history_q, strict=True)]
    return BatchResult(
        final_w,
        final_q,
        np.asarray(times),
        np.stack([p[0] for p in pairs]),
        np.stack([p[1] for p in pairs]),
        step,
        method,
    )
