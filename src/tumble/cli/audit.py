"""``tumble audit``: the declared inertias of a robot description, judged."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tumble.cli.app import app, loading, run_command

if TYPE_CHECKING:
    from tumble.robots import Audit

__all__ = ["FINDINGS", "audit_robot"]

#: The exit code of an audit with findings of values no body has.
FINDINGS = 1


@app.command("audit")
def audit_robot(
    robot: Annotated[
        str, typer.Argument(metavar="ROBOT", help="A URDF (.urdf) or MJCF (.xml) file.")
    ],
    geometry: Annotated[
        str,
        typer.Option(
            "--geometry",
            metavar="collision|visual|none",
            help="The shapes the declared values are compared with (none: judged alone).",
        ),
    ] = "collision",
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the findings as JSON instead of a table.")
    ] = False,
    report: Annotated[
        Path | None,
        typer.Option(
            "--report",
            metavar="PAGE.html",
            help="Also write an HTML page: the links drawn in 3D as ellipsoids of equal "
            "inertia, coloured by finding, and the table.",
            show_default=False,
        ),
    ] = None,
    fix: Annotated[
        Path | None,
        typer.Option(
            "--fix",
            metavar="OUT",
            help="Write a corrected copy here: only the inertial lines of corrected links "
            "change; the source is never touched.",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Audit the declared inertia of every link: tensors no body has, slipped decimal
    points, massless links with shapes, values far from what the shapes give. Exit
    code 0 when no link has an error, 1 when some has, 2 for bad input."""
    errors = 0

    def work() -> None:
        nonlocal errors
        with loading():
            from tumble.robots import audit, load, write_corrected
            from tumble.robots.auditing import GEOMETRY_CHOICES

        if geometry not in GEOMETRY_CHOICES:
            from tumble.errors import unknown_choice

            raise unknown_choice(geometry, GEOMETRY_CHOICES, "--geometry")
        if fix is not None:
            from tumble.robots.fix import check_corrected_path

            check_corrected_path(Path(robot), fix)
        if report is not None:
            from tumble.files import check_output

            check_output(report, "the report", folder=False)
        result = audit(load(robot), geometry)
        errors = len(result.errors)
        if as_json:
            typer.echo(json.dumps(result.to_dict(), indent=2, ensure_ascii=False))
        else:
            _print_table(result)
        if report is not None:
            from tumble.report.robot import write_audit_page

            page = write_audit_page(result, report)
            if not as_json:
                typer.echo(f"Report: {page}")
        if fix is not None:
            written = write_corrected(result, fix)
            if not as_json:
                count = len(result.corrections())
                typer.echo(f"Corrected {count} link{'s' * (count != 1)} into {written}")

    run_command(work)
    if errors:
        raise typer.Exit(FINDINGS)


def _print_table(result: Audit) -> None:
    """A table of the links (declared mass and principal moments, the geometry's,
    the findings), then each finding's message."""
    from rich.console import Console
    from rich.table import Table

    console = Console(soft_wrap=False)
    robot = result.robot
    table = Table(title=f"{robot.name}: {len(robot.links)} links ({robot.path.name})")
    table.add_column("link")
    table.add_column("mass (kg)", justify="right")
    table.add_column("declared moments (kg·m²)", justify="right")
    if result.geometry != "none":
        table.add_column(f"{result.geometry} shapes' moments", justify="right")
    table.add_column("findings")
    codes: dict[str, list[str]] = {}
    for finding in result.findings:
        codes.setdefault(finding.link, []).append(finding.code)
    for summary in result.links:
        row = [summary.link, f"{summary.mass:.4g}", _moments(summary.moments)]
        if result.geometry != "none":
            row.append(
                "" if summary.geometry is None else _moments(summary.geometry.principal()[0])
            )
        found = codes.get(summary.link, [])
        row.append(", ".join(found) if found else "[green]ok[/green]")
        table.add_row(*row)
    console.print(table)
    for finding in result.findings:
        colour = {"error": "red", "warning": "yellow"}.get(finding.severity, "blue")
        fixed = f" → {_correction(finding.correction)}" if finding.correction else ""
        console.print(
            f"[{colour}]{finding.severity}[/{colour}] {finding.link} ({finding.code}): "
            f"{finding.message}{fixed}",
            highlight=False,
        )
    errors = len(result.errors)
    console.print(
        f"{errors} error{'s' * (errors != 1)}, "
        f"{len(result.findings) - errors} other finding{'s' * (len(result.findings) - errors != 1)}"
    )


def _moments(values: object) -> str:
    return " ".join(f"{v:.4g}" for v in values)  # type: ignore[attr-defined]


def _correction(correction: dict[str, object]) -> str:
    parts = []
    for name, value in correction.items():
        text = " ".join(f"{v:.6g}" for v in value) if isinstance(value, tuple) else f"{value:.6g}"
        parts.append(f'{name}="{text}"')
    return " ".join(parts)
