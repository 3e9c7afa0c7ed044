"""Mass properties of a solid bounded by a closed triangle mesh.

Files are read with trimesh (STL, OBJ, PLY, GLB/glTF, OFF, ...; STEP through
cascadio, which tessellates it with OpenCASCADE in a child process that a crash
of OpenCASCADE cannot take down with it, bounded in time and memory
(:mod:`tumble.mesh.step`), and converts its units to metres); the volume
integrals are tumble's own compiled kernel,
:func:`tumble.core.polyhedron.mesh_integrals`, which is exact for the polyhedron
(Tonon 2004, via the divergence theorem).

Before integrating, the mesh is checked, because the integrals of a mesh that
does not bound a solid are meaningless rather than approximately right:

* vertices with bit-identical coordinates are merged (STL files repeat them)
  and triangles that then have a repeated corner (zero area) are dropped;
* where edges are left with one triangle (a seam whose two sides differ by
  round-off, as CAD exports write them), the vertices of those edges closer
  than ``merge_tolerance`` are welded (:func:`tumble.core.topology.weld`:
  deterministic, whatever the vertex order), with a :class:`MeshRepairWarning`;
* every edge must be shared by exactly two triangles (watertight), or split
  the mesh into closed pieces: coincident triangles of opposite winding (two
  solids sharing a face) cancel and are removed, and closed pieces that touch
  along edges or at vertices (a convex decomposition) are accepted;
* the two triangles of every edge must traverse it in opposite directions
  (consistent winding);
* the signed volume must be non-zero; a negative one (an inside-out mesh, all
  normals inward) is reversed with a :class:`MeshOrientationWarning`;
* separate parts must all be wound the same way, except inward-wound cavities
  nested inside a part; overlapping parts are added (their overlap counts twice).
"""

from __future__ import annotations

import os
import re
import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core.polyhedron import mesh_integrals
from tumble.errors import (
    QUOTED_PATH_LENGTH,
    InputError,
    MeshError,
    RequestTooLargeError,
    quoted,
)
from tumble.massprops import MassProperties
from tumble.mesh.reading import check_mesh_file
from tumble.mesh.step import STEP_SUFFIXES, tessellate_step
from tumble.mesh.validation import (
    DEFAULT_MERGE_FRACTION,
    MeshRepairWarning,
    bounds_and_centre,
    check_parts,
    checked_topology,
    cubic_metres,
    scaled_inertia,
)
from tumble.units import length_scale, to_si

__all__ = [
    "DEFAULT_MERGE_FRACTION",
    "MeshOrientationWarning",
    "MeshRepairWarning",
    "check_mesh_file",
    "declared_scale",
    "from_mesh",
]

#: A mesh whose |volume| is below this fraction of (surface area × largest
#: extent) encloses nothing: the volume of a flat or self-cancelling surface is
#: round-off, at most about 1e-16 · √n_triangles of that product. A plate of
#: thickness t has a ratio t / (2 · length), so only plates thinner than
#: 2e-9 of their length are refused.
ZERO_VOLUME_FRACTION = 1e-9


class MeshOrientationWarning(UserWarning):
    """An inside-out mesh (inward normals) was reversed before integrating."""


def from_mesh(
    mesh: Any,
    density: Any = None,
    mass: Any = None,
    units: Any = None,
    *,
    merge_tolerance: Any = None,
    shell_thickness: Any = None,
) -> MassProperties:
    """Mass properties of the uniform solid bounded by a closed triangle mesh.

    Parameters
    ----------
    mesh : path to a mesh file (anything trimesh reads: STL, OBJ, PLY, GLB, STEP, ...),
        or a ``trimesh.Trimesh`` / ``trimesh.Scene``. Body coordinates are the
        mesh's own coordinates.
    density : uniform density, kg/m³ (or e.g. ``"2700 kg/m^3"``). Give exactly
        one of ``density`` and ``mass``.
    mass : total mass, kg (or e.g. ``"1.2 kg"``); the density follows from the volume.
    units : length unit of the mesh coordinates, e.g. ``"mm"`` for most CAD
        files. Default: the unit the file declares (glTF/GLB may), else metres;
        given, it overrides what the file declares.
    merge_tolerance : the largest distance at which the vertices of edges with
        one triangle are welded, a length (m, or e.g. ``"0.01 mm"``; after
        ``units``). Default: round-off only, 4 units in the last place of the
        largest coordinate in the precision the file stores (single in STL
        files), and at least 1e-9 of the bounding box's diagonal; 0 welds
        nothing.
    shell_thickness : instead of the solid the mesh bounds, its surface as a
        thin shell of this wall thickness (a length, e.g. ``"2 mm"``): sheet
        metal, thin-walled or open parts (:mod:`tumble.mesh.shell`; the surface
        need not be closed, and nothing is welded). ``density`` is then the
        wall material's.

    Returns
    -------
    MassProperties, with the centre of mass in the mesh's coordinates (m) and
    the inertia about it in the mesh's axes.

    Raises
    ------
    InputError
        Unreadable file (also a STEP file OpenCASCADE crashes on, or does not
        finish within its time limit, ``TUMBLE_STEP_TIME_LIMIT``), both or
        neither of density and mass, non-positive density or mass, a unit that
        is not a length, a mass or inertia beyond float range; a file that is
        not a regular file (a FIFO, a device) or is sparse
        (``tumble.mesh.check_mesh_file``, before it is read).
    RequestTooLargeError
        A file whose reading would take more than the memory budget
        (``TUMBLE_MEMORY_BUDGET``), told from its size before it is read
        (``tumble.mesh.check_mesh_file``); a STEP file whose tessellation reaches its
        memory limit (the same budget).
    MeshError
        No triangles, non-finite vertices (or numbers in a STEP file), a mesh
        wider than float range (a diagonal over 1.8e308 m), holes (the message counts the
        boundary edges, gives their length, and suggests the
        ``merge_tolerance`` that closes a seam), edges shared by more than two
        triangles that do not split the mesh into closed pieces, inconsistent
        winding, or zero volume.

    Warns
    -----
    MeshOrientationWarning
        If the mesh is inside out; its winding is reversed (never a silent abs()).
    MeshRepairWarning
        If vertices were welded (how many, and the largest distance moved),
        coincident triangles removed, or the mesh is closed pieces touching
        along edges (how many).

    Examples
    --------
    A box of 10 × 20 × 30 cm as a triangle mesh has the inertia of the
    closed-form solid box:

    >>> import numpy as np
    >>> import trimesh
    >>> import tumble as tb
    >>> mesh = trimesh.creation.box(extents=[0.1, 0.2, 0.3])
    >>> brick = tb.from_mesh(mesh, mass="1 kg")
    >>> np.allclose(brick.inertia, tb.shapes.box(1.0, [0.1, 0.2, 0.3]).inertia)
    True

    Given a density instead, the mass follows from the volume (6 litres):

    >>> print(f"{tb.from_mesh(mesh, density='2700 kg/m^3').mass:.2f} kg")
    16.20 kg

    Coordinates in millimetres, as most CAD files have them:

    >>> mesh_mm = trimesh.creation.box(extents=[100, 200, 300])
    >>> np.allclose(tb.from_mesh(mesh_mm, mass=1.0, units="mm").inertia, brick.inertia)
    True
    """
    if (density is None) == (mass is None):
        raise InputError(
            "Expected exactly one of `density` and `mass`, got "
            + ("both." if density is not None else "neither.")
        )
    label, vertices, faces, file_scale = _load(mesh)
    # Coordinates that are all single-precision numbers (STL stores them so)
    # carry single-precision round-off.
    with np.errstate(over="ignore", invalid="ignore"):  # beyond single range: not single
        single = bool(np.all(vertices == vertices.astype(np.float32)))
    epsilon = float(np.finfo(np.float32 if single else np.float64).eps)
    if units is not None:
        vertices = vertices * length_scale(units, "units")
    elif file_scale is not None:
        vertices = vertices * file_scale
    if shell_thickness is not None:
        from tumble.mesh.shell import shell_mass_properties

        thickness = to_si(shell_thickness, "length", "shell_thickness")
        if not thickness > 0:
            raise InputError(f"Expected `shell_thickness` > 0 m, got {thickness!r}.")
        rho = None if density is None else to_si(density, "density", "density")
        total = None if mass is None else to_si(mass, "mass", "mass")
        if (rho is not None and rho <= 0) or (total is not None and total <= 0):
            name, value = ("density", rho) if rho is not None else ("mass", total)
            raise InputError(f"Expected `{name}` > 0, got {value!r}.")
        return shell_mass_properties(
            vertices, faces, thickness, density=rho, mass=total, label=label
        )
    tolerance = None
    if merge_tolerance is not None:
        tolerance = to_si(merge_tolerance, "length", "merge_tolerance")
        if not tolerance >= 0:
            raise InputError(f"Expected `merge_tolerance` >= 0 m, got {tolerance!r}.")
    if density is not None:
        rho = to_si(density, "density", "density")
        if rho <= 0:
            raise InputError(f"Expected `density` > 0 kg/m^3, got {rho!r}.")
        return mesh_mass_properties(
            vertices,
            faces,
            density=rho,
            label=label,
            merge_tolerance=tolerance,
            epsilon=epsilon,
        )
    total = to_si(mass, "mass", "mass")
    if total <= 0:
        raise InputError(f"Expected `mass` > 0 kg, got {total!r}.")
    return mesh_mass_properties(vertices, faces, mass=total, label=label, merge_tolerance=tolerance)


def _load(mesh: Any) -> tuple[str, NDArray[np.float64], NDArray[np.int64], float | None]:
    """Vertices, faces and declared length unit of a file or trimesh object, unprocessed."""
    import trimesh

    if isinstance(mesh, str | os.PathLike):
        path = Path(mesh)
        shown = quoted(path, QUOTED_PATH_LENGTH)
        label = f"mesh {shown}"
        check_mesh_file(path, "`mesh`")  # before a byte is read: the file and its size
        try:
            why = None if path.is_file() else "a directory" if path.is_dir() else "no such file"
        except OSError as exc:  # a name too long, a folder that cannot be read
            why = exc.strerror or str(exc)
        if why is not None:
            raise InputError(f"Expected `mesh` to be a mesh file, got {shown} ({why}).")
        try:
            # process=False: keep the file's triangles as they are; merging and
            # the checks below are ours, so that errors can say what is wrong.
            if path.suffix.lower() in STEP_SUFFIXES:
                with tempfile.TemporaryDirectory() as folder:
                    glb = Path(folder) / "tessellated.glb"
                    tessellate_step(path, glb)
                    loaded = trimesh.load_mesh(glb, process=False)
            else:
                loaded = trimesh.load_mesh(path, process=False)
        except InputError:
            raise
        except ImportError as exc:
            raise InputError(
                f"Reading {shown} needs a package that is not installed: {exc}."
            ) from None
        except Exception as exc:  # trimesh raises many types for unreadable files
            raise _unreadable(path, label, exc) from None
    elif isinstance(mesh, trimesh.Scene):
        label, loaded = "mesh (scene)", mesh.to_mesh()
    elif isinstance(mesh, trimesh.Trimesh):
        label, loaded = "mesh", mesh
    else:
        raise InputError(
            f"Expected `mesh` to be a file path or a trimesh.Trimesh, got {type(mesh).__name__}."
        )
    vertices = np.ascontiguousarray(loaded.vertices, dtype=float)
    faces = np.ascontiguousarray(loaded.faces, dtype=np.int64)
    return label, vertices, faces, declared_scale(loaded)


def declared_scale(loaded: Any) -> float | None:
    """Metres per unit of a mesh trimesh read, where its file declares a unit (glTF,
    COLLADA's ``<unit meter="0.01"/>``, which trimesh gives as ``"0.01 * meters"``):
    trimesh's own conversion. None where it declares none."""
    import trimesh

    declared = getattr(loaded, "units", None)
    if not declared:
        return None
    try:
        return float(trimesh.units.unit_conversion(str(declared), "meters"))
    except Exception as exc:  # trimesh raises ValueError or KeyError for unknown units
        raise InputError(
            f"Expected a mesh in a length unit, got one in {quoted(str(declared))}: {exc}."
        ) from None


#: What a well-formed file of a text format holds, for the message about one that is not.
_WELL_FORMED = {
    ".stl": "each facet has 3 `vertex` lines of 3 numbers",
    ".obj": "each `v` line has 3 numbers, each `f` line the numbers of its vertices",
}

# numpy's words for lines with too few or too many numbers, which trimesh's text
# readers let through from numpy (and trimesh's own, for a facet of two vertices).
_MALFORMED = re.compile(
    r"cannot reshape|unmatched data|could not convert|invalid literal|incorrect number of vertices"
)
_OUT_OF_BOUNDS = re.compile(r"index (-?\d+) is out of bounds for axis \d+ with size (\d+)")


def _unreadable(path: Path, label: str, exc: Exception) -> InputError:
    """The error for a file trimesh could not read: what is wrong with it, in the
    words of the format rather than numpy's where the cause is known."""
    if isinstance(exc, MemoryError):  # its message is often empty
        return RequestTooLargeError(
            f"Expected `mesh` to be a mesh file that fits in memory, got "
            f"{quoted(path, QUOTED_PATH_LENGTH)}: the system ran out of memory reading it "
            "(use a mesh of fewer triangles)."
        )
    text = str(exc)
    bounds = _OUT_OF_BOUNDS.search(text) if isinstance(exc, IndexError) else None
    if bounds:  # a face with a vertex index beyond the vertices
        return MeshError(
            f"Expected {label} face indices in [0, {int(bounds[2]) - 1}], got index {bounds[1]}."
        )
    if isinstance(exc, IndexError | ValueError) and (_MALFORMED.search(text) or not text):
        rule = _WELL_FORMED.get(path.suffix.lower())
        return MeshError(
            f"Expected {label} to be a well-formed {path.suffix.lstrip('.').upper()} file"
            + (f" ({rule})" if rule else "")
            + ", got one that is not."
        )
    return InputError(
        f"Expected `mesh` to be a readable mesh file (STL, OBJ, PLY, GLB, STEP, ...), "
        f"got {quoted(path, QUOTED_PATH_LENGTH)}: {text or type(exc).__name__}"
    )


def mesh_mass_properties(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    *,
    density: float | None = None,
    mass: float | None = None,
    label: str = "mesh",
    merge_tolerance: float | None = None,
    epsilon: float = float(np.finfo(np.float64).eps),
) -> MassProperties:
    """Mass properties from SI arrays (``vertices`` (n, 3) m, ``faces`` (k, 3));
    exactly one of ``density`` (kg/m³) and ``mass`` (kg); ``merge_tolerance``
    in m (None: the default); ``epsilon`` the relative round-off of the
    coordinates as stored (double precision for arrays). See :func:`from_mesh`."""
    vertices, faces = checked_topology(vertices, faces, label, merge_tolerance, epsilon)
    low, high, reference = bounds_and_centre(vertices)
    size = float(np.max(high - low))
    # Integrate in units of the mesh's own size about a point near it: the sums
    # neither cancel (far from the origin) nor overflow or underflow (1e±100 m).
    scaled = (vertices - reference) / size
    origin = np.zeros(3)
    integrals = mesh_integrals(scaled, faces, origin)
    volume, area = integrals[0], integrals[10]
    if abs(volume) <= ZERO_VOLUME_FRACTION * area:
        raise MeshError(
            f"Expected {label} to enclose a volume, got a signed volume of "
            f"{cubic_metres(volume, size, '.3g')} (flat or self-cancelling)."
        )
    check_parts(scaled, faces, volume, label, size)
    if volume < 0:
        warnings.warn(
            f"{label} is inside out (normals point inward, signed volume "
            f"{cubic_metres(volume, size)}); its winding was reversed.",
            MeshOrientationWarning,
            stacklevel=3,
        )
        integrals = -integrals
        volume = -volume
    first = integrals[1:4]
    sxx, syy, szz, sxy, sxz, syz = integrals[4:10]
    centroid = first / volume  # relative to the reference point, in units of `size`
    # Second moments about the centroid: ∫ x xᵀ dV − V c cᵀ.
    second = np.array([[sxx, sxy, sxz], [sxy, syy, syz], [sxz, syz, szz]])
    second -= volume * np.outer(centroid, centroid)
    if density is not None:
        with np.errstate(over="ignore", under="ignore"):
            total = float(density * volume * np.float64(size) ** 3)
        if not 0 < total < np.inf:
            raise InputError(
                f"Expected the mass of {label} (density × volume) within float range, got "
                f"{total!r} kg from {density!r} kg/m³ and {size:.3g} m across."
            )
    else:
        total = float(mass)  # type: ignore[arg-type]
    # Inertia per unit mass is (trace(C) E − C) / V in units of size²: no size³ or
    # size⁵ factors that would overflow for huge meshes or vanish for tiny ones.
    inertia = scaled_inertia(total, size, (np.trace(second) * np.eye(3) - second) / volume, label)
    return MassProperties(total, reference + size * centroid, inertia)
