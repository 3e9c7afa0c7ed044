"""Benchmark: the built-in scenarios of the model kinds, this tree against another.

Milliseconds for a whole run of ``tumble.scenario.run`` (simulation, comparison with
theory and its panels; no report written) of the gimballed gyroscope
(``gyrocompass``: two amplitudes) and of the rigid rotor on elastic bearings
(``rotor-on-bearings``: the run-up and the steady run), each the best of three
after a run that compiles, each tree in fresh processes, alternated, medians of the
repeats (the harness of ``bench/part_kinds.py``). With ``--other SRC`` (another
tree's ``src``, e.g. the commit before a change checked out with ``git worktree``)
the two are printed side by side with their ratio (> 1: this tree is faster).

Run from the repository root::

    .venv/bin/python bench/scenario_models.py [--repeat 5] [--other /path/src]
"""

from __future__ import annotations

import part_kinds

#: One process's measurements: each built-in run, its best of three after a warm-up.
CHILD = r"""
import json, time
from tumble import scenario

out = {}
for name in ("gyrocompass", "rotor-on-bearings"):
    loaded = scenario.load(name)
    scenario.run(loaded)
    times = []
    for _ in range(3):
        start = time.perf_counter()
        scenario.run(loaded)
        times.append(time.perf_counter() - start)
    out[name] = min(times) * 1e3
print(json.dumps(out))
"""

if __name__ == "__main__":
    part_kinds.main(CHILD, __doc__, unit="ms a run")
