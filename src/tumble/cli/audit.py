"""``tumble audit``: the declared inertias of a robot description, judged."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from tumble.cli.app import app, loading, one_line, run_command
from tumble.cli.progress import LazyProgress

if TYPE_CHECKING:
    from tumble.robots import Audit

__all__ = ["FINDINGS", "audit_robot"]

#: The exit code of an audit with findings of values no body has.
FINDINGS = 1


@app.command("audit")
def audit_robot(
    robot: Annotated[
        str,
        typer.Argument(
            metavar="ROBOT",
            help="A URDF (.urdf), xacro (.urdf.xacro, .xacro) or MJCF (.xml) file, or a folder: "
            "every robot file under it is audited.",
        ),
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
        bool,
        typer.Option(
            "--json",
            help="Print the findings as JSON instead of a table; for a folder, one JSON object "
            "per line per file.",
        ),
    ] = False,
    report: Annotated[
        Path | None,
        typer.Option(
            "--report",
            metavar="PAGE.html",
            help="Also write an HTML page: the links drawn in 3D as ellipsoids of equal "
            "inertia, coloured by finding, and the table. A new file: never the robot file, "
            "a file it includes or reads (a mesh), or the --fix file. Not with a folder.",
            show_default=False,
        ),
    ] = None,
    fix: Annotated[
        Path | None,
        typer.Option(
            "--fix",
            metavar="OUT",
            help="Write a corrected copy here: only the inertial lines of corrected links "
            "change; the source is never touched. Not with a folder.",
            show_default=False,
        ),
    ] = None,
    package: Annotated[
        list[str] | None,
        typer.Option(
            "--package",
            metavar="NAME=DIR",
            help="The folder of ROS package NAME, for $(find NAME) and package://NAME/ "
            "(repeat for more); looked up first, before the robot file's parent folders and "
            "ROS_PACKAGE_PATH.",
            show_default=False,
        ),
    ] = None,
    xacro_arg: Annotated[
        list[str] | None,
        typer.Option(
            "--xacro-arg",
            metavar="NAME=VALUE",
            help="The value of a xacro file's <xacro:arg> NAME (repeat for more).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Audit the declared inertia of every link: tensors no body has, slipped decimal
    points, massless links with shapes, values far from what the shapes give. A xacro
    file is expanded first (the xacro package). Exit code 0 when no link has an error,
    1 when some has, 2 for bad input. A folder: every .urdf, xacro file and MuJoCo .xml
    model under it (a xacro file that expands to no robot, one of macros meant to be
    included, is skipped and counted), then a summary table; exit code 1 when a file
    has an error or could not be read."""
    errors = 0

    def work() -> None:
        nonlocal errors
        with loading():
            from tumble.robots import audit
            from tumble.robots.auditing import GEOMETRY_CHOICES
            from tumble.robots.load import read_robot

        if geometry not in GEOMETRY_CHOICES:
            from tumble.errors import unknown_choice

            raise unknown_choice(geometry, GEOMETRY_CHOICES, "--geometry")
        packages = _pairs(package or [], "--package", "NAME=DIR", "'kuka_kr16_support=kuka_kr16'")
        arguments = _pairs(xacro_arg or [], "--xacro-arg", "NAME=VALUE", "'prefix=left_'")
        if Path(robot).is_dir():
            errors = _audit_folder(Path(robot), geometry, as_json, packages, arguments, fix, report)
            return
        outputs = _check_outputs(Path(robot), {"--report": report, "--fix": fix})
        if fix is not None:
            from tumble.robots.fix import check_corrected_path

            check_corrected_path(Path(robot), fix)
        if report is not None:
            from tumble.files import check_output

            check_output(report, "the report", folder=False)
        loaded = read_robot(robot, packages=packages, xacro_args=arguments)
        for source in loaded.sources[1:]:
            _refuse_alias(outputs, source, f"a file that {robot!r} includes")
        for reference in loaded.references:
            _refuse_alias(outputs, reference, f"a file that {robot!r} reads (a mesh...)")
        result = audit(loaded.robot, geometry)
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
            from tumble.robots import write_corrected

            written = write_corrected(result, fix)
            if not as_json:
                count = len(result.corrections())
                typer.echo(f"Corrected {count} link{'s' * (count != 1)} into {written}")

    run_command(work)
    if errors:
        raise typer.Exit(FINDINGS)


def _pairs(items: list[str], option: str, form: str, example: str) -> dict[str, str]:
    """Repeated ``NAME=VALUE`` options as a mapping; a malformed one, or a name given
    two different values, is refused (xacro's own ``NAME:=VALUE`` is taken too)."""
    from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted

    pairs: dict[str, str] = {}
    for item in items:
        name, equals, value = item.partition("=")
        name = name.removesuffix(":").strip()
        if not equals or not name or (option == "--package" and not value.strip()):
            raise InputError(
                f"Expected {option} {form}, e.g. {example}, got {quoted(item, QUOTED_PATH_LENGTH)}."
            )
        if name in pairs and pairs[name] != value:
            raise InputError(
                f"Expected one value for {option} {name}, got two: "
                f"{quoted(pairs[name], QUOTED_PATH_LENGTH)} and "
                f"{quoted(value, QUOTED_PATH_LENGTH)}."
            )
        pairs[name] = value
    return pairs


def _same(a: Path, b: Path) -> bool:
    """Whether two paths name one file (a link or another spelling of it included)."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one does not exist (yet): compare where they lead
        return Path(os.path.abspath(a)).resolve() == Path(os.path.abspath(b)).resolve()


def _check_outputs(robot: Path, outputs: dict[str, Path | None]) -> dict[str, Path]:
    """Refuse, before any work, an output that is the robot file or another output:
    writing it would destroy what it replaces. Returns the outputs given."""
    from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted

    given = {option: path for option, path in outputs.items() if path is not None}
    _refuse_alias(given, robot, "the audited file itself")
    names = list(given)
    for k, first in enumerate(names):
        for second in names[k + 1 :]:
            if _same(given[first], given[second]):
                raise InputError(
                    f"Expected {first} and {second} to name two files, got "
                    f"{quoted(str(given[second]), QUOTED_PATH_LENGTH)} for both: one would "
                    "replace the other."
                )
    return given


def _refuse_alias(outputs: dict[str, Path], source: Path, what: str) -> None:
    from tumble.errors import QUOTED_PATH_LENGTH, InputError, quoted

    for option, path in outputs.items():
        if _same(path, source):
            raise InputError(
                f"Expected {option} to name a new file, got {what}, "
                f"{quoted(str(source), QUOTED_PATH_LENGTH)}: the robot's files are never changed."
            )


class _FileProgress(LazyProgress):
    """The progress bar of a folder's audit: files done of the total."""

    def files(self, done: int, total: int, name: str) -> None:
        if self._show():
            self.bar.update(self.task, description=name, completed=done, total=total)


def _audit_folder(
    folder: Path,
    geometry: str,
    as_json: bool,
    packages: dict[str, str],
    arguments: dict[str, str],
    fix: Path | None,
    report: Path | None,
) -> int:
    """Audit every robot file under ``folder``: JSON lines or a summary table.
    Returns the count of files with an error or that could not be read."""
    import warnings

    from tumble.errors import InputError
    from tumble.robots import robot_files
    from tumble.robots.auditing import audit_robot
    from tumble.robots.load import NotARobot, read_robot, robot_kind
    from tumble.robots.ros import package_folders

    for option, path in (("--fix", fix), ("--report", report)):
        if path is not None:
            raise InputError(
                f"Expected {option} only with a robot file, got the folder {str(folder)!r}: "
                "audit a file alone to correct it or draw it."
            )
    folders = package_folders(packages)
    paths = list(robot_files(folder))
    records: list[dict[str, Any]] = []
    progress = _FileProgress(enabled=True)
    with progress:
        for done, path in enumerate(paths):
            progress.files(done, len(paths), str(path.relative_to(folder)))
            kind = robot_kind(path)
            record: dict[str, Any] = {"file": str(path)}
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    loaded = read_robot(
                        path,
                        packages=folders if kind != "MJCF" else None,
                        xacro_args=arguments if kind == "xacro" else None,
                    )
                    record = {"status": "audited", **audit_robot(loaded.robot, geometry).to_dict()}
                except NotARobot as error:
                    record.update(status="skipped", reason=" ".join(str(error).split()))
                except (InputError, OSError, MemoryError) as error:
                    record.update(status="unreadable", reason=" ".join(one_line(error).split()))
            record["warnings"] = [str(w.message) for w in caught]
            records.append(record)
            if as_json:
                typer.echo(json.dumps(record, ensure_ascii=False))
        progress.files(len(paths), len(paths), "done")
    if not as_json:
        _print_summary(folder, records)
    return sum(r["status"] == "unreadable" or r.get("errors", 0) > 0 for r in records)


def _print_summary(folder: Path, records: list[dict[str, Any]]) -> None:
    """The summary of a folder's audit: files, links, errors by code, and the files
    with errors, skipped, or that could not be read."""
    from rich.console import Console
    from rich.table import Table

    console = Console(soft_wrap=False)
    audited = [r for r in records if r["status"] == "audited"]
    skipped = [r for r in records if r["status"] == "skipped"]
    unreadable = [r for r in records if r["status"] == "unreadable"]
    codes: dict[str, list[int]] = {}
    for record in audited:
        for finding in record["findings"]:
            counts = codes.setdefault(finding["code"], [0, 0])
            counts[finding["severity"] != "error"] += 1
    table = Table(title=f"{folder}: {len(records)} robot files")
    table.add_column("")
    table.add_column("count", justify="right")
    table.add_row("files audited", str(len(audited)))
    table.add_row("links", str(sum(r["links"] for r in audited)))
    table.add_row("files with errors", str(sum(r["errors"] > 0 for r in audited)))
    for severity, column in (("[red]error[/red]", 0), ("other", 1)):
        for code, counts in sorted(codes.items()):
            if counts[column]:
                table.add_row(f"  {severity} {code}", str(counts[column]))
    table.add_row("skipped (no robot: xacro macros)", str(len(skipped)))
    table.add_row("could not be read", str(len(unreadable)))
    console.print(table)
    flagged = [r for r in audited if r["errors"]]
    if flagged:
        files = Table(title="Files with errors")
        files.add_column("file", overflow="fold")
        files.add_column("errors", justify="right")
        files.add_column("codes")
        for record in flagged:
            found = sorted({f["code"] for f in record["findings"] if f["severity"] == "error"})
            files.add_row(
                _relative(folder, record["file"]), str(record["errors"]), ", ".join(found)
            )
        console.print(files)
    if unreadable:
        files = Table(title="Files that could not be read")
        files.add_column("file", overflow="fold")
        files.add_column("reason", overflow="fold")
        for record in unreadable:
            files.add_row(_relative(folder, record["file"]), record["reason"])
        console.print(files, highlight=False)
    errors = sum(r["errors"] for r in audited)
    console.print(
        f"{len(audited)} file{'s' * (len(audited) != 1)} audited: {errors} "
        f"error{'s' * (errors != 1)} in {len(flagged)} file{'s' * (len(flagged) != 1)}; "
        f"{len(unreadable)} could not be read, {len(skipped)} skipped",
        highlight=False,
    )


def _relative(folder: Path, file: str) -> str:
    return str(Path(file).relative_to(folder))


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
