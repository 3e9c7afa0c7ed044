"""Benchmark: tumble's mesh mass properties against trimesh's, on the same closed meshes.

What is measured
----------------
Each mesh is a closed, consistently wound "bumpy torus" (a tube whose radius varies around
the ring), anisotropically scaled, rotated and translated, so its centre of mass is off the
origin and its inertia tensor has non-zero products. Its m x n grid of quads gives exactly
2 m n triangles: 10 000, 100 000, 1 000 000 and 4 000 000.

Five timings per mesh, all from the same float64 ``vertices`` (n, 3) and int64 ``faces``
(k, 3) arrays, at density 1:

* ``kernel``   tumble's compiled kernel, ``mesh_integrals(vertices, faces, reference)``, with
  the reference point (the vertex mean) computed beforehand;
* ``full``     ``tumble.mesh.mesh_mass_properties`` (vertex merging, edge checks, reference
  point, kernel, central inertia): what ``tumble.from_mesh`` costs once
  the file is read;
* ``tm v[f]``  ``trimesh.triangles.mass_properties(vertices[faces])``, building the (k, 3, 3)
  triangles array inside the timing, as trimesh's ``Trimesh.mass_properties`` does;
* ``tm tri``   the same with the triangles array built beforehand (trimesh's best case).

numba is warmed up (compiled or loaded from its cache, and its thread pool started) on a
40 000-triangle mesh before anything is timed, and every method is called once, untimed, on
each mesh before its timings; compile time is therefore excluded. The repeats of the four
methods are interleaved (one call of each per round), so a noisy shared machine slows them
alike; the table gives medians. Speed-ups are trimesh's median time over tumble's.

Accuracy: the largest relative differences between ``mesh_mass_properties`` and trimesh of
the volume, of the centre of mass (relative to the mesh's bounding-box diagonal) and of the
inertia tensor about the centre of mass (relative to its largest entry). trimesh's
``.inertia`` is about its centre of mass (when ``center_mass`` is not given) with products
``I_xy = -∫ x y dm``, tumble's convention, so the tensors are compared entry by entry.

``--breakdown`` adds where the time goes: ``merge`` (merging identical vertices), the edge check and
all of the topology checks of the full path, the kernel on 1 thread and on all of numba's
threads, and the gather ``vertices[faces]`` that trimesh needs.

Run from the repository root::

    .venv/bin/python bench/mass_properties.py                 # all sizes
    .venv/bin/python bench/mass_properties.py --sizes 10k 1M --repeat 5 --breakdown
"""

from __future__ import annotations

import argparse
import datetime
import gc
import os
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numba
import numpy as np
import trimesh
from numpy.typing import NDArray

from tumble.core.polyhedron import mesh_integrals
from tumble.core.topology import directed_edge_keys, edge_defects
from tumble.mesh import MeshRepairWarning, mesh_mass_properties
from tumble.mesh.validation import checked_topology, merge_identical_vertices

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Mesh sizes: label -> (sections around the ring, sections around the tube); 2 m n triangles.
SIZES: dict[str, tuple[int, int]] = {
    "10k": (100, 50),
    "100k": (250, 200),
    "1M": (1000, 500),
    "4M": (2000, 1000),
}

#: Default repeats per size (``--repeat`` overrides them all).
DEFAULT_REPEAT: dict[str, int] = {"10k": 7, "100k": 7, "1M": 7, "4M": 5}

#: Environment variables that change how numba's (and numpy's) threads run.
THREAD_SETTINGS = (
    "NUMBA_NUM_THREADS",
    "NUMBA_THREADING_LAYER",
    "OMP_NUM_THREADS",
    "OMP_WAIT_POLICY",
    "GOMP_SPINCOUNT",
    "OPENBLAS_NUM_THREADS",
)

#: Accuracy target: results equal to this relative difference.
TARGET_RELATIVE = 1e-10

#: Speed target: trimesh time over tumble time at 1M triangles.
TARGET_SPEEDUP = 3.0


@dataclass(frozen=True)
class Mesh:
    """A closed, outward-wound triangle mesh."""

    vertices: FloatArray
    faces: IntArray

    @property
    def n_triangles(self) -> int:
        return int(self.faces.shape[0])


def bumpy_torus(n_ring: int, n_tube: int) -> Mesh:
    """Torus of ``2 n_ring n_tube`` triangles, tube radius 0.3 (1 + 0.4 cos u), transformed.

    The shape is scaled by (1, 0.6, 0.35), rotated by 40° about (1, 2, 3) and translated by
    (0.4, -0.25, 0.7): no symmetry plane is a coordinate plane and the centre of mass is off
    the origin. Every vertex is distinct, so vertex merging changes nothing.
    """
    u = np.linspace(0.0, 2.0 * np.pi, n_ring, endpoint=False)[:, None]
    v = np.linspace(0.0, 2.0 * np.pi, n_tube, endpoint=False)[None, :]
    tube = 0.3 * (1.0 + 0.4 * np.cos(u))
    ring = 1.0 + tube * np.cos(v)
    points = np.stack(
        [ring * np.cos(u), ring * np.sin(u), np.broadcast_to(tube * np.sin(v), ring.shape)],
        axis=-1,
    ).reshape(-1, 3)
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    angle = np.radians(40.0)
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    rotation = np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * cross @ cross
    transform = rotation @ np.diag([1.0, 0.6, 0.35])
    vertices = np.ascontiguousarray(points @ transform.T + np.array([0.4, -0.25, 0.7]))

    i = np.arange(n_ring)[:, None]
    j = np.arange(n_tube)[None, :]
    a = i * n_tube + j
    b = ((i + 1) % n_ring) * n_tube + j
    c = ((i + 1) % n_ring) * n_tube + (j + 1) % n_tube
    d = i * n_tube + (j + 1) % n_tube
    # (a, b, c) runs +u then +v: ∂/∂u × ∂/∂v points out of the tube.
    quads = np.stack([a, b, c, d], axis=-1).reshape(-1, 4)
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return Mesh(vertices, np.ascontiguousarray(faces, dtype=np.int64))


def median_times(calls: dict[str, Callable[[], object]], repeat: int) -> dict[str, float]:
    """Median wall time (s) of each call: one untimed call each, then interleaved rounds."""
    for call in calls.values():
        call()
    samples: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(repeat):
        for name, call in calls.items():
            gc.collect()
            gc.disable()
            try:
                start = time.perf_counter()
                call()
                samples[name].append(time.perf_counter() - start)
            finally:
                gc.enable()
    return {name: statistics.median(times) for name, times in samples.items()}


@dataclass(frozen=True)
class Accuracy:
    """Largest relative differences between tumble and trimesh."""

    volume: float
    com: float
    inertia: float

    @property
    def worst(self) -> float:
        return max(self.volume, self.com, self.inertia)


def compare(mesh: Mesh) -> Accuracy:
    """tumble's ``mesh_mass_properties`` against trimesh's ``mass_properties``, density 1."""
    ours = mesh_mass_properties(mesh.vertices, mesh.faces, density=1.0)
    theirs = trimesh.triangles.mass_properties(mesh.vertices[mesh.faces], density=1.0)
    if not theirs.volume > 0:
        raise RuntimeError(f"Expected an outward-wound mesh, trimesh's volume is {theirs.volume}.")
    size = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    their_inertia = np.asarray(theirs.inertia)
    return Accuracy(
        volume=abs(ours.mass - theirs.volume) / abs(theirs.volume),  # density 1: mass = volume
        com=float(np.max(np.abs(ours.center_of_mass - theirs.center_mass))) / size,
        inertia=float(np.max(np.abs(ours.inertia - their_inertia)))
        / float(np.max(np.abs(their_inertia))),
    )


def benchmark(mesh: Mesh, repeat: int) -> dict[str, float]:
    """Median times (s) of tumble's kernel and full path and of trimesh, with and without gather."""
    vertices, faces = mesh.vertices, mesh.faces
    reference = vertices.mean(axis=0)
    triangles = vertices[faces]
    return median_times(
        {
            "kernel": lambda: mesh_integrals(vertices, faces, reference),
            "full": lambda: mesh_mass_properties(vertices, faces, density=1.0),
            "tm v[f]": lambda: trimesh.triangles.mass_properties(vertices[faces], density=1.0),
            "tm tri": lambda: trimesh.triangles.mass_properties(triangles, density=1.0),
        },
        repeat,
    )


def breakdown(mesh: Mesh, repeat: int) -> dict[str, float]:
    """Median times (s) of the stages of tumble's full path and of trimesh's gather."""
    vertices, faces = mesh.vertices, mesh.faces
    reference = vertices.mean(axis=0)
    threads = numba.get_num_threads()
    # The edge check sees the faces as the full path does: after the vertex merge.
    merged, renumbered = checked_topology(vertices, faces, "mesh")
    n_merged = merged.shape[0]

    def kernel_on(n_threads: int) -> Callable[[], object]:
        def call() -> object:
            numba.set_num_threads(n_threads)
            try:
                return mesh_integrals(vertices, faces, reference)
            finally:
                numba.set_num_threads(threads)

        return call

    calls: dict[str, Callable[[], object]] = {
        "merge": lambda: merge_identical_vertices(vertices),
        "edges": lambda: _edge_defects(renumbered, n_merged),
        "topology": lambda: checked_topology(vertices, faces, "mesh"),
        "kernel 1T": kernel_on(1),
    }
    if threads > 1:
        calls[f"kernel {threads}T"] = kernel_on(threads)
    calls["gather"] = lambda: vertices[faces]
    return median_times(calls, repeat)


def _edge_defects(faces: IntArray, n_vertices: int) -> object:
    """The edge check of the full path: sorted edge keys and their defects."""
    keys = directed_edge_keys(faces, n_vertices)
    keys.sort()
    return edge_defects(keys)


def with_seam(mesh: Mesh, n_ring: int, n_tube: int) -> Mesh:
    """The torus cut along the tube's seam (v = 0), as CAD exports write one: the
    quads that close the tube use copies of the seam's vertices one ulp away in
    z, so its 2 n_ring edges are boundary edges until they are welded."""
    seam = np.arange(n_ring) * n_tube  # the vertices (i, 0)
    copies = mesh.vertices[seam].copy()
    copies[:, 2] = np.nextafter(copies[:, 2], np.inf)
    vertices = np.vstack([mesh.vertices, copies])
    replace = np.arange(mesh.vertices.shape[0])
    replace[seam] = mesh.vertices.shape[0] + np.arange(n_ring)
    faces = mesh.faces.copy()
    # The quads (i, n_tube − 1) close the tube: their corners c and d are (·, 0).
    last = np.arange(n_ring) * n_tube + (n_tube - 1)
    closing = np.concatenate([last, n_ring * n_tube + last])
    faces[closing] = np.where(
        np.isin(faces[closing], seam), replace[faces[closing]], faces[closing]
    )
    return Mesh(np.ascontiguousarray(vertices), np.ascontiguousarray(faces))


def with_touching_cubes(mesh: Mesh) -> Mesh:
    """The torus and, beside it, two cubes sharing an edge: the full path then
    splits the whole mesh into closed pieces."""
    cubes = []
    for low in ((5.0, 5.0, 5.0), (5.1, 5.1, 5.0)):
        box = trimesh.creation.box(bounds=[low, np.add(low, 0.1)])
        cubes.append((np.asarray(box.vertices), np.asarray(box.faces)))
    vertices = [mesh.vertices]
    faces = [mesh.faces]
    count = mesh.vertices.shape[0]
    for points, triangles in cubes:
        vertices.append(points)
        faces.append(triangles + count)
        count += points.shape[0]
    return Mesh(np.ascontiguousarray(np.vstack(vertices)), np.ascontiguousarray(np.vstack(faces)))


def repairs(label: str, repeat: int) -> dict[str, float]:
    """Median times (s) of the full path on the closed torus, on the torus with a
    round-off seam (welded), and with two cubes sharing an edge (split into
    closed pieces)."""
    import warnings

    n_ring, n_tube = SIZES[label]
    closed = bumpy_torus(n_ring, n_tube)
    seam = with_seam(closed, n_ring, n_tube)
    pieces = with_touching_cubes(closed)

    def full(mesh: Mesh) -> Callable[[], object]:
        def call() -> object:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", MeshRepairWarning)
                return mesh_mass_properties(mesh.vertices, mesh.faces, density=1.0)

        return call

    # The seam's weld must give the closed torus back.
    welded, reference = full(seam)(), full(closed)()
    # (the welded-away copies still count in the reference point: round-off)
    assert abs(welded.mass / reference.mass - 1) < 1e-12  # type: ignore[attr-defined]
    return median_times(
        {"closed": full(closed), "seam": full(seam), "pieces": full(pieces)}, repeat
    )


def machine() -> str:
    """nproc, CPU model, numba threads and threading layer, library versions."""
    from machine import describe

    try:
        layer: str = numba.threading_layer()
    except ValueError:  # no parallel kernel has run yet
        layer = "not started"
    settings = (
        ", ".join(f"{name}={os.environ[name]}" for name in THREAD_SETTINGS if name in os.environ)
        or "none set"
    )
    return (
        f"{describe({'trimesh': trimesh.__version__})}\n"
        f"thread settings in the environment: {settings}; numba threading layer {layer}"
    )


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument(
        "--sizes",
        nargs="+",
        choices=list(SIZES),
        default=list(SIZES),
        help="mesh sizes to run (default: all)",
    )
    parser.add_argument(
        "--repeat",
        type=int,
        default=None,
        help="timed repeats per method (default: 7, and 5 at 4M)",
    )
    parser.add_argument(
        "--repairs",
        action="store_true",
        help="also time the full path on a mesh with a round-off seam (welded) and on one "
        "with closed pieces that touch (split), against the closed mesh",
    )
    parser.add_argument(
        "--breakdown",
        action="store_true",
        help="also time the stages: topology checks, kernel on 1 thread and "
        "all threads, trimesh's gather",
    )
    args = parser.parse_args(argv)
    if args.repeat is not None and args.repeat < 1:
        parser.error("--repeat must be >= 1")
    return args


def main(argv: Sequence[str] | None = None) -> None:
    args = parse_args(argv)
    sizes = [label for label in SIZES if label in args.sizes]

    start = time.perf_counter()
    # Several chunks of the kernel, so that numba also starts its thread pool here.
    warm = bumpy_torus(200, 100)
    mesh_integrals(warm.vertices, warm.faces, warm.vertices.mean(axis=0))
    mesh_mass_properties(warm.vertices, warm.faces, density=1.0)
    warm_up = time.perf_counter() - start

    print("Mesh mass properties: tumble vs trimesh (density 1, closed bumpy torus)")
    print(datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M:%S %Z"))
    print(machine())
    print(f"numba warm-up (compile or cache load) {warm_up:.2f} s, excluded from the timings")
    print()

    header = (
        f"{'triangles':>10} {'rep':>3} | {'kernel':>9} {'full':>9} | {'tm v[f]':>9} "
        f"{'tm tri':>9} | {'x kernel':>8} {'x kern*':>8} {'x full':>7} | "
        f"{'d vol':>8} {'d COM':>8} {'d I':>8}"
    )
    print(
        "times: median ms; x kernel = tm v[f] / kernel, x kern* = tm tri / kernel, "
        "x full = tm v[f] / full"
    )
    print(header)
    print("-" * len(header))
    results: dict[str, tuple[dict[str, float], Accuracy]] = {}
    for label in sizes:
        mesh = bumpy_torus(*SIZES[label])
        repeat = args.repeat or DEFAULT_REPEAT[label]
        times = benchmark(mesh, repeat)
        accuracy = compare(mesh)
        results[label] = (times, accuracy)
        ms = {name: 1e3 * t for name, t in times.items()}
        print(
            f"{mesh.n_triangles:>10} {repeat:>3} | {ms['kernel']:>9.2f} {ms['full']:>9.2f} | "
            f"{ms['tm v[f]']:>9.2f} {ms['tm tri']:>9.2f} | "
            f"{times['tm v[f]'] / times['kernel']:>8.1f} "
            f"{times['tm tri'] / times['kernel']:>8.1f} "
            f"{times['tm v[f]'] / times['full']:>7.2f} | "
            f"{accuracy.volume:>8.1e} {accuracy.com:>8.1e} {accuracy.inertia:>8.1e}",
            flush=True,
        )
        del mesh
        gc.collect()

    if "1M" in results:
        times, accuracy = results["1M"]
        kernel_speedup = times["tm v[f]"] / times["kernel"]
        full_speedup = times["tm v[f]"] / times["full"]
        print()
        print(
            f"target at 1M: speed-up >= {TARGET_SPEEDUP:g}x: kernel {kernel_speedup:.1f}x "
            f"({'met' if kernel_speedup >= TARGET_SPEEDUP else 'NOT met'}), "
            f"full path {full_speedup:.2f}x "
            f"({'met' if full_speedup >= TARGET_SPEEDUP else 'NOT met'}); "
            f"relative difference <= {TARGET_RELATIVE:g}: {accuracy.worst:.1e} "
            f"({'met' if accuracy.worst <= TARGET_RELATIVE else 'NOT met'})"
        )

    if args.repairs:
        print()
        print(
            "repairs: median ms of the full path; seam = the torus cut along a seam whose two "
            "sides differ by one ulp (welded);\npieces = the torus and two cubes sharing an "
            "edge (split into closed pieces); ratios to the closed torus (target <= 1.3 at 1M)"
        )
        row = (
            f"{'triangles':>10} | {'closed':>9} {'seam':>9} {'pieces':>9} | "
            f"{'seam x':>7} {'pieces x':>8}"
        )
        print(row)
        print("-" * len(row))
        for label in sizes:
            stages = repairs(label, args.repeat or DEFAULT_REPEAT[label])
            n = 2 * SIZES[label][0] * SIZES[label][1]
            print(
                f"{n:>10} | {1e3 * stages['closed']:>9.2f} {1e3 * stages['seam']:>9.2f} "
                f"{1e3 * stages['pieces']:>9.2f} | {stages['seam'] / stages['closed']:>7.2f} "
                f"{stages['pieces'] / stages['closed']:>8.2f}",
                flush=True,
            )
            gc.collect()

    if args.breakdown:
        print()
        print(
            "breakdown: median ms; topology = all of full's checks (merge, renumbering the "
            "faces, edges);\nkernel NT = the kernel on N numba threads; "
            "gather = building vertices[faces]"
        )
        names: list[str] = []
        for label in sizes:
            mesh = bumpy_torus(*SIZES[label])
            stages = breakdown(mesh, args.repeat or DEFAULT_REPEAT[label])
            if not names:
                names = list(stages)
                row = f"{'triangles':>10} | " + " ".join(f"{name:>12}" for name in names)
                print(row)
                print("-" * len(row))
            print(
                f"{mesh.n_triangles:>10} | "
                + " ".join(f"{1e3 * stages[name]:>12.2f}" for name in names),
                flush=True,
            )
            del mesh
            gc.collect()


if __name__ == "__main__":
    main()
