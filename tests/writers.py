"""Helpers of the tests that start real ``tumble`` processes against one output:
starting them, finding what they leave behind (processes, temporary folders
and files), and checking that the outputs they finished are whole."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import psutil

from test_sweep import SMALL

#: A free box spun about its intermediate axis, stepped by RK4 as asked (not
#: solved in closed form): about 100 steps a second of motion, some 10 million
#: steps a second of work. Its figures are drawn by worker processes; no viewer.
RUN = """
[scenario]
name = "busy"

[body]
shape = "box"
mass = "1 kg"
size = "10, 20, 30 cm"

[initial]
omega = "3, 0.1, 0.1 rad/s"

[simulation]
duration = "DURATION s"
method = "rk4"

[output]
samples = 200
viewer = false
"""

#: The small sweep of test_sweep (120 bodies in 7 chunks of 18), each body
#: stepped DURATION seconds.
SWEEP = SMALL.replace("duration = 1.5", "duration = DURATION")


def scenario(folder: Path, text: str, duration: float, name: str) -> Path:
    """Write ``text`` with its duration into ``folder/name`` and return the path."""
    path = folder / name
    path.write_text(text.replace("DURATION", repr(duration)), encoding="utf-8")
    return path


def tumble(*args: str | Path, cwd: Path) -> subprocess.Popen[str]:
    """Start ``tumble ARGS`` in a session of its own (its workers share it)."""
    return subprocess.Popen(
        [sys.executable, "-m", "tumble", *map(str, args)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        env={**os.environ, "PYTHONWARNINGS": "ignore::DeprecationWarning"},
    )


def finish(process: subprocess.Popen[str]) -> tuple[int, str, str]:
    """Wait for a process (a safety net of 10 minutes against a hang) and return
    its exit code, stdout and stderr."""
    out, err = process.communicate(timeout=600)
    return process.returncode, out, err


def session(sid: int) -> list[psutil.Process]:
    """The live processes (zombies are dead) of the session ``sid``."""
    found = []
    for process in psutil.process_iter():
        try:
            if os.getsid(process.pid) == sid and process.status() != psutil.STATUS_ZOMBIE:
                found.append(process)
        except (OSError, psutil.Error):  # ended meanwhile
            continue
    return found


def survivors(sid: int, patience: float = 10.0) -> list[psutil.Process]:
    """The processes of session ``sid`` still alive after at most ``patience``
    seconds (the kernel signals a dead parent's workers at once; the wait is
    only for them to exit). Whatever is left is killed, so that a failing test
    leaves no process behind, and returned."""
    deadline = time.monotonic() + patience
    left = session(sid)
    while left and time.monotonic() < deadline:
        time.sleep(0.05)
        left = session(sid)
    for process in left:
        with contextlib.suppress(psutil.Error):
            process.send_signal(signal.SIGKILL)
    return left


def leftovers(folder: Path) -> list[str]:
    """Temporary folders and files (``.partial``, ``.old``) and lock files under
    ``folder``, as paths relative to it."""
    found = []
    for root, folders, files in os.walk(folder):
        for name in [*folders, *files]:
            if name.endswith((".partial", ".old", ".lock")):
                found.append(str(Path(root, name).relative_to(folder)))
    return sorted(found)


def check_run_folder(folder: Path) -> dict:
    """Check that a run folder is whole: its summary lists exactly its files,
    and each parses. Returns the summary."""
    import pyarrow.parquet as pq

    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    assert sorted(p.name for p in folder.iterdir()) == summary["files"]
    table = pq.read_table(folder / "trajectory.parquet")
    assert table.num_rows == len(np.unique(table.column("t").to_numpy())) > 0
    assert (folder / "report.html").read_text(encoding="utf-8").rstrip().endswith("</html>")
    for png in folder.glob("*.png"):
        assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n"), png.name
    return summary


def check_fit_folder(folder: Path) -> dict:
    """Check that a fit folder is whole: its fit.json lists exactly its files,
    and each parses. Returns fit.json."""
    import tomllib

    summary = json.loads((folder / "fit.json").read_text(encoding="utf-8"))
    assert sorted(p.name for p in folder.iterdir()) == summary["files"]
    tomllib.loads((folder / "fitted-scenario.toml").read_text(encoding="utf-8"))
    for png in folder.glob("*.png"):
        assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n"), png.name
    return summary


def wait_for(path: Path, process: subprocess.Popen[str]) -> None:
    """Wait until ``path`` exists, while ``process`` runs (at most 10 minutes)."""
    deadline = time.monotonic() + 600
    while not path.exists():
        assert process.poll() is None, finish(process)
        assert time.monotonic() < deadline, f"no {path} after 10 minutes"
        time.sleep(0.02)
