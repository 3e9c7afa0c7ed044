"""The report and the viewer in a real browser (:mod:`browsing`): headless
Chromium, offline."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from browsing import chromium, open_offline
from tumble.report import write_run
from tumble.scenario import run


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with chromium() as launched:
        yield launched


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run(run("gyroscope"), tmp_path_factory.mktemp("browser") / "gyro")


def _open(browser: Any, path: Path) -> tuple[Any, list[str]]:
    return open_offline(browser, path.as_uri())


def _not_blank(png: bytes) -> float:
    """The spread of grey levels of a screenshot: 0 for a blank (uniform) image."""
    from PIL import Image, ImageStat

    image = Image.open(io.BytesIO(png)).convert("L")
    return float(ImageStat.Stat(image).stddev[0])


@pytest.mark.slow  # a browser plays the viewer: 6 s
def test_viewer_plays(browser: Any, folder: Path) -> None:
    page, errors = _open(browser, folder / "viewer.html")
    page.wait_for_function(
        "window.tumbleViewer && window.tumbleViewer.ready === true", timeout=120_000
    )
    assert page.evaluate("window.tumbleViewer.frame") == 0
    start_text = page.inner_text("#time")
    assert start_text.startswith("t = 0.000 s")
    page.click("#play")
    page.wait_for_function("window.tumbleViewer.frame >= 3", timeout=60_000)
    assert page.inner_text("#play") == "Pause"
    page.click("#play")  # pause
    frame = page.evaluate("window.tumbleViewer.frame")
    assert frame >= 3 and page.inner_text("#time") != start_text
    assert int(page.input_value("#slider")) == frame
    # The slider moves the body: the mesh's vertices change with the frame.
    before = page.evaluate("document.getElementById('plot').data[0].x.slice(0, 5)")
    page.eval_on_selector("#slider", "s => { s.value = 200; s.dispatchEvent(new Event('input')); }")
    assert page.evaluate("window.tumbleViewer.frame") == 200
    assert page.evaluate("document.getElementById('plot').data[0].x.slice(0, 5)") != before
    assert _not_blank(page.locator("#plot").screenshot()) > 5
    assert errors == []
    page.close()


def test_report_renders(browser: Any, folder: Path) -> None:
    page, errors = _open(browser, folder / "report.html")
    page.wait_for_load_state("load")
    sizes = page.evaluate("Array.from(document.images).map(i => [i.complete, i.naturalWidth])")
    assert len(sizes) == 6 and all(done and width > 100 for done, width in sizes)
    assert page.locator("table").first.inner_text().startswith("quantity")
    assert _not_blank(page.screenshot(full_page=True)) > 5
    assert errors == []
    page.close()


@pytest.fixture(scope="module")
def racket(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run(run("tennis-racket"), tmp_path_factory.mktemp("browser") / "racket")


@pytest.mark.slow  # a browser plays the viewer: 5 s
def test_poinsot_panel_rolls_the_ellipsoid_on_the_plane(browser: Any, racket: Path) -> None:
    page, errors = _open(browser, racket / "viewer.html")
    page.wait_for_function(
        "window.tumbleViewer && window.tumbleViewer.ready === true", timeout=120_000
    )
    panel = page.locator("#poinsot")
    names = page.evaluate("document.getElementById('poinsot').data.map(t => t.name)")
    assert names[0].startswith("inertia ellipsoid") and names[1].startswith("invariable plane")
    first = panel.screenshot()
    ellipsoid = "document.getElementById('poinsot').data[0].x.slice(0, 5)"
    trail = "document.getElementById('poinsot').data[3].x.length"
    before = page.evaluate(ellipsoid)
    assert page.evaluate(trail) == 1
    page.eval_on_selector("#slider", "s => { s.value = 150; s.dispatchEvent(new Event('input')); }")
    # The ellipsoid has turned with the body, and the herpolhode has grown on the plane.
    assert page.evaluate(ellipsoid) != before
    assert page.evaluate(trail) == 151
    later = panel.screenshot()
    assert _not_blank(first) > 5 and _not_blank(later) > 5
    assert _changed(first, later) > 0.01
    assert errors == []
    page.close()


def _changed(a: bytes, b: bytes) -> float:
    """The fraction of pixels that differ between two screenshots of one size."""
    import numpy as np
    from PIL import Image

    x = np.asarray(Image.open(io.BytesIO(a)).convert("L"), dtype=float)
    y = np.asarray(Image.open(io.BytesIO(b)).convert("L"), dtype=float)
    return float(np.mean(np.abs(x - y) > 8))
