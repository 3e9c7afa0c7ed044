"""The ROSS half of ``bench/rotors.py``: rigid rotors on elastic bearings in ROSS.

Runs in ROSS's own environment (``bench/.venv-ross``, see
``bench/requirements-ross.txt``), never imports tumble. Reads a request (JSON)
on stdin and writes its answer (JSON) to the file named by its one argument:
importing ROSS prints to stdout (its ``ccp`` dependency looks for REFPROP), so
stdout carries no data.

Each rotor is a rigid body in ROSS's terms: a shaft of steel made
``stiffening`` times stiffer (Young's modulus) and ``lightening`` times lighter
(density), with nodes at the bearings and at the centre of mass, a
``DiskElement`` there carrying the body's mass, polar and transverse moments,
and a ``BearingElement`` at each bearing. Positions are ROSS's axial
coordinate (m): its node 0 is at the smallest position given.

ROSS's nodes carry six degrees of freedom (x, y, z, α about x, β about y, θ
about z), so its modal analysis also holds axial, torsional and shaft-bending
modes. The four lateral rigid-body modes are picked by their shape (see
:func:`rigid_modes`).
"""

from __future__ import annotations

import contextlib
import io
import itertools
import json
import statistics
import sys
import time
import warnings
from typing import Any

import numpy as np
import scipy.linalg as la

with contextlib.redirect_stdout(io.StringIO()):
    import ross as rs

#: Rigidity (see :func:`rigidity`) a lateral mode needs to count as a rigid-body mode.
RIGID = 0.99


def positions(case: dict[str, Any]) -> list[float]:
    """The nodes' axial positions, m: the bearings' and the centre of mass's, sorted."""
    return sorted({case["centre"], *(b["position"] for b in case["bearings"])})


def build(case: dict[str, Any], shaft: dict[str, Any], stiffening: float | None = None,
          lightening: float | None = None, per_span: int = 1) -> rs.Rotor:  # fmt: skip
    """The rotor of ``case``: a solid shaft of ``shaft``'s diameter, its Young's
    modulus × ``stiffening`` and density / ``lightening`` (default: the
    shaft's own factors), ``per_span`` elements between consecutive nodes."""
    stiffening = shaft["stiffening"] if stiffening is None else stiffening
    lightening = shaft["lightening"] if lightening is None else lightening
    diameter = shaft["diameter"]
    material = rs.Material(
        name="stiffened_steel", rho=shaft["density"] / lightening,
        E=shaft["young"] * stiffening, Poisson=shaft["poisson"],
    )  # fmt: skip
    stations = positions(case)
    elements = []
    for left, right in itertools.pairwise(stations):
        length = (right - left) / per_span
        elements += [
            rs.ShaftElement(length, 0.0, diameter, material=material) for _ in range(per_span)
        ]
    node = {z: i * per_span for i, z in enumerate(stations)}
    disk = rs.DiskElement(
        node[case["centre"]], m=case["mass"], Id=case["transverse"], Ip=case["polar"]
    )
    bearings = [
        rs.BearingElement(
            node[b["position"]], kxx=b["kx"], kyy=b["ky"], cxx=b["cx"], cyy=b["cy"],
            kzz=b.get("kz", 0.0), tag=f"bearing {i}",
        )
        for i, b in enumerate(case["bearings"])
    ]  # fmt: skip
    return rs.Rotor(elements, [disk], bearings)


def rigidity(rotor: rs.Rotor, vector: np.ndarray, centre: float) -> tuple[float, np.ndarray]:
    """How well a mode's lateral motion is that of a rigid body: 1 − |r| / |v|,
    r the residual of the least-squares fit of (x, y, α, β) at every node by a
    rigid motion (X, Y, α_c, β_c) of the centre of mass (x = X + (z − c) β_c,
    y = Y − (z − c) α_c, tilts equal), the tilts scaled by the rotor's length;
    and the fitted (X, Y, α_c, β_c), tumble's coordinates of the mode."""
    dof = rotor.number_dof
    z = np.asarray(rotor.nodes_pos) - centre
    scale = max(float(np.ptp(rotor.nodes_pos)), 1e-3)
    x, y = vector[0::dof], vector[1::dof]
    alpha, beta = vector[3::dof], vector[4::dof]
    n = len(z)
    one, nil = np.ones(n), np.zeros(n)
    # Columns: X, Y, α_c, β_c; rows: x, y, α·scale, β·scale at every node.
    design = np.block([
        [one[:, None], nil[:, None], nil[:, None], z[:, None]],
        [nil[:, None], one[:, None], -z[:, None], nil[:, None]],
        [nil[:, None], nil[:, None], scale * one[:, None], nil[:, None]],
        [nil[:, None], nil[:, None], nil[:, None], scale * one[:, None]],
    ])  # fmt: skip
    lateral = np.concatenate([x, y, scale * alpha, scale * beta])
    fit, *_ = np.linalg.lstsq(design.astype(complex), lateral, rcond=None)
    size = float(np.linalg.norm(lateral))
    if size == 0.0:
        return 0.0, fit
    return 1.0 - float(np.linalg.norm(design @ fit - lateral)) / size, fit


def rigid_modes(
    rotor: rs.Rotor, speed: float, case: dict[str, Any], per_span: int = 1,
    least: float = RIGID,
) -> dict[str, Any]:  # fmt: skip
    """The four lateral rigid-body modes of ``rotor.run_modal(speed)`` (ROSS's
    defaults: 12 modes, ARPACK): of the modes it returns, those ROSS classifies
    as lateral, with a damped frequency > 0 and a rigidity ≥ ``least``, the
    four lowest. Also what was left out, by kind. ``kappa``: ROSS's orbit
    parameter (± minor/major axis, + forward) at each bearing, in the case's
    order; ``smallest``: the smallest orbit of a node (major axis) over the largest."""
    centre = case["centre"]
    nodes = [per_span * positions(case).index(b["position"]) for b in case["bearings"]]
    modal = rotor.run_modal(speed=speed)
    whirl = modal.whirl_direction()
    picked, others = [], []
    for j, wd in enumerate(modal.wd):
        kind = modal.shapes[j].mode_type
        score, fit = rigidity(rotor, modal.evectors[: rotor.ndof, j], centre)
        entry = {
            "frequency": float(wd), "kind": kind, "rigidity": score,
            "whirl": None if whirl[j] is None else str(whirl[j]),
            "damping_ratio": float(modal.damping_ratio[j]),
            "shape": [[float(v.real), float(v.imag)] for v in fit],
        }  # fmt: skip
        orbits = modal.shapes[j].orbits
        if orbits:
            entry["kappa"] = [float(orbits[n].kappa) for n in nodes]
            majors = [float(orbit.major_axis) for orbit in orbits]
            entry["smallest"] = min(majors) / max(majors)
        if kind == "Lateral" and wd > 0 and score >= least and len(picked) < 4:
            picked.append(entry)
        else:
            others.append(entry)
    return {"modes": picked, "others": others}


def critical_speeds(rotor: rs.Rotor) -> dict[str, Any]:
    """``run_critical_speed`` of the four lowest modes (Newton on the speed where
    the i-th damped frequency equals it), at rtol 1e-10 (ROSS's default: 0.005);
    or the error it raised."""
    try:
        found = rotor.run_critical_speed(num_modes=8, rtol=1e-10)
    except RuntimeError as error:  # Newton that does not converge
        return {"error": str(error)}
    return {"wd": found.wd().tolist(), "whirl": [str(w) for w in found.whirl_direction]}


def timed(call: Any, repeat: int) -> tuple[list[float], Any]:
    """The wall times of ``repeat`` calls, and the last result."""
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = call()
        times.append(time.perf_counter() - start)
    return times, result


def campbell(request: dict[str, Any], shaft: dict[str, Any]) -> dict[str, Any]:
    """A Campbell diagram of one case, timed: ``run_campbell`` (4 frequencies a
    speed, tracked by ROSS's MAC criterion, with whirl directions) and the loop
    of ``run_modal`` it makes, keeping the four lowest damped frequencies."""
    case = request["case"]
    rotor = build(case, shaft)
    speeds = np.linspace(0.0, request["top"], request["speeds"])
    build_times, _ = timed(lambda: build(case, shaft), 5)
    repeat = request["repeat"]
    diagram_times, diagram = timed(lambda: rotor.run_campbell(speeds, frequencies=4), repeat)

    def loop() -> np.ndarray:
        return np.array([rotor.run_modal(speed=w).wd[:4] for w in speeds])

    loop_times, looped = timed(loop, repeat)

    def lean() -> np.ndarray:
        # The algorithm without ROSS's results objects: its matrices assembled once
        # (the bearings' coefficients do not depend on the speed here), then the
        # eigenvalues of the state matrix [[0, I], [−M⁻¹K, −M⁻¹(C + ΩG)]] at each speed.
        mass = rotor.M(0.0)
        stiffness = la.solve(-mass, rotor.K(0.0))
        damping = la.solve(-mass, rotor.C(0.0))
        gyroscopic = la.solve(-mass, rotor.G())
        size = mass.shape[0]
        top = np.hstack([np.zeros((size, size)), np.eye(size)])
        return np.array(
            [
                la.eigvals(np.vstack([top, np.hstack([stiffness, damping + w * gyroscopic])]))
                for w in speeds
            ]
        )

    lean_times, eigenvalues = timed(lean, repeat)
    # The four frequencies run_modal keeps, found among the lean path's eigenvalues (the
    # nearest imaginary part of each): the two paths solve the same problem.
    imaginary = np.abs(eigenvalues.imag)
    nearest = np.array(
        [
            [float(np.min(np.abs(row - wd))) for wd in kept]
            for row, kept in zip(imaginary, looped, strict=True)
        ]
    )
    return {
        "case": case["name"],
        "speeds": speeds.tolist(),
        "build_s": statistics.median(build_times),
        "campbell_s": diagram_times,
        "loop_s": loop_times,
        "lean_s": lean_times,
        "lean_miss": float(np.max(nearest / np.maximum(looped, 1e-300))),
        "wd": np.asarray(diagram.wd).tolist(),
        "whirl": np.asarray(diagram.whirl_values).tolist(),
        "loop_wd": looped.tolist(),
    }


def main() -> None:
    request = json.load(sys.stdin)
    warnings.simplefilter("ignore")  # ROSS's own warnings; its results are checked instead
    shaft = request["shaft"]
    answer: dict[str, Any] = {"versions": {"ROSS": rs.__version__}}
    for name in ("plotly", "numpy", "scipy", "numba"):
        answer["versions"][name] = __import__(name).__version__

    # The first modal analysis of a process compiles ROSS's numba orbit code.
    first = request["cases"][0]
    rotor = build(first, shaft)
    start = time.perf_counter()
    rotor.run_modal(speed=0.0)
    answer["first_modal_s"] = time.perf_counter() - start

    answer["cases"] = {}
    for case in request["cases"]:
        rotor = build(case, shaft)
        answer["cases"][case["name"]] = {
            "ndof": int(rotor.ndof),
            "speeds": [rigid_modes(rotor, w, case) for w in request["speeds"]],
            "critical": critical_speeds(rotor),
        }

    answer["sweep"] = []
    for sweep in request["sweep"]:
        rows = []
        for row in sweep["rows"]:
            per_span = row.get("per_span", 1)
            rotor = build(sweep["case"], shaft, row["stiffening"], row["lightening"], per_span)
            least = sweep.get("least", RIGID)  # 0: however bent (a soft shaft's are)
            found = rigid_modes(rotor, sweep["speed"], sweep["case"], per_span, least)
            rows.append(
                {**row, "frequencies": [m["frequency"] for m in found["modes"]],
                 "rigidity": min((m["rigidity"] for m in found["modes"]), default=0.0),
                 "shaft_mass": float(sum(e.m for e in rotor.shaft_elements))}
            )  # fmt: skip
        answer["sweep"].append({"case": sweep["case"]["name"], "rows": rows})

    answer["campbell"] = [campbell(diagram, shaft) for diagram in request["campbell"]]
    with open(sys.argv[1], "w", encoding="utf-8") as out:
        json.dump(answer, out)


if __name__ == "__main__":
    main()
