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


@njit(inline="always")
def _edge_run(sorted_keys, k):  # type: ignore[no-untyped-def]
    """The undirected edge of ``sorted_keys[k]`` and how many keys from k on
    share it (sorted directed edge keys: :func:`directed_edge_keys`)."""
    edge = sorted_keys[k] >> 1
    run = 1
    while k + run < sorted_keys.shape[0] and (sorted_keys[k + run] >> 1) == edge:
        run += 1
    return edge, run


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
        _, run = _edge_run(sorted_keys, k)
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


@njit(inline="always")
def _cell_key(cx, cy, cz):  # type: ignore[no-untyped-def]
    """A uint64 hash of an integer grid cell (collisions are checked by the caller)."""
    return (
        np.uint64(cx) * np.uint64(0x9E3779B97F4A7C15)
        ^ np.uint64(cy) * np.uint64(0xC2B2AE3D27D4EB4F)
        ^ np.uint64(cz) * np.uint64(0x165667B19E3779F9)
    )


#: Grid cells this many tolerances wide: a point then needs the neighbouring
#: cells only along the axes where it lies within the tolerance of its cell's
#: side, so most points look in their own cell alone.
_CELL_TOLERANCES = 64.0


@njit
def weld(points, tolerance):  # type: ignore[no-untyped-def]
    """Weld points closer than ``tolerance``: the connected groups of the graph
    "within ``tolerance`` of each other" (Euclidean distance), each replaced by
    its lexicographically smallest point, so the result depends neither on the
    order of the points nor on the grid.

    Parameters
    ----------
    points : (n, 3) float64, distinct.
    tolerance : > 0, in the units of ``points``.

    Returns
    -------
    unique : (n_groups, 3), one point per group, groups in order of first appearance.
    inverse : (n,) int64, the group of each point.
    chosen : (n_groups,) int64, the index of each group's point in ``points``.
    largest : float, the largest distance from a point to its group's point.
    """
    n = points.shape[0]
    width = _CELL_TOLERANCES * tolerance
    low = points[0].copy()
    for i in range(n):
        for c in range(3):
            low[c] = min(low[c], points[i, c])
    cells = np.empty((n, 3), dtype=np.int64)
    keys = np.empty(n, dtype=np.uint64)
    for i in range(n):
        for c in range(3):
            cells[i, c] = np.int64(np.floor((points[i, c] - low[c]) / width))
        keys[i] = _cell_key(cells[i, 0], cells[i, 1], cells[i, 2])
    order = np.argsort(keys)
    ordered = keys[order]
    parent = np.arange(n)
    squared = tolerance * tolerance
    reach = np.empty((3, 2), dtype=np.int64)  # per axis, the neighbour offsets to look at
    for i in range(n):
        for c in range(3):
            offset = points[i, c] - low[c] - cells[i, c] * width
            reach[c, 0] = -1 if offset <= tolerance else 0
            reach[c, 1] = 1 if width - offset <= tolerance else 0
        for dx in range(reach[0, 0], reach[0, 1] + 1):
            for dy in range(reach[1, 0], reach[1, 1] + 1):
                for dz in range(reach[2, 0], reach[2, 1] + 1):
                    cx, cy, cz = cells[i, 0] + dx, cells[i, 1] + dy, cells[i, 2] + dz
                    key = _cell_key(cx, cy, cz)
                    k = np.searchsorted(ordered, key)
                    while k < n and ordered[k] == key:
                        j = order[k]
                        k += 1
                        if j == i or cells[j, 0] != cx or cells[j, 1] != cy or cells[j, 2] != cz:
                            continue
                        d0 = points[i, 0] - points[j, 0]
                        d1 = points[i, 1] - points[j, 1]
                        d2 = points[i, 2] - points[j, 2]
                        if d0 * d0 + d1 * d1 + d2 * d2 <= squared:
                            a, b = _root(parent, i), _root(parent, j)
                            if a != b:
                                parent[max(a, b)] = min(a, b)
    # Each group's point: its lexicographically smallest member.
    best = np.arange(n)
    for i in range(n):
        r = _root(parent, i)
        b = best[r]
        if (points[i, 0], points[i, 1], points[i, 2]) < (points[b, 0], points[b, 1], points[b, 2]):
            best[r] = i
    number = np.full(n, -1, dtype=np.int64)
    inverse = np.empty(n, dtype=np.int64)
    count = 0
    for i in range(n):
        r = _root(parent, i)
        if number[r] < 0:
            number[r] = count
            count += 1
        inverse[i] = number[r]
    unique = np.empty((count, 3))
    chosen = np.empty(count, dtype=np.int64)
    largest = 0.0
    for i in range(n):
        r = _root(parent, i)
        b = best[r]
        chosen[inverse[i]] = b
        for c in range(3):
            unique[inverse[i], c] = points[b, c]
        d0 = points[i, 0] - points[b, 0]
        d1 = points[i, 1] - points[b, 1]
        d2 = points[i, 2] - points[b, 2]
        largest = max(largest, np.sqrt(d0 * d0 + d1 * d1 + d2 * d2))
    return unique, inverse, chosen, largest


@njit
def boundary_vertices(sorted_keys, n_vertices):  # type: ignore[no-untyped-def]
    """The vertices of the edges used once in sorted directed edge keys
    (:func:`directed_edge_keys`), each once, ascending."""
    seen = np.zeros(n_vertices, dtype=np.bool_)
    n = sorted_keys.shape[0]
    k = 0
    while k < n:
        edge, run = _edge_run(sorted_keys, k)
        if run == 1:
            seen[edge // n_vertices] = True
            seen[edge % n_vertices] = True
        k += run
    return np.flatnonzero(seen)


@njit
def crowded_edges(sorted_keys):  # type: ignore[no-untyped-def]
    """The undirected edges (``key >> 1``, ascending) used more than twice in
    sorted directed edge keys (:func:`directed_edge_keys`)."""
    n = sorted_keys.shape[0]
    out = np.empty(n // 3 + 1, dtype=np.int64)
    m = 0
    k = 0
    while k < n:
        edge, run = _edge_run(sorted_keys, k)
        if run > 2:
            out[m] = edge
            m += 1
        k += run
    return out[:m]


@njit
def faces_at_edges(faces, n_vertices, edges):  # type: ignore[no-untyped-def]
    """The triangles that use the undirected ``edges`` (ascending): for each
    edge, its uses as (triangle, 1 if it runs from the lower vertex to the
    higher else 0), grouped by edge.

    Returns ``starts`` (len(edges) + 1,) and ``uses`` (n_uses, 2) int64, the uses
    of edge j being ``uses[starts[j]:starts[j + 1]]``.
    """
    m = edges.shape[0]
    slots = np.full((faces.shape[0], 3), -1, dtype=np.int64)  # the edge of each side, if listed
    counts = np.zeros(m + 1, dtype=np.int64)
    on_edge = np.zeros(n_vertices, dtype=np.bool_)  # a triangle needs two such corners
    for j in range(m):
        on_edge[edges[j] // n_vertices] = True
        on_edge[edges[j] % n_vertices] = True
    for f in range(faces.shape[0]):
        if on_edge[faces[f, 0]] + on_edge[faces[f, 1]] + on_edge[faces[f, 2]] < 2:
            continue
        for corner in range(3):
            a, b = faces[f, corner], faces[f, (corner + 1) % 3]
            edge = min(a, b) * n_vertices + max(a, b)
            j = np.searchsorted(edges, edge)
            if j < m and edges[j] == edge:
                slots[f, corner] = j
                counts[j + 1] += 1
    starts = np.cumsum(counts)
    fill = starts[:-1].copy()
    uses = np.empty((starts[m], 2), dtype=np.int64)
    for f in range(faces.shape[0]):
        for corner in range(3):
            j = slots[f, corner]
            if j >= 0:
                uses[fill[j], 0] = f
                uses[fill[j], 1] = 1 if faces[f, corner] < faces[f, (corner + 1) % 3] else 0
                fill[j] += 1
    return starts, uses


@njit
def _third_vertex(faces, f, a, b):  # type: ignore[no-untyped-def]
    """The corner of triangle ``f`` that is neither ``a`` nor ``b``."""
    for c in range(3):
        v = faces[f, c]
        if v != a and v != b:
            return v
    return faces[f, 0]


#: Triangles around an edge whose angles differ by less than this (rad) are
#: taken as coplanar: far above the round-off of the angles, far below any
#: angle a mesh draws.
_COPLANAR_ANGLE = 1e-9


@njit
def unpaired_edges(vertices, faces, edges, starts, uses):  # type: ignore[no-untyped-def]
    """How many of the ``edges`` of more than two triangles (:func:`faces_at_edges`)
    do not split into closed pieces.

    Around such an edge, sorted by their angle about it, a triangle whose
    outward normal faces back (against increasing angle) has its solid on the
    side of the next one: the two bound one solid wedge and must traverse the
    edge in opposite directions, and the triangles must alternate so. Where
    every such edge pairs up, the mesh is closed pieces that touch along them.
    """
    n_vertices = vertices.shape[0]
    bad = 0
    for j in range(edges.shape[0]):
        a, b = edges[j] // n_vertices, edges[j] % n_vertices
        run = starts[j + 1] - starts[j]
        if run % 2:
            bad += 1
            continue
        d = vertices[b] - vertices[a]
        d = d / np.sqrt(d @ d)
        axis = np.zeros(3)
        axis[np.argmin(np.abs(d))] = 1.0
        e1 = np.cross(d, axis)
        e1 = e1 / np.sqrt(e1 @ e1)
        e2 = np.cross(d, e1)
        angles = np.empty(run)
        backward = np.empty(run, dtype=np.bool_)
        for i in range(run):
            f = uses[starts[j] + i, 0]
            u = vertices[_third_vertex(faces, f, a, b)] - vertices[a]
            angles[i] = np.arctan2(u @ e2, u @ e1)
            tangent = np.cross(d, u - (u @ d) * d)  # towards increasing angle
            p0, p1, p2 = vertices[faces[f, 0]], vertices[faces[f, 1]], vertices[faces[f, 2]]
            backward[i] = np.cross(p1 - p0, p2 - p0) @ tangent < 0.0
        around = np.argsort(angles)
        # Coplanar triangles (solids sharing a face) have one angle: between
        # them the wedge is empty, so the one closing a wedge goes first.
        for _ in range(run):
            swapped = False
            for i in range(run - 1):
                first, second = around[i], around[i + 1]
                if (
                    abs(angles[second] - angles[first]) <= _COPLANAR_ANGLE
                    and backward[first]
                    and not backward[second]
                ):
                    around[i], around[i + 1] = second, first
                    swapped = True
            if not swapped:
                break
        # The pairs start at a backward triangle; try both phases of the cycle.
        paired = False
        for phase in range(2):
            ok = True
            for i in range(phase, run + phase, 2):
                first, second = around[i % run], around[(i + 1) % run]
                if (
                    not backward[first]
                    or backward[second]
                    or uses[starts[j] + first, 1] == uses[starts[j] + second, 1]
                ):
                    ok = False
                    break
            if ok:
                paired = True
                break
        if not paired:
            bad += 1
    return bad


@njit
def defects_after_renumbering(sorted_keys, faces, touched, n_vertices):  # type: ignore[no-untyped-def]
    """:func:`edge_defects` of ``faces`` (already renumbered), from the sorted
    keys of the faces before, when only the vertices marked in ``touched``
    (bool, (n_vertices,)) were renumbered: the edges away from them are
    counted from ``sorted_keys``, and those at them from the faces that use
    them, so no full sort is needed."""
    rest = np.zeros(3, dtype=np.int64)
    n = sorted_keys.shape[0]
    k = 0
    while k < n:
        edge, run = _edge_run(sorted_keys, k)
        if not (touched[edge // n_vertices] or touched[edge % n_vertices]):
            if run == 1:
                rest[0] += 1
            elif run > 2:
                rest[1] += 1
            elif (sorted_keys[k] & 1) == (sorted_keys[k + 1] & 1):
                rest[2] += 1
        k += run
    count = 0
    for f in range(faces.shape[0]):
        for c in range(3):
            if touched[faces[f, c]]:
                count += 1
                break
    near = np.empty(3 * count, dtype=np.int64)
    m = 0
    for f in range(faces.shape[0]):
        if touched[faces[f, 0]] or touched[faces[f, 1]] or touched[faces[f, 2]]:
            for corner in range(3):
                start = faces[f, corner]
                end = faces[f, (corner + 1) % 3]
                if touched[start] or touched[end]:
                    if start < end:
                        near[m] = ((start * n_vertices + end) << 1) | 1
                    else:
                        near[m] = (end * n_vertices + start) << 1
                    m += 1
    near = np.sort(near[:m])
    return rest + edge_defects(near)


@njit
def part_volumes_and_boxes(points, faces, labels, n_parts):  # type: ignore[no-untyped-def]
    """Each part's signed volume (Σ v0 · (v1 × v2) / 6 over its triangles, the
    divergence theorem about the origin) and bounding box, in one pass.

    Returns ``volumes`` (n_parts,) and ``boxes`` (n_parts, 2, 3): lowest and
    highest corner.
    """
    volumes = np.zeros(n_parts)
    boxes = np.empty((n_parts, 2, 3))
    boxes[:, 0, :] = np.inf
    boxes[:, 1, :] = -np.inf
    for f in range(faces.shape[0]):
        part = labels[f]
        a, b, c = points[faces[f, 0]], points[faces[f, 1]], points[faces[f, 2]]
        volumes[part] += (
            a[0] * (b[1] * c[2] - b[2] * c[1])
            + a[1] * (b[2] * c[0] - b[0] * c[2])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
        ) / 6.0
        for corner in range(3):
            p = points[faces[f, corner]]
            for k in range(3):
                boxes[part, 0, k] = min(boxes[part, 0, k], p[k])
                boxes[part, 1, k] = max(boxes[part, 1, k], p[k])
    return volumes, boxes
