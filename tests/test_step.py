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
from pathlib import Path

import numpy as np
import pytest
import trimesh

import tumble as tb
from tumble.mesh import mesh_mass_properties

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
