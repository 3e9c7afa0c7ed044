"""The interactive 3D viewer: one self-contained, offline HTML file.

The page holds the plotly.js bundle inline, the body's mesh once (body
coordinates) and the attitude quaternion of each frame; a small script turns the
mesh, the principal axes and the ω and L arrows frame by frame, so the file
stays small however fine the mesh. A body's rotors are discs with a stripe,
turned by the body and by their own spin angle (the integral of their speed).
For a torque-free body a second panel draws the Poinsot construction in
ω-space: the inertia ellipsoid turning with the body and rolling on the
invariable plane, with the polhode and the herpolhode (:func:`tumble.report.poinsot.poinsot_data`).
Controls: play / pause, a time slider and the time shown. The script keeps the
current frame in ``window.tumbleViewer.frame``.
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.report.numbers import rounded
from tumble.report.poinsot import poinsot_data, poinsot_figure

if TYPE_CHECKING:
    from collections.abc import Sequence

    from tumble.report.geometry import Geometry, RotorDrawing
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


def _rotor_drawings(traj: Trajectory, reach: float) -> list[RotorDrawing]:
    """Discs for the trajectory's parts that spin (its rotors), as each part draws
    itself (:meth:`tumble.parts.InternalPart.drawing`): at the centre of mass,
    sized to the body."""
    from tumble.report.geometry import RotorDrawing

    centre = traj.mass_properties.center_of_mass
    drawings = [part.drawing(reach, centre) for part in traj.internal]
    return [
        RotorDrawing(d.position, np.asarray(d.axis), d.radius, d.thickness)
        for d in drawings
        if d is not None and d.shape == "disc" and d.spin is not None
    ]


def _rotor_data(
    traj: Trajectory,
    drawings: Sequence[RotorDrawing],
    origin: Array,
    index: Any,
) -> list[dict[str, Any]]:
    """Each rotor's mesh (body coordinates about the fixed point), axis and spin
    angle at each frame (rad, the integral of its speed, modulo 2π)."""
    speeds = traj.rotor_speed
    if len(drawings) != speeds.shape[1]:
        raise ValueError(f"Expected {speeds.shape[1]} rotor drawings, got {len(drawings)}.")
    if not drawings:
        return []  # without importing scipy.integrate (0.1 s)
    from scipy.integrate import cumulative_trapezoid

    from tumble.report.geometry import rotor_mesh

    rotors = []
    for k, drawing in enumerate(drawings):
        vertices, faces, marked = rotor_mesh(drawing)
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
    rotors: Sequence[RotorDrawing] | None = None,
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

    drawings = _rotor_drawings(traj, reach) if rotors is None else rotors
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

_SCRIPT = """
(function () {
  const D = JSON.parse(document.getElementById('tumble-data').textContent);
  const gd = document.getElementById('plot');
  const poinsot = document.getElementById('poinsot');
  const P = D.poinsot;
  const slider = document.getElementById('slider');
  const play = document.getElementById('play');
  const clock = document.getElementById('time');
  const n = D.t.length;
  const state = { frame: 0, playing: false, timer: null };
  window.tumbleViewer = state;

  function rotate(q, v) {
    const w = q[0], x = q[1], y = q[2], z = q[3];
    // v + 2w (u × v) + 2 u × (u × v), u = (x, y, z): the rotation of v by q.
    const tx = 2 * (y * v[2] - z * v[1]);
    const ty = 2 * (z * v[0] - x * v[2]);
    const tz = 2 * (x * v[1] - y * v[0]);
    return [
      v[0] + w * tx + (y * tz - z * ty),
      v[1] + w * ty + (z * tx - x * tz),
      v[2] + w * tz + (x * ty - y * tx),
    ];
  }
  function segment(a, b) { return [[a[0], b[0]], [a[1], b[1]], [a[2], b[2]]]; }

  function draw(i) {
    const q = D.q[i];
    const count = D.vertices.length;
    const mx = new Array(count), my = new Array(count), mz = new Array(count);
    for (let k = 0; k < count; k++) {
      const p = rotate(q, D.vertices[k]);
      mx[k] = p[0]; my[k] = p[1]; mz[k] = p[2];
    }
    const c = rotate(q, D.centre);
    const xs = [mx], ys = [my], zs = [mz];
    for (let k = 0; k < 3; k++) {
      const s = segment(c, rotate(q, D.axis_ends[k]));
      xs.push(s[0]); ys.push(s[1]); zs.push(s[2]);
    }
    for (const v of [D.omega[i], D.momentum[i]]) {
      const s = segment([0, 0, 0], v);
      xs.push(s[0]); ys.push(s[1]); zs.push(s[2]);
    }
    const trail = D.omega.slice(0, i + 1);
    xs.push(trail.map(p => p[0])); ys.push(trail.map(p => p[1])); zs.push(trail.map(p => p[2]));
    const traces = [0, 1, 2, 3, 4, 5, 6];
    D.rotors.forEach(function (r, k) {
      // Turned about its axis by its spin angle, about its centre, then with the body.
      const half = 0.5 * r.angles[i], s = Math.sin(half);
      const spin = [Math.cos(half), s * r.axis[0], s * r.axis[1], s * r.axis[2]];
      const rx = [], ry = [], rz = [];
      const c = r.position;
      for (const v of r.vertices) {
        const local = rotate(spin, [v[0] - c[0], v[1] - c[1], v[2] - c[2]]);
        const p = rotate(q, [local[0] + c[0], local[1] + c[1], local[2] + c[2]]);
        rx.push(p[0]); ry.push(p[1]); rz.push(p[2]);
      }
      xs.push(rx); ys.push(ry); zs.push(rz);
      traces.push(8 + k);
    });
    Plotly.restyle(gd, { x: xs, y: ys, z: zs }, traces);
    if (P) {
      // The ellipsoid and the polhode turn with the body; the herpolhode grows on the plane.
      const ex = [], ey = [], ez = [];
      for (const v of P.ellipsoid) {
        const p = rotate(q, v);
        ex.push(p[0]); ey.push(p[1]); ez.push(p[2]);
      }
      const pol = P.polhode.map(v => rotate(q, v));
      const her = P.herpolhode.slice(0, i + 1);
      const tip = P.herpolhode[i];
      Plotly.restyle(poinsot, {
        x: [ex, pol.map(p => p[0]), her.map(p => p[0]), [0, tip[0]], [tip[0]]],
        y: [ey, pol.map(p => p[1]), her.map(p => p[1]), [0, tip[1]], [tip[1]]],
        z: [ez, pol.map(p => p[2]), her.map(p => p[2]), [0, tip[2]], [tip[2]]],
      }, [0, 2, 3, 4, 5]);
    }
    state.frame = i;
    slider.value = i;
    clock.textContent = 't = ' + D.t[i].toFixed(3) + ' s  (' + (i + 1) + ' / ' + n + ')';
  }

  function stop() {
    state.playing = false;
    if (state.timer !== null) { clearInterval(state.timer); state.timer = null; }
    play.textContent = 'Play';
  }
  function start() {
    if (state.frame >= n - 1) { draw(0); }
    state.playing = true;
    play.textContent = 'Pause';
    state.timer = setInterval(function () {
      if (state.frame >= n - 1) { stop(); return; }
      draw(state.frame + 1);
    }, 1000 / 30);
  }
  play.addEventListener('click', function () { state.playing ? stop() : start(); });
  slider.addEventListener('input', function () { stop(); draw(parseInt(slider.value, 10)); });

  const figure = JSON.parse(document.getElementById('tumble-figure').textContent);
  const config = { responsive: true, displaylogo: false };
  const shown = [Plotly.newPlot(gd, figure.data, figure.layout, config)];
  if (P) {
    const second = JSON.parse(document.getElementById('tumble-poinsot').textContent);
    shown.push(Plotly.newPlot(poinsot, second.data, second.layout, config));
  }
  Promise.all(shown).then(function () {
    draw(0);
    state.ready = true;
  });
})();
"""


def _figure(data: dict[str, Any]) -> dict[str, Any]:
    """The plotly figure (data and layout) of frame 0; the script moves it."""
    faces = data["faces"]
    vertices = np.asarray(data["vertices"])
    half = data["reach"] * 0.5 * 1.6
    axis_range = [-half, half]
    colours = ("#d62728", "#2ca02c", "#1f77b4")
    traces: list[dict[str, Any]] = [
        {
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
    ]
    for k in range(3):
        traces.append(
            {
                "type": "scatter3d",
                "mode": "lines",
                "name": f"principal axis {k + 1} (I{k + 1} = {data['moments'][k]:.4g} kg·m²)",
                "x": [0, 0],
                "y": [0, 0],
                "z": [0, 0],
                "line": {"color": colours[k], "width": 5},
                "hoverinfo": "name",
            }
        )
    traces.append(
        {
            "type": "scatter3d",
            "mode": "lines",
            "name": f"ω (max {data['omega_max']:.4g} rad/s)",
            "x": [0, 0],
            "y": [0, 0],
            "z": [0, 0],
            "line": {"color": "#ff7f0e", "width": 8},
        }
    )
    traces.append(
        {
            "type": "scatter3d",
            "mode": "lines",
            "name": f"L (max {data['momentum_max']:.4g} kg·m²/s)",
            "x": [0, 0],
            "y": [0, 0],
            "z": [0, 0],
            "line": {"color": "#9467bd", "width": 8},
        }
    )
    traces.append(
        {
            "type": "scatter3d",
            "mode": "lines",
            "name": "trail of the ω tip",
            "x": [0],
            "y": [0],
            "z": [0],
            "line": {"color": "#ff7f0e", "width": 2},
            "opacity": 0.6,
        }
    )
    traces.append(
        {
            "type": "scatter3d",
            "mode": "markers",
            "name": data["fixed_point"],
            "x": [0],
            "y": [0],
            "z": [0],
            "marker": {"size": 4, "color": "#000000"},
        }
    )
    for k, rotor in enumerate(data["rotors"]):
        points = np.asarray(rotor["vertices"])
        traces.append(
            {
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
        )
    layout = {
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
    return {"data": traces, "layout": layout}


def _json_script(value: Any) -> str:
    # "</" must not end the <script> element early.
    return json.dumps(value, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")


def viewer_html(
    traj: Trajectory,
    geometry: Geometry | None = None,
    *,
    frames: int = 300,
    title: str = "",
    rotors: Sequence[RotorDrawing] | None = None,
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
        + f"<script>{_SCRIPT}</script>\n</body>\n</html>\n"
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
