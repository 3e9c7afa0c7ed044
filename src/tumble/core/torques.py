"""Compiled torque functions: one per torque model, all of one signature.

Each torque model of :mod:`tumble.torques` names one function here (a model
defined elsewhere, in a user's module or a test, brings its own)::

    @njit(inline="always")
    def kernel(t, w, q, params, row, column, context):
        ...
        return t1, t2, t3, c

* ``t``: time, s; ``w``: (ω1, ω2, ω3) angular velocity, rad/s, and ``q``:
  (q0, q1, q2, q3) unit quaternion turning principal-body coordinates into
  space coordinates, both tuples in the body's principal frame;
* ``params`` (rows, columns): the packed parameters of every model of the
  simulation; this model's fields are the rows ``row``, ``row + 1``, … in the
  order its class lists them (:attr:`tumble.torques.TorqueModel.fields`);
  ``column`` is the body's column (0 when all bodies share the values);
* ``context``: the simulation's one non-numeric argument (the user-torque
  callback of :func:`user_torque`), 0.0 when there is none.

It returns the torque on the body as ``τ − c ω`` (N·m, principal-body axes):
``(τ1, τ2, τ3)`` and ``c`` (N·m·s), the part linear in ω of an isotropic viscous
damping, which the splitting integrators integrate exactly; any other
dependence on ω goes into τ.

:func:`combine` turns the models of one simulation into a single function of
the same signature without ``row``, which the integrator factories close over.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from tumble.core._jit import njit
from tumble.core.dynamics import free_torque, rotate_to_body


@njit(inline="always")
def constant_body_torque(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """A torque fixed in the body; fields τ1, τ2, τ3 (N·m, principal axes)."""
    return params[row, column], params[row + 1, column], params[row + 2, column], 0.0


@njit(inline="always")
def constant_space_torque(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """A torque fixed in space; fields τx, τy, τz (N·m, space axes): ``Aᵀ τ``."""
    space = (params[row, column], params[row + 1, column], params[row + 2, column])
    t1, t2, t3 = rotate_to_body(q, space)
    return t1, t2, t3, 0.0


@njit(inline="always")
def gravity_about_pivot(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """The weight acting at the centre of mass, about the pivot: ``r × (Aᵀ W)``;
    fields r1, r2, r3 (m, principal axes: pivot → centre of mass) and Wx, Wy, Wz
    (N, space axes: m g)."""
    r1 = params[row, column]
    r2 = params[row + 1, column]
    r3 = params[row + 2, column]
    weight = (params[row + 3, column], params[row + 4, column], params[row + 5, column])
    f1, f2, f3 = rotate_to_body(q, weight)
    return r2 * f3 - r3 * f2, r3 * f1 - r1 * f3, r1 * f2 - r2 * f1, 0.0


@njit(inline="always")
def linear_damping(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """Viscous damping ``−c ω``; field c (N·m·s)."""
    return 0.0, 0.0, 0.0, params[row, column]


@njit(inline="always")
def gravity_gradient(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """The gravity-gradient torque of a circular orbit, ``3 n² r × (I r)`` about the
    centre of mass, r the unit vector from the planet's centre to the body in
    principal axes (Hughes, *Spacecraft Attitude Dynamics*, §8.1); fields n
    (rad/s), e1 and e2 (space axes: r = e1 cos n t + e2 sin n t) and the whole
    inertia I in the kernels' axes (kg·m²: I11, I22, I33, I12, I13, I23; diagonal
    for a body without parts, whose kernels use its principal axes)."""
    n = params[row, column]
    c = math.cos(n * t)
    s = math.sin(n * t)
    space = (
        c * params[row + 1, column] + s * params[row + 4, column],
        c * params[row + 2, column] + s * params[row + 5, column],
        c * params[row + 3, column] + s * params[row + 6, column],
    )
    r1, r2, r3 = rotate_to_body(q, space)
    i12 = params[row + 10, column]
    i13 = params[row + 11, column]
    i23 = params[row + 12, column]
    k = 3.0 * n * n
    m1 = params[row + 7, column] * r1 + i12 * r2 + i13 * r3
    m2 = i12 * r1 + params[row + 8, column] * r2 + i23 * r3
    m3 = i13 * r1 + i23 * r2 + params[row + 9, column] * r3
    return k * (r2 * m3 - r3 * m2), k * (r3 * m1 - r1 * m3), k * (r1 * m2 - r2 * m1), 0.0


# ------------------------------------------------------------------ user functions
#: The C signature a user's torque function is compiled to (see
#: :func:`tumble.core.torques.compile_user_torque`): t, ω (3,), q (4,), params (n,),
#: n, out (3,).
USER_TORQUE_SIGNATURE = numba.types.void(
    numba.types.float64,
    numba.types.CPointer(numba.types.float64),
    numba.types.CPointer(numba.types.float64),
    numba.types.CPointer(numba.types.float64),
    numba.types.intp,
    numba.types.CPointer(numba.types.float64),
)


def compile_user_torque(function):  # type: ignore[no-untyped-def]
    """A C callback (``numba.cfunc``) around a user's torque function.

    ``function(t, omega, quaternion, params, out)`` is compiled with
    ``numba.njit`` and takes arrays; the callback takes pointers, so every user
    function has the same type and the kernels compile (and are cached) once
    for all of them, each new function costing only its own compilation.
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
    """The callback as plain Python (``NUMBA_DISABLE_JIT=1``): the kernel then
    passes ``ndarray.ctypes`` objects, read back here as arrays."""
    import ctypes

    def view(pointer, n):  # type: ignore[no-untyped-def]
        return np.ctypeslib.as_array(
            ctypes.cast(pointer.data, ctypes.POINTER(ctypes.c_double)), (n,)
        )

    def callback(t, omega, quaternion, params, n_params, out):  # type: ignore[no-untyped-def]
        function(t, view(omega, 3), view(quaternion, 4), view(params, n_params), view(out, 3))

    return callback


def compile_user_potential(potential):  # type: ignore[no-untyped-def]
    """A compiled loop ``energies(t, quaternion, params, out)`` that fills ``out``
    (n,) with a user's potential energy, J, at each sample.

    ``potential(t, quaternion, params) -> float`` is compiled with
    ``numba.njit``; ``t`` (n,) s, ``quaternion`` (n, 4) C-contiguous unit
    quaternions ``[w, x, y, z]`` (body → space, the user's body axes) and
    ``params`` (k,) are passed through, one row of ``quaternion`` per call, so
    a trajectory's energy costs one compiled pass rather than a Python call per
    sample.
    """

    def energies(t, quaternion, params, out):  # type: ignore[no-untyped-def]
        for i in range(t.size):
            out[i] = potential(t[i], quaternion[i], params)

    if numba.config.DISABLE_JIT:  # type: ignore[attr-defined]
        return energies
    # Not cached on disk: the closure holds the user's function, compiled per process.
    return numba.njit(cache=False, nogil=True, error_model="numpy")(energies)


@njit(inline="always")
def user_torque(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """A user's torque function, called through its callback.

    ``context`` is the tuple ``(axes, axes_quaternion, user_params, omega,
    quaternion, out, callback)``: the principal axes as columns in body
    coordinates (3, 3), the same rotation as a quaternion (principal → body),
    the user's params, three scratch arrays and the callback from
    :func:`tumble.core.torques.compile_user_torque`. The state is turned from the
    principal frame into the user's body axes, and the torque back.
    """
    axes, axes_q, user_params, omega, quaternion, out, callback = context
    w1, w2, w3 = w
    q0, q1, q2, q3 = q
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
    callback(t, omega.ctypes, quaternion.ctypes, user_params.ctypes, user_params.size, out.ctypes)
    return (
        axes[0, 0] * out[0] + axes[1, 0] * out[1] + axes[2, 0] * out[2],
        axes[0, 1] * out[0] + axes[1, 1] * out[1] + axes[2, 1] * out[2],
        axes[0, 2] * out[0] + axes[1, 2] * out[1] + axes[2, 2] * out[2],
        0.0,
    )


# ------------------------------------------------------------------ one simulation's torque
def combine(terms):  # type: ignore[no-untyped-def]
    """One compiled torque function ``torque(t, w, q, params, column, context)`` for
    ``terms``, a sequence of ``(kernel, row)``: the sum of each kernel reading its
    fields from ``row`` on. The kernels and rows are constants of the closures
    built here, so the compiler inlines every term (and folds away zeros); no
    terms give :func:`~tumble.core.dynamics.free_torque`."""
    if not terms:
        return free_torque  # recognised by tumble.core.dynamics.rates
    combined = _bound(*terms[0])
    for kernel, row in terms[1:]:
        combined = _sum(combined, _bound(kernel, row))
    return combined


def _bound(kernel, row):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def bound(t, w, q, params, column, context):  # type: ignore[no-untyped-def]
        return kernel(t, w, q, params, row, column, context)

    return bound


def _sum(first, second):  # type: ignore[no-untyped-def]
    @njit(inline="always", cache=False)
    def both(t, w, q, params, column, context):  # type: ignore[no-untyped-def]
        a = first(t, w, q, params, column, context)
        b = second(t, w, q, params, column, context)
        return a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]

    return both


@njit(inline="always")
def attitude_feedback(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """Quaternion feedback toward a target attitude, ``τ = −K ε − C ω``, its
    magnitude clipped to a largest torque (Wie, Weiss & Arapostathis, J. Guid.
    Control Dyn. 12 (1989) 375). ε is the vector part of the error quaternion
    ``q_target⁻¹ ⊗ q`` (principal axes), its sign chosen so its scalar part is
    >= 0 (the shorter way round). Fields: the target (q0, q1, q2, q3;
    principal → space), K (N·m), C (N·m·s) and the largest torque (N·m)."""
    a0 = params[row, column]
    a1 = -params[row + 1, column]
    a2 = -params[row + 2, column]
    a3 = -params[row + 3, column]
    q0, q1, q2, q3 = q
    e0 = a0 * q0 - a1 * q1 - a2 * q2 - a3 * q3
    e1 = a0 * q1 + a1 * q0 + a2 * q3 - a3 * q2
    e2 = a0 * q2 - a1 * q3 + a2 * q0 + a3 * q1
    e3 = a0 * q3 + a1 * q2 - a2 * q1 + a3 * q0
    stiffness = params[row + 4, column] if e0 >= 0.0 else -params[row + 4, column]
    damping = params[row + 5, column]
    t1 = -stiffness * e1 - damping * w[0]
    t2 = -stiffness * e2 - damping * w[1]
    t3 = -stiffness * e3 - damping * w[2]
    size = math.sqrt(t1 * t1 + t2 * t2 + t3 * t3)
    largest = params[row + 6, column]
    if size > largest:
        scale = largest / size
        t1 *= scale
        t2 *= scale
        t3 *= scale
    return t1, t2, t3, 0.0


@njit(inline="always")
def rotor_momentum(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """Rotors whose momentum relative to the body is prescribed, ``h(t) = h0 + ḣ t``
    (principal axes): on the body, the torque ``−ω × h − ḣ`` (N·m). Fields h0 (3,
    kg·m²/s) and ḣ (3, N·m)."""
    h1 = params[row, column] + params[row + 3, column] * t
    h2 = params[row + 1, column] + params[row + 4, column] * t
    h3 = params[row + 2, column] + params[row + 5, column] * t
    w1, w2, w3 = w
    return (
        -(w2 * h3 - w3 * h2) - params[row + 3, column],
        -(w3 * h1 - w1 * h3) - params[row + 4, column],
        -(w1 * h2 - w2 * h1) - params[row + 5, column],
        0.0,
    )


@njit(inline="always")
def _per_axis_drag(w, params, row, column, quadratic):  # type: ignore[no-untyped-def]
    """``−Σᵢ cᵢ uᵢ eᵢ`` (or ``−Σᵢ cᵢ uᵢ |uᵢ| eᵢ`` when ``quadratic``), ``uᵢ = eᵢ · ω``
    the rate about body axis i: fields c1, c2, c3 and then e1, e2, e3, the body's
    own axes in principal coordinates (three components each)."""
    t1 = 0.0
    t2 = 0.0
    t3 = 0.0
    for i in range(3):
        base = row + 3 + 3 * i
        e1 = params[base, column]
        e2 = params[base + 1, column]
        e3 = params[base + 2, column]
        rate = e1 * w[0] + e2 * w[1] + e3 * w[2]
        size = params[row + i, column] * (rate * abs(rate) if quadratic else rate)
        t1 -= size * e1
        t2 -= size * e2
        t3 -= size * e3
    return t1, t2, t3


@njit(inline="always")
def axis_drag(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """Linear drag about each body axis, ``τᵢ = −cᵢ ωᵢ`` in body axes, turned into
    principal axes; fields c1, c2, c3 (N·m·s) and the body axes e1, e2, e3 in
    principal coordinates."""
    t1, t2, t3 = _per_axis_drag(w, params, row, column, False)
    return t1, t2, t3, 0.0


@njit(inline="always")
def quadratic_axis_drag(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """Quadratic drag about each body axis, ``τᵢ = −cᵢ ωᵢ |ωᵢ|`` in body axes, turned
    into principal axes; fields c1, c2, c3 (N·m·s²) and the body axes e1, e2, e3
    in principal coordinates."""
    t1, t2, t3 = _per_axis_drag(w, params, row, column, True)
    return t1, t2, t3, 0.0
