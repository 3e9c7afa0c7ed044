"""A rigid rotor on elastic bearings run up with an unbalance, stepped by a compiled RK4.

The rotor's small motions q = (x, y, α, β) (its centre of mass perpendicular
to the axis, m, and the axis's tilts, rad) obey

    q̈ = M⁻¹ f(t) − M⁻¹ (C + Ω G) q̇ − M⁻¹ (K + Ω̇ G) q

with the spin Ω(t) = Ω₀ + Ω̇ t and the unbalance U (kg·m) at axial arm a from
the centre of mass, carried round at φ(t) = Ω₀ t + Ω̇ t² / 2:
f = U (φ̇² cos φ + φ̈ sin φ, φ̇² sin φ − φ̈ cos φ) as (f_x, f_y, −a f_y, a f_x)
(see :mod:`tumble.models.run_up` for the derivation).

State ``y`` (8,): ``[x, y, α, β, ẋ, ẏ, α̇, β̇]``. ``matrices`` (4, 4, 4): M⁻¹,
M⁻¹K, M⁻¹C and M⁻¹G. ``params`` (``N_PARAMS``,): ``[Ω₀ (rad/s), Ω̇ (rad/s²),
U (kg·m), a (m)]``.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import FINITE, njit

__all__ = ["N_PARAMS", "derivatives", "rk4_run"]

N_PARAMS = 4


@njit
def derivatives(t, y, matrices, params, dy):  # type: ignore[no-untyped-def]
    """Write ẏ = (q̇, q̈) into ``dy`` (8,) for the state ``y`` at time ``t`` (s)."""
    start, rate, unbalance, arm = params[0], params[1], params[2], params[3]
    spin = start + rate * t
    angle = (start + 0.5 * rate * t) * t
    c = math.cos(angle)
    s = math.sin(angle)
    fx = unbalance * (spin * spin * c + rate * s)
    fy = unbalance * (spin * spin * s - rate * c)
    force = (fx, fy, -arm * fy, arm * fx)
    for i in range(4):
        total = 0.0
        for j in range(4):
            total += (
                matrices[0, i, j] * force[j]
                - (matrices[2, i, j] + spin * matrices[3, i, j]) * y[4 + j]
                - (matrices[1, i, j] + rate * matrices[3, i, j]) * y[j]
            )
        dy[i] = y[4 + i]
        dy[4 + i] = total


@njit
def rk4_run(y, matrices, params, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
    """Advance ``y`` in place by ``n_steps`` classical Runge–Kutta steps of ``dt`` s
    from the time ``first_step * dt``.

    After global step ``first_step + j + 1`` (j = 0 … n_steps − 1), if that
    number is a multiple of ``record_every``, the state is written to row
    ``number // record_every`` of ``out`` (·, 8).

    Returns
    -------
    ``FINITE`` (−1) if every step stayed finite, else the global number of the
    first step that produced a NaN or an infinity (``y`` is left as it was
    before that step).
    """
    k1 = np.empty(8)
    k2 = np.empty(8)
    k3 = np.empty(8)
    k4 = np.empty(8)
    trial = np.empty(8)
    half = 0.5 * dt
    for j in range(n_steps):
        number = first_step + j
        t = number * dt
        derivatives(t, y, matrices, params, k1)
        for i in range(8):
            trial[i] = y[i] + half * k1[i]
        derivatives(t + half, trial, matrices, params, k2)
        for i in range(8):
            trial[i] = y[i] + half * k2[i]
        derivatives(t + half, trial, matrices, params, k3)
        for i in range(8):
            trial[i] = y[i] + dt * k3[i]
        derivatives(t + dt, trial, matrices, params, k4)
        finite = True
        for i in range(8):
            trial[i] = y[i] + dt / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i])
            finite = finite and math.isfinite(trial[i])
        if not finite:
            return number + 1
        for i in range(8):
            y[i] = trial[i]
        if (number + 1) % record_every == 0:
            row = (number + 1) // record_every
            for i in range(8):
                out[row, i] = y[i]
    return FINITE
