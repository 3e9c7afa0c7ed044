"""Exact volume integrals of a closed triangle mesh (a polyhedron).

Each triangle (a, b, c), taken relative to a reference point, closes a signed
tetrahedron with that point. By the divergence theorem the sum over triangles of
these tetrahedra's integrals is the integral over the solid, exactly, whatever
the reference point; it is chosen near the mesh so the sums do not cancel.

For a tetrahedron with one vertex at the origin and the others at a, b, c,
with ``d = a · (b × c)`` (six times its signed volume) and ``s = a + b + c``:

* volume                ``∫ dV      = d / 6``
* first moments         ``∫ x_i dV  = d s_i / 24``
* second moments        ``∫ x_i x_j dV = d (a_i a_j + b_i b_j + c_i c_j + s_i s_j) / 120``

These are Tonon's explicit formulas (F. Tonon, "Explicit exact formulas for the
3-D tetrahedron inertia tensor in terms of its vertex coordinates", J. Math.
Stat. 1(1), 8-11, 2004) written in the compact covariance form: the second
moment of a uniform simplex is ``V/20 (Σ_k v_k v_kᵀ + s sᵀ)``.
"""

from __future__ import annotations

import numpy as np

from tumble.core._jit import njit, njit_parallel, prange

#: Number of accumulated sums: volume, 3 first moments, 6 second moments, and
#: the surface area (the scale against which a volume counts as zero).
N_INTEGRALS = 11

#: Triangles per work item: large enough to amortise scheduling, small enough
#: that two threads share a 4M-triangle mesh evenly. The sums are always taken
#: chunk by chunk, serial or parallel, so both give bit-identical results.
CHUNK = 8192

#: Below this many triangles the serial kernel runs: waking a thread team costs
#: more than the work (tens of microseconds to milliseconds on a busy machine).
PARALLEL_THRESHOLD = 4 * CHUNK


@njit
def _accumulate_chunk(vertices, faces, reference, start, stop, out):  # type: ignore[no-untyped-def]
    """Sums over triangles ``start:stop`` into ``out`` (length ``N_INTEGRALS``), unscaled."""
    rx = reference[0]
    ry = reference[1]
    rz = reference[2]
    v = 0.0
    twice_area = 0.0
    sx = 0.0
    sy = 0.0
    sz = 0.0
    sxx = 0.0
    syy = 0.0
    szz = 0.0
    sxy = 0.0
    sxz = 0.0
    syz = 0.0
    for f in range(start, stop):
        i = faces[f, 0]
        j = faces[f, 1]
        k = faces[f, 2]
        ax = vertices[i, 0] - rx
        ay = vertices[i, 1] - ry
        az = vertices[i, 2] - rz
        bx = vertices[j, 0] - rx
        by = vertices[j, 1] - ry
        bz = vertices[j, 2] - rz
        cx = vertices[k, 0] - rx
        cy = vertices[k, 1] - ry
        cz = vertices[k, 2] - rz
        d = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
        nx = (by - ay) * (cz - az) - (bz - az) * (cy - ay)
        ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az)
        nz = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        twice_area += np.sqrt(nx * nx + ny * ny + nz * nz)
        tx = ax + bx + cx
        ty = ay + by + cy
        tz = az + bz + cz
        v += d
        sx += d * tx
        sy += d * ty
        sz += d * tz
        sxx += d * (ax * ax + bx * bx + cx * cx + tx * tx)
        syy += d * (ay * ay + by * by + cy * cy + ty * ty)
        szz += d * (az * az + bz * bz + cz * cz + tz * tz)
        sxy += d * (ax * ay + bx * by + cx * cy + tx * ty)
        sxz += d * (ax * az + bx * bz + cx * cz + tx * tz)
        syz += d * (ay * az + by * bz + cy * cz + ty * tz)
    out[0] = v
    out[1] = sx
    out[2] = sy
    out[3] = sz
    out[4] = sxx
    out[5] = syy
    out[6] = szz
    out[7] = sxy
    out[8] = sxz
    out[9] = syz
    out[10] = twice_area


@njit_parallel
def _chunk_sums_parallel(vertices, faces, reference):  # type: ignore[no-untyped-def]
    n_chunks = (faces.shape[0] + CHUNK - 1) // CHUNK
    partial = np.zeros((n_chunks, N_INTEGRALS))
    for chunk in prange(n_chunks):
        start = chunk * CHUNK
        _accumulate_chunk(
            vertices, faces, reference, start, min(start + CHUNK, faces.shape[0]), partial[chunk]
        )
    return partial


@njit
def _chunk_sums_serial(vertices, faces, reference):  # type: ignore[no-untyped-def]
    n_chunks = (faces.shape[0] + CHUNK - 1) // CHUNK
    partial = np.zeros((n_chunks, N_INTEGRALS))
    for chunk in range(n_chunks):
        start = chunk * CHUNK
        _accumulate_chunk(
            vertices, faces, reference, start, min(start + CHUNK, faces.shape[0]), partial[chunk]
        )
    return partial


@njit
def _finish(partial):  # type: ignore[no-untyped-def]
    """Add the chunks' sums in a fixed order and apply the tetrahedron factors."""
    totals = np.zeros(N_INTEGRALS)
    for chunk in range(partial.shape[0]):
        for q in range(N_INTEGRALS):
            totals[q] += partial[chunk, q]
    totals[0] /= 6.0
    totals[10] /= 2.0
    for q in range(1, 4):
        totals[q] /= 24.0
    for q in range(4, 10):
        totals[q] /= 120.0
    return totals


def mesh_integrals(vertices, faces, reference):  # type: ignore[no-untyped-def]
    """Volume integrals of the solid bounded by a closed, outward-wound triangle mesh.

    Parameters
    ----------
    vertices : (n_vertices, 3) float64, metres.
    faces : (n_faces, 3) int64, indices into ``vertices``, counter-clockwise
        seen from outside (outward normals by the right-hand rule).
    reference : (3,) float64, metres; the point the moments are taken about.

    Returns
    -------
    (11,) float64: ``[V, Sx, Sy, Sz, Sxx, Syy, Szz, Sxy, Sxz, Syz, A]`` where
    ``V = ∫ dV`` (m³, negative for an inside-out mesh), ``S_i = ∫ x_i dV`` (m⁴)
    and ``S_ij = ∫ x_i x_j dV`` (m⁵), with x measured from ``reference``, and
    ``A`` the surface area (m²): ``|V|`` below round-off of ``A × size`` means
    the mesh encloses no volume.

    Meshes of at least ``PARALLEL_THRESHOLD`` triangles are summed on all
    threads; the result does not depend on the number of threads.
    """
    if faces.shape[0] >= PARALLEL_THRESHOLD:
        return _finish(_chunk_sums_parallel(vertices, faces, reference))
    return _finish(_chunk_sums_serial(vertices, faces, reference))


@njit
def shell_integrals(vertices, faces, reference):  # type: ignore[no-untyped-def]
    """Surface integrals of a triangle mesh (open or closed, either winding).

    For a triangle of area A with vertices a, b, c (from ``reference``) and
    ``s = a + b + c``: ``∫ dA = A``, ``∫ x_i dA = A s_i / 3`` and
    ``∫ x_i x_j dA = A (a_i a_j + b_i b_j + c_i c_j + s_i s_j) / 12`` (the
    covariance form of a uniform triangle, as the tetrahedron's above).

    Returns
    -------
    (10,) float64: ``[A, Sx, Sy, Sz, Sxx, Syy, Szz, Sxy, Sxz, Syz]``, area (m²),
    first (m³) and second (m⁴) moments about ``reference``.
    """
    out = np.zeros(10)
    for f in range(faces.shape[0]):
        a = vertices[faces[f, 0]] - reference
        b = vertices[faces[f, 1]] - reference
        c = vertices[faces[f, 2]] - reference
        u, v = b - a, c - a
        nx = u[1] * v[2] - u[2] * v[1]
        ny = u[2] * v[0] - u[0] * v[2]
        nz = u[0] * v[1] - u[1] * v[0]
        area = 0.5 * np.sqrt(nx * nx + ny * ny + nz * nz)
        s = a + b + c
        out[0] += area
        for i in range(3):
            out[1 + i] += area * s[i] / 3.0
        second = area / 12.0
        for q, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
            out[4 + q] += second * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j])
    return out
