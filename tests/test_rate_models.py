"""The compiled models of measured rates that the fits use: their Jacobians against
central differences of the same models taken in Python with a longer step, and
against the exact derivative of the bias (the identity: a sample reads the bias
once); the trial steps they turn back; the starts a drag is searched from."""

from __future__ import annotations

import numpy as np
import pytest

from tumble.core import drag_model, rate_model
from tumble.errors import InputError
from tumble.identification.validation import biases_within_rates

#: Parameters: ln(I1/I3), ln(I2/I3), a small turn of the axes, ω0 (rad/s), the bias
#: (rad/s), and for the drag model c/I3 (1/s) per axis.
BODY = np.array([np.log(0.3), np.log(0.8), 0.02, -0.01, 0.03, 1.0, 6.0, 0.5])
BIAS = np.array([0.01, -0.02, 0.005])
DRAG = np.array([0.05, 0.12, 0.15])
FRAME = np.linalg.qr(np.array([[1.0, 0.2, 0.1], [0.1, 1.0, 0.3], [0.0, 0.2, 1.0]]))[0]
TIMES = np.linspace(0.0, 0.8, 81)


def central_differences(residuals, x: np.ndarray, args: tuple, step: float) -> np.ndarray:  # type: ignore[no-untyped-def]
    """(3 n, len(x)) by central differences with ``step`` (absolute)."""
    columns = []
    for j in range(x.size):
        shift = np.zeros(x.size)
        shift[j] = step
        columns.append((residuals(x + shift, *args) - residuals(x - shift, *args)) / (2 * step))
    return np.stack(columns, axis=1)


@pytest.mark.parametrize("with_bias", [True, False])
def test_the_torque_free_jacobian_matches_central_differences(with_bias: bool) -> None:
    x = np.concatenate([BODY, BIAS if with_bias else []])
    measured = np.zeros((TIMES.size, 3))
    args = (FRAME, TIMES, measured, with_bias)
    compiled = rate_model.rate_jacobian(x, *args)
    # Central differences with a step of 1e-5 have truncation ~1e-10 and round-off
    # ~1e-11 relative; the compiled forward differences (step √ε of the scale) truncate
    # at h f''/2, which the motion's growing sensitivity to ω0 makes ~1e-7 of the
    # largest derivative here (measured 1.1e-7): 1e-6 of it leaves a tenfold margin,
    # and a wrong column (a sign, a scale, a parameter skipped) is off by its own size.
    reference = central_differences(rate_model.rate_residuals, x, args, 1e-5)
    assert np.abs(compiled - reference).max() <= 1e-6 * np.abs(reference).max()
    if with_bias:
        # d(residual of sample n, axis r)/d(bias s) = δ_rs, exactly.
        expected = np.tile(np.eye(3), (TIMES.size, 1))
        assert np.abs(compiled[:, 8:11] - expected).max() <= 1e-6


@pytest.mark.parametrize("quadratic", [False, True])
def test_the_drag_jacobian_matches_central_differences(quadratic: bool) -> None:
    x = np.concatenate([BODY, BIAS, DRAG])
    # Samples the bias lies well within (the derivatives do not depend on them).
    measured = np.full((TIMES.size, 3), 5.0)
    args = (FRAME, TIMES, measured, True, quadratic)
    compiled = drag_model.drag_jacobian(x, *args)
    # The stepped model is smooth only to its integration's error (~1e-9 of |ω|, which
    # jumps where a parameter changes the count of substeps; none does at these values):
    # the central step of 1e-4 truncates at ~1e-8, the compiled forward step (1e-7 of
    # the scale) at ~1e-7. Measured: 3.5e-7 of the largest column at worst, column by
    # column on the norm; 1e-5 leaves a thirtyfold margin and checks every column's
    # sign and scale (a wrong one is off by its own size).
    reference = central_differences(drag_model.drag_residuals, x, args, 1e-4)
    column_errors = np.linalg.norm(compiled - reference, axis=0)
    assert np.all(column_errors <= 1e-5 * np.linalg.norm(reference, axis=0).max())
    # The drag columns: a faster decay lowers the rates, so the residual's change has
    # the opposite sign of the rate on that axis, on average over the throw.
    rates = drag_model.drag_rates(
        rate_model.moments_and_axes(x, FRAME)[0], DRAG, quadratic, x[5:8].copy(), TIMES
    )
    axes = rate_model.moments_and_axes(x, FRAME)[1]
    for i in range(3):
        along = (compiled[:, 11 + i].reshape(-1, 3) @ axes)[:, i]
        assert np.mean(along * np.sign(rates[:, i])) < 0


def test_a_bias_beyond_every_sample_is_turned_back_at_once() -> None:
    x = np.concatenate([BODY, BIAS, DRAG])
    measured = drag_model.drag_rates(
        rate_model.moments_and_axes(x, FRAME)[0], DRAG, False, x[5:8].copy(), TIMES
    )
    largest = float(np.linalg.norm(measured, axis=1).max())
    inside = drag_model.drag_residuals(x, FRAME, TIMES, measured, True, False)
    assert np.all(np.abs(inside) < drag_model.GIVEN_UP)
    # The same body read with a bias just beyond the largest rate measured.
    x[8:11] = [1.001 * largest, 0.0, 0.0]
    beyond = drag_model.drag_residuals(x, FRAME, TIMES, measured, True, False)
    assert np.all(beyond == drag_model.GIVEN_UP)


def test_drag_starts_keep_biases_within_the_rates_or_are_refused_saying_why() -> None:
    # A torque-free motion, smoothed rates and their derivative as the fit takes them.
    moments = np.array([0.3, 0.8, 1.0])
    rates = rate_model.principal_rates(moments, BODY[5:8], TIMES)
    derivative = np.gradient(rates, TIMES, axis=0)
    largest = float(np.linalg.norm(rates, axis=1).max())
    biases = np.array([[2.0 * largest, 0.0, 0.0], [0.0, 0.5 * largest, 0.0]])
    assert list(biases_within_rates(biases, rates, rates, derivative)) == [False, True]
    with pytest.raises(
        InputError,
        match=r"^Expected a recording that determines the moment ratios, got only bodies whose "
        r"bias exceeds every rate measured \(the best: \d+\.\d+ rad/s against rates up to "
        r"\d+\.\d+ rad/s\): near a sphere, ω0 trades off against a bias",
    ):
        biases_within_rates(biases[:1], rates, rates, derivative)
    # Rates that break |dω/dt| ≤ |ω|²/√3 (in deg/s read as rad/s, 57.3 times too small):
    # the refusal names the likely unit instead.
    small = rates / 57.3
    with pytest.raises(InputError, match=r"the rates look too small for their unit"):
        biases_within_rates(biases[:1] / 57.3, small, small, derivative / 57.3)
