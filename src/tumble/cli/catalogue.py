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
        from tumble.scenario import builtin_names, builtin_text
        from tumble.sweep import builtin_sweeps, show_sweep

        if name not in builtin_names() and name in builtin_sweeps():
            typer.echo(show_sweep(name), nl=False)
            return
        typer.echo(builtin_text(name), nl=False)

    run_command(work)
