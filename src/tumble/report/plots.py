"""Static figures of a trajectory: each described as a :class:`~tumble.report.charts.Sheet`
(data only, so it can be drawn in a worker process) and drawn with matplotlib.

The ``*_sheet`` functions describe a figure; the ``*_figure`` functions return
it drawn, a ``matplotlib.figure.Figure`` made without pyplot, so nothing is
kept in a global figure registry and no window opens; notebooks show the
returned figures as images.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from tumble.report.charts import COLOURS, Chart, Line, Points, Sheet, Wireframe, draw, png

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from tumble.analysis import Herpolhode
    from tumble.checks import Panel
    from tumble.trajectory import Trajectory

__all__ = [
    "angular_momentum_figure",
    "drift_figure",
    "omega_figure",
    "panel_figure",
    "png_bytes",
    "polhode_figure",
    "rotors_figure",
    "trajectory_figures",
    "trajectory_sheets",
]


def _colour(k: int) -> str:
    """The colour of a chart's k-th series."""
    return COLOURS[k % len(COLOURS)]


def _components(t: np.ndarray, values: np.ndarray, symbol: str, frame: str) -> tuple[Line, ...]:
    """The three components of a vector over time, and its magnitude dashed."""
    lines = [
        Line(t, values[:, k], label=f"{symbol}_{name} ({frame})", colour=colour)
        for k, (name, colour) in enumerate(zip("xyz", COLOURS, strict=False))
    ]
    magnitude = np.linalg.norm(values, axis=1)
    return (*lines, Line(t, magnitude, label=f"|{symbol}|", colour="k", width=1.2, dash="--"))


def omega_sheet(traj: Trajectory) -> Sheet:
    """ω(t) in body axes, and |ω|."""
    chart = Chart(
        "Angular velocity in body axes",
        "t (s)",
        "ω (rad/s)",
        lines=_components(traj.t, traj.omega, "ω", "body"),
    )
    return Sheet((chart,))


def angular_momentum_sheet(traj: Trajectory) -> Sheet:
    """L(t) in space axes (about the centre of mass, or about the pivot), and |L|."""
    about = "the centre of mass" if traj.pivot is None else "the pivot"
    chart = Chart(
        f"Angular momentum about {about}, space axes",
        "t (s)",
        "L (kg·m²/s)",
        lines=_components(traj.t, traj.angular_momentum, "L", "space"),
    )
    return Sheet((chart,))


def drift_sheet(traj: Trajectory) -> Sheet:
    """Relative change from their initial values of the quantities the motion
    conserves (:meth:`tumble.Trajectory.relative_change`): the numerical error."""
    from tumble.invariants import label

    names = traj.conserved_quantities
    lines = tuple(
        Line(traj.t, traj.relative_change(name), label=label(name), colour=_colour(k))
        for k, name in enumerate(names)
    )
    chart = Chart(
        f"Drift of the conserved quantities (method {traj.method})",
        "t (s)",
        "relative change",
        lines=lines,
        legend="upper right" if names else None,
        scientific_y=True,
        note=None if names else "nothing is conserved in this motion",
    )
    return Sheet((chart,))


def polhode_sheet(traj: Trajectory) -> Sheet:
    """The polhode: L in principal body axes on the energy ellipsoid; for a
    torque-free rigid body, beside it the herpolhode (the Poinsot construction).

    Torque-free, L (body axes) stays on the sphere |L| = const and on the energy
    ellipsoid ``Σ L_i² / (2 E I_i) = 1``: its path is their intersection. Under
    torques the ellipsoid is drawn for the initial kinetic energy only as a guide.
    The herpolhode is ω in space on the invariable plane
    (:func:`tumble.analysis.herpolhode`), seen along L from the fixed point.
    """
    from tumble.analysis import herpolhode
    from tumble.errors import InputError
    from tumble.massprops import principal_decomposition

    try:
        plane = herpolhode(traj)
    except InputError:  # no fixed plane: the polhode alone
        plane = None
    mp = traj.mass_properties
    inertia = mp.inertia if traj.pivot is None else mp.inertia_about(traj.pivot)
    moments, frame = principal_decomposition(inertia)
    momentum = traj.body_momentum @ frame  # L in principal axes (the parts' included)
    kinetic = 0.5 * float(np.sum(momentum[0] ** 2 / moments))
    semi = np.sqrt(2.0 * kinetic * moments)
    wireframes: tuple[Wireframe, ...] = ()
    if not traj.internal:  # a gyrostat's energy surface is another ellipsoid, off centre
        u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 36), np.linspace(0, np.pi, 18))
        wireframes = (
            Wireframe(
                semi[0] * np.cos(u) * np.sin(v),
                semi[1] * np.sin(u) * np.sin(v),
                semi[2] * np.cos(v),
            ),
        )
    aspect = semi / semi.max() if semi.max() > 0 else np.ones(3)
    polhode = Chart(
        "Polhode: L in principal axes on the energy ellipsoid",
        "L₁",
        "L₂",
        zlabel="L₃",
        wireframes=wireframes,
        lines=(
            Line(
                momentum[:, 0],
                momentum[:, 1],
                momentum[:, 2],
                label="L (polhode)",
                colour=COLOURS[1],
                width=1.5,
            ),
        ),
        points=(Points(momentum[:1, 0], momentum[:1, 1], momentum[:1, 2], label="t = 0"),),
        legend="upper left",
        box_aspect=(aspect[0], aspect[1], aspect[2]),
        title_size="medium",
    )
    if plane is None:
        return Sheet(
            (polhode,),
            size=(6.0, 5.5),
            margins={"left": 0.0, "right": 0.95, "top": 0.93, "bottom": 0.03},
        )
    margins = {"left": 0.0, "right": 0.97, "top": 0.93, "bottom": 0.1, "wspace": 0.2}
    return Sheet((polhode, _herpolhode_chart(plane)), size=(11.0, 5.5), margins=margins)


def _herpolhode_chart(plane: Herpolhode) -> Chart:
    """The herpolhode on the invariable plane, with the foot of L at the centre."""
    points = plane.in_plane
    return Chart(
        f"Herpolhode: ω on the invariable plane, {plane.height:.4g} rad/s along L",
        "ω along the plane's first axis (rad/s)",
        "ω along its second axis (rad/s)",
        lines=(Line(points[:, 0], points[:, 1], label="ω (herpolhode)"),),
        points=(
            Points(points[:1, 0], points[:1, 1], label="t = 0", on_top=True),
            Points(
                np.zeros(1),
                np.zeros(1),
                label="L through the fixed point",
                colour="0.4",
                size=40.0,
                marker="+",
            ),
        ),
        equal_aspect=True,
        title_size="medium",
    )


def panel_sheet(panel: Panel) -> Sheet:
    """A scenario's own plot (theory dashed, simulation solid)."""
    simulated = sum(curve.style == "simulation" for curve in panel.curves)
    colour = COLOURS[0]
    count = 0
    lines = []
    for curve in panel.curves:
        if curve.style == "simulation":
            colour = _colour(count)
            count += 1
            lines.append(Line(curve.t, curve.values, label=curve.label, colour=colour))
        elif curve.style == "fit":
            lines.append(
                Line(curve.t, curve.values, label=curve.label, colour="0.4", width=1.4, dash=":")
            )
        else:  # theory: dashed, black, or in the colour of the simulation it goes with
            paired = "k" if simulated <= 1 else colour
            lines.append(
                Line(
                    curve.t,
                    curve.values,
                    label=curve.label,
                    colour=paired,
                    width=1.4,
                    dash="--",
                    alpha=0.8,
                )
            )
    title = panel.title
    if panel.until is not None:
        title += f" (first {panel.until:.3g} s)"
    chart = Chart(
        title,
        panel.xlabel,
        panel.ylabel,
        lines=tuple(lines),
        log_y=panel.log,
        x_range=None if panel.until is None else (0.0, panel.until),
        equal_aspect=panel.equal_aspect,
    )
    return Sheet((chart,))


def rotors_sheet(traj: Trajectory) -> Sheet:
    """The rotors' spin rates relative to the body, rad/s."""
    lines = tuple(
        Line(traj.t, traj.rotor_speed[:, k], label=f"rotor {k + 1}", colour=_colour(k))
        for k in range(traj.rotor_speed.shape[1])
    )
    return Sheet((Chart("Rotor speeds relative to the body", "t (s)", "Ω (rad/s)", lines=lines),))


def trajectory_sheets(traj: Trajectory, panels: Sequence[Panel] = ()) -> dict[str, Sheet]:
    """All figures of a trajectory by name, as sheets: omega, angular_momentum,
    drift, polhode, rotors (if it has rotors), then one per panel."""
    sheets = {
        "omega": omega_sheet(traj),
        "angular_momentum": angular_momentum_sheet(traj),
        "drift": drift_sheet(traj),
        "polhode": polhode_sheet(traj),
    }
    if traj.rotor_speed.shape[1]:
        sheets["rotors"] = rotors_sheet(traj)
    for panel in panels:
        sheets[panel.name] = panel_sheet(panel)
    return sheets


def omega_figure(traj: Trajectory) -> Figure:
    """ω(t) in body axes, and |ω| (:func:`omega_sheet`, drawn)."""
    return draw(omega_sheet(traj))


def angular_momentum_figure(traj: Trajectory) -> Figure:
    """L(t) in space axes and |L| (:func:`angular_momentum_sheet`, drawn)."""
    return draw(angular_momentum_sheet(traj))


def drift_figure(traj: Trajectory) -> Figure:
    """The drift of the conserved quantities (:func:`drift_sheet`, drawn)."""
    return draw(drift_sheet(traj))


def polhode_figure(traj: Trajectory) -> Figure:
    """The polhode and herpolhode (:func:`polhode_sheet`, drawn)."""
    return draw(polhode_sheet(traj))


def panel_figure(panel: Panel) -> Figure:
    """A scenario's own plot (:func:`panel_sheet`, drawn)."""
    return draw(panel_sheet(panel))


def rotors_figure(traj: Trajectory) -> Figure:
    """The rotors' spin rates (:func:`rotors_sheet`, drawn)."""
    return draw(rotors_sheet(traj))


def trajectory_figures(traj: Trajectory, panels: Sequence[Panel] = ()) -> dict[str, Figure]:
    """All figures of a trajectory by name (:func:`trajectory_sheets`, drawn)."""
    return {name: draw(sheet) for name, sheet in trajectory_sheets(traj, panels).items()}


def png_bytes(figure: Figure, dpi: int = 100) -> bytes:
    """The figure as PNG bytes."""
    return png(figure, dpi)
