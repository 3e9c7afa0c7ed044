"""Benchmark: reading and fitting large gyroscope recordings, time and peak memory.

A synthetic phone throw (``tumble.identification.synthetic_phone``) sampled at
``--rate`` (default 300 kHz: about 1.3 million samples, a 60 MB phyphox CSV)
is written as a CSV file and as the zip file phyphox exports. Each is read
(``read_recording``) and fitted (``tumble fit``) in a fresh process, whose
wall time and peak resident memory (``ru_maxrss`` of the child) are printed,
for the working tree and, with ``--other SRC``, for another tree's ``src``
(e.g. an older commit checked out elsewhere) in the same run, alternated.

Run from the repository root::

    .venv/bin/python bench/recordings.py [--rate 300000] [--repeat 3] \
        [--other /path/src] [--patience 120]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

from machine import describe

READ = (
    "import sys; from tumble.identification import read_recording; "
    "r = read_recording(sys.argv[1]); print(r.t.size)"
)
FIT = "from tumble.cli import main; main()"


def measured(command: list[str], source: str | None, patience: float) -> tuple[float, float, int]:
    """Wall seconds, peak resident MiB and the exit code of a fresh process.

    A process still running after ``patience`` seconds is killed: its exit
    code is then -9 and its time the patience.
    """
    environment = dict(os.environ, MPLBACKEND="Agg")
    if source:
        environment["PYTHONPATH"] = source
    start = time.perf_counter()
    process = subprocess.Popen(
        command, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    while True:
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
        if pid:
            break
        if time.perf_counter() - start > patience:
            process.kill()
            _, status, usage = os.wait4(process.pid, 0)
            break
        time.sleep(0.05)
    seconds = time.perf_counter() - start
    return seconds, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rate", type=float, default=300_000.0, help="Samples a second.")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--other", help="Another tree's src folder, measured alongside.")
    parser.add_argument(
        "--patience", type=float, default=120.0, help="Seconds before a job is killed."
    )
    args = parser.parse_args()
    print(describe({}))
    from tumble.identification import synthetic_phone
    from tumble.identification.recordings import phyphox_csv

    phone = synthetic_phone(0, rate=args.rate)
    with tempfile.TemporaryDirectory(prefix="tumble-recordings-") as place:
        folder = Path(place)
        csv = folder / "phone.csv"
        csv.write_text(phyphox_csv(phone.t, phone.omega))
        archive = folder / "phone.zip"
        with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as packed:
            packed.write(csv, "Raw Data.csv")
        print(
            f"{phone.t.size} samples at {args.rate:g} Hz: CSV {csv.stat().st_size / 2**20:.1f} "
            f"MiB, zip {archive.stat().st_size / 2**20:.1f} MiB; medians of {args.repeat}\n"
        )
        trees = {"this tree": None, **({"other": args.other} if args.other else {})}
        jobs = {
            "read CSV": [sys.executable, "-c", READ, str(csv)],
            "read zip": [sys.executable, "-c", READ, str(archive)],
            "tumble fit CSV": [
                sys.executable, "-c", FIT, "fit", str(csv), "--no-figures", "-q",
                "-o", str(folder / "out"), "--force",
            ],
        }  # fmt: skip
        print(f"{'job':<16} {'tree':<10} {'seconds':>8} {'peak MiB':>9} {'MiB/MiB of CSV':>15}")
        for name, command in jobs.items():
            results: dict[str, list[tuple[float, float, int]]] = {tree: [] for tree in trees}
            for _ in range(args.repeat):
                for tree, source in trees.items():  # alternated: the host's phases hit both
                    results[tree].append(measured(command, source, args.patience))
            for tree, runs in results.items():
                seconds = statistics.median(r[0] for r in runs)
                peak = statistics.median(r[1] for r in runs)
                codes = sorted({r[2] for r in runs})
                flag = "" if codes == [0] else f"  (exit {codes})"
                ratio = peak / (csv.stat().st_size / 2**20)
                print(
                    f"{name:<16} {tree:<10} {seconds:8.2f} {peak:9.0f} {ratio:15.1f}{flag}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
