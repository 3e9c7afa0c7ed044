"""How a link's declared inertial values compare with its shapes'.

The shapes (collision or visual) are read as a solid of density 1, set to the
link's declared mass, and compared with the declared values: the density (a
mass no material of that volume has, with the unit of length that explains
it), the sum of the principal moments (with the unit of inertia that explains
it), each moment's share of the sum, the tensors themselves (their axes), and
the centre of mass. A massless link with shapes is given the robot's typical
density.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.massprops import MassProperties
from tumble.robots.findings import Finding, link_finding
from tumble.robots.model import INERTIA_ATTRIBUTES, Link, Robot
from tumble.robots.tensors import ENTRIES, principal_moments

__all__ = [
    "AXIS_DIFFERENCE",
    "CENTRE_MARGIN",
    "DENSITY_RANGE",
    "LENGTH_UNITS",
    "MOMENT_FACTOR",
    "SHARE_DIFFERENCE",
    "against_geometry",
    "inertial_correction",
    "shapes_at_mass",
    "typical_density",
    "unit_solid",
]

Array = NDArray[np.float64]

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

#: The largest difference between a principal moment's share of the sum, declared
#: and its shapes', before the two are said not to match. The shares (each
#: moment over the sum, between 0 and 1/2) tell the form of the mass: a rod's are
#: (0, 1/2, 1/2), a disc's (1/4, 1/4, 1/2), a ball's 1/3 each. Mass spread
#: differently within the same shapes moves them little (a solid cylinder and a
#: thin tube of the same size: 0.03), all of it gathered at a rod's middle at most
#: some 0.2; beyond, the declared tensor is another form than the shapes'.
SHARE_DIFFERENCE = 0.2

#: The largest spectral norm of the difference of the declared tensor and its
#: shapes', each over its trace, in link axes, before the two are said not to
#: match: the exact measure of both differences at once, moments and axes. Two
#: tensors alike but turned by θ against each other differ by γ sin θ, γ the
#: difference of the shares of the two moments the turn mixes (so a turn mixing
#: equal moments, whose axes are undefined, changes nothing); tensors of the same
#: axes differ by their largest difference of shares. Mass spread differently
#: within the same shapes moves it little: a solid cylinder and a thin tube of
#: the same size differ by at most 0.086 (at radius 0.34 times the length).
#: Twice that, 0.18, leaves out links whose mass sits unevenly in their shapes
#: (the wheels of pybullet_data's bicycle differ by 0.17) and keeps the turned
#: tensors of real files (pybullet_data and example-robot-data: the least turned
#: differs by 0.19). A rod (γ = 1/2) may stand 21° off its shape, a disc (γ =
#: 1/4) 46°.
AXIS_DIFFERENCE = 0.18

#: The units a shape's lengths may be written in, read as metres, and the factor
#: they multiply the density by (the cube of the unit in metres).
LENGTH_UNITS = (
    (1e-9, "millimetres"),
    (1e-6, "centimetres"),
    (0.0254**3, "inches"),
    (1e9, "kilometres (or scaled by 0.001 twice)"),
)

#: How far beyond the box around a link's shapes the declared centre of mass may
#: lie, as a fraction of the box's diagonal (the shapes are approximations).
CENTRE_MARGIN = 0.05


def unit_solid(
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
        except (InputError, ArithmeticError) as error:
            # Sizes whose volume or moments pass float64's range give no solid.
            code = (
                "missing-mesh"
                if shape.mesh is not None and not shape.mesh.is_file()
                else "geometry-unavailable"
            )
            findings.append(
                link_finding(link, code, f"Its {kind} {shape.label} gives no solid: {error}")
            )
            return None
    points = np.vstack(corners)
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            total = sum(solids[1:], start=solids[0])
    except (InputError, ArithmeticError) as error:
        findings.append(
            link_finding(link, "geometry-unavailable", f"Its {kind} shapes give no solid: {error}")
        )
        return None
    if not (np.isfinite(total.mass) and np.all(np.isfinite(total.inertia))):
        findings.append(
            link_finding(
                link,
                "geometry-unavailable",
                f"Its {kind} shapes give no solid: their volume or moments pass "
                f"float64's range (volume {total.mass:.4g} m³).",
            )
        )
        return None
    return total, (points.min(axis=0), points.max(axis=0))


def typical_density(robot: Robot, solids: dict[str, Any]) -> float:
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


def inertial_correction(link: Link, solid: MassProperties) -> dict[str, Any]:
    """The attributes that give ``solid`` in the link's inertial frame."""
    rotation = link.inertial.rotation if link.inertial is not None else np.eye(3)
    tensor = rotation.T @ solid.inertia @ rotation
    correction: dict[str, Any] = {"xyz": tuple(float(f"{v:.6g}") for v in solid.center_of_mass)}
    for name, (i, j) in zip(INERTIA_ATTRIBUTES, ENTRIES, strict=True):
        correction[name] = float(f"{tensor[i, j]:.6g}")
    return correction


def against_geometry(
    link: Link,
    solid: tuple[MassProperties, tuple[Array, Array]],
    density: float,
    findings: list[Finding],
) -> tuple[list[Finding], MassProperties | None]:
    unit, (low, high) = solid
    volume = unit.mass
    found: list[Finding] = []
    if link.mass == 0.0:
        mass = float(f"{density * volume:.6g}")
        at_mass = shapes_at_mass(unit, mass)
        if at_mass is None:
            return found, None
        correction = {"mass": mass, **inertial_correction(link, at_mass)}
        found.append(
            link_finding(
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
    at_mass = shapes_at_mass(unit, link.mass)
    if at_mass is None:
        found.append(
            link_finding(
                link,
                "geometry-unavailable",
                f"Its shapes at the declared mass {link.mass:.4g} kg pass float64's range: "
                "not compared.",
            )
        )
        return found, None
    with np.errstate(over="ignore", divide="ignore"):
        own = link.mass / volume
    if not DENSITY_RANGE[0] <= own <= DENSITY_RANGE[1]:
        found.append(_implausible_density(link, volume, own, density))
        return found, at_mass
    if any(f.link == link.name and f.severity == "error" for f in findings + found):
        return found, at_mass
    diagonal = float(np.linalg.norm(high - low))
    outside = np.any(link.center_of_mass < low - CENTRE_MARGIN * diagonal) or np.any(
        link.center_of_mass > high + CENTRE_MARGIN * diagonal
    )
    difference = _shape_difference(link, at_mass)
    if difference is not None:
        message, hint, factor = difference
        correction = inertial_correction(link, at_mass)
        if factor is not None:
            assert link.inertial is not None
            correction = {
                name: float(f"{value / factor:.10g}")
                for name, value in zip(INERTIA_ATTRIBUTES, link.inertial.values, strict=True)
                if value != 0.0
            }
        if not outside and "xyz" in correction and not hint:
            correction.pop("xyz")
        if outside:
            hint += " Its declared centre of mass lies outside its shapes too."
        found.append(link_finding(link, "geometry-mismatch", message + hint, correction))
    elif outside:
        found.append(
            link_finding(
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


def _implausible_density(link: Link, volume: float, own: float, typical: float) -> Finding:
    """The finding of a density no solid has, with the unit of length that
    explains it best: the one giving the density nearest the robot's typical
    one (decades apart, so the nearest in the logarithm)."""
    hint = ""
    fits = [
        (abs(math.log10(own / factor / typical)), factor, name)
        for factor, name in LENGTH_UNITS
        if own > 0 and link.shapes and DENSITY_RANGE[0] <= own / factor <= DENSITY_RANGE[1]
    ]
    if fits:
        _, factor, name = min(fits)
        hint = f" Shapes in {name} read as metres? Scaled, the density is {own / factor:.4g} kg/m³."
    return link_finding(
        link,
        "implausible-density",
        f"Mass {link.mass:.4g} kg in "
        f"{volume:.4g} m³ of shapes is {own:.4g} kg/m³, outside the "
        f"{DENSITY_RANGE[0]:g}–{DENSITY_RANGE[1]:g} kg/m³ of solids.{hint}",
    )


def _shape_difference(link: Link, at_mass: MassProperties) -> tuple[str, str, float | None] | None:
    """How the declared tensor differs from its shapes' at the declared mass (both
    about their centres of mass, link axes): the message, a hint of a unit, and
    the unit's factor (None for the shapes' tensor as correction); None where
    they match. In turn: the sum of the principal moments (its ratio, within
    :data:`MOMENT_FACTOR`), each moment's share of the sum (within
    :data:`SHARE_DIFFERENCE`), then the tensors themselves, axes and all (the
    spectral norm of their difference, each over its trace, within
    :data:`AXIS_DIFFERENCE`). Worked on each tensor over its sum: no overflow for
    entries up to float64's largest."""
    assert link.inertial is not None
    declared_moments = principal_moments(link.inertial.values)
    expected_moments = principal_moments(_flat(at_mass.inertia))
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        declared_scale = float(np.abs(declared_moments).max())
        expected_scale = float(np.abs(expected_moments).max())
        declared_sum = float(np.sum(declared_moments / declared_scale))
        expected_sum = float(np.sum(expected_moments / expected_scale))
        ratio = declared_sum / expected_sum * (declared_scale / expected_scale)
        declared = float(np.sum(declared_moments))
        expected = float(np.sum(expected_moments))
    if not np.isfinite(ratio) or not 1 / MOMENT_FACTOR <= ratio <= MOMENT_FACTOR:
        hint, unit = "", None
        for factor, what in (
            (1e6, "kg·mm² for kg·m²"),
            (1e4, "kg·cm² for kg·m²"),
            (1e3, "g·m² for kg·m²"),
        ):
            if 1 / MOMENT_FACTOR <= ratio / factor <= MOMENT_FACTOR:
                hint, unit = f" A factor of {factor:g}: {what}?", factor
                break
        return (
            f"The sum of the principal moments, {declared:.4g} kg·m², is {ratio:.3g} times "
            f"that of its shapes at the declared mass ({expected:.4g} kg·m²).",
            hint,
            unit,
        )
    rotation = link.inertial.rotation
    written = link.inertial.tensor / max(float(np.abs(link.inertial.tensor).max()), 1e-300)
    mine_tensor = _over_trace(rotation @ written @ rotation.T)
    theirs_tensor = _over_trace(at_mass.inertia)
    mine, my_axes = np.linalg.eigh(mine_tensor)
    theirs, their_axes = np.linalg.eigh(theirs_tensor)
    shares = np.abs(mine - theirs)
    if shares.max() > SHARE_DIFFERENCE:
        return (
            "The principal moments' shares of their sum, "
            f"{_vector(mine)}, differ from its shapes' ({_vector(theirs)}) by "
            f"{shares.max():.2f}: another form of body (a rod's are (0, 0.5, 0.5), a "
            "disc's (0.25, 0.25, 0.5)).",
            "",
            None,
        )
    difference = float(np.linalg.norm(mine_tensor - theirs_tensor, 2))
    if difference <= AXIS_DIFFERENCE:
        return None
    exceeds = (
        f"the tensor and its shapes', each over its trace, differ by {difference:.2f} "
        f"(spectral norm, link axes), more than {AXIS_DIFFERENCE:g}"
    )
    # The moment standing farthest from the other two in both tensors: the one
    # whose axis is best defined, where a turn shows. Its axis is named where it
    # stands apart by half the allowed difference (a turn of an axis standing γ
    # apart moves the tensor by up to γ).
    gaps = [
        min(abs(values[k] - values[j]) for values in (mine, theirs) for j in range(3) if j != k)
        for k in range(3)
    ]
    k = int(np.argmax(gaps))
    if gaps[k] <= AXIS_DIFFERENCE / 2:
        return f"The principal moments and axes differ: {exceeds}.", "", None
    angle = math.degrees(math.acos(min(1.0, abs(float(my_axes[:, k] @ their_axes[:, k])))))
    return (
        f"The principal axis of its {_ORDINAL[k]} moment ({_vector(my_axes[:, k])}, "
        f"link axes) lies {angle:.0f}° from its shapes' ({_vector(their_axes[:, k])}): "
        f"{exceeds}.",
        "",
        None,
    )


_ORDINAL = ("smallest", "middle", "largest")


def _over_trace(tensor: Array) -> Array:
    """A tensor over its trace (its principal moments become their shares of the
    sum); over its largest entry first, against overflow."""
    scale = float(np.abs(tensor).max())
    unit = tensor / scale if np.isfinite(scale) and scale > 0 else tensor
    return np.asarray(unit / np.trace(unit), dtype=float)


def _flat(tensor: Array) -> tuple[float, ...]:
    """A tensor's six URDF entries (ixx, ixy, ixz, iyy, iyz, izz)."""
    return tuple(float(tensor[i, j]) for i, j in ENTRIES)


def shapes_at_mass(unit: MassProperties, mass: float) -> MassProperties | None:
    """The shapes of density 1 (``unit``) at ``mass``; None where that passes
    float64's range."""
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        factor = mass / unit.mass
        inertia = unit.inertia * factor
    if not (np.isfinite(factor) and np.all(np.isfinite(inertia))):
        return None
    try:
        return MassProperties(mass, unit.center_of_mass, inertia)
    except InputError:
        return None


def _vector(values: Array) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in values) + ")"
