"""``tumble conform``: physics engines measured against the exact rotation of a rigid body."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from tumble.cli.app import app, loading, run_command
from tumble.cli.progress import LazyProgress

if TYPE_CHECKING:
    from tumble.conformance import ConformanceResult

__all__ = ["conform", "parse_numbers"]


@app.command("conform")
def conform(
    engines: Annotated[
        list[str] | None,
        typer.Option(
            "--engines",
            metavar="A,B",
            help="Engines as engine/variant names, comma-separated or repeated (a plain engine "
            "name: its default variant, or all its variants when it has no default; "
            "engine/*: all its variants). Default: every engine installed. --list shows them.",
            show_default=False,
        ),
    ] = None,
    scenario: Annotated[
        str,
        typer.Option(
            "--scenario",
            metavar="NAME",
            help="A built-in scenario: intermediate-slow, intermediate-fast, major-spin, "
            "minor-spin, symmetric-top, heavy-top.",
        ),
    ] = "intermediate-fast",
    dt: Annotated[
        list[str] | None,
        typer.Option(
            "--dt",
            metavar="DT",
            help='The step, s ("1 ms" works); several, comma-separated or repeated, make a '
            "sweep with each engine's observed order and largest safe step. [default: 1e-3]",
            show_default=False,
        ),
    ] = None,
    duration: Annotated[
        str | None,
        typer.Option(
            "--duration",
            metavar="T",
            help="The horizon, s. [default: the scenario's, 20 s]",
            show_default=False,
        ),
    ] = None,
    inertia: Annotated[
        str | None,
        typer.Option(
            "--inertia",
            metavar="I1,I2,I3",
            help='Your own body: its principal moments, kg·m² (units allowed: "1, 2, 3 g*m^2"); '
            "with --omega (or the scenario's ω0).",
            show_default=False,
        ),
    ] = None,
    omega: Annotated[
        str | None,
        typer.Option(
            "--omega",
            metavar="W1,W2,W3",
            help="Your own initial angular velocity in body axes, rad/s (with --inertia, or on "
            "the scenario's body).",
            show_default=False,
        ),
    ] = None,
    tolerance: Annotated[
        float,
        typer.Option("--tolerance", help="The energy and attitude error of a safe step (sweeps)."),
    ] = 1e-6,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the table as JSON lines instead of a table.")
    ] = False,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="FOLDER",
            help="Also write FOLDER: table.parquet, table.json, report.html (figures) and "
            "conformance.json.",
            show_default=False,
        ),
    ] = None,
    force: Annotated[
        bool,
        typer.Option("--force", help="Replace the output folder if it holds an earlier table."),
    ] = False,
    listing: Annotated[
        bool, typer.Option("--list", help="List the engines, installed or not, and the scenarios.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
) -> None:
    """Run physics engines on a rotating body whose exact motion is known and measure how far
    each drifts: energy, momentum, attitude, flips, failures (exit 2 for an engine that is not
    installed, an unknown scenario, or a dt or duration that cannot work)."""

    def work() -> None:
        with loading():
            from tumble import conformance

        if listing:
            _print_listing()
            return
        if output is not None:
            from tumble.report.conformance import check_conformance_folder

            check_conformance_folder(output, force)
        chosen = _scenario(scenario, inertia, omega)
        names = _chosen_engines(engines, chosen)
        steps = [step for text in (dt or ["1e-3"]) for step in parse_numbers(text, "--dt")]
        with LazyProgress(enabled=not (quiet or as_json)) as progress:
            if len(steps) == 1:
                result = conformance.run(names, chosen, steps[0], duration, progress=progress.steps)
            else:
                result = conformance.sweep(
                    names, chosen, steps, duration, tolerance=tolerance, progress=progress.steps
                )
            if output is not None:
                from tumble.report.conformance import write_conformance

                progress.stage("the report")
                write_conformance(result, output, force=force)
        if as_json:
            for record in result.table.to_dict(orient="records"):
                typer.echo(json.dumps({k: _plain(v) for k, v in record.items()}, allow_nan=False))
        elif not quiet:
            _print_result(result, output)

    run_command(work)


def parse_numbers(text: str, option: str) -> list[Any]:
    """The comma-separated values of an option ("1e-3, 5e-4" or "1 ms, 0.5 ms"), as given."""
    from tumble.errors import InputError

    parts = [part.strip() for part in str(text).split(",")]
    if not all(parts):
        raise InputError(f"Expected {option} to be values separated by commas, got {text!r}.")
    values: list[Any] = []
    for part in parts:
        try:
            values.append(float(part))
        except ValueError:
            values.append(part)  # a quantity with its unit, converted by the library
    return values


def _scenario(name: str, inertia: str | None, omega: str | None) -> Any:
    from tumble.conformance import Scenario, get_scenario
    from tumble.units import vector_to_si

    base = get_scenario(name)
    if inertia is None and omega is None:
        return base
    if base.pivot is not None:
        from tumble.errors import InputError

        raise InputError(
            f"Expected --inertia and --omega with a free body's scenario, got --scenario {name} "
            "(a body on a pivot)."
        )
    moments = base.moments if inertia is None else vector_to_si(inertia, "inertia", "--inertia")
    rates = base.omega0 if omega is None else vector_to_si(omega, "angular_velocity", "--omega")
    text = ", ".join(f"{value:g}" for value in moments)
    spin = ", ".join(f"{value:g}" for value in rates)
    description = f"I = ({text}) kg·m², ω0 = ({spin}) rad/s"
    return Scenario(moments, rates, base.duration, name="custom", description=description)


def _chosen_engines(engines: list[str] | None, scenario: Any) -> list[str] | None:
    """The engines asked for; an InputError for one that is named but not installed."""
    from tumble.conformance import unavailable
    from tumble.conformance.running import chosen_engines
    from tumble.errors import InputError

    if not engines:
        return None
    names = chosen_engines([name for text in engines for name in text.split(",") if name.strip()])
    for name in names:
        reason = unavailable(name, scenario)
        if reason.startswith("not installed"):
            raise InputError(f"Expected an installed engine, got {name}: {reason}.")
    return names


def _plain(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if hasattr(value, "item"):
        return _plain(value.item())
    return value


def _print_listing() -> None:
    from rich.console import Console
    from rich.table import Table

    from tumble.conformance import ENGINES, SCENARIOS
    from tumble.conformance.engine import missing_modules

    console = Console()
    table = Table(title="Engines", title_justify="left")
    for column in ("engine", "installed", "ω axes", "pivot", "what it runs"):
        table.add_column(column)
    for cls in ENGINES.values():
        missing = missing_modules(cls)
        for variant, summary in cls.variants.items():
            name = f"{cls.name}/{variant}" if variant else cls.name
            installed = "yes" if not missing else f"no: tumble[{cls.extra}]"
            table.add_row(
                name, installed, cls.omega_frame, "yes" if cls.holds_pivot else "no", summary
            )
    console.print(table)
    scenarios = Table(title="Scenarios", title_justify="left")
    scenarios.add_column("scenario")
    scenarios.add_column("body and initial state")
    for name, one in SCENARIOS.items():
        scenarios.add_row(name, one.description)
    console.print(scenarios)


#: The table's columns as the terminal shows them: header, column, format.
_COLUMNS = (
    ("energy drift", "energy_drift_final", "{:+.2e}"),
    ("max", "energy_drift_max", "{:+.2e}"),
    ("|L| drift", "momentum_drift_max", "{:+.1e}"),
    ("L dir. rad", "direction_drift_max", "{:.1e}"),
    ("attitude rad", "attitude_error_max", "{:.1e}"),
    ("ω error", "omega_error_max", "{:.1e}"),
    ("flips", "flips", "{:d}"),
    ("failed at s", "failed_at", "{:.3g}"),
    ("steps/s", "steps_per_second", "{:.3g}"),
)


def _print_result(result: ConformanceResult, output: Path | None) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    if not console.is_terminal:
        console.width = 160  # a file or a pipe: keep each row on one line
    scenario = result.scenario
    table = Table(
        title=f"{scenario.name}: {scenario.description}", title_justify="left", show_lines=False
    )
    sweep = "order" in result.table.columns
    table.add_column("engine")
    table.add_column("dt s", justify="right")
    for header, _, _ in _COLUMNS:
        table.add_column(header, justify="right")
    if sweep:
        table.add_column("order", justify="right")
        table.add_column("safe dt", justify="right")
    flips_exact = ""
    for row in result.table.to_dict(orient="records"):
        cells = [row["engine"], f"{row['dt']:g}"]
        for _, key, form in _COLUMNS:
            value = row[key]
            cells.append(
                "" if isinstance(value, float) and math.isnan(value) else form.format(value)
            )
        if sweep:
            cells += [f"{row['order']:.2f}", f"{row['safe_dt']:g}"]
        flips_exact = str(row["flips_exact"])
        style = "red" if math.isfinite(row["failed_at"]) else None
        table.add_row(*cells, style=style)
    console.print(table)
    if flips_exact:
        console.print(f"exact flips: {flips_exact}", highlight=False)
    for row in result.table.to_dict(orient="records"):
        if row["failure"]:
            console.print(f"{row['engine']} (dt {row['dt']:g}): {row['failure']}", highlight=False)
    for name, notes in result.notes.items():
        for note in notes:
            console.print(f"note: {name}: {note}", highlight=False)
    for name, reason in result.skipped.items():
        console.print(f"skipped: {name}: {reason}", highlight=False, soft_wrap=True)
    share = result.reference_seconds / max(result.engine_seconds, 1e-12)
    console.print(
        f"reference (closed form): {result.reference_seconds:.3g} s, {share:.2%} of the engines' "
        f"{result.engine_seconds:.3g} s",
        highlight=False,
    )
    if output is not None:
        console.print(f"Report: {output / 'report.html'}", highlight=False, soft_wrap=True)
