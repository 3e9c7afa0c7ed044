"""The compiled model of measured rates (tumble.core.rate_model) against the same
model put together from scipy's rotations and numpy, as the fit once did."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tumble.core.rate_model import principal_rates, rate_residuals, rotation_matrix


@pytest.mark.parametrize("size", [0.0, 1e-12, 1e-4, 0.999e-3, 1.001e-3, 0.5, np.pi, 10.0])
def test_the_rotation_of_a_vector_is_scipys(size: float) -> None:
    # Oracle: scipy's Rotation.from_rotvec. Either side of the switch to the
    # series (1e-3), at the half turn and beyond it: the entries agree to a few
    # ε (each is a few products of numbers ≤ 1, rounded in another order).
    for direction in np.random.default_rng(3).normal(size=(20, 3)):
        vector = size * direction / np.linalg.norm(direction)
        expected = Rotation.from_rotvec(vector).as_matrix()
        np.testing.assert_allclose(rotation_matrix(vector), expected, rtol=0, atol=4e-16)


def _model(x: np.ndarray, frame: np.ndarray, times: np.ndarray, bias: bool) -> np.ndarray:
    """The model of the samples at ``times``, by scipy and numpy."""
    moments = np.array([*np.exp(np.clip(x[:2], -60.0, 60.0)), 1.0])
    axes = frame @ Rotation.from_rotvec(x[2:5]).as_matrix()
    offset = x[8:11] if bias else np.zeros(3)
    return np.asarray(principal_rates(moments, x[5:8], times) @ axes.T + offset)


@pytest.mark.parametrize("bias", [True, False])
def test_the_residuals_are_the_model_less_the_samples(bias: bool) -> None:
    # Random parameters (ratios in any order, so the odd permutations are taken
    # too, and one far off, clipped), random axes, a ragged grid of times. The
    # same arithmetic in another order: to 1e-14 of the rates' size.
    rng = np.random.default_rng(7)
    times = np.sort(rng.uniform(0.0, 5.0, 300))
    frame = Rotation.random(random_state=rng).as_matrix()
    for trial in range(12):
        x = np.concatenate([rng.normal(0, 0.8, 2), rng.normal(0, 1.5, 3), rng.normal(0, 3, 3),
                            rng.normal(0, 0.1, 3 if bias else 0)])  # fmt: skip
        if trial == 0:
            x[0] = 100.0  # beyond e^60: clipped
        measured = rng.normal(size=(len(times), 3))
        expected = (_model(x, frame, times, bias) - measured).ravel()
        residuals = rate_residuals(x, frame, times, measured, bias)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(residuals, expected, rtol=0, atol=1e-14 * scale)


def test_equal_moments_keep_their_order() -> None:
    # A symmetric body given with its equal moments first or last: the sort is
    # stable and the motion the same as for the moments given sorted, mapped back
    # (oracle: Euler's equations of a symmetric body, whose transverse ω turns
    # about its axis k at ν = ω_k (I_k − I)/I in the body, I the equal moments).
    times = np.linspace(0.0, 3.0, 50)
    for moments, axis in (((0.5, 0.5, 1.0), 2), ((1.0, 0.5, 0.5), 0)):
        others = [k for k in range(3) if k != axis]
        omega0 = np.zeros(3)
        omega0[others[0]], omega0[axis] = 0.4, 2.0
        rates = principal_rates(np.array(moments), omega0, times)
        rate = 2.0 * (moments[axis] - 0.5) / 0.5
        # (axis, others) is a cyclic order of (1, 2, 3) in both cases, so both
        # turn the same way.
        expected = 0.4 * np.exp(1j * rate * times)
        np.testing.assert_allclose(rates[:, axis], 2.0, rtol=0, atol=1e-15)
        np.testing.assert_allclose(
            rates[:, others[0]] + 1j * rates[:, others[1]], expected, rtol=0, atol=1e-12
        )
