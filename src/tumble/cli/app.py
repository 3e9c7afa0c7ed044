"""The ``tumble`` command line's application object and how a command runs.

Each command is: load → validate → call the library → print. User errors
print one line on stderr and exit with code 2; ``--debug`` shows the
traceback instead. Heavy imports live inside the commands so that
``tumble --help`` is instant.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator
from typing import Annotated, Any

import typer

__all__ = ["USER_ERROR", "State", "app", "loading", "run_command"]

app = typer.Typer(
    name="tumble",
    help="Rotation of rigid bodies: mass properties, angular momentum, torque, Euler's equations.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)

#: Exit code for errors in what the user asked for (bad values, missing files).
USER_ERROR = 2


class State:
    """Options of the whole command line."""

    debug = False


def _version(value: bool) -> None:
    if value:
        from tumble._version import __version__

        typer.echo(f"tumble {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks for errors.")] = False,
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version.")
    ] = False,
) -> None:
    State.debug = debug


def run_command(work: Any) -> None:
    """Run a command body: user errors become one line and exit code 2, warnings
    one line each. An error of the file system that the library did not name
    (``OSError``) and a request that ran out of memory (``MemoryError``) are
    one line and exit code 2 as well."""
    import warnings

    from tumble.errors import InputError

    error = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            work()
        except (InputError, OSError, MemoryError) as exc:
            if State.debug:
                raise
            error = one_line(exc)
        finally:  # the warnings first: the error, when there is one, is the last line
            for warning in caught:
                typer.echo(f"warning: {warning.message}", err=True)
    if error is not None:
        typer.echo(f"error: {error}", err=True)
        raise typer.Exit(USER_ERROR)


def one_line(exc: BaseException) -> str:
    """The message of a user error on one line."""
    from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted

    if isinstance(exc, MemoryError):
        return (
            f"Expected the request to fit in memory, got a MemoryError ({exc or 'no details'}): "
            "record fewer samples, or run a sweep, which streams its results to disk."
        )
    if isinstance(exc, OSError) and not isinstance(exc, InputError):
        where = quoted(exc.filename, QUOTED_PATH_LENGTH) if exc.filename else "the output"
        return f"Expected to read or write {where}, got: {exc.strerror or exc}."
    return str(exc)


@contextlib.contextmanager
def loading() -> Iterator[None]:
    """Around a command's imports and loading: the cyclic garbage collector off,
    then what they made moved out of its sight (``gc.freeze``) and the collector
    back on. Imports make about a million objects that live as long as the
    process and are no garbage: the collector would search them again and again
    (0.1 s of a 1 s run), and, frozen, they do not slow its later passes."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if enabled:
            gc.enable()
