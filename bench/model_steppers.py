"""Benchmark: the compiled fixed-step runs of the models, this tree against another.

Nanoseconds per RK4 step of the gimbal (``tumble.core.gimbal.rk4_run``, 3 states
held in registers), the rotor's whirl (``tumble.core.whirl.rk4_run``, 8 states) and the fitted drag
(``tumble.core.drag_model.drag_rates``, 3 states, ~5 substeps between samples)
and the rigid body (``simulate`` of one body recording every 100th step, and
``simulate_batch`` of 100 000 bodies, 1000 steps, per body-step), each
tree in fresh processes, alternated, medians of the repeats (the harness of
``bench/part_kinds.py``). With ``--other SRC`` (another tree's ``src``, e.g. the
commit before a change checked out with ``git worktree``) the two are printed side by
side with their ratio (> 1: this tree is faster). The runs' arguments are laid out
as each tree lays them out: a tree whose runs are made by
``tumble.core.rk4.fixed_step_run`` takes the model's parameters as a tuple last.

Run from the repository root::

    .venv/bin/python bench/model_steppers.py [--repeat 5] [--other /path/src]
"""

from __future__ import annotations

import part_kinds

#: One process's measurements: its cases, timed after a warm-up call.
CHILD = r"""
import json, time
import numpy as np
from tumble.core import drag_model, gimbal, rk4, whirl

shared = hasattr(rk4, "fixed_step_run")
steps = 200_000
out = {}

params = np.array([50.0, 1.0, 0.2])
record = np.empty((steps // 100 + 1, 3))
def run_gimbal(count):
    y = np.array([0.3, 0.0, 0.0])
    gimbal.rk4_run(y, params, 1e-4, count, 0, 100, record)
run_gimbal(100)
start = time.perf_counter()
run_gimbal(steps)
out["gimbal, 3 states"] = (time.perf_counter() - start) / steps * 1e9

rng = np.random.default_rng(0)
matrices = 1e-3 * rng.standard_normal((4, 4, 4))
matrices[1] += 100.0 * np.eye(4)
wparams = np.array([10.0, 5.0, 1e-4, 0.02])
wrecord = np.empty((steps // 100 + 1, 8))
def run_whirl(count):
    y = np.zeros(8)
    if shared:
        whirl.rk4_run(y, 1e-4, count, 0, 100, wrecord, (matrices, wparams))
    else:
        whirl.rk4_run(y, matrices, wparams, 1e-4, count, 0, 100, wrecord)
run_whirl(100)
start = time.perf_counter()
run_whirl(steps)
out["whirl, 8 states"] = (time.perf_counter() - start) / steps * 1e9

moments = np.array([0.3, 0.8, 1.0])
drag = np.array([0.05, 0.12, 0.15])
omega0 = np.array([1.0, 9.0, 0.5])
times = np.linspace(0.0, 100.0, 10_001)
drag_model.drag_rates(moments, drag, False, omega0, times[:10])
start = time.perf_counter()
drag_model.drag_rates(moments, drag, False, omega0, times)
seconds = time.perf_counter() - start
substeps = sum(  # as drag_model counts them: |ω| h / MOST_TURN a sample, at least one
    max(1, int(np.ceil(0.01 * np.linalg.norm(w) / drag_model.MOST_TURN)))
    for w in drag_model.drag_rates(moments, drag, False, omega0, times)[:-1]
)
out["drag, 3 states"] = seconds / substeps * 1e9
import tumble as tb
body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.5, 2.0]))
w0 = [0.1, 0.2, 1.0]
tb.simulate(body, w0, duration=0.1, dt=1e-3, method="rk4")
start = time.perf_counter()
tb.simulate(body, w0, duration=20.0, dt=1e-4, record_every=100, method="rk4")
out["rigid body, rk4 (one body)"] = (time.perf_counter() - start) / 2e5 * 1e9
inertia = np.tile(body.inertia, (100_000, 1, 1))
omega = np.tile(w0, (100_000, 1))
tb.simulate_batch(inertia, omega, duration=0.1, dt=1e-2, method="rk4")
start = time.perf_counter()
tb.simulate_batch(inertia, omega, duration=10.0, dt=1e-2, method="rk4")
out["rigid body, rk4 (batch)"] = (time.perf_counter() - start) / 1e8 * 1e9
print(json.dumps(out))
"""

if __name__ == "__main__":
    part_kinds.main(CHILD, __doc__)
