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

import numba
import numpy as np
from numba import types

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


@njit(inline="always")
def no_extra_torque(t, w1, w2, w3, q0, q1, q2, q3, context):  # type: ignore[no-untyped-def]
    """The extra-torque hook when there is none: zero, folded away by the compiler."""
    return 0.0, 0.0, 0.0


#: The C signature a user's torque function is compiled to (see
#: :func:`compile_user_torque`): t, ω (3,), q (4,), params (n,), n, out (3,).
USER_TORQUE_SIGNATURE = types.void(
    types.float64,
    types.CPointer(types.float64),
    types.CPointer(types.float64),
    types.CPointer(types.float64),
    types.intp,
    types.CPointer(types.float64),
)


def compile_user_torque(function):  # type: ignore[no-untyped-def]
    """A C callback (``numba.cfunc``) around a user's torque function.

    ``function(t, omega, quaternion, params, out)`` is compiled with
    ``numba.njit`` and takes arrays; the callback takes pointers, so every
    user function has the same type and the hooked kernels compile (and are
    cached) once for all of them, each new function costing only its own
    compilation (a fraction of a second).
    """

    if numba.config.DISABLE_JIT:  # type: ignore[attr-defined]
        return _python_callback(function)

    @numba.cfunc(USER_TORQUE_SIGNATURE)
    def callback(t, omega, quaternion, params, n_params, out):  # type: ignore[no-untyped-def]
        function(
            t,
            numba.carray(omega, 3),
            numba.carray(quaternion, 4),
            numba.carray(params, n_params),
            numba.carray(out, 3),
        )

    return callback


def _python_callback(function):  # type: ignore[no-untyped-def]
    """The callback as plain Python (``NUMBA_DISABLE_JIT=1``): the hook then
    passes ``ndarray.ctypes`` objects, read back here as arrays."""
    import ctypes

    def view(pointer, n):  # type: ignore[no-untyped-def]
        return np.ctypeslib.as_array(
            ctypes.cast(pointer.data, ctypes.POINTER(ctypes.c_double)), (n,)
        )

    def callback(t, omega, quaternion, params, n_params, out):  # type: ignore[no-untyped-def]
        function(t, view(omega, 3), view(quaternion, 4), view(params, n_params), view(out, 3))

    return callback


@njit(inline="always")
def user_torque_hook(t, w1, w2, w3, q0, q1, q2, q3, context):  # type: ignore[no-untyped-def]
    """The extra-torque hook that calls a user's torque function.

    ``context`` is the tuple ``(axes, axes_quaternion, params, omega,
    quaternion, out, callback)``: the principal axes as columns in body
    coordinates (3, 3), the same rotation as a quaternion (principal → body),
    the user's params, three scratch arrays and the callback from
    :func:`compile_user_torque`. The hook converts the state from the
    principal frame to the body axes and the torque back.
    """
    axes, axes_q, params, omega, quaternion, out, callback = context
    for i in range(3):
        omega[i] = axes[i, 0] * w1 + axes[i, 1] * w2 + axes[i, 2] * w3
    # body → space = (principal → space) ⊗ (body → principal)
    a0, a1, a2, a3 = axes_q[0], -axes_q[1], -axes_q[2], -axes_q[3]
    quaternion[0] = q0 * a0 - q1 * a1 - q2 * a2 - q3 * a3
    quaternion[1] = q0 * a1 + q1 * a0 + q2 * a3 - q3 * a2
    quaternion[2] = q0 * a2 - q1 * a3 + q2 * a0 + q3 * a1
    quaternion[3] = q0 * a3 + q1 * a2 - q2 * a1 + q3 * a0
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    callback(t, omega.ctypes, quaternion.ctypes, params.ctypes, params.size, out.ctypes)
    return (
        axes[0, 0] * out[0] + axes[1, 0] * out[1] + axes[2, 0] * out[2],
        axes[0, 1] * out[0] + axes[1, 1] * out[1] + axes[2, 1] * out[2],
        axes[0, 2] * out[0] + axes[1, 2] * out[1] + axes[2, 2] * out[2],
    )


@njit
def derivatives(w, q, inertia, params, dw, dq):  # type: ignore[no-untyped-def]
    """Write ω̇ (rad/s²) into ``dw`` and q̇ (1/s) into ``dq`` for the state (w, q)."""
    rates = _rates(
        0.0, w[0], w[1], w[2], q[0], q[1], q[2], q[3], inertia[0], inertia[1], inertia[2],
        params, True, no_extra_torque, 0.0,
    )  # fmt: skip
    for i in range(3):
        dw[i] = rates[i]
    for i in range(4):
        dq[i] = rates[3 + i]


@njit(inline="always")
def applied_torque(q0, q1, q2, q3, params, attitude_torque):  # type: ignore[no-untyped-def]
    """The packed torque without damping, principal-body coordinates (N·m):
    ``τ_body + Aᵀ τ_space + r × (Aᵀ F)``; ``attitude_torque`` False skips the
    terms that depend on the attitude."""
    t1 = params[0]
    t2 = params[1]
    t3 = params[2]
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
def _torque(t, w1, w2, w3, q0, q1, q2, q3, params, attitude_torque, extra, context):  # type: ignore[no-untyped-def]
    """The whole torque in principal-body coordinates (N·m): the packed terms,
    damping ``−c ω`` and the extra hook's torque."""
    t1, t2, t3 = applied_torque(q0, q1, q2, q3, params, attitude_torque)
    e1, e2, e3 = extra(t, w1, w2, w3, q0, q1, q2, q3, context)
    c = params[12]
    return t1 + e1 - c * w1, t2 + e2 - c * w2, t3 + e3 - c * w3


@njit(inline="always")
def _rates(t, w1, w2, w3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context):  # type: ignore[no-untyped-def]
    """(ω̇1, ω̇2, ω̇3, q̇0, q̇1, q̇2, q̇3) as scalars at time ``t``."""
    t1, t2, t3 = _torque(t, w1, w2, w3, q0, q1, q2, q3, params, attitude_torque, extra, context)
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
    """As :func:`_rates` without the extra hook, with ``c1 = (I2 − I3)/I1``
    (cyclic) and ``r = 1/I`` precomputed: multiplications only, which vectorise
    across bodies."""
    t1, t2, t3 = applied_torque(q0, q1, q2, q3, params, attitude_torque)
    c = params[12]
    t1 -= c * w1
    t2 -= c * w2
    t3 -= c * w3
    return (
        t1 * r1 + c1 * w2 * w3,
        t2 * r2 + c2 * w3 * w1,
        t3 * r3 + c3 * w1 * w2,
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    )


@njit(inline="always")
def has_attitude_torque(params):  # type: ignore[no-untyped-def]
    """True when the packed torque has terms that depend on the attitude."""
    for k in range(3, 12):  # noqa: SIM110 (a loop numba compiles without a generator)
        if params[k] != 0.0:
            return True
    return False


@njit(inline="always")
def any_attitude_torque(params):  # type: ignore[no-untyped-def]
    """True when some column of (N_TORQUE_PARAMS, M) packed torques depends on
    the attitude."""
    found = False
    for column in range(params.shape[1]):
        if has_attitude_torque(params[:, column]):
            found = True
    return found


@njit(inline="always")
def _record(step, record_every, out_w, out_q, w1, w2, w3, q0, q1, q2, q3):  # type: ignore[no-untyped-def]
    """Write the state to row ``step // record_every`` when ``step`` is a multiple."""
    if step % record_every == 0:
        row = step // record_every
        out_w[row, 0] = w1
        out_w[row, 1] = w2
        out_w[row, 2] = w3
        out_q[row, 0] = q0
        out_q[row, 1] = q1
        out_q[row, 2] = q2
        out_q[row, 3] = q3


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
    return _rk4_loop(
        w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q,
        no_extra_torque, 0.0,
    )  # fmt: skip


@njit
def rk4_run_hooked(  # type: ignore[no-untyped-def]
    w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, context
):
    """:func:`rk4_run` with a user's torque added (``context`` as in
    :func:`user_torque_hook`); the time of global step k is ``k dt``."""
    return _rk4_loop(
        w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q,
        user_torque_hook, context,
    )  # fmt: skip


@njit(inline="always")
def _rk4_loop(  # type: ignore[no-untyped-def]
    w, q, inertia, params, dt, n_steps, first_step, record_every, out_w, out_q, extra, context
):
    i1 = inertia[0]
    i2 = inertia[1]
    i3 = inertia[2]
    attitude_torque = has_attitude_torque(params)
    w1, w2, w3 = w[0], w[1], w[2]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    h = 0.5 * dt
    sixth = dt / 6.0
    for k in range(n_steps):
        t = (first_step + k) * dt
        a = _rates(
            t, w1, w2, w3, q0, q1, q2, q3, i1, i2, i3, params, attitude_torque, extra, context
        )
        b = _rates(
            t + h, w1 + h * a[0], w2 + h * a[1], w3 + h * a[2],
            q0 + h * a[3], q1 + h * a[4], q2 + h * a[5], q3 + h * a[6],
            i1, i2, i3, params, attitude_torque, extra, context,
        )  # fmt: skip
        c = _rates(
            t + h, w1 + h * b[0], w2 + h * b[1], w3 + h * b[2],
            q0 + h * b[3], q1 + h * b[4], q2 + h * b[5], q3 + h * b[6],
            i1, i2, i3, params, attitude_torque, extra, context,
        )  # fmt: skip
        d = _rates(
            t + dt, w1 + dt * c[0], w2 + dt * c[1], w3 + dt * c[2],
            q0 + dt * c[3], q1 + dt * c[4], q2 + dt * c[5], q3 + dt * c[6],
            i1, i2, i3, params, attitude_torque, extra, context,
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
        _record(first_step + k + 1, record_every, out_w, out_q, w1, w2, w3, q0, q1, q2, q3)
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
    moments; ``params`` (``N_TORQUE_PARAMS``, M) the packed torque, shared
    (M = 1) or one column per body (M = N). A body whose state became NaN or
    infinite keeps that state; the caller checks (fast-math may not keep a
    finiteness test inside the kernel).
    """
    n = w.shape[1]
    n_blocks = (n + BLOCK - 1) // BLOCK
    attitude_torque = any_attitude_torque(params)
    for block in prange(n_blocks):
        start = block * BLOCK
        stop = min(start + BLOCK, n)
        m = stop - start
        w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3 = load_block(w, q, inertia, start, stop)
        block_params = _block_params(params, start, m)
        if attitude_torque:
            _steps_block(
                w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, block_params, dt, n_steps,
                True,
            )  # fmt: skip
        else:
            _steps_block(
                w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, block_params, dt, n_steps,
                False,
            )  # fmt: skip
        for j in range(m):
            w[0, start + j] = w1[j]
            w[1, start + j] = w2[j]
            w[2, start + j] = w3[j]
            q[0, start + j] = q0[j]
            q[1, start + j] = q1[j]
            q[2, start + j] = q2[j]
            q[3, start + j] = q3[j]


@njit(inline="always")
def load_block(w, q, inertia, start, stop):  # type: ignore[no-untyped-def]
    """Copies of the states of bodies ``start:stop`` (ω1, ω2, ω3, q0 … q3) and
    their coefficients ``c1 = (I2 − I3)/I1`` (cyclic) and ``r = 1/I``, as the
    block's own arrays (they stay in L1 cache through its steps)."""
    i1 = inertia[0, start:stop]
    i2 = inertia[1, start:stop]
    i3 = inertia[2, start:stop]
    return (
        w[0, start:stop].copy(), w[1, start:stop].copy(), w[2, start:stop].copy(),
        q[0, start:stop].copy(), q[1, start:stop].copy(), q[2, start:stop].copy(),
        q[3, start:stop].copy(),
        (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3, 1.0 / i1, 1.0 / i2, 1.0 / i3,
    )  # fmt: skip


@njit(inline="always")
def _block_params(params, start, m):  # type: ignore[no-untyped-def]
    """The packed torque of a block's bodies as (N_TORQUE_PARAMS, m), from
    shared (one column) or per-body params."""
    out = np.empty((N_TORQUE_PARAMS, m))
    shared = params.shape[1] == 1
    for k in range(N_TORQUE_PARAMS):
        for j in range(m):
            out[k, j] = params[k, 0] if shared else params[k, start + j]
    return out


@njit(inline="always")
def _column(p, j):  # type: ignore[no-untyped-def]
    """Column j of the block's params as a tuple (kept in registers)."""
    return (
        p[0, j], p[1, j], p[2, j], p[3, j], p[4, j], p[5, j], p[6, j], p[7, j], p[8, j],
        p[9, j], p[10, j], p[11, j], p[12, j],
    )  # fmt: skip


@njit(inline="always")
def _steps_block(  # type: ignore[no-untyped-def]
    w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt, n_steps, attitude_torque
):
    """RK4 steps for one block of bodies (arrays of its states), in place; called
    with a literal ``attitude_torque`` so the torque-free loop has no branch."""
    m = w1.shape[0]
    for _ in range(n_steps):
        for j in range(m):
            rk4_body_step(
                j, w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt,
                attitude_torque,
            )  # fmt: skip


@njit(inline="always")
def rk4_body_step(  # type: ignore[no-untyped-def]
    j, w1, w2, w3, q0, q1, q2, q3, c1, c2, c3, r1, r2, r3, params, dt, attitude_torque
):
    """One RK4 step of body j of a block (arrays of the block's states and
    coefficients, ``params`` (N_TORQUE_PARAMS, m)), in place; the quaternion
    renormalised. Inlined into the loops over a block's bodies, which the
    compiler vectorises."""
    h = 0.5 * dt
    sixth = dt / 6.0
    p = _column(params, j)
    a = _rates_fast(
        w1[j], w2[j], w3[j], q0[j], q1[j], q2[j], q3[j],
        c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], p, attitude_torque,
    )  # fmt: skip
    b = _rates_fast(
        w1[j] + h * a[0], w2[j] + h * a[1], w3[j] + h * a[2],
        q0[j] + h * a[3], q1[j] + h * a[4], q2[j] + h * a[5], q3[j] + h * a[6],
        c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], p, attitude_torque,
    )  # fmt: skip
    c = _rates_fast(
        w1[j] + h * b[0], w2[j] + h * b[1], w3[j] + h * b[2],
        q0[j] + h * b[3], q1[j] + h * b[4], q2[j] + h * b[5], q3[j] + h * b[6],
        c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], p, attitude_torque,
    )  # fmt: skip
    d = _rates_fast(
        w1[j] + dt * c[0], w2[j] + dt * c[1], w3[j] + dt * c[2],
        q0[j] + dt * c[3], q1[j] + dt * c[4], q2[j] + dt * c[5], q3[j] + dt * c[6],
        c1[j], c2[j], c3[j], r1[j], r2[j], r3[j], p, attitude_torque,
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
