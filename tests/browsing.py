"""Headless Chromium (Debian's package, installed by ``make setup``) driven by
Playwright, with no browser download, for the tests of pages: the run report,
the viewer and the documentation site.

A test that needs what is missing is skipped where it cannot be had (a developer
machine without root); under CI (``CI`` set) it fails instead.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, NoReturn

import pytest

CHROMIUM = "/usr/bin/chromium"


def missing(reason: str) -> NoReturn:
    """Skip, or under CI fail, for want of ``reason``."""
    if os.environ.get("CI"):
        pytest.fail(f"{reason}: under CI this test must run (make setup / make test provide it)")
    pytest.skip(reason)


@contextmanager
def chromium() -> Iterator[Any]:
    """A launched headless Chromium, closed on exit."""
    if not (Path(CHROMIUM).is_file() or shutil.which("chromium")):
        missing("Debian's chromium is not installed (apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        missing("playwright is not installed (pip install -e '.[dev]')")
    with sync_playwright() as playwright:
        # Software WebGL (SwiftShader) for plotly's 3D scene on machines without a GPU.
        browser = playwright.chromium.launch(
            executable_path=CHROMIUM if Path(CHROMIUM).is_file() else shutil.which("chromium"),
            args=["--enable-unsafe-swiftshader", "--use-angle=swiftshader"],
        )
        yield browser
        browser.close()


def open_offline(browser: Any, address: str) -> tuple[Any, list[str]]:
    """A page at ``address`` (a file:// URI), and the list its console errors, page
    errors and failed requests are appended to. Any request for the network is
    refused, and so reported."""
    page = browser.new_page(viewport={"width": 1000, "height": 760})
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("requestfailed", lambda r: errors.append(f"request failed: {r.url}"))
    page.route("http*://**", lambda route: route.abort())
    page.goto(address)
    return page, errors
