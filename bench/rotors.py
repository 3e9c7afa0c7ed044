"""Benchmark: rigid rotors on elastic bearings, tumble's RigidRotor against ROSS,
side by side in one run.

ROSS (``ross-rotordynamics`` 2.3.0, a finite-element rotor-dynamics package)
runs in an environment of its own, ``bench/.venv-ross``: it imports only with
plotly < 6, which conflicts with the project's plotly (``make bench`` makes it
from ``bench/requirements-ross.txt``). This script sends the rotors as JSON to
``bench/ross_rotors.py`` run there, and reads back ROSS's frequencies, whirl
directions and timings.

Five rotors, each a rigid body on two bearings (positions: ROSS's axial
coordinate, m; the same numbers are tumble's bearing positions, measured from
the body point ``point`` at ROSS's node 0):

a. **long**: a solid cylinder, 250 kg, 0.2 m across, 1 m long (I_t > I_p:
   it has a forward conical critical speed), bearings of 1e7 N/m at 0 and
   0.8 m, its centre of mass at 0.4 m.
b. **disk-like**: a disk, 50 kg, 0.6 m across, 5 cm thick (I_p ≈ 2 I_t),
   bearings of 5e6 N/m at 0 and 0.4 m, the centre of mass at 0.2 m.
c. **anisotropic**: rotor a on bearings of 1e7 N/m along x and 2.5e7 N/m along
   y, and, in ROSS only, an axial (thrust) stiffness of 4e6 N/m at the first:
   ROSS then has an axial mode among the lowest, which the mode picking must
   leave out (tumble's model has no axial motion).
d. **damped**: rotor a with 1e4 N·s/m of damping at each bearing.
e. **overhung**: the disk of b at 0.55 m, beyond bearings of 5e6 N/m at 0 and
   0.3 m (cylindrical and conical motions coupled).

In ROSS each is a shaft of steel made ``STIFFENING`` times stiffer (Young's
modulus) and ``LIGHTENING`` times lighter (density), with nodes at the bearings
and the centre of mass, a ``DiskElement`` there with the body's mass, polar and
transverse moments (tumble's numbers, from ``tumble.shapes``), and a
``BearingElement`` at each bearing. ROSS's nodes carry six degrees of freedom,
so its modal analysis also holds axial, torsional and shaft modes; the four
lateral rigid-body modes are picked by shape (``bench/ross_rotors.py``: those
ROSS classifies as lateral whose motion a rigid body's fits to 1 %, the four
lowest).

For each rotor, at ``SPEEDS``: the four damped natural frequencies (rad/s)
from the closed forms (the symmetric rotors: roots of the characteristic
polynomials of the cylindrical and conical motions), tumble and ROSS; the
relative differences, also against tumble given what ROSS's shaft adds (its
compliance in series with each bearing and its mass on the body, see
``with_shaft``); and each mode's whirl direction in both, with the orbit
parameter κ (± minor/major axis, + forward, ROSS's) at the bearing that moves
most. Then rotors a, d and e in ROSS as the shaft is made stiffer and lighter
(the differences shrink as they should if they are the shaft's), the critical
speeds, and Campbell diagrams (``--speeds`` speeds from 0 to ``TOP``) of
rotors a (timed, ``--ross-repeat`` runs in ROSS) and e (one run in ROSS: its
whirl directions are labelled by ROSS where a's are not) in each.

Run from the repository root (``make bench`` makes ROSS's environment)::

    .venv/bin/python bench/rotors.py [--speeds 1000] [--repeat 21] [--ross-repeat 3]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy

import tumble as tb
from machine import describe

HERE = Path(__file__).resolve().parent
ROSS_PYTHON = HERE / ".venv-ross" / "bin" / "python"
MAKE_ROSS = (
    "python3 -m venv bench/.venv-ross && "
    "bench/.venv-ross/bin/pip install -r bench/requirements-ross.txt"
)

#: The shaft in ROSS: a solid 5 cm steel shaft, E × STIFFENING, density / LIGHTENING.
DIAMETER, STEEL_E, STEEL_RHO, POISSON = 0.05, 2.1e11, 7810.0, 0.3
STIFFENING = LIGHTENING = 1e6
#: Speeds of the side-by-side tables, and the top of the Campbell diagram, rad/s.
SPEEDS = (0.0, 250.0, 500.0, 1000.0)
TOP = 1000.0
#: Frequencies closer than this (relative) are a repeated pair: their whirl
#: directions are any combination of forward and backward.
REPEATED = 1e-6
#: An orbit flatter than this (|κ|) is a line: it has no direction.
FLAT = 1e-3


@dataclass(frozen=True)
class Case:
    """A rotor: the body (centre of mass at the body origin, axis body z), the
    axial position of its centre of mass (m, ROSS's coordinate) and its bearings
    (position m, kx ky N/m, cx cy N·s/m; kz, axial, ROSS only)."""

    name: str
    title: str
    body: tb.MassProperties
    centre: float
    bearings: tuple[dict[str, float], ...]

    @property
    def polar(self) -> float:
        return float(self.body.inertia[2, 2])

    @property
    def transverse(self) -> float:
        return float(self.body.inertia[0, 0])

    def request(self) -> dict[str, Any]:
        """The case as ROSS's side reads it."""
        return {
            "name": self.name, "mass": self.body.mass, "polar": self.polar,
            "transverse": self.transverse, "centre": self.centre,
            "bearings": list(self.bearings),
        }  # fmt: skip


def bearing(
    position: float, k: float | tuple[float, float], c: float = 0.0, kz: float = 0.0
) -> dict[str, float]:
    """A bearing at ``position`` (m) of stiffness ``k`` (N/m, or (k_x, k_y)),
    damping ``c`` (N·s/m) and, in ROSS only, axial stiffness ``kz`` (N/m)."""
    kx, ky = k if isinstance(k, tuple) else (k, k)
    return {"position": position, "kx": kx, "ky": ky, "cx": c, "cy": c, "kz": kz}


LONG = tb.shapes.solid_cylinder(250.0, 0.1, 1.0)
DISK = tb.shapes.solid_cylinder(50.0, 0.3, 0.05)
CASES = (
    Case("a", "long rotor", LONG, 0.4, (bearing(0.0, 1e7), bearing(0.8, 1e7))),
    Case("b", "disk-like rotor", DISK, 0.2, (bearing(0.0, 5e6), bearing(0.4, 5e6))),
    Case("c", "anisotropic bearings (ROSS: with a thrust stiffness)", LONG, 0.4,
         (bearing(0.0, (1e7, 2.5e7), kz=4e6), bearing(0.8, (1e7, 2.5e7)))),
    Case("d", "damped bearings", LONG, 0.4, (bearing(0.0, 1e7, 1e4), bearing(0.8, 1e7, 1e4))),
    Case("e", "overhung disk", DISK, 0.55, (bearing(0.0, 5e6), bearing(0.3, 5e6))),
)  # fmt: skip


# ------------------------------------------------------------------ tumble
def rigid_rotor(case: Case, bearings: tuple[dict[str, float], ...] | None = None) -> Any:
    """tumble's rotor of ``case``: bearing positions measured from the body point
    at ROSS's axial coordinate 0."""
    return tb.theory.RigidRotor(
        case.body,
        [tb.theory.Bearing(b["position"], (b["kx"], b["ky"]), (b["cx"], b["cy"]))
         for b in bearings or case.bearings],
        point=(0.0, 0.0, -case.centre),
    )  # fmt: skip


def with_shaft(
    case: Case, stiffening: float = STIFFENING, lightening: float = LIGHTENING,
    shear: bool = True,
) -> Any:  # fmt: skip
    """tumble's rotor with what ROSS's shaft adds (each measured by the sweep of
    ``main``): its compliance in series with each bearing (the shaft from the centre of mass
    to a bearing at arm a is a Timoshenko cantilever: 1/k' = 1/k + |a|³/(3 E I)
    + |a|/(κ G A), Cowper's κ, as ROSS) and its mass and moments added to the
    body (a solid cylinder between the end nodes). Only for undamped bearings
    on either side of the centre of mass (elsewhere the shaft is no such
    cantilever), else None. ``shear=False`` leaves out the shear term."""
    arms = [b["position"] - case.centre for b in case.bearings]
    damped = any(b["cx"] or b["cy"] for b in case.bearings)
    if damped or sorted(np.sign(arms)) != [-1.0, 1.0]:
        return None
    e = STEEL_E * stiffening
    g = e / (2 * (1 + POISSON))
    kappa = 6 * (1 + POISSON) / (7 + 6 * POISSON)
    area, second = math.pi * DIAMETER**2 / 4, math.pi * DIAMETER**4 / 64
    soft = []
    for b, a in zip(case.bearings, arms, strict=True):
        compliance = abs(a) ** 3 / (3 * e * second) + shear * abs(a) / (kappa * g * area)
        soft.append({**b, "kx": 1 / (1 / b["kx"] + compliance),
                     "ky": 1 / (1 / b["ky"] + compliance)})  # fmt: skip
    ends = [min(*arms, 0.0), max(*arms, 0.0)]  # from the centre of mass
    length = ends[1] - ends[0]
    own = tb.shapes.solid_cylinder(STEEL_RHO / lightening * area * length, DIAMETER / 2, length)
    shaft = tb.MassProperties(own.mass, [0.0, 0.0, sum(ends) / 2], own.inertia)
    heavier = Case(case.name, case.title, case.body + shaft, case.centre, tuple(soft))
    return rigid_rotor(heavier)


def closed_form(case: Case, speed: float) -> tuple[np.ndarray, str] | None:
    """The four damped frequencies (rad/s, ascending) of a symmetric rotor
    (Σ k a = Σ c a = 0: cylindrical and conical motions apart), or None; and
    which form. Undamped, isotropic ("formula"): √(Σk/m) twice and
    (±I_p Ω + √(I_p² Ω² + 4 I_t K_θ)) / 2 I_t, K_θ = Σ k a². Damped, isotropic
    ("quadratics"): the roots of m s² + C s + K and, for φ = α + i β,
    I_t s² + (C_θ − i I_p Ω) s + K_θ, by the quadratic formula. Anisotropic
    ("quartic"): m s² + C_x s + K_x, the same in y, and the roots of
    (I_t s² + C_θy s + K_θy)(I_t s² + C_θx s + K_θx) + (I_p Ω s)² (the tilt
    about x is held by the y stiffnesses)."""
    arms = np.array([b["position"] - case.centre for b in case.bearings])

    def total(key: str, power: int) -> float:
        return float(sum(b[key] * a**power for b, a in zip(case.bearings, arms, strict=True)))

    def quadratic(a: complex, b: complex, c: complex) -> list[complex]:
        root = np.sqrt(complex(b * b - 4 * a * c))
        return [(-b + root) / (2 * a), (-b - root) / (2 * a)]

    keys = ("kx", "ky", "cx", "cy")
    if any(abs(total(k, 1)) > 1e-9 * max(total(k, 0), 1.0) * np.abs(arms).max() for k in keys):
        return None
    m, ip, it = case.body.mass, case.polar, case.transverse
    isotropic = all(b["kx"] == b["ky"] and b["cx"] == b["cy"] for b in case.bearings)
    undamped = all(total(k, 0) == 0 for k in ("cx", "cy"))
    if isotropic and undamped:
        cylindrical = math.sqrt(total("kx", 0) / m)
        root = math.sqrt(ip**2 * speed**2 + 4 * it * total("kx", 2))
        conical = [(root - ip * speed) / (2 * it), (root + ip * speed) / (2 * it)]
        return np.sort([cylindrical, cylindrical, *conical]), "formula"
    if isotropic:
        translation = quadratic(m, total("cx", 0), total("kx", 0))[0]
        tilts = quadratic(it, total("cx", 2) - 1j * ip * speed, total("kx", 2))
        found = [abs(translation.imag)] * 2 + [abs(s.imag) for s in tilts]
        return np.sort(found), "quadratics"
    roots = [*quadratic(m, total("cx", 0), total("kx", 0)),
             *quadratic(m, total("cy", 0), total("ky", 0))]  # fmt: skip
    tilt_y = np.array([it, total("cy", 2), total("ky", 2)])
    tilt_x = np.array([it, total("cx", 2), total("kx", 2)])
    quartic = np.polymul(tilt_y, tilt_x) + np.array([0, 0, (ip * speed) ** 2, 0, 0])
    roots += list(np.roots(quartic))
    return np.sort([r.imag for r in roots if r.imag > 0]), "quartic"


def orbit_kappa(rotor: Any, shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For modes (..., 4 coordinates): κ = ± minor/major axis of the orbit at the
    bearing that moves most (+: forward, x towards y), and that bearing's index."""
    x = shapes[..., [0]] + rotor.arms * shapes[..., [3]]
    y = shapes[..., [1]] - rotor.arms * shapes[..., [2]]
    total = np.abs(x) ** 2 + np.abs(y) ** 2
    spread = np.hypot(np.abs(x) ** 2 - np.abs(y) ** 2, 2 * np.real(np.conj(x) * y))
    major, minor = (total + spread) / 2, np.maximum((total - spread) / 2, 0.0)
    sign = np.where(np.imag(np.conj(x) * y) < 0, 1.0, -1.0)
    kappa = sign * np.sqrt(minor / np.where(major > 0, major, 1.0))
    k = np.argmax(total, axis=-1)
    return np.take_along_axis(kappa, k[..., None], axis=-1)[..., 0], k


def repeated(frequencies: np.ndarray) -> np.ndarray:
    """(..., 4) True where a frequency has a neighbour within ``REPEATED``."""
    close = np.abs(np.diff(frequencies, axis=-1)) <= REPEATED * frequencies[..., 1:]
    pad = np.zeros((*close.shape[:-1], 1), dtype=bool)
    return np.concatenate([close, pad], axis=-1) | np.concatenate([pad, close], axis=-1)


# ------------------------------------------------------------------ ROSS
def ross(request: dict[str, Any], python: Path) -> dict[str, Any]:
    """Run ``ross_rotors.py`` in ROSS's environment: the request on its stdin,
    its answer from a file (importing ROSS prints to stdout)."""
    with tempfile.TemporaryDirectory() as folder:
        answer = Path(folder) / "answer.json"
        done = subprocess.run(
            [str(python), str(HERE / "ross_rotors.py"), str(answer)],
            input=json.dumps(request), capture_output=True, text=True, check=False,
        )  # fmt: skip
        if done.returncode != 0:
            sys.exit(f"ROSS's side failed (exit {done.returncode}):\n{done.stderr[-3000:]}")
        return json.loads(answer.read_text())


def relative(a: Any, b: Any) -> np.ndarray:
    return np.asarray(a, dtype=float) / np.asarray(b, dtype=float) - 1.0


def label(forward: bool, kappa: float, pair: bool) -> str:
    """tumble's direction, and why it is not compared where it is not."""
    if pair:
        return "pair"
    if abs(kappa) < FLAT:
        return "line"
    return "F" if forward else "B"


def short(whirl: str | None) -> str:
    return {"Forward": "F", "Backward": "B", "Mixed": "Mixed"}.get(str(whirl), str(whirl))


# ------------------------------------------------------------------ reports
def side_by_side(case: Case, found: dict[str, Any]) -> dict[str, Any]:
    """Print the frequencies of ``case`` at ``SPEEDS`` and return the largest
    differences and the direction tallies."""
    rotor, stiff = rigid_rotor(case), with_shaft(case)
    whirl = rotor.whirl(SPEEDS)
    kappas, nearest = orbit_kappa(rotor, whirl.shapes)
    pairs = repeated(whirl.frequencies)
    shifted = stiff.frequencies(SPEEDS) if stiff is not None else None
    print(
        f"\n{case.name}. {case.title}: m {case.body.mass:g} kg, I_p {case.polar:.4g}, "
        f"I_t {case.transverse:.4g} kg·m²; ROSS: {found['ndof']} degrees of freedom"
    )
    print(
        f"  {'Ω':>6s} {'closed form':>13s} {'tumble':>13s} {'ROSS':>13s} {'tumble/closed':>14s}"
        f" {'ROSS/tumble':>12s} {'ROSS/tumble+shaft':>18s}  {'whirl tumble (κ)':18s}"
        f" {'ROSS (κ)':14s} {'ROSS left out':s}"
    )
    worst: dict[str, float | None] = {"closed": None, "ross": 0.0, "shaft": None}
    tally = {"agree": 0, "differ": 0, "Mixed": 0, "pair": 0, "line": 0}
    # The smallest node orbit (over the largest) of ROSS's 'Mixed' modes, and of the others.
    still = {"Mixed": 0.0, "labelled": 1.0}
    rigidity = {"picked": 1.0, "lateral left out": 0.0}
    for i, speed in enumerate(SPEEDS):
        exact = closed_form(case, speed)
        modes = found["speeds"][i]["modes"]
        if len(modes) != 4:
            sys.exit(f"case {case.name} at {speed:g} rad/s: ROSS gave {len(modes)} rigid modes")
        for mode in modes:
            rigidity["picked"] = min(rigidity["picked"], mode["rigidity"])
        for other in found["speeds"][i]["others"]:
            if other["kind"] == "Lateral":
                rigidity["lateral left out"] = max(rigidity["lateral left out"], other["rigidity"])
        left_out = ", ".join(
            f"{o['kind'].lower()} {o['frequency']:.4g} (ζ {o['damping_ratio']:.2g})"
            for o in found["speeds"][i]["others"]
        )
        for j, mode in enumerate(modes):
            mine = whirl.frequencies[i, j]
            shown_exact = f"{exact[0][j]:13.6f}" if exact else f"{'—':>13s}"
            versus_exact = f"{relative(mine, exact[0][j]):14.1e}" if exact else f"{'—':>14s}"
            theirs = mode["frequency"]
            versus_shaft = (f"{relative(theirs, shifted[i, j]):18.1e}" if shifted is not None
                            else f"{'—':>18s}")  # fmt: skip
            if exact:
                worst["closed"] = max(worst["closed"] or 0.0, abs(relative(mine, exact[0][j])))
            worst["ross"] = max(worst["ross"] or 0.0, abs(relative(theirs, mine)))
            if shifted is not None:
                found_shift = abs(relative(theirs, shifted[i, j]))
                worst["shaft"] = max(worst["shaft"] or 0.0, found_shift)
            kappa = kappas[i, j]
            own = label(bool(whirl.forward[i, j]), kappa, bool(pairs[i, j]))
            other = short(mode["whirl"])
            other_kappa = mode["kappa"][nearest[i, j]] if mode["kappa"] else float("nan")
            if own in ("pair", "line"):
                tally[own] += 1
            elif other == "Mixed":
                tally["Mixed"] += 1
                still["Mixed"] = max(still["Mixed"], mode["smallest"])
            else:
                tally["agree" if own == other else "differ"] += 1
                still["labelled"] = min(still["labelled"], mode["smallest"])
            print(
                f"  {speed:6g} {shown_exact} {mine:13.6f} {theirs:13.6f} {versus_exact}"
                f" {relative(theirs, mine):12.1e} {versus_shaft}  {own:4s} ({kappa:+.3f})"
                f"{'':6s} {other:5s} ({other_kappa:+.3f}) {left_out if j == 0 else ''}"
            )
    if exact:
        print(f"  closed form: {exact[1]}")
    return {**worst, "tally": tally, "still": still, "rigidity": rigidity}


def sweep_table(answer: list[dict[str, Any]], case: Case, speed: float) -> None:
    """ROSS's frequencies of ``case`` as its shaft changes, against tumble and
    tumble with the shaft's compliance and mass (where ``with_shaft`` has them)."""
    mine = rigid_rotor(case).frequencies(speed)
    print(
        f"\nROSS's shaft made stiffer and lighter: case {case.name} at Ω = {speed:g} rad/s "
        f"(tumble: {', '.join(f'{f:.6f}' for f in mine)} rad/s)"
    )
    print(
        f"  {'E ×':>7s} {'ρ /':>7s} {'elements':>8s} {'shaft kg':>9s} {'rigidity':>9s}   "
        f"{'ROSS/tumble − 1, each mode':44s} {'ROSS/(tumble+shaft) − 1, largest':>32s}"
    )
    for row in answer:
        theirs = np.array(row["frequencies"])
        if len(theirs) != 4:
            print(f"  {row['stiffening']:7.0e} {row['lightening']:7.0e}: ROSS gave {len(theirs)}")
            continue
        stiff = with_shaft(case, row["stiffening"], row["lightening"])
        shown = (f"{np.abs(relative(theirs, stiff.frequencies(speed))).max():32.2e}"
                 if stiff is not None else f"{'—':>32s}")  # fmt: skip
        print(
            f"  {row['stiffening']:7.0e} {row['lightening']:7.0e} {row.get('per_span', 1):8d}"
            f" {row['shaft_mass']:9.2e} {row['rigidity']:9.6f}   "
            + " ".join(f"{r:10.2e}" for r in relative(theirs, mine))
            + f"  {shown}"
        )
    soft = [r for r in answer if r["stiffening"] == 1.0 and r["lightening"] > 1.0]
    for row in soft:
        bending = with_shaft(case, row["stiffening"], row["lightening"], shear=False)
        if bending is not None:
            miss = np.abs(relative(row["frequencies"], bending.frequencies(speed))).max()
            print(
                f"  E × 1, ρ / {row['lightening']:g} against tumble + shaft without its shear "
                f"term: {miss:.1e}"
            )
    finer = [r for r in answer if r.get("per_span", 1) > 1]
    for row in finer:
        same = next(r for r in answer if r.get("per_span", 1) == 1
                    and r["stiffening"] == row["stiffening"]
                    and r["lightening"] == row["lightening"])  # fmt: skip
        change = np.abs(relative(row["frequencies"], same["frequencies"])).max()
        print(
            f"  {row['per_span']} elements a span instead of 1 (E × {row['stiffening']:g}, "
            f"ρ / {row['lightening']:g}): the frequencies move by at most {change:.1e}"
        )


def critical_closed(case: Case) -> list[float] | None:
    """The undamped critical speeds of a symmetric rotor (rad/s): √(Σk_x/m),
    √(Σk_y/m), and the positive roots u = Ω² of the conical motion's
    synchronous equation (I_t² − I_p²) u² − I_t (K_θx + K_θy) u + K_θx K_θy = 0
    (isotropic: u = K_θ / (I_t ∓ I_p), forward and backward whirl)."""
    if closed_form(case, 0.0) is None:
        return None
    arms = [b["position"] - case.centre for b in case.bearings]
    k = {key: sum(b[key] for b in case.bearings) for key in ("kx", "ky")}
    tilt = {key: sum(b[key] * a * a for b, a in zip(case.bearings, arms, strict=True))
            for key in ("kx", "ky")}  # fmt: skip
    it, ip = case.transverse, case.polar
    roots = np.roots([it**2 - ip**2, -it * (tilt["kx"] + tilt["ky"]), tilt["kx"] * tilt["ky"]])
    found = [math.sqrt(k["kx"] / case.body.mass), math.sqrt(k["ky"] / case.body.mass)]
    found += [math.sqrt(u.real) for u in roots if abs(u.imag) == 0 and u.real > 0]
    return sorted(set(found))


def critical_table(found: dict[str, Any]) -> None:
    print(
        "\nCritical speeds, rad/s. tumble: critical_speeds(backward=False / True), undamped;"
        "\nROSS: run_critical_speed(num_modes=8, rtol=1e-10), Newton on the i-th damped frequency"
    )
    for case in CASES:
        rotor = rigid_rotor(case)
        theirs = found[case.name]["critical"]
        shown = (
            ", ".join(f"{w:.4f} {short(d)}" for w, d in zip(theirs["wd"], theirs["whirl"],
                                                            strict=True))
            if "wd" in theirs else f"failed: {theirs['error']}"
        )  # fmt: skip
        closed = critical_closed(case)
        listed = {
            "tumble, forward": rotor.critical_speeds(backward=False),
            "tumble, both": rotor.critical_speeds(backward=True),
            "closed form": closed,
        }
        text = "; ".join(
            f"{name} {', '.join(f'{w:.4f}' for w in values)}"
            for name, values in listed.items()
            if values is not None
        )
        print(f"  {case.name}: {text}\n     ROSS {shown}")


def median(values: list[float]) -> float:
    return statistics.median(values)


def timings(case: Case, answer: dict[str, Any], repeat: int) -> dict[str, float]:
    """Time tumble's Campbell diagram of ``case``, print both sides' times and
    how the diagrams agree; return the ratios."""
    speeds = np.array(answer["speeds"])
    rotor = rigid_rotor(case)
    clock: dict[str, list[float]] = {"build": [], "whirl": [], "frequencies": [], "eigvals": []}
    inverse = np.linalg.inv(rotor.mass_matrix)
    for _ in range(repeat):
        start = time.perf_counter()
        rigid_rotor(case)
        clock["build"].append(time.perf_counter() - start)
        start = time.perf_counter()
        whirl = rotor.whirl(speeds)
        clock["whirl"].append(time.perf_counter() - start)
        start = time.perf_counter()
        rotor.frequencies(speeds)
        clock["frequencies"].append(time.perf_counter() - start)
        # The same stacked eigenproblem without eigenvectors: what frequencies alone need.
        start = time.perf_counter()
        state = np.zeros((len(speeds), 8, 8))
        state[:, :4, 4:] = np.eye(4)
        state[:, 4:, :4] = -inverse @ rotor.stiffness
        state[:, 4:, 4:] = -inverse @ rotor.damping - speeds[:, None, None] * (
            inverse @ rotor.gyroscopic
        )
        np.linalg.eigvals(state)
        clock["eigvals"].append(time.perf_counter() - start)
    ross_runs = len(answer["campbell_s"])
    rows = [
        ("tumble", "RigidRotor(...)", median(clock["build"]), repeat),
        ("tumble", "rotor.whirl(speeds)", median(clock["whirl"]), repeat),
        ("tumble", "rotor.frequencies(speeds)", median(clock["frequencies"]), repeat),
        ("numpy", "np.linalg.eigvals of the same stack", median(clock["eigvals"]), repeat),
        ("ROSS", "Rotor(...)", answer["build_s"], 5),
        ("ROSS", "rotor.run_campbell(speeds, frequencies=4)", median(answer["campbell_s"]),
         ross_runs),
        ("ROSS", "[rotor.run_modal(w).wd[:4] for w in speeds]", median(answer["loop_s"]),
         ross_runs),
        ("ROSS", "lean: M, K, C, G once, eigvals a speed", median(answer["lean_s"]), ross_runs),
    ]  # fmt: skip
    print(
        f"\nCampbell diagram, case {case.name}: {len(speeds)} speeds from 0 to {speeds[-1]:g} "
        "rad/s, medians (after a first call)"
    )
    print(f"  {'who':7s} {'call':46s} {'median s':>10s} {'runs':>5s}")
    for who, call, seconds, runs in rows:
        print(f"  {who:7s} {call:46s} {seconds:10.5f} {runs:5d}")
    ratio_whirl = median(answer["campbell_s"]) / median(clock["whirl"])
    ratio_freq = median(answer["loop_s"]) / median(clock["frequencies"])
    ratio_lean = median(answer["lean_s"]) / median(clock["frequencies"])
    print(
        f"  what a user pays (the API): ROSS run_campbell / tumble whirl: {ratio_whirl:.0f}×; "
        f"ROSS run_modal loop / tumble frequencies: {ratio_freq:.0f}× (goal ≥ 100×: "
        f"{'met' if min(ratio_whirl, ratio_freq) >= 100 else 'not met'})"
    )
    print(
        f"  the algorithm (ROSS's matrices, eigvals a speed): ROSS lean / tumble frequencies: "
        f"{ratio_lean:.1f}×; its eigenvalues hold run_modal's four frequencies to "
        f"{answer['lean_miss']:.1e} (relative)"
    )
    # The diagram itself, side by side: ROSS tracks modes by MAC; sorted here.
    theirs = np.array(answer["wd"])
    order = np.argsort(theirs, axis=1)
    theirs = np.take_along_axis(theirs, order, axis=1)
    values = np.take_along_axis(np.array(answer["whirl"]), order, axis=1)
    kappas, _ = orbit_kappa(rotor, whirl.shapes)
    pairs = repeated(whirl.frequencies)
    comparable = ~pairs & (np.abs(kappas) >= FLAT)
    other = np.where(values == 0.0, 1, np.where(values == 1.0, 0, -1))  # 1 F, 0 B, −1 Mixed
    agree = comparable & (other == whirl.forward)
    mixed = comparable & (other == -1)
    looped = np.sort(np.array(answer["loop_wd"]), axis=1)
    spread = np.abs(relative(theirs, whirl.frequencies)).max()
    print(
        f"  over the diagram: max |ROSS/tumble − 1| {spread:.1e} (run_modal loop: "
        f"{np.abs(relative(looped, whirl.frequencies)).max():.1e}); "
        f"directions of {comparable.sum()} modes neither in a repeated pair nor flat: "
        f"{agree.sum()} agree, {mixed.sum()} ROSS 'Mixed', "
        f"{(comparable & ~agree & ~mixed).sum()} differ"
    )
    return {"whirl": ratio_whirl, "frequencies": ratio_freq, "lean": ratio_lean}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=1000, help="speeds of the Campbell diagram")
    parser.add_argument("--repeat", type=int, default=21, help="timed runs of tumble")
    parser.add_argument("--ross-repeat", type=int, default=3, help="timed runs of ROSS")
    parser.add_argument("--ross-python", type=Path, default=ROSS_PYTHON)
    args = parser.parse_args()
    if not args.ross_python.is_file():
        print(f"ROSS's environment is missing ({args.ross_python}): make it with `{MAKE_ROSS}`")
        sys.exit(2)

    # tumble's first call in this process, before any other.
    rotor = rigid_rotor(CASES[0])
    start = time.perf_counter()
    rotor.whirl(0.0)
    first = time.perf_counter() - start

    shaft = {"diameter": DIAMETER, "young": STEEL_E, "density": STEEL_RHO, "poisson": POISSON,
             "stiffening": STIFFENING, "lightening": LIGHTENING}  # fmt: skip
    rows = [{"stiffening": s, "lightening": s} for s in (1.0, 1e2, 1e4, 1e6, 1e8, 1e10)]
    rows += [{"stiffening": 1e6, "lightening": 1.0}, {"stiffening": 1.0, "lightening": 1e6},
             {"stiffening": 1e2, "lightening": 1e2, "per_span": 4}]  # fmt: skip
    fewer = [{"stiffening": s, "lightening": s} for s in (1e4, 1e6, 1e8)]
    request = {
        "shaft": shaft,
        "cases": [case.request() for case in CASES],
        "speeds": list(SPEEDS),
        # Case a: the four lowest lateral modes however bent (a steel shaft bends).
        "sweep": [{"case": CASES[0].request(), "speed": TOP, "rows": rows, "least": 0.0}]
        + [{"case": CASES[i].request(), "speed": TOP, "rows": fewer} for i in (3, 4)],
        # Case a timed; case e, whose whirl directions ROSS labels, once.
        "campbell": [{"case": CASES[i].request(), "top": TOP, "speeds": args.speeds,
                      "repeat": repeat} for i, repeat in ((0, args.ross_repeat), (4, 1))],
    }  # fmt: skip
    start = time.perf_counter()
    answer = ross(request, args.ross_python)
    took = time.perf_counter() - start
    versions = answer["versions"]
    print(describe({
        "scipy": scipy.__version__,
        "ROSS": f"{versions.pop('ROSS')} (its environment: "
        + ", ".join(f"{k} {v}" for k, v in versions.items()) + ")",
    }))  # fmt: skip
    print(
        f"ROSS's shaft: {DIAMETER * 100:g} cm, steel's E × {STIFFENING:g}, density / "
        f"{LIGHTENING:g}; ROSS's side took {took:.1f} s in all"
    )

    summary = {}
    for case in CASES:
        summary[case.name] = side_by_side(case, answer["cases"][case.name])
    by_name = {case.name: case for case in CASES}
    for sweep in answer["sweep"]:
        sweep_table(sweep["rows"], by_name[sweep["case"]], TOP)
    critical_table(answer["cases"])
    ratios = {
        diagram["case"]: timings(by_name[diagram["case"]], diagram, args.repeat)
        for diagram in answer["campbell"]
    }
    print(
        f"\nFirst call in a process: tumble's whirl {first * 1e3:.1f} ms, ROSS's run_modal "
        f"{answer['first_modal_s']:.2f} s (numba compiles ROSS's orbit code)"
    )

    print("\nLargest relative differences over the side-by-side tables:")
    for name, worst in summary.items():
        tally = worst["tally"]
        shaft_text = "—" if worst["shaft"] is None else f"{worst['shaft']:.1e}"
        closed_text = "—" if worst["closed"] is None else f"{worst['closed']:.1e}"
        print(
            f"  {name}: tumble/closed {closed_text}, ROSS/tumble {worst['ross']:.1e}, "
            f"ROSS/(tumble+shaft) {shaft_text}; directions: {tally['agree']} agree, "
            f"{tally['differ']} differ, {tally['Mixed']} ROSS 'Mixed', not compared: "
            f"{tally['pair']} in repeated pairs, {tally['line']} flat"
        )
        print(
            f"     rigidity of the four picked ≥ {worst['rigidity']['picked']:.6f}, of the "
            f"lateral modes left out ≤ {worst['rigidity']['lateral left out']:.3f}"
        )
        if tally["Mixed"]:
            print(
                f"     ROSS 'Mixed': a node's orbit ≤ {worst['still']['Mixed']:.1e} of the "
                f"largest; its F and B: ≥ {worst['still']['labelled']:.1e}"
            )
    for name, ratio in ratios.items():
        print(
            f"Speed, case {name}: ROSS run_campbell / tumble whirl {ratio['whirl']:.0f}×, "
            f"ROSS run_modal loop / tumble frequencies {ratio['frequencies']:.0f}×"
        )


if __name__ == "__main__":
    main()
