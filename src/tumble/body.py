"""The body model: what a simulation integrates, and what its motion conserves.

A :class:`RigidBody` is a body's mass properties turning about a reference
point: its centre of mass (a free body) or a pivot, a body point held fixed in
space. Everything the integrators and the trajectories need of the body is
computed here, once: the inertia about the reference point and its principal
frame (the kernels work in it), the changes of axes between the user's body
axes and that frame, the angular momentum and kinetic energy, the fastest rate
a time step must resolve, and the quantities its motion conserves
(:data:`INVARIANTS`).

:class:`BodyBatch` is the same for N free bodies at once (:func:`tumble.simulate_batch`).

Conventions as in the rest of tumble: SI units, angular velocity in body axes,
quaternions ``[w, x, y, z]`` turning body coordinates into space coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.errors import InputError
from tumble.massprops import PHYSICAL_TOLERANCE, MassProperties, principal_decomposition

__all__ = [
    "INVARIANTS",
    "ZERO_MOMENT",
    "BodyBatch",
    "Invariant",
    "RigidBody",
    "label",
    "reduce_invariants",
]

Array = NDArray[np.float64]

#: A principal moment below this fraction of the largest counts as zero: such a
#: body (a thin rod, point masses on a line) has an axis it cannot spin about,
#: and Euler's equations divide by each moment.
ZERO_MOMENT = 1e-12


@dataclass(frozen=True)
class Invariant:
    """A quantity a motion may conserve: its key in drift reports, a short label
    and what it is."""

    name: str
    label: str
    description: str
    implied_by: str | None = None


#: Every quantity a body model or a torque model can declare conserved.
INVARIANTS: dict[str, Invariant] = {
    invariant.name: invariant
    for invariant in (
        Invariant("energy", "energy", "kinetic plus potential energy, J"),
        Invariant(
            "angular_momentum_vector",
            "vector L",
            "angular momentum about the reference point, space axes, kg·m²/s",
        ),
        Invariant(
            "angular_momentum_norm",
            "|L|",
            "magnitude of the angular momentum, kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "angular_momentum_vertical",
            "L_vertical",
            "component of L along the upward vertical (against gravity), kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "angular_momentum_axial",
            "L_axial",
            "component of L along the body's symmetry axis through the pivot, kg·m²/s",
            implied_by="angular_momentum_vector",
        ),
        Invariant(
            "jacobi_integral",
            "Jacobi integral",
            "energy in a frame turning at a constant rate, J",
        ),
    )
}

#: What a torque-free rigid body conserves (every component of L with L).
FREE_BODY_INVARIANTS = frozenset(
    {
        "energy",
        "angular_momentum_vector",
        "angular_momentum_norm",
        "angular_momentum_vertical",
        "angular_momentum_axial",
    }
)


def label(name: str) -> str:
    """The short label of a conserved quantity (its name when it is a model's own)."""
    invariant = INVARIANTS.get(name)
    return invariant.label if invariant is not None else name.replace("_", " ")


def reduce_invariants(names: frozenset[str] | set[str]) -> tuple[str, ...]:
    """The conserved quantities to report, in the order of :data:`INVARIANTS`,
    leaving out those implied by another one in the set (the components of a
    conserved vector L)."""
    return tuple(
        name
        for name, invariant in INVARIANTS.items()
        if name in names and invariant.implied_by not in names
    )


@dataclass(frozen=True, eq=False)
class RigidBody:
    """A rigid body turning about its reference point: the centre of mass
    (``pivot`` None) or a body point held fixed in space.

    Attributes
    ----------
    mass_properties : the body (its inertia about the centre of mass, body axes).
    pivot : None, or (3,) body coordinates of the fixed point, m.
    """

    mass_properties: MassProperties
    pivot: Array | None = None

    @cached_property
    def reference_point(self) -> Array:
        """(3,) body coordinates of the point the body turns about, m."""
        mp = self.mass_properties
        return mp.center_of_mass if self.pivot is None else np.asarray(self.pivot, dtype=float)

    @cached_property
    def inertia(self) -> Array:
        """(3, 3) inertia about the reference point, body axes, kg·m²."""
        mp = self.mass_properties
        return mp.inertia if self.pivot is None else mp.inertia_about(self.reference_point)

    @cached_property
    def _principal(self) -> tuple[Array, Array]:
        return principal_decomposition(self.inertia)

    @property
    def moments(self) -> Array:
        """(3,) principal moments about the reference point, ascending, kg·m²."""
        return self._principal[0]

    @property
    def axes(self) -> Array:
        """(3, 3) principal axes as columns in body coordinates (a proper rotation)."""
        return self._principal[1]

    @cached_property
    def principal_rotation(self) -> Rotation:
        """The rotation principal axes → body axes."""
        return Rotation.from_matrix(self.axes)

    @cached_property
    def lever(self) -> Array:
        """(3,) from the reference point to the centre of mass, body axes, m."""
        return np.asarray(self.mass_properties.center_of_mass - self.reference_point)

    def check_simulable(self) -> None:
        """Raise InputError for a body with a zero principal moment."""
        moments = self.moments
        if moments[0] <= ZERO_MOMENT * moments[2]:
            raise InputError(
                f"Expected a body with no zero principal moment to simulate, got moments "
                f"{moments.tolist()} kg·m² (an idealised rod or point masses on a line: give the "
                "body some thickness)."
            )

    # ------------------------------------------------------------ axes
    def to_principal(self, vectors: Any) -> Array:
        """Body-axes vectors (..., 3) in principal coordinates."""
        return np.asarray(np.asarray(vectors, dtype=float) @ self.axes)

    def from_principal(self, vectors: Any) -> Array:
        """Principal-coordinates vectors (..., 3) in body axes."""
        return np.asarray(np.asarray(vectors, dtype=float) @ self.axes.T)

    def attitude_to_principal(self, quaternions: Array) -> Array:
        """Quaternions body → space (..., 4) as principal → space (``q ⊗ q_axes``)."""
        return compose(quaternions, self.principal_rotation)

    def attitude_from_principal(self, quaternions: Array) -> Array:
        """Quaternions principal → space (..., 4) as body → space."""
        return compose(quaternions, self.principal_rotation.inv())

    # ------------------------------------------------------------ physics
    def angular_momentum(self, omega: Array) -> Array:
        """``I ω`` about the reference point, body axes, kg·m²/s, for ω (..., 3) rad/s."""
        return np.asarray(np.asarray(omega, dtype=float) @ self.inertia.T)

    def kinetic_energy(self, omega: Array) -> Array:
        """``½ ω · I ω``, J, for ω (..., 3) rad/s in body axes."""
        omega = np.asarray(omega, dtype=float)
        return np.asarray(0.5 * np.einsum("...i,...i->...", omega, self.angular_momentum(omega)))

    def is_symmetric_top(self) -> bool:
        """True for a body on a pivot with two equal principal moments about the
        pivot and its centre of mass on the third axis (a Lagrange top): then
        the component of L along that axis is conserved under gravity."""
        if self.pivot is None:
            return False
        size = float(np.linalg.norm(self.lever))
        if size == 0.0:
            return False
        moments, axes = self.moments, self.axes
        along = np.abs(axes.T @ (self.lever / size))
        close = PHYSICAL_TOLERANCE * float(moments.sum())
        for axis, (i, j) in ((0, (1, 2)), (2, (0, 1))):
            if abs(moments[i] - moments[j]) <= close and along[axis] >= 1 - 1e-9:
                return True
        return False

    def conserved(self, torques: Any) -> tuple[str, ...]:
        """The quantities (keys of :data:`INVARIANTS`) the motion of this body conserves
        under the torque models ``torques`` (those that act on it; see
        :meth:`tumble.torques.TorqueModel.conserves`): what a torque-free body
        conserves, less what each model changes."""
        kept = set(FREE_BODY_INVARIANTS)
        for torque in torques:
            kept &= torque.conserves(self)
        return reduce_invariants(kept)

    def fastest_rate(self, omega: Array, weight: float, exact_spin: bool = False) -> float:
        """An upper estimate of the fastest angular rate a time step must resolve, rad/s.

        Torque-free, |ω| never exceeds |L| / I1 (``omega`` in body axes, rad/s). A
        body on a pivot under a weight ``weight`` (N) adds the pendulum rate
        √(m g l / I1). With ``exact_spin`` (integrators whose free flow turns a
        symmetric body exactly), a symmetric body's spin about its symmetry
        axis needs no resolving: the rate is |L| / I⊥, that of the precession of
        the axis about L (and of nutation).
        """
        moments = self.moments
        momentum = float(np.linalg.norm(moments * self.to_principal(omega)))
        rate = momentum / moments[0]
        # principal_decomposition makes repeated moments exactly equal; an oblate
        # body (I1 = I2) keeps |L| / I1.
        if exact_spin and moments[2] == moments[1]:  # prolate: symmetry axis 1
            rate = momentum / moments[1]
        if self.pivot is not None:
            rate += math.sqrt(weight * float(np.linalg.norm(self.lever)) / moments[0])
        return rate


@dataclass(frozen=True, eq=False)
class BodyBatch:
    """N free bodies at once, each turning about its centre of mass.

    Attributes
    ----------
    moments : (N, 3) principal moments, kg·m², ascending per body when given
        as tensors, in the order given otherwise.
    axes : None when the body axes are principal axes, else (N, 3, 3) each
        body's principal axes as columns in its body coordinates.
    """

    moments: Array
    axes: Array | None = None

    @classmethod
    def from_inertia(cls, inertia: Array) -> BodyBatch:
        """From (N, 3) principal moments or (N, 3, 3) inertia tensors (kg·m²)."""
        if inertia.ndim == 2:
            return cls(inertia)
        tensors = 0.5 * (inertia + np.swapaxes(inertia, 1, 2))
        moments, axes = principal_decomposition(tensors)
        return cls(moments, axes)

    def __len__(self) -> int:
        return len(self.moments)

    @cached_property
    def principal_rotation(self) -> Rotation | None:
        """The rotations principal axes → body axes, or None."""
        return None if self.axes is None else Rotation.from_matrix(self.axes)

    def to_principal(self, vectors: Any) -> Array:
        """Body-axes vectors ((3,) shared or (N, 3)) in each body's principal axes."""
        values = np.asarray(vectors, dtype=float)
        if self.axes is None:
            return values
        values = np.broadcast_to(values, (len(self), 3))
        return np.asarray(np.einsum("nji,nj->ni", self.axes, values))

    def from_principal(self, vectors: Array) -> Array:
        """(N, 3) principal-axes vectors in each body's axes."""
        if self.axes is None:
            return vectors
        return np.asarray(np.einsum("nij,nj->ni", self.axes, vectors))

    def attitude_to_principal(self, quaternions: Array) -> Array:
        """(N, 4) quaternions body → space as principal → space."""
        if self.principal_rotation is None:
            return quaternions
        return compose(quaternions, self.principal_rotation)

    def attitude_from_principal(self, quaternions: Array) -> Array:
        """(N, 4) quaternions principal → space as body → space."""
        if self.principal_rotation is None:
            return quaternions
        return compose(quaternions, self.principal_rotation.inv())


def compose(quaternions: Array, rotation: Rotation) -> Array:
    """Scalar-first quaternions of ``R(q) · rotation``: a compiled loop for one
    rotation (the samples of a trajectory), scipy for one rotation per row."""
    if rotation.single:
        from tumble.core.quaternion import multiply_right

        stack = np.ascontiguousarray(np.atleast_2d(quaternions), dtype=float)
        r = np.asarray(rotation.as_quat(scalar_first=True), dtype=float)
        out = multiply_right(stack, r)
        return np.asarray(out[0] if np.ndim(quaternions) == 1 else out)
    return np.asarray(
        (Rotation.from_quat(quaternions, scalar_first=True) * rotation).as_quat(scalar_first=True)
    )
