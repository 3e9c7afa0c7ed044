"""Running a sweep's chunks on Dask: a LocalCluster, or an existing scheduler.

* The plan is scattered to every worker once (``broadcast=True``); each task
  names only its chunk indices, so the task graph stays tiny and nothing
  large is embedded in it. Workers build their chunks' bodies from the plan.
* Chunks are grouped into tasks of at least :data:`TASK_BODY_STEPS`
  body-steps (a task costs a few milliseconds of scheduling), but into no
  fewer than two tasks per worker thread while there are enough chunks, so
  the load stays balanced. At most two tasks per worker thread are in flight
  at once: memory on the client stays bounded whatever the size of the sweep.
* Results come back to the client, which writes them: workers need no
  access to the output folder (a remote cluster shares no disk with it).
* A local cluster listens on 127.0.0.1 only, its dashboard on a free port
  there too, and keeps its scratch files inside the output folder.
* An existing scheduler is first greeted as Dask's client would greet it (its
  handshake), with a timeout: distributed's own connection waits for the
  handshake's answer without one, forever when the server at the address is
  not a Dask scheduler. ``tls://`` needs Dask's TLS settings (its configuration's
  ``distributed.comm.tls``).
"""

from __future__ import annotations

import logging
import math
import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.errors import InputError
from tumble.sweep.plan import Plan

__all__ = ["check_scheduler", "run_on_dask"]

#: Smallest work per task, body-steps: 2e7 is about 0.2–0.5 s on one core, so
#: the scheduling overhead (~3 ms per task) stays near 1 %.
TASK_BODY_STEPS = 20_000_000

#: Seconds to wait for a scheduler to answer (the default of [dask] timeout: a
#: scheduler on a network answers in milliseconds), and for it to have a worker.
CONNECT_TIMEOUT = 10.0
WORKER_TIMEOUT = 60.0

Results = list[tuple[int, dict[str, NDArray[np.generic]]]]


def run_chunks(plan: Plan, indices: list[int], threads: int | None) -> Results:
    """A task: compute chunks ``indices`` of ``plan`` (on a worker)."""
    from tumble.sweep.metrics import compute_chunk

    if threads is not None:
        import numba

        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))  # type: ignore[attr-defined]
    return [(index, compute_chunk(plan, index)) for index in indices]


def group_chunks(plan: Plan, pending: list[int], slots: int) -> list[list[int]]:
    """Consecutive pending chunks grouped into tasks (see the module's docstring)."""
    if not pending:
        return []
    per_chunk = plan.chunk_size * plan.n_steps
    size = max(1, math.ceil(TASK_BODY_STEPS / per_chunk))
    size = min(size, max(1, len(pending) // (2 * max(1, slots))))
    return [pending[k : k + size] for k in range(0, len(pending), size)]


def check_scheduler(address: str, timeout: float) -> None:
    """Refuse, within ``timeout`` s, an ``address`` (checked by
    :func:`~tumble.sweep.schema.check_address`) where no Dask scheduler answers
    Dask's handshake: nothing listening, a server that stays silent or one of
    another protocol; and ``tls://`` without Dask's TLS settings.

    Raises
    ------
    InputError
        Naming the address and what answered.
    """
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from distributed.comm import connect
    from distributed.security import Security

    options: dict[str, Any] = {}
    if address.startswith("tls://"):
        options = Security().get_connection_args("client")
        if options.get("ssl_context") is None:
            raise InputError(
                f"Expected Dask's TLS settings for the scheduler at {address} (its "
                "distributed.comm.tls.ca-file, .client.cert and .client.key), got none: set "
                "them in Dask's configuration, or use tcp://."
            )

    async def greet() -> None:
        comm = await asyncio.wait_for(connect(address, timeout=timeout, **options), timeout)
        await comm.close()

    # In a thread of its own: the caller may be running an event loop (a notebook).
    with ThreadPoolExecutor(1) as pool:
        try:
            pool.submit(asyncio.run, greet()).result()
        except (OSError, TimeoutError):  # refused, unreachable, silent, or closed on us
            raise InputError(
                f"Expected a Dask scheduler at {address}, got no answer within {timeout:g} s: "
                "is a Dask scheduler listening there? ([dask] timeout sets the wait.)"
            ) from None
        except Exception:  # what Dask's reader makes of another protocol's bytes
            raise InputError(
                f"Expected a Dask scheduler at {address}, got an answer in another protocol: "
                "is a Dask scheduler listening there?"
            ) from None


def run_on_dask(
    plan: Plan,
    pending: list[int],
    on_result: Callable[[int, dict[str, NDArray[np.generic]]], None],
    *,
    workers: int | None,
    scheduler: str | None,
    scratch: Path,
    timeout: float | None = None,
) -> str:
    """Compute chunks ``pending`` on Dask; ``on_result(index, arrays)`` is called
    on this thread for each, as they finish; ``timeout``: seconds the scheduler
    has to answer (None: :data:`CONNECT_TIMEOUT`). Returns a description of the
    backend."""
    try:
        import distributed
    except ImportError as exc:  # pragma: no cover - a dependency of tumble
        raise InputError(
            f"Expected dask.distributed to be installed for --workers or --scheduler, got {exc}."
        ) from None
    cluster = _Cluster(
        distributed, workers, scheduler, scratch, CONNECT_TIMEOUT if timeout is None else timeout
    )
    with cluster as (client, slots, threads, where):
        if not pending:
            return where
        shared = client.scatter(plan, broadcast=True, hash=False)
        groups = iter(group_chunks(plan, pending, slots))
        window = distributed.as_completed(loop=client.loop)

        def submit() -> bool:
            indices = next(groups, None)
            if indices is None:
                return False
            window.add(
                client.submit(
                    run_chunks,
                    shared,
                    indices,
                    threads,
                    key=f"tumble-sweep-{indices[0]}-{os.urandom(4).hex()}",
                    pure=False,
                )
            )
            return True

        for _ in range(2 * slots):
            if not submit():
                break
        for future in window:
            for index, arrays in future.result():
                on_result(index, arrays)
            future.release()
            submit()
        return where


class _Cluster:
    """Context manager: (client, worker threads, numba threads per task, description)."""

    def __init__(
        self,
        distributed: Any,
        workers: int | None,
        scheduler: str | None,
        scratch: Path,
        timeout: float,
    ) -> None:
        self.distributed = distributed
        self.workers = workers
        self.scheduler = scheduler
        self.scratch = scratch
        self.timeout = timeout
        self.cluster: Any = None
        self.client: Any = None

    def __enter__(self) -> tuple[Any, int, int | None, str]:
        distributed = self.distributed
        if self.scheduler is not None:
            check_scheduler(self.scheduler, self.timeout)
            try:
                self.client = distributed.Client(
                    self.scheduler, timeout=self.timeout, set_as_default=False
                )
            except (OSError, TimeoutError) as exc:  # it answered the greeting, then went
                raise InputError(
                    f"Expected a Dask scheduler at {self.scheduler}, got no answer within "
                    f"{self.timeout:g} s ({type(exc).__name__})."
                ) from None
            try:
                self.client.wait_for_workers(1, timeout=WORKER_TIMEOUT)
            except (OSError, TimeoutError):
                self.client.close()
                raise InputError(
                    f"Expected a Dask scheduler with workers at {self.scheduler}, got none "
                    f"within {WORKER_TIMEOUT:g} s."
                ) from None
            threads = self.client.nthreads()
            slots = max(1, sum(threads.values()))
            return self.client, slots, None, f"dask {self.scheduler} ({_workers(len(threads))})"
        assert self.workers is not None
        self.scratch.mkdir(parents=True, exist_ok=True)
        self.cluster = distributed.LocalCluster(
            n_workers=self.workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            # Its HTTP server (dashboard, or a page asking for bokeh; health
            # checks) on a free port of the loopback: None would mean 8787.
            dashboard_address="127.0.0.1:0",
            local_directory=str(self.scratch),
            silence_logs=logging.CRITICAL,  # shutdown races log errors that mean nothing
        )
        self.client = distributed.Client(self.cluster, set_as_default=False)
        cores = os.cpu_count() or 1
        threads = max(1, cores // self.workers)
        return self.client, self.workers, threads, f"dask LocalCluster ({_workers(self.workers)})"

    def __exit__(self, *exc: object) -> None:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
            shutil.rmtree(self.scratch, ignore_errors=True)


def _workers(count: int) -> str:
    return f"{count} worker{'' if count == 1 else 's'}"
