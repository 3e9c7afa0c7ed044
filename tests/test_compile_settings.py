"""numba's optimisation level: ``max`` for tumble's kernels unless the environment
says otherwise (:mod:`tumble`, :mod:`tumble.core`). Each case runs in a fresh process, since
numba reads the setting once, when it makes its code generator."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

#: Prints whether numba's level is max, the level, and whether its code generator
#: vectorises loops in its first, cheap optimisation (what ``max`` changes), after
#: tumble's first kernel.
PROBE = """
import sys
if sys.argv[1] == "numba first":
    import numba
import tumble
if sys.argv[1] == "the program's own numba function first":
    import numba

    @numba.njit
    def own(x):
        return x
import tumble.core.quaternion
import numpy as np
tumble.core.quaternion.multiply_right(np.array([[1.0, 0, 0, 0]]), np.array([1.0, 0, 0, 0]))
from numba.core import config, registry
print(config.OPT.is_opt_max, int(config.OPT), registry.cpu_target.target_context._internal_codegen._loopvect)
"""


def probe(order: str, **environment: str) -> str:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_OPT"}
    done = subprocess.run(
        [sys.executable, "-c", PROBE, order],
        env={**env, **environment},
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout.strip()


@pytest.mark.parametrize(
    "order", ["tumble first", "numba first", "the program's own numba function first"]
)
def test_kernels_are_optimised_at_numbas_most_unless_told_otherwise(order: str) -> None:
    assert probe(order) == "True 3 True"
    # The user's setting is kept: numba's own default, 3, optimises cheaply first.
    assert probe(order, NUMBA_OPT="3") == "False 3 False"
