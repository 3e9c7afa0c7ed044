"""Oracle tests for ``tumble.from_mesh``: mass properties of solids bounded by triangle meshes.

Every expected value comes from somewhere other than the mesh code: the closed
forms of ``tumble.shapes`` (themselves re-derived with sympy in
``test_shapes_symbolic.py``), exact formulas for polygonal prisms and pyramids
derived here, the classical moments of the regular polyhedra, assemblies of
boxes, or invariance under rigid motions and changes of units. Conventions: SI,
inertia about the centre of mass in the mesh's axes, ``I_xy = −∫ x y dm``.
"""

from __future__ import annotations

import importlib.util
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation
from trimesh import creation

import tumble
from tumble import InputError, MeshError, MeshOrientationWarning, shapes
from tumble.core.polyhedron import mesh_integrals
from tumble.mesh import MeshRepairWarning, mesh_mass_properties

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
MM = 1e-3
RHO_ALUMINIUM = 2700.0  # kg/m³, the density the bracket example uses


# ----------------------------------------------------------------------- helpers


def assert_same_body(actual, expected, rtol, size):
    """Same mass (relative), centre of mass (to rtol·size) and inertia (to rtol·‖I‖)."""
    assert actual.mass == pytest.approx(expected.mass, rel=rtol)
    np.testing.assert_allclose(
        actual.center_of_mass, expected.center_of_mass, rtol=0, atol=rtol * size
    )
    np.testing.assert_allclose(
        actual.inertia, expected.inertia, rtol=0, atol=rtol * np.linalg.norm(expected.inertia)
    )


def relative_error(actual, expected):
    return float(np.linalg.norm(np.asarray(actual) - expected) / np.linalg.norm(expected))


def load_example(name):
    spec = importlib.util.spec_from_file_location(
        f"_tumble_example_{name}", EXAMPLES / f"{name}.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def bracket_mesh_mm():
    """The example's L-bracket mesh, coordinates in millimetres."""
    return load_example("make_l_bracket").l_bracket()


def bracket_parts():
    """The L-bracket as two boxes (the oracle): a 60×8×30 mm leg along x with its
    corner at the origin, and an 8×32×30 mm leg on top of it along y; 2700 kg/m³."""
    parts = []
    for size_mm, centre_mm in [((60, 8, 30), (30, 4, 15)), ((8, 32, 30), (4, 8 + 16, 15))]:
        size = np.array(size_mm, dtype=float) * MM
        box = shapes.box(RHO_ALUMINIUM * float(np.prod(size)), size)
        parts.append(box.transformed(translation=np.array(centre_mm, dtype=float) * MM))
    return parts


def bracket_assembly():
    first, second = bracket_parts()
    return first + second


BRACKET_SIZE = 0.06  # m, the bracket's largest dimension, for absolute tolerances


def box_trimesh(lo, hi):
    return creation.box(bounds=[lo, hi])


def unit_cube():
    mesh = box_trimesh((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def raw(vertices, faces):
    """A trimesh that keeps exactly the given arrays (no merging, no repair)."""
    return trimesh.Trimesh(
        np.asarray(vertices, dtype=float), np.asarray(faces), process=False, validate=False
    )


# ------------------------------------------------------------------ convergence
#
# A tessellation inscribed in a curved surface replaces each arc of angular
# width δ by its chord; the gap (sagitta) is R(1 − cos(δ/2)) ≈ R δ²/8, so the
# missing volume and every change of a moment are O(δ²): doubling the angular
# resolution divides the error by 4 (order 2). For the cylinder this is exact:
# the prism over a regular n-gon has I_zz/m = R² (2 + cos(2π/n))/6, a relative
# error (1 − cos(2π/n))/3 ≈ (2π²/3)/n² (see test_polygonal_prism_is_exact).
# Both the mesh and the closed form are compared per unit mass (the gyration
# tensor I/m), since the mesh's volume is itself slightly short; the volume is
# checked separately and converges at the same order.

RADIUS, HEIGHT, INNER = 0.5, 1.2, 0.3
SEMI_AXES = np.array([0.6, 0.45, 0.3])
MAJOR, MINOR = 1.0, 0.3
SECTIONS = [16, 32, 64, 128, 256]
SUBDIVISIONS = [1, 2, 3, 4, 5]  # each halves the icosphere's edges


def _ellipsoid(k):
    sphere = creation.icosphere(subdivisions=k, radius=1.0)
    return raw(np.asarray(sphere.vertices) * SEMI_AXES, sphere.faces)


def _centred(mesh):
    return np.zeros(3)


def _cone_com(mesh):
    # Any pyramid's centroid lies a quarter of the way from its base to its apex
    # (cross-sections scale as s², and ∫ z s² dz / ∫ s² dz = H/4 with s = 1 − z/H).
    z_base, z_apex = mesh.bounds[:, 2]
    assert z_apex - z_base == pytest.approx(HEIGHT, rel=1e-14)
    return np.array([0.0, 0.0, z_base + HEIGHT / 4])


CONVERGENCE = {
    "sphere": (
        lambda k: creation.icosphere(subdivisions=k, radius=RADIUS),
        SUBDIVISIONS,
        shapes.solid_sphere(1.0, RADIUS),
        4 / 3 * math.pi * RADIUS**3,
        _centred,
    ),
    "ellipsoid": (
        _ellipsoid,
        SUBDIVISIONS,
        shapes.ellipsoid(1.0, SEMI_AXES),
        4 / 3 * math.pi * float(np.prod(SEMI_AXES)),
        _centred,
    ),
    "cylinder": (
        lambda n: creation.cylinder(radius=RADIUS, height=HEIGHT, sections=n),
        SECTIONS,
        shapes.solid_cylinder(1.0, RADIUS, HEIGHT),
        math.pi * RADIUS**2 * HEIGHT,
        _centred,
    ),
    "cone": (
        lambda n: creation.cone(radius=RADIUS, height=HEIGHT, sections=n),
        SECTIONS,
        shapes.solid_cone(1.0, RADIUS, HEIGHT),
        math.pi * RADIUS**2 * HEIGHT / 3,
        _cone_com,
    ),
    "capsule": (
        lambda n: creation.capsule(height=HEIGHT, radius=RADIUS, count=[n, n]),
        SECTIONS,
        shapes.capsule(1.0, RADIUS, HEIGHT),
        math.pi * RADIUS**2 * HEIGHT + 4 / 3 * math.pi * RADIUS**3,
        _centred,
    ),
    "hollow_cylinder": (
        lambda n: creation.annulus(r_min=INNER, r_max=RADIUS, height=HEIGHT, sections=n),
        SECTIONS,
        shapes.hollow_cylinder(1.0, INNER, RADIUS, HEIGHT),
        math.pi * (RADIUS**2 - INNER**2) * HEIGHT,
        _centred,
    ),
    "torus": (
        lambda n: creation.torus(
            major_radius=MAJOR, minor_radius=MINOR, major_sections=n, minor_sections=n
        ),
        [8, 16, 32, 64, 128],
        shapes.torus(1.0, MAJOR, MINOR),
        2 * math.pi**2 * MAJOR * MINOR**2,
        _centred,
    ),
}


@pytest.mark.parametrize("name", list(CONVERGENCE))
def test_tessellations_converge_to_the_closed_form_at_second_order(name):
    build, resolutions, exact, exact_volume, expected_com = CONVERGENCE[name]
    gyration = exact.inertia / exact.mass
    inertia_errors, volume_errors = [], []
    for resolution in resolutions:
        mesh = build(resolution)
        mp = tumble.from_mesh(mesh, density=1.0)  # so mass == volume, m³
        size = float(np.ptp(mesh.vertices, axis=0).max())
        # The centre of mass is fixed by the mesh's symmetry (or, for the cone, by
        # the pyramid's quarter-height rule) at every resolution, to round-off.
        np.testing.assert_allclose(mp.center_of_mass, expected_com(mesh), rtol=0, atol=1e-12 * size)
        inertia_errors.append(relative_error(mp.inertia / mp.mass, gyration))
        volume_errors.append(abs(mp.mass - exact_volume) / exact_volume)

    for errors in (inertia_errors, volume_errors):
        orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
        # Observed orders tend to 2 from below as the O(δ⁴) term fades: at the
        # coarsest step (80-triangle icosphere, 8-section torus) it is ≈ 1.9.
        assert np.all((orders > 1.8) & (orders < 2.2)), f"orders {orders}, errors {errors}"
    # At the finest resolution the error is the coarsest one over 4⁴ = 256; the
    # coarsest errors are at most ~0.1 (sphere, torus) and ~0.2 in volume.
    assert inertia_errors[-1] < 1e-3
    assert volume_errors[-1] < 2e-3


@pytest.mark.parametrize("n_sides", [3, 5, 12])
def test_polygonal_prism_is_exact(n_sides):
    # trimesh's n-section cylinder is exactly the prism over a regular n-gon of
    # circumradius R. With α = 2π/n, the n-gon is n triangles (centre, P_k, P_k+1)
    # of area R² sin α / 2; a triangle with a vertex at the centre has
    # ∫ |x|² dA = A R² (2 + cos α)/6, and the n-fold symmetry makes the area
    # tensor isotropic. Per unit mass: I_zz = R² (2 + cos α)/6 (→ R²/2 as n → ∞)
    # and I_xx = I_yy = I_zz/2 + H²/12; the volume is n R² sin(α) H / 2.
    alpha = 2 * math.pi / n_sides
    mesh = creation.cylinder(radius=RADIUS, height=HEIGHT, sections=n_sides)
    mp = tumble.from_mesh(mesh, density=1.0)
    axial = RADIUS**2 * (2 + math.cos(alpha)) / 6
    expected = np.diag([axial / 2 + HEIGHT**2 / 12, axial / 2 + HEIGHT**2 / 12, axial])
    # Exact formula for the exact polyhedron: round-off only.
    assert mp.mass == pytest.approx(n_sides * RADIUS**2 * math.sin(alpha) * HEIGHT / 2, rel=1e-13)
    np.testing.assert_allclose(
        mp.inertia / mp.mass, expected, rtol=0, atol=1e-13 * np.linalg.norm(expected)
    )


@pytest.mark.parametrize("n_sides", [3, 5, 12])
def test_polygonal_pyramid_is_exact(n_sides):
    # The cross-section at height z is the base n-gon scaled by s = 1 − z/H
    # (area A s², polar moment J s⁴). Per unit mass:
    #   I_zz = (J/A) ∫s⁴dz / ∫s²dz = (3/5) R² (2 + cos α)/6 = R² (2 + cos α)/10,
    #   I_xx = I_zz/2 + Var(z) with z̄ = H/4, E[z²] = H²/10, Var(z) = 3H²/80;
    # V = A H / 3. As n → ∞ these are the cone's 3R²/10 and 3R²/20 + 3H²/80.
    alpha = 2 * math.pi / n_sides
    mesh = creation.cone(radius=RADIUS, height=HEIGHT, sections=n_sides)
    mp = tumble.from_mesh(mesh, density=1.0)
    axial = RADIUS**2 * (2 + math.cos(alpha)) / 10
    expected = np.diag([axial / 2 + 3 * HEIGHT**2 / 80, axial / 2 + 3 * HEIGHT**2 / 80, axial])
    assert mp.mass == pytest.approx(n_sides * RADIUS**2 * math.sin(alpha) * HEIGHT / 6, rel=1e-13)
    np.testing.assert_allclose(
        mp.inertia / mp.mass, expected, rtol=0, atol=1e-13 * np.linalg.norm(expected)
    )


def test_box_is_exact_against_its_closed_form():
    # A box mesh is the box: no discretisation error at all.
    lo, hi = np.array([-0.25, 0.5, 1.0]), np.array([0.75, 0.625, 1.5])
    mp = tumble.from_mesh(box_trimesh(lo, hi), density=7800.0)
    size = hi - lo
    expected = shapes.box(7800.0 * float(np.prod(size)), size).transformed(
        translation=(lo + hi) / 2
    )
    assert_same_body(mp, expected, rtol=1e-13, size=1.0)


# ------------------------------------------------------------- regular polyhedra

PHI = (1 + math.sqrt(5)) / 2
SIGNS = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def _cyclic(points):
    return [tuple(np.roll(p, k)) for p in points for k in range(3)]


# name: (vertices, edge, c in I = c m a², k in V = k a³)
REGULAR = {
    # Alternate cube corners (even number of minus signs): edge |(1,1,1) − (1,−1,−1)| = 2√2.
    "tetrahedron": (
        [s for s in SIGNS if np.prod(s) > 0],
        2 * math.sqrt(2),
        1 / 20,
        1 / (6 * math.sqrt(2)),
    ),
    "cube": (SIGNS, 2.0, 1 / 6, 1.0),
    # (±1, 0, 0) and permutations: edge |(1,0,0) − (0,1,0)| = √2.
    "octahedron": (_cyclic([(1, 0, 0), (-1, 0, 0)]), math.sqrt(2), 1 / 10, math.sqrt(2) / 3),
    # Cyclic permutations of (0, ±1, ±φ): edge 2.
    "icosahedron": (
        _cyclic([(0, s1, s2 * PHI) for s1 in (-1, 1) for s2 in (-1, 1)]),
        2.0,
        (3 + math.sqrt(5)) / 20,
        5 * (3 + math.sqrt(5)) / 12,
    ),
    # (±1, ±1, ±1) and cyclic permutations of (0, ±1/φ, ±φ): edge 2/φ.
    "dodecahedron": (
        SIGNS + _cyclic([(0, s1 / PHI, s2 * PHI) for s1 in (-1, 1) for s2 in (-1, 1)]),
        2 / PHI,
        (95 + 39 * math.sqrt(5)) / 300,
        (15 + 7 * math.sqrt(5)) / 4,
    ),
}


@pytest.mark.parametrize("rotated", [False, True], ids=["aligned", "rotated"])
@pytest.mark.parametrize("name", list(REGULAR))
def test_regular_polyhedra_are_isotropic(name, rotated):
    # Every regular polyhedron has more than one 3-fold symmetry axis, so its
    # inertia tensor commutes with rotations about non-parallel axes and must be
    # a multiple of the identity, I = c m a², in any orientation.
    points, edge, c, k = REGULAR[name]
    points = np.array(points, dtype=float)
    if rotated:
        points = Rotation.from_euler("zyx", [0.3, -1.1, 2.0]).apply(points)
    distances = np.linalg.norm(points[:, None] - points[None], axis=-1)
    assert distances[distances > 1e-9].min() == pytest.approx(edge, rel=1e-14)  # the stated edge
    hull = trimesh.convex.convex_hull(points)
    mp = tumble.from_mesh(hull, density=1.0)
    # Exact polyhedra, coordinates within a few ulps: round-off only.
    assert mp.mass == pytest.approx(k * edge**3, rel=1e-12)
    np.testing.assert_allclose(mp.center_of_mass, 0.0, rtol=0, atol=1e-12 * edge)
    expected = c * mp.mass * edge**2 * np.eye(3)
    np.testing.assert_allclose(mp.inertia, expected, rtol=0, atol=1e-12 * np.linalg.norm(expected))


# --------------------------------------------------------------- rigid motions


def random_polyhedron(seed):
    rng = np.random.default_rng(seed)
    return trimesh.convex.convex_hull(rng.normal(size=(30, 3)) * [0.9, 0.5, 0.3])


MOTION_MESHES = {
    "bracket": lambda: raw(np.asarray(bracket_mesh_mm().vertices) * MM, bracket_mesh_mm().faces),
    "polyhedron": lambda: random_polyhedron(4),
}


@pytest.mark.parametrize(
    "rotation",
    [
        Rotation.from_euler("zyx", [0.3, -1.1, 2.0]),
        Rotation.random(random_state=1),
        Rotation.random(random_state=2),
    ],
    ids=["euler", "random1", "random2"],
)
@pytest.mark.parametrize("name", list(MOTION_MESHES))
def test_moving_the_mesh_moves_the_mass_properties(name, rotation):
    # Moving a body rigidly (x → R x + t) carries its centre of mass along and
    # rotates its central inertia, I → R I Rᵀ; the mass is unchanged.
    mesh = MOTION_MESHES[name]()
    translation = np.array([0.3, -1.25, 0.8])
    moved = raw(rotation.apply(mesh.vertices) + translation, mesh.faces)
    expected = tumble.from_mesh(mesh, density=1000.0).transformed(rotation, translation)
    # The rotated coordinates are rounded once (a few eps relative), and both
    # sides are sums of tens of well-conditioned terms: round-off, ~1e-15.
    size = float(np.ptp(mesh.vertices, axis=0).max()) + float(np.linalg.norm(translation))
    assert_same_body(tumble.from_mesh(moved, density=1000.0), expected, rtol=1e-12, size=size)


def _inertia_about_origin_reference(vertices, faces):
    """Central inertia (density 1) from integrals taken about the coordinate origin."""
    result = mesh_integrals(
        np.ascontiguousarray(vertices, dtype=float),
        np.ascontiguousarray(faces, dtype=np.int64),
        np.zeros(3),
    )
    volume, first = result[0], result[1:4]
    sxx, syy, szz, sxy, sxz, syz = result[4:10]
    second = np.array([[sxx, sxy, sxz], [sxy, syy, syz], [sxz, syz, szz]])
    centroid = first / volume
    central = second - volume * np.outer(centroid, centroid)
    return np.trace(central) * np.eye(3) - central


def test_a_mesh_far_from_the_origin_keeps_its_central_inertia():
    mesh = MOTION_MESHES["bracket"]()
    size = float(np.ptp(mesh.vertices, axis=0).max())
    offset = 1e4 * size * np.array([0.8, -0.6, 0.5])
    far = raw(np.asarray(mesh.vertices) + offset, mesh.faces)
    near_mp = tumble.from_mesh(mesh, density=1.0)
    far_mp = tumble.from_mesh(far, density=1.0)
    # Translation invariance of central inertia. The far coordinates carry a
    # rounding of eps·|offset| ≈ 2e-12·size, which alone perturbs the inertia by
    # ~1e-11 relative; 1e-9 leaves margin while still demanding ~7 more digits
    # than the naive sum below keeps.
    assert far_mp.mass == pytest.approx(near_mp.mass, rel=1e-9)
    np.testing.assert_allclose(
        far_mp.center_of_mass, near_mp.center_of_mass + offset, rtol=0, atol=1e-9 * size
    )
    assert relative_error(far_mp.inertia, near_mp.inertia) < 1e-9

    # Why the reference point matters: summing tetrahedra from the far origin,
    # each triple product a·(b×c) of vectors of length L rounds by ~eps·L³ while
    # its value is ~L·s², and the second moments multiply that by L², so the
    # central inertia (~s⁵) is lost to ~eps·(L/s)⁵ ≈ 1e4. The kernel is exact in
    # both cases; only the choice of a nearby reference keeps the digits.
    naive = _inertia_about_origin_reference(far.vertices, far.faces)
    assert relative_error(naive, near_mp.inertia) > 1e-6


# ------------------------------------------------------------------------- files


def _write_stl_binary(mesh, path):
    path = path.with_suffix(".stl")
    path.write_bytes(trimesh.exchange.stl.export_stl(mesh))
    return path


def _write_stl_ascii(mesh, path):
    path = path.with_suffix(".stl")
    path.write_text(trimesh.exchange.stl.export_stl_ascii(mesh))
    return path


def _writer(suffix, **kwargs):
    def write(mesh, path):
        path = path.with_suffix(suffix)
        mesh.export(path, **kwargs)
        return path

    return write


WRITERS = {
    "stl-binary": _write_stl_binary,
    "stl-ascii": _write_stl_ascii,
    "obj": _writer(".obj"),
    "ply-binary": _writer(".ply"),
    "ply-ascii": _writer(".ply", encoding="ascii"),
    "off": _writer(".off"),
    "glb": _writer(".glb"),
}


@pytest.mark.parametrize("as_str", [False, True], ids=["Path", "str"])
@pytest.mark.parametrize("file_format", list(WRITERS))
def test_mesh_files_give_the_assembly_of_two_boxes(tmp_path, file_format, as_str):
    # The bracket's corners are whole millimetres: exact in float32 (STL, PLY,
    # GLB) and in the text formats, so every format holds the same polyhedron.
    path = WRITERS[file_format](bracket_mesh_mm(), tmp_path / "bracket")
    mp = tumble.from_mesh(str(path) if as_str else path, density=RHO_ALUMINIUM, units="mm")
    # Exact geometry against an exact closed form: round-off only.
    assert_same_body(mp, bracket_assembly(), rtol=1e-12, size=BRACKET_SIZE)


def test_shipped_l_bracket_is_two_boxes_and_shows_the_sign_of_the_products():
    mp = tumble.from_mesh(EXAMPLES / "l_bracket.stl", density="2700 kg/m^3", units="mm")
    assembly = bracket_assembly()
    assert_same_body(mp, assembly, rtol=1e-12, size=BRACKET_SIZE)

    # Sign of I_xy = −∫ (x − x̄)(y − ȳ) dm. Each leg is a box whose own central
    # product vanishes by symmetry, so by the parallel-axis theorem
    # I_xy = −Σ m_k dx_k dy_k with d_k = (leg centre − bracket centre). The long
    # leg lies to the right of and below the centre of mass (dx > 0, dy < 0), the
    # upright leg to its left and above (dx < 0, dy > 0): mass sits in the
    # quadrants where x y < 0, so ∫ x y dm < 0 and I_xy > 0.
    i_xy = 0.0
    for part in bracket_parts():
        dx, dy = (part.center_of_mass - assembly.center_of_mass)[:2]
        assert dx * dy < 0
        i_xy -= part.mass * dx * dy
    assert mp.inertia[0, 1] == pytest.approx(i_xy, rel=1e-12)
    assert mp.inertia[0, 1] > 0
    # The bracket is symmetric about its mid-plane z = 15 mm: no xz, yz products.
    np.testing.assert_allclose(
        mp.inertia[[0, 1], [2, 2]], 0.0, atol=1e-12 * np.linalg.norm(mp.inertia)
    )


def test_units_mm_equals_the_same_mesh_in_metres(tmp_path):
    mesh_mm = bracket_mesh_mm()
    mm_file = _write_stl_binary(mesh_mm, tmp_path / "bracket_mm")
    metre_file = tmp_path / "bracket_m.obj"
    # 17 significant digits round-trip float64 exactly.
    metre_file.write_text(
        trimesh.exchange.obj.export_obj(
            raw(np.asarray(mesh_mm.vertices) * MM, mesh_mm.faces), digits=17
        )
    )
    from_mm = tumble.from_mesh(mm_file, density=RHO_ALUMINIUM, units="mm")
    from_m = tumble.from_mesh(metre_file, density=RHO_ALUMINIUM)
    # x_mm · 0.001 and the metre coordinate differ by at most an ulp.
    assert_same_body(from_mm, from_m, rtol=1e-12, size=BRACKET_SIZE)


def test_a_ten_millimetre_cube_of_water_weighs_one_gram(tmp_path):
    path = _write_stl_binary(box_trimesh((0, 0, 0), (10, 10, 10)), tmp_path / "cube")
    # (0.01 m)³ · 1000 kg/m³ = 1e-3 kg, I = m a²/6 about the centre (5, 5, 5) mm.
    for density in (1000.0, "1 g/cm^3", "1000 kg/m^3"):
        mp = tumble.from_mesh(path, density=density, units="mm")
        assert mp.mass == pytest.approx(1e-3, rel=1e-12)
        np.testing.assert_allclose(mp.center_of_mass, [5e-3] * 3, rtol=1e-12)
        np.testing.assert_allclose(
            mp.inertia, 1e-3 * 0.01**2 / 6 * np.eye(3), rtol=0, atol=1e-12 * 1e-3 * 0.01**2
        )


def test_an_inch_cube_uses_the_exact_inch(tmp_path):
    # 1 inch = 25.4 mm exactly, so a 1-inch cube at 1000 kg/m³ is 16.387064 g.
    path = _write_stl_binary(box_trimesh((0, 0, 0), (1, 1, 1)), tmp_path / "inch")
    assert tumble.from_mesh(path, density=1000.0, units="inch").mass == pytest.approx(
        16.387064e-3, rel=1e-12
    )


def test_mass_gives_the_same_body_as_the_matching_density(tmp_path):
    path = _write_stl_binary(bracket_mesh_mm(), tmp_path / "bracket")
    # Closed-form volume of the two legs: (60·8 + 8·32)·30 mm³ = 22 080 mm³.
    volume = (60 * 8 + 8 * 32) * 30 * MM**3
    mass = RHO_ALUMINIUM * volume  # 59.616 g
    by_density = tumble.from_mesh(path, density=RHO_ALUMINIUM, units="mm")
    for given in (mass, f"{mass * 1e3!r} g"):
        by_mass = tumble.from_mesh(path, mass=given, units="mm")
        assert_same_body(by_mass, by_density, rtol=1e-12, size=BRACKET_SIZE)


def test_binary_stl_repeats_vertices_and_still_loads_as_a_closed_solid(tmp_path):
    lo, hi = np.array([0.5, -1.0, 2.0]), np.array([2.5, 0.5, 2.75])
    path = _write_stl_binary(box_trimesh(lo, hi), tmp_path / "cube")
    loaded = trimesh.load_mesh(path, process=False)
    # Three fresh vertices per triangle: without merging, every edge would be a
    # boundary edge and the watertight check would reject the file.
    assert loaded.vertices.shape == (36, 3) and loaded.faces.shape == (12, 3)
    mp = tumble.from_mesh(path, density=1.0)
    size = hi - lo
    expected = shapes.box(float(np.prod(size)), size).transformed(translation=(lo + hi) / 2)
    assert_same_body(mp, expected, rtol=1e-12, size=float(size.max()))


def test_scene_of_two_boxes_is_their_assembly():
    first = box_trimesh((0, 0, 0), (1, 2, 1))
    second = box_trimesh((3, 0, 0), (4, 1, 0.5))
    scene = trimesh.Scene([first, second])
    mp = tumble.from_mesh(scene, density=10.0)
    parts = [
        shapes.box(10.0 * m.volume, np.ptp(m.vertices, axis=0)).transformed(
            translation=m.bounds.mean(axis=0)
        )
        for m in (first, second)
    ]
    assert_same_body(mp, parts[0] + parts[1], rtol=1e-12, size=4.0)


def test_an_inward_wound_inner_shell_is_a_cavity():
    # A closed outer surface with a second, inward-wound closed surface inside it
    # bounds a hollow solid: by the divergence theorem the inner shell subtracts
    # its volume integrals. Oracle: outer box minus inner box, about a common point.
    outer = box_trimesh((-1, -1, -1), (1, 1, 1))
    inner = box_trimesh((-0.25, -0.5, -0.5), (0.75, 0.5, 0.5))
    vertices = np.vstack([outer.vertices, inner.vertices])
    faces = np.vstack([outer.faces, inner.faces[:, ::-1] + len(outer.vertices)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshOrientationWarning)  # net volume is positive
        mp = tumble.from_mesh(raw(vertices, faces), density=1.0)

    volume = 8.0 - 1.0
    inner_centre = np.array([0.25, 0.0, 0.0])
    com = -1.0 * inner_centre / volume  # (8·0 − 1·c)/7

    def about(point, mass, size, centre):
        body = shapes.box(mass, size).transformed(translation=centre)
        return body.inertia_about(point)

    expected = about(com, 8.0, (2, 2, 2), np.zeros(3)) - about(com, 1.0, (1, 1, 1), inner_centre)
    assert mp.mass == pytest.approx(volume, rel=1e-13)
    np.testing.assert_allclose(mp.center_of_mass, com, rtol=0, atol=1e-13)
    np.testing.assert_allclose(mp.inertia, expected, rtol=0, atol=1e-13 * np.linalg.norm(expected))


# ------------------------------------------------------------------ orientation


def test_inside_out_mesh_warns_and_gives_the_same_body():
    mesh = MOTION_MESHES["bracket"]()
    inside_out = raw(mesh.vertices, np.asarray(mesh.faces)[:, ::-1])
    with pytest.warns(
        MeshOrientationWarning,
        match=r"mesh is inside out \(normals point inward, signed volume -\S+ m³\); "
        r"its winding was reversed\.",
    ) as record:
        mp = tumble.from_mesh(inside_out, density=RHO_ALUMINIUM)
    # The warning points at the caller's line, not at tumble's internals.
    assert record[0].filename == __file__
    # Reversed triangles negate every integral (to round-off: the reversed
    # triangle's terms are summed in another order); the wrapper negates back.
    assert_same_body(
        mp, tumble.from_mesh(mesh, density=RHO_ALUMINIUM), rtol=1e-13, size=BRACKET_SIZE
    )


def test_correct_mesh_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tumble.from_mesh(MOTION_MESHES["bracket"](), density=RHO_ALUMINIUM)


# ----------------------------------------------------------------------- errors


def test_one_missing_triangle_leaves_three_boundary_edges():
    vertices, faces = unit_cube()
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to be closed \(watertight\), got 3 boundary edges "
        r"\(edges of only one triangle, 3\.41 m long in all, 2 of the mesh's diagonal\) "
        r"after welding vertices closer than 4\.77e-07 m: it has holes, so it bounds no "
        r"solid\. For a sheet or a thin-walled part, shell_thickness gives the mass "
        r"properties of its surface as a shell\.$",
    ):
        tumble.from_mesh(raw(vertices, faces[1:]), density=1.0)


def test_one_missing_square_leaves_four_boundary_edges():
    vertices, faces = unit_cube()
    # The two triangles of the x = 1 face share their diagonal, which goes with them.
    on_face = np.all(vertices[faces][:, :, 0] == 1.0, axis=1)
    assert on_face.sum() == 2
    with pytest.raises(MeshError, match=r"got 4 boundary edges"):
        tumble.from_mesh(raw(vertices, faces[~on_face]), density=1.0)


def test_open_mesh_file_names_the_file(tmp_path):
    vertices, faces = unit_cube()
    path = _write_stl_binary(raw(vertices, faces[1:]), tmp_path / "open")
    with pytest.raises(
        MeshError, match=rf"Expected mesh {re.escape(repr(str(path)))} to be closed"
    ):
        tumble.from_mesh(path, density=1.0)


def test_open_scene_is_labelled_as_a_scene():
    vertices, faces = unit_cube()
    scene = trimesh.Scene([raw(vertices, faces[1:])])
    with pytest.raises(
        MeshError, match=r"Expected mesh \(scene\) to be closed \(watertight\), got 3 boundary"
    ):
        tumble.from_mesh(scene, density=1.0)


def test_two_cubes_sharing_an_edge_are_two_closed_pieces():
    # The edge x = y = 1 belongs to two triangles of each cube: four in all. Each
    # cube is closed: the pair's mass is 2, its centre (1, 1, 0.5), and about it
    # each cube adds 1/6 + m d⊥² with d = (±0.5, ±0.5, 0): I_xx = I_yy = 2 (1/6 +
    # 1/4), I_zz = 2 (1/6 + 1/2), I_xy = −Σ m x y = −0.5.
    first = box_trimesh((0, 0, 0), (1, 1, 1))
    second = box_trimesh((1, 1, 0), (2, 2, 1))
    vertices = np.vstack([first.vertices, second.vertices])
    faces = np.vstack([first.faces, second.faces + len(first.vertices)])
    with pytest.warns(
        MeshRepairWarning,
        match=r"^mesh: 1 edges are shared by more than two triangles; read as closed "
        r"pieces touching there \(solids sharing edges or faces; pieces that overlap in "
        r"volume would count twice\)\.$",
    ):
        mp = tumble.from_mesh(raw(vertices, faces), density=1.0)
    assert mp.mass == pytest.approx(2.0, rel=1e-15)
    np.testing.assert_allclose(mp.center_of_mass, [1.0, 1.0, 0.5], rtol=1e-15)
    expected = [[5 / 6, -0.5, 0.0], [-0.5, 5 / 6, 0.0], [0.0, 0.0, 4 / 3]]
    np.testing.assert_allclose(mp.inertia, expected, atol=1e-14)


def test_a_fin_listed_with_both_windings_cancels():
    # A zero-thickness fin (one triangle, listed with both windings) hanging from
    # the cube edge (0,0,0)–(1,0,0): its two triangles cancel in every integral,
    # so they are removed (said), and the cube is what is left.
    vertices, faces = unit_cube()
    p, q = (
        np.flatnonzero(np.all(vertices == corner, axis=1))[0] for corner in ([0, 0, 0], [1, 0, 0])
    )
    tip = len(vertices)
    cube = tumble.from_mesh(raw(vertices, faces), density=1.0)
    vertices = np.vstack([vertices, [0.5, -1.0, -1.0]])
    faces = np.vstack([faces, [[p, q, tip], [p, tip, q]]])
    with pytest.warns(
        MeshRepairWarning,
        match=r"^mesh: removed 1 pairs of coincident triangles of opposite winding \(solids "
        r"sharing a face; their integrals cancel\)\.$",
    ):
        mp = tumble.from_mesh(raw(vertices, faces), density=1.0)
    # The fin's tip stays a vertex and moves the integration's reference point:
    # round-off only.
    assert mp.mass == pytest.approx(cube.mass, rel=1e-15)
    np.testing.assert_allclose(mp.inertia, cube.inertia, atol=1e-16)


def test_edges_of_more_than_two_triangles_that_close_no_piece_are_refused():
    # A fin of one triangle (one winding) on a cube edge: that edge has three
    # triangles and the fin's other edges one each. Refused for its holes first.
    vertices, faces = unit_cube()
    p, q = (
        np.flatnonzero(np.all(vertices == corner, axis=1))[0] for corner in ([0, 0, 0], [1, 0, 0])
    )
    vertices = np.vstack([vertices, [0.5, -1.0, -1.0]])
    faces = np.vstack([faces, [[p, q, len(vertices) - 1]]])
    with pytest.raises(MeshError, match=r"got 2 boundary edges"):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


def test_one_flipped_triangle_is_inconsistent_winding():
    vertices, faces = unit_cube()
    faces = faces.copy()
    faces[0] = faces[0, ::-1]
    # Each of its three edges is now traversed in the same direction as by its neighbour.
    with pytest.raises(
        MeshError,
        match=r"Expected mesh to have consistent winding, got 3 edges traversed in "
        r"the same direction by both of their triangles \(some triangles are "
        r"flipped; trimesh\.repair\.fix_normals, with networkx installed, can repair it\)\.",
    ):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


def test_one_flipped_square_is_inconsistent_on_its_four_sides():
    vertices, faces = unit_cube()
    faces = faces.copy()
    on_face = np.all(vertices[faces][:, :, 0] == 1.0, axis=1)
    faces[on_face] = faces[on_face][:, ::-1]
    # The shared diagonal is flipped in both triangles, so it stays consistent.
    with pytest.raises(MeshError, match=r"got 4 edges traversed in the same direction"):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


ZERO_VOLUME = (
    r"Expected mesh to enclose a volume, got a signed volume of {} m³ \(flat or self-cancelling\)\."
)


def test_doubled_triangle_has_zero_volume():
    # Closed, manifold and consistently wound, but the two sides cancel exactly.
    vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    with pytest.raises(MeshError, match=ZERO_VOLUME.format("0")):
        tumble.from_mesh(raw(vertices, [[0, 1, 2], [0, 2, 1]]), density=1.0)


def test_flattened_box_has_zero_volume():
    # Squashing a box to z = 0 merges top and bottom corners; the sides become
    # zero-area triangles and are dropped, the lids cancel.
    vertices, faces = unit_cube()
    vertices = vertices * [1.0, 1.0, 0.0]
    with pytest.raises(MeshError, match=ZERO_VOLUME.format("0")):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


def flat_pillow(vertices_xy, z):
    """A flat pentagon, fanned from vertex 0 on top and from vertex 1 underneath:
    closed and consistently wound, with zero enclosed volume."""
    vertices = np.column_stack([vertices_xy, np.full(5, z)])
    faces = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [1, 3, 2], [1, 4, 3], [1, 0, 4]]
    return vertices, np.array(faces)


def test_tilted_flat_pillow_has_zero_volume():
    # In a tilted plane the two different fans cancel only to round-off; the
    # volume is then ~1e-17 of area × size, far below the flatness threshold.
    xy = np.array([[0.1, 0.1], [2.1, -0.1], [1.9, 0.9], [0.9, 1.9], [0.2, 0.8]])
    vertices, faces = flat_pillow(xy, 0.21)
    vertices = Rotation.from_euler("xy", [0.4, 0.3]).apply(vertices)
    with pytest.raises(MeshError, match=ZERO_VOLUME.format(r"-?[0-9.e+-]+")):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


def test_axis_aligned_flat_pillow_has_zero_volume():
    # The vertex mean (the kernel's reference) may sit an ulp off the plane, so
    # the fans cancel only to ~1e-33 m³: still round-off against area × size.
    xy = np.array([[0.1, 0.1], [2.1, -0.1], [1.9, 0.9], [0.9, 1.9], [0.2, 0.8]])
    vertices, faces = flat_pillow(xy, 0.21)
    with pytest.raises(MeshError, match=ZERO_VOLUME.format(r"-?[0-9.e+-]+")):
        tumble.from_mesh(raw(vertices, faces), density=1000.0)


def test_no_triangles():
    with pytest.raises(MeshError, match=r"Expected mesh to have triangles, got none"):
        tumble.from_mesh(raw(np.zeros((3, 3)), np.zeros((0, 3), dtype=np.int64)), density=1.0)


def test_only_zero_area_triangles():
    # Three copies of one point: the single triangle collapses when they merge.
    with pytest.raises(
        MeshError, match=r"Expected mesh to have triangles of non-zero area, got none\."
    ):
        tumble.from_mesh(raw(np.ones((3, 3)), [[0, 1, 2]]), density=1.0)


def test_faces_that_are_not_triangles():
    vertices, faces = unit_cube()
    with pytest.raises(
        MeshError, match=r"Expected mesh to have triangles, got faces of shape \(12, 4\)\."
    ):
        mesh_mass_properties(vertices, np.column_stack([faces, faces[:, 0]]), density=1.0)


def test_vertices_that_are_not_three_dimensional():
    vertices, faces = unit_cube()
    with pytest.raises(
        MeshError, match=r"Expected mesh vertices of shape \(n, 3\), got \(8, 2\)\."
    ):
        mesh_mass_properties(vertices[:, :2], faces, density=1.0)


@pytest.mark.parametrize("bad_rows, count", [([0], 1), ([2, 5], 2)])
def test_non_finite_vertices(bad_rows, count):
    vertices, faces = unit_cube()
    vertices[bad_rows[0], 1] = np.nan
    vertices[bad_rows[-1], 2] = np.inf
    with pytest.raises(
        MeshError, match=rf"Expected mesh vertices to be finite, got {count} with NaN or inf\."
    ):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


@pytest.mark.parametrize("bad, low, high", [(8, 0, 8), (-1, -1, 7)])
def test_face_indices_out_of_range(bad, low, high):
    vertices, faces = unit_cube()
    faces = faces.copy()
    faces[3, 1] = bad
    with pytest.raises(
        MeshError,
        match=rf"Expected mesh face indices in \[0, 7\], got indices from {low} to {high}\.",
    ):
        tumble.from_mesh(raw(vertices, faces), density=1.0)


def test_both_density_and_mass():
    with pytest.raises(
        InputError, match=r"Expected exactly one of `density` and `mass`, got both\."
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=1.0, mass=1.0)


def test_neither_density_nor_mass():
    with pytest.raises(
        InputError, match=r"Expected exactly one of `density` and `mass`, got neither\."
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)))


@pytest.mark.parametrize(
    "value, shown", [(0.0, "0.0"), (-2.0, "-2.0"), ("-2700 kg/m^3", "-2700.0")]
)
def test_non_positive_density(value, shown):
    with pytest.raises(InputError, match=rf"Expected `density` > 0 kg/m\^3, got {shown}\."):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=value)


@pytest.mark.parametrize("value, shown", [(0.0, "0.0"), (-1.0, "-1.0"), ("-250 g", "-0.25")])
def test_non_positive_mass(value, shown):
    with pytest.raises(InputError, match=rf"Expected `mass` > 0 kg, got {shown}\."):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), mass=value)


def test_density_with_the_units_of_a_mass():
    with pytest.raises(
        InputError,
        match=r"Expected `density` to be a density in kg/m\^3, got 3 kg "
        r"\(dimensions \[mass\]\)\.",
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density="3 kg")


def test_density_that_is_not_a_number():
    with pytest.raises(
        InputError,
        match=r"Expected `density` to be a number or a quantity such as '250 g', "
        r"got 'heavy'",
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density="heavy")


def test_density_that_is_not_finite():
    with pytest.raises(InputError, match=r"Expected `density` to be finite, got nan\."):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=float("nan"))


def test_mass_with_the_units_of_a_length():
    with pytest.raises(InputError, match=r"Expected `mass` to be a mass in kg, got 3 m"):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), mass="3 m")


def test_units_that_are_not_a_length():
    with pytest.raises(
        InputError,
        match=r"Expected `units` to be a length in m, got 1 kg \(dimensions \[mass\]\)\.",
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=1.0, units="kg")


@pytest.mark.parametrize("units", ["furlongz", ""])
def test_units_that_are_not_a_unit(units):
    with pytest.raises(
        InputError,
        match=rf"Expected `units` to be a length unit such as 'mm' or 'inch', "
        rf"got {re.escape(repr(units))}\.",
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=1.0, units=units)


def test_units_that_are_a_negative_length():
    with pytest.raises(
        InputError, match=r"Expected `units` to be a positive length unit, got -0\.001\."
    ):
        tumble.from_mesh(box_trimesh((0, 0, 0), (1, 1, 1)), density=1.0, units=-0.001)


def test_missing_file(tmp_path):
    path = tmp_path / "missing.stl"
    with pytest.raises(
        InputError,
        match=rf"Expected `mesh` to be a mesh file, got {re.escape(repr(str(path)))} "
        r"\(no such file\)\.",
    ):
        tumble.from_mesh(path, density=1.0)


def test_a_directory_is_not_a_mesh_file(tmp_path):
    with pytest.raises(InputError, match=r"\(a directory\)"):
        tumble.from_mesh(tmp_path, density=1.0)


_FACET = "solid bad\n facet normal 0 0 1\n  outer loop\n{}  endloop\n endfacet\nendsolid bad\n"


@pytest.mark.parametrize(
    "vertices",
    [
        "   vertex 0 0 0\n   vertex 1 0\n",  # five numbers: not xyz vertices
        "   vertex 0 0 0\n   vertex 1 0 0\n",  # a facet of two vertices
    ],
)
def test_malformed_ascii_stl_says_what_a_facet_needs(tmp_path, vertices):
    path = tmp_path / "bad.stl"
    path.write_text(_FACET.format(vertices))
    with pytest.raises(
        MeshError,
        match=rf"^Expected mesh {re.escape(repr(str(path)))} to be a well-formed STL file "
        r"\(each facet has 3 `vertex` lines of 3 numbers\), got one that is not\.$",
    ):
        tumble.from_mesh(path, density=1.0)


def test_an_obj_vertex_that_is_not_three_numbers_says_what_a_line_needs(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(
        MeshError,
        match=rf"^Expected mesh {re.escape(repr(str(path)))} to be a well-formed OBJ file "
        r"\(each `v` line has 3 numbers, each `f` line the numbers of its vertices\), "
        r"got one that is not\.$",
    ):
        tumble.from_mesh(path, density=1.0)


def test_an_obj_face_beyond_the_vertices_names_the_index(tmp_path):
    path = tmp_path / "bad.obj"
    # OBJ counts vertices from 1: vertex 9 of 3 is index 8.
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(
        MeshError,
        match=rf"^Expected mesh {re.escape(repr(str(path)))} face indices in \[0, 2\], "
        r"got index 8\.$",
    ):
        tumble.from_mesh(path, density=1.0)


def test_a_long_file_name_is_cut_in_the_message(tmp_path):
    # A name longer than the system allows is "File name too long" in the same place.
    path = tmp_path.joinpath(*["n" * 200] * 10, "part.stl")  # 2000 characters
    with pytest.raises(InputError) as caught:
        tumble.from_mesh(path, density=1.0)
    message = str(caught.value)
    assert (
        message == f"Expected `mesh` to be a mesh file, got {str(path)[:200]!r}... (no such file)."
    )


def test_garbage_bytes_are_rejected_with_the_file_named(tmp_path):
    path = tmp_path / "garbage.stl"
    # Not a binary STL (the triangle count in bytes 80-84 does not match the
    # size) and not UTF-8: trimesh decodes it to text with no solids, an empty
    # mesh, which tumble reports with the file named.
    path.write_bytes(bytes(range(256)) * 3)
    name = re.escape(repr(str(path)))
    with pytest.raises(
        MeshError,
        match=rf"Expected mesh {name} to have triangles, got none \(is it a mesh file\?\)",
    ):
        tumble.from_mesh(path, density=1.0)


def test_empty_file_has_no_triangles(tmp_path):
    path = tmp_path / "empty.stl"
    path.write_bytes(b"")
    with pytest.raises(
        MeshError,
        match=rf"Expected mesh {re.escape(repr(str(path)))} to have triangles, "
        r"got none \(is it a mesh file\?\)\.",
    ):
        tumble.from_mesh(path, density=1.0)


@pytest.mark.parametrize(
    "value, type_name", [(42, "int"), (np.zeros((8, 3)), "ndarray"), (None, "NoneType")]
)
def test_wrong_type(value, type_name):
    with pytest.raises(
        InputError,
        match=rf"Expected `mesh` to be a file path or a trimesh\.Trimesh, "
        rf"got {type_name}\.",
    ):
        tumble.from_mesh(value, density=1.0)


def test_mesh_errors_are_input_errors():
    # One except clause (InputError, or ValueError) catches every bad mesh.
    assert issubclass(MeshError, InputError) and issubclass(InputError, ValueError)


def test_a_missing_reader_package_is_named(tmp_path, monkeypatch):
    # Some formats need optional packages; the error says which, not "unreadable".
    import trimesh

    def needs_a_package(*args, **kwargs):
        raise ImportError("No module named 'some_reader'")

    path = tmp_path / "part.3mf"
    path.write_bytes(b"PK")
    monkeypatch.setattr(trimesh, "load_mesh", needs_a_package)
    with pytest.raises(
        InputError, match=r"needs a package that is not installed: No module named 'some_reader'"
    ):
        tumble.from_mesh(path, density=1.0)


def test_a_hash_collision_falls_back_to_the_exact_merge(monkeypatch):
    # Vertices are merged by a hash of their bits; if two different points ever
    # shared a hash, the merge must notice and fall back to np.unique(axis=0).
    import tumble.mesh.validation as mesh_module

    real = mesh_module.merge_by_key

    def colliding(points, keys, order):
        unique, inverse, _ = real(points, keys, order)
        return unique, inverse, False

    mesh = trimesh.creation.icosphere(subdivisions=2)
    expected = tumble.from_mesh(mesh, density=1.0)
    monkeypatch.setattr(mesh_module, "merge_by_key", colliding)
    got = tumble.from_mesh(mesh, density=1.0)
    np.testing.assert_allclose(got.inertia, expected.inertia, rtol=1e-13, atol=1e-16)


def test_an_inside_out_part_outside_the_others_is_an_error():
    # A 1 m cube and, beside it, a 0.2 m cube wound inward: not a cavity (it is
    # outside the big cube), so subtracting it would give 992 kg, not 1008.
    big = box_trimesh((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5))
    small = box_trimesh((0.7, -0.1, -0.1), (0.9, 0.1, 0.1))
    vertices = np.vstack([big.vertices, small.vertices])
    faces = np.vstack([big.faces, small.faces[:, ::-1] + len(big.vertices)])
    with pytest.raises(
        MeshError,
        match=r"Expected every part of mesh to be wound like the whole \(or to be a cavity inside "
        r"another part\), got part 2 of 2 with signed volume -0.008 m³ against 0.992 m³ in all: it is inside out",
    ):
        tumble.from_mesh(raw(vertices, faces), density=1000.0)


def test_separate_parts_wound_outward_add_up():
    big = box_trimesh((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5))
    small = box_trimesh((0.7, -0.1, -0.1), (0.9, 0.1, 0.1))
    vertices = np.vstack([big.vertices, small.vertices])
    faces = np.vstack([big.faces, small.faces + len(big.vertices)])
    mp = tumble.from_mesh(raw(vertices, faces), density=1000.0)
    expected = shapes.box(1000.0, (1, 1, 1)) + shapes.box(8.0, (0.2, 0.2, 0.2)).transformed(
        translation=[0.8, 0, 0]
    )
    assert mp.mass == pytest.approx(1008.0, rel=1e-13)
    np.testing.assert_allclose(mp.inertia, expected.inertia, rtol=1e-12, atol=1e-13 * 170)


@pytest.mark.parametrize("scale", [1e-120, 1e-30, 1e30, 1e100])
def test_huge_and_tiny_meshes_scale_exactly(scale):
    # Inertia scales as length⁵ at fixed density: integrating in the mesh's own
    # size keeps 1e±100 m meshes free of overflow and underflow. Compare per unit
    # of mass and length² so the expected values stay representable.
    mesh = box_trimesh((0.0, 0.0, 0.0), (1.0, 2.0, 3.0))
    mp = tumble.from_mesh(raw(np.asarray(mesh.vertices) * scale, mesh.faces), mass=1.0)
    expected = shapes.box(1.0, (1.0, 2.0, 3.0)).inertia
    np.testing.assert_allclose(mp.inertia / scale**2, expected, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(mp.center_of_mass / scale, [0.5, 1.0, 1.5], rtol=1e-13)


def test_units_declared_in_a_glb_file_are_used(tmp_path):
    # A 10 mm cube whose file says "mm": 1 g at 1000 kg/m³, not 1000 kg.
    cube = creation.box((10.0, 10.0, 10.0))
    cube.units = "mm"
    path = tmp_path / "cube_mm.glb"
    cube.export(path)
    assert tumble.from_mesh(path, density=1000.0).mass == pytest.approx(1e-3, rel=1e-12)
    # An explicit `units` overrides what the file says.
    assert tumble.from_mesh(path, density=1000.0, units="cm").mass == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize(("scale", "shown"), [(1e110, "inf"), (1e-120, "0.0")])
def test_a_mass_beyond_float_range_is_an_error(scale, shown):
    cube = box_trimesh((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    with pytest.raises(
        InputError,
        match=rf"Expected the mass of mesh \(density × volume\) within float range, got {shown} kg",
    ):
        tumble.from_mesh(raw(np.asarray(cube.vertices) * scale, cube.faces), density=1000.0)


def test_a_mesh_in_a_unit_that_is_no_length_is_refused() -> None:
    # trimesh keeps the unit a file declares (glTF, COLLADA); one that is no length
    # is refused, named.
    mesh = trimesh.creation.box(extents=[1, 2, 3])
    mesh.units = "bananas"
    with pytest.raises(
        InputError, match=r"^Expected a mesh in a length unit, got one in 'bananas': "
    ):
        tumble.from_mesh(mesh, mass=1.0)
    mesh.units = "0.01 * meters"  # COLLADA's <unit meter="0.01"/>, as trimesh gives it
    assert tumble.from_mesh(mesh, mass=1.0).inertia[0, 0] == pytest.approx((4 + 9) / 12 * 1e-4)
