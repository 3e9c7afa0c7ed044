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
"""

from __future__ import annotations

from collections.abc import Iterable
from decimal import Decimal, InvalidOperation
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from tumble.robots.model import INERTIA_ATTRIBUTES

__all__ = [
    "CHOSEN_DIGITS",
    "POWERS",
    "judge_tensor",
    "physical_within_rounding",
    "power_of_ten_candidates",
    "rounding",
    "swap_candidates",
    "tensor_of",
]

Array = NDArray[np.float64]

#: The powers of ten tried on one attribute: a decimal point moved by up to six places.
POWERS = tuple(k for k in range(-6, 7) if k != 0)

#: Relative rounding allowed to any written number: those of one or two
#: significant digits are taken as chosen, not rounded, within 0.5 %.
CHOSEN_DIGITS = 5e-3


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
        [0.5 - v[0] ** 2, -2 * v[0] * v[1], -2 * v[0] * v[2], 0.5 - v[1] ** 2,
         -2 * v[1] * v[2], 0.5 - v[2] ** 2]
    )  # fmt: skip


def _spread(values: Array) -> tuple[float, Array]:
    """The smallest eigenvalue of Σ = tr(I)/2 E − I for URDF's six numbers, and
    its unit eigenvector."""
    tensor = tensor_of(values)
    eigenvalues, vectors = np.linalg.eigh(np.trace(tensor) / 2 * np.eye(3) - tensor)
    return float(eigenvalues[0]), vectors[:, 0]


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
    size = float(np.abs(centre).max(initial=0.0))
    tolerance = 8 * np.finfo(float).eps
    if size == 0.0 or _spread(centre)[0] >= -tolerance * size:
        return True
    half = np.array([rounding(t) for t in texts]) / size + tolerance
    box = [(c - h, c + h) for c, h in zip(centre / size, half, strict=True)]
    tensor = tensor_of(centre)
    cuts = list(np.linalg.eigh(np.trace(tensor) / 2 * np.eye(3) - tensor)[1].T)
    for _ in range(100):
        # Maximise s subject to s <= g(v) · x for every cut v, x in the box.
        rows = np.array([[*(-_quadratic(v)), 1.0] for v in cuts])
        result = linprog(
            np.r_[np.zeros(6), -1.0], A_ub=rows, b_ub=np.zeros(len(cuts)),
            bounds=[*box, (None, None)], method="highs",
        )  # fmt: skip
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
    moments = np.linalg.eigvalsh(tensor_of(values))
    if moments[0] < -1e-12 * np.abs(moments).max():  # below round-off: negative
        return "not-positive-definite", float(moments[0])
    return "triangle-inequality", float((moments[2] - moments[0] - moments[1]) / moments[2])


def _scaled_text(text: str, power: int) -> str:
    """A number's text with its decimal point moved by ``power`` places, exactly."""
    scaled = Decimal(text.strip()).scaleb(power)
    return format(scaled.normalize(), "f") if abs(scaled.adjusted()) < 12 else str(scaled)


def power_of_ten_candidates(
    values: tuple[float, ...], texts: tuple[str, ...]
) -> list[dict[str, float]]:
    """Every single-attribute change by a power of ten (:data:`POWERS`) that makes
    the tensor one some body has: ``[{attribute: new value}]``."""
    found = []
    for i, name in enumerate(INERTIA_ATTRIBUTES):
        if values[i] == 0.0:
            continue
        for power in POWERS:
            new_texts = list(texts)
            new_texts[i] = _scaled_text(texts[i], power)
            new = list(values)
            new[i] = float(new_texts[i])
            if judge_tensor(new, new_texts) is None:
                found.append({name: new[i]})
    return found


def swap_candidates(values: tuple[float, ...], texts: tuple[str, ...]) -> list[dict[str, float]]:
    """Every exchange of two different attributes' values that makes the tensor
    one some body has."""
    found = []
    for i, j in combinations(range(6), 2):
        if values[i] == values[j]:
            continue
        new = list(values)
        new[i], new[j] = new[j], new[i]
        new_texts = list(texts)
        new_texts[i], new_texts[j] = new_texts[j], new_texts[i]
        if judge_tensor(new, new_texts) is None:
            found.append({INERTIA_ATTRIBUTES[i]: new[i], INERTIA_ATTRIBUTES[j]: new[j]})
    return found
