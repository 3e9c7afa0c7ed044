"""Closed forms for bodies with rotors and dampers, in orbit and under control:
sympy linearisations, simulations of the full equations, and every error."""

from __future__ import annotations

import cmath
import math

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import taylor_gyrostat
from tumble import checks, theory

DIAGONAL = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))


def body(*moments: float) -> tb.MassProperties:
    return tb.MassProperties(10.0, [0, 0, 0], np.diag(moments))


def growth_rate(t: np.ndarray, values: np.ndarray) -> float:
    """The slope of log |values| (least squares): an exponential rate, 1/s."""
    return float(np.polyfit(t, np.log(np.abs(values)), 1)[0])


# ------------------------------------------------------------------ dual spin
@pytest.mark.parametrize("k", [0, 1, 2])
def test_the_gyrostat_condition_is_the_linearised_euler_equations(k: int) -> None:
    # H = I ω + h e_k, H' + ω × H = 0 linearised about ω = Ω e_k: the transverse
    # 2 × 2 system has characteristic polynomial s² + P / (I_i I_j).
    inertia = sp.symbols("I1:4", positive=True)
    spin, h, s = sp.symbols("Omega h s", real=True)
    d = sp.symbols("d1:4")
    e = sp.Matrix([1 if m == k else 0 for m in range(3)])
    w = spin * e + sp.Matrix(d)
    momentum = sp.diag(*inertia) * w + h * e
    rates = sp.diag(*inertia).inv() * (-w.cross(momentum))
    i, j = (k + 1) % 3, (k + 2) % 3
    jacobian = sp.Matrix(
        [[sp.diff(rates[r], d[c]).subs(dict.fromkeys(d, 0)) for c in (i, j)] for r in (i, j)]
    )
    product = ((inertia[i] - inertia[k]) * spin - h) * ((inertia[j] - inertia[k]) * spin - h)
    expected = s**2 + product / (inertia[i] * inertia[j])
    assert sp.simplify((s * sp.eye(2) - jacobian).det() - expected) == 0
    if k == 1:
        issue_form = (h - (inertia[2] - inertia[1]) * spin) * (h + (inertia[1] - inertia[0]) * spin)
        assert sp.expand(product - issue_form) == 0


def test_the_nutation_of_a_dual_spin_body_has_the_closed_form_frequency() -> None:
    # Spin 1 rad/s about the intermediate axis (4 < 6 < 8) with a free rotor of
    # h = J Ω_rel = 4 kg·m²/s along it: stable. ω1 wobbles at the frequency of
    # the theory; amplitude 1e-3 keeps nonlinear corrections ~1e-6.
    result = theory.gyrostat_stability(DIAGONAL, 1.0, 4.0, axis=(0, 1, 0))
    assert result.stable and result.unstable_between == (-2.0, 2.0)
    rotor = tb.Rotor([0, 1, 0], 0.5, speed=8.0)
    run = tb.simulate(
        DIAGONAL, [1e-3, 1.0, 0.0], duration=200.0, dt=0.01, method="splitting", internal=[rotor]
    )
    signal = run.omega[:, 0]
    up = np.flatnonzero((signal[:-1] <= 0) & (signal[1:] > 0))
    # Crossing times by linear interpolation between samples.
    times = run.t[up] - signal[up] * (run.t[up + 1] - run.t[up]) / (signal[up + 1] - signal[up])
    measured = 2 * math.pi / np.mean(np.diff(times))
    assert measured == pytest.approx(result.nutation_frequency, rel=1e-5)
    # The same through tumble.checks.compare, which routes a GyrostatStability
    # to the dual-spin check (its own crossing fit: the same 1e-5).
    (row,) = checks.compare(run, result, axis=(0, 1, 0))
    assert row["measured"] == pytest.approx(result.nutation_frequency, rel=1e-5)


@pytest.mark.parametrize(("h", "moments"), [(0.0, (4.0, 6.0, 8.0)), (1.0, (4.0, 6.0, 8.0))])
def test_an_unstable_gyrostat_grows_at_the_closed_form_rate(h: float, moments) -> None:
    # Inside (−2, 2) kg·m²/s the intermediate-axis spin is unstable: a deviation
    # of 1e-9 grows as exp(γ t) until it reaches ~1e-3, where the fit stops.
    mp = body(*moments)
    result = theory.gyrostat_stability(mp, 1.0, h, axis=(0, 1, 0))
    assert not result.stable and math.isnan(result.nutation_frequency)
    parts = [tb.Rotor([0, 1, 0], 0.5, speed=2 * h)] if h else None
    run = tb.simulate(mp, [1e-9, 1.0, 0.0], duration=40.0, dt=0.01, method="rk4", internal=parts)
    size = np.hypot(run.omega[:, 0], run.omega[:, 2])
    window = (run.t > 5.0) & (size < 1e-3)
    assert growth_rate(run.t[window], size[window]) == pytest.approx(result.growth_rate, rel=1e-3)


@pytest.mark.parametrize(
    ("locked", "axis", "inertia", "speed", "steady", "offset"),
    [
        # The dual-spin body: ω = (0, 1, 0) rad/s about the intermediate axis with
        # a rotor along it of h = J Ω_rel = 0.4 kg·m²/s, inside the unstable
        # range (−1, 1) (gyrostat_stability: growth 0.53/s, a deviation of 1e-6
        # reaches O(1) in 26 s). Off it in ω1 and ω3: four real roots, the state
        # 5e-13 (in 1 − s, s = sn²) from a turning point, where the phase is
        # steepest.
        ((1.0, 2.0, 3.0), (0, 1, 0), 0.1, 4.0, (0.0, 1.0, 0.0), (1e-6, 0.0, 1e-6)),
        # A rotor across the spin: on z, h = 0.1 kg·m²/s; ω = (0, 1, −0.125) rad/s
        # is a steady spin (H = (0, 3, −0.375) = 3 ω), unstable (the deviation
        # grows 8000-fold in 30 s): off it in ω1, a complex pair of roots, the
        # motion 1.5e-12 (in 1 − m) from the separatrix.
        ((2.0, 3.0, 4.0), (0, 0, 1), 0.2, 0.625, (0.0, 1.0, -0.125), (1e-6, 0.0, 0.0)),
    ],
)
def test_the_exact_gyrostat_keeps_its_digits_next_to_an_unstable_steady_spin(
    locked, axis, inertia, speed, steady, offset
) -> None:
    # 1e-6 rad/s from an unstable steady spin, over 30 s, against a Taylor-series
    # integration at 30 digits of the same doubles. How well the motion is
    # determined: a change of the inputs by round-off (1e-16 relative; the
    # library rounds the platform's moment 4 − 0.2) moves the state by 1e-16 of
    # |ω| against its 1e-6 distance from the steady spin, 1e-10 of it, which
    # shifts the growing deviation by 1e-10 of its size (≤ ~1 rad/s): a closed
    # form that keeps its digits errs by ~1e-10 rad/s at most (measured 2e-15
    # and 3e-13). With the roots' differences formed by subtraction it erred
    # 3.4e-5 and 2.1e-6 rad/s. (tests/core/test_gyrostat.py holds the closed
    # form itself to 1e-13.)
    mp = body(*locked)
    rotor = tb.Rotor(axis, inertia, speed=speed)
    spin = np.asarray(steady)
    momentum = np.multiply(locked, spin) + inertia * speed * np.asarray(axis, dtype=float)
    assert np.allclose(np.cross(spin, momentum), 0.0, atol=1e-15)  # ω ∥ H: a steady spin
    if np.allclose(np.cross(spin, axis), 0.0):  # the rotor along the spin: the dual spin
        stability = theory.gyrostat_stability(mp, 1.0, inertia * speed, axis=axis)
        assert not stability.stable and stability.growth_rate == pytest.approx(0.5292, abs=1e-4)
    omega0 = spin + offset
    run = tb.simulate(mp, omega0, duration=30.0, dt=1.0, internal=[rotor])
    assert run.method == "exact"
    # The oracle's platform and h formed from the given doubles at 30 digits.
    with mpmath.workdps(30):
        j = mpmath.mpf(inertia)
        platform = [mpmath.mpf(locked[k]) - j * axis[k] ** 2 for k in range(3)]
        along = mpmath.fsum(mpmath.mpf(a) * w for a, w in zip(axis, omega0, strict=True))
        h = j * (along + mpmath.mpf(speed))
        reference = taylor_gyrostat(platform, axis, h, omega0, run.t)
    assert np.max(np.abs(reference[-1] - spin)) > 1e3 * np.max(offset)  # it grew
    assert np.max(np.abs(run.omega - reference)) < 1e-9


# ------------------------------------------------------------------ Kane damper
def axisymmetric_nutation(it: float, i3: float, j: float, d: float, spin: float) -> complex:
    """The nutation exponent of an axisymmetric body (transverse I_t) with a Kane
    damper, from the complex quadratic f(s) = a s² + b s + c into which the
    transverse motion factors (X = x1 + i x2, Z = z1 + i z2): a closed form
    derived separately from the 4 × 4 system of the library."""
    k = i3 - it
    a = (it - j) * j
    b = d * it + 1j * j * spin * (2 * it - i3 - j)
    c = j * spin**2 * k - 1j * d * spin * k
    root = cmath.sqrt(b * b - 4 * a * c)
    candidates = [(-b + root) / (2 * a), (-b - root) / (2 * a)]
    return max(candidates, key=lambda z: z.real)  # the slower mode


@pytest.mark.parametrize(
    ("moments", "d"),
    [((100.0, 100.0, 120.0), 2.0), ((100.0, 100.0, 120.0), 40.0), ((100.0, 100.0, 80.0), 2.0)],
)
def test_the_kane_damper_exponents_match_the_axisymmetric_closed_form(moments, d: float) -> None:
    result = theory.kane_damper_decay(body(*moments), 5.0, d, 2.0)
    exact = axisymmetric_nutation(moments[0], moments[2], 5.0, d, 2.0)
    assert result.decay_rate == pytest.approx(-exact.real, rel=1e-10)
    assert result.nutation_frequency == pytest.approx(abs(exact.imag), rel=1e-10)
    assert result.grows == (moments[2] < moments[0])


def test_the_small_damping_limit_is_the_energy_sink_rate() -> None:
    # D (I3 − I_t) / ((I_t − J)(I3 − J)) for D ≪ J Ω: within 1e-4 at D = 0.1.
    result = theory.kane_damper_decay(body(100.0, 100.0, 120.0), 5.0, 0.1, 2.0)
    assert result.decay_rate == pytest.approx(0.1 * 20.0 / (95.0 * 115.0), rel=1e-4)


@pytest.mark.parametrize(("moments", "d"), [((100.0, 100.0, 120.0), 2.0), ((90.0, 110.0, 130.0), 2.0),
                                            ((110.0, 130.0, 90.0), 2.0)])  # fmt: skip
def test_a_simulated_damper_damps_or_grows_the_nutation_at_the_closed_form_rate(moments, d) -> None:
    # The full nonlinear equations (tumble's kernels) from a spin of 2 rad/s
    # about axis 3 with a deviation of 1e-4: once the damper's own mode has died
    # (~1 s), ω1 = Re(v e^{s t}) of the nutation mode, so its successive maxima
    # grow or shrink by exactly e^{−σ T} per period T. Fitted over ~400 s, to
    # 1e-3 (the maxima sampled every 20 ms are off by ~(ν dt)² / 2 ~ 5e-5 each;
    # nonlinear terms ~1e-8).
    j = 5.0
    sphere = tb.MassProperties(1.0, [0, 0, 0], j * np.eye(3))
    hub = body(*(m - j for m in moments))
    result = theory.kane_damper_decay(hub + sphere, j, d, 2.0)
    run = tb.simulate(
        hub + sphere, [1e-4, 0.0, 2.0], duration=420.0, dt=0.02, method="rk4",
        internal=[tb.KaneDamper(j, d)],
    )  # fmt: skip
    w1 = run.omega[:, 0]
    peaks = np.flatnonzero((w1[1:-1] > w1[:-2]) & (w1[1:-1] >= w1[2:])) + 1
    peaks = peaks[run.t[peaks] > 20.0]
    measured = -growth_rate(run.t[peaks], w1[peaks])
    assert measured == pytest.approx(result.decay_rate, rel=1e-3)
    period = np.mean(np.diff(run.t[peaks]))
    assert 2 * math.pi / period == pytest.approx(result.nutation_frequency, rel=1e-3)
    # tumble.checks.compare routes a KaneDamperDecay to the energy-sink check,
    # which fits the tilt of the spin axis from L over its linear stage (the
    # damper's own mode included: 1e-2).
    (row,) = checks.compare(run, result, axis=(0, 0, 1))
    assert row["relative_error"] < 1e-2


def test_the_sphere_lags_a_torqued_body_at_the_closed_form_spin_down_rate() -> None:
    # A constant torque τ about the spin axis: the sphere's axial rate relative to
    # the body, z = ω_s − ω, obeys (I_k − J) ω̇ = τ + D z, J (ω̇ + ż) = −D z, so
    # z(t) = −τ / ((I_k − J) λ) (1 − e^{−λ t}) with λ the spin-down rate (the
    # transverse motion stays zero). RK4 at λ dt ≈ 0.02: 1e-10 relative.
    j, d, tau = 2.0, 3.0, 0.5
    hub = body(8.0, 10.0, 13.0)
    mp = hub + tb.MassProperties(1.0, [0, 0, 0], j * np.eye(3))
    rate = theory.kane_damper_decay(mp, j, d, 1.0).spin_down_rate
    run = tb.simulate(
        mp, [0.0, 0.0, 1.0], duration=5.0, dt=0.01, method="rk4",
        torque=tb.torques.ConstantBodyTorque([0.0, 0.0, tau]), internal=[tb.KaneDamper(j, d)],
    )  # fmt: skip
    lag = run.internal_values[:, 2] - run.omega[:, 2]
    expected = -tau / ((15.0 - j) * rate) * (1.0 - np.exp(-rate * run.t))
    np.testing.assert_allclose(lag[1:], expected[1:], rtol=1e-9)


# ------------------------------------------------------------------ wheel spin-up
def test_the_spin_up_closed_form_solves_the_gyrostat_equations() -> None:
    # (I − J) ω̇ + ḣ = 0 (H stays, about the axis) and ḣ = u, with h = J (ω + Ω).
    i, j, u, t = sp.symbols("I J u t", positive=True)
    w, speed = sp.symbols("omega Omega", cls=sp.Function)
    h = j * (w(t) + speed(t))
    solution = sp.solve(
        [sp.Eq((i - j) * w(t).diff(t) + h.diff(t), 0), sp.Eq(h.diff(t), u)],
        [w(t).diff(t), speed(t).diff(t)],
    )
    assert sp.simplify(solution[w(t).diff(t)] + u / (i - j)) == 0
    assert sp.simplify(solution[speed(t).diff(t)] - (u / j + u / (i - j))) == 0


def test_the_spin_up_follows_a_simulation() -> None:
    mp = body(10.0, 12.0, 15.5)
    spin_up = theory.wheel_spin_up(mp, 0.5, 0.1, axis=(0, 0, 1), rotor_speed0=20.0)
    run = tb.simulate(
        mp, [0, 0, 0], duration=10.0, dt=0.01, method="rk4",
        internal=[tb.Rotor([0, 0, 1], 0.5, speed=20.0, torque=0.1)],
    )  # fmt: skip
    rate, speed, angle, energy = spin_up.at(run.t)
    # ω, Ω linear in t: RK4 exact to round-off; the angle to RK4's (ω dt)⁵: 1e-12.
    np.testing.assert_allclose(run.omega[:, 2], rate, rtol=0, atol=1e-13)
    np.testing.assert_allclose(run.rotor_speed[:, 0], speed, rtol=1e-13)
    np.testing.assert_allclose(run.energy, energy, rtol=1e-12)
    turned = Rotation.from_rotvec(np.outer(angle, [0, 0, 1]))
    assert np.max((run.rotation * turned.inv()).magnitude()) < 1e-12
    assert spin_up.body_acceleration == pytest.approx(-0.1 / 15.0)


# ------------------------------------------------------------------ orbits
def fitted_frequencies(t: np.ndarray, signals: list[np.ndarray], count: int) -> np.ndarray:
    """``count`` angular frequencies shared by sums of sinusoids: the highest
    well-separated peaks of their spectra, refined by one least-squares fit of
    every signal (no theory used)."""
    padded = 16 * len(t)
    spectrum = sum(
        np.abs(np.fft.rfft((y - y.mean()) * np.hanning(len(y)), padded)) for y in signals
    )
    freqs = 2 * np.pi * np.fft.rfftfreq(padded, t[1] - t[0])
    peaks = [k for k in range(1, len(spectrum) - 1)
             if spectrum[k] > spectrum[k - 1] and spectrum[k] > spectrum[k + 1]]  # fmt: skip
    chosen: list[int] = []
    resolution = 2 * np.pi / (t[-1] - t[0])
    for k in sorted(peaks, key=lambda k: -spectrum[k]):
        if all(abs(freqs[k] - freqs[c]) > 8 * resolution for c in chosen):
            chosen.append(k)
        if len(chosen) == count:
            break

    def residual(p: np.ndarray) -> np.ndarray:
        omegas = p[:count]
        out = []
        for m, y in enumerate(signals):
            coefficients = p[count + 2 * count * m : count + 2 * count * (m + 1)]
            fit = sum(
                coefficients[2 * r] * np.cos(omegas[r] * t)
                + coefficients[2 * r + 1] * np.sin(omegas[r] * t)
                for r in range(count)
            )
            out.append((fit - (y - y.mean())) / np.max(np.abs(y)))
        return np.concatenate(out)

    start = np.concatenate([freqs[chosen], np.zeros(2 * count * len(signals))])
    # The amplitudes enter linearly: a first least-squares solve gives them.
    for m, y in enumerate(signals):
        basis = np.column_stack([f(w * t) for w in start[:count] for f in (np.cos, np.sin)])
        start[count + 2 * count * m : count + 2 * count * (m + 1)] = np.linalg.lstsq(
            basis, y - y.mean(), rcond=None
        )[0]
    fit = least_squares(residual, start, x_scale="jac")
    return np.sort(np.abs(fit.x[:count]))


@pytest.mark.parametrize(("moments", "region"), [((5.0, 50.0, 52.0), "Lagrange"),
                                                 ((32.0988, 52.4691, 30.0), "DeBra-Delp")])  # fmt: skip
def test_roll_and_yaw_librate_at_the_closed_form_frequencies(moments, region: str) -> None:
    # Body x radial, z along the orbit normal, at rest in the orbiting frame
    # (ω = n about z), then turned by 1e-4 rad about x (yaw) and y (roll): the
    # yaw and roll angles of the body from the orbiting frame mix the two
    # roll–yaw modes; their fitted frequencies agree within 1e-4 (over 40
    # orbits; nonlinear terms ~1e-8).
    n = 1e-3
    mp = body(*moments)
    libration = theory.gravity_gradient_libration(mp, n)
    assert libration.region == region and libration.stable
    start = Rotation.from_rotvec([1e-4, -0.7e-4, 0.0])
    omega0 = start.inv().apply([0.0, 0.0, n])
    run = tb.simulate(
        mp, omega0, attitude0=start, duration=40 * 2 * math.pi / n, dt=20.0, method="rk4",
        torque=tb.torques.GravityGradient(n),
    )  # fmt: skip
    orbiting = Rotation.from_rotvec(np.outer(n * run.t, [0.0, 0.0, 1.0]))
    angles = (orbiting.inv() * run.rotation).as_rotvec()
    measured = fitted_frequencies(run.t, [angles[:, 0], angles[:, 1]], 2)
    np.testing.assert_allclose(measured, libration.roll_yaw_frequencies, rtol=1e-4)


def test_outside_both_regions_the_libration_diverges() -> None:
    mp = body(5.0, 52.0, 50.0)  # pitch stable, roll–yaw not (k3 < 0 < k1)
    libration = theory.gravity_gradient_libration(mp, 1e-3)
    assert libration.region == "unstable" and libration.pitch_stable
    assert not libration.roll_yaw_stable and np.all(np.isnan(libration.roll_yaw_frequencies))
    start = Rotation.from_rotvec([1e-6, 1e-6, 0.0])
    run = tb.simulate(
        mp, start.inv().apply([0, 0, 1e-3]), attitude0=start, duration=3e4, dt=10.0,
        method="rk4", torque=tb.torques.GravityGradient(1e-3),
    )  # fmt: skip
    tilt = np.arccos(np.clip(run.rotation.apply([0, 0, 1.0])[:, 2], -1, 1))
    assert tilt[-1] > 1e3 * 1.4e-6


# ------------------------------------------------------------------ control
def test_a_small_slew_follows_the_linearised_closed_form() -> None:
    # 1e-3 rad about principal axis 2: I φ̈ = −K sin(φ/2) − C φ̇ is linear to
    # 1e-7 relative at this angle; RK4 at 10 ms is exact to ~1e-12.
    mp = body(10.0, 15.0, 20.0)
    slew = theory.attitude_slew(mp, 3.0, 4.0, axis=(0, 1, 0))
    assert slew.natural_frequency == pytest.approx(math.sqrt(3.0 / 30.0))
    assert slew.damping_ratio == pytest.approx(4.0 / math.sqrt(90.0))
    control = tb.torques.AttitudeController([1, 0, 0, 0], 3.0, 4.0)
    start = Rotation.from_rotvec([0.0, 1e-3, 0.0])
    run = tb.simulate(mp, [0, 0, 0], attitude0=start, duration=60.0, dt=0.01, method="rk4",
                      torque=control)  # fmt: skip
    angle = run.rotation.as_rotvec()[:, 1]
    np.testing.assert_allclose(angle, slew.angle(run.t, 1e-3), rtol=0, atol=1e-3 * 2e-7)


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: theory.gyrostat_stability(DIAGONAL, 0.0),
            r"Expected `spin_rate` ≠ 0 rad/s, got 0.0",
        ),
        (
            lambda: theory.gyrostat_stability(DIAGONAL, 1.0, axis=(1, 1, 0)),
            r"Expected `axis` along a principal axis of the body, got \[0.7071",
        ),
        (
            lambda: theory.gyrostat_stability(DIAGONAL, 1.0, axis=(0, 0, 0)),
            r"Expected `axis` to be a non-zero vector",
        ),
        (lambda: theory.gyrostat_stability(DIAGONAL, 1.0, "2 kg"), r"`rotor_momentum`"),
        (
            lambda: theory.kane_damper_decay(DIAGONAL, 0.0, 1.0, 1.0),
            r"Expected `damper_inertia` > 0 kg·m², got 0.0",
        ),
        (
            lambda: theory.kane_damper_decay(DIAGONAL, 1.0, -1.0, 1.0),
            r"Expected `damping` > 0 N·m·s, got -1.0",
        ),
        (
            lambda: theory.kane_damper_decay(DIAGONAL, 1.0, 1.0, 0.0),
            r"Expected `spin_rate` ≠ 0 rad/s, got 0\.0\.",
        ),
        (
            lambda: theory.kane_damper_decay(DIAGONAL, 5.0, 1.0, 1.0),
            r"Expected `damper_inertia` below the body's principal moments \[4, 6, 8\]",
        ),
        (
            lambda: theory.wheel_spin_up(DIAGONAL, 9.0, 1.0),
            r"Expected `rotor_inertia` below the body's moment 8 kg·m² about the axis",
        ),
        (
            lambda: theory.gravity_gradient_libration(DIAGONAL, 0.0),
            r"Expected `orbit_rate` > 0 rad/s, got 0.0",
        ),
        (
            lambda: theory.gravity_gradient_libration(DIAGONAL, 1e-3, radial=(0, 0, 1)),
            r"Expected `radial` perpendicular to `normal`",
        ),
        (
            lambda: theory.attitude_slew(DIAGONAL, 1.0, -1.0),
            r"Expected `damping` >= 0 N·m·s, got -1.0",
        ),
    ],
)
def test_bad_values_are_refused(call, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()
