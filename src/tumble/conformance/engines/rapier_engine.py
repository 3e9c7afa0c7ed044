"""Rapier (the ``rapier3d`` Python package, float32) stepping one rigid body.

The body is a dynamic rigid body whose mass properties are given explicitly
(Rapier's "additional mass properties"), with no collider, so nothing is
computed from geometry and nothing can collide. Rapier stores the angular
velocity in space (world) axes and integrates it with its gyroscopic term on
(its default), in float32: rotating ω into body axes and back in each of its
4 substeps a step adds about an ulp to |ω|, so the energy gained grows with the
number of steps, not with dt. By default it clamps the rotation of a step to
π/4 (for its continuous collision detection) and puts a body to sleep once its
rates stay below its thresholds (0.5 rad/s) for 0.5 s, zeroing them; the plain
variant turns both off, the ``sleeping`` variant keeps them and reports the
sleep.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np

from tumble.conformance.engine import Array, Engine, EngineBody, register_engine, rotation

__all__ = ["RapierEngine"]


def _vector(values: Any) -> list[float]:
    """A 3-vector as Rapier takes it: a list of Python floats."""
    return [float(v) for v in values]


@register_engine
class RapierEngine(Engine):
    """Rapier's dynamic rigid body with explicit mass properties and no collider."""

    name: ClassVar[str] = "rapier"
    variants: ClassVar[dict[str, str]] = {
        "": "Rapier's defaults (float32, gyroscopic term on), sleeping and the spin cap turned off",
        "sleeping": "Rapier's defaults as they are: a body slower than 0.5 rad/s for 0.5 s sleeps",
    }
    modules: ClassVar[tuple[str, ...]] = ("rapier3d",)
    omega_frame: ClassVar[Literal["body", "space"]] = "space"
    holds_pivot: ClassVar[bool] = True
    pivot_method: ClassVar[str] = (
        "a spherical impulse joint between the body point and a fixed body at the origin"
    )
    precision: ClassVar[str] = "float32"

    def build(self, body: EngineBody, dt: float) -> None:
        """Create a world with the body (and a fixed body holding its pivot), stepping at
        ``dt`` s."""
        import rapier3d

        self._body = body
        self._dt = float(dt)
        self._steps = 0
        self._slept_at = float("nan")
        self._quarantined_at = float("nan")
        self._world = world = rapier3d.PhysicsWorld(gravity=_vector(body.gravity))
        world.integration_parameters.dt = self._dt
        props = rapier3d.MassProperties(
            local_com=(0.0, 0.0, 0.0),
            mass=float(body.mass),
            principal_inertia=_vector(body.moments),
            principal_inertia_local_frame=rapier3d.Rotation3.identity(),
        )
        builder = rapier3d.RigidBody.dynamic().additional_mass_properties(props)
        if not builder.build().gyroscopic_forces_enabled:
            # Without its gyroscopic term Rapier keeps ω constant in space: no rigid body.
            builder = builder.gyroscopic_forces(True)
            self.notes.append("gyroscopic forces turned on")
        if self.variant == "":
            # Sleeping stops a slow body; the cap on a step's rotation limits |ω| dt to π/4.
            builder = builder.can_sleep(False).allow_fast_rotation(True)
            self.notes.append("sleeping turned off")
            self.notes.append("angular speed cap (π/4 rad a step) turned off")
        self._handle = world.add_body(builder)
        # Rapier gathers the mass properties when it first steps; gather them now so that
        # inertia() reads what the first step will use.
        self._rigid_body().recompute_mass_properties_from_colliders(world.colliders)
        if body.pivot is not None:
            anchor = world.add_body(rapier3d.RigidBody.fixed())
            joint = (
                rapier3d.SphericalJoint.builder()
                .local_anchor1((0.0, 0.0, 0.0))
                .local_anchor2(_vector(body.pivot))
                .build()
            )
            world.impulse_joints.insert(anchor, self._handle, joint)

    def _rigid_body(self) -> Any:
        return self._world.rigid_bodies[self._handle]

    def inertia(self) -> tuple[float, Array]:
        """The mass (kg) and inertia about the centre of mass in body axes (kg·m²) Rapier uses."""
        props = self._rigid_body().mass_properties
        frame = props.principal_inertia_local_frame
        axes = rotation(np.array([frame.w, frame.i, frame.j, frame.k])).as_matrix()
        moments = np.array(props.principal_inertia.to_tuple(), dtype=float)
        return float(props.mass), axes @ np.diag(moments) @ axes.T

    def set_state(self, quaternion: Array, omega: Array) -> None:
        """Set the attitude (scalar first, body → space) and ω in space axes (rad/s)."""
        import rapier3d

        q = np.asarray(quaternion, dtype=float)
        w = np.asarray(omega, dtype=float)
        rigid_body = self._rigid_body()
        rigid_body.rotation = rapier3d.Rotation3(*map(float, q))
        rigid_body.angvel = _vector(w)
        if self._body.pivot is None:
            rigid_body.translation = (0.0, 0.0, 0.0)
            rigid_body.linvel = (0.0, 0.0, 0.0)
        else:
            # The centre of mass sits at -R p from the pivot and moves with ω × (-R p).
            arm = -rotation(q).apply(self._body.pivot)
            rigid_body.translation = _vector(arm)
            rigid_body.linvel = _vector(np.cross(w, arm))

    def step(self, count: int) -> None:
        """Advance ``count`` steps of dt, noting when Rapier puts the body to sleep or
        quarantines it (a non-finite state)."""
        world = self._world
        watch_sleep = self.variant == "sleeping" and np.isnan(self._slept_at)
        for _ in range(int(count)):
            world.step()
            self._steps += 1
            if watch_sleep and self._rigid_body().is_sleeping:
                self._slept_at = self._steps * self._dt
                watch_sleep = False
        # A quarantined body stays disabled, so one look after the steps finds it.
        if np.isnan(self._quarantined_at) and not self._rigid_body().is_enabled:
            self._quarantined_at = self._steps * self._dt

    def state(self) -> tuple[Array, Array]:
        """The attitude (scalar first, body → space) and ω in space axes (rad/s)."""
        rigid_body = self._rigid_body()
        attitude = rigid_body.rotation
        q = np.array([attitude.w, attitude.i, attitude.j, attitude.k], dtype=float)
        return q, np.array(rigid_body.angvel.to_tuple(), dtype=float)

    def failure(self) -> str:
        """Rapier's quarantine of a non-finite body, or the body put to sleep ("" if neither)."""
        if not np.isnan(self._quarantined_at):
            return (
                "Rapier quarantined the body (its state became non-finite) "
                f"by t = {self._quarantined_at:.6g} s"
            )
        if not np.isnan(self._slept_at):
            return f"put to sleep at t = {self._slept_at:.6g} s"
        return ""

    def close(self) -> None:
        """Drop the world."""
        self.__dict__.pop("_world", None)
