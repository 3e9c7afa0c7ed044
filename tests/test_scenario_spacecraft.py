"""Scenario files of bodies with rotors and dampers, in orbit and under control:
the ``[[internal]]`` tables and their errors, and the four built-in scenarios
(dual spin, Explorer 1, gravity gradient, reaction-wheel slew) against theory."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import scenario_tools
import tumble as tb
from scenario_tools import rows
from tumble.report import write_run
from tumble.scenario import ScenarioError, builtin_text, parse, run

DUAL = builtin_text("dual-spin")
SLEW = builtin_text("reaction-wheel-slew")


def edited(old: str, new: str, text: str = DUAL) -> str:
    return scenario_tools.edited(old, new, text)


# ------------------------------------------------------------------ the built-ins
def test_dual_spin_is_stable_with_its_rotor_and_flips_without() -> None:
    result = run("dual-spin")
    table = rows(result)
    # The nutation of the stable spin: measured between maxima over 300 s of
    # the exact solution (a rotor on a principal axis), against the linearised
    # theory; the finite amplitude and the sampling leave ~1e-8: 1e-6.
    assert table["nutation frequency with the rotors"]["relative_error"] < 1e-6
    # The growth without the rotor: fitted over its linear stage (10× the start
    # to 5 % of the spin), where the decaying mode and nonlinear terms leave ~1e-3.
    assert table["growth rate of the wobble without them"]["relative_error"] < 1e-3
    assert set(result.runs) == {"main", "without-rotors"}
    main = result.trajectory
    assert main.method == "exact"
    assert max(result.drift.values()) < 1e-12  # energy and L: the closed form keeps both
    assert np.min(main.omega[:, 1]) > 0.49  # no flip
    assert np.min(result.runs["without-rotors"].omega[:, 1]) < -0.49  # flipped
    assert_allclose(main.rotor_speed[:, 0], 100 * 2 * math.pi / 60, rtol=1e-3)


def test_explorer_1_ends_in_a_flat_spin_with_its_energy_at_the_minimum() -> None:
    result = run("explorer-1")
    table = rows(result)
    # Linear growth of the nutation fitted from 2× its start to 0.1 rad: ~1e-3.
    assert table["growth rate of the nutation"]["relative_error"] < 1e-3
    # After ~8 time constants of the final decay, the energy is |H|²/(2 I_max) to 1e-5.
    assert table["energy at the end: |H|² / (2 I_max)"]["relative_error"] < 1e-5
    assert table["|H| / (I_max |ω|) at the end"]["relative_error"] < 1e-3
    traj = result.trajectory
    assert traj.energy[0] / traj.energy[-1] > 100  # the flat spin holds a hundredth of it
    assert result.drift.keys() == {"angular_momentum_vector"}
    assert result.drift["angular_momentum_vector"] < 1e-6  # the adaptive method at rtol 1e-10


def test_gravity_gradient_pitches_at_the_pendulum_frequency() -> None:
    result = run("gravity-gradient")
    # The large-swing pitch frequency (an elliptic integral) to the measurement's
    # ~1e-8 (maxima refined by parabolas over five orbits).
    assert rows(result)["pitch libration frequency"]["relative_error"] < 1e-6
    small = tb.theory.gravity_gradient_libration(result.trajectory.mass_properties, 1.078007613e-3)
    assert small.region == "Lagrange"
    assert rows(result)["pitch libration frequency"]["theory"] < small.pitch_frequency


def test_in_a_reversed_orbit_the_pitch_turns_over_and_no_libration_is_compared() -> None:
    # The orbit normal reversed: the body, still turning at n about +z, turns at
    # −2n relative to the orbiting frame, past the pitch pendulum's separatrix
    # (θ̇² ≥ ω_p² with ω_p = n √(3 (B − A) / C) < √3 n): the pitch goes round.
    text = builtin_text("gravity-gradient").replace(
        "orbit_normal = [0, 0, 1]", "orbit_normal = [0, 0, -1]"
    )
    result = run(parse(text, "gravity-gradient.toml"))
    assert "pitch libration frequency" not in rows(result)
    (panel,) = [p for p in result.panels if p.name == "libration"]
    assert panel.title.endswith("; the pitch turns over, past its separatrix)")
    (pitch,) = [c for c in panel.curves if c.label.startswith("pitch")]
    assert np.max(np.abs(pitch.values)) > 170.0  # degrees: all the way round
    assert not any(c.style == "theory" for c in panel.curves)


def test_the_reaction_wheel_slew_reaches_its_target_with_l_kept() -> None:
    result = run("reaction-wheel-slew")
    assert rows(result)["decay rate of the pointing error"]["relative_error"] < 1e-3
    traj = result.trajectory
    assert result.drift["angular_momentum_vector"] < 1e-12
    # The torque limit (0.1 N·m) bounds how fast the z wheel spins up.
    speeds = traj.rotor_speed[:, 2]
    rate = np.diff(speeds) / np.diff(traj.t)
    j = 0.5 * 2.0 * 0.1**2
    assert np.max(np.abs(rate)) < 0.1 / j * (1 + 1e-9) + 0.1 / 20.0
    assert np.max(np.abs(traj.rotor_speed[-1])) < 1e-3  # the wheels stop with the body


def test_a_run_folder_holds_the_extra_run_and_the_rotor_figure(tmp_path) -> None:
    result = run(parse(edited('duration = "300 s"', 'duration = "120 s"'), source="d.toml"))
    folder = write_run(result, tmp_path / "dual")
    names = {path.name for path in folder.iterdir()}
    assert {"trajectory-without-rotors.parquet", "rotors.png", "dual-spin.png"} <= names
    page = (folder / "viewer.html").read_text()
    assert '"rotors":[{' in page and "rotor 1" in page
    back = tb.Trajectory.read_parquet(folder / "trajectory.parquet")
    assert back.rotor_speed.shape == (len(back.t), 1)


def test_the_viewer_wants_one_drawing_per_rotor() -> None:
    from tumble.report.viewer import viewer_data

    traj = tb.simulate(tb.shapes.box(1.0, [0.3, 0.4, 0.5]), [0.1, 0.2, 0.3], duration=1.0,
                       dt=0.1, internal=[tb.Rotor([0, 0, 1], 1e-3, speed=5.0)])  # fmt: skip
    with pytest.raises(ValueError, match=r"^Expected 1 rotor drawings, got 0\.$"):
        viewer_data(traj, rotors=[])


# ------------------------------------------------------------------ [[internal]]
def test_a_rotor_given_by_its_inertia_is_already_in_the_body() -> None:
    # The same wheel as a 20 kg disc in [[body.parts]] and given by its J: the
    # same motion as the dual-spin scenario, where tumble adds the disc.
    given = edited(
        '''[body]
shape = "box"
mass = "300 kg"
size = "1.2, 1.0, 0.8 m"''',
        """[[body.parts]]
shape = "box"
mass = "300 kg"
size = "1.2, 1.0, 0.8 m"

[[body.parts]]
shape = "solid-cylinder"
mass = "20 kg"
radius = "30 cm"
height = "6 cm"
rotation = { axis = [1, 0, 0], angle = "90 deg" }""",
    )
    given = edited(
        '''mass = "20 kg"
radius = "30 cm"
thickness = "6 cm"''',
        '''inertia = "0.9 kg*m^2"''',
        given,
    )
    given = edited('duration = "300 s"', 'duration = "20 s"', given)
    added = edited('duration = "300 s"', 'duration = "20 s"')
    a, b = run(parse(given)).trajectory, run(parse(added)).trajectory
    assert_allclose(a.mass_properties.inertia, b.mass_properties.inertia, rtol=1e-12, atol=1e-12)
    assert_allclose(a.omega, b.omega, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'type = "rotor"',
            'type = "roter"',
            r"d\.toml, line 25, `internal\[0\]\.type`: Expected `type` to be one of kane-damper, spring-mass-damper, rotor, got 'roter'\. Did you mean rotor\?",
        ),
        (
            "axis = [0, 1, 0]",
            "axis = [0, 0, 0]",
            r"d\.toml, line 24, `internal\[0\]`: Expected `axis` of a Rotor to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            "axis = [0, 1, 0]\n",
            "",
            r"`internal\[0\]\.axis`: Expected `axis` \(the rotor's spin axis, body axes\), which is missing\.",
        ),
        (
            'mass = "20 kg"',
            'mass = "-20 kg"',
            r"`internal\[0\]\.mass`: Expected `mass` > 0 kg, got -20\.0\.",
        ),
        (
            'mass = "20 kg"',
            'inertia = "-1 kg*m^2"',
            r"`internal\[0\]\.inertia`: Expected `inertia` > 0",
        ),
        (
            'mass = "20 kg"',
            'inertia = "1 kg*m^2"\nmass = "20 kg"',
            r"`internal\[0\]\.inertia`: Expected either `inertia` \(a rotor already in \[body\]\) or `mass` and `radius` \(a uniform one tumble adds\), got both\.",
        ),
        (
            'radius = "30 cm"\n',
            "",
            r"`internal\[0\]\.radius`: Expected `radius` with `mass`, which is missing\.",
        ),
        (
            'mass = "20 kg"\nradius = "30 cm"\n',
            "",
            r"`internal\[0\]\.inertia`: Expected either `inertia` \(a rotor already in \[body\]\) or `mass` and `radius` \(a uniform one tumble adds\), got neither\.",
        ),
        (
            'speed = "100 rpm"',
            'speed = "100 m"',
            r"`internal\[0\]\.speed`: Expected `speed` to be an angular velocity in rad/s",
        ),
        (
            'speed = "100 rpm"',
            'speed = "100 rpm"\ndamping = 1',
            r"`internal\[0\]\.damping`: Expected no `damping` for a rotor, got one\.",
        ),
        (
            'speed = "100 rpm"',
            'speed = "100 rpm"\ntorque = [[1, 0.1], [0.5, 0]]',
            r"`internal\[0\]`: Expected `torque` of a Rotor as \(time, torque\) pairs with increasing times, got times \[1\.0, 0\.5\] s\.",
        ),
        (
            'speed = "100 rpm"',
            'speed = "100 rpm"\nmax_speed = "-5 rpm"',
            r"`internal\[0\]\.max_speed`: Expected `max_speed` > 0 rad/s",
        ),
        (
            'speed = "100 rpm"',
            'speed = "100 rpm"\nspeeed = 1',
            r"`internal\[0\]\.speeed`: Expected the key to be one of .*, got 'speeed'\. Did you mean speed\?",
        ),
        (
            'mass = "20 kg"\nradius = "30 cm"',
            'inertia = "60 kg*m^2"',
            r"`internal`: Expected internal parts whose spin inertia the body can hold",
        ),
    ],
)
def test_bad_internal_parts_name_the_key_and_line(old: str, new: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        run(parse(edited(old, new), source="d.toml"))


def test_a_damper_needs_its_damping_and_takes_no_axis() -> None:
    base = builtin_text("explorer-1")
    with pytest.raises(
        ScenarioError,
        match=r"`internal\[0\]\.damping`: Expected `damping` \(the fluid's viscous coupling D, "
        r"N·m·s\), which is missing\.",
    ):
        parse(edited('damping = "3.5e-3 N*m*s"\n', "", base))
    with pytest.raises(
        ScenarioError,
        match=r"`internal\[0\]\.axis`: Expected no `axis` for a kane-damper, got one\.",
    ):
        parse(
            edited('damping = "3.5e-3 N*m*s"', 'damping = "3.5e-3 N*m*s"\naxis = [0, 0, 1]', base)
        )
    with pytest.raises(
        ScenarioError,
        match=r"`internal\[0\]\.damping`: Expected `damping` >= 0 N·m·s, got -1\.0\.",
    ):
        run(parse(edited('damping = "3.5e-3 N*m*s"', "damping = -1", base)))


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'actuator = "rotors"',
            'actuator = "wheels"',
            r"`torques\[0\]\.actuator`: Expected `actuator` to be one of external, rotors, got 'wheels'\.",
        ),
        (
            'stiffness = "0.41 N*m"',
            'stiffness = "-0.41 N*m"',
            r"`torques\[0\]\.stiffness`: Expected `stiffness` > 0 N·m, got -0\.41\.",
        ),
        (
            "target = [0.8660254037844387, 0, 0, 0.5]",
            "target = [0, 0, 0, 0]",
            r"`torques\[0\]`: Expected `target` to be a non-zero quaternion",
        ),
    ],
)
def test_bad_controller_values_name_the_key(old: str, new: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        run(parse(edited(old, new, SLEW), source="s.toml"))


def test_a_damper_refuses_the_splitting_with_the_key_named() -> None:
    base = builtin_text("explorer-1")
    with pytest.raises(
        ScenarioError,
        match=r"`internal`: Expected a method that integrates a body carrying kane-damper parts \(auto, rk4, adaptive\), got 'splitting'",
    ):
        run(parse(edited('method = "auto"', 'method = "splitting"', base)))


def test_an_orbit_rate_of_zero_is_refused_with_its_key() -> None:
    base = builtin_text("gravity-gradient")
    with pytest.raises(
        ScenarioError,
        match=r"`torques\[0\]\.orbit_rate`: Expected `orbit_rate` > 0 rad/s, got 0\.0\.",
    ):
        parse(edited('orbit_rate = "1.078007613e-3 rad/s"', "orbit_rate = 0", base))


def test_internal_parts_are_refused_with_a_gyrocompass() -> None:
    base = builtin_text("gyrocompass")
    extra = '\n[[internal]]\ntype = "kane-damper"\ninertia = 1e-4\ndamping = 0.1\n'
    with pytest.raises(ScenarioError, match=r"Expected no \[internal\] with \[gyrocompass\]"):
        parse(base + extra)


SPRING = """
[scenario]
name = "spring"
[body]
inertia = "1, 3, 3.2 kg*m^2"
mass = "30 kg"
[[internal]]
type = "spring-mass-damper"
mass = "1 kg"
position = "0, 0.4, 0 m"
axis = [1, 0, 0]
stiffness = "6 N/m"
damping = "1 N*s/m"
[initial]
omega = "2, 0.05, 0.02 rad/s"
[simulation]
duration = "20 s"
dt = "5 ms"
method = "rk4"
"""


def test_a_spring_mass_damper_in_a_file_is_the_library_s() -> None:
    # The file adds the 1 kg point mass to the body; the run equals tumble.simulate
    # with the same parts (the same arithmetic: to the bit).
    result = run(parse(SPRING))
    body = tb.MassProperties(30.0, [0, 0, 0], np.diag([1.0, 3.0, 3.2])) + tb.point_masses(
        [1.0], [[0.0, 0.4, 0.0]]
    )
    part = tb.SpringMassDamper(1.0, [0, 0.4, 0], [1, 0, 0], 6.0, 1.0)
    alone = tb.simulate(body, [2.0, 0.05, 0.02], duration=20.0, dt=0.005, method="rk4",
                        internal=[part])  # fmt: skip
    assert_allclose(result.trajectory.omega[-1], alone.omega[-1], rtol=0, atol=0)
    assert result.trajectory.internal_values.shape[1] == 2


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'stiffness = "6 N/m"\n',
            "",
            r"`internal\[0\]\.stiffness`: Expected `stiffness` \(N/m\), which is missing\.",
        ),
        (
            'stiffness = "6 N/m"',
            'stiffness = "6 N/m"\nradius = 1',
            r"`internal\[0\]\.radius`: Expected no `radius` for a spring-mass-damper, got one\.",
        ),
        (
            'stiffness = "6 N/m"',
            'stiffness = "6 kg"',
            r"`internal\[0\]\.stiffness`: Expected `stiffness` to be a stiffness in N/m",
        ),
        (
            'damping = "1 N*s/m"',
            'damping = "-1 N*s/m"',
            r"`internal\[0\]\.damping`: Expected `damping` >= 0 N·s/m, got -1\.0\.",
        ),
    ],
)
def test_bad_spring_tables_name_the_key(old: str, new: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        run(parse(edited(old, new, SPRING)))


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "axis = [0, 1, 0]",
            "axis = [0, 0, 0]",
            "Expected `axis` of a Rotor to be a non-zero vector",
        ),
        (
            'mass = "20 kg"\nradius = "30 cm"',
            'inertia = "-1 kg*m^2"',
            "Expected `inertia` > 0 kg·m², got -1.0",
        ),
        (
            'mass = "20 kg"\nradius = "30 cm"',
            'inertia = "60 kg*m^2"',
            "Expected internal parts whose spin inertia the body can hold",
        ),
    ],
)
def test_the_cli_prints_one_line_and_exits_2_for_a_bad_part(tmp_path, old, new, message) -> None:
    from typer.testing import CliRunner

    from tumble.cli import app

    path = tmp_path / "bad.toml"
    path.write_text(edited(old, new))
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert "bad.toml, line " in lines[0] and message in lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["dual-spin", "energy-sink", "libration", "slew"])
def test_a_spacecraft_check_refuses_a_setup_it_does_not_describe(name: str) -> None:
    # A bare box tumbling freely: no rotor, no damper, no orbit, no controller.
    box = tb.MassProperties(20.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))
    case = tb.checks.Case(box, np.array([0.1, 0.2, 0.3]), np.array([1.0, 0, 0, 0]))
    trajectory = tb.simulate(box, case.omega0, duration=1.0, dt=0.1)
    check = tb.checks.THEORY_CHECKS[name]
    assert not check.fits(case)
    with pytest.raises(tb.InputError, match=rf"^Expected {check.needs}, got another setup\.$"):
        check.compare(case, trajectory)
