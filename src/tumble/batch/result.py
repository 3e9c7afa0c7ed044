"""What a batch run returns, and the progress callback it takes."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["BatchResult", "Progress"]

Array = NDArray[np.float64]

#: None, or ``progress(done, total)`` called as a run goes.
Progress = Callable[[int, int], object] | None


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
    internal_values : (N, m) the internal parts' final values (each Rotor's
        relative speed, rad/s; each KaneDamper's ω in body axes, rad/s), in the
        order of ``internal``; (N, 0) without parts.
    internal_history : (n, N, m), or None.
    """

    omega: Array
    quaternion: Array
    t: Array
    omega_history: Array | None
    quaternion_history: Array | None
    dt: float
    method: str
    internal_values: Array = field(default_factory=lambda: np.zeros((0, 0)))
    internal_history: Array | None = None
    rotor_columns: tuple[int, ...] = ()

    @property
    def rotor_speed(self) -> Array:
        """(N, k) the Rotors' final speeds relative to their bodies, rad/s."""
        return np.asarray(self.internal_values[:, list(self.rotor_columns)])
