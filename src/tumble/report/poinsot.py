"""The Poinsot construction of a torque-free motion, for the viewer
(:mod:`tumble.report.viewer`): the inertia ellipsoid that turns with the body
and rolls on the invariable plane, the polhode and the herpolhode, in ω-space.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from tumble.report.numbers import rounded

if TYPE_CHECKING:
    from tumble.trajectory import Trajectory

__all__ = ["poinsot_data", "poinsot_figure"]


def poinsot_data(traj: Trajectory, index: Any) -> dict[str, Any] | None:
    """The Poinsot construction of a torque-free motion, in ω-space (rad/s, space
    axes), for the frames ``index``; None where it does not apply (a torque,
    gravity about a pivot, internal parts).

    The inertia ellipsoid ``ω · J ω = 2T`` (J the inertia about the fixed point,
    body axes; a mesh in body axes that the page turns with the body) touches
    the invariable plane ``ω · L̂ = 2T/|L|`` at ω and rolls on it without
    slipping (Landau & Lifshitz §37): the polhode is ω's path on the ellipsoid
    (body axes), the herpolhode its path on the plane (space axes)."""
    from tumble.analysis import herpolhode
    from tumble.errors import InputError
    from tumble.shapes.surfaces import sphere

    try:
        plane = herpolhode(traj)
    except InputError:
        return None
    energy = float(traj.energy[0])
    inertia = traj.body.inertia
    moments, axes = np.linalg.eigh(inertia)
    semi = np.sqrt(2.0 * energy / moments)  # rad/s along each principal axis
    unit, faces = sphere(rings=18, sections=36)
    ellipsoid = (unit * semi) @ axes.T
    herpolhode_points = plane.omega_space[index]
    centre = plane.height * plane.normal
    # The plane drawn as a square about the foot of the normal, wide enough for
    # the herpolhode and the ellipsoid's shadow on it.
    half = 1.15 * max(
        float(np.max(semi)), float(np.max(np.linalg.norm(herpolhode_points - centre, axis=1)))
    )
    corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * half
    square = centre + corners @ plane.plane_axes.T
    return {
        "ellipsoid": rounded(ellipsoid),
        "ellipsoid_faces": np.asarray(faces, dtype=np.int64).T.tolist(),
        "polhode": rounded(traj.omega[index]),
        "herpolhode": rounded(herpolhode_points),
        "plane": rounded(square),
        "normal": [float(v) for v in plane.normal],
        "height": plane.height,
        "reach": float(max(np.max(semi), plane.height, half)),
    }


def poinsot_figure(data: dict[str, Any]) -> dict[str, Any]:
    """The plotly figure of the Poinsot construction at frame 0 (ω-space, rad/s)."""
    half = 1.1 * data["reach"]
    traces = [*_surfaces(data), *_curves(np.asarray(data["normal"]) * data["height"])]
    axis = {"range": [-half, half]}
    layout = {
        "margin": {"l": 0, "r": 0, "t": 30, "b": 0},
        "uirevision": "keep",
        "title": {"text": "Poinsot construction: the ellipsoid rolls on the plane", "x": 0.5},
        "legend": {"x": 0, "y": 1, "bgcolor": "rgba(255,255,255,0.6)"},
        "scene": {
            "aspectmode": "cube",
            "xaxis": {**axis, "title": {"text": "ωx (rad/s)"}},
            "yaxis": {**axis, "title": {"text": "ωy (rad/s)"}},
            "zaxis": {**axis, "title": {"text": "ωz (rad/s)"}},
            "camera": {"eye": {"x": 1.5, "y": -1.5, "z": 0.9}},
        },
    }
    return {"data": traces, "layout": layout}


def _surfaces(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The inertia ellipsoid and the invariable plane, as plotly meshes."""
    ellipsoid = np.asarray(data["ellipsoid"])
    faces = data["ellipsoid_faces"]
    square = np.asarray(data["plane"])
    return [
        {
            "type": "mesh3d",
            "name": "inertia ellipsoid ω·Jω = 2T (turns with the body)",
            "x": ellipsoid[:, 0].tolist(),
            "y": ellipsoid[:, 1].tolist(),
            "z": ellipsoid[:, 2].tolist(),
            "i": faces[0],
            "j": faces[1],
            "k": faces[2],
            "color": "#9fb7d9",
            "opacity": 0.6,
            "flatshading": True,
            "showlegend": True,
            "hoverinfo": "skip",
        },
        {
            "type": "mesh3d",
            "name": f"invariable plane ω·L̂ = 2T/|L| = {data['height']:.4g} rad/s",
            "x": square[:, 0].tolist(),
            "y": square[:, 1].tolist(),
            "z": square[:, 2].tolist(),
            "i": [0, 0],
            "j": [1, 2],
            "k": [2, 3],
            "color": "#c8c8c8",
            "opacity": 0.45,
            "showlegend": True,
            "hoverinfo": "skip",
        },
    ]


def _curves(foot: Any) -> list[dict[str, Any]]:
    """The polhode, the herpolhode, ω and its contact point (filled frame by frame),
    and L̂ to the plane's ``foot``."""

    def line(name: str, colour: str, width: int) -> dict[str, Any]:
        return {
            "type": "scatter3d",
            "mode": "lines",
            "name": name,
            "x": [0],
            "y": [0],
            "z": [0],
            "line": {"color": colour, "width": width},
        }

    return [
        line("polhode (ω on the body)", "#d62728", 4),
        line("herpolhode (ω on the plane)", "#2ca02c", 4),
        line("ω", "#ff7f0e", 8),
        {
            "type": "scatter3d",
            "mode": "markers",
            "name": "contact point (ω)",
            "x": [0],
            "y": [0],
            "z": [0],
            "marker": {"size": 4, "color": "#000000"},
        },
        {
            "type": "scatter3d",
            "mode": "lines",
            "name": "L̂ (fixed)",
            "x": [0, float(foot[0])],
            "y": [0, float(foot[1])],
            "z": [0, float(foot[2])],
            "line": {"color": "#9467bd", "width": 6, "dash": "dash"},
        },
    ]
