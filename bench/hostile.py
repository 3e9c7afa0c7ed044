"""Benchmark: what tumble does with hostile input, case by case.

Replays the catalogue of ``bench/hostile_catalogue.py`` (several hundred bad
requests through the command line and the library, and the valid requests at
their edges) and sorts what came of each into six outcomes:

* **clean refusal** — the library raised ``tumble.InputError`` with a message;
  the command printed one ``error:`` line and exited with code 2;
* **correct result** — a valid request computed, and its answer passed the
  case's check against an independent oracle;
* **traceback** — any other exception, a traceback printed, or a process that
  died (a signal, an exit code other than 0 and 2);
* **hang** — still running after ``--timeout`` seconds (30): killed;
* **runaway** — its process tree held more than ``--memory`` (2 GiB) at once:
  killed. Every case runs with ``TUMBLE_MEMORY_BUDGET`` at ``--budget`` (1 GiB),
  the most a request may take: a request beyond it must be refused before the
  work, so twice the budget is a runaway;
* **silent wrong answer** — a bad request accepted, or a valid one answered
  wrong;
* **lost data** — an input of the request (a file, a FIFO, a device) changed,
  replaced or gone after it, whatever else came of it;

and a seventh that a strict tool also avoids: **refused a valid request**.
Each case runs in a fresh process of its own, in an empty folder, in a process
group killed whole at the end, so that nothing one case leaves behind (a
stray worker, a lock) touches another; processes still alive in that group
5 s after the case ended are counted as left behind.

Run from the repository root::

    .venv/bin/python bench/hostile.py [--jobs 2] [--only PATTERN] [--json FILE]

The target: zero in the last five outcomes (and no orphans).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import fnmatch
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from hostile_case import lost_inputs, make_inputs
from hostile_catalogue import CATALOGUE, Case

OUTCOMES = (
    "clean refusal",
    "correct result",
    "traceback",
    "hang",
    "runaway",
    "silent wrong answer",
    "lost data",
    "refused a valid request",
)
BAD = OUTCOMES[2:]
CASES = {case.name: case for case in CATALOGUE}


@dataclass
class Outcome:
    """What came of one case."""

    case: Case
    outcome: str
    seconds: float
    peak_bytes: int
    detail: str
    orphans: int


# ------------------------------------------------------------------ the child
def run_library_case(name: str, folder: Path) -> None:
    """Run one library case here (a child process) and write what came of it to
    ``folder/outcome.json``."""
    import warnings

    import numpy as np
    import pint

    import tumble as tb
    from tumble.units import ureg

    case = CASES[name]
    scope: dict[str, Any] = {
        "tb": tb,
        "np": np,
        "pint": pint,
        "ureg": ureg,
        "Path": Path,
        "tmp": folder,
    }
    report: dict[str, Any] = {"raised": None, "input_error": False, "message": "", "check": None}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            exec(compile(str(case.call), name, "exec"), scope)
        except tb.InputError as exc:
            report.update(raised=type(exc).__name__, input_error=True, message=str(exc))
        except Exception as exc:
            clean = type(exc).__name__ in case.refusals
            message = str(exc) if clean else traceback.format_exc()
            report.update(raised=type(exc).__name__, input_error=clean, message=message)
        except BaseException as exc:  # every other kind is the finding
            report.update(raised=type(exc).__name__, message=traceback.format_exc())
        else:
            if case.check:
                try:
                    report["check"] = bool(eval(case.check, scope))
                except Exception:
                    report["check"] = False
                    report["message"] = "the check raised: " + traceback.format_exc()
            report["answer"] = repr(scope.get("result"))[:300]
    report["warnings"] = [f"{w.category.__name__}: {w.message}" for w in caught][:5]
    (folder / "outcome.json").write_text(json.dumps(report))


# ------------------------------------------------------------------ the parent
class Peers:
    """Addresses for the scheduler cases: a port that accepts and never answers,
    and a port where nobody listens."""

    def __init__(self) -> None:
        self.silent = socket.socket()
        self.silent.bind(("127.0.0.1", 0))
        self.silent.listen(16)
        self.accepted: list[socket.socket] = []
        threading.Thread(target=self._accept, daemon=True).start()
        closed = socket.socket()
        closed.bind(("127.0.0.1", 0))
        self.closed_port = closed.getsockname()[1]
        closed.close()

    def _accept(self) -> None:
        with contextlib.suppress(OSError):
            while True:
                connection, _ = self.silent.accept()
                self.accepted.append(connection)  # held open, never answered

    def fill(self, text: str) -> str:
        return text.replace("{silent_port}", str(self.silent.getsockname()[1])).replace(
            "{closed_port}", str(self.closed_port)
        )


def _tree_memory(pid: int) -> int:
    """Bytes resident in a process and all its descendants."""
    import psutil

    try:
        root = psutil.Process(pid)
        processes = [root, *root.children(recursive=True)]
    except psutil.Error:
        return 0
    total = 0
    for process in processes:
        with contextlib.suppress(psutil.Error):
            total += process.memory_info().rss
    return total


def _group_alive(group: int) -> list[int]:
    """The processes still in process group ``group``."""
    import psutil

    alive = []
    for process in psutil.process_iter(["pid"]):
        with contextlib.suppress(psutil.Error, OSError):
            if os.getpgid(process.pid) == group:
                alive.append(process.pid)
    return alive


def run_case(case: Case, peers: Peers, timeout: float, memory: int, budget: str) -> Outcome:
    """Run one case in a fresh process and sort what came of it."""
    folder = Path(tempfile.mkdtemp(prefix="tumble-hostile-"))
    try:
        kept = make_inputs(case, folder)
        if case.surface == "cli":
            command = [
                sys.executable,
                "-c",
                "from tumble.cli import main; main()",
                *(peers.fill(a) for a in case.call),
            ]
        else:
            command = [sys.executable, __file__, "--run-case", case.name, "--folder", str(folder)]
        environment = {**os.environ, "MPLBACKEND": "Agg", "TUMBLE_MEMORY_BUDGET": budget}
        start = time.perf_counter()
        process = subprocess.Popen(
            command,
            cwd=folder,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env=environment,
            start_new_session=True,
        )
        output: dict[str, bytes] = {}

        def drain(name: str, stream: Any) -> None:
            output[name] = stream.read()

        readers = [
            threading.Thread(target=drain, args=(n, s), daemon=True)
            for n, s in (("stdout", process.stdout), ("stderr", process.stderr))
        ]
        for reader in readers:
            reader.start()
        peak, killed = 0, ""
        while process.poll() is None:
            peak = max(peak, _tree_memory(process.pid))
            seconds = time.perf_counter() - start
            if peak > memory:
                killed = "runaway"
            elif seconds > timeout:
                killed = "hang"
            if killed:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(process.pid, signal.SIGKILL)
                process.wait()
                break
            time.sleep(0.05)
        seconds = time.perf_counter() - start
        for reader in readers:
            reader.join(5)
        # What ends with its parent (a pool's worker, a killed child) may take a
        # moment to go: a process is left behind if it is still there 5 s later.
        orphans = _group_alive(process.pid)
        for _ in range(100):
            if not orphans:
                break
            time.sleep(0.05)
            orphans = _group_alive(process.pid)
        for pid in orphans:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        stdout = output.get("stdout", b"").decode("utf-8", "replace")
        stderr = output.get("stderr", b"").decode("utf-8", "replace")
        if killed:
            detail = f"killed after {seconds:.0f} s at {peak / 2**30:.2f} GiB"
            return Outcome(case, killed, seconds, peak, detail, len(orphans))
        lost = lost_inputs(folder, kept)
        if lost:
            outcome, detail = "lost data", "; ".join(lost)
        elif case.surface == "cli":
            outcome, detail = _sort_command(case, process.returncode, stdout, stderr, folder)
        else:
            outcome, detail = _sort_library(case, folder, stderr)
        return Outcome(case, outcome, seconds, peak, detail, len(orphans))
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _sort_command(case: Case, code: int, stdout: str, stderr: str, folder: Path) -> tuple[str, str]:
    lines = [line for line in stderr.splitlines() if line.strip()]
    errors = [line for line in lines if line.startswith("error: ")]
    if "Traceback" in stderr or code not in (0, 2, *case.exit_codes):
        return "traceback", f"exit {code}: {stderr.strip()[-600:]}"
    if code == 2:
        if len(errors) != 1 or lines[-1] != errors[0]:
            return "traceback", f"exit 2 without one error line: {stderr.strip()[-600:]}"
        if case.expect == "result":
            return "refused a valid request", errors[0]
        return "clean refusal", errors[0]
    if case.expect == "refusal":
        return "silent wrong answer", f"exit {code}: {(stdout + stderr).strip()[-300:]}"
    run = subprocess.CompletedProcess(case.call, code, stdout, stderr)
    try:
        right = bool(eval(case.check, {"run": run, "folder": folder, "json": json, "Path": Path}))
    except Exception as exc:
        return "silent wrong answer", f"the check raised {exc!r}"
    return ("correct result", "") if right else ("silent wrong answer", "the check failed")


def _sort_library(case: Case, folder: Path, stderr: str) -> tuple[str, str]:
    try:
        report = json.loads((folder / "outcome.json").read_text())
    except (OSError, ValueError):
        return "traceback", f"the process died: {stderr.strip()[-600:]}"
    if report["raised"]:
        if not report["input_error"]:
            return "traceback", report["message"][-600:]
        if case.expect == "result":
            return "refused a valid request", report["message"]
        return "clean refusal", report["message"]
    if case.expect == "refusal":
        return "silent wrong answer", f"accepted, gave {report.get('answer')}"
    if report["check"]:
        return "correct result", ""
    return "silent wrong answer", f"gave {report.get('answer')} {report['message']}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run-case", help=argparse.SUPPRESS)
    parser.add_argument("--folder", help=argparse.SUPPRESS)
    parser.add_argument("--only", default="*", help="Run the cases whose names match this pattern.")
    parser.add_argument("--jobs", type=int, default=2, help="Cases run at once (default 2).")
    parser.add_argument("--timeout", type=float, default=30.0, help="Seconds before a hang (30).")
    parser.add_argument("--memory", type=float, default=2.0, help="GiB before a runaway (2).")
    parser.add_argument(
        "--budget",
        default="1 GiB",
        help="TUMBLE_MEMORY_BUDGET of every case (1 GiB): what tumble must keep within.",
    )
    parser.add_argument("--json", type=Path, help="Write every case's outcome here.")
    parser.add_argument("--list", action="store_true", help="List the cases and stop.")
    args = parser.parse_args()
    if args.run_case:
        run_library_case(args.run_case, Path(args.folder))
        return
    cases = [c for c in CATALOGUE if fnmatch.fnmatch(c.name, args.only)]
    if args.list:
        for case in cases:
            print(f"{case.surface:8} {case.expect:8} {case.name}")
        print(f"{len(cases)} cases")
        return
    from machine import describe

    print(describe({}))
    peers = Peers()
    memory = int(args.memory * 2**30)
    done: list[Outcome] = []
    start = time.perf_counter()
    with ThreadPoolExecutor(args.jobs) as pool:
        futures = [
            pool.submit(run_case, case, peers, args.timeout, memory, args.budget) for case in cases
        ]
        for k, future in enumerate(futures, 1):
            outcome = future.result()
            done.append(outcome)
            mark = "" if outcome.outcome in OUTCOMES[:2] else "  <--"
            head = f"[{k:3}/{len(cases)}] {outcome.seconds:5.1f} s  {outcome.outcome:<22}"
            print(f"{head} {outcome.case.name}{mark}", flush=True)
    print(
        f"\n{len(cases)} cases in {time.perf_counter() - start:.0f} s, memory budget {args.budget} "
        f"({args.jobs} at once), timeout {args.timeout:g} s, memory {args.memory:g} GiB\n"
    )
    counts = collections.Counter((o.case.surface, o.outcome) for o in done)
    print(f"{'outcome':<26}{'cli':>6}{'library':>9}{'all':>6}")
    for name in OUTCOMES:
        cli, library = counts[("cli", name)], counts[("library", name)]
        print(f"{name:<26}{cli:>6}{library:>9}{cli + library:>6}")
    orphans = sum(o.orphans for o in done)
    print(f"{'processes left behind':<26}{'':>6}{'':>9}{orphans:>6}")
    peak = max(done, key=lambda o: o.peak_bytes)
    print(
        f"largest peak memory: {peak.peak_bytes / 2**20:.0f} MiB ({peak.case.name}); "
        f"slowest: {max(o.seconds for o in done):.1f} s"
    )
    findings = [o for o in done if o.outcome in BAD or o.orphans]
    if findings:
        print("\nfindings:")
        for o in findings:
            print(f"- {o.case.name} [{o.outcome}, orphans {o.orphans}]: {o.detail[:400]}")
    if args.json:
        args.json.write_text(
            json.dumps(
                [
                    {
                        "name": o.case.name,
                        "surface": o.case.surface,
                        "outcome": o.outcome,
                        "seconds": round(o.seconds, 3),
                        "peak_bytes": o.peak_bytes,
                        "orphans": o.orphans,
                        "detail": o.detail,
                    }
                    for o in done
                ],
                indent=1,
            )
        )
    sys.exit(1 if findings else 0)


if __name__ == "__main__":
    main()
