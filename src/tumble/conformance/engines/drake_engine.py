"""Drake: one rigid body in a bare MultibodyPlant, continuous or discrete, run by a Simulator.

The body is added with :meth:`MultibodyPlant.AddRigidBody` from a spatial inertia
built from the mass and the central inertia (no geometry, no SceneGraph), so
Drake's free-body joint (a quaternion floating joint) carries it. Drake stores
the angular velocity of a free body in world axes, ``V_WB``.

Two ways of running it:

* ``continuous``: a continuous plant (``time_step=0``) and the Simulator's
  default integrator, an error-controlled third-order Runge–Kutta at a target
  accuracy of 1e-4 (Drake's ``SimulatorConfig`` defaults, largest step 0.1 s).
  It picks its own steps, and the adapter lets it: one ``AdvanceTo`` of the
  whole horizon, the state recorded after each step by the Simulator's monitor,
  as a user's run with a logger at every step gets it; ``dt`` is not used (an
  ``AdvanceTo`` at each multiple of ``dt`` would end a step there and make the
  run more accurate than the integrator's own choice).
* ``discrete``: a discrete plant (``time_step=dt``), one update per ``dt``;
  without contact its update is a semi-implicit Euler step. Drake does not
  renormalise the free body's quaternion (it normalises it where it is used),
  so its length drifts with the error.

With a pivot, a :class:`BallRpyJoint` holds the body: roll–pitch–yaw angles,
singular only when the body's axis lies horizontal along one direction.

Drake has no sleeping and no velocity limit on a free body, so nothing is
turned off. A blow-up of the state is silent in Drake (the suite sees the
non-finite state); an exception raised while stepping is reported by
:meth:`DrakeEngine.failure`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from tumble.conformance.engine import (
    Array,
    Engine,
    EngineBody,
    Samples,
    diverged,
    divergence_limit,
    register_engine,
)

__all__ = ["DrakeEngine"]


@register_engine
class DrakeEngine(Engine):
    """Drake's MultibodyPlant with one body (free or on a ball joint), run by a Simulator."""

    name = "drake"
    variants: ClassVar[dict[str, str]] = {
        "continuous": (
            "continuous plant (time_step=0), the Simulator's default error-controlled RK3 at"
            " accuracy 1e-4, over the whole horizon in one AdvanceTo, sampled after each of"
            " its own steps (dt not used)"
        ),
        "discrete": "discrete plant (time_step=dt): one semi-implicit Euler update per dt",
    }
    modules = ("pydrake",)
    omega_frame = "space"
    holds_pivot = True
    pivot_method = (
        "a BallRpyJoint from the world origin to the pivot point, its roll axis along the"
        " body's axis and zero pitch with that axis straight up (singular only with the axis"
        " horizontal towards one direction)"
    )

    def build(self, body: EngineBody, dt: float) -> None:
        """Create a plant with this one body and a Simulator sampling every ``dt`` (s)."""
        from pydrake.math import RigidTransform, RotationMatrix
        from pydrake.multibody.plant import MultibodyPlant
        from pydrake.multibody.tree import (
            BallRpyJoint,
            FixedOffsetFrame,
            RotationalInertia,
            SpatialInertia,
        )
        from pydrake.systems.analysis import Simulator

        self.dt = float(dt)
        plant = MultibodyPlant(time_step=self.dt if self.variant == "discrete" else 0.0)
        moments = [float(m) for m in body.moments]
        inertia = SpatialInertia.MakeFromCentralInertia(
            float(body.mass), _vector(np.zeros(3)), RotationalInertia(*moments)
        )
        self.body = plant.AddRigidBody("body", inertia)
        self.joint: Any = None
        if body.pivot is not None:
            # Roll–pitch–yaw angles are singular at pitch ±90°, when the joint's x axis
            # (here the body's axis, pivot → centre of mass) lies along the parent frame's
            # z axis; the parent's x axis points up, so only a horizontal axis towards the
            # parent's z can reach it.
            pivot = np.asarray(body.pivot, dtype=float)
            down = np.asarray(body.gravity, dtype=float)
            up = -down / np.linalg.norm(down) if np.linalg.norm(down) > 0 else np.array([0, 0, 1.0])
            self.parent_axes = _axes_with_x(up)
            self.child_axes = _axes_with_x(-pivot / np.linalg.norm(pivot))
            parent = plant.AddFrame(
                FixedOffsetFrame(
                    "pivot_in_world",
                    plant.world_frame(),
                    RigidTransform(RotationMatrix(self.parent_axes), _vector(np.zeros(3))),
                )
            )
            child = plant.AddFrame(
                FixedOffsetFrame(
                    "pivot_in_body",
                    self.body.body_frame(),
                    RigidTransform(RotationMatrix(self.child_axes), _vector(pivot)),
                )
            )
            self.joint = plant.AddJoint(BallRpyJoint("pivot", parent, child))
        plant.mutable_gravity_field().set_gravity_vector(_vector(body.gravity))
        plant.Finalize()
        self.plant = plant
        self.simulator = Simulator(plant)
        self.context = self.simulator.get_mutable_context()
        self.steps_done = 0
        self.error = ""

    def inertia(self) -> tuple[float, Array]:
        """The mass (kg) and the inertia about the centre of mass in body axes (kg·m²) that
        the plant's context holds."""
        spatial = self.body.CalcSpatialInertiaInBodyFrame(self.context)
        # The spatial inertia is taken about the body origin: shift it to the centre of mass.
        central = spatial.Shift(spatial.get_com())
        return float(central.get_mass()), np.array(
            central.CalcRotationalInertia().CopyToFullMatrix3()
        )

    def set_state(self, quaternion: Array, omega: Array) -> None:
        """Set the attitude (scalar first, body → space) and ω in space axes (rad/s); a free
        body's centre of mass stays at rest at the origin."""
        from pydrake.common.eigen_geometry import Quaternion
        from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix
        from pydrake.multibody.math import SpatialVelocity

        q = np.asarray(quaternion, dtype=float)
        rotation = RotationMatrix(Quaternion(q / np.linalg.norm(q)))
        omega = np.asarray(omega, dtype=float)
        if self.joint is None:
            self.plant.SetFreeBodyPose(
                self.context, self.body, RigidTransform(rotation, _vector(np.zeros(3)))
            )
            self.plant.SetFreeBodySpatialVelocity(
                self.context, self.body, SpatialVelocity(_vector(omega), _vector(np.zeros(3)))
            )
        else:
            # The joint's angles give the child frame in the parent frame; its velocities are
            # the child's angular velocity in parent axes.
            relative = self.parent_axes.T @ rotation.matrix() @ self.child_axes
            angles = RollPitchYaw(RotationMatrix(relative)).vector()
            self.joint.set_angles(self.context, angles)
            self.joint.set_angular_velocity(self.context, self.parent_axes.T @ omega)
        self.simulator.Initialize()

    def step(self, count: int) -> None:
        """Advance ``count`` intervals of ``dt``; an exception from Drake is kept for
        :meth:`failure`."""
        if self.error:
            return
        # The target is a multiple of dt (not a running sum): a discrete plant makes
        # exactly one update per step.
        self.steps_done += int(count)
        try:
            self.simulator.AdvanceTo(self.steps_done * self.dt)
        except RuntimeError as error:
            self.error = " ".join(str(error).split()) or type(error).__name__

    def simulate(
        self,
        body: EngineBody,
        quaternion0: Array,
        omega0: Array,
        dt: float,
        steps: int,
        every: int,
        progress: Callable[[int], object] | None = None,
    ) -> Samples:
        """The discrete plant as every engine; the continuous one over the whole horizon in
        one ``AdvanceTo``, sampled after each of its integrator's own steps."""
        if self.variant != "continuous":
            return super().simulate(body, quaternion0, omega0, dt, steps, every, progress)
        from pydrake.systems.framework import EventStatus

        self.set_state(np.asarray(quaternion0, float), self.engine_omega(quaternion0, omega0))
        limit = divergence_limit(body, omega0)
        times: list[float] = []
        quaternions: list[Array] = []
        omegas: list[Array] = []
        stopped = ""

        def record(context: Any) -> Any:
            nonlocal stopped
            q, w = self.state()
            stopped = diverged(q, w, limit)
            if stopped:
                return EventStatus.ReachedTermination(None, stopped)
            time_now = float(context.get_time())
            if not times or time_now > times[-1]:
                times.append(time_now)
                quaternions.append(q / np.linalg.norm(q))
                omegas.append(self.body_omega(q, w))
            return EventStatus.Succeeded()

        record(self.context)
        self.simulator.set_monitor(record)
        start = time.perf_counter()
        try:
            self.simulator.AdvanceTo(steps * dt)
        except RuntimeError as error:
            self.error = " ".join(str(error).split()) or type(error).__name__
        wall = time.perf_counter() - start
        if progress is not None:
            progress(steps)
        failure = self.failure() or stopped
        failed_at = float(self.context.get_time()) if failure else float("nan")
        return Samples(
            np.array(times),
            np.array(quaternions),
            np.array(omegas),
            failed_at,
            failure,
            wall,
            steps,
        )

    def state(self) -> tuple[Array, Array]:
        """The attitude (scalar first, body → space) and ω in space axes (rad/s) now."""
        if self.error:
            return np.full(4, np.nan), np.full(3, np.nan)
        pose = self.plant.EvalBodyPoseInWorld(self.context, self.body)
        velocity = self.plant.EvalBodySpatialVelocityInWorld(self.context, self.body)
        q = pose.rotation().ToQuaternion()
        return np.array([q.w(), q.x(), q.y(), q.z()]), np.array(velocity.rotational())

    def failure(self) -> str:
        """The exception Drake raised while stepping ("" if none)."""
        return f"Drake raised: {self.error}" if self.error else ""

    def close(self) -> None:
        """Drop the plant and its Simulator."""
        for attribute in ("simulator", "context", "plant", "body", "joint"):
            self.__dict__.pop(attribute, None)


def _axes_with_x(direction: Array) -> Array:
    """A rotation matrix (columns: axes) whose x axis is the unit vector ``direction``."""
    x = np.asarray(direction, dtype=float)
    helper = np.eye(3)[int(np.argmin(np.abs(x)))]
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def _vector(values: Any) -> Any:
    """A float64 array as pydrake's bindings take it (their stubs spell the type their own way)."""
    return np.asarray(values, dtype=float)
