"""The Rapier adapter of tumble.conformance against Rapier itself and tumble's exact motions."""

from __future__ import annotations

import numpy as np
import pytest

rapier3d = pytest.importorskip("rapier3d")

from scipy.spatial.transform import Rotation  # noqa: E402

import tumble as tb  # noqa: E402
from conformance_checks import BODY as CHECK_BODY  # noqa: E402
from conformance_checks import convention_errors, read_back_error  # noqa: E402
from tumble.conformance.engine import ENGINES, EngineBody, Samples, rotation  # noqa: E402
from tumble.conformance.engines.rapier_engine import RapierEngine  # noqa: E402
from tumble.errors import InputError  # noqa: E402

VARIANTS = list(RapierEngine.variants)
#: I = (1, 2, 3) kg·m², 1 kg: the body of the named torque-free scenarios.
MOMENTS = np.array([1.0, 2.0, 3.0])
BODY = EngineBody(mass=1.0, moments=MOMENTS)
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])
#: The "intermediate-slow" start: near the intermediate axis, rad/s.
INTERMEDIATE_SLOW = np.array([0.01, 2.0, 0.01])
#: A slow tumble, every rate below Rapier's default sleep threshold (0.5 rad/s).
SLOW_TUMBLE = np.array([0.01, 0.02, 0.01])
#: The heavy top of the "heavy-top" scenario: pivot 0.1 m below the centre of mass on
#: the symmetry axis, tilted 0.3 rad, spinning at 30 rad/s, g = 9.81 m/s² downwards.
TOP_MOMENTS = np.array([0.05, 0.05, 0.08])
TOP_PIVOT = np.array([0.0, 0.0, -0.1])
TOP = EngineBody(1.0, TOP_MOMENTS, pivot=TOP_PIVOT, gravity=np.array([0.0, 0.0, -9.81]))
TOP_ATTITUDE = Rotation.from_rotvec([0.3, 0.0, 0.0]).as_quat(scalar_first=True)
TOP_OMEGA = np.array([0.0, 0.0, 30.0])


def run(
    variant: str,
    body: EngineBody,
    omega0: np.ndarray,
    dt: float,
    duration: float,
    every: int = 10,
    q0: np.ndarray = IDENTITY,
) -> Samples:
    """Rapier's samples of ``body`` from ω0 (body axes) over ``duration`` s at ``dt``."""
    engine = RapierEngine(variant)
    engine.build(body, dt)
    samples = engine.simulate(body, q0, np.asarray(omega0, float), dt, round(duration / dt), every)
    engine.close()
    return samples


def energy_drift(samples: Samples, moments: np.ndarray = MOMENTS) -> float:
    """Relative change of the kinetic energy from the first sample to the last."""
    energy = 0.5 * np.sum(moments * samples.omega**2, axis=1)
    return float((energy[-1] - energy[0]) / energy[0])


def omega_error(samples: Samples, omega0: np.ndarray) -> float:
    """Largest |ω - ω_exact| over the samples, relative to |ω0|."""
    exact, _ = tb.theory.free_motion(
        tb.MassProperties(1.0, [0, 0, 0], np.diag(MOMENTS)), omega0
    ).at(samples.t)
    return float(np.max(np.linalg.norm(samples.omega - exact, axis=1)) / np.linalg.norm(omega0))


def test_registered_as_a_float32_engine_with_space_rates():
    assert ENGINES["rapier"] is RapierEngine
    assert set(VARIANTS) == {"", "sleeping"}
    assert RapierEngine.precision == "float32"
    assert RapierEngine.modules == ("rapier3d",)


@pytest.mark.parametrize("variant", VARIANTS)
def test_angular_velocity_is_in_space_axes(variant):
    # At dt = 1e-3 the rate finite-differenced over one step differs from the end-of-step
    # ω by |ω̇| dt / 2 ≈ 4.4e-4 of |ω| for this body, and the float32 attitude adds a few
    # ulps (1.2e-7 rad) divided by |ω| dt ≈ 2.7e-3: 1.8e-4; measured 3.6e-4 in all.
    # (At the default dt = 1e-4 the round-off term alone is ten times larger.)
    declared, other = convention_errors(RapierEngine(variant), dt=1e-3)
    assert declared < 2e-3
    assert other > 0.1


@pytest.mark.parametrize("variant", VARIANTS)
def test_mass_and_inertia_read_back(variant):
    # Rapier stores float32: each value within half an ulp, 2**-24 ≈ 6e-8 relative
    # (measured 0 for the mass, 1.9e-8 for the inertia); 1e-6 leaves room and still
    # catches any wrong moment or axis.
    mass_error, inertia_error = read_back_error(RapierEngine(variant))
    assert mass_error < 1e-6
    assert inertia_error < 1e-6


def test_inertia_is_stored_in_float32():
    engine = RapierEngine()
    engine.build(CHECK_BODY, 1e-3)
    _, inertia = engine.inertia()
    engine.close()
    # 0.3 is not a float32: what Rapier holds is its float32 neighbour, not 0.3.
    assert inertia[0, 0] == float(np.float32(0.3))
    assert inertia[0, 0] != 0.3
    assert np.count_nonzero(inertia - np.diag(np.diag(inertia))) == 0


def test_energy_gain_grows_as_the_step_shrinks():
    # Rapier's gyroscopic step rotates ω into body axes and back in float32 in each of its
    # 4 substeps, and |ω| comes out larger by about an ulp each time: a fixed gain per
    # step, so 10 times as many steps gain 10 times the energy, where a consistent
    # float64 scheme would lose its error as dt shrinks. Over 2 s on "intermediate-slow":
    # measured +1.74e-3 at dt = 1e-3 and +1.83e-2 at 1e-4 (ratio 10.5).
    coarse = energy_drift(run("", BODY, INTERMEDIATE_SLOW, 1e-3, 2.0, every=100))
    fine_samples = run("", BODY, INTERMEDIATE_SLOW, 1e-4, 2.0, every=1000)
    fine = energy_drift(fine_samples)
    assert 1e-3 < coarse < 3e-3
    assert 7.0 < fine / coarse < 14.0
    # The error against the exact motion is that growth of |ω| (E ∝ |ω|², so its
    # relative ω error is half the energy drift; measured 0.50), not a wrong motion.
    assert omega_error(fine_samples, INTERMEDIATE_SLOW) / fine == pytest.approx(0.5, abs=0.2)


def test_sleeping_variant_follows_a_fast_tumble():
    # Above the sleep thresholds the defaults run the same integration as the plain
    # variant: ω within 8.7e-4 of |ω0| of the exact motion over 2 s at dt = 1e-3 (the
    # float32 gain of 1.7e-3 in energy, halved); 2e-3 allows twice that.
    samples = run("sleeping", BODY, INTERMEDIATE_SLOW, 1e-3, 2.0, every=100)
    assert samples.failure == ""
    assert omega_error(samples, INTERMEDIATE_SLOW) < 2e-3


def test_sleeping_variant_reports_the_body_put_to_sleep():
    # Rapier puts a body to sleep once its rates stay below the thresholds for
    # `time_until_sleep` (0.5 s by default, read from Rapier itself) and zeroes its rates.
    dt = 1e-3
    engine = RapierEngine("sleeping")
    engine.build(BODY, dt)
    samples = engine.simulate(BODY, IDENTITY, SLOW_TUMBLE, dt, 2000, 10)
    _, omega = engine.state()
    engine.close()
    asleep_after = rapier3d.RigidBodyActivation().time_until_sleep
    assert samples.failure.startswith("put to sleep at t = ")
    slept_at = float(samples.failure.removeprefix("put to sleep at t = ").removesuffix(" s"))
    assert slept_at == pytest.approx(asleep_after, abs=2 * dt)
    assert slept_at <= samples.failed_at < slept_at + 10 * dt
    assert np.all(omega == 0.0)
    assert engine.notes == []


def test_plain_variant_keeps_a_slow_tumble_going():
    # Sleeping turned off: the slow tumble runs its 2 s and stays on the exact motion
    # (measured 8.7e-4 of |ω0|, the float32 gain).
    engine = RapierEngine()
    engine.build(BODY, 1e-3)
    samples = engine.simulate(BODY, IDENTITY, SLOW_TUMBLE, 1e-3, 2000, 100)
    engine.close()
    assert "sleeping turned off" in engine.notes
    assert samples.failure == ""
    assert samples.t[-1] == pytest.approx(2.0)
    assert omega_error(samples, SLOW_TUMBLE) < 2e-3


@pytest.mark.parametrize(("variant", "capped"), [("", False), ("sleeping", True)])
def test_spin_cap_is_off_in_the_plain_variant(variant, capped):
    # Rapier's defaults clamp a step's rotation to π/4 (kept for its collision
    # detection): at dt = 0.05 s a 20 rad/s spin about a principal axis (no gyroscopic
    # change) would turn 1 rad, so the defaults cut it to π/4 / dt = 15.7 rad/s.
    dt = 0.05
    engine = RapierEngine(variant)
    engine.build(BODY, dt)
    engine.set_state(IDENTITY, np.array([0.0, 0.0, 20.0]))
    engine.step(1)
    _, omega = engine.state()
    engine.close()
    expected = np.pi / 4 / dt if capped else 20.0
    # float32 rates: 1e-5 relative is a hundred ulps.
    assert omega[2] == pytest.approx(expected, rel=1e-5)


@pytest.mark.parametrize("variant", VARIANTS)
def test_quarantine_of_a_non_finite_state_is_reported(variant):
    # Rapier resets a body whose state is not finite to its last pose, at rest, and
    # disables it: the run must stop with Rapier's reason, not read a body at rest.
    engine = RapierEngine(variant)
    engine.build(BODY, 1e-3)
    assert engine.failure() == ""
    engine.set_state(IDENTITY, np.array([np.nan, 0.0, 0.0]))
    engine.step(3)
    assert engine.failure() == (
        "Rapier quarantined the body (its state became non-finite) by t = 0.003 s"
    )
    engine.close()


def test_heavy_top_follows_the_exact_lagrange_top():
    # Against the exact Lagrange top over 1 s: measured attitude errors 4.6e-3 rad at
    # dt = 1e-3 and 4.2e-2 rad at 1e-4 (the float32 gain again, ten times the steps),
    # and the pivot held to 3e-8 m at 1e-3 (float32 positions of about 0.1 m: an ulp is
    # 7e-9 m). Bounds: twice the error, the ratio within 5 to 15, the pivot to 1e-6 m.
    top = tb.theory.gyroscope(
        tb.MassProperties(1.0, [0, 0, 0], np.diag(TOP_MOMENTS)),
        TOP_PIVOT,
        omega0=TOP_OMEGA,
        attitude0=TOP_ATTITUDE,
        gravity=9.81,
    )

    def attitude_error(dt: float) -> tuple[float, float]:
        """The largest attitude error over 1 s (rad) and where the pivot ends (m)."""
        engine = RapierEngine()
        engine.build(TOP, dt)
        samples = engine.simulate(TOP, TOP_ATTITUDE, TOP_OMEGA, dt, round(1.0 / dt), 50)
        q, _ = engine.state()
        centre = np.array(engine._rigid_body().translation.to_tuple())
        engine.close()
        assert samples.failure == ""
        _, exact = top.at(samples.t)
        error = (rotation(exact).inv() * rotation(samples.quaternion)).magnitude()
        return float(np.max(error)), float(np.linalg.norm(centre + rotation(q).apply(TOP_PIVOT)))

    coarse, pivot = attitude_error(1e-3)
    fine, _ = attitude_error(1e-4)
    assert coarse < 1e-2
    assert 5.0 < fine / coarse < 15.0
    assert pivot < 1e-6


def test_unknown_variant_is_refused():
    with pytest.raises(InputError, match="variant of rapier"):
        RapierEngine("float64")
