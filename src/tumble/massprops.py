"""Mass properties of a rigid body: mass, centre of mass and inertia tensor.

Conventions (see the README):

* SI units: kg, m, kg·m².
* ``inertia`` is always taken **about the centre of mass**, in **body axes**:
  ``I_ij = Σ m (r² δ_ij − r_i r_j)``, so products of inertia carry a minus sign,
  ``I_xy = −Σ m x y``.
* Principal moments are ascending, ``I1 <= I2 <= I3``; principal axes are the
  columns of a proper rotation matrix ``R`` (det +1), ``I = R diag(I1, I2, I3) Rᵀ``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from tumble.errors import InputError
from tumble.units import to_si, vector_to_si

__all__ = [
    "PHYSICAL_TOLERANCE",
    "MassProperties",
    "as_mass_properties",
    "axisymmetric_moments",
    "check_symmetric",
    "point_masses",
    "readonly",
]

#: Relative tolerance of the physical checks, as a fraction of the trace of the
#: inertia tensor (or of its largest entry for symmetry): a principal moment may
#: be as low as ``-PHYSICAL_TOLERANCE * trace`` and ``I1 + I2`` may fall short of
#: ``I3`` by as much, which admits flat and linear bodies (``I1 + I2 == I3``,
#: ``I1 == 0``) computed in floating point, while rejecting any real violation.
PHYSICAL_TOLERANCE = 1e-9

#: Principal moments closer than this fraction of the trace are taken as equal
#: (a sphere, a symmetric top), so their axes are chosen by a fixed rule.
REPEATED_MOMENT_TOLERANCE = 1e-9

Array = NDArray[np.float64]


def check_symmetric(inertia: Array) -> None:
    """Refuse an inertia tensor (3, 3), or a stack of them (N, 3, 3, one a body),
    that is not symmetric to ``PHYSICAL_TOLERANCE`` of its largest entry (kg·m²,
    finite). The message names the pair of entries farthest apart (and their body).

    Raises
    ------
    InputError
        A tensor that is not symmetric.
    """
    tensors = inertia.reshape(-1, 3, 3)
    scale = np.max(np.abs(tensors), axis=(1, 2))
    # Over each tensor's largest entry: no difference of entries near 1e308 overflows.
    unit = tensors / np.where(scale > 0.0, scale, 1.0)[:, None, None]
    asymmetry = np.abs(unit - np.swapaxes(unit, 1, 2)).reshape(-1, 9)
    bad = np.flatnonzero(np.max(asymmetry, axis=1) > PHYSICAL_TOLERANCE)
    if bad.size == 0:
        return
    k = int(bad[0])
    i, j = np.unravel_index(int(np.argmax(asymmetry[k])), (3, 3))
    body, at = (f"body {k} with ", f"{k}, ") if inertia.ndim == 3 else ("", "")
    raise InputError(
        f"Expected `inertia` to be symmetric, got {body}inertia[{at}{i}, {j}] = "
        f"{float(tensors[k, i, j])!r} but inertia[{at}{j}, {i}] = {float(tensors[k, j, i])!r} "
        "kg·m²."
    )


def readonly(values: Any) -> Array:
    """A read-only float64 copy (results are immutable)."""
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False, repr=False)
class MassProperties:
    """Mass, centre of mass and central inertia tensor of a rigid body. Immutable.

    Parameters
    ----------
    mass : float, pint quantity or string such as ``"250 g"``; kg, > 0.
    center_of_mass : (3,) position of the centre of mass in body coordinates, m.
    inertia : (3, 3) inertia tensor about the centre of mass in body axes, kg·m².
        Symmetric, with products of inertia as ``I_xy = −∫ x y dm``.

    Raises
    ------
    InputError
        If the mass is not positive, any value is NaN or infinite, a shape is
        wrong, the tensor is not symmetric (to ``PHYSICAL_TOLERANCE`` of its
        largest entry), a principal moment is negative, or the principal moments
        break the triangle inequality ``I1 + I2 >= I3`` (both to
        ``PHYSICAL_TOLERANCE`` of the trace). A zero moment is valid: thin rods,
        collinear point masses and single point masses have one or three.

    Examples
    --------
    A body with a product of inertia ``I_xy = −1 kg·m²``: its principal axes
    are the diagonals of the xy plane, and body z.

    >>> import numpy as np
    >>> import tumble as tb
    >>> inertia = [[3.0, -1.0, 0.0], [-1.0, 3.0, 0.0], [0.0, 0.0, 5.0]]
    >>> body = tb.MassProperties("2 kg", [0, 0, 0.1], inertia)
    >>> moments, axes = body.principal()
    >>> print(", ".join(f"{m:.6f}" for m in moments))
    2.000000, 4.000000, 5.000000
    >>> np.allclose(axes[:, 0], np.array([1, 1, 0]) / np.sqrt(2))
    True
    >>> np.allclose(axes @ np.diag(moments) @ axes.T, body.inertia)
    True

    About the body origin, 0.1 m from the centre of mass along z, the moments
    about x and y grow by ``m d² = 0.02 kg·m²``:

    >>> print(np.round(body.inertia_about([0, 0, 0]).diagonal(), 6))
    [3.02 3.02 5.  ]

    Parts in the same body coordinates add into an assembly:

    >>> ball = tb.shapes.solid_sphere(1.0, 0.1)
    >>> pair = sum(ball.transformed(translation=[x, 0, 0]) for x in (-0.3, 0.3))
    >>> print(f"{pair.mass:.1f} kg, I_yy = {pair.inertia[1, 1]:.3f} kg·m²")  # 2 (2/5 m r² + m d²)
    2.0 kg, I_yy = 0.188 kg·m²
    """

    mass: float
    center_of_mass: Array
    inertia: Array

    def __init__(self, mass: Any, center_of_mass: Any, inertia: Any) -> None:
        mass_si = to_si(mass, "mass", "mass")
        if mass_si <= 0:
            raise InputError(f"Expected `mass` > 0 kg, got {mass_si!r}.")
        com = vector_to_si(center_of_mass, "length", "center_of_mass", (3,))
        tensor = vector_to_si(inertia, "inertia", "inertia", (3, 3))
        check_symmetric(tensor)
        scale = float(np.max(np.abs(tensor)))
        # The checks work on the tensor over its largest entry, so that sums and
        # eigenvalues of entries near 1e308 neither overflow nor fail to converge.
        unit = tensor / scale if scale > 0 else tensor
        if scale <= np.finfo(float).max / 2:
            tensor = 0.5 * (tensor + tensor.T)
        else:  # halves first: the sum would overflow (halving rounds only subnormals)
            tensor = 0.5 * tensor + 0.5 * tensor.T
        unit = 0.5 * unit + 0.5 * unit.T
        moments = np.linalg.eigvalsh(unit)
        # The floor `tiny` admits subnormal round-off when the tensor is (near) zero.
        # A tensor of subnormal entries holds them only to steps of 4.9e-324 kg·m²
        # (a point mass 1e-145 m from its centre): each entry off by a few steps
        # from the operations that formed it, its eigenvalues by the Frobenius norm
        # of those errors, a few steps more, which no relative tolerance covers.
        grid = 4.0 * np.finfo(float).smallest_subnormal / scale if scale > 0 else 0.0
        tolerance = (
            PHYSICAL_TOLERANCE * max(float(np.trace(unit)), 0.0) + np.finfo(float).tiny + grid
        )
        if moments[0] < -tolerance:
            raise InputError(
                f"Expected the principal moments of `inertia` to be >= 0, got "
                f"{_format(moments * scale)} kg·m² (no distribution of mass has a negative "
                "moment)."
            )
        if moments[0] + moments[1] < moments[2] - tolerance:
            raise InputError(
                "Expected the principal moments of `inertia` to satisfy the triangle inequality "
                f"I1 + I2 >= I3, got I1 + I2 = {(moments[0] + moments[1]) * scale:.6g} < "
                f"I3 = {moments[2] * scale:.6g} kg·m² (no distribution of mass has these moments)."
            )
        object.__setattr__(self, "mass", mass_si)
        object.__setattr__(self, "center_of_mass", readonly(com))
        object.__setattr__(self, "inertia", readonly(tensor))

    # ------------------------------------------------------------------ derived
    def inertia_about(self, point: ArrayLike | str) -> Array:
        """Inertia tensor about a body point, in body axes (parallel-axis theorem).

        ``I_P = I_G + m (|d|² E − d dᵀ)`` with ``d = P − G``, G the centre of mass.

        Parameters
        ----------
        point : (3,) body coordinates of the point, m (or quantities).

        Returns
        -------
        (3, 3) float64, kg·m².

        Examples
        --------
        A uniform rod about its end: ``m L² / 12 + m (L/2)² = m L² / 3``.

        >>> import tumble as tb
        >>> rod = tb.shapes.thin_rod(3.0, 2.0)
        >>> print(f"{rod.inertia_about([0, 0, 1.0])[0, 0]:.6f} kg·m²")
        4.000000 kg·m²
        """
        p = vector_to_si(point, "length", "point", (3,))
        d = p - self.center_of_mass
        with np.errstate(over="ignore", invalid="ignore"):
            result = np.asarray(self.inertia + self.mass * (d @ d * np.eye(3) - np.outer(d, d)))
        if not np.all(np.isfinite(result)):
            raise InputError(
                f"Expected `point` within float range of the centre of mass, got {p.tolist()} m "
                f"(the inertia about it overflows)."
            )
        return result

    def principal(self) -> tuple[Array, Array]:
        """Principal moments and axes.

        Returns
        -------
        moments : (3,) ascending, kg·m², never negative (a round-off negative
            is returned as 0). Moments equal to within ``REPEATED_MOMENT_TOLERANCE``
            of the trace are returned exactly equal.
        axes : (3, 3) proper rotation matrix (det +1) whose columns are the
            principal axes in body coordinates: ``inertia = axes @ diag(moments) @ axes.T``.

        Notes
        -----
        Eigenvectors are fixed by a rule, so the result is reproducible and
        continuous in the inertia away from repeated moments: each distinct axis
        points so that its largest component is positive (the first of those
        within 1e-9 of the largest, if several); within a plane of
        repeated moments the first axis is the projection of the body axis
        (x, then y, then z) that lies most in that plane; with three equal moments
        the axes are the body axes; the last axis completes a right-handed frame.

        Examples
        --------
        >>> import numpy as np
        >>> import tumble as tb
        >>> brick = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
        >>> moments, axes = brick.principal()
        >>> print(", ".join(f"{m:.6f}" for m in moments))  # ascending: about z, y, x
        0.004167, 0.008333, 0.010833
        >>> print(f"{np.linalg.det(axes):.1f}")
        1.0
        """
        return self._principal_cached

    @cached_property
    def _principal_cached(self) -> tuple[Array, Array]:
        moments, axes = principal_decomposition(self.inertia)
        return readonly(moments), readonly(axes)

    # ------------------------------------------------------------ operations
    def transformed(self, rotation: Any = None, translation: Any = None) -> MassProperties:
        """The same body moved rigidly: first rotated about the body origin, then translated.

        Use it to place a part inside an assembly: the part's body coordinates x
        become ``R x + t`` in the assembly's coordinates.

        Parameters
        ----------
        rotation : None, a (3, 3) proper rotation matrix, or a single
            ``scipy.spatial.transform.Rotation``.
        translation : None or (3,) displacement, m.

        Returns
        -------
        MassProperties with centre of mass ``R c + t`` and inertia ``R I Rᵀ``.
        """
        matrix = np.eye(3) if rotation is None else rotation_matrix(rotation, "rotation")
        shift = (
            np.zeros(3)
            if translation is None
            else vector_to_si(translation, "length", "translation")
        )
        return MassProperties(
            self.mass,
            matrix @ self.center_of_mass + shift,
            matrix @ self.inertia @ matrix.T,
        )

    def __reduce__(self) -> tuple[type[MassProperties], tuple[float, Array, Array]]:
        # Rebuild through __init__ when unpickled, so arrays come back read-only.
        return (MassProperties, (self.mass, self.center_of_mass, self.inertia))

    def __add__(self, other: object) -> MassProperties:
        """Assembly of two parts given in the same body coordinates."""
        if not isinstance(other, MassProperties):
            return NotImplemented
        mass = self.mass + other.mass
        com = (self.mass * self.center_of_mass + other.mass * other.center_of_mass) / mass
        return MassProperties(mass, com, self.inertia_about(com) + other.inertia_about(com))

    def __radd__(self, other: object) -> MassProperties:
        # Lets ``sum(parts)`` start from 0.
        if isinstance(other, int) and other == 0:
            return self
        return NotImplemented

    def _repr_html_(self) -> str:
        from tumble.report.html import mass_properties_html

        return mass_properties_html(self)

    def __repr__(self) -> str:
        moments, _ = self.principal()
        rows = np.array2string(
            self.inertia, precision=6, separator=", ", prefix="    ", floatmode="maxprec"
        )
        return (
            "MassProperties(\n"
            f"  mass           = {self.mass:.6g} kg\n"
            f"  center_of_mass = {_format(self.center_of_mass)} m\n"
            f"  inertia about the centre of mass, body axes (kg·m²) =\n    {rows}\n"
            f"  principal moments = {_format(moments)} kg·m²\n"
            ")"
        )


def _format(values: ArrayLike) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in np.asarray(values, dtype=float)) + "]"


def rotation_matrix(rotation: Any, name: str) -> Array:
    """A validated (3, 3) proper rotation matrix from a matrix or a scipy ``Rotation``."""
    from scipy.spatial.transform import Rotation

    if isinstance(rotation, Rotation):
        if not rotation.single:
            raise InputError(f"Expected `{name}` to be a single rotation, got {len(rotation)}.")
        return np.asarray(rotation.as_matrix(), dtype=float)
    matrix = vector_to_si(rotation, "dimensionless", name, (3, 3))
    error = np.abs(matrix.T @ matrix - np.eye(3)).max()
    if error > 1e-9 or np.linalg.det(matrix) < 0:
        raise InputError(
            f"Expected `{name}` to be a proper rotation matrix (orthonormal, det +1), got "
            f"det = {np.linalg.det(matrix):.6g} and max |RᵀR − E| = {error:.3g}."
        )
    return matrix


def principal_decomposition(inertia: Array) -> tuple[Array, Array]:
    """Ascending principal moments and a proper rotation of principal axes (see
    :meth:`MassProperties.principal` for the rule that fixes the axes), of one
    (3, 3) tensor or of a stack (..., 3, 3) at once (then (..., 3) and (..., 3, 3))."""
    tensors = np.asarray(inertia, dtype=float)
    if tensors.ndim == 2:
        return _principal_one(tensors)
    scale = np.maximum(np.trace(tensors, axis1=-2, axis2=-1), np.finfo(float).tiny)
    diagonal = np.diagonal(tensors, axis1=-2, axis2=-1)
    if not np.any(tensors - diagonal[..., None] * np.eye(3)) and np.all(
        np.diff(diagonal, axis=-1) > REPEATED_MOMENT_TOLERANCE * scale[..., None]
    ):
        # Every tensor already principal, ascending and distinct, as _principal_one
        # finds of one: the rule below gives the body axes (eigh costs 0.4 µs a tensor).
        return np.maximum(diagonal, 0.0), np.broadcast_to(np.eye(3), tensors.shape).copy()
    moments, vectors = np.linalg.eigh(tensors)
    repeated = np.any(np.diff(moments, axis=-1) <= REPEATED_MOMENT_TOLERANCE * scale[..., None], -1)
    # Distinct moments (nearly every body of a batch): the rule of _principal_one
    # for every tensor at once; the rare repeated ones go through it one by one.
    moments = np.maximum(moments, 0.0)
    axes = np.empty_like(vectors)
    for k in (0, 1):
        column = vectors[..., :, k]
        magnitudes = np.abs(column)
        first = np.argmax(magnitudes >= magnitudes.max(axis=-1, keepdims=True) - 1e-9, axis=-1)
        sign = np.sign(np.take_along_axis(column, first[..., None], axis=-1))
        axes[..., :, k] = column * np.where(sign == 0, 1.0, sign)
    third = np.cross(axes[..., :, 0], axes[..., :, 1])
    axes[..., :, 2] = third / np.linalg.norm(third, axis=-1, keepdims=True)
    for index in zip(*np.nonzero(repeated), strict=True):
        moments[index], axes[index] = _principal_one(tensors[index])
    return moments, axes


def _principal_one(inertia: Array) -> tuple[Array, Array]:
    scale = max(float(np.trace(inertia)), np.finfo(float).tiny)
    tol = REPEATED_MOMENT_TOLERANCE * scale
    diagonal = np.diag(inertia)
    if not np.any(inertia - np.diag(diagonal)) and np.all(np.diff(diagonal) > tol):
        # Already principal, ascending and distinct: what the rule below gives.
        return np.maximum(diagonal, 0.0), np.eye(3)
    moments, vectors = np.linalg.eigh(inertia)
    # Group repeated moments: eigh sorts ascending, so equal ones are neighbours.
    groups: list[list[int]] = [[0]]
    for k in (1, 2):
        if moments[k] - moments[groups[-1][-1]] <= tol:
            groups[-1].append(k)
        else:
            groups.append([k])
    axes = np.zeros((3, 3))
    # Within the validation tolerance a negative moment is round-off of a zero one.
    moments = np.maximum(moments, 0.0)
    for group in groups:
        moments[group] = moments[group].mean()
        if len(group) == 1:
            (k,) = group
            axes[:, k] = _signed(vectors[:, k])
        elif len(group) == 3:
            axes = np.eye(3)
        else:
            basis = vectors[:, group]
            projector = basis @ basis.T
            lengths = np.linalg.norm(projector, axis=0)  # |P e_k| for body axes e_k
            k = int(np.flatnonzero(lengths >= lengths.max() - 1e-9)[0])
            first = projector[:, k] / lengths[k]
            axes[:, group[0]] = first
            axes[:, group[1]] = 0.0  # completed below
    if len(groups) != 1:
        # Complete a right-handed frame with the axis that is still free: the
        # second of a repeated pair, or else the last axis.
        free = next((g[1] for g in groups if len(g) == 2), 2)
        i, j = {0: (1, 2), 1: (2, 0), 2: (0, 1)}[free]
        axes[:, free] = np.cross(axes[:, i], axes[:, j])
        axes[:, free] /= np.linalg.norm(axes[:, free])
    return moments, axes


def _signed(vector: Array) -> Array:
    """The vector or its opposite, whichever has its largest component positive.

    Components within 1e-9 of the largest count as tied, and the first of them
    decides, so round-off cannot flip the sign of an axis like (1, -1, 0)/√2.
    """
    magnitudes = np.abs(vector)
    k = int(np.flatnonzero(magnitudes >= magnitudes.max() - 1e-9)[0])
    return vector if vector[k] > 0 else -vector


def point_masses(masses: Any, positions: Any) -> MassProperties:
    """Mass properties of a set of point masses rigidly joined.

    Parameters
    ----------
    masses : (n,) masses, kg, each > 0.
    positions : (n, 3) body coordinates of the masses, m.

    Returns
    -------
    MassProperties with ``I_ij = Σ m_k (r_k² δ_ij − r_k,i r_k,j)`` about the
    centre of mass (products of inertia ``I_xy = −Σ m x y``).

    Examples
    --------
    A dumbbell of 1 kg and 3 kg, 1 m apart along x: the centre of mass is
    0.75 m from the light mass, and the moment across the bar is the reduced
    mass times the distance squared, ``(1 × 3 / 4) × 1² = 0.75 kg·m²``.

    >>> import tumble as tb
    >>> dumbbell = tb.point_masses([1.0, 3.0], [[0, 0, 0], [1.0, 0, 0]])
    >>> print(f"{dumbbell.mass:.1f} kg at x = {dumbbell.center_of_mass[0]:.2f} m")
    4.0 kg at x = 0.75 m
    >>> print(", ".join(f"{m:.2f}" for m in dumbbell.inertia.diagonal()))
    0.00, 0.75, 0.75
    """
    m = vector_to_si(masses, "mass", "masses", (-1,))
    r = vector_to_si(positions, "length", "positions", (-1, 3))
    if m.size == 0:
        raise InputError("Expected `masses` to hold at least one mass, got none.")
    if r.shape[0] != m.shape[0]:
        raise InputError(
            f"Expected `positions` to have shape ({m.size}, 3) to match `masses`, got {r.shape}."
        )
    bad = np.flatnonzero(m <= 0)
    if bad.size:
        raise InputError(
            f"Expected every entry of `masses` > 0 kg, got masses[{bad[0]}] = {float(m[bad[0]])!r}."
        )
    total = float(m.sum())
    com = m @ r / total
    d = r - com  # about the centre of mass directly: no cancellation from a far origin
    inertia = np.eye(3) * np.sum(m * np.einsum("ij,ij->i", d, d)) - np.einsum(
        "k,ki,kj->ij", m, d, d
    )
    return MassProperties(total, com, inertia)


def as_mass_properties(value: Any, name: str = "mp") -> MassProperties:
    """``value`` if it is a :class:`MassProperties`.

    Raises
    ------
    InputError
        Anything else; the message names ``name`` and the type received.
    """
    if not isinstance(value, MassProperties):
        raise InputError(f"Expected `{name}` to be a MassProperties, got {type(value).__name__}.")
    return value


def axisymmetric_moments(mp: MassProperties) -> tuple[float, float]:
    """``(I_s, I_⊥)``, kg·m²: the moments about the centre of mass along and across
    body z of a body symmetric about body z (inertia ``diag(I⊥, I⊥, Is)``).

    Raises
    ------
    InputError
        A body not symmetric about z (I_xx ≠ I_yy or products of inertia, beyond
        ``PHYSICAL_TOLERANCE`` of the trace), or with no moment about z.
    """
    inertia = mp.inertia
    scale = max(float(np.trace(inertia)), np.finfo(float).tiny)
    tol = PHYSICAL_TOLERANCE * scale
    off = max(abs(inertia[0, 1]), abs(inertia[0, 2]), abs(inertia[1, 2]))
    if off > tol or abs(inertia[0, 0] - inertia[1, 1]) > tol:
        raise InputError(
            "Expected `mp` to be symmetric about body z (inertia about the centre of mass "
            "diag(I⊥, I⊥, Is): I_xx = I_yy and no products of inertia), got inertia rows "
            f"{_format(inertia[0])}, {_format(inertia[1])}, {_format(inertia[2])} kg·m²."
        )
    axial = float(inertia[2, 2])
    if axial <= tol:
        raise InputError(
            "Expected `mp` to have a moment about its symmetry axis z > 0 kg·m² (a spin about "
            f"the axis needs one), got I_zz = {axial!r} (a thin rod along z?)."
        )
    return axial, 0.5 * float(inertia[0, 0] + inertia[1, 1])
