"""MuJoCo: one free body (a ``<freejoint>``) or a body on a ball joint, from MJCF text.

MuJoCo integrates ``M v̇ = −c(q, v) + τ``; the gyroscopic term ω × I ω is in
the bias ``c``. Its integrators (``<option integrator>``, mjtIntegrator):
``Euler`` (the default: semi-implicit, velocities first, then positions with
the new velocities), ``RK4`` (classic fourth-order Runge–Kutta), ``implicit``
and ``implicitfast`` (implicit in the velocity-dependent forces, which damp the
gyroscopic motion). A free joint's ``qvel`` holds the linear velocity in world
axes, then the angular velocity in the body's local axes; a ball joint's holds
the local angular velocity (MuJoCo's documentation, "Floating objects"). When
the accelerations go bad MuJoCo warns (``mjWARN_BADQACC``) and resets the state
to the model's reference: :meth:`MujocoEngine.failure` reports it.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np

from tumble.conformance.engine import Array, Engine, EngineBody, register_engine

__all__ = ["MujocoEngine"]

#: MuJoCo's name of the integrator of each variant (``<option integrator>``).
INTEGRATORS = {
    "euler": "Euler",
    "rk4": "RK4",
    "implicit": "implicit",
    "implicitfast": "implicitfast",
}


def _numbers(values: Any) -> str:
    """Numbers as MJCF attribute text, every digit of a float64 kept."""
    return " ".join(repr(float(v)) for v in np.ravel(values))


@register_engine
class MujocoEngine(Engine):
    """MuJoCo (``mujoco``): the body from MJCF text, its mass and principal moments in an
    ``<inertial>`` element, no geom, no damping, each of MuJoCo's integrators."""

    name = "mujoco"
    variants: ClassVar[dict[str, str]] = {
        "euler": "semi-implicit Euler, MuJoCo's default integrator",
        "rk4": 'fourth-order Runge–Kutta (integrator="RK4")',
        "implicit": 'implicit in the velocity-dependent forces (integrator="implicit")',
        "implicitfast": "implicit, without the Coriolis and centrifugal derivatives "
        '(integrator="implicitfast")',
    }
    modules = ("mujoco",)
    omega_frame: ClassVar[Literal["body", "space"]] = "body"
    holds_pivot = True
    pivot_method = (
        'a ball joint (<joint type="ball">) at the pivot, the body\'s frame at its centre of mass'
    )

    def build(self, body: EngineBody, dt: float) -> None:
        import mujoco

        pivot = body.pivot
        joint = (
            "<freejoint/>"
            if pivot is None
            else f'<joint type="ball" pos="{_numbers(pivot)}" damping="0" armature="0"/>'
        )
        # With a pivot the body's frame sits at −pivot: the joint's anchor is then the
        # origin of space.
        position = _numbers(np.zeros(3) if pivot is None else -np.asarray(pivot))
        text = f"""
<mujoco model="tumble-conformance">
  <option timestep="{float(dt)!r}" integrator="{INTEGRATORS[self.variant]}"
          gravity="{_numbers(body.gravity)}"/>
  <worldbody>
    <body name="body" pos="{position}">
      {joint}
      <inertial pos="0 0 0" mass="{float(body.mass)!r}" diaginertia="{_numbers(body.moments)}"/>
    </body>
  </worldbody>
</mujoco>"""
        self._mujoco = mujoco
        self.model = mujoco.MjModel.from_xml_string(text)
        self.data = mujoco.MjData(self.model)
        self._free = pivot is None
        self._badqacc = int(mujoco.mjtWarning.mjWARN_BADQACC)
        self._message = ""
        self._instability = int(mujoco.mjtWarning.mjWARN_BADQVEL)

    def inertia(self) -> tuple[float, Array]:
        from scipy.spatial.transform import Rotation

        model = self.model
        axes = Rotation.from_quat(model.body_iquat[1], scalar_first=True).as_matrix()
        inertia = axes @ np.diag(model.body_inertia[1]) @ axes.T
        if np.any(model.body_ipos[1] != 0.0):
            raise RuntimeError(f"MuJoCo moved the centre of mass to {model.body_ipos[1]}")
        return float(model.body_mass[1]), inertia

    def set_state(self, quaternion: Array, omega: Array) -> None:
        data = self.data
        data.qvel[:] = 0.0
        if self._free:
            data.qpos[:3] = 0.0
            data.qpos[3:7] = quaternion
            data.qvel[3:6] = omega
        else:
            data.qpos[:4] = quaternion
            data.qvel[:3] = omega
        data.time = 0.0
        self._mujoco.mj_forward(self.model, data)

    def step(self, count: int) -> None:
        # MuJoCo prints its warnings and appends them to MUJOCO_LOG.TXT in the working
        # folder unless a handler takes them: this one keeps them for failure().
        mujoco = self._mujoco
        previous = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(self._warned)
        try:
            mujoco.mj_step(self.model, self.data, nstep=count)
        finally:
            mujoco.set_mju_user_warning(previous)

    def _warned(self, message: str) -> None:
        if not self._message:
            self._message = " ".join(str(message).split())

    def state(self) -> tuple[Array, Array]:
        data = self.data
        if self._free:
            return data.qpos[3:7].copy(), data.qvel[3:6].copy()
        return data.qpos[:4].copy(), data.qvel[:3].copy()

    def failure(self) -> str:
        warnings = self.data.warning
        if warnings[self._badqacc].number > 0:
            said = f": {self._message}" if self._message else ""
            return f"MuJoCo warned of bad accelerations (mjWARN_BADQACC) and reset the state{said}"
        if warnings[self._instability].number > 0:
            return "MuJoCo warned of a bad velocity (mjWARN_BADQVEL) and reset the state"
        return ""
