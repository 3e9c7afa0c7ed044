"""The closed form of a torque-free gyrostat with its rotor momentum on a
principal axis (tumble.core.gyrostat) against an independent integration of
Ḣ = H × ω, and its period against the motion itself.

Also run with NUMBA_DISABLE_JIT=1 (small sample counts).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from reference import taylor_gyrostat
from tumble.core.gyrostat import gyrostat_constants, gyrostat_momentum, gyrostat_period


def reference(moments, h, h0, times):
    """Ḣ = H × ω with ω = (H1/I1, H2/I2, (H3 − h)/I3), DOP853 at rtol 1e-13."""
    moments = np.asarray(moments, dtype=float)

    def rate(t, m):
        return np.cross(m, (m - [0.0, 0.0, h]) / moments)

    solution = solve_ivp(rate, (0.0, times[-1]), h0, t_eval=times, method="DOP853",
                         rtol=1e-13, atol=1e-14)  # fmt: skip
    return solution.y.T


def cases():
    """Platform moments (rotor on axis 3, in any order), h and ω0: random ones
    with h from zero to three times |I ω|, and the moment about the rotor equal
    to another (a root at infinity), some starting with H1 or H2 zero."""
    rng = np.random.default_rng(7)
    out = []
    for n in range(60):
        moments = rng.uniform(1.0, 5.0, 3)
        if n % 10 == 0:
            moments[2] = moments[0]
        elif n % 10 == 1:
            moments[2] = moments[1]
        omega = rng.normal(size=3)
        if n % 7 == 0:
            omega[0] = 0.0
        elif n % 7 == 1:
            omega[1] = 0.0
        h = rng.normal() * (0.3, 1.0, 3.0)[n % 3] * float(np.linalg.norm(moments * omega))
        out.append((moments, h, omega))
    return out


@pytest.mark.slow  # reference integrations of every normal form: 9 s
def test_the_closed_form_follows_an_independent_integration_in_every_normal_form() -> None:
    # 60 bodies over 20 s: the closed form against DOP853 (good to ~1e-12 of
    # |H|): 1e-11 of |H|. Every normal form of the module docstring is met: four
    # real roots with sn, cn, dn placed in each way, and the complex pair.
    forms = set()
    times = np.linspace(0.0, 20.0, 81)
    for moments, h, omega in cases():
        h0 = moments * omega + [0.0, 0.0, h]
        constants = gyrostat_constants(moments, h, *omega)
        assert constants is not None
        forms.add((constants[0], tuple(constants[12:18])))
        error = np.max(
            np.abs(gyrostat_momentum(constants, times) - reference(moments, h, h0, times))
        )
        assert error < 1e-11 * np.linalg.norm(h0), (moments, h, omega)
    assert len(forms) >= 6


@pytest.mark.parametrize("index", [2, 5, 13, 22])
def test_z_returns_after_one_period(index) -> None:
    # gyrostat_period is 2K/|λ| (s = sn²) or 4K/|λ| (s = cn): integrating for
    # exactly that time returns z = H3 and the squares H1², H2² to their start
    # (DOP853, 1e-11 of |H|), and half of it does not (z is then at its other
    # turning point: the period is not a multiple of the true one).
    moments, h, omega = cases()[index]
    h0 = moments * omega + [0.0, 0.0, h]
    constants = gyrostat_constants(moments, h, *omega)
    period = gyrostat_period(constants)
    end = reference(moments, h, h0, np.array([0.0, 0.5 * period, period]))
    size = np.linalg.norm(h0)
    assert abs(end[2, 2] - h0[2]) < 1e-11 * size
    assert np.max(np.abs(end[2, :2] ** 2 - h0[:2] ** 2)) < 1e-11 * size**2
    assert abs(end[1, 2] - h0[2]) > 1e-6 * size


def test_a_steady_rotation_has_no_elliptic_motion() -> None:
    # ω along the rotor axis: H parallel to ω, nothing moves in the body.
    assert gyrostat_constants(np.array([2.0, 3.0, 4.0]), 1.0, 0.0, 0.0, 0.5) is None


# Platform moments (the rotors on axis 3), h and ω0, 1e-6 rad/s from an
# unstable steady spin (ω ∥ H), each reaching a form where the closed form
# once lost digits:
NEXT_TO_STEADY_SPINS = [
    # About axis 2, (I3 − I2) ω3 + h = 0 (b1 = 0): off it in ω1, a complex pair
    # 3e-6 from the real axis, 1 − m = 1.5e-12 (the amplitude over 1 − m).
    ((2.0, 3.0, 3.8), 0.1, (1e-6, 1.0, -0.125)),
    # The same spin, off it in ω3: four real roots, two 7.6e-6 apart, which put
    # the pole of the Möbius map next to s = 1 (the map near z = q).
    ((2.0, 3.0, 3.8), 0.1, (0.0, 1.0, -0.125 + 1e-6)),
    # About the rotor axis (h = 0.5 in (I1 − I3, I2 − I3) ω3: unstable): four
    # real roots, the state 5e-13 (in 1 − s) from a turning point of z, where
    # the initial phase is steepest (the angle am u0 would lose it).
    ((1.0, 3.0, 1.9), 0.5, (1e-6, -1e-6, 1.0)),
]


@pytest.mark.parametrize(("moments", "h", "omega"), NEXT_TO_STEADY_SPINS)
def test_the_closed_form_keeps_its_digits_next_to_an_unstable_steady_spin(moments, h, omega):
    # Against a Taylor-series integration at 30 digits over 30 s, from the same
    # doubles: the constants carry no cancellation, so what is left is their
    # round-off times the phase's sensitivity, ~1e-16 of the ~20 rad of u:
    # 1e-13 of |H| (measured ≤ 1.3e-15; with the differences formed by
    # subtraction these cases erred 2e-6, 1.4e-12 and 4e-5 of |H|).
    moments = np.array(moments)
    times = np.linspace(0.0, 30.0, 16)
    constants = gyrostat_constants(moments, h, *omega)
    omega_reference = taylor_gyrostat(moments, (0, 0, 1), h, omega, times)
    expected = moments * omega_reference + [0.0, 0.0, h]
    size = np.linalg.norm(expected[0])
    assert np.max(np.abs(expected - expected[0])) > 1e3 * 1e-6 * size  # it moved away
    assert np.max(np.abs(gyrostat_momentum(constants, times) - expected)) < 1e-13 * size
