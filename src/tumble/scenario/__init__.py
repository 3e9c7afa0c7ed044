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

import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tumble.errors import InputError

if TYPE_CHECKING:
    from tumble.scenario.execute import RunResult
    from tumble.scenario.schema import Scenario

__all__ = [
    "LoadedScenario",
    "ScenarioError",
    "builtin_description",
    "builtin_names",
    "builtin_text",
    "load",
    "parse",
    "run",
]

#: The built-in scenario run when none is named.
DEFAULT = "gyroscope"

# Their order in `tumble list`.
_ORDER = (
    "gyroscope",
    "gyrocompass",
    "skew-rod",
    "tennis-racket",
    "heavy-top",
    "free-symmetric-top",
    "tumbling-satellite",
)


class ScenarioError(InputError):
    """A scenario file or name is invalid; the message names the key and line."""


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


def _builtin_folder() -> Path:
    return Path(str(resources.files("tumble.scenario") / "builtin"))


def builtin_names() -> list[str]:
    """Names of the built-in scenarios, in the order `tumble list` shows them."""
    found = {p.stem for p in _builtin_folder().glob("*.toml")}
    return [n for n in _ORDER if n in found] + sorted(found - set(_ORDER))


def builtin_text(name: str) -> str:
    """The TOML text of a built-in scenario.

    Raises
    ------
    ScenarioError
        If there is no built-in scenario of that name (the message lists them).
    """
    names = builtin_names()
    if name not in names:
        import difflib

        close = difflib.get_close_matches(name, names, n=1)
        hint = f" Did you mean {close[0]}?" if close else ""
        raise ScenarioError(
            f"Expected a built-in scenario ({', '.join(names)}) or a .toml file, "
            f"got {name!r}.{hint}"
        )
    return (_builtin_folder() / f"{name}.toml").read_text(encoding="utf-8")


def builtin_description(name: str) -> str:
    """The one-line title of a built-in scenario."""
    data = tomllib.loads(builtin_text(name))
    info = data.get("scenario", {})
    return str(info.get("title") or info.get("description") or "")


def load(scenario: str | Path | None = None) -> LoadedScenario:
    """A built-in scenario by name (default ``gyroscope``) or a scenario file.

    Raises
    ------
    ScenarioError
        Unknown name, unreadable file, invalid TOML or an invalid scenario.
    """
    if scenario is None:
        scenario = DEFAULT
    text_name = str(scenario)
    path = Path(text_name)
    if path.suffix.lower() == ".toml" or path.exists():
        if not path.is_file():
            raise ScenarioError(f"Expected a scenario file, got {text_name!r} (no such file).")
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ScenarioError(
                f"Expected a readable UTF-8 file, got {text_name!r}: {exc}."
            ) from None
        return parse(text, source=text_name, folder=path.resolve().parent)
    return parse(builtin_text(text_name), source=f"builtin:{text_name}", folder=_builtin_folder())


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
        first problem: key path, line, and what was expected).
    """
    from pydantic import ValidationError

    from tumble.scenario.schema import Scenario

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: Expected valid TOML, got an error: {exc}.") from None
    try:
        spec = Scenario.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(_first_error(exc, text, source)) from None
    return LoadedScenario(spec, text, source, Path(folder) if folder is not None else Path.cwd())


def _first_error(exc: Any, text: str, source: str) -> str:
    from tumble.scenario._locate import key_lines, line_of

    errors = exc.errors(include_url=False)
    # With a union, pydantic reports the tag's branch; an unknown key is the most
    # telling problem, so it comes first when there are several.
    errors.sort(key=lambda e: 0 if e["type"] == "unknown_key" else 1)
    error = errors[0]
    loc = _without_tags(error["loc"])
    if error["type"] in ("unknown_key", "scenario_value"):
        loc.append(error["ctx"]["key"])
    path = tuple(loc)
    line = line_of(key_lines(text), path)
    where = f"{source}, line {line}" if line is not None else source
    dotted = _dotted(path)
    message = str(error["msg"])
    for prefix in ("Value error, ", "Assertion failed, "):
        message = message.removeprefix(prefix)
    if error["type"] == "missing":
        message = (
            f"Expected the table [{dotted}], which is missing."
            if dotted in {"scenario", "body", "simulation"}
            else f"Expected the key `{path[-1]}`, which is missing."
        )
    elif not message.startswith(("Expected", "Unknown")):
        message = f"Expected a valid value: {message[0].lower()}{message[1:]}."
    more = len(errors) - 1
    tail = f" ({more} more problem{'s' if more > 1 else ''})" if more else ""
    return f"{where}, `{dotted}`: {message}{tail}" if dotted else f"{where}: {message}{tail}"


_TAGS = {"shape", "mesh", "points", "inertia", "parts", "ambiguous"}


def _without_tags(loc: Any) -> list[Any]:
    """The key path without pydantic's union tags (after `body`, or after a part's index)."""
    path: list[Any] = []
    for k, part in enumerate(loc):
        after_body = k == 1 and loc[0] == "body"
        after_part = k >= 2 and isinstance(loc[k - 1], int) and loc[k - 2] == "parts"
        if (after_body or after_part) and part in _TAGS:
            continue
        path.append(part)
    return path


def where(loaded: LoadedScenario, path: tuple[Any, ...]) -> str:
    """``source, line N, `dotted.path``` for messages about a key of a loaded scenario."""
    from tumble.scenario._locate import key_lines, line_of

    line = line_of(key_lines(loaded.text), path)
    place = f"{loaded.source}, line {line}" if line is not None else loaded.source
    return f"{place}, `{_dotted(path)}`"


def _dotted(path: tuple[Any, ...]) -> str:
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text


def run(scenario: LoadedScenario | str | Path | None = None, progress: Any = None) -> RunResult:
    """Simulate a scenario (a :class:`LoadedScenario`, a built-in name or a file) and
    compare with theory. ``progress`` is None or a callable ``(done, total)``."""
    from tumble.scenario.execute import execute

    loaded = scenario if isinstance(scenario, LoadedScenario) else load(scenario)
    return execute(loaded, progress=progress)
