"""The Drake adapter of tumble.conformance, against Drake itself and the exact motion."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tumble as tb
from conformance_checks import convention_errors, read_back_error
from tumble.conformance.engine import EngineBody, Samples
from tumble.conformance.engines.drake_engine import DrakeEngine
from tumble.conformance.scenarios import SCENARIOS

pytest.importorskip("pydrake")

MOMENTS = np.array([1.0, 2.0, 3.0])
BODY_123 = EngineBody(mass=1.0, moments=MOMENTS)
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])
EXACT_123 = tb.MassProperties(1.0, [0, 0, 0], np.diag(MOMENTS))


def run(variant: str, omega0: np.ndarray, dt: float, steps: int, every: int) -> Samples:
    """Samples of the body (1, 2, 3) kg·m² from ω0 (body axes) at the identity attitude."""
    engine = DrakeEngine(variant)
    engine.build(BODY_123, dt)
    samples = engine.simulate(BODY_123, IDENTITY, omega0, dt, steps, every)
    engine.close()
    return samples


def omega_error(samples: Samples, omega0: np.ndarray) -> float:
    """Largest |ω - ω_exact| over the run, relative to |ω0|."""
    exact, _ = tb.theory.free_motion(EXACT_123, omega0).at(samples.t)
    return float(np.max(np.linalg.norm(samples.omega - exact, axis=1)) / np.linalg.norm(omega0))


def energy_drift(samples: Samples) -> float:
    """Signed relative change of the kinetic energy from the first sample to the last."""
    energy = 0.5 * np.einsum("ij,j,ij->i", samples.omega, MOMENTS, samples.omega)
    return float(energy[-1] / energy[0] - 1.0)


@pytest.mark.parametrize("variant", list(DrakeEngine.variants))
def test_drake_angular_velocity_is_in_world_axes(variant: str) -> None:
    # Drake keeps a free body's V_WB in world axes. Over one step of 1e-4 s the rate read
    # back differs from the finite-differenced one by O(|ω|² dt) ≈ 1e-3 relative at most
    # (measured 5e-5 continuous, 6e-9 discrete, whose update turns the attitude by exactly
    # the new ω·dt); body axes would be off by O(1) (measured 0.81).
    declared, other = convention_errors(DrakeEngine(variant))
    assert declared < 2e-3
    assert other > 0.1


@pytest.mark.parametrize("variant", list(DrakeEngine.variants))
@pytest.mark.parametrize(
    "body",
    [
        EngineBody(mass=2.0, moments=np.array([0.3, 0.5, 0.7])),
        EngineBody(
            0.7, np.array([0.02, 0.02, 0.03]), np.array([0, 0, -0.1]), np.array([0, 0, -9.81])
        ),
    ],
    ids=["free", "pivot"],
)
def test_drake_reads_back_the_given_inertia(variant: str, body: EngineBody) -> None:
    # Drake stores the mass and the unit inertia (inertia / mass): one rounding each way.
    mass_error, inertia_error = read_back_error(DrakeEngine(variant), body)
    assert mass_error < 1e-12
    assert inertia_error < 1e-12


def test_drake_default_integrator_is_error_controlled_rk3() -> None:
    # The continuous variant says it runs the Simulator's default integrator: check that it is.
    engine = DrakeEngine("continuous")
    engine.build(BODY_123, 1e-3)
    integrator = engine.simulator.get_integrator()
    assert type(integrator).__name__ == "RungeKutta3Integrator"
    assert not integrator.get_fixed_step_mode()
    assert integrator.get_target_accuracy() == pytest.approx(1e-4)
    engine.close()


def test_drake_discrete_gains_energy_at_first_order() -> None:
    # A discrete plant without contact takes semi-implicit Euler steps: first order, and
    # gaining energy on the fast intermediate-axis tumble (measured over 1 s: ω error 0.067,
    # 0.033, 0.017 and energy +4.8 %, +2.3 %, +1.2 % at dt = 2e-3, 1e-3, 5e-4). Halving dt
    # must halve both within 10 % (order 1 ± 0.15).
    omega0 = np.array([0.1, 20.0, 0.1])
    errors, drifts = [], []
    for dt in (2e-3, 1e-3, 5e-4):
        steps = round(1.0 / dt)
        samples = run("discrete", omega0, dt, steps, steps // 50)
        assert samples.failure == ""
        errors.append(omega_error(samples, omega0))
        drifts.append(energy_drift(samples))
    assert all(drift > 0.005 for drift in drifts)
    for values in (errors, drifts):
        for coarse, fine in itertools.pairwise(values):
            assert 1.8 < coarse / fine < 2.2


def test_drake_continuous_keeps_its_accuracy() -> None:
    # On its own steps, the error-controlled RK3 at accuracy 1e-4 follows the slow flip for
    # 5 s to ~1e-3 of |ω0| with energy ~1e-5 (measured); bounds at a few times those, far
    # below the discrete plant's 2e-3 and 2e-4 at dt = 1e-3.
    omega0 = np.array([0.01, 2.0, 0.01])
    samples = run("continuous", omega0, 1e-3, 5000, 100)
    assert omega_error(samples, omega0) < 5e-3
    assert abs(energy_drift(samples)) < 3e-5


def test_drake_continuous_does_not_depend_on_how_often_the_suite_samples() -> None:
    # The continuous plant runs the whole horizon in one AdvanceTo, sampled after each of
    # its integrator's own steps, whatever the suite's sampling: the same state, bit for
    # bit, at 2 s, asked for every step or every 200 steps.
    omega0 = np.array([0.1, 20.0, 0.1])
    dense = run("continuous", omega0, 1e-3, 2000, 1)
    sparse = run("continuous", omega0, 1e-3, 2000, 200)
    np.testing.assert_array_equal(dense.omega[-1], sparse.omega[-1])
    np.testing.assert_array_equal(dense.quaternion[-1], sparse.quaternion[-1])


@pytest.mark.parametrize("variant, bound", [("continuous", 2e-3), ("discrete", 0.1)])
def test_drake_holds_the_heavy_top(variant: str, bound: float) -> None:
    # The Lagrange top on a BallRpyJoint, against its exact motion over 5 s at dt = 1e-3:
    # measured attitude error 3.5e-4 rad (continuous, at accuracy 1e-4) and 0.037 rad
    # (discrete, first order at 30 rad/s of spin); bounds at about 3 times those.
    scenario = SCENARIOS["heavy-top"]
    body = scenario.body
    quaternion0, omega0 = scenario.initial_state
    engine = DrakeEngine(variant)
    engine.build(body, 1e-3)
    samples = engine.simulate(body, quaternion0, omega0, 1e-3, 5000, 50)
    pose = engine.plant.EvalBodyPoseInWorld(engine.context, engine.body)
    pivot_in_space = pose.translation() + pose.rotation().matrix() @ np.asarray(body.pivot)
    engine.close()
    _, exact = scenario.reference(samples.t)
    turned = Rotation.from_quat(samples.quaternion, scalar_first=True).inv()
    attitude_error = (turned * Rotation.from_quat(exact, scalar_first=True)).magnitude()
    assert samples.failure == ""
    assert np.max(attitude_error) < bound
    np.testing.assert_allclose(pivot_in_space, 0.0, atol=1e-12)


def test_drake_discrete_blows_up_silently() -> None:
    # The stable major-axis spin under the discrete plant tilts, flips after about half a
    # minute and goes non-finite (at 36 s at dt = 1e-3) without Drake raising anything: the
    # adapter has nothing to report, and the non-finite state is left for the suite to see.
    engine = DrakeEngine("discrete")
    engine.build(BODY_123, 1e-3)
    engine.set_state(IDENTITY, np.array([0.1, 0.0, 20.0]))
    engine.step(40_000)
    quaternion, omega = engine.state()
    assert engine.failure() == ""
    assert not np.all(np.isfinite(quaternion)) and not np.all(np.isfinite(omega))
    assert engine.simulator.get_num_unrestricted_updates() == 40_000
    engine.close()


def test_drake_reports_the_integrator_giving_up() -> None:
    # An absurd spin makes the error-controlled integrator fail to find a step; Drake raises
    # and the adapter reports what it said, then stops stepping.
    engine = DrakeEngine("continuous")
    engine.build(BODY_123, 1e-3)
    engine.set_state(IDENTITY, np.full(3, 1e150))
    engine.step(10)
    assert engine.failure().startswith("Drake raised: Error control wants to select step")
    engine.step(10)
    assert engine.steps_done == 10  # the steps after the failure do nothing
    engine.close()


def test_drake_s_default_integrator_miscounts_flips_of_a_fast_tumble() -> None:
    # Its own error control (accuracy 1e-4) loses the phase of the fast tumble: over 20 s
    # it counts 26 sign changes of ω2 where the exact motion has 18 (measured), half as
    # many again; the discrete plant counts right but gains 59 % of the energy.
    result = tb.conformance.run(["drake"], "intermediate-fast", dt=1e-3, duration=20.0)
    table = result.table.set_index("engine")
    continuous = table.loc["drake/continuous"]
    assert continuous["flips_exact"] == 18
    assert continuous["flips"] >= 23
    assert abs(continuous["energy_drift_final"]) < 1e-2
    assert table.loc["drake/discrete", "flips"] == 18
    assert 0.3 < table.loc["drake/discrete", "energy_drift_final"] < 0.9
