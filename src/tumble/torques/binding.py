"""A torque model bound to a body: the packed fields and the combined compiled function."""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.core import torques as kernels
from tumble.core._jit import file_stamp
from tumble.errors import InputError
from tumble.torques.model import TORQUES, TorqueModel

__all__ = ["BoundTorque", "bind"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class BoundTorque:
    """A torque model bound to a body: what the compiled kernels take.

    Attributes
    ----------
    terms : the models that act on the body, in registry order.
    params : (rows, 1) or (rows, N) the packed fields of every term, principal axes.
    context : the one non-numeric argument of the kernels (0.0 when none).
    identity : names the terms' compiled functions, their sources and rows: the
        key under which kernels specialised for this torque are cached.
    function : the combined compiled function (:func:`tumble.core.torques.combine`)
        of the terms acting from outside.
    drive : the same for the terms the body's rotors produce (``actuator="rotors"``):
        the torque the rotors must exert on the body (:mod:`tumble.core.parts`).
    """

    terms: tuple[TorqueModel, ...]
    params: Array
    context: Any
    identity: str
    function: Any = field(repr=False)
    drive: Any = field(repr=False, default=None)

    @property
    def torque_free(self) -> bool:
        return not self.terms

    @property
    def through_rotors(self) -> bool:
        """True when some term acts through the body's rotors."""
        return any(term.actuator == "rotors" for term in self.terms)

    @property
    def conservative(self) -> bool:
        """True when every term derives from a potential (and acts from outside)."""
        return all(term.conservative and term.actuator == "external" for term in self.terms)

    @property
    def depends_on(self) -> frozenset[str]:
        found: frozenset[str] = frozenset()
        for term in self.terms:
            found |= term.depends_on
        return found


_COMBINED: dict[str, Any] = {}
_LOCK = threading.Lock()


def bind(
    model: TorqueModel | None, body: Any, omega0: Array | None = None, bodies: int | None = None
) -> BoundTorque:
    """Bind a torque model to a body (:class:`tumble.body.RigidBody`) or a batch
    (:class:`tumble.body.BodyBatch`, ``bodies`` N): the terms that act on it, their
    fields packed in its principal axes, and the combined compiled function.

    Raises
    ------
    InputError
        Per-body values outside a batch or for the wrong number of bodies.
    """
    models = () if model is None else model.terms
    if not models:  # torque-free: nothing to pack
        free = _combined([])
        return BoundTorque((), np.zeros((1, 1)), 0.0, "free", free, free)
    order = {cls: k for k, cls in enumerate(TORQUES.values())}
    acting = sorted(
        (term for term in models if term.acts_on(body)),
        key=lambda term: order.get(type(term), len(order)),
    )
    columns = 1 if bodies is None else bodies
    blocks, contexts, row = [], [], 0
    outside: list[tuple[Any, int]] = []
    rotors: list[tuple[Any, int]] = []
    for term in acting:
        _check_bodies(term, bodies)
        if term.actuator == "rotors" and not any(
            getattr(part, "actuated", False) for part in getattr(body, "parts", ())
        ):
            raise InputError(
                f"Expected rotors in the body for {term!r}, which acts through them, got none "
                "(give the body's rotors with `internal=[Rotor(...), ...]`)."
            )
        packed = np.asarray(term.pack(body, omega0), dtype=float)
        packed = packed.reshape(len(term.fields), -1) if term.fields else np.zeros((0, 1))
        blocks.append(packed)
        (rotors if term.actuator == "rotors" else outside).append((type(term).kernel, row))
        row += len(term.fields)
        context = term.context(body)
        if context is not None:
            contexts.append(context)
    per_body = any(block.shape[1] > 1 for block in blocks)
    width = columns if per_body else 1
    params = np.ascontiguousarray(
        np.vstack(
            [
                block if block.shape[1] == width else np.broadcast_to(block, (len(block), width))
                for block in blocks
            ]
        )
        if blocks
        else np.zeros((1, width))
    )
    identity = _identity(outside) or "free"
    if rotors:
        identity += f"|rotors:{_identity(rotors)}"
    return BoundTorque(
        tuple(acting),
        params,
        contexts[0] if contexts else 0.0,
        identity,
        _combined(outside),
        _combined(rotors),
    )


def _identity(terms: list[tuple[Any, int]]) -> str:
    return "+".join(f"{file_stamp(kernel)}@{at}" for kernel, at in terms)


def _combined(terms: list[tuple[Any, int]]) -> Any:
    """The compiled sum of ``terms`` (kernel, row), built once per process."""
    key = _identity(terms) or "free"
    with _LOCK:
        function = _COMBINED.get(key)
        if function is None:
            function = _COMBINED[key] = kernels.combine(terms)
    return function


def _check_bodies(term: TorqueModel, bodies: int | None) -> None:
    """Per-body values only in a batch, and one per body."""
    count = term.per_body
    if count is None:
        return
    if bodies is None:
        raise InputError(
            f"Expected one torque for one body, got per-body values ({term!r}): those are for "
            "simulate_batch."
        )
    if count != bodies:
        for parameter, value in zip(term.parameters, term.values().values(), strict=True):
            if np.ndim(value) == len(parameter.shape) + 1:
                raise InputError(
                    f"Expected per-body {type(term).__name__} values of shape "
                    f"{(bodies, *parameter.shape)} for {bodies} bodies, got {np.shape(value)}."
                )
