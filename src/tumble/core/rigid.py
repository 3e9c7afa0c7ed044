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

from tumble.core._jit import njit, njit_vector, prange

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
    rates = _rates(
        w[0], w[1], w[2], q[0], q[1], q[2], q[3], inertia[0], inertia[1], inertia[2], params, True
    )
    for i in range(3):
        dw[i] = rates[i]
    for i in range(4):
        dq[i] = rates[3 + i]


@njit(inline="always")
def _torque(w1, w2, w3, q0, q1, q2, q3, params, attitude_torque):  # type: ignore[no-untyped-def]
    """Torque in principal-body coordinates (N·m) from the packed ``params``;
    ``attitude_torque`` False skips the terms that depend on the attitude."""
    t1 = params[0] - params[12] * w1
    t2 = params[1] - params[12] * w2
    t3 = params[2] - params[12] * w3
    if attitude_torque:
        ts = rotate_to_body((q0, q1, q2, q3), (params[3], params[4], params[5]))
        fb = rotate_to_body((q0, q1, q2, q3), (params[9], params[10], params[11]))
        rx = params[6]
        ry = params[7]
        rz = params[8]
        t1 += ts[0] + (ry * fb[2] - rz * fb[1])
        t2 += ts[1] + (rz * fb[0] - rx * fb[2])
        t3 += ts[2] + (rx * fb[1] - ry * fb[0])
    return t1, t2, t3


@njit(inline="always")
def _rates(w1, w2, w3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque):  # type: ignore[no-untyped-def]
    """(ω̇1, ω̇2, ω̇3, q̇0, q̇1, q̇2, q̇3) as scalars; ``attitude_torque`` False skips
    the torque terms that depend on the attitude (space torque, gravity)."""
    t1, t2, t3 = _torque(w1, w2, w3, q0, q1, q2, q3, params, attitude_torque)
    return (
        (t1 - (i3 - i2) * w2 * w3) / i1,
        (t2 - (i1 - i3) * w3 * w1) / i2,
        (t3 - (i2 - i1) * w1 * w2) / i3,
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    )


@njit(inline="always")
def _rates_fast(w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, attitude_torque):  # type: ignore[no-untyped-def]
    """As :func:`_rates`, with ``c1 = (I2 − I3)/I1`` (cyclic) and ``r = 1/I``
    precomputed: multiplications only, which vectorise across bodies."""
    t1, t2, t3 = _torque(w1, w2, w3, q0, q1, q2, q3, params, attitude_torque)
    return (
        t1 * r1 + c1 * w2 * w3,
        t2 * r2 + c2 * w3 * w1,
        t3 * r3 + c3 * w1 * w2,
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    )


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
    i1 = inertia[0]
    i2 = inertia[1]
    i3 = inertia[2]
    attitude_torque = False
    for k in range(3, 12):
        if params[k] != 0.0:
            attitude_torque = True
    w1, w2, w3 = w[0], w[1], w[2]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    h = 0.5 * dt
    sixth = dt / 6.0
    for k in range(n_steps):
        a = _rates(w1, w2, w3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque)
        b = _rates(
            w1 + h * a[0], w2 + h * a[1], w3 + h * a[2],
            q0 + h * a[3], q1 + h * a[4], q2 + h * a[5], q3 + h * a[6],
            i1, i2, i3, params, attitude_torque,
        )  # fmt: skip
        c = _rates(
            w1 + h * b[0], w2 + h * b[1], w3 + h * b[2],
            q0 + h * b[3], q1 + h * b[4], q2 + h * b[5], q3 + h * b[6],
            i1, i2, i3, params, attitude_torque,
        )  # fmt: skip
        d = _rates(
            w1 + dt * c[0], w2 + dt * c[1], w3 + dt * c[2],
            q0 + dt * c[3], q1 + dt * c[4], q2 + dt * c[5], q3 + dt * c[6],
            i1, i2, i3, params, attitude_torque,
        )  # fmt: skip
        n1 = w1 + sixth * (a[0] + 2.0 * (b[0] + c[0]) + d[0])
        n2 = w2 + sixth * (a[1] + 2.0 * (b[1] + c[1]) + d[1])
        n3 = w3 + sixth * (a[2] + 2.0 * (b[2] + c[2]) + d[2])
        p0 = q0 + sixth * (a[3] + 2.0 * (b[3] + c[3]) + d[3])
        p1 = q1 + sixth * (a[4] + 2.0 * (b[4] + c[4]) + d[4])
        p2 = q2 + sixth * (a[5] + 2.0 * (b[5] + c[5]) + d[5])
        p3 = q3 + sixth * (a[6] + 2.0 * (b[6] + c[6]) + d[6])
        norm = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
        if not (math.isfinite(norm) and math.isfinite(n1 + n2 + n3) and norm > 0.0):
            w[0], w[1], w[2] = w1, w2, w3
            q[0], q[1], q[2], q[3] = q0, q1, q2, q3
            return first_step + k + 1
        w1, w2, w3 = n1, n2, n3
        q0, q1, q2, q3 = p0 / norm, p1 / norm, p2 / norm, p3 / norm
        step = first_step + k + 1
        if step % record_every == 0:
            row = step // record_every
            out_w[row, 0] = w1
            out_w[row, 1] = w2
            out_w[row, 2] = w3
            out_q[row, 0] = q0
            out_q[row, 1] = q1
            out_q[row, 2] = q2
            out_q[row, 3] = q3
    w[0], w[1], w[2] = w1, w2, w3
    q[0], q[1], q[2], q[3] = q0, q1, q2, q3
    return FINITE


#: Bodies per block of the batch kernel: a block's state and coefficients
#: (13 × 128 doubles, 13 kB) stay in L1 cache for all its steps, and the inner
#: loop over the block's bodies is what the compiler vectorises.
BLOCK = 128


@njit_vector
def rk4_batch(w, q, inertia, params, dt, n_steps):  # type: ignore[no-untyped-def]
    """Advance N bodies in place by ``n_steps`` RK4 steps of ``dt`` s, in parallel.

    Structure of arrays: ``w`` (3, N) principal-frame angular velocities,
    ``q`` (4, N) quaternions (principal → space), ``inertia`` (3, N) principal
    moments; ``params`` (``N_TORQUE_PARAMS``,) one torque shared by all bodies.
    A body whose state became NaN or infinite keeps that state; the caller
    checks (fast-math may not keep a finiteness test inside the kernel).
    """
    n = w.shape[1]
    n_blocks = (n + BLOCK - 1) // BLOCK
    attitude_torque = False
    for k in range(3, 12):
        if params[k] != 0.0:
            attitude_torque = True
    for block in prange(n_blocks):
        start = block * BLOCK
        stop = min(start + BLOCK, n)
        m = stop - start
        w1 = w[0, start:stop].copy()
        w2 = w[1, start:stop].copy()
        w3 = w[2, start:stop].copy()
        q0 = q[0, start:stop].copy()
        q1 = q[1, start:stop].copy()
        q2 = q[2, start:stop].copy()
        q3 = q[3, start:stop].copy()
        i1 = inertia[0, start:stop]
        i2 = inertia[1, start:stop]
        i3 = inertia[2, start:stop]
        c1 = (i2 - i3) / i1
        c2 = (i3 - i1) / i2
        c3 = (i1 - i2) / i3
        r1 = 1.0 / i1
        r2 = 1.0 / i2
        r3 = 1.0 / i3
        if attitude_torque:
            _steps_block(
                w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt, n_steps, True
            )
        else:
            _steps_block(
                w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt, n_steps, False
            )
        for j in range(m):
            w[0, start + j] = w1[j]
            w[1, start + j] = w2[j]
            w[2, start + j] = w3[j]
            q[0, start + j] = q0[j]
            q[1, start + j] = q1[j]
            q[2, start + j] = q2[j]
            q[3, start + j] = q3[j]


@njit(inline="always")
def _steps_block(  # type: ignore[no-untyped-def]
    w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt, n_steps, attitude_torque
):
    """RK4 steps for one block of bodies (arrays of its states), in place; called
    with a literal ``attitude_torque`` so the torque-free loop has no branch."""
    m = w1.shape[0]
    h = 0.5 * dt
    sixth = dt / 6.0
    for _ in range(n_steps):
        for j in range(m):
            a = _rates_fast(
                w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j],
                c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], params, attitude_torque,
            )  # fmt: skip
            b = _rates_fast(
                w1[j] + h * a[0], w2[j] + h * a[1], w3[j] + h * a[2],
                q0[j] + h * a[3], q1[j] + h * a[4], q2[j] + h * a[5], q3[j] + h * a[6],
                c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], params, attitude_torque,
            )  # fmt: skip
            c = _rates_fast(
                w1[j] + h * b[0], w2[j] + h * b[1], w3[j] + h * b[2],
                q0[j] + h * b[3], q1[j] + h * b[4], q2[j] + h * b[5], q3[j] + h * b[6],
                c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], params, attitude_torque,
            )  # fmt: skip
            d = _rates_fast(
                w1[j] + dt * c[0], w2[j] + dt * c[1], w3[j] + dt * c[2],
                q0[j] + dt * c[3], q1[j] + dt * c[4], q2[j] + dt * c[5], q3[j] + dt * c[6],
                c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], params, attitude_torque,
            )  # fmt: skip
            w1[j] += sixth * (a[0] + 2.0 * (b[0] + c[0]) + d[0])
            w2[j] += sixth * (a[1] + 2.0 * (b[1] + c[1]) + d[1])
            w3[j] += sixth * (a[2] + 2.0 * (b[2] + c[2]) + d[2])
            p0 = q0[j] + sixth * (a[3] + 2.0 * (b[3] + c[3]) + d[3])
            p1 = q1[j] + sixth * (a[4] + 2.0 * (b[4] + c[4]) + d[4])
            p2 = q2[j] + sixth * (a[5] + 2.0 * (b[5] + c[5]) + d[5])
            p3 = q3[j] + sixth * (a[6] + 2.0 * (b[6] + c[6]) + d[6])
            scale = 1.0 / math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3)
            q0[j] = p0 * scale
            q1[j] = p1 * scale
            q2[j] = p2 * scale
            q3[j] = p3 * scale
