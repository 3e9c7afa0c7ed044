"""The gimballed gyroscope on a turning platform, stepped by a compiled RK4.

A disk symmetric about its spin axis is pivoted at its centre in a gimbal
free to turn about an axis AB fixed to a platform; the platform turns at a
constant angular velocity whose component perpendicular to AB is Ω. θ is
the angle of the spin axis from that component, about AB. With the total
spin ω_s conserved (ψ is cyclic), the motion reduces to one degree of freedom:

    θ̈ = −a Ω sin θ + Ω² sin θ cos θ − k θ̇,     χ̇ = Ω cos θ,

with ``a = I_s ω_s / I_AB`` (rad/s) and ``k = c / I_AB`` (1/s, viscous
damping about AB). ``χ`` (rad) is the part of the spin angle that the
platform's turning takes away: the spin angle of the disk relative to the
gimbal is ``ψ = ω_s t − χ``, so the fast part ``ω_s t`` is never stepped.

State ``y`` (3,): ``[θ (rad), θ̇ (rad/s), χ (rad)]``. Parameters ``params``
(``N_PARAMS``,): ``[a (rad/s), Ω (rad/s), k (1/s)]``.
"""

from __future__ import annotations

import math

from tumble.core._jit import FINITE, njit

__all__ = ["N_PARAMS", "derivatives", "rk4_run"]

N_PARAMS = 3


@njit(inline="always")
def _rates(theta, theta_rate, a, big_omega, k):  # type: ignore[no-untyped-def]
    """(θ̇, θ̈, χ̇) as scalars."""
    s = math.sin(theta)
    c = math.cos(theta)
    return (
        theta_rate,
        s * (big_omega * big_omega * c - a * big_omega) - k * theta_rate,
        big_omega * c,
    )


@njit
def derivatives(y, params, dy):  # type: ignore[no-untyped-def]
    """Write ``(θ̇, θ̈, χ̇)`` (rad/s, rad/s², rad/s) into ``dy`` for the state ``y``."""
    rates = _rates(y[0], y[1], params[0], params[1], params[2])
    dy[0] = rates[0]
    dy[1] = rates[1]
    dy[2] = rates[2]


@njit
def rk4_run(y, params, dt, n_steps, first_step, record_every, out):  # type: ignore[no-untyped-def]
    """Advance ``y`` in place by ``n_steps`` classical Runge–Kutta steps of ``dt`` s.

    The steps are written out on scalars, not taken by the shared stepper of arrays
    (:func:`tumble.core.rk4.fixed_step_run`): with three states held in registers a
    step takes 57 ns, through arrays 72 ns (``bench/model_steppers.py``).

    After global step ``first_step + j + 1`` (j = 0 … n_steps − 1), if that
    number is a multiple of ``record_every``, the state is written to row
    ``number // record_every`` of ``out`` (·, 3).

    Returns
    -------
    ``FINITE`` (−1) if every step stayed finite, else the global number of the
    first step that produced a NaN or an infinity (``y`` is left as it was
    before that step).
    """
    a = params[0]
    big_omega = params[1]
    k = params[2]
    h = 0.5 * dt
    sixth = dt / 6.0
    theta, rate, chi = y[0], y[1], y[2]
    for j in range(n_steps):
        r1 = _rates(theta, rate, a, big_omega, k)
        r2 = _rates(theta + h * r1[0], rate + h * r1[1], a, big_omega, k)
        r3 = _rates(theta + h * r2[0], rate + h * r2[1], a, big_omega, k)
        r4 = _rates(theta + dt * r3[0], rate + dt * r3[1], a, big_omega, k)
        new_theta = theta + sixth * (r1[0] + 2.0 * (r2[0] + r3[0]) + r4[0])
        new_rate = rate + sixth * (r1[1] + 2.0 * (r2[1] + r3[1]) + r4[1])
        new_chi = chi + sixth * (r1[2] + 2.0 * (r2[2] + r3[2]) + r4[2])
        if not math.isfinite(new_theta + new_rate + new_chi):
            y[0], y[1], y[2] = theta, rate, chi
            return first_step + j + 1
        theta, rate, chi = new_theta, new_rate, new_chi
        number = first_step + j + 1
        if number % record_every == 0:
            row = number // record_every
            out[row, 0] = theta
            out[row, 1] = rate
            out[row, 2] = chi
    y[0], y[1], y[2] = theta, rate, chi
    return FINITE
