"""What the conformance suite measures of one run: drifts and errors against the exact motion.

Energies, momenta and errors are measured at the sample times, in the body's
principal axes. Relative drifts are signed, ``(x(t) − x(0)) / x(0)``; "max" is
the value of largest magnitude over the run, with its sign.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from tumble.conformance.engine import Array, EngineBody, Samples
from tumble.conformance.scenarios import Scenario

__all__ = [
    "METRICS",
    "Reference",
    "attitude_errors",
    "energies",
    "flip_count",
    "measure",
    "momenta",
]

#: The columns of a run's row besides ``engine`` and ``dt``, in order.
METRICS = (
    "energy_drift_max",
    "energy_drift_final",
    "momentum_drift_max",
    "direction_drift_max",
    "attitude_error_max",
    "omega_error_max",
    "flips",
    "flips_exact",
    "failed_at",
    "steps_per_second",
)


def _rotate(quaternion: Array, vectors: Array) -> Array:
    """Body vectors (n, 3) in space axes under attitudes (n, 4) (scalar first, not
    necessarily unit): v + 2 w (u × v) + 2 u × (u × v) for unit q."""
    q = quaternion / np.linalg.norm(quaternion, axis=1, keepdims=True)
    w, u = q[:, :1], q[:, 1:]
    twice = 2.0 * np.cross(u, vectors)
    return np.asarray(vectors + w * twice + np.cross(u, twice))


def energies(body: EngineBody, quaternion: Array, omega: Array) -> Array:
    """Kinetic energy about the pivot (the centre of mass without one) plus gravity's
    potential −m g·r_com, J, at each sample."""
    kinetic = 0.5 * np.einsum("ni,ij,nj->n", omega, body.pivot_inertia, omega)
    if body.pivot is None:
        return np.asarray(kinetic)
    centre = _rotate(quaternion, np.broadcast_to(-np.asarray(body.pivot), omega.shape))
    return np.asarray(kinetic - body.mass * centre @ np.asarray(body.gravity))


def momenta(body: EngineBody, quaternion: Array, omega: Array) -> Array:
    """(n, 3) angular momentum in space axes, about the pivot (or the centre of mass), N·m·s."""
    return _rotate(quaternion, omega @ body.pivot_inertia)


def attitude_errors(quaternion: Array, exact: Array) -> Array:
    """The angle of the rotation from each exact attitude to the measured one, rad, in [0, π]."""
    q = quaternion / np.linalg.norm(quaternion, axis=1, keepdims=True)
    # Unit quaternions of rotations θ apart are 2 sin(θ/4) apart (the nearer of ±q):
    # small angles keep their digits, unlike arccos of the dot product.
    chord = np.minimum(np.linalg.norm(q - exact, axis=1), np.linalg.norm(q + exact, axis=1))
    return np.asarray(4.0 * np.arcsin(np.minimum(chord / 2.0, np.sqrt(0.5))))


def flip_count(component: Array, scale: float) -> int:
    """Sign changes of a rate component over the samples, values within 1e-9 ``scale`` of
    zero skipped (round-off of a component that starts at zero, ~1e-16 ``scale``, is no
    flip)."""
    signs = np.sign(component[np.abs(component) > 1e-9 * scale])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


def _signed_extreme(values: Array) -> float:
    if values.size == 0:
        return float("nan")
    return float(values[np.argmax(np.abs(values))])


@dataclass(frozen=True, eq=False)
class Reference:
    """A scenario's exact motion at the sample times of a run, computed once for every
    engine run at the same step, and its flip count at those times over the whole horizon
    (counted as the engines' flips are, at the same samples: a pair of sign changes closer
    than the sampling is missed by both alike)."""

    scenario: Scenario
    t: Array
    omega: Array
    quaternion: Array
    flips: int

    @classmethod
    def sampled(cls, scenario: Scenario, times: Array) -> Reference:
        omega, quaternion = scenario.reference(times)
        scale = float(np.linalg.norm(omega[0]))
        flips = flip_count(omega[:, scenario.intermediate_axis], scale)
        return cls(scenario, times, omega, quaternion, flips)

    def at(self, times: Array) -> tuple[Array, Array, int]:
        """The exact ω and attitude at ``times``, and the exact flip count to compare with
        a run sampled there: this sampling's (over the whole horizon) when ``times`` begins
        it (a run that stopped early), else evaluated anew and counted at ``times`` (an
        engine that samples at its own steps)."""
        count = len(times)
        if count <= len(self.t) and np.array_equal(times, self.t[:count]):
            return self.omega[:count], self.quaternion[:count], self.flips
        omega, quaternion = self.scenario.reference(times)
        axis = self.scenario.intermediate_axis
        return omega, quaternion, flip_count(omega[:, axis], float(np.linalg.norm(omega[0])))


def measure(reference: Reference, samples: Samples) -> dict[str, Any]:
    """One run's row: the :data:`METRICS` of ``samples`` against the exact motion.

    ``flips_exact`` is the exact motion's flip count at the run's sample times, over the
    whole horizon when the run stopped early (at ``samples.failed_at``).
    The time spent here is the reference's cost (:attr:`ConformanceResult.reference_seconds`).
    """
    scenario = reference.scenario
    body = scenario.body
    t, q, w = samples.t, samples.quaternion, samples.omega
    exact_omega, exact_quaternion, exact_flips = reference.at(t)
    energy = energies(body, q, w)
    momentum = momenta(body, q, w)
    if body.pivot is None:
        size = np.linalg.norm(momentum, axis=1)
        momentum_drift = (size - size[0]) / size[0]
        # atan2(|L × L0|, L·L0): arccos of the cosine would lose half the digits.
        cross = np.linalg.norm(np.cross(momentum, momentum[0]), axis=1)
        direction = float(np.max(np.arctan2(cross, momentum @ momentum[0])))
    else:
        # About a pivot under gravity only the vertical component is conserved; its
        # drift is measured against |L(0)| (the vertical part may be near zero).
        vertical = momentum[:, 2]
        momentum_drift = (vertical - vertical[0]) / np.linalg.norm(momentum[0])
        direction = float("nan")
    omega0 = np.linalg.norm(w[0])
    return {
        "energy_drift_max": _signed_extreme((energy - energy[0]) / energy[0]),
        "energy_drift_final": float((energy[-1] - energy[0]) / energy[0]),
        "momentum_drift_max": _signed_extreme(momentum_drift),
        "direction_drift_max": direction,
        "attitude_error_max": float(np.max(attitude_errors(q, exact_quaternion))),
        "omega_error_max": float(np.max(np.linalg.norm(w - exact_omega, axis=1)) / omega0),
        "flips": flip_count(w[:, scenario.intermediate_axis], float(omega0)),
        "flips_exact": exact_flips,
        "failed_at": samples.failed_at,
        "steps_per_second": samples.steps / samples.wall_time if samples.wall_time > 0 else np.inf,
        "failure": samples.failure,
    }
