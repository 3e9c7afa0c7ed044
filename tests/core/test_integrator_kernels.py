"""The splitting and adaptive kernels, the user-torque callback and the loop over a
user's potential on small cases (also run with NUMBA_DISABLE_JIT=1, so the kernels
run as Python)."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from numpy.testing import assert_allclose

from tumble.core import adaptive, splitting, stepping
from tumble.core._jit import FINITE, file_stamp
from tumble.core.adaptive import ACCEPTED, STEP_UNDERFLOW
from tumble.core.rk4 import rk4_step
from tumble.core.splitting import (
    YOSHIDA_INNER,
    YOSHIDA_OUTER,
    sub_step,
    sub_step_start,
    sub_steps,
)
from tumble.core.torques import (
    combine,
    compile_user_potential,
    compile_user_torque,
    constant_body_torque,
    linear_damping,
    user_torque,
)

FREE = combine(())
#: A body torque in rows 0-2 and linear damping in row 3.
FORCED = combine([(constant_body_torque, 0), (linear_damping, 3)])
USER = combine([(user_torque, 0)])


def splitting_run(w, q, inertia, params, dt, n_steps, first, every, out_w, out_q, order):
    step = splitting.strang_step if order == 2 else splitting.yoshida_step
    # The kernel's key names the torque, FORCED, and this file, which defines it:
    # the same in every process, so that numba's cache serves the next run.
    identity = f"{file_stamp(splitting_run)}|forced"
    run = stepping.single_kernel(step, FORCED, identity, splitting.MOMENTUM)
    return run(w, q, inertia, params, 0.0, dt, n_steps, first, every, out_w, out_q)


def forcing(body=(0.0, 0.0, 0.0), damping=0.0):
    """The packed params of FORCED: (4, 1)."""
    return np.array([[*body, damping]]).T.copy()


def test_yoshida_weights_sum_to_one_and_cancel_the_third_order_error() -> None:
    # w0 + 2 w1 = 1 and w0³ + 2 w1³ = 0 (Yoshida 1990, eq. 4.11).
    assert YOSHIDA_INNER + 2 * YOSHIDA_OUTER == 1.0
    assert abs(YOSHIDA_INNER**3 + 2 * YOSHIDA_OUTER**3) < 1e-15


@pytest.mark.parametrize("order", [2, 4])
def test_the_sub_steps_tile_the_step_from_its_start(order) -> None:
    # Strang's one whole step, or the triple jump's w1, w0, w1: each sub-step
    # starts where the ones before it end, their times added one by one as a loop
    # over them adds them (so the kernels that take one sub-step at a time and
    # those that take them in a loop give the same bits), and together they make
    # the step (1 = w1 + w0 + w1 to round-off: within 2 ulp of t + dt).
    t, dt = 0.37, 0.013
    count = sub_steps(order)
    assert count == (1 if order == 2 else 3)
    fractions = [sub_step(order, j) for j in range(count)]
    assert fractions == ([1.0] if order == 2 else [YOSHIDA_OUTER, YOSHIDA_INNER, YOSHIDA_OUTER])
    running = t
    for j in range(count):
        assert sub_step_start(order, j, t, dt) == running
        running += fractions[j] * dt
    assert running == pytest.approx(t + dt, rel=0, abs=2 * np.spacing(t + dt))


def test_splitting_is_exact_for_a_symmetric_body_in_one_step() -> None:
    # I1 = I2: ω3 constant, (ω1, ω2) turning at Ω = (I3 − I1)/I1 ω3 in the body
    # (Landau & Lifshitz §33); one step of any length reproduces it.
    inertia = np.array([1.0, 1.0, 1.6])
    omega_3, t = 2.0, 0.9
    for order in (2, 4):
        w = np.array([0.3, 0.0, omega_3])
        q = np.array([1.0, 0.0, 0.0, 0.0])
        status = splitting_run(
            w, q, inertia, forcing(), t, 1, 0, 1, np.zeros((2, 3)), np.zeros((2, 4)), order,
        )  # fmt: skip
        assert status == FINITE
        rate = (1.6 - 1.0) / 1.0 * omega_3
        assert_allclose(
            w, [0.3 * math.cos(rate * t), 0.3 * math.sin(rate * t), omega_3], atol=1e-15
        )


def test_splitting_spin_up_under_a_body_torque_and_damping() -> None:
    # Sphere, τ = τ0 − c ω about z: ω(t) = τ0/c + (ω0 − τ0/c) exp(−c t / I), which the
    # kick integrates exactly (its flow is this ODE with the attitude held).
    inertia = np.full(3, 0.5)
    params = forcing((0.0, 0.0, 0.3), 0.1)
    w = np.array([0.0, 0.0, 1.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    splitting_run(w, q, inertia, params, 0.5, 4, 0, 10, np.zeros((1, 3)), np.zeros((1, 4)), 2)
    expected = 3.0 + (1.0 - 3.0) * math.exp(-0.1 * 2.0 / 0.5)
    assert_allclose(w, [0.0, 0.0, expected], atol=1e-14)


def test_a_non_finite_state_is_reported_with_its_step() -> None:
    params = forcing((math.inf, 0.0, 0.0))
    w = np.array([0.0, 0.0, 1.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    status = splitting_run(
        w, q, np.ones(3), params, 0.1, 5, 7, 1, np.zeros((20, 3)), np.zeros((20, 4)), 4
    )
    assert status == 8  # the global number of the first step (7 + 1)
    assert_allclose(w, [0.0, 0.0, 1.0])  # left as before that step


def test_adaptive_kernel_on_a_uniform_spin_up() -> None:
    # ω linear in t, q a rotation by ω0 t + α t²/2 about z: the 5th-order method
    # integrates ω exactly and q to its tolerance; samples come from dense output.
    inertia = np.full(3, 0.4)
    params = forcing((0.0, 0.0, 0.2))
    w = np.array([0.0, 0.0, 1.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    control = np.array([0.0, 1e-12, 1e-14, 0.0, 0.0, 0.0, 2.0**53])
    adaptive_run = adaptive.single_kernel(FORCED, "test.forced")
    times = np.array([0.25, 0.5, 1.0])
    out_w = np.zeros((3, 3))
    out_q = np.zeros((3, 4))
    assert (
        adaptive_run(w, q, inertia, params, 0.0, 0.0, 1.0, control, times, out_w, out_q) == FINITE
    )
    assert control[ACCEPTED] > 3
    alpha = 0.2 / 0.4
    assert_allclose(out_w[:, 2], 1.0 + alpha * times, atol=1e-13)
    angle = times + alpha * times**2 / 2
    assert_allclose(out_q[:, 0], np.cos(angle / 2), atol=1e-11)
    assert_allclose(out_q[:, 3], np.sin(angle / 2), atol=1e-11)
    assert_allclose(w, out_w[-1], atol=0)


def test_adaptive_kernel_reports_an_underflow() -> None:
    params = forcing((math.nan, 0.0, 0.0))
    control = np.array([0.0, 1e-8, 1e-10, 0.0, 0.0, 0.0, 2.0**53])
    adaptive_run = adaptive.single_kernel(FORCED, "test.forced")
    status = adaptive_run(
        np.ones(3), np.array([1.0, 0, 0, 0]), np.ones(3), params, 0.0, 0.0, 1.0, control,
        np.array([1.0]), np.zeros((1, 3)), np.zeros((1, 4)),
    )  # fmt: skip
    assert status == STEP_UNDERFLOW


@numba.njit
def constant_body_torque(t, omega, quaternion, params, out):
    out[0] = params[0]
    out[1] = params[1]
    out[2] = params[2]


def test_the_user_torque_turns_a_body_torque_into_the_principal_frame() -> None:
    # Principal axes = the body axes turned 90° about z: body x is principal y.
    axes = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    axes_q = np.array([math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)])
    callback = compile_user_torque(constant_body_torque)
    context = (
        axes,
        axes_q,
        np.array([0.3, 0.0, 0.0]),
        np.zeros(3),
        np.zeros(4),
        np.zeros(3),
        callback,
    )
    inertia = np.full(3, 0.5)
    w = np.zeros(3)
    q = np.array([1.0, 0.0, 0.0, 0.0])
    rk4_run = stepping.single_kernel(rk4_step, USER, "test.user")
    status = rk4_run(
        w, q, inertia, np.zeros((1, 1)), context, 0.1, 10, 0, 100, np.zeros((1, 3)),
        np.zeros((1, 4)),
    )  # fmt: skip
    assert status == FINITE
    # A torque along body x is along −(principal y)... axes[:, 1] = (−1, 0, 0): so
    # τ_principal = axesᵀ τ_body = (0, −0.3, 0); ω = τ t / I.
    assert_allclose(w, [0.0, -0.3 * 1.0 / 0.5, 0.0], atol=1e-14)
    w2 = np.zeros(3)
    control = np.array([0.0, 1e-10, 1e-12, 0.0, 0.0, 0.0, 2.0**53])
    adaptive_run = adaptive.single_kernel(USER, "test.user")
    status = adaptive_run(
        w2, np.array([1.0, 0.0, 0.0, 0.0]), inertia, np.zeros((1, 1)), context, 0.0, 1.0,
        control, np.array([1.0]), np.zeros((1, 3)), np.zeros((1, 4)),
    )  # fmt: skip
    assert status == FINITE
    assert_allclose(w2, w, atol=1e-13)


@numba.njit
def tilt_energy(t, quaternion, params):
    # U = k (1 − cos θ) for a rotation by θ about any axis (cos(θ/2) = w), plus a
    # term in t, J.
    w = quaternion[0]
    return params[0] * (1.0 - (2.0 * w * w - 1.0)) + params[1] * t


def test_the_potential_loop_evaluates_the_users_function_at_each_sample() -> None:
    angles = np.array([0.0, math.pi / 3, math.pi / 2, math.pi])
    quaternions = np.column_stack(
        [np.cos(angles / 2), np.sin(angles / 2), np.zeros(4), np.zeros(4)]
    )
    times = np.array([0.0, 1.0, 2.0, 3.0])
    out = np.full(4, np.nan)
    compile_user_potential(tilt_energy)(times, quaternions, np.array([2.0, 0.5]), out)
    assert_allclose(out, 2.0 * (1.0 - np.cos(angles)) + 0.5 * times, rtol=1e-15, atol=1e-15)
