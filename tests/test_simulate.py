"""simulate(): RK4 against closed forms, a high-precision reference, and conservation laws."""

from __future__ import annotations

import dataclasses
import itertools
import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation
from scipy.special import ellipk

import tumble as tb
from reference import attitude_error, reference
from tumble.errors import CoarseStepWarning, IntegrationError

# A body whose principal axes are not its body axes, so every test also checks
# the change to the principal frame and back.
AXES = Rotation.from_rotvec([0.3, -0.5, 0.8])
TUMBLER = tb.MassProperties(
    1.0, [0.0, 0.0, 0.0], AXES.as_matrix() @ np.diag([1.0, 2.0, 3.0]) @ AXES.as_matrix().T
)


def test_rk4_is_fourth_order_against_a_reference() -> None:
    # Halving dt must divide the error by 2⁴ = 16; we accept 12-20 (the
    # asymptotic regime is reached at these steps, far above round-off).
    omega0 = np.array([0.5, 1.5, -0.3])
    q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
    w_ref, a_ref = reference(TUMBLER, omega0, q0, 5.0)
    errors = []
    for dt in (0.02, 0.01):
        run = tb.simulate(TUMBLER, omega0, attitude0=q0, duration=5.0, dt=dt, method="rk4")
        errors.append(
            np.linalg.norm(run.omega[-1] - w_ref) + attitude_error(run.quaternion[-1], a_ref)
        )
    assert 12 < errors[0] / errors[1] < 20
    run = tb.simulate(TUMBLER, omega0, attitude0=q0, duration=5.0, dt=1e-3, method="rk4")
    # 20⁴ = 1.6e5 times smaller than at dt = 0.02, i.e. ~1e-10 here; 1e-9 allows for round-off.
    assert np.linalg.norm(run.omega[-1] - w_ref) < max(errors[0] / 1e5, 1e-9)
    assert attitude_error(run.quaternion[-1], a_ref) < max(errors[0] / 1e5, 1e-9)


def test_free_body_conserves_energy_and_angular_momentum() -> None:
    # RK4 is not symplectic, but its drift per step is O(dt⁵): over 1e5 steps of
    # 1e-3 s on this body the energy and L move by well under 1e-10.
    run = tb.simulate(
        TUMBLER, [0.01, 2.0, 0.01], duration=100.0, dt=1e-3, record_every=100, method="rk4"
    )
    # Torque-free: the drift report holds exactly the energy and the vector L.
    assert set(run.drift) == {"energy", "angular_momentum_vector"}
    assert run.drift["energy"] < 1e-10
    assert run.drift["angular_momentum_vector"] < 1e-10


@pytest.mark.parametrize("method", ["exact", "rk4"])
def test_free_symmetric_top_precesses_in_the_body_frame(method: str) -> None:
    # I1 = I2: ω⊥ turns in the body frame at Ω = (I3 − I1)/I1 ω3, ω3 constant:
    # ω1 = a cos Ωt, ω2 = a sin Ωt (Euler's equations, solved by hand).
    top = tb.MassProperties(2.0, [0, 0, 0], np.diag([1.0, 1.0, 1.6]))
    a, w3 = 0.4, 5.0
    run = tb.simulate(top, [a, 0.0, w3], duration=10.0, dt=1e-3, record_every=50, method=method)
    rate = (1.6 - 1.0) / 1.0 * w3
    expected = np.column_stack(
        [a * np.cos(rate * run.t), a * np.sin(rate * run.t), np.full_like(run.t, w3)]
    )
    # RK4 phase error: (rate dt)⁴/120 per step × 1e4 steps × a ≈ 1e-12; allow 1e-9.
    assert_allclose(run.omega, expected, atol=1e-9)


def test_intermediate_axis_flip_period_matches_the_elliptic_integral() -> None:
    # Landau & Lifshitz §37: for L² > 2 E I2 the period of ω(t) is 4 K(k²)/λ with
    # λ = √((I3−I2)(L²−2EI1)/(I1I2I3)), k² = (I2−I1)(2EI3−L²)/((I3−I2)(L²−2EI1)).
    # ω2 changes sign twice a period: the mean spacing of its zero crossings is T/2.
    i1, i2, i3 = 1.0, 2.0, 3.0
    w0 = np.array([0.01, 2.0, 0.01])
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([i1, i2, i3]))
    energy2 = i1 * w0[0] ** 2 + i2 * w0[1] ** 2 + i3 * w0[2] ** 2
    momentum2 = (i1 * w0[0]) ** 2 + (i2 * w0[1]) ** 2 + (i3 * w0[2]) ** 2
    assert momentum2 > energy2 * i2
    lam = math.sqrt((i3 - i2) * (momentum2 - energy2 * i1) / (i1 * i2 * i3))
    k2 = (i2 - i1) * (energy2 * i3 - momentum2) / ((i3 - i2) * (momentum2 - energy2 * i1))
    period = 4 * ellipk(k2) / lam
    run = tb.simulate(body, w0, duration=3.2 * period, dt=2e-3)
    w2 = run.omega[:, 1]
    idx = np.flatnonzero(np.sign(w2[1:]) != np.sign(w2[:-1]))
    crossings = run.t[idx] - w2[idx] * (run.t[idx + 1] - run.t[idx]) / (w2[idx + 1] - w2[idx])
    assert len(crossings) >= 6
    measured = 2 * np.mean(np.diff(crossings))
    # Linear interpolation of a crossing errs by ~dt² |ω2''| / |ω2'| ≈ 1e-6 s; RK4's
    # phase error is smaller. The period is ~16 s: 1e-6 relative is generous.
    assert measured == pytest.approx(period, rel=1e-6)


def test_heavy_top_matches_a_reference_integration() -> None:
    # A disk on a pivot 0.1 m down its axis, axis tilted 60° from vertical, spinning.
    disk = tb.shapes.solid_cylinder(1.0, 0.1, 0.02)
    pivot = [0.0, 0.0, -0.1]
    q0 = Rotation.from_euler("x", 60, degrees=True).as_quat(scalar_first=True)
    omega0 = np.array([0.3, -0.2, 60.0])
    g = [0.0, 0.0, -9.81]
    run = tb.simulate(disk, omega0, attitude0=q0, duration=2.0, dt=2e-4, pivot=pivot, gravity=g)
    w_ref, a_ref = reference(disk, omega0, q0, 2.0, pivot=pivot, gravity=g)
    # RK4 at 2e-4 s with nutation at ~I3 ω3/I1 ≈ 2e2 rad/s: per-step error (0.04)⁵/120·1e4
    # steps ≈ 1e-8 relative; allow 1e-7 of |ω|.
    assert np.linalg.norm(run.omega[-1] - w_ref) < 1e-7 * np.linalg.norm(omega0)
    assert attitude_error(run.quaternion[-1], a_ref) < 1e-7
    assert run.drift["energy"] < 1e-8


def test_the_vertical_angular_momentum_of_a_heavy_top_is_conserved() -> None:
    # Gravity's torque about the pivot is horizontal, so L_z (space) is constant.
    disk = tb.shapes.solid_cylinder(1.0, 0.1, 0.02)
    q0 = Rotation.from_euler("x", 40, degrees=True).as_quat(scalar_first=True)
    run = tb.simulate(
        disk,
        [0.0, 0.0, 80.0],
        attitude0=q0,
        duration=1.0,
        dt=1e-4,
        pivot=[0, 0, -0.1],
        gravity=[0, 0, -9.81],
        record_every=20,
    )
    lz = run.angular_momentum[:, 2]
    assert np.max(np.abs(lz - lz[0])) < 1e-9 * np.abs(run.angular_momentum).max()


def test_motion_does_not_depend_on_the_choice_of_body_axes() -> None:
    # The same body described in rotated axes B' = R B, with ω0' = R ω0 and the
    # attitude re-expressed (A' = A Rᵀ), must move identically in space.
    rotation = Rotation.from_rotvec([1.0, 0.4, -0.7])
    omega0 = np.array([0.7, -1.2, 0.4])
    q0 = Rotation.from_rotvec([0.1, 0.2, 0.3])
    one = tb.simulate(TUMBLER, omega0, attitude0=q0, duration=3.0, dt=1e-3, record_every=100)
    two = tb.simulate(
        TUMBLER.transformed(rotation),
        rotation.apply(omega0),
        attitude0=q0 * rotation.inv(),
        duration=3.0,
        dt=1e-3,
        record_every=100,
    )
    # Round-off only (both runs take the same principal-frame steps): 1e-12.
    assert_allclose(two.omega_space, one.omega_space, atol=1e-12)
    assert_allclose(two.angular_momentum, one.angular_momentum, atol=1e-12)


def test_constant_space_torque_changes_l_linearly() -> None:
    # dL/dt = τ in space axes for any free body: L(t) = L0 + τ t exactly.
    tau = np.array([0.02, -0.01, 0.03])
    run = tb.simulate(
        TUMBLER,
        [0.3, 1.0, -0.5],
        duration=4.0,
        dt=1e-3,
        record_every=100,
        torque=tb.torques.ConstantSpaceTorque(tau),
    )
    expected = run.angular_momentum[0] + np.outer(run.t, tau)
    assert_allclose(run.angular_momentum, expected, atol=1e-10)


def test_body_torque_and_damping_on_a_sphere() -> None:
    # A sphere (I = 0.4 m r² = 0.1) spun about z with τ_body along z and damping
    # c: I ω̇ = τ − c ω, so ω(t) = τ/c + (ω0 − τ/c) e^{−c t / I}.
    ball = tb.shapes.solid_sphere(1.0, 0.5)
    tau, c, w0 = 0.05, 0.02, 3.0
    torque = tb.torques.ConstantBodyTorque([0, 0, tau]) + tb.torques.LinearDamping(c)
    run = tb.simulate(ball, [0, 0, w0], duration=5.0, dt=1e-3, torque=torque, record_every=100)
    expected = tau / c + (w0 - tau / c) * np.exp(-c * run.t / 0.1)
    assert_allclose(run.omega[:, 2], expected, rtol=1e-11)


def test_gravity_exerts_no_torque_on_a_free_body() -> None:
    free = tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-3)
    falling = tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-3, gravity=[0, 0, -9.81])
    assert np.array_equal(free.omega, falling.omega)


def test_recording_keeps_every_kth_state_and_the_last() -> None:
    run = tb.simulate(
        TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=0.01, record_every=30, method="rk4"
    )
    assert run.t[-1] == 1.0
    assert_allclose(run.t[:-1], np.arange(4) * 0.3, atol=1e-15)
    full = tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=0.01, method="rk4")
    assert np.array_equal(run.omega[:-1], full.omega[::30])
    assert np.array_equal(run.omega[-1], full.omega[-1])


def test_progress_reports_reach_the_total() -> None:
    calls = []
    tb.simulate(
        TUMBLER,
        [0.3, 1.0, -0.5],
        duration=1.0,
        dt=1e-5,
        record_every=1000,
        progress=lambda done, total: calls.append((done, total)),
    )
    assert calls[-1] == (100000, 100000)
    assert all(a[0] < b[0] for a, b in itertools.pairwise(calls))


def test_default_step_resolves_the_fastest_rotation() -> None:
    # 200 steps a turn of the fastest rate the motion reaches (the largest |ω|
    # of the exact solution over a period of its polhode, sampled finely).
    run = tb.simulate(TUMBLER, [0.0, 0.0, 10.0], duration=1.0, method="rk4")
    fastest = largest_rate_reached(TUMBLER, [0.0, 0.0, 10.0])
    target = 2 * math.pi / fastest / 200  # shortened so that whole steps span 1 s
    steps = math.ceil(1.0 / target)
    assert target * (steps - 1) / steps < run.dt <= target * (1 + 4e-5)  # 4e-5: the sampling


def test_parquet_round_trip(tmp_path) -> None:
    run = tb.simulate(
        tb.shapes.solid_cylinder(1.0, 0.1, 0.02),
        [0, 0, 50.0],
        duration=0.5,
        dt=1e-3,
        pivot=[0, 0, -0.1],
        gravity=[0, 0, -9.81],
        attitude0=[0.9, 0.3, 0, 0],
    )
    path = tmp_path / "run.parquet"
    run.to_parquet(path)
    back = tb.Trajectory.read_parquet(path)
    assert np.array_equal(back.t, run.t)
    assert np.array_equal(back.omega, run.omega)
    assert np.array_equal(back.quaternion, run.quaternion)
    assert np.array_equal(back.energy, run.energy)
    assert back.method == run.method and back.dt == run.dt
    assert not list(tmp_path.glob(".*partial"))


def test_read_parquet_errors(tmp_path) -> None:
    bad = tmp_path / "bad.parquet"
    bad.write_bytes(b"not parquet")
    with pytest.raises(
        tb.InputError, match=r"Expected a Parquet file written by tumble, got '.*bad.parquet'"
    ):
        tb.Trajectory.read_parquet(bad)
    import pyarrow as pa
    import pyarrow.parquet as pq

    other = tmp_path / "other.parquet"
    pq.write_table(pa.table({"x": [1.0]}), other)
    with pytest.raises(tb.InputError, match=r"\(no tumble metadata\)"):
        tb.Trajectory.read_parquet(other)


def test_repr_reports_method_and_drift() -> None:
    text = repr(tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-3))
    assert "method exact" in text and "torque-free" in text and "relative drift: energy" in text


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"duration": 0.0}, r"Expected `duration` > 0 s, got 0.0"),
        ({"duration": 1.0, "dt": -1e-3}, r"Expected `dt` > 0 s, got -0.001"),
        ({"duration": 1.0, "dt": "1 m"}, r"Expected `dt` to be a time in s, got 1 m"),
        (
            {"duration": 1.0, "attitude0": [0, 0, 0, 0]},
            r"Expected `attitude0` to be a non-zero quaternion \[w, x, y, z\], got \[0.0, 0.0, 0.0, 0.0\]",
        ),
        (
            {"duration": 1.0, "attitude0": Rotation.random(2, random_state=1)},
            r"Expected `attitude0` to be a single rotation, got 2",
        ),
        ({"duration": 1.0, "pivot": [0, 0, -0.1]}, r"Expected `gravity` with `pivot`, got none"),
        (
            {"duration": 1.0, "method": "euler"},
            r"Expected `method` to be one of auto, exact, splitting, strang, splitting-exact, strang-exact, rk4, adaptive, got 'euler'",
        ),
        (
            {"duration": 1.0, "record_every": 0},
            r"Expected `record_every` to be an integer >= 1, got 0",
        ),
        (
            {"duration": 1.0, "torque": 3.0},
            r"Expected `torque` to be a model from tumble.torques, got float",
        ),
    ],
)
def test_simulate_rejects_bad_input(kwargs: dict, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(TUMBLER, [0.3, 1.0, -0.5], **kwargs)


def test_simulate_rejects_nan_omega_and_a_rod() -> None:
    with pytest.raises(tb.InputError, match=r"Expected `omega0` to be finite"):
        tb.simulate(TUMBLER, [np.nan, 1.0, 0.0], duration=1.0)
    with pytest.raises(
        tb.InputError, match=r"Expected a body with no zero principal moment to simulate"
    ):
        tb.simulate(tb.shapes.thin_rod(1.0, 1.0), [1.0, 0.0, 0.0], duration=1.0)
    with pytest.raises(tb.InputError, match=r"Expected `mp` to be a MassProperties, got str"):
        tb.simulate("box", [1.0, 0.0, 0.0], duration=1.0)


def test_a_diverging_integration_stops_with_the_step_named() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseStepWarning)
        with pytest.raises(
            IntegrationError,
            match=r"got NaN or inf at step \d+ \(t = [0-9.e+]+ s\) with dt = 50 s: reduce dt",
        ):
            tb.simulate(TUMBLER, [0.3, 10.0, -0.5], duration=1e6, dt=50.0, method="rk4")


def test_a_coarse_step_warns() -> None:
    with pytest.warns(
        CoarseStepWarning, match=r"dt = 0.5 s gives [0-9.]+ steps per turn of the fastest rotation"
    ):
        tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=0.5, method="rk4")


def test_damping_must_not_be_negative() -> None:
    with pytest.raises(tb.InputError, match=r"Expected `coefficient` >= 0 N·m·s, got -1.0"):
        tb.torques.LinearDamping(-1.0)


# ------------------------------------------------------------ exact solution
@pytest.mark.parametrize(
    "omega0",
    [(0.5, 1.5, -0.3), (0.01, 2.0, 0.01), (2.0, 0.1, 0.1), (-0.2, 0.3, 1.9), (1e-6, 2.0, -1e-6)],
)
def test_exact_solution_matches_a_reference_integration(omega0) -> None:
    # Both sides of the separatrix and 1e-6 from it, in non-principal body axes.
    # DOP853 at rtol 1e-13 over 20 s is good to ~1e-11 (it is the limit here).
    q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
    run = tb.simulate(TUMBLER, omega0, attitude0=q0, duration=20.0, dt=0.5, method="exact")
    w_ref, a_ref = reference(TUMBLER, np.array(omega0), q0, 20.0)
    assert np.linalg.norm(run.omega[-1] - w_ref) < 1e-10
    assert attitude_error(run.quaternion[-1], a_ref) < 1e-10


def test_exact_solution_conserves_l_to_round_off_over_long_times() -> None:
    # No truncation error: the space-frame L is fixed to a few ulp after 1e5 s
    # (≈ 6000 periods, 12 000 flips), where any integrator would drift.
    run = tb.simulate(TUMBLER, [0.01, 2.0, 0.01], duration=1e5, dt=97.0, method="exact")
    assert run.drift["angular_momentum_vector"] < 1e-12
    assert run.drift["energy"] < 1e-13


def test_auto_picks_exact_splitting_or_adaptive() -> None:
    free = tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-2)
    assert free.method == "exact" and "torque-free" in free.reason
    # On a pivot without gravity the body is torque-free about the pivot.
    weightless = tb.simulate(
        TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-2, pivot=[0, 0, -0.1], gravity=[0, 0, 0]
    )
    assert weightless.method == "exact"
    top = tb.simulate(
        TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-2, pivot=[0, 0, -0.1], gravity=[0, 0, -9.81]
    )
    assert top.method == "splitting" and "conservative" in top.reason
    forced = tb.simulate(
        TUMBLER, [0.3, 1.0, -0.5], duration=1.0, dt=1e-2, torque=tb.torques.LinearDamping(0.1)
    )
    assert forced.method == "adaptive" and "non-conservative" in forced.reason


@pytest.mark.parametrize(
    ("body", "omega0"), [(TUMBLER, None), (tb.shapes.solid_sphere(1.0, 0.2), (0.3, -0.2, 2.0))]
)
def test_exact_steady_rotations(body, omega0) -> None:
    # About a principal axis (the unstable middle one too, exactly) or any axis
    # of a sphere, ω is constant and the body turns uniformly about it.
    if omega0 is None:
        _, axes = body.principal()
        omega0 = 1.5 * axes[:, 1]
    run = tb.simulate(body, omega0, duration=10.0, dt=1.0, method="exact")
    assert_allclose(run.omega, np.tile(omega0, (len(run.t), 1)), atol=1e-15)
    # A(t) = exp([ω]× t) from the identity: compare rotations sample by sample.
    expected = Rotation.from_rotvec(np.outer(run.t, omega0))
    assert np.max((run.rotation * expected.inv()).magnitude()) < 1e-13


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"pivot": [0, 0, -0.1], "gravity": [0, 0, -9.81]},
            r"Expected a method that integrates this motion \(auto, splitting, strang, splitting-exact, strang-exact, rk4, adaptive\), got 'exact': its closed forms solve torque-free bodies and a symmetric top under uniform gravity \(two equal moments about the pivot, the pivot and the centre of mass on the symmetry axis, no parts\) only, and this motion has gravity on a body that is not such a top\.",
        ),
        (
            {"torque": tb.torques.ConstantSpaceTorque([0, 0, 1])},
            r"this motion has ConstantSpaceTorque\.",
        ),
    ],
)
def test_exact_needs_a_torque_free_body_or_a_symmetric_top(kwargs, message) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(TUMBLER, [0.3, 1.0, -0.5], duration=1.0, method="exact", **kwargs)


# Bodies of every shape the bound must be tight for: elongated (a pencil), flat
# (a plate), near-spherical, and a general box whose axes are not the body axes.
STEP_BODIES = {
    "pencil": tb.shapes.solid_cylinder(0.01, 0.004, 0.08),
    "plate": tb.shapes.box(0.2, [0.2, 0.15, 0.002]),
    "near-sphere": tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.001, 1.003])),
    "tumbler": TUMBLER,
}
STEP_STARTS = [[30.0, 0.5, 1.0], [0.2, 5.0, 0.3], [1.0, 0.2, 6.0], [2.0, -3.0, 1.5]]


def largest_rate_reached(body: tb.MassProperties, omega0: list[float]) -> float:
    """max |ω| over the torque-free motion, from the closed form sampled over
    20 s: a period of |ω| or more (it repeats with the polhode) for the pencil,
    the plate and the tumbler; the near-sphere's |ω| changes by < 1e-6 in all."""
    run = tb.simulate(body, omega0, duration=20.0, dt=2e-4, method="exact")
    return float(np.linalg.norm(run.omega, axis=1).max())


@pytest.mark.parametrize("name", STEP_BODIES)
@pytest.mark.parametrize("omega0", STEP_STARTS)
def test_the_fastest_rate_is_the_largest_rate_the_motion_reaches(name: str, omega0) -> None:
    from tumble.body import RigidBody

    body = STEP_BODIES[name]
    bound = RigidBody(body, None, ()).fastest_rate(np.array(omega0, dtype=float), 0.0)
    reached = largest_rate_reached(body, omega0)
    # An upper bound to round-off; tight to the sampling: near its maximum |ω|
    # departs from it quadratically in time, by < (2e-4 s · 30 rad/s)² relative.
    assert reached <= bound * (1 + 1e-12)
    assert reached >= bound * (1 - 4e-5)


@pytest.mark.parametrize("name", STEP_BODIES)
def test_the_step_warning_fires_when_and_only_when_the_step_is_coarse(name: str) -> None:
    # "Coarse": fewer than MIN_STEPS_PER_TURN steps per turn of the fastest rate
    # the motion reaches (from the exact solution). 10 % either side of that step
    # must be silent and warn.
    from tumble.integrators.steps import MIN_STEPS_PER_TURN

    body, omega0 = STEP_BODIES[name], STEP_STARTS[0]
    limit = 2 * math.pi / largest_rate_reached(body, omega0) / MIN_STEPS_PER_TURN
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoarseStepWarning)
        tb.simulate(body, omega0, duration=100 * limit, dt=0.9 * limit, method="rk4")
    with pytest.warns(CoarseStepWarning, match=r"steps per turn of the fastest rotation"):
        tb.simulate(body, omega0, duration=100 * limit, dt=1.1 * limit, method="rk4")


def test_a_pencil_tumbling_end_over_end_at_a_fine_step_does_not_warn() -> None:
    # |L| / I1 = 2015 rad/s for this pencil turning at 30 rad/s about a transverse
    # axis: the loose bound called dt = 1/300 of a turn "4.5 steps per turn".
    # RK4 at that step agrees with the exact solution to ~1e-13 rad/s and
    # ~1e-8 rad of attitude over 20 turns; so the warning must stay silent.
    pencil, omega0 = STEP_BODIES["pencil"], [30.0, 0.5, 1.0]
    turn = 2 * math.pi / 30.02
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoarseStepWarning)
        run = tb.simulate(pencil, omega0, duration=20 * turn, dt=turn / 300, method="rk4")
    exact = tb.simulate(pencil, omega0, duration=20 * turn, dt=turn / 300, method="exact")
    assert_allclose(run.omega, exact.omega, atol=1e-10)
    turned = (
        Rotation.from_quat(run.quaternion, scalar_first=True)
        * Rotation.from_quat(exact.quaternion, scalar_first=True).inv()
    )
    assert turned.magnitude().max() < 1e-6


@pytest.mark.parametrize("scale", [1e-110, 1e-30, 1e30, 1e110])
def test_the_largest_rate_does_not_depend_on_the_scale_of_the_moments(scale: float) -> None:
    # The motion depends on the ratios of the moments only. Oracle at unit scale:
    # the largest |ω| the exact solution reaches (sampled finely, see above).
    from tumble.invariants import largest_rate

    moments, omega = np.array([0.2, 0.9, 1.0]), np.array([1.0, 0.1, 3.0])
    unit = largest_rate(moments, omega)
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag(moments))
    assert unit == pytest.approx(largest_rate_reached(body, list(omega)), rel=4e-5)
    assert largest_rate(moments * scale, omega) == pytest.approx(unit, rel=1e-15)


def test_the_drift_of_a_body_released_from_rest_is_relative_to_its_swing() -> None:
    # A bar swinging on a pivot from rest: L(0) = 0 exactly, and the conserved
    # vertical component stays 0 (the swing's L is horizontal). Measured against
    # the momentum of the swing it is round-off (100 ε); against |L(0)| it was
    # a division by zero's scale (1e291).
    bar = tb.shapes.box(1.0, [0.05, 0.02, 1.0])
    tilt = [np.cos(0.3), np.sin(0.3), 0.0, 0.0]
    swing = tb.simulate(bar, [0, 0, 0], pivot=[0, 0, 0.5], gravity=[0, 0, -9.81],
                        attitude0=tilt, duration=2.0, dt=1e-3)  # fmt: skip
    assert swing.drift["angular_momentum_vertical"] < 100 * np.finfo(float).eps


def _scaled(mp: tb.MassProperties, scale: float) -> tb.MassProperties:
    """The same body with its mass and inertia multiplied by ``scale``."""
    return tb.MassProperties(mp.mass * scale, mp.center_of_mass, mp.inertia * scale)


@pytest.mark.parametrize("scale", [1e-200, 1e154, 1e200])
def test_the_drift_report_does_not_depend_on_the_scale_of_the_moments(scale: float) -> None:
    # The motion depends on the ratios of the moments only, and the drift is
    # relative: a body 1e±200 times heavier drifts as much. RK4's drift here is
    # its truncation error (~1e-10); the scaled moments differ from the unit
    # ones by a rounding, which moves the drift by round-off accumulated over
    # the 200 steps (at most 200 ε ≈ 4.4e-14), far below it.
    omega0 = [0.3, 2.0, 0.1]
    unit = tb.simulate(TUMBLER, omega0, duration=2.0, dt=0.01, method="rk4")
    run = tb.simulate(_scaled(TUMBLER, scale), omega0, duration=2.0, dt=0.01, method="rk4")
    assert unit.drift["angular_momentum_vector"] > 1e-11
    for name, drift in unit.drift.items():
        assert run.drift[name] == pytest.approx(drift, abs=200 * np.finfo(float).eps)


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e154, 1e200, 1e300])
def test_relative_change_does_not_depend_on_the_scale_of_the_moments(scale: float) -> None:
    # The same samples (ω, attitude, a rotor's speed) on a body and rotor scaled
    # by `scale`: L and the energy are scaled by it, up to one rounding each,
    # which moves a relative change by a few ε at most.
    rotor = tb.Rotor([0, 0, 1], 0.05, speed=3.0)
    unit = tb.simulate(TUMBLER, [0.3, 2.0, 0.1], duration=2.0, dt=0.01, method="rk4",
                       internal=[rotor])  # fmt: skip
    run = dataclasses.replace(
        unit,
        mass_properties=_scaled(TUMBLER, scale),
        internal=(tb.Rotor([0, 0, 1], 0.05 * scale, speed=3.0),),
    )
    for name in ("energy", "angular_momentum_vector", "angular_momentum_norm"):
        expected = unit.relative_change(name)
        assert np.abs(expected).max() > 1e-11  # a drift to measure, not round-off
        assert_allclose(run.relative_change(name), expected, rtol=0, atol=8 * np.finfo(float).eps)


@pytest.mark.parametrize(
    ("attitude0", "expected"),
    [
        ([1e300, 1e300, 0, 0], [math.sqrt(0.5), math.sqrt(0.5), 0, 0]),
        ([1e-300, 1e-300, 0, 0], [math.sqrt(0.5), math.sqrt(0.5), 0, 0]),
        ([0, -1.7e308, 0, 1.7e308], [0, -math.sqrt(0.5), 0, math.sqrt(0.5)]),
        ([5e-324, 0, 0, 0], [1, 0, 0, 0]),  # the smallest float: not zero
    ],
)
def test_a_quaternion_of_any_size_is_normalised(attitude0: list, expected: list) -> None:
    # Only the direction of attitude0 counts; its length (its squares overflow
    # or underflow at these sizes) does not. To round-off (one rounding in the
    # scaling, one in the division by the length: a few ε).
    run = tb.simulate(TUMBLER, [0.3, 1.0, -0.5], attitude0=attitude0, duration=1.0, dt=0.1)
    assert_allclose(run.quaternion[0], expected, rtol=0, atol=4 * np.finfo(float).eps)
