"""The driver of the closed forms (``method="exact"``): the motions of
:mod:`tumble.theory.motions` sampled at the recorded times, no steps."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import IntegrationError
from tumble.integrators.problem import Problem, Samples, Schedule
from tumble.integrators.steps import Progress
from tumble.theory.motions import exact_principal, gyrostat_solution, lagrange_top

__all__ = ["check_finite_motion", "run_exact"]

Array = NDArray[np.float64]


def run_exact(integrator: Any, problem: Problem, schedule: Schedule, progress: Progress) -> Samples:
    """The exact solution at ``schedule.times``: torque-free (a rigid body or a
    gyrostat) or the Lagrange top under uniform gravity; no steps.

    Raises
    ------
    IntegrationError
        When the solution is not finite at some time (:func:`check_finite_motion`).
    """
    body = problem.body
    if not problem.torque.torque_free:
        # Every term is uniform gravity here (the registry's rule for the closed form).
        accelerations = (term.uniform_gravity() for term in problem.torque.terms)
        gravity = sum((g for g in accelerations if g is not None), np.zeros(3))
        top = lagrange_top(body, gravity, problem.omega0, problem.attitude0)
        samples = Samples(*top.at(schedule.times), np.zeros((schedule.times.size, 0)), 0)
    elif body.parts:
        omega, quaternion, values = gyrostat_solution(
            body, problem.omega0, problem.attitude0, schedule.times
        )
        samples = Samples(omega, quaternion, values, 0)
    else:
        w, q = exact_principal(
            body.moments,
            body.to_principal(problem.omega0),
            body.attitude_to_principal(problem.attitude0),
            schedule.times,
        )
        samples = Samples.rigid(problem, w, q, 0)
    check_finite_motion(schedule.times, samples)
    if progress is not None:
        progress(schedule.n_steps, schedule.n_steps)
    return samples


def check_finite_motion(times: Array, samples: Samples) -> None:
    """Refuse a closed-form motion that is not finite at some of ``times`` (s).

    The closed forms are evaluated at a scale of order one, so what is left is
    a motion whose own numbers leave float64 (a rotor's momentum beyond 1e308
    kg·m²/s) or a phase lost at times so long that a turn is below round-off.

    Raises
    ------
    IntegrationError
        Naming the first such time.
    """
    arrays = (samples.omega, samples.quaternion, samples.values)
    if all(np.isfinite(array).all() for array in arrays):
        return
    finite = np.isfinite(samples.omega).all(axis=1) & np.isfinite(samples.quaternion).all(axis=1)
    finite &= np.isfinite(samples.values).all(axis=1)
    if not finite.all():
        first = int(np.argmin(finite))
        raise IntegrationError(
            "Expected the closed-form motion to stay finite, got NaN or inf at "
            f"t = {times[first]:.6g} s (sample {first}): its momentum or energy is beyond "
            "float64's range, or t is too long to keep its phase; use SI values of an "
            "ordinary size or a shorter duration."
        )
