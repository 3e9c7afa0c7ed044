"""tumble.identify_many: every throw of one body in a recording, fitted alone and together,
on recordings of throws under air drag made by tumble's own simulation and torque models
(:func:`tumble.identification.synthetic_throws`), with known truth."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.errors import InputError
from tumble.identification import JointFit, ThrowFits, synthetic_throws
from tumble.identification.joint import OUTLIER_DEVIATION, fit_under
from tumble.identification.many import COLUMNS
from tumble.identification.validation import canonical


@pytest.fixture(scope="module")
def thirty() -> tuple[tb.identification.ThrowsRecording, ThrowFits]:
    """30 throws under linear drag at a racquet's level (c_i/I3 = 0.05, 0.12, 0.15 1/s)
    with a phone gyroscope's noise, 0.0035 rad/s, each fitted with drag and 40 % held out."""
    recording = synthetic_throws(30, seed=0)
    many = tb.identify_many(
        recording.t, recording.omega, recording.windows, torque="drag", hold_out=0.4
    )
    return recording, many


@pytest.mark.slow  # 30 throws fitted twice (whole and first part) and together: a minute
def test_thirty_throws_recover_the_body_alone_and_together(thirty) -> None:
    recording, many = thirty
    table = many.table
    fitted = table[table.fitted]
    # At least 90 % of the throws fitted (measured: 29; one throw alone does not
    # determine the ratios, standard errors 0.05, and is refused with that reason).
    assert len(fitted) >= 27
    truth = recording.moment_ratios
    z = np.abs(fitted[["r1", "r2"]].to_numpy() - truth) / fitted[["r1_error", "r2_error"]]
    # The single throws: both ratios within 2σ in at least 95 % of those fitted (measured:
    # 28 of 29).
    assert np.mean(np.all(z.to_numpy() < 2.0, axis=1)) >= 0.95
    # A throw refused alone joins the joint fit under the joint body (measured: all 30 in).
    assert table.in_joint.sum() >= 28
    assert set(many.joined) <= set(np.flatnonzero(~table.fitted.to_numpy()))
    joint = many.joint
    assert isinstance(joint, JointFit) and joint.torque == "drag"
    # The joint ratios within 2σ, known at least 4 times better than a typical throw's
    # (30 throws: about √30 = 5.5 times for throws alike).
    assert np.all(np.abs(joint.moment_ratios - truth) < 2.0 * joint.uncertainty)
    assert np.all(joint.uncertainty <= 0.25 * np.median(fitted[["r1_error", "r2_error"]], axis=0))
    # The drag coefficients within 3σ, and their units.
    assert joint.torque_units == "1/s"
    assert np.all(np.abs(joint.torque_parameters - recording.drag) < 3.0 * joint.torque_uncertainty)
    # The sensor's axes and bias, shared: the axes within a few of their errors' size
    # (the rotation's standard errors are ~1e-4 rad), the bias within 3σ.
    truth_axes = canonical(np.array([*truth, 1.0]), recording.axes, np.zeros(3))[1]
    angle = Rotation.from_matrix(joint.axes.T @ truth_axes).magnitude()
    assert angle < 1e-3
    errors = np.sqrt(np.diag(joint.covariance))
    assert np.all(np.abs(joint.bias - recording.bias) < 3.0 * errors[5:8])
    # The residuals are the noise: the model is the truth's. Their rms over ~29 × 80 × 3
    # samples spreads by 1/√(2 N) = 0.8 %, and the fitted parameters take 1.5 % of the
    # degrees of freedom: within 5 % of the noise.
    assert joint.residual_rms == pytest.approx(recording.noise, rel=0.05)


@pytest.mark.slow  # shares the fixture of 30 throws
def test_the_joint_body_forecasts_each_throws_held_out_part(thirty) -> None:
    _, many = thirty
    assert many.held_out_joint is not None
    errors = many.forecast_errors[list(many.held_out_joint.throws)]
    # The body known from the first 60 % of every throw forecasts each throw's last 40 %
    # from its own first 60 %: the noise alone is 0.0035 rad/s of rates of ~10 rad/s,
    # 3.5e-4; asked: within 1 % for every throw (a few percent is the aim).
    assert np.all(errors < 0.01)
    # A throw alone forecasts worse (its ratios and drag are known from 48 samples):
    # within a few percent for most.
    single = many.single_forecast_errors[np.isfinite(many.single_forecast_errors)]
    assert np.median(single) < 0.05
    assert np.median(single) > np.median(errors)


def test_the_joint_fit_of_exact_samples_is_the_truth() -> None:
    # Three torque-free throws with a noise of 1e-7 rad/s: the joint model, assembled
    # from the throws' blocks, must find the truth to the noise's level.
    recording = synthetic_throws(3, seed=4, drag=(0.0, 0.0, 0.0), noise=1e-7)
    many = tb.identify_many(recording.t, recording.omega, recording.windows, torque="free")
    joint = many.joint
    assert joint is not None and joint.torque == "free" and joint.outliers == ()
    # Ratios to 1e-7: the noise over rates of ~10 rad/s, with margin for the conditioning.
    np.testing.assert_allclose(joint.moment_ratios, recording.moment_ratios, atol=1e-7)
    # The truth's axes in the fit's choice of signs (each column's largest component > 0).
    _, axes, _ = canonical(np.array([*recording.moment_ratios, 1.0]), recording.axes, np.zeros(3))
    np.testing.assert_allclose(joint.axes, axes, atol=1e-7)
    np.testing.assert_allclose(joint.bias, recording.bias, atol=1e-7)
    for k, throw in enumerate(joint.throws):
        fit = joint.throw_fit(throw)
        # ω0 at the window's start: the truth's motion there.
        start = recording.windows[throw][0]
        assert fit.window[0] >= start
        np.testing.assert_allclose(
            fit.predicted(fit.t), fit.measured, atol=1e-6
        )  # residuals at the noise
        np.testing.assert_allclose(joint.omega0[k], fit.omega0)


def test_torque_free_throws_stay_torque_free() -> None:
    recording = synthetic_throws(3, seed=1, drag=(0.0, 0.0, 0.0))
    many = tb.identify_many(recording.t, recording.omega, recording.windows)
    assert all(fit.torque == "free" for fit in many.fits if not isinstance(fit, str))
    assert many.joint is not None and many.joint.torque == "free"
    assert "chosen by every throw" in many.joint.choice
    assert many.joint.torque_parameters.size == 0


def test_a_throw_of_another_body_is_an_outlier() -> None:
    # The second of four throws is turned by 20° in the sensor's axes, as if the phone
    # had been strapped on differently: the joint body misses it, and leaves it out.
    recording = synthetic_throws(4, seed=2)
    omega = recording.omega.copy()
    start, end = recording.windows[1]
    inside = (recording.t >= start - 0.05) & (recording.t <= end + 0.05)
    turn = Rotation.from_rotvec([0.0, np.radians(20.0), 0.0]).as_matrix()
    omega[inside] = omega[inside] @ turn.T
    many = tb.identify_many(recording.t, omega, recording.windows, torque="drag")
    joint = many.joint
    assert joint is not None
    assert joint.outliers == (1,)
    assert joint.throws == (0, 2, 3)
    table = many.table
    assert table.outlier.tolist() == [False, True, False, False]
    # The others agree with the joint body within the outlier rule.
    assert np.all(table.disagreement[[0, 2, 3]] < OUTLIER_DEVIATION)
    with pytest.raises(
        InputError, match=r"Expected a throw of the joint fit \(one of \[0, 2, 3\]\), got 1"
    ):
        joint.throw_fit(1)


def test_the_table_has_a_row_per_throw_and_progress_counts_them() -> None:
    recording = synthetic_throws(2, seed=3)
    calls = []
    # The second window holds the hand turning the body before the second throw, not a
    # free flight: refused by its own fit, with the reason.
    start, _ = recording.windows[1]
    windows = [recording.windows[0], (start - 0.75, start - 0.15)]
    many = tb.identify_many(
        recording.t,
        recording.omega,
        windows,
        torque="drag",
        progress=lambda done, total: calls.append((done, total)),
    )
    assert calls == [(1, 2), (2, 2)]
    table = many.table
    assert list(table.columns) == list(COLUMNS)
    assert table.throw.tolist() == [1, 2]
    assert table.fitted.tolist() == [True, False]
    assert table.reason[1].startswith("Expected ")
    assert many.joint is None
    assert many.joint_refusal == "1 of 2 throws fitted; a joint fit needs 2"
    assert "no joint fit: 1 of 2 throws fitted" in repr(many)


@pytest.mark.parametrize("hold_out", [-0.1, 0.9, "half", float("nan")])
def test_a_hold_out_outside_its_range_is_refused(hold_out) -> None:
    recording = synthetic_throws(2, seed=3)
    with pytest.raises(InputError, match=r"Expected `hold_out` a fraction in \[0, 0\.9\), got"):
        tb.identify_many(recording.t, recording.omega, recording.windows, hold_out=hold_out)


def test_overlapping_windows_are_refused_before_any_fit() -> None:
    recording = synthetic_throws(2, seed=3)
    (a, b), _ = recording.windows
    with pytest.raises(InputError, match="overlap"):
        tb.identify_many(recording.t, recording.omega, [(a, b), (b - 0.2, b + 0.5)])


def test_the_noise_level_of_throws_sampled_at_100_hz_is_the_sensors() -> None:
    # Rates of 7–12 rad/s sampled at 100 Hz: the third differences leave the noise alone
    # (measured 0.00374 against 0.0035; second differences gave 0.0046). The median of
    # 5900 × 3 differences spreads by ~1.5 %: within 10 %.
    recording = synthetic_throws(30, seed=0)
    assert tb.identification.noise_level(recording.t, recording.omega) == pytest.approx(
        recording.noise, rel=0.1
    )


def test_a_throw_under_the_joint_body_has_its_own_start_and_another_bodys_has_none() -> None:
    # The joint body of three throws; a fourth throw, fitted under it (its ω0 alone), starts
    # where the truth does, within 4 of its standard errors; the same throw turned by 20°
    # in the sensor's axes (another mounting) is missed and not fitted.
    recording = synthetic_throws(4, seed=5)
    many = tb.identify_many(recording.t, recording.omega, recording.windows[:3], torque="drag")
    assert many.joint is not None
    start, end = recording.windows[3]
    inside = (recording.t >= start) & (recording.t <= end)
    under = fit_under(many.joint, recording.t[inside], recording.omega[inside], "refused alone")
    assert under is not None and under.choice.endswith("alone: refused alone")
    # The truth's ω0 in the joint's choice of axis signs.
    signs = np.sign(np.diag(recording.axes.T @ many.joint.axes))
    errors = np.sqrt(np.diag(under.covariance)[5:8])
    assert np.all(np.abs(under.omega0 - signs * recording.omega0[3]) < 4.0 * errors)
    assert under.residual_rms == pytest.approx(recording.noise, rel=0.25)  # 240 residuals
    turn = Rotation.from_rotvec([0.0, np.radians(20.0), 0.0]).as_matrix()
    turned = recording.omega[inside] @ turn.T
    assert fit_under(many.joint, recording.t[inside], turned, "refused alone") is None


def test_throws_that_do_not_agree_on_one_body_have_no_joint_fit() -> None:
    # Two throws, the second strapped on 20° differently: neither agrees with the other.
    recording = synthetic_throws(2, seed=2)
    omega = recording.omega.copy()
    start, end = recording.windows[1]
    inside = (recording.t >= start - 0.05) & (recording.t <= end + 0.05)
    omega[inside] = omega[inside] @ Rotation.from_rotvec([0.0, np.radians(20.0), 0.0]).as_matrix().T
    many = tb.identify_many(recording.t, omega, recording.windows, torque="drag")
    assert many.joint is None
    assert many.joint_refusal.startswith(
        "Expected at least 2 throws that agree on one body, got 1 of 2 fitted"
    )
