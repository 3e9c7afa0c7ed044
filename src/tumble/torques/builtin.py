"""The torque models tumble brings: gravity, constant torques, damping, drag, a held rotation.

Each is one class, registered under its name in scenario files, with its
compiled function in :mod:`tumble.core.torques`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.core import torques as kernels
from tumble.invariants import FREE_BODY_INVARIANTS
from tumble.torques.model import Parameter, TorqueModel, register_torque

__all__ = [
    "AxisDrag",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "Gravity",
    "HoldRotation",
    "LinearDamping",
    "QuadraticDrag",
    "RotorMomentum",
]

Array = NDArray[np.float64]


def _vector_field(prefix: str) -> tuple[str, str, str]:
    return (f"{prefix}_1", f"{prefix}_2", f"{prefix}_3")


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class Gravity(TorqueModel):
    """Uniform gravity of acceleration ``acceleration`` (space axes, m/s², default
    −9.81 ẑ) acting at the centre of mass: a torque about a pivot only.

    Examples
    --------
    A 2 kg ball of radius 10 cm hung 20 cm below a pivot, given a small push:
    a pendulum of angular frequency ``√(m g d / I_pivot)``.

    >>> import numpy as np
    >>> import tumble as tb
    >>> tb.torques.Gravity()
    Gravity([0.0, 0.0, -9.81] m/s²)
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)
    >>> swing = tb.simulate(ball, [0.05, 0, 0], pivot=[0, 0, 0.2], torque=tb.torques.Gravity(),
    ...                     duration=3.0, dt=0.005)
    >>> rate = tb.analysis.oscillation_frequency(swing.t, swing.omega[:, 0])
    >>> print(f"{rate:.3f} rad/s, theory {np.sqrt(2 * 9.81 * 0.2 / (0.008 + 2 * 0.2**2)):.3f}")
    6.678 rad/s, theory 6.678
    >>> swing.conserved_quantities
    ('energy', 'angular_momentum_vertical', 'angular_momentum_axial')
    """

    acceleration: Any = (0.0, 0.0, -9.81)

    name = "gravity"
    summary = "uniform gravity at the centre of mass (a torque about a pivot only)"
    parameters = (
        Parameter("acceleration", "acceleration", (3,), "gravitational acceleration, space axes"),
    )
    fields = (*_vector_field("lever"), "weight_x", "weight_y", "weight_z")
    kernel = staticmethod(kernels.gravity_about_pivot)
    depends_on = frozenset({"attitude"})
    conservative = True

    def acts_on(self, body: Any) -> bool:
        return getattr(body, "pivot", None) is not None and bool(np.any(self.acceleration))

    def pack(self, body: Any, omega0: Array | None) -> Array:
        weight = body.mass_properties.mass * np.asarray(self.acceleration)
        return np.concatenate([body.to_principal(body.lever), weight])

    def potential_energy(self, body: Any, t: Array, quaternion: Array) -> Array:
        """``U = −m g · (A r)``, J, (n,): r the lever from the pivot to the centre of
        mass (body axes, m), A the attitude's rotation matrix (body → space), g
        the acceleration (space axes, m/s²); zero for a free body, whose energy is
        taken about its centre of mass. Independent of the time ``t``."""
        if getattr(body, "pivot", None) is None:
            return np.zeros(len(quaternion))
        matrices = Rotation.from_quat(quaternion, scalar_first=True).as_matrix()
        height = np.einsum("nij,j->ni", matrices, body.lever)
        return np.asarray(-body.mass_properties.mass * (height @ np.asarray(self.acceleration)))

    def uniform_gravity(self) -> Array:
        """The acceleration g (3,), m/s², space axes."""
        return np.asarray(self.acceleration, dtype=float)

    def conserves(self, body: Any) -> frozenset[str]:
        if not self.acts_on(body):
            return FREE_BODY_INVARIANTS
        kept = {"energy", "angular_momentum_vertical"}
        if body.is_symmetric_top():
            kept.add("angular_momentum_axial")
        return frozenset(kept)


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class ConstantBodyTorque(TorqueModel):
    """A constant torque in body axes (N·m): (3,), or (N, 3) one per body of a batch.
    With ``actuator="rotors"`` the body's rotors produce it (their motor torques
    share it out, :mod:`tumble.core.parts`), so the total angular momentum stays.

    Examples
    --------
    8 mN·m about z spins a ball of ``I = 0.008 kg·m²`` up at 1 rad/s²:

    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)
    >>> push = tb.torques.ConstantBodyTorque([0, 0, 0.008])
    >>> traj = tb.simulate(ball, [0, 0, 0], torque=push, duration=2.0, dt=0.01)
    >>> print(f"{traj.omega[-1, 2]:.6f} rad/s")
    2.000000 rad/s
    """

    torque: Any
    actuator: str = "external"

    name = "constant-body"
    summary = "a constant torque fixed in the body (a thruster, a motor)"
    parameters = (
        Parameter(
            "torque", "torque", (3,), "torque in body axes", sweep=_vector_field("body_torque")
        ),
    )
    fields = _vector_field("torque")
    kernel = staticmethod(kernels.constant_body_torque)
    in_batches = True
    drives_rotors = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(body.to_principal(self.torque)).T


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class ConstantSpaceTorque(TorqueModel):
    """A constant torque in space axes (N·m): (3,), or (N, 3) one per body of a batch.

    Examples
    --------
    However the body tumbles, its angular momentum in space grows by ``τ t``:

    >>> import numpy as np
    >>> import tumble as tb
    >>> brick = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
    >>> push = tb.torques.ConstantSpaceTorque([0.001, 0, 0])
    >>> traj = tb.simulate(brick, [0.0, 1.0, 3.0], torque=push, duration=2.0, dt=0.01)
    >>> L = traj.angular_momentum
    >>> np.allclose(L[-1], L[0] + [0.002, 0, 0])
    True
    """

    torque: Any

    name = "constant-space"
    summary = "a constant torque fixed in space"
    parameters = (
        Parameter(
            "torque",
            "torque",
            (3,),
            "torque in space axes",
            sweep=("space_torque_x", "space_torque_y", "space_torque_z"),
        ),
    )
    fields = ("torque_x", "torque_y", "torque_z")
    kernel = staticmethod(kernels.constant_space_torque)
    depends_on = frozenset({"attitude"})
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(self.torque, dtype=float).T


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class LinearDamping(TorqueModel):
    """Viscous damping ``τ = −c ω`` with ``c`` >= 0 in N·m·s: a number, or (N,) one
    per body of a batch.

    Examples
    --------
    The spin decays as ``exp(−c t / I)``; with ``c = I`` it falls to 1/e in 1 s:

    >>> import numpy as np
    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg·m²
    >>> drag = tb.torques.LinearDamping(0.008)
    >>> traj = tb.simulate(ball, [0, 0, 1.0], torque=drag, duration=1.0, dt=0.01)
    >>> print(f"{traj.omega[-1, 2]:.6f} rad/s, exp(-1) = {np.exp(-1):.6f}")
    0.367879 rad/s, exp(-1) = 0.367879
    """

    coefficient: Any

    name = "damping"
    summary = "viscous damping τ = −c ω"
    parameters = (
        Parameter("coefficient", "damping", (), "damping coefficient c", 0.0, sweep=("damping",)),
    )
    fields = ("coefficient",)
    kernel = staticmethod(kernels.linear_damping)
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return np.asarray(self.coefficient, dtype=float)[None, ...]


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class HoldRotation(TorqueModel):
    """The body-fixed torque ``ω0 × (I ω0)`` (``ω0 × H0`` with the momentum of the
    body's parts, its rotors keeping their speeds) about the reference point that
    keeps the initial rotation ω0 steady: what a motor supplies to hold a shaft at a
    constant rate (the rotating skew rod, an unbalanced rotor). It does no work
    (it is perpendicular to ω) and turns L rigidly: energy and |L| stay.

    Examples
    --------
    A brick held turning about a diagonal of its xy plane, which is not a
    principal axis: ω stays as it was, under the torque
    :func:`tumble.required_torque` gives.

    >>> import numpy as np
    >>> import tumble as tb
    >>> brick = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
    >>> traj = tb.simulate(brick, [1.0, 1.0, 0.0], torque=tb.torques.HoldRotation(),
    ...                    duration=2.0, dt=0.01)
    >>> np.allclose(traj.omega, [1.0, 1.0, 0.0])
    True
    >>> print(f"{tb.required_torque(brick, [1.0, 1.0, 0.0], [0, 0, 0])[2]:.6f} N·m")
    -0.002500 N·m
    """

    name = "hold-rotation"
    summary = "the torque ω0 × (I ω0) that keeps the initial rotation steady"
    closed_forms = frozenset({"rotor-loads"})
    fields = _vector_field("torque")
    kernel = staticmethod(kernels.constant_body_torque)

    def pack(self, body: Any, omega0: Array | None) -> Array:
        omega = np.zeros(3) if omega0 is None else np.asarray(omega0, dtype=float)
        w = body.to_principal(omega)
        if getattr(body, "parts", ()):  # ω0 × H0, the parts' momentum in H0
            return np.asarray(np.cross(w, body.to_principal(body.angular_momentum(omega))))
        return np.asarray(np.cross(w, body.moments * w))

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset({"energy", "angular_momentum_norm"})


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class RotorMomentum(TorqueModel):
    """Rotors whose angular momentum relative to the body is prescribed: ``h(t) =
    momentum + momentum_rate · t`` (body axes; kg·m²/s and kg·m²/s² = N·m), held
    by their motors — at a constant relative speed when ``momentum_rate`` is zero
    (a momentum wheel, the rotor of a dual-spin satellite).

    The body (its MassProperties holding the rotors as if locked, I) then obeys
    the gyrostat's equation ``I ω̇ + ω × (I ω + h) = −ḣ`` (Hughes, *Spacecraft
    Attitude Dynamics*, §6.2): this model is the torque ``−ω × h − ḣ`` on it.
    (ḣ is not the motors' torque, which also turns the rotors with the body:
    ``J (a·ω̇) + ḣ`` each.) Its values may be one per body of a batch, and sweep
    files vary them (``rotor_momentum_1`` …, ``rotor_momentum_rate_1`` …,
    principal axes). With a constant h it does no work: the body's energy
    ``½ ω · I ω`` stays, and the total ``I ω + h`` is the conserved angular
    momentum (the trajectory's L is the body's own, ``I ω``). For rotors with
    their own dynamics (free rotors, motor torques and their limits, a
    controller), use :class:`tumble.Rotor` parts.
    """

    momentum: Any
    momentum_rate: Any = (0.0, 0.0, 0.0)

    name = "rotor-momentum"
    summary = "rotors of prescribed relative momentum h(t): the torque −ω × h − ḣ"
    parameters = (
        Parameter(
            "momentum",
            "angular_momentum",
            (3,),
            "the rotors' relative momentum h at t = 0",
            sweep=_vector_field("rotor_momentum"),
        ),
        Parameter(
            "momentum_rate",
            "torque",
            (3,),
            "dh/dt, constant",
            sweep=_vector_field("rotor_momentum_rate"),
        ),
    )
    fields = (*_vector_field("momentum"), *_vector_field("rate"))
    kernel = staticmethod(kernels.rotor_momentum)
    depends_on = frozenset({"omega", "time"})
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        momentum = np.atleast_2d(body.to_principal(self.momentum))  # (1 or N, 3)
        rate = np.atleast_2d(body.to_principal(self.momentum_rate))
        momentum, rate = np.broadcast_arrays(momentum, rate)
        return np.concatenate([momentum.T, rate.T])

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset() if np.any(self.momentum_rate) else frozenset({"energy"})


def _per_axis_fields() -> tuple[str, ...]:
    """The fields of a drag per body axis: its three coefficients, then the body's
    three axes in principal coordinates (what :func:`_pack_per_axis` packs)."""
    axes = (f"axis_{i}_{k}" for i in (1, 2, 3) for k in (1, 2, 3))
    return (*_vector_field("coefficient"), *axes)


def _pack_per_axis(coefficients: Any, body: Any) -> Array:
    """(12, 1) or (12, N): the coefficients (3,) or (N, 3), then each body axis in
    the principal axes of its body (one column per body when they differ)."""
    c = np.atleast_2d(np.asarray(coefficients, dtype=float))  # (1 or N, 3)
    # Row i of each (3, 3): body axis i in principal coordinates, so the rate
    # about it is axes[i] · ω and its torque turns back as τᵢ axes[i].
    axes = np.stack([np.atleast_2d(body.to_principal(e)) for e in np.eye(3)], axis=1)
    count = max(len(c), len(axes))
    c = np.broadcast_to(c, (count, 3))
    axes = np.broadcast_to(axes, (count, 3, 3)).reshape(count, 9)
    return np.concatenate([c.T, axes.T])


def _coefficients(kind: str, unit: str, sweep: str) -> tuple[Parameter, ...]:
    """The one parameter of a drag per body axis: its three coefficients, >= 0."""
    text = f"drag coefficient cᵢ about each body axis{unit}"
    return (Parameter("coefficients", kind, (3,), text, 0.0, sweep=_vector_field(sweep)),)


class _DragPerAxis(TorqueModel):
    """What the drags per body axis share: their coefficients, one per body axis, packed
    with the body axes in principal coordinates; dissipative, in batches too."""

    coefficients: Any

    fields = _per_axis_fields()
    depends_on = frozenset({"omega"})
    in_batches = True

    def pack(self, body: Any, omega0: Array | None) -> Array:
        return _pack_per_axis(self.coefficients, body)

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset()


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class AxisDrag(_DragPerAxis):
    """Linear air drag about each body axis, ``τᵢ = −cᵢ ωᵢ`` in body axes, with
    ``coefficients`` c >= 0 in N·m·s: (3,), or (N, 3) one row per body of a batch.

    The drag of a thrown object at moderate rates: each axis of the body meets the
    air differently (a racquet's face, its handle). Equal coefficients make it
    :class:`LinearDamping`. It dissipates: the motion keeps neither energy nor
    angular momentum.

    Examples
    --------
    On a ball (equal moments I, so each axis decays on its own) each rate falls
    as ``exp(−cᵢ t / I)``:

    >>> import numpy as np
    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg·m²
    >>> drag = tb.torques.AxisDrag([0.008, 0.004, 0.0])
    >>> drag
    AxisDrag([0.008, 0.004, 0.0] N·m·s)
    >>> traj = tb.simulate(ball, [1.0, 1.0, 1.0], torque=drag, duration=1.0, dt=0.01)
    >>> print(np.round(traj.omega[-1], 6), np.round(np.exp([-1.0, -0.5, 0.0]), 6))
    [0.367879 0.606531 1.      ] [0.367879 0.606531 1.      ]
    """

    coefficients: Any

    name = "drag"
    summary = "linear drag per body axis τᵢ = −cᵢ ωᵢ"
    parameters = _coefficients("damping", "", "drag")
    kernel = staticmethod(kernels.axis_drag)


@register_torque
@dataclass(frozen=True, eq=False, repr=False)
class QuadraticDrag(_DragPerAxis):
    """Quadratic air drag about each body axis, ``τᵢ = −cᵢ ωᵢ |ωᵢ|`` in body axes,
    with ``coefficients`` c >= 0 in N·m·s² (= kg·m²): (3,), or (N, 3) one row per
    body of a batch.

    The drag of a fast-turning body whose air flow is turbulent. It dissipates:
    the motion keeps neither energy nor angular momentum.

    Examples
    --------
    About one axis of a ball, ``I ω̇ = −c ω²``, so ``ω(t) = ω0 / (1 + c ω0 t / I)``:

    >>> import tumble as tb
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg·m²
    >>> drag = tb.torques.QuadraticDrag([0.0, 0.0, 0.0008])
    >>> traj = tb.simulate(ball, [0, 0, 10.0], torque=drag, duration=1.0, dt=0.01)
    >>> print(f"{traj.omega[-1, 2]:.6f} rad/s, theory {10.0 / (1 + 0.0008 * 10.0 / 0.008):.6f}")
    5.000000 rad/s, theory 5.000000
    """

    coefficients: Any

    name = "quadratic-drag"
    summary = "quadratic drag per body axis τᵢ = −cᵢ ωᵢ² sign(ωᵢ)"
    parameters = _coefficients("inertia", ", N·m·s²", "quadratic_drag")
    kernel = staticmethod(kernels.quadratic_axis_drag)
