"""The catalogue of primitives (tumble.shapes.SHAPE_KINDS, Shape): every closed form
is in it with the dimensions it takes; each volume and bounding box against a
fine triangle mesh of the same solid (trimesh's primitives, an independent
construction), and a Shape at a density against its closed form at that mass."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
import trimesh
from numpy.testing import assert_allclose

import tumble as tb
from tumble.errors import InputError
from tumble.shapes import SHAPE_KINDS, Shape


def test_every_closed_form_is_in_the_catalogue_with_the_dimensions_it_takes() -> None:
    functions = {
        name
        for name in tb.shapes.__all__
        if inspect.isfunction(getattr(tb.shapes, name)) and name != "shape_kind"
    }
    assert {kind.function.__name__ for kind in SHAPE_KINDS.values()} == functions
    for name, kind in SHAPE_KINDS.items():
        assert name == kind.function.__name__.replace("_", "-")
        parameters = list(inspect.signature(kind.function).parameters)
        assert parameters == ["mass", *kind.dimensions]


def _turned(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """A mesh moved so that its centre of mass is at the origin."""
    return mesh.copy().apply_translation(-mesh.center_mass)


# Each solid as a fine mesh. A polygon of n sides inscribed in a circle keeps
# sin(2π/n)/(2π/n) of its area (2.5e-5 short at n = 512); an icosphere of 6
# subdivisions 1.4e-4 of a sphere's volume (measured): 3e-4 covers both.
TOLERANCE = 3e-4
SEGMENTS = 512
MESHES = {
    "box": ({"size": (0.3, 0.5, 0.7)}, lambda: trimesh.creation.box((0.3, 0.5, 0.7))),
    "solid-cylinder": (
        {"radius": 0.2, "height": 0.5},
        lambda: trimesh.creation.cylinder(0.2, 0.5, sections=SEGMENTS),
    ),
    "hollow-cylinder": (
        {"inner_radius": 0.1, "outer_radius": 0.25, "height": 0.4},
        lambda: trimesh.creation.annulus(0.1, 0.25, 0.4, sections=SEGMENTS),
    ),
    "solid-sphere": ({"radius": 0.3}, lambda: trimesh.creation.icosphere(6, 0.3)),
    "solid-cone": (
        {"radius": 0.2, "height": 0.6},
        lambda: trimesh.creation.cone(0.2, 0.6, sections=SEGMENTS),
    ),
    "ellipsoid": (
        {"semi_axes": (0.1, 0.2, 0.3)},
        lambda: trimesh.creation.icosphere(6, 1.0).apply_scale((0.1, 0.2, 0.3)),
    ),
    "torus": (
        {"major_radius": 0.3, "minor_radius": 0.1},
        lambda: trimesh.creation.torus(0.3, 0.1, major_sections=SEGMENTS, minor_sections=SEGMENTS),
    ),
    "capsule": (
        {"radius": 0.1, "cylinder_height": 0.4},
        # 256 a side: at 512 trimesh's capsule is no longer watertight (1.1e-4 short).
        lambda: trimesh.creation.capsule(0.4, 0.1, count=(256, 256)),
    ),
    "regular-tetrahedron": (
        {"edge": 0.5},
        lambda: trimesh.Trimesh(
            0.5 / math.sqrt(8) * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]),
            [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
        ),
    ),
}


@pytest.mark.parametrize("name", sorted(MESHES))
def test_the_volume_and_box_are_the_meshed_solids(name: str) -> None:
    dimensions, make = MESHES[name]
    mesh = _turned(make())
    assert mesh.is_volume
    shape = Shape.of(name, **dimensions)
    assert shape.volume == pytest.approx(mesh.volume, rel=TOLERANCE)
    low, high = shape.bounding_box
    scale = float(np.max(mesh.extents))
    assert_allclose(low, mesh.bounds[0], rtol=0, atol=TOLERANCE * scale)
    assert_allclose(high, mesh.bounds[1], rtol=0, atol=TOLERANCE * scale)


# Every kind's dimensions for the drawn surfaces, the solids of MESHES and the rest.
SURFACES = {name: dimensions for name, (dimensions, _) in MESHES.items()} | {
    "spherical-shell": {"radius": 0.3},
    "hollow-sphere": {"inner_radius": 0.2, "outer_radius": 0.3},
    "thin-rod": {"length": 0.8},
    "thin-disk": {"radius": 0.4},
    "thin-ring": {"radius": 0.4},
}


def test_every_kind_has_a_surface_checked_below() -> None:
    assert set(SURFACES) == set(SHAPE_KINDS)


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_the_surface_is_closed_centred_and_fills_the_box(name: str) -> None:
    shape = Shape.of(name, **SURFACES[name])
    mesh = trimesh.Trimesh(*shape.surface(), process=True)
    assert mesh.is_watertight
    assert mesh.volume > 0  # outward faces
    low, high = shape.bounding_box
    size = float(np.max(high - low))
    if shape.kind.volume is None:
        # An idealised thin body is drawn with a thickness of at most 1/40 of its size
        # (a rod of radius length/80, a disk of thickness radius/40, a ring's tube of
        # radius/30): the drawing stays within that of the box.
        assert np.all(mesh.bounds[0] >= low - size / 30) and np.all(
            mesh.bounds[1] <= high + size / 30
        )
        return
    # Polygons of 16 to 48 sides inscribed in circles lose < 3 % of the volume and
    # move the centre of mass by < 1 % of the size.
    assert mesh.volume == pytest.approx(shape.volume, rel=0.03)
    assert_allclose(mesh.center_mass, 0, atol=0.01 * size)
    # Inscribed polygons keep within the box and reach its faces to 2 % (cos(π/16)).
    assert np.all(mesh.bounds[0] >= low - 1e-12) and np.all(mesh.bounds[1] <= high + 1e-12)
    assert_allclose(mesh.bounds, [low, high], rtol=0, atol=0.02 * size)


def test_the_hollow_sphere_is_the_difference_of_two_spheres() -> None:
    shape = Shape.of("hollow-sphere", inner_radius=0.2, outer_radius=0.3)
    spheres = [Shape.of("solid-sphere", radius=r).volume for r in (0.3, 0.2)]
    assert shape.volume == pytest.approx(spheres[0] - spheres[1], rel=1e-15)
    assert_allclose(shape.bounding_box[1], [0.3, 0.3, 0.3], rtol=0, atol=0)


def test_at_a_density_is_the_closed_form_at_its_mass() -> None:
    # Exact: at_density is at_mass of ρ V, each a closed form of this module.
    shape = Shape.of("capsule", radius="5 cm", cylinder_height="20 cm")
    solid = shape.at_density("7800 kg/m^3")
    expected = tb.shapes.capsule(7800 * shape.volume, 0.05, 0.2)
    assert solid.mass == pytest.approx(expected.mass, rel=1e-15)
    assert_allclose(solid.inertia, expected.inertia, rtol=1e-15)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: Shape.of("cube", size=1), r"Expected a shape to be one of box, .*, got 'cube'"),
        (
            lambda: Shape.of("solid-cylinder", radius=1, height=1, edge=1),
            r"Expected only `radius`, `height` for a solid-cylinder, got `edge`\.",
        ),
        (
            lambda: Shape.of("torus", major_radius=1),
            r"Expected `minor_radius` for a torus \(it takes `major_radius`, `minor_radius`\)\.",
        ),
        (lambda: Shape.of("solid-sphere", radius="-1 m"), r"Expected `radius` > 0 m, got -1\.0\."),
        (
            lambda: Shape.of("thin-disk", radius=1).at_density(1000),
            r"Expected a solid with a volume, got a thin-disk \(an idealised thin body: give "
            r"its mass\)\.",
        ),
        (
            lambda: Shape.of("box", size=(1, 1, 1)).at_density(0),
            r"Expected `density` > 0 kg/m³, got 0\.0\.",
        ),
    ],
    ids=["kind", "extra", "missing", "negative", "thin", "density"],
)
def test_refusals(make, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InputError, match=message):
        make()


def test_the_scenario_body_takes_every_dimension_of_the_catalogue_and_no_other() -> None:
    from tumble.scenario.bodies import ShapeBody

    placed = {"shape", "mass", "translation", "rotation"}
    dimensions = {n for kind in SHAPE_KINDS.values() for n in kind.dimensions}
    assert set(ShapeBody.model_fields) - placed == dimensions
