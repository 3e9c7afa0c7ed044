"""The RK4 step in the stepping kernels, and the equations of motion on small cases (also run with
NUMBA_DISABLE_JIT=1)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

from tumble.core import stepping
from tumble.core._jit import FINITE, njit
from tumble.core.dynamics import rotate_to_body
from tumble.core.rk4 import fixed_step_run, rk4_step, rk4_tuple_step
from tumble.core.torques import combine, constant_body_torque, constant_space_torque

FREE = combine(())
BODY_TORQUE = combine([(constant_body_torque, 0)])
SPACE_TORQUE = combine([(constant_space_torque, 0)])


def test_rotate_to_body_is_the_inverse_attitude() -> None:
    rotation = Rotation.from_rotvec([0.4, -1.1, 0.3])
    q = tuple(rotation.as_quat(scalar_first=True))
    v = (0.3, -2.0, 1.5)
    assert_allclose(rotate_to_body(q, v), rotation.inv().apply(v), atol=1e-15)


def test_spin_up_of_a_sphere_under_a_body_torque() -> None:
    # I ω̇ = τ about a fixed axis: ω(t) = ω0 + τ t / I, exact for RK4 (linear in t),
    # and the attitude turns by ω0 t + τ t² / (2 I) about z.
    run = stepping.single_kernel(rk4_step, BODY_TORQUE, "test.body")
    inertia = np.full(3, 0.4)
    params = np.array([[0.0], [0.0], [0.2]])
    w = np.array([0.0, 0.0, 1.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    out_w = np.zeros((11, 3))
    out_q = np.zeros((11, 4))
    status = run(w, q, inertia, params, 0.0, 0.01, 100, 0, 10, out_w, out_q)
    assert status == FINITE
    assert_allclose(w, [0.0, 0.0, 1.0 + 0.2 * 1.0 / 0.4], atol=1e-14)
    angle = 1.0 * 1.0 + 0.2 * 1.0**2 / (2 * 0.4)
    assert_allclose(q, [np.cos(angle / 2), 0, 0, np.sin(angle / 2)], atol=1e-10)
    assert_allclose(out_w[10], w, atol=0)


def test_batch_kernel_equals_the_single_body_kernel() -> None:
    rng = np.random.default_rng(5)
    n = 130  # two blocks, one partial
    second = rng.uniform(0.2, 1.0, size=(3, n))
    inertia = np.vstack([second[1] + second[2], second[0] + second[2], second[0] + second[1]])
    w = rng.normal(size=(3, n))
    q = Rotation.random(n, random_state=5).as_quat(scalar_first=True).T.copy()
    params = np.array([[0.1], [-0.2], [0.05]])  # a space torque: the attitude-dependent path
    w_batch, q_batch = w.copy(), q.copy()
    batch = stepping.batch_kernel(rk4_step, SPACE_TORQUE, "test.space")
    batch(w_batch, q_batch, inertia, params, 0.0, 0.0, 1e-2, 50, np.zeros(n, dtype=np.int64))
    single = stepping.single_kernel(rk4_step, SPACE_TORQUE, "test.space")
    for k in (0, 77, 129):
        wk, qk = w[:, k].copy(), q[:, k].copy()
        single(
            wk, qk, inertia[:, k].copy(), params, 0.0, 1e-2, 50, 0, 10**9, np.zeros((1, 3)),
            np.zeros((1, 4)),
        )  # fmt: skip
        # FMA contraction and reassociation in the batch differ from the serial
        # kernel by round-off only: 1e-13 after 50 steps.
        assert_allclose(w_batch[:, k], wk, atol=1e-13)
        assert_allclose(q_batch[:, k], qk, atol=1e-13)


def test_a_diverging_step_is_reported_and_not_taken() -> None:
    run = stepping.single_kernel(rk4_step, FREE, "test.free")
    w = np.array([0.0, 1e200, 1e200])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    status = run(
        w, q, np.array([1.0, 2.0, 3.0]), np.zeros((1, 1)), 0.0, 1.0, 5, 7, 1, np.zeros((20, 3)),
        np.zeros((20, 4)),
    )  # fmt: skip
    assert status == 8
    assert_allclose(w, [0.0, 1e200, 1e200])


@njit
def _oscillator(t, y, dy, model):  # type: ignore[no-untyped-def]
    """ẋ = v, v̇ = −ω² x, ω = model[0]."""
    dy[0] = y[1]
    dy[1] = -model[0] * model[0] * y[0]


@njit
def _cubic_in_time(t, y, dy, model):  # type: ignore[no-untyped-def]
    """ẏ = t³ (then NaN from model[0] s on: a step that diverges)."""
    dy[0] = t * t * t if t < model[0] else math.nan


def test_the_shared_stepper_is_the_classical_runge_kutta_map() -> None:
    # On ẏ = A y, one RK4 step of h multiplies y by R(hA) = I + hA + (hA)²/2 + (hA)³/6
    # + (hA)⁴/24, exactly: 400 steps are the 400th power of that matrix (computed in
    # numpy, an independent route), equal to round-off over 400 steps (1e-13 of |y|).
    omega, h, steps = 3.0, 0.01, 400
    run = fixed_step_run(_oscillator)
    y = np.array([1.0, 0.0])
    out = np.zeros((steps // 100 + 1, 2))
    assert run(y, h, steps, 0, 100, out, (omega,)) == FINITE
    z = h * np.array([[0.0, 1.0], [-omega * omega, 0.0]])
    one_step = np.eye(2) + z + z @ z / 2 + z @ z @ z / 6 + z @ z @ z @ z / 24
    assert_allclose(y, np.linalg.matrix_power(one_step, steps) @ [1.0, 0.0], atol=1e-13)
    # Rows every 100th step, from row 1 (row 0 is the caller's: the start).
    for row in range(1, 5):
        expected = np.linalg.matrix_power(one_step, 100 * row) @ [1.0, 0.0]
        assert_allclose(out[row], expected, atol=1e-13)
    # And it is the oscillator: RK4's error over 4 s at ω h = 0.03 is ~(ωh)⁴ ω t / 120
    # ≈ 8e-8 of the amplitude.
    assert_allclose(y, [np.cos(omega * 4.0), -omega * np.sin(omega * 4.0)], atol=1e-6)


def test_the_shared_stepper_reads_the_time_and_stops_before_a_diverging_step() -> None:
    # Simpson's rule, which RK4 is on ẏ = f(t), is exact for cubics: y = t⁴/4 at each
    # step, from the time first_step · dt (steps 50 to 149 of 0.01 s: 0.5 to 1.5 s).
    run = fixed_step_run(_cubic_in_time)
    y = np.array([0.5**4 / 4])
    assert run(y, 0.01, 100, 50, 1000, np.zeros((1, 1)), (math.inf,)) == FINITE
    assert y[0] == pytest.approx(1.5**4 / 4, rel=1e-14)
    # The rates turn NaN from 1 s: the step from 0.99 s (global step 100) is not taken.
    y = np.array([0.5**4 / 4])
    assert run(y, 0.01, 100, 50, 1000, np.zeros((1, 1)), (1.0,)) == 100
    assert y[0] == pytest.approx(0.99**4 / 4, rel=1e-13)


@njit
def _tuple_oscillator(torque, t, y, model, params, column, context):  # type: ignore[no-untyped-def]
    """ẋ = v, v̇ = −ω² x + torque(t), ω = model[0]: the form of rk4_tuple_step."""
    return (y[1], -model[0] * model[0] * y[0] + torque(t))


@njit
def _no_force(t):  # type: ignore[no-untyped-def]
    return 0.0


@njit
def _cubic_force(t):  # type: ignore[no-untyped-def]
    return t * t * t


_OSCILLATOR_STEP = rk4_tuple_step(_tuple_oscillator)


@njit
def _tuple_steps(torque, y, dt, steps, model):  # type: ignore[no-untyped-def]
    for k in range(steps):
        y = _OSCILLATOR_STEP(torque, k * dt, dt, y, model, None, 0, None)
    return y


def test_the_tuple_stepper_is_the_classical_runge_kutta_map() -> None:
    # The same oracle as the stepper of arrays: on ẏ = A y, 400 steps of RK4 are the
    # 400th power of R(hA), equal to round-off (1e-13 of |y|).
    omega, h, steps = 3.0, 0.01, 400
    y = _tuple_steps(_no_force, (1.0, 0.0), h, steps, (omega,))
    z = h * np.array([[0.0, 1.0], [-omega * omega, 0.0]])
    one_step = np.eye(2) + z + z @ z / 2 + z @ z @ z / 6 + z @ z @ z @ z / 24
    assert_allclose(y, np.linalg.matrix_power(one_step, steps) @ [1.0, 0.0], atol=1e-13)


def test_the_tuple_stepper_reads_the_time_and_calls_its_function() -> None:
    # With ω = 0 the oscillator is v̇ = t³ (the function passed apart from the model):
    # Simpson's rule, which RK4 is on ẏ = f(t), is exact for cubics, so v = t⁴/4 to
    # round-off. x = t⁵/20 comes through the stages' v, to RK4's fourth order: halving
    # the step divides its error by 2⁴ (16.0 to 1e-3 here; asserted to 2 %).
    errors = []
    for steps in (100, 200):
        x, v = _tuple_steps(_cubic_force, (0.0, 0.0), 1.0 / steps, steps, (0.0,))
        assert v == pytest.approx(0.25, rel=1e-14)
        errors.append(x - 1.0 / 20.0)
    assert errors[0] / errors[1] == pytest.approx(16.0, rel=0.02)
