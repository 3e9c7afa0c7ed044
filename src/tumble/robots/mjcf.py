"""Reading an MJCF file into a :class:`~tumble.robots.model.Robot`, through MuJoCo.

MJCF's semantics (default classes, ``fromto``, the compiler's angle units and
Euler sequences, ``childclass``, included files) are MuJoCo's own, so its
parser and compiler read the file (the ``mujoco`` package, an optional extra)
and tumble takes the compiled frames and geom sizes. A link is a body (the
world body is the root); its joints are the body's, in order, each turning
about its axis through its anchor. A body's geometry is the geoms MuJoCo counts
in its inertia (those of a group within the compiler's ``inertiagrouprange``),
each at its own ``mass`` or ``density``, as MuJoCo counts them; its declared
values are those of its ``<inertial>`` where it has one, else those MuJoCo
computed from the geoms.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from tumble.errors import InputError
from tumble.robots.model import Inertial, Joint, Link, Robot, Shape, at_own_mass, shown

__all__ = ["read_mjcf"]

#: MuJoCo's joint types (mjtJoint) as tumble's joint kinds.
_JOINT_KINDS = {0: "floating", 1: "ball", 2: "prismatic", 3: "revolute"}

# MuJoCo's geom types (mjtGeom) that bound a volume.
_SPHERE, _CAPSULE, _ELLIPSOID, _CYLINDER, _BOX, _MESH = 2, 3, 4, 5, 6, 7


def _matrix(quaternion: Any) -> np.ndarray:
    return Rotation.from_quat(np.asarray(quaternion, dtype=float), scalar_first=True).as_matrix()


def read_mjcf(path: Path) -> Robot:
    """The robot of an MJCF file (see :mod:`tumble.robots.mjcf`)."""
    try:
        import mujoco
    except ImportError:
        raise InputError(
            f"Expected the mujoco package to read the MJCF file {shown(path)}, got none "
            "installed: pip install 'tumble[robots]'."
        ) from None
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except Exception as error:  # MuJoCo raises ValueError with its parser's message
        raise InputError(f"Expected an MJCF model in {shown(path)}, got: {error}") from None
    declared = {body.name: _explicit(body) for body in spec.bodies if body.explicitinertial}
    try:
        model = spec.compile()
    except Exception as error:
        # An invalid explicit inertia stops MuJoCo's compiler: the audit must
        # still read it, so the declared values come from the spec and the
        # frames and geoms from a compile that accepts any inertia.
        spec.compiler.balanceinertia = True
        spec.compiler.boundmass = 1e-12
        spec.compiler.boundinertia = 1e-18
        try:
            model = spec.compile()
        except Exception:
            raise InputError(
                f"Expected an MJCF model MuJoCo compiles, got {path.name}: {error}"
            ) from None
    return _robot(mujoco, spec, model, path, declared)


def _explicit(body: Any) -> Inertial:
    """A body's ``<inertial>`` as written: diagonal inertia in the frame of its
    quaternion, or the full tensor."""
    full = np.asarray(body.fullinertia, dtype=float)
    if np.all(np.isfinite(full)):
        values = (full[0], full[3], full[4], full[1], full[5], full[2])
    else:
        diagonal = np.asarray(body.inertia, dtype=float)
        values = (diagonal[0], 0.0, 0.0, diagonal[1], 0.0, diagonal[2])
    return _inertial(body.mass, body.ipos, body.iquat, values)


def _inertial(mass: float, centre: Any, quaternion: Any, values: tuple[float, ...]) -> Inertial:
    """An MJCF body's inertial values: its frame given by a quaternion."""
    axes = _matrix(quaternion)
    return Inertial(
        mass=float(mass), xyz=tuple(float(v) for v in centre), rpy=(0.0, 0.0, 0.0),
        values=tuple(float(v) for v in values), texts=tuple(repr(float(v)) for v in values),
        axes=axes,
    )  # fmt: skip


def _robot(mujoco: Any, spec: Any, model: Any, path: Path, declared: dict[str, Inertial]) -> Robot:
    low, high = (int(v) for v in spec.compiler.inertiagrouprange)
    geoms = {geom.id: geom for geom in spec.geoms}
    names = [model.body(i).name or f"body {i}" for i in range(model.nbody)]
    links: dict[str, Link] = {}
    joints: dict[str, Joint] = {}
    for i, name in enumerate(names):
        shapes = []
        for g in range(model.body_geomadr[i], model.body_geomadr[i] + model.body_geomnum[i]):
            if i == 0 or not low <= model.geom_group[g] <= high:
                continue
            shape = _shape(model, g, geoms.get(g))
            if shape is not None:
                shapes.append(shape)
        inertial = declared.get(name)
        if inertial is None and i > 0:
            inertia = model.body_inertia[i]
            values = (inertia[0], 0.0, 0.0, inertia[1], 0.0, inertia[2])
            inertial = _inertial(
                model.body_mass[i], model.body_ipos[i], model.body_iquat[i], values
            )
        links[name] = Link(name, inertial, {"collision": tuple(shapes), "visual": tuple(shapes)})
        if i == 0:
            continue
        parent = names[model.body_parentid[i]]
        placement = (_matrix(model.body_quat[i]), np.array(model.body_pos[i], dtype=float))
        first = True
        for j in range(model.body_jntadr[i], model.body_jntadr[i] + model.body_jntnum[i]):
            joint_name = model.joint(j).name or f"{name} joint {j - model.body_jntadr[i]}"
            rotation, translation = placement if first else (np.eye(3), np.zeros(3))
            kind = _JOINT_KINDS[int(model.jnt_type[j])]
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
    total = float(spec.compiler.settotalmass)
    if total > 0:
        links = _scaled_to(total, links)
    return Robot(spec.modelname or path.stem, path, links, joints, names[0])


def _scaled_to(total: float, links: dict[str, Link]) -> dict[str, Link]:
    """The links with every geom's mass scaled so that they sum to ``total`` kg, as
    MuJoCo's compiler does for ``settotalmass`` (the declared values it computed
    are scaled already)."""
    solids = {id(s): at_own_mass(s) for link in links.values() for s in link.shapes["collision"]}
    masses = {key: 0.0 if solid is None else solid.mass for key, solid in solids.items()}
    factor = total / sum(masses.values())
    scaled = {}
    for name, link in links.items():
        shapes = tuple(
            replace(s, mass=masses[id(s)] * factor, density=None) for s in link.shapes["collision"]
        )
        scaled[name] = replace(link, shapes={"collision": shapes, "visual": shapes})
    return scaled


def _shape(model: Any, g: int, geom: Any) -> Shape | None:
    """Geom ``g`` as a :class:`Shape` in its body's frame, with its own mass or
    density (``geom``: its element of the spec); None for one without volume."""
    kind, size = int(model.geom_type[g]), [float(v) for v in model.geom_size[g]]
    rotation = _matrix(model.geom_quat[g])
    translation = np.array(model.geom_pos[g], dtype=float)
    mass = None if geom is None or not np.isfinite(geom.mass) else float(geom.mass)
    density = None if mass is not None else 1000.0 if geom is None else float(geom.density)

    def shape(name: str, dimensions: tuple[float, ...]) -> Shape:
        return Shape(name, dimensions, rotation, translation, mass=mass, density=density)

    if kind == _SPHERE:
        return shape("sphere", (size[0],))
    if kind in (_CAPSULE, _CYLINDER):  # MuJoCo gives the half-length
        return shape("capsule" if kind == _CAPSULE else "cylinder", (size[0], 2 * size[1]))
    if kind == _ELLIPSOID:
        return shape("ellipsoid", tuple(size))
    if kind == _BOX:  # MuJoCo gives the half-edges
        return shape("box", tuple(2 * v for v in size))
    if kind == _MESH:
        mesh = int(model.geom_dataid[g])
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        first, faces = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
        return Shape(
            "mesh", (), rotation, translation, mass=mass, density=density,
            vertices=np.array(model.mesh_vert[start : start + count], dtype=float),
            faces=np.array(model.mesh_face[first : first + faces], dtype=np.int64),
        )  # fmt: skip
    return None
