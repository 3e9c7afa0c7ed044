"""The model registry: a model kind defined in this module alone — a torsion
pendulum, the body of ``[body]`` hung on a wire about its z axis — registered for
one test, runs from a scenario file with its own table, is compared by its own
theory check (a row and a panel) and written by the report, with no change to
tumble.

The pendulum (moment C about z, wire stiffness k in N·m/rad, damping c in
N·m·s) obeys C θ̈ + c θ̇ + k θ = 0: released at rest from θ0 it swings at the
damped frequency ω_d = √(k/C − (c/2C)²), as θ0 e^{−ζω_n t} (cos ω_d t +
(ζω_n/ω_d) sin ω_d t) with ω_n = √(k/C) and ζω_n = c/2C — the closed form the
check compares with.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble import scenario
from tumble.checks import (
    THEORY_CHECKS,
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    comparison_row,
    register_check,
)
from tumble.config import StrictModel
from tumble.core._jit import njit
from tumble.report import write_run
from tumble.scenario.bodies import Angle, scalar_field
from tumble.scenario.model_kinds import MODEL_KINDS, ModelKind, ModelRuns, Span, register_model_kind
from tumble.trajectory import Trajectory


@njit
def wire_torque(t, omega, quaternion, params, out):  # type: ignore[no-untyped-def]
    # About z only: θ the turn of the body about z, from its quaternion.
    angle = 2.0 * math.atan2(quaternion[3], quaternion[0])
    out[0] = 0.0
    out[1] = 0.0
    out[2] = -params[0] * angle - params[1] * omega[2]


class TorsionSettings(StrictModel):
    """``[test_torsion_pendulum]``: the wire's ``stiffness`` (N·m/rad) and
    ``damping`` (N·m·s), and the ``amplitude`` the body is released from."""

    stiffness: Annotated[float, scalar_field("torque", positive=True)]
    damping: Annotated[float, scalar_field("damping", non_negative=True)] = 0.0
    amplitude: Angle


class TorsionPendulum(ModelKind):
    table = "test_torsion_pendulum"
    settings = TorsionSettings
    summary = "the body hung on a torsion wire"
    check = "test-torsion-pendulum"
    notes = ("The wire's damping takes the energy away.",)

    def run(self, body: tb.MassProperties, settings: Any, span: Span, progress: Any) -> ModelRuns:
        wire = tb.torques.UserTorque(wire_torque, [settings.stiffness, settings.damping])
        start = Rotation.from_rotvec([0.0, 0.0, settings.amplitude]).as_quat(scalar_first=True)
        step = span.dt if span.dt is not None else 1e-3
        trajectory = tb.simulate(
            body,
            [0.0, 0.0, 0.0],
            attitude0=start,
            torque=wire,
            duration=span.duration,
            dt=step,
            method="rk4",
            record_every=max(1, round(span.duration / step / span.samples)),
            progress=progress,
        )
        options = {"stiffness": settings.stiffness, "damping": settings.damping}
        case = Case(body, trajectory.omega[0], trajectory.quaternion[0], options=options)
        return ModelRuns({"main": trajectory}, case)


def turn_about_z(trajectory: Trajectory) -> np.ndarray:
    """θ(t), rad: the body's turn about z."""
    q = trajectory.quaternion
    return 2.0 * np.arctan2(q[:, 3], q[:, 0])


class TorsionCheck(TheoryCheck):
    name = "test-torsion-pendulum"
    needs = "a torsion pendulum"

    def fits(self, case: Case) -> bool:
        return "stiffness" in case.options

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        moment = float(case.mass_properties.inertia[2, 2])
        k, c = case.options["stiffness"], case.options["damping"]
        decay = c / (2.0 * moment)
        frequency = math.sqrt(k / moment - decay**2)
        angle = turn_about_z(trajectory)
        t = trajectory.t
        # Zero crossings, linearly interpolated: half a period apart.
        k_cross = np.flatnonzero(np.sign(angle[:-1]) != np.sign(angle[1:]))
        crossings = t[k_cross] - angle[k_cross] * (t[k_cross + 1] - t[k_cross]) / (
            angle[k_cross + 1] - angle[k_cross]
        )
        measured = math.pi / float(np.mean(np.diff(crossings)))
        row = comparison_row("damped frequency ω_d", frequency, measured, "rad/s")
        theta0 = float(angle[0])
        closed = (
            theta0
            * np.exp(-decay * t)
            * (np.cos(frequency * t) + decay / frequency * np.sin(frequency * t))
        )
        panel = Panel(
            "Torsion pendulum: θ(t)",
            "θ (deg)",
            [
                Curve("simulation", t, np.degrees(angle)),
                Curve("closed form", t, np.degrees(closed), "theory"),
            ],
            name="torsion",
        )
        return Comparison([row], [panel])


@pytest.fixture
def pendulum() -> Iterator[None]:
    register_check(TorsionCheck())
    register_model_kind(TorsionPendulum())
    try:
        yield
    finally:
        del MODEL_KINDS["test_torsion_pendulum"]
        del THEORY_CHECKS["test-torsion-pendulum"]


TEXT = """
[scenario]
name = "torsion"
[body]
shape = "solid-cylinder"
mass = "2 kg"
radius = "10 cm"
height = "2 cm"
[test_torsion_pendulum]
stiffness = "0.04 N*m"
damping = "0.001 N*m*s"
amplitude = "20 deg"
[simulation]
duration = "10 s"
dt = "1 ms"
[output]
samples = 5000
viewer = false
"""


def test_a_model_kind_added_here_runs_from_a_scenario_file_with_its_row_and_panel(
    pendulum: None, tmp_path: Path
) -> None:
    result = scenario.run(scenario.parse(TEXT))
    assert result.theory == "test-torsion-pendulum"
    (row,) = result.comparisons
    # RK4 at 1 ms against a swing of 2 rad/s: its phase error (ω h)⁴/120 a radian
    # is ~1e-13, and linear interpolation of the crossings errs by O(θ''' h²/θ') ~
    # 1e-6 of a step each, averaged over ~12 crossings: 1e-6 is well above both,
    # and far below a wrong moment (a 1 % error of C moves ω_d by 0.5 %).
    assert row["relative_error"] < 1e-6, row
    moment = 0.5 * 2.0 * 0.1**2  # a solid cylinder about its axis, ½ m r²
    assert row["theory"] == pytest.approx(math.sqrt(0.04 / moment - (0.001 / (2 * moment)) ** 2))
    assert row["run"] == "main"
    assert [panel.name for panel in result.panels] == ["torsion"]
    assert result.notes[0] == "The wire's damping takes the energy away."
    folder = write_run(result, tmp_path / "run")
    assert (folder / "torsion.png").stat().st_size > 1000


def test_a_model_kind_added_here_has_its_table_checked(pendulum: None) -> None:
    with pytest.raises(
        scenario.ScenarioError, match=r"`test_torsion_pendulum\.stifness`.*stiffness"
    ):
        scenario.parse(TEXT.replace("stiffness =", "stifness ="))
    with pytest.raises(
        scenario.ScenarioError,
        match=r"Expected no \[initial\] with \[test_torsion_pendulum\] \(its model sets",
    ):
        scenario.parse(TEXT + '[initial]\nomega = "0, 0, 1 rad/s"\n')


def test_without_the_kind_its_table_is_an_unknown_key() -> None:
    with pytest.raises(scenario.ScenarioError, match=r"`test_torsion_pendulum`: Expected the key"):
        scenario.parse(TEXT)


def test_a_model_kind_may_not_take_a_table_of_every_file() -> None:
    class Clash(TorsionPendulum):
        table = "simulation"

    register_model_kind(Clash())
    try:
        with pytest.raises(
            ValueError,
            match=r"Expected the model kinds' tables to be named other than every file's tables "
            r"\(scenario, body, .*\), got 'simulation'\.",
        ):
            scenario.parse(TEXT)
    finally:
        del MODEL_KINDS["simulation"]
    with pytest.raises(
        ValueError, match=r"Expected a model kind's table to be an identifier, got 'a-b'\."
    ):
        register_model_kind(type("Dashed", (TorsionPendulum,), {"table": "a-b"})())
    assert "a-b" not in MODEL_KINDS
