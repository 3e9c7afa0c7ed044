"""Shared test settings: hypothesis profiles."""

from __future__ import annotations

import os

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
settings.load_profile(
    os.environ.get("TUMBLE_HYPOTHESIS") or ("ci" if os.environ.get("CI") else "default")
)
