"""An independent reference integration of a rigid body, for the oracle tests.

Euler's equations in the *body* axes with the full inertia tensor and the
attitude as a rotation matrix, integrated by scipy's DOP853 — written without
any of tumble's kernels (no principal frame, no quaternions), so an error in
either is not shared.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation


def reference(
    mp,
    omega0,
    q0,
    duration,
    pivot=None,
    gravity=(0.0, 0.0, 0.0),
    rtol=1e-13,
    torque: Callable | None = None,
    times=None,
):
    """Body ω and attitude matrix at ``duration`` (or at each of ``times``).

    I ω̇ = τ − ω × I ω about the centre of mass or the pivot, with
    τ = r × (Aᵀ m g) + torque(t, ω, A) (body axes), and Ȧ = A [ω]×.
    """
    inertia = mp.inertia if pivot is None else mp.inertia_about(pivot)
    inverse = np.linalg.inv(inertia)
    lever = np.zeros(3) if pivot is None else mp.center_of_mass - np.asarray(pivot)
    weight = mp.mass * np.asarray(gravity, dtype=float)

    def rhs(t, y):
        w = y[:3]
        a = y[3:].reshape(3, 3)
        tau = np.cross(lever, a.T @ weight)
        if torque is not None:
            tau = tau + torque(t, w, a)
        w_dot = inverse @ (tau - np.cross(w, inertia @ w))
        skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([w_dot, (a @ skew).ravel()])

    a0 = Rotation.from_quat(q0, scalar_first=True).as_matrix()
    sol = solve_ivp(
        rhs,
        (0, duration),
        np.concatenate([omega0, a0.ravel()]),
        method="DOP853",
        rtol=rtol,
        atol=1e-14,
        t_eval=times,
    )
    if times is not None:
        return sol.y[:3].T, sol.y[3:].T.reshape(-1, 3, 3)
    return sol.y[:3, -1], sol.y[3:, -1].reshape(3, 3)


def attitude_error(q, matrix) -> float:
    """Angle (rad) between quaternion rotations and rotation matrices (largest)."""
    return float(
        np.max(
            (
                Rotation.from_quat(q, scalar_first=True) * Rotation.from_matrix(matrix).inv()
            ).magnitude()
        )
    )
