"""PyBullet: one body as a Featherstone multibody or as a maximal-coordinates rigid body.

PyBullet (the Python binding of Bullet 3) builds bodies with ``createMultiBody``.
By default that is a ``btMultiBody``: semi-implicit Euler with an explicit
gyroscopic term and a damping of 0.04 on by default, applied to the base as the
torque −I ω (0.04 + 0.04 |ω|) (and the force −m v (0.04 + 0.04 |v|)). With
``useMaximalCoordinates=True`` it is a ``btRigidBody``: an implicit gyroscopic
step and no damping by default. Both distort the attitude update of a step that
turns more than π/4 (``ANGULAR_MOTION_THRESHOLD``: the angle is capped, the axis part
is not); the multibody also clamps each
velocity coordinate to 100 rad/s (``maxJointVelocity``), which the adapter lifts.

PyBullet stores the angular velocity in space axes and its quaternions vector
first ``[x, y, z, w]``.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from tumble.conformance.engine import Engine, EngineBody, NativeOutput, register_engine, rotation

__all__ = ["PyBulletEngine"]

Array = NDArray[np.float64]

#: Bullet's limit on the rotation of one step, rad (ANGULAR_MOTION_THRESHOLD = π/4 in
#: btTransformUtil.h and btMultiBody.cpp): beyond it the angle of the attitude update is
#: capped and the update turns by neither |ω| dt nor π/4.
STEP_ROTATION_LIMIT = 0.25 * np.pi

#: The multibody's velocity clamp (maxJointVelocity, 100 rad/s by default) raised to this.
VELOCITY_CLAMP = 1e30

#: Radius of the collision sphere a maximal-coordinates body needs, m (PyBullet builds
#: no rigid body without a shape); its collisions are filtered off and its inertia replaced.
SPHERE_RADIUS = 0.01


def _vector_first(quaternion: Array) -> list[float]:
    """PyBullet's [x, y, z, w] of a scalar-first quaternion."""
    w, x, y, z = (float(v) for v in quaternion)
    return [x, y, z, w]


def _scalar_first(quaternion: Any) -> Array:
    """Scalar-first quaternion of PyBullet's [x, y, z, w]."""
    x, y, z, w = quaternion
    return np.array([w, x, y, z], dtype=float)


@register_engine
class PyBulletEngine(Engine):
    """PyBullet's multibody (its default) and maximal-coordinates rigid body, each
    with PyBullet's default damping or none."""

    name: ClassVar[str] = "pybullet"
    variants: ClassVar[dict[str, str]] = {
        "": "createMultiBody (Featherstone), PyBullet's defaults: damping 0.04 included",
        "undamped": "createMultiBody (Featherstone), linear and angular damping 0",
        "maximal": "createMultiBody(useMaximalCoordinates=True) rigid body, PyBullet's defaults",
        "maximal-undamped": "createMultiBody(useMaximalCoordinates=True), damping set to 0",
    }
    modules: ClassVar[tuple[str, ...]] = ("pybullet",)
    omega_frame: ClassVar[Literal["body", "space"]] = "space"
    holds_pivot: ClassVar[bool] = True
    pivot_method: ClassVar[str] = (
        "multibody: a fixed base and one link on a JOINT_SPHERICAL joint at the pivot; "
        "maximal: createConstraint JOINT_POINT2POINT between the body and the world"
    )

    def __init__(self, variant: str = "") -> None:
        super().__init__(variant)
        self._pybullet: Any = None
        self._client = -1
        self._body_id = -1
        self._dt = 0.0
        self._pivot: Array | None = None

    @property
    def _maximal(self) -> bool:
        return self.variant.startswith("maximal")

    @property
    def _damped(self) -> bool:
        return not self.variant.endswith("undamped")

    def build(self, body: EngineBody, dt: float) -> None:
        """Create a DIRECT PyBullet client stepping ``dt`` (s) with this one body."""
        # PyBullet prints a banner when it is imported and connected: kept off the terminal.
        with NativeOutput() as banner:
            import pybullet  # type: ignore[import-not-found, unused-ignore]

            self.close()
            self.notes = []
            p = self._pybullet = pybullet
            client = self._client = p.connect(p.DIRECT)
        banner.close()
        # numSubSteps = 0: each stepSimulation is one step of fixedTimeStep.
        p.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=0, physicsClientId=client)
        p.setGravity(*(float(g) for g in body.gravity), physicsClientId=client)
        self._dt = float(dt)
        self._pivot = None if body.pivot is None else np.asarray(body.pivot, dtype=float)
        shape = -1
        if self._maximal:
            shape = p.createCollisionShape(
                p.GEOM_SPHERE, radius=SPHERE_RADIUS, physicsClientId=client
            )
        if self._pivot is not None and not self._maximal:
            self._body_id = self._build_pivot_multibody(body, self._pivot)
            link = 0
        else:
            self._body_id = p.createMultiBody(
                baseMass=float(body.mass),
                baseCollisionShapeIndex=shape,
                baseVisualShapeIndex=-1,
                basePosition=[0.0, 0.0, 0.0],
                baseOrientation=[0.0, 0.0, 0.0, 1.0],
                baseInertialFramePosition=[0.0, 0.0, 0.0],
                baseInertialFrameOrientation=[0.0, 0.0, 0.0, 1.0],
                useMaximalCoordinates=self._maximal,
                physicsClientId=client,
            )
            link = -1
        settings: dict[str, Any] = {
            # The mass again: a rigid body's inertia is set together with its mass.
            "mass": float(body.mass),
            "localInertiaDiagonal": [float(m) for m in body.moments],
        }
        p.changeDynamics(self._body_id, link, physicsClientId=client, **settings)
        # Sleeping, damping and the velocity clamp belong to the whole body, set through
        # the base in a call of their own: PyBullet's client turns the link of a call that
        # sets the activation state or a damping into the base (its C API sets
        # m_linkIndex = -1), which would give a link's mass and inertia to the base.
        whole: dict[str, Any] = {"activationState": p.ACTIVATION_STATE_DISABLE_SLEEPING}
        if not self._maximal:
            whole["maxJointVelocity"] = VELOCITY_CLAMP
        if not self._damped:
            whole["linearDamping"] = 0.0
            whole["angularDamping"] = 0.0
        p.changeDynamics(self._body_id, -1, physicsClientId=client, **whole)
        if self._maximal:
            self._hold_maximal(shape)
        else:
            self._hold_reduced()
        self.notes.append("sleeping turned off (ACTIVATION_STATE_DISABLE_SLEEPING)")
        if self._damped and not self._maximal:
            self.notes.append("PyBullet's default damping 0.04 kept: torque −Iω(0.04 + 0.04|ω|)")
        if self._damped and self._maximal:
            self.notes.append("PyBullet's defaults: a maximal-coordinates body has no damping")
        if not self._damped:
            self.notes.append("linear and angular damping set to 0")

    def _hold_maximal(self, shape: int) -> None:
        """A maximal-coordinates body: its collision sphere filtered off, and its pivot
        (if any) a point-to-point constraint to a static anchor."""
        p, client = self._pybullet, self._client
        p.setCollisionFilterGroupMask(self._body_id, -1, 0, 0, physicsClientId=client)
        self.notes.append(
            f"a collision sphere of radius {SPHERE_RADIUS} m with collisions filtered off "
            "(PyBullet needs a shape for a maximal-coordinates body); inertia given explicitly"
        )
        if self._pivot is None:
            return
        # PyBullet joins a maximal-coordinates body only to another body: a static
        # one (mass 0) at the origin.
        anchor = p.createMultiBody(
            baseMass=0.0,
            baseCollisionShapeIndex=shape,
            baseVisualShapeIndex=-1,
            useMaximalCoordinates=True,
            physicsClientId=client,
        )
        p.setCollisionFilterGroupMask(anchor, -1, 0, 0, physicsClientId=client)
        p.createConstraint(
            self._body_id,
            -1,
            anchor,
            -1,
            p.JOINT_POINT2POINT,
            [0.0, 0.0, 0.0],
            [float(r) for r in self._pivot],
            [0.0, 0.0, 0.0],
            physicsClientId=client,
        )
        self.notes.append(
            "the pivot is a JOINT_POINT2POINT constraint to a static anchor, held by "
            "the constraint solver (it drifts by ~1e-5 m at dt = 1e-3 s)"
        )

    def _hold_reduced(self) -> None:
        """A multibody: its spherical joint's motor (if pivoted) turned off."""
        p = self._pybullet
        if self._pivot is not None:
            # PyBullet puts a motor (max impulse 1000 N·m·s a step) on every spherical
            # joint; no gains and no force turn it off.
            p.setJointMotorControlMultiDof(
                self._body_id,
                0,
                p.POSITION_CONTROL,
                targetPosition=[0.0, 0.0, 0.0, 1.0],
                targetVelocity=[0.0, 0.0, 0.0],
                positionGain=0.0,
                velocityGain=0.0,
                force=[0.0, 0.0, 0.0],
                physicsClientId=self._client,
            )
            self.notes.append("the spherical joint's default motor turned off (force 0)")
        self.notes.append(
            f"velocity clamp maxJointVelocity raised from 100 rad/s to {VELOCITY_CLAMP:g}"
        )

    def _build_pivot_multibody(self, body: EngineBody, pivot: Array) -> int:
        """A fixed massless base at the origin and the body as one link on a spherical
        joint there, its centre of mass at −pivot (m) in its own axes."""
        p = self._pybullet
        return int(
            p.createMultiBody(
                baseMass=0.0,
                baseCollisionShapeIndex=-1,
                baseVisualShapeIndex=-1,
                basePosition=[0.0, 0.0, 0.0],
                baseOrientation=[0.0, 0.0, 0.0, 1.0],
                linkMasses=[float(body.mass)],
                linkCollisionShapeIndices=[-1],
                linkVisualShapeIndices=[-1],
                linkPositions=[[0.0, 0.0, 0.0]],
                linkOrientations=[[0.0, 0.0, 0.0, 1.0]],
                linkInertialFramePositions=[[-float(r) for r in pivot]],
                linkInertialFrameOrientations=[[0.0, 0.0, 0.0, 1.0]],
                linkParentIndices=[0],
                linkJointTypes=[p.JOINT_SPHERICAL],
                linkJointAxis=[[0.0, 0.0, 1.0]],
                physicsClientId=self._client,
            )
        )

    @property
    def _link(self) -> int:
        """The link that is the body: the base, or link 0 of a pivot multibody."""
        return 0 if self._pivot is not None and not self._maximal else -1

    def inertia(self) -> tuple[float, Array]:
        """Mass and inertia about the centre of mass in body axes from getDynamicsInfo."""
        p = self._pybullet
        info = p.getDynamicsInfo(self._body_id, self._link, physicsClientId=self._client)
        mass, diagonal, frame_orientation = float(info[0]), np.array(info[2]), info[4]
        orientation = np.array(frame_orientation, dtype=float)
        # A maximal-coordinates body does not report its inertial frame (PyBullet leaves
        # it zero); the adapter gave the identity there.
        if not np.any(orientation):
            orientation = np.array([0.0, 0.0, 0.0, 1.0])
        axes = rotation(_scalar_first(orientation)).as_matrix()
        return mass, axes @ np.diag(diagonal) @ axes.T

    def set_state(self, quaternion: Array, omega: Array) -> None:
        """Attitude (scalar first, body → space) and ω in space axes (rad/s)."""
        p, client = self._pybullet, self._client
        omega = np.asarray(omega, dtype=float)
        if self._link == 0:
            # The spherical joint's rate is ω in the link's (body) axes.
            omega_body = rotation(quaternion).inv().apply(omega)
            p.resetJointStateMultiDof(
                self._body_id,
                0,
                targetValue=_vector_first(quaternion),
                targetVelocity=[float(w) for w in omega_body],
                physicsClientId=client,
            )
            return
        position = np.zeros(3)
        velocity = np.zeros(3)
        if self._pivot is not None:
            # The centre of mass at −R·pivot, moving so that the pivot stays still.
            position = -rotation(quaternion).apply(self._pivot)
            velocity = np.cross(omega, position)
        p.resetBasePositionAndOrientation(
            self._body_id, position.tolist(), _vector_first(quaternion), physicsClientId=client
        )
        p.resetBaseVelocity(
            self._body_id, velocity.tolist(), omega.tolist(), physicsClientId=client
        )

    def step(self, count: int) -> None:
        """``count`` calls of stepSimulation (PyBullet has no multi-step call of fixed dt)."""
        step, client = self._pybullet.stepSimulation, self._client
        for _ in range(count):
            step(physicsClientId=client)

    def state(self) -> tuple[Array, Array]:
        """Attitude (scalar first) and ω in space axes (rad/s)."""
        p, client = self._pybullet, self._client
        if self._link == 0:
            link = p.getLinkState(self._body_id, 0, computeLinkVelocity=1, physicsClientId=client)
            return _scalar_first(link[5]), np.array(link[7], dtype=float)
        _, orientation = p.getBasePositionAndOrientation(self._body_id, physicsClientId=client)
        _, omega = p.getBaseVelocity(self._body_id, physicsClientId=client)
        return _scalar_first(orientation), np.array(omega, dtype=float)

    def failure(self) -> str:
        """Bullet's cap on the rotation of one step, when the rate reaches it (checked on
        the state now)."""
        _, omega = self.state()
        turn = float(np.linalg.norm(omega)) * self._dt
        if turn > STEP_ROTATION_LIMIT:
            return (
                f"|ω|·dt = {turn:.3g} rad beyond Bullet's limit π/4 on the rotation of a step: "
                "the attitude update is distorted"
            )
        return ""

    def close(self) -> None:
        """Disconnect this adapter's PyBullet client."""
        if self._pybullet is not None and self._client >= 0:
            self._pybullet.disconnect(physicsClientId=self._client)
        self._client = -1
        self._body_id = -1
