"""``tumble run`` (a scenario into a run folder) and ``tumble sweep`` (many bodies into a store)."""

from __future__ import annotations

import contextlib
import dataclasses
import json
from collections.abc import Container, Iterator
from pathlib import Path
from typing import Annotated, Any

import typer

from tumble.cli.app import app, loading, run_command
from tumble.cli.progress import LazyProgress

__all__ = [
    "figure_workers",
    "new_run_folder",
    "run_scenario",
    "scenario_argument",
    "sweep",
    "warm_up",
    "without_outputs",
]


def scenario_argument(help_text: str) -> Any:
    """The argument naming a scenario: a built-in name or a file."""
    return typer.Argument(metavar="SCENARIO|FILE.toml", help=help_text, show_default=False)


@app.command("run")
def run_scenario(
    scenario: Annotated[
        str | None,
        scenario_argument(
            "A built-in scenario (see `tumble list`) or a scenario file; default: gyroscope."
        ),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            help="Run folder to write; default runs/NAME-YYYYmmdd-HHMMSS.",
            show_default=False,
        ),
    ] = None,
    force: Annotated[
        bool,
        typer.Option("--force", help="Replace the output folder if it holds an earlier run."),
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the run's summary as JSON on stdout.")
    ] = False,
    no_figures: Annotated[
        bool,
        typer.Option("--no-figures", help="Write no PNG figures (as [output] figures = false)."),
    ] = False,
    no_viewer: Annotated[
        bool, typer.Option("--no-viewer", help="Write no 3D viewer (as [output] viewer = false).")
    ] = False,
) -> None:
    """Simulate a scenario, compare with theory, and write a run folder with a report."""

    def work() -> None:
        from tumble.files import check_replaceable
        from tumble.locks import OutputLock
        from tumble.report import check_folder

        with contextlib.ExitStack() as claims:
            if output is not None:  # before anything else: say it at once
                claims.enter_context(OutputLock(output, "the run folder"))
                # --force replaces an earlier run's own folder only: never the
                # scenario being run, nor a file the run did not write.
                check_replaceable(
                    output,
                    "the run folder",
                    listed_in="summary.json",
                    inputs=[scenario] if scenario is not None and _is_path(scenario) else [],
                )
                check_folder(output, force)
            # Started first, so that importing matplotlib overlaps with the rest.
            workers = claims.enter_context(figure_workers(not no_figures))
            with loading():
                from tumble.report import write_run
                from tumble.scenario import load, run

                loaded = load(scenario)
            loaded = without_outputs(loaded, figures=not no_figures, viewer=not no_viewer)
            folder = output
            if folder is None:
                folder = claims.enter_context(new_run_folder(loaded.name))
                check_folder(folder, force)  # before simulating
            with LazyProgress(enabled=not quiet) as progress:
                result = run(loaded, progress=progress.steps)
                write_run(
                    result, folder, force=force, progress=progress.stage, figure_workers=workers
                )
        report = folder / "report.html"
        if as_json:
            summary = result.summary()
            summary["folder"] = str(folder)
            summary["report"] = str(report)
            summary["viewer"] = (
                str(folder / "viewer.html") if (folder / "viewer.html").exists() else None
            )
            typer.echo(json.dumps(summary, indent=2, allow_nan=False))
        elif not quiet:
            print_run(result, folder)

    run_command(work)


@app.command("warm-up")
def warm_up(
    scenarios: Annotated[
        list[str] | None,
        scenario_argument(
            "The scenarios to prepare for; default: gyroscope (what `tumble run` runs)."
        ),
    ] = None,
    every: Annotated[
        bool, typer.Option("--all", help="Prepare for every built-in scenario.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
) -> None:
    """Compile the kernels a run needs into numba's cache, and fill matplotlib's font
    cache, so that the first `tumble run` is as fast as the later ones (`make setup`
    runs it). Each scenario is run and its folder written to a temporary place."""

    def work() -> None:
        import tempfile
        import time

        from tumble.report import write_run
        from tumble.scenario import builtin_names, load, run

        names = builtin_names() if every else (scenarios or ["gyroscope"])
        with tempfile.TemporaryDirectory(prefix="tumble-warm-up-") as place:
            for name in names:
                start = time.perf_counter()
                loaded = load(name)
                write_run(run(loaded), Path(place) / loaded.name)
                if not quiet:
                    typer.echo(f"{loaded.name}: ready ({time.perf_counter() - start:.1f} s)")

    run_command(work)


@contextlib.contextmanager
def figure_workers(wanted: bool) -> Iterator[Any]:
    """Processes that draw the run's figures, started now so that importing
    matplotlib overlaps with loading and simulating the scenario
    (:class:`~tumble.report.charts.FigureWorkers`); None if no figures are
    ``wanted``."""
    if not wanted:
        yield None
        return
    from tumble.report.charts import FigureWorkers

    with FigureWorkers() as workers:
        yield workers


def without_outputs(loaded: Any, *, figures: bool, viewer: bool) -> Any:
    """``loaded`` (a :class:`~tumble.scenario.LoadedScenario`) with its figures or
    viewer turned off when ``figures`` or ``viewer`` is false."""
    output = loaded.spec.output
    if (figures or not output.figures) and (viewer or not output.viewer):
        return loaded
    changed = output.model_copy(
        update={"figures": output.figures and figures, "viewer": output.viewer and viewer}
    )
    return dataclasses.replace(loaded, spec=loaded.spec.model_copy(update={"output": changed}))


@app.command("sweep")
def sweep(
    file: Annotated[
        str,
        typer.Argument(
            metavar="FILE.toml",
            help="A sweep file, or a built-in sweep (see `tumble list`), e.g. flip-map.",
            show_default=False,
        ),
    ],
    output: Annotated[
        Path | None,
        typer.Option(
            "-o", "--output", help="Output folder; default sweep-NAME.", show_default=False
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            metavar="tcp://HOST:PORT",
            help="Run on an existing Dask cluster.",
            show_default=False,
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option(
            "--workers", help="Run on a local Dask cluster of N workers.", show_default=False
        ),
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Discard the results of a different sweep there.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the sweep's summary as JSON on stdout.")
    ] = False,
) -> None:
    """Run (or resume) a sweep over many bodies into a chunked Zarr store with a report."""

    def work() -> None:
        from tumble.report import write_sweep_report
        from tumble.sweep import load_sweep, run_sweep
        from tumble.sweep.engine import claim_folder, sweep_folder

        plan = load_sweep(file)
        folder = sweep_folder(plan, output)
        # Claimed until the report is written (run_sweep claims it too, and alone
        # would let another sweep in before the report).
        with claim_folder(folder):
            with LazyProgress(enabled=not quiet) as progress:
                progress.description = "chunks"
                summary = run_sweep(
                    plan,
                    folder,
                    workers=workers,
                    scheduler=scheduler,
                    force=force,
                    progress=progress.chunks,
                )
            write_sweep_report(summary)
        if as_json:
            typer.echo(json.dumps(summary.to_dict(), indent=2, allow_nan=False, default=str))
        elif not quiet:
            rate = summary.body_steps_per_second
            speed = f", {rate:.3g} body-steps/s" if rate else ""
            typer.echo(
                f"{summary.name}: {summary.bodies} bodies in {summary.chunks} chunks "
                f"({summary.chunks_run} run, {summary.chunks_reused} reused) on "
                f"{summary.backend}, {summary.seconds:.2f} s{speed}"
            )
            typer.echo(f"Results: {summary.folder}")
            typer.echo(f"Report: {summary.report}")

    run_command(work)


def _is_path(given: str) -> bool:
    """Whether ``given`` names something on disk (else a built-in's name)."""
    import os

    try:
        return os.path.lexists(given)
    except (OSError, ValueError):  # a name too long, a NUL: no file
        return False


def default_folder(name: str, passed: Container[Path] = ()) -> Path:
    """runs/NAME-YYYYmmdd-HHMMSS, with -2, -3, ... if that exists already (or is
    in ``passed``)."""
    import time

    base = Path("runs") / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    folder, k = base, 1
    while folder.exists() or folder in passed:
        k += 1
        folder = base.with_name(f"{base.name}-{k}")
    return folder


@contextlib.contextmanager
def new_run_folder(name: str) -> Iterator[Path]:
    """A new default run folder (:func:`default_folder`), claimed for the block
    (:class:`tumble.locks.OutputLock`): a name that another run started in the
    same second has claimed, or has written meanwhile, is passed over."""
    from tumble.errors import OutputInUseError
    from tumble.locks import OutputLock

    passed: set[Path] = set()
    while True:
        folder = default_folder(name, passed)
        passed.add(folder)
        claim = OutputLock(folder, "the run folder")
        try:
            claim.acquire()
        except OutputInUseError:
            continue
        if not folder.exists():
            break
        claim.release()
    try:
        yield folder
    finally:
        claim.release()


def print_run(result: Any, folder: Path) -> None:
    """The run's theory-vs-simulation table and drift, and where its files are."""
    import math

    from rich.console import Console
    from rich.table import Table

    console = Console()
    spec = result.scenario.spec
    traj = result.trajectory
    console.print(
        f"[bold]{spec.scenario.title or spec.scenario.name}[/bold]  "
        f"({traj.method}, {len(traj.t)} samples over {traj.t[-1]:.4g} s, {result.elapsed:.2f} s)",
        highlight=False,
    )
    if result.comparisons:
        table = Table(title=f"Theory ({result.theory}) vs simulation", title_justify="left")
        table.add_column("quantity")
        table.add_column("theory", justify="right")
        table.add_column("simulation", justify="right")
        table.add_column("relative error", justify="right")
        table.add_column("unit")
        for row in result.comparisons:
            error = row["relative_error"]
            table.add_row(
                row["quantity"],
                f"{row['theory']:.9g}",
                f"{row['measured']:.9g}",
                f"{error:.2e}" if math.isfinite(error) else "inf",
                row.get("unit", ""),
            )
        console.print(table)
    for note in result.notes:  # why nothing was compared, or what a reader should know
        console.print(f"Note: {note}", highlight=False, soft_wrap=True)
    from tumble.invariants import label

    parts = [f"{label(key)} {value:.2e}" for key, value in result.drift.items()]
    console.print(
        "Relative drift of the conserved quantities: " + (", ".join(parts) or "none conserved"),
        highlight=False,
    )
    console.print(f"Run folder: {folder}", highlight=False, soft_wrap=True)
    console.print(f"Report: {folder / 'report.html'}", highlight=False, soft_wrap=True)
