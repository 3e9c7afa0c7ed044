"""The registry of theory checks, and what a check takes and gives.

A theory check is one closed form of :mod:`tumble.theory` that a simulation can
be compared with: it says which cases it fits (:meth:`TheoryCheck.fits`: a
:class:`Case` is the body, its initial state, supports, torques and parts),
which quantities it compares (the closed form next to the same quantity
measured on the trajectory by :mod:`tumble.analysis`) and which curves show
the comparison (:class:`Panel`). :data:`THEORY_CHECKS` holds them in the order
``auto`` tries them; scenario files name them in ``[theory] model``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, unknown_choice

if TYPE_CHECKING:
    from tumble.massprops import MassProperties
    from tumble.torques import TorqueModel
    from tumble.trajectory import Trajectory

__all__ = [
    "THEORY_CHECKS",
    "Case",
    "Comparison",
    "Curve",
    "Panel",
    "TheoryCheck",
    "choose_check",
    "compare",
    "comparison_row",
    "comparison_table",
    "register_check",
    "steady_state",
]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Curve:
    """One line of a panel: ``t`` (s), ``values`` and a legend ``label``;
    ``style`` is "simulation" (solid), "theory" (dashed) or "fit"."""

    label: str
    t: Array
    values: Array
    style: str = "simulation"


@dataclass(frozen=True)
class Panel:
    """A plot of a comparison: a title, the y label with its unit, and curves;
    ``name`` names its figure file, ``until`` limits it to t <= until (a few
    periods of a fast oscillation), ``log`` draws the y axis logarithmic (an
    exponential growth or decay); ``xlabel`` says what the curves' ``t`` are
    when they are not times (a spin speed, a coordinate of an orbit), and
    ``equal_aspect`` draws both axes to one scale (an orbit)."""

    title: str
    ylabel: str
    curves: list[Curve]
    name: str = "angles"
    until: float | None = None
    log: bool = False
    xlabel: str = "t (s)"
    equal_aspect: bool = False


@dataclass(frozen=True, eq=False)
class Case:
    """What a check needs to know of a simulation: the body, its initial state, its
    pivot and gravity, its torques and parts (not how it is integrated).

    Attributes
    ----------
    mass_properties : the body.
    omega0 : (3,) initial angular velocity, body axes, rad/s.
    attitude0 : (4,) initial attitude ``[w, x, y, z]``, body → space.
    pivot : None, or the fixed body point, m; ``gravity``: None or (3,) m/s², space axes.
    torque : the torque models besides gravity, or None.
    options : what a check takes besides (``bearings`` of a rotor, the
        gyrocompass's ``spin_rate`` and ``platform_rate``).
    internal : the parts the body carries (:mod:`tumble.parts`), locked in
        ``mass_properties``.
    """

    mass_properties: MassProperties
    omega0: Array
    attitude0: Array
    pivot: Any = None
    gravity: Any = None
    torque: TorqueModel | None = None
    options: Mapping[str, Any] = field(default_factory=dict)
    internal: tuple[Any, ...] = ()

    @property
    def rigid(self) -> bool:
        """No internal parts: the closed forms of a rigid body apply."""
        return not self.internal

    def parts_for(self, check: str) -> tuple[Any, ...]:
        """The internal parts whose kind declares that the closed form of the theory
        check named ``check`` holds with it (:attr:`tumble.parts.InternalPart.closed_forms`)."""
        return tuple(part for part in self.internal if check in part.closed_forms)

    def torques_for(self, check: str) -> tuple[TorqueModel, ...]:
        """The torque models (besides gravity) whose kind declares that the closed form
        of the theory check named ``check`` holds under it
        (:attr:`tumble.torques.TorqueModel.closed_forms`)."""
        return tuple(term for term in self.torques if check in term.closed_forms)

    @property
    def heavy(self) -> bool:
        """A pivot under gravity: a top."""
        return self.pivot is not None and self.gravity is not None and bool(np.any(self.gravity))

    @property
    def torques(self) -> tuple[TorqueModel, ...]:
        """The torque models besides gravity."""
        return () if self.torque is None else self.torque.terms

    @property
    def free(self) -> bool:
        """No torque at all."""
        return not self.torques and not self.heavy


@dataclass(frozen=True)
class Comparison:
    """The rows theory vs simulation (:func:`comparison_row`) and the panels to draw;
    ``runs``: trajectories the check simulated itself to compare with, by label
    (e.g. the same body without its rotor), written beside the main one;
    ``notes``: sentences for the report, such as why nothing was compared."""

    rows: list[dict[str, Any]]
    panels: list[Panel]
    runs: Mapping[str, Trajectory] = field(default_factory=dict)
    notes: tuple[str, ...] = ()


class TheoryCheck:
    """A closed form a simulation can be compared with (see the module's docstring)."""

    #: Its name in ``[theory] model``.
    name: ClassVar[str] = ""
    #: The case it needs, for messages.
    needs: ClassVar[str] = ""
    #: The type of the :mod:`tumble.theory` result :func:`compare` hands to
    #: :meth:`rows`; () when :meth:`rows` needs more than ``axis`` and ``vertical``.
    result_type: ClassVar[Any] = ()

    def fits(self, case: Case) -> bool:
        """True when the closed form describes this case."""
        raise NotImplementedError

    def compare(self, case: Case, trajectory: Trajectory) -> Comparison:
        """The comparison of a trajectory of this case with the closed form."""
        raise NotImplementedError

    def compare_runs(
        self, case: Case, trajectories: Mapping[str, Trajectory], results: Mapping[str, Any]
    ) -> Comparison:
        """The comparison of a model's runs (:class:`tumble.scenario.ModelRuns`): its
        trajectories by label, ``"main"`` first, and the model's own results by the
        same labels. By default the main trajectory's, by :meth:`compare`; a check
        that reads more of a model's runs says so."""
        comparison = self.compare(case, trajectories["main"])
        for row in comparison.rows:
            row.setdefault("run", "main")
        return comparison

    def rows(self, trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
        """The rows for a result of :mod:`tumble.theory` (see :func:`compare`)."""
        raise NotImplementedError


#: Every registered check by name, in the order ``auto`` tries them.
THEORY_CHECKS: dict[str, TheoryCheck] = {}


def register_check(check: TheoryCheck) -> TheoryCheck:
    """Add a check to :data:`THEORY_CHECKS` (replacing one of the same name)."""
    THEORY_CHECKS[check.name] = check
    return check


def choose_check(name: str, case: Case) -> TheoryCheck | None:
    """The check named ``name`` ("none": None; "auto": the first that fits, or None).

    Raises
    ------
    InputError
        An unknown name, or a check that does not fit the case.
    """
    if name == "none":
        return None
    if name == "auto":
        return next((check for check in THEORY_CHECKS.values() if check.fits(case)), None)
    check = THEORY_CHECKS.get(name)
    if check is None:
        raise unknown_choice(name, ["auto", "none", *THEORY_CHECKS], "`model`")
    if not check.fits(case):
        raise InputError(
            f"Expected {check.needs} for {name!r}, got another setup "
            '(use model = "auto" or "none").'
        )
    return check


def compare(trajectory: Trajectory, result: Any, **options: Any) -> list[dict[str, Any]]:
    """Closed-form results next to the same quantities measured on a trajectory.

    Each row is ``{"quantity", "theory", "measured", "relative_error", "unit"}``
    (:func:`comparison_row`). What is compared depends on the type of
    ``result`` (a :class:`~tumble.theory.Gyroscope`,
    :class:`~tumble.theory.FreeSymmetricTop`, :class:`~tumble.theory.Gyrocompass`,
    :class:`~tumble.theory.GyrostatStability`,
    :class:`~tumble.theory.KaneDamperDecay` or a flip period from
    :func:`~tumble.theory.flip_period`): the check of
    that type says (see :meth:`TheoryCheck.rows` of each check). ``options``
    are ``axis`` (a body axis) and ``vertical`` (a space direction).

    Raises
    ------
    InputError
        An unsupported ``result``, an option other than ``axis`` and
        ``vertical``, or any error of the measurements it needs.
    """
    from tumble.trajectory import Trajectory

    unknown = sorted(set(options) - {"axis", "vertical"})
    if unknown:
        raise InputError(f"Expected options `axis` or `vertical`, got {', '.join(unknown)}.")
    if not isinstance(trajectory, Trajectory):
        raise InputError(
            f"Expected `trajectory` to be a Trajectory, got {type(trajectory).__name__}."
        )
    for check in THEORY_CHECKS.values():
        if check.result_type and isinstance(result, check.result_type):
            if isinstance(result, bool):
                break
            return check.rows(trajectory, result, **options)
    accepted = [
        kind.__name__
        for check in THEORY_CHECKS.values()
        for kind in (
            check.result_type if isinstance(check.result_type, tuple) else (check.result_type,)
        )
        if kind.__module__.startswith("tumble.")
    ]
    raise InputError(
        f"Expected `result` to be one of {', '.join(accepted)} from tumble.theory, or a flip "
        f"period (float), got {type(result).__name__}."
    )


def comparison_row(quantity: str, theory: float, measured: float, unit: str) -> dict[str, Any]:
    """One row of a theory-vs-measurement table: ``{quantity, theory, measured,
    relative_error, unit}``, the error ``|measured − theory| / |theory|`` (inf
    when theory is 0 or not finite and they differ)."""
    if theory != 0 and math.isfinite(theory):
        error = abs(measured - theory) / abs(theory)
    else:
        error = math.inf if measured != theory else 0.0
    return {
        "quantity": quantity,
        "theory": float(theory),
        "measured": float(measured),
        "relative_error": error,
        "unit": unit,
    }


def comparison_table(rows: list[dict[str, Any]]) -> str:
    """The rows of :func:`compare` as a plain-text table (one line per row, aligned)."""
    header = ("quantity", "theory", "measured", "relative error", "unit")
    lines = [header]
    for row in rows:
        lines.append(
            (
                str(row["quantity"]),
                f"{row['theory']:.9g}",
                f"{row['measured']:.9g}",
                f"{row['relative_error']:.2e}",
                str(row["unit"]),
            )
        )
    widths = [max(len(line[k]) for line in lines) for k in range(len(header))]
    text = []
    for n, line in enumerate(lines):
        cells = [line[0].ljust(widths[0])]
        cells += [cell.rjust(width) for cell, width in zip(line[1:4], widths[1:4], strict=True)]
        cells.append(line[4].ljust(widths[4]))
        text.append("  ".join(cells).rstrip())
        if n == 0:
            text.append("  ".join("-" * width for width in widths))
    return "\n".join(text) + "\n"


def axis_angles(trajectory: Trajectory, axis: Array, vertical: Array) -> tuple[Array, Array]:
    """Tilt (rad) of a body axis from a space direction, and its azimuth about it
    (unwrapped, from 0), for the panels."""
    directions = trajectory.rotation.apply(np.array(axis, dtype=float))
    tilt = np.arccos(np.clip(directions @ vertical, -1.0, 1.0))
    helper = np.array([1.0, 0.0, 0.0]) if abs(vertical[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(vertical, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(vertical, e1)
    azimuth = np.unwrap(np.arctan2(directions @ e2, directions @ e1))
    return tilt, azimuth - azimuth[0]


#: ω counts as along a principal axis (a steady spin) when the part of I ω across
#: ω is below this fraction of |I ω|: round-off of the principal decomposition.
STEADY_TOLERANCE = 1e-12


def steady_state(case: Case) -> str | None:
    """Why a free rigid body's motion is steady, as a note for the report: at
    rest, or spinning about a principal axis (I ω parallel to ω); None otherwise.

    Euler's equations give ω̇ = 0 exactly there: the closed forms describe a
    motion that does not change, and no rate or period can be measured."""
    omega = np.asarray(case.omega0, dtype=float)
    scale = float(np.max(np.abs(omega)))
    if scale == 0:
        return (
            "no theory comparison: the body is at rest (ω = 0), where the free-body solution "
            "stays at rest; nothing to compare."
        )
    moments, axes = case.mass_properties.principal()
    along = axes.T @ (omega / scale)  # ω in principal axes, scaled: no overflow
    momentum = moments * along
    across = np.cross(momentum, along)
    if np.linalg.norm(across) > STEADY_TOLERANCE * np.linalg.norm(momentum) * np.linalg.norm(along):
        return None
    k = int(np.argmax(np.abs(along)))
    return (
        f"no theory comparison: the body spins about a principal axis (I{k + 1} = "
        f"{moments[k]:.3g} kg·m²), where the free-body solution is a steady spin; "
        "nothing to compare."
    )


def periods(period: float, count: int, duration: float) -> float | None:
    """The end of the first ``count`` periods, or None when the run is not much longer."""
    if not math.isfinite(period) or count * period * 2 > duration:
        return None
    return count * period
