"""Real CAD meshes: seams that differ by round-off are welded, closed pieces that
touch are accepted, and an open mesh is refused with a message that says how
much is open and, for a seam, which ``merge_tolerance`` closes it.

Oracles: the same solid written without the defect, the closed forms of boxes,
and the convex hull of the pieces of a decomposition.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

import tumble
from tumble import InputError, MeshError
from tumble.core.topology import weld
from tumble.mesh import MeshRepairWarning, mesh_mass_properties

SIZE = (0.1, 0.2, 0.3)  # m


def stl_box(size=SIZE, lo=(0.0, 0.0, 0.0)):
    """A box as CAD STL exports write it: every triangle's corners separately,
    its lowest corner at ``lo``."""
    box = trimesh.creation.box(bounds=[lo, np.add(lo, size)])
    vertices = box.vertices[box.faces].reshape(-1, 3).copy()
    return vertices, np.arange(len(vertices)).reshape(-1, 3)


def lift_one_copy_of_the_origin(vertices, height):
    """Move one of the copies of the corner at the origin to z = ``height``: a
    seam (an STL file repeats each corner in every triangle that uses it)."""
    corner = np.flatnonzero(np.all(vertices == 0.0, axis=1))[0]
    vertices[corner, 2] = height


def quiet(vertices, faces, **kwargs):
    """Mass properties (density 1000) and the messages of the repair warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mp = mesh_mass_properties(vertices, faces, density=1000.0, **kwargs)
    return mp, [str(w.message) for w in caught if issubclass(w.category, MeshRepairWarning)]


def box_inertia(mass, size):
    a, b, c = size
    return mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def test_a_seam_that_differs_by_round_off_is_welded() -> None:
    # One repeated corner at z = 5.36e-18 m instead of 0: a hole of zero area.
    vertices, faces = stl_box()
    exact, _ = quiet(vertices, faces)
    lift_one_copy_of_the_origin(vertices, 5.36e-18)
    mp, said = quiet(vertices, faces)
    assert said == [
        "mesh: welded 1 vertices of its seams, moved by at most 5.36e-18 m "
        "(merge_tolerance 3.74e-10 m)."
    ]
    # The same solid; the welded-away copy still counts in the point the
    # integrals are taken about (the vertex mean): round-off.
    assert mp.mass == pytest.approx(exact.mass, rel=1e-15)
    np.testing.assert_allclose(mp.inertia, exact.inertia, rtol=1e-14, atol=1e-17)
    # With no welding it is refused, and the message says what closes it.
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to be closed \(watertight\), got 4 boundary edges \(edges of only "
        r"one triangle, 1\.32 m long in all, 3\.5 of the mesh's diagonal\) without welding "
        r"\(merge_tolerance 0\): it has holes, so it bounds no solid\. Its vertices at the "
        r"holes are at most 5\.36e-18 m from one another: merge_tolerance = 1\.1e-17 m welds "
        r"them and closes it\. For a sheet or a thin-walled part, shell_thickness gives the "
        r"mass properties of its surface as a shell\.$",
    ):
        mesh_mass_properties(vertices, faces, density=1000.0, merge_tolerance=0.0)


def test_a_gap_far_above_round_off_needs_a_larger_tolerance_which_the_message_names() -> None:
    vertices, faces = stl_box()
    exact, _ = quiet(vertices, faces)
    lift_one_copy_of_the_origin(vertices, 1e-6 * SIZE[2])  # 3e-7 m: 1e-6 of the box
    with pytest.raises(
        MeshError,
        match=r"after welding vertices closer than 3\.74e-10 m: it has holes, so it bounds no "
        r"solid\. Its vertices at the holes are at most 3e-07 m from one another: "
        r"merge_tolerance = 6e-07 m welds them and closes it\. For a sheet",
    ):
        mesh_mass_properties(vertices, faces, density=1000.0)
    mp, said = quiet(vertices, faces, merge_tolerance=6e-7)
    assert said == [
        "mesh: welded 1 vertices of its seams, moved by at most 3e-07 m (merge_tolerance 6e-07 m)."
    ]
    # The corner is welded to its exact position (the lexicographically smallest).
    assert mp.mass == pytest.approx(exact.mass, rel=1e-15)
    np.testing.assert_allclose(mp.inertia, exact.inertia, rtol=1e-14, atol=1e-17)


def test_a_real_hole_gets_no_suggestion() -> None:
    vertices, faces = stl_box()
    with pytest.raises(
        MeshError, match=r"it has holes, so it bounds no solid\. For a sheet or a thin-walled"
    ) as caught:
        mesh_mass_properties(vertices, faces[1:], density=1000.0)
    assert "merge_tolerance =" not in str(caught.value)


def test_welding_does_not_depend_on_the_vertex_order() -> None:
    rng = np.random.default_rng(3)
    points = rng.uniform(size=(200, 3))
    jittered = np.vstack([points, points + rng.normal(scale=1e-13, size=points.shape)])
    unique, inverse, _, largest = weld(jittered, 1e-9)
    assert unique.shape == (200, 3) and largest < 1e-12
    order = rng.permutation(len(jittered))
    unique2, inverse2, _, largest2 = weld(jittered[order], 1e-9)
    # Each point goes to the same place, whatever the order.
    np.testing.assert_array_equal(unique[inverse][order], unique2[inverse2])
    assert largest2 == largest


def test_welding_joins_chains_near_a_grid_cell_boundary() -> None:
    # Points straddling a cell side (the grid starts at the smallest point):
    # the neighbouring cells are searched too.
    tolerance = 1e-3
    width = 64 * tolerance
    points = np.array([[0.0, 0.0, 0.0], [width - 1e-4, 0.0, 0.0], [width + 1e-4, 0.0, 0.0]])
    unique, inverse, _, largest = weld(points, tolerance)
    assert unique.shape[0] == 2 and inverse[1] == inverse[2]
    assert largest == pytest.approx(2e-4, rel=1e-12)


def test_two_solids_sharing_a_face_are_their_union() -> None:
    # Two unit cubes side by side: the shared face's edges are four-fold (its
    # triangles have different diagonals in the two cubes, so they do not
    # cancel). The pair is a 2 × 1 × 1 box: mass 2, I = m/12 (b² + c², a² + c², a² + b²).
    first, first_faces = stl_box((1.0, 1.0, 1.0))
    second, second_faces = stl_box((1.0, 1.0, 1.0), lo=(1.0, 0.0, 0.0))
    vertices = np.vstack([first, second])
    faces = np.vstack([first_faces, second_faces + len(first)])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mp = mesh_mass_properties(vertices, faces, density=1.0)
    said = [str(w.message) for w in caught if issubclass(w.category, MeshRepairWarning)]
    assert said == [
        "mesh: 4 edges are shared by more than two triangles; read as closed pieces touching "
        "there (solids sharing edges or faces; pieces that overlap in volume would count twice)."
    ]
    assert mp.mass == pytest.approx(2.0, rel=1e-15)
    np.testing.assert_allclose(mp.center_of_mass, [1.0, 0.5, 0.5], rtol=1e-15)
    np.testing.assert_allclose(mp.inertia, box_inertia(2.0, (2.0, 1.0, 1.0)), atol=1e-14)


def test_a_mirrored_pair_sharing_a_face_cancels_the_face() -> None:
    # A cube and its mirror image across x = 1 (winding reversed to stay
    # outward): their common face is the same two triangles wound both ways.
    vertices, faces = stl_box((1.0, 1.0, 1.0))
    mirrored = vertices * [-1.0, 1.0, 1.0] + [2.0, 0.0, 0.0]
    both = np.vstack([vertices, mirrored])
    all_faces = np.vstack([faces, faces[:, ::-1] + len(vertices)])
    mp, said = quiet(both, all_faces)
    assert said == [
        "mesh: removed 2 pairs of coincident triangles of opposite winding (solids sharing a "
        "face; their integrals cancel)."
    ]
    assert mp.mass == pytest.approx(2000.0, rel=1e-15)
    np.testing.assert_allclose(mp.inertia, box_inertia(2000.0, (2.0, 1.0, 1.0)), rtol=1e-14)


def test_a_convex_decomposition_equals_its_hull() -> None:
    # The tetrahedra of a Delaunay triangulation are closed convex pieces that
    # share faces, edges and vertices; together they fill the hull.
    rng = np.random.default_rng(11)
    points = rng.normal(size=(40, 3)) * [0.3, 0.2, 0.1] + [0.5, -0.2, 0.1]
    tetrahedra = Delaunay(points).simplices
    faces = []
    for a, b, c, d in tetrahedra:
        # Outward winding: each face opposite a vertex, turned away from it.
        for face, opposite in (((b, c, d), a), ((a, d, c), b), ((a, b, d), c), ((a, c, b), d)):
            p0, p1, p2 = points[list(face)]
            if np.cross(p1 - p0, p2 - p0) @ (points[opposite] - p0) > 0:
                face = face[::-1]
            faces.append(face)
    mp, said = quiet(points, np.array(faces))
    hull = trimesh.convex.convex_hull(points)
    expected, _ = quiet(np.asarray(hull.vertices), np.asarray(hull.faces))
    assert said and "coincident triangles" in said[0]
    # The same solid summed in another order: round-off.
    assert mp.mass == pytest.approx(expected.mass, rel=1e-12)
    np.testing.assert_allclose(mp.center_of_mass, expected.center_of_mass, atol=1e-13)
    np.testing.assert_allclose(mp.inertia, expected.inertia, atol=1e-12 * expected.mass)


def test_a_nested_cavity_is_subtracted() -> None:
    # A 1 m cube with a 0.5 m cube inside wound inward: mass 1 − 0.125 (density
    # 1), inertia the difference of the two boxes' (same centre).
    outer, outer_faces = stl_box((1.0, 1.0, 1.0))
    inner, inner_faces = stl_box((0.5, 0.5, 0.5), lo=(0.25, 0.25, 0.25))
    vertices = np.vstack([outer, inner])
    faces = np.vstack([outer_faces, inner_faces[:, ::-1] + len(outer)])
    mp = mesh_mass_properties(vertices, faces, density=1.0)
    assert mp.mass == pytest.approx(0.875, rel=1e-15)
    expected = box_inertia(1.0, (1, 1, 1)) - box_inertia(0.125, (0.5, 0.5, 0.5))
    np.testing.assert_allclose(mp.inertia, expected, atol=1e-15)


def test_merge_tolerance_is_a_length_after_the_units(tmp_path) -> None:
    vertices, faces = stl_box((100.0, 200.0, 300.0))  # mm
    # 0.001 mm: above the round-off of the file's single-precision coordinates
    # (4 ε of 300 mm: 1.43e-4 mm), so not welded by default.
    lift_one_copy_of_the_origin(vertices, 1e-3)
    path = tmp_path / "box.stl"
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    with pytest.raises(MeshError, match=r"closer than 1\.43e-07 m: .* merge_tolerance = 2e-06 m"):
        tumble.from_mesh(path, density=1000.0, units="mm")
    with pytest.warns(MeshRepairWarning, match=r"moved by at most 1e-06 m"):
        mp = tumble.from_mesh(path, density=1000.0, units="mm", merge_tolerance="0.002 mm")
    assert mp.mass == pytest.approx(6.0, rel=1e-12)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (-1e-6, r"^Expected `merge_tolerance` >= 0 m, got -1e-06\.$"),
        ("5 kg", r"merge_tolerance"),
    ],
)
def test_merge_tolerance_errors(value, message) -> None:
    vertices, faces = stl_box()
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    with pytest.raises(InputError, match=message):
        tumble.from_mesh(mesh, density=1000.0, merge_tolerance=value)


def thin_walled_box(surface_density, size):
    """Mass and central inertia of the surface of a box (a, b, c) of uniform
    surface density: each pair of faces by the plate formula and the
    parallel-axis theorem (the faces normal to x at ±a/2 add, to I_xx,
    σ b c (b² + c²)/12 each, to I_yy σ b c (c²/12 + a²/4) each, ...)."""
    a, b, c = size
    inertia = np.zeros(3)
    mass = 0.0
    for axis in range(3):
        sides = [size[k] for k in range(3) if k != axis]
        face = surface_density * sides[0] * sides[1]
        mass += 2 * face
        for k in range(3):
            if k == axis:  # about the face's normal: a plate spinning in its plane
                inertia[k] += 2 * face * (sides[0] ** 2 + sides[1] ** 2) / 12
            else:  # about an axis in the face's plane, offset by half the box
                along = next(size[j] for j in range(3) if j not in (axis, k))
                inertia[k] += 2 * face * (along**2 / 12 + (size[axis] / 2) ** 2)
    assert np.isclose(mass, 2 * surface_density * (a * b + b * c + a * c))
    return mass, np.diag(inertia)


def test_the_shell_of_a_closed_box_is_the_thin_walled_box() -> None:
    vertices, faces = stl_box()
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mp = tumble.from_mesh(mesh, density="2700 kg/m^3", shell_thickness="2 mm")
    mass, inertia = thin_walled_box(2700 * 2e-3, SIZE)
    # The same integrals written two ways: round-off.
    assert mp.mass == pytest.approx(mass, rel=1e-14)
    np.testing.assert_allclose(mp.center_of_mass, np.array(SIZE) / 2, atol=1e-16)
    np.testing.assert_allclose(mp.inertia, inertia, rtol=1e-13, atol=1e-18)


def test_an_open_box_as_a_shell_and_its_total_mass() -> None:
    # Without its top (z = c): the bottom at z = 0 and four sides centred at
    # c/2, all of one surface density.
    vertices, faces = stl_box()
    keep = ~np.all(vertices[faces][:, :, 2] == SIZE[2], axis=1)
    mesh = trimesh.Trimesh(vertices, faces[keep], process=False)
    with pytest.raises(MeshError, match=r"shell_thickness gives the mass properties"):
        tumble.from_mesh(mesh, density=2700.0)
    mp = tumble.from_mesh(mesh, mass="1.5 kg", shell_thickness="1 mm")
    a, b, c = SIZE
    bottom, sides = a * b, 2 * (a * c + b * c)
    z = sides * (c / 2) / (bottom + sides)
    assert mp.mass == 1.5
    assert mp.center_of_mass[2] == pytest.approx(z, rel=1e-13)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"shell_thickness": 0.0, "density": 1.0},
            r"^Expected `shell_thickness` > 0 m, got 0\.0\.$",
        ),
        ({"shell_thickness": "5 s", "density": 1.0}, r"shell_thickness"),
        ({"shell_thickness": "1 mm", "density": -1.0}, r"^Expected `density` > 0, got -1\.0\.$"),
    ],
)
def test_shell_errors(kwargs, message) -> None:
    vertices, faces = stl_box()
    with pytest.raises(InputError, match=message):
        tumble.from_mesh(trimesh.Trimesh(vertices, faces, process=False), **kwargs)


def test_the_cli_takes_merge_tolerance_and_shell_thickness(tmp_path) -> None:
    from typer.testing import CliRunner

    from tumble.cli import app

    vertices, faces = stl_box()
    lift_one_copy_of_the_origin(vertices, 3e-7)
    path = tmp_path / "box.stl"
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    runner = CliRunner()
    refused = runner.invoke(app, ["inertia", str(path), "--density", "1000"])
    assert refused.exit_code != 0
    assert "merge_tolerance = 6e-07 m welds them" in " ".join(refused.output.split())
    welded = runner.invoke(
        app, ["inertia", str(path), "--density", "1000", "--merge-tolerance", "1 um"]
    )
    assert welded.exit_code == 0, welded.output
    assert re.search(r"mass\s*│\s*6\s*│\s*kg", welded.output)
    shell = runner.invoke(
        app, ["inertia", str(path), "--density", "1000", "--shell-thickness", "1 mm"]
    )
    assert shell.exit_code == 0, shell.output
    # 2 (ab + bc + ac) = 0.22 m² of 1 mm at 1000 kg/m³
    assert re.search(r"mass\s*│\s*0\.22\s*│\s*kg", shell.output)
    wrong = runner.invoke(app, ["inertia", "box", "--mass", "1", "--size", "1, 1, 1 m",
                                "--shell-thickness", "1 mm"])  # fmt: skip
    assert wrong.exit_code != 0
    assert "got --shell-thickness" in wrong.output


def test_a_scenario_file_takes_merge_tolerance_and_shell_thickness(tmp_path) -> None:
    from tumble.scenario.bodies import MeshBody

    body = MeshBody(mesh="box.stl", density=1000.0, merge_tolerance="1 um",
                    shell_thickness="1 mm")  # fmt: skip
    assert body.merge_tolerance == pytest.approx(1e-6)
    assert body.shell_thickness == pytest.approx(1e-3)
    with pytest.raises(ValueError, match=r"shell_thickness"):
        MeshBody(mesh="box.stl", density=1000.0, shell_thickness="0 mm")


def test_single_precision_files_get_single_precision_round_off(tmp_path) -> None:
    # STL stores coordinates in single precision: a seam 8e-8 of the part's size
    # (under a unit in the last place) is round-off there and welded by default.
    vertices, faces = stl_box((0.0625, 0.1, 0.125))
    lift_one_copy_of_the_origin(vertices, 1e-8)
    path = tmp_path / "seam.stl"
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    with pytest.warns(MeshRepairWarning, match=r"welded 1 vertices"):
        tumble.from_mesh(path, density=1000.0)
    # The same numbers as double-precision arrays: 1e-8 is far above their round-off.
    stored = trimesh.load_mesh(path, process=False)
    with pytest.raises(MeshError, match=r"merge_tolerance = 2e-08 m welds them"):
        mesh_mass_properties(np.asarray(stored.vertices, dtype=float), stored.faces, density=1.0)


def test_touching_pieces_wound_differently_are_refused() -> None:
    # A cube and, touching it along an edge, a cube wound inside out: around
    # that edge the four triangles do not pair into solid wedges.
    first, first_faces = stl_box((1.0, 1.0, 1.0))
    second, second_faces = stl_box((1.0, 1.0, 1.0), lo=(1.0, 1.0, 0.0))
    vertices = np.vstack([first, second])
    faces = np.vstack([first_faces, second_faces[:, ::-1] + len(first)])
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to be manifold, got 1 edges shared by more than two triangles, "
        r"1 of which do not split it into closed pieces wound alike \(at such an edge the "
        r"triangles must pair up around it, each pair bounding one solid wedge\)\.$",
    ):
        mesh_mass_properties(vertices, faces, density=1.0)


def test_a_mesh_of_triangles_that_all_cancel_is_refused() -> None:
    # One box listed twice, once wound each way: every edge is used four times,
    # the coincident pairs cancel and nothing is left.
    box = trimesh.creation.box(bounds=[(0, 0, 0), SIZE])
    both = np.vstack([box.faces, box.faces[:, ::-1]])
    with (
        pytest.warns(MeshRepairWarning, match=r"removed 12 pairs of coincident triangles"),
        pytest.raises(
            MeshError, match=r"^Expected mesh to enclose a volume, got triangles that cancel\.$"
        ),
    ):
        mesh_mass_properties(np.asarray(box.vertices), both, density=1.0)


@pytest.mark.parametrize(
    ("vertices", "kwargs", "error", "message"),
    [
        (np.zeros((3, 3)), {"density": 1.0}, MeshError,
         r"^Expected mesh to have a surface, got all its vertices at one point\.$"),
        (np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]), {"density": 1.0}, MeshError,
         r"^Expected mesh to have a surface, got zero area\.$"),
        (np.array([[0.0, 0, 0], [1e200, 0, 0], [0, 1e200, 0]]), {"density": 1e100}, InputError,
         r"^Expected the mass of the shell of mesh \(density × thickness × area\) within float "
         r"range, got inf kg\.$"),
    ],
)  # fmt: skip
def test_shell_errors_of_the_surface(vertices, kwargs, error, message) -> None:
    from tumble.mesh.shell import shell_mass_properties

    with pytest.raises(error, match=message):
        shell_mass_properties(vertices, np.array([[0, 1, 2]]), 1e-3, **kwargs)


def test_a_shell_refuses_a_mass_that_is_not_positive() -> None:
    vertices, faces = stl_box()
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    with pytest.raises(InputError, match=r"^Expected `mass` > 0, got 0\.0\.$"):
        tumble.from_mesh(mesh, mass=0.0, shell_thickness="1 mm")
