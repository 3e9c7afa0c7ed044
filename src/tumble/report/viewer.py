"""The interactive 3D viewer: one self-contained, offline HTML file.

The page holds the plotly.js bundle inline, the body's mesh once (body
coordinates) and the attitude quaternion of each frame; a small script
(``viewer.js``, beside this module) turns the mesh, the principal axes and the
ω and L arrows frame by frame, so the file stays small however fine the mesh. A
body's rotors are discs with a stripe, turned by the body and by their own spin
angle (the integral of their speed).
For a torque-free body a second panel draws the Poinsot construction in
ω-space: the inertia ellipsoid turning with the body and rolling on the
invariable plane, with the polhode and the herpolhode (:func:`tumble.report.poinsot.poinsot_data`).
Controls: play / pause, a time slider and the time shown. The script keeps the
current frame in ``window.tumbleViewer.frame``.
"""

from __future__ import annotations

import functools
import html
import json
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.numbers import rounded
from tumble.report.poinsot import poinsot_data, poinsot_figure

if TYPE_CHECKING:
    from collections.abc import Sequence

    from tumble.report.geometry import DiscDrawing, Geometry
    from tumble.trajectory import Trajectory

__all__ = ["Viewer", "viewer_html"]

Array = NDArray[np.float64]


def _frames(count: int, frames: int) -> NDArray[np.int64]:
    """At most ``frames`` sample indices, evenly spread, first and last included."""
    if count <= frames:
        return np.arange(count)
    return np.unique(np.round(np.linspace(0, count - 1, frames)).astype(np.int64))


def _geometry(traj: Trajectory, geometry: Geometry | None) -> tuple[Array, NDArray[np.int64], bool]:
    if geometry is None:
        from tumble.report.geometry import equal_inertia_ellipsoid

        geometry = equal_inertia_ellipsoid(traj.mass_properties)
    return geometry.vertices, geometry.faces, geometry.exact


def _disc_drawings(traj: Trajectory, reach: float) -> list[DiscDrawing | None]:
    """Discs for the trajectory's parts that spin (its rotors, one per column of
    ``rotor_speed``), as each part draws itself
    (:meth:`tumble.parts.InternalPart.drawing`): at the centre of mass, sized to
    the body; None for one that does not draw itself as a disc."""
    from tumble.report.geometry import disc_drawing

    centre = traj.mass_properties.center_of_mass
    return [
        disc_drawing(part.drawing(reach, centre)) for part in traj.internal if part.spin is not None
    ]


def _rotor_data(
    traj: Trajectory,
    drawings: Sequence[DiscDrawing | None],
    origin: Array,
    index: Any,
) -> list[dict[str, Any]]:
    """Each drawn rotor's mesh (body coordinates about the fixed point), axis and
    spin angle at each frame (rad, the integral of its speed, modulo 2π);
    ``drawings`` one per column of the rotors' speeds, None for one not drawn."""
    speeds = traj.rotor_speed
    if len(drawings) != speeds.shape[1]:
        raise ValueError(f"Expected {speeds.shape[1]} rotor drawings, got {len(drawings)}.")
    if not any(drawings):
        return []  # without importing scipy.integrate (0.1 s)
    from scipy.integrate import cumulative_trapezoid

    from tumble.report.geometry import disc_mesh

    rotors = []
    for k, drawing in enumerate(drawings):
        if drawing is None:
            continue
        vertices, faces, marked = disc_mesh(drawing)
        angles = cumulative_trapezoid(speeds[:, k], traj.t, initial=0.0)[index] % (2 * np.pi)
        rotors.append(
            {
                "vertices": rounded(vertices - origin),
                "faces": faces.T.tolist(),
                "marked": marked.tolist(),
                "position": rounded(np.asarray(drawing.position) - origin),
                "axis": [float(a) for a in drawing.axis],
                "angles": np.round(angles, 4).tolist(),
            }
        )
    return rotors


def viewer_data(
    traj: Trajectory,
    geometry: Geometry | None = None,
    frames: int = 300,
    rotors: Sequence[DiscDrawing | None] | None = None,
) -> dict[str, Any]:
    """The numbers the viewer's script needs (SI, space axes; the fixed point at the
    origin); ``rotors`` places the trajectory's rotors (default: discs at the
    centre of mass)."""
    vertices, faces, exact = _geometry(traj, geometry)
    mp = traj.mass_properties
    origin = mp.center_of_mass if traj.pivot is None else np.asarray(traj.pivot)
    body = vertices - origin
    reach = float(np.max(np.linalg.norm(body, axis=1))) if len(body) else 1.0
    reach = reach if reach > 0 else 1.0
    index = _frames(len(traj.t), frames)
    moments, axes = mp.principal()
    # Principal axes through the centre of mass, each as far as the body reaches along it.
    centre = mp.center_of_mass - origin
    ends = []
    for k in range(3):
        extent = (
            float(np.max(np.abs((vertices - mp.center_of_mass) @ axes[:, k])))
            if len(vertices)
            else reach
        )
        ends.append(centre + 1.25 * max(extent, 0.2 * reach) * axes[:, k])
    omega = traj.omega_space[index]
    momentum = traj.angular_momentum[index]
    arrow = 1.5 * reach

    # The scale of the motion's momenta: an L below round-off of it (a body and
    # its wheels at rest in total) is drawn as nothing, not as noise blown up.
    carried = float(np.max(np.linalg.norm(traj.omega @ traj.body.inertia.T, axis=1)))

    def scaled(vectors: Array, floor: float = 0.0) -> Array:
        size = float(np.max(np.linalg.norm(vectors, axis=1)))
        if not size > floor:
            return np.zeros_like(vectors)
        return vectors * (arrow / size)

    drawings = _disc_drawings(traj, reach) if rotors is None else rotors
    return {
        "poinsot": poinsot_data(traj, index),
        "rotors": _rotor_data(traj, drawings, origin, index),
        "t": rounded(traj.t[index]),
        "q": rounded(traj.quaternion[index]),
        "vertices": rounded(body),
        "faces": np.asarray(faces, dtype=np.int64).T.tolist(),
        "centre": rounded(centre),
        "axis_ends": rounded(np.array(ends)),
        "moments": [float(m) for m in moments],
        "omega": rounded(scaled(omega)),
        "momentum": rounded(scaled(momentum, 1e-9 * carried)),
        "omega_max": float(np.max(np.linalg.norm(traj.omega_space, axis=1))),
        "momentum_max": float(np.max(np.linalg.norm(traj.angular_momentum, axis=1))),
        "reach": 2.0 * reach,
        "exact_shape": bool(exact),
        "fixed_point": "centre of mass" if traj.pivot is None else "pivot",
    }


_STYLE = """
body { font-family: system-ui, sans-serif; margin: 0; background: #fafafa; color: #222; }
header { padding: 8px 14px; }
h1 { font-size: 1.1rem; margin: 0 0 2px 0; }
p.note { margin: 0; font-size: 0.85rem; color: #555; }
#views { display: flex; flex-wrap: wrap; }
#plot, #poinsot { flex: 1 1 420px; height: calc(100vh - 120px); min-height: 420px; }
#controls { display: flex; gap: 12px; align-items: center; padding: 6px 14px; }
#controls input[type=range] { flex: 1; }
#time { font-variant-numeric: tabular-nums; min-width: 9em; }
button { font-size: 0.95rem; padding: 3px 14px; }
"""


@functools.cache
def _script() -> str:
    """The page's script (``viewer.js``, beside this module): it reads the numbers of
    :func:`viewer_data` and the figures, draws frame 0, and turns the body, its
    axes, ω, L and the rotors frame by frame, with the play button and the slider."""
    return resources.files("tumble.report").joinpath("viewer.js").read_text(encoding="utf-8")


#: The colours of principal axes 1, 2 and 3.
_AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")


def _figure(data: dict[str, Any]) -> dict[str, Any]:
    """The plotly figure (data and layout) of frame 0; the script moves it. The
    script addresses the traces by their order: the body, the three principal
    axes, ω, L, the trail of ω's tip, the fixed point, then the rotors."""
    traces = [
        _body_trace(data),
        *_axis_traces(data["moments"]),
        *_vector_traces(data),
        *(_rotor_trace(k, rotor) for k, rotor in enumerate(data["rotors"])),
    ]
    return {"data": traces, "layout": _layout(data["reach"])}


def _body_trace(data: dict[str, Any]) -> dict[str, Any]:
    """The body's mesh (its shape, or the ellipsoid of equal inertia), see-through
    enough to show the rotors inside it."""
    faces = data["faces"]
    vertices = np.asarray(data["vertices"])
    return {
        "type": "mesh3d",
        "name": "body" if data["exact_shape"] else "body (ellipsoid of equal inertia)",
        "x": vertices[:, 0].tolist() if len(vertices) else [],
        "y": vertices[:, 1].tolist() if len(vertices) else [],
        "z": vertices[:, 2].tolist() if len(vertices) else [],
        "i": faces[0],
        "j": faces[1],
        "k": faces[2],
        "color": "#9fb7d9",
        "opacity": 0.35 if data["rotors"] else 0.75,
        "flatshading": True,
        "lighting": {"ambient": 0.55, "diffuse": 0.7, "specular": 0.2},
        "showlegend": True,
        "hoverinfo": "skip",
    }


def _segment(name: str, colour: str, width: int, **more: Any) -> dict[str, Any]:
    """A line from the origin, of zero length until the script places it."""
    return {
        "type": "scatter3d",
        "mode": "lines",
        "name": name,
        "x": [0, 0],
        "y": [0, 0],
        "z": [0, 0],
        "line": {"color": colour, "width": width},
        **more,
    }


def _axis_traces(moments: Sequence[float]) -> list[dict[str, Any]]:
    """The principal axes, labelled with their moments (kg·m²)."""
    return [
        _segment(
            f"principal axis {k + 1} (I{k + 1} = {moments[k]:.4g} kg·m²)",
            _AXIS_COLOURS[k],
            5,
            hoverinfo="name",
        )
        for k in range(3)
    ]


def _vector_traces(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The ω and L arrows (labelled with their largest values), the trail of ω's
    tip, and the fixed point (the centre of mass or the pivot) at the origin."""
    return [
        _segment(f"ω (max {data['omega_max']:.4g} rad/s)", "#ff7f0e", 8),
        _segment(f"L (max {data['momentum_max']:.4g} kg·m²/s)", "#9467bd", 8),
        {
            "type": "scatter3d",
            "mode": "lines",
            "name": "trail of the ω tip",
            "x": [0],
            "y": [0],
            "z": [0],
            "line": {"color": "#ff7f0e", "width": 2},
            "opacity": 0.6,
        },
        {
            "type": "scatter3d",
            "mode": "markers",
            "name": data["fixed_point"],
            "x": [0],
            "y": [0],
            "z": [0],
            "marker": {"size": 4, "color": "#000000"},
        },
    ]


def _rotor_trace(k: int, rotor: dict[str, Any]) -> dict[str, Any]:
    """Rotor ``k``'s disc, its marked faces (the stripe that shows its angle) dark."""
    points = np.asarray(rotor["vertices"])
    return {
        "type": "mesh3d",
        "name": f"rotor {k + 1}",
        "x": points[:, 0].tolist(),
        "y": points[:, 1].tolist(),
        "z": points[:, 2].tolist(),
        "i": rotor["faces"][0],
        "j": rotor["faces"][1],
        "k": rotor["faces"][2],
        "facecolor": ["#5a4a1a" if m else "#f2b134" for m in rotor["marked"]],
        "flatshading": True,
        "showlegend": True,
        "hoverinfo": "name",
    }


def _layout(reach: float) -> dict[str, Any]:
    """A cube of space axes 1.6 × ``reach`` (m) wide, centred on the fixed point; the
    camera kept when the script restyles the traces."""
    half = reach * 0.5 * 1.6
    axis_range = [-half, half]
    return {
        "margin": {"l": 0, "r": 0, "t": 30, "b": 0},
        "uirevision": "keep",
        "legend": {"x": 0, "y": 1, "bgcolor": "rgba(255,255,255,0.6)"},
        "scene": {
            "aspectmode": "cube",
            "xaxis": {"range": axis_range, "title": {"text": "x (m)"}},
            "yaxis": {"range": axis_range, "title": {"text": "y (m)"}},
            "zaxis": {"range": axis_range, "title": {"text": "z (m)"}},
            "camera": {"eye": {"x": 1.5, "y": -1.5, "z": 0.9}},
        },
    }


def _json_script(value: Any) -> str:
    # "</" must not end the <script> element early.
    return json.dumps(value, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")


def viewer_html(
    traj: Trajectory,
    geometry: Geometry | None = None,
    *,
    frames: int = 300,
    title: str = "",
    rotors: Sequence[DiscDrawing | None] | None = None,
) -> str:
    """The viewer page of a trajectory, as one self-contained HTML string.

    Parameters
    ----------
    traj : the trajectory.
    geometry : the body's mesh in body coordinates; default the ellipsoid of
        equal inertia.
    frames : at most this many frames, evenly spread over the trajectory.
    title : shown above the plot.
    rotors : where to draw the trajectory's rotors (default: discs at the centre
        of mass, sized to the body).
    """
    from plotly.offline import get_plotlyjs

    data = viewer_data(traj, geometry, frames, rotors)
    heading = title or "tumble: rigid-body rotation"
    shape = "its shape" if data["exact_shape"] else "an ellipsoid of equal inertia"
    note = (
        f"The body ({shape}), its principal axes, ω (orange) and L (purple), space axes with the "
        f"{data['fixed_point']} at the origin; arrows scaled to their largest value. "
        + (
            f"Its {len(data['rotors'])} rotor(s) as discs turning at their speed (the stripe "
            "shows their angle; a fast rotor seen once a frame may seem to turn slowly). "
            if data["rotors"]
            else ""
        )
        + (
            "Beside it, the Poinsot construction: the inertia ellipsoid turns with the body and "
            "rolls without slipping on the invariable plane, touching it at ω; the polhode is "
            "ω's path on the ellipsoid, the herpolhode its path on the plane. "
            if data["poinsot"]
            else ""
        )
        + f"{len(data['t'])} frames over {data['t'][-1]:.4g} s."
    )
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(heading)}</title>\n<style>{_STYLE}</style>\n"
        f"<script>{get_plotlyjs()}</script>\n</head>\n<body>\n"
        f'<header><h1>{html.escape(heading)}</h1><p class="note">{html.escape(note)}</p></header>\n'
        '<div id="controls"><button id="play" type="button">Play</button>'
        f'<input id="slider" type="range" min="0" max="{len(data["t"]) - 1}" value="0" step="1" '
        'aria-label="time"><span id="time">t = 0 s</span></div>\n'
        '<div id="views"><div id="plot"></div>'
        + ('<div id="poinsot"></div>' if data["poinsot"] else "")
        + "</div>\n"
        f'<script type="application/json" id="tumble-data">{_json_script(data)}</script>\n'
        '<script type="application/json" id="tumble-figure">'
        f"{_json_script(_figure(data))}</script>\n"
        + (
            '<script type="application/json" id="tumble-poinsot">'
            f"{_json_script(poinsot_figure(data['poinsot']))}</script>\n"
            if data["poinsot"]
            else ""
        )
        + f"<script>\n{_script()}</script>\n</body>\n</html>\n"
    )


class Viewer:
    """The interactive viewer of a trajectory: shown inline in a notebook,
    saved as a self-contained HTML file with :meth:`save`."""

    def __init__(self, page: str) -> None:
        self.html = page

    def save(self, path: str | Path) -> Path:
        """Write the page (atomically: a temporary name, then renamed)."""
        from tumble.files import write_text

        return write_text(Path(path), self.html)

    def _repr_html_(self) -> str:
        return (
            '<iframe style="width:100%;height:640px;border:0" sandbox="allow-scripts" '
            f'srcdoc="{html.escape(self.html, quote=True)}"></iframe>'
        )

    def __repr__(self) -> str:
        return f"Viewer({len(self.html) / 1e6:.1f} MB of HTML; .save(path) writes it)"
