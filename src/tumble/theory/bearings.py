"""A rigid rotor on elastic bearings: its whirl, critical speeds and unbalance response.

The rotor is a rigid body spinning at Ω about its axis (a principal axis, with
equal transverse moments I_t about the centre of mass and the polar moment
I_p), carried by bearings that are springs (and dashpots) perpendicular to the
axis. Its small motions have four degrees of freedom: the centre of mass's
displacement (x, y) perpendicular to the axis and the axis's tilts α about x and
β about y (Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines*,
2010, §3.5; Genta, *Dynamics of Rotating Systems*, 2005, ch. 3). A bearing at
axial position a from the centre of mass, of stiffness (k_x, k_y), sees the
shaft at (x + a β, y − a α), and with the angular momentum I_p Ω along the
tilted axis the equations are ``M q̈ + (C + Ω G) q̇ + K q = f`` for
q = (x, y, α, β), M = diag(m, m, I_t, I_t), G the gyroscopic matrix (I_p
between α and β, antisymmetric) and

    K = [[Σk_x, 0, 0, Σk_x a], [0, Σk_y, −Σk_y a, 0],
         [0, −Σk_y a, Σk_y a², 0], [Σk_x a, 0, 0, Σk_x a²]]

(C alike with the dampings). The gyroscopic moment splits each pair of
frequencies into a forward whirl (the orbit turns with the spin) and a
backward one; for a symmetric rotor on isotropic bearings the cylindrical
modes are at √(Σk/m) and the conical at (±I_p Ω + √(I_p² Ω² + 4 I_t K_θ)) / 2 I_t.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties, as_mass_properties, readonly
from tumble.theory.common import spin_axis
from tumble.units import to_si, vector_to_si

__all__ = ["Bearing", "RigidRotor", "Whirl"]

Array = NDArray[np.float64]

#: How far the two transverse moments may differ (relative) for the rotor to be
#: axisymmetric: beyond it the equations in the fixed frame have coefficients
#: that vary with the spin angle, which this model does not solve.
SYMMETRY_TOLERANCE = 1e-3


def _pair(value: Any, kind: str, name: str) -> tuple[float, float]:
    """A number (the same along both transverse axes) or a pair (x, y), ≥ 0."""
    array = np.atleast_1d(np.asarray(value, dtype=object))
    values: tuple[float, float]
    if array.shape == (1,):
        values = (to_si(array[0], kind, name),) * 2
    else:
        pair = vector_to_si(value, kind, name, (2,))
        values = (float(pair[0]), float(pair[1]))
    if not all(v >= 0 for v in values):
        raise InputError(f"Expected `{name}` >= 0, got {list(values)}.")
    return values


@dataclass(frozen=True)
class Bearing:
    """An elastic bearing of a :class:`RigidRotor`.

    Parameters
    ----------
    position : its axial position from the rotor's ``point`` along its axis, m.
    stiffness : N/m: one number (isotropic) or a pair (k_x, k_y) along the two
        body axes perpendicular to the rotor's axis.
    damping : N·s/m, likewise (default 0).
    """

    position: float
    stiffness: tuple[float, float]
    damping: tuple[float, float] = (0.0, 0.0)

    def __init__(self, position: Any, stiffness: Any, damping: Any = 0.0) -> None:
        object.__setattr__(self, "position", to_si(position, "length", "position"))
        object.__setattr__(self, "stiffness", _pair(stiffness, "stiffness", "stiffness"))
        object.__setattr__(self, "damping", _pair(damping, "linear_damping", "damping"))


@dataclass(frozen=True, eq=False)
class Whirl:
    """The modes of a rotor at each speed (see :meth:`RigidRotor.whirl`).

    Attributes
    ----------
    speeds : (n,) spin speeds, rad/s.
    frequencies : (n, 4) damped natural frequencies, rad/s, ascending.
    forward : (n, 4) True where the mode whirls with the spin.
    damping_ratios : (n, 4) −Re λ / |λ|.
    shapes : (n, 4, 4) complex mode shapes, (x, y, α, β) of each mode, scaled to
        a largest component of 1.
    """

    speeds: Array
    frequencies: Array
    forward: NDArray[np.bool_]
    damping_ratios: Array
    shapes: NDArray[np.complex128]


class RigidRotor:
    """A rigid axisymmetric rotor on elastic bearings (see :mod:`tumble.theory.bearings`).

    Parameters
    ----------
    body : the rotor's MassProperties: ``axis`` must be one of its principal
        axes, with equal moments about the other two (an axisymmetric rotor),
        and its centre of mass on the axis.
    bearings : :class:`Bearing` objects, with stiffness at two or more axial
        positions (to hold the rotor's tilt).
    axis : (3,) the spin axis in body coordinates.
    point : (3,) the body point from which bearing positions are measured, m.

    Examples
    --------
    A 10 kg disk (I_p = 0.05, I_t = 0.025 kg·m²) between two bearings of
    1e6 N/m at ±0.2 m: the cylindrical modes at √(2e6 / 10) = 447 rad/s, and
    no forward conical critical speed (I_p > I_t):

    >>> import tumble as tb
    >>> disk = tb.shapes.thin_disk(10.0, 0.1)
    >>> bearings = [tb.theory.Bearing(-0.2, 1e6), tb.theory.Bearing(0.2, 1e6)]
    >>> rotor = tb.theory.RigidRotor(disk, bearings)
    >>> print(rotor.frequencies(0.0).round(1))
    [ 447.2  447.2 1788.9 1788.9]
    >>> print(rotor.critical_speeds().round(1))
    [447.2]
    """

    def __init__(self, body: Any, bearings: Any, axis: Any = (0.0, 0.0, 1.0),
                 point: Any = (0.0, 0.0, 0.0)) -> None:  # fmt: skip
        mp: MassProperties = as_mass_properties(body, "body")
        n = spin_axis(axis)
        p = vector_to_si(point, "length", "point", (3,))
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
        transverse = np.linalg.eigvalsh(inertia - polar * np.outer(n, n))[1:]
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
        bearings = list(bearings)
        if not all(isinstance(b, Bearing) for b in bearings):
            raise InputError("Expected `bearings` to be tumble.theory.Bearing objects.")
        stiff = [b.position for b in bearings if max(b.stiffness) > 0]
        if len(set(stiff)) < 2:
            raise InputError(
                f"Expected bearings with stiffness at two or more axial positions (to hold the "
                f"rotor's tilt), got {len(set(stiff))}."
            )
        self.mass = mp.mass
        self.polar = polar
        self.transverse = float(transverse.mean())
        self.centre = along
        self.bearings = tuple(bearings)
        self.arms = np.array([b.position - along for b in bearings])
        self.stiffness = self._matrix([b.stiffness for b in bearings])
        self.damping = self._matrix([b.damping for b in bearings])
        self.mass_matrix = np.diag([self.mass, self.mass, self.transverse, self.transverse])
        self.gyroscopic = np.zeros((4, 4))
        self.gyroscopic[2, 3], self.gyroscopic[3, 2] = polar, -polar

    def _matrix(self, pairs: list[tuple[float, float]]) -> Array:
        """K (or C) of the bearings' (x, y) values at their arms a from the centre of mass."""
        kx = np.array([p[0] for p in pairs])
        ky = np.array([p[1] for p in pairs])
        a = self.arms
        return np.array(
            [[kx.sum(), 0.0, 0.0, (kx * a).sum()], [0.0, ky.sum(), -(ky * a).sum(), 0.0],
             [0.0, -(ky * a).sum(), (ky * a * a).sum(), 0.0],
             [(kx * a).sum(), 0.0, 0.0, (kx * a * a).sum()]]
        )  # fmt: skip

    def _speeds(self, speeds: Any) -> tuple[Array, bool]:
        """Speeds (rad/s) as an array, and whether one was given as a scalar."""
        if isinstance(speeds, str) or np.ndim(speeds) == 0:
            return np.array([to_si(speeds, "angular_velocity", "speeds")]), True
        values = np.asarray(speeds, dtype=float).ravel()
        if not np.all(np.isfinite(values)):
            bad = values[~np.isfinite(values)][:3].tolist()
            raise InputError(f"Expected finite `speeds` (rad/s), got {bad}.")
        return values, False

    def _state_matrix(self, speed: float) -> Array:
        inverse = np.linalg.inv(self.mass_matrix)
        return np.block([
            [np.zeros((4, 4)), np.eye(4)],
            [-inverse @ self.stiffness, -inverse @ (self.damping + speed * self.gyroscopic)],
        ])  # fmt: skip

    def _sense(self, shape: NDArray[np.complex128]) -> bool:
        """Whether a mode whirls forward: the orbit of the bearing point with the
        largest motion turns the way of the spin (x towards y)."""
        x = shape[0] + self.arms * shape[3]
        y = shape[1] - self.arms * shape[2]
        k = int(np.argmax(np.abs(x) ** 2 + np.abs(y) ** 2))
        # x = Re(X e^{iωt}), y = Re(Y e^{iωt}) turns from x to y when Im(conj(X) Y) < 0.
        return bool(np.imag(np.conj(x[k]) * y[k]) < 0)

    def whirl(self, speeds: Any) -> Whirl:
        """The four modes at each spin speed (rad/s): damped natural frequencies
        (the imaginary parts of the eigenvalues with positive imaginary part),
        their direction, damping ratio and shape."""
        values, _ = self._speeds(speeds)
        n = len(values)
        frequencies = np.empty((n, 4))
        ratios = np.empty((n, 4))
        forward = np.empty((n, 4), dtype=bool)
        shapes = np.empty((n, 4, 4), dtype=complex)
        for i, speed in enumerate(values):
            eigenvalues, vectors = np.linalg.eig(self._state_matrix(speed))
            order = np.argsort(-eigenvalues.imag)[:4]  # the four of non-negative imaginary part
            order = order[np.argsort(eigenvalues.imag[order])]
            for j, k in enumerate(order):
                lam = eigenvalues[k]
                shape = vectors[:4, k]
                shape = shape / shape[np.argmax(np.abs(shape))]
                frequencies[i, j] = max(lam.imag, 0.0)
                ratios[i, j] = -lam.real / abs(lam) if abs(lam) > 0 else 1.0
                forward[i, j] = self._sense(shape) if lam.imag > 0 else False
                shapes[i, j] = shape
            # A repeated frequency (isotropic bearings: cylindrical modes, and every
            # mode at rest) is one forward and one backward circular whirl, whatever
            # pair of eigenvectors the solver returned.
            for j in range(3):
                close = (
                    abs(frequencies[i, j + 1] - frequencies[i, j]) <= 1e-9 * frequencies[i, j + 1]
                )
                if close and frequencies[i, j] > 0:
                    forward[i, j], forward[i, j + 1] = False, True
        return Whirl(readonly(values), readonly(frequencies), forward, readonly(ratios), shapes)

    def frequencies(self, speeds: Any) -> Array:
        """Damped natural frequencies, rad/s, ascending: (n, 4), or (4,) for a scalar speed."""
        values, scalar = self._speeds(speeds)
        result = self.whirl(values).frequencies
        return np.array(result[0]) if scalar else np.array(result)

    def critical_speeds(self, backward: bool = False) -> Array:
        """The spin speeds (rad/s, ascending) where a forward whirl frequency equals
        the spin, undamped: the real positive Ω² of ``K v = Ω² (M − i G) v`` (the
        synchronous solution ``q = v e^{iΩt}``) whose mode whirls forward. A
        disk-like rotor (I_p ≥ I_t) has no conical forward critical speed.
        ``backward=True`` adds those of backward whirl, which an unbalance
        excites too where the bearings are anisotropic (their orbits are then
        ellipses, and a nearly flat one may turn either way)."""
        import scipy.linalg

        inertial = self.mass_matrix - 1j * self.gyroscopic  # Hermitian
        try:  # positive definite where I_t > I_p: real roots, by the Hermitian solver
            eigenvalues, vectors = scipy.linalg.eigh(self.stiffness.astype(complex), inertial)
        except np.linalg.LinAlgError:  # a disk-like rotor: the general solver
            eigenvalues, vectors = scipy.linalg.eig(self.stiffness, inertial)
        real = [
            (float(value.real), vector)
            for value, vector in zip(eigenvalues, vectors.T, strict=True)
            if np.isfinite(value) and abs(value.imag) <= 1e-9 * abs(value) and value.real > 0
        ]
        speeds: list[float] = []
        for value, vector in real:
            # A repeated root (isotropic bearings) holds both senses of whirl.
            repeated = sum(abs(other - value) <= 1e-9 * value for other, _ in real) > 1
            speed = float(np.sqrt(value))
            if (repeated or backward or self._sense(vector)) and not any(
                abs(speed - known) <= 1e-9 * speed for known in speeds
            ):
                speeds.append(speed)
        return np.array(sorted(speeds))

    def unbalance_orbits(
        self, speeds: Any, unbalance: Any, position: Any = 0.0
    ) -> NDArray[np.complex128]:
        """The steady orbits at the bearings for an unbalance ``unbalance`` (kg·m, the
        mass times its distance from the axis) in the plane at axial ``position``
        (m from ``point``), turning with the rotor: complex amplitudes (n, n_bearings,
        2) of (x, y), each coordinate ``Re(A e^{iΩt})`` (m)."""
        values, _ = self._speeds(speeds)
        u = to_si(unbalance, "unbalance", "unbalance")
        arm = to_si(position, "length", "position") - self.centre
        orbits = np.empty((len(values), len(self.bearings), 2), dtype=complex)
        scale = 1.0 / np.sqrt(np.diag(self.stiffness))
        for i, speed in enumerate(values):
            force = u * speed**2 * np.array([1.0, -1j, 1j * arm, arm])
            matrix = (self.stiffness - speed**2 * self.mass_matrix
                      + 1j * speed * (self.damping + speed * self.gyroscopic))  # fmt: skip
            # Scaled by the stiffness's diagonal: translations (N/m) and tilts
            # (N·m/rad) differ by orders of magnitude, and the solve keeps its digits.
            q = scale * np.linalg.solve(scale[:, None] * matrix * scale, scale * force)
            orbits[i, :, 0] = q[0] + self.arms * q[3]
            orbits[i, :, 1] = q[1] - self.arms * q[2]
        return orbits

    def unbalance_response(self, speeds: Any, unbalance: Any, position: Any = 0.0) -> Array:
        """The major semi-axis of the steady orbit at each bearing, m: (n, n_bearings)
        (see :meth:`unbalance_orbits`; a circle's radius on isotropic bearings)."""
        orbits = self.unbalance_orbits(speeds, unbalance, position)
        x, y = orbits[..., 0], orbits[..., 1]
        # The ellipse Re((X, Y) e^{iθ}) has semi-axes a ≥ b with a² + b² = |X|² + |Y|²
        # and a b = |Im(X̄ Y)|; (a² − b²)² = (|X|² − |Y|²)² + 4 Re(X̄ Y)², a sum of
        # squares (no cancellation for a circle, where it is 0).
        total = np.abs(x) ** 2 + np.abs(y) ** 2
        spread = np.hypot(np.abs(x) ** 2 - np.abs(y) ** 2, 2 * np.real(np.conj(x) * y))
        return np.sqrt((total + spread) / 2)
