"""The scenarios of the conformance suite: bodies whose exact motion tumble knows.

A :class:`Scenario` is a body (mass, inertia, optionally a pivot under gravity)
and an initial state. Its reference, :meth:`Scenario.reference`, is the
closed-form motion — :func:`tumble.theory.free_motion` (Jacobi's elliptic
functions, torque-free) or :func:`tumble.theory.gyroscope` (the heavy
Lagrange top) — evaluated at the sample times, never an integration.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from tumble.conformance.engine import Array, EngineBody
from tumble.errors import InputError, unknown_choice
from tumble.massprops import MassProperties
from tumble.theory import free_motion, gyroscope
from tumble.units import to_si, vector_to_si

__all__ = ["SCENARIOS", "Scenario", "get_scenario", "scenario_names"]

#: The body of the named torque-free scenarios: principal moments, kg·m².
MOMENTS_123 = (1.0, 2.0, 3.0)


@dataclass(frozen=True, eq=False)
class Scenario:
    """A body and an initial state whose exact motion is known. SI units.

    Parameters
    ----------
    inertia : (3,) principal moments or a (3, 3) inertia tensor about the centre of mass,
        body axes, kg·m² (pint quantities and strings accepted).
    omega0 : (3,) initial angular velocity in the same body axes, rad/s.
    duration : s, the horizon of a run unless :func:`tumble.conformance.run` is given one.
    attitude0 : initial attitude, a scalar-first quaternion body → space (identity if None).
    mass : kg.
    pivot : a body point held fixed in space (m, body axes, from the centre of mass), or
        None for a free body. With a pivot the body must be a symmetric top with the pivot
        on its symmetry axis, body z (the exact Lagrange top).
    gravity : the magnitude of gravity along space −z, m/s² (used with a pivot).
    name, description : how tables and reports name it.

    The engines are given the body in its principal axes (a diagonal inertia), and every
    measurement is made there: ω in principal axes, the attitude principal → space.
    """

    inertia: Any
    omega0: Any
    duration: Any = 20.0
    attitude0: Any = None
    mass: Any = 1.0
    pivot: Any = None
    gravity: Any = 0.0
    name: str = "custom"
    description: str = ""
    _principal: tuple[Array, Array] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        mass = to_si(self.mass, "mass", "mass")
        shape = (3,) if np.ndim(np.asarray(self.inertia, dtype=object)) <= 1 else (3, 3)
        tensor = vector_to_si(self.inertia, "inertia", "inertia", shape)
        tensor = np.diag(tensor) if shape == (3,) else tensor
        mp = MassProperties(mass, np.zeros(3), tensor)
        if np.count_nonzero(mp.inertia - np.diag(np.diag(mp.inertia))) == 0:
            # Already principal: keep the axes as given (a top's symmetry axis stays z).
            moments, axes = np.diag(mp.inertia).copy(), np.eye(3)
        else:
            moments, axes = mp.principal()
        omega0 = vector_to_si(self.omega0, "angular_velocity", "omega0")
        duration = to_si(self.duration, "time", "duration")
        if not (np.isfinite(duration) and duration > 0.0):
            raise InputError(f"Expected a duration > 0 s, got {self.duration!r}.")
        object.__setattr__(self, "mass", float(mass))
        object.__setattr__(self, "duration", duration)
        object.__setattr__(self, "omega0", omega0)
        object.__setattr__(self, "gravity", to_si(self.gravity, "acceleration", "gravity"))
        object.__setattr__(self, "_principal", (moments, axes))
        self._reference_motion()  # refuses a pivot without an exact motion now, not mid-run

    @property
    def moments(self) -> Array:
        """(3,) principal moments about the centre of mass, kg·m², in the engines' body axes."""
        return self._principal[0].copy()

    @property
    def body(self) -> EngineBody:
        """The body the engines build, in its principal axes."""
        moments, axes = self._principal
        pivot = None if self.pivot is None else axes.T @ self._pivot()
        gravity = np.array([0.0, 0.0, -self.gravity]) if pivot is not None else np.zeros(3)
        return EngineBody(self.mass, moments, pivot, gravity)

    @property
    def initial_state(self) -> tuple[Array, Array]:
        """The attitude (principal axes → space, scalar first) and ω (rad/s, principal axes)."""
        axes = self._principal[1]
        attitude = (
            Rotation.identity()
            if self.attitude0 is None
            else Rotation.from_quat(np.asarray(self.attitude0, dtype=float), scalar_first=True)
        )
        quaternion = (attitude * Rotation.from_matrix(axes)).as_quat(scalar_first=True)
        if quaternion[0] < 0.0:
            quaternion = -quaternion
        omega = axes.T @ np.asarray(self.omega0, dtype=float)
        return quaternion, omega

    @property
    def intermediate_axis(self) -> int:
        """The principal axis (0, 1, 2) of the middle moment: its ω component counts flips."""
        return int(np.argsort(self._principal[0], kind="stable")[1])

    def reference(self, times: Array) -> tuple[Array, Array]:
        """The exact ω (n, 3; rad/s, principal axes) and attitude (n, 4) at ``times`` (s)."""
        omega, quaternion = self._reference_motion().at(np.asarray(times, dtype=float))
        return np.asarray(omega), np.asarray(quaternion)

    def _pivot(self) -> Array:
        return vector_to_si(self.pivot, "length", "pivot")

    def _reference_motion(self) -> Any:
        body = self.body
        mp = MassProperties(body.mass, np.zeros(3), body.inertia)
        quaternion, omega = self.initial_state
        if body.pivot is None:
            return free_motion(mp, omega, quaternion)
        if not self.gravity > 0.0:
            raise InputError(f"Expected gravity > 0 m/s² with a pivot, got {self.gravity!r}.")
        return gyroscope(mp, body.pivot, gravity=self.gravity, omega0=omega, attitude0=quaternion)


def _named(name: str, description: str, **values: Any) -> Scenario:
    return Scenario(name=name, description=description, **values)


#: The built-in scenarios by name.
SCENARIOS: dict[str, Scenario] = {
    scenario.name: scenario
    for scenario in (
        _named(
            "intermediate-slow",
            "I = (1, 2, 3) kg·m², ω0 = (0.01, 2, 0.01) rad/s: a slow tumble about the "
            "intermediate axis, flipping",
            inertia=MOMENTS_123,
            omega0=(0.01, 2.0, 0.01),
        ),
        _named(
            "intermediate-fast",
            "I = (1, 2, 3) kg·m², ω0 = (0.1, 20, 0.1) rad/s: a fast tumble about the "
            "intermediate axis",
            inertia=MOMENTS_123,
            omega0=(0.1, 20.0, 0.1),
        ),
        _named(
            "major-spin",
            "I = (1, 2, 3) kg·m², ω0 = (0.1, 0, 20) rad/s: a stable spin about the major axis",
            inertia=MOMENTS_123,
            omega0=(0.1, 0.0, 20.0),
        ),
        _named(
            "minor-spin",
            "I = (1, 2, 3) kg·m², ω0 = (20, 0, 0.1) rad/s: a stable spin about the minor axis",
            inertia=MOMENTS_123,
            omega0=(20.0, 0.0, 0.1),
        ),
        _named(
            "symmetric-top",
            "I = (1, 1, 2) kg·m², ω0 = (2, 0, 10) rad/s: torque-free nutation and precession "
            "of a symmetric body",
            inertia=(1.0, 1.0, 2.0),
            omega0=(2.0, 0.0, 10.0),
        ),
        _named(
            "heavy-top",
            "the Lagrange top: 1 kg, I = (0.05, 0.05, 0.08) kg·m² about its centre of mass, "
            "pivot 0.1 m below it on the axis, tilted 0.3 rad, spinning at 30 rad/s, g = 9.81 m/s²",
            inertia=(0.05, 0.05, 0.08),
            omega0=(0.0, 0.0, 30.0),
            attitude0=Rotation.from_rotvec([0.3, 0.0, 0.0]).as_quat(scalar_first=True),
            mass=1.0,
            pivot=(0.0, 0.0, -0.1),
            gravity=9.81,
        ),
    )
}


def scenario_names() -> list[str]:
    """The names of the built-in scenarios."""
    return list(SCENARIOS)


def get_scenario(scenario: Scenario | str) -> Scenario:
    """A scenario by name (or itself); an InputError naming the built-in ones otherwise."""
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, str) and scenario in SCENARIOS:
        return SCENARIOS[scenario]
    raise unknown_choice(scenario, scenario_names(), "the scenario", alternative="a Scenario")
