"""Sweeps on Dask: a real LocalCluster, and a real scheduler and worker started as
separate processes on loopback; both give the same bits as the in-process run."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import tumble as tb
from test_sweep import SMALL, assert_same_bits, stored, write
from tumble.errors import CoarseStepWarning, IntegrationError
from tumble.sweep import dask_backend, run_sweep
from tumble.sweep.build import parse_sweep

BIN = Path(sys.executable).parent


@pytest.fixture(scope="module")
def in_process(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, np.ndarray]]:
    folder = tmp_path_factory.mktemp("in-process")
    source = write(folder, SMALL, "small.toml")
    run_sweep(source, folder / "out")
    return source, stored(folder / "out")


@pytest.mark.slow  # a dask cluster started: 5 s
def test_local_cluster_gives_the_same_bits(
    tmp_path: Path, in_process: tuple[Path, dict[str, np.ndarray]]
) -> None:
    source, arrays = in_process
    seen: list[int] = []
    summary = run_sweep(source, tmp_path / "out", workers=2, progress=lambda d, t: seen.append(d))
    assert summary.backend == "dask LocalCluster (2 workers)"
    assert summary.chunks_run == 7
    assert seen == list(range(8))
    assert_same_bits(stored(tmp_path / "out"), arrays)
    # The cluster's scratch folder lived inside the output folder and is gone.
    assert not (tmp_path / "out" / "dask-scratch").exists()
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["backend"] == summary.backend


def test_dask_table_of_the_file_chooses_a_local_cluster(
    tmp_path: Path, in_process: tuple[Path, dict[str, np.ndarray]]
) -> None:
    _, arrays = in_process
    source = write(tmp_path, SMALL + "\n[dask]\nworkers = 1\n", "with-dask.toml")
    summary = run_sweep(source, tmp_path / "out")
    assert summary.backend == "dask LocalCluster (1 worker)"
    assert_same_bits(stored(tmp_path / "out"), arrays)


def test_errors_on_workers_come_back_whole(tmp_path: Path) -> None:
    text = SMALL.replace("dt = 0.01", "dt = 0.75").replace("duration = 1.5", "duration = 300")
    text = text.replace('spin_rate = "1 turn/s"', 'spin_rate = "40 turn/s"')
    with pytest.warns(CoarseStepWarning):
        plan = parse_sweep(text)
    with pytest.raises(
        IntegrationError,
        match=r"Expected the integration to stay finite, got NaN or inf for \d+ bodies of chunk",
    ):
        run_sweep(plan, tmp_path / "out", workers=1)
    assert not (tmp_path / "out" / "dask-scratch").exists()


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@pytest.fixture
def scheduler_and_worker(tmp_path: Path) -> Iterator[str]:
    """`dask scheduler` and `dask worker` as separate processes on 127.0.0.1; both
    stopped by PID at the end."""
    address_file = tmp_path / "scheduler.json"
    log = (tmp_path / "dask.log").open("wb")
    processes = [
        subprocess.Popen(
            [
                str(BIN / "dask"),
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(address_file),
            ],
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    ]
    try:
        for _ in range(600):
            if address_file.exists() and address_file.stat().st_size:
                break
            if processes[0].poll() is not None:
                raise RuntimeError((tmp_path / "dask.log").read_text())
            time.sleep(0.1)
        address = json.loads(address_file.read_text())["address"]
        processes.append(
            subprocess.Popen(
                [
                    str(BIN / "dask"),
                    "worker",
                    address,
                    "--host",
                    "127.0.0.1",
                    "--nthreads",
                    "2",
                    "--nworkers",
                    "1",
                    "--no-dashboard",
                    "--local-directory",
                    str(tmp_path / "w"),
                ],
                stdout=log,
                stderr=subprocess.STDOUT,
            )
        )
        yield address
    finally:
        # The worker first (it leaves the scheduler cleanly), then the scheduler.
        for process in reversed(processes):
            if process.poll() is None:
                os.kill(process.pid, signal.SIGTERM)
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.kill(process.pid, signal.SIGKILL)
                process.wait()
        log.close()


@pytest.mark.slow  # a dask scheduler and worker started: 4 s
def test_external_scheduler_and_worker_give_the_same_bits(
    tmp_path: Path, scheduler_and_worker: str, in_process: tuple[Path, dict[str, np.ndarray]]
) -> None:
    # A worker with two threads: chunks share its process, one kernel at a time.
    source, arrays = in_process
    address = scheduler_and_worker
    assert address.startswith("tcp://127.0.0.1:")
    summary = run_sweep(source, tmp_path / "out", scheduler=address)
    assert summary.backend == f"dask {address} (1 worker)"
    assert_same_bits(stored(tmp_path / "out"), arrays)
    # Resuming on the cluster: half the chunks removed, redone remotely.
    for marker in sorted((tmp_path / "out" / "chunks").glob("*.done"))[::2]:
        marker.unlink()
    again = run_sweep(source, tmp_path / "out", scheduler=address)
    assert (again.chunks_run, again.chunks_reused) == (4, 3)
    assert_same_bits(stored(tmp_path / "out"), arrays)


def test_unreachable_scheduler_is_one_clear_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(dask_backend, "CONNECT_TIMEOUT", 1.0)
    port = _free_port()
    with pytest.raises(
        tb.InputError,
        match=rf"Expected a Dask scheduler at tcp://127.0.0.1:{port}, got no answer within 1 s",
    ):
        run_sweep(parse_sweep(SMALL), tmp_path / "out", scheduler=f"tcp://127.0.0.1:{port}")


def test_tasks_are_few_and_balanced() -> None:
    plan = parse_sweep(SMALL)  # 7 chunks of 18 bodies × 150 steps: tiny work each
    assert dask_backend.group_chunks(plan, list(range(7)), slots=2) == [
        [0],
        [1],
        [2],
        [3],
        [4],
        [5],
        [6],
    ]
    assert dask_backend.group_chunks(plan, list(range(7)), slots=1) == [[0, 1, 2], [3, 4, 5], [6]]
    big = parse_sweep(SMALL.replace("chunk_size = 18", "chunk_size = 1"))  # 120 chunks
    groups = dask_backend.group_chunks(big, list(range(120)), slots=2)
    assert len(groups) == 4 and sum(len(g) for g in groups) == 120
    # Enough work per chunk: one chunk per task.
    heavy = parse_sweep(SMALL.replace("duration = 1.5", "duration = 100000"))
    assert dask_backend.group_chunks(heavy, [1, 4, 6], slots=2) == [[1], [4], [6]]


def test_a_scheduler_without_workers_is_one_clear_error(tmp_path: Path, monkeypatch) -> None:
    import distributed

    from tumble.sweep import dask_backend

    monkeypatch.setattr(dask_backend, "WORKER_TIMEOUT", 1.0)
    with distributed.LocalCluster(n_workers=0, host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        with pytest.raises(
            tb.InputError,
            match=rf"Expected a Dask scheduler with workers at {address}, got none within 1 s\.",
        ):
            tb.sweep.run_sweep(write(tmp_path, SMALL), tmp_path / "out", scheduler=address)
