"""A declared inertia tensor judged alone: is it one a body has, up to the
rounding of its written numbers, and which one-attribute slips would explain it.

Round-off is told apart from error by the digits written. A number printed
from a computation is within half a unit of its last digit of the value meant;
a number of one or two significant digits (a placeholder ``1e-6``, a hand-written
``0.01``) is taken as meant, give or take 0.5 % (:data:`CHOSEN_DIGITS`). A tensor
is flagged only when no tensor within those bounds of every entry is one a body
has: a body's tensor is I = tr(Σ) E − Σ with Σ = ∫ r rᵀ dm positive
semidefinite (Wensing, Kim & Slotine 2017), so the question is whether the
smallest eigenvalue of Σ = tr(I)/2 E − I, a concave function of the entries,
reaches 0 somewhere in their box: a convex problem, solved by cutting planes
(:func:`physical_within_rounding`). The eigenvalues of Σ are half the sums
I_j + I_k − I_i, so Σ ⪰ 0 is the triangle inequalities, and with them I ⪰ 0.

A tensor physical only within that rounding is still refused as written by the
engines that load it (:func:`refusals`): MuJoCo's compiler demands A + B >= C of
its principal moments with no tolerance at all, Drake's
``CouldBePhysicallyValid`` within 16 ε of half the trace, tumble's
:class:`~tumble.massprops.MassProperties` within 1e-9 of the trace. Such a
tensor gets the nearest one they all accept (:func:`nearest_accepted`).
"""

from __future__ import annotations

from collections.abc import Iterable
from decimal import Decimal, InvalidOperation
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from tumble.robots.model import INERTIA_ATTRIBUTES

__all__ = [
    "ACCEPTED_MARGIN",
    "CHOSEN_DIGITS",
    "ENGINE_ROUNDOFF",
    "ENTRIES",
    "POWERS",
    "accepted_change",
    "judge_tensor",
    "nearest_accepted",
    "physical_within_rounding",
    "power_of_ten_candidates",
    "principal_moments",
    "refusals",
    "rounding",
    "swap_candidates",
    "tensor_of",
]

Array = NDArray[np.float64]

#: The (row, column) of each of URDF's six attributes in the tensor.
ENTRIES = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))

#: The powers of ten tried on one attribute: a decimal point moved by up to six places.
POWERS = tuple(k for k in range(-6, 7) if k != 0)

#: Relative rounding allowed to any written number: those of one or two
#: significant digits are taken as chosen, not rounded, within 0.5 %.
CHOSEN_DIGITS = 5e-3

#: How far, as a fraction of the trace, another solver's principal moments of a
#: tensor with products may stand from numpy's: MuJoCo's eigen-solver and numpy's
#: disagree on I1 + I2 − I3 by up to 1 ε of the trace (3000 rotated thin plates on
#: the boundary, MuJoCo 3.2 to 4.0), so a margin below 4 ε is MuJoCo's to refuse.
ENGINE_ROUNDOFF = 4 * float(np.finfo(float).eps)

#: The margin I1 + I2 − I3 >= ACCEPTED_MARGIN × trace of a corrected tensor: far
#: above the engines' round-off (:data:`ENGINE_ROUNDOFF`) and above the change of
#: the margin by the correction's twelve written digits (at most some 4e-11 of
#: the trace), and far below any digit a file writes.
ACCEPTED_MARGIN = 1e-10

#: The significant digits a corrected tensor is written with.
CORRECTION_DIGITS = 12


def rounding(text: str) -> float:
    """How far a written number may be from the value meant: half a unit in its
    last digit, at most :data:`CHOSEN_DIGITS` of it (0 for a written zero, meant
    exactly)."""
    try:
        value = Decimal(text.strip())
    except InvalidOperation:
        return 0.0
    if value == 0 or not value.is_finite():
        return 0.0
    half = 0.5 * 10.0 ** int(value.as_tuple().exponent)
    return min(half, CHOSEN_DIGITS * abs(float(value)))


def tensor_of(values: Iterable[float]) -> Array:
    """The symmetric tensor of URDF's six numbers (ixx, ixy, ixz, iyy, iyz, izz)."""
    xx, xy, xz, yy, yz, zz = values
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], dtype=float)


def _quadratic(v: Array) -> Array:
    """The row g with vᵀ Σ v = g · (ixx, ixy, ixz, iyy, iyz, izz) for Σ = tr(I)/2 E − I."""
    return np.array(
        [
            0.5 - v[0] ** 2,
            -2 * v[0] * v[1],
            -2 * v[0] * v[2],
            0.5 - v[1] ** 2,
            -2 * v[1] * v[2],
            0.5 - v[2] ** 2,
        ]
    )


def _spread(values: Array) -> tuple[float, Array]:
    """The smallest eigenvalue of Σ = tr(I)/2 E − I for URDF's six numbers, and
    its unit eigenvector."""
    tensor = tensor_of(values)
    eigenvalues, vectors = np.linalg.eigh(np.trace(tensor) / 2 * np.eye(3) - tensor)
    return float(eigenvalues[0]), vectors[:, 0]


def _unit(values: Iterable[float]) -> tuple[Array, float]:
    """URDF's six numbers as a tensor over its largest entry, and that entry: sums
    and eigenvalues of entries near 1e308 neither overflow nor fail to converge."""
    tensor = tensor_of(values)
    scale = float(np.abs(tensor).max())
    if not np.isfinite(scale) or scale == 0.0:
        return tensor, 1.0
    return tensor / scale, scale


def principal_moments(values: Iterable[float]) -> Array:
    """The principal moments (kg·m², ascending) of URDF's six numbers: those of the
    tensor over its largest entry, scaled back (infinite beyond float64's range,
    NaN for numbers that are not finite)."""
    unit, scale = _unit(values)
    if not np.all(np.isfinite(unit)):
        return np.full(3, np.nan)
    with np.errstate(over="ignore"):
        return np.asarray(np.linalg.eigvalsh(unit) * scale, dtype=float)


def refusals(values: Iterable[float]) -> tuple[str, ...]:
    """The engines that refuse URDF's six numbers as written: ``"MuJoCo"``,
    ``"Drake"``, ``"tumble"``, or none.

    * MuJoCo's compiler (``user_objects.cc``, mjCBody::Compile) takes the
      principal moments of a full inertia from its eigen-solver (a diagonal one
      as written) and refuses a negative one or ``A + B < C`` exactly, in
      float64. Products that are all zero are judged exactly so; with products,
      a margin below :data:`ENGINE_ROUNDOFF` of the trace is within its
      solver's round-off and counted as refused. (Its floor ``mjMINVAL`` on the
      moments of moving bodies is a simulation bound, not a physical one: a zero
      moment is a thin rod's, valid here.)
    * Drake's ``RotationalInertia::CouldBePhysicallyValid``: principal moments
      >= −ε and ``I1 + I2 + ε >= I3``, ε = 16 ε_mach max(1, trace / 2).
    * tumble's :class:`~tumble.massprops.MassProperties` (``tumble inertia``):
      the same to 1e-9 of the trace.
    """
    from tumble.errors import InputError
    from tumble.massprops import MassProperties

    values = tuple(float(v) for v in values)
    if not all(np.isfinite(values)):
        return ("MuJoCo", "Drake", "tumble")
    unit, scale = _unit(values)
    moments = np.linalg.eigvalsh(unit)
    trace = float(np.trace(unit))
    found = []
    if values[1] == values[2] == values[4] == 0.0:
        low, middle, high = sorted((values[0], values[3], values[5]))
        with np.errstate(over="ignore"):
            mujoco = low < 0 or low + middle < high
    else:
        mujoco = (
            moments[0] < -ENGINE_ROUNDOFF * trace
            or moments[0] + moments[1] - moments[2] < ENGINE_ROUNDOFF * trace
        )
    if mujoco:
        found.append("MuJoCo")
    drake = 16 * float(np.finfo(float).eps) * max(1.0 / scale, trace / 2)
    if moments[0] < -drake or moments[0] + moments[1] + drake < moments[2]:
        found.append("Drake")
    try:
        with np.errstate(over="ignore"):  # its message's moments of 1e308 tensors
            MassProperties(1.0, np.zeros(3), tensor_of(values))
    except InputError:
        found.append("tumble")
    return tuple(found)


def nearest_accepted(values: Iterable[float]) -> dict[str, float] | None:
    """The tensor nearest URDF's six numbers (Frobenius norm) that every engine
    accepts (:func:`refusals`), as URDF's attributes; None where no margin tried
    gives one they accept (no correction is better than a refused one).

    Its principal axes are the written tensor's (the nearest tensor of a set
    defined by the eigenvalues shares them: von Neumann's trace inequality); its
    moments p = A σ, A = [[0, 1, 1], [1, 0, 1], [1, 1, 0]], are the least-squares
    fit to the written ones with every spread σ_i = (p_j + p_k − p_i) / 2 at least
    :data:`ACCEPTED_MARGIN` of the trace (σ >= 0 is the triangle inequalities,
    and with them p >= 0), written with :data:`CORRECTION_DIGITS` digits, the
    margin widened tenfold (up to six times) while the written digits eat it.
    """
    from scipy.optimize import lsq_linear

    values = tuple(float(v) for v in values)
    unit, scale = _unit(values)
    moments, axes = np.linalg.eigh(unit)
    if values[1] == values[2] == values[4] == 0.0:  # keep the products exactly zero
        moments, axes = np.diag(unit).copy(), np.eye(3)
    pairs = np.ones((3, 3)) - np.eye(3)
    margin = ACCEPTED_MARGIN
    for _ in range(6):
        floor = margin * max(float(moments.sum()), float(np.abs(moments).max()))
        spreads = lsq_linear(pairs, moments, bounds=(floor, np.inf), method="bvls").x
        with np.errstate(over="ignore"):  # past float64's largest: refused below
            tensor = axes @ np.diag(pairs @ spreads) @ axes.T * scale
        # `+ 0.0` writes a zero product as 0, not -0.
        corrected = [float(f"{tensor[i, j]:.{CORRECTION_DIGITS}g}") + 0.0 for i, j in ENTRIES]
        if not refusals(corrected):
            return dict(zip(INERTIA_ATTRIBUTES, corrected, strict=True))
        margin *= 10  # the written digits ate the margin: a wider one
    return None


def accepted_change(values: Iterable[float], change: dict[str, float]) -> dict[str, float] | None:
    """The correction that makes URDF's six numbers with ``change`` (attribute →
    new value) applied a tensor every engine accepts: ``change`` itself where they
    accept it as written, else the nearest accepted tensor to it
    (:func:`nearest_accepted`), None where there is none."""
    new = [change.get(name, value) for name, value in zip(INERTIA_ATTRIBUTES, values, strict=True)]
    return change if not refusals(new) else nearest_accepted(new)


def physical_within_rounding(values: Iterable[float], texts: Iterable[str]) -> bool:
    """Whether some tensor within the rounding of the written numbers
    (:func:`rounding`, plus a few ε of the largest) is one a body has: whether
    max over that box of λ_min(Σ) is ≥ 0. λ_min(Σ) is the minimum over unit v of
    vᵀ Σ v, linear in the six numbers, so the maximum is found by cutting
    planes: a linear programme over the box with one cut per v found (an upper
    bound; below 0, no tensor there is a body's), then the smallest eigenvector
    at its solution as the next cut (at or above 0 there, one is)."""
    from scipy.optimize import linprog

    centre = np.array(list(values), dtype=float)
    if not np.all(np.isfinite(centre)):
        return False
    size = float(np.abs(centre).max(initial=0.0))
    tolerance = 8 * np.finfo(float).eps
    # Over the largest entry: entries near 1e308 would overflow the sums.
    if size == 0.0 or _spread(centre / size)[0] >= -tolerance:
        return True
    half = np.array([rounding(t) for t in texts]) / size + tolerance
    box = [(c - h, c + h) for c, h in zip(centre / size, half, strict=True)]
    tensor = tensor_of(centre / size)
    cuts = list(np.linalg.eigh(np.trace(tensor) / 2 * np.eye(3) - tensor)[1].T)
    for _ in range(100):
        # Maximise s subject to s <= g(v) · x for every cut v, x in the box.
        rows = np.array([[*(-_quadratic(v)), 1.0] for v in cuts])
        result = linprog(
            np.r_[np.zeros(6), -1.0],
            A_ub=rows,
            b_ub=np.zeros(len(cuts)),
            bounds=[*box, (None, None)],
            method="highs",
        )
        if not result.success or -result.fun < -tolerance:
            return False
        smallest, vector = _spread(result.x[:6])
        if smallest >= -tolerance:
            return True
        cuts.append(vector)
    return False


def judge_tensor(values: Iterable[float], texts: Iterable[str]) -> tuple[str, float] | None:
    """None for a tensor some body has, up to the rounding of its written numbers
    (:func:`physical_within_rounding`); else ``("not-positive-definite",
    smallest moment)`` or ``("triangle-inequality", shortfall)``, the shortfall
    (I₃ − I₁ − I₂) / I₃ of the tensor as written."""
    values = tuple(values)
    if physical_within_rounding(values, texts):
        return None
    unit, scale = _unit(values)
    if not np.all(np.isfinite(unit)):
        return "not-positive-definite", float("nan")
    moments = np.linalg.eigvalsh(unit)  # over the largest entry: no overflow
    if moments[0] < -1e-12 * np.abs(moments).max():  # below round-off: negative
        return "not-positive-definite", float(moments[0] * scale)
    return "triangle-inequality", float((moments[2] - moments[0] - moments[1]) / moments[2])


def _scaled_text(text: str, power: int) -> str:
    """A number's text with its decimal point moved by ``power`` places, exactly."""
    scaled = Decimal(text.strip()).scaleb(power)
    return format(scaled.normalize(), "f") if abs(scaled.adjusted()) < 12 else str(scaled)


def power_of_ten_candidates(
    values: tuple[float, ...], texts: tuple[str, ...]
) -> list[dict[str, float]]:
    """Every single-attribute change by a power of ten (:data:`POWERS`) that makes
    the tensor one some body has, and leaves one the engines accept as written or
    corrected (:func:`accepted_change`): ``[{attribute: new value}]``."""
    found = []
    for i, name in enumerate(INERTIA_ATTRIBUTES):
        if values[i] == 0.0:
            continue
        for power in POWERS:
            new_texts = list(texts)
            new_texts[i] = _scaled_text(texts[i], power)
            new = list(values)
            new[i] = float(new_texts[i])
            change = {name: new[i]}
            if judge_tensor(new, new_texts) is None and accepted_change(values, change):
                found.append(change)
    return found


def swap_candidates(values: tuple[float, ...], texts: tuple[str, ...]) -> list[dict[str, float]]:
    """Every exchange of two different attributes' values that makes the tensor
    one some body has, and leaves one the engines accept as written or corrected
    (:func:`accepted_change`)."""
    found = []
    for i, j in combinations(range(6), 2):
        if values[i] == values[j]:
            continue
        new = list(values)
        new[i], new[j] = new[j], new[i]
        new_texts = list(texts)
        new_texts[i], new_texts[j] = new_texts[j], new_texts[i]
        change = {INERTIA_ATTRIBUTES[i]: new[i], INERTIA_ATTRIBUTES[j]: new[j]}
        if judge_tensor(new, new_texts) is None and accepted_change(values, change):
            found.append(change)
    return found
