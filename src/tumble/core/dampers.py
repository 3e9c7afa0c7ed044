"""Compiled equations of the internal energy sinks (the signatures are those of
:class:`tumble.core.parts.PartEquations`).

**Kane damper** (:class:`tumble.parts.KaneDamper`): a sphere of moment J turning
in a viscous fluid, coupled to the body by ``D (ω − ω_s)``. State: its angular
momentum ``σ = J ω_s`` (3, kg·m²/s, ω_s its absolute angular velocity in body
components), taken out of H before ω is solved for::

    σ̇ = D (ω − ω_s) − ω × σ

Packed rows: J (kg·m²) and D (N·m·s).

**Spring–mass damper** (:class:`tumble.parts.SpringMassDamper`; one a body at
most): a point mass sliding along the body-fixed unit direction n. State: its
displacement x (m) and momentum ``p = g·ω + μ ẋ`` (kg·m/s), with μ = m (M − m)
/ M the reduced mass, d0 its rest position from the centre of mass of the rest
of the body, ``d = d0 + x n`` and ``g = μ d0 × n``. The body's inertia about the
moving centre of mass becomes ``I_p + Δ(x)``, ``Δ = μ ((|d|² − |d0|²) 1 − (d dᵀ −
d0 d0ᵀ))``, and ω and ẋ solve ``(I_p + Δ) ω + g ẋ = H − …``, ``g·ω + μ ẋ = p``:
eliminating ẋ, its momentum is ``g p / μ`` and its inertia ``Δ − g gᵀ / μ``. The
kinetic energy is ``½ ωᵀ (I_p + Δ) ω + ẋ ω·g + ½ μ ẋ²`` (checked against the sum
over the masses with sympy in the tests), whence::

    ẋ = (p − g·ω) / μ
    ṗ = μ (ω × n)·(ω × d) − k x − c ẋ   (k its stiffness, c its damping)

Packed rows: d0 (3, m), n (3), μ (kg), k (N/m), c (N·s/m).
"""

from __future__ import annotations

from tumble.core._jit import njit
from tumble.core.parts import PartEquations

__all__ = ["DAMPER_EQUATIONS", "DAMPER_FIELDS", "SPRING_EQUATIONS", "SPRING_FIELDS"]

#: The rows of one Kane damper: the sphere's moment J (kg·m²) and the coupling D (N·m·s).
DAMPER_FIELDS = ("inertia", "damping")
#: The rows of a spring–mass damper: the rest position d0 (m, from the centre of
#: mass of the rest of the body), the unit direction n, the reduced mass μ (kg),
#: the stiffness k (N/m) and the damping c (N·s/m).
SPRING_FIELDS = (
    "rest_1",
    "rest_2",
    "rest_3",
    "direction_1",
    "direction_2",
    "direction_3",
    "reduced_mass",
    "stiffness",
    "damping",
)


@njit(inline="always")
def damper_momentum(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    """σ, the sphere's angular momentum."""
    return y[k], y[k + 1], y[k + 2]


@njit(inline="always")
def damper_rates(y, k, parts, row, rows, pc, w, v, hold):  # type: ignore[no-untyped-def]
    """``σ̇ = D (ω − σ / J) − ω × σ``."""
    w1, w2, w3 = w
    moment = parts[row, pc]
    damping = parts[row + 1, pc]
    s1 = y[k]
    s2 = y[k + 1]
    s3 = y[k + 2]
    return (
        damping * (w1 - s1 / moment) - (w2 * s3 - w3 * s2),
        damping * (w2 - s2 / moment) - (w3 * s1 - w1 * s3),
        damping * (w3 - s3 / moment) - (w1 * s2 - w2 * s1),
    )


@njit(inline="always")
def _spring_geometry(y, k, parts, row, pc):  # type: ignore[no-untyped-def]
    """d = d0 + x n, n, μ, d0 and g = μ d0 × n of the spring–mass damper."""
    x = y[k]
    e1 = parts[row, pc]
    e2 = parts[row + 1, pc]
    e3 = parts[row + 2, pc]
    n1 = parts[row + 3, pc]
    n2 = parts[row + 4, pc]
    n3 = parts[row + 5, pc]
    mu = parts[row + 6, pc]
    return (
        e1 + x * n1,
        e2 + x * n2,
        e3 + x * n3,
        n1,
        n2,
        n3,
        mu,
        e1,
        e2,
        e3,
        mu * (e2 * n3 - e3 * n2),
        mu * (e3 * n1 - e1 * n3),
        mu * (e1 * n2 - e2 * n1),
    )


@njit(inline="always")
def spring_momentum(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    """``g p / μ``: what the sliding mass's momentum p takes out of H."""
    _, _, _, _, _, _, mu, _, _, _, g4, g5, g6 = _spring_geometry(y, k, parts, row, pc)
    p = y[k + 1]
    return g4 * p / mu, g5 * p / mu, g6 * p / mu


@njit(inline="always")
def spring_inertia(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    """``Δ(x) − g gᵀ / μ`` as (a11, a12, a13, a22, a23, a33), kg·m²."""
    d1, d2, d3, _, _, _, mu, e1, e2, e3, g4, g5, g6 = _spring_geometry(y, k, parts, row, pc)
    grow = (d1 * d1 + d2 * d2 + d3 * d3) - (e1 * e1 + e2 * e2 + e3 * e3)
    return (
        mu * (grow - (d1 * d1 - e1 * e1)) - g4 * g4 / mu,
        -mu * (d1 * d2 - e1 * e2) - g4 * g5 / mu,
        -mu * (d1 * d3 - e1 * e3) - g4 * g6 / mu,
        mu * (grow - (d2 * d2 - e2 * e2)) - g5 * g5 / mu,
        -mu * (d2 * d3 - e2 * e3) - g5 * g6 / mu,
        mu * (grow - (d3 * d3 - e3 * e3)) - g6 * g6 / mu,
    )


@njit(inline="always")
def spring_rates(y, k, parts, row, rows, pc, w, v, hold):  # type: ignore[no-untyped-def]
    """``ẋ = (p − g·ω) / μ``, ``ṗ = μ (ω × n)·(ω × d) − k x − c ẋ``."""
    w1, w2, w3 = w
    d1, d2, d3, n1, n2, n3, mu, _, _, _, g4, g5, g6 = _spring_geometry(y, k, parts, row, pc)
    speed = (y[k + 1] - (g4 * w1 + g5 * w2 + g6 * w3)) / mu
    # ∂T/∂x = μ (ω × n)·(ω × d), then the spring and its damping.
    c1, c2, c3 = w2 * n3 - w3 * n2, w3 * n1 - w1 * n3, w1 * n2 - w2 * n1
    f1, f2, f3 = w2 * d3 - w3 * d2, w3 * d1 - w1 * d3, w1 * d2 - w2 * d1
    force = mu * (c1 * f1 + c2 * f2 + c3 * f3) - parts[row + 7, pc] * y[k]
    return speed, force - parts[row + 8, pc] * speed


@njit(inline="always")
def damper_energy(y, k, parts, row, rows, pc, w):  # type: ignore[no-untyped-def]
    """``σ · (σ / J − ω)``: the sphere's momentum times its angular velocity
    relative to the body (twice its kinetic energy ``σ² / J`` less the ``ω · σ``
    of ``ω · H``)."""
    moment = parts[row, pc]
    s1 = y[k]
    s2 = y[k + 1]
    s3 = y[k + 2]
    return s1 * (s1 / moment - w[0]) + s2 * (s2 / moment - w[1]) + s3 * (s3 / moment - w[2])


@njit(inline="always")
def spring_energy(y, k, parts, row, rows, pc, w):  # type: ignore[no-untyped-def]
    """``ẋ p + k x²``: the sliding mass's momentum times its speed, and twice the
    spring's energy."""
    _, _, _, _, _, _, mu, _, _, _, g4, g5, g6 = _spring_geometry(y, k, parts, row, pc)
    p = y[k + 1]
    speed = (p - (g4 * w[0] + g5 * w[1] + g6 * w[2])) / mu
    return speed * p + parts[row + 7, pc] * y[k] * y[k]


#: The Kane damper's equations, for :mod:`tumble.core.parts`.
DAMPER_EQUATIONS = PartEquations(momentum=damper_momentum, rates=damper_rates, energy=damper_energy)
#: The spring–mass damper's equations, for :mod:`tumble.core.parts`.
SPRING_EQUATIONS = PartEquations(
    momentum=spring_momentum, rates=spring_rates, inertia=spring_inertia, energy=spring_energy
)
