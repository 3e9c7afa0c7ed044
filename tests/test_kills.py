"""``tumble run``, ``sweep`` and ``fit`` killed (SIGKILL) at seeded random moments:
no process of theirs outlives them, every output they finished is whole, and the
next run leaves nothing of theirs behind (no ``.partial``, no lock file).

Half of the kills come at a random moment of a run's time after the start; the
other half at a random moment after the output's writing has begun (its
temporary folder, its claim or its first chunk appears), where a kill leaves
half-made files. The counts of what the kills hit and left are printed (-s)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import psutil
import pytest

from test_sweep import ARRAYS
from writers import (
    RUN,
    SWEEP,
    check_fit_folder,
    check_run_folder,
    finish,
    leftovers,
    scenario,
    survivors,
    tumble,
)

#: Kills per command (TUMBLE_KILLS to change it: each costs a start of tumble).
KILLS = int(os.environ.get("TUMBLE_KILLS", "20"))
#: Every this many kills, the next run goes to its end and is checked.
EVERY = 5


#: A process that starts two figure workers, says their pids, and waits.
WORKERS = """
import sys, time
from tumble.report.charts import FigureWorkers
workers = FigureWorkers(2)
workers.submit({}).result()
print(*(p.pid for p in workers._pool._processes.values()), flush=True)
time.sleep(600)
"""


def test_figure_workers_end_with_their_killed_process() -> None:
    process = subprocess.Popen(
        [sys.executable, "-c", WORKERS], stdout=subprocess.PIPE, text=True,
        start_new_session=True,
    )  # fmt: skip
    assert process.stdout is not None
    pids = [int(pid) for pid in process.stdout.readline().split()]
    assert len(pids) == 2 and all(psutil.pid_exists(pid) for pid in pids)
    process.kill()
    process.wait()
    left = survivors(process.pid)
    process.communicate()
    assert left == []


def kill_at_random(
    args: tuple[str | Path, ...],
    cwd: Path,
    rng: np.random.Generator,
    span: float,
    writing: str,
    window: float,
    counts: Counter[str],
) -> None:
    """Start ``tumble ARGS`` in ``cwd`` and SIGKILL it: ``span`` × a uniform draw
    after the start, or, one time in two, ``window`` × a uniform draw after a
    path matching the pattern ``writing`` appears (s). Check that none of its
    processes outlives it, and count what it left."""
    process = tumble(*args, cwd=cwd)
    after_writing = rng.uniform() < 0.5
    delay = rng.uniform(0.0, window if after_writing else span)
    if after_writing:
        while not any(cwd.glob(writing)) and process.poll() is None:
            time.sleep(0.005)
    time.sleep(delay)
    counts["ended before the kill" if process.poll() is not None else "killed"] += 1
    process.kill()
    process.wait()
    left = survivors(process.pid)  # first: a survivor would keep the pipes open
    process.communicate()
    assert left == []
    for name in leftovers(cwd):
        counts[f"left {Path(name).suffix}"] += 1


def run_to_the_end(args: tuple[str | Path, ...], cwd: Path) -> tuple[str, float]:
    """Run ``tumble ARGS`` to its end: it succeeds and leaves nothing temporary
    behind, its own or a killed run's. Its stdout and wall time, s."""
    start = time.monotonic()
    code, out, err = finish(tumble(*args, cwd=cwd))
    assert code == 0, err
    assert leftovers(cwd) == []
    return out, time.monotonic() - start


@pytest.mark.slow  # KILLS starts of tumble, each killed or run to its end
def test_killed_runs(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    source = scenario(tmp_path, RUN, 500.0, "busy.toml")
    out = tmp_path / "out"
    # With figures: their worker processes must end with the run.
    args = ("run", source, "-o", "out", "--force", "-q")
    run_to_the_end(args, tmp_path)  # the first compiles what the others find cached
    _, span = run_to_the_end(args, tmp_path)  # the kills fall within a run's time
    counts: Counter[str] = Counter()
    for kill in range(KILLS):
        kill_at_random(args, tmp_path, rng, span, ".out.*.partial", span / 5, counts)
        if out.exists():
            check_run_folder(out)
        if kill % EVERY == EVERY - 1:
            run_to_the_end((*args, "--no-figures"), tmp_path)
            check_run_folder(out)
    print(f"runs ({span:.1f} s each): {dict(counts)}")
    assert counts["killed"] >= KILLS // 4


def sweep_store(folder: Path) -> tuple[set[int], dict[str, np.ndarray]]:
    """The chunks marked done in a sweep's folder, and its arrays."""
    import zarr

    from tumble.sweep.store import MARKERS, STORE

    done = {int(p.name.split(".")[0]) for p in (folder / MARKERS).glob("*.done")}
    group = zarr.open_group(str(folder / STORE), mode="r")
    return done, {name: np.asarray(group[name][:]) for name in ARRAYS}


@pytest.mark.slow  # KILLS starts of tumble, each killed or run to its end
def test_killed_sweeps(tmp_path: Path) -> None:
    rng = np.random.default_rng(2)
    source = scenario(tmp_path, SWEEP, 300.0, "small.toml")
    run_to_the_end(("sweep", source, "-o", "first", "-q"), tmp_path)  # compiles
    _, span = run_to_the_end(("sweep", source, "-o", "reference", "-q"), tmp_path)
    _, reference = sweep_store(tmp_path / "reference")
    for name, values in sweep_store(tmp_path / "first")[1].items():
        np.testing.assert_array_equal(values, reference[name])  # the same bits each time
    chunk = 18
    out = tmp_path / "out"
    counts: Counter[str] = Counter()
    for kill in range(KILLS):
        args = ("sweep", source, "-o", "out", "-q")
        kill_at_random(args, tmp_path, rng, span, "out/chunks/*.done", span / 4, counts)
        if (out / "results.zarr").exists():
            # Each chunk marked done holds its bodies' results, the very bits of
            # an uninterrupted sweep.
            done, arrays = sweep_store(out)
            counts["chunks found done"] += len(done)
            for name in ARRAYS:
                for index in done:
                    rows = slice(index * chunk, (index + 1) * chunk)
                    np.testing.assert_array_equal(arrays[name][rows], reference[name][rows])
        if kill % EVERY == EVERY - 1:
            before = len(sweep_store(out)[0]) if (out / "results.zarr").exists() else 0
            printed, _ = run_to_the_end(("sweep", source, "-o", "out", "--json"), tmp_path)
            assert json.loads(printed)["chunks_run"] == 7 - before  # none twice
            done, arrays = sweep_store(out)
            assert done == set(range(7))
            for name in ARRAYS:
                np.testing.assert_array_equal(arrays[name], reference[name])
            shutil.rmtree(out)  # the next kills start a new sweep
    print(f"sweeps ({span:.1f} s each): {dict(counts)}")
    assert counts["killed"] >= KILLS // 4


@pytest.mark.slow  # KILLS starts of tumble, each killed or run to its end
def test_killed_fits(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    out = tmp_path / "out"
    args = ("fit", "-o", "out", "--force", "-q")
    run_to_the_end(args, tmp_path)
    _, span = run_to_the_end(args, tmp_path)
    counts: Counter[str] = Counter()
    for kill in range(KILLS):
        # The fit's folder is claimed as its writing begins, which is short.
        kill_at_random(args, tmp_path, rng, span, ".out.lock", span / 20, counts)
        if out.exists():
            check_fit_folder(out)
        if kill % EVERY == EVERY - 1:
            run_to_the_end((*args, "--no-figures"), tmp_path)
            check_fit_folder(out)
    print(f"fits ({span:.1f} s each): {dict(counts)}")
    assert counts["killed"] >= KILLS // 4


def test_a_fit_stopped_while_replacing_an_earlier_one_leaves_that_one_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The folder is filled beside and moved in whole: a fit stopped at its last
    # file (here by a full disk; a kill is no different) leaves the earlier fit
    # as it was, never a mix of the two.
    import errno

    from test_cli_fit import invoke

    out = tmp_path / "out"
    assert invoke("fit", "-q", "-o", str(out))[0] == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    real = Path.write_bytes

    def write(self: Path, data: bytes) -> int:
        if self.name.startswith(".fit.json."):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, data)

    monkeypatch.setattr(Path, "write_bytes", write)
    code, _, err = invoke("fit", "-q", "--force", "--no-figures", "-o", str(out))
    assert code == 2 and "No space left on device" in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    check_fit_folder(out)
    assert leftovers(tmp_path) == []
