"""Reading an MJCF file into a :class:`~tumble.robots.model.Robot`, through MuJoCo.

MJCF's semantics (default classes, ``fromto``, the compiler's angle units and
Euler sequences, ``childclass``, included files) are MuJoCo's own, so its
parser and compiler read the file (the ``mujoco`` package, an optional extra)
and tumble takes the compiled frames and geom sizes. A link is a body (the
world body is the root); its joints are the body's, in order, each turning
about its axis through its anchor. A body's geometry is the geoms MuJoCo counts
in its inertia (those of a group within the compiler's ``inertiagrouprange``),
each at its own ``mass`` or ``density``, as MuJoCo counts them.

Two sets of values per body:

- declared (:attr:`Link.inertial`, what the audit judges): the body's
  ``<inertial>`` as written, its numbers' texts kept (the digits of the file),
  wherever the compiler reads it (``inertiafromgeom`` false or auto); else the
  values MuJoCo computed from the geoms;
- compiled (:attr:`Link.compiled`, what :meth:`Robot.mass_properties`
  sums): MuJoCo's ``body_mass``, ``body_ipos``, ``body_iquat`` and
  ``body_inertia``, after everything the compiler does to the declared values
  (``settotalmass``, ``boundmass``, ``boundinertia``, ``balanceinertia``,
  ``fusestatic``), so that the whole robot is MuJoCo's.

A body with an explicit inertial that ``fusestatic`` merges into the body it is
welded to stays a link, welded there, for the audit to judge: its compiled
mass is none, as MuJoCo counts it in that body's. A file MuJoCo refuses for
its explicit inertials is still read (frames and geoms compiled with valid
stand-ins for them), for the audit to judge them; each link then counts as
declared, so that :meth:`Robot.mass_properties` refuses what no body has.

Before MuJoCo opens anything, the file, the files it includes and the files
they name are checked and the model's size bounded
(:mod:`tumble.robots.mjcf_files`).
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from tumble.errors import InputError, cut
from tumble.robots.geometry import LinkShape, at_own_mass, shown
from tumble.robots.mjcf_files import FULL_TO_URDF, MAX_BODIES, MAX_GEOMS, WrittenModel
from tumble.robots.model import Inertial, Joint, Link, Robot
from tumble.robots.ros import read_regular

__all__ = ["MAX_BODIES", "MAX_GEOMS", "one_line", "read_mjcf"]


def _matrix(quaternion: Any) -> np.ndarray:
    return Rotation.from_quat(np.asarray(quaternion, dtype=float), scalar_first=True).as_matrix()


def read_mjcf(path: Path) -> Robot:
    """The robot of an MJCF file (see :mod:`tumble.robots.mjcf`).

    Raises
    ------
    InputError
        The ``mujoco`` package missing; the file or a file it names (an include,
        a mesh, a texture...) not a regular file; malformed XML; a model MuJoCo
        refuses (its message, on one line); mass properties it cannot hold.
    RequestTooLargeError
        More than :data:`MAX_BODIES` bodies or :data:`MAX_GEOMS` geoms, or files
        too large for the memory budget.
    """
    try:
        import mujoco
    except ImportError:
        raise InputError(
            f"Expected the mujoco package to read the MJCF file {shown(path)}, got none "
            "installed: pip install 'tumble[robots]'."
        ) from None
    path = Path(path)
    written = WrittenModel(path.parent)
    written.scan(path, read_regular(path, "an MJCF file"))
    written.check(path)
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except Exception as error:  # MuJoCo raises ValueError with its parser's message
        raise InputError(
            f"Expected an MJCF model in {shown(path)}, got: {one_line(error)}"
        ) from None
    explicit = spec.compiler.inertiafromgeom != mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    # MuJoCo's compiler changes the spec (fusestatic removes bodies from it):
    # everything read of the file is taken before, each body by its place here.
    bodies = list(spec.bodies)
    texts = written.texts(bodies)
    declared = {
        k: _explicit(body, texts.get(k))
        for k, body in enumerate(bodies)
        if explicit and body.explicitinertial
    }
    unfused = _unfused(mujoco, spec, declared)
    try:
        model = spec.compile()
    except Exception:
        # An invalid explicit inertia stops MuJoCo's compiler: the audit must
        # still judge it, so the frames and geoms come from the copy, where
        # every explicit inertial is a valid stand-in (not counted: those
        # bodies are counted as declared).
        try:
            model = unfused.compile()
        except Exception as error:
            raise InputError(
                f"Expected an MJCF model MuJoCo compiles, got {path.name}: {one_line(error)}"
            ) from None
        return _robot(mujoco, unfused, model, path, declared, list(range(model.nbody)))
    # The wrappers of the spec's bodies stay the same objects through the compile.
    where = {id(body): k for k, body in enumerate(bodies)}
    of_model = [where.get(id(body), -1) for body in spec.bodies]
    if -1 in of_model or len(of_model) != model.nbody:  # bodies the compiler made: by place
        of_model = list(range(model.nbody))
    fused = None
    if len(of_model) < len(bodies) and set(declared) - set(of_model):
        try:
            fused = unfused.compile()
        except Exception as error:
            raise InputError(
                f"Expected an MJCF model MuJoCo compiles, got {path.name}: {one_line(error)}"
            ) from None
    return _robot(mujoco, spec, model, path, declared, of_model, fused, compiled=True)


def _unfused(mujoco: Any, spec: Any, declared: dict[int, Inertial]) -> Any:
    """A copy of ``spec`` that compiles whatever its explicit inertials (each
    ``declared`` body given mass 1 kg and moments 1 kg·m²) and keeps every body
    (no ``fusestatic``): its bodies are the spec's, in the same order."""
    copy = spec.copy()
    copy.compiler.fusestatic = False
    for k, body in enumerate(copy.bodies):
        if k in declared:
            body.mass = 1.0
            body.ipos = [0.0, 0.0, 0.0]
            body.iquat = [1.0, 0.0, 0.0, 0.0]
            body.ialt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
            body.inertia = [1.0, 1.0, 1.0]
            body.fullinertia = [math.nan] * 6
    return copy


def one_line(error: BaseException) -> str:
    """MuJoCo's message (several lines: the error, then the element and its line)
    as one line ending in a full stop, without its leading ``Error:``."""
    lines = [line.strip().rstrip(".:") for line in str(error).splitlines() if line.strip()]
    if lines:
        lines[0] = re.sub(r"(^|: )Error: ", r"\1", lines[0], count=1)
    return cut("; ".join(lines) or type(error).__name__, 400) + "."


def _explicit(body: Any, texts: tuple[str, ...] | None) -> Inertial:
    """A body's ``<inertial>`` as written: diagonal inertia in the frame of its
    quaternion, or the full tensor; ``texts``: its numbers as written (None:
    as MuJoCo read them)."""
    full = np.asarray(body.fullinertia, dtype=float)
    if np.all(np.isfinite(full)):
        values = tuple(float(full[k]) for k in FULL_TO_URDF)
    else:
        diagonal = np.asarray(body.inertia, dtype=float)
        values = (diagonal[0], 0.0, 0.0, diagonal[1], 0.0, diagonal[2])
    return _inertial(body.mass, body.ipos, body.iquat, values, texts)


def _inertial(
    mass: float,
    centre: Any,
    quaternion: Any,
    values: tuple[float, ...],
    texts: tuple[str, ...] | None = None,
) -> Inertial:
    """An MJCF body's inertial values: its frame given by a quaternion."""
    numbers = tuple(float(v) for v in values)
    return Inertial(
        mass=float(mass),
        xyz=tuple(float(v) for v in centre),
        rpy=(0.0, 0.0, 0.0),
        values=numbers,
        texts=texts or tuple(repr(v) for v in numbers),
        axes=_matrix(quaternion),
    )


def _compiled(model: Any, i: int) -> Inertial:
    """Body ``i``'s mass properties as MuJoCo compiled them."""
    inertia = model.body_inertia[i]
    values = (inertia[0], 0.0, 0.0, inertia[1], 0.0, inertia[2])
    return _inertial(model.body_mass[i], model.body_ipos[i], model.body_iquat[i], values)


def _robot(
    mujoco: Any,
    spec: Any,
    model: Any,
    path: Path,
    declared: dict[int, Inertial],
    of_model: list[int],
    unfused: Any = None,
    *,
    compiled: bool = False,
) -> Robot:
    """The robot of ``model``, compiled from ``spec``: ``declared``, the explicit
    inertials by the place of their body in the file; ``of_model``, that place
    of each of the model's bodies; ``unfused``, the model with every body of the
    file, where ``fusestatic`` merged away a body with an explicit inertial;
    ``compiled``: whether ``model`` is MuJoCo's own (else its explicit inertials
    are stand-ins, and every link counts as declared)."""
    low, high = (int(v) for v in spec.compiler.inertiagrouprange)
    geoms = {geom.id: geom for geom in spec.geoms}
    names = [model.body(i).name or f"body {k}" for i, k in enumerate(of_model)]
    links: dict[int, Link] = {}
    joints: dict[str, Joint] = {}
    settotalmass = float(spec.compiler.settotalmass) > 0
    for i, name in enumerate(names):
        shapes = []
        for g in range(model.body_geomadr[i], model.body_geomadr[i] + model.body_geomnum[i]):
            if i == 0 or not low <= model.geom_group[g] <= high:
                continue
            shape = _shape(mujoco, model, g, geoms.get(g))
            if shape is not None:
                shapes.append(shape)
        inertial = declared.get(of_model[i])
        simulated = _compiled(model, i) if compiled and i > 0 else None
        if i > 0 and inertial is None:
            inertial = _compiled(model, i)
            _check_finite(inertial, name, path)
            if settotalmass:
                shapes = _scaled_to(inertial.mass, shapes)
        geometry = {"collision": tuple(shapes), "visual": tuple(shapes)}
        links[of_model[i]] = Link(name, inertial, geometry, compiled=simulated)
        if i == 0:
            continue
        parent = names[model.body_parentid[i]]
        placement = (_matrix(model.body_quat[i]), np.array(model.body_pos[i], dtype=float))
        first = True
        for j in range(model.body_jntadr[i], model.body_jntadr[i] + model.body_jntnum[i]):
            joint_name = model.joint(j).name or f"{name} joint {j - model.body_jntadr[i]}"
            rotation, translation = placement if first else (np.eye(3), np.zeros(3))
            kind = _JOINT_KINDS[mujoco.mjtJoint(int(model.jnt_type[j])).name]
            reference = (
                float(model.qpos0[model.jnt_qposadr[j]])
                if kind in ("revolute", "prismatic")
                else 0.0
            )
            joints[joint_name] = Joint(
                joint_name,
                kind,
                parent,
                name,
                rotation,
                translation,
                np.array(model.jnt_axis[j], dtype=float),
                None,
                np.array(model.jnt_pos[j], dtype=float),
                reference,
            )
            first = False
        if first:
            joints[f"{name} (welded)"] = Joint(
                f"{name} (welded)", "fixed", parent, name, placement[0], placement[1], np.zeros(3)
            )
    if unfused is not None:
        for k, link, parent, rotation, translation in _fused(unfused, declared, of_model):
            links[k] = link
            weld = f"{link.name} (welded)"
            joints[weld] = Joint(
                weld,
                "fixed",
                names[of_model.index(parent)],
                link.name,
                rotation,
                translation,
                np.zeros(3),
            )
    ordered = {link.name: link for _, link in sorted(links.items())}
    return Robot(spec.modelname or path.stem, path, ordered, joints, names[0])


#: MuJoCo's compiled values of a body that ``fusestatic`` merged into the body
#: it is welded to: none of its own (its mass is counted in that body's).
_MERGED = Inertial(mass=0.0, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0), values=(0.0,) * 6)


def _fused(
    unfused: Any, declared: dict[int, Inertial], of_model: list[int]
) -> list[tuple[int, Link, int, np.ndarray, np.ndarray]]:
    """Each body with an explicit inertial that ``fusestatic`` merged away, for
    the audit to judge it: its place in the file, its link (declared values;
    compiled, none of its own), the place of the body it is merged into and its
    frame in that body's (x = R x_own + t), from ``unfused``, the model that
    keeps every body."""
    kept = set(of_model)
    found = []
    for k in sorted(set(declared) - kept):
        rotation = _matrix(unfused.body_quat[k])
        translation = np.array(unfused.body_pos[k], dtype=float)
        parent = int(unfused.body_parentid[k])
        while parent not in kept:  # the world body is always kept
            turn = _matrix(unfused.body_quat[parent])
            rotation = turn @ rotation
            translation = turn @ translation + np.array(unfused.body_pos[parent], dtype=float)
            parent = int(unfused.body_parentid[parent])
        name = unfused.body(k).name or f"body {k}"
        link = Link(name, declared[k], {"collision": (), "visual": ()}, compiled=_MERGED)
        found.append((k, link, parent, rotation, translation))
    return found


def _check_finite(inertial: Inertial, name: str, path: Path) -> None:
    """Refuse a body whose mass properties MuJoCo computed from its geoms past
    float64's range (a geom's mass or density near 1e308): no digits of the
    file hold them, so the audit could say nothing true of them."""
    if not all(math.isfinite(v) for v in (inertial.mass, *inertial.xyz, *inertial.values)):
        moments = ", ".join(f"{inertial.values[k]:g}" for k in (0, 3, 5))
        raise InputError(
            f"Expected body {name!r} of {shown(path)} to have mass properties MuJoCo computes "
            f"as finite numbers from its geoms, got mass {inertial.mass:g} kg and moments "
            f"{moments} kg·m² (its geoms' masses or densities are near float64's limit)."
        )


def _scaled_to(mass: float, shapes: list[LinkShape]) -> list[LinkShape]:
    """A body's shapes with their masses scaled to sum to ``mass`` kg, as MuJoCo's
    compiler scales a body computed from its geoms for ``settotalmass``."""
    solids = [at_own_mass(shape) for shape in shapes]
    total = sum(solid.mass for solid in solids if solid is not None)
    if not total > 0:
        return shapes
    return [
        replace(shape, mass=(0.0 if solid is None else solid.mass) * mass / total, density=None)
        for shape, solid in zip(shapes, solids, strict=True)
    ]


#: MuJoCo's joint types (``mjtJoint``, by name) as tumble's joint kinds.
_JOINT_KINDS = {
    "mjJNT_FREE": "floating",
    "mjJNT_BALL": "spherical",
    "mjJNT_SLIDE": "prismatic",
    "mjJNT_HINGE": "revolute",
}


def _shape(mujoco: Any, model: Any, g: int, geom: Any) -> LinkShape | None:
    """Geom ``g`` as a :class:`LinkShape` in its body's frame, with its own mass or
    density (``geom``: its element of the spec); None for one without volume."""
    kind = mujoco.mjtGeom(int(model.geom_type[g]))
    size = [float(v) for v in model.geom_size[g]]
    rotation = _matrix(model.geom_quat[g])
    translation = np.array(model.geom_pos[g], dtype=float)
    mass = None if geom is None or not np.isfinite(geom.mass) else float(geom.mass)
    density = None if mass is not None else 1000.0 if geom is None else float(geom.density)
    types = mujoco.mjtGeom

    def shape(name: str, dimensions: tuple[float, ...]) -> LinkShape:
        return LinkShape(name, dimensions, rotation, translation, mass=mass, density=density)

    if kind == types.mjGEOM_SPHERE:
        return shape("sphere", (size[0],))
    if kind in (types.mjGEOM_CAPSULE, types.mjGEOM_CYLINDER):  # MuJoCo gives the half-length
        name = "capsule" if kind == types.mjGEOM_CAPSULE else "cylinder"
        return shape(name, (size[0], 2 * size[1]))
    if kind == types.mjGEOM_ELLIPSOID:
        return shape("ellipsoid", tuple(size))
    if kind == types.mjGEOM_BOX:  # MuJoCo gives the half-edges
        return shape("box", tuple(2 * v for v in size))
    if kind == types.mjGEOM_MESH:
        mesh = int(model.geom_dataid[g])
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        first, faces = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
        return LinkShape(
            "mesh",
            (),
            rotation,
            translation,
            mass=mass,
            density=density,
            vertices=np.array(model.mesh_vert[start : start + count], dtype=float),
            faces=np.array(model.mesh_face[first : first + faces], dtype=np.int64),
        )
    return None
