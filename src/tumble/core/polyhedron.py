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

from tumble.core._jit import njit_parallel, prange

#: Number of accumulated integrals: volume, 3 first moments, 6 second moments.
N_INTEGRALS = 10

#: Triangles per parallel work item: large enough to amortise scheduling,
#: small enough that two threads share a 4M-triangle mesh evenly.
CHUNK = 8192


@njit_parallel
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
    (10,) float64: ``[V, Sx, Sy, Sz, Sxx, Syy, Szz, Sxy, Sxz, Syz]`` where
    ``V = ∫ dV`` (m³, negative for an inside-out mesh), ``S_i = ∫ x_i dV`` (m⁴)
    and ``S_ij = ∫ x_i x_j dV`` (m⁵), with x measured from ``reference``.
    """
    n_faces = faces.shape[0]
    n_chunks = (n_faces + CHUNK - 1) // CHUNK
    partial = np.zeros((n_chunks, N_INTEGRALS))
    rx = reference[0]
    ry = reference[1]
    rz = reference[2]
    for chunk in prange(n_chunks):
        start = chunk * CHUNK
        stop = min(start + CHUNK, n_faces)
        v = 0.0
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
        partial[chunk, 0] = v
        partial[chunk, 1] = sx
        partial[chunk, 2] = sy
        partial[chunk, 3] = sz
        partial[chunk, 4] = sxx
        partial[chunk, 5] = syy
        partial[chunk, 6] = szz
        partial[chunk, 7] = sxy
        partial[chunk, 8] = sxz
        partial[chunk, 9] = syz
    totals = np.zeros(N_INTEGRALS)
    for chunk in range(n_chunks):
        for q in range(N_INTEGRALS):
            totals[q] += partial[chunk, q]
    totals[0] /= 6.0
    for q in range(1, 4):
        totals[q] /= 24.0
    for q in range(4, N_INTEGRALS):
        totals[q] /= 120.0
    return totals
