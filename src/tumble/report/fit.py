"""The folder of a fit of a body to a gyroscope's recording (``tumble fit``).

* :func:`fit_summary` — every fitted value, its uncertainty and the
  covariance, as JSON-ready data (``fit.json``).
* :func:`fitted_scenario` — a scenario file that replays the fitted motion
  with ``tumble run`` (``fitted-scenario.toml``).
* :func:`fit_sheets` — the figures: measured and fitted ω(t), the residuals,
  and the polhode of the fitted body with the measured points on it.
* :func:`write_fit` — the folder with all of them.

Rates alone fix only the ratios of the moments, not their size: the fitted
body is given a mass of 1 kg and the moments ``(I1/I3, I2/I3, 1)`` kg·m², in
its principal axes, which are its body axes. Any other size of the moments
turns in the same way.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.charts import COLOURS, Chart, Line, Points, Sheet, Wireframe

if TYPE_CHECKING:
    from tumble.identification import BodyFit
    from tumble.identification.recordings import Recording

__all__ = [
    "FIT_FIGURES",
    "FIT_FILES",
    "check_fit_folder",
    "draw_fit_sheet",
    "fit_folder",
    "fit_name",
    "fit_sheets",
    "fit_summary",
    "fitted_scenario",
    "write_fit",
]

Array = NDArray[np.float64]

#: The figures of a fit folder (each ``NAME.png``), besides its other files.
FIT_FIGURES = ("omega", "residuals", "polhode")

#: The files of a fit folder; ``fit.json`` is written last, so a folder that
#: holds it is complete.
FIT_FILES = ("fitted-scenario.toml", *(f"{name}.png" for name in FIT_FIGURES), "fit.json")

#: Samples of the fitted polhode drawn over one period of ω(t).
POLHODE_SAMPLES = 600


def fit_name(source: str | os.PathLike[str]) -> str:
    """A scenario and folder name for the fit of the recording ``source``:
    ``STEM-fit``, letters, digits, '-', '_' and '.' only."""
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "-", Path(source).stem).strip("-_.")[:56]
    return f"{stem or 'recording'}-fit"


def _physical_moments(fit: BodyFit) -> tuple[Array, bool]:
    """``(I1/I3, I2/I3, 1)``, with I1/I3 raised to 1 − I2/I3 where noise put the
    ratios just outside the triangle inequality (the nearest physical body, a
    flat plate, as the fit's flip period takes); and whether it was."""
    r1, r2 = (float(v) for v in fit.moment_ratios)
    raised = r1 + r2 < 1.0
    return np.array([1.0 - r2 if raised else r1, r2, 1.0]), raised


def fit_summary(
    fit: BodyFit,
    recording: Recording,
    source: str,
    *,
    noise: float,
    found: bool,
    loss: str,
) -> dict[str, Any]:
    """The fit as JSON-ready data: the recording read, the window, every fitted
    value with its standard error, the covariance of the parameters, the
    residual against the sensor's ``noise`` (rad/s), and the conventions.
    ``found``: the window was found (not given); ``loss``: the loss fitted."""
    errors = np.sqrt(np.abs(np.diag(fit.covariance)))
    fitted_bias = fit.bias_fitted
    period = float(fit.flip_period)
    return {
        "recording": source,
        "columns": list(recording.columns),
        "note": recording.note,
        "samples": int(recording.t.size),
        "window": [float(fit.window[0]), float(fit.window[1])],
        "window_samples": int(fit.t.size),
        "window_found": found,
        "loss": loss,
        "moment_ratios": fit.moment_ratios.tolist(),
        "moment_ratios_standard_error": fit.uncertainty.tolist(),
        "principal_axes": fit.axes.tolist(),
        "omega0": fit.omega0.tolist(),
        "omega0_standard_error": errors[5:8].tolist(),
        "bias": fit.bias.tolist(),
        "bias_standard_error": errors[8:11].tolist() if fitted_bias else None,
        "bias_fitted": fitted_bias,
        "flip_period": period if math.isfinite(period) else None,
        "residual_rms": float(fit.residual_rms),
        "noise": float(noise),
        "fit_note": fit.note,
        "torque": fit.torque,
        "torque_parameters": fit.torque_parameters.tolist(),
        "torque_parameters_standard_error": fit.torque_uncertainty.tolist(),
        "torque_units": fit.torque_units,
        "torque_choice": fit.choice,
        "noise_ratio": float(fit.noise_ratio),
        "parameters": list(fit.parameter_names),
        "covariance": fit.covariance.tolist(),
        "units": {"time": "s", "rates": "rad/s", "moment_ratios": "1", "rotation": "rad"},
        "conventions": (
            "principal moments ascending, I1 <= I2 <= I3, as ratios to I3; principal_axes: "
            "the principal axes as columns in the sensor's axes (a proper rotation); omega0: "
            "the angular velocity at window[0] in the principal axes; bias: in the sensor's "
            "axes; covariance: of the parameters named, r1 and r2 the ratios, rx, ry, rz a "
            "small rotation of the axes about the fitted principal axes, w1..w3 omega0, "
            "bx..bz the bias, c1..c3 a drag's coefficients c_i / I3 per principal axis "
            "(torque drag: tau_i = -c_i w_i, 1/s; quadratic-drag: tau_i = -c_i w_i |w_i|, "
            "1/rad); flip_period: of the body without its torque, null on the separatrix "
            "(infinite)"
        ),
    }


def fitted_scenario(fit: BodyFit, name: str, source: str) -> str:
    """A scenario file (TOML) that replays the fitted motion: a body of 1 kg with
    the moments ``(I1/I3, I2/I3, 1)`` kg·m² in its principal (= body) axes,
    ω at t = 0 the fitted ω at the window's start, for the window's length, by
    the exact solution, with the flip-period check (the symmetric top's for a
    symmetric body). ``tumble run`` on it gives ω(t) in the fitted principal
    axes, t measured from the window's start."""
    from tumble.checks.free import SYMMETRY_TOLERANCE

    moments, raised = _physical_moments(fit)
    symmetric = bool(np.any(np.diff(moments) <= SYMMETRY_TOLERANCE * moments.sum()))
    r, e = fit.moment_ratios, fit.uncertainty
    start, end = fit.window
    shown = _escaped(Path(source).name)
    adjusted = (
        f"\nThe fitted ratios break the triangle inequality I1 + I2 >= I3 (their sum is "
        f"{float(r[0] + r[1]):.6g}):\nthe body has the nearest physical I1/I3 = 1 - I2/I3 "
        "(a flat plate)."
        if raised
        else ""
    )
    lines = [
        f"# The body and motion `tumble fit` fitted to {_escaped(source)}.",
        "# Replay it with `tumble run` and this file's path.",
        "",
        "[scenario]",
        f"name = {json.dumps(name)}",
        f"title = {json.dumps(f'Body fitted to {Path(source).name}')}",
        'description = """',
        f"The {'torque-free ' if fit.torque == 'free' else ''}body fitted to the recording "
        f"{shown}, samples of",
        f"{start:.6g} to {end:.6g} s: I1/I3 = {r[0]:.5f} ± {e[0]:.2g}, "
        f"I2/I3 = {r[1]:.5f} ± {e[1]:.2g}.",
        "Rates fix only the ratios of the moments: the body has a mass of 1 kg and the",
        "moments (I1/I3, I2/I3, 1) kg·m² in its principal axes, which are its body axes",
        "(the columns of principal_axes in fit.json, in the sensor's axes); any other",
        "size turns in the same way. ω at t = 0 is the fitted ω at the window's start;",
        f"t = 0 is {start:.6g} s of the recording.{adjusted}",
        '"""',
        "",
        "[body]",
        "mass = 1.0   # kg",
        f"inertia = {_numbers(moments)}   # principal moments, kg·m²",
        "",
        "[initial]",
        f"omega = {_numbers(fit.omega0)}   # rad/s, body axes",
        "",
        *_torque_lines(fit),
        "[simulation]",
        f"duration = {float(end - start)!r}   # s",
        'method = "exact"' if fit.torque == "free" else 'method = "adaptive"',
        "",
        "[theory]",
        f'model = "{_theory(fit, symmetric)}"',
        "",
        "[output]",
        f"samples = {min(max(int(fit.t.size), 100), 100_000)}",
        "",
    ]
    return "\n".join(lines)


def _torque_lines(fit: BodyFit) -> list[str]:
    """The ``[[torques]]`` table of a fitted drag: with I3 = 1 kg·m² the coefficients
    c_i / I3 are the coefficients in N·m·s (N·m·s² for quadratic drag), and the body's
    axes are the principal axes, so tumble's drag model of that name replays it."""
    if fit.torque == "free":
        return []
    unit = "N·m·s" if fit.torque == "drag" else "N·m·s²"
    return [
        "[[torques]]",
        f'type = "{fit.torque}"',
        f"coefficients = {_numbers(fit.torque_parameters)}   # {unit}, principal axes",
        "",
    ]


def _theory(fit: BodyFit, symmetric: bool) -> str:
    """The closed form a replay is checked against: none under drag (no closed form)."""
    if fit.torque != "free":
        return "none"
    return "free-symmetric-top" if symmetric else "flip-period"


def _numbers(values: Array) -> str:
    """A TOML array of floats, each with the digits that give it back exactly."""
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def _escaped(text: str) -> str:
    """``text`` as it may stand inside a TOML string or comment: quotes,
    backslashes and control characters escaped as JSON (and TOML) escape them."""
    return json.dumps(text, ensure_ascii=False)[1:-1]


# ------------------------------------------------------------------ figures
def fit_sheets(fit: BodyFit, recording: Recording, noise: float) -> dict[str, Sheet]:
    """The figures of a fit by name (:data:`FIT_FIGURES`): ω(t) measured over the
    whole recording and fitted over the window (sensor axes); the residuals in
    the window against the sensor's ``noise`` σ (rad/s); and the polhode of the
    fitted body. The window's shading is added as the first is drawn
    (:func:`draw_fit_sheet`)."""
    return {
        "omega": _omega_sheet(fit, recording),
        "residuals": _residuals_sheet(fit, noise),
        "polhode": _polhode_sheet(fit),
    }


def _omega_sheet(fit: BodyFit, recording: Recording) -> Sheet:
    predicted = fit.predicted(fit.t)
    lines = []
    for k, axis in enumerate("xyz"):
        lines.append(
            Line(
                recording.t,
                recording.omega[:, k],
                label=f"ω_{axis} measured",
                colour=COLOURS[k],
                width=0.8,
            )
        )
    for k in range(3):
        lines.append(
            Line(
                fit.t,
                predicted[:, k],
                label="fitted (+ bias)" if k == 0 else None,
                colour="k",
                width=1.2,
                dash="--",
            )
        )
    chart = Chart(
        f"Angular velocity, sensor axes: measured, and fitted in the window "
        f"{fit.window[0]:.4g}–{fit.window[1]:.4g} s (shaded)",
        "t (s)",
        "ω (rad/s)",
        lines=tuple(lines),
        title_size="medium",
    )
    return Sheet((chart,), size=(9.0, 4.5))


def _residuals_sheet(fit: BodyFit, noise: float) -> Sheet:
    residuals = fit.residuals
    lines = [
        Line(fit.t, residuals[:, k], label=f"ω_{axis}", colour=COLOURS[k], width=0.7)
        for k, axis in enumerate("xyz")
    ]
    edges = np.array([fit.t[0], fit.t[-1]])
    for sign in (1.0, -1.0):
        lines.append(
            Line(
                edges,
                np.full(2, sign * noise),
                label="± sensor noise σ" if sign > 0 else None,
                colour="0.3",
                width=1.2,
                dash="--",
            )
        )
    chart = Chart(
        f"Residuals, measured − fitted, sensor axes: rms {fit.residual_rms:.3g} rad/s, "
        f"noise σ {noise:.3g} rad/s",
        "t (s)",
        "residual (rad/s)",
        lines=tuple(lines),
        title_size="medium",
    )
    return Sheet((chart,), size=(9.0, 4.0))


def _polhode_sheet(fit: BodyFit) -> Sheet:
    """The fitted body's L = I ω in its principal axes (I3 = 1 kg·m²) over one
    period of ω(t) (the window, on the separatrix) on its energy ellipsoid, and
    the measured rates less the bias, turned into the principal axes, times the
    moments."""
    moments, _ = _physical_moments(fit)
    start, end = fit.window
    period = float(fit.flip_period)
    span = period if math.isfinite(period) else end - start
    times = start + np.linspace(0.0, span, POLHODE_SAMPLES)
    fitted = fit.principal_rates(times) * moments
    measured = ((fit.measured - fit.bias) @ fit.axes) * moments
    energy = 0.5 * float(np.sum(fitted[0] ** 2 / moments))
    semi = np.sqrt(2.0 * energy * moments)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 36), np.linspace(0, np.pi, 18))
    surface = Wireframe(
        semi[0] * np.cos(u) * np.sin(v), semi[1] * np.sin(u) * np.sin(v), semi[2] * np.cos(v)
    )
    aspect = semi / semi.max() if semi.max() > 0 else np.ones(3)
    chart = Chart(
        "Polhode of the fitted body: L in principal axes (I3 = 1 kg·m²)",
        "L₁ (kg·m²/s)",
        "L₂ (kg·m²/s)",
        zlabel="L₃ (kg·m²/s)",
        wireframes=(surface,),
        lines=(
            Line(
                fitted[:, 0],
                fitted[:, 1],
                fitted[:, 2],
                label="fitted",
                colour=COLOURS[1],
                width=1.5,
            ),
        ),
        points=(
            Points(
                measured[:, 0],
                measured[:, 1],
                measured[:, 2],
                label="measured − bias",
                size=3.0,
                on_top=True,
            ),
        ),
        legend="upper left",
        box_aspect=(aspect[0], aspect[1], aspect[2]),
        title_size="medium",
    )
    margins = {"left": 0.02, "right": 0.93, "top": 0.93, "bottom": 0.08}
    return Sheet((chart,), size=(7.0, 6.5), margins=margins)


def draw_fit_sheet(name: str, sheet: Sheet, window: tuple[float, float]) -> bytes:
    """A figure of :func:`fit_sheets` as PNG bytes; the ω(t) figure with the
    window fitted shaded (a sheet has no shading of its own)."""
    from tumble.report.charts import draw, png

    figure = draw(sheet)
    if name == "omega":
        figure.axes[0].axvspan(window[0], window[1], color="0.9", zorder=0)
    return png(figure)


# ------------------------------------------------------------------ the folder
def check_fit_folder(folder: str | os.PathLike[str], force: bool) -> None:
    """Refuse, before any work, a fit folder that cannot be written (or replaced
    whole), or that holds files unless ``force``; with ``force``, one that holds
    files but no ``fit.json`` (other work) too (:func:`tumble.report.check_folder`)."""
    from tumble.report import check_folder

    check_folder(folder, force, kind="fit", marker="fit.json")


def write_fit(
    fit: BodyFit,
    recording: Recording,
    folder: str | os.PathLike[str],
    *,
    source: str,
    noise: float,
    found: bool = True,
    loss: str = "linear",
    figures: bool = True,
    force: bool = False,
) -> Path:
    """Write the fit folder: ``fitted-scenario.toml``, the PNG figures (unless
    ``figures`` is false) and ``fit.json`` (last: a folder that holds it is
    complete). The folder is filled under a temporary name beside ``folder``
    and renamed (:func:`tumble.locks.staged_folder`); with ``force`` an earlier
    fit there is replaced whole. The folder is claimed first
    (:class:`tumble.locks.OutputLock`): another process writing it is refused,
    and what a killed writer left beside it is removed. ``source`` names the
    recording; ``noise``, ``found`` and ``loss`` go into ``fit.json``
    (:func:`fit_summary`).

    Raises
    ------
    tumble.report.RunFolderExistsError
        The folder holds files and ``force`` is false, or holds other files
        than a fit's.
    tumble.OutputInUseError
        Another process (or thread) is writing ``folder``.
    tumble.errors.OutputError
        The folder cannot be written (checked first), or the file system fails
        while writing: an earlier fit there is then unchanged.
    """
    from tumble.files import write_bytes, write_text

    target = Path(folder)
    check_fit_folder(target, force)
    name = fit_name(source)
    summary = fit_summary(fit, recording, source, noise=noise, found=found, loss=loss)
    images = (
        {
            key: draw_fit_sheet(key, sheet, fit.window)
            for key, sheet in fit_sheets(fit, recording, noise).items()
        }
        if figures
        else {}
    )
    summary["files"] = sorted(["fitted-scenario.toml", "fit.json", *(f"{k}.png" for k in images)])
    with fit_folder(target, force) as staging:
        write_text(staging / "fitted-scenario.toml", fitted_scenario(fit, name, source))
        for key, image in images.items():
            write_bytes(staging / f"{key}.png", image)
        write_text(staging / "fit.json", json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return target


@contextmanager
def fit_folder(target: Path, force: bool) -> Iterator[Path]:
    """A staging folder whose files replace ``target`` whole when the block ends
    (:func:`tumble.locks.staged_folder`), under the folder's lock, checked again once
    locked (:func:`check_fit_folder`); the file system's errors as one
    :class:`tumble.errors.OutputError` naming the fit folder."""
    from tumble.errors import OutputError
    from tumble.files import output_error
    from tumble.locks import OutputLock, staged_folder

    try:
        with OutputLock(target, "the fit folder"):
            check_fit_folder(target, force)  # claimed: no other writer changes it now
            with staged_folder(target) as staging:
                yield staging
    except OSError as exc:
        raise output_error(exc, target, "the fit folder") from exc
    except OutputError as exc:
        if not isinstance(exc.cause, OSError):
            raise
        raise output_error(exc.cause, target, "the fit folder") from exc.cause
