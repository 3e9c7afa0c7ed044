"""Static figures of a trajectory, drawn with matplotlib (Agg: no display needed).

Each function returns a ``matplotlib.figure.Figure`` made without pyplot, so
nothing is kept in a global figure registry and no window opens; notebooks
show the returned figures as images.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from tumble.analysis import Herpolhode
    from tumble.checks import Panel
    from tumble.trajectory import Trajectory

__all__ = [
    "angular_momentum_figure",
    "drift_figure",
    "omega_figure",
    "panel_figure",
    "polhode_figure",
    "rotors_figure",
    "trajectory_figures",
]

_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


def _figure(figsize: tuple[float, float] = (8.0, 4.0)) -> Figure:
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    figure = Figure(figsize=figsize)
    # Fixed margins: a layout engine would double the time to draw each figure.
    figure.subplots_adjust(left=0.1, right=0.97, top=0.91, bottom=0.13)
    return figure


def omega_figure(traj: Trajectory) -> Figure:
    """ω(t) in body axes, and |ω|."""
    figure = _figure()
    axes = figure.add_subplot()
    for k, (name, colour) in enumerate(zip("xyz", _COLOURS, strict=False)):
        axes.plot(traj.t, traj.omega[:, k], color=colour, lw=1.0, label=f"ω_{name} (body)")
    axes.plot(traj.t, np.linalg.norm(traj.omega, axis=1), color="k", lw=1.2, ls="--", label="|ω|")
    axes.set(xlabel="t (s)", ylabel="ω (rad/s)", title="Angular velocity in body axes")
    axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)
    return figure


def angular_momentum_figure(traj: Trajectory) -> Figure:
    """L(t) in space axes (about the centre of mass, or about the pivot), and |L|."""
    figure = _figure()
    axes = figure.add_subplot()
    momentum = traj.angular_momentum
    for k, (name, colour) in enumerate(zip("xyz", _COLOURS, strict=False)):
        axes.plot(traj.t, momentum[:, k], color=colour, lw=1.0, label=f"L_{name} (space)")
    axes.plot(traj.t, np.linalg.norm(momentum, axis=1), color="k", lw=1.2, ls="--", label="|L|")
    about = "the centre of mass" if traj.pivot is None else "the pivot"
    axes.set(
        xlabel="t (s)", ylabel="L (kg·m²/s)", title=f"Angular momentum about {about}, space axes"
    )
    axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)
    return figure


def drift_figure(traj: Trajectory) -> Figure:
    """Relative change from their initial values of the quantities the motion
    conserves (:meth:`tumble.Trajectory.relative_change`): the numerical error."""
    from tumble.body import label

    figure = _figure()
    axes = figure.add_subplot()
    names = traj.conserved_quantities
    for k, name in enumerate(names):
        axes.plot(traj.t, traj.relative_change(name), lw=1.0, color=_COLOURS[k % len(_COLOURS)],
                  label=label(name))  # fmt: skip
    if not names:
        axes.text(0.5, 0.5, "nothing is conserved in this motion", ha="center",
                  transform=axes.transAxes)  # fmt: skip
    axes.set(
        xlabel="t (s)",
        ylabel="relative change",
        title=f"Drift of the conserved quantities (method {traj.method})",
    )
    axes.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    if names:
        axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)
    return figure


def polhode_figure(traj: Trajectory) -> Figure:
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

    try:
        plane = herpolhode(traj)
    except InputError:  # no fixed plane: the polhode alone
        plane = None
    figure = _figure(figsize=(6.0, 5.5) if plane is None else (11.0, 5.5))
    if plane is None:
        figure.subplots_adjust(left=0.0, right=0.95, top=0.93, bottom=0.03)
    else:
        figure.subplots_adjust(left=0.0, right=0.97, top=0.93, bottom=0.1, wspace=0.2)
    axes = figure.add_subplot(1, 1 if plane is None else 2, 1, projection="3d")
    if plane is not None:
        _herpolhode_axes(figure.add_subplot(1, 2, 2), plane)
    mp = traj.mass_properties
    inertia = mp.inertia if traj.pivot is None else mp.inertia_about(traj.pivot)
    from tumble.massprops import principal_decomposition

    moments, frame = principal_decomposition(inertia)
    momentum = traj.body_momentum @ frame  # L in principal axes (the parts' included)
    kinetic = 0.5 * float(np.sum(momentum[0] ** 2 / moments))
    semi = np.sqrt(2.0 * kinetic * moments)
    if not traj.internal:  # a gyrostat's energy surface is another ellipsoid, off centre
        u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 36), np.linspace(0, np.pi, 18))
        axes.plot_wireframe(
            semi[0] * np.cos(u) * np.sin(v),
            semi[1] * np.sin(u) * np.sin(v),
            semi[2] * np.cos(v),
            color="0.75",
            lw=0.4,
        )
    axes.plot(
        momentum[:, 0],
        momentum[:, 1],
        momentum[:, 2],
        color=_COLOURS[1],
        lw=1.5,
        label="L (polhode)",
    )
    axes.scatter(*momentum[0], color="k", s=12, label="t = 0")
    axes.set(xlabel="L₁", ylabel="L₂", zlabel="L₃")
    axes.set_box_aspect(semi / semi.max() if semi.max() > 0 else np.ones(3))
    axes.set_title("Polhode: L in principal axes on the energy ellipsoid", fontsize="medium")
    axes.legend(loc="upper left", fontsize="small")
    return figure


def _herpolhode_axes(axes: Axes, plane: Herpolhode) -> None:
    """The herpolhode on the invariable plane, with the foot of L at the centre."""
    points = plane.in_plane
    axes.plot(points[:, 0], points[:, 1], color=_COLOURS[0], lw=1.0, label="ω (herpolhode)")
    axes.scatter(points[0, 0], points[0, 1], color="k", s=12, label="t = 0", zorder=3)
    axes.scatter(0.0, 0.0, marker="+", color="0.4", s=40, label="L through the fixed point")
    axes.set_aspect("equal", adjustable="datalim")
    axes.set(xlabel="ω along the plane's first axis (rad/s)",
             ylabel="ω along its second axis (rad/s)")  # fmt: skip
    axes.set_title(
        f"Herpolhode: ω on the invariable plane, {plane.height:.4g} rad/s along L",
        fontsize="medium",
    )
    axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)


def panel_figure(panel: Panel) -> Figure:
    """A scenario's own plot (theory dashed, simulation solid)."""
    figure = _figure()
    axes = figure.add_subplot()
    simulated = sum(curve.style == "simulation" for curve in panel.curves)
    colour = _COLOURS[0]
    count = 0
    for curve in panel.curves:
        if curve.style == "simulation":
            colour = _COLOURS[count % len(_COLOURS)]
            count += 1
            axes.plot(curve.t, curve.values, lw=1.0, color=colour, label=curve.label)
        elif curve.style == "fit":
            axes.plot(curve.t, curve.values, ls=":", lw=1.4, color="0.4", label=curve.label)
        else:  # theory: dashed, black, or in the colour of the simulation it goes with
            paired = "k" if simulated <= 1 else colour
            axes.plot(
                curve.t, curve.values, ls="--", lw=1.4, color=paired, alpha=0.8, label=curve.label
            )
    title = panel.title
    if panel.until is not None:
        axes.set_xlim(0.0, panel.until)
        title += f" (first {panel.until:.3g} s)"
    axes.set(xlabel="t (s)", ylabel=panel.ylabel, title=title)
    if panel.log:
        axes.set_yscale("log")
    axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)
    return figure


def rotors_figure(traj: Trajectory) -> Figure:
    """The rotors' spin rates relative to the body, rad/s."""
    figure = _figure()
    axes = figure.add_subplot()
    for k in range(traj.rotor_speed.shape[1]):
        axes.plot(traj.t, traj.rotor_speed[:, k], lw=1.0, color=_COLOURS[k % len(_COLOURS)],
                  label=f"rotor {k + 1}")  # fmt: skip
    axes.set(xlabel="t (s)", ylabel="Ω (rad/s)", title="Rotor speeds relative to the body")
    axes.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes.grid(alpha=0.3)
    return figure


def trajectory_figures(traj: Trajectory, panels: Sequence[Panel] = ()) -> dict[str, Figure]:
    """All figures of a trajectory by name: omega, angular_momentum, drift, polhode,
    then one per panel."""
    figures = {
        "omega": omega_figure(traj),
        "angular_momentum": angular_momentum_figure(traj),
        "drift": drift_figure(traj),
        "polhode": polhode_figure(traj),
    }
    if traj.rotor_speed.shape[1]:
        figures["rotors"] = rotors_figure(traj)
    for panel in panels:
        figures[panel.name] = panel_figure(panel)
    return figures


def png_bytes(figure: Figure, dpi: int = 100) -> bytes:
    """The figure as PNG bytes."""
    import io

    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi, pil_kwargs={"compress_level": 3})
    return buffer.getvalue()
