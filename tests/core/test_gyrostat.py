"""The closed form of a torque-free gyrostat with its rotor momentum on a
principal axis (tumble.core.gyrostat) against an independent integration of
Ḣ = H × ω, and its period against the motion itself.

Also run with NUMBA_DISABLE_JIT=1 (small sample counts).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

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


def test_the_closed_form_follows_an_independent_integration_in_every_normal_form() -> None:
    # 60 bodies over 20 s: the closed form against DOP853 (good to ~1e-12 of
    # |H|): 1e-11 of |H|. Every normal form of the module docstring is met: four
    # real roots with sn, cn, dn placed in each way, and the complex pair.
    forms = set()
    times = np.linspace(0.0, 20.0, 81)
    for moments, h, omega in cases():
        h0 = moments * omega + [0.0, 0.0, h]
        constants = gyrostat_constants(moments, h, *h0)
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
    constants = gyrostat_constants(moments, h, *h0)
    period = gyrostat_period(constants)
    end = reference(moments, h, h0, np.array([0.0, 0.5 * period, period]))
    size = np.linalg.norm(h0)
    assert abs(end[2, 2] - h0[2]) < 1e-11 * size
    assert np.max(np.abs(end[2, :2] ** 2 - h0[:2] ** 2)) < 1e-11 * size**2
    assert abs(end[1, 2] - h0[2]) > 1e-6 * size


def test_a_steady_rotation_has_no_elliptic_motion() -> None:
    # ω along the rotor axis: H parallel to ω, nothing moves in the body.
    assert gyrostat_constants(np.array([2.0, 3.0, 4.0]), 1.0, 0.0, 0.0, 3.0) is None
