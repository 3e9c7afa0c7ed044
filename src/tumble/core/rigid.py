"""Euler's equations and the attitude quaternion, stepped by compiled integrators.

State, in the body's **principal** frame (inertia diag(I1, I2, I3)):

* ``w`` (3,): angular velocity in principal-body coordinates, rad/s;
* ``q`` (4,): unit quaternion ``[w, x, y, z]`` rotating principal-body
  coordinates into space coordinates.

Equations: ``I ω̇ + ω × (I ω) = τ`` (Euler; in the principal frame
``I1 ω̇1 + (I3 − I2) ω2 ω3 = τ1`` and cyclic) and ``q̇ = ½ q ⊗ (0, ω)``.

Torque, in principal-body coordinates, from a packed parameter vector
``params`` (``N_TORQUE_PARAMS`` floats, so sums of models cost nothing):

    τ = τ_body + Aᵀ τ_space + r × (Aᵀ F) − c ω

with A the attitude matrix, ``τ_body = params[0:3]`` (N·m, body),
``τ_space = params[3:6]`` (N·m, space), ``r = params[6:9]`` (m, body: from the
pivot to the centre of mass), ``F = params[9:12]`` (N, space: the weight m g)
and ``c = params[12]`` (N·m·s, linear damping).
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit

N_TORQUE_PARAMS = 13

#: Status returned by the stepping kernels when every step stayed finite.
FINITE = -1


@njit
def rotate_to_body(q, v):  # type: ignore[no-untyped-def]
    """``Aᵀ v``: a space vector in body coordinates, for the unit quaternion q."""
    s = q[0]
    ux = -q[1]
    uy = -q[2]
    uz = -q[3]
    # v' = v + 2 s (u × v) + 2 u × (u × v), with u the conjugate's vector part.
    cx = uy * v[2] - uz * v[1]
    cy = uz * v[0] - ux * v[2]
    cz = ux * v[1] - uy * v[0]
    return (
        v[0] + 2.0 * (s * cx + uy * cz - uz * cy),
        v[1] + 2.0 * (s * cy + uz * cx - ux * cz),
        v[2] + 2.0 * (s * cz + ux * cy - uy * cx),
    )


@njit
def derivatives(w, q, inertia, params, dw, dq):  # type: ignore[no-untyped-def]
    """Write ω̇ (rad/s²) into ``dw`` and q̇ (1/s) into ``dq`` for the state (w, q)."""
    i1 = inertia[0]
    i2 = inertia[1]
    i3 = inertia[2]
    space = (params[3], params[4], params[5])
    force = (params[9], params[10], params[11])
    ts = rotate_to_body(q, space)
    fb = rotate_to_body(q, force)
    rx = params[6]
    ry = params[7]
    rz = params[8]
    c = params[12]
    t1 = params[0] + ts[0] + (ry * fb[2] - rz * fb[1]) - c * w[0]
    t2 = params[1] + ts[1] + (rz * fb[0] - rx * fb[2]) - c * w[1]
    t3 = params[2] + ts[2] + (rx * fb[1] - ry * fb[0]) - c * w[2]
    dw[0] = (t1 - (i3 - i2) * w[1] * w[2]) / i1
    dw[1] = (t2 - (i1 - i3) * w[2] * w[0]) / i2
    dw[2] = (t3 - (i2 - i1) * w[0] * w[1]) / i3
    # q̇ = ½ q ⊗ (0, ω)
    dq[0] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2])
    dq[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
    dq[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2])
    dq[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])


@njit
def rk4_run(w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q):  # type: ignore[no-untyped-def]
    """Advance (w, q) in place by ``n_steps`` classical Runge–Kutta steps of ``dt`` s.

    The quaternion is renormalised after every step. After global step
    ``first_step + k + 1`` (k = 0 … n_steps − 1), if that number is a multiple
    of ``record_every``, the state is written to row ``number // record_every``
    of ``out_w`` (·, 3) and ``out_q`` (·, 4).

    Returns
    -------
    ``FINITE`` (−1) if every step stayed finite, else the global number of the
    first step that produced a NaN or an infinity (the state is left as it was
    before that step).
    """
    k1w = np.empty(3)
    k2w = np.empty(3)
    k3w = np.empty(3)
    k4w = np.empty(3)
    k1q = np.empty(4)
    k2q = np.empty(4)
    k3q = np.empty(4)
    k4q = np.empty(4)
    tw = np.empty(3)
    tq = np.empty(4)
    half = 0.5 * dt
    sixth = dt / 6.0
    for k in range(n_steps):
        derivatives(w, q, inertia, params, k1w, k1q)
        for i in range(3):
            tw[i] = w[i] + half * k1w[i]
        for i in range(4):
            tq[i] = q[i] + half * k1q[i]
        derivatives(tw, tq, inertia, params, k2w, k2q)
        for i in range(3):
            tw[i] = w[i] + half * k2w[i]
        for i in range(4):
            tq[i] = q[i] + half * k2q[i]
        derivatives(tw, tq, inertia, params, k3w, k3q)
        for i in range(3):
            tw[i] = w[i] + dt * k3w[i]
        for i in range(4):
            tq[i] = q[i] + dt * k3q[i]
        derivatives(tw, tq, inertia, params, k4w, k4q)
        for i in range(3):
            tw[i] = w[i] + sixth * (k1w[i] + 2.0 * (k2w[i] + k3w[i]) + k4w[i])
        norm = 0.0
        for i in range(4):
            tq[i] = q[i] + sixth * (k1q[i] + 2.0 * (k2q[i] + k3q[i]) + k4q[i])
            norm += tq[i] * tq[i]
        norm = math.sqrt(norm)
        if not (math.isfinite(norm) and math.isfinite(tw[0] + tw[1] + tw[2]) and norm > 0.0):
            return first_step + k + 1
        for i in range(3):
            w[i] = tw[i]
        for i in range(4):
            q[i] = tq[i] / norm
        step = first_step + k + 1
        if step % record_every == 0:
            row = step // record_every
            for i in range(3):
                out_w[row, i] = w[i]
            for i in range(4):
                out_q[row, i] = q[i]
    return FINITE
