"""Kernels specialised for a torque are cached on disk and found by a new process.

numba keys its cache of a closure by pickling the closure's cells, which for
compiled functions differ in every process; tumble.core._jit.specialise keys
it by a stable identity instead (through numba's cache class). This checks the
behaviour end to end, so a numba release that changes that class is noticed.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

SCRIPT = """
import numpy as np
from tumble.body import BodyBatch
from tumble.integrators import INTEGRATORS
from tumble.torques import LinearDamping, bind

bound = bind(LinearDamping(0.1), BodyBatch(np.ones((1, 3))), bodies=1)
kernel = INTEGRATORS["rk4"].kernel("single", bound)
w, q = np.array([1.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0, 0.0])
kernel(w, q, np.ones(3), bound.params, bound.context, 0.1, 10, 0, 100, np.zeros((1, 3)),
       np.zeros((1, 4)))
# Spin-down under damping c = 0.1 N·m·s of a sphere of moment 1: ω = exp(−0.1 t).
assert abs(w[0] - np.exp(-0.1)) < 1e-8, w
print(sum(kernel.stats.cache_hits.values()), sum(kernel.stats.cache_misses.values()))
"""


@pytest.mark.skipif(numba.config.DISABLE_JIT, reason="nothing is compiled without the JIT")
@pytest.mark.slow  # a kernel compiled from nothing in a process of its own: 7 s
def test_a_second_process_loads_the_specialised_kernel_from_the_cache(tmp_path: Path) -> None:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), TUMBLE_NUMBA_CACHE="1")

    def run() -> tuple[int, int]:
        out = subprocess.run(
            [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=True
        ).stdout.split()
        return int(out[0]), int(out[1])

    assert run() == (0, 1)  # compiled, and saved
    assert run() == (1, 0)  # loaded


# Two batch kernels of one factory for bodies carrying parts (two rotors, with
# and without a damper): identical argument types, different closures. Each of
# two processes compiles one; a third loads both from the cache and must run
# each one's own body.
LAYOUTS = """
import sys
import numpy as np
import tumble as tb
from tumble.parts import KaneDamper, Rotor

for flag in sys.argv[1:]:
    parts = [Rotor([1, 0.2, 0], 0.1, speed=30.0), Rotor([0, 0, 1], 0.05, speed=-10.0)]
    parts += [KaneDamper(0.1, 0.2)] if flag == "damper" else []
    batch = tb.simulate_batch([[2.0, 3.0, 4.0]], [[0.3, -0.5, 0.8]], duration=0.05, dt=1e-3,
                              internal=parts)
    print(*batch.omega[0].tolist(), end=" ")
"""


@pytest.mark.skipif(numba.config.DISABLE_JIT, reason="nothing is compiled without the JIT")
@pytest.mark.slow  # processes of their own, which compile from nothing
def test_kernels_compiled_in_separate_processes_keep_their_own_bodies(tmp_path: Path) -> None:
    # numba names symbols after the qualified name and a per-process counter:
    # without a name of its own per identity, the third process ran the body
    # loaded first for both (numba issue #10486), an error of ~1e-3 rad/s.
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), TUMBLE_NUMBA_CACHE="1")
    script = tmp_path / "layouts.py"
    script.write_text(LAYOUTS)

    def run(*flags: str) -> list[float]:
        out = subprocess.run(
            [sys.executable, str(script), *flags], env=env, capture_output=True, text=True,
            check=True,
        ).stdout.split()  # fmt: skip
        return [float(v) for v in out]

    with_damper = run("damper")
    without = run("none")
    assert with_damper != without
    assert run("none", "damper") == without + with_damper
