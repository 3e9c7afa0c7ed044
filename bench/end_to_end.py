"""End to end: `tumble run` on the default (gyroscope) scenario, as a user runs it.

Measures, each in a fresh process as the command line runs:

* the first run with an empty numba cache (the kernels compile),
* the first run after `tumble warm-up` (what `make setup` runs) in another
  empty cache: target ≤ 2× a warm run,
* warm runs (the cache filled): target ≤ WARM_TARGET_S for the whole command,
  and the same with `--no-figures --no-viewer`,
* `tumble inertia solid-cylinder ...`: target ≤ INERTIA_TARGET_S,
* the start-up alone (`tumble --version`, and importing what a run imports),
* where the time of a warm run goes (in one process: simulate and measure,
  figures, viewer, report),
* the size of viewer.html (target ≤ 10 MB) and its load time in headless
  Chromium (Debian's package), until the viewer has drawn its first frame.

Run: ``.venv/bin/python bench/end_to_end.py`` (``make bench`` runs it too).
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path

from machine import describe

WARM_RUNS = 5
TARGET_S = 1.5
INERTIA_TARGET_S = 0.5
TARGET_MB = 10.0
CHROMIUM = "/usr/bin/chromium"


def tumble(cache: Path, *arguments: str) -> float:
    """Seconds for `tumble ARGUMENTS` in a fresh process with the given numba cache."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, "-c", "from tumble.cli import main; main()", *arguments],
        check=True,
        env=env,
        stdout=subprocess.DEVNULL,
    )
    return time.perf_counter() - start


def command_line(folder: Path, cache: Path, *options: str) -> float:
    """Seconds for `tumble run -q -o FOLDER [OPTIONS]` in a fresh process."""
    return tumble(cache, "run", "-q", "-o", str(folder), *options)


def summary(label: str, seconds: list[float], target: float | None = None) -> None:
    """One line: the median of ``seconds``, each of them, and the target."""
    median = statistics.median(seconds)
    line = f"  {label:<29s}: {median:6.2f} s  [{', '.join(f'{s:.2f}' for s in seconds)}]"
    if target is not None:
        line += f"  target <= {target:g} s: " + ("met" if median <= target else "NOT met")
    print(line)


def _mark(marks: list[tuple[str, float]], name: str) -> None:
    marks.append((name, time.perf_counter()))


def breakdown(folder: Path) -> dict[str, float]:
    """Seconds of each stage of a warm run, in this process (imports already paid):
    with the figures drawn here, then by the worker processes `tumble run` starts
    (the figures' stage is then the wait for them after the other files)."""
    from tumble.report import write_run
    from tumble.report.charts import FigureWorkers
    from tumble.scenario import run

    run("gyroscope")  # loads the kernels from the cache, and the plotting libraries
    stages: dict[str, float] = {}
    start = time.perf_counter()
    result = run("gyroscope")
    stages["simulate and measure"] = time.perf_counter() - start
    with FigureWorkers() as workers:
        for suffix, drawing in (("", None), (" (workers)", workers)):
            marks: list[tuple[str, float]] = []
            start = time.perf_counter()
            write_run(result, folder / f"run{suffix.strip(' ()')}", figure_workers=drawing,
                      progress=partial(_mark, marks))  # fmt: skip
            end = time.perf_counter()
            names = [name for name, _ in marks]
            times = [t for _, t in marks] + [end]
            for k, name in enumerate(names):
                stages[f"write {name}{suffix}"] = times[k + 1] - times[k]
    return stages


def load_times(viewer: Path, repeats: int = 3) -> list[float] | str:
    """Seconds from opening viewer.html to its first drawn frame, in headless Chromium."""
    if not Path(CHROMIUM).is_file():
        return "chromium not installed"
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        return "playwright not installed"
    seconds = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=CHROMIUM,
            args=["--enable-unsafe-swiftshader", "--use-angle=swiftshader"],
        )
        for _ in range(repeats):
            page = browser.new_page()
            start = time.perf_counter()
            page.goto(viewer.as_uri())
            page.wait_for_function(
                "window.tumbleViewer && window.tumbleViewer.ready === true", timeout=120_000
            )
            seconds.append(time.perf_counter() - start)
            page.close()
        browser.close()
    return seconds


def main() -> None:
    print(describe({}))
    scratch = Path(tempfile.mkdtemp(prefix="tumble-bench-"))
    try:
        cache = scratch / "numba-cache"
        cache.mkdir()
        first = command_line(scratch / "first", cache)
        warm = [command_line(scratch / f"warm{k}", cache) for k in range(WARM_RUNS)]
        bare = [
            command_line(scratch / f"bare{k}", cache, "--no-figures", "--no-viewer")
            for k in range(WARM_RUNS)
        ]
        prepared = scratch / "warm-up-cache"
        prepared.mkdir()
        warm_up = tumble(prepared, "warm-up", "-q")
        after_warm_up = command_line(scratch / "after", prepared)
        version = [tumble(cache, "--version") for _ in range(WARM_RUNS)]
        inertia = [
            tumble(cache, "inertia", "solid-cylinder", "--mass", "250 g", "--radius", "3 cm",
                   "--height", "8 cm")
            for _ in range(WARM_RUNS)
        ]  # fmt: skip
        stages = breakdown(scratch / "inprocess")
        viewer = scratch / "first" / "viewer.html"
        size_mb = viewer.stat().st_size / 1e6
        report_mb = (scratch / "first" / "report.html").stat().st_size / 1e6
        loads = load_times(viewer)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    median = statistics.median(warm)
    print("End to end: tumble run (default gyroscope scenario), each a fresh process")
    print(f"  first run, empty numba cache : {first:6.2f} s")
    print(f"  tumble warm-up, empty cache  : {warm_up:6.2f} s")
    print(
        f"  first run after warm-up      : {after_warm_up:6.2f} s = {after_warm_up / median:.2f} "
        "× a warm run, target <= 2×: " + ("met" if after_warm_up <= 2 * median else "NOT met")
    )
    summary(f"warm runs (median of {WARM_RUNS})", warm, TARGET_S)
    summary("warm, --no-figures --no-viewer", bare)
    summary("tumble --version", version)
    summary("tumble inertia solid-cylinder", inertia, INERTIA_TARGET_S)
    print("  a warm run in one process, by stage:")
    for name, seconds in stages.items():
        print(f"    {name:<36s} {seconds:6.2f} s")
    print(
        f"  viewer.html                  : {size_mb:6.2f} MB  target <= {TARGET_MB:.0f} MB: "
        + ("met" if size_mb <= TARGET_MB else "NOT met")
    )
    print(f"  report.html                  : {report_mb:6.2f} MB")
    if isinstance(loads, str):
        print(f"  viewer load in Chromium      : not measured ({loads})")
    else:
        print(
            f"  viewer load in Chromium      : {statistics.median(loads):6.2f} s median "
            f"[{', '.join(f'{s:.2f}' for s in loads)}] (headless, software WebGL)"
        )


if __name__ == "__main__":
    main()
