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

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, quoted
from tumble.massprops import MassProperties, as_mass_properties, readonly
from tumble.resources import check_memory
from tumble.theory.common import spin_axis
from tumble.theory.rotordynamics_validation import (
    check_matrices,
    check_tilt_held,
    checked_speeds,
    rotor_moments,
    transverse_pair,
)
from tumble.units import to_si, vector_to_si

__all__ = ["Bearing", "RigidRotor", "Whirl"]

Array = NDArray[np.float64]

#: Speeds solved at once: the stacked eigenproblems (or solves) of this many
#: speeds take a few MB, so that millions of speeds run in bounded memory beside
#: their result, as fast as in one stack (the per-call cost is small at this size).
CHUNK = 4096


@dataclass(frozen=True)
class Bearing:
    """An elastic bearing of a :class:`RigidRotor`.

    Parameters
    ----------
    position : its axial position from the rotor's ``point`` along its axis, m.
    stiffness : N/m: one number (isotropic) or a pair (k_x, k_y) along the
        rotor's two axes perpendicular to its spin axis (:class:`RigidRotor`'s ``frame``;
        the body's x and y for a rotor spinning about z). The bearings do not
        turn with the rotor.
    damping : N·s/m, likewise (default 0).
    """

    position: float
    stiffness: tuple[float, float]
    damping: tuple[float, float] = (0.0, 0.0)

    def __init__(self, position: Any, stiffness: Any, damping: Any = 0.0) -> None:
        object.__setattr__(self, "position", to_si(position, "length", "position"))
        object.__setattr__(self, "stiffness", transverse_pair(stiffness, "stiffness", "stiffness"))
        object.__setattr__(self, "damping", transverse_pair(damping, "linear_damping", "damping"))


@dataclass(frozen=True, eq=False)
class Whirl:
    """The modes of a rotor at each speed (see :meth:`RigidRotor.whirl`).

    Attributes
    ----------
    speeds : (n,) spin speeds, rad/s.
    frequencies : (n, 4) damped natural frequencies, rad/s, ascending.
    forward : (n, 4) True where the mode whirls with the spin: its orbit turns from
        x towards y at a positive speed, from y towards x at a negative one (at
        rest, from x towards y).
    damping_ratios : (n, 4) −Re λ / |λ|.
    shapes : (n, 4, 4) complex mode shapes, (x, y, α, β) of each mode, scaled to
        a largest component of 1.
    """

    speeds: Array
    frequencies: Array
    forward: NDArray[np.bool_]
    damping_ratios: Array
    shapes: NDArray[np.complex128]


def _rotor_frame(axis: Array) -> Array:
    """(3, 3) the rotor's axes in body coordinates, as columns (e_x, e_y, axis),
    right-handed: e_x is the body axis after the one the spin axis is most
    along (z → x; x → y; y → z), made perpendicular to it. So along a body axis
    the frame is that of the body's axes in turn (z: x, y), and an axis a
    round-off away from one has the same frame to that round-off."""
    k = (int(np.argmax(np.abs(axis))) + 1) % 3
    first = np.eye(3)[k] - axis[k] * axis  # |axis[k]|² ≤ 1/2: well conditioned
    first /= np.linalg.norm(first)
    return np.column_stack([first, np.cross(axis, first), axis])


class RigidRotor:
    """A rigid axisymmetric rotor on elastic bearings (see :mod:`tumble.theory.rotordynamics`).

    Parameters
    ----------
    body : the rotor's MassProperties: ``axis`` must be one of its principal
        axes, with equal moments about the other two (an axisymmetric rotor),
        and its centre of mass on the axis.
    bearings : :class:`Bearing` objects, with stiffness at two or more axial
        positions (to hold the rotor's tilt).
    axis : (3,) the spin axis in body coordinates.
    point : (3,) the body point from which bearing positions are measured, m.

    Attributes
    ----------
    frame : (3, 3) the rotor's axes (e_x, e_y, axis) as columns in body
        coordinates: x, y of the motion and of the bearings' (k_x, k_y) are
        along e_x, e_y (for the axis along z, the body's x and y).
    body : the rotor's MassProperties.
    mass, polar, transverse : m (kg), I_p and I_t about the centre of mass (kg·m²).
    centre : the centre of mass's axial position from ``point``, m.
    arms : (n_bearings,) each bearing's axial position from the centre of mass, m.
    mass_matrix, stiffness, damping, gyroscopic : (4, 4) M, K, C and G of the
        equations of motion (see the module's docstring).

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

    def __init__(
        self, body: Any, bearings: Any, axis: Any = (0.0, 0.0, 1.0), point: Any = (0.0, 0.0, 0.0)
    ) -> None:
        mp: MassProperties = as_mass_properties(body, "body")
        n = spin_axis(axis)
        p = vector_to_si(point, "length", "point", (3,))
        polar, transverse, along = rotor_moments(mp, n, p)
        bearings = _bearing_list(bearings)
        check_tilt_held(transverse, bearings)
        self.body = mp
        self.frame = _rotor_frame(n)
        self.mass = mp.mass
        self.polar = polar
        self.transverse = float(transverse.mean())
        self.centre = along
        self.bearings = tuple(bearings)
        self.arms = np.array([b.position - along for b in bearings])
        with np.errstate(over="ignore", invalid="ignore"):  # refused below
            self.stiffness = self._matrix([b.stiffness for b in bearings])
            self.damping = self._matrix([b.damping for b in bearings])
        self.mass_matrix = np.diag([self.mass, self.mass, self.transverse, self.transverse])
        self.gyroscopic = np.zeros((4, 4))
        self.gyroscopic[2, 3], self.gyroscopic[3, 2] = polar, -polar
        check_matrices(self)

    def _matrix(self, pairs: list[tuple[float, float]]) -> Array:
        """K (or C) of the bearings' (x, y) values at their arms a from the centre of mass."""
        kx = np.array([p[0] for p in pairs])
        ky = np.array([p[1] for p in pairs])
        a = self.arms
        return np.array(
            [
                [kx.sum(), 0.0, 0.0, (kx * a).sum()],
                [0.0, ky.sum(), -(ky * a).sum(), 0.0],
                [0.0, -(ky * a).sum(), (ky * a * a).sum(), 0.0],
                [(kx * a).sum(), 0.0, 0.0, (kx * a * a).sum()],
            ]
        )

    @staticmethod
    def _fits(count: int, output: int, working: int, what: str) -> None:
        """Refuse results of ``output`` bytes a speed for ``count`` speeds that would not
        fit in the memory budget, with the ``working`` bytes a speed of one chunk takes."""
        check_memory(
            count * output + min(count, CHUNK) * working,
            lambda: f"{what} at {count} speeds ({output} bytes each)",
            "Ask for fewer speeds at once.",
        )

    def _speeds_in_budget(
        self, speeds: Any, output: int, working: int, what: str
    ) -> tuple[Array, bool]:
        """The speeds (rad/s; see
        :func:`~tumble.theory.rotordynamics_validation.checked_speeds`) and whether one was
        given as a scalar, refusing ``what`` (``output`` bytes a speed,
        ``working`` bytes a speed of one chunk) where it would not fit in the memory budget."""
        values, scalar = checked_speeds(self, speeds)
        self._fits(len(values), output, working, what)
        return values, scalar

    def state_matrices(self, speeds: Any) -> Array:
        """(n, 8, 8) the first-order system ẏ = A y of each spin speed (rad/s), for the
        state y = (q, q̇), q = (x, y, α, β): its eigenvalues are the modes.

        Raises
        ------
        RequestTooLargeError
            Matrices that would not fit in the memory budget.
        """
        values, _ = self._speeds_in_budget(speeds, 512, 0, "the state matrices")
        return self._state_matrices(values)

    def _state_matrices(self, speeds: Array) -> Array:
        """(n, 8, 8) the state matrices of the speeds (rad/s, checked)."""
        inverse = np.linalg.inv(self.mass_matrix)
        matrices = np.zeros((len(speeds), 8, 8))
        matrices[:, :4, 4:] = np.eye(4)
        matrices[:, 4:, :4] = -inverse @ self.stiffness
        matrices[:, 4:, 4:] = -inverse @ self.damping - speeds[:, None, None] * (
            inverse @ self.gyroscopic
        )
        return matrices

    def _forward(self, shapes: NDArray[np.complex128], speeds: Any = 1.0) -> NDArray[np.bool_]:
        """Whether modes (..., 4) whirl forward: the orbit of the bearing point with
        the largest motion turns the way of the spin, from x towards y at
        ``speeds`` ≥ 0 (rad/s, broadcast against the modes; at rest, that way by
        convention) and from y towards x below 0. A flat orbit (a line) is not
        forward."""
        x = shapes[..., [0]] + self.arms * shapes[..., [3]]
        y = shapes[..., [1]] - self.arms * shapes[..., [2]]
        k = np.argmax(np.abs(x) ** 2 + np.abs(y) ** 2, axis=-1)[..., None]
        xk = np.take_along_axis(x, k, axis=-1)[..., 0]
        yk = np.take_along_axis(y, k, axis=-1)[..., 0]
        # x = Re(X e^{iωt}), y = Re(Y e^{iωt}) turns from x to y when Im(conj(X) Y) < 0.
        turning = np.imag(np.conj(xk) * yk)
        return np.asarray(np.where(np.asarray(speeds) < 0, turning > 0, turning < 0))

    def whirl(self, speeds: Any) -> Whirl:
        """The four modes at each spin speed (rad/s): damped natural frequencies
        (the imaginary parts of the eigenvalues with positive imaginary part),
        their direction (forward: with the spin, at either sign of the speed),
        damping ratio and shape. Stacked eigenproblems of ``CHUNK`` speeds.

        Raises
        ------
        RequestTooLargeError
            Results that would not fit in the memory budget.
        """
        # The results (8 + 32 + 1 + 32 + 256 bytes a speed), and a chunk's
        # matrices, eigenvectors and their copies.
        what = "the whirl (frequencies, directions, damping ratios, shapes)"
        values, _ = self._speeds_in_budget(speeds, 329, 4096, what)
        n = len(values)
        frequencies, ratios = np.empty((n, 4)), np.empty((n, 4))
        forward = np.empty((n, 4), dtype=bool)
        shapes = np.empty((n, 4, 4), dtype=complex)
        for part in _chunks(n):
            (frequencies[part], forward[part], ratios[part], shapes[part]) = self._whirl(
                values[part]
            )
        return Whirl(readonly(values), readonly(frequencies), forward, readonly(ratios), shapes)

    def _whirl(
        self, values: Array
    ) -> tuple[Array, NDArray[np.bool_], Array, NDArray[np.complex128]]:
        """The frequencies, directions, damping ratios and shapes of :meth:`whirl`
        at the speeds ``values`` (rad/s, checked), in one stacked eigenproblem."""
        eigenvalues, vectors = np.linalg.eig(self._state_matrices(values))
        order = np.argsort(-eigenvalues.imag, axis=1)[:, :4]  # the four of Im λ ≥ 0
        order = np.take_along_axis(
            order, np.argsort(np.take_along_axis(eigenvalues.imag, order, axis=1), axis=1), axis=1
        )
        lam = np.take_along_axis(eigenvalues, order, axis=1)
        # (n, mode, coordinate): the displacement half of each eigenvector.
        shapes = np.take_along_axis(vectors[:, :4, :], order[:, None, :], axis=2)
        shapes = np.swapaxes(shapes, 1, 2)
        largest = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=2)[..., None], axis=2)
        shapes = shapes / largest
        frequencies = np.maximum(lam.imag, 0.0)
        size = np.abs(lam)
        ratios = np.where(size > 0, -lam.real / np.where(size > 0, size, 1.0), 1.0)
        forward = self._forward(shapes, values[:, None]) & (lam.imag > 0)
        # A repeated frequency (isotropic bearings: cylindrical modes, and every
        # mode at rest) is one forward and one backward circular whirl, whatever
        # pair of eigenvectors the solver returned.
        for j in range(3):
            close = (
                np.abs(frequencies[:, j + 1] - frequencies[:, j]) <= 1e-9 * frequencies[:, j + 1]
            ) & (frequencies[:, j] > 0)
            forward[close, j], forward[close, j + 1] = False, True
        return frequencies, forward, ratios, shapes

    def frequencies(self, speeds: Any) -> Array:
        """Damped natural frequencies, rad/s, ascending: (n, 4), or (4,) for a scalar speed.

        Raises
        ------
        RequestTooLargeError
            Results that would not fit in the memory budget.
        """
        # The results, and a chunk's matrices and eigenvalues.
        values, scalar = self._speeds_in_budget(speeds, 32, 1024, "the natural frequencies")
        n = len(values)
        result = np.empty((n, 4))
        for part in _chunks(n):
            # The eigenvalues alone (no eigenvectors): what whirl() gives, in half the time.
            eigenvalues = np.linalg.eigvals(self._state_matrices(values[part]))
            result[part] = np.maximum(np.sort(eigenvalues.imag, axis=1)[:, 4:], 0.0)
        return result[0] if scalar else result

    def critical_speeds(self, backward: bool | np.bool_ | None = None) -> Array:
        """The spin speeds (rad/s, ascending) where an unbalance makes the rotor
        resonate, undamped: the real positive Ω² of ``K v = Ω² (M − i G) v`` (the
        synchronous solution ``q = v e^{iΩt}``).

        On isotropic bearings an unbalance, a force turning with the spin,
        drives forward whirl only: the critical speeds are where a forward whirl
        frequency equals the spin, and a disk-like rotor (I_p ≥ I_t) has no
        conical one. On anisotropic bearings every mode whirls on an ellipse
        (a nearly flat one, turning either way), which the unbalance excites
        whichever way it turns: the roots of backward whirl count too.
        ``backward`` = True or False includes or leaves out those roots
        whatever the bearings (default: included on anisotropic bearings).

        Raises
        ------
        InputError
            A ``backward`` that is not None, True or False.
        """
        if backward is None:
            backward = any(b.stiffness[0] != b.stiffness[1] for b in self.bearings)
        elif not isinstance(backward, bool | np.bool_):
            raise InputError(f"Expected `backward` to be None, True or False, got {backward!r}.")
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
            if (repeated or backward or bool(self._forward(vector))) and not any(
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
        2) of (x, y), each coordinate ``Re(A e^{iΩt})`` (m).

        Raises
        ------
        InputError
            Speeds, unbalance and position whose orbits overflow float64.
        RequestTooLargeError
            Results that would not fit in the memory budget.
        """
        values, u, arm = self._unbalance(speeds, unbalance, position)
        n, count = len(values), len(self.bearings)
        self._fits(n, 32 * count, 1024 + 64 * count, "the unbalance orbits")
        orbits = np.empty((n, count, 2), dtype=complex)
        for part in _chunks(n):
            orbits[part] = self._orbits(values[part], u, arm)
        return orbits

    def _unbalance(self, speeds: Any, unbalance: Any, position: Any) -> tuple[Array, float, float]:
        """The speeds (rad/s), the unbalance (kg·m) and its arm from the centre of mass (m)."""
        values, _ = checked_speeds(self, speeds)
        u = to_si(unbalance, "unbalance", "unbalance")
        arm = to_si(position, "length", "position") - self.centre
        return values, u, arm

    def _orbits(self, values: Array, u: float, arm: float) -> NDArray[np.complex128]:
        """(n, n_bearings, 2) :meth:`unbalance_orbits` at the speeds ``values`` (rad/s)."""
        scale = 1.0 / np.sqrt(np.diag(self.stiffness))
        w = values[:, None, None]
        with np.errstate(over="ignore", invalid="ignore"):
            forces = u * values[:, None] ** 2 * np.array([1.0, -1j, 1j * arm, arm])
            matrices = (
                self.stiffness
                - w**2 * self.mass_matrix
                + 1j * w * (self.damping + w * self.gyroscopic)
            )
            # Scaled by the stiffness's diagonal: translations (N/m) and tilts
            # (N·m/rad) differ by orders of magnitude, and the solve keeps its digits.
            matrices = scale[:, None] * matrices * scale
            finite = np.isfinite(matrices).all(axis=(1, 2)) & np.isfinite(forces).all(axis=1)
            q = np.zeros((len(values), 4), dtype=complex)
            q[finite] = np.linalg.solve(matrices[finite], (scale * forces[finite])[..., None])[
                ..., 0
            ]
            q = scale * q
            x = q[:, [0]] + self.arms * q[:, [3]]
            y = q[:, [1]] - self.arms * q[:, [2]]
            orbits = np.stack([x, y], axis=2)
        bad = ~(finite & np.isfinite(orbits).all(axis=(1, 2)))
        if bad.any():
            raise InputError(
                f"Expected a speed, `unbalance` and `position` whose steady orbits are finite "
                f"in float64, got {float(values[bad][0])!r} rad/s with {u!r} kg·m at "
                f"{arm + self.centre!r} m: they overflow."
            )
        return np.asarray(orbits, dtype=complex)

    def unbalance_response(self, speeds: Any, unbalance: Any, position: Any = 0.0) -> Array:
        """The major semi-axis of the steady orbit at each bearing, m: (n, n_bearings)
        (see :meth:`unbalance_orbits`; a circle's radius on isotropic bearings).

        Raises
        ------
        InputError, RequestTooLargeError
            As :meth:`unbalance_orbits`.
        """
        values, u, arm = self._unbalance(speeds, unbalance, position)
        n, count = len(values), len(self.bearings)
        self._fits(n, 8 * count, 1024 + 96 * count, "the unbalance response")
        response = np.empty((n, count))
        for part in _chunks(n):
            orbits = self._orbits(values[part], u, arm)
            response[part] = major_semi_axis(orbits[..., 0], orbits[..., 1])
        return response


def _chunks(count: int) -> Iterator[slice]:
    """Slices of ``CHUNK`` of ``count`` items, in order."""
    for start in range(0, count, CHUNK):
        yield slice(start, min(start + CHUNK, count))


def _bearing_list(bearings: Any) -> list[Bearing]:
    """``bearings`` as a list of :class:`Bearing`.

    Raises
    ------
    InputError
        Anything but a sequence of Bearing objects.
    """
    try:
        items = None if isinstance(bearings, str | bytes | Bearing) else list(bearings)
    except TypeError:
        items = None
    if items is None or not all(isinstance(b, Bearing) for b in items):
        raise InputError(
            f"Expected `bearings` to be a list of tumble.theory.Bearing objects, got "
            f"{quoted(bearings)}."
        )
    return items


def major_semi_axis(x: Any, y: Any) -> Any:
    """The major semi-axis of the ellipse ``(Re(X e^{iθ}), Re(Y e^{iθ}))`` for the
    complex amplitudes X = ``x``, Y = ``y`` (arrays of one shape, or numbers), in
    their unit: the largest distance of the orbit from its centre."""
    x, y = np.asarray(x), np.asarray(y)
    # The semi-axes a ≥ b have a² + b² = |X|² + |Y|² and a b = |Im(X̄ Y)|;
    # (a² − b²)² = (|X|² − |Y|²)² + 4 Re(X̄ Y)², a sum of squares (no
    # cancellation for a circle, where it is 0).
    total = np.abs(x) ** 2 + np.abs(y) ** 2
    spread = np.hypot(np.abs(x) ** 2 - np.abs(y) ** 2, 2 * np.real(np.conj(x) * y))
    return np.sqrt((total + spread) / 2)
