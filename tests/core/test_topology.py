"""Topology kernels against numpy one-liners and hand-counted meshes.

Also run with ``NUMBA_DISABLE_JIT=1``; the meshes are tiny.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from numpy.testing import assert_array_equal

from tumble.core.topology import (
    bounds_and_mean,
    count_nonfinite_rows,
    directed_edge_keys,
    edge_defects,
    face_components,
    index_range,
    merge_by_key,
    renumber_faces,
)


def cube() -> tuple[np.ndarray, np.ndarray]:
    mesh = trimesh.creation.box()
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def defects(faces: np.ndarray, n_vertices: int) -> tuple[int, int, int]:
    keys = np.sort(directed_edge_keys(np.ascontiguousarray(faces, dtype=np.int64), n_vertices))
    boundary, crowded, same = edge_defects(keys)
    return int(boundary), int(crowded), int(same)


def test_a_closed_oriented_cube_has_no_defects() -> None:
    vertices, faces = cube()
    assert defects(faces, len(vertices)) == (0, 0, 0)


def test_removing_one_triangle_opens_three_edges() -> None:
    vertices, faces = cube()
    assert defects(faces[1:], len(vertices)) == (3, 0, 0)


def test_flipping_one_triangle_makes_its_three_edges_same_direction() -> None:
    vertices, faces = cube()
    flipped = faces.copy()
    flipped[0] = flipped[0, ::-1]
    assert defects(flipped, len(vertices)) == (0, 0, 3)


def test_a_fin_on_an_edge_is_non_manifold() -> None:
    # A third and fourth triangle (a doubled fin, itself closed) on one cube edge.
    vertices, faces = cube()
    a, b = faces[0, 0], faces[0, 1]
    vertices = np.vstack([vertices, [5.0, 5.0, 5.0]])
    apex = len(vertices) - 1
    fin = np.array([[a, b, apex], [b, a, apex]])
    boundary, crowded, _ = defects(np.vstack([faces, fin]), len(vertices))
    assert crowded == 1
    assert boundary == 0


def test_keys_encode_the_undirected_edge_and_its_direction() -> None:
    keys = directed_edge_keys(np.array([[2, 0, 1]], dtype=np.int64), 3)
    # Edges 2→0, 0→1, 1→2: undirected (0, 2), (0, 1), (1, 2); forward iff start < end.
    assert keys.tolist() == [((0 * 3 + 2) << 1) | 0, ((0 * 3 + 1) << 1) | 1, ((1 * 3 + 2) << 1) | 1]


def test_merge_by_key_keeps_first_appearance_order() -> None:
    points = np.array([[1.0, 0, 0], [0, 1, 0], [1.0, 0, 0], [2, 2, 2], [0, 1, 0]])
    keys = np.array([7, 3, 7, 1, 3], dtype=np.uint64)
    unique, inverse, exact = merge_by_key(points, keys, np.argsort(keys))
    assert exact
    assert_array_equal(unique, [[1.0, 0, 0], [0, 1, 0], [2, 2, 2]])
    assert_array_equal(inverse, [0, 1, 0, 2, 1])
    assert_array_equal(unique[inverse], points)


def test_merge_by_key_reports_a_collision() -> None:
    # Different points sharing a key must not be merged silently.
    points = np.array([[1.0, 0, 0], [0, 1, 0]])
    keys = np.array([5, 5], dtype=np.uint64)
    _, _, exact = merge_by_key(points, keys, np.argsort(keys))
    assert not exact


def test_renumber_faces_drops_triangles_with_a_repeated_corner() -> None:
    faces = np.array([[0, 1, 2], [0, 3, 1], [2, 3, 4]], dtype=np.int64)
    inverse = np.array([0, 1, 2, 1, 4], dtype=np.int64)  # vertex 3 merged into 1
    assert_array_equal(renumber_faces(faces, inverse), [[0, 1, 2], [2, 1, 4]])


def test_index_range_nonfinite_rows_bounds_and_mean_equal_numpy() -> None:
    rng = np.random.default_rng(3)
    faces = rng.integers(-2, 50, size=(40, 3))
    assert index_range(faces) == (faces.min(), faces.max())
    points = rng.normal(size=(30, 3))
    assert count_nonfinite_rows(points) == 0
    points[[3, 7], [1, 2]] = [np.nan, -np.inf]
    points[7, 0] = np.inf  # two bad entries in one row count once
    assert count_nonfinite_rows(points) == 2
    points = rng.normal(size=(30, 3))
    low, high, mean = bounds_and_mean(points)
    assert_array_equal(low, points.min(axis=0))
    assert_array_equal(high, points.max(axis=0))
    assert mean == pytest.approx(points.mean(axis=0), rel=1e-14, abs=1e-15)


def test_face_components_separate_disjoint_parts() -> None:
    vertices, faces = cube()
    n = len(vertices)
    two = np.vstack([faces, faces + n, faces[:3] + 2 * n])  # two cubes and a loose strip
    n_parts, labels = face_components(np.ascontiguousarray(two), 3 * n)
    assert n_parts == 3
    assert_array_equal(labels, [0] * len(faces) + [1] * len(faces) + [2] * 3)
