"""Running a sweep: load, claim the output folder, compute the missing chunks, report."""

from __future__ import annotations

import copy
import json
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.config import Builtins, read_source
from tumble.errors import InputError
from tumble.files import write_text
from tumble.locks import OutputLock
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import body_bytes
from tumble.sweep.plan import Plan
from tumble.sweep.schema import SweepError, check_address
from tumble.sweep.store import OWN, SweepStore, fingerprint
from tumble.sweep.summary import MapData

__all__ = [
    "CHUNK_BYTES_PER_BODY",
    "SweepSummary",
    "builtin_sweeps",
    "check_chunk_memory",
    "claim_folder",
    "load_sweep",
    "run_sweep",
    "show_sweep",
    "sweep_folder",
    "warn_if_short_of_room",
]

Progress = Callable[[int, int], object] | None


@dataclass(frozen=True)
class SweepSummary:
    """What a sweep run did and found (also written to ``summary.json``).

    Attributes
    ----------
    name, description : from the sweep file.
    folder : the output folder; ``store``, ``report``, ``summary_file`` its files.
    bodies, chunk_size, chunks : sizes of the sweep.
    chunks_run, chunks_reused : chunks computed by this run, and found done.
    steps, dt, duration, method : the integration (dt in s).
    backend : where the chunks ran.
    seconds : wall time of this run's computation (writing included).
    body_steps_per_second : bodies × steps computed by this run per second
        (None when it computed nothing).
    metrics : per metric: unit, bodies with a finite value, NaN count, mean,
        min, max (and for flips the fraction of bodies that flipped).
    fingerprint : SHA-256 of what decides the results.
    maps : the maps of the sweep file's [report] as numbers, for
        :func:`tumble.report.write_sweep_report` (not in ``summary.json``).
    text : the sweep file as written.
    """

    name: str
    description: str
    folder: Path
    bodies: int
    chunk_size: int
    chunks: int
    chunks_run: int
    chunks_reused: int
    steps: int
    dt: float
    duration: float
    method: str
    backend: str
    seconds: float
    body_steps_per_second: float | None
    metrics: dict[str, Any] = field(default_factory=dict)
    fingerprint: str = ""
    maps: tuple[MapData, ...] = field(default=(), repr=False)
    text: str = field(default="", repr=False)

    @property
    def store(self) -> Path:
        return self.folder / "results.zarr"

    @property
    def report(self) -> Path:
        return self.folder / "report.html"

    @property
    def summary_file(self) -> Path:
        return self.folder / "summary.json"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (paths as strings; without the maps and the file's text)."""
        data = {
            name: getattr(self, name)
            for name in self.__dataclass_fields__
            if name not in ("maps", "text")
        }
        data["metrics"] = copy.deepcopy(self.metrics)
        data["folder"] = str(self.folder)
        data["files"] = {
            "store": str(self.store),
            "report": str(self.report),
            "summary": str(self.summary_file),
        }
        return data


# ------------------------------------------------------------- built-ins
#: The sweeps shipped with tumble.
BUILTINS = Builtins(kind="sweep", package="tumble.sweep", folder_name="examples", error=SweepError)


def builtin_sweeps() -> dict[str, str]:
    """The built-in sweeps: name → one-line description.

    Examples
    --------
    >>> import tumble as tb
    >>> sorted(tb.sweep.builtin_sweeps())
    ['dual-spin-map', 'flip-map']
    """
    return {name: BUILTINS.description(name) for name in BUILTINS.names()}


#: The TOML text of a built-in sweep, to copy and edit (SweepError for an unknown name).
show_sweep = BUILTINS.text


def load_sweep(sweep: str | os.PathLike[str]) -> Plan:
    """A sweep file, or a built-in sweep by name, validated into a :class:`Plan`.

    Raises
    ------
    SweepError
        Unknown name, unreadable file, invalid TOML or an invalid sweep.

    Examples
    --------
    The built-in flip map: a grid of 181 × 181 bodies over the ratio of the
    intermediate to the smallest moment and the angle of the initial spin
    from the intermediate axis, each stepped 40 s:

    >>> import tumble as tb
    >>> plan = tb.sweep.load_sweep("flip-map")
    >>> plan.varied, plan.grid_shape, plan.n_bodies
    (('ratio_2', 'perturbation'), (181, 181), 32761)
    >>> plan.method, plan.duration, plan.n_steps
    ('rk4', 40.0, 8000)
    """
    source = read_source(sweep, BUILTINS)
    # A sweep's messages name its file without the folder.
    name = source.file.name if source.file is not None else source.name
    return parse_sweep(source.text, source=name)


# ------------------------------------------------------------------ run
def run_sweep(
    sweep: str | os.PathLike[str] | Plan,
    output_dir: str | os.PathLike[str] | None = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    force: bool = False,
    progress: Progress = None,
) -> SweepSummary:
    """Run a sweep into a folder, resuming it if the folder holds part of it.

    Parameters
    ----------
    sweep : a sweep file, a built-in sweep's name (``"flip-map"``) or a
        :class:`Plan` from :func:`load_sweep`.
    output_dir : the output folder; default ``sweep-NAME`` in the current
        directory. A folder holding the same sweep is resumed: finished chunks
        are kept, the others computed (the results are the same bits as an
        uninterrupted run's). Until every chunk is done, :func:`open_results`
        warns that the results are incomplete.
    workers : run on a Dask LocalCluster of this many worker processes
        (127.0.0.1 only, scratch files in the output folder).
    scheduler : run on the Dask cluster whose scheduler is at this address,
        ``tcp://HOST:PORT`` (``tcp://[::1]:8786`` for IPv6; ``tls://`` with
        Dask's TLS settings); it must answer within the file's [dask]
        ``timeout`` (default 10 s). Without ``workers`` and ``scheduler``,
        those of the file's [dask] table; without any, the chunks run in this
        process on all cores.
    force : discard the results of a different sweep in ``output_dir``
        (only the files a sweep writes are removed).
    progress : None or ``progress(done, total)``, in chunks, called once at
        the start and after each chunk is written.

    Returns
    -------
    SweepSummary, also written to ``output_dir/summary.json``; the per-body
    results are in ``output_dir/results.zarr``. Its maps are drawn into
    ``output_dir/report.html`` by :func:`tumble.report.write_sweep_report`
    (``tumble sweep`` does it).

    Raises
    ------
    SweepError, InputError
        An invalid sweep or one beyond its [limits] (refused when it is
        loaded), a folder holding a different sweep (or other files), an
        address where no Dask scheduler answers, bad ``workers``.
    tumble.IntegrationError
        A body's state became NaN or infinite (reduce dt).
    """
    plan = sweep if isinstance(sweep, Plan) else load_sweep(sweep)
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int | np.integer) or workers < 1
    ):
        raise InputError(f"Expected `workers` to be an integer >= 1, got {workers!r}.")
    if workers is not None and scheduler is not None:
        raise InputError(
            f"Expected at most one of `workers` and `scheduler`, got workers={workers} and "
            f"scheduler={scheduler!r}."
        )
    if workers is None and scheduler is None:
        workers, scheduler = plan.workers, plan.scheduler
    if scheduler is not None:
        from tumble.sweep import dask_backend

        scheduler = check_address(scheduler)
        timeout = plan.timeout if plan.timeout is not None else dask_backend.CONNECT_TIMEOUT
        dask_backend.check_scheduler(scheduler, timeout)  # before the folder is written
    folder = sweep_folder(plan, output_dir)
    check_chunk_memory(plan)
    with claim_folder(folder):  # one writer at a time: a second is refused, naming the first
        return _run_claimed(plan, folder, force, workers, scheduler, progress)


def sweep_folder(plan: Plan, output_dir: str | os.PathLike[str] | None = None) -> Path:
    """A sweep's output folder: ``output_dir``, or ``sweep-NAME`` in the current directory."""
    return Path(output_dir) if output_dir is not None else Path(f"sweep-{plan.name}")


def claim_folder(folder: Path) -> OutputLock:
    """The claim on a sweep's output folder (:class:`tumble.locks.OutputLock`, its
    lock file inside): :func:`run_sweep` takes it; hold it around the run and the
    report's writing to keep the folder for both."""
    return OutputLock(folder, "the sweep's output folder", inside=True, own=OWN)


def _run_claimed(
    plan: Plan,
    folder: Path,
    force: bool,
    workers: int | None,
    scheduler: str | None,
    progress: Progress,
) -> SweepSummary:
    """:func:`run_sweep` once its output folder is claimed."""
    store = SweepStore.open(folder, plan, force=force)
    done = store.done()
    pending = [k for k in range(plan.n_chunks) if k not in done]
    warn_if_short_of_room(plan, folder, len(pending))
    finished = len(done)
    if progress is not None:
        progress(finished, plan.n_chunks)

    def write(index: int, arrays: dict[str, NDArray[np.generic]]) -> None:
        nonlocal finished
        store.write_chunk(index, arrays)
        finished += 1
        if progress is not None:
            progress(finished, plan.n_chunks)

    started = time.perf_counter()
    if workers is None and scheduler is None:
        import numba

        from tumble.sweep.metrics import compute_chunk

        backend = f"in-process ({numba.get_num_threads()} threads)"
        for index in pending:
            write(index, compute_chunk(plan, index))
    else:
        from tumble.sweep.dask_backend import run_on_dask

        backend = run_on_dask(
            plan,
            pending,
            write,
            workers=workers,
            scheduler=scheduler,
            scratch=folder / "dask-scratch",
            timeout=plan.timeout,
        )
    seconds = time.perf_counter() - started
    store.finish()
    return _finish(store, pending, backend, seconds)


#: Memory a body of a chunk takes while it is computed, bytes, besides its
#: outputs: its parameters, tensors, frames and state, with copies.
CHUNK_BYTES_PER_BODY = 1000


def check_chunk_memory(plan: Plan) -> None:
    """Refuse, before any work, a sweep whose chunks cannot fit in the memory
    budget (:mod:`tumble.resources`): each chunk is computed whole in memory
    (the sweep as a whole streams to disk).

    Raises
    ------
    RequestTooLargeError
        With the estimate and the advice of a smaller ``chunk_size``.
    """
    from tumble.resources import check_memory

    check_memory(
        plan.chunk_size * (CHUNK_BYTES_PER_BODY + body_bytes(plan)),
        f"chunks of {plan.chunk_size} bodies",
        "Ask for a smaller chunk_size in [sweep]: the chunks stream to disk one by one.",
    )


def warn_if_short_of_room(plan: Plan, folder: Path, pending: int) -> None:
    """Warn when the chunks still to compute may not fit on the disk of
    ``folder`` (uncompressed: the store compresses, so they may fit after all;
    a sweep stopped by a full disk resumes where it stopped)."""
    import shutil
    import warnings

    from tumble.resources import format_bytes

    needed = pending * plan.chunk_size * body_bytes(plan)
    free = shutil.disk_usage(folder).free
    if needed > free:
        warnings.warn(
            f"The sweep's {pending} chunks to compute take up to {format_bytes(needed)} "
            f"uncompressed, and {str(folder)!r} has {format_bytes(free)} free: if the disk "
            "fills, free some space and run the sweep again (it resumes).",
            UserWarning,
            stacklevel=3,
        )


def _finish(store: SweepStore, pending: list[int], backend: str, seconds: float) -> SweepSummary:
    """Summary and summary.json of a finished sweep."""
    from tumble.sweep.summary import summarize

    plan = store.plan
    computed = sum(plan.chunk_range(k)[1] - plan.chunk_range(k)[0] for k in pending)
    rate = computed * plan.n_steps / seconds if computed and seconds > 0 else None
    metrics, maps = summarize(store)
    summary = SweepSummary(
        name=plan.name,
        description=plan.description,
        folder=store.folder,
        bodies=plan.n_bodies,
        chunk_size=plan.chunk_size,
        chunks=plan.n_chunks,
        chunks_run=len(pending),
        chunks_reused=plan.n_chunks - len(pending),
        steps=plan.n_steps,
        dt=plan.dt,
        duration=plan.duration,
        method=plan.method,
        backend=backend,
        seconds=seconds,
        body_steps_per_second=rate,
        metrics=metrics,
        fingerprint=fingerprint(plan.identity()),
        maps=tuple(maps),
        text=plan.text,
    )
    write_text(store.folder / "summary.json", json.dumps(_clean(summary.to_dict()), indent=2))
    return summary


def _clean(value: Any) -> Any:
    """JSON-ready: non-finite floats become None."""
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
