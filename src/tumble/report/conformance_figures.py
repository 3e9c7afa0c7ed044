"""The figures of a conformance result (:func:`tumble.conformance.run` and ``sweep``).

* ``energy`` — the relative energy error (E(t) − E0)/E0 of each engine against time;
* ``attitude`` — the attitude error against the exact attitude, rad, against time;
* ``convergence`` — for a sweep over two or more steps, the ω error against dt on
  log-log axes with the lines of order 1, 2 and 4;
* ``momentum-sphere`` — for a free body, each engine's path of the angular
  momentum in body axes on the unit sphere beside the exact polhode.

The time figures show each engine's run at the smallest step of a sweep. The
values come from :mod:`tumble.conformance.metrics`, so the figures show what
the table measures.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.charts import Chart, Line, Points, Sheet, draw, png

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from tumble.conformance import ConformanceResult, Run, Scenario

__all__ = ["CONFORMANCE_FIGURES", "circulation_axis", "conformance_figures", "exact_polhode"]

Array = NDArray[np.float64]

#: The figures by name, in the order a report shows them (each only where it applies).
CONFORMANCE_FIGURES = ("energy", "attitude", "convergence", "momentum-sphere")

#: Colours of the engines: more than the run report's six, since a table holds
#: a dozen engines or more (matplotlib's "tab10"); past ten the dash changes too.
PALETTE = (
    "#1f77b4",
    "#d62728",
    "#2ca02c",
    "#9467bd",
    "#ff7f0e",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)
DASHES = ("-", "--", ":")

#: Points of the exact polhode drawn over one period of ω(t).
POLHODE_SAMPLES = 720

#: Panels per row of the momentum sphere's small multiples.
COLUMNS = 4

#: Margins of the time and convergence figures: the legend stands right of the axes,
#: where a dozen engines' labels cover no line.
_MARGINS = {"left": 0.1, "right": 0.72, "top": 0.91, "bottom": 0.12}


def _style(k: int) -> tuple[str, str]:
    """The colour and dash of the k-th engine."""
    return PALETTE[k % len(PALETTE)], DASHES[(k // len(PALETTE)) % len(DASHES)]


def _finite(values: Array) -> Array:
    """``values`` with non-finite entries as NaN (matplotlib leaves a gap there)."""
    return np.where(np.isfinite(values), values, np.nan)


def _shown_runs(result: ConformanceResult) -> list[Run]:
    """The runs the time figures show: every run at the smallest dt of the result."""
    if not result.runs:
        return []
    smallest = min(one.dt for one in result.runs)
    return [one for one in result.runs if one.dt == smallest]


def _engine_styles(result: ConformanceResult) -> dict[str, tuple[str, str]]:
    """One colour and dash per engine, the same in every figure."""
    names = list(dict.fromkeys(one.engine for one in result.runs))
    return {name: _style(k) for k, name in enumerate(names)}


def _exact_attitudes(scenario: Scenario, runs: Sequence[Run]) -> dict[int, Array]:
    """The exact attitude at each run's sample times, by ``id`` of the run; the runs
    at one dt share their times (a failed run's are a prefix), so the reference is
    evaluated once for the longest."""
    exact: dict[int, Array] = {}
    longest = max(runs, key=lambda one: one.samples.t.size)
    times = longest.samples.t
    shared = scenario.reference(times)[1]
    for one in runs:
        t = one.samples.t
        if t.size <= times.size and np.array_equal(t, times[: t.size]):
            exact[id(one)] = shared[: t.size]
        else:
            exact[id(one)] = scenario.reference(t)[1]
    return exact


def _legend_outside(figure: Figure) -> None:
    axes = figure.axes[0]
    if axes.get_legend_handles_labels()[0]:
        axes.legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize="small", framealpha=0.8)


def _failure_points(runs: Sequence[Run], values: dict[int, Array], styles: Any) -> tuple:
    """A cross at the last finite value of each run that failed."""
    points = []
    for one in runs:
        finite = np.flatnonzero(np.isfinite(values[id(one)]))
        if math.isfinite(one.samples.failed_at) and finite.size:
            last = finite[-1]
            points.append(
                Points(
                    one.samples.t[last : last + 1],
                    values[id(one)][last : last + 1],
                    colour=styles[one.engine][0],
                    size=40.0,
                    marker="x",
                    on_top=True,
                )
            )
    return tuple(points)


def _time_lines(runs: Sequence[Run], values: dict[int, Array], styles: Any) -> tuple[Line, ...]:
    return tuple(
        Line(
            one.samples.t,
            values[id(one)],
            label=one.engine,
            colour=styles[one.engine][0],
            dash=styles[one.engine][1],
            width=1.2,
        )
        for one in runs
    )


def _dt_label(runs: Sequence[Run]) -> str:
    return f"dt = {runs[0].dt:.3g} s" if runs else ""


def energy_figure(result: ConformanceResult) -> bytes:
    """The relative energy error (E(t) − E0)/E0 of each engine against time, PNG."""
    from tumble.conformance.metrics import energies

    body = result.scenario.body
    runs = _shown_runs(result)
    styles = _engine_styles(result)
    values: dict[int, Array] = {}
    for one in runs:
        energy = energies(body, one.samples.quaternion, one.samples.omega)
        with np.errstate(divide="ignore", invalid="ignore"):
            values[id(one)] = _finite((energy - energy[0]) / energy[0])
    chart = Chart(
        f"Relative energy error (E − E₀)/E₀, {_dt_label(runs)} (symmetric log scale)",
        "t (s)",
        "(E − E₀)/E₀",
        lines=_time_lines(runs, values, styles),
        points=_failure_points(runs, values, styles),
        legend=None,
        title_size="medium",
    )
    figure = draw(Sheet((chart,), size=(10.0, 4.5), margins=_MARGINS))
    # A symmetric log scale: the errors span from round-off (1e-16) to order one, and
    # their sign matters (the explicit schemes gain energy, the implicit ones lose it),
    # which a log of |ΔE/E0| would hide. Below the linear threshold the axis is linear:
    # it is set a power of ten under the smallest engine's largest error, so that every
    # engine's line rises out of the linear band (at 1e-16 at least: round-off).
    peaks = [np.nanmax(np.abs(v)) for v in values.values() if np.any(np.isfinite(v))]
    positive = [p for p in peaks if p > 0.0]
    smallest = min(positive) if positive else 1e-12
    threshold = 10.0 ** math.floor(math.log10(min(max(smallest, 1e-16), 1e-3)))
    axes = figure.axes[0]
    axes.set_yscale("symlog", linthresh=threshold, linscale=0.5)
    axes.axhline(0.0, color="0.5", lw=0.6)
    _legend_outside(figure)
    return png(figure)


def attitude_figure(result: ConformanceResult) -> bytes:
    """The attitude error against the exact attitude (rad) of each engine against
    time, log scale, PNG."""
    from tumble.conformance.metrics import attitude_errors

    runs = _shown_runs(result)
    styles = _engine_styles(result)
    exact = _exact_attitudes(result.scenario, runs) if runs else {}
    values: dict[int, Array] = {}
    for one in runs:
        errors = _finite(attitude_errors(one.samples.quaternion, exact[id(one)]))
        # 0 at t = 0 (and wherever an engine is exact) has no place on a log axis.
        values[id(one)] = np.where(errors > 0.0, errors, np.nan)
    chart = Chart(
        f"Attitude error against the exact attitude, {_dt_label(runs)}",
        "t (s)",
        "attitude error (rad)",
        lines=_time_lines(runs, values, styles),
        points=_failure_points(runs, values, styles),
        legend=None,
        log_y=True,
        title_size="medium",
    )
    figure = draw(Sheet((chart,), size=(10.0, 4.5), margins=_MARGINS))
    _legend_outside(figure)
    return png(figure)


def convergence_figure(result: ConformanceResult) -> bytes:
    """The ω error relative to |ω0| against dt of each engine on log-log axes, with
    the lines of order 1, 2 and 4 and each engine's observed order, PNG."""
    table = result.table
    styles = _engine_styles(result)
    lines: list[Line] = []
    points: list[Points] = []
    for engine, rows in table.groupby("engine", sort=False):
        rows = rows.sort_values("dt")
        dt = rows["dt"].to_numpy(dtype=float)
        error = rows["omega_error_max"].to_numpy(dtype=float)
        error = np.where(np.isfinite(error) & (error > 0.0), error, np.nan)
        order = float(rows["order"].iloc[0]) if "order" in rows else math.nan
        shown = f"order {order:.2f}" if math.isfinite(order) else "order —"
        colour, dash = styles.get(str(engine), _style(0))
        lines.append(Line(dt, error, label=f"{engine} ({shown})", colour=colour, dash=dash))
        points.append(Points(dt, error, colour=colour, size=14.0))
    dts = np.unique(table["dt"].to_numpy(dtype=float))
    # The order lines pass through the engines' typical error at the largest dt
    # (the geometric mean), from where they fan out to the smaller steps.
    largest = table[table["dt"] == dts[-1]]["omega_error_max"].to_numpy(dtype=float)
    largest = largest[np.isfinite(largest) & (largest > 0.0)]
    anchor = float(np.exp(np.mean(np.log(largest)))) if largest.size else 1e-3
    edges = np.array([dts[0], dts[-1]])
    for slope, dash in ((1, ":"), (2, "--"), (4, "-.")):
        lines.append(
            Line(
                edges,
                anchor * (edges / dts[-1]) ** slope,
                label=f"slope {slope}",
                colour="0.45",
                dash=dash,
                width=0.9,
            )
        )
    chart = Chart(
        "Convergence: largest ω error / |ω₀| against the step",
        "dt (s)",
        "ω error / |ω₀|",
        lines=tuple(lines),
        points=tuple(points),
        legend=None,
        log_y=True,
        title_size="medium",
    )
    figure = draw(Sheet((chart,), size=(10.0, 5.0), margins=_MARGINS))
    figure.axes[0].set_xscale("log")
    _legend_outside(figure)
    return png(figure)


def exact_polhode(scenario: Scenario, horizon: float) -> Array:
    """The exact L/|L(0)| (L = Iω, principal body axes) over one period of ω(t), (n, 3):
    the closed curve of the polhode on the unit sphere. On the separatrix, where the
    period is infinite, over ``horizon`` (s) instead."""
    from tumble.theory import flip_period

    period = flip_period(scenario.moments, scenario.initial_state[1])
    span = period if math.isfinite(period) and period > 0.0 else horizon
    omega = scenario.reference(np.linspace(0.0, span, POLHODE_SAMPLES))[0]
    return _unit_of_first(omega * scenario.moments)


def _reach(points: Array) -> float:
    """The largest |coordinate| of the finite points (0 for none)."""
    finite = np.abs(points[np.all(np.isfinite(points), axis=1)])
    return float(finite.max()) if finite.size else 0.0


def _unit_of_first(momentum: Array) -> Array:
    """``momentum`` over the size of its first row (itself for a body at rest)."""
    size = float(np.linalg.norm(momentum[0]))
    return momentum / size if size > 0.0 and math.isfinite(size) else momentum


def circulation_axis(polhode: Array, moments: Array) -> int:
    """The principal axis L circulates about: of the axes whose component of L keeps
    its sign along the exact polhode, the one it stays farthest from zero on (the
    major axis on the separatrix, where none does)."""
    keeps = [k for k in range(3) if np.all(polhode[:, k] > 0) or np.all(polhode[:, k] < 0)]
    if not keeps:
        return int(np.argmax(moments))
    return max(keeps, key=lambda k: float(np.min(np.abs(polhode[:, k]))))


def momentum_sphere_figure(result: ConformanceResult) -> bytes:
    """Each engine's path of L/|L(0)| in body axes (L = I ω) beside the exact polhode,
    one panel per engine, seen along the axis L circulates about, PNG."""
    from matplotlib.figure import Figure

    # An orthographic view along the axis the exact polhode circles: the whole closed
    # curve is seen at once, without the perspective, hidden back and tiny size of a
    # 3-D sphere in small multiples; any drift of energy or |L| shows as a path leaving
    # the polhode, and a gain of |L| as one leaving the unit circle. The one thing a projection
    # hides, the far hemisphere, is where an engine's L goes only after it has crossed
    # a separatrix (a false flip): that part is drawn dotted. 2-D panels also draw
    # far faster than 3-D ones, which matters for a dozen engines.
    scenario = result.scenario
    moments = scenario.moments
    runs = _shown_runs(result)
    styles = _engine_styles(result)
    horizon = max(float(one.samples.t[-1]) for one in runs)
    exact = exact_polhode(scenario, horizon)
    k = circulation_axis(exact, moments)
    side = 1.0 if exact[0, k] >= 0.0 else -1.0
    # Seen from the +k side the axes (k+1, k+2) stand right-handed; from −k swapped.
    i, j = ((k + 1) % 3, (k + 2) % 3) if side > 0 else ((k + 2) % 3, (k + 1) % 3)
    columns = min(COLUMNS, len(runs))
    rows = math.ceil(len(runs) / columns)
    height = 3.0 * rows + 0.8
    figure = Figure(figsize=(max(2.9 * columns + 0.4, 7.5), height))
    figure.subplots_adjust(
        left=0.08, right=0.98, top=1.0 - 0.75 / height, bottom=0.45 / height, wspace=0.5, hspace=0.4
    )
    circle = np.linspace(0.0, 2.0 * np.pi, 181)
    names = "₁₂₃"
    for n, one in enumerate(runs):
        axes = figure.add_subplot(rows, columns, n + 1)
        momentum = _unit_of_first(_finite(one.samples.omega * moments))
        near = side * momentum[:, k] >= 0.0
        colour = styles[one.engine][0]
        axes.plot(np.cos(circle), np.sin(circle), color="0.75", lw=0.6)
        axes.plot(
            np.where(near, momentum[:, i], np.nan),
            np.where(near, momentum[:, j], np.nan),
            color=colour,
            lw=1.0,
        )
        if not np.all(near):
            far = ~near
            axes.plot(
                np.where(far, momentum[:, i], np.nan),
                np.where(far, momentum[:, j], np.nan),
                color=colour,
                lw=1.0,
                ls=":",
            )
        # The exact polhode over the engine's path: where they agree, black dashes on colour.
        axes.plot(exact[:, i], exact[:, j], color="k", lw=0.9, ls="--", zorder=3)
        axes.scatter(momentum[:1, i], momentum[:1, j], color="k", s=10, zorder=3)
        # Each panel frames the exact polhode and the engine's path: a stable spin's
        # polhode is a small loop round the pole, lost at the sphere's scale. The whole
        # circle shows once the paths reach past most of it; a blow-up runs off the panel.
        reach = max(_reach(exact[:, [i, j]]), _reach(momentum[:, [i, j]]))
        limit = min(max(1.25 * reach, 1e-3), 1.6)
        if limit > 0.8:
            limit = max(limit, 1.08)
            axes.set(xticks=(-1.0, 0.0, 1.0), yticks=(-1.0, 0.0, 1.0))
        else:  # few ticks: fewer labels draw faster
            axes.locator_params(nbins=3)
        axes.set(xlim=(-limit, limit), ylim=(-limit, limit), aspect="equal")
        axes.set_xlabel(f"L{names[i]}/|L₀|", fontsize="small")
        axes.set_ylabel(f"L{names[j]}/|L₀|", fontsize="small")
        axes.tick_params(labelsize="x-small")
        axes.set_title(one.engine, fontsize="small")
        axes.grid(alpha=0.3)
    figure.suptitle(
        f"L/|L₀| = Iω/|L₀| in body axes on the unit sphere, seen along principal axis {k + 1} "
        f"from its {'+' if side > 0 else '−'} side, {_dt_label(runs)}\n"
        "engine: coloured (dotted on the far hemisphere); exact polhode: black dashes",
        fontsize="medium",
    )
    return png(figure)


def conformance_figures(result: ConformanceResult) -> dict[str, bytes]:
    """The figures of a conformance result as PNG bytes by name (see
    :data:`CONFORMANCE_FIGURES`): ``energy`` and ``attitude`` (at the smallest dt),
    ``convergence`` for a sweep over two or more steps, ``momentum-sphere`` for a
    free body; none when no engine ran."""
    if not result.runs:
        return {}
    figures = {"energy": energy_figure(result), "attitude": attitude_figure(result)}
    table = result.table
    if "order" in table.columns and table["dt"].nunique() >= 2:
        figures["convergence"] = convergence_figure(result)
    if result.scenario.body.pivot is None:
        figures["momentum-sphere"] = momentum_sphere_figure(result)
    return figures
