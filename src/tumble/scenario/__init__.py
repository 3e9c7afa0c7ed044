"""Scenario files: a whole simulation described in TOML, with units as strings.

* :func:`load` — a built-in scenario by name, or a ``.toml`` file.
* :func:`parse` — scenario text (with the name of its source, for messages).
* :func:`builtin_names`, :func:`builtin_text` — the scenarios shipped with tumble.
* :func:`run` — simulate a scenario and compare with theory: a :class:`RunResult`.

Errors are :class:`ScenarioError` (an :class:`~tumble.InputError`), one line
that names the file, the line where it could be found, the key path and what
was expected, e.g.::

    spin.toml, line 7, `body.radius`: Expected `radius` to be a length in m, got 3 kg ...
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from tumble.config import read_source, validate_toml
from tumble.scenario.loaded import BUILTINS, DEFAULT, LoadedScenario, ScenarioError, where

if TYPE_CHECKING:
    from tumble.scenario.execute import RunResult

__all__ = [
    "LoadedScenario",
    "ScenarioError",
    "builtin_description",
    "builtin_names",
    "builtin_text",
    "load",
    "parse",
    "run",
    "where",
]


#: Names of the built-in scenarios, in the order `tumble list` shows them.
builtin_names = BUILTINS.names
#: The TOML text of a built-in scenario (ScenarioError for an unknown name).
builtin_text = BUILTINS.text
#: The one-line title of a built-in scenario.
builtin_description = BUILTINS.description


def load(scenario: str | Path | None = None) -> LoadedScenario:
    """A built-in scenario by name (default ``gyroscope``) or a scenario file.

    Raises
    ------
    ScenarioError
        Unknown name, unreadable file, invalid TOML or an invalid scenario.
    """
    source = read_source(DEFAULT if scenario is None else scenario, BUILTINS)
    return parse(source.text, source=source.name, folder=source.folder)


def parse(
    text: str, source: str = "<scenario>", folder: str | Path | None = None
) -> LoadedScenario:
    """Validate scenario text.

    Parameters
    ----------
    text : the TOML text.
    source : its name in error messages.
    folder : where relative paths (mesh files) are looked up; default the
        current directory.

    Raises
    ------
    ScenarioError
        Invalid TOML (with its line and column) or an invalid scenario (the
        first problem: key path, line, and what was expected; and how many
        others there are).
    """
    from tumble.scenario.bodies import key_path
    from tumble.scenario.schema import scenario_schema

    spec = validate_toml(
        scenario_schema(),
        text,
        source,
        error=ScenarioError,
        key_path=key_path,
        name_input=True,
        count_others=True,
    )
    return LoadedScenario(spec, text, source, Path(folder) if folder is not None else Path.cwd())


def run(scenario: LoadedScenario | str | Path | None = None, progress: Any = None) -> RunResult:
    """Simulate a scenario (a :class:`LoadedScenario`, a built-in name or a file) and
    compare with theory. ``progress`` is None or a callable ``(done, total)``.

    Raises
    ------
    ScenarioError
        As :func:`load`; a body, part or torque the library refuses; an
        integration that diverges; a run of more than
        :data:`~tumble.scenario.schema.MAX_STEPS` steps (without ``dt``, the
        step follows the fastest rotation: a file that spins a body at 1e9 rad/s
        would otherwise run for hours).
    """
    from tumble.scenario.execute import execute

    loaded = scenario if isinstance(scenario, LoadedScenario) else load(scenario)
    return execute(loaded, progress=_within_steps(loaded, progress))


def _within_steps(loaded: LoadedScenario, progress: Any) -> Any:
    """``progress`` behind a check of the steps the run announces: the stepping
    drivers report their total after their first chunk of steps (milliseconds),
    so a run over the limit is refused before it takes its time."""
    from tumble.scenario.execute import check_steps

    def report(done: int, total: int) -> None:
        check_steps(loaded, total)
        if progress is not None:
            progress(done, total)

    return report
