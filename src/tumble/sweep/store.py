"""The output folder of a sweep: a Zarr store chunked by bodies, and what makes it resumable.

Layout::

    DIR/sweep.json          the sweep's identity (what decides the results) and its sizes
    DIR/sweep.toml          the sweep file as given
    DIR/results.zarr/       one array per output, shape (bodies, ...), chunked by bodies
    DIR/chunks/NNNNNNNN.done  one marker per finished chunk, written last
    DIR/summary.json, DIR/report.html

Every file is written to a temporary name and renamed (Zarr's local store does
the same for each chunk), so none is ever half-written. A chunk counts as done
only once its marker exists, and the marker is written after all its arrays:
a run killed at any moment leaves chunks that are either done or redone,
whole, by the next run. The bodies of a chunk depend only on the sweep and
the chunk's index, so the redone chunk has the same bits.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError, OutputError
from tumble.files import check_output, output_error, write_text
from tumble.sweep.plan import FORMAT, Plan

__all__ = ["SweepStore", "open_results"]

STORE = "results.zarr"
IDENTITY = "sweep.json"
MARKERS = "chunks"
#: Files and folders a sweep writes into its output folder (``--force`` removes these only).
OWN = (IDENTITY, "sweep.toml", STORE, MARKERS, "summary.json", "report.html", "dask-scratch")


def fingerprint(identity: dict[str, Any]) -> str:
    """SHA-256 of the identity as canonical JSON."""
    text = json.dumps(identity, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


class SweepStore:
    """A sweep's output folder, opened for one run."""

    def __init__(self, folder: Path, plan: Plan) -> None:
        self.folder = folder
        self.plan = plan
        self._group: Any = None
        self._arrays: dict[str, Any] = {}

    # ------------------------------------------------------------ opening
    @classmethod
    def open(cls, folder: str | os.PathLike[str], plan: Plan, *, force: bool = False) -> SweepStore:
        """Claim ``folder`` for ``plan``: create it, or check that it holds the
        same sweep (to resume it).

        Raises
        ------
        InputError
            If the folder holds a different sweep, or other files, and
            ``force`` is False; or if it cannot be written.
        """
        from tumble import __version__

        path = Path(folder)
        check_output(path, "the sweep's output folder", folder=True, staged=False)
        identity = plan.identity()
        record = {
            "format": FORMAT,
            "tumble_version": __version__,
            "fingerprint": fingerprint(identity),
            "name": plan.name,
            "bodies": plan.n_bodies,
            "chunk_size": plan.chunk_size,
            "chunks": plan.n_chunks,
            "identity": identity,
        }
        if force and path.is_dir():
            for name in OWN:
                target = path / name
                if target.is_dir():
                    shutil.rmtree(target)
                elif target.exists():
                    target.unlink()
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise output_error(exc, path, "the sweep's output folder") from None
        store = cls(path, plan)
        existing = path / IDENTITY
        if existing.exists():
            store._check_same(existing, record)
        else:
            others = sorted(p.name for p in path.iterdir() if not p.name.startswith("."))
            if others:
                raise InputError(
                    f"Expected a new or empty output folder, or one holding a sweep's results, "
                    f"got {str(path)!r} with {', '.join(others[:3])}"
                    f"{' ...' if len(others) > 3 else ''} (no sweep.json): choose another folder."
                )
            write_text(existing, json.dumps(record, indent=2, allow_nan=False))
            write_text(path / "sweep.toml", plan.text)
        try:
            if not (path / STORE).exists():
                # Markers without their data (the store deleted by hand) mean nothing.
                shutil.rmtree(path / MARKERS, ignore_errors=True)
                store._create_arrays()
            (path / MARKERS).mkdir(exist_ok=True)
        except OSError as exc:
            raise output_error(exc, path / STORE, "the sweep's results") from None
        return store

    def _check_same(self, existing: Path, record: dict[str, Any]) -> None:
        try:
            old = json.loads(existing.read_text(encoding="utf-8"))
            old_identity = old["identity"]
            old_print = old["fingerprint"]
        except (OSError, ValueError, KeyError, TypeError):
            raise InputError(
                f"Expected {str(existing)!r} to be a sweep record written by tumble, got an "
                "unreadable file: use another folder, or --force to start over."
            ) from None
        if old_print != record["fingerprint"]:
            changed = sorted(
                key
                for key in set(old_identity) | set(record["identity"])
                if old_identity.get(key) != record["identity"].get(key)
            )
            raise InputError(
                f"Expected the sweep that {str(self.folder)!r} holds, got a changed sweep "
                f"({', '.join(changed)} differ{'s' if len(changed) == 1 else ''}): run it into "
                "another folder, or use --force to discard the results there."
            )
        from tumble import __version__

        if old.get("tumble_version") != __version__ and len(self.done()) < self.plan.n_chunks:
            raise InputError(
                f"Expected results from this version of tumble ({__version__}) to resume, got "
                f"{old.get('tumble_version')!r} in {str(self.folder)!r}: a resumed sweep is "
                "identical to an uninterrupted one only with the same code; use --force to "
                "start over."
            )

    def _create_arrays(self) -> None:
        import zarr

        from tumble import __version__
        from tumble.sweep.metrics import output_arrays

        plan = self.plan
        final = self.folder / STORE
        building = self.folder / f"{STORE}.partial"
        if building.exists():
            shutil.rmtree(building)
        group = zarr.open_group(
            str(building),
            mode="w",
            attributes={
                "name": plan.name,
                "description": plan.description,
                "bodies": plan.n_bodies,
                "chunk_size": plan.chunk_size,
                "samples": plan.samples,
                "grid": {a.name: a.values.tolist() for a in plan.grid},
                "random": {
                    a.name: {"distribution": a.distribution, "min": a.low, "max": a.high}
                    for a in plan.random
                },
                "fixed": plan.fixed,
                "duration": plan.duration,
                "dt": plan.dt,
                "steps": plan.n_steps,
                "method": plan.method,
                "tumble_version": __version__,
                "layout": "body b is grid point b // samples (C order over `grid`), "
                "draw b % samples",
            },
        )
        for name, (shape, dtype, unit, meaning) in output_arrays(plan).items():
            parent, _, _ = name.rpartition("/")
            if parent:
                group.require_group(parent)
            group.create_array(
                name,
                shape=(plan.n_bodies, *shape),
                chunks=(plan.chunk_size, *shape),
                dtype=dtype,
                fill_value=np.nan if dtype == "float64" else 0,
                attributes={"units": unit, "description": meaning},
                dimension_names=("body", *(("component",) if shape else ())),
            )
        os.replace(building, final)

    # ------------------------------------------------------------ chunks
    def done(self) -> set[int]:
        """Indices of the chunks whose marker exists."""
        found: set[int] = set()
        folder = self.folder / MARKERS
        if not folder.is_dir():
            return found
        for entry in os.scandir(folder):
            stem, _, suffix = entry.name.partition(".")
            if suffix == "done" and stem.isdigit():
                index = int(stem)
                if index < self.plan.n_chunks:
                    found.add(index)
        return found

    def _marker(self, index: int) -> Path:
        return self.folder / MARKERS / f"{index:08d}.done"

    @property
    def group(self) -> Any:
        if self._group is None:
            import zarr

            self._group = zarr.open_group(str(self.folder / STORE), mode="r+")
        return self._group

    def write_chunk(self, index: int, arrays: dict[str, NDArray[np.generic]]) -> None:
        """Write chunk ``index``'s arrays, then its marker.

        Raises
        ------
        OutputError
            An error of the file system (a full disk): the chunks done so far
            are kept, and running the sweep again resumes from them.
        """
        start, stop = self.plan.chunk_range(index)
        try:
            for name, data in arrays.items():
                self._array(name)[start:stop] = data
            write_text(self._marker(index), f"{start} {stop}\n")
        except (OSError, OutputError) as exc:
            cause = exc.cause if isinstance(exc, OutputError) else exc
            if cause is None:
                raise
            error = output_error(cause, self.folder / STORE, f"chunk {index} of the sweep to")
            raise OutputError(
                f"{error} The chunks done ({len(self.done())}) are kept: run the same sweep "
                "again to resume.",
                error.path,
                cause,
            ) from None

    def _array(self, name: str) -> Any:
        if name not in self._arrays:
            self._arrays[name] = self.group[name]
        return self._arrays[name]

    def read(self, name: str, index: int) -> NDArray[np.generic]:
        """Array ``name`` over chunk ``index``'s bodies."""
        start, stop = self.plan.chunk_range(index)
        return np.asarray(self._array(name)[start:stop])


def open_results(folder: str | os.PathLike[str]) -> Any:
    """The Zarr group of a sweep's results, read-only (``group["metrics/flips"][:]``)."""
    import zarr

    path = Path(folder) / STORE
    if not path.is_dir():
        raise InputError(f"Expected a sweep's output folder, got {str(folder)!r} (no {STORE}).")
    return zarr.open_group(str(path), mode="r")
