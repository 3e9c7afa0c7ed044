"""Motions at the edges of float64's range, checked against the scale laws of the
equations they solve.

Euler's equations ``I ω̇ + ω × I ω = τ`` are unchanged when every moment (and the
torque) is multiplied by s: the motion does not depend on the mass's scale. A
torque-free ω0 multiplied by r gives ``r ω(r t)``: the same path, r times faster.
A top's motion depends on ``m g l / I`` and ``I_s / I``. So a body of 1e300 kg,
or one turning at 1e300 rad/s, must move as the body of 1 kg at 1 rad/s does,
to round-off; these motions once gave NaN, OverflowError or ZeroDivisionError
(|L|², 2T and the elliptic constants hold up to fourth powers of the moments
and rates). What float64 cannot hold is refused with an InputError.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble.errors import IntegrationError
from tumble.invariants import largest_rate

BOX = tb.shapes.box(1.0, (1.0, 2.0, 3.0))
OMEGA0 = np.array([0.3, 1.0, 0.2])  # near the intermediate axis: it flips
# Relative to the unit-scale run: the closed forms at a scale of order one are
# the unit-scale closed forms up to the rounding of the scaled inputs (exact
# powers of two, but 1e300 is not one), a few ε in ω and the attitude; measured
# 3e-15, allowed 100 ε.
ROUND_OFF = 100 * np.finfo(float).eps


def scaled(mp: tb.MassProperties, factor: float) -> tb.MassProperties:
    """``mp`` with its mass and inertia multiplied by ``factor`` (same shape)."""
    return tb.MassProperties(mp.mass * factor, mp.center_of_mass, mp.inertia * factor)


@pytest.mark.parametrize("mass_scale", [1e-300, 1e-150, 1e150, 1e300])
@pytest.mark.parametrize("rate_scale", [1e-300, 1.0, 1e150, 1e300])
def test_the_exact_free_motion_keeps_euler_s_scale_laws(mass_scale, rate_scale) -> None:
    unit = tb.simulate(BOX, OMEGA0, duration=5.0, dt=0.01, method="exact")
    run = tb.simulate(
        scaled(BOX, mass_scale), OMEGA0 * rate_scale, duration=5.0 / rate_scale,
        dt=0.01 / rate_scale, method="exact",
    )  # fmt: skip
    assert_allclose(run.omega / rate_scale, unit.omega, rtol=0, atol=ROUND_OFF)
    assert_allclose(run.quaternion, unit.quaternion, rtol=0, atol=ROUND_OFF)


# Platforms with a rotor on their principal axis 3: of unequal moments (the
# general gyrostat, Jacobi elliptic functions) and symmetric about the rotor (a
# steady precession, Hughes §7.2).
GYROSTATS = {
    "general": (np.diag([2.0, 3.0, 4.0]), [0.1, 0.5, 0.2]),
    "symmetric": (np.diag([3.0, 3.0, 4.0]), [0.4, -0.2, 0.7]),
}


# (The rotors' momenta J Ω must be within float64's range themselves: a rotor of
# 1e-300 kg·m² at 1e-100 rad/s is not.)
@pytest.mark.parametrize("platform", sorted(GYROSTATS))
@pytest.mark.parametrize(
    ("mass_scale", "rate_scale"), [(1e300, 1.0), (1e-300, 1.0), (1e-100, 1e-100), (1.0, 1e120)]
)
def test_the_exact_gyrostat_keeps_euler_s_scale_laws(platform, mass_scale, rate_scale) -> None:
    # The rotor's momentum J Ω scales as the moments times the rates.
    inertia, spin = GYROSTATS[platform]

    def run(mass: float, rate: float) -> tb.Trajectory:
        body = tb.MassProperties(10.0 * mass, [0, 0, 0], inertia * mass)
        rotor = tb.Rotor([0, 0, 1], 0.5 * mass, speed=3.0 * rate)
        return tb.simulate(
            body, np.multiply(spin, rate), duration=20.0 / rate, dt=0.05 / rate,
            method="exact", internal=[rotor],
        )  # fmt: skip

    unit, big = run(1.0, 1.0), run(mass_scale, rate_scale)
    assert_allclose(big.omega / rate_scale, unit.omega, rtol=0, atol=ROUND_OFF)
    assert_allclose(big.quaternion, unit.quaternion, rtol=0, atol=ROUND_OFF)
    assert_allclose(big.rotor_speed / rate_scale, unit.rotor_speed, rtol=1e-14)


@pytest.mark.parametrize("mass_scale", [1e-300, 1e300])
def test_the_exact_top_does_not_depend_on_the_mass_s_scale(mass_scale) -> None:
    disk = tb.shapes.solid_cylinder(0.5, 0.04, 0.02)
    options = {
        "pivot": [0.0, 0.0, -0.05], "gravity": [0.0, 0.0, -9.81], "duration": 2.0,
        "dt": 0.01, "method": "exact",
    }  # fmt: skip
    omega0 = [0.5, -0.3, 150.0]
    unit = tb.simulate(disk, omega0, **options)
    run = tb.simulate(scaled(disk, mass_scale), omega0, **options)
    # The closed form's constants are ratios m l / I: rounded once more than at
    # unit scale; the top's nutation phase after 2 s carries that to ~1e-13.
    assert_allclose(run.omega, unit.omega, rtol=0, atol=1e-12 * 150.0)
    assert_allclose(run.quaternion, unit.quaternion, rtol=0, atol=1e-12)


@pytest.mark.parametrize("mass_scale", [1e-300, 1e300, 1e307])
def test_the_gyroscope_s_closed_forms_do_not_depend_on_the_mass_s_scale(mass_scale) -> None:
    disk = tb.shapes.solid_cylinder(0.5, 0.04, 0.02)
    pivot = [0.0, 0.0, -0.05]
    unit = tb.theory.gyroscope(disk, pivot, "1500 rpm", "30 deg")
    big = tb.theory.gyroscope(scaled(disk, mass_scale), pivot, "1500 rpm", "30 deg")
    for name in ("precession_rate", "nutation_frequency", "nutation_amplitude",
                 "mean_precession_rate", "nutation_period"):  # fmt: skip
        assert getattr(big, name) == pytest.approx(getattr(unit, name), rel=1e-13), name
    assert_allclose(big.precession_rates, unit.precession_rates, rtol=1e-13)
    assert_allclose(big.small_nutation_frequencies, unit.small_nutation_frequencies, rtol=1e-13)
    assert unit.precession_rates is not None  # a fast top: steady precession exists
    assert_allclose(big.nutation_limits, unit.nutation_limits, rtol=1e-13)


@pytest.mark.parametrize("exponent", [-1000, -500, 500, 1000])
def test_the_largest_rate_scales_with_the_rates(exponent: int) -> None:
    # max |ω| is homogeneous of degree one in ω: times 2^k exactly.
    moments = BOX.principal()[0]
    expected = math.ldexp(largest_rate(moments, OMEGA0), exponent)
    assert largest_rate(moments, np.ldexp(OMEGA0, exponent)) == expected


def test_a_closed_form_past_2_53_radians_of_phase_is_refused() -> None:
    # 1 rad/s for 1e17 s: float64's spacing there is 16 s, many turns.
    with pytest.raises(IntegrationError) as caught:
        tb.simulate(BOX, OMEGA0, duration=1e17, dt=1e15, method="exact")
    assert str(caught.value) == (
        "Expected a motion of at most 2**53 rad of phase for the closed form, got about 2e+17 "
        "rad (its rates times t = 1e+17 s), where a turn is below float64's round-off: ask for "
        "a shorter duration or slower rates."
    )


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")  # the weight, on the way
def test_a_top_whose_weight_overflows_is_refused() -> None:
    # g = 1.8e308 m/s²: m g l / I overflows to inf in the closed form's constants.
    with pytest.raises(IntegrationError, match=r"^Expected the closed-form motion to stay "
                       r"finite, got NaN or inf at t = 0 s \(sample 0\)"):  # fmt: skip
        tb.simulate(
            tb.shapes.solid_cylinder(0.5, 0.04, 0.02), [0.5, -0.3, 150.0],
            pivot=[0.0, 0.0, -0.05], gravity=[1.7976931348623157e308, 0.0, -9.81],
            duration=1.0, dt=0.1, method="exact",
        )  # fmt: skip
