"""Exceptions raised by tumble for bad input.

Every message follows one template: name the value, state what was expected,
show what was received, e.g. ``Expected `mass` > 0 kg, got -1.0.``
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable

__all__ = [
    "QUOTED_LENGTH",
    "QUOTED_PATH_LENGTH",
    "CoarseStepWarning",
    "InputError",
    "IntegrationError",
    "JointLimitWarning",
    "MeshError",
    "OutputError",
    "OutputInUseError",
    "RequestTooLargeError",
    "cut",
    "nearest",
    "quoted",
    "uncoloured",
    "unknown_choice",
]

#: The most characters of a value a message echoes; the rest is cut (``'...'...``).
QUOTED_LENGTH = 60

#: The same for a file's path, which is longer: folders and a file name.
QUOTED_PATH_LENGTH = 200


class InputError(ValueError):
    """A value given to tumble is invalid: wrong shape, units, range or physics.

    Examples
    --------
    Moments that no distribution of mass has are refused:

    >>> import numpy as np
    >>> import tumble as tb
    >>> tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.0, 3.0]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
        ...
    tumble.errors.InputError: Expected ... inequality I1 + I2 >= I3, got I1 + I2 = 2 < I3 = 3 ...
    >>> try:
    ...     tb.shapes.solid_sphere("-1 kg", 0.1)
    ... except tb.InputError as error:
    ...     print(error)
    Expected `mass` > 0 kg, got -1.0.
    """


class MeshError(InputError):
    """A triangle mesh cannot bound a solid: open, non-manifold, badly wound or empty."""


class IntegrationError(InputError):
    """The integration produced NaN or infinity (usually: ``dt`` far too large)."""


class OutputError(InputError):
    """A file or folder cannot be written where it was asked for (a path under a
    file, a folder that cannot be written, a full disk, a name too long). The
    message names the path and the cause; nothing half-written is left.

    Attributes
    ----------
    path : the file or folder that was to be written.
    cause : the operating system's error, when there was one.
    """

    def __init__(self, message: str, path: str = "", cause: OSError | None = None) -> None:
        super().__init__(message)
        self.path = path
        self.cause = cause


class OutputInUseError(OutputError):
    """Another process (or another thread of this one) is writing the same output:
    the message names it (pid, host, since when). Nothing was written."""


class RequestTooLargeError(InputError):
    """A request whose output cannot fit in the memory budget (see
    :mod:`tumble.resources`): refused before any work, with the estimate and
    how to ask for less."""


class CoarseStepWarning(UserWarning):
    """The time step is too coarse for the fastest rotation of the body."""


class JointLimitWarning(UserWarning):
    """A joint value outside the limits the robot file gives that joint: used as
    given (a pose the robot may not reach)."""


def cut(text: str, limit: int = QUOTED_LENGTH) -> str:
    """``text`` as a message shows it, unquoted: cut after ``limit`` characters
    with ``...``."""
    return text if len(text) <= limit else f"{text[:limit]}..."


def uncoloured(text: str) -> str:
    """``text`` without the terminal's colour codes (ANSI SGR sequences), which
    other tools' messages carry when they believe they write to a terminal (numba's
    typing errors in bold), so that a message quoting them reads as plain text."""
    return re.sub(r"\x1b\[[0-9;]*m", "", text)


def quoted(value: object, limit: int = QUOTED_LENGTH) -> str:
    """``value`` as a message shows a value it echoes: its ``repr`` (a path as its
    text, quoted), cut after ``limit`` characters with ``...`` (a 5000-character
    name would bury the message); :data:`QUOTED_PATH_LENGTH` for a path."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if isinstance(value, str):
        return repr(value) if len(value) <= limit else f"{value[:limit]!r}..."
    return cut(repr(value), limit)


def nearest(value: object, choices: Iterable[str]) -> str | None:
    """The choice closest to ``value`` (:func:`difflib.get_close_matches`, with
    case and ``_`` against ``-`` ignored), or None when none is close."""
    import difflib

    folded: dict[str, str] = {}
    for choice in choices:
        folded.setdefault(_folded(choice), choice)
    close = difflib.get_close_matches(_folded(str(value)), list(folded), n=1)
    return folded[close[0]] if close else None


def _folded(name: str) -> str:
    return name.strip().lower().replace("_", "-")


def unknown_choice(
    value: object,
    choices: Iterable[str],
    what: str,
    *,
    alternative: str = "",
    hint: str | None = None,
) -> InputError:
    """The error for ``value``, which is none of ``choices``: the one message of
    every lookup by name in tumble,
    ``Expected WHAT to be one of a, b, c[, or ALTERNATIVE], got 'x'. Did you mean b?``

    Parameters
    ----------
    value : what was received; the message shows it with :func:`quoted`.
    choices : the names accepted, in the order the message lists them.
    what : what was expected, as the message names it (``"`method`"``, ``"the key"``).
    alternative : what else is accepted besides the names (``"a .toml file"``).
    hint : a sentence said instead of the nearest name (None: the nearest, if any).

    Examples
    --------
    >>> print(unknown_choice("strnag", ["rk4", "strang"], "`method`"))
    Expected `method` to be one of rk4, strang, got 'strnag'. Did you mean strang?
    >>> print(unknown_choice("top", ["gyroscope"], "the scenario", alternative="a .toml file"))
    Expected the scenario to be one of gyroscope, or a .toml file, got 'top'.
    """
    choices = list(choices)
    if hint is None:
        close = nearest(value, choices)
        hint = f"Did you mean {close}?" if close is not None else ""
    listed = ", ".join(choices) + (f", or {alternative}" if alternative else "")
    tail = f" {hint}" if hint else ""
    return InputError(f"Expected {what} to be one of {listed}, got {quoted(value)}.{tail}")
