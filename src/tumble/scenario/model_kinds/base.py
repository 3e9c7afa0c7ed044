"""The registry of model kinds a scenario file may run, and what a kind declares.

A model kind is a mechanism built around the body of ``[body]`` that a scenario
runs in place of the free rigid body (the gimballed gyroscope, the rigid rotor on
elastic bearings, …). It declares, in one module:

* its table in scenario files (:attr:`ModelKind.table`) and the table's schema
  (:attr:`ModelKind.settings`, a pydantic model converting to SI);
* its runner (:meth:`ModelKind.run`): its runs (:class:`ModelRuns`), their
  trajectories by label, the main first, the model's own results, and the
  :class:`~tumble.checks.Case` its closed form is compared on;
* its comparison with theory, a check of :data:`tumble.checks.THEORY_CHECKS`
  named by :attr:`ModelKind.check`, whose
  :meth:`~tumble.checks.TheoryCheck.compare_runs` gives the rows and the
  report's panels.

:data:`MODEL_KINDS` holds them by table name; :func:`tumble.scenario.parse`
and :func:`tumble.scenario.run` read it when a file is read and run, so a kind
registered later (a user's, a test's) runs from a file with no change to
either.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

if TYPE_CHECKING:
    from tumble.checks import Case
    from tumble.config import StrictModel
    from tumble.massprops import MassProperties
    from tumble.trajectory import Trajectory

__all__ = ["MODEL_KINDS", "ModelKind", "ModelRuns", "Span", "register_model_kind"]

Progress = Callable[[int, int], object] | None


@dataclass(frozen=True)
class Span:
    """How long a model runs and what it keeps: ``[simulation] duration`` (s) and
    ``dt`` (s; None: the model's own step), and about ``[output] samples`` samples
    of each run."""

    duration: float
    dt: float | None
    samples: int


@dataclass(frozen=True)
class ModelRuns:
    """What a model kind's run gives: ``trajectories`` by label, ``"main"`` first
    (written to the run folder, drawn and viewed), ``case``, what its check compares
    them on, and ``results``, the model's own results by the same labels (a
    :class:`~tumble.models.GyrocompassRun`, a :class:`~tumble.models.RunUp`), for
    its check to read besides the trajectories."""

    trajectories: dict[str, Trajectory]
    case: Case
    results: Mapping[str, Any] = field(default_factory=dict)


class ModelKind:
    """A model a scenario file runs from its own table (see the module's docstring)."""

    #: The name of its table in scenario files, a Python identifier (``gyrocompass``).
    table: ClassVar[str] = ""
    #: Former names of the table, still read for one release with a warning.
    former_tables: ClassVar[tuple[str, ...]] = ()
    #: The schema of its table: a pydantic model (:class:`tumble.config.StrictModel`)
    #: whose fields convert to SI.
    settings: ClassVar[type[StrictModel]]
    #: What it is, in a few words, for messages and listings.
    summary: ClassVar[str] = ""
    #: The name of the theory check (:data:`tumble.checks.THEORY_CHECKS`) its runs
    #: are compared with.
    check: ClassVar[str] = ""
    #: Sentences for the report: what the model conserves and what it does not.
    notes: ClassVar[tuple[str, ...]] = ()

    def run(self, body: MassProperties, settings: Any, span: Span, progress: Progress) -> ModelRuns:
        """Run the model of ``body`` with the table's ``settings`` (SI) over ``span``;
        ``progress`` is None or ``(done, total)``.

        Raises
        ------
        InputError
            A body or setting the model refuses (located at the table by the caller).
        """
        raise NotImplementedError


#: Every registered model kind by its table's name.
MODEL_KINDS: dict[str, ModelKind] = {}


def register_model_kind(kind: ModelKind) -> ModelKind:
    """Add a model kind to :data:`MODEL_KINDS` (replacing one of the same table).

    Raises
    ------
    ValueError
        A table name that is not an identifier (one that a scenario file's own tables
        already use is refused when files are read:
        :func:`tumble.scenario.schema.scenario_schema`).
    """
    for name in (kind.table, *kind.former_tables):
        if not name.isidentifier():
            raise ValueError(f"Expected a model kind's table to be an identifier, got {name!r}.")
    MODEL_KINDS[kind.table] = kind
    return kind
