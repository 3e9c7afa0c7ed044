"""``tumble fit --windows FILE`` or ``--all``: one body fitted to many throws of a
recording, each alone and all together, with a forecast of each throw's held-out end."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from tumble.cli.app import loading

if TYPE_CHECKING:
    from tumble.identification import JointFit, ThrowFits
    from tumble.identification.recordings import Recording

__all__ = [
    "HOLD_OUT",
    "ThrowProgress",
    "check_modes",
    "concise",
    "fit_throws",
    "print_throws",
    "with_error",
]

#: The share of each window held out for the forecast when ``--hold-out`` is not given.
HOLD_OUT = 0.4

#: Characters of a refusal's reason printed below the table of the throws.
REASON_LENGTH = 160


def check_modes(window: str | None, windows: Path | None, every: bool, hold_out: Any) -> bool:
    """Whether the options ask for the many-throw fit; one line for a mix of the
    options of one throw and of many (``--window``, ``--windows``, ``--all``), and for
    ``--hold-out`` without many throws or outside [0, 0.9)."""
    from tumble.errors import InputError

    given = [
        name
        for name, on in (
            ("--window", window is not None),
            ("--windows", windows is not None),
            ("--all", every),
        )
        if on
    ]
    if len(given) > 1:
        raise InputError(
            f"Expected one of --window, --windows and --all, got {' and '.join(given)}."
        )
    many = windows is not None or every
    if hold_out is not None:
        if not many:
            raise InputError(
                f"Expected --hold-out with --windows or --all (a fit of many throws), got "
                f"--hold-out {hold_out!r} alone."
            )
        if not 0.0 <= hold_out < 0.9:
            raise InputError(f"Expected --hold-out a fraction in [0, 0.9), got {hold_out!r}.")
    return many


class ThrowProgress:
    """A rich progress bar over the throws on stderr (none when not ``enabled``), as
    :func:`tumble.identify_many`'s progress callback."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled
        self.bar: Any = None
        self.task: Any = None

    def __enter__(self) -> ThrowProgress:
        if self.enabled:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
            )

            self.bar = Progress(
                TextColumn("fitting throws"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                console=Console(stderr=True),
                transient=True,
            )
            self.bar.start()
            self.task = self.bar.add_task("throws", total=None)
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()

    def __call__(self, done: int, total: int) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=done, total=total)


def fit_throws(
    recording: str | None,
    *,
    columns: str | None,
    units: str | None,
    windows: Path | None,
    bias: bool,
    loss: str,
    torque: str,
    hold_out: float | None,
    output: Path | None,
    force: bool,
    figures: bool,
    quiet: bool,
) -> None:
    """The many-throw fit of ``tumble fit``: checked, fitted, written, printed. The
    output folder is checked by the caller first."""
    with loading():
        from tumble.cli.runs import default_folder
        from tumble.identification.many import identify_many
        from tumble.identification.recordings import rate_unit, read_recording
        from tumble.identification.throws import example_throws_path
        from tumble.identification.validation import check_loss, check_torque
        from tumble.identification.windows import read_windows
        from tumble.report.fit import fit_name
        from tumble.report.fit_many import write_many

    check_loss(loss, "--loss")
    check_torque(torque, "--torque")
    rate_unit(units, "--units")
    spans = read_windows(windows) if windows is not None else None
    path = Path(recording) if recording is not None else example_throws_path()
    source = str(path) if recording is not None else path.name
    measured = read_recording(path, columns, units)
    share = HOLD_OUT if hold_out is None else hold_out
    with ThrowProgress(not quiet) as progress:
        many = identify_many(
            measured.t,
            measured.omega,
            spans,
            bias=bias,
            loss=loss,
            torque=torque,
            hold_out=share,
            progress=progress,
        )
    folder = output if output is not None else default_folder(fit_name(source))
    settings = {
        "loss": loss,
        "torque_asked": torque,
        "windows_found": spans is None,
        "windows_file": str(windows) if windows is not None else None,
    }
    write_many(
        many, measured, folder, source=source, settings=settings, figures=figures, force=force
    )
    if quiet:
        return
    if recording is None:
        typer.echo(
            f"No recording given: fitted the many-throw example shipped with tumble, {path} "
            "(synthetic_throws(12, seed=0) of tumble.identification)."
        )
    print_throws(many, measured, source, folder)


def print_throws(many: ThrowFits, measured: Recording, source: str, folder: Path) -> None:
    """The table of the throws, the joint fit with its standard errors and its choice
    of torque, the medians of the forecast errors, and where the files are."""
    from rich.console import Console

    console = Console()
    t = measured.t
    console.print(
        f"[bold]Fit of {len(many.windows)} throws of {source}[/bold]  ({len(t)} samples over "
        f"{t[-1] - t[0]:.4g} s)",
        highlight=False,
    )
    if measured.note:
        console.print(f"note: {measured.note}", highlight=False, soft_wrap=True)
    console.print(_throws_table(many))
    for row in many.table.itertuples():
        if not row.fitted:
            reason = str(row.reason)
            shown = reason if len(reason) <= REASON_LENGTH else reason[: REASON_LENGTH - 1] + "…"
            how = "refused alone, fitted under the joint body" if row.in_joint else "refused"
            console.print(f"throw {row.throw} {how}: {shown}", highlight=False, soft_wrap=True)
    joint = many.joint
    if joint is None:
        console.print(f"No joint fit: {many.joint_refusal}", highlight=False, soft_wrap=True)
    else:
        console.print(_joint_table(joint))
        console.print(f"Torque: {joint.choice}", highlight=False, soft_wrap=True)
    if many.hold_out > 0:
        console.print(
            f"Forecast of the held-out last {100 * many.hold_out:.3g} % of each throw, median "
            f"error: {_percent(many.forecast_errors)} by the joint body of the first parts, "
            f"{_percent(many.single_forecast_errors)} by each throw's first part alone",
            highlight=False,
            soft_wrap=True,
        )
    console.print(f"Fit folder: {folder}", highlight=False, soft_wrap=True)
    console.print(f"Report: {folder / 'report.html'}", highlight=False, soft_wrap=True)
    if joint is not None:
        console.print(
            f"Replay: tumble run {folder / 'fitted-scenario.toml'}", highlight=False, soft_wrap=True
        )


def _throws_table(many: ThrowFits) -> Any:
    """A rich table of the throws, a row each: its window, its fit (its torque, or
    refused, or joined), its ratios with their errors, residual over the noise,
    forecast error and whether it is an outlier."""
    import math

    from rich import box
    from rich.table import Table

    table = Table(
        title="Throws, each fitted alone (fit: its torque, or refused; ratios as "
        "value(standard error in its last digits))",
        title_justify="left",
        box=box.SIMPLE_HEAD,
        padding=(0, 1),
        pad_edge=False,
        collapse_padding=True,
    )
    for name in ("#", "window (s)", "fit", "I1/I3", "I2/I3", "res/σ", "forecast", "outlier"):
        wraps = name == "fit"
        table.add_column(
            name,
            justify="left" if wraps else "right",
            no_wrap=not wraps,
            min_width=7 if wraps else None,
        )
    for row in many.table.itertuples():
        ratios = [
            concise(value, error) if row.fitted else ""
            for value, error in ((row.r1, row.r1_error), (row.r2, row.r2_error))
        ]
        table.add_row(
            str(row.throw),
            f"{row.start:.4g}–{row.end:.4g}",
            str(row.torque) if row.fitted else ("joined" if row.in_joint else "refused"),
            *ratios,
            f"{row.noise_ratio:.2f}" if row.fitted else "",
            f"{100 * row.forecast_error:.2g} %" if math.isfinite(row.forecast_error) else "",
            "yes" if row.outlier else "",
        )
    return table


def _joint_table(joint: JointFit) -> Any:
    """A rich table of the joint fit: the ratios and the drag with their standard
    errors, the residual and the noise, the bias and the outliers."""
    from rich.table import Table

    summary = Table(
        title=f"Joint fit of {len(joint.throws)} throws (moments ascending)",
        title_justify="left",
    )
    for name, justify in (
        ("quantity", "left"),
        ("value", "right"),
        ("± std. error", "right"),
        ("unit", "left"),
    ):
        summary.add_column(name, justify=justify)  # type: ignore[arg-type]
    for k, name in enumerate(("I1/I3", "I2/I3")):
        summary.add_row(name, *with_error(joint.moment_ratios[k], joint.uncertainty[k]), "")
    for k in range(joint.torque_parameters.size):
        value, error = with_error(joint.torque_parameters[k], joint.torque_uncertainty[k])
        summary.add_row(f"c{k + 1}/I3 ({joint.torque})", value, error, joint.torque_units)
    summary.add_row("residual rms", f"{joint.residual_rms:.3g}", "", "rad/s")
    summary.add_row("sensor noise σ", f"{joint.noise:.3g}", "", "rad/s")
    for k, axis in enumerate("xyz"):
        summary.add_row(f"bias {axis}", f"{joint.bias[k]:.4g}", "", "rad/s")
    outliers = ", ".join(str(i + 1) for i in joint.outliers) or "none"
    summary.add_row("outliers", outliers, "", "")
    return summary


def concise(value: float, error: float) -> str:
    """``value(error)``: the value to the decimals of its standard error's two
    significant digits, and that error in units of its last digit."""
    import math

    shown, _ = with_error(value, error)
    if not (error > 0 and math.isfinite(error)):
        return shown
    decimals = len(shown.partition(".")[2])
    return f"{shown}({round(error * 10**decimals)})"


def _percent(errors: Any) -> str:
    """The median of the finite forecast errors in %, or "none" when there is none."""
    import numpy as np

    finite = np.asarray(errors)[np.isfinite(errors)]
    return f"{100 * float(np.median(finite)):.2g} %" if finite.size else "none"


def with_error(value: float, error: float) -> tuple[str, str]:
    """A value to the decimals its standard error's two significant digits have,
    and that error."""
    import math

    decimals = 6 if not error > 0 else min(max(1 - math.floor(math.log10(error)), 0), 12)
    return f"{value:.{decimals}f}", f"{error:.2g}"
