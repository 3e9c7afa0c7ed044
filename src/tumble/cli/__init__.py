"""The ``tumble`` command line: load → validate → call the library → print.

User errors print one line on stderr and exit with code 2; ``--debug`` shows
the traceback instead. Heavy imports live inside the commands so that
``tumble --help`` is instant. One module per group of commands:
:mod:`~tumble.cli.inertia`, :mod:`~tumble.cli.runs` (run, sweep),
:mod:`~tumble.cli.catalogue` (list, show), :mod:`~tumble.cli.fit`.
"""

from __future__ import annotations

import gc
import sys
from typing import Any

import typer

from tumble.cli import audit, catalogue, conform, fit, inertia, runs  # noqa: F401 - registers the commands
from tumble.cli.app import USER_ERROR, app

__all__ = ["USER_ERROR", "app", "main"]


def _click_exceptions() -> Any:
    """The click exception classes typer raises: recent typer vendors its own click."""
    try:
        from typer._click import exceptions
    except ImportError:  # typer that uses the click package
        from click import exceptions  # type: ignore[no-redef]
    return exceptions


def main() -> None:
    """Entry point of the ``tumble`` script: usage errors, too, are one line and exit code 2."""
    try:
        _main()
    finally:
        # What is left is freed as the process ends: moved out of the collector's
        # sight, it is not searched for cycles first (0.3 s after a run, most of it
        # numba's compiled code; 0.04 s frozen).
        gc.freeze()


def _main() -> None:
    click = _click_exceptions()
    try:
        # Without standalone mode click returns the code of a typer.Exit instead of exiting.
        code = app(prog_name="tumble", standalone_mode=False)
    except click.NoArgsIsHelpError as exc:
        typer.echo(exc.format_message())
        sys.exit(0)
    except click.UsageError as exc:
        hint = f" (see: tumble {exc.ctx.info_name} --help)" if exc.ctx and exc.ctx.parent else ""
        typer.echo(f"error: {exc.format_message()}{hint}", err=True)
        sys.exit(USER_ERROR)
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except typer.Abort:
        typer.echo("aborted", err=True)
        sys.exit(130)
    sys.exit(code if isinstance(code, int) else 0)
