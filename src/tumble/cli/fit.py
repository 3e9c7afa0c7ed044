"""``tumble fit``: a body and its motion fitted to a gyroscope's recording."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from tumble.cli.app import app, loading, run_command

if TYPE_CHECKING:
    from tumble.identification import BodyFit
    from tumble.identification.recordings import Recording

__all__ = ["fit_recording", "parse_window"]


@app.command("fit")
def fit_recording(
    recording: Annotated[
        str | None,
        typer.Argument(
            metavar="RECORDING",
            help="A gyroscope recording: a CSV file (phyphox's export, or any with a time "
            "and three rate columns), phyphox's zip file, or a Parquet file; default: the "
            "example shipped with tumble.",
            show_default=False,
        ),
    ] = None,
    columns: Annotated[
        str | None,
        typer.Option(
            "--columns",
            metavar="T,WX,WY,WZ",
            help="The columns of t, ωx, ωy, ωz: four names or zero-based positions; default: "
            "a column named t or time… and the three after it.",
            show_default=False,
        ),
    ] = None,
    units: Annotated[
        str | None,
        typer.Option(
            "--units",
            metavar="rad/s|deg/s",
            help="Units of the rates when the header states none; default: rad/s, or deg/s "
            "for rates beyond 20 turns/s in rad/s.",
            show_default=False,
        ),
    ] = None,
    window: Annotated[
        str | None,
        typer.Option(
            "--window",
            metavar="START,END",
            help="The free flight to fit, in s of the recording; default: found.",
            show_default=False,
        ),
    ] = None,
    windows: Annotated[
        Path | None,
        typer.Option(
            "--windows",
            metavar="FILE.csv",
            help="Fit many throws of one body, each alone and all together: their free "
            "flights, a CSV file with columns start and end (s), one throw a row.",
            show_default=False,
        ),
    ] = None,
    every: Annotated[
        bool,
        typer.Option(
            "--all",
            help="Fit every free flight found in the recording, each alone and all together "
            "(default recording: the many-throw example shipped with tumble).",
        ),
    ] = False,
    hold_out: Annotated[
        float | None,
        typer.Option(
            "--hold-out",
            metavar="FRACTION",
            help="With --windows or --all: the share of each throw's end held out and "
            "forecast by the joint body of the rest (default 0.4; 0 for none).",
            show_default=False,
        ),
    ] = None,
    no_bias: Annotated[
        bool, typer.Option("--no-bias", help="Fit no sensor bias (for a sensor without one).")
    ] = False,
    loss: Annotated[
        str,
        typer.Option(
            "--loss",
            metavar="LOSS",
            help="The fit's loss: linear (least squares), or a robust loss of scipy's "
            "least_squares for outliers (soft_l1, huber, cauchy, arctan).",
        ),
    ] = "linear",
    torque: Annotated[
        str,
        typer.Option(
            "--torque",
            metavar="auto|free|drag|quadratic-drag",
            help="The torque the body flew under: free (the exact torque-free motion), drag "
            "(linear air drag per principal axis), quadratic-drag, or auto (torque-free when "
            "its residuals look like the noise, else the model of least BIC).",
        ),
    ] = "auto",
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            help="Folder to write; default runs/RECORDING-fit-YYYYmmdd-HHMMSS.",
            show_default=False,
        ),
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Replace the output folder if it holds an earlier fit.")
    ] = False,
    no_figures: Annotated[bool, typer.Option("--no-figures", help="Write no PNG figures.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")] = False,
) -> None:
    """Fit a body to a gyroscope's recording (a phone thrown spinning), torque-free or under
    air drag: its moment ratios, principal axes, motion and drag, with a scenario that
    replays it; with --windows or --all, to many throws at once, with a report."""

    def work() -> None:
        from tumble.cli.fit_many import check_modes, fit_throws
        from tumble.files import check_replaceable
        from tumble.report.fit import check_fit_folder

        many = check_modes(window, windows, every, hold_out)
        if output is not None:
            # Before anything else, to say it at once. --force replaces an earlier
            # fit's own folder only: never the recording being fitted, nor a file
            # the fit did not write.
            check_replaceable(
                output,
                "the fit folder",
                listed_in="fit.json",
                inputs=[path for path in (recording, windows) if path is not None],
            )
            check_fit_folder(output, force)
        common: dict[str, Any] = {
            "columns": columns,
            "units": units,
            "bias": not no_bias,
            "loss": loss,
            "torque": torque,
            "output": output,
            "force": force,
            "figures": not no_figures,
            "quiet": quiet,
        }
        if many:
            fit_throws(recording, windows=windows, hold_out=hold_out, **common)
        else:
            fit_window(recording, window=window, **common)

    run_command(work)


def fit_window(
    recording: str | None,
    *,
    columns: str | None,
    units: str | None,
    window: str | None,
    bias: bool,
    loss: str,
    torque: str,
    output: Path | None,
    force: bool,
    figures: bool,
    quiet: bool,
) -> None:
    """``tumble fit`` of one free flight: the recording read, the flight in ``window``
    (``START,END`` in s; None: found) fitted, the fit folder written and the fit
    printed (see :func:`fit_recording`)."""
    span = parse_window(window) if window is not None else None
    with loading():
        from tumble.cli.runs import default_folder
        from tumble.identification.fit import identify
        from tumble.identification.recordings import (
            example_recording_path,
            rate_unit,
            read_recording,
        )
        from tumble.identification.validation import check_loss, check_torque
        from tumble.report.fit import fit_name, write_fit

    # The library's own checks, before the recording is read: said at once.
    check_loss(loss, "--loss")
    check_torque(torque, "--torque")
    rate_unit(units, "--units")
    path = Path(recording) if recording is not None else example_recording_path()
    source = str(path) if recording is not None else path.name
    measured = read_recording(path, columns, units)
    fit = identify(measured.t, measured.omega, window=span, bias=bias, loss=loss, torque=torque)
    folder = output if output is not None else default_folder(fit_name(source))
    write_fit(
        fit,
        measured,
        folder,
        source=source,
        noise=fit.noise,
        found=span is None,
        loss=loss,
        figures=figures,
        force=force,
    )
    if quiet:
        return
    if recording is None:
        typer.echo(
            f"No recording given: fitted the example shipped with tumble, {path} (a phone "
            "thrown spinning about its intermediate axis: synthetic_phone(0) of "
            "tumble.identification)."
        )
    print_fit(fit, measured, source, folder, fit.noise, found=span is None)


def parse_window(text: str) -> tuple[float, float]:
    """``START,END`` in s, as ``--window`` gives it."""
    from tumble.errors import InputError

    try:
        start, end = (float(part) for part in text.split(","))
    except ValueError:
        raise InputError(f"Expected --window START,END in s (two numbers), got {text!r}.") from None
    return start, end


def print_fit(
    fit: BodyFit, measured: Recording, source: str, folder: Path, noise: float, *, found: bool
) -> None:
    """The fitted values with their standard errors, the residual against the
    sensor's noise, the principal axes, and where the files are."""
    import math

    import numpy as np
    from rich.console import Console
    from rich.table import Table

    from tumble.cli.fit_many import with_error

    console = Console()
    t = measured.t
    console.print(
        f"[bold]Fit of {source}[/bold]  ({len(t)} samples over {t[-1] - t[0]:.4g} s)",
        highlight=False,
    )
    for note in (measured.note, fit.note):
        if note:
            console.print(f"note: {note}", highlight=False, soft_wrap=True)
    how = "found: the free flight" if found else "as given"
    console.print(
        f"Window fitted: {fit.window[0]:.6g}–{fit.window[1]:.6g} s, {len(fit.t)} samples ({how})",
        highlight=False,
    )
    errors = np.sqrt(np.abs(np.diag(fit.covariance)))
    table = Table(title="Fitted body (moments ascending)", title_justify="left")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_column("± std. error", justify="right")
    table.add_column("unit")
    for k, name in enumerate(("I1/I3", "I2/I3")):
        table.add_row(name, f"{fit.moment_ratios[k]:.5f}", f"{fit.uncertainty[k]:.2g}", "")
    period = fit.flip_period
    table.add_row(
        "flip period", f"{period:.4g}" if math.isfinite(period) else "inf (separatrix)", "", "s"
    )
    if fit.torque != "free":
        for k in range(3):
            value, error = with_error(fit.torque_parameters[k], fit.torque_uncertainty[k])
            table.add_row(f"c{k + 1}/I3 ({fit.torque})", value, error, fit.torque_units)
    table.add_row("residual rms", f"{fit.residual_rms:.3g}", "", "rad/s")
    table.add_row("sensor noise σ", f"{noise:.3g}", "", "rad/s")
    for k, axis in enumerate("xyz"):
        if fit.bias_fitted:
            table.add_row(f"bias {axis}", *with_error(fit.bias[k], errors[8 + k]), "rad/s")
        else:
            table.add_row(f"bias {axis}", "0", "not fitted", "rad/s")
    for k in range(3):
        table.add_row(f"ω{k + 1} at start", *with_error(fit.omega0[k], errors[5 + k]), "rad/s")
    console.print(table)
    console.print(f"Torque: {fit.choice}", highlight=False, soft_wrap=True)
    console.print("Principal axes (columns) in the sensor's axes", style="italic")
    axes = Table()
    axes.add_column("")
    for k in range(3):
        axes.add_column(f"axis {k + 1}", justify="right")
    for name, row in zip("xyz", fit.axes, strict=True):
        axes.add_row(name, *(f"{v:.5f}" for v in row))
    console.print(axes)
    console.print(f"Fit folder: {folder}", highlight=False, soft_wrap=True)
    console.print(
        f"Replay: tumble run {folder / 'fitted-scenario.toml'}", highlight=False, soft_wrap=True
    )
