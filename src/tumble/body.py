"""The body model: what a simulation integrates, and what its motion conserves.

A :class:`RigidBody` is a body's mass properties turning about a reference
point: its centre of mass (a free body) or a pivot, a body point held fixed in
space, with the parts it carries inside (:mod:`tumble.parts`: rotors,
dampers; held in the mass properties as if locked). Everything the
integrators and the trajectories need of the body is computed here, once: the
inertia about the reference point, the *platform inertia* that turns at the
body's own rate (the inertia less the parts' spin inertia; the whole inertia
for a body without parts) and its principal frame (the kernels work in it),
the changes of axes between the user's body axes and that frame, the state of
the parts, the angular momentum and kinetic energy, the fastest rate a time
step must resolve, and the quantities its motion conserves (:data:`tumble.invariants.INVARIANTS`).

:class:`BodyBatch` is the same for N free bodies at once (:func:`tumble.simulate_batch`).

Conventions as in the rest of tumble: SI units, angular velocity in body axes,
quaternions ``[w, x, y, z]`` turning body coordinates into space coordinates.
"""

from __future__ import annotations

import itertools
import math
import operator
import threading
from collections import OrderedDict
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.errors import InputError
from tumble.invariants import FREE_BODY_INVARIANTS, largest_rate, reduce_invariants
from tumble.massprops import PHYSICAL_TOLERANCE, MassProperties, principal_decomposition
from tumble.parts import InternalPart, kernel_layout, pack_parts

__all__ = ["BODY_CACHE_SIZE", "ZERO_MOMENT", "BodyBatch", "RigidBody", "body_model"]

Array = NDArray[np.float64]

#: A principal moment below this fraction of the largest counts as zero: such a
#: body (a thin rod, point masses on a line) has an axis it cannot spin about,
#: and Euler's equations divide by each moment.
ZERO_MOMENT = 1e-12


@dataclass(frozen=True, eq=False)
class RigidBody:
    """A rigid body turning about its reference point: the centre of mass
    (``pivot`` None) or a body point held fixed in space, possibly carrying parts.

    Attributes
    ----------
    mass_properties : the body, its parts included as if locked (its inertia about
        the centre of mass, body axes).
    pivot : None, or (3,) body coordinates of the fixed point, m.
    parts : the parts it carries (:mod:`tumble.parts`), in the order given.

    Raises
    ------
    InputError
        Parts whose spin inertia the body cannot hold (the platform inertia
        would not be positive definite).
    """

    mass_properties: MassProperties
    pivot: Array | None = None
    parts: tuple[InternalPart, ...] = ()

    def __post_init__(self) -> None:
        if self.parts:
            attached = tuple(part.attached(self.mass_properties) for part in self.parts)
            object.__setattr__(self, "parts", attached)
            for part in attached:
                if self.pivot is not None and part.free_body_only is not None:
                    raise InputError(
                        f"Expected a free body for a {type(part).__name__} "
                        f"({part.free_body_only}), got a pivot."
                    )
            moments = np.linalg.eigvalsh(0.5 * (self.platform_inertia + self.platform_inertia.T))
            if not moments[0] > ZERO_MOMENT * max(float(moments[2]), 0.0):
                locked = np.linalg.eigvalsh(self.inertia)
                left = np.round(moments, 12).tolist()
                raise InputError(
                    "Expected internal parts whose spin inertia the body can hold (each "
                    "rotor's J a aᵀ and each damper's J 1 taken from the body's inertia must "
                    f"leave positive principal moments), got {left} kg·m² left of the body's "
                    f"{np.round(locked, 12).tolist()} kg·m²: is a part's inertia missing from "
                    "the body's mass properties, or too large?"
                )

    @cached_property
    def reference_point(self) -> Array:
        """(3,) body coordinates of the point the body turns about, m."""
        mp = self.mass_properties
        return mp.center_of_mass if self.pivot is None else np.asarray(self.pivot, dtype=float)

    @cached_property
    def inertia(self) -> Array:
        """(3, 3) inertia about the reference point, body axes, kg·m² (the parts locked)."""
        mp = self.mass_properties
        return mp.inertia if self.pivot is None else mp.inertia_about(self.reference_point)

    @cached_property
    def platform_inertia(self) -> Array:
        """(3, 3) the inertia that turns at the body's own rate ω (kg·m², body axes,
        about the reference point): :attr:`inertia` less each part's spin inertia."""
        tensor = np.array(self.inertia, dtype=float)
        for part in self.parts:
            tensor -= part.spin_inertia()
        return tensor

    @cached_property
    def _principal(self) -> tuple[Array, Array]:
        if self.pivot is None and not self.parts:
            # The platform is the body: its decomposition, computed once per body. Copies,
            # writable: the kernels' arguments keep the type they were compiled for.
            moments, axes = self.mass_properties.principal()
            return np.array(moments), np.array(axes)
        return principal_decomposition(self.platform_inertia)

    @property
    def moments(self) -> Array:
        """(3,) principal moments of the platform inertia (the inertia about the
        reference point for a body without parts), ascending, kg·m²."""
        return self._principal[0]

    @property
    def axes(self) -> Array:
        """(3, 3) their principal axes as columns in body coordinates (a proper
        rotation): the frame the kernels work in."""
        return self._principal[1]

    @cached_property
    def inertia_principal(self) -> Array:
        """(3, 3) the whole inertia (parts locked) about the reference point in the
        principal axes of :attr:`moments`, kg·m² (diagonal without parts)."""
        return np.asarray(self.axes.T @ self.inertia @ self.axes)

    @cached_property
    def principal_rotation(self) -> Rotation:
        """The rotation principal axes → body axes."""
        return Rotation.from_matrix(self.axes)

    @cached_property
    def _principal_quaternions(self) -> tuple[Array, Array]:
        """The scalar-first quaternions of :attr:`principal_rotation` and of its
        inverse (the conjugate, as scipy's ``inv``): each attitude's change of
        axes multiplies by one of them."""
        turn = np.asarray(self.principal_rotation.as_quat(scalar_first=True), dtype=float)
        return turn, turn * np.array([1.0, -1.0, -1.0, -1.0])

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

    @cached_property
    def _axes_are_body_axes(self) -> bool:
        return bool(np.array_equal(self.axes, np.eye(3)))

    def attitude_to_principal(self, quaternions: Array) -> Array:
        """Quaternions body → space (..., 4) as principal → space (``q ⊗ q_axes``)."""
        if self._axes_are_body_axes:  # the principal axes are the body's: q ⊗ 1 = q
            return np.array(quaternions, dtype=float)
        return _turned(quaternions, self._principal_quaternions[0])

    def attitude_from_principal(self, quaternions: Array) -> Array:
        """Quaternions principal → space (..., 4) as body → space."""
        if self._axes_are_body_axes:
            return np.array(quaternions, dtype=float)
        return _turned(quaternions, self._principal_quaternions[1])

    # ------------------------------------------------------------ parts
    @cached_property
    def layout(self) -> Any:
        """The kernels' layout of its parts (:func:`tumble.parts.kernel_layout`)."""
        return kernel_layout(self, self.parts)

    @cached_property
    def packed_parts(self) -> Array:
        """(rows, 1) its parts packed for the kernels (:func:`tumble.parts.pack_parts`)."""
        packed = pack_parts(self, self.parts)
        packed.flags.writeable = False
        return packed

    def initial_values(self, omega0: Array) -> Array:
        """(..., m) the parts' values at t = 0 for the body's ω0 (..., 3)
        (:meth:`tumble.parts.InternalPart.initial_values`); m, here and below, is
        the sum of the parts' sizes."""
        omega0 = np.asarray(omega0, dtype=float)
        pieces = [part.initial_values(omega0) for part in self.parts]
        return np.concatenate(pieces, axis=-1) if pieces else np.zeros((*omega0.shape[:-1], 0))

    def split_values(self, values: Array | None, omega: Array | None = None) -> list[Array]:
        """The parts' values (..., m), cut per part; None: their initial
        values for ω (..., 3) (a damper turning with the body)."""
        if values is None:
            start = np.zeros(3) if omega is None else omega
            return [part.initial_values(start) for part in self.parts]
        cuts = np.cumsum([0, *(part.size for part in self.parts)])
        return [values[..., a:b] for a, b in itertools.pairwise(cuts)]

    def kernel_state(self, omega0: Array, attitude0: Array) -> Array:
        """(7 + m,) the state the parts' kernels integrate (:mod:`tumble.core.parts`):
        H, q (principal-platform frame), then the parts' momenta, from ω0 (rad/s,
        body axes) and the attitude (body → space)."""
        total, momenta = self._initial_momenta(omega0)
        pieces = [part.to_kernel(own, self) for part, own in zip(self.parts, momenta, strict=True)]
        momentum = self.to_principal(total)
        return np.concatenate(
            [momentum, self.attitude_to_principal(np.asarray(attitude0, dtype=float)), *pieces]
        )

    def _initial_momenta(self, omega0: Array) -> tuple[Array, list[Array]]:
        """The angular momentum (3,) at t = 0 (body axes, kg·m²/s) and each part's
        momenta (:meth:`tumble.parts.InternalPart.momenta`) for ω0 (3,), rad/s:
        what :meth:`fastest_rate` and :meth:`kernel_state` both read, computed
        once for the last ω0 asked."""
        omega0 = np.asarray(omega0, dtype=float)
        key = (omega0.shape, omega0.tobytes())
        last = self.__dict__.get("_last_start")
        if last is not None and last[0] == key:
            return last[1], list(last[2])
        momenta = tuple(part.momenta(omega0, part.initial_values(omega0)) for part in self.parts)
        total = self.angular_momentum(omega0)
        total.flags.writeable = False
        self.__dict__["_last_start"] = (key, total, momenta)
        return total, list(momenta)

    def from_kernel_state(self, states: Array) -> tuple[Array, Array, Array]:
        """ω (n, 3) and the attitude (n, 4), body axes, and the parts' values
        (n, m), from kernel states (n, 7 + m): ω as the kernels solve for it
        (:func:`tumble.core.parts.velocities`)."""
        from tumble.core.parts import velocities

        states = np.asarray(states, dtype=float)
        moments = np.ascontiguousarray(self.moments[:, None])
        principal = velocities(self.layout)(np.ascontiguousarray(states.T), moments,
                                            np.ascontiguousarray(self.packed_parts))  # fmt: skip
        omega = self.from_principal(principal)
        values, k = [], 7
        for part in self.parts:
            momenta = part.from_kernel(states[:, k : k + part.size], self)
            values.append(part.values_from(omega, momenta))
            k += part.size
        parts = np.concatenate(values, axis=1) if values else np.zeros((len(states), 0))
        return omega, self.attitude_from_principal(states[:, 3:7]), parts

    # ------------------------------------------------------------ physics
    def angular_momentum(self, omega: Array, values: Array | None = None) -> Array:
        """Angular momentum about the reference point, body axes, kg·m²/s, for ω
        (..., 3) rad/s: ``I ω`` without parts; with parts ``I_p ω`` plus each
        part's own (``values`` (..., m) the parts' values, None: their
        initial values, a damper turning with the body)."""
        omega = np.asarray(omega, dtype=float)
        momentum = omega @ self.platform_inertia.T
        for part, own in zip(self.parts, self.split_values(values, omega), strict=True):
            momentum = momentum + part.momentum(omega, own)
        return np.asarray(momentum)

    def kinetic_energy(self, omega: Array, values: Array | None = None) -> Array:
        """Kinetic energy, J, for ω (..., 3) rad/s in body axes: ``½ ω · I ω``, with
        the parts' own (``values`` as in :meth:`angular_momentum`)."""
        omega = np.asarray(omega, dtype=float)
        energy = 0.5 * np.einsum("...i,...i->...", omega, omega @ self.platform_inertia.T)
        for part, own in zip(self.parts, self.split_values(values, omega), strict=True):
            energy = energy + part.kinetic_energy(omega, own)
        return np.asarray(energy)

    def gyrostat_axis(self) -> Array | None:
        """The unit axis (body axes) on which every part lies, when every part is
        a rotor free of motors and that axis is a principal axis of the platform
        (a gyrostat whose rotor momentum is constant along a principal axis: its
        free motion is in closed form, :mod:`tumble.core.gyrostat`); None for
        any other body."""
        axes = [part.gyrostatic_axis for part in self.parts]
        if not axes or any(a is None for a in axes):
            return None
        axis = axes[0]
        assert axis is not None
        if any(abs(abs(float(a @ axis)) - 1.0) > 1e-12 for a in axes if a is not None):
            return None
        turned = self.platform_inertia @ axis
        off = turned - float(axis @ turned) * axis
        if math.hypot(*off) > 1e-12 * float(np.trace(self.platform_inertia)):
            return None
        return np.asarray(axis, dtype=float)

    def symmetric_gyrostat_axis(self) -> int | None:
        """The index (0 or 2) of the principal axis of symmetry of a body whose
        platform moments are equal about the other two and whose parts are rotors
        on that axis, free of motors (a symmetric gyrostat: its free motion is a
        steady precession, in closed form); None for any other body."""
        moments = self.moments
        if moments[0] == moments[1] and moments[1] != moments[2]:
            axis = 2
        elif moments[1] == moments[2] and moments[0] != moments[1]:
            axis = 0
        else:
            return None
        for part in self.parts:
            along = part.gyrostatic_axis
            if along is None or abs(abs(float(self.to_principal(along)[axis])) - 1.0) > 1e-12:
                return None
        return axis

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

    def symmetric_top_axis(self) -> Array | None:
        """The unit symmetry axis (body axes, from the pivot towards the centre of
        mass) of a Lagrange top without parts: a body on a pivot whose principal
        moments about the pivot are equal about two axes (as
        :func:`tumble.massprops.principal_decomposition` makes repeated moments
        equal) and whose centre of mass lies on the third, off the pivot. Its
        motion under uniform gravity is in closed form
        (:mod:`tumble.core.lagrange`). None for any other body."""
        if self.pivot is None or self.parts:
            return None
        size = float(np.linalg.norm(self.lever))
        if size == 0.0:
            return None
        moments, axes = self.moments, self.axes
        if moments[0] == moments[2]:  # every axis through the pivot is principal
            return np.asarray(self.lever / size)
        for axis, (i, j) in ((0, (1, 2)), (2, (0, 1))):
            if moments[i] == moments[j]:
                along = float(axes[:, axis] @ self.lever) / size
                if abs(along) >= 1.0 - 1e-12:
                    return np.asarray(axes[:, axis] * math.copysign(1.0, along))
        return None

    def conserved(self, torques: Any) -> tuple[str, ...]:
        """The quantities (keys of :data:`tumble.invariants.INVARIANTS`) the motion
        of this body conserves under the torque models ``torques`` (those that act
        on it; see :meth:`tumble.torques.TorqueModel.conserves`): what a
        torque-free body conserves, less what each model changes. Internal parts
        keep L (their torques are internal); a motor or a damper changes the
        energy."""
        kept = set(FREE_BODY_INVARIANTS)
        if any(part.driven or part.dissipative for part in self.parts):
            kept.discard("energy")
        for torque in torques:
            if getattr(torque, "actuator", "external") == "rotors":
                kept.discard("energy")  # the motors do work; L moves between body and rotors
            else:
                kept &= torque.conserves(self)
        return reduce_invariants(kept)

    def fastest_rate(self, omega: Array, weight: float, exact_spin: bool = False) -> float:
        """An upper estimate of the fastest angular rate a time step must resolve, rad/s.

        Torque-free, the largest |ω| the motion reaches (``omega`` in body axes,
        rad/s): :func:`tumble.invariants.largest_rate`, exact, where the bound |L| / I1 would
        overstate an elongated body's rate many times. A body on a pivot under a
        weight ``weight`` (N) adds the pendulum rate √(m g l / I1). With
        ``exact_spin`` (integrators whose free flow turns a symmetric body
        exactly), a symmetric body's spin about its symmetry axis needs no
        resolving: the rate is |L| / I⊥, that of the precession of the axis
        about L (and of nutation). With parts, ω = I_p⁻¹ (L − the parts'
        momenta) stays below (|L| + |the parts' momenta|) / I1 (platform
        moments; their momenta at t = 0: a motor changes them).
        """
        moments = self.moments
        principal = self.to_principal(omega)
        # Norms by hypot: no overflow of the squares of a body of 1e300 kg.
        if self.parts:
            total, momenta = self._initial_momenta(omega)
            momentum = math.hypot(*total.tolist()) + sum(
                math.hypot(*np.ravel(own).tolist()) for own in momenta
            )
            rate = momentum / moments[0]
        # principal_decomposition makes repeated moments exactly equal: I⊥ = I2 for
        # a prolate body (I2 = I3) and an oblate one (I1 = I2).
        elif exact_spin and moments[1] in (moments[0], moments[2]):
            rate = math.hypot(*(moments / moments[1] * principal))  # |L| / I⊥
        else:
            rate = largest_rate(moments, principal)
        return rate + self.pendulum_rate(weight)

    def internal_rate(self) -> tuple[float, list[str]]:
        """An upper bound of the fastest rate of the parts' own motion relative to
        the platform, 1/s, and the kinds of parts it comes from (0 and none
        without such parts): what an explicit step must keep within its
        stability interval (:func:`tumble.parts.internal_rate`)."""
        rate, names = self._internal_rate
        return rate, list(names)

    @cached_property
    def _internal_rate(self) -> tuple[float, tuple[str, ...]]:
        from tumble.parts import internal_rate

        if not self.parts:
            return 0.0, ()
        rate, names = internal_rate(self.parts, self.platform_inertia)
        return rate, tuple(names)

    def pendulum_rate(self, weight: float) -> float:
        """√(m g l / I1), rad/s: an upper estimate of the rate of the swing that a
        weight ``weight`` (N) at the centre of mass drives about the pivot (0
        for a free body)."""
        if self.pivot is None:
            return 0.0
        return math.sqrt(weight * float(np.linalg.norm(self.lever)) / self.moments[0])


#: How many body models :func:`body_model` keeps: the most recently asked for.
BODY_CACHE_SIZE = 64

_BODIES: OrderedDict[tuple[Any, ...], tuple[MassProperties, tuple[Any, ...], RigidBody]] = (
    OrderedDict()
)
_BODIES_LOCK = threading.Lock()


def body_model(
    mp: MassProperties, pivot: Array | None = None, parts: tuple[InternalPart, ...] = ()
) -> RigidBody:
    """The :class:`RigidBody` of ``mp`` about ``pivot`` ((3,) body coordinates, m,
    or None: the centre of mass) carrying ``parts``, built once and shared by the
    calls that ask for the same body: its principal frame, its parts' layout and
    every other derived value are computed once for a run of simulations.

    The last :data:`BODY_CACHE_SIZE` are kept, keyed by the identity of ``mp``
    and of each part *and* by the values of ``mp`` and ``pivot``: mass
    properties and parts are immutable (frozen, their arrays read-only), and an
    entry holds them, so that no other object can take their identities while
    it lives; the values in the key guard against arrays made writable and
    changed in place. The pivot is copied (read-only) into the model.

    Raises
    ------
    InputError
        As :class:`RigidBody` (never cached).
    """
    point = None if pivot is None else np.array(pivot, dtype=float)
    key = (
        id(mp),
        mp.mass,
        mp.center_of_mass.tobytes(),
        mp.inertia.tobytes(),
        None if point is None else point.tobytes(),
        tuple(map(id, parts)),
    )
    with _BODIES_LOCK:
        entry = _BODIES.get(key)
        if entry is not None:
            _BODIES.move_to_end(key)
    if entry is not None and entry[0] is mp and all(map(operator.is_, entry[1], parts)):
        return entry[2]
    if point is not None:
        point.flags.writeable = False
    body = RigidBody(mp, point, tuple(parts))
    with _BODIES_LOCK:
        _BODIES[key] = (mp, tuple(parts), body)
        while len(_BODIES) > BODY_CACHE_SIZE:
            _BODIES.popitem(last=False)
    return body


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

    @property
    def inertia_principal(self) -> Array:
        """(N, 3, 3) each body's inertia in its principal axes (diagonal), kg·m²."""
        return np.asarray(np.einsum("ni,ij->nij", self.moments, np.eye(3)))

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
        return _turned(quaternions, np.asarray(rotation.as_quat(scalar_first=True), dtype=float))
    return np.asarray(
        (Rotation.from_quat(quaternions, scalar_first=True) * rotation).as_quat(scalar_first=True)
    )


def _turned(quaternions: Array, turn: Array) -> Array:
    """Scalar-first quaternions (4,) or (n, 4) times the unit quaternion ``turn``
    (4,) on the right, renormalised (:func:`tumble.core.quaternion.multiply_right`)."""
    from tumble.core.quaternion import multiply_right

    stack = np.ascontiguousarray(np.atleast_2d(quaternions), dtype=float)
    out = multiply_right(stack, turn)
    return np.asarray(out[0] if np.ndim(quaternions) == 1 else out)
