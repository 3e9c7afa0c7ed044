"""Scenario files: validation messages (key path, line, what was expected), the
built-in scenarios, and the physics each one checks against theory."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import scenario_tools
import tumble as tb
from scenario_tools import rows
from tumble.scenario import ScenarioError, builtin_names, builtin_text, load, parse, run

GYRO = builtin_text("gyroscope")


def edited(old: str, new: str, text: str = GYRO) -> str:
    return scenario_tools.edited(old, new, text)


# ------------------------------------------------------------------ validation
@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        # unknown keys (typos), with the nearest known key
        (
            'radius = "10 cm"',
            'radus = "10 cm"',
            r"g\.toml, line 20, `body\.radus`: Expected the key to be one of translation, rotation, shape, mass, radius, .*, got 'radus'\. Did you mean radius\?",
        ),
        (
            "[output]",
            "[outputs]",
            r"line 38, `outputs`: Expected the key to be one of scenario, body, .*, got 'outputs'\. Did you mean output\?",
        ),
        (
            'method = "auto"  ',
            'methd = "auto"  ',
            r"line 33, `simulation\.methd`: Expected the key to be one of duration, dt, method, got 'methd'\. Did you mean method\?",
        ),
        # wrong units
        (
            'radius = "10 cm"',
            'radius = "10 kg"',
            r"line 20, `body\.radius`: Expected `radius` to be a length in m, got 10 kg \(dimensions \[mass\]\)\.",
        ),
        (
            '"0, 0, 200 rad/s"',
            '"0, 0, 200 m/s"',
            r"line 24, `initial\.omega`: Expected `omega` to be an angular velocity in rad/s",
        ),
        (
            '"0, 0, 200 rad/s"',
            '"0, 0, 200 Hz"',
            r"`initial\.omega`: Expected `omega` in rad/s, rpm or turn/s, got .*hertz is ambiguous",
        ),
        (
            'duration = "5 s"',
            'duration = "5 m"',
            r"line 32, `simulation\.duration`: Expected `duration` to be a time in s, got 5 m",
        ),
        (
            '"0, 0, -9.81 m/s^2"',
            '"0, 0, -9.81 N"',
            r"`environment\.gravity`: Expected `gravity` to be an acceleration in m/s\^2",
        ),
        # non-physical values
        (
            'mass = "1 kg"',
            'mass = "-1 kg"',
            r"line 19, `body\.mass`: Expected `mass` > 0 kg, got -1\.0\.",
        ),
        (
            'height = "1 cm"',
            'height = "0 cm"',
            r"`body\.height`: Expected `height` > 0 m, got 0\.0\.",
        ),
        (
            'duration = "5 s"',
            'duration = "5 s"\ndt = "-1 ms"',
            r"line 33, `simulation\.dt`: Expected `dt` > 0 s, got -0\.001\.",
        ),
        (
            'duration = "5 s"',
            'duration = "5000 s"\ndt = "1 us"',
            r"`simulation`: Expected at most 5e7 steps \(duration / dt\), got 5e\+09",
        ),
        (
            '{ euler_zxz = "0, 90, 0 deg" }',
            "{ quaternion = [0, 0, 0, 0] }",
            r"line 25, `initial\.attitude`: Expected `quaternion` to be non-zero \[w, x, y, z\]",
        ),
        (
            "samples = 2500",
            "samples = 3",
            r"line 39, `output\.samples`: Expected a value greater than or equal to 10, got 3\.",
        ),
        (
            "samples = 2500",
            "samples = 0",
            r"line 39, `output\.samples`: Expected a value greater than or equal to 10, got 0\.$",
        ),
        # missing keys and tables
        (
            'duration = "5 s"',
            "",
            r"line 31, `simulation\.duration`: Expected the key `duration`, which is missing\.",
        ),
        (
            'height = "1 cm"',
            "",
            r"line 17, `body\.height`: Expected `height` for a solid-cylinder \(it takes `mass`, `radius`, `height`\)\.",
        ),
        ('gravity = "0, 0, -9.81 m/s^2"', "", r"`environment`: Expected `gravity` with `pivot`"),
        # wrong shapes and choices
        (
            '"0, 0, 200 rad/s"',
            '"0, 200 rad/s"',
            r"`initial\.omega`: Expected `omega` to have shape \(3,\), got \(2,\)\.",
        ),
        (
            '"solid-cylinder"',
            '"cilinder"',
            r"line 18, `body\.shape`: Expected `shape` to be one of box, .* got 'cilinder'\. Did you mean solid-cylinder\?",
        ),
        (
            'height = "1 cm"',
            'height = "1 cm"\nlength = "1 m"',
            r"line 22, `body\.length`: Expected only `radius`, `height` for a solid-cylinder, got `length`\.",
        ),
        (
            'method = "auto"',
            'method = "euler"',
            r"line 33, `simulation\.method`: Expected `method` to be one of auto, exact, splitting, strang, splitting-exact, strang-exact, rk4, adaptive, got 'euler'\.",
        ),
        (
            'mass = "1 kg"',
            'mass = "1 kg"\nmesh = "x.stl"',
            r"`body`: Expected one kind of body \(`shape`, `mesh`, `masses`, `inertia` or `parts`\), got `shape` and `mesh`\.",
        ),
        (
            '{ euler_zxz = "0, 90, 0 deg" }',
            '{ euler_zxz = "0, 90, 0 deg", quaternion = [1, 0, 0, 0] }',
            r"`initial\.attitude`: Expected exactly one of `euler_zxz`, `axis` with `angle`, or `quaternion`, got `euler_zxz` and `quaternion`\.",
        ),
        (
            '{ euler_zxz = "0, 90, 0 deg" }',
            "{ axis = [0, 1, 0] }",
            r"`initial\.attitude`: Expected both `axis` and `angle`",
        ),
        (
            'name = "gyroscope"',
            'name = "my gyro!"',
            r"line 7, `scenario\.name`: Expected `name` to be letters, digits",
        ),
        (
            'model = "gyroscope"',
            'model = "lagrange"',
            r"line 36, `theory\.model`: Expected `model` to be one of auto, none, dual-spin, energy-sink, libration, slew, gyroscope, rotor-loads, free-symmetric-top, flip-period, gyrocompass, rigid-rotor, got 'lagrange'\.",
        ),
        (
            "samples = 2500",
            'samples = "many"',
            r"`output\.samples`: Expected a valid integer, unable to parse string as an integer, "
            r"got 'many'\.$",
        ),
        # not TOML at all
        (
            "[body]",
            "[body",
            r"g\.toml: Expected valid TOML, got an error: .*\(at line 17, column 6\)\.",
        ),
    ],
)
def test_errors_name_the_key_its_line_and_what_was_expected(
    old: str, new: str, message: str
) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse(edited(old, new), source="g.toml")


def test_an_empty_body_lists_the_kinds_of_body() -> None:
    text = "[scenario]\nname = 'x'\n[body]\nfoo = 1\n[simulation]\nduration = 1\n"
    with pytest.raises(
        ScenarioError,
        match=r"<scenario>, line 3, `body`: Expected a body: `shape` \(a solid\), `mesh` \(a file\), `masses` and `positions`.*\(an assembly\)\.",
    ):
        parse(text)


def test_a_missing_table_is_named() -> None:
    with pytest.raises(
        ScenarioError, match=r"`simulation`: Expected the table \[simulation\], which is missing\."
    ):
        parse("[scenario]\nname = 'x'\n[body]\nshape = 'solid-sphere'\nmass = 1\nradius = 1\n")


def test_other_problems_are_counted() -> None:
    text = edited('duration = "5 s"', 'duration = "0 s"', edited('mass = "1 kg"', 'mass = "-1 kg"'))
    with pytest.raises(
        ScenarioError,
        match=r"^<scenario>, line 19, `body\.mass`: Expected `mass` > 0 kg, got -1\.0\. \(1 more problem\)$",
    ):
        parse(text)


def test_keys_inside_a_part_are_located() -> None:
    text = edited('radius = "4 cm"', 'radius = "4 kg"', builtin_text("heavy-top"))
    with pytest.raises(
        ScenarioError,
        match=r"line 20, `body\.parts\[0\]\.radius`: Expected `radius` to be a length",
    ):
        parse(text)
    with pytest.raises(
        ScenarioError,
        match=r"`body\.parts\[0\]\.rotation\.angel`: Expected the key to be one of euler_zxz, axis, angle, quaternion, got 'angel'\. Did you mean angle\?",
    ):
        parse(edited('angle = "180 deg"', 'angel = "180 deg"', builtin_text("heavy-top")))


def test_library_errors_while_building_name_the_part() -> None:
    # Inertia that no mass distribution has: refused by MassProperties, reported at the key.
    text = (
        "[scenario]\nname = 'bad'\n\n[body]\nmass = '1 kg'\ninertia = '1, 1, 3 kg*m^2'\n\n"
        "[simulation]\nduration = '1 s'\n"
    )
    with pytest.raises(
        ScenarioError,
        match=r"bad\.toml, line 4, `body`: Expected the principal moments of `inertia` to satisfy the triangle inequality",
    ):
        run(parse(text, source="bad.toml"))


def test_a_missing_mesh_file_is_named(tmp_path: Path) -> None:
    text = builtin_text("tumbling-satellite").replace("satellite.stl", "nothere.stl")
    path = tmp_path / "sat.toml"
    path.write_text(text)
    with pytest.raises(
        ScenarioError,
        match=r"sat\.toml, line \d+, `body`: Expected a mesh file, got 'nothere\.stl' \(not found in ",
    ):
        run(load(path))


def test_a_theory_that_does_not_fit_is_refused() -> None:
    text = edited(
        'model = "free-symmetric-top"', 'model = "gyroscope"', builtin_text("free-symmetric-top")
    )
    with pytest.raises(
        ScenarioError,
        match=r"`theory\.model`: Expected a pivot with gravity and no other torque for 'gyroscope'",
    ):
        run(parse(text))


def test_gyrocompass_refuses_an_initial_state() -> None:
    text = builtin_text("gyrocompass") + '\n[initial]\nomega = "0, 0, 1 rad/s"\n'
    with pytest.raises(ScenarioError, match=r"Expected no \[initial\] with \[gyrocompass\]"):
        parse(text)


def test_unknown_names_and_files() -> None:
    with pytest.raises(
        ScenarioError,
        match=r"Expected a built-in scenario to be one of gyroscope, .*, or a \.toml file, got 'gyroskope'\. Did you mean gyroscope\?",
    ):
        load("gyroskope")
    with pytest.raises(
        ScenarioError, match=r"Expected a scenario file, got 'nothere\.toml' \(no such file\)\."
    ):
        load("nothere.toml")


# ------------------------------------------------------------------ the format
def test_attitude_forms_agree() -> None:
    forms = [
        '{ euler_zxz = "0, 90, 0 deg" }',
        '{ axis = [1, 0, 0], angle = "90 deg" }',
        f"{{ quaternion = [{math.cos(math.pi / 4)}, {math.sin(math.pi / 4)}, 0, 0] }}",
        "{ quaternion = [2, 2, 0, 0] }",  # normalised
    ]
    quaternions = [
        parse(
            edited('{ euler_zxz = "0, 90, 0 deg" }', form)
        ).spec.initial.attitude.quaternion_wxyz()  # type: ignore[union-attr]
        for form in forms
    ]
    for q in quaternions:
        assert_allclose(q, quaternions[0], atol=1e-15)
    # z-x-z: precession φ about z, then nutation θ about the new x, then spin ψ.
    q = parse(edited('"0, 90, 0 deg"', '"90, 30, 45 deg"')).spec.initial.attitude.quaternion_wxyz()  # type: ignore[union-attr]
    from scipy.spatial.transform import Rotation

    expected = (
        Rotation.from_rotvec([0, 0, math.pi / 2])
        * Rotation.from_rotvec([math.radians(30), 0, 0])
        * Rotation.from_rotvec([0, 0, math.pi / 4])
    )
    assert_allclose(
        Rotation.from_quat(q, scalar_first=True).as_matrix(), expected.as_matrix(), atol=1e-15
    )


def test_omega_in_space_axes() -> None:
    text = edited('omega = "0, 0, 200 rad/s"', 'omega = "0, -200, 0 rad/s"\nomega_frame = "space"')
    text = edited('duration = "5 s"', 'duration = "0.1 s"', text)
    result = run(parse(text))
    # The axis starts along −y in space (Rx(90°) ẑ), so −200 ŷ in space is +200 about body z.
    assert_allclose(result.trajectory.omega[0], [0, 0, 200], atol=1e-12)
    assert_allclose(result.trajectory.omega_space[0], [0, -200, 0], atol=1e-12)


def test_assembly_of_parts_with_poses() -> None:
    spec = parse(builtin_text("skew-rod")).spec
    from tumble.scenario.build import mass_properties

    mp = mass_properties(spec.body, Path("."))
    u = np.array([math.cos(math.radians(30)), 0.0, math.sin(math.radians(30))])
    ball = tb.shapes.solid_sphere(0.3, 0.01)
    rod = tb.shapes.thin_rod(0.05, 0.5)
    from scipy.spatial.transform import Rotation

    expected = (
        ball.transformed(translation=0.25 * u)
        + ball.transformed(translation=-0.25 * u)
        + rod.transformed(rotation=Rotation.from_rotvec([0, math.radians(60), 0]))
    )
    assert mp.mass == pytest.approx(0.65, rel=1e-15)
    assert_allclose(mp.inertia, expected.inertia, rtol=1e-6, atol=1e-15)  # positions to 1e-8 m


def test_points_and_inertia_bodies() -> None:
    text = (
        "[scenario]\nname = 'p'\n[body]\nmasses = '1, 1, 2 kg'\n"
        "positions = [[1, 0, 0], [-1, 0, 0], '0, 0.5, 0 m']\n"
        "[initial]\nomega = '0.1, 0, 2 rad/s'\n[simulation]\nduration = '2 s'\n"
        "[output]\nsamples = 100\n"
    )
    result = run(parse(text))
    expected = tb.point_masses([1, 1, 2], [[1, 0, 0], [-1, 0, 0], [0, 0.5, 0]])
    assert_allclose(result.trajectory.mass_properties.inertia, expected.inertia, rtol=1e-15)
    assert result.theory == "flip-period"
    given = (
        "[scenario]\nname = 'i'\n[body]\nmass = 2\ninertia = '1, 2, 2.5 kg*m^2'\n"
        "[simulation]\nduration = 1\n"
    )
    assert_allclose(run(parse(given)).trajectory.mass_properties.inertia, np.diag([1, 2, 2.5]))


def test_every_builtin_is_valid_and_listed_in_order() -> None:
    names = builtin_names()
    assert names[:8] == [
        "gyroscope",
        "gyrocompass",
        "skew-rod",
        "rotor-on-bearings",
        "tennis-racket",
        "heavy-top",
        "free-symmetric-top",
        "tumbling-satellite",
    ]
    for name in names:
        assert load(name).spec.scenario.name == name


def test_a_copied_scenario_runs_from_its_own_folder(tmp_path: Path) -> None:
    # `tumble show NAME > FILE.toml` then edit: the shipped mesh is still found.
    path = tmp_path / "sat.toml"
    path.write_text(
        builtin_text("tumbling-satellite").replace('duration = "90 s"', 'duration = "1 s"')
    )
    assert run(load(path)).trajectory.mass_properties.mass == pytest.approx(500)
    # A mesh beside the file wins over the shipped one.
    import tumble.scenario

    shipped = Path(tumble.scenario.__file__).parent / "builtin" / "satellite.stl"
    shutil.copy(shipped, tmp_path / "satellite.stl")
    assert run(load(path)).scenario.folder == tmp_path


# ------------------------------------------------------------------ physics
def test_gyroscope_precession_and_nutation_match_theory() -> None:
    result = run("gyroscope")
    table = rows(result)
    # The run is the exact solution, so theory and measurement differ by the
    # measuring error alone: 2500 samples over 5 s are 39 a nutation period, and
    # a turning point refined by a parabola is off by ~(2π/39)³/24 = 2e-4 rad of
    # phase, 4e-7 of the 63 periods' span (5e-7 and 3e-7 measured); its height
    # by ~(2π/39)⁴/8 = 8e-5 of the swing at worst (6e-6 measured).
    assert table["precession rate (mean, exact)"]["relative_error"] < 2e-6
    assert table["nutation frequency (exact)"]["relative_error"] < 2e-6
    assert table["nutation amplitude (exact)"]["relative_error"] < 1e-4
    # Fast-top formulas hold to O(m g l I⊥' / (I_s ω_s)²) ≈ 1.2e-2 of the nutation ...
    assert table["precession rate (fast top)"]["relative_error"] < 1e-3
    # ... and the measured precession is m g l / (I_s ω_s) = 0.981 rad/s to that order.
    assert table["precession rate (fast top)"]["theory"] == pytest.approx(0.981, rel=1e-12)
    # Conserved by a symmetric top under gravity, and kept by the closed form to round-off.
    assert set(result.drift) == {"energy", "angular_momentum_vertical", "angular_momentum_axial"}
    assert max(result.drift.values()) < 1e-10
    assert result.trajectory.method == "exact"
    assert 2000 <= len(result.trajectory.t) <= 3000  # [output] samples = 2500, about


def test_heavy_top_exact_nutation_where_the_fast_top_formula_fails() -> None:
    table = rows(run("heavy-top"))
    assert table["nutation amplitude (exact)"]["relative_error"] < 1e-6
    assert table["nutation frequency (exact)"]["relative_error"] < 1e-6
    assert math.degrees(2 * table["nutation amplitude (exact)"]["theory"]) > 15  # a large swing
    assert table["precession rate (fast top)"]["relative_error"] > 0.1
    assert table["nutation amplitude (fast top)"]["relative_error"] > 0.3


def test_free_symmetric_top_cones() -> None:
    result = run("free-symmetric-top")
    for row in result.comparisons:  # the exact solution: round-off only
        assert row["relative_error"] < 1e-9, row
    assert {"body cone half-angle (ω to the axis)", "space precession rate"} <= set(rows(result))


def test_tennis_racket_flip_period() -> None:
    table = rows(run("tennis-racket"))
    assert table["flip period"]["relative_error"] < 1e-6
    assert table["flips in the run"]["measured"] == table["flips in the run"]["theory"] >= 8


def test_satellite_mesh_and_its_tumbling() -> None:
    result = run("tumbling-satellite")
    mp = result.trajectory.mass_properties
    # The shipped mesh is four boxes: bus, two panels, mast (edges and centres in m).
    boxes = [
        ((1.0, 1.2, 1.6), (0, 0, 0)),
        ((0.9, 2.4, 0.04), (0, 1.95, 0.2)),
        ((0.9, 2.4, 0.04), (0, -1.95, 0.2)),
        ((0.2, 0.2, 0.5), (0, 0, 1.05)),
    ]
    volume = sum(float(np.prod(size)) for size, _ in boxes)
    expected = sum(
        tb.shapes.box(500 * float(np.prod(size)) / volume, size).transformed(translation=centre)
        for size, centre in boxes
    )
    # A binary STL stores float32 coordinates: 6e-8 relative, so about 1e-7 in the inertia.
    assert_allclose(mp.inertia, expected.inertia, rtol=1e-6, atol=1e-6 * mp.inertia.max())
    _, axes = mp.principal()
    assert abs(axes[:, 1] @ [0, 0, 1]) == pytest.approx(1.0)  # spun about the intermediate axis
    table = rows(result)
    assert table["flip period"]["relative_error"] < 1e-6
    assert table["flips in the run"]["measured"] >= 4
    from tumble.report.scenario_geometry import body_geometry

    geometry = body_geometry(result.scenario.spec.body, result.scenario.folder)
    assert geometry.exact and len(geometry.faces) == 48


def test_skew_rod_torque_and_bearing_loads() -> None:
    result = run("skew-rod")
    table = rows(result)
    # |τ| = (2 m ℓ² + m_rod L²/12) ω² sin α cos α: the balls' own inertia is isotropic.
    alpha, omega = math.radians(30), 20.0
    point = tb.theory.skew_rod(0.3, 0.25, alpha, omega, bearing_separation=0.2)
    scale = 1 + (0.05 * 0.5**2 / 12) / (2 * 0.3 * 0.25**2)
    assert table["|τ| = |dL/dt|"]["theory"] == pytest.approx(point.torque * scale, rel=1e-6)
    assert table["bearing force (each)"]["theory"] == pytest.approx(
        point.bearing_force * scale, rel=1e-6
    )
    # Measured: |dL/dt| by five-point differences, error ≈ (ω Δt)⁴/30 ≈ 5e-9.
    assert table["|τ| = |dL/dt|"]["relative_error"] < 1e-7
    assert table["|ω| (held steady)"]["relative_error"] < 1e-9
    assert table["|L|"]["relative_error"] < 1e-9
    assert table["angle between L and ω"]["theory"] > 0.5  # L is far from parallel to ω


def test_gyrocompass_small_angle_formula_holds_then_fails() -> None:
    result = run("gyrocompass")
    table = rows(result)
    small = "θ0 = 10°: "
    large = "θ0 = 100°: "
    assert table[small + "oscillation frequency (amplitude, exact)"]["relative_error"] < 1e-6
    assert table[small + "oscillation frequency β"]["relative_error"] < 1e-2
    assert table[large + "oscillation frequency (amplitude, exact)"]["relative_error"] < 1e-6
    assert table[large + "oscillation frequency β"]["relative_error"] > 0.2
    assert list(result.runs) == ["main", "amplitude-100deg"]
    # Over the first swing θ(t) follows θ0 sin βt closely at θ0 = 10° (the phase error grows
    # later by |β − β_exact| t, 0.4 % of βt), and misses it by far at 100°.
    curves = result.panels[0].curves
    first = curves[0].t < 2 * math.pi / 28.24
    small_error = np.max(np.abs(curves[0].values - curves[1].values)[first])
    large_error = np.max(
        np.abs(curves[2].values - curves[3].values)[curves[2].t < 2 * math.pi / 28.24]
    )
    assert small_error < 0.03 * 10  # degrees
    assert large_error > 0.2 * 100
    # The dashed curve is the small swing from the run's own start (θ = 0, θ̇ = β θ0):
    # θ0 sin βt, β of tumble.theory.gyrocompass for the built-in's disk and rates.
    beta = tb.theory.gyrocompass(result.trajectory.mass_properties, 200.0, 2.0)
    expected = 10.0 * np.sin(beta.oscillation_frequency * curves[1].t)
    np.testing.assert_allclose(curves[1].values, expected, rtol=0, atol=1e-9)  # degrees


def test_progress_is_reported() -> None:
    calls: list[tuple[int, int]] = []
    run("tennis-racket", progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][0] == calls[-1][1]


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_are_valid(path: Path) -> None:
    assert load(path).spec.scenario.name == path.stem.replace("_", "-")


def test_example_top_loses_energy_to_drag() -> None:
    text = (
        (EXAMPLES / "spinning_top.toml")
        .read_text()
        .replace('duration = "4 s"', 'duration = "0.5 s"')
    )
    result = run(parse(text))
    energy = result.trajectory.energy
    # dE/dt = −c |ω|² ≤ 0 with drag: never rises (beyond the integrator's tolerance).
    assert np.all(np.diff(energy) <= 1e-9 * abs(energy[0]))
    assert energy[-1] < energy[0]
    assert result.theory is None and result.comparisons == []
    assert result.drift == {}  # damped: nothing is conserved, so nothing is shown as drift


def test_more_value_errors_name_their_keys(tmp_path: Path) -> None:
    points = "[scenario]\nname = 'x'\n[body]\nmasses = [1, 2]\npositions = [[0, 0, 1]]\n[simulation]\nduration = 1\n"
    with pytest.raises(
        ScenarioError, match=r"Expected as many `positions` as `masses` \(2\), got 1\."
    ):
        parse(points)
    compass = builtin_text("gyrocompass")
    with pytest.raises(
        ScenarioError,
        match=r"Expected `spin_rate` and `platform_rate` ≠ 0 rad/s, got 0\.0 and 2\.0\.",
    ):
        parse(edited('spin_rate = "200 rad/s"', 'spin_rate = "0 rad/s"', compass))
    with pytest.raises(
        ScenarioError, match=r"Expected each of `amplitudes` in \(0, 180\) deg, got 3\.49"
    ):
        parse(
            edited(
                'amplitudes = ["10 deg", "100 deg"]', 'amplitudes = ["10 deg", "200 deg"]', compass
            )
        )
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"[scenario]\nname = '\xff'\n")
    with pytest.raises(ScenarioError, match=r"Expected a readable UTF-8 file, got '.*bad.toml'"):
        load(bad)


def test_a_rotor_at_rest_has_no_loads_to_compare() -> None:
    rod = edited('omega = "0, 0, 20 rad/s"', 'omega = "0, 0, 0 rad/s"', builtin_text("skew-rod"))
    with pytest.raises(
        tb.InputError, match=r"Expected a non-zero initial ω to hold steady, got 0\."
    ):
        run(parse(rod))


# ------------------------------------------------------------------ [[torques]]: the registry
TUMBLING = """\
[scenario]
name = "spun"

[body]
shape = "box"
mass = "2 kg"
size = "0.1, 0.2, 0.3 m"

[initial]
omega = "0.1, 2, 0.1 rad/s"

[[torques]]
type = "damping"
coefficient = "0.001 N*m*s"

[simulation]
duration = "2 s"
"""


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'type = "damping"',
            'type = "dampng"',
            r"spun\.toml, line 13, `torques\[0\]\.type`: Expected `type` to be one of gravity, constant-body, constant-space, damping, hold-rotation, rotor-momentum, drag, quadratic-drag, attitude-control, gravity-gradient, got 'dampng'\. Did you mean damping\?",
        ),
        (
            'type = "damping"',
            "",
            r"`torques\[0\]\.type`: Expected `type` \(gravity, .*gravity-gradient\), which is missing\.",
        ),
        (
            'coefficient = "0.001 N*m*s"',
            "",
            r"`torques\[0\]\.coefficient`: Expected `coefficient` \(damping coefficient c\) for a damping torque, which is missing\.",
        ),
        (
            'coefficient = "0.001 N*m*s"',
            'coefficient = "0.001 N*m*s"\ntorque = "1, 0, 0 N*m"',
            r"line 15, `torques\[0\]\.torque`: Expected the key to be one of type, coefficient, got 'torque'\.",
        ),
        (
            'coefficient = "0.001 N*m*s"',
            'coefficient = "-1 N*m*s"',
            r"line 14, `torques\[0\]\.coefficient`: Expected `coefficient` >= 0 N·m·s, got -1\.0\.",
        ),
        (
            'coefficient = "0.001 N*m*s"',
            'coefficient = "2 kg"',
            r"`torques\[0\]\.coefficient`: Expected `coefficient` to be a damping in N\*m\*s, got",
        ),
    ],
)
def test_torque_entries_are_checked_against_the_registry(old: str, new: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse(edited(old, new, TUMBLING), source="spun.toml")


def test_torque_entries_become_the_registrys_models() -> None:
    # Damping c = 1e-3 N·m·s on a box tumbling about its intermediate axis: the
    # run equals tumble.simulate with the same LinearDamping, and with a body
    # torque and a space torque added, with the same models as given directly.
    text = TUMBLING + (
        '\n[[torques]]\ntype = "constant-body"\ntorque = "0, 0, 1 mN*m"\n'
        '\n[[torques]]\ntype = "constant-space"\ntorque = "1 mN*m, 0, 0"\n'
    )
    result = run(parse(text, source="spun.toml"))
    model = (
        tb.torques.LinearDamping(1e-3)
        + tb.torques.ConstantBodyTorque([0, 0, 1e-3])
        + tb.torques.ConstantSpaceTorque([1e-3, 0, 0])
    )
    traj = result.trajectory
    expected = tb.simulate(
        tb.shapes.box(2.0, [0.1, 0.2, 0.3]), [0.1, 2.0, 0.1], duration=2.0, dt=traj.dt,
        torque=model, method=traj.method,
    )  # fmt: skip
    # The same models and method at the same step: the same arithmetic; the
    # adaptive method's samples agree to its tolerance (1e-10 relative).
    assert_allclose(traj.omega[-1], expected.omega[-1], rtol=1e-9)
    assert traj.method == "adaptive" and result.drift == {}


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ('name = "gyroscope"', 'name = "' + "n" * 5000 + '"'),
        ('shape = "solid-cylinder"', 'shape = "' + "n" * 5000 + '"'),
        ('model = "gyroscope"', 'model = "' + "n" * 5000 + '"'),
        ('method = "auto"', 'method = "' + "n" * 5000 + '"'),
        ('name = "gyroscope"', 'name = "gyroscope"\n' + "n" * 5000 + " = 1"),  # unknown key
    ],
)
def test_long_values_and_keys_are_cut_in_messages(old: str, new: str) -> None:
    with pytest.raises(ScenarioError) as caught:
        parse(edited(old, new), source="g.toml")
    message = str(caught.value)
    assert "n" * 60 + "..." in message.replace("'", "")
    assert "n" * 61 not in message


# ------------------------------------------------------------------ why nothing was compared
RACKET = builtin_text("tennis-racket").replace('model = "flip-period"', 'model = "auto"')
TOP = builtin_text("heavy-top")


@pytest.mark.parametrize(
    ("omega", "note"),
    [
        (
            "0, 10, 0",
            "no theory comparison: the body spins about a principal axis (I2 = 0.00173 kg·m²), "
            "where the free-body solution is a steady spin; nothing to compare.",
        ),
        (
            "10, 0, 0",
            "no theory comparison: the body spins about a principal axis (I1 = 0.000483 kg·m²), "
            "where the free-body solution is a steady spin; nothing to compare.",
        ),
        (
            "0, 0, 0",
            "no theory comparison: the body is at rest (ω = 0), where the free-body solution "
            "stays at rest; nothing to compare.",
        ),
    ],
)
def test_a_free_body_in_a_steady_state_says_why_nothing_is_compared(omega: str, note: str) -> None:
    text = edited('omega = "0.05, 10, 0.05 rad/s"', f'omega = "{omega} rad/s"', RACKET)
    result = run(parse(text.replace('duration = "20 s"', 'duration = "2 s"')))
    assert result.comparisons == []
    assert result.summary()["notes"] == [note]


def test_a_symmetric_body_spun_about_its_axis_says_why_nothing_is_compared() -> None:
    text = edited(
        'omega = "0.05, 10, 0.05 rad/s"',
        'omega = "0, 0, 10 rad/s"',
        RACKET.replace('size = "20, 10, 4 cm"', 'size = "10, 10, 4 cm"'),
    )
    result = run(parse(text.replace('duration = "20 s"', 'duration = "2 s"')))
    assert result.comparisons == []
    assert result.summary()["notes"] == [
        "no theory comparison: the body spins about a principal axis (I3 = 0.000833 kg·m²), "
        "where the free-body solution is a steady spin; nothing to compare."
    ]


def test_a_run_shorter_than_two_flips_says_so() -> None:
    text = RACKET.replace('duration = "20 s"', 'duration = "1 s"')
    result = run(parse(text))
    assert result.comparisons == []
    assert result.summary()["notes"] == [
        "no theory comparison: the run (1 s) holds fewer than two flips (the flip period is "
        "4.46 s); run longer to compare."
    ]


@pytest.mark.parametrize(
    ("old", "new", "cause"),
    [
        # Upright: the azimuth of the axis about the vertical is not defined.
        ('euler_zxz = "0, 30, 0 deg"', 'euler_zxz = "0, 0, 0 deg"', r"Expected `axis` to stay off"),
        # No spin: a spherical pendulum, not a top.
        ('omega = "0, 0, 250 rad/s"', 'omega = "0, 0, 0 rad/s"', r"Expected `spin_rate` ≠ 0"),
    ],
)
def test_a_named_check_that_cannot_measure_the_run_names_the_key_that_runs_it(
    old: str, new: str, cause: str
) -> None:
    text = edited(old, new, TOP).replace('duration = "3 s"', 'duration = "0.5 s"')
    with pytest.raises(
        ScenarioError,
        match=rf"^<scenario>, line \d+, `theory`: {cause}.* Set \[theory\] model = \"none\" to "
        r"run it without a comparison\.$",
    ):
        run(parse(text))
    result = run(parse(text.replace('model = "gyroscope"', 'model = "none"')))
    assert result.comparisons == []
    assert result.summary()["notes"] == ['no theory comparison: [theory] model = "none".']


def test_the_automatic_check_that_cannot_measure_the_run_says_why() -> None:
    text = edited('euler_zxz = "0, 30, 0 deg"', 'euler_zxz = "0, 0, 0 deg"', TOP)
    text = text.replace('duration = "3 s"', 'duration = "0.5 s"')
    result = run(parse(text.replace('model = "gyroscope"', 'model = "auto"')))
    assert result.comparisons == [] and result.theory is None
    (note,) = result.summary()["notes"]
    assert note.startswith(
        "no theory comparison: the gyroscope check cannot measure this run: Expected `axis` to "
        "stay off"
    )
