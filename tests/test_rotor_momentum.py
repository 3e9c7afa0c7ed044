"""Rotors of prescribed relative momentum (tumble.torques.RotorMomentum): against
an independent integration and the gyrostat's closed forms, in batches with one
momentum per body, and the dual-spin stability map of the sweeps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from tumble.sweep import show_sweep
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import compute_chunk

AXES = Rotation.from_rotvec([0.3, -0.2, 0.5])
BODY = tb.MassProperties(
    10.0, [0.1, 0, 0], AXES.as_matrix() @ np.diag([4.0, 6.0, 8.0]) @ AXES.as_matrix().T
)
H0 = np.array([0.5, 3.0, -1.0])
RATE = np.array([0.02, -0.01, 0.03])


def test_it_follows_an_independent_integration_of_the_gyrostat() -> None:
    # I ω̇ = −ω × (I ω + h) − ḣ, h = h0 + ḣ t, in body axes with the full tensor
    # (DOP853 at rtol 1e-13); the adaptive method at rtol 1e-12 over 30 s: 1e-10.
    model = tb.torques.RotorMomentum(H0, RATE)
    q0 = Rotation.from_rotvec([0.2, 0.1, 0.4]).as_quat(scalar_first=True)
    run = tb.simulate(BODY, [0.3, 0.8, -0.2], attitude0=q0, duration=30.0, dt=0.1,
                      torque=model, rtol=1e-12, atol=1e-14)  # fmt: skip

    def gyroscopic(t: float, w: np.ndarray, a: np.ndarray) -> np.ndarray:
        return -np.cross(w, H0 + RATE * t) - RATE

    omega, matrices = reference(BODY, [0.3, 0.8, -0.2], q0, 30.0, torque=gyroscopic, times=run.t)
    assert np.max(np.abs(run.omega - omega)) < 1e-10
    assert attitude_error(run.quaternion, matrices) < 1e-10
    assert run.method == "adaptive" and run.conserved_quantities == ()


def test_with_a_constant_momentum_the_energy_and_the_total_momentum_stay() -> None:
    # −ω × h does no work; I ω + h is fixed in space. RK4 at 10 ms, |ω| ~ 1, over
    # 50 s: the energy to ~1e-12 (its error is of higher order), the direction of
    # the attitude, hence of H in space, to ~1e-10 relative: 1e-9 asked.
    run = tb.simulate(BODY, [0.3, 0.8, -0.2], duration=50.0, dt=0.01, method="rk4",
                      torque=tb.torques.RotorMomentum(H0))  # fmt: skip
    assert run.conserved_quantities == ("energy",)
    assert run.drift["energy"] < 1e-11
    total = run.angular_momentum + run.rotation.apply(H0)
    assert np.max(np.abs(total - total[0])) < 1e-9 * np.linalg.norm(total[0])


def test_the_nutation_of_a_dual_spin_body_is_the_closed_form_s() -> None:
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))
    run = tb.simulate(body, [1e-3, 1.0, 0.0], duration=100.0, dt=0.01, method="rk4",
                      torque=tb.torques.RotorMomentum([0.0, 4.0, 0.0]))  # fmt: skip
    expected = tb.theory.gyrostat_stability(body, 1.0, 4.0, axis=(0, 1, 0)).nutation_frequency
    # Between maxima refined by parabolas over ~10 periods: 1e-6.
    measured = tb.analysis.oscillation_frequency(run.t, run.omega[:, 0])
    assert measured == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("method", ["rk4", "splitting"])
def test_one_momentum_per_body_in_a_batch_equals_separate_runs(method: str) -> None:
    # The same arithmetic body by body (FMA contraction in the vectorised
    # kernel: round-off), 1e-12.
    moments = np.array([[4.0, 6.0, 8.0], [1.0, 1.5, 2.0], [2.0, 2.5, 4.0]])
    omega0 = np.array([[1e-3, 1.0, 0.0], [0.1, 0.5, 0.2], [0.3, -0.2, 0.4]])
    momentum = np.array([[0.0, 4.0, 0.0], [0.2, 0.0, -0.5], [1.0, 1.0, 1.0]])
    batch = tb.simulate_batch(moments, omega0, duration=10.0, dt=0.01, method=method,
                              torque=tb.torques.RotorMomentum(momentum))  # fmt: skip
    for k in range(3):
        alone = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])), omega0[k], duration=10.0,
            dt=0.01, method=method, torque=tb.torques.RotorMomentum(momentum[k]),
        )  # fmt: skip
        assert_allclose(batch.omega[k], alone.omega[-1], rtol=0, atol=1e-12)


def test_the_dual_spin_map_tumbles_inside_the_theory_s_wedge() -> None:
    # The shipped map on a 21 × 21 grid: where the linear theory says unstable
    # with a growth fast enough to reach π from 1° within the run (γ T > ln(π/1°)
    # + 2), the largest nutation passes 15°; where it says stable with a margin
    # (P / (I1 I3) > 0.05: a nutation amplitude at most ~a few times the 1° start)
    # it stays below 10°.
    text = show_sweep("dual-spin-map").replace("num = 121", "num = 21")
    plan = parse_sweep(text)
    result = compute_chunk(plan, 0)
    ratio = result["parameters/ratio_2"]
    h = result["parameters/rotor_momentum_2"]
    product = (h - (2.0 - ratio)) * (h + (ratio - 1.0))
    growth = np.sqrt(np.maximum(-product, 0.0) / 2.0)
    nutation = np.degrees(result["metrics/max_nutation"])
    tumbling = growth * plan.duration > math.log(math.pi / math.radians(1.0)) + 2.0
    steady = product / 2.0 > 0.05
    assert tumbling.sum() > 50 and steady.sum() > 200
    assert np.all(nutation[tumbling] > 15.0)
    assert np.all(nutation[steady] < 10.0)
    for k in np.flatnonzero(steady)[:3]:
        assert tb.theory.gyrostat_stability(
            tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, ratio[k], 2.0])), 1.0, h[k],
            axis=(0, 1, 0),
        ).stable  # fmt: skip


def test_its_values_are_checked() -> None:
    with pytest.raises(tb.InputError, match=r"`momentum`"):
        tb.torques.RotorMomentum("2 kg")
    with pytest.raises(
        tb.InputError, match=r"Expected one torque for one body, got per-body values"
    ):
        tb.simulate(BODY, [0, 0, 1], duration=1.0,
                    torque=tb.torques.RotorMomentum(np.ones((4, 3))))  # fmt: skip


def test_a_model_leaves_the_caller_s_array_writable() -> None:
    values = np.array([0.5, 3.0, -1.0])
    model = tb.torques.RotorMomentum(values)
    values[0] = 7.0  # still the caller's to change; the model keeps its own copy
    assert model.momentum[0] == 0.5 and not model.momentum.flags.writeable
