"""The gimbal kernel on cases with known answers (also run with NUMBA_DISABLE_JIT=1).

The kernel steps ``θ̈ = −a Ω sin θ + Ω² sin θ cos θ − k θ̇``, ``χ̇ = Ω cos θ``.
Oracles: the exact solution of the linear decay (Ω = 0) and RK4's own
amplification factor for it, the equilibrium (χ = Ω t), scipy's DOP853 at
rtol 1e-13, and the conserved energy of the undamped equation.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from tumble.core._jit import FINITE
from tumble.core.gimbal import N_PARAMS, derivatives, rk4_run


def run(y0: list[float], params: list[float], dt: float, n_steps: int, record_every: int = 1):
    y = np.array(y0, dtype=float)
    out = np.full((n_steps // record_every + 1, 3), np.nan)
    out[0] = y
    status = rk4_run(y, np.array(params), dt, n_steps, 0, record_every, out)
    return status, y, out


def test_derivatives_are_the_equation() -> None:
    a, big_omega, k = 40.0, 1.5, 0.3
    y = np.array([0.7, -2.0, 5.0])
    dy = np.zeros(3)
    derivatives(y, np.array([a, big_omega, k]), dy)
    theta, rate = 0.7, -2.0
    expected = [
        rate,
        -a * big_omega * math.sin(theta)
        + big_omega**2 * math.sin(theta) * math.cos(theta)
        - k * rate,
        big_omega * math.cos(theta),
    ]
    assert_allclose(dy, expected, rtol=1e-15)
    assert N_PARAMS == 3


def test_damping_alone_is_rk4s_exponential_decay() -> None:
    # Ω = 0: θ̇' = −k θ̇. One RK4 step multiplies θ̇ by R(z) = 1 + z + z²/2 + z³/6 + z⁴/24,
    # z = −k dt, exactly; the exact factor is e^z, and n steps differ by ≈ n |z|⁵/120.
    k, dt, n = 2.0, 0.01, 100
    status, y, out = run([0.3, 1.5, 0.0], [7.0, 0.0, k], dt, n)
    assert status == FINITE
    z = -k * dt
    factor = 1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24
    steps = np.arange(n + 1)
    assert_allclose(out[:, 1], 1.5 * factor**steps, rtol=1e-13)
    times = steps * dt
    assert_allclose(out[:, 1], 1.5 * np.exp(-k * times), rtol=1.1 * n * abs(z) ** 5 / 120)
    # θ = θ0 + θ̇0 (1 − e^{−kt}) / k, to the same relative order.
    theta = 0.3 + 1.5 * (1 - np.exp(-k * times)) / k
    assert_allclose(out[:, 0], theta, rtol=1e-8)
    assert np.all(out[:, 2] == 0.0)  # no platform, no spin lag
    assert_allclose(y, out[-1], atol=0)


def test_at_equilibrium_the_angle_stays_and_the_spin_lag_grows_as_omega_t() -> None:
    big_omega, dt, n = 3.0, 0.02, 50
    status, _, out = run([0.0, 0.0, 0.0], [80.0, big_omega, 0.5], dt, n)
    assert status == FINITE
    assert np.all(out[:, :2] == 0.0)
    # RK4 integrates a constant rate exactly: χ_n = n dt Ω to round-off.
    assert_allclose(out[:, 2], big_omega * dt * np.arange(n + 1), rtol=1e-14)


def reference(y0: list[float], params: list[float], times: np.ndarray) -> np.ndarray:
    a, big_omega, k = params

    def rhs(_: float, y: np.ndarray) -> list[float]:
        s, c = math.sin(y[0]), math.cos(y[0])
        return [y[1], -a * big_omega * s + big_omega**2 * s * c - k * y[1], big_omega * c]

    sol = solve_ivp(rhs, (0, times[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-14, t_eval=times)
    return np.asarray(sol.y.T)


def test_large_swing_matches_dop853_at_fourth_order() -> None:
    y0, params = [2.0, 0.5, 0.0], [50.0, 2.0, 0.3]  # β ≈ 10 rad/s: 3 s is about four swings
    duration = 3.0
    errors = []
    for n in (3000, 6000):
        status, _, out = run(y0, params, duration / n, n)
        assert status == FINITE
        expected = reference(y0, params, np.linspace(0.0, duration, n + 1))
        errors.append(np.max(np.abs(out - expected)))
    # Halving dt divides RK4's global error by 2⁴ = 16 (DOP853's ~1e-12 is far below).
    assert 12 < errors[0] / errors[1] < 20
    assert errors[1] < 1e-8


def test_undamped_energy_is_kept_to_fourth_order() -> None:
    # Per unit I_AB: E = ½ θ̇² − a Ω cos θ − ½ Ω² sin² θ is conserved when k = 0.
    a, big_omega = 50.0, 2.0

    def energy(out: np.ndarray) -> np.ndarray:
        return (
            0.5 * out[:, 1] ** 2
            - a * big_omega * np.cos(out[:, 0])
            - 0.5 * (big_omega * np.sin(out[:, 0])) ** 2
        )

    drifts = []
    for n in (2000, 4000):
        status, _, out = run([2.5, 0.0, 0.0], [a, big_omega, 0.0], 3.0 / n, n)
        assert status == FINITE
        e = energy(out)
        drifts.append(np.max(np.abs(e - e[0])) / (a * big_omega))
    assert 12 < drifts[0] / drifts[1] < 20
    assert drifts[1] < 1e-8


def test_chunks_continue_one_run_and_rows_are_every_kth_step() -> None:
    params = np.array([30.0, 1.2, 0.1])
    dt, n, every = 0.003, 40, 4
    status, y_one, out_one = run([1.0, 0.2, 0.0], list(params), dt, n, every)
    assert status == FINITE
    y = np.array([1.0, 0.2, 0.0])
    out = np.full_like(out_one, np.nan)
    out[0] = y
    for first, count in ((0, 7), (7, 13), (20, 20)):
        assert rk4_run(y, params, dt, count, first, every, out) == FINITE
    assert np.array_equal(y, y_one) and np.array_equal(out, out_one)
    _, _, every_step = run([1.0, 0.2, 0.0], list(params), dt, n)
    assert np.array_equal(out_one, every_step[::every])


def test_a_diverging_step_is_reported_and_not_taken() -> None:
    # k dt = 1000: RK4 multiplies θ̇ by ≈ (k dt)⁴/24 ≈ 4e10 a step and overflows in ~30.
    params = np.array([1.0, 1.0, 1000.0])
    y = np.array([0.1, 1.0, 0.0])
    # Without the compiler the kernel runs on numpy floats, which warn on overflow.
    with np.errstate(over="ignore", invalid="ignore"):
        status = rk4_run(y, params, 1.0, 100, 5, 1, np.zeros((200, 3)))
        assert status != FINITE and 5 < status <= 105
        assert np.all(np.isfinite(y))
        # From the state it returned, the very next step is the one that fails.
        assert rk4_run(y, params, 1.0, 1, status - 1, 1, np.zeros((200, 3))) == status
