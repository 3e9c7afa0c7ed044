"""What the scenario modules share: the error, a loaded scenario, the built-in files.

They live below the package's entry points (:func:`tumble.scenario.load`,
:func:`~tumble.scenario.run`) so that the modules those call, which build and
run a scenario, can import them without importing the package back.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tumble import config

if TYPE_CHECKING:
    from tumble.scenario.schema import Scenario

__all__ = ["BUILTINS", "DEFAULT", "LoadedScenario", "ScenarioError", "where"]

#: The built-in scenario run when none is named.
DEFAULT = "gyroscope"


class ScenarioError(config.ConfigError):
    """A scenario file or name is invalid; the message names the key and line."""


#: The scenarios shipped with tumble, in the order of `tumble list`; the meshes
#: they name are beside them.
BUILTINS = config.Builtins(
    kind="scenario",
    package="tumble.scenario",
    folder_name="builtin",
    error=ScenarioError,
    order=(
        "gyroscope",
        "gyrocompass",
        "skew-rod",
        "rotor-on-bearings",
        "tennis-racket",
        "heavy-top",
        "free-symmetric-top",
        "tumbling-satellite",
        "dual-spin",
        "explorer-1",
        "gravity-gradient",
        "reaction-wheel-slew",
    ),
    describe=("title", "description"),
    command="tumble run",
)


@dataclass(frozen=True)
class LoadedScenario:
    """A validated scenario with where it came from.

    Attributes
    ----------
    spec : the validated :class:`~tumble.scenario.schema.Scenario` (SI values).
    text : the TOML text as written.
    source : the file name, or ``builtin:NAME``.
    folder : where relative paths in it (mesh files) are looked up.
    """

    spec: Scenario
    text: str
    source: str
    folder: Path

    @property
    def name(self) -> str:
        return self.spec.scenario.name


def where(loaded: LoadedScenario, path: tuple[Any, ...]) -> str:
    """``source, line N, `dotted.path``` for messages about a key of a loaded scenario."""
    return config.where(loaded.text, loaded.source, path)
