"""Real meshes: the robot links that a simulator's package ships, read by tumble,
trimesh and MuJoCo side by side.

The meshes are every STL file of ``gymnasium-robotics`` (a bench-only
dependency: the Adroit and Shadow hands, the Fetch robot, the kitchen...),
which nobody here made. For each:

* tumble: ``from_mesh(path, density=1000)``: accepted (volume, and what it
  repaired: welded seams, cancelled coincident triangles, touching pieces) or
  refused (the first words of its message);
* trimesh: ``load_mesh`` with its default processing (merging vertices), then
  whether it calls the mesh a volume (``is_volume``: watertight, consistently
  wound, outward) and its volume;
* MuJoCo: the mesh (``inertia="exact"``: the volume it bounds, not its convex
  hull, MuJoCo's default) as the only geom of a body at density 1000, compiled,
  its mass divided by the density.

A closed mesh is one trimesh calls a volume. The checks: every closed mesh is
accepted by tumble with trimesh's volume (to 1e-9 relative); every mesh tumble
refuses is one trimesh does not call a volume, and its message names the
defect. Disagreements are listed.

Run from the repository root::

    .venv/bin/python bench/real_meshes.py
"""

from __future__ import annotations

import importlib.util
import re
import warnings
from pathlib import Path

import mujoco
import trimesh

import tumble as tb
from machine import describe

DENSITY = 1000.0


def meshes() -> list[Path]:
    spec = importlib.util.find_spec("gymnasium_robotics")
    if spec is None or not spec.submodule_search_locations:
        raise SystemExit("gymnasium-robotics is not installed: pip install -e '.[bench]'")
    root = Path(next(iter(spec.submodule_search_locations)))
    return sorted(root.rglob("*.stl"))


def ours(path: Path) -> tuple[str, float | None, str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            mp = tb.from_mesh(path, density=DENSITY)
        except tb.MeshError as error:
            return "refused", None, str(error).split(":", 1)[0].split(", got ")[-1][:60]
    repaired = "; ".join(
        re.sub(r"^mesh '[^']*':? ", "", str(w.message))[:50]
        for w in caught
        if issubclass(w.category, tb.MeshRepairWarning | tb.MeshOrientationWarning)
    )
    return "accepted", mp.mass / DENSITY, repaired


def theirs(path: Path) -> tuple[bool, float]:
    mesh = trimesh.load_mesh(path)
    return bool(mesh.is_volume), float(mesh.volume)


def mujoco_volume(path: Path) -> float | str:
    xml = f"""<mujoco><asset><mesh name="m" file="{path}" inertia="exact"/></asset>
    <worldbody><body><freejoint/><geom type="mesh" mesh="m" density="{DENSITY}"/></body>
    </worldbody></mujoco>"""
    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        return f"refused: {str(error).splitlines()[0][:40]}"
    return float(model.body_mass[1]) / DENSITY


def main() -> None:
    print("Real meshes: tumble, trimesh and MuJoCo on the STL files of gymnasium-robotics")
    print(describe({"trimesh": trimesh.__version__, "mujoco": mujoco.__version__}))
    paths = meshes()
    print(f"{len(paths)} meshes, density {DENSITY:g} kg/m³; volumes in cm³\n")
    header = f"{'mesh':<34} {'tumble':>9} {'trimesh':>9} {'closed':>6} {'MuJoCo':>9}  notes"
    print(header)
    print("-" * len(header))
    accepted = refused = 0
    disagreements = []
    for path in paths:
        outcome, volume, note = ours(path)
        closed, their_volume = theirs(path)
        mj = mujoco_volume(path)
        name = "/".join(path.parts[-2:])[-34:]
        shown = f"{volume * 1e6:9.3f}" if volume is not None else f"{'refused':>9}"
        mj_shown = f"{mj * 1e6:9.3f}" if isinstance(mj, float) else f"{'refused':>9}"
        print(
            f"{name:<34} {shown} {their_volume * 1e6:9.3f} {'yes' if closed else 'no':>6} "
            f"{mj_shown}  {note}"
        )
        if outcome == "accepted":
            accepted += 1
            if closed and abs(volume / their_volume - 1) > 1e-9:  # type: ignore[operator]
                disagreements.append(f"{name}: volume {volume} vs trimesh {their_volume}")
        else:
            refused += 1
            if closed:
                disagreements.append(f"{name}: closed (trimesh) but refused: {note}")
    print(f"\naccepted {accepted}, refused {refused} of {len(paths)}")
    closed_all = sum(theirs(p)[0] for p in paths)
    print(f"trimesh calls {closed_all} of them volumes")
    if disagreements:
        print("disagreements:")
        for line in disagreements:
            print("  " + line)
    else:
        print("every closed mesh accepted with trimesh's volume; every refused one is open")


if __name__ == "__main__":
    main()
