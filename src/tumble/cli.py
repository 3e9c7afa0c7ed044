"""The ``tumble`` command line: load → validate → call the library → print.

User errors print one line on stderr and exit with code 2; ``--debug`` shows
the traceback instead. Heavy imports live inside the commands so that
``tumble --help`` is instant.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

if TYPE_CHECKING:
    from tumble.massprops import MassProperties

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

MESH_SUFFIXES = {".stl", ".obj", ".ply", ".glb", ".gltf", ".off"}


class _State:
    debug = False


def _version(value: bool) -> None:
    if value:
        from tumble import __version__

        typer.echo(f"tumble {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks for errors.")] = False,
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version.")
    ] = False,
) -> None:
    _State.debug = debug


# Options shared by the shapes; each maps to the shape function's parameter of the same name.
_SHAPE_OPTIONS = (
    "radius",
    "inner_radius",
    "outer_radius",
    "height",
    "length",
    "size",
    "semi_axes",
    "major_radius",
    "minor_radius",
    "cylinder_height",
    "edge",
)


@app.command()
def inertia(
    body: Annotated[
        str,
        typer.Argument(
            metavar="SHAPE-or-MESH",
            help="A solid (box, solid-cylinder, hollow-cylinder, solid-sphere, spherical-shell, "
            "hollow-sphere, solid-cone, thin-rod, thin-disk, thin-ring, ellipsoid, torus, capsule, "
            "regular-tetrahedron) or a mesh file (STL, OBJ, PLY, GLB).",
        ),
    ],
    mass: Annotated[str | None, typer.Option(help="Mass, e.g. '250 g' (SI if no unit).")] = None,
    density: Annotated[
        str | None, typer.Option(help="Density of a mesh, e.g. '2700 kg/m^3'.")
    ] = None,
    units: Annotated[
        str | None, typer.Option(help="Length unit of a mesh file, e.g. 'mm'.")
    ] = None,
    radius: Annotated[str | None, typer.Option(help="Radius, e.g. '3 cm'.")] = None,
    inner_radius: Annotated[str | None, typer.Option(help="Inner radius.")] = None,
    outer_radius: Annotated[str | None, typer.Option(help="Outer radius.")] = None,
    height: Annotated[str | None, typer.Option(help="Height along the axis (z).")] = None,
    length: Annotated[str | None, typer.Option(help="Length of a thin rod.")] = None,
    size: Annotated[
        str | None, typer.Option(help="Box edges along x, y, z, e.g. '10, 20, 30 cm'.")
    ] = None,
    semi_axes: Annotated[
        str | None, typer.Option(help="Ellipsoid semi-axes, e.g. '1, 2, 3 cm'.")
    ] = None,
    major_radius: Annotated[
        str | None, typer.Option(help="Torus: radius of the tube's centre circle.")
    ] = None,
    minor_radius: Annotated[str | None, typer.Option(help="Torus: radius of the tube.")] = None,
    cylinder_height: Annotated[
        str | None, typer.Option(help="Capsule: height of the cylindrical part.")
    ] = None,
    edge: Annotated[str | None, typer.Option(help="Edge of a regular tetrahedron.")] = None,
    about: Annotated[
        str | None,
        typer.Option(help="Also give the inertia about this body point, e.g. '0, 0, -5 cm'."),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Mass, centre of mass, inertia tensor, principal moments and axes of a solid or a mesh."""
    options = {
        "radius": radius,
        "inner_radius": inner_radius,
        "outer_radius": outer_radius,
        "height": height,
        "length": length,
        "size": size,
        "semi_axes": semi_axes,
        "major_radius": major_radius,
        "minor_radius": minor_radius,
        "cylinder_height": cylinder_height,
        "edge": edge,
    }
    given = {k: v for k, v in options.items() if v is not None}

    def work() -> None:
        from tumble.units import vector_to_si

        label, mp = _build_body(body, mass=mass, density=density, units=units, dimensions=given)
        point = vector_to_si(about, "length", "--about") if about is not None else None
        if as_json:
            typer.echo(json.dumps(_inertia_json(label, mp, point), indent=2))
        else:
            _print_inertia(label, mp, point)

    _run(work)


# ------------------------------------------------------------------ scenarios
@app.command("run")
def run_scenario(
    scenario: Annotated[
        str | None,
        typer.Argument(
            metavar="SCENARIO|FILE.toml",
            help="A built-in scenario (see `tumble list`) or a scenario file; default: gyroscope.",
            show_default=False,
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
        bool, typer.Option("--force", help="Replace the output folder if it holds files.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the run's summary as JSON on stdout.")
    ] = False,
) -> None:
    """Simulate a scenario, compare with theory, and write a run folder with a report."""

    def work() -> None:
        from tumble.report import check_folder, write_run
        from tumble.scenario import load, run

        loaded = load(scenario)
        folder = output if output is not None else _default_folder(loaded.name)
        check_folder(folder, force)  # before simulating: say it at once
        with _LazyProgress(enabled=not quiet) as progress:
            result = run(loaded, progress=progress.steps)
            write_run(result, folder, force=force, progress=progress.stage)
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
            _print_run(result, folder)

    _run(work)


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
        from tumble.sweep import run_sweep

        with _LazyProgress(enabled=not quiet) as progress:
            progress.description = "chunks"
            summary = run_sweep(
                file,
                output,
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

    _run(work)


def _default_folder(name: str) -> Path:
    """runs/NAME-YYYYmmdd-HHMMSS, with -2, -3, ... if that exists already."""
    import time

    base = Path("runs") / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    folder, k = base, 1
    while folder.exists():
        k += 1
        folder = base.with_name(f"{base.name}-{k}")
    return folder


class _LazyProgress:
    """A rich progress bar on stderr that appears only once a run has taken about a second."""

    DELAY = 1.0

    def __init__(self, enabled: bool) -> None:
        import time

        self.enabled = enabled
        self.start = time.monotonic()
        self.bar: Any = None
        self.task: Any = None
        self.description = "simulating"

    def __enter__(self) -> _LazyProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()

    def _show(self) -> bool:
        import time

        if not self.enabled:
            return False
        if self.bar is None and time.monotonic() - self.start > self.DELAY:
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                TextColumn("{task.percentage:>3.0f}%"),
                TimeElapsedColumn(),
                console=Console(stderr=True),
                transient=True,
            )
            self.bar.start()
            self.task = self.bar.add_task(self.description, total=None)
        return self.bar is not None

    def steps(self, done: int, total: int) -> None:
        """The library's progress callback: steps done of total."""
        if self._show():
            self.bar.update(self.task, description="simulating", completed=done, total=total)

    def chunks(self, done: int, total: int) -> None:
        """A sweep's progress callback: chunks done of total."""
        if self._show():
            self.bar.update(self.task, description="chunks", completed=done, total=total)

    def stage(self, name: str) -> None:
        """A stage of writing the run folder."""
        self.description = f"writing {name}"
        if self._show():
            self.bar.update(self.task, description=self.description, total=None)


def _print_run(result: Any, folder: Path) -> None:
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
    from tumble.body import label

    parts = [f"{label(key)} {value:.2e}" for key, value in result.drift.items()]
    console.print(
        "Relative drift of the conserved quantities: " + (", ".join(parts) or "none conserved"),
        highlight=False,
    )
    console.print(f"Run folder: {folder}", highlight=False, soft_wrap=True)
    console.print(f"Report: {folder / 'report.html'}", highlight=False, soft_wrap=True)


def _sweep_examples() -> dict[str, str]:
    """Example sweeps by name, with a one-line description, where tumble.sweep offers them."""
    import importlib

    try:
        found = importlib.import_module("tumble.sweep").builtin_sweeps()
    except (ImportError, AttributeError):
        return {}
    items: Any = (
        found.items()
        if isinstance(found, dict)
        else ((getattr(item, "name", item), item) for item in found)
    )
    examples = {}
    for name, value in items:
        text = (
            value
            if isinstance(value, str)
            else getattr(value, "title", None) or getattr(value, "description", "")
        )
        examples[str(name)] = str(text or "").strip().splitlines()[0] if text else ""
    return examples


@app.command("list")
def list_scenarios() -> None:
    """The built-in scenarios (and example sweeps), one line each."""

    def work() -> None:
        from tumble.scenario import builtin_description, builtin_names

        names = builtin_names()
        sweeps = _sweep_examples()
        width = max(len(n) for n in [*names, *sweeps])
        for name in names:
            typer.echo(f"{name:<{width}}  {builtin_description(name)}")
        for name, text in sweeps.items():
            typer.echo(f"{name:<{width}}  sweep: {text}".rstrip())

    _run(work)


@app.command("show")
def show_scenario(
    name: Annotated[str, typer.Argument(metavar="SCENARIO", help="A name from `tumble list`.")],
) -> None:
    """Print a built-in scenario as TOML, to copy and edit."""

    def work() -> None:
        from tumble.scenario import builtin_names, builtin_text

        if name not in builtin_names() and name in _sweep_examples():
            import importlib

            typer.echo(importlib.import_module("tumble.sweep").show_sweep(name), nl=False)
            return
        typer.echo(builtin_text(name), nl=False)

    _run(work)


def _run(work: Any) -> None:
    """Run a command body: user errors become one line and exit code 2, warnings one line each."""
    import warnings

    from tumble.errors import InputError

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            work()
        except InputError as exc:
            if _State.debug:
                raise
            typer.echo(f"error: {exc}", err=True)
            raise typer.Exit(USER_ERROR) from None
        finally:
            for warning in caught:
                typer.echo(f"warning: {warning.message}", err=True)


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


def _build_body(
    body: str,
    *,
    mass: str | None,
    density: str | None,
    units: str | None,
    dimensions: dict[str, str],
) -> tuple[str, MassProperties]:
    import inspect

    from tumble import shapes
    from tumble.errors import InputError
    from tumble.mesh import from_mesh

    shape_name = body.strip().lower().replace("-", "_")
    if shape_name in shapes.__all__:
        function = getattr(shapes, shape_name)
        parameters = [p for p in inspect.signature(function).parameters if p != "mass"]
        accepted = ", ".join(_option(p) for p in ["mass", *parameters])
        extra = [p for p in dimensions if p not in parameters]
        if density is not None or units is not None:
            extra += ["density"] if density is not None else []
            extra += ["units"] if units is not None else []
        if extra:
            raise InputError(f"Expected only {accepted} for {shape_name}, got {_option(extra[0])}.")
        missing = [
            p
            for p in ["mass", *parameters]
            if (p == "mass" and mass is None) or (p != "mass" and p not in dimensions)
        ]
        if missing:
            raise InputError(
                f"Expected {_option(missing[0])} for {shape_name} (it takes {accepted})."
            )
        return shape_name.replace("_", "-"), function(mass, **dimensions)
    path = Path(body)
    if path.suffix.lower() in MESH_SUFFIXES or path.exists():
        if dimensions:
            raise InputError(
                f"Expected --density or --mass (and --units) for a mesh, "
                f"got {_option(next(iter(dimensions)))}."
            )
        return str(path), from_mesh(path, density=density, mass=mass, units=units)
    import difflib

    close = difflib.get_close_matches(shape_name, shapes.__all__, n=1)
    hint = f" Did you mean {close[0].replace('_', '-')}?" if close else ""
    raise InputError(
        f"Expected a shape ({', '.join(s.replace('_', '-') for s in shapes.__all__)}) "
        f"or a mesh file, got {body!r}.{hint}"
    )


def _inertia_json(label: str, mp: MassProperties, point: Any) -> dict[str, Any]:
    moments, axes = mp.principal()
    result: dict[str, Any] = {
        "body": label,
        "mass": mp.mass,
        "center_of_mass": mp.center_of_mass.tolist(),
        "inertia": mp.inertia.tolist(),
        "principal_moments": moments.tolist(),
        "principal_axes": axes.tolist(),
        "units": {"mass": "kg", "length": "m", "inertia": "kg*m^2"},
        "conventions": "inertia about the centre of mass in body axes; I_xy = -sum(m x y); "
        "principal axes are the columns of principal_axes (det +1)",
    }
    if point is not None:
        result["about"] = {"point": point.tolist(), "inertia": mp.inertia_about(point).tolist()}
    return result


def _print_inertia(label: str, mp: MassProperties, point: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    moments, axes = mp.principal()

    console.print(f"[bold]Mass properties of {label}[/bold]", highlight=False)
    summary = Table(show_header=False)
    summary.add_column("quantity", style="bold")
    summary.add_column("value", justify="right")
    summary.add_column("unit")
    summary.add_row("mass", f"{mp.mass:.6g}", "kg")
    summary.add_row("centre of mass", _vector_text(mp.center_of_mass), "m (body coordinates)")
    console.print(summary)

    def tensor_table(title: str, tensor: Any) -> Table:
        scale = float(abs(tensor).max())
        console.print(f"[bold]{title}[/bold]", highlight=False)
        table = Table()
        table.add_column("")
        for axis in "xyz":
            table.add_column(axis, justify="right")
        for name, row in zip("xyz", tensor, strict=True):
            table.add_row(name, *(f"{_clean(v, scale):.6g}" for v in row))
        return table

    console.print(
        tensor_table("Inertia tensor about the centre of mass, body axes (kg·m²)", mp.inertia)
    )
    if point is not None:
        console.print(
            tensor_table(
                f"Inertia tensor about the point {_vector_text(point)} m (kg·m²)",
                mp.inertia_about(point),
            )
        )
    console.print("[bold]Principal moments (kg·m²) and axes (columns, body coordinates)[/bold]")
    principal = Table()
    principal.add_column("")
    for k in range(3):
        principal.add_column(f"I{k + 1}", justify="right")
    principal.add_row("moment", *(f"{v:.6g}" for v in moments), style="bold")
    for name, row in zip("xyz", axes, strict=True):
        principal.add_row(f"axis {name}", *(f"{_clean(v):.6f}" for v in row))
    console.print(principal)
    console.print("Products of inertia carry the minus sign: I_xy = −Σ m x y.", style="dim")


def _clean(value: float, scale: float = 1.0) -> float:
    """Show round-off (below 1e-12 of the scale) as 0 rather than as -1e-19."""
    return 0.0 if abs(value) <= 1e-12 * scale else float(value)


def _vector_text(vector: Any) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in vector) + "]"


def _click_exceptions() -> Any:
    """The click exception classes typer raises: recent typer vendors its own click."""
    try:
        from typer._click import exceptions
    except ImportError:  # typer that uses the click package
        from click import exceptions  # type: ignore[no-redef]
    return exceptions


def main() -> None:
    """Entry point of the ``tumble`` script: usage errors, too, are one line and exit code 2."""
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
