"""The samples a scenario keeps: about ``[output] samples`` of them, the last included."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["decimate", "kept", "record_every"]


def kept(count: int, samples: int) -> NDArray[np.int64]:
    """Indices of every k-th of ``count`` samples, and the last, about ``samples`` in all."""
    index = np.arange(0, count, max(1, count // samples))
    if index[-1] != count - 1:
        index = np.append(index, count - 1)
    return index


def decimate(traj: Trajectory, samples: int) -> Trajectory:
    """Every k-th sample (and the last) so that about ``samples`` remain."""
    index = kept(len(traj.t), samples)
    if len(index) == len(traj.t):
        return traj
    return traj.samples(index)


def record_every(duration: float, dt: float, samples: int) -> int:
    """The step count between kept samples: about ``samples`` over ``duration``."""
    return max(1, math.ceil(duration / dt) // samples)
