"""Oracle tests for the raw kernel ``tumble.core.polyhedron.mesh_integrals``.

The kernel returns ``[V, Sx, Sy, Sz, Sxx, Syy, Szz, Sxy, Sxz, Syz, A]`` with
``V = ∫ dV``, ``S_i = ∫ x_i dV``, ``S_ij = ∫ x_i x_j dV`` and x measured from
``reference``, and A the surface area (tested on its own; :func:`integrals`
returns the ten volume integrals). Every expected value below comes from somewhere else: hand
integration over a simplex or a box, the exact moments of a regular-polygon
prism, the algebra of moving the reference point, or trimesh's own (different)
mass-properties algorithm.

These tests also run with ``NUMBA_DISABLE_JIT=1``, where the kernel is a Python
loop (tens of microseconds a triangle), so the meshes stay small except for the
one that must span several work chunks.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.core.polyhedron import CHUNK, N_INTEGRALS, mesh_integrals

EPS = np.finfo(float).eps

# Index of each integral in the kernel's result.
V, SX, SY, SZ, SXX, SYY, SZZ, SXY, SXZ, SYZ, AREA = range(N_INTEGRALS)
FIRST = [SX, SY, SZ]
SECOND = {(0, 0): SXX, (1, 1): SYY, (2, 2): SZZ, (0, 1): SXY, (0, 2): SXZ, (1, 2): SYZ}


def all_sums(vertices, faces, reference=(0.0, 0.0, 0.0)):
    """The kernel called with the exact dtypes it is compiled for."""
    return mesh_integrals(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int64),
        np.asarray(reference, dtype=np.float64),
    )


def integrals(vertices, faces, reference=(0.0, 0.0, 0.0)):
    """The ten signed volume integrals."""
    return all_sums(vertices, faces, reference)[:AREA]


def first_moments(result):
    return result[FIRST]


def second_moments(result):
    """The symmetric matrix ∫ x xᵀ dV from the six independent entries."""
    m = np.empty((3, 3))
    for (i, j), k in SECOND.items():
        m[i, j] = m[j, i] = result[k]
    return m


def assert_within(actual, expected, tolerance):
    """|actual − expected| <= tolerance entry by entry (tolerance may be an array)."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    error = np.abs(actual - expected)
    bad = error > tolerance
    assert not bad.any(), (
        f"entries {np.flatnonzero(bad).tolist()} differ: actual {actual[bad]}, "
        f"expected {expected[bad]}, error {error[bad]}, tolerance {np.broadcast_to(tolerance, error.shape)[bad]}"
    )


# Unit tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward winding: each
# face's (b − a) × (c − a) points away from the opposite vertex (checked below).
TET_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def box_mesh(lo, hi):
    """Closed, outward-wound triangulated box with the given corners."""
    mesh = trimesh.creation.box(bounds=[lo, hi])
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def random_convex(seed, n_points=24):
    """A generic convex polyhedron (no symmetry, so no integral vanishes by accident)."""
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n_points, 3)) * [1.3, 0.8, 0.5] + rng.normal(size=3)
    hull = trimesh.convex.convex_hull(points)
    assert hull.is_watertight and hull.is_winding_consistent and hull.volume > 0
    return np.asarray(hull.vertices, dtype=float), np.asarray(hull.faces, dtype=np.int64)


def magnitude_scale(vertices, reference):
    """A size for each integral: V·L^k with L the largest distance from the reference.

    Round-off in a sum of n tetrahedron terms is at most ~n·eps times the sum of
    their magnitudes, and every term of order k is bounded by (volume of a
    tetrahedron spanned from the reference) · L^k, so errors are compared with this.
    """
    length = float(np.max(np.linalg.norm(vertices - reference, axis=1)))
    volume = length**3
    return np.array([volume] + [volume * length] * 3 + [volume * length**2] * 6)


# --------------------------------------------------------------------------- simplex


def test_unit_tetrahedron_fixture_is_outward_wound():
    # Guard for the fixture itself: every face normal points away from the
    # vertex not on that face, i.e. the winding is outward.
    for face in TET_FACES:
        a, b, c = TET_VERTICES[face]
        opposite = TET_VERTICES[np.setdiff1d(np.arange(4), face)[0]]
        assert np.dot(np.cross(b - a, c - a), a - opposite) > 0


def test_unit_tetrahedron_matches_simplex_integrals():
    # Over the unit simplex x, y, z >= 0, x + y + z <= 1 (Dirichlet integral):
    #   ∫ x^a y^b z^c dV = a! b! c! / (a + b + c + 3)!
    # so  V      = 0!0!0!/3! = 1/6,
    #     ∫x dV  = 1!/4!     = 1/24   (and ∫y, ∫z by symmetry),
    #     ∫x² dV = 2!/5!     = 2/120 = 1/60,
    #     ∫xy dV = 1!1!/5!   = 1/120.
    expected = np.array([1 / 6] + [1 / 24] * 3 + [1 / 60] * 3 + [1 / 120] * 3)
    result = integrals(TET_VERTICES, TET_FACES)
    # About the origin three faces contain the reference (zero contribution) and
    # the fourth is exact small-integer arithmetic, so only the final division
    # by 6, 24 or 120 rounds: half an ulp; allow 2 ulps.
    np.testing.assert_allclose(result, expected, rtol=2 * EPS, atol=0)


def test_unit_tetrahedron_about_its_centroid():
    # Centroid g = (1/4, 1/4, 1/4). By the shift law (derived in the box test),
    # about g: ∫x' = ∫x − V g_x = 1/24 − 1/24 = 0 and
    #   ∫x'² = ∫x² − 2 g_x ∫x + V g_x² = 1/60 − 1/48 + 1/96 = (8 − 10 + 5)/480 = 1/160,
    #   ∫x'y' = ∫xy − g_x ∫y − g_y ∫x + V g_x g_y = 1/120 − 1/48 + 1/96 = −1/480.
    expected = np.array([1 / 6] + [0.0] * 3 + [1 / 160] * 3 + [-1 / 480] * 3)
    result = integrals(TET_VERTICES, TET_FACES, reference=[0.25, 0.25, 0.25])
    # Coordinates relative to g are exact (quarters); four terms of size ≤ 1
    # before dividing, so a few ulps of the largest entry of each order.
    np.testing.assert_allclose(result, expected, rtol=8 * EPS, atol=8 * EPS / 24)


# ------------------------------------------------------------------------------ box


def box_closed_form(lo, hi, r):
    """Integrals of the box [lo, hi] about reference r, by separation of variables.

    Along one axis: ∫ dx = x1 − x0, ∫ (x − r) dx = ((x1 − r)² − (x0 − r)²)/2,
    ∫ (x − r)² dx = ((x1 − r)³ − (x0 − r)³)/3; a box integral of a product of
    per-axis factors is the product of the per-axis integrals.
    """
    lo, hi, r = (np.asarray(v, dtype=float) for v in (lo, hi, r))
    p0 = hi - lo
    p1 = ((hi - r) ** 2 - (lo - r) ** 2) / 2
    p2 = ((hi - r) ** 3 - (lo - r) ** 3) / 3
    volume = np.prod(p0)
    out = np.empty(AREA)
    out[V] = volume
    for i, k in enumerate(FIRST):
        out[k] = volume / p0[i] * p1[i]
    for (i, j), k in SECOND.items():
        if i == j:
            out[k] = volume / p0[i] * p2[i]
        else:
            out[k] = volume / (p0[i] * p0[j]) * p1[i] * p1[j]
    return out


BOX_LO = (-0.5, 1.0, 2.0)
BOX_HI = (1.5, 1.25, 2.75)


@pytest.mark.parametrize(
    "reference",
    [(0.0, 0.0, 0.0), (0.5, 1.125, 2.375), (0.3, 1.2, 2.1), (4.0, -3.0, 7.5)],
    ids=["origin", "centre", "inside", "outside"],
)
def test_box_matches_closed_form(reference):
    vertices, faces = box_mesh(BOX_LO, BOX_HI)
    result = integrals(vertices, faces, reference)
    expected = box_closed_form(BOX_LO, BOX_HI, reference)
    scale = magnitude_scale(vertices, np.asarray(reference))
    # 12 triangles: a few dozen roundings per term, each ≤ eps of the scale.
    assert_within(result, expected, 100 * EPS * scale)


def shifted(result, r):
    """Integrals about reference r from integrals about the origin.

    With x' = x − r:
      ∫ dV          = V
      ∫ x'_i dV     = S_i − r_i V
      ∫ x'_i x'_j dV = ∫ (x_i − r_i)(x_j − r_j) dV = S_ij − r_i S_j − r_j S_i + V r_i r_j.
    """
    r = np.asarray(r, dtype=float)
    out = np.empty(AREA)
    volume = result[V]
    first = first_moments(result)
    out[V] = volume
    out[FIRST] = first - volume * r
    second = (
        second_moments(result) - np.outer(r, first) - np.outer(first, r) + volume * np.outer(r, r)
    )
    for (i, j), k in SECOND.items():
        out[k] = second[i, j]
    return out


@pytest.mark.parametrize("r", [(0.5, 1.125, 2.375), (4.0, -3.0, 7.5)])
def test_box_moments_transform_with_the_reference(r):
    vertices, faces = box_mesh(BOX_LO, BOX_HI)
    about_origin = integrals(vertices, faces)
    about_r = integrals(vertices, faces, r)
    scale = magnitude_scale(vertices, np.zeros(3)) + magnitude_scale(vertices, np.asarray(r))
    assert_within(about_r, shifted(about_origin, r), 100 * EPS * scale)


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    r=st.tuples(*[st.floats(-3.0, 3.0, allow_nan=False)] * 3),
)
def test_reference_shift_law_on_random_polyhedra(seed, r):
    # The shift law is pure algebra of the integrands, so it must hold for any
    # closed mesh and any reference, inside or outside the solid.
    vertices, faces = random_convex(seed)
    about_origin = integrals(vertices, faces)
    about_r = integrals(vertices, faces, r)
    scale = magnitude_scale(vertices, np.zeros(3)) + magnitude_scale(vertices, np.asarray(r))
    # ~50 triangles, each term rounding to a few eps of the scale.
    assert_within(about_r, shifted(about_origin, r), 1000 * EPS * scale)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_matches_trimesh_mass_properties(seed):
    # trimesh.triangles.mass_properties implements a different algorithm
    # (Eberly's polyhedral mass properties, with per-face polynomial
    # subexpressions): an independent oracle for volume, centroid and the
    # central inertia tensor I = tr(C) E − C, C = ∫ (x − g)(x − g)ᵀ dV.
    vertices, faces = random_convex(seed)
    reference = vertices.mean(axis=0)
    result = integrals(vertices, faces, reference)
    volume = result[V]
    centroid = first_moments(result) / volume
    central = second_moments(result) - volume * np.outer(centroid, centroid)
    inertia = np.trace(central) * np.eye(3) - central

    oracle = trimesh.Trimesh(vertices, faces, process=False).mass_properties
    size = float(np.ptp(vertices, axis=0).max())
    # Both are sums of ~50 well-conditioned terms about a nearby point: the
    # agreement is limited by round-off, ~1e-14; 1e-12 leaves room for the
    # different operation orders of the two algorithms.
    assert volume == pytest.approx(oracle.volume, rel=1e-12)
    assert_within(reference + centroid, oracle.center_mass, 1e-12 * size)
    assert_within(inertia, oracle.inertia, 1e-12 * np.linalg.norm(oracle.inertia))


# ------------------------------------------------------------------ winding, order


def integer_meshes():
    """Meshes whose integer coordinates make every kernel operation exact.

    Products and sums of integers of a few units stay far below 2**53, so d, t
    and every accumulated sum are exact; the only rounding is the final division
    by 6, 24 or 120, which is symmetric under negation.
    """
    box_v, box_f = box_mesh((-2, 1, 3), (5, 4, 7))
    yield "tetrahedron", TET_VERTICES * 3 + [1, -2, 4], TET_FACES, (0.0, 0.0, 0.0)
    yield "box-origin", box_v, box_f, (0.0, 0.0, 0.0)
    yield "box-reference", box_v, box_f, (1.0, 2.0, -3.0)


@pytest.mark.parametrize(
    "name, vertices, faces, reference", list(integer_meshes()), ids=[m[0] for m in integer_meshes()]
)
def test_reversed_winding_negates_every_integral_exactly(name, vertices, faces, reference):
    # Reversing every triangle reverses every normal; by the divergence theorem
    # each surface integral, hence each volume integral, changes sign.
    forward = integrals(vertices, faces, reference)
    for reversed_faces in (faces[:, ::-1], faces[:, [0, 2, 1]]):
        backward = integrals(vertices, reversed_faces, reference)
        np.testing.assert_array_equal(backward, -forward)
    assert forward[V] > 0


def test_reversed_winding_negates_to_round_off_on_a_generic_mesh():
    vertices, faces = random_convex(7)
    reference = vertices.mean(axis=0) + np.array([0.1, -0.2, 0.05])
    forward = integrals(vertices, faces, reference)
    backward = integrals(vertices, faces[:, ::-1], reference)
    # The reversed triangle is evaluated with its terms in another order, so
    # agreement is to round-off (a few eps per term), not bitwise.
    assert_within(backward, -forward, 100 * EPS * magnitude_scale(vertices, reference))


def test_face_order_and_cyclic_vertex_order_do_not_matter():
    # The solid is the same whatever order its triangles are listed in, and a
    # cyclic shift (a, b, c) → (b, c, a) keeps each triangle's orientation.
    vertices, faces = random_convex(3, n_points=60)
    reference = vertices.mean(axis=0)
    rng = np.random.default_rng(11)
    expected = integrals(vertices, faces, reference)
    permuted = faces[rng.permutation(len(faces))]
    rotated = np.roll(faces, shift=1, axis=1)
    scale = magnitude_scale(vertices, reference)
    # Reordering a sum of n terms changes it by at most ~n·eps·Σ|terms|.
    tolerance = 4 * len(faces) * EPS * scale
    assert_within(integrals(vertices, permuted, reference), expected, tolerance)
    assert_within(integrals(vertices, rotated, reference), expected, tolerance)


def test_closed_surface_integrals_do_not_depend_on_where_the_mesh_sits():
    # Translating both the mesh and the reference by the same vector moves
    # nothing relative to the reference.
    vertices, faces = random_convex(5)
    reference = vertices.mean(axis=0)
    shift = np.array([0.75, -1.5, 2.25])
    scale = magnitude_scale(vertices, reference)
    # The shifted coordinates are rounded once (≤ eps·|shift|) before the
    # difference is taken; that perturbs each term by a few eps of the scale.
    assert_within(
        integrals(vertices + shift, faces, reference + shift),
        integrals(vertices, faces, reference),
        1000 * EPS * scale,
    )


# --------------------------------------------------------------------------- chunks


def prism_closed_form(n_sides, radius, height):
    """Integrals about its centre of a prism over a regular n-gon of circumradius R.

    The n-gon is n triangles (centre, P_k, P_k+1) of apex angle α = 2π/n, each of
    area R² sin(α)/2, so A = n R² sin(α)/2. For a triangle with one vertex at the
    origin, ∫ x xᵀ dA = A/12 (a aᵀ + b bᵀ + (a + b)(a + b)ᵀ), whose trace is
    A R² (2 + cos α)/6; by n-fold symmetry (n >= 3) the area tensor is isotropic,
    so ∫ x² dA = ∫ y² dA = A R² (2 + cos α)/12 and ∫ xy dA = 0. Extruding over
    z ∈ [−h/2, h/2] multiplies by h, and ∫ z² dV = A h³/12.
    """
    alpha = 2 * np.pi / n_sides
    area = n_sides * radius**2 * np.sin(alpha) / 2
    in_plane = area * radius**2 * (2 + np.cos(alpha)) / 12 * height
    out = np.zeros(AREA)
    out[V] = area * height
    out[SXX] = out[SYY] = in_plane
    out[SZZ] = area * height**3 / 12
    return out


def test_mesh_spanning_several_chunks_equals_the_sum_of_its_pieces():
    # The kernel sums CHUNK triangles per work item and then the items; this mesh
    # has two full chunks and a partial third. Since every integral is a sum over
    # triangles, evaluating arbitrary (unaligned) pieces separately and adding
    # them must give the whole.
    sections = CHUNK // 2 + 7  # trimesh's cylinder has 4 triangles per section
    radius, height = 0.8, 1.5
    mesh = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    vertices = np.asarray(mesh.vertices, dtype=float)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    assert 2 * CHUNK < len(faces) < 3 * CHUNK
    reference = np.zeros(3)

    whole = integrals(vertices, faces, reference)
    cuts = [0, 1001, CHUNK + 1, 2 * CHUNK - 5, len(faces)]
    pieces = sum(integrals(vertices, faces[a:b], reference) for a, b in itertools.pairwise(cuts))
    scale = magnitude_scale(vertices, reference)
    # ~16 000 terms summed in two different groupings: ≤ n·eps·Σ|terms|, and in
    # practice far less; 1e-11 of the scale is well above pairwise-sum round-off.
    assert_within(whole, pieces, 1e-11 * scale)

    # And the whole is the exact integral of the polygonal prism (a different
    # construction: closed form over the regular n-gon), not just self-consistent.
    rim = np.hypot(vertices[:, 0], vertices[:, 1])
    assert np.allclose(rim[rim > 1e-9], radius, rtol=1e-14)  # vertices on the circle
    assert np.allclose(np.abs(vertices[:, 2]), height / 2, rtol=1e-14)
    assert_within(whole, prism_closed_form(sections, radius, height), 1e-11 * scale)


# ---------------------------------------------------------------- surface area
def test_surface_area_of_a_box_from_any_reference_and_winding() -> None:
    # 2 (ab + bc + ca) for a 2 × 3 × 4 box, whatever the reference point and winding.
    vertices, faces = box_mesh([-1.0, -1.0, -1.0], [1.0, 2.0, 3.0])
    for reference in ([0.1, 0.2, 0.3], [50.0, -7.0, 3.0]):
        assert all_sums(vertices, faces, reference)[AREA] == pytest.approx(52.0, rel=1e-14)
        assert all_sums(vertices, faces[:, ::-1], reference)[AREA] == pytest.approx(52.0, rel=1e-14)


def test_flat_closed_surface_has_round_off_volume_and_twice_its_area() -> None:
    # Two copies of a triangle with opposite windings enclose nothing; the area
    # counts both sides: 2 × 0.98 m², by the shoelace formula
    # ½ |0.1 (−0.1 − 0.9) + 2.1 (0.9 − 0.1) + 1.9 (0.1 + 0.1)| = 0.98.
    vertices = np.array([[0.1, 0.1, 0.21], [2.1, -0.1, 0.21], [1.9, 0.9, 0.21]])
    faces = np.array([[0, 1, 2], [0, 2, 1]])
    sums = all_sums(vertices, faces, vertices.mean(axis=0) + np.array([0.0, 0.0, 1.0]))
    assert sums[AREA] == pytest.approx(1.96, rel=1e-14)
    assert abs(sums[V]) <= 4 * EPS * sums[AREA]


def test_parallel_and_serial_sums_are_bit_identical() -> None:
    # Both add the same CHUNK-triangle partial sums in the same order, so the
    # thread count cannot change a result (a test of determinism, not physics).
    from tumble.core import polyhedron

    mesh = trimesh.creation.cylinder(radius=1.0, height=2.0, sections=CHUNK // 2 + 7)
    vertices = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    faces = np.ascontiguousarray(mesh.faces, dtype=np.int64)
    reference = np.array([0.1, -0.2, 0.3])
    parallel = polyhedron._finish(polyhedron._chunk_sums_parallel(vertices, faces, reference))
    serial = polyhedron._finish(polyhedron._chunk_sums_serial(vertices, faces, reference))
    assert np.array_equal(parallel, serial)
