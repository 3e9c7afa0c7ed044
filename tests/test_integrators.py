"""The splitting, Strang, RK4 and adaptive integrators and user torques.

Oracles: an independent DOP853 integration in body axes (tests/reference.py),
the exact torque-free solution, closed forms, convergence orders, and the
conservation laws each method must keep. Every registered integrator also runs
the oracle tests of tests/test_registries.py.
"""

from __future__ import annotations

import itertools
import math
import warnings

import numba
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from tumble.errors import CoarseStepWarning, IntegrationError

AXES = Rotation.from_rotvec([0.3, -0.5, 0.8])
TUMBLER = tb.MassProperties(
    1.0, [0.0, 0.0, 0.0], AXES.as_matrix() @ np.diag([1.0, 2.0, 3.0]) @ AXES.as_matrix().T
)
Q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
OMEGA0 = np.array([0.3, 1.0, -0.5])

# A forced, damped, asymmetric body: a body torque, a space torque and damping.
FORCING = (
    tb.torques.ConstantBodyTorque([0.05, -0.02, 0.01])
    + tb.torques.ConstantSpaceTorque([0.0, 0.03, -0.01])
    + tb.torques.LinearDamping(0.02)
)


def forcing_reference(t, w, a):
    return np.array([0.05, -0.02, 0.01]) + a.T @ np.array([0.0, 0.03, -0.01]) - 0.02 * w


def heavy_top():
    disk = tb.shapes.solid_cylinder(1.0, 0.1, 0.02)
    q0 = Rotation.from_euler("x", 60, degrees=True).as_quat(scalar_first=True)
    return disk, q0, np.array([0.3, -0.2, 60.0])


@pytest.mark.parametrize(
    ("method", "order", "counts"),
    [
        ("strang", 2, (1000, 2000, 4000)),
        # The splitting is ~100× more accurate than RK4 here: coarser steps keep
        # its errors (1e-7 … 6e-10) far above the reference's (~4e-12).
        ("splitting", 4, (250, 500, 1000)),
        ("rk4", 4, (1000, 2000, 4000)),
    ],
)
def test_convergence_order_on_a_heavy_top(method, order, counts) -> None:
    disk, q0, omega0 = heavy_top()
    g = [0.0, 0.0, -9.81]
    w_ref, _ = reference(disk, omega0, q0, 0.5, pivot=[0, 0, -0.1], gravity=g)
    errors = []
    for n in counts:
        run = tb.simulate(
            disk,
            omega0,
            attitude0=q0,
            duration=0.5,
            dt=0.5 / n,
            pivot=[0, 0, -0.1],
            gravity=g,
            method=method,
            record_every=n,
        )
        errors.append(np.max(np.abs(run.omega[-1] - w_ref)))
    # Halving dt divides the error by 2^order (within 12 %: the steps are in the
    # asymptotic range, and the errors stay far above the reference's ~4e-12).
    for coarse, fine in itertools.pairwise(errors):
        assert coarse / fine == pytest.approx(2.0**order, rel=0.12)


def test_splitting_beats_rk4_on_a_heavy_top_at_equal_step() -> None:
    # The free motion of the symmetric disk is exact in the splitting, so only
    # gravity's kicks err: at the same dt its error is far below RK4's.
    disk, q0, omega0 = heavy_top()
    w_ref, _ = reference(disk, omega0, q0, 0.5, pivot=[0, 0, -0.1], gravity=[0, 0, -9.81])
    errors = {}
    for method in ("splitting", "rk4"):
        run = tb.simulate(
            disk, omega0, attitude0=q0, duration=0.5, dt=2.5e-4, pivot=[0, 0, -0.1],
            gravity=[0, 0, -9.81], method=method, record_every=2000,
        )  # fmt: skip
        errors[method] = np.max(np.abs(run.omega[-1] - w_ref))
    assert errors["splitting"] < 0.05 * errors["rk4"]


def test_splitting_moves_a_free_symmetric_top_exactly_at_any_step() -> None:
    # Oblate and prolate: the splitting's free flow is exact for I1 = I2 or I2 = I3,
    # so one step of 0.7 s (a third of a turn) agrees with the closed form to
    # round-off (1e-13 after the quaternion products of 100 steps).
    for moments in ((1.0, 1.0, 1.7), (0.6, 1.0, 1.0)):
        body = tb.MassProperties(
            1.0, [0, 0, 0], AXES.as_matrix() @ np.diag(moments) @ AXES.as_matrix().T
        )
        kwargs = {"attitude0": Q0, "duration": 70.0, "dt": 0.7}
        with pytest.warns(CoarseStepWarning):  # 5 steps a turn: coarse for any other method
            split = tb.simulate(body, OMEGA0, method="splitting", **kwargs)
        exact = tb.simulate(body, OMEGA0, method="exact", **kwargs)
        assert np.max(np.abs(split.omega - exact.omega)) < 1e-13
        assert attitude_error(split.quaternion, exact.rotation.as_matrix()) < 1e-12


def test_splitting_keeps_l_to_round_off_and_energy_bounded_over_a_million_steps() -> None:
    # Torque-free asymmetric body, 1e6 Strang and Yoshida steps of 0.01 s (the
    # body turns ~0.01 rad a step; ~1600 flips). Every part of the splitting is
    # a rotation, so |L| and the space-frame L change only by round-off, a
    # random walk of ~1e-16 √(1e6 · 5) ≈ 2e-13. The energy error is that of a
    # symplectic method: O(dt²) (Strang) or O(dt⁴) (Yoshida) and not growing.
    for method, bound in (("strang", 1e-4), ("splitting", 1e-8)):
        run = tb.simulate(
            TUMBLER, [0.01, 2.0, 0.01], duration=1e4, dt=1e-2, method=method, record_every=1000
        )
        assert run.steps == 1_000_000
        norms = np.linalg.norm(run.angular_momentum, axis=1)
        assert np.max(np.abs(norms / norms[0] - 1)) < 1e-12
        assert run.drift["angular_momentum_vector"] < 1e-12
        error = np.abs(run.energy / run.energy[0] - 1)
        assert error.max() < bound
        # Bounded, not drifting: the last tenth is no worse than twice the first.
        tenth = len(error) // 10
        assert error[-tenth:].max() < 2 * error[:tenth].max() + 1e-15


def test_splitting_keeps_a_heavy_tops_energy_bounded_over_a_million_steps() -> None:
    # Gravity about a pivot is conservative: the symplectic splitting keeps the
    # energy error bounded and, gravity's torque being horizontal in every
    # kick, the vertical component of L exactly (to round-off).
    disk, q0, omega0 = heavy_top()
    run = tb.simulate(
        disk, omega0, attitude0=q0, duration=1000.0, dt=1e-3, pivot=[0, 0, -0.1],
        gravity=[0, 0, -9.81], method="splitting", record_every=500,
    )  # fmt: skip
    assert run.steps == 1_000_000
    energy = run.energy
    error = np.abs(energy - energy[0]) / abs(energy[0])
    # Yoshida-4 at dt = 1e-3 (nutation at ~190 rad/s, 0.19 rad a step): the
    # error oscillates at ~2e-11, well above round-off, so a drift would show.
    # Not growing: the last tenth of the run is no worse than twice the first.
    assert error.max() < 1e-9
    tenth = len(error) // 10
    assert error[-tenth:].max() < 2 * error[:tenth].max() + 1e-15
    lz = run.angular_momentum[:, 2]
    assert np.max(np.abs(lz - lz[0])) < 1e-11 * np.linalg.norm(run.angular_momentum[0])


def test_adaptive_error_follows_the_tolerance_and_dense_output_is_smooth() -> None:
    # Samples every 0.05 s fall between steps, so they come from the dense
    # output; its error (order 4) stays within a small multiple of the step's.
    times = np.linspace(0.0, 5.0, 101)
    w_ref, a_ref = reference(TUMBLER, OMEGA0, Q0, 5.0, torque=forcing_reference, times=times)
    previous = math.inf
    for rtol in (1e-6, 1e-8, 1e-10):
        run = tb.simulate(
            TUMBLER, OMEGA0, attitude0=Q0, duration=5.0, dt=0.05, torque=FORCING,
            method="adaptive", rtol=rtol, atol=rtol * 1e-2,
        )  # fmt: skip
        if rtol == 1e-6:  # fewer steps than samples: most samples are dense output
            assert run.steps < len(times) / 2
        error = np.max(np.abs(run.omega - w_ref))
        assert error < 100 * rtol
        assert attitude_error(run.quaternion, a_ref) < 100 * rtol
        assert error < previous
        previous = error


@numba.njit
def space_torque_function(t, omega, quaternion, params, out):
    # Aᵀ τ_space by the quaternion, written out: the same torque as ConstantSpaceTorque.
    w, x, y, z = quaternion[0], -quaternion[1], -quaternion[2], -quaternion[3]
    v0, v1, v2 = params[0], params[1], params[2]
    cx = y * v2 - z * v1
    cy = z * v0 - x * v2
    cz = x * v1 - y * v0
    out[0] = v0 + 2.0 * (w * cx + y * cz - z * cy)
    out[1] = v1 + 2.0 * (w * cy + z * cx - x * cz)
    out[2] = v2 + 2.0 * (w * cz + x * cy - y * cx)


@numba.njit
def body_torque_function(t, omega, quaternion, params, out):
    out[0] = params[0] - params[3] * omega[0]
    out[1] = params[1] - params[3] * omega[1]
    out[2] = params[2] - params[3] * omega[2]


@pytest.mark.parametrize("method", ["rk4", "strang", "splitting", "adaptive"])
def test_a_user_torque_equals_the_same_built_in_torque(method) -> None:
    # TUMBLER's body axes are not principal, so this also checks the hook's
    # change of frame (ω to body axes, q to body → space, τ back).
    built_in = (
        tb.torques.ConstantSpaceTorque([0.0, 0.03, -0.01])
        + tb.torques.ConstantBodyTorque([0.05, -0.02, 0.01])
        + tb.torques.LinearDamping(0.02)
    )
    user = tb.torques.UserTorque(space_torque_function, [0.0, 0.03, -0.01]) + (
        tb.torques.ConstantBodyTorque([0.05, -0.02, 0.01]) + tb.torques.LinearDamping(0.02)
    )
    alone = tb.torques.UserTorque(body_torque_function, [0.05, -0.02, 0.01, 0.02]) + (
        tb.torques.ConstantSpaceTorque([0.0, 0.03, -0.01])
    )
    kwargs = {"attitude0": Q0, "duration": 2.0, "dt": 1e-2, "method": method}
    expected = tb.simulate(TUMBLER, OMEGA0, torque=built_in, **kwargs)
    for model in (user, alone):
        run = tb.simulate(TUMBLER, OMEGA0, torque=model, **kwargs)
        # Same arithmetic up to the order of the sums: round-off (1e-16),
        # amplified by the flow over 2 s to ~5e-12 (1e-10 allowed); the adaptive
        # method may also pick slightly different steps: its tolerance, 1e-9.
        # In the splitting the damping moves from the exact decay into the kick
        # (first order within the kick) when it is in the user's function.
        bound = {"rk4": 1e-10, "adaptive": 1e-9}.get(method, 1e-12 if model is user else 1e-3)
        assert np.max(np.abs(run.omega - expected.omega)) < bound
    assert "UserTorque(space_torque_function" in repr(user)


@numba.njit
def oscillating_torque(t, omega, quaternion, params, out):
    out[2] = params[0] * math.sin(params[1] * t)


@pytest.mark.parametrize("method", ["rk4", "splitting", "adaptive"])
def test_a_time_dependent_user_torque_against_its_closed_form(method) -> None:
    # A sphere spun about z by τ = A sin(ν t): ω_z(t) = ω0 + A (1 − cos ν t) / (I ν).
    sphere = tb.shapes.solid_sphere(2.0, 0.1)  # I = 0.008 kg m²
    inertia = 0.4 * 2.0 * 0.1**2
    amplitude, rate = 0.01, 3.0
    run = tb.simulate(
        sphere, [0.0, 0.0, 1.0], duration=3.0, dt=1e-3, method=method, rtol=1e-13,
        torque=tb.torques.UserTorque(oscillating_torque, [amplitude, rate]),
    )  # fmt: skip
    expected = 1.0 + amplitude * (1 - np.cos(rate * run.t)) / (inertia * rate)
    # Fourth-order methods at dt = 1e-3 on a torque varying at 3 rad/s: ≪ 1e-10;
    # the adaptive method at rtol 1e-13 keeps its global error below 1e-10 too.
    assert np.max(np.abs(run.omega[:, 2] - expected)) < 1e-10
    assert np.max(np.abs(run.omega[:, :2])) < 1e-14


@numba.njit
def exploding_torque(t, omega, quaternion, params, out):
    out[0] = 1.0 / (params[0] - t)


def test_a_singular_torque_stops_the_adaptive_method_with_the_time() -> None:
    with pytest.raises(IntegrationError, match=r"step size below round-off at t = 1 s"):
        tb.simulate(
            TUMBLER, OMEGA0, duration=2.0, dt=0.1, method="adaptive",
            torque=tb.torques.UserTorque(exploding_torque, [1.0]),
        )  # fmt: skip


def plain_function(t, omega, quaternion, params, out):
    out[0] = 1.0


@numba.njit
def wrong_signature(t, omega):
    return t


def test_user_torque_errors() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"Expected `function` to be compiled with numba.njit, got function 'plain_function'",
    ):
        tb.torques.UserTorque(plain_function)
    with pytest.raises(
        tb.InputError,
        match=r"Expected `function\(t, omega, quaternion, params, out\)` to run on a test state \(t = 0, omega = 0, identity attitude\), got TypeError: too many arguments: expected 2, got 5",
    ):
        tb.torques.UserTorque(wrong_signature)
    one = tb.torques.UserTorque(body_torque_function, [0, 0, 0, 0])
    with pytest.raises(tb.InputError, match=r"Expected at most one UserTorque in a sum, got two"):
        _ = one + one


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rtol": 0.0}, r"Expected `rtol` > 0, got 0.0"),
        ({"atol": -1.0}, r"Expected `atol` > 0, got -1.0"),
        ({"rtol": float("nan")}, r"Expected `rtol` > 0, got nan"),
        ({"rtol": 1e-17}, r"Expected `rtol` >= 1e-15 \(round-off\), got 1e-17"),
    ],
)
def test_adaptive_tolerance_errors(kwargs, message) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(TUMBLER, OMEGA0, duration=1.0, method="adaptive", **kwargs)


@pytest.mark.parametrize("method", ["exact", "rk4"])
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rtol": -1}, r"^Expected `rtol` > 0, got -1\.$"),
        ({"atol": True}, r"^Expected `atol` > 0, got True\.$"),
        ({"rtol": "tight"}, r"^Expected `rtol` > 0, got 'tight'\.$"),
        (
            {"progress": 3},
            r"^Expected `progress` to be None or a function \(done, total\), got 3\.$",
        ),
    ],
)
def test_arguments_a_method_does_not_read_are_still_checked(method, kwargs, message) -> None:
    # A value that cannot be right is refused whichever method runs, not ignored.
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(TUMBLER, OMEGA0, duration=1.0, dt=0.01, method=method, **kwargs)


def test_progress_and_recording_for_the_adaptive_method() -> None:
    calls = []
    run = tb.simulate(
        TUMBLER, OMEGA0, duration=1.0, dt=1e-4, torque=FORCING, method="adaptive",
        record_every=7, progress=lambda done, total: calls.append((done, total)),
    )  # fmt: skip
    # 10000 sample steps kept every 7th: 1429 rows plus the final time.
    assert len(run.t) == 10000 // 7 + 2 and run.t[-1] == 1.0
    assert calls[-1] == (len(run.t) - 1, len(run.t) - 1)
    assert_allclose(np.diff(run.t[:-1]), 7e-4, rtol=1e-12)


def test_the_coarse_step_warning_knows_the_splitting_spins_a_symmetric_top_exactly() -> None:
    # The gyroscope disk spins at 200 rad/s (a turn in 31 ms) but its axis moves
    # at |L|/I⊥ ≈ 80 rad/s. dt = 3 ms is 10 steps a turn of the spin: coarse for
    # RK4, which must resolve it, but 26 steps a turn of the axis for the
    # splitting, whose free flow turns the symmetric disk exactly.
    disk = tb.shapes.thin_disk(1.0, 0.1)
    kwargs = {
        "attitude0": [math.sqrt(0.5), 0, math.sqrt(0.5), 0], "duration": 0.1, "dt": 3.0e-3,
        "pivot": [0, 0, -0.1], "gravity": [0, 0, -9.81],
    }  # fmt: skip
    with pytest.warns(
        CoarseStepWarning, match=r"steps per turn of the fastest rotation \(2\d\d rad/s\)"
    ):
        tb.simulate(disk, [0, 0, 200.0], method="rk4", **kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoarseStepWarning)
        tb.simulate(disk, [0, 0, 200.0], method="splitting", **kwargs)


def test_per_body_torque_values_belong_to_batches() -> None:
    many = tb.torques.ConstantBodyTorque([[0.1, 0, 0], [0, 0.1, 0]])
    with pytest.raises(
        tb.InputError,
        match=r"Expected one torque for one body, got per-body values \(ConstantBodyTorque\(per body, 2 vectors\)\): those are for simulate_batch",
    ):
        tb.simulate(TUMBLER, OMEGA0, duration=1.0, torque=many)
    with pytest.raises(
        tb.InputError,
        match=r"Expected per-body torque terms for the same number of bodies, got .*2 vectors.* and .*3 vectors",
    ):
        _ = many + tb.torques.ConstantBodyTorque(np.zeros((3, 3)) + 0.1)
    with pytest.raises(
        tb.InputError, match=r"Expected `coefficient` >= 0 N·m·s, got coefficient\[1\] = -0\.2\."
    ):
        tb.torques.LinearDamping([0.1, -0.2])


def test_the_exact_solution_needs_a_body_with_thickness() -> None:
    rod = tb.theory.free_motion(tb.shapes.thin_rod(1.0, 1.0), [1.0, 0.0, 0.0])
    with pytest.raises(
        tb.InputError, match=r"Expected a body with no zero principal moment, got moments \[0\.0, "
    ):
        rod.at(1.0)


def test_the_reason_says_when_kicks_are_first_order_in_the_torque() -> None:
    # A user torque may depend on ω: the splitting's kicks hold it, so the method is
    # first order in it (the damping test above measures it); linear damping is
    # integrated exactly by the kicks and gets no such note.
    kwargs = {"duration": 0.1, "dt": 1e-2, "method": "splitting"}
    user = tb.simulate(
        TUMBLER, OMEGA0, torque=tb.torques.UserTorque(body_torque_function, [0, 0, 0, 0.02]),
        **kwargs,
    )  # fmt: skip
    assert user.reason == (
        "requested (its kicks hold the torque, which depends on ω here: splitting is first "
        "order in it)"
    )
    damped = tb.simulate(TUMBLER, OMEGA0, torque=tb.torques.LinearDamping(0.02), **kwargs)
    assert damped.reason == "requested"
    assert tb.simulate(TUMBLER, OMEGA0, torque=FORCING, **{**kwargs, "method": "rk4"}).reason == (
        "requested"
    )
