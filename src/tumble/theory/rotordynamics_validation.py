"""The validation of a rigid rotor's inputs (see :mod:`tumble.theory.rotordynamics`).

The values of a bearing, the rotor's body about its spin axis, the bearings'
matrices and the spin speeds: each refused with one :class:`~tumble.errors.InputError`
where the model does not hold (a rotor that is not axisymmetric, bearings that do
not hold its tilt) or where float64 would overflow or lose the digits it needs.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties
from tumble.theory.common import as_flat
from tumble.units import to_si, vector_to_si

if TYPE_CHECKING:
    from tumble.theory.rotordynamics import Bearing, RigidRotor

__all__ = [
    "check_matrices",
    "check_tilt_held",
    "checked_speeds",
    "rotor_moments",
    "transverse_pair",
]

Array = NDArray[np.float64]

#: How far the two transverse moments may differ (relative) for the rotor to be
#: axisymmetric: beyond it the equations in the fixed frame have coefficients
#: that vary with the spin angle, which this model does not solve.
SYMMETRY_TOLERANCE = 1e-3

#: The smallest eigenvalue of the bearings' stiffness matrix scaled to a unit
#: diagonal (1 for bearings far apart, (δ / L)² for two a distance δ apart at arms
#: of L): below it the matrix is singular to round-off (its tilt held by digits
#: that float64 does not keep), and the frequencies and orbits would be noise.
SEPARATION_FLOOR = 1e-12


def transverse_pair(value: Any, kind: str, name: str) -> tuple[float, float]:
    """A value of a bearing in SI units of ``kind``: one number or quantity (the
    same along both transverse axes) or a pair (x, y), each ≥ 0.

    Raises
    ------
    InputError
        A value of the wrong unit, shape or sign, naming ``name``.
    """
    # One value: a number, a quantity, or a string without a comma ("1e6 N/m",
    # where "1e6, 2e6 N/m" is a pair).
    text = isinstance(value, str)
    if (text and "," not in value) or (not text and np.ndim(value) == 0):
        number = to_si(value, kind, name)
        if not number >= 0:
            raise InputError(f"Expected `{name}` >= 0, got {number!r}.")
        return number, number
    pair = vector_to_si(value, kind, name, (2,))
    if not np.all(pair >= 0):
        raise InputError(f"Expected `{name}` >= 0 along x and y, got {pair.tolist()}.")
    return float(pair[0]), float(pair[1])


def rotor_moments(mp: MassProperties, n: Array, p: Array) -> tuple[float, Array, float]:
    """The polar moment I_p (kg·m²), the two transverse moments (2,) about the
    centre of mass (kg·m², ascending) and the centre of mass's axial position from
    the point ``p`` (m) of a body spinning about the unit axis ``n`` (body coordinates).

    Raises
    ------
    InputError
        An axis that is not a principal axis of the body, unequal transverse
        moments (beyond :data:`SYMMETRY_TOLERANCE`), or a centre of mass off the axis.
    """
    inertia = mp.inertia
    polar = float(n @ inertia @ n)
    coupling = inertia @ n - polar * n
    scale = float(np.abs(inertia).max())
    if np.linalg.norm(coupling) > 1e-9 * scale:
        raise InputError(
            f"Expected `axis` {n.round(6).tolist()} to be a principal axis of the body, got "
            f"products of inertia with it of {np.linalg.norm(coupling):.3g} kg·m²: a "
            "dynamically unbalanced rotor; give its axis along a principal axis "
            "(body.principal()) and its imbalance as an unbalance."
        )
    transverse = np.asarray(np.linalg.eigvalsh(inertia - polar * np.outer(n, n))[1:], float)
    if abs(transverse[1] - transverse[0]) > SYMMETRY_TOLERANCE * transverse[1]:
        raise InputError(
            f"Expected an axisymmetric rotor (equal moments about the axes perpendicular to "
            f"`axis`), got {transverse[0]:.6g} and {transverse[1]:.6g} kg·m²."
        )
    offset = mp.center_of_mass - p
    along = float(offset @ n)
    off_axis = float(np.linalg.norm(offset - along * n))
    if off_axis > 1e-9 * max(1.0, float(np.linalg.norm(offset))):
        raise InputError(
            f"Expected the rotor's centre of mass on its axis, got it {off_axis:.3g} m off: "
            "give the offset as an unbalance."
        )
    return polar, transverse, along


def check_tilt_held(transverse: Array, bearings: Sequence[Bearing]) -> None:
    """Refuse a rotor without inertia about its tilt (``transverse``, kg·m²) or
    bearings without stiffness at two or more axial positions along x or y.

    Raises
    ------
    InputError
        Either, naming what is missing.
    """
    if not transverse[0] > 0:
        raise InputError(
            f"Expected the rotor's moment of inertia about the axes perpendicular to `axis` "
            f"> 0 kg·m² (the inertia of its tilt), got {float(transverse[0])!r}."
        )
    for k, direction in enumerate("xy"):
        stiff = {b.position for b in bearings if b.stiffness[k] > 0}
        if len(stiff) < 2:
            raise InputError(
                f"Expected bearings with stiffness along {direction} at two or more axial "
                f"positions (to hold the rotor's tilt), got {len(stiff)}."
            )


def check_matrices(rotor: RigidRotor) -> None:
    """Refuse bearings whose matrices overflow float64 (with the rotor's
    inertia, in the state matrices), or whose stiffness holds the tilt only by
    digits float64 does not keep (below :data:`SEPARATION_FLOOR`).

    Raises
    ------
    InputError
        Either, with the bearings' values and positions.
    """
    inverse = 1.0 / np.diag(rotor.mass_matrix)
    for name, matrix, unit in (
        ("stiffness", rotor.stiffness, "N/m"),
        ("damping", rotor.damping, "N·s/m"),
    ):
        with np.errstate(over="ignore", invalid="ignore"):
            finite = np.all(np.isfinite(matrix)) and np.all(np.isfinite(inverse[:, None] * matrix))
        if not finite:
            values = [max(getattr(b, name)) for b in rotor.bearings]
            raise InputError(
                f"Expected bearings whose {name} matrix (the sums of each one's {name} "
                f"times 1, a and a² for its arm a, over the mass and inertia) is finite in "
                f"float64, got {name} up to {max(values):.6g} {unit} at arms up to "
                f"{np.abs(rotor.arms).max():.6g} m from the centre of mass: it overflows."
            )
    diagonal = np.diag(rotor.stiffness)
    smallest = 0.0  # a tilt stiffness Σk a² that underflows holds nothing
    if np.all(diagonal > 0):
        scale = 1.0 / np.sqrt(diagonal)
        smallest = float(np.linalg.eigvalsh(scale[:, None] * rotor.stiffness * scale).min())
    if not smallest > SEPARATION_FLOOR:
        positions = sorted({b.position for b in rotor.bearings})
        raise InputError(
            f"Expected bearings far enough apart to hold the rotor's tilt in float64, got "
            f"positions {positions} m (their stiffness matrix is singular to round-off)."
        )


def checked_speeds(rotor: RigidRotor, speeds: Any) -> tuple[Array, bool]:
    """Speeds (rad/s) of ``rotor`` as an array, and whether one was given as a scalar.

    Raises
    ------
    InputError
        Speeds that are not angular velocities, or so large that the
        gyroscopic terms I_p Ω / I_t (with the damping) overflow float64.
    """
    values, shape = as_flat(speeds, "angular_velocity", "speeds")
    if values.size:
        top = float(np.abs(values).max())
        damping = float(np.abs(rotor.damping).max()) / min(rotor.mass, rotor.transverse)
        with np.errstate(over="ignore"):
            gyroscopic = top * rotor.polar / rotor.transverse + damping
        if not np.isfinite(gyroscopic):
            raise InputError(
                f"Expected `speeds` whose gyroscopic terms I_p Ω / I_t are finite in "
                f"float64, got a speed of {top:.6g} rad/s with I_p / I_t = "
                f"{rotor.polar / rotor.transverse:.6g}: it overflows."
            )
    return values, shape == ()
