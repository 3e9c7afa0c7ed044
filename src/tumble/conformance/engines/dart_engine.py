"""DART (dartpy): one Skeleton with one BodyNode on a FreeJoint, stepped by its World.

DART's FreeJoint keeps six generalized positions (the rotation's log map, then
the translation) and six generalized velocities whose angular part is in the
parent's axes, here space axes: its relative Jacobian is ``Rᵀ`` times the
identity (``FreeJoint::updateRelativeJacobian``), so the body's own spatial
velocity is ``Rᵀ`` times them. The adapter stores ω there, in space axes.

The plain variant is DART's default step: forward dynamics by the articulated
body algorithm, the velocity advanced by explicit Euler, then the pose by the
new velocity (semi-implicit Euler). DART turns automatic deactivation
(sleeping) on by default; the adapter turns it off.

A pivot is a BallJoint whose joint frame sits at the body's pivot point
(``setTransformFromChildBodyNode``) and at the space origin on the world side;
its three generalized velocities are the body's angular velocity in body axes.
"""

from __future__ import annotations

import importlib
from typing import Any, ClassVar, Literal

import numpy as np
from scipy.spatial.transform import Rotation

from tumble.conformance.engine import (
    Array,
    Engine,
    EngineBody,
    NativeOutput,
    register_engine,
    rotation,
)

#: The note of a run: the setting the adapter changed.
SLEEPING_OFF = "automatic deactivation (sleeping) turned off"


@register_engine
class DartEngine(Engine):
    """DART stepping one body on a FreeJoint (free) or a BallJoint (pivot)."""

    name: ClassVar[str] = "dart"
    variants: ClassVar[dict[str, str]] = {"": "DART's default step (semi-implicit)"}
    modules: ClassVar[tuple[str, ...]] = ("dartpy",)
    omega_frame: ClassVar[Literal["body", "space"]] = "space"
    holds_pivot: ClassVar[bool] = True
    pivot_method: ClassVar[str] = (
        "a BallJoint between the world and the body, its frame at the body's pivot point "
        "(setTransformFromChildBodyNode), gravity on"
    )

    def __init__(self, variant: str = "") -> None:
        super().__init__(variant)
        self._dart: Any = None
        self._world: Any = None
        self._joint: Any = None
        self._node: Any = None
        self._pivot: Array | None = None
        self._output = NativeOutput()

    def build(self, body: EngineBody, dt: float) -> None:
        """Create a World stepping at ``dt`` (s) with one Skeleton of one BodyNode whose
        inertia is set explicitly; no shape, so nothing collides."""
        # Imported by name: dartpy ships no type stubs, and an adapter never imports its
        # engine before it is built.
        dartpy = importlib.import_module("dartpy")
        self._output.reset()
        self._dart = dartpy
        world = dartpy.simulation.World()
        world.setTimeStep(float(dt))
        world.setGravity(np.asarray(body.gravity, dtype=float))
        # DART puts quiet skeletons to sleep by default: a tumbling body must never stop.
        options = world.getDeactivationOptions()
        options.mEnabled = False
        world.setDeactivationOptions(options)
        if SLEEPING_OFF not in self.notes:
            self.notes.append(SLEEPING_OFF)
        skeleton = dartpy.dynamics.Skeleton("body")
        self._pivot = None if body.pivot is None else np.asarray(body.pivot, dtype=float)
        if self._pivot is None:
            joint, node = skeleton.createFreeJointAndBodyNodePair()
        else:
            joint, node = skeleton.createBallJointAndBodyNodePair()
            # The joint frame seen from the body: at the pivot point, body axes.
            joint.setTransformFromChildBodyNode(dartpy.math.Isometry3(np.eye(3), self._pivot))
        node.setInertia(
            dartpy.dynamics.Inertia(
                float(body.mass), np.zeros(3), np.diag(np.asarray(body.moments, dtype=float))
            )
        )
        world.addSkeleton(skeleton)
        self._world, self._joint, self._node = world, joint, node

    def inertia(self) -> tuple[float, Array]:
        """The mass (kg) and the inertia about the centre of mass in body axes (kg·m²)
        that the BodyNode holds (DART keeps its moment about the centre of mass)."""
        inertia = self._node.getInertia()
        return float(inertia.getMass()), np.array(inertia.getMoment(), dtype=float)

    def set_state(self, quaternion: Array, omega: Array) -> None:
        """Set the attitude (scalar first, body → space) and ω (space axes, rad/s); a free
        body's centre of mass stays at rest at the origin, a pivot stays still."""
        matrix = rotation(quaternion).as_matrix()
        omega = np.asarray(omega, dtype=float)
        if self._pivot is None:
            transform = self._dart.math.Isometry3(matrix, np.zeros(3))
            self._joint.setPositions(self._joint.convertToPositions(transform))
            self._joint.setVelocities(np.concatenate([omega, np.zeros(3)]))
        else:
            # A BallJoint's positions are the log map of the joint rotation and its
            # velocities the angular velocity in the joint's (body) axes.
            self._joint.setPositions(self._joint.convertToPositions(matrix))
            self._joint.setVelocities(matrix.T @ omega)

    def step(self, count: int) -> None:
        """Advance ``count`` steps of the World's time step."""
        step = self._world.step
        # DART prints its warnings (non-finite accelerations, forces, transforms) to
        # stderr at every step once the state has blown up: kept as its report.
        with self._output:
            for _ in range(int(count)):
                step()

    def state(self) -> tuple[Array, Array]:
        """The attitude (scalar first, body → space) of the BodyNode and ω (space axes,
        rad/s) from the joint's velocities now."""
        velocities = np.asarray(self._joint.getVelocities(), dtype=float)
        matrix = np.asarray(self._node.getTransform().rotation(), dtype=float)
        if not np.all(np.isfinite(matrix)):
            # No attitude to read: show the identity, as DART's FreeJoint does for a
            # non-finite pose, and let :meth:`failure` report the joint's state.
            matrix = np.eye(3)
        quaternion = Rotation.from_matrix(matrix).as_quat(scalar_first=True)
        if self._pivot is None:
            return np.asarray(quaternion, dtype=float), velocities[:3]
        # A BallJoint's velocities are ω in the body's axes.
        return np.asarray(quaternion, dtype=float), matrix @ velocities[:3]

    def failure(self) -> str:
        """Why the joint's state is no longer a state (non-finite), "" otherwise."""
        if self._joint is None:
            return ""
        positions = np.asarray(self._joint.getPositions(), dtype=float)
        velocities = np.asarray(self._joint.getVelocities(), dtype=float)
        if not (np.all(np.isfinite(positions)) and np.all(np.isfinite(velocities))):
            return "DART's joint positions or velocities are not finite"
        if self._output.first:
            return f"DART warned: {self._output.first}"
        return ""

    def close(self) -> None:
        """Drop the World and its Skeleton."""
        self._world = self._joint = self._node = None
        self._output.close()
