"""Robot descriptions: tumble's audit of every URDF of pybullet_data and
example-robot-data, side by side with what MuJoCo and PyBullet make of the same
files, and a humanoid's audit with its meshes.

1. Corpus: every URDF of both packages (the ``robot-files`` extra) audited with
   ``geometry="none"``: files a second, links, findings by code, files refused
   (and why).
2. The links whose declared tensor no body has, as tumble finds them (beyond
   the rounding of the written digits), with its correction where there is one,
   beside MuJoCo's compiler (``MjModel.from_xml_path`` of the same file: it
   refuses a file, naming the first bad body, or compiles it) and PyBullet
   (``loadURDF`` in a DIRECT client: the diagonal inertia it then integrates
   for that link, ``getDynamicsInfo``). Per file, the MuJoCo and PyBullet
   columns are for the whole file: one refusal stops MuJoCo at the first bad
   link.
3. A humanoid (TALOS, 30+ links with meshes) audited against its collision
   meshes: cold (first call in the process, compiled kernels from the cache)
   and warm (the meshes read again, nothing cached but the imports), medians.
4. The same meshes as yourdfpy hands them over (trimesh), with trimesh's own
   volume and watertightness beside tumble's solid: where tumble gives one, the
   two volumes side by side; where it refuses (holes), what trimesh returns.

Run from the repository root::

    .venv/bin/python bench/robots.py [--repeat 5] [--table 60]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import statistics
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from importlib import metadata
from pathlib import Path

from machine import describe


def corpus() -> list[Path]:
    import pybullet_data

    erd = metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots"
    )
    folders = [Path(pybullet_data.getDataPath()), Path(str(erd))]
    return sorted(p for folder in folders for p in folder.rglob("*.urdf"))


def short(path: Path) -> str:
    parts = path.parts
    for anchor in ("pybullet_data", "robots"):
        if anchor in parts:
            return "/".join(parts[parts.index(anchor) + 1 :])
    return path.name


def audit_corpus(paths: list[Path]) -> tuple[dict[Path, object], Counter[str], list[str], float]:
    import tumble as tb

    audits: dict[Path, object] = {}
    refused: list[str] = []
    codes: Counter[str] = Counter()
    start = time.perf_counter()
    for path in paths:
        try:
            audit = tb.robots.audit(path, geometry="none")
        except tb.InputError as error:
            refused.append(f"{short(path)}: {str(error)[:110]}")
            continue
        audits[path] = audit
        codes.update(f.code for f in audit.findings)
    return audits, codes, refused, time.perf_counter() - start


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """The C libraries' own printing (PyBullet's b3Printf, MuJoCo's warnings) kept
    off the table: file descriptors 1 and 2 sent to /dev/null."""
    sys.stdout.flush()
    saved = [os.dup(1), os.dup(2)]
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    try:
        yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for handle in (*saved, null):
            os.close(handle)


def mujoco_verdict(path: Path) -> str:
    """MuJoCo's compile of a URDF whose shapes are taken out (so that its verdict is
    on the inertias, not on mesh names it cannot resolve): 'compiles' or the first
    words of its refusal."""
    try:
        import mujoco
    except ImportError:
        return "(mujoco not installed)"
    text = path.read_text(encoding="utf-8", errors="replace")
    text = re.sub(r"<(visual|collision)\b.*?</\1>", "", text, flags=re.S)
    folder = Path(tempfile.mkdtemp())
    bare = folder / path.name
    bare.write_text(text, encoding="utf-8")
    here = os.getcwd()
    os.chdir(folder)  # MuJoCo writes its log (MUJOCO_LOG.TXT) into the working folder
    try:
        with quiet():
            mujoco.MjModel.from_xml_path(str(bare))
        return "compiles"
    except Exception as error:  # MuJoCo raises ValueError with its compiler's message
        return " ".join(str(error).split()).removeprefix("Error: ")[:70]
    finally:
        os.chdir(here)


def pybullet_inertia(path: Path, link: str) -> str:
    """PyBullet's diagonal inertia for ``link`` after loadURDF, or why not."""
    try:
        import pybullet
    except ImportError:
        return "(pybullet not installed)"
    client = pybullet.connect(pybullet.DIRECT)
    try:
        with quiet():
            body = pybullet.loadURDF(str(path), physicsClientId=client)
        names = {pybullet.getBodyInfo(body, physicsClientId=client)[0].decode(): -1}
        for j in range(pybullet.getNumJoints(body, physicsClientId=client)):
            names[pybullet.getJointInfo(body, j, physicsClientId=client)[12].decode()] = j
        if link not in names:
            return "(link merged away)"
        inertia = pybullet.getDynamicsInfo(body, names[link], physicsClientId=client)[2]
        return "(" + ", ".join(f"{v:.3g}" for v in inertia) + ")"
    except Exception as error:
        return f"refused: {str(error)[:40]}"
    finally:
        pybullet.disconnect(client)


def humanoid_times(repeat: int) -> tuple[str, int, float, float, Counter[str]]:
    import tumble as tb
    from tumble.robots import geometry

    erd = metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots"
    )
    path = Path(str(erd)) / "talos_data" / "robots" / "talos_full_v2.urdf"
    if not path.exists():
        path = Path(str(erd)) / "talos_data" / "robots" / "talos_reduced.urdf"
    start = time.perf_counter()
    audit = tb.robots.audit(path)
    cold = time.perf_counter() - start
    warm = []
    for _ in range(repeat):
        geometry._MESHES.clear()
        start = time.perf_counter()
        tb.robots.audit(path)
        warm.append(time.perf_counter() - start)
    return (
        short(path),
        len(audit.robot.links),
        cold,
        statistics.median(warm),
        Counter(f.code for f in audit.findings),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--table", type=int, default=80, help="rows of the invalid links' table")
    args = parser.parse_args()
    import mujoco
    import pybullet

    import tumble

    print(describe({"tumble": tumble.__version__, "mujoco": mujoco.__version__,
                    "pybullet": str(pybullet.getAPIVersion())}))  # fmt: skip
    paths = corpus()
    audits, codes, refused, seconds = audit_corpus(paths)
    links = sum(len(a.robot.links) for a in audits.values())  # type: ignore[attr-defined]
    rate = len(paths) / seconds
    print(f"\n1. corpus: {len(paths)} URDF files, {links} links, audited (geometry none) "
          f"in {seconds:.2f} s ({rate:.0f} files/s); {len(refused)} refused")  # fmt: skip
    for code, count in codes.most_common():
        print(f"   {code:<24} {count}")
    for line in refused:
        print(f"   refused: {line}")
    print("\n2. links whose declared tensor no body has")
    columns = ("file", 46), ("link", 22), ("tumble", 22), ("correction", 18), ("MuJoCo", 40)
    print("   " + " ".join(f"{name:<{width}}" for name, width in columns) + " PyBullet")
    rows = 0
    verdicts: Counter[str] = Counter()
    for path, audit in audits.items():
        findings = audit.findings  # type: ignore[attr-defined]
        bad = [f for f in findings if f.code in ("not-positive-definite", "triangle-inequality")]
        if not bad:
            continue
        mujoco_says = mujoco_verdict(path)
        for finding in bad:
            corrections = [
                f.correction for f in findings if f.link == finding.link and f.correction
            ]
            fix = str(corrections[0]) if corrections else "-"
            verdicts[
                "MuJoCo compiles the file" if mujoco_says == "compiles" else "MuJoCo refuses"
            ] += 1
            if rows < args.table:
                cells = short(path), finding.link, finding.code, fix, mujoco_says
                line = " ".join(f"{c[:w]:<{w}}" for c, (_, w) in zip(cells, columns, strict=True))
                print(f"   {line} {pybullet_inertia(path, finding.link)}")
            rows += 1
    print(f"   {rows} links; " + ", ".join(f"{k}: {v}" for k, v in verdicts.items()))
    name, count, cold, warm, found = humanoid_times(args.repeat)
    print(f"\n3. humanoid {name}: {count} links with their collision meshes: first audit "
          f"{cold:.2f} s, then {warm:.2f} s (median of {args.repeat}, meshes read again); "
          f"target < 2 s warm: {'met' if warm < 2 else 'not met'}")  # fmt: skip
    for code, number in found.most_common():
        print(f"   {code:<24} {number}")
    mesh_volumes(name)


def mesh_volumes(name: str) -> None:
    """Section 4: each collision mesh of the humanoid, trimesh's volume against tumble's."""
    import trimesh

    import tumble as tb

    erd = metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots"
    )
    robot = tb.robots.load(Path(str(erd)) / name)
    seen: set[Path] = set()
    agree, worst, refused = 0, 0.0, []
    for link in robot.links.values():
        for shape in link.shapes["collision"]:
            if shape.mesh is None or shape.mesh in seen or not shape.mesh.is_file():
                continue
            seen.add(shape.mesh)
            theirs = trimesh.load(shape.mesh, force="mesh")
            try:
                ours = shape.unit_density().mass
            except tb.InputError as error:
                refused.append((shape.mesh.name, theirs.is_watertight, theirs.volume, str(error)))
                continue
            agree += 1
            worst = max(worst, abs(theirs.volume - ours) / ours)
    print(f"\n4. {len(seen)} collision meshes of {name}: {agree} solids, volumes as "
          f"trimesh's to {worst:.1e} (largest relative difference); {len(refused)} refused "
          "by tumble:")  # fmt: skip
    for mesh, watertight, volume, why in refused:
        reason = why.split("' ", 1)[-1][:70]  # after the file's name
        print(f"   {mesh:<34} trimesh: watertight {watertight!s:<5}, volume {volume:.3e} m³ "
              f"(given without a word); tumble: {reason}...")  # fmt: skip


if __name__ == "__main__":
    main()
