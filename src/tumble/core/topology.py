"""Kernels for checking that a triangle mesh bounds a solid.

The wrappers in :mod:`tumble.mesh` merge identical vertices and check that
every edge belongs to exactly two triangles that traverse it in opposite
directions. numpy sorts; these kernels make the single passes around the sorts
without the temporary arrays a chain of numpy expressions would allocate.
"""

from __future__ import annotations

import numpy as np

from tumble.core._jit import njit


@njit
def merge_by_key(points, keys, order):  # type: ignore[no-untyped-def]
    """Merge points with equal keys, numbering them in order of first appearance.

    Parameters
    ----------
    points : (n, 3) float64.
    keys : (n,) uint64, equal for equal points (a hash of their bits).
    order : (n,) int64, ``argsort(keys)``.

    Returns
    -------
    unique : (n_unique, 3) float64, one point per key, in the order the keys
        first appear, so a mesh's vertex order (and its memory locality) is kept.
    inverse : (n,) int64, ``unique[inverse[i]]`` stands for ``points[i]``.
    exact : bool, False if some point differs from the point it was merged
        with (a hash collision): the caller must then merge another way.
    """
    n = keys.shape[0]
    group = np.empty(n, dtype=np.int64)
    g = -1
    for k in range(n):
        i = order[k]
        if k == 0 or keys[i] != keys[order[k - 1]]:
            g += 1
        group[i] = g
    label = np.full(g + 1, -1, dtype=np.int64)
    unique = np.empty((g + 1, 3))
    inverse = np.empty(n, dtype=np.int64)
    count = 0
    exact = True
    for i in range(n):
        j = label[group[i]]
        if j < 0:
            j = count
            label[group[i]] = j
            unique[j, 0] = points[i, 0]
            unique[j, 1] = points[i, 1]
            unique[j, 2] = points[i, 2]
            count += 1
        elif (
            points[i, 0] != unique[j, 0]
            or points[i, 1] != unique[j, 1]
            or points[i, 2] != unique[j, 2]
        ):
            exact = False
        inverse[i] = j
    return unique, inverse, exact


@njit
def directed_edge_keys(faces, n_vertices):  # type: ignore[no-untyped-def]
    """One int64 key per triangle edge: the undirected edge, and its direction in bit 0.

    ``key = ((low · n_vertices + high) << 1) | (start < end)`` for the edge from
    ``start`` to ``end``, ``low``/``high`` the smaller/larger index, so sorting
    the keys puts all uses of an edge side by side. Needs ``n_vertices² < 2⁶²``.
    """
    n_faces = faces.shape[0]
    keys = np.empty(3 * n_faces, dtype=np.int64)
    for f in range(n_faces):
        for corner in range(3):
            start = faces[f, corner]
            end = faces[f, (corner + 1) % 3]
            if start < end:
                keys[3 * f + corner] = ((start * n_vertices + end) << 1) | 1
            else:
                keys[3 * f + corner] = (end * n_vertices + start) << 1
    return keys


@njit
def edge_defects(sorted_keys):  # type: ignore[no-untyped-def]
    """Count what keeps sorted edge keys from a closed, oriented manifold.

    Returns
    -------
    (3,) int64: edges used once (boundary), edges used more than twice
    (non-manifold), and edges used twice in the same direction (inconsistent
    winding).
    """
    boundary = 0
    crowded = 0
    same_direction = 0
    n = sorted_keys.shape[0]
    k = 0
    while k < n:
        edge = sorted_keys[k] >> 1
        run = 1
        while k + run < n and (sorted_keys[k + run] >> 1) == edge:
            run += 1
        if run == 1:
            boundary += 1
        elif run > 2:
            crowded += 1
        elif (sorted_keys[k] & 1) == (sorted_keys[k + 1] & 1):
            same_direction += 1
        k += run
    result = np.empty(3, dtype=np.int64)
    result[0] = boundary
    result[1] = crowded
    result[2] = same_direction
    return result


@njit
def index_range(faces):  # type: ignore[no-untyped-def]
    """Smallest and largest vertex index in ``faces`` (one pass, no temporaries)."""
    low = faces[0, 0]
    high = faces[0, 0]
    for f in range(faces.shape[0]):
        for c in range(3):
            index = faces[f, c]
            low = min(low, index)
            high = max(high, index)
    return low, high


@njit
def count_nonfinite_rows(points):  # type: ignore[no-untyped-def]
    """Number of rows of ``points`` holding a NaN or an infinity."""
    count = 0
    for i in range(points.shape[0]):
        if not (
            np.isfinite(points[i, 0]) and np.isfinite(points[i, 1]) and np.isfinite(points[i, 2])
        ):
            count += 1
    return count


@njit
def renumber_faces(faces, inverse):  # type: ignore[no-untyped-def]
    """Faces in merged vertex numbering, without the triangles that then repeat a corner.

    Such triangles have zero area and contribute nothing to any integral.
    """
    out = np.empty_like(faces)
    kept = 0
    for f in range(faces.shape[0]):
        a = inverse[faces[f, 0]]
        b = inverse[faces[f, 1]]
        c = inverse[faces[f, 2]]
        if a != b and b != c and c != a:
            out[kept, 0] = a
            out[kept, 1] = b
            out[kept, 2] = c
            kept += 1
    return out[:kept]


@njit
def bounds_and_mean(points):  # type: ignore[no-untyped-def]
    """Per-axis minimum, maximum and mean of ``points`` (n, 3) in one pass.

    numpy's ``min/max/mean(axis=0)`` on an (n, 3) array stride across rows and
    take several times longer than this single sweep.
    """
    low = points[0].copy()
    high = points[0].copy()
    total = np.zeros(3)
    for i in range(points.shape[0]):
        for c in range(3):
            x = points[i, c]
            low[c] = min(low[c], x)
            high[c] = max(high[c], x)
            total[c] += x
    return low, high, total / points.shape[0]


@njit
def _root(parent, i):  # type: ignore[no-untyped-def]
    while parent[i] != i:
        parent[i] = parent[parent[i]]  # path halving
        i = parent[i]
    return i


@njit
def face_components(faces, n_vertices):  # type: ignore[no-untyped-def]
    """Connected parts of a mesh (triangles sharing a vertex belong together).

    Union-find over the vertices of each triangle.

    Returns
    -------
    n_parts : int
    labels : (n_faces,) int64 in ``range(n_parts)``, numbered in order of first
        appearance.
    """
    parent = np.arange(n_vertices)
    for f in range(faces.shape[0]):
        a = _root(parent, faces[f, 0])
        for c in (1, 2):
            b = _root(parent, faces[f, c])
            if a != b:
                parent[b] = a
    number = np.full(n_vertices, -1, dtype=np.int64)
    labels = np.empty(faces.shape[0], dtype=np.int64)
    n_parts = 0
    for f in range(faces.shape[0]):
        r = _root(parent, faces[f, 0])
        if number[r] < 0:
            number[r] = n_parts
            n_parts += 1
        labels[f] = number[r]
    return n_parts, labels
