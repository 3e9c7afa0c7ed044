"""The start of a fit without a guess: :func:`linear_start`, from the samples
smoothed and differentiated by :func:`smoothed`."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.signal import savgol_filter

__all__ = ["linear_start", "smoothed"]

Array = NDArray[np.float64]


def smoothed(times: Array, measured: Array) -> tuple[Array, Array]:
    """The samples put on an even grid and smoothed, and their derivative, (n, 3)
    each: Savitzky–Golay filters over about a quarter of a turn (noise in a plain
    difference would swamp ω̇)."""
    grid = np.linspace(times[0], times[-1], times.size)
    even = np.stack([np.interp(grid, times, measured[:, k]) for k in range(3)], axis=1)
    step = grid[1] - grid[0]
    turn = 0.5 / max(float(np.linalg.norm(even, axis=1).max()), 1e-300)  # s, ~ a quarter turn
    length = int(np.clip(2 * (turn / step // 2) + 1, 5, 2 * (times.size // 8) + 1))
    smooth = savgol_filter(even, length, 3, axis=0)
    rates = savgol_filter(even, length, 3, deriv=1, delta=step, axis=0)
    return smooth, rates


def linear_start(smooth: Array, rates: Array) -> tuple[Array, Array, Array]:
    """Moments and axes without a guess, from the smoothed samples ``smooth`` and
    their derivative ``rates`` (:func:`smoothed`) in two sets of equations
    linear in the inertia tensor I (6 entries, up to scale):

    * Euler's, ``I ω̇ + ω × (I ω) = 0`` at every sample;
    * the conservation of energy, ``ωᵀ I ω`` equal at every sample to its mean
      over the samples, which needs no derivative (alone it also admits I², as
      |L|² is conserved too; with Euler's equations only I remains).

    The tensor is the right singular vector of the least singular value, its
    eigenvectors the axes; the smoothed rate at the first sample starts ω0. The
    bias is ignored here; the fit takes it up."""
    euler, energy = [], []
    for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)):
        unit = np.zeros((3, 3))
        unit[i, j] = unit[j, i] = 1.0
        euler.append((rates @ unit + np.cross(smooth, smooth @ unit)).ravel())
        form = np.einsum("ni,ij,nj->n", smooth, unit, smooth)
        energy.append(form - form.mean())
    a, b = np.stack(euler, axis=1), np.stack(energy, axis=1)
    # Each block scaled to unit size, so neither outweighs the other by its units.
    system = np.vstack(
        [a / max(float(np.linalg.norm(a)), 1e-300), b / max(float(np.linalg.norm(b)), 1e-300)]
    )
    _, _, vt = np.linalg.svd(system, full_matrices=False)
    p = vt[-1]
    tensor = np.array([[p[0], p[3], p[4]], [p[3], p[1], p[5]], [p[4], p[5], p[2]]])
    if np.trace(tensor) < 0:
        tensor = -tensor
    moments, axes = np.linalg.eigh(tensor)
    moments = np.clip(moments, 1e-3 * moments[2], None)
    if np.linalg.det(axes) < 0:
        axes[:, 0] *= -1.0
    return moments / moments[2], axes, smooth[0]
