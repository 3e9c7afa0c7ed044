"""The gravity-gradient torque of a circular orbit: against an independent
integration, the small-angle pitch libration, batches, files and errors."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from tumble import scenario
from tumble.errors import CoarseStepWarning

AXES = Rotation.from_rotvec([0.3, -0.5, 0.8])
#: A boom-like body whose body axes are not principal.
BODY = tb.MassProperties(
    50.0, [0.1, 0.0, -0.2], AXES.as_matrix() @ np.diag([10.0, 40.0, 45.0]) @ AXES.as_matrix().T
)
RATE = 1.1e-3  # rad/s: a low Earth orbit, ~95 min
NORMAL = np.array([0.2, -0.3, 1.0])
RADIAL0 = np.array([1.0, 0.5, 0.0])


def gradient_reference(t: float, w: np.ndarray, a: np.ndarray) -> np.ndarray:
    """3 n² r × (I r) in body axes with the full tensor, r turned in space by hand."""
    normal = NORMAL / np.linalg.norm(NORMAL)
    e1 = RADIAL0 - (RADIAL0 @ normal) * normal
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    r = a.T @ (e1 * math.cos(RATE * t) + e2 * math.sin(RATE * t))
    return 3 * RATE**2 * np.cross(r, BODY.inertia @ r)


def test_a_tumbling_body_in_orbit_follows_an_independent_integration() -> None:
    # Over two orbits (12000 s), ω ~ 1e-2 rad/s: the adaptive method at rtol 1e-12
    # against DOP853 at rtol 1e-13 in body axes with the full tensor; both
    # accurate to ~1e-11 of |ω|, so 1e-9 rad/s and 1e-9 rad.
    omega0 = np.array([0.004, -0.01, 0.007])
    q0 = Rotation.from_rotvec([0.4, 0.2, -0.1]).as_quat(scalar_first=True)
    model = tb.torques.GravityGradient(RATE, orbit_normal=NORMAL, radial0=RADIAL0)
    run = tb.simulate(
        BODY, omega0, attitude0=q0, duration=12000.0, dt=1000.0, torque=model, rtol=1e-12,
        atol=1e-15,
    )  # fmt: skip
    assert run.method == "adaptive" and run.drift == {}
    w_ref, a_ref = reference(BODY, omega0, q0, 12000.0, torque=gradient_reference, times=run.t)
    assert np.max(np.abs(run.omega - w_ref)) < 1e-9
    assert attitude_error(run.quaternion, a_ref) < 1e-9


@pytest.mark.parametrize("method", ["splitting-exact", "strang-exact"])
@pytest.mark.slow  # long runs against a reference integration: 3.5 s a case
def test_the_splitting_around_the_exact_free_motion_errs_only_through_the_torque(
    method: str,
) -> None:
    # A fast tumble (|ω| 0.5 rad/s, 48 turns in 600 s) under the weak gradient
    # torque: the steppers' errors grow with the rotation, the exact flow's only
    # with the torque. Measured at dt = 1 s against DOP853 (~1e-11): 1.1e-6 rad
    # (splitting-exact), 2.4e-5 (strang-exact); RK4 0.16 rad, the rotation
    # splitting 2.6e-3. The bounds leave a factor of ~5 and show the gap.
    omega0 = np.array([0.3, -0.35, 0.2])
    q0 = Rotation.from_rotvec([0.4, 0.2, -0.1]).as_quat(scalar_first=True)
    model = tb.torques.GravityGradient(RATE, orbit_normal=NORMAL, radial0=RADIAL0)
    times = np.linspace(0.0, 600.0, 61)
    _, a_ref = reference(BODY, omega0, q0, 600.0, torque=gradient_reference, times=times)

    def error(name: str) -> tuple[float, bool]:
        """The largest attitude error, and whether a coarse step was warned of."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run = tb.simulate(
                BODY, omega0, attitude0=q0, duration=600.0, dt=1.0, record_every=10,
                torque=model, method=name,
            )  # fmt: skip
        coarse = any(issubclass(w.category, CoarseStepWarning) for w in caught)
        return attitude_error(run.quaternion, a_ref), coarse

    bound = 5e-6 if method == "splitting-exact" else 1e-4
    # Twelve steps a turn: coarse for the steppers, not for a method that
    # needs to resolve the torque only.
    exact_flow, exact_flow_warned = error(method)
    assert exact_flow < bound and not exact_flow_warned
    (rk4, rk4_warned), (rotations, _) = error("rk4"), error("splitting")
    assert rk4 > 1e3 * bound and rotations > 20 * bound and rk4_warned


def test_small_pitch_libration_has_the_textbook_frequency() -> None:
    # Principal moments A < B < C with C about the orbit normal and the axis of A
    # along the local vertical: pitch θ about the normal obeys
    # C θ̈ = −3 n² (B − A) sin θ cos θ (Hughes §9.3), so small swings have the
    # frequency n √(3 (B − A)/C). At θ0 = 1e-3 rad the amplitude correction is
    # ~θ0²/4 ≈ 3e-7; RK4 at 100 steps a libration period adds ~1e-8: 1e-5.
    a, b, c = 10.0, 40.0, 45.0
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([a, b, c]))
    theta0 = 1e-3
    expected = RATE * math.sqrt(3 * (b - a) / c)
    period = 2 * math.pi / expected
    run = tb.simulate(
        body, [0.0, 0.0, RATE], attitude0=Rotation.from_rotvec([0, 0, theta0]),
        duration=6 * period, dt=period / 100, method="rk4",
        torque=tb.torques.GravityGradient(RATE),
    )  # fmt: skip
    x = run.rotation.apply([1.0, 0.0, 0.0])
    pitch = np.arctan2(x[:, 1], x[:, 0]) - RATE * run.t  # from the local vertical
    pitch = np.angle(np.exp(1j * pitch))
    crossings = np.flatnonzero(np.diff(np.sign(pitch)) != 0)
    # Linear interpolation of the zero crossings: half a period apart.
    times = run.t[crossings] - pitch[crossings] * (run.t[crossings + 1] - run.t[crossings]) / (
        pitch[crossings + 1] - pitch[crossings]
    )
    measured = math.pi / np.mean(np.diff(times))
    assert measured == pytest.approx(expected, rel=1e-5)
    assert np.max(np.abs(pitch)) == pytest.approx(theta0, rel=1e-4)  # a libration, not a tumble


def test_batches_take_one_orbit_rate_per_body() -> None:
    # Each body of the batch equals its own simulation with the same step (the
    # vectorised kernel reassociates: round-off, 1e-15 of |ω| after 200 steps).
    rates = np.array([1e-3, 2e-3, 5e-3])
    omega0 = np.tile([0.01, 0.02, -0.01], (3, 1))
    moments = np.tile([10.0, 40.0, 45.0], (3, 1))
    model = tb.torques.GravityGradient(rates, radial0=[0.0, 1.0, 0.0])
    batch = tb.simulate_batch(moments, omega0, duration=200.0, dt=1.0, torque=model)
    for k in range(3):
        alone = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])), omega0[k], duration=200.0,
            dt=1.0, method="rk4",
            torque=tb.torques.GravityGradient(rates[k], radial0=[0.0, 1.0, 0.0]),
        )  # fmt: skip
        assert_allclose(batch.omega[k], alone.omega[-1], atol=1e-15)


def test_scenario_files_take_it_with_units() -> None:
    text = (
        scenario.builtin_text("tennis-racket")
        .replace('model = "flip-period"', 'model = "none"')
        .replace(
            "[simulation]",
            '[[torques]]\ntype = "gravity-gradient"\norbit_rate = "0.06 deg/s"\n'
            "orbit_normal = [0, 0, 1]\nradial0 = [1, 0, 0]\n\n[simulation]",
        )
    )
    loaded = scenario.parse(text.replace('method = "exact"', 'method = "rk4"'))
    (entry,) = loaded.spec.torques
    assert entry.values["orbit_rate"] == pytest.approx(math.radians(0.06), rel=1e-15)
    with pytest.raises(
        scenario.ScenarioError, match=r"`torques\[0\]\.orbit_rate`: Expected `orbit_rate` > 0"
    ):
        scenario.parse(text.replace('"0.06 deg/s"', '"-1 rad/s"'))


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: tb.torques.GravityGradient(0.0), r"Expected `orbit_rate` > 0 rad/s, got 0\.0\."),
        (
            lambda: tb.torques.GravityGradient([1e-3, -1e-3]),
            r"Expected `orbit_rate` > 0 rad/s, got orbit_rate\[1\] = -0\.001\.",
        ),
        (
            lambda: tb.torques.GravityGradient(1e-3, orbit_normal=[0, 0, 0]),
            r"Expected `orbit_normal` to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            lambda: tb.simulate(
                BODY,
                [0, 0, 0.01],
                duration=1.0,
                torque=tb.torques.GravityGradient(1e-3, radial0=[0, 0, 2]),
            ),
            r"Expected `radial0` off the orbit's normal .*, got \[0\.0, 0\.0, 2\.0\] along \[0\.0, 0\.0, 1\.0\]\.",
        ),
        (
            lambda: tb.simulate(
                BODY,
                [0, 0, 0.01],
                duration=1.0,
                pivot=[0, 0, 0],
                gravity=[0, 0, 0],
                torque=tb.torques.GravityGradient(1e-3),
            ),
            r"Expected a free body for GravityGradient .*, got a pivot\.",
        ),
    ],
)
def test_bad_orbits_are_refused(make, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        make()
