"""Shared test settings: hypothesis profiles, and the markers that split the
suite between ``make check`` and ``make test`` (see the Makefile)."""

from __future__ import annotations

import os
from datetime import timedelta

import pytest
from hypothesis import HealthCheck, settings

# No deadline: the first call of a kernel compiles it (about a second), which
# says nothing about the property under test. CI runs more examples.
settings.register_profile(
    "default", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "ci",
    deadline=None,
    max_examples=200,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
# A long search for counter-examples, run by hand: TUMBLE_HYPOTHESIS=stress pytest
settings.register_profile(
    "stress", deadline=None, max_examples=3000, suppress_health_check=[HealthCheck.too_slow]
)
# Fuzzing, run by hand (see tests/test_fuzz.py): many examples per test, and a deadline
# per example, so that a hang fails instead of stalling. 5 s is 50 times the slowest
# example seen (a built-in scenario's run, compiled) and above a kernel's compile
# time (1 to 5 s), should one compile during the run.
settings.register_profile(
    "fuzz",
    deadline=timedelta(seconds=5),
    max_examples=int(os.environ.get("TUMBLE_FUZZ_EXAMPLES", "5000")),
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.load_profile(
    os.environ.get("TUMBLE_HYPOTHESIS") or ("ci" if os.environ.get("CI") else "default")
)


#: Files that compile the most kernels, run first. The Makefile's parallel workers
#: take whole files (pytest-xdist's --dist loadfile: tests of one file share their
#: kernels, and a worker that compiles one alone does not compile it twice); the
#: sweep tests compile a third of the suite's kernels, a quarter of a first run,
#: and started last they would run on one worker while the other stood idle.
FIRST = ("test_sweep.py",)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark ``site`` every test that reads the built site (through the ``site``
    fixture of tests/test_site.py), so that ``make test`` runs them after ``make
    docs`` and the rest of the suite alongside it; run the files of ``FIRST`` first."""
    for item in items:
        if "site" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.site)
    items.sort(key=lambda item: item.path.name not in FIRST)
