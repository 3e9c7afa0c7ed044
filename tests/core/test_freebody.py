"""Exact torque-free ω(t) against a reference integration, conservation laws and closed forms.

Also run with NUMBA_DISABLE_JIT=1 (small sample counts).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.special import ellipk

from tumble.core.freebody import free_omega

BODIES = [(1.0, 2.0, 3.0), (0.7, 1.3, 1.9), (1.0, 1.0, 2.0), (1.0, 2.0, 2.0), (2.0, 2.1, 3.9)]
OMEGAS = [
    (0.5, 1.2, -0.3),
    (1.5, 0.3, -0.2),
    (-0.3, 1.0, -1.2),
    (0.2, -0.5, 0.1),
    (1.0, 0.0, 0.5),
    (-1.0, 0.4, 0.3),
]


def euler(moments):
    i1, i2, i3 = moments

    def rhs(_t, w):
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    return rhs


@pytest.mark.parametrize("moments", BODIES)
@pytest.mark.parametrize("omega0", OMEGAS)
def test_exact_omega_matches_a_reference_integration(moments, omega0) -> None:
    # DOP853 at rtol 1e-13 over |t| <= 20 s keeps ω to ~1e-12 away from the
    # separatrix; both sides of it, both symmetric tops and negative times are here.
    times = np.array([-7.0, 0.0, 3.3, 20.0])
    exact = free_omega(np.array(moments), np.array(omega0), times)
    for t, w in zip(times, exact, strict=True):
        ref = (
            omega0
            if t == 0
            else solve_ivp(
                euler(moments), (0, t), omega0, method="DOP853", rtol=1e-13, atol=1e-15
            ).y[:, -1]
        )
        assert_allclose(w, ref, atol=1e-11)


@pytest.mark.parametrize(
    "omega0", [(0.01, 2.0, 0.01), (1e-7, 2.0, -1e-7), (0.01, 2.0, -0.01), (0.02, 2.0, 0.0005)]
)
def test_conserves_energy_and_momentum_to_round_off_near_the_separatrix(omega0) -> None:
    # The closed form has no truncation error: E and |L| hold to a few ulp
    # at any time, even 1e-7 from the separatrix and after 1e4 s.
    moments = np.array([1.0, 2.0, 3.0])
    w0 = np.array(omega0)
    times = np.linspace(0.0, 1e4, 301)
    w = free_omega(moments, w0, times)
    energy = np.sum(moments * w**2, axis=1)
    momentum = np.sum((moments * w) ** 2, axis=1)
    assert_allclose(energy, np.sum(moments * w0**2), rtol=2e-14)
    assert_allclose(momentum, np.sum((moments * w0) ** 2), rtol=2e-14)


def test_period_is_four_k_over_lambda() -> None:
    # Landau & Lifshitz §37: T = 4 K(m) / λ; ω(t + T) = ω(t).
    moments = np.array([1.0, 2.0, 3.0])
    w0 = np.array([0.3, 2.0, 0.2])
    i1, i2, i3 = moments
    energy2 = np.sum(moments * w0**2)
    momentum2 = np.sum((moments * w0) ** 2)
    lam = math.sqrt((i3 - i2) * (momentum2 - energy2 * i1) / (i1 * i2 * i3))
    m = (i2 - i1) * (energy2 * i3 - momentum2) / ((i3 - i2) * (momentum2 - energy2 * i1))
    period = 4 * ellipk(m) / lam
    times = np.array([0.7, 0.7 + period, 0.7 + 10 * period])
    w = free_omega(moments, w0, times)
    assert_allclose(w[1], w[0], atol=1e-13)
    assert_allclose(w[2], w[0], atol=1e-12)


def test_symmetric_top_closed_form() -> None:
    # I1 = I2: ω⊥ turns at Ω = (I3 − I1)/I1 ω3 in the body frame.
    moments = np.array([1.0, 1.0, 1.6])
    times = np.linspace(0, 10, 11)
    w = free_omega(moments, np.array([0.4, 0.0, 5.0]), times)
    rate = 0.6 * 5.0
    assert_allclose(
        w,
        np.column_stack([0.4 * np.cos(rate * times), 0.4 * np.sin(rate * times), np.full(11, 5.0)]),
        atol=1e-13,
    )


@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ((1.0, 2.0, 3.0), (0.0, 2.0, 0.0)),
        ((1.0, 2.0, 3.0), (0.0, 0.0, -1.0)),
        ((2.0, 2.0, 2.0), (0.3, -0.2, 0.9)),
    ],
)
def test_axis_rotations_and_spheres_keep_omega(moments, omega0) -> None:
    # Steady rotation about a principal axis (even the unstable middle one, exactly)
    # and any rotation of a sphere are equilibria of Euler's equations.
    w = free_omega(np.array(moments), np.array(omega0), np.array([0.0, 5.0, 1e3]))
    assert np.array_equal(w, np.tile(omega0, (3, 1)))


@pytest.mark.parametrize(
    "omega0",
    [
        (0.5, 1.2, -0.3),  # rotation about the axis of I3
        (1.5, 0.3, -0.2),  # about the axis of I1 (the other side of the separatrix)
        (1e-6, 2.0, 1e-6),  # next to the separatrix: mc ≈ 1e-12, a half period of ~30 in u
    ],
)
def test_precession_angle_series_against_direct_quadrature(omega0) -> None:
    # The Chebyshev panels (built over one half period, then reused) against
    # Gauss–Legendre panels integrated from 0 to each t afresh: two evaluations
    # of the same integral that share only φ̇. Both are at round-off per panel;
    # over ~100 panels the sums differ by a few 1e-15 relative to φ.
    from tumble.core.freebody import (
        _PANEL_U,
        _phi_integral,
        elliptic_rate_and_mc,
        free_precession_angle,
    )

    moments = np.array([1.0, 2.0, 3.0])
    w0 = np.array(omega0)
    momentum = float(np.linalg.norm(moments * w0))
    rate, _ = elliptic_rate_and_mc(moments, w0)
    times = np.array([-3.7, 0.0, 0.9, 6.1, 25.0])
    phi = free_precession_angle(moments, w0, times)
    for t, value in zip(times, phi, strict=True):
        panels = max(1, math.ceil(abs(t) * rate / _PANEL_U))
        edges = np.linspace(0.0, t, panels + 1)
        direct = sum(
            _phi_integral(moments, w0, momentum, a, b) for a, b in itertools.pairwise(edges)
        )
        assert value == pytest.approx(direct, rel=1e-13, abs=1e-14)


def test_a_million_periods_later_omega_is_still_exact() -> None:
    # Oracle: the same Landau–Lifshitz solution evaluated by mpmath at 40 digits
    # (its own K, sn, cn, dn). The phase λ t and the period 4K(m) are carried in
    # double-double, so at t = 1e6 periods (u ≈ 1e7) ω keeps ~1e-16 relative
    # accuracy; a double phase would have lost ~1e-11.
    import mpmath as mp

    mp.mp.dps = 40
    inertia = [mp.mpf(1), mp.mpf(2), mp.mpf(3)]
    w = [mp.mpf(0.01), mp.mpf(2), mp.mpf(0.01)]
    p1, p2, p3 = (inertia[k] * w[k] ** 2 for k in range(3))
    upper = p1 * (inertia[2] - inertia[0]) + p2 * (inertia[2] - inertia[1])
    lower = p2 * (inertia[1] - inertia[0]) + p3 * (inertia[2] - inertia[0])
    a1 = mp.sqrt(upper / (inertia[0] * (inertia[2] - inertia[0])))
    a2 = mp.sqrt(upper / (inertia[1] * (inertia[2] - inertia[1])))
    a3 = mp.sqrt(lower / (inertia[2] * (inertia[2] - inertia[0])))
    rate = mp.sqrt((inertia[2] - inertia[1]) * lower / (inertia[0] * inertia[1] * inertia[2]))
    m = (inertia[1] - inertia[0]) * upper / ((inertia[2] - inertia[1]) * lower)
    phase = mp.ellipf(mp.atan2(w[1] / a2, w[0] / a1), m)
    t = float(1e6 * 4 * mp.ellipk(m) / rate)
    u = rate * mp.mpf(t) + phase
    expected = np.array(
        [float(a1 * mp.ellipfun("cn", u, m)), float(a2 * mp.ellipfun("sn", u, m)),
         float(a3 * mp.ellipfun("dn", u, m))]
    )  # fmt: skip
    got = free_omega(np.array([1.0, 2.0, 3.0]), np.array([0.01, 2.0, 0.01]), np.array([t]))[0]
    assert np.max(np.abs(got - expected)) < 1e-15 * np.linalg.norm(expected)


def test_the_closed_form_metrics_count_what_dense_samples_of_omega_show() -> None:
    # free_metrics reads the flips, the first flip and the largest nutation off
    # the lattice of zeros and extrema of ω's Jacobi functions. Against ω from
    # free_omega sampled densely (5e3 points): the same number of sign changes
    # of ω_j, the first one within a sample (duration / 5e3), and the least
    # I_j ω_j / |L| within what samples can miss of a minimum (½ f'' h², with
    # |f''| ≲ |ω|² ≲ 4 s⁻² and h ≤ 6 ms: 1e-4). Bodies on both sides of the separatrix (the relabelled side runs
    # λ < 0), every nominal axis and both signs of it.
    from tumble.core.freebody import free_metrics

    rng = np.random.default_rng(4)
    checked = 0
    for moments in [*BODIES[:2], (0.5, 1.7, 2.0)]:
        for omega in OMEGAS:
            for j in range(3):
                for sign in (1.0, -1.0):
                    moments_a = np.asarray(moments, dtype=float)
                    omega_a = np.asarray(omega, dtype=float)
                    duration = float(rng.uniform(5.0, 30.0))
                    axis = np.zeros(3)
                    axis[j] = sign
                    flips, first, least, _, _ = free_metrics(moments_a, omega_a, axis, duration)
                    times = np.linspace(0.0, duration, 5001)
                    w = free_omega(moments_a, omega_a, times)
                    along = sign * w[:, j]
                    changes = np.flatnonzero(along[:-1] * along[1:] < 0)
                    assert flips == len(changes)
                    if len(changes):
                        assert abs(first - times[changes[0]]) <= duration / 5e3
                    else:
                        assert math.isinf(first)
                    size = np.linalg.norm(moments_a * omega_a)
                    sampled = np.min(sign * moments_a[j] * w[:, j] / size)
                    assert least <= sampled + 1e-12
                    assert sampled - least < 1e-4
                    checked += 1
    assert checked == 3 * len(OMEGAS) * 6
