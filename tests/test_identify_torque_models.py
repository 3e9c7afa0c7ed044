"""tumble.identify with a torque model of tumble's registry or a user's: its parameters
fitted beside the body, on throws simulated by tumble.simulate under the same model
(adaptive Dormand–Prince, independent of the fit's Runge–Kutta stepping)."""

from __future__ import annotations

from dataclasses import replace

import numba
import numpy as np
import pytest

import tumble as tb
from test_identify_drag import LINEAR, MOMENTS, throw
from tumble.core.dynamics import euler_coefficients
from tumble.core.stepped_model import stepped_rates
from tumble.errors import InputError
from tumble.identification.result import principal_rates
from tumble.identification.torque_values import model_rates


@numba.njit
def cubic_drag(t, omega, quaternion, params, out):  # type: ignore[no-untyped-def]
    """τ_i = −p_i ω_i³ about each body axis (N·m, p in N·m·s³)."""
    for i in range(3):
        out[i] = -params[i] * omega[i] ** 3


@pytest.mark.slow  # a fit with a user's torque compiled: 5 s
def test_a_users_torque_is_fitted_with_the_body() -> None:
    # p_i / I3 = (0.002, 0.001, 0.003) s: at 10 rad/s a torque of ~1 % of dL/dt, as the
    # racquet's drag. Measured: the parameters within 1.7σ, the ratios within 0.6σ.
    truth = np.array([0.002, 0.001, 0.003])
    t, measured, _ = throw(3, tb.torques.UserTorque(cubic_drag, truth * MOMENTS[2]))
    fit = tb.identify(
        t, measured, window=(0.0, t[-1]), torque=tb.torques.UserTorque(cubic_drag, np.zeros(3))
    )
    assert fit.torque == "user" and fit.torque_units == "SI, for a body of I3 = 1 kg·m²"
    assert fit.parameter_names[-3:] == ("params[0]", "params[1]", "params[2]")
    # Within 3σ: the residuals are the noise, so the standard errors hold.
    assert np.all(np.abs(fit.torque_parameters - truth) < 3.0 * fit.torque_uncertainty)
    assert np.all(np.abs(fit.moment_ratios - [0.067, 0.94]) < 3.0 * fit.uncertainty)
    assert fit.residual_rms == pytest.approx(0.0035, rel=0.2)  # 240 residuals: ±5 %, and dof
    # The fitted model is kept, with the fitted values, and forecasts past the window.
    np.testing.assert_array_equal(fit.torque_model.params, fit.torque_parameters)
    later = np.arange(80, 100) / 100.0
    _, more, _ = throw(3, tb.torques.UserTorque(cubic_drag, truth * MOMENTS[2]), samples=100)
    assert np.sqrt(np.mean((fit.forecast(later) - more[80:]) ** 2)) < 3.0 * 0.0035


@pytest.mark.slow  # a fit of a torque model: 4 s
def test_a_registry_model_of_omega_is_fitted_from_its_given_values() -> None:
    # Linear damping, equal about every axis: c / I3 = 0.1 1/s.
    t, measured, _ = throw(5, tb.torques.LinearDamping(0.1 * MOMENTS[2]))
    fit = tb.identify(t, measured, window=(0.0, t[-1]), torque=tb.torques.LinearDamping(0.0))
    assert fit.torque == "damping" and fit.parameter_names[-1] == "coefficient"
    assert abs(fit.torque_parameters[0] - 0.1) < 3.0 * fit.torque_uncertainty[0]


def test_the_stepped_rates_are_the_exact_motion_without_torque_and_decay_with_damping() -> None:
    # Torque-free: against the Jacobi elliptic solution. RK4 substeps turning 0.05 rad err
    # by ~(0.05)⁵/120 ≈ 3e-9 of |ω| each; over the 2 s here (~360 substeps each way)
    # measured 1.1e-6 rad/s at |ω| = 9 rad/s: asked 1e-5, 350 times below a phone's noise.
    moments = np.array([0.067, 0.94, 1.0])
    omega0 = np.array([0.4, -9.0, 1.1])
    times = np.linspace(-0.5, 1.5, 201)
    stepped = model_rates(tb.torques.UserTorque(cubic_drag, np.zeros(3)), moments, omega0, times)
    np.testing.assert_allclose(stepped, principal_rates(moments, omega0, times), atol=1e-5)
    # A ball under linear damping c: each rate decays as exp(−c t / I), backwards too
    # (a ball's gyroscopic term is zero, so the substeps' error is RK4's on exp alone).
    ball = np.ones(3)
    damped = model_rates(tb.torques.LinearDamping(0.3), ball, omega0, times)
    np.testing.assert_allclose(damped, np.exp(-0.3 * times)[:, None] * omega0, rtol=1e-9)


def test_a_motion_run_away_gives_non_finite_rates() -> None:
    # More than the substeps allowed between two samples: the rest are not computed.
    from tumble.identification.torque_values import axes_body
    from tumble.torques.binding import bind

    bound = bind(tb.torques.LinearDamping(0.0), axes_body(), np.ones(3))
    coefficients = euler_coefficients(1.0, 2.0, 2.5)
    start, times = np.array([100.0, 0.0, 0.0]), np.array([0.01, 10.0, 11.0])
    rates = stepped_rates(
        bound.function, coefficients, bound.params, bound.context, start, times, 0.05, 1000
    )
    assert np.all(np.isfinite(rates[0])) and np.all(np.isnan(rates[1:]))


@pytest.mark.parametrize(
    ("torque", "why"),
    [
        ("damping", "a name or a class gives no starting values"),
        (tb.torques.LinearDamping, "a name or a class gives no starting values"),
        (tb.torques.GravityGradient(0.001), "its torque reads the attitude"),
        (tb.torques.LinearDamping(0.1) + tb.torques.AxisDrag(LINEAR), "a sum of models"),
    ],
)
def test_models_a_fit_of_rates_cannot_fit_are_refused_saying_why(torque, why) -> None:
    t, measured, _ = throw(3, None)
    with pytest.raises(
        InputError,
        match=r"Expected `torque` to be one of auto, free, drag, quadratic-drag, or a model "
        r"of a torque of ω and time with its parameters' starting values, got .*: " + why,
    ):
        tb.identify(t, measured, window=(0.0, t[-1]), torque=torque)


def test_many_throws_share_only_the_drags() -> None:
    recording = tb.identification.synthetic_throws(2, seed=3)
    with pytest.raises(InputError, match=r"the joint fit of many throws shares the drags"):
        user = tb.torques.UserTorque(cubic_drag, np.zeros(3))
        tb.identify_many(recording.t, recording.omega, recording.windows, torque=user)


@pytest.mark.parametrize(
    ("torque", "why"),
    [
        (
            tb.torques.ConstantBodyTorque([0.0, 0.0, 1e-3], actuator="rotors"),
            "it acts through the body.s rotors",
        ),
        (tb.torques.HoldRotation(), "it has no parameters to fit"),
    ],
)
def test_models_of_rotors_or_without_parameters_are_refused(torque, why) -> None:
    t, measured, _ = throw(3, None)
    with pytest.raises(InputError, match=r"starting values, got .*: " + why):
        tb.identify(t, measured, window=(0.0, t[-1]), torque=torque)


@numba.njit
def no_torque(t, omega, quaternion, params, out):  # type: ignore[no-untyped-def]
    """A parameter that changes nothing."""
    out[0] = 0.0 * params[0]


def test_a_model_that_misses_the_samples_is_refused() -> None:
    # Throws under drag fitted with a torque that does nothing: the torque-free body's
    # residuals, twenty times the noise, remain.
    t, measured, _ = throw(3, tb.torques.AxisDrag(LINEAR))
    with pytest.raises(
        InputError,
        match=r"Expected the samples of 0–0\.79 s to follow a motion under "
        r"UserTorque\(no_torque, params=\[0\.0\]\), got residuals of [0-9.]+ rad/s against noise",
    ):
        tb.identify(
            t, measured, window=(0.0, t[-1]), torque=tb.torques.UserTorque(no_torque, [0.0])
        )


def test_a_fit_whose_moments_change_order_is_refused() -> None:
    # Started from the same body with its first two axes swapped (moments (r2, r1, 1)),
    # the fit stays there: the moments are not ascending, and the fit says so.
    from tumble.identification.torque_fit import fit_torque_model

    t, measured, _ = throw(3, tb.torques.AxisDrag(LINEAR))
    fit = tb.identify(t, measured, window=(0.0, t[-1]), torque="drag")
    swapped = replace(
        fit,
        moment_ratios=fit.moment_ratios[::-1].copy(),
        axes=fit.axes[:, [1, 0, 2]] * [1.0, 1.0, -1.0],
        omega0=fit.omega0[[1, 0, 2]] * [1.0, 1.0, -1.0],
    )
    with pytest.raises(InputError, match=r"to keep the moments' order, got moments 0\.8"):
        fit_torque_model(swapped, tb.torques.UserTorque(no_torque, [0.0]), "linear")
