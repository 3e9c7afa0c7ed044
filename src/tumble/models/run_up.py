"""A rigid rotor on elastic bearings run up through its critical speeds.

The rotor of :class:`tumble.theory.RigidRotor` spins at Ω(t) = Ω₀ + Ω̇ t, its
angle φ(t) = Ω₀ t + Ω̇ t² / 2, and an unbalance U (kg·m) in the plane at axial
arm a_u from the centre of mass turns with it. The unbalance's mass, carried
round at φ, pushes on the rotor with U (φ̇² cos φ + φ̈ sin φ, φ̇² sin φ − φ̈ cos φ)
and the moment of that force about the centre of mass. With the spin speeding
up, the angular momentum I_p Ω along the tilted axis (β, −α, 1) changes also
through Ω̇: its rate adds I_p Ω̇ (β, −α) to the gyroscopic I_p Ω (β̇, −α̇), so

    M q̈ + (C + Ω G) q̇ + (K + Ω̇ G) q = f(t)

for q = (x, y, α, β) (Friswell, Penny, Garvey & Lees, *Dynamics of Rotating
Machines*, 2010, §3.6 on run-up). At a constant speed the orbits settle on the
steady unbalance response of :meth:`RigidRotor.unbalance_orbits`; through a
critical speed at a finite rate the peak comes later and lower than the
steady one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
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
    state : (n, 4) the rotor's (x, y, α, β): centre of mass (m) and tilts (rad).
    orbits : (n, n_bearings, 2) the shaft's displacement at each bearing, m.
    """

    t: Array
    speed: Array
    state: Array
    orbits: Array

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
    samples: int = 2001,
) -> RunUp:
    """Run a rigid rotor on elastic bearings up (or at a constant speed) with an unbalance.

    Parameters
    ----------
    rotor : the :class:`~tumble.theory.RigidRotor`, at rest at its centre at t = 0.
    unbalance : U, kg·m (the unbalance mass times its distance from the axis).
    duration : s.
    speed : Ω₀, the spin speed at t = 0, rad/s.
    acceleration : Ω̇, rad/s², constant (0: a constant speed).
    position : the unbalance's axial position from the rotor's ``point``, m.
    samples : how many evenly spaced samples to return (≥ 2).

    Returns
    -------
    RunUp. Integrated by scipy's DOP853 at a relative tolerance of 1e-10.

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
    from scipy.integrate import solve_ivp

    try:  # the rotor's matrices (M, K, C, G) and bearing arms, as the theory gives them
        matrices = rotor.mass_matrix, rotor.stiffness, rotor.damping, rotor.gyroscopic
        centre, arms = rotor.centre, rotor.arms
    except AttributeError:
        raise InputError(
            f"Expected `rotor` to be a tumble.theory.RigidRotor, got {type(rotor).__name__}."
        ) from None
    u = to_si(unbalance, "unbalance", "unbalance")
    span = to_si(duration, "time", "duration")
    start = to_si(speed, "angular_velocity", "speed")
    rate = to_si(acceleration, "angular_acceleration", "acceleration")
    arm = to_si(position, "length", "position") - centre
    if not span > 0:
        raise InputError(f"Expected `duration` > 0 s, got {span!r}.")
    if not (isinstance(samples, int) and samples >= 2):
        raise InputError(f"Expected `samples` to be an integer >= 2, got {samples!r}.")
    inverse = np.linalg.inv(matrices[0])
    stiffness, damping, gyroscopic = matrices[1:]

    def rates(t: float, y: Array) -> Array:
        spin = start + rate * t
        angle = start * t + 0.5 * rate * t * t
        c, s = np.cos(angle), np.sin(angle)
        fx = u * (spin * spin * c + rate * s)
        fy = u * (spin * spin * s - rate * c)
        force = np.array([fx, fy, -arm * fy, arm * fx])
        q, v = y[:4], y[4:]
        accel = inverse @ (
            force - (damping + spin * gyroscopic) @ v - (stiffness + rate * gyroscopic) @ q
        )
        return np.concatenate([v, accel])

    times = np.linspace(0.0, span, samples)
    solution = solve_ivp(rates, (0.0, span), np.zeros(8), method="DOP853", t_eval=times,
                         rtol=1e-10, atol=1e-16)  # fmt: skip
    if not solution.success:
        raise InputError(f"Expected the run-up to integrate, got: {solution.message}")
    state = solution.y[:4].T
    orbits = np.stack(
        [state[:, [0]] + arms * state[:, [3]], state[:, [1]] - arms * state[:, [2]]], axis=2
    )
    return RunUp(times, start + rate * times, state, orbits)
