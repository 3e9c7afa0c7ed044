"""The audit of a robot description's declared inertias.

Each link's declared values are judged on their own (a tensor that no body has,
a negative mass) and against the link's geometry at its declared mass (a tensor
or centre of mass far from what the shapes give, a density no material has, a
massless link with shapes). Where one correction explains a finding, the
finding carries it, as the attributes of the file to change and their new
values.
The declared tensor alone is judged in :mod:`tumble.robots.tensors`, the
comparison with the shapes made in :mod:`tumble.robots.against_shapes`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from tumble.errors import unknown_choice
from tumble.massprops import MassProperties
from tumble.robots.against_shapes import (
    against_geometry,
    inertial_correction,
    shapes_at_mass,
    typical_density,
    unit_solid,
)
from tumble.robots.findings import CODES, Audit, Finding, LinkSummary, link_finding
from tumble.robots.model import INERTIA_ATTRIBUTES, Link, Robot
from tumble.robots.tensors import (
    accepted_change,
    judge_tensor,
    nearest_accepted,
    power_of_ten_candidates,
    principal_moments,
    refusals,
    swap_candidates,
)

__all__ = ["GEOMETRY_CHOICES", "audit_robot"]

Array = NDArray[np.float64]

#: The geometry an audit compares the declared values with.
GEOMETRY_CHOICES = ("collision", "visual", "none")

#: Tensors whose entries are all below this fraction of the robot's largest are
#: zeros written with the round-off of the computation that made them (1e-18
#: kg·m² beside links of 0.1 kg·m², with products of 2⁻⁶⁵): not judged as a
#: body's, but still one the engines refuse as written is a round-off warning.
ZERO_FRACTION = 1e-12


# ------------------------------------------------------------------ the audit
def audit_robot(robot: Robot, geometry: str = "collision") -> Audit:
    """Audit every link of ``robot`` (see :func:`tumble.robots.audit`)."""
    if geometry not in GEOMETRY_CHOICES:
        raise unknown_choice(geometry, GEOMETRY_CHOICES, "`geometry`")
    findings: list[Finding] = [
        Finding(notice.link, notice.code, CODES[notice.code], notice.message)
        for notice in robot.notices
    ]
    summaries = []
    solids: dict[str, tuple[MassProperties, tuple[Array, Array]] | None] = {}
    for link in robot.links.values():
        if geometry != "none" and link.shapes.get(geometry):
            solids[link.name] = unit_solid(link, geometry, findings)
    density = typical_density(robot, solids)
    floor = ZERO_FRACTION * max(
        (max(map(abs, link.inertial.values)) for link in robot.links.values() if link.inertial),
        default=0.0,
    )
    for link in robot.links.values():
        solid = solids.get(link.name)
        findings += _declared(link, None if solid is None else solid[0], floor)
        at_mass = None
        if solid is not None and not link.unreadable:  # values unknown: nothing to compare
            more, at_mass = against_geometry(link, solid, density, findings)
            findings += more
        summaries.append(
            LinkSummary(
                link.name,
                link.mass,
                principal_moments(link.inertial.values) if link.inertial else np.zeros(3),
                at_mass,
                None if solid is None else solid[0].mass,
            )
        )
    return Audit(robot, geometry, tuple(findings), tuple(summaries))


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
    at_mass = shapes_at_mass(solid, link.mass)
    if at_mass is None:
        return None, ""
    expected = inertial_correction(link, at_mass)
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
            link_finding(
                link,
                "negative-mass",
                f"Declared mass {link.mass:g} kg is negative: a sign slip?",
                {"mass": -link.mass},
            )
        )
    values, texts = link.inertial.values, link.inertial.texts
    moments = principal_moments(values)
    if max(map(abs, values)) < floor:
        # A zero written with round-off is no body to judge, but the engines
        # still load it as written: what they refuse must not pass unsaid.
        refused = refusals(values)
        if refused:
            found.append(_round_off(link, moments, refused, zero=True))
        return found
    verdict = judge_tensor(values, texts)
    if verdict is None:
        refused = refusals(values)
        if refused:
            found.append(_round_off(link, moments, refused))
        return found
    found.append(_unphysical(link, moments, *verdict))
    found += _corrections(link, values, texts, solid)
    if texts[1] == texts[3] and values[1] != 0.0:
        found.append(
            link_finding(
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


def _unphysical(link: Link, moments: Array, code: str, amount: float) -> Finding:
    """The finding of a declared tensor no body has (``code`` and ``amount`` of
    :func:`judge_tensor`), naming its principal moments (kg·m²)."""
    listed = ", ".join(f"{m:.6g}" for m in moments)
    if code == "not-positive-definite":
        return link_finding(
            link,
            code,
            f"Principal moments {listed} kg·m²: one is negative "
            f"({amount:.3g}), beyond the rounding of the written digits; no body "
            "has it.",
        )
    return link_finding(
        link,
        code,
        f"Principal moments {listed} kg·m² break I1 + I2 >= I3 "
        f"by {100 * amount:.3g} % of I3; no body has them.",
    )


def _corrections(
    link: Link, values: tuple[float, ...], texts: tuple[str, ...], solid: MassProperties | None
) -> list[Finding]:
    """The corrections that make an unphysical tensor physical: a decimal point moved
    (the one its shapes choose, or every one when they cannot tell), or the one
    exchange of two attributes."""
    powers = power_of_ten_candidates(values, texts)
    swaps = swap_candidates(values, texts)
    chosen, why = _one_power(link, powers, solid)
    if chosen is not None:
        ((name, value),) = chosen.items()
        return [
            link_finding(
                link,
                "power-of-ten",
                f"Writing {name} = {value:.10g} (for "
                f"{texts[INERTIA_ATTRIBUTES.index(name)]}) is {why}"
                f"{_still_refused(values, chosen)}.",
                accepted_change(values, chosen),
            )
        ]
    if powers:
        listed = ", ".join(f"{k} = {v:.6g}" for p in powers for k, v in p.items())
        which = "its shapes do not tell which" if solid is not None else "no geometry to tell which"
        return [
            link_finding(
                link,
                "power-of-ten",
                f"Moving a decimal point makes the tensor "
                f"physical in {len(powers)} ways ({listed}); {which}.",
                None,
            )
        ]
    if len(swaps) == 1:
        names = " and ".join(swaps[0])
        return [
            link_finding(
                link,
                "swapped-attributes",
                f"Exchanging {names} is the one "
                "exchange of two attributes that makes the tensor physical"
                f"{_still_refused(values, swaps[0])}.",
                accepted_change(values, swaps[0]),
            )
        ]
    return []


def _still_refused(values: tuple[float, ...], change: dict[str, float]) -> str:
    """What a message adds where ``change`` gives a tensor physical only within
    the rounding of its digits, which the engines refuse as written."""
    if accepted_change(values, change) is change:
        return ""
    return (
        "; the engines refuse that as written (physical only within its digits' "
        "rounding): the correction is the nearest tensor they all accept"
    )


def _round_off(link: Link, moments: Array, refused: tuple[str, ...], zero: bool = False) -> Finding:
    """The finding of a tensor physical within the rounding of its written
    digits (``zero``: one so small beside the robot's other links that it is a
    zero written with round-off) that the engines ``refused`` refuse as written."""
    assert link.inertial is not None
    listed = ", ".join(f"{m:.6g}" for m in moments)
    names = {"MuJoCo": "MuJoCo", "Drake": "Drake", "tumble": "tumble's MassProperties"}
    who = ", ".join(names[r] for r in refused)
    with np.errstate(over="ignore", invalid="ignore"):
        margin = moments[0] + moments[1] - moments[2]
    if moments[0] < 0:
        what = f"one is negative ({moments[0]:.3g}): refused by {who}"
    elif margin < 0:
        what = f"I1 + I2 falls short of I3 by {-margin:.3g}: refused by {who}"
    else:  # the boundary I1 + I2 = I3 (or a zero moment) to the last bits
        what = (
            f"I1 + I2 - I3 = {margin:.3g}, within the round-off of MuJoCo's "
            "eigen-solver of the boundary I1 + I2 = I3: it may refuse it"
        )
    reading = (
        f"A zero written with round-off (all entries below {ZERO_FRACTION:g} of the "
        "robot's largest), not judged as a body's"
        if zero
        else "Within the rounding of the written digits (a body's tensor rounded)"
    )
    correction = nearest_accepted(link.inertial.values)
    fix = (
        "the correction is the nearest tensor every engine accepts"
        if correction is not None
        else "no nearby tensor every engine accepts was found"
    )
    return link_finding(
        link,
        "round-off",
        f"Principal moments {listed} kg·m² as written: {what}. {reading}: {fix}.",
        correction,
    )
