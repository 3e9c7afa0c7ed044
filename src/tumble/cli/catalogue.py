"""``tumble list`` and ``tumble show``: the built-in scenarios and sweeps."""

from __future__ import annotations

from typing import Annotated

import typer

from tumble.cli.app import app, run_command

__all__ = ["list_scenarios", "show_scenario"]


@app.command("list")
def list_scenarios() -> None:
    """The built-in scenarios (and example sweeps), one line each."""

    def work() -> None:
        from tumble.scenario import builtin_description, builtin_names
        from tumble.sweep import builtin_sweeps

        names = builtin_names()
        sweeps = builtin_sweeps()
        width = max(len(n) for n in [*names, *sweeps])
        for name in names:
            typer.echo(f"{name:<{width}}  {builtin_description(name)}")
        for name, text in sweeps.items():
            typer.echo(f"{name:<{width}}  sweep: {text}".rstrip())

    run_command(work)


@app.command("show")
def show_scenario(
    name: Annotated[str, typer.Argument(metavar="SCENARIO", help="A name from `tumble list`.")],
) -> None:
    """Print a built-in scenario as TOML, to copy and edit."""

    def work() -> None:
        from tumble.errors import InputError
        from tumble.scenario import builtin_names, builtin_text
        from tumble.sweep import builtin_sweeps, show_sweep

        scenarios, sweeps = builtin_names(), list(builtin_sweeps())
        if name in scenarios:
            typer.echo(builtin_text(name), nl=False)
        elif name in sweeps:
            typer.echo(show_sweep(name), nl=False)
        else:
            raise InputError(_not_builtin(name, scenarios, sweeps))

    run_command(work)


def _not_builtin(name: str, scenarios: list[str], sweeps: list[str]) -> str:
    """The message for a name ``tumble show`` does not know, with the nearest name,
    or, for a file of the user's, that only built-in files are shown."""
    from pathlib import Path

    from tumble.errors import nearest, unknown_choice

    path = Path(name)
    try:
        own_file = path.is_file()
    except OSError:  # a name too long for the system
        own_file = False
    names = [*scenarios, *sweeps]
    hint = None  # the nearest name, if any
    if own_file and not (path.suffix.lower() == ".toml" and nearest(path.stem, names)):
        hint = "That is a file of your own: `tumble show` prints the files tumble ships."
    return str(unknown_choice(name, names, "a built-in scenario or sweep", hint=hint))
