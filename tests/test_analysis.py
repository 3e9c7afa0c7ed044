"""Measurements of ``tumble.analysis`` against the closed forms of ``tumble.theory``.

Each measurement is taken on a trajectory from ``tb.simulate`` (or, for the
gyrocompass, which ``simulate`` cannot constrain, from its Lagrange equations
integrated by DOP853) and checked

* against an exact value: the released heavy top's nutation limits and period
  (``theory.gyroscope``), its mean precession rate by quadrature of
  φ̇ = (p_φ − L_s cos θ) / (I⊥' sin² θ) along the exact tilt ``tilt_at``; the free
  symmetric top's cone rates; the flip period; the gyrocompass's period at the
  measured amplitude;
* at two samplings, coarse and fine, with a tolerance derived from the
  measuring method's error at that sampling (h = 2π/n the phase step for n
  samples a period): a parabola's vertex through three samples of a sinusoid
  is off the peak by at most h³/24 rad of phase in time and A h⁴/40 in value;
  linear interpolation of a zero crossing errs at third order.

The simulations integrate to ~1e-10 (energy drift checked), far below every
tolerance here except those of the fine sampling, which allow for it.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad, solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble import analysis, checks, theory
from tumble.trajectory import Trajectory

G = 9.81


# ----------------------------------------------------------------- helpers
def subsample(trajectory: Trajectory, indices: np.ndarray) -> Trajectory:
    """The same motion recorded only at the given sample indices."""
    return Trajectory(
        t=trajectory.t[indices],
        omega=trajectory.omega[indices],
        quaternion=trajectory.quaternion[indices],
        mass_properties=trajectory.mass_properties,
        pivot=trajectory.pivot,
        torque=trajectory.torque,
        method=trajectory.method,
        reason="subsampled",
        dt=trajectory.dt,
        steps=trajectory.steps,
    )


def assert_allclose_unit(vector: np.ndarray, expected: list[float]) -> None:
    np.testing.assert_allclose(vector, expected, atol=1e-15)


def phase_step(period: float, trajectory: Trajectory) -> float:
    """h = 2π × (largest sample spacing) / period."""
    return 2 * math.pi * float(np.max(np.diff(trajectory.t))) / period


# ================================================================= heavy top
# The gyroscope of the brief: a 1 kg thin disk of radius 0.1 m, pivot 0.1 m from
# its centre on the axis, spun at ±200 rad/s, released from rest with its axis
# horizontal.
DISK = tb.shapes.thin_disk(1.0, 0.1)
PIVOT = [0.0, 0.0, -0.1]


@functools.cache
def heavy_top(spin: float) -> tuple[Trajectory, theory.Gyroscope]:
    horizontal = Rotation.from_euler("y", 90, degrees=True)  # body z along space x
    gyro = theory.gyroscope(DISK, PIVOT, spin, math.pi / 2, gravity=G)
    trajectory = tb.simulate(
        DISK,
        [0.0, 0.0, spin],
        attitude0=horizontal,
        pivot=PIVOT,
        gravity=[0.0, 0.0, -G],
        duration=12.5 * gyro.nutation_period,
        dt=gyro.nutation_period / 500,
    )
    return trajectory, gyro


def exact_mean_precession(gyro: theory.Gyroscope) -> float:
    """Mean φ̇ over a nutation period of the top released from rest (φ̇(0) = 0).

    p_φ = I⊥' sin² θ φ̇ + L_s cos θ is conserved, so φ̇ = L_s (cos θ0 − cos θ)/(I⊥' sin² θ)
    along the exact θ(t) of ``tilt_at``; quadrature to 1e-13.
    """
    spin_momentum = gyro.axial_moment * gyro.spin_rate

    def rate(t: float) -> float:
        theta = float(gyro.tilt_at(t))
        return (
            spin_momentum
            * (math.cos(gyro.tilt) - math.cos(theta))
            / (gyro.transverse_moment * math.sin(theta) ** 2)
        )

    period = gyro.nutation_period
    return quad(rate, 0.0, period, epsabs=0.0, epsrel=1e-13, limit=200)[0] / period


def exact_mean_tilt(gyro: theory.Gyroscope) -> float:
    """Time average of the exact θ(t) over a nutation period, by quadrature."""
    period = gyro.nutation_period
    average = quad(lambda t: float(gyro.tilt_at(t)), 0.0, period, epsabs=0.0, epsrel=1e-13)[0]
    return average / period


@pytest.mark.parametrize("spin", [200.0, -200.0, 40.0])
def test_mean_precession_rate_is_the_average_of_the_exact_precession(spin: float) -> None:
    # The closed form's mean (complete integrals of the third kind) against an
    # independent quadrature of φ̇ = L_s (cos θ0 − cos θ)/(I⊥' sin² θ) along
    # tilt_at; both to ~1e-13 relative.
    gyro = theory.gyroscope(DISK, PIVOT, spin, math.pi / 2, gravity=G)
    assert gyro.mean_precession_rate == pytest.approx(exact_mean_precession(gyro), rel=1e-11)


def test_the_brief_gyroscope_values() -> None:
    _, gyro = heavy_top(200.0)
    low, high = gyro.nutation_limits
    # Half-amplitude 0.7022° (exact) against the fast-top 0.7026°.
    assert math.degrees(0.5 * (high - low)) == pytest.approx(0.70224, abs=1e-5)
    assert math.degrees(gyro.nutation_amplitude) == pytest.approx(0.70259, abs=1e-5)
    # Mean precession 0.98071 rad/s exactly; m g l / (I_s ω_s) = 0.981.
    assert exact_mean_precession(gyro) == pytest.approx(0.980705, abs=1e-6)
    assert gyro.mean_precession_rate == pytest.approx(0.980705, abs=1e-6)
    assert gyro.precession_rate == pytest.approx(0.981, rel=1e-14)


@pytest.mark.parametrize("spin", [200.0, -200.0])
@pytest.mark.parametrize("every", [1, 23])
def test_heavy_top_nutation_and_precession_are_the_exact_released_top(
    spin: float, every: int
) -> None:
    fine, gyro = heavy_top(spin)
    trajectory = subsample(fine, np.arange(0, fine.t.size, every))
    h = phase_step(
        gyro.nutation_period, trajectory
    )  # 0.0126 (fine) or 0.29 (coarse: 21.7 samples a period, so the maxima fall anywhere between samples)
    periods = 11  # whole nutation periods between the first and last of 12 maxima
    nut = analysis.nutation(trajectory)
    assert nut.method == "turning points" and nut.maxima.size == periods + 1
    # Time: each of the two end maxima off by ≤ h³/24 rad of phase, over 11 periods;
    # plus 1e-8 for the integration.
    frequency = 2 * math.pi / gyro.nutation_period
    assert nut.frequency == pytest.approx(
        frequency, rel=2 * h**3 / 24 / (2 * math.pi * periods) + 1e-8
    )
    # Value: each turning point off by ≤ A h⁴/40 (θ(t) is a cn² of parameter
    # m = 6e-4, sinusoidal to that order).
    low, high = gyro.nutation_limits
    half = 0.5 * (high - low)
    assert nut.amplitude == pytest.approx(half, rel=h**4 / 40 + 1e-8)
    # The time average over whole periods by trapezoids: spectrally accurate for a
    # smooth periodic function; what is left comes from the interpolated ends,
    # far below the turning points' bound A h⁴/40.
    assert nut.mean_tilt == pytest.approx(exact_mean_tilt(gyro), abs=h**4 / 40 * half + 1e-9)
    assert np.all(np.abs(nut.maxima - high) < h**4 / 40 * half + 1e-9)
    assert np.all(np.abs(nut.minima - low) < h**4 / 40 * half + 1e-9)
    # Maxima every nutation period: at (k + 1/2) T after the release from the minimum.
    expected_times = (np.arange(periods + 1) + 0.5) * gyro.nutation_period
    assert np.abs(nut.maxima_times - expected_times).max() < h**3 / 24 / frequency + 1e-7

    # The mean precession over whole periods: φ at the two end maxima, each off by
    # ≤ 2 Ω × (its time error) (φ̇ = 2 Ω there), plus linear interpolation of φ,
    # whose curvature vanishes at the maxima.
    prec = analysis.precession(trajectory)
    assert prec.method == "whole nutation periods"
    exact = exact_mean_precession(gyro)
    assert prec.rate == pytest.approx(exact, rel=2 * h**3 / 24 / (2 * math.pi * periods) + 1e-8)
    # φ from space x: the axis starts along x.
    assert prec.angle.shape == trajectory.t.shape and prec.angle[0] == pytest.approx(0.0, abs=1e-12)
    assert_allclose_unit(prec.vertical, [0.0, 0.0, 1.0])


def test_heavy_top_measurements_do_not_depend_much_on_the_sampling() -> None:
    fine, gyro = heavy_top(200.0)
    rng = np.random.default_rng(7)
    # Uneven sampling: one sample in each block of 20, at a random place in it
    # (500 samples a period in the fine record): 1 to 39 apart, h ≤ 0.49.
    starts = np.arange(0, fine.t.size, 20)
    picks = np.minimum(starts + rng.integers(0, 20, starts.size), fine.t.size - 1)
    uneven = subsample(fine, np.unique(np.concatenate(([0], picks, [fine.t.size - 1]))))
    h = phase_step(gyro.nutation_period, uneven)
    assert h < 0.5
    reference_nut = analysis.nutation(fine)
    reference_rate = analysis.precession(fine).rate
    nut = analysis.nutation(uneven)
    # The bounds of even sampling, taken at the largest gap h.
    assert nut.frequency == pytest.approx(
        reference_nut.frequency, rel=2 * h**3 / 24 / (2 * math.pi * 11)
    )
    assert nut.amplitude == pytest.approx(reference_nut.amplitude, rel=h**4 / 40)
    assert analysis.precession(uneven).rate == pytest.approx(
        reference_rate, rel=2 * h**3 / 24 / (2 * math.pi * 11)
    )


def test_compare_a_heavy_top_with_theory() -> None:
    trajectory, gyro = heavy_top(200.0)
    rows = {row["quantity"]: row for row in checks.compare(trajectory, gyro)}
    assert set(rows) == {
        "precession rate (mean, exact)",
        "precession rate (steady at θ0)",
        "precession rate (fast top)",
        "nutation frequency (exact)",
        "nutation frequency (small, about steady)",
        "nutation frequency (fast top)",
        "nutation amplitude (exact)",
        "nutation amplitude (fast top)",
    }
    for row in rows.values():
        assert row["relative_error"] == pytest.approx(
            abs(row["measured"] - row["theory"]) / abs(row["theory"]), rel=1e-12
        )
        assert row["unit"] in ("rad/s", "rad")
    # Exact values of the released top: to the integration and measuring error.
    assert rows["precession rate (mean, exact)"]["relative_error"] < 1e-7
    assert rows["nutation frequency (exact)"]["relative_error"] < 1e-7
    assert rows["nutation amplitude (exact)"]["relative_error"] < 1e-7
    # The steady-precession and fast-top values are those of a top nutating by
    # ε = m g l I⊥' / (I_s ω_s)² = 0.0123 rad: they differ from the released top's
    # by O(ε) at most.
    epsilon = (
        gyro.mass
        * G
        * gyro.lever_arm
        * gyro.transverse_moment
        / (gyro.axial_moment * gyro.spin_rate) ** 2
    )
    for name in (
        "precession rate (steady at θ0)",
        "precession rate (fast top)",
        "nutation frequency (small, about steady)",
        "nutation frequency (fast top)",
        "nutation amplitude (fast top)",
    ):
        assert rows[name]["relative_error"] < epsilon
    table = checks.comparison_table(checks.compare(trajectory, gyro))
    assert "nutation amplitude (exact)" in table


# ================================================================= free symmetric top
TOP = tb.shapes.solid_cylinder(1.0, 0.1, 0.05)  # oblate: I_s / I⊥ = 1.85
OMEGA0 = np.array([1.0, 0.5, 5.0])


@pytest.mark.parametrize(("method", "per_turn"), [("exact", 8), ("exact", 300), ("rk4", 300)])
def test_free_symmetric_top_cones(method: str, per_turn: int) -> None:
    top = theory.free_symmetric_top(TOP, OMEGA0)
    fastest = max(abs(top.body_precession_rate), top.space_precession_rate)
    period = 2 * math.pi / fastest
    trajectory = tb.simulate(TOP, OMEGA0, duration=4 * period, dt=period / per_turn, method=method)
    rows = {row["quantity"]: row for row in checks.compare(trajectory, top)}
    # Both rates are constant, the azimuths linear in t: the least-squares slope is
    # exact whatever the sampling. The exact solution is good to ~1e-12; RK4 at 300
    # steps a turn to ~(2π/300)⁴/120 ≈ 2e-9 a turn.
    tolerance = 1e-10 if method == "exact" else 1e-8
    assert rows["body precession rate"]["relative_error"] < tolerance
    assert rows["space precession rate"]["relative_error"] < tolerance
    momentum = trajectory.angular_momentum[0]
    prec = analysis.precession(trajectory, axis=top.axis, vertical=momentum)
    assert prec.method == "least squares"
    assert prec.rate == pytest.approx(top.space_precession_rate, rel=tolerance)
    # The axis keeps its angle to L: the nutation angle.
    with pytest.raises(tb.InputError, match=r"Expected the tilt of `axis` to nutate"):
        analysis.nutation(trajectory, axis=top.axis, vertical=momentum)


# ================================================================= tennis racket
RACKET = tb.shapes.box(0.3, (0.02, 0.25, 0.6))  # intermediate axis: body y
RACKET_OMEGA0 = np.array([0.05, 6.0, 0.02])


def elliptic_rate(moments: np.ndarray, omega: np.ndarray) -> float:
    """λ of ω(t) = Jacobi functions of λ t (Landau & Lifshitz §37), side L² > 2 E I2."""
    i1, i2, i3 = moments
    momentum2 = float(np.sum((moments * omega) ** 2))
    energy2 = float(np.sum(moments * omega**2))  # 2E
    if momentum2 < energy2 * i2:
        i1, i3 = i3, i1
    return math.sqrt((i3 - i2) * (momentum2 - energy2 * i1) / (i1 * i2 * i3))


@pytest.mark.parametrize("per_period", [50, 500])
def test_tennis_racket_flips(per_period: int) -> None:
    period = theory.flip_period(RACKET, RACKET_OMEGA0)
    # A step incommensurate with the period, so that no two flips fall alike between samples.
    step = period / per_period / (1 + 1 / math.pi)
    trajectory = tb.simulate(RACKET, RACKET_OMEGA0, duration=3.3 * period, dt=step)
    result = analysis.flips(trajectory)
    assert result.count == 7  # two a period over 3.3 periods
    np.testing.assert_allclose(np.abs(result.axis), [0.0, 1.0, 0.0], atol=1e-15)
    # Near a flip ω2 ≈ A sn(λ (t − t0)), whose curvature vanishes at the zero: the
    # chord's zero is off by ≤ (1 + k²)(λ h)³/(6 λ) ≤ (λ h)³/(3 λ) for a step h; the
    # period comes from the first and last flip, 3 periods apart.
    rate = elliptic_rate(np.diag(RACKET.inertia), RACKET_OMEGA0)
    error = (rate * step) ** 3 / (3 * rate)
    assert result.period == pytest.approx(period, rel=2 * error / (3 * period) + 1e-10)
    # Flips half a period apart, each to the same bound.
    np.testing.assert_allclose(np.diff(result.times), period / 2, atol=2 * error + 1e-9)
    [row] = checks.compare(trajectory, period)
    assert row["quantity"] == "flip period" and row["unit"] == "s"
    assert row["relative_error"] == pytest.approx(abs(result.period / period - 1), abs=1e-16)


def test_polhode_lies_on_the_momentum_sphere_and_the_energy_ellipsoid() -> None:
    period = theory.flip_period(RACKET, RACKET_OMEGA0)
    trajectory = tb.simulate(RACKET, RACKET_OMEGA0, duration=period, dt=period / 100)
    result = analysis.polhode(trajectory)
    moments = np.sort(np.diag(RACKET.inertia))
    np.testing.assert_allclose(result.moments, moments, rtol=1e-15)
    momentum = result.angular_momentum_body
    # Torque-free, exact solution: |L| and E conserved to ~1e-14.
    np.testing.assert_allclose(np.linalg.norm(momentum, axis=1), result.momentum_sphere, rtol=1e-12)
    ellipsoid = np.sum((momentum / result.energy_ellipsoid) ** 2, axis=1)
    np.testing.assert_allclose(ellipsoid, 1.0, rtol=1e-12)
    energy = 0.5 * float(RACKET_OMEGA0 @ RACKET.inertia @ RACKET_OMEGA0)
    np.testing.assert_allclose(result.energy_ellipsoid, np.sqrt(2 * energy * moments), rtol=1e-14)
    # The principal frame is the body frame up to the order of the axes.
    np.testing.assert_allclose(
        np.abs(momentum[0]),
        np.abs(result.axes.T @ (RACKET.inertia @ RACKET_OMEGA0)),
        atol=1e-14 * result.momentum_sphere,
    )
    assert analysis.drift(trajectory) == trajectory.drift
    assert analysis.drift(trajectory) is not trajectory.drift


# ================================================================= gyrocompass
COMPASS_DISK = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)


def gyrocompass_trajectory(
    spin: float, platform: float, amplitude: float, per_period: int = 50
) -> tuple[Trajectory, theory.Gyrocompass]:
    """The disk in its gimbal, R = Rz(Ω t) Rx(θ) Rz(ψ), from the Lagrange equations.

    θ̈ is the equation ``tumble.symbolic`` derives from the Lagrangian, ψ̇ = ω_s − Ω cos θ
    (the conserved spin); DOP853 at rtol 1e-12. With spin and Ω of opposite signs
    the spin angular momentum settles along Ω with the axis down: θ about π.
    """
    from tumble import symbolic

    derived = symbolic.gyrocompass_equation()
    compass = theory.gyrocompass(COMPASS_DISK, spin, platform)
    q = sp.Symbol("q")
    values = {
        derived.gimbal_moment: compass.gimbal_moment,
        derived.axial_moment: compass.axial_moment,
        derived.platform_rate: platform,
        derived.spin: spin,
    }
    acceleration = sp.lambdify(q, derived.angular_acceleration.subs(values).subs(derived.theta, q))
    start = amplitude if spin * platform > 0 else math.pi - amplitude
    period = compass.period(amplitude)
    times = np.arange(0.0, 6 * period, period / per_period / (1 + 1 / math.pi))

    def rhs(_: float, y: np.ndarray) -> list[float]:
        return [y[1], float(acceleration(y[0])), spin - platform * math.cos(y[0])]

    sol = solve_ivp(
        rhs,
        (0.0, times[-1]),
        [start, 0.0, 0.0],
        t_eval=times,
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
    )
    theta, theta_dot, psi = sol.y
    psi_dot = spin - platform * np.cos(theta)
    attitude = Rotation.from_euler("ZXZ", np.column_stack([platform * times, theta, psi]))
    # Body angular velocity from [ω]× = Rᵀ Ṙ.
    omega = np.column_stack(
        [
            theta_dot * np.cos(psi) + platform * np.sin(theta) * np.sin(psi),
            -theta_dot * np.sin(psi) + platform * np.sin(theta) * np.cos(psi),
            psi_dot + platform * np.cos(theta),
        ]
    )
    trajectory = Trajectory(
        t=times,
        omega=omega,
        quaternion=attitude.as_quat(scalar_first=True),
        mass_properties=COMPASS_DISK,
        pivot=None,
        method="reference",
        reason="Lagrange equations, DOP853",
        dt=float(times[1]),
    )
    return trajectory, compass


@pytest.mark.parametrize(
    ("spin", "platform", "amplitude"),
    [(100.0, 2.0, 0.01), (100.0, 2.0, 0.5), (100.0, 2.0, 2.5), (-50.0, 1.0, 0.3)],
)
def test_gyrocompass_oscillation_frequency(spin: float, platform: float, amplitude: float) -> None:
    trajectory, compass = gyrocompass_trajectory(spin, platform, amplitude)
    rows = {row["quantity"]: row for row in checks.compare(trajectory, compass)}
    # The platform's axis may be given with either sign.
    assert checks.compare(trajectory, compass, vertical=[0.0, 0.0, -1.0]) == list(rows.values())
    # |θ| peaks twice a period, ~25 samples apart (h ≈ 0.25): its maxima are
    # smooth turning points, 11 half-periods apart, timed to h³/24 each; the
    # period at the measured amplitude θ0 changes by dT/dθ0 δθ0 with δθ0 ≤ θ0 h⁴/40.
    h = 2 * math.pi / 25
    assert (
        rows["oscillation frequency (amplitude, exact)"]["relative_error"]
        < 2 * h**3 / 24 / (2 * math.pi * 11) + h**4 / 40
    )
    # Small amplitude: the exact small-angle frequency, to the amplitude
    # correction θ0²/16 of a pendulum; β misses the Ω² term, Ω²/(2 β²) relative.
    if amplitude < 0.05:
        assert rows["oscillation frequency (small, exact)"]["relative_error"] < amplitude**2 / 8
        beta = compass.oscillation_frequency
        assert rows["oscillation frequency β"]["relative_error"] == pytest.approx(
            platform**2 / (2 * beta**2), rel=0.05
        )


# ================================================================= tables and errors
def test_comparison_table_lists_each_row() -> None:
    rows = [
        {
            "quantity": "flip period",
            "theory": 4.845376147,
            "measured": 4.84537,
            "relative_error": 1.27e-6,
            "unit": "s",
        },
        {
            "quantity": "nutation amplitude (exact)",
            "theory": 0.0122563606,
            "measured": 0.0122564,
            "relative_error": 3.2e-6,
            "unit": "rad",
        },
    ]
    lines = checks.comparison_table(rows).splitlines()
    assert lines[0].split() == ["quantity", "theory", "measured", "relative", "error", "unit"]
    assert set(lines[1]) == {"-", " "}
    assert len(lines) == 4
    for line, row in zip(lines[2:], rows, strict=True):
        assert line.startswith(row["quantity"])
        cells = line[len(row["quantity"]) :].split()
        assert float(cells[0]) == pytest.approx(row["theory"], rel=1e-9)
        assert float(cells[1]) == pytest.approx(row["measured"], rel=1e-9)
        assert float(cells[2]) == pytest.approx(row["relative_error"], rel=1e-2)
        assert cells[3] == row["unit"]
    # Columns aligned: every line as long as the header's rule, at most.
    assert len({len(line) for line in lines[:2]}) == 1


def short_top(periods: float) -> Trajectory:
    gyro = theory.gyroscope(DISK, PIVOT, 200.0, math.pi / 2)
    return tb.simulate(
        DISK,
        [0.0, 0.0, 200.0],
        attitude0=Rotation.from_euler("y", 90, degrees=True),
        pivot=PIVOT,
        gravity=[0.0, 0.0, -G],
        duration=periods * gyro.nutation_period,
        dt=gyro.nutation_period / 500,
        record_every=10,
    )


def test_a_short_record_falls_back_to_the_spectrum() -> None:
    trajectory = short_top(2.2)  # two maxima: too few for the intervals
    nut = analysis.nutation(trajectory)
    assert nut.method == "spectrum"
    gyro = theory.gyroscope(DISK, PIVOT, 200.0, math.pi / 2)
    # The refined spectral peak: within a quarter of the resolution 2π / duration.
    resolution = 2 * math.pi / trajectory.t[-1]
    assert abs(nut.frequency - 2 * math.pi / gyro.nutation_period) < 0.25 * resolution


SPHERE = tb.shapes.solid_sphere(1.0, 0.1)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: analysis.precession([1.0, 2.0]),
            r"Expected `trajectory` to be a Trajectory, got list\.",
        ),
        (
            lambda: analysis.nutation(tb.simulate(SPHERE, [0, 0, 1.0], duration=1.0, dt=1.0)),
            r"Expected `trajectory` to hold at least 3 samples, got 2\.",
        ),
        (
            lambda: analysis.precession(short_top(3.0), axis=[0, 0, 0]),
            r"Expected `axis` to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            lambda: analysis.nutation(short_top(3.0), vertical=[0, 0, 0]),
            r"Expected `vertical` to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            lambda: analysis.nutation(short_top(0.6)),
            r"Expected a trajectory covering at least one nutation period \(two turning points of the tilt\), got 1 over 0\.0471\d* s\.",
        ),
        (
            lambda: analysis.nutation(tb.simulate(SPHERE, [0, 0, 1.0], duration=2.0)),
            r"Expected the tilt of `axis` to nutate \(a swing above 1e-09 rad\), got a swing of .* rad over 2 s\.",
        ),
        (
            lambda: analysis.precession(tb.simulate(SPHERE, [0, 0, 1.0], duration=2.0)),
            r"Expected `axis` to stay off the axis of the azimuth \(\[0\.0, 0\.0, 1\.0\]\) to measure it, got an angle of 0 rad at t = 0 s\.",
        ),
        (
            lambda: analysis.flips(tb.simulate(RACKET, [0, 0, 3.0], duration=10.0)),
            r"Expected ω to change sign along the intermediate principal axis at least twice to measure the flip period, got 0 sign changes over 10 s\.",
        ),
        (
            lambda: checks.compare(short_top(3.0), "gyroscope"),
            r"Expected `result` to be one of GyrostatStability, KaneDamperDecay, Gyroscope, FreeSymmetricTop, Gyrocompass from tumble.theory, or a flip period \(float\), got str\.",
        ),
        (
            lambda: analysis.pointing_error(short_top(3.0), [0, 0, 0, 0]),
            r"Expected `target` to be a non-zero quaternion \[w, x, y, z\], got \[0\.0, 0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            lambda: analysis.orbit_deviation(short_top(3.0), 1e-3, [1, 0, 0], [0, 0, 1], [0, 0, 2]),
            r"Expected `radial0` off the orbit's normal, got \[0\.0, 0\.0, 2\.0\]\.",
        ),
        (
            lambda: analysis.exponential_rate([0.0, 1.0, 2.0], [1.0, 2.0, 4.0], (10.0, 20.0)),
            r"Expected at least 3 samples to fit an exponential rate, got 0 \(band \(10\.0, 20\.0\)\)\.",
        ),
        (
            lambda: checks.compare(short_top(3.0), theory.gravity_gradient_libration(DISK, 1e-3)),
            r"Expected `result` to be one of GyrostatStability, KaneDamperDecay, Gyroscope, FreeSymmetricTop, Gyrocompass from tumble.theory, or a flip period \(float\), got Libration\.",
        ),
        (
            lambda: checks.compare(short_top(3.0), 1.0, spam=1),
            r"Expected options `axis` or `vertical`, got spam\.",
        ),
    ],
)
def test_bad_input_is_refused(call, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()


# ------------------------------------------------------------------ the Poinsot construction
def test_omega_stays_on_the_invariable_plane_of_an_exact_run() -> None:
    # Poinsot: ω · L̂ = 2T/|L| at every instant of torque-free motion (the
    # contact point of the rolling inertia ellipsoid). Along the closed form
    # over 50 s (several flips) it holds to round-off: 1e-14 of 2T/|L|.
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    run = tb.simulate(body, [0.3, 1.0, 0.2], duration=50.0, dt=0.01)
    assert run.method == "exact"
    plane = tb.analysis.herpolhode(run)
    assert np.max(np.abs(plane.omega_space @ plane.normal - plane.height)) < 1e-14 * plane.height
    frame = np.column_stack([plane.plane_axes, plane.normal])
    np.testing.assert_allclose(frame.T @ frame, np.eye(3), atol=1e-15)
    assert np.linalg.det(frame) > 0.0


def test_the_herpolhode_of_a_symmetric_body_is_a_circle_of_the_radius_theory_gives() -> None:
    # A symmetric body (A, A, C): ω = (|L|/A) L̂ − λ e with λ = (C − A) ω3 / A and
    # e the symmetry axis precessing about L̂, so ω's part in the plane has the
    # constant length |λ| sin θ = |C − A| |ω3| |ω⊥| / |L| (sin θ = A |ω⊥| / |L|).
    # Along the closed form: 1e-13 of it.
    a, c = 2.0, 3.0
    w0 = np.array([0.3, 0.4, 1.2])
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([a, a, c]))
    plane = tb.analysis.herpolhode(tb.simulate(body, w0, duration=20.0, dt=0.01))
    momentum = np.linalg.norm([a * w0[0], a * w0[1], c * w0[2]])
    radius = abs(c - a) * abs(w0[2]) * np.hypot(w0[0], w0[1]) / momentum
    np.testing.assert_allclose(np.linalg.norm(plane.in_plane, axis=1), radius, rtol=1e-13)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"torque": tb.torques.LinearDamping(0.1)},
            r"^Expected a torque-free rigid body for the Poinsot construction \(energy and the "
            r"angular momentum vector conserved, no internal parts\), got a motion with "
            r"conserved \[\]\.$",
        ),
        (
            {"internal": [tb.Rotor([0, 0, 1], 0.1, speed=5.0)]},
            r"got a motion with internal parts\.$",
        ),
    ],
)
def test_the_poinsot_construction_refuses_motions_without_a_fixed_plane(kwargs, message) -> None:
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    run = tb.simulate(body, [0.3, 1.0, 0.2], duration=1.0, dt=0.01, **kwargs)
    with pytest.raises(tb.InputError, match=message):
        tb.analysis.herpolhode(run)


def test_the_poinsot_construction_refuses_a_body_at_rest() -> None:
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    run = tb.simulate(body, [0.0, 0.0, 0.0], duration=1.0, dt=0.1)
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a body that turns for the Poinsot construction, got L = 0\.$",
    ):
        tb.analysis.herpolhode(run)
