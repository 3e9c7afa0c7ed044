"""Measures of each body's motion taken while a batch kernel steps it.

A sweep over millions of bodies cannot keep their histories, so the measures
it reports are accumulated step by step, in arrays that stay in cache, by the same compiled
loops that advance the state (the batch kernels of :mod:`tumble.core.rk4` and
:mod:`tumble.core.splitting` built with metrics). Each body has a *nominal
axis* ``a``: a unit vector in principal-body coordinates (the axis it was spun
about).

After every step, with ``L = I ω`` the angular momentum in body coordinates,
the kernels update the rows of ``out`` (5, N):

0. the number of sign changes of ``a · L``: each one is a *flip*, the nominal
   axis crossing the plane perpendicular to L, so a body spun near its
   intermediate axis flips twice per period of ω(t) (about a principal axis
   ``a``, these are the sign changes of ``a · ω`` too);
1. the time of the first flip, s, from linear interpolation of ``a · L``
   between the two steps around it (``inf`` if there is none; should the step
   before land exactly on zero, the last non-zero value stands in for it);
2. the smallest ``a · L / |L|`` over the run, the initial state included: the
   cosine of the largest angle between the nominal axis and L (the nutation);
3. the largest ``|2 E − 2 E₀|``, with ``2 E = ω · I ω`` (J, times two; for a
   body carrying parts, ``ω · H`` plus each part's share:
   :func:`tumble.core.part_measures.measuring_kernel`);
4. the largest ``| |L| − |L₀| |`` (kg·m²/s).
"""

from __future__ import annotations

import math

from tumble.core._jit import njit

#: Rows of the ``out`` array the kernels fill.
N_METRICS = 5
FLIPS, FIRST_FLIP, MIN_COS, ENERGY_DEVIATION, MOMENTUM_DEVIATION = range(N_METRICS)


@njit(inline="always")
def observe(  # type: ignore[no-untyped-def]
    twice_energy,
    c,
    signed,
    squared,
    reference,
    flips,
    numerator,
    denominator,
    energy0,
    energy_dev,
    smallest,
    largest,
):
    """Update one body's running measures after a step from twice its energy (J;
    ``ω · L`` for a rigid body) and three numbers of its L (kg·m²/s, principal
    frame), and say whether the step was its first flip.

    The caller gives three numbers of L about the nominal axis (a measuring kernel's
    own way, see :func:`tumble.core.stepping.metrics_kernel`): ``c``, whose sign
    changes are those of ``a · L`` (the flips); ``signed``, the nutation's signed
    square ``(b·L)|b·L|`` with ``b = a / |L₀|`` (:func:`initial`), so that it is
    of order 1 whatever the units; and ``squared``, ``|L|²``. ``reference``
    is the last non-zero ``c`` (so a sample exactly on zero neither hides nor
    doubles a flip); the new one is returned. The nutation is tracked as the least
    ``signed / |L|²``, held as a fraction ``numerator / denominator`` and compared
    by cross-multiplication, and |L| by the extremes of |L|²: no division and no
    square root per step. Written without branches so the loop over a block
    vectorises.
    """
    crossing = reference * c < 0.0
    first = crossing and flips == 0.0
    flips += 1.0 if crossing else 0.0
    reference = c if c != 0.0 else reference
    # (denominator and |L|² are never negative; at |L| = 0, 0 < 0 keeps the least.)
    lower = signed * denominator < numerator * squared
    numerator = signed if lower else numerator
    denominator = squared if lower else denominator
    energy_dev = max(energy_dev, abs(twice_energy - energy0))
    smallest = min(smallest, squared)
    largest = max(largest, squared)
    return first, reference, flips, numerator, denominator, energy_dev, smallest, largest


@njit(inline="always")
def initial(l1, l2, l3, w1, w2, w3, a1, a2, a3):  # type: ignore[no-untyped-def]
    """The scaled nominal axis and the energy the measures of :func:`observe` start
    from, for a body of L₀ (kg·m²/s) and ω₀ (rad/s) about the nominal axis ``a``:
    ``(b1, b2, b3, 2 E₀)`` with ``b = a / |L₀|`` (``a`` itself when L₀ = 0)."""
    squared = l1 * l1 + l2 * l2 + l3 * l3
    scale = 1.0 / math.sqrt(squared) if squared > 0.0 else 1.0
    return a1 * scale, a2 * scale, a3 * scale, l1 * w1 + l2 * w2 + l3 * w3


@njit(inline="always")
def nutation_start(signed, squared):  # type: ignore[no-untyped-def]
    """The nutation's running fraction ``(numerator, denominator)`` of :func:`observe`
    at the initial state: ``signed / |L₀|²``, or 1/1 when L₀ = 0 (no angle)."""
    return (signed, squared) if squared > 0.0 else (1.0, 1.0)


@njit(inline="always")
def finish(  # type: ignore[no-untyped-def]
    dt,
    flips,
    crossed_at,
    before,
    after,
    numerator,
    denominator,
    energy_dev,
    squared0,
    smallest,
    largest,
):
    """The measures of ``out`` from the running ones."""
    first = math.inf
    if flips > 0.0:
        gap = before - after
        first = crossed_at - dt + (dt * before / gap if gap != 0.0 else 0.0)
    # b · L = a · L / |L₀|: the fraction times |L₀|² is (a·L)|a·L| / |L|².
    lowest = numerator / denominator * (squared0 if squared0 > 0.0 else 1.0)
    cosine = math.copysign(math.sqrt(abs(lowest)), lowest)
    size = math.sqrt(squared0)
    momentum_dev = max(abs(math.sqrt(largest) - size), abs(math.sqrt(smallest) - size))
    return flips, first, cosine, energy_dev, momentum_dev
