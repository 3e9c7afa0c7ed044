"""End to end: `tumble run` on the default (gyroscope) scenario, as a user runs it.

Measures, each in a fresh process as the command line runs:

* the first run with an empty numba cache (the kernels compile),
* warm runs (the cache filled): target ≤ 5 s for the whole command,
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
from pathlib import Path

WARM_RUNS = 3
TARGET_S = 5.0
TARGET_MB = 10.0
CHROMIUM = "/usr/bin/chromium"


def command_line(folder: Path, cache: Path) -> float:
    """Seconds for `tumble run -q -o FOLDER` in a fresh process with the given numba cache."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    start = time.perf_counter()
    subprocess.run(
        [
            sys.executable,
            "-c",
            "from tumble.cli import main; main()",
            "run",
            "-q",
            "-o",
            str(folder),
        ],
        check=True,
        env=env,
    )
    return time.perf_counter() - start


def breakdown(folder: Path) -> dict[str, float]:
    """Seconds of each stage of a warm run, in this process (imports already paid)."""
    from tumble.report import write_run
    from tumble.scenario import run

    run("gyroscope")  # loads the kernels from the cache, and the plotting libraries
    stages: dict[str, float] = {}
    start = time.perf_counter()
    result = run("gyroscope")
    stages["simulate and measure"] = time.perf_counter() - start
    marks: list[tuple[str, float]] = []
    start = time.perf_counter()
    write_run(result, folder, progress=lambda name: marks.append((name, time.perf_counter())))
    end = time.perf_counter()
    names = [name for name, _ in marks]
    times = [t for _, t in marks] + [end]
    for k, name in enumerate(names):
        stages[f"write {name}"] = times[k + 1] - times[k]
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
    scratch = Path(tempfile.mkdtemp(prefix="tumble-bench-"))
    try:
        cache = scratch / "numba-cache"
        cache.mkdir()
        first = command_line(scratch / "first", cache)
        warm = [command_line(scratch / f"warm{k}", cache) for k in range(WARM_RUNS)]
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
    print(
        f"  warm runs (median of {WARM_RUNS})     : {median:6.2f} s  "
        f"[{', '.join(f'{w:.2f}' for w in warm)}]  target <= {TARGET_S:.0f} s: "
        + ("met" if median <= TARGET_S else "NOT met")
    )
    print("  a warm run in one process, by stage:")
    for name, seconds in stages.items():
        print(f"    {name:<28s} {seconds:6.2f} s")
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
