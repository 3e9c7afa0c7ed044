"""The output folder of a sweep: a Zarr store chunked by bodies, and what makes it resumable.

Layout::

    DIR/sweep.json          the sweep's identity (what decides the results) and its sizes
    DIR/sweep.toml          the sweep file as given
    DIR/results.zarr/       one array per output, shape (bodies, ...), chunked by bodies,
                            and `computed`: True for the bodies whose chunk was written
    DIR/chunks/NNNNNNNN.done  one marker per finished chunk, written last
    DIR/summary.json, DIR/report.html

Every file is written to a temporary name and renamed (Zarr's local store does
the same for each chunk), so none is ever half-written. A chunk counts as done
only once its marker exists, and the marker is written after all its arrays:
a run killed at any moment leaves chunks that are either done or redone,
whole, by the next run. The bodies of a chunk depend only on the sweep and
the chunk's index, so the redone chunk has the same bits.

An interrupted sweep is never read as a finished one: the store's attribute
``complete`` turns true only once every chunk is done; until then a body whose
chunk was not written has ``computed`` False and reads NaN (-1 for the counts,
such as ``metrics/flips``, and for ``spin_axis``), and :func:`open_results`
warns (:class:`IncompleteSweepWarning`) with the number of bodies missing and
the command that finishes the sweep.
"""

from __future__ import annotations

import hashlib
import json
import os
import shlex
import shutil
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble._version import __version__
from tumble.errors import InputError, OutputError
from tumble.files import check_output, output_error, write_text
from tumble.sweep.plan import FORMAT, Plan

__all__ = ["IncompleteSweepWarning", "SweepStore", "open_results"]

STORE = "results.zarr"
IDENTITY = "sweep.json"
MARKERS = "chunks"
#: The store's (bodies,) array of booleans: True where the body's chunk was written.
COMPUTED = "computed"
#: What integer arrays hold for a body that was not computed (float arrays: NaN).
MISSING = -1
#: Files and folders a sweep writes into its output folder (``--force`` removes these only).
OWN = (IDENTITY, "sweep.toml", STORE, MARKERS, "summary.json", "report.html", "dask-scratch")


class IncompleteSweepWarning(UserWarning):
    """The results read are those of a sweep that was interrupted: some of its
    bodies were never computed (their metrics read NaN, -1 for counts, and the
    ``computed`` array is False for them). Running the same sweep into the same
    folder again finishes it."""


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
            elif not (path / STORE / COMPUTED).is_dir():
                store._add_computed()  # a store written before it kept the bodies computed
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
        if old.get("tumble_version") != __version__ and len(self.done()) < self.plan.n_chunks:
            raise InputError(
                f"Expected results from this version of tumble ({__version__}) to resume, got "
                f"{old.get('tumble_version')!r} in {str(self.folder)!r}: a resumed sweep is "
                "identical to an uninterrupted one only with the same code; use --force to "
                "start over."
            )

    def _create_arrays(self) -> None:
        import zarr

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
                "complete": False,
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
                fill_value=np.nan if dtype == "float64" else MISSING,
                attributes={"units": unit, "description": meaning},
                dimension_names=("body", *(("component",) if shape else ())),
            )
        self._computed_array(group)
        os.replace(building, final)

    def _computed_array(self, where: Any, **place: Any) -> Any:
        """Create the ``computed`` array in group ``where`` (or, with ``store=``,
        as an array of its own)."""
        import zarr

        plan = self.plan
        options: dict[str, Any] = {
            "shape": (plan.n_bodies,),
            "chunks": (plan.chunk_size,),
            "dtype": "bool",
            "fill_value": False,
            "attributes": {
                "units": "",
                "description": "True where the body was computed: its chunk's arrays were "
                "all written (False: the sweep was interrupted before it; run it again)",
            },
            "dimension_names": ("body",),
        }
        if where is None:
            return zarr.create_array(**place, **options)
        return where.create_array(COMPUTED, **options)

    def _add_computed(self) -> None:
        """Give a store written before it kept ``computed`` that array, True for
        the chunks done: built beside the store's arrays and renamed into it, so
        that a run killed meanwhile leaves no array that forgets a chunk."""
        final = self.folder / STORE / COMPUTED
        building = self.folder / STORE / f"{COMPUTED}.partial"
        if building.exists():
            shutil.rmtree(building)
        array = self._computed_array(None, store=str(building))
        for index in sorted(self.done()):
            start, stop = self.plan.chunk_range(index)
            array[start:stop] = True
        os.replace(building, final)

    # ------------------------------------------------------------ chunks
    def done(self) -> set[int]:
        """Indices of the chunks whose marker exists."""
        return _done(self.folder, self.plan.n_chunks)

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
            # After every array of the chunk: True means all of them are there.
            self._array(COMPUTED)[start:stop] = True
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

    def finish(self) -> None:
        """Mark the store ``complete`` once every chunk is done (a store whose
        attribute says so is read without looking further)."""
        if len(self.done()) == self.plan.n_chunks and self.group.attrs.get("complete") is not True:
            try:
                self.group.attrs.update({"complete": True})
            except OSError as exc:
                raise output_error(exc, self.folder / STORE, "the sweep's results") from None

    def _array(self, name: str) -> Any:
        if name not in self._arrays:
            self._arrays[name] = self.group[name]
        return self._arrays[name]

    def read(self, name: str, index: int) -> NDArray[np.generic]:
        """Array ``name`` over chunk ``index``'s bodies."""
        start, stop = self.plan.chunk_range(index)
        return np.asarray(self._array(name)[start:stop])


def _done(folder: Path, chunks: int) -> set[int]:
    """Indices below ``chunks`` of the chunks whose marker exists in ``folder``."""
    found: set[int] = set()
    markers = folder / MARKERS
    if not markers.is_dir():
        return found
    for entry in os.scandir(markers):
        stem, _, suffix = entry.name.partition(".")
        if suffix == "done" and stem.isdigit():
            index = int(stem)
            if index < chunks:
                found.add(index)
    return found


def open_results(folder: str | os.PathLike[str]) -> Any:
    """The Zarr group of a sweep's results, read-only (``group["metrics/flips"][:]``).

    Each array has one row per body. ``group["computed"]`` is True for the
    bodies computed, ``group.attrs["complete"]`` True once all of them are.

    Warns
    -----
    IncompleteSweepWarning
        When the sweep was interrupted: the message gives the number of bodies
        never computed and the command that finishes the sweep. Their metrics
        read NaN (-1 for counts such as ``metrics/flips``); select the others
        with ``group["computed"][:]``.

    Raises
    ------
    InputError
        If ``folder`` holds no sweep's results.
    """
    import zarr

    path = Path(folder) / STORE
    if not path.is_dir():
        raise InputError(f"Expected a sweep's output folder, got {str(folder)!r} (no {STORE}).")
    group = zarr.open_group(str(path), mode="r")
    if group.attrs.get("complete") is not True:
        _warn_if_incomplete(Path(folder), group)
    return group


#: Bodies of ``computed`` read at once while counting them.
_COUNT_SLICE = 1 << 22


def _warn_if_incomplete(folder: Path, group: Any) -> None:
    """Warn when bodies of the sweep in ``folder`` were never computed: those whose
    ``computed`` is False, or, in a store written before it kept ``computed``,
    those of the chunks without a marker."""
    bodies = int(group.attrs["bodies"])
    size = int(group.attrs["chunk_size"])
    if COMPUTED in group:
        computed = group[COMPUTED]
        missing = bodies - sum(
            int(np.count_nonzero(computed[k : k + _COUNT_SLICE]))
            for k in range(0, bodies, _COUNT_SLICE)
        )
        # A store given `computed` when it was resumed keeps the counts' old fill, 0.
        fill = int(group["metrics/flips"].fill_value) if "metrics/flips" in group else MISSING
        meaning = f"their metrics read NaN ({fill} for counts) and `computed` is False for them"
    else:
        done = _done(folder, -(-bodies // size))
        missing = bodies - sum(min(size, bodies - k * size) for k in done)
        meaning = (
            "this store was written before tumble marked the bodies computed, and their "
            "values read as its fill values (0 for counts)"
        )
    if missing == 0:
        return
    command = (
        f"tumble sweep {shlex.quote(str(folder / 'sweep.toml'))} -o {shlex.quote(str(folder))}"
    )
    warnings.warn(
        f"Expected a complete sweep in {str(folder)!r}, got {missing} of {bodies} bodies never "
        f"computed: {meaning}. Run `{command}` again to finish it.",
        IncompleteSweepWarning,
        stacklevel=3,
    )
