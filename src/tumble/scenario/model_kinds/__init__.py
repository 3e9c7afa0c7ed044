"""Model kinds a scenario file runs from their own tables, in one registry.

* :data:`MODEL_KINDS` — each kind by its table's name: ``gyrocompass``
  (:mod:`~tumble.scenario.model_kinds.gyrocompass`, the gimballed gyroscope on
  a turning platform) and ``rotordynamics``
  (:mod:`~tumble.scenario.model_kinds.rotordynamics`, the rigid rotor on
  elastic bearings run up).
* :class:`ModelKind` — what a kind declares: its table and schema, its runner,
  its theory check; :class:`ModelRuns` — what its runner gives.
* :func:`register_model_kind` — add one: scenario files can then hold its table.
"""

from __future__ import annotations

from tumble.scenario.model_kinds.base import (
    MODEL_KINDS,
    ModelKind,
    ModelRuns,
    Span,
    register_model_kind,
)
from tumble.scenario.model_kinds.gyrocompass import Gyrocompass
from tumble.scenario.model_kinds.rotordynamics import Rotordynamics

__all__ = [
    "MODEL_KINDS",
    "Gyrocompass",
    "ModelKind",
    "ModelRuns",
    "Rotordynamics",
    "Span",
    "register_model_kind",
]
