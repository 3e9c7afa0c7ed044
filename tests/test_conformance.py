"""tumble.conformance: scenarios, metrics, the registry, run and sweep, against exact answers."""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import ClassVar

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.conformance import ENGINES, Engine, EngineBody, Scenario, register_engine
from tumble.conformance.engine import engine_class
from tumble.conformance.metrics import attitude_errors, energies, flip_count, momenta
from tumble.conformance.running import chosen_engines, observed_order, safe_step
from tumble.errors import InputError


# -- a user engine, written as the recipe says -------------------------------------------
class ExactRotation(Engine):
    """A user's engine: steps the exact torque-free motion (tumble's closed form), so its
    errors are round-off; variants that misbehave on purpose test the suite's checks."""

    name = "exact-test"
    variants: ClassVar[dict[str, str]] = {
        "": "the exact motion, stepped",
        "heavy": "reads back an inertia 1 % larger than given",
        "nan": "goes non-finite after 0.505 s",
    }
    modules = ("numpy",)

    def build(self, body: EngineBody, dt: float) -> None:
        self.body, self.dt, self.time = body, dt, 0.0

    def inertia(self) -> tuple[float, np.ndarray]:
        scale = 1.01 if self.variant == "heavy" else 1.0
        return self.body.mass, scale * self.body.inertia

    def set_state(self, quaternion: np.ndarray, omega: np.ndarray) -> None:
        mp = tb.MassProperties(self.body.mass, np.zeros(3), self.body.inertia)
        self.motion = tb.theory.free_motion(mp, omega, quaternion)

    def step(self, count: int) -> None:
        self.time += count * self.dt

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        omega, quaternion = self.motion.at(self.time)
        if self.variant == "nan" and self.time > 0.505:
            omega = omega * np.nan
        return quaternion, omega


@pytest.fixture
def user_engine() -> Iterator[type[Engine]]:
    register_engine(ExactRotation)
    yield ExactRotation
    del ENGINES[ExactRotation.name]


# -- scenarios ---------------------------------------------------------------------------
@pytest.mark.parametrize("name", tb.conformance.scenario_names())
def test_each_scenario_s_reference_starts_at_its_initial_state(name: str) -> None:
    scenario = tb.conformance.get_scenario(name)
    quaternion0, omega0 = scenario.initial_state
    omega, quaternion = scenario.reference(np.array([0.0]))
    # The closed forms start from the given state up to round-off (1e-12 of |ω0|).
    assert np.allclose(omega[0], omega0, atol=1e-12 * np.linalg.norm(omega0))
    assert attitude_errors(quaternion, quaternion0[None])[0] < 1e-12


@pytest.mark.parametrize("name", tb.conformance.scenario_names())
def test_each_scenario_s_reference_conserves_energy_and_momentum(name: str) -> None:
    # Oracle: conservation laws; the closed forms hold them to round-off (1e-12 relative),
    # an integration would not.
    scenario = tb.conformance.get_scenario(name)
    times = np.linspace(0.0, scenario.duration, 501)
    omega, quaternion = scenario.reference(times)
    energy = energies(scenario.body, quaternion, omega)
    momentum = momenta(scenario.body, quaternion, omega)
    assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-11
    conserved = momentum if scenario.pivot is None else momentum[:, 2:]  # about a pivot, L_z
    assert np.max(np.abs(conserved - conserved[0])) < 1e-11 * np.linalg.norm(momentum[0])


def test_the_named_scenarios_are_the_ones_the_suite_documents() -> None:
    scenarios = tb.conformance.SCENARIOS
    assert np.array_equal(scenarios["intermediate-slow"].omega0, [0.01, 2.0, 0.01])
    assert np.array_equal(scenarios["intermediate-fast"].omega0, [0.1, 20.0, 0.1])
    assert np.array_equal(scenarios["major-spin"].omega0, [0.1, 0.0, 20.0])
    assert np.array_equal(scenarios["minor-spin"].omega0, [20.0, 0.0, 0.1])
    for name in ("intermediate-slow", "intermediate-fast", "major-spin", "minor-spin"):
        assert np.array_equal(scenarios[name].moments, [1.0, 2.0, 3.0])
        assert scenarios[name].duration == 20.0


def test_a_user_scenario_with_a_full_tensor_runs_in_its_principal_axes() -> None:
    # A body with products of inertia: the engines get its principal moments, and the
    # state they start from is the same motion: the same energy and the same L in space.
    axes = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()
    tensor = axes @ np.diag([1.0, 2.0, 3.0]) @ axes.T
    omega0 = np.array([0.5, 1.0, -2.0])
    attitude = Rotation.from_rotvec([0.1, 0.7, -0.4])
    scenario = Scenario(tensor, omega0, 5.0, attitude0=attitude.as_quat(scalar_first=True))
    quaternion, omega = scenario.initial_state
    assert np.allclose(scenario.moments, [1.0, 2.0, 3.0], atol=1e-12)
    assert np.isclose(
        0.5 * omega @ np.diag(scenario.moments) @ omega, 0.5 * omega0 @ tensor @ omega0
    )
    momentum = Rotation.from_quat(quaternion, scalar_first=True).apply(scenario.moments * omega)
    assert np.allclose(momentum, attitude.apply(tensor @ omega0), atol=1e-12)


def test_scenario_accepts_units() -> None:
    scenario = Scenario("1000, 2000, 3000 g*m^2", "0, 0, 60 rpm", "2 min")
    assert np.allclose(scenario.moments, [1.0, 2.0, 3.0])
    assert np.allclose(scenario.omega0, [0.0, 0.0, 2.0 * np.pi])
    assert scenario.duration == 120.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"duration": 0.0}, r"Expected `duration` .*|Expected a duration > 0 s, got 0.0"),
        ({"duration": -1.0}, r"Expected a duration > 0 s, got -1.0"),
        ({"omega0": (1.0, 2.0)}, r"Expected `omega0` to have shape \(3,\), got \(2,\)"),
        ({"inertia": (1.0, 1.0, 3.0)}, r"triangle"),
        ({"pivot": (0.0, 0.0, -0.1)}, r"Expected gravity > 0 m/s² with a pivot, got 0.0"),
    ],
)
def test_scenario_refusals(kwargs: dict[str, object], match: str) -> None:
    values: dict[str, object] = {"inertia": (1.0, 2.0, 3.0), "omega0": (0.0, 1.0, 0.0)}
    values.update(kwargs)
    with pytest.raises(InputError, match=match):
        Scenario(**values)  # type: ignore[arg-type]


def test_an_unknown_scenario_is_refused_with_the_names() -> None:
    with pytest.raises(
        InputError, match=r"Expected the scenario to be one of intermediate-slow, .*got 'major'"
    ):
        tb.conformance.run(["tumble/rk4"], "major")


# -- metrics -----------------------------------------------------------------------------
def test_attitude_errors_are_the_angles_scipy_measures() -> None:
    rng = np.random.default_rng(3)
    exact = Rotation.random(50, random_state=rng)
    angles = np.concatenate([np.geomspace(1e-9, 1.0, 25), np.linspace(1.0, np.pi, 25)])
    turned = exact * Rotation.from_rotvec(
        angles[:, None] * Rotation.random(50, random_state=rng).apply([1, 0, 0])
    )
    measured = attitude_errors(turned.as_quat(scalar_first=True), exact.as_quat(scalar_first=True))
    # Oracle: scipy's magnitude of the relative rotation; the chord formula keeps small
    # angles to ~1e-16 absolute where arccos of a dot product would give ~1e-8.
    assert np.allclose(measured, angles, rtol=1e-9, atol=1e-15)
    # The sign of a quaternion is no rotation.
    minus = attitude_errors(-turned.as_quat(scalar_first=True), exact.as_quat(scalar_first=True))
    assert np.allclose(minus, measured, atol=1e-15)


def test_flips_count_sign_changes_and_skip_round_off_at_zero() -> None:
    assert flip_count(np.array([1.0, 0.5, -0.5, -1.0, 0.2]), 1.0) == 2
    assert flip_count(np.array([1e-17, -0.1, -0.2, 0.0, -0.3]), 1.0) == 0
    assert flip_count(np.array([0.0, 0.0]), 1.0) == 0


def test_heavy_top_energy_includes_gravity_s_potential() -> None:
    # The pivot 0.1 m below the centre of mass, the axis tilted θ from up: the centre of
    # mass is 0.1 cos θ above the pivot, so U = m g 0.1 cos θ.
    body = tb.conformance.SCENARIOS["heavy-top"].body
    tilt = 0.3
    quaternion = Rotation.from_rotvec([tilt, 0.0, 0.0]).as_quat(scalar_first=True)[None]
    energy = energies(body, quaternion, np.zeros((1, 3)))
    assert np.isclose(energy[0], 1.0 * 9.81 * 0.1 * np.cos(tilt), rtol=1e-14)


# -- the registry ------------------------------------------------------------------------
def test_the_registry_names_every_engine_and_variant_the_suite_promises() -> None:
    names = tb.conformance.engine_names()
    for name in (
        "mujoco/euler",
        "mujoco/rk4",
        "mujoco/implicit",
        "mujoco/implicitfast",
        "pybullet",
        "pybullet/undamped",
        "pybullet/maximal",
        "drake/continuous",
        "drake/discrete",
        "dart",
        "rapier",
        "scipy/dop853",
        "scipy/rk45",
        "tumble/rk4",
        "tumble/splitting",
    ):
        assert name in names


def test_plain_engine_names_mean_its_default_or_every_variant() -> None:
    assert chosen_engines("mujoco") == [
        "mujoco/euler",
        "mujoco/rk4",
        "mujoco/implicit",
        "mujoco/implicitfast",
    ]
    assert chosen_engines(["pybullet"]) == ["pybullet"]
    assert chosen_engines("pybullet/*")[:2] == ["pybullet", "pybullet/undamped"]


@pytest.mark.parametrize(
    ("name", "match"),
    [
        (
            "mujoco/rk5",
            r"Expected the engine to be one of .*got 'mujoco/rk5'. Did you mean mujoco/rk4\?",
        ),
        ("bullet", r"Expected the engine to be one of .*got 'bullet'"),
    ],
)
def test_an_unknown_engine_is_refused(name: str, match: str) -> None:
    with pytest.raises(InputError, match=match):
        tb.conformance.run([name], "major-spin", duration=0.1)


def test_an_adapter_needs_a_name_and_variants() -> None:
    class Nameless(Engine):
        variants: ClassVar[dict[str, str]] = {"": "x"}

    class Variantless(Engine):
        name = "variantless"

    with pytest.raises(
        InputError, match=r"Expected an engine adapter with a `name` without '/', got Nameless"
    ):
        register_engine(Nameless)
    with pytest.raises(
        InputError, match=r"Expected an engine adapter with `variants`, got none in Variantless"
    ):
        register_engine(Variantless)
    with pytest.raises(InputError, match=r"Expected the variant of mujoco to be one of euler, rk4"):
        engine_class("mujoco/euler")("rk2")


def test_an_engine_that_is_not_installed_is_skipped_with_the_extra_named() -> None:
    class Missing(Engine):
        name = "missing-test"
        variants: ClassVar[dict[str, str]] = {"": "needs a module nobody has"}
        modules = ("no_such_engine_module",)

    register_engine(Missing)
    try:
        result = tb.conformance.run(["missing-test", "tumble/rk4"], "major-spin", duration=0.1)
    finally:
        del ENGINES["missing-test"]
    assert list(result.table["engine"]) == ["tumble/rk4"]
    assert result.skipped == {
        "missing-test": "not installed: no_such_engine_module (pip install 'tumble[engines]')"
    }


# -- run and sweep -----------------------------------------------------------------------
def test_a_user_engine_stepping_the_exact_motion_has_round_off_errors(
    user_engine: type[Engine],
) -> None:
    result = tb.conformance.run(["exact-test"], "intermediate-fast", dt=1e-2, duration=5.0)
    row = result.table.iloc[0]
    # The engine is the closed form itself: every error is round-off (1e-12 relative; the
    # attitude, after turning ~100 rad, 1e-11 rad: its time is summed step by step).
    for column in ("energy_drift_max", "momentum_drift_max", "omega_error_max"):
        assert abs(row[column]) < 1e-12, column
    assert row["attitude_error_max"] < 1e-11
    # ω2 changes sign twice a flip period (2.196 s): at 0.55, 1.65, ... s, 5 times in 5 s.
    assert row["flips"] == row["flips_exact"] == 5
    assert np.isnan(row["failed_at"]) and row["failure"] == ""


def test_an_engine_that_reads_back_another_inertia_is_refused(user_engine: type[Engine]) -> None:
    result = tb.conformance.run(["exact-test/heavy", "exact-test"], "major-spin", duration=0.5)
    assert list(result.table["engine"]) == ["exact-test"]
    assert result.skipped["exact-test/heavy"].startswith(
        "refused: it uses mass 1 kg and inertia [[1.01"
    )
    assert "not the 1 kg and diag(1.0, 2.0, 3.0) given" in result.skipped["exact-test/heavy"]


def test_a_run_that_goes_non_finite_reports_when(user_engine: type[Engine]) -> None:
    result = tb.conformance.run(["exact-test/nan"], "major-spin", dt=1e-2, duration=2.0)
    row = result.table.iloc[0]
    # Sampled every step (200 steps < 2000 samples): the first state after 0.505 s fails.
    assert row["failed_at"] == pytest.approx(0.51)
    assert row["failure"] == "the state is not finite"


def test_tumble_s_own_methods_against_the_exact_motion() -> None:
    result = tb.conformance.run(
        ["tumble/rk4", "tumble/splitting"], "major-spin", dt=1e-3, duration=2.0
    )
    table = result.table.set_index("engine")
    # Fourth-order methods at |ω| dt = 0.02: errors ~ (0.02)^4 × 40 rad ≈ 1e-5 at most;
    # measured ~1e-9. The bound keeps a factor 100 for other machines' round-off.
    assert (table["attitude_error_max"] < 1e-7).all()
    assert (table["flips"] == table["flips_exact"]).all()
    assert result.reference_seconds > 0 and result.engine_seconds > 0


def test_scipy_at_its_default_tolerances_drifts() -> None:
    # scipy's defaults (rtol 1e-3) are what a hand-written simulation gets: RK45 drifts
    # by far more than tumble's RK4 (measured: 3e-2 against 2e-10 over 20 s).
    result = tb.conformance.run(
        ["scipy/rk45", "tumble/rk4"], "intermediate-fast", dt=1e-3, duration=20.0
    )
    drift = result.table.set_index("engine")["energy_drift_max"].abs()
    assert drift["scipy/rk45"] > 1e-3
    assert drift["tumble/rk4"] < 1e-8


@pytest.mark.parametrize(
    ("dt", "duration", "match"),
    [
        (0.0, 1.0, r"Expected dt > 0 s, got 0.0"),
        (-1e-3, 1.0, r"Expected dt > 0 s, got -0.001"),
        (2.0, 1.0, r"Expected dt no longer than the duration 1 s, got 2 s"),
        (1e-9, 1.0, r"Expected at most 20,000,000 steps \(duration / dt\), got 1,000,000,000"),
        (1e-3, -1.0, r"Expected a duration > 0 s, got -1.0"),
        ("1 kg", 1.0, r"Expected `dt` to be a time in s, got 1 kg"),
    ],
)
def test_steps_that_cannot_work_are_refused_before_any_run(
    dt: object, duration: float, match: str
) -> None:
    with pytest.raises(InputError, match=match):
        tb.conformance.run(["tumble/rk4"], "major-spin", dt=dt, duration=duration)


def test_sweep_order_and_safe_step_of_tumble_s_integrators() -> None:
    # Oracle: the methods' orders (RK4 4, Strang 2) on a smooth motion.
    result = tb.conformance.sweep(
        ["tumble/rk4", "tumble/strang"], "intermediate-slow", [0.02, 0.01, 0.005], 5.0
    )
    table = result.table.drop_duplicates("engine").set_index("engine")
    assert table.loc["tumble/rk4", "order"] == pytest.approx(4.0, abs=0.3)
    assert table.loc["tumble/strang", "order"] == pytest.approx(2.0, abs=0.2)
    # RK4 is within 1e-6 at every step of the sweep (measured: 1e-8 at 0.02 s), Strang
    # never (1.5e-4 at 0.02 s).
    assert table.loc["tumble/rk4", "safe_dt"] == 0.02
    assert np.isnan(table.loc["tumble/strang", "safe_dt"])


def test_order_and_safe_step_from_rows() -> None:
    rows = [
        {
            "dt": dt,
            "omega_error_max": 3.0 * dt**2,
            "failed_at": np.nan,
            "energy_drift_max": dt**2,
            "attitude_error_max": dt**2,
        }
        for dt in (1e-1, 1e-2, 1e-3, 1e-4)
    ]
    # Errors above 0.1 are left out; the rest lie on a line of slope 2.
    assert observed_order(rows) == pytest.approx(2.0, abs=1e-12)
    assert safe_step(rows, 1e-5) == 1e-3
    rows[0]["failed_at"] = 1.0
    assert safe_step(rows, 1.0) == 1e-2
    assert np.isnan(observed_order(rows[:1]))


def test_native_output_is_kept_off_the_terminal_and_reported(
    capfd: pytest.CaptureFixture[str],
) -> None:
    # What native code writes to file descriptors 1 and 2 (as an engine's C++ does)
    # lands in the capture, colour codes dropped from its first line, not on the terminal.
    from tumble.conformance.engine import NativeOutput

    output = NativeOutput()
    with output:
        os.write(2, b"\x1b[1;33mWarning\x1b[0m non-finite acceleration\n")
        os.write(1, b"banner\n")
    assert output.lines == ["\x1b[1;33mWarning\x1b[0m non-finite acceleration", "banner"]
    assert output.first == "Warning non-finite acceleration"
    with output:
        pass
    assert output.lines == [] and output.first == "Warning non-finite acceleration"
    output.reset()
    assert output.first == ""
    output.close()
    os.write(2, b"after\n")
    assert capfd.readouterr().err == "after\n"
