"""Peer implementations the benchmark scripts run beside tumble.

Two cases, each as a MuJoCo model (MJCF written here, no files) and as a scipy
``solve_ivp`` reference (Euler's equations and quaternion kinematics written out):

* a torque-free body with principal moments ``I`` (free joint, no gravity, no
  damping, no contacts);
* the heavy gyroscope: a thin disk on a ball joint at a pivot on its symmetry
  axis, under gravity (:class:`Top`).

Conventions, as in tumble: quaternions scalar-first ``[w, x, y, z]``, rotating
body coordinates into space coordinates; angular velocity ω in body axes;
``q̇ = ½ q ⊗ (0, ω)``. MuJoCo uses the same quaternion convention (``qpos`` of a
free or ball joint, ``xquat``), and the angular part of a free or ball joint's
``qvel`` is ω in the body (local) frame (:func:`mujoco_free_body_frame_check`
measures it). When a state becomes NaN or huge MuJoCo prints a warning, resets
the data to the model's initial state and time 0, and goes on stepping: the
runs here detect that and report when it happened.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import mujoco
import numpy as np
import scipy
from mujoco import rollout
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

Array = NDArray[np.float64]

#: MuJoCo's warnings (e.g. the reset after a NaN), collected here instead of being
#: printed and appended to MUJOCO_LOG.TXT in the working directory; the runs below
#: detect a reset themselves.
MUJOCO_WARNINGS: list[str] = []
mujoco.set_mju_user_warning(MUJOCO_WARNINGS.append)

#: MuJoCo integrators, by their MJCF names.
INTEGRATORS = ("RK4", "Euler", "implicit", "implicitfast")

_FREE_BODY_MJCF = """
<mujoco model="free body">
  <option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 0">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="body">
      <freejoint/>
      <inertial pos="0 0 0" mass="1" diaginertia="{i1!r} {i2!r} {i3!r}"/>
    </body>
  </worldbody>
</mujoco>
"""

# The body frame's origin is the pivot (the ball joint); the disk's centre is at
# `lever` along its symmetry axis, body z. No geoms: inertia given explicitly.
_TOP_MJCF = """
<mujoco model="heavy gyroscope">
  <option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 {gz!r}">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="disk">
      <joint name="pivot" type="ball" pos="0 0 0" damping="0" armature="0"/>
      <inertial pos="0 0 {lever!r}" mass="{mass!r}" diaginertia="{ip!r} {ip!r} {js!r}"/>
    </body>
  </worldbody>
</mujoco>
"""


# ------------------------------------------------------------------ helpers
def environment() -> str:
    """Date, machine (nproc, CPU model) and versions, for the head of a benchmark's output."""
    from machine import describe

    return describe({"mujoco": mujoco.__version__, "scipy": scipy.__version__})


def quat_matrix(q: Array) -> Array:
    """Rotation matrices (..., 3, 3) of unit quaternions (..., 4) [w, x, y, z], body → space."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def _quat_rate(q: Array, w: Array) -> Array:
    """q̇ = ½ q ⊗ (0, ω), ω in body axes."""
    return 0.5 * np.array(
        [
            -q[1] * w[0] - q[2] * w[1] - q[3] * w[2],
            q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
            q[0] * w[1] + q[3] * w[0] - q[1] * w[2],
            q[0] * w[2] + q[1] * w[1] - q[2] * w[0],
        ]
    )


def _euler_rate(moments: Array, w: Array, torque: Array) -> Array:
    """ω̇ from Euler's equations in the principal frame: I ω̇ = τ − ω × I ω."""
    i1, i2, i3 = moments
    return np.array(
        [
            (torque[0] + (i2 - i3) * w[1] * w[2]) / i1,
            (torque[1] + (i3 - i1) * w[2] * w[0]) / i2,
            (torque[2] + (i1 - i2) * w[0] * w[1]) / i3,
        ]
    )


def _reset_index(times: Array) -> int | None:
    """Index of the first sample after MuJoCo reset its state (time went back), or None."""
    back = np.flatnonzero(np.diff(times) < 0)
    return int(back[0]) + 1 if back.size else None


# --------------------------------------------------------- torque-free body
@dataclass(frozen=True)
class FreeRun:
    """A torque-free run: the final state and sampled invariants.

    ``omega`` (3,) body axes and ``quaternion`` (4,) at the end; ``t``, ``energy``
    and ``momentum`` (|L|) at the samples; ``steps``: time steps (MuJoCo) or
    right-hand-side evaluations (scipy); ``diverged_at``: the simulated time (s)
    at which the state became NaN/huge and MuJoCo reset it (the run stops there,
    its final state is NaN), else None.
    """

    omega: Array
    quaternion: Array
    t: Array
    energy: Array
    momentum: Array
    steps: int
    diverged_at: float | None = None


def free_body_model(moments: Array, dt: float, integrator: str) -> mujoco.MjModel:
    """MuJoCo model of a torque-free body with principal moments ``moments`` (body axes)."""
    i1, i2, i3 = (float(v) for v in moments)
    xml = _FREE_BODY_MJCF.format(dt=float(dt), integrator=integrator, i1=i1, i2=i2, i3=i3)
    return mujoco.MjModel.from_xml_string(xml)


def mujoco_free_body(
    moments: Array,
    omega0: Array,
    duration: float,
    dt: float,
    integrator: str,
    *,
    attitude0: Array | None = None,
    sample_every: int = 100,
) -> FreeRun:
    """Run MuJoCo's free body from ω0 (body axes) for ``duration`` s at step ``dt``.

    Energy and |L| are sampled every ``sample_every`` steps (``mj_step`` runs
    that many steps in C between samples).
    """
    moments = np.asarray(moments, dtype=float)
    model = free_body_model(moments, dt, integrator)
    data = mujoco.MjData(model)
    if attitude0 is not None:
        data.qpos[3:7] = attitude0
    data.qvel[3:6] = omega0  # angular part of a free joint's qvel: body frame
    n_steps = round(duration / dt)
    chunks = [sample_every] * (n_steps // sample_every)
    if n_steps % sample_every:
        chunks.append(n_steps % sample_every)
    t = np.empty(len(chunks) + 1)
    w = np.empty((len(chunks) + 1, 3))
    t[0], w[0] = 0.0, omega0
    bad = mujoco.mjtWarning.mjWARN_BADQACC
    diverged_at = None
    for k, count in enumerate(chunks, 1):
        before = data.warning[bad].number
        mujoco.mj_step(model, data, count)
        t[k], w[k] = data.time, data.qvel[3:6]
        if data.warning[bad].number > before:
            # MuJoCo restarted from time 0 within this chunk
            diverged_at = t[k - 1] + count * dt - data.time
            t, w = t[:k], w[:k]
            break
    energy = 0.5 * np.sum(moments * w**2, axis=1)
    momentum = np.linalg.norm(moments * w, axis=1)
    nan = np.full(4, np.nan)
    return FreeRun(
        omega=w[-1].copy() if diverged_at is None else nan[:3],
        quaternion=data.qpos[3:7].copy() if diverged_at is None else nan,
        t=t,
        energy=energy,
        momentum=momentum,
        steps=n_steps,
        diverged_at=diverged_at,
    )


def mujoco_free_body_frame_check(
    moments: Array, omega0: Array, duration: float = 10.0, dt: float = 1e-3
) -> tuple[float, float]:
    """Which frame is a free joint's angular ``qvel`` in? Measured, not assumed.

    The body starts turned (a generic attitude) and runs torque-free under RK4.
    Returns the largest change of the space-frame angular momentum over the run,
    relative to |L|, computed (a) as ``R I qvel`` (qvel in body axes) and (b) as
    ``R I Rᵀ qvel`` (qvel in world axes). L is conserved, so the right reading
    gives round-off-level change; the wrong one changes by O(1).
    """
    moments = np.asarray(moments, dtype=float)
    model = free_body_model(moments, dt, "RK4")
    data = mujoco.MjData(model)
    turned = np.array([0.8, 0.3, -0.4, 0.34])
    data.qpos[3:7] = turned / np.linalg.norm(turned)
    data.qvel[3:6] = omega0
    as_body, as_world = [], []
    for _ in range(100):
        mujoco.mj_step(model, data, max(1, round(duration / dt / 100)))
        rot = data.xmat[1].reshape(3, 3)
        v = data.qvel[3:6]
        as_body.append(rot @ (moments * v))
        as_world.append(rot @ (moments * (rot.T @ v)))
    size = float(np.linalg.norm(moments * np.asarray(omega0)))
    return (
        float(np.max(np.ptp(np.array(as_body), axis=0)) / size),
        float(np.max(np.ptp(np.array(as_world), axis=0)) / size),
    )


def scipy_free_body(
    moments: Array,
    omega0: Array,
    duration: float,
    *,
    attitude0: Array | None = None,
    rtol: float = 1e-12,
    atol: float = 1e-14,
    method: str = "DOP853",
    t_eval: Array | None = None,
) -> FreeRun:
    """scipy reference: Euler's equations and q̇ = ½ q ⊗ (0, ω) in the principal frame.

    ``moments`` are principal moments and ω0 is in those axes; the quaternion is
    principal → space. The quaternion is not renormalised (its norm drift is part
    of the integrator's error).
    """
    moments = np.asarray(moments, dtype=float)
    q0 = np.array([1.0, 0, 0, 0]) if attitude0 is None else np.asarray(attitude0, dtype=float)
    zero = np.zeros(3)

    def rhs(_t: float, y: Array) -> Array:
        return np.concatenate([_euler_rate(moments, y[:3], zero), _quat_rate(y[3:], y[:3])])

    sol = solve_ivp(
        rhs,
        (0.0, duration),
        np.concatenate([omega0, q0]),
        method=method,
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
    )
    w = sol.y[:3].T
    return FreeRun(
        omega=w[-1].copy(),
        quaternion=sol.y[3:, -1].copy(),
        t=sol.t,
        energy=0.5 * np.sum(moments * w**2, axis=1),
        momentum=np.linalg.norm(moments * w, axis=1),
        steps=int(sol.nfev),
    )


# --------------------------------------------------------- heavy gyroscope
@dataclass(frozen=True)
class Top:
    """A thin disk spinning on a pivot on its symmetry axis (body z), under gravity.

    The disk's centre is ``lever`` m from the pivot along +z (body axes); about its
    centre I_s = m r²/2 (axis), I_⊥ = m r²/4; about the pivot the transverse moment
    is I_⊥ + m l². At t = 0 the axis is horizontal (body z along space +x), the
    disk spins at ``spin`` rad/s about it and is otherwise at rest.
    """

    mass: float = 1.0
    radius: float = 0.1
    lever: float = 0.1
    spin: float = 200.0
    gravity: float = 9.81
    duration: float = 5.0

    @property
    def spin_moment(self) -> float:
        return self.mass * self.radius**2 / 2

    @property
    def transverse_moment(self) -> float:
        """About the disk's centre."""
        return self.mass * self.radius**2 / 4

    @property
    def pivot_moments(self) -> Array:
        """Principal moments about the pivot, body axes (x, y, z = symmetry axis)."""
        transverse = self.transverse_moment + self.mass * self.lever**2
        return np.array([transverse, transverse, self.spin_moment])

    @property
    def attitude0(self) -> Array:
        """Quaternion turning body z onto space +x: 90° about space y."""
        return np.array([np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])

    @property
    def omega0(self) -> Array:
        return np.array([0.0, 0.0, self.spin])

    @property
    def energy0(self) -> float:
        """Total energy at release, J (the potential is zero with the axis horizontal)."""
        return 0.5 * self.spin_moment * self.spin**2

    def fast_top(self) -> tuple[float, float, float]:
        """Goldstein §5.7, fast top released from rest at θ₀ = 90°: precession rate
        m g l/(I_s ω_s), nutation rate I_s ω_s/I₁, nutation half-amplitude
        I₁ m g l/(I_s ω_s)² (rad), with I₁ about the pivot."""
        spin_momentum = self.spin_moment * self.spin
        weight = self.mass * self.gravity * self.lever
        i1 = self.pivot_moments[0]
        return (
            weight / spin_momentum,
            spin_momentum / i1,
            i1 * weight / spin_momentum**2,
        )

    def turning_angle(self) -> float:
        """The exact lower turning angle θ₁ (rad from the upward vertical).

        With u = cos θ, released at rest at u₀: u̇² = (1 − u²) β (u₀ − u) − a² (u₀ − u)²,
        a = I_s ω_s / I₁, β = 2 m g l / I₁. Its other root with |u| ≤ 1 solves
        β u² − a² u + a² u₀ − β = 0.
        """
        i1 = self.pivot_moments[0]
        a = self.spin_moment * self.spin / i1
        beta = 2 * self.mass * self.gravity * self.lever / i1
        u0 = 0.0
        disc = a**4 - 4 * beta * (a**2 * u0 - beta)
        # the smaller root, written without cancellation: (a² − √disc)/(2β)
        u1 = 2 * (a**2 * u0 - beta) / (a**2 + np.sqrt(disc))
        return float(np.arccos(u1))

    def mjcf(self, dt: float, integrator: str) -> str:
        return _TOP_MJCF.format(
            dt=float(dt),
            integrator=integrator,
            gz=-float(self.gravity),
            lever=float(self.lever),
            mass=float(self.mass),
            ip=float(self.transverse_moment),
            js=float(self.spin_moment),
        )


@dataclass(frozen=True)
class TopRun:
    """A sampled run of the top: times ``t``, body ω (n, 3), attitudes (n, 4).

    ``diverged_at``: the time at which the state became NaN/huge (MuJoCo reset it
    and the samples after that are dropped), else None. ``turning_theta``: θ at
    the located turning points (θ̇ = 0), when the integrator located them.
    """

    t: Array
    omega: Array
    quaternion: Array
    steps: int
    diverged_at: float | None = None
    turning_theta: Array | None = field(default=None)

    @cached_property
    def axis(self) -> Array:
        """(n, 3) the symmetry axis (body z) in space."""
        return quat_matrix(self.quaternion)[:, :, 2]

    @cached_property
    def theta(self) -> Array:
        """Polar angle of the axis from the upward vertical, rad."""
        a = self.axis
        return np.arctan2(np.hypot(a[:, 0], a[:, 1]), a[:, 2])

    @cached_property
    def phi(self) -> Array:
        """Azimuth of the axis (precession angle), rad, unwrapped."""
        return np.unwrap(np.arctan2(self.axis[:, 1], self.axis[:, 0]))

    def energy(self, top: Top) -> Array:
        """Kinetic energy about the pivot plus m g (height of the centre)."""
        kinetic = 0.5 * np.sum(top.pivot_moments * self.omega**2, axis=1)
        return kinetic + top.mass * top.gravity * top.lever * self.axis[:, 2]


def top_model(top: Top, dt: float, integrator: str) -> mujoco.MjModel:
    """MuJoCo model of the top (compiled from MJCF once; runs reuse it)."""
    return mujoco.MjModel.from_xml_string(top.mjcf(dt, integrator))


def mujoco_top(top: Top, model: mujoco.MjModel) -> TopRun:
    """Run MuJoCo's ball-joint top (a :func:`top_model`) for ``top.duration`` s.

    The steps run in C (``mujoco.rollout``), which returns the full state after
    every step; all are kept.
    """
    dt = float(model.opt.timestep)
    data = mujoco.MjData(model)
    data.qpos[:] = top.attitude0
    data.qvel[:] = top.omega0  # a ball joint's qvel: ω in body axes
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state0, spec)
    n_steps = round(top.duration / dt)
    states, _ = rollout.rollout(model, data, state0, nstep=n_steps)
    states = np.concatenate([state0[None], states[0]])
    # FULLPHYSICS layout: time, qpos (4), qvel (3), ...
    t, q, w = states[:, 0], states[:, 1:5], states[:, 5:8]
    reset = _reset_index(t)
    diverged_at = None
    if reset is not None:
        diverged_at = reset * dt
        t, q, w = t[:reset], q[:reset], w[:reset]
    return TopRun(t=t, omega=w, quaternion=q, steps=n_steps, diverged_at=diverged_at)


def scipy_top(
    top: Top,
    *,
    rtol: float = 1e-12,
    atol: float = 1e-14,
    method: str = "DOP853",
    t_eval: Array | None = None,
    turning_points: bool = False,
) -> TopRun:
    """scipy reference for the top, in the principal frame about the pivot.

    I ω̇ = τ − ω × I ω with I = diag(I_⊥ + m l², I_⊥ + m l², I_s) and the torque
    of gravity about the pivot τ = r × (Aᵀ m g), r = (0, 0, l), A the attitude
    matrix (body → space); q̇ = ½ q ⊗ (0, ω). With ``turning_points`` the nutation
    turning points (u̇ = 0, u = cos θ the vertical component of the axis) are
    located on the integrator's dense output and θ there is returned.
    """
    moments = top.pivot_moments
    weight = np.array([0.0, 0.0, -top.mass * top.gravity])
    lever = top.lever

    def rhs(_t: float, y: Array) -> Array:
        w, q = y[:3], y[3:]
        down = quat_matrix(q).T @ weight  # m g in body axes
        torque = np.array([-lever * down[1], lever * down[0], 0.0])  # (0, 0, l) × down
        return np.concatenate([_euler_rate(moments, w, torque), _quat_rate(q, w)])

    def vertical_rate(_t: float, y: Array) -> float:
        # u = (A e_z)_z; u̇ = (A (ω × e_z))_z = A_zx ω_y − A_zy ω_x
        w, q = y[:3], y[3:]
        a_zx = 2 * (q[1] * q[3] - q[0] * q[2])
        a_zy = 2 * (q[2] * q[3] + q[0] * q[1])
        return float(a_zx * w[1] - a_zy * w[0])

    sol = solve_ivp(
        rhs,
        (0.0, top.duration),
        np.concatenate([top.omega0, top.attitude0]),
        method=method,
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
        events=vertical_rate if turning_points else None,
    )
    turning = None
    if turning_points:
        ys = sol.y_events[0]
        axis_z = quat_matrix(ys[:, 3:])[:, :, 2]
        turning = np.arctan2(np.hypot(axis_z[:, 0], axis_z[:, 1]), axis_z[:, 2])
    return TopRun(
        t=sol.t,
        omega=sol.y[:3].T,
        quaternion=sol.y[3:].T,
        steps=int(sol.nfev),
        turning_theta=turning,
    )
