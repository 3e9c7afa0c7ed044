"""The part registry: a part kind defined in this module alone — a viscous wheel,
a wheel on a body-fixed axis coupled to the body by a viscous torque (a
single-axis nutation damper) — registered for one test, runs in simulate,
simulate_batch, a scenario file, a sweep file and the report, and round-trips
through Parquet, with no change to tumble.

The wheel (axial moment J on the unit axis a, body axes; coupling c, N·m·s):
its axial momentum ``h = J (a·ω + Ω)`` (Ω its rate relative to the body) obeys
``ḣ = −c Ω``, the body's ``ω = I_p⁻¹ (H − h a)`` with ``I_p = I − J a aᵀ``, and
``Ḣ = −ω × H`` in body axes: an internal energy sink, like a Kane damper on
one axis. An independent integration of those equations (DOP853) is the oracle.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble import scenario
from tumble.core._jit import njit
from tumble.core.parts import PartEquations
from tumble.parameters import Parameter
from tumble.parts import PARTS, InternalPart, PartDrawing, register_part
from tumble.report import write_run
from tumble.trajectory import Trajectory

AXES = Rotation.from_rotvec([0.2, -0.4, 0.3])
BODY = tb.MassProperties(
    2.0, [0.0, 0.0, 0.0], AXES.as_matrix() @ np.diag([1.0, 1.6, 2.2]) @ AXES.as_matrix().T
)
OMEGA0 = np.array([0.4, 1.1, -0.3])
AXIS = np.array([0.0, 0.6, 0.8])
WHEEL_J, COUPLING = 0.08, 0.15


# ------------------------------------------------------------------ the part kind
@njit(inline="always")
def wheel_momentum(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    h = y[k]
    return h * parts[row, pc], h * parts[row + 1, pc], h * parts[row + 2, pc]


@njit(inline="always")
def wheel_rates(y, k, parts, row, rows, pc, w, v, hold):  # type: ignore[no-untyped-def]
    along = parts[row, pc] * w[0] + parts[row + 1, pc] * w[1] + parts[row + 2, pc] * w[2]
    return (-parts[row + 4, pc] * (y[k] / parts[row + 3, pc] - along),)


@njit(inline="always")
def wheel_energy(y, k, parts, row, rows, pc, w):  # type: ignore[no-untyped-def]
    # h Ω: its momentum times its rate relative to the body (PartEquations.energy).
    along = parts[row, pc] * w[0] + parts[row + 1, pc] * w[1] + parts[row + 2, pc] * w[2]
    return y[k] * (y[k] / parts[row + 3, pc] - along)


@dataclass(frozen=True, eq=False)
class ViscousWheel(InternalPart):
    """A wheel on a body-fixed axis, slowed against the body by a viscous torque."""

    axis: Any
    inertia: Any
    coupling: Any

    kind = "test-viscous-wheel"
    summary = "a wheel coupled to the body by a viscous torque"
    label = "wheel"
    size = 1
    value_labels = ("speed",)
    spin = 0
    parameters = (
        Parameter("axis", "dimensionless", (3,), "its axis, body axes"),
        Parameter("inertia", "inertia", (), "its axial moment J", 0.0, strict=True),
        Parameter("coupling", "damping", (), "the viscous coupling c", 0.0),
    )
    equations = PartEquations(momentum=wheel_momentum, rates=wheel_rates, energy=wheel_energy)

    def __post_init__(self) -> None:
        for parameter in self.parameters:
            object.__setattr__(
                self, parameter.name, parameter.convert(getattr(self, parameter.name), False)
            )
        object.__setattr__(self, "axis", self.axis / np.linalg.norm(self.axis))

    @property
    def dissipative(self) -> bool:
        return self.coupling > 0

    def spin_inertia(self) -> np.ndarray:
        return self.inertia * np.outer(self.axis, self.axis)

    def initial_values(self, omega0: np.ndarray) -> np.ndarray:
        return np.zeros((*np.shape(omega0)[:-1], 1))  # turning with the body

    def momenta(self, omega: np.ndarray, values: np.ndarray) -> np.ndarray:
        return self.inertia * (np.asarray(omega) @ self.axis + values[..., 0])[..., None]

    def momentum(self, omega: np.ndarray, values: np.ndarray) -> np.ndarray:
        return self.momenta(omega, values) * self.axis

    def kinetic_energy(self, omega: np.ndarray, values: np.ndarray) -> np.ndarray:
        rate = np.asarray(omega) @ self.axis + values[..., 0]
        return 0.5 * self.inertia * rate * rate

    def values_from(self, omega: np.ndarray, momenta: np.ndarray) -> np.ndarray:
        return (momenta[..., 0] / self.inertia - np.asarray(omega) @ self.axis)[..., None]

    def internal_rates(self, platform_inertia: np.ndarray) -> tuple[float, float]:
        smallest = float(np.linalg.eigvalsh(platform_inertia)[0])
        return self.coupling / self.inertia, self.coupling / smallest

    def pack(self, frame: Any, parts: tuple[InternalPart, ...]) -> list[Any]:
        turned = np.asarray(frame.to_principal(self.axis), dtype=float)
        return [*(turned[..., i] for i in range(3)), self.inertia, self.coupling]

    def drawing(
        self, reach: float, centre: np.ndarray, position: Any = None, radius: Any = None,
        thickness: Any = None,
    ) -> PartDrawing:  # fmt: skip
        return PartDrawing("disc", np.asarray(centre), 0.2 * reach, self.axis, 0.04 * reach, 0)


@pytest.fixture
def wheel() -> Iterator[type[ViscousWheel]]:
    register_part(ViscousWheel)
    yield ViscousWheel
    PARTS.pop(ViscousWheel.kind)


# ------------------------------------------------------------------ the oracle
def reference(duration: float, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ω (n, 3) and the wheel's relative speed (n,) by DOP853 of the module's
    equations in body axes (rtol 1e-12)."""
    platform = BODY.inertia - WHEEL_J * np.outer(AXIS, AXIS)
    inverse = np.linalg.inv(platform)

    def rates(t: float, state: np.ndarray) -> np.ndarray:
        h_body, h = state[:3], state[3]
        omega = inverse @ (h_body - h * AXIS)
        return np.array([*(-np.cross(omega, h_body)), -COUPLING * (h / WHEEL_J - AXIS @ omega)])

    start = np.array([*(BODY.inertia @ OMEGA0), WHEEL_J * (AXIS @ OMEGA0)])
    solution = solve_ivp(
        rates, (0.0, duration), start, "DOP853", t_eval=times, rtol=1e-12, atol=1e-14
    )
    states = solution.y.T
    omega = (states[:, :3] - states[:, 3:] * AXIS) @ inverse.T
    return omega, states[:, 3] / WHEEL_J - omega @ AXIS


# ------------------------------------------------------------------ the tests
def test_a_part_kind_added_here_runs_in_simulate(wheel: type[ViscousWheel]) -> None:
    part = wheel(AXIS, WHEEL_J, COUPLING)
    for method, tolerance in (("rk4", 1e-9), ("adaptive", 1e-8)):
        traj = tb.simulate(
            BODY, OMEGA0, internal=[part], duration=8.0, dt=1e-3, method=method, rtol=1e-11,
            atol=1e-13,
        )  # fmt: skip
        omega, speed = reference(8.0, traj.t)
        # RK4 at dt = 1 ms on rates of order 1/s: a global error ~(dt)⁴ ≈ 1e-12 per
        # unit time, well inside 1e-9; the adaptive method at rtol 1e-11 within 1e-8.
        assert np.max(np.abs(traj.omega - omega)) < tolerance
        assert np.max(np.abs(traj.rotor_speed[:, 0] - speed)) < tolerance
        # Internal torques keep the angular momentum (to round-off of the steps);
        # the viscous wheel only takes energy away.
        space = np.linalg.norm(traj.angular_momentum, axis=1)
        assert np.max(np.abs(space - space[0])) < 1e-12 * space[0]
        assert np.all(np.diff(traj.energy) <= 1e-15)
        assert traj.energy[-1] < 0.99 * traj.energy[0]
    # Its values have their columns; the splitting, which needs a kick, refuses it.
    assert traj.internal_values.shape == (traj.t.size, 1)
    with pytest.raises(tb.InputError, match=r"test-viscous-wheel parts"):
        tb.simulate(BODY, OMEGA0, internal=[part], duration=1.0, dt=0.01, method="splitting")


def test_a_part_kind_added_here_runs_in_simulate_batch(wheel: type[ViscousWheel]) -> None:
    part = wheel(AXIS, WHEEL_J, COUPLING)
    starts = OMEGA0 * np.array([[1.0], [0.5], [-1.5]])
    batch = tb.simulate_batch(
        np.tile(BODY.inertia, (3, 1, 1)), starts, duration=4.0, dt=1e-3, method="rk4",
        internal=[part],
    )  # fmt: skip
    for k, start in enumerate(starts):
        single = tb.simulate(BODY, start, internal=[part], duration=4.0, dt=1e-3, method="rk4")
        # The same steps in the same order, body by body: equal to round-off.
        assert_allclose(batch.omega[k], single.omega[-1], rtol=0, atol=1e-12)
        assert_allclose(batch.rotor_speed[k], single.rotor_speed[-1], rtol=0, atol=1e-12)


def test_a_part_kind_added_here_runs_in_a_scenario_file_and_the_report(
    wheel: type[ViscousWheel], tmp_path: Path
) -> None:
    text = f"""
        [scenario]
        name = "wheel"
        [body]
        mass = "2 kg"
        center_of_mass = [0, 0, 0]
        inertia = {BODY.inertia.tolist()}
        [initial]
        omega = {OMEGA0.tolist()}
        [[internal]]
        type = "test-viscous-wheel"
        axis = {AXIS.tolist()}
        inertia = "{WHEEL_J} kg*m^2"
        coupling = "{COUPLING} N*m*s"
        [simulation]
        duration = "4 s"
        dt = "1 ms"
        method = "rk4"
    """
    result = scenario.run(scenario.parse(text.replace("\n        ", "\n")))
    traj = result.trajectory
    omega, speed = reference(4.0, traj.t)
    assert np.max(np.abs(traj.omega - omega)) < 1e-9  # RK4 at 1 ms, as above
    assert np.max(np.abs(traj.rotor_speed[:, 0] - speed)) < 1e-9
    # A key the kind does not have is named, with the kind's own keys; one it
    # needs is asked for with what it is.
    bad = text.replace('coupling = "', 'couplng = "').replace("\n        ", "\n")
    with pytest.raises(scenario.ScenarioError, match=r"`internal\[0\]\.couplng`.*coupling"):
        scenario.parse(bad)
    missing = "\n".join(line for line in text.splitlines() if "coupling" not in line)
    with pytest.raises(
        scenario.ScenarioError,
        match=r"`internal\[0\]\.coupling`: Expected `coupling` \(the viscous coupling c\) for a "
        r"test-viscous-wheel, which is missing\.",
    ):
        scenario.parse(missing.replace("\n        ", "\n"))
    # The report draws the wheel, and the trajectory file keeps it: read back,
    # the part and its values are the same.
    folder = write_run(result, tmp_path / "run")
    assert "viewer.html" in {p.name for p in folder.iterdir()}
    back = Trajectory.read_parquet(folder / "trajectory.parquet")
    (read,) = back.internal
    assert isinstance(read, wheel)
    assert read.describe() == traj.internal[0].describe()
    assert_allclose(back.rotor_speed, traj.rotor_speed, rtol=0, atol=0)
    assert_allclose(back.energy, traj.energy, rtol=1e-14)


SWEEP = """
[sweep]
name = "wheels"
seed = 1
chunk_size = 2
[base]
duration = "6 s"
dt = "2 ms"
method = "rk4"
moment_1 = "1 kg*m^2"
ratio_3 = 2.2
spin_rate = "1 rad/s"
spin_axis = 2
perturbation = "10 deg"
[vary.ratio_2]
values = [1.3, 1.6, 1.9]
[[internal]]
type = "test-viscous-wheel"
axis = [0, 0.6, 0.8]
inertia = "0.08 kg*m^2"
coupling = "0.15 N*m*s"
[outputs]
metrics = ["flips", "max_nutation", "energy_drift", "momentum_drift"]
final_state = true
"""


def test_a_part_kind_added_here_runs_in_a_sweep_file(
    wheel: type[ViscousWheel], tmp_path: Path
) -> None:
    from tumble.sweep import open_results, run_sweep
    from tumble.sweep.build import parse_sweep
    from tumble.sweep.schema import SweepError

    path = tmp_path / "wheels.toml"
    path.write_text(SWEEP)
    run_sweep(path, tmp_path / "out")
    results = open_results(tmp_path / "out")
    part = wheel(AXIS, WHEEL_J, COUPLING)
    for k, ratio in enumerate([1.3, 1.6, 1.9]):
        mp = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, ratio, 2.2]))
        tilt = np.radians(10.0)
        start = np.array([0.0, np.cos(tilt), np.sin(tilt)])
        traj = tb.simulate(mp, start, internal=[part], duration=6.0, dt=2e-3, method="rk4")
        # The same steps as tb.simulate: equal to round-off; the energy drift against
        # the trajectory's energy, summed by the wheel's Python kinetic_energy.
        assert_allclose(results["final/omega"][k], traj.omega[-1], rtol=0, atol=1e-12)
        energy = traj.energy
        drift = np.max(np.abs(energy - energy[0])) / energy[0]
        assert_allclose(results["metrics/energy_drift"][k], drift, rtol=1e-9)
        assert drift > 1e-4  # the wheel dissipates: a drift far above round-off
    # A kind without its energy's equation runs every other measure, and refuses
    # the energy drift.
    quiet = ViscousWheel.equations._replace(energy=None)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(ViscousWheel, "equations", quiet)
        with pytest.raises(
            SweepError,
            match=r"`outputs\.metrics`: Expected parts whose energy can be measured for "
            r"`energy_drift`, got test-viscous-wheel parts, whose equations leave it out",
        ):
            parse_sweep(SWEEP)
        plan = parse_sweep(SWEEP.replace('"energy_drift", ', ""))
        from tumble.sweep.metrics import compute_chunk

        flips = compute_chunk(plan, 0)["metrics/flips"]
        assert_allclose(flips, results["metrics/flips"][:2])


def test_the_registry_refuses_an_incomplete_kind_and_names_the_known_ones() -> None:
    @dataclass(frozen=True, eq=False)
    class Nameless(InternalPart):
        size = 1
        value_labels = ("speed",)

    with pytest.raises(
        tb.InputError,
        match=r"^Expected a part kind with `kind`, `label`, `equations`, got Nameless without\.$",
    ):
        register_part(Nameless)

    @dataclass(frozen=True, eq=False)
    class Mislabelled(ViscousWheel):
        kind = "test-mislabelled"
        value_labels = ("speed", "angle")

    with pytest.raises(
        tb.InputError,
        match=r"^Expected 1 `value_labels` of Mislabelled \(its `size`\), got 2\.$",
    ):
        register_part(Mislabelled)
    assert "test-mislabelled" not in PARTS

    @dataclass(frozen=True, eq=False)
    class Undrawn(ViscousWheel):
        kind = "test-undrawn"
        drawing = InternalPart.drawing

    with pytest.raises(
        tb.InputError,
        match=r"^Expected a `drawing` of Undrawn, which spins \(`spin` = 0\): the viewer turns "
        r"a disc at its speed, got none\.$",
    ):
        register_part(Undrawn)
    # A trajectory file naming a kind that is not registered (here: this
    # module's wheel, outside its fixture) is refused with the known kinds.
    from tumble.parts import from_description

    with pytest.raises(
        tb.InputError,
        match=r"^Expected `type` to be one of kane-damper, spring-mass-damper, rotor, got "
        r"'test-viscous-wheel'\.",
    ):
        from_description({"type": "test-viscous-wheel", "axis": [0, 0, 1]})


def test_an_internal_table_without_a_type_names_the_kinds() -> None:
    text = '[scenario]\nname = "t"\n[body]\nshape = "solid-sphere"\nmass = 1\nradius = 1\n[[internal]]\ninertia = 0.1\n'
    with pytest.raises(
        scenario.ScenarioError,
        match=r"`internal\[0\]\.type`: Expected `type` \(kane-damper, spring-mass-damper, rotor\), "
        r"which is missing\.",
    ):
        scenario.parse(text + "[simulation]\nduration = 1\n")
