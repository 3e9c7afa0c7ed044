"""A rigid rotor on elastic bearings run up with an unbalance, stepped by the compiled
RK4 of :func:`tumble.core.rk4.fixed_step_run`.

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

from tumble.core._jit import njit
from tumble.core.rk4 import fixed_step_run

__all__ = ["N_PARAMS", "derivatives", "rk4_run"]

N_PARAMS = 4


@njit(inline="always")
def derivatives(t, y, dy, model):  # type: ignore[no-untyped-def]
    """Write ẏ = (q̇, q̈) into ``dy`` (8,) for the state ``y`` at time ``t`` (s);
    ``model`` is ``(matrices, params)``."""
    matrices, params = model
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


#: ``rk4_run(y, dt, n_steps, first_step, record_every, out, (matrices, params))``: the
#: run of :func:`tumble.core.rk4.fixed_step_run` with these rates, recording rows
#: (·, 8).
rk4_run = fixed_step_run(derivatives)
