"""Integrators as engines: scipy's ODE solvers as a user calls them, and tumble's own methods.

``scipy/…`` integrate Euler's equations and the quaternion kinematics written
as one first-order system, ``I ω̇ = τ − ω × I ω`` (inertia and torque about the
pivot, if any) and ``q̇ = ½ q ⊗ (0, ω)``, with :func:`scipy.integrate.solve_ivp`
at its default tolerances (rtol 1e-3, atol 1e-6): what a hand-written
simulation gets. They choose their own steps; ``dt`` is then the sampling
interval. ``tumble/…`` are :func:`tumble.simulate` with that method: the
baseline rows.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from tumble.conformance.engine import Array, Engine, EngineBody, Samples, register_engine
from tumble.integrators import INTEGRATORS

__all__ = ["ScipyEngine", "TumbleEngine", "rigid_body_rates"]


def rigid_body_rates(body: EngineBody) -> Callable[[float, Array], Array]:
    """The right-hand side ``f(t, y)`` of ``y = (q, ω)``: Euler's equations about the pivot
    (the centre of mass without one), gravity's torque included, and ``q̇ = ½ q ⊗ (0, ω)``."""
    inertia = body.pivot_inertia
    inverse = np.linalg.inv(inertia)
    # The centre of mass seen from the pivot, body axes; gravity's force m g acts there.
    lever = np.zeros(3) if body.pivot is None else -np.asarray(body.pivot, dtype=float)
    weight = body.mass * np.asarray(body.gravity, dtype=float)

    def rates(_t: float, y: Array) -> Array:
        w0, x, y_, z = y[:4]
        omega = y[4:]
        torque = np.zeros(3)
        if body.pivot is not None:
            # Gravity in body axes: Rᵀ (m g), R of the quaternion (not normalised: divided by |q|²).
            norm = w0 * w0 + x * x + y_ * y_ + z * z
            rotation = (
                np.array(
                    [
                        [
                            w0 * w0 + x * x - y_ * y_ - z * z,
                            2 * (x * y_ - w0 * z),
                            2 * (x * z + w0 * y_),
                        ],
                        [
                            2 * (x * y_ + w0 * z),
                            w0 * w0 - x * x + y_ * y_ - z * z,
                            2 * (y_ * z - w0 * x),
                        ],
                        [
                            2 * (x * z - w0 * y_),
                            2 * (y_ * z + w0 * x),
                            w0 * w0 - x * x - y_ * y_ + z * z,
                        ],
                    ]
                )
                / norm
            )
            torque = np.cross(lever, rotation.T @ weight)
        omega_dot = inverse @ (torque - np.cross(omega, inertia @ omega))
        p, q_, r = omega
        quaternion_dot = 0.5 * np.array(
            [
                -x * p - y_ * q_ - z * r,
                w0 * p + y_ * r - z * q_,
                w0 * q_ + z * p - x * r,
                w0 * r + x * q_ - y_ * p,
            ]
        )
        return np.concatenate([quaternion_dot, omega_dot])

    return rates


class _WholeRun(Engine):
    """An engine that integrates a whole run at once: nothing to build or to step."""

    def build(self, body: EngineBody, dt: float) -> None:
        self._body = body

    def inertia(self) -> tuple[float, Array]:
        return self._body.mass, self._body.inertia


@register_engine
class ScipyEngine(_WholeRun):
    """scipy's ``solve_ivp`` at its default tolerances on Euler's equations and q̇ = ½ q ω."""

    name = "scipy"
    variants: ClassVar[dict[str, str]] = {
        "dop853": 'solve_ivp(method="DOP853"), rtol 1e-3, atol 1e-6 (scipy\'s defaults)',
        "rk45": 'solve_ivp(method="RK45"), rtol 1e-3, atol 1e-6 (scipy\'s defaults)',
    }
    modules = ("scipy",)
    holds_pivot = True
    pivot_method = "Euler's equations about the pivot with gravity's torque"

    def simulate(
        self,
        body: EngineBody,
        quaternion0: Array,
        omega0: Array,
        dt: float,
        steps: int,
        every: int,
        progress: Callable[[int], object] | None = None,
    ) -> Samples:
        from scipy.integrate import solve_ivp

        times = dt * np.arange(0, steps + 1, every)
        if times[-1] < steps * dt:
            times = np.append(times, steps * dt)
        start = time.perf_counter()
        solution = solve_ivp(
            rigid_body_rates(body),
            (0.0, steps * dt),
            np.concatenate([quaternion0, omega0]),
            method=self.variant.upper(),
            t_eval=times,
        )
        wall = time.perf_counter() - start
        if progress is not None:
            progress(steps)
        quaternion = solution.y[:4].T / np.linalg.norm(solution.y[:4].T, axis=1, keepdims=True)
        samples = Samples(solution.t, quaternion, solution.y[4:].T.copy(), wall_time=wall)
        samples.steps = steps
        if not solution.success:
            samples.failure = f"solve_ivp stopped: {solution.message}"
            samples.failed_at = float(solution.t[-1]) if solution.t.size else 0.0
        return samples


@register_engine
class TumbleEngine(_WholeRun):
    """:func:`tumble.simulate` with one of its stepping or adaptive methods."""

    name = "tumble"
    variants: ClassVar[dict[str, str]] = {
        name: integrator.summary
        for name, integrator in INTEGRATORS.items()
        if integrator.kind != "sampling" and name != "auto"
    }
    modules = ("numba",)
    holds_pivot = True
    pivot_method = "tumble.simulate(pivot=..., gravity=...)"

    def simulate(
        self,
        body: EngineBody,
        quaternion0: Array,
        omega0: Array,
        dt: float,
        steps: int,
        every: int,
        progress: Callable[[int], object] | None = None,
    ) -> Samples:
        from tumble.massprops import MassProperties
        from tumble.simulation import simulate

        mp = MassProperties(body.mass, np.zeros(3), body.inertia)
        keywords: dict[str, Any] = {"attitude0": quaternion0, "dt": dt, "method": self.variant}
        if body.pivot is not None:
            keywords.update(pivot=body.pivot, gravity=body.gravity)
        # Compile (or load from numba's cache) before the clock starts.
        simulate(mp, omega0, duration=2 * dt, **keywords)
        start = time.perf_counter()
        trajectory = simulate(mp, omega0, duration=steps * dt, record_every=every, **keywords)
        wall = time.perf_counter() - start
        if progress is not None:
            progress(steps)
        return Samples(
            np.asarray(trajectory.t),
            np.asarray(trajectory.quaternion),
            np.asarray(trajectory.omega),
            wall_time=wall,
            steps=steps,
        )
