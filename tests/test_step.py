"""STEP files, the format CAD exports: read through trimesh and cascadio
(OpenCASCADE), units from the file.

``tests/data/bracket_with_hole.step`` is an L bracket in millimetres (the file
declares ``SI_UNIT(.MILLI.,.METRE.)``): a 60 × 8 × 30 plate and an 8 × 32 × 30
upright on it, with a hole of radius 5 through the plate along y at x = 30,
z = 15. It was written by gmsh's OpenCASCADE kernel (``addBox``, ``fuse``,
``addCylinder``, ``cut``, ``write``).
"""

from __future__ import annotations

import math
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

import tumble as tb
from tumble.errors import RequestTooLargeError
from tumble.mesh import mesh_mass_properties
from tumble.mesh.step import tessellate_step

STEP = Path(__file__).parent / "data" / "bracket_with_hole.step"
MM = 1e-3


def bracket_closed_form(density: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre of mass and central inertia of the exact solid: two boxes
    less a cylinder, each by its closed form and the parallel-axis theorem."""
    parts = []  # (signed mass, centre, inertia about its own centre)
    for size, low in (((60, 8, 30), (0, 0, 0)), ((8, 32, 30), (0, 8, 0))):
        a, b, c = (s * MM for s in size)
        m = density * a * b * c
        centre = (np.array(low) + 0.5 * np.array(size)) * MM
        parts.append((m, centre, m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])))
    r, h = 5 * MM, 8 * MM  # the hole through the plate (y from 0 to 8)
    m = density * math.pi * r * r * h
    axial, transverse = m * r * r / 2, m * (3 * r * r + h * h) / 12
    parts.append((-m, np.array([30, 4, 15]) * MM, -np.diag([transverse, axial, transverse])))
    mass = sum(p[0] for p in parts)
    centre = sum(p[0] * p[1] for p in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, own in parts:
        d = c - centre
        inertia += own + m * ((d @ d) * np.eye(3) - np.outer(d, d))
    return mass, centre, inertia


def test_a_step_file_gives_the_solid_in_metres() -> None:
    mp = tb.from_mesh(STEP, density=2700.0)
    mass, centre, inertia = bracket_closed_form(2700.0)
    # OpenCASCADE tessellates the hole as a polygon, which removes a little less
    # than the cylinder: the hole is 3 % of the volume and the polygon's area
    # deficit below 0.3 % of it, so 1e-4 relative (measured: mass 3.8e-5, centre
    # 5.9e-6 of the size, inertia 1.2e-5 of its largest entry).
    assert mp.mass == pytest.approx(mass, rel=1e-4)
    np.testing.assert_allclose(mp.center_of_mass, centre, atol=1e-4 * 60 * MM)
    np.testing.assert_allclose(mp.inertia, inertia, atol=2e-4 * np.max(np.abs(inertia)))


def test_the_step_tessellation_agrees_with_trimesh_on_the_same_triangles() -> None:
    loaded = trimesh.load_mesh(STEP, process=False)
    assert str(loaded.units) == "meters"  # converted from the file's millimetres
    ours = mesh_mass_properties(
        np.asarray(loaded.vertices, dtype=float), np.asarray(loaded.faces), density=2700.0
    )
    merged = trimesh.Trimesh(loaded.vertices, loaded.faces, process=True)
    theirs = trimesh.triangles.mass_properties(merged.triangles, density=2700.0)
    # The same triangles summed two ways: round-off.
    assert ours.mass == pytest.approx(theirs.mass, rel=1e-12)
    np.testing.assert_allclose(ours.inertia, theirs.inertia, atol=1e-12 * np.max(ours.inertia))


def test_the_cli_reads_a_step_file() -> None:
    from typer.testing import CliRunner

    from tumble.cli import app

    result = CliRunner().invoke(app, ["inertia", str(STEP), "--density", "2700"])
    assert result.exit_code == 0, result.output
    assert "0.0579" in result.output  # kg


def with_text(tmp_path: Path, old: str, new: str, name: str = "changed.step") -> Path:
    """The bracket's STEP file with one piece of its text replaced."""
    text = STEP.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / name
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def test_the_same_part_in_kilometres_is_the_solid_scaled(tmp_path: Path) -> None:
    # The tessellation's tolerance is relative to each edge, so the triangles do not
    # depend on the file's unit (an absolute tolerance asked a part in kilometres
    # for 1e12 times more triangles, and gigabytes).
    km = with_text(tmp_path, "SI_UNIT(.MILLI.,.METRE.)", "SI_UNIT(.KILO.,.METRE.)")
    mm = tb.from_mesh(STEP, density=2700.0)
    scaled = tb.from_mesh(km, density=2700.0)
    # Lengths 1e6 times longer: the mass 1e18 times larger, the inertia 1e30. The same
    # triangles, scaled: GLB stores coordinates in single precision (6e-8 relative
    # round-off each), hence 1e-6; another tessellation differs by 1e-5 or more
    # (twice as many segments along the hole: 2.3e-5 in the mass).
    assert scaled.mass == pytest.approx(1e18 * mm.mass, rel=1e-6)
    np.testing.assert_allclose(scaled.center_of_mass, 1e6 * mm.center_of_mass, rtol=1e-6)
    np.testing.assert_allclose(
        scaled.inertia, 1e30 * mm.inertia, atol=1e-6 * 1e30 * mm.inertia.max()
    )


@pytest.mark.parametrize("value", ["NaN", "-inf", "1.E999"])
def test_a_coordinate_that_is_not_finite_is_refused_before_opencascade(
    tmp_path: Path, value: str
) -> None:
    # OpenCASCADE reads "NaN" as a number and then meshes for minutes; "inf" and an
    # overflowing exponent leave a part without geometry.
    bad = with_text(
        tmp_path,
        "#25 = CARTESIAN_POINT('',(0.,0.,30.));",
        f"#25 = CARTESIAN_POINT('',(0.,{value},30.));",
    )
    with pytest.raises(
        tb.MeshError,
        match=rf"^Expected finite numbers in the STEP file '.*changed.step', got {re.escape(value)} at line 37\.$",
    ):
        tb.from_mesh(bad, density=2700.0)


def test_words_and_strings_that_look_like_non_finite_numbers_are_read(tmp_path: Path) -> None:
    # "inf" and "NaN" inside a quoted name or a comment are text, not numbers.
    named = with_text(
        tmp_path,
        "#25 = CARTESIAN_POINT('',(0.,0.,30.));",
        "#25 = CARTESIAN_POINT('NaN inf',(0.,0.,30.)); /* inf */",
    )
    assert tb.from_mesh(named, density=2700.0).mass == pytest.approx(
        tb.from_mesh(STEP, density=2700.0).mass, rel=1e-12
    )


def test_a_conversion_over_its_time_limit_is_stopped_with_the_limit_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Starting the child alone takes longer than a millisecond.
    monkeypatch.setenv("TUMBLE_STEP_TIME_LIMIT", "0.001")
    with pytest.raises(
        tb.InputError,
        match=r"^Expected OpenCASCADE to read '.*bracket_with_hole.step' within its time limit "
        r"of 0.001 s \(TUMBLE_STEP_TIME_LIMIT = 0.001\), got a conversion still running then: "
        r"set TUMBLE_STEP_TIME_LIMIT to more seconds to let it finish\.$",
    ):
        tb.from_mesh(STEP, density=2700.0)


def test_the_time_limit_may_carry_a_unit(monkeypatch: pytest.MonkeyPatch) -> None:
    # 0.06 s: shorter than starting the child and importing OpenCASCADE.
    monkeypatch.setenv("TUMBLE_STEP_TIME_LIMIT", "0.001 min")
    with pytest.raises(
        tb.InputError, match=r"time limit of 0\.06 s \(TUMBLE_STEP_TIME_LIMIT = 0\.001 min\)"
    ):
        tb.from_mesh(STEP, density=2700.0)


def test_the_time_limit_is_an_argument_too(tmp_path: Path) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"time limit of 0.001 s \(the `time_limit` argument\), got a conversion still "
        r"running then: give a longer `time_limit` to let it finish\.$",
    ):
        tessellate_step(STEP, tmp_path / "out.glb", time_limit=0.001)
    assert not (tmp_path / "out.glb").exists()


@pytest.mark.parametrize("value", ["0", "-3", "soon", "nan"])
def test_a_time_limit_that_is_not_a_positive_time_is_refused(
    monkeypatch: pytest.MonkeyPatch, value: str
) -> None:
    monkeypatch.setenv("TUMBLE_STEP_TIME_LIMIT", value)
    with pytest.raises(
        tb.InputError,
        match=rf"^Expected TUMBLE_STEP_TIME_LIMIT to be a time > 0 s such as '600' or '10 min', "
        rf"got '{value}'\.$",
    ):
        tb.from_mesh(STEP, density=2700.0)


def test_a_conversion_over_its_memory_limit_is_stopped_with_the_limit_named(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The interpreter and OpenCASCADE's libraries alone take more than 50 MB.
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "50 MB")
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected OpenCASCADE to read '.*bracket_with_hole.step' within its memory "
        r"limit of 47.7 MiB \(TUMBLE_MEMORY_BUDGET = 50 MB\), got a conversion that reached "
        r"it: set TUMBLE_MEMORY_BUDGET to a larger amount to let it finish\.$",
    ):
        tb.from_mesh(STEP, density=2700.0)


def test_the_memory_limit_is_an_argument_too(tmp_path: Path) -> None:
    with pytest.raises(
        RequestTooLargeError,
        match=r"memory limit of 47.7 MiB \(the `memory_limit` argument\), got a conversion that "
        r"reached it: give a larger `memory_limit` to let it finish\.$",
    ):
        tessellate_step(STEP, tmp_path / "out.glb", memory_limit=50e6)


# The parent: converts with a conversion that sleeps instead of reading (writing its
# process id first), so that it is still running when the parent is ended.
_PARENT = """
import sys
from pathlib import Path
from tumble.mesh import step
step._CONVERSION = (
    "import os, time\\n"
    "open(sys.argv[2] + '.pid', 'w').write(str(os.getpid()))\\n"
    "time.sleep(600)\\n"
)
step.tessellate_step(Path(sys.argv[1]), Path(sys.argv[2]), time_limit=float(sys.argv[3]))
"""


def _ended(pid: int) -> bool:
    """True when the process ``pid`` is gone or a zombie (ended, not yet reaped)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True
    return "\nState:\tZ" in status


def _child_of(glb: Path, parent: subprocess.Popen[bytes]) -> int:
    """The process id the sleeping conversion writes, once it has."""
    marker = Path(f"{glb}.pid")
    for _ in range(6000):  # a safety net: the child starts in about a second
        if marker.is_file() and marker.read_text():
            return int(marker.read_text())
        assert parent.poll() is None, parent.stderr.read() if parent.stderr else ""
        time.sleep(0.01)
    raise AssertionError("the conversion never started")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
@pytest.mark.parametrize("signal_number", [signal.SIGTERM, signal.SIGKILL])
def test_the_conversion_ends_with_the_process_that_started_it(
    tmp_path: Path, signal_number: int
) -> None:
    glb = tmp_path / "out.glb"
    parent = subprocess.Popen(
        [sys.executable, "-c", _PARENT, str(STEP), str(glb), "600"], stderr=subprocess.PIPE
    )
    try:
        child = _child_of(glb, parent)
        parent.send_signal(signal_number)
        parent.wait(timeout=60)  # a safety net, not a measure
        for _ in range(6000):
            if _ended(child):
                break
            time.sleep(0.01)
        assert _ended(child)
    finally:
        parent.kill()
        parent.wait()


@pytest.mark.slow  # waits out a conversion's time limit
def test_a_conversion_stopped_at_its_time_limit_leaves_no_process(tmp_path: Path) -> None:
    glb = tmp_path / "out.glb"
    parent = subprocess.Popen(
        [sys.executable, "-c", _PARENT, str(STEP), str(glb), "10"], stderr=subprocess.PIPE
    )
    try:
        child = _child_of(glb, parent)
        _, errors = parent.communicate(timeout=300)  # a safety net, not a measure
        assert b"within its time limit of 10 s" in errors
        assert _ended(child)
    finally:
        parent.kill()
        parent.wait()
