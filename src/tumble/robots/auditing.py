"""The audit of a robot description's declared inertias.

Each link's declared values are judged on their own (a tensor that no body has,
a negative mass) and against the link's geometry at its declared mass (a tensor
or centre of mass far from what the shapes give, a density no material has, a
massless link with shapes). Where one correction explains a finding, the
finding carries it, as the attributes of the file to change and their new
values.
The declared tensor alone is judged in :mod:`tumble.robots.tensors`.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, unknown_choice
from tumble.massprops import MassProperties
from tumble.robots.findings import CODES, Audit, Finding, LinkSummary
from tumble.robots.model import INERTIA_ATTRIBUTES, Link, Robot
from tumble.robots.tensors import (
    judge_tensor,
    power_of_ten_candidates,
    swap_candidates,
    tensor_of,
)

__all__ = ["GEOMETRY_CHOICES", "audit_robot"]

Array = NDArray[np.float64]

#: The geometry an audit compares the declared values with.
GEOMETRY_CHOICES = ("collision", "visual", "none")

#: Densities of solid materials, kg/m³: from foams and light plastics (some 10)
#: to the densest metals (osmium, 22 600). A link's mass over its shapes'
#: volume outside this range is not a solid of that shape: most often a mesh in
#: millimetres read as metres (a density 10⁹ times too small).
DENSITY_RANGE = (10.0, 25_000.0)

#: The factor by which the sum of the principal moments (twice the mass times
#: the mean squared distance from the centre of mass) may differ from the
#: geometry's before the two are said not to match. A link is rarely a uniform
#: solid (motors, hollow shells), but mass spread differently within the same
#: shapes moves this sum by less than 2: a solid cylinder and a thin tube of the
#: same size and mass differ by a factor of 2 in their axial moment and less in
#: the sum. Beyond it, the tensor belongs to another body (or another unit).
MOMENT_FACTOR = 2.0

#: How far beyond the box around a link's shapes the declared centre of mass may
#: lie, as a fraction of the box's diagonal (the shapes are approximations).
CENTRE_MARGIN = 0.05

#: Tensors whose entries are all below this fraction of the robot's largest are
#: zeros written with the round-off of the computation that made them (1e-18
#: kg·m² beside links of 0.1 kg·m², with products of 2⁻⁶⁵): not judged.
ZERO_FRACTION = 1e-12

#: The (row, column) of each of URDF's six attributes in the tensor.
_ENTRIES = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


# ------------------------------------------------------------------ the audit
def audit_robot(robot: Robot, geometry: str = "collision") -> Audit:
    """Audit every link of ``robot`` (see :func:`tumble.robots.audit`)."""
    if geometry not in GEOMETRY_CHOICES:
        raise unknown_choice(geometry, GEOMETRY_CHOICES, "`geometry`")
    findings: list[Finding] = []
    summaries = []
    solids: dict[str, tuple[MassProperties, tuple[Array, Array]] | None] = {}
    for link in robot.links.values():
        if geometry != "none" and link.shapes.get(geometry):
            solids[link.name] = _unit_solid(link, geometry, findings)
    density = _typical_density(robot, solids)
    floor = ZERO_FRACTION * max(
        (max(map(abs, link.inertial.values)) for link in robot.links.values() if link.inertial),
        default=0.0,
    )
    for link in robot.links.values():
        solid = solids.get(link.name)
        findings += _declared(link, None if solid is None else solid[0], floor)
        at_mass = None
        if solid is not None:
            more, at_mass = _against_geometry(link, solid, density, findings)
            findings += more
        summaries.append(
            LinkSummary(
                link.name,
                link.mass,
                np.asarray(np.linalg.eigvalsh(link.inertia), dtype=float),
                at_mass,
                None if solid is None else solid[0].mass,
            )
        )
    return Audit(robot, geometry, tuple(findings), tuple(summaries))


def _finding(
    link: Link, code: str, message: str, correction: dict[str, Any] | None = None
) -> Finding:
    return Finding(link.name, code, CODES[code], message, correction)


def _one_power(
    link: Link, powers: list[dict[str, float]], solid: MassProperties | None
) -> tuple[dict[str, float] | None, str]:
    """The power-of-ten correction and why it is the one: the only candidate, or
    the only one within a factor √10 of the link's geometry (at the declared
    mass, in the inertial frame) in the attribute it changes: two powers of
    ten cannot both be within half a decade of one value."""
    if len(powers) == 1:
        return powers[
            0
        ], "the one move of a decimal point in one attribute that makes the tensor physical"
    if not powers or solid is None or not link.mass > 0 or link.inertial is None:
        return None, ""
    expected = _inertial_correction(link, _at_mass(solid, link.mass))
    size = sum(abs(expected[name]) for name in ("ixx", "iyy", "izz"))
    near = []
    for candidate in powers:
        ((name, value),) = candidate.items()
        reference = expected[name]
        comparable = abs(reference) > 1e-3 * size and value * reference > 0
        if comparable and abs(math.log10(value / reference)) < 0.5:
            near.append(candidate)
    if len(near) == 1:
        ((name, _),) = near[0].items()
        return near[0], (
            f"the one of {len(powers)} moves of a decimal point making the tensor "
            f"physical that is within a factor √10 of its shapes' {name} "
            f"({expected[name]:.4g})"
        )
    return None, ""


def _declared(link: Link, solid: MassProperties | None, floor: float) -> list[Finding]:
    """The findings of a link's declared values alone (``solid``: its shapes at
    density 1, to choose among corrections, or None; a tensor whose entries are
    all below ``floor`` is a zero)."""
    if link.inertial is None:
        return []
    found = []
    if link.mass < 0:
        found.append(
            _finding(
                link,
                "negative-mass",
                f"Declared mass {link.mass:g} kg is negative: a sign slip?",
                {"mass": -link.mass},
            )
        )
    values, texts = link.inertial.values, link.inertial.texts
    if max(map(abs, values)) < floor:
        return found
    verdict = judge_tensor(values, texts)
    if verdict is None:
        return found
    moments = np.linalg.eigvalsh(tensor_of(values))
    listed = ", ".join(f"{m:.6g}" for m in moments)
    code, amount = verdict
    if code == "not-positive-definite":
        found.append(
            _finding(
                link,
                code,
                f"Principal moments {listed} kg·m²: one is negative "
                f"({amount:.3g}), beyond the rounding of the written digits; no body "
                "has it.",
            )
        )
    else:
        found.append(
            _finding(
                link,
                code,
                f"Principal moments {listed} kg·m² break I1 + I2 >= I3 "
                f"by {100 * amount:.3g} % of I3; no body has them.",
            )
        )
    powers = power_of_ten_candidates(values, texts)
    swaps = swap_candidates(values, texts)
    chosen, why = _one_power(link, powers, solid)
    if chosen is not None:
        ((name, value),) = chosen.items()
        found.append(
            _finding(
                link,
                "power-of-ten",
                f"Writing {name} = {value:.10g} (for "
                f"{texts[INERTIA_ATTRIBUTES.index(name)]}) is {why}.",
                chosen,
            )
        )
    elif powers:
        listed = ", ".join(f"{k} = {v:.6g}" for p in powers for k, v in p.items())
        which = "its shapes do not tell which" if solid is not None else "no geometry to tell which"
        found.append(
            _finding(
                link,
                "power-of-ten",
                f"Moving a decimal point makes the tensor "
                f"physical in {len(powers)} ways ({listed}); {which}.",
                None,
            )
        )
    elif len(swaps) == 1:
        names = " and ".join(swaps[0])
        found.append(
            _finding(
                link,
                "swapped-attributes",
                f"Exchanging {names} is the one "
                "exchange of two attributes that makes the tensor physical.",
                swaps[0],
            )
        )
    if texts[1] == texts[3] and values[1] != 0.0:
        found.append(
            _finding(
                link,
                "row-major",
                f"ixy and iyy are both {texts[1]}: the first "
                "six entries of the 3 × 3 matrix written row by row (ixx ixy ixz "
                "iyx iyy iyz) into URDF's ixx ixy ixz iyy iyz izz? Then iyy is "
                f"{texts[4]}, iyz {texts[5]}, and izz is missing.",
                None,
            )
        )
    return found


def _unit_solid(
    link: Link, kind: str, findings: list[Finding]
) -> tuple[MassProperties, tuple[Array, Array]] | None:
    """The link's shapes as a solid of density 1 and the box around them; None
    (and a finding) where a shape cannot be read."""
    from tumble.mesh import MeshRepairWarning

    solids, corners = [], []
    for shape in link.shapes[kind]:
        try:
            with warnings.catch_warnings():
                # Seams welded by round-off: the solid is the mesh's; nothing to report.
                warnings.simplefilter("ignore", MeshRepairWarning)
                solids.append(shape.unit_density())
                corners.append(shape.corners())
        except InputError as error:
            code = (
                "missing-mesh"
                if shape.mesh is not None and not shape.mesh.is_file()
                else "geometry-unavailable"
            )
            findings.append(
                _finding(link, code, f"Its {kind} {shape.label} gives no solid: {error}")
            )
            return None
    points = np.vstack(corners)
    return sum(solids[1:], start=solids[0]), (points.min(axis=0), points.max(axis=0))


def _typical_density(robot: Robot, solids: dict[str, Any]) -> float:
    """The robot's declared mass over its shapes' volume, among links with both
    (kg/m³); that of water where there are none."""
    mass = volume = 0.0
    for name, solid in solids.items():
        link = robot.links[name]
        if solid is not None and link.mass > 0:
            density = link.mass / solid[0].mass
            if DENSITY_RANGE[0] <= density <= DENSITY_RANGE[1]:
                mass += link.mass
                volume += solid[0].mass
    return mass / volume if volume > 0 else 1000.0


def _inertial_correction(link: Link, solid: MassProperties) -> dict[str, Any]:
    """The attributes that give ``solid`` in the link's inertial frame."""
    rotation = link.inertial.rotation if link.inertial is not None else np.eye(3)
    tensor = rotation.T @ solid.inertia @ rotation
    correction: dict[str, Any] = {"xyz": tuple(float(f"{v:.6g}") for v in solid.center_of_mass)}
    for name, (i, j) in zip(INERTIA_ATTRIBUTES, _ENTRIES, strict=True):
        correction[name] = float(f"{tensor[i, j]:.6g}")
    return correction


def _against_geometry(
    link: Link,
    solid: tuple[MassProperties, tuple[Array, Array]],
    density: float,
    findings: list[Finding],
) -> tuple[list[Finding], MassProperties | None]:
    unit, (low, high) = solid
    volume = unit.mass
    found = []
    if link.mass == 0.0:
        mass = float(f"{density * volume:.6g}")
        correction = {"mass": mass, **_inertial_correction(link, _at_mass(unit, mass))}
        found.append(
            _finding(
                link,
                "massless-with-geometry",
                f"Mass 0 with {volume:.4g} m³ of "
                f"shapes: at the robot's density ({density:.4g} kg/m³) it would be "
                f"{mass:.4g} kg. A massless link with shapes is an error in most "
                "engines (or a fixed base in PyBullet's).",
                correction,
            )
        )
        return found, None
    if link.mass < 0:
        return found, None
    at_mass = _at_mass(unit, link.mass)
    own = link.mass / volume
    if not DENSITY_RANGE[0] <= own <= DENSITY_RANGE[1]:
        hint = ""
        for factor, unit_name in (
            (1e-9, "millimetres"),
            (1e-6, "tenths of a millimetre"),
            (1e9, "kilometres"),
        ):
            if DENSITY_RANGE[0] <= own / factor <= DENSITY_RANGE[1] and link.shapes:
                hint = (
                    f" Shapes in {unit_name} read as metres? Scaled, the density is "
                    f"{own / factor:.4g} kg/m³."
                )
                break
        found.append(
            _finding(
                link,
                "implausible-density",
                f"Mass {link.mass:.4g} kg in "
                f"{volume:.4g} m³ of shapes is {own:.4g} kg/m³, outside the "
                f"{DENSITY_RANGE[0]:g}–{DENSITY_RANGE[1]:g} kg/m³ of solids.{hint}",
            )
        )
        return found, at_mass
    if any(f.link == link.name and f.severity == "error" for f in findings + found):
        return found, at_mass
    declared = np.trace(link.inertia)
    expected = np.trace(at_mass.inertia)
    ratio = declared / expected
    diagonal = float(np.linalg.norm(high - low))
    outside = np.any(link.center_of_mass < low - CENTRE_MARGIN * diagonal) or np.any(
        link.center_of_mass > high + CENTRE_MARGIN * diagonal
    )
    if not 1 / MOMENT_FACTOR <= ratio <= MOMENT_FACTOR:
        correction = _inertial_correction(link, at_mass)
        hint = ""
        for factor, what in (
            (1e6, "kg·mm² for kg·m²"),
            (1e4, "kg·cm² for kg·m²"),
            (1e3, "g·m² for kg·m²"),
        ):
            if 1 / MOMENT_FACTOR <= ratio / factor <= MOMENT_FACTOR:
                hint = f" A factor of {factor:g}: {what}?"
                assert link.inertial is not None
                correction = {
                    name: float(f"{value / factor:.10g}")
                    for name, value in zip(INERTIA_ATTRIBUTES, link.inertial.values, strict=True)
                    if value != 0.0
                }
                break
        if not outside and "xyz" in correction and not hint:
            correction.pop("xyz")
        found.append(
            _finding(
                link,
                "geometry-mismatch",
                f"The sum of the principal moments, "
                f"{declared:.4g} kg·m², is {ratio:.3g} times that of its shapes at "
                f"the declared mass ({expected:.4g} kg·m²).{hint}",
                correction,
            )
        )
    elif outside:
        found.append(
            _finding(
                link,
                "geometry-mismatch",
                "The declared centre of mass "
                f"{_vector(link.center_of_mass)} m lies outside its shapes "
                f"({_vector(low)} to {_vector(high)} m); theirs is at "
                f"{_vector(at_mass.center_of_mass)} m.",
                {"xyz": tuple(float(f"{v:.6g}") for v in at_mass.center_of_mass)},
            )
        )
    return found, at_mass


def _at_mass(unit: MassProperties, mass: float) -> MassProperties:
    factor = mass / unit.mass
    return MassProperties(mass, unit.center_of_mass, unit.inertia * factor)


def _vector(values: Array) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in values) + ")"
