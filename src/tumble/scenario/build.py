"""From a validated scenario to the library's objects: the body's mass properties,
a triangle mesh to draw it, the initial state and the torque model.

Errors raised by the library while building (a mesh with holes, a part whose
inertia breaks the triangle inequality) are re-raised as
:class:`~tumble.scenario.ScenarioError` naming the key path of the part.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.config import dotted
from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted
from tumble.massprops import MassProperties
from tumble.scenario.bodies import (
    Attitude,
    InertiaBody,
    MeshBody,
    PartsBody,
    PointsBody,
    ShapeBody,
)
from tumble.scenario.loaded import BUILTINS, ScenarioError, where
from tumble.scenario.schema import Scenario

if TYPE_CHECKING:
    from tumble.scenario.loaded import LoadedScenario

__all__ = [
    "InitialState",
    "at_key",
    "initial_state",
    "internal_parts",
    "mass_properties",
    "mesh_path",
    "rotation",
    "torque_model",
]

Array = NDArray[np.float64]


@contextmanager
def at_key(loaded: LoadedScenario | None, *path: str | int) -> Iterator[None]:
    """Re-raise the library's InputError as a ScenarioError naming the key ``path``
    (and its line in the scenario's text)."""
    try:
        yield
    except ScenarioError:
        raise
    except InputError as exc:
        place = where(loaded, path) if loaded is not None else f"`{dotted(path)}`"
        raise ScenarioError(f"{place}: {exc}") from None


def rotation(attitude: Attitude | None) -> Any:
    from scipy.spatial.transform import Rotation

    if attitude is None:
        return Rotation.identity()
    return Rotation.from_quat(attitude.quaternion_wxyz(), scalar_first=True)


def mesh_path(body: MeshBody, folder: Path) -> Path:
    """The mesh file: relative to the scenario's folder, else one shipped with tumble."""
    path = Path(body.mesh)
    if not path.is_absolute():
        for base in (folder, BUILTINS.folder()):
            if (base / path).is_file():
                return base / path
        raise InputError(
            f"Expected a mesh file, got {quoted(body.mesh, QUOTED_PATH_LENGTH)} "
            f"(not found in {quoted(folder, QUOTED_PATH_LENGTH)})."
        )
    if not path.is_file():
        raise InputError(
            f"Expected a mesh file, got {quoted(body.mesh, QUOTED_PATH_LENGTH)} (no such file)."
        )
    return path


def mass_properties(
    spec: Any,
    folder: Path,
    loaded: LoadedScenario | None = None,
    path: tuple[str | int, ...] = ("body",),
) -> MassProperties:
    """The mass properties of a body of the schema (parts added in the same coordinates)."""
    from tumble.massprops import point_masses

    with at_key(loaded, *path):
        if isinstance(spec, PartsBody):
            parts = [
                mass_properties(part, folder, loaded, (*path, "parts", k))
                for k, part in enumerate(spec.parts)
            ]
            result: MassProperties = sum(parts[1:], parts[0])
        elif isinstance(spec, ShapeBody):
            result = spec.solid()
        elif isinstance(spec, MeshBody):
            from tumble.mesh import from_mesh  # numba kernels: load only for meshes

            result = from_mesh(
                mesh_path(spec, folder),
                density=spec.density,
                mass=spec.mass,
                units=spec.units,
                merge_tolerance=spec.merge_tolerance,
                shell_thickness=spec.shell_thickness,
            )
        elif isinstance(spec, PointsBody):
            result = point_masses(list(spec.masses), [list(p) for p in spec.positions])
        elif isinstance(spec, InertiaBody):
            result = MassProperties(spec.mass, spec.center_of_mass, spec.inertia)
        else:  # pragma: no cover - the schema admits no other body
            raise InputError(f"Expected a body, got {type(spec).__name__}.")
        if spec.rotation is not None or spec.translation is not None:
            result = result.transformed(rotation(spec.rotation), spec.translation)
        return result


# ------------------------------------------------------------------ state, torques
@dataclass(frozen=True)
class InitialState:
    """ω0 in body axes (rad/s) and the attitude quaternion ``[w, x, y, z]``, body → space."""

    omega: Array
    attitude: Array


def initial_state(scenario: Scenario) -> InitialState:
    """The initial ω (body axes) and attitude of a scenario."""
    from scipy.spatial.transform import Rotation

    attitude = scenario.initial.attitude
    q = np.array(attitude.quaternion_wxyz() if attitude is not None else (1.0, 0.0, 0.0, 0.0))
    omega = np.asarray(scenario.initial.omega, dtype=float)
    if scenario.initial.omega_frame == "space":
        omega = Rotation.from_quat(q, scalar_first=True).inv().apply(omega)
    return InitialState(omega, q)


def torque_model(scenario: Scenario, loaded: LoadedScenario | None = None) -> Any:
    """The sum of the scenario's ``[[torques]]`` (models of the registry,
    :data:`tumble.torques.TORQUES`), or None."""
    from tumble.torques import TORQUES

    terms = []
    for k, torque in enumerate(scenario.torques):
        with at_key(loaded, "torques", k):
            terms.append(TORQUES[torque.type](**torque.values))
    return sum(terms[1:], terms[0]) if terms else None


def file_parts(scenario: Scenario, loaded: LoadedScenario | None = None) -> list[Any]:
    """The scenario's ``[[internal]]`` parts as read (:class:`tumble.parts.FilePart`:
    the part, the solid tumble adds, where it is drawn)."""
    from tumble.parts import TableKeyError

    read = []
    for k, spec in enumerate(scenario.internal):
        try:
            read.append(spec.file_part())
        except InputError as exc:
            path = ("internal", k, exc.key) if isinstance(exc, TableKeyError) else ("internal", k)
            with at_key(loaded, *path):
                raise InputError(str(exc)) from None
    return read


def internal_parts(
    scenario: Scenario, loaded: LoadedScenario | None = None
) -> tuple[tuple[Any, ...], MassProperties | None]:
    """The scenario's ``[[internal]]`` parts (:mod:`tumble.parts`) and the sum of the
    uniform solids tumble adds to the body for those given by mass and radius
    (None when there are none)."""
    read = file_parts(scenario, loaded)
    solids = [entry.solid for entry in read if entry.solid is not None]
    added = sum(solids[1:], solids[0]) if solids else None
    return tuple(entry.part for entry in read), added
