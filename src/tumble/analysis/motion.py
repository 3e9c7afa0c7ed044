"""Flips of a tumbling body, its polhode and herpolhode (the Poinsot
construction), the drift of what its motion conserves."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from tumble.analysis.common import as_trajectory
from tumble.errors import InputError
from tumble.trajectory import Trajectory

__all__ = ["Flips", "Herpolhode", "Polhode", "drift", "flips", "herpolhode", "polhode"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Flips:
    """Sign changes of ω along the intermediate principal axis (see :func:`flips`).

    Attributes
    ----------
    times : the times of the sign changes, s, each linearly interpolated
        between the two samples around it.
    period : twice the mean interval between successive flips, s: the full
        period of ω(t), comparable to :func:`tumble.theory.flip_period`.
    count : the number of flips.
    axis : (3,) the intermediate principal axis, body coordinates.
    """

    times: Array
    period: float
    count: int
    axis: Array


@dataclass(frozen=True, eq=False)
class Polhode:
    """The polhode: L in the principal axes (see :func:`polhode`). SI units.

    Attributes
    ----------
    angular_momentum_body : (n, 3) L in the principal axes, kg·m²/s (about the
        centre of mass, or about the pivot).
    moments : (3,) principal moments, ascending, kg·m².
    axes : (3, 3) principal axes as columns, body coordinates.
    energy_ellipsoid : (3,) semi-axes √(2 E I_k) of the ellipsoid
        ``Σ L_k² / (2 E I_k) = 1`` on which L lies, E the kinetic energy at t = 0, kg·m²/s.
    momentum_sphere : |L| at t = 0, kg·m²/s: the radius of the sphere on which
        L lies; the polhode is the intersection of the two (torque-free motion).
    """

    angular_momentum_body: Array
    moments: Array
    axes: Array
    energy_ellipsoid: Array
    momentum_sphere: float


def _principal(trajectory: Trajectory) -> tuple[Array, Array]:
    """Principal moments (ascending) and axes of the inertia the dynamics used."""
    from tumble.massprops import principal_decomposition

    mp = trajectory.mass_properties
    inertia = mp.inertia if trajectory.pivot is None else mp.inertia_about(trajectory.pivot)
    return principal_decomposition(inertia)


def flips(trajectory: Trajectory) -> Flips:
    """The flips of a torque-free body: sign changes of ω along its intermediate axis.

    The component of ω (body coordinates) along the intermediate principal axis
    (of the inertia about the centre of mass, or about the pivot) is sampled;
    each sign change between two successive samples is located by linear
    interpolation (its error is third order in the sampling interval where the
    component crosses zero with no curvature, as the Jacobi sn and cn do).
    Samples within 1e-12 of the largest |ω| of zero are skipped, so round-off
    about an exact zero makes no flips. The period is twice the mean interval
    between successive flips: ω(t) changes sign twice in each of its periods,
    the period given by :func:`tumble.theory.flip_period`.

    Raises
    ------
    InputError
        Fewer than 3 samples, or fewer than two sign changes (no period can be
        measured: a record too short, or a body that does not flip).

    Examples
    --------
    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> traj = tb.simulate(body, [0.1, 1.0, 0.1], duration=50.0)
    >>> found = tb.analysis.flips(traj)
    >>> found.count, found.axis.tolist()
    (4, [0.0, 1.0, 0.0])
    >>> expected = tb.theory.flip_period(body, [0.1, 1.0, 0.1])
    >>> print(f"{found.period:.4f} s, theory {expected:.4f} s")
    22.9963 s, theory 22.9963 s
    """
    traj = as_trajectory(trajectory)
    _, axes = _principal(traj)
    middle = axes[:, 1]
    component = traj.omega @ middle
    scale = float(np.max(np.abs(traj.omega)))
    keep = np.flatnonzero(np.abs(component) > 1e-12 * scale)
    t, w = traj.t[keep], component[keep]
    change = np.flatnonzero(np.signbit(w[1:]) != np.signbit(w[:-1]))
    times = t[change] - w[change] * (t[change + 1] - t[change]) / (w[change + 1] - w[change])
    if times.size < 2:
        raise InputError(
            "Expected ω to change sign along the intermediate principal axis at least twice "
            f"to measure the flip period, got {times.size} sign changes over "
            f"{traj.t[-1] - traj.t[0]:.6g} s."
        )
    period = 2.0 * (times[-1] - times[0]) / (times.size - 1)
    return Flips(times=times, period=float(period), count=int(times.size), axis=middle)


def polhode(trajectory: Trajectory) -> Polhode:
    """The angular momentum in the principal axes, with the surfaces that hold it.

    ``L_k = I_k ω_k`` in the principal axes of the inertia about the centre of
    mass (or about the pivot). For torque-free motion L stays on the sphere
    ``|L| = const`` and on the energy ellipsoid ``Σ L_k² / (2 E I_k) = 1`` (semi-axes
    √(2 E I_k)): their intersection is the polhode. Both are taken at t = 0.

    Raises
    ------
    InputError
        Fewer than 3 samples.

    Examples
    --------
    Without torque, L stays on both the momentum sphere and the energy ellipsoid:

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> path = tb.analysis.polhode(tb.simulate(body, [0.1, 1.0, 0.1], duration=30.0))
    >>> L = path.angular_momentum_body
    >>> np.allclose(np.linalg.norm(L, axis=1), path.momentum_sphere)
    True
    >>> np.allclose(np.sum((L / path.energy_ellipsoid) ** 2, axis=1), 1.0)
    True
    """
    traj = as_trajectory(trajectory)
    moments, axes = _principal(traj)
    momentum = (traj.omega @ axes) * moments
    energy = 0.5 * float(np.sum(momentum[0] ** 2 / moments))
    return Polhode(
        angular_momentum_body=momentum,
        moments=moments,
        axes=axes,
        energy_ellipsoid=np.sqrt(2.0 * energy * moments),
        momentum_sphere=float(np.linalg.norm(momentum[0])),
    )


@dataclass(frozen=True, eq=False)
class Herpolhode:
    """The herpolhode: ω in space on the invariable plane (see :func:`herpolhode`).

    Attributes
    ----------
    omega_space : (n, 3) ω in space coordinates, rad/s.
    normal : (3,) the unit vector of the fixed L, space coordinates.
    height : 2 T / |L|, rad/s: the distance of the invariable plane from the
        body's fixed point, the same for every sample (``ω · normal``).
    plane_axes : (3, 2) two unit vectors spanning the plane, space coordinates
        (with ``normal`` a right-handed frame).
    in_plane : (n, 2) ω's coordinates along ``plane_axes``, rad/s: the curve
        the contact point traces on the plane.
    """

    omega_space: Array
    normal: Array
    height: float
    plane_axes: Array
    in_plane: Array


def herpolhode(trajectory: Trajectory) -> Herpolhode:
    """ω in space on the invariable plane: the Poinsot construction.

    In torque-free motion the inertia ellipsoid ``ω · I ω = 2T`` rolls without
    slipping on the plane normal to the fixed L at the distance ``2T / |L|``
    from the fixed point; the contact point is ω itself, so ω·L̂ = 2T/|L| at
    every instant (Landau & Lifshitz, *Mechanics*, §37; Goldstein §5.6). The
    curve ω traces on the body is the polhode (:func:`polhode`), the one on
    the plane the herpolhode. L̂ and T are taken at t = 0.

    Raises
    ------
    InputError
        A motion that does not keep its energy and its angular momentum vector
        (a torque, gravity about a pivot, internal parts): no fixed plane.

    Examples
    --------
    ω stays on the invariable plane, at the distance ``2 T / |L|`` from the
    fixed point:

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> traj = tb.simulate(body, [0.1, 1.0, 0.1], duration=30.0)
    >>> plane = tb.analysis.herpolhode(traj)
    >>> print(f"{plane.height:.6f} rad/s")  # 2.04 J / 2.024846 kg·m²/s
    1.007484 rad/s
    >>> np.allclose(plane.omega_space @ plane.normal, plane.height)
    True
    """
    traj = as_trajectory(trajectory)
    kept = set(traj.conserved_quantities)
    if traj.internal or not {"energy", "angular_momentum_vector"} <= kept:
        what = "internal parts" if traj.internal else f"conserved {sorted(kept)}"
        raise InputError(
            "Expected a torque-free rigid body for the Poinsot construction (energy and the "
            f"angular momentum vector conserved, no internal parts), got a motion with {what}."
        )
    momentum = traj.angular_momentum[0]
    size = float(np.linalg.norm(momentum))
    if size == 0.0:
        raise InputError("Expected a body that turns for the Poinsot construction, got L = 0.")
    normal = momentum / size
    omega = traj.omega_space
    height = float(2.0 * traj.energy[0] / size)
    # Two unit vectors normal to L̂, with L̂ a right-handed frame.
    first = np.cross(normal, np.eye(3)[int(np.argmin(np.abs(normal)))])
    first /= np.linalg.norm(first)
    second = np.cross(normal, first)
    plane = np.column_stack([first, second])
    return Herpolhode(
        omega_space=omega, normal=normal, height=height, plane_axes=plane, in_plane=omega @ plane
    )


def drift(trajectory: Trajectory) -> dict[str, float]:
    """Largest relative drift of each quantity the motion conserves over the
    trajectory (:attr:`tumble.Trajectory.drift`; a copy)."""
    traj = as_trajectory(trajectory)
    return dict(traj.drift)
