"""tumble.identify: a torque-free body fitted to measured rates.

Oracles: recordings made from known bodies (the exact torque-free motion, checked
here against scipy's integration of Euler's equations), so every fitted value
has a true one; the coverage of the reported standard errors over seeded trials
(a calibration); and the scale of the noise.
"""

from __future__ import annotations

import os
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.errors import InputError
from tumble.identification import free_flight, noise_level, synthetic_phone
from tumble.identification.result import principal_rates

SENSOR = Rotation.from_euler("xyz", [20.0, -35.0, 50.0], degrees=True).as_matrix()
BIAS = np.array([0.01, -0.02, 0.005])


def recording(
    moments: tuple[float, float, float],
    omega0: tuple[float, float, float],
    *,
    sigma: float = 0.0,
    bias: np.ndarray = BIAS,
    axes: np.ndarray = SENSOR,
    seed: int = 0,
    duration: float = 10.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Samples at 500 Hz ± 15 % of a body with principal axes ``axes`` (columns,
    sensor axes), as a gyroscope with ``bias`` and white noise ``sigma`` reads it."""
    generator = np.random.default_rng(seed)
    steps = 0.002 * (1.0 + 0.15 * generator.uniform(-1.0, 1.0, int(duration / 0.002)))
    t = np.cumsum(steps) - steps[0]
    w = principal_rates(np.array(moments), np.array(omega0, dtype=float), t)
    return t, w @ axes.T + bias + sigma * generator.standard_normal(w.shape)


def test_the_model_is_eulers_equations_for_moments_in_any_order() -> None:
    # Oracle: scipy's DOP853 on I ω̇ = (I ω) × ω, for each order of the moments
    # (the odd ones are solved through a reflection).
    t = np.linspace(0.0, 8.0, 200)
    for order in ((0, 1, 2), (2, 1, 0), (1, 0, 2), (0, 2, 1), (2, 0, 1), (1, 2, 0)):
        moments = np.array([0.3, 0.8, 1.0])[list(order)]
        omega0 = np.array([0.4, 2.0, 0.3])[list(order)]

        def euler(_: float, w: np.ndarray, moments: np.ndarray = moments) -> np.ndarray:
            return np.cross(moments * w, w) / moments

        reference = solve_ivp(euler, (0, 8), omega0, "DOP853", t, rtol=1e-12, atol=1e-12).y.T
        # Both to about 1e-10 (DOP853's error at these tolerances over 8 s).
        assert np.allclose(principal_rates(moments, omega0, t), reference, atol=1e-9)


@pytest.mark.parametrize(
    ("moments", "omega0", "bias"),
    [
        ((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), True),  # L² > 2EI2: about the major axis
        ((0.3, 0.8, 1.0), (2.0, 0.3, 0.4), True),  # L² < 2EI2: about the minor axis
        ((0.3, 0.8, 1.0), (0.03, 3.0, 0.03), True),  # near the separatrix (1 %)
        ((0.2, 0.9, 1.0), (0.4, 0.5, 2.0), False),  # a flat body, no bias fitted
        ((0.6, 1.0, 1.0), (1.0, 0.5, 2.0), False),  # symmetric (prolate)
        ((0.5, 0.5, 1.0), (1.0, 0.5, 2.0), False),  # symmetric (a flat disk)
    ],
)
def test_exact_samples_give_back_the_body(
    moments: tuple[float, float, float], omega0: tuple[float, float, float], bias: bool
) -> None:
    t, w = recording(moments, omega0, bias=BIAS if bias else np.zeros(3))
    fit = tb.identify(t, w, window=(t[0], t[-1]), bias=bias)
    # 1e-8: the bound; the fits reach ~1e-15 (the data are exact).
    assert np.allclose(fit.moment_ratios, np.array(moments[:2]) / moments[2], rtol=0, atol=1e-8)
    assert np.allclose(fit.bias, BIAS if bias else 0.0, atol=1e-8)
    # ω at the start in the sensor's axes, whatever sign each axis was given.
    assert np.allclose(fit.axes @ fit.omega0, SENSOR @ np.array(omega0), atol=1e-8)
    assert np.isclose(np.linalg.det(fit.axes), 1.0)
    assert np.allclose(fit.axes.T @ fit.axes, np.eye(3), atol=1e-12)
    if moments[0] != moments[1] and moments[1] != moments[2]:
        # Each principal axis, up to its sign (a symmetric body's are not determined).
        assert np.allclose(np.abs(np.diag(fit.axes.T @ SENSOR)), 1.0, atol=1e-8)
    assert fit.residual_rms < 1e-10
    assert fit.flip_period == pytest.approx(tb.theory.flip_period(moments, omega0), rel=1e-8)
    assert np.allclose(fit.predicted(t), w, atol=1e-9)


def _random_body(generator: np.random.Generator) -> tuple[tuple[float, ...], np.ndarray]:
    """Moments in the triangle r1 ≤ r2 ≤ 1 ≤ r1 + r2, kept 5 % from symmetry."""
    while True:
        r1, r2 = np.sort(generator.uniform(0.1, 1.0, 2))
        if r1 + r2 >= 1.0 and r2 - r1 > 0.05 and 1.0 - r2 > 0.05:
            return (r1, r2, 1.0), Rotation.random(random_state=generator).as_matrix()


def test_the_standard_errors_cover_the_truth() -> None:
    # Calibration: noisy recordings of random bodies, both sides of the separatrix;
    # the truth within 3 standard errors in at least 95 % of the trials (Gaussian
    # errors would give 99.5 % for both ratios at once). 20 trials, 200 under CI.
    # A recording the fit refuses as not determining the body counts as a miss: one
    # of the 200 (seed 93) starts within 0.1 % of the separatrix (L²/2T = I2), and
    # bodies from (0.45, 0.50) to the true (0.61, 0.87) match its 10 s to the noise.
    trials = 200 if os.environ.get("CI") else 20
    generator = np.random.default_rng(2024)
    inside = 0
    for seed in range(trials):
        moments, axes = _random_body(generator)
        omega0 = 3.0 * generator.normal(size=3)
        bias = 0.02 * generator.normal(size=3)
        t, w = recording(moments, omega0, sigma=0.01, bias=bias, axes=axes, seed=seed)
        try:
            fit = tb.identify(t, w, window=(t[0], t[-1]))
        except InputError as refusal:
            assert "determines the moment ratios" in str(refusal)
            continue
        misses = np.abs(fit.moment_ratios - np.array(moments[:2])) / fit.uncertainty
        inside += bool(np.all(misses < 3.0))
    assert inside >= 0.95 * trials


def test_the_phone_is_found_in_its_recording_and_fitted() -> None:
    phone = synthetic_phone(0)
    start, end = free_flight(phone.t, phone.omega)
    # The rule keeps the flight and nothing of the hand: at most the throw's last
    # few samples, which the fit then drops.
    assert phone.release - 0.02 <= start and end <= phone.catch
    assert end - start > 0.9 * (phone.catch - phone.release)
    fit = tb.identify(phone.t, phone.omega)
    assert phone.release <= fit.window[0] and fit.window[1] <= phone.catch
    assert np.all(np.abs(fit.moment_ratios - phone.moment_ratios) < 3 * fit.uncertainty)
    bias_errors = np.sqrt(np.diag(fit.covariance)[8:11])
    assert np.all(np.abs(fit.bias - phone.bias) < 3 * bias_errors)
    # The residuals are the sensor's noise (σ = 0.01 rad/s), within 10 %.
    assert fit.residual_rms == pytest.approx(phone.noise, rel=0.1)
    assert fit.flip_period == pytest.approx(
        tb.theory.flip_period([*phone.moment_ratios, 1.0], phone.omega0), rel=0.02
    )


def test_the_noise_level_is_the_sensors() -> None:
    t = np.linspace(0, 4, 4000)
    smooth = np.stack([np.sin(3 * t), np.cos(2 * t), t], axis=1)
    noisy = smooth + 0.01 * np.random.default_rng(3).standard_normal(smooth.shape)
    # The median-based estimate of 12000 samples: within 5 %.
    assert noise_level(t, noisy) == pytest.approx(0.01, rel=0.05)


def test_a_steady_spin_is_refused() -> None:
    t = np.linspace(0.0, 5.0, 1000)
    w = [0.0, 0.0, 5.0] + 0.01 * np.random.default_rng(1).standard_normal((1000, 3))
    with pytest.raises(InputError, match=r"^Expected the angular velocity to change in the"):
        tb.identify(t, w, window=(0, 5))


def test_a_symmetric_body_with_a_bias_is_refused() -> None:
    # Its ratio trades off exactly against a bias along the symmetry axis.
    t, w = recording((0.6, 1.0, 1.0), (1.0, 0.5, 2.0))
    with pytest.raises(InputError, match=r"other ratios reproduce exactly \(with a bias"):
        tb.identify(t, w, window=(t[0], t[-1]))


@pytest.mark.slow  # the fits tried before the refusal: 6 s
def test_ratios_with_large_errors_are_refused() -> None:
    # Nearly exchangeable with the bias (a symmetric body, noisy): errors of ~0.5.
    t, w = recording((0.6, 1.0, 1.0), (1.0, 0.5, 2.0), sigma=0.05)
    with pytest.raises(InputError, match=r"got standard errors .* \(above 0\.05\): the motion"):
        tb.identify(t, w, window=(t[0], t[-1]))


@pytest.mark.slow  # the fits tried before the refusal: 10 s and more
def test_a_noisy_symmetric_body_with_a_bias_is_refused() -> None:
    # The same trade-off with noise: the fit can slide along it to a wrong ratio
    # whose local error looks small; a body symmetric within its errors is refused.
    t, w = recording((0.6, 1.0, 1.0), (1.0, 0.5, 2.0), sigma=0.01)
    with pytest.raises(InputError, match=r"got a body symmetric within its errors \(I1/I3 = "):
        tb.identify(t, w, window=(t[0], t[-1]))
    fit = tb.identify(t, w - BIAS, window=(t[0], t[-1]), bias=False)
    assert np.all(np.abs(fit.moment_ratios - [0.6, 1.0]) < 3 * fit.uncertainty)


def test_a_motion_that_shows_too_little_is_refused() -> None:
    # A second of a slow wobble, noisy: the ratios are not determined.
    t, w = recording((0.3, 0.8, 1.0), (0.1, 0.1, 1.0), sigma=0.02, duration=1.0)
    with pytest.raises(
        InputError, match=r"^Expected a recording that determines the moment ratios, got "
    ):
        tb.identify(t, w, window=(t[0], t[-1]))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t, w: (t[:10], w[:10]), r"^Expected at least 30 samples, got 10\.$"),
        (lambda t, w: (t, w[:, :2]), r"^Expected t of shape \(n,\) and omega of shape \(n, 3\)"),
        (
            lambda t, w: (t, np.where(np.arange(len(t))[:, None] == 7, np.nan, w)),
            r"^Expected finite times and rates, got 1 sample that is not \(the first is "
            r"sample 7",
        ),
        (
            lambda t, w: (np.concatenate([t[:5], t[4:5], t[6:]]), w),
            r"^Expected increasing times, got t\[5\] = .* after t\[4\] = ",
        ),
    ],
)
def test_bad_samples_are_refused(change: object, message: str) -> None:
    t, w = recording((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), duration=1.0)
    t, w = change(t, w)  # type: ignore[operator]
    with pytest.raises(InputError, match=message):
        tb.identify(t, w, window=(0, 1))


@pytest.mark.parametrize(
    ("window", "message"),
    [
        ("soon", r"^Expected `window` to be \(start, end\) in s, got 'soon'\.$"),
        ((2.0, 1.0), r"^Expected `window` start < end, both finite, got \(2\.0, 1\.0\)\.$"),
        ((5.0, 6.0), r"^Expected `window` to overlap the samples \(0–1\.0\d* s\), got 5–6 s\.$"),
        ((0.0, 0.02), r"^Expected at least 30 samples in the window 0–0\.02 s, got 1"),
    ],
)
def test_bad_windows_are_refused(window: object, message: str) -> None:
    t, w = recording((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), duration=1.0)
    with pytest.raises(InputError, match=message):
        tb.identify(t, w, window=window)


@pytest.mark.slow  # the fits tried before the refusal: 10 s and more
def test_a_window_that_is_not_free_flight_is_refused() -> None:
    phone = synthetic_phone(0)
    # The hand's part breaks |dω/dt| ≤ |ω|²/√3, and the refusal says where: the window's
    # start, before the release (1.26 s), the free flight after it.
    where = (
        r"to follow a torque-free motion, got residuals of .* rad/s against noise of .* is the "
        r"window all free flight\? \(the rates break \|dω/dt\| ≤ \|ω\|²/√3, which a free body "
        r"keeps, at the window's start, \d+ samples: a throw or a catch inside the window\? "
        r"Its samples of 1\.2[67]\d*–2\.8\d* s keep it\)"
    )
    with pytest.raises(InputError, match=where):
        tb.identify(phone.t, phone.omega, window=(0.5, phone.catch), torque="free")
    # With a torque offered too, no model fits either: each is named with its residual.
    refusal = (
        r"Expected a window that one of the torque models fits, got none, against noise of .* "
        r"rad/s: free: residuals of .* rad/s; drag: .*; quadratic-drag: .*: is the window all "
        r"free flight\? \(the rates break \|dω/dt\| "
        r"≤ \|ω\|²/√3, which a free body keeps, at the window's start"
    )
    with pytest.raises(InputError, match=refusal):
        tb.identify(phone.t, phone.omega, window=(0.5, phone.catch))


def test_long_flights_are_fitted_from_their_start() -> None:
    # Eight flips: a start of ω0 off by the noise would shift the late flips by
    # whole turns; the fit must still find the body (truth within 3 errors).
    for seed in range(4):
        phone = synthetic_phone(seed, flight=10.0)
        fit = tb.identify(phone.t, phone.omega, window=(phone.release, phone.catch))
        assert np.all(np.abs(fit.moment_ratios - phone.moment_ratios) < 3 * fit.uncertainty)


def test_an_unknown_loss_is_refused() -> None:
    t, w = recording((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), duration=1.0)
    with pytest.raises(InputError, match=r"^Expected `loss` to be one of linear, soft_l1, "):
        tb.identify(t, w, loss="square")


@pytest.mark.slow  # a plain and a robust fit of the same recording: 10 s and more
def test_a_robust_loss_ignores_outliers() -> None:
    # Oracle: the truth. 1 % of the samples knocked by 2 rad/s (impacts, glitches):
    # plain least squares is pulled off; soft_l1 keeps the truth within its errors.
    t, w = recording((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), sigma=0.01, duration=4.0)
    knocked = np.random.default_rng(5).choice(len(t), len(t) // 100, replace=False)
    w[knocked] += 2.0
    robust = tb.identify(t, w, window=(t[0], t[-1]), loss="soft_l1")
    plain = tb.identify(t, w, window=(t[0], t[-1]))
    truth = np.array([0.3, 0.8])
    assert np.all(np.abs(robust.moment_ratios - truth) < 3 * robust.uncertainty)
    assert np.max(np.abs(plain.moment_ratios - truth)) > np.max(
        np.abs(robust.moment_ratios - truth)
    )


@pytest.mark.parametrize("loss", ["soft_l1", "huber", "cauchy", "arctan"])
def test_every_robust_loss_agrees_with_least_squares_on_a_clean_recording(loss: str) -> None:
    # Oracle: plain least squares on the same samples. The shipped recording has
    # no outliers, so a robust loss must land within the errors of the plain fit
    # (2 σ: the two estimates share the samples, so they differ by less than
    # independent ones would); a loss that crawls from a poor start does not.
    recorded = tb.identification.read_recording(tb.identification.example_recording_path())
    plain = tb.identify(recorded.t, recorded.omega)
    robust = tb.identify(recorded.t, recorded.omega, loss=loss)
    assert np.all(np.abs(robust.moment_ratios - plain.moment_ratios) < 2 * plain.uncertainty)


def test_a_recording_without_a_free_flight_is_refused() -> None:
    # A phone turned in the hand: slow, with accelerations far above |ω|².
    t = np.linspace(0.0, 4.0, 2000)
    w = 0.3 * np.stack([np.sin(5 * t), np.cos(7 * t), np.sin(3 * t)], axis=1)
    with pytest.raises(InputError, match=r"^Expected a free flight of at least 30 samples"):
        tb.identify(t, w)


def test_the_synthetic_phone_is_a_box_of_a_phones_size() -> None:
    # Oracle: tumble.shapes.box of the same edges, its moments in closed form.
    phone = synthetic_phone(0)
    moments = np.sort(np.linalg.eigvalsh(tb.shapes.box(1.0, [0.075, 0.160, 0.008]).inertia))
    assert np.allclose(phone.moment_ratios, moments[:2] / moments[2], rtol=1e-14)
    assert np.allclose(phone.axes.T @ phone.axes, np.eye(3), atol=1e-14)
    assert np.linalg.det(phone.axes) == pytest.approx(1.0, abs=1e-14)


# ------------------------------------------------------------------ what identify is given
def test_quantities_of_any_registry_are_converted() -> None:
    # Oracle: the fit of the same samples as plain numbers in s and rad/s; the
    # conversions are exact to rounding, so the fits agree far within their errors.
    import warnings

    import pint

    from tumble.units import ureg

    phone = synthetic_phone(0)
    plain = tb.identify(phone.t, phone.omega)
    other = pint.UnitRegistry()
    given = [
        (phone.t, ureg.Quantity(phone.omega / (2 * np.pi), "turn/s")),
        (phone.t, other.Quantity(np.degrees(phone.omega), "deg/s")),
        (other.Quantity(1e3 * phone.t, "ms"), ureg.Quantity(phone.omega, "rad/s")),
    ]
    for t, omega in given:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no unit is stripped on the way
            fit = tb.identify(t, omega)
        assert np.allclose(
            fit.moment_ratios, plain.moment_ratios, rtol=0, atol=1e-3 * plain.uncertainty.min()
        )
        assert np.all(np.abs(fit.moment_ratios - phone.moment_ratios) < 3 * fit.uncertainty)


@pytest.mark.parametrize(
    ("t", "omega", "message"),
    [
        ("[0, 1, 2] ms", None, r"^Expected `t` to be "),
        (None, "1, 2, 3 rad/s", r"^Expected `omega` to have shape \(n, 3\), got \(3,\)\.$"),
        ("1, 2, 3 kg", None, r"^Expected `t` to be a time in s, got .*\(dimensions \[mass\]\)\.$"),
        (None, "rates", r"^Expected `omega` to be "),
    ],
)
def test_times_and_rates_that_are_no_array_are_refused(
    t: object, omega: object, message: str
) -> None:
    phone = synthetic_phone(0)
    with pytest.raises(InputError, match=message):
        tb.identify(phone.t if t is None else t, phone.omega if omega is None else omega)


@pytest.mark.parametrize("flag", ["no", "yes", "False", 1, 0.0, None, [True]])
def test_bias_must_be_true_or_false(flag: object) -> None:
    phone = synthetic_phone(0)
    with pytest.raises(
        InputError, match=rf"^Expected `bias` to be True or False, got {re.escape(repr(flag))}\.$"
    ):
        tb.identify(phone.t, phone.omega, bias=flag)  # type: ignore[arg-type]


def test_bias_as_a_numpy_bool_is_taken() -> None:
    phone = synthetic_phone(0)
    fit = tb.identify(phone.t, phone.omega - phone.bias, bias=np.False_)  # type: ignore[arg-type]
    assert fit.covariance.shape == (8, 8) and np.all(fit.bias == 0.0)


def test_the_samples_refused_are_shown_as_plain_numbers() -> None:
    t, w = recording((0.3, 0.8, 1.0), (0.5, 3.0, 0.4), duration=1.0)
    w[[3, 7]] = np.nan
    with pytest.raises(InputError, match=r"got 2 samples that are not \(the first is sample 3: "
                       r"t = 0\.00\d+, omega = \[nan, nan, nan\]\)\.$"):  # fmt: skip
        tb.identify(t, w)
    w[3] = 1.0
    with pytest.raises(InputError, match=r"got 1 sample that is not \(the first is sample 7: "
                       r"t = 0\.01\d+, omega = \[nan, nan, nan\]\)\.$"):  # fmt: skip
        tb.identify(t, w)
    t[5] = t[4]
    w[7] = 1.0
    with pytest.raises(InputError, match=r"^Expected increasing times, got t\[5\] = 0\.0\d+ after "
                       r"t\[4\] = 0\.0\d+\.$"):  # fmt: skip
        tb.identify(t, w)


# ------------------------------------------------------------------ rates in the wrong unit
@pytest.mark.slow  # the fits tried before the refusals: 10 s and more
def test_rates_too_small_for_any_body_are_refused() -> None:
    # The shipped recording in rad/s divided by 180/π (np.radians applied twice,
    # or a header that says rad/s of rates in deg/s): they break |dω/dt| ≤ |ω|²/√3,
    # and a torque-free body fits them only with a fast spin hidden in a bias of
    # 7.4 rad/s, 35 times the rates' median: refused, naming the likely units.
    from tumble.identification.recordings import example_recording_path, read_recording

    recording = read_recording(example_recording_path())
    with pytest.raises(
        InputError,
        match=r"^Expected a sensor bias smaller than the rates measured, got a fit whose bias "
        r"\(7\.\d+ rad/s\) exceeds the rates' median \(0\.2\d+ rad/s\): the rates look too small "
        r"for their unit \(they break \|dω/dt\| ≤ \|ω\|²/√3, which every torque-free body keeps, "
        r"and the bias makes up the rest\): were they in deg/s read as rad/s \(57\.3 times\), or "
        r"in turn/s \(6\.28 times\)\? \(Give them in rad/s, or as quantities with their unit\.\)$",
    ):
        tb.identify(recording.t, np.radians(recording.omega))
    # Rates in turn/s read as rad/s: 2π times too small, and refused too.
    with pytest.raises(InputError, match=r"the rates look too small for their unit"):
        tb.identify(recording.t, recording.omega / (2 * np.pi))
    # Over the whole flight no body matches them; the refusal says why that may be.
    phone = synthetic_phone(0)
    with pytest.raises(
        InputError,
        match=r"is the window all free flight\? \(the rates break \|dω/dt\| ≤ \|ω\|²/√3 too, "
        r"at \d+\.\d+ \|ω\|²: a hand's torque does, and so do rates too small for their unit, "
        r"as deg/s read as rad/s\)$",
    ):
        tb.identify(phone.t, np.radians(phone.omega), window=(phone.release, phone.catch))


@pytest.mark.parametrize(
    ("sigma", "bias"),
    [(0.0, 0.5), (0.3, 0.0)],
)
def test_a_large_bias_or_heavy_noise_is_not_taken_for_a_wrong_unit(
    sigma: float, bias: float
) -> None:
    # A bias of half the rates' size, or noise of 10 % of them at 500 Hz, make the
    # measured |dω/dt| / |ω|² look far beyond the bound; the fit is right all the
    # same (oracle: the truth, within 3 standard errors) and must not be refused.
    moments, omega0 = (1.0 / 2.95, 2.0 / 2.95, 1.0), (0.5, 3.0, 0.4)
    offset = bias * np.linalg.norm(omega0) * np.array([-1.0, -1.0, -1.0]) / np.sqrt(3.0)
    t, w = recording(moments, omega0, sigma=sigma, bias=offset, duration=6.0)
    fit = tb.identify(t, w, window=(t[0], t[-1]))
    # Without noise the errors are round-off, 1e-17: the truth to 1e-8 then.
    error = np.abs(fit.moment_ratios - np.array(moments[:2]))
    assert np.all(error < np.maximum(3 * fit.uncertainty, 1e-8))


@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ((0.3, 0.8, 1.0), (0.5, 3.0, 0.4)),  # about the major axis
        ((0.3, 0.8, 1.0), (2.0, 0.3, 0.4)),  # about the minor axis
        ((0.5, 0.5, 1.0), (1.0, 0.5, 2.0)),  # a flat disk: I1 + I2 = I3, the bound's edge
        ((0.05, 0.95, 1.0), (1.0, 0.7, 0.9)),  # nearly a rod and a flat plate at once
    ],
)
def test_every_free_body_keeps_the_bound(
    moments: tuple[float, float, float], omega0: tuple[float, float, float]
) -> None:
    # Bodies that come closest to |dω/dt| = |ω|²/√3: none is refused, noisy or not.
    for sigma in (0.0, 0.02):
        t, w = recording(moments, omega0, sigma=sigma, bias=np.zeros(3))
        fit = tb.identify(t, w, window=(t[0], t[-1]), bias=False)
        assert np.all(
            np.abs(fit.moment_ratios - np.array(moments[:2])) < max(3 * fit.uncertainty.max(), 1e-8)
        )


# ------------------------------------------------------------------ recordings sampled far too fast
@pytest.mark.slow  # 2.2 million samples averaged, then fitted: 10 s and more
def test_a_recording_sampled_far_too_fast_is_averaged_with_a_note() -> None:
    # The phone at 590 kHz: 2.2 million samples, averaged in blocks of far less
    # than a degree of turn. Oracle: the truth, within 3 standard errors.
    from tumble.identification.decimation import MAX_SAMPLES

    phone = synthetic_phone(0, rate=590_000.0)
    fit = tb.identify(phone.t, phone.omega)
    assert re.fullmatch(
        r"averaged \d+ samples at a time \(\d+ samples at about 590 kHz to \d+; each average spans "
        r"0\.0\d+ rad of turn at most\)",
        fit.note,
    ), fit.note
    assert fit.t.size <= MAX_SAMPLES
    assert np.all(np.abs(fit.moment_ratios - phone.moment_ratios) < 3 * fit.uncertainty)
    # The noise of an average of k samples: σ/√k, as the residuals show.
    k = int(fit.note.split()[1])
    assert fit.residual_rms == pytest.approx(phone.noise / np.sqrt(k), rel=0.15)
    assert fit.noise == pytest.approx(phone.noise / np.sqrt(k), rel=0.1)


def test_a_recording_sampled_as_the_motion_needs_is_not_averaged() -> None:
    phone = synthetic_phone(0)
    fit = tb.identify(phone.t, phone.omega)
    assert fit.note == "" and fit.noise == pytest.approx(noise_level(phone.t, phone.omega))


def test_a_fit_beyond_the_memory_budget_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    # A slow tumble sampled at 10 Hz for 80 min: no average could keep its motion,
    # so all 48000 samples would be fitted; a budget of 1 MB cannot hold that.
    from tumble.errors import RequestTooLargeError

    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 MB")
    t = np.arange(48_000) * 0.1
    w = principal_rates(np.array([0.3, 0.8, 1.0]), np.array([0.05, 0.3, 0.04]), t) @ SENSOR.T
    with pytest.raises(RequestTooLargeError, match=r"^Expected a request that fits in the memory "
                       r"budget of .*, got a fit of 48000 samples: about .*\. Fit a shorter window"):  # fmt: skip
        tb.identify(t, w, window=(t[0], t[-1]))
