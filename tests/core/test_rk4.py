"""The RK4 step in the stepping kernels, and the equations of motion on small cases (also run with
NUMBA_DISABLE_JIT=1)."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

from tumble.core import stepping
from tumble.core._jit import FINITE
from tumble.core.dynamics import rotate_to_body
from tumble.core.rk4 import rk4_step
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
