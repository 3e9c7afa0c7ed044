"""A rigid rotor on elastic bearings run up through its critical speeds.

The rotor of :class:`tumble.theory.RigidRotor` spins at Ω(t) = Ω₀ + Ω̇ t, its
angle φ(t) = Ω₀ t + Ω̇ t² / 2, and an unbalance U (kg·m) in the plane at axial
arm a_u from the centre of mass turns with it. The unbalance's mass, carried
round at φ, pushes on the rotor with U (φ̇² cos φ + φ̈ sin φ, φ̇² sin φ − φ̈ cos φ)
and the moment of that force about the centre of mass. With the spin speeding
up, the angular momentum I_p Ω along the tilted axis (β, −α, 1) changes also
through Ω̇: its rate adds I_p Ω̇ (β, −α) to the gyroscopic I_p Ω (β̇, −α̇), so

    M q̈ + (C + Ω G) q̇ + (K + Ω̇ G) q = f(t)

for q = (x, y, α, β). This takes the drive's torque I_p Ω̇ about the bearings'
fixed axis (a motor on the frame, no moment across the axis). A drive whose
torque turns with the tilted axis (a flexible coupling) supplies I_p Ω̇ (β, −α)
itself and takes the Ω̇ G term away; with the spin angle the last of the
Euler angles Rx(α) Ry(β) Rz(φ) and the drive an ideal constraint on it
(Lagrange's equations), only its part in the α equation remains. The three
differ by I_p Ω̇ / K_θ of the tilt (below 1e-4 for the rotors of the tests and
the built-in scenario), far below the run-up's own lag of the peak (Friswell,
Penny, Garvey & Lees, *Dynamics of Rotating Machines*, 2010, §3.6, on run-up
through a critical speed). At a constant speed the orbits settle on the
steady unbalance response of :meth:`RigidRotor.unbalance_orbits`; through a
critical speed at a finite rate the peak comes later and lower than the
steady one. The equations are stepped by the compiled RK4 of
:mod:`tumble.core.whirl` (a Python right-hand side under scipy's integrators
costs seconds per second of a fast rotor's run).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.core import whirl
from tumble.errors import InputError, RequestTooLargeError
from tumble.integrators.problem import Schedule
from tumble.integrators.steps import step_in_chunks
from tumble.kinematics import same_hemisphere
from tumble.massprops import readonly
from tumble.resources import DEFAULT_MAX_STEPS
from tumble.simulation import most_steps
from tumble.theory import RigidRotor
from tumble.trajectory import Trajectory
from tumble.units import to_si

__all__ = ["RunUp", "run_up"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class RunUp:
    """A run-up in time (see :func:`run_up`). SI units.

    Attributes
    ----------
    t : (n,) sample times, s.
    speed : (n,) spin speed Ω(t), rad/s.
    state : (n, 4) the rotor's (x, y, α, β): centre of mass (m) and tilts (rad),
        along and about the rotor's e_x, e_y (the ``frame`` of the RigidRotor).
    orbits : (n, n_bearings, 2) the shaft's displacement at each bearing, m.
    trajectory : the rotor's attitude and body rates as a
        :class:`~tumble.Trajectory` (its spin and tilts; its centre's motion is
        ``state``): the motor does work, so nothing is conserved.
    """

    t: Array
    speed: Array
    state: Array
    orbits: Array
    trajectory: Trajectory

    @property
    def amplitude(self) -> Array:
        """(n, n_bearings) the distance of the shaft from its centre at each bearing, m."""
        return np.linalg.norm(self.orbits, axis=2)


def run_up(
    rotor: Any,
    unbalance: Any,
    *,
    duration: Any,
    speed: Any = 0.0,
    acceleration: Any = 0.0,
    position: Any = 0.0,
    dt: Any = None,
    samples: int = 2001,
    progress: Callable[[int, int], object] | None = None,
    max_steps: int | None = DEFAULT_MAX_STEPS,
) -> RunUp:
    """Run a rigid rotor on elastic bearings up (or at a constant speed) with an unbalance.

    Parameters
    ----------
    rotor : the :class:`~tumble.theory.RigidRotor`, at rest at its centre at t = 0.
    unbalance : U, kg·m (the unbalance mass times its distance from the axis),
        on the rotor's e_x at t = 0.
    duration : s.
    speed : Ω₀, the spin speed at t = 0, rad/s.
    acceleration : Ω̇, rad/s², constant (0: a constant speed).
    position : the unbalance's axial position from the rotor's ``point``, m.
    dt : the RK4 step, s; by default 1/200 of a period of the fastest motion
        (the fastest mode or the spin, at either end of the run).
    samples : about how many evenly spaced samples to keep (≥ 2), the last at
        ``duration``.
    progress : called as ``progress(steps_done, steps_total)`` as the run goes.
    max_steps : the most RK4 steps the run may take (default 5e7,
        :data:`tumble.resources.DEFAULT_MAX_STEPS`, as :func:`tumble.simulate`;
        None: up to 2^53): a longer run is refused before it starts.

    Returns
    -------
    RunUp.

    Raises
    ------
    InputError
        A rotor that is not a RigidRotor, a duration ≤ 0, fewer than 2
        samples, a ``max_steps`` that is not an integer >= 1 or None, or a spin
        that would change sign (or overflow) during the run.
    RequestTooLargeError
        A run of more than ``max_steps`` steps (duration / dt).

    Examples
    --------
    At a constant speed with damped bearings the orbit settles on the steady
    unbalance response:

    >>> import tumble as tb
    >>> from tumble.models import run_up
    >>> rod = tb.shapes.solid_cylinder(10.0, 0.05, 0.6)
    >>> bearings = [tb.theory.Bearing(-0.2, 1e6, 500.0), tb.theory.Bearing(0.2, 1e6, 500.0)]
    >>> rotor = tb.theory.RigidRotor(rod, bearings)
    >>> run = run_up(rotor, 1e-4, duration=2.0, speed=300.0, samples=11)
    >>> steady = rotor.unbalance_response(300.0, 1e-4)[0]
    >>> print(abs(run.amplitude[-1] / steady - 1).max() < 1e-6)
    True
    """
    if not isinstance(rotor, RigidRotor):
        raise InputError(
            f"Expected `rotor` to be a tumble.theory.RigidRotor, got {type(rotor).__name__}."
        )
    # The rotor's matrices (M, K, C, G) and bearing arms, as the theory gives them.
    matrices = rotor.mass_matrix, rotor.stiffness, rotor.damping, rotor.gyroscopic
    centre, arms, frame = rotor.centre, rotor.arms, rotor.frame
    u = to_si(unbalance, "unbalance", "unbalance")
    span = to_si(duration, "time", "duration")
    start = to_si(speed, "angular_velocity", "speed")
    rate = to_si(acceleration, "angular_acceleration", "acceleration")
    arm = to_si(position, "length", "position") - centre
    if not span > 0:
        raise InputError(f"Expected `duration` > 0 s, got {span!r}.")
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InputError(f"Expected `samples` to be an integer >= 2, got {samples!r}.")
    most = most_steps(max_steps)
    end = start + rate * span
    if not math.isfinite(end):
        raise InputError(
            f"Expected the spin at the end of the run to be finite, got {start!r} rad/s + "
            f"{rate!r} rad/s² × {span!r} s = {end!r} rad/s."
        )
    if start * end < 0:
        raise InputError(
            f"Expected the spin not to reverse during the run, got {start!r} rad/s at the start "
            f"and {end!r} rad/s at the end."
        )
    # The fastest motion: the largest |λ| of the modes at either end, or the spin.
    fastest = max(
        float(np.abs(np.linalg.eigvals(rotor.state_matrices([start, end]))).max()),
        abs(start),
        abs(end),
    )
    schedule = Schedule.sampled(
        span, dt, fastest, "the fastest mode of the rotor", 1, samples - 1, 8
    )
    if schedule.n_steps > most:
        raise RequestTooLargeError(
            f"Expected at most max_steps = {most:.6g} steps, got duration / dt = {span:.6g} s / "
            f"{schedule.step:.3g} s = {schedule.n_steps:.3g} steps: use a larger dt or a shorter "
            "duration, or raise `max_steps=`."
        )
    inverse = np.linalg.inv(matrices[0])
    stacked = np.stack([inverse] + [inverse @ matrix for matrix in matrices[1:]])
    params = np.array([start, rate, u, arm])
    out = np.empty((len(schedule.times), 8))
    out[0] = y = np.zeros(8)
    n_steps, step, every = schedule.n_steps, schedule.step, schedule.record_every
    step_in_chunks(
        lambda done, count: whirl.rk4_run(y, step, count, done, every, out, (stacked, params)),
        n_steps,
        step,
        progress,
    )
    if n_steps % every != 0:
        out[-1] = y
    times = schedule.times
    state = out[:, :4]
    orbits = np.stack(
        [state[:, [0]] + arms * state[:, [3]], state[:, [1]] - arms * state[:, [2]]], axis=2
    )
    spin = start + rate * times
    quaternion, omega = _attitude(frame, (start + 0.5 * rate * times) * times, spin, out)
    trajectory = Trajectory(
        t=times,
        omega=omega,
        quaternion=quaternion,
        mass_properties=rotor.body,
        pivot=None,
        method="rk4",
        reason="rotor run-up model",
        dt=step,
        steps=n_steps,
        conserved=(),
    )
    return RunUp(readonly(times), readonly(spin), readonly(state), readonly(orbits), trajectory)


def _attitude(frame: Array, angle: Array, spin: Array, out: Array) -> tuple[Array, Array]:
    """The rotor's attitude (n, 4) and body rates (n, 3): the tilts (α about e_x, β
    about e_y, small) of the spin φ about the axis, in the rotor's frame; to first
    order in the tilts, ω = α̇ e_x + β̇ e_y + φ̇ (the tilted axis)."""
    zero = np.zeros(len(angle))
    tilt = Rotation.from_rotvec(np.column_stack([out[:, 2], out[:, 3], zero]))
    spun = tilt * Rotation.from_rotvec(np.outer(np.remainder(angle, 2 * math.pi), [0, 0, 1]))
    to_body = Rotation.from_matrix(frame)
    attitude = to_body * spun * to_body.inv()
    rates = np.column_stack([out[:, 6], out[:, 7], zero]) + spin[:, None] * tilt.apply([0, 0, 1])
    omega = attitude.inv().apply(rates @ frame.T)
    return same_hemisphere(attitude.as_quat(scalar_first=True)), np.asarray(omega)
