"""Accuracy of the stepping and adaptive methods against the exact solution, at
steps where round-off rather than truncation may dominate.

For three free bodies (I = 1, 2, 3 kg·m²; ω0 near the separatrix, a generic
tumble, near the major axis) and T = 100 and 1000 s: the largest |Δω| (rad/s)
at T against tumble's closed form, for the adaptive method at rtol 1e-10 and
1e-12 (atol = rtol / 100) and RK4 at dt 1e-2 and 1e-3. Run it on two versions
of tumble to see whether a change moved the errors beyond round-off::

    .venv/bin/python bench/accuracy.py
"""

from __future__ import annotations

import numpy as np

import tumble as tb

STARTS = ([0.01, 2.0, 0.01], [0.3, 1.0, -0.5], [1.0, 0.2, 0.1])


def main() -> None:
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    print(f"{'omega0':>20s} {'T s':>6s}  adaptive 1e-10  adaptive 1e-12     rk4 1e-2     rk4 1e-3")
    for omega0 in STARTS:
        for duration in (100.0, 1000.0):
            exact = tb.simulate(body, omega0, duration=duration, dt=duration, method="exact")
            errors = []
            for rtol in (1e-10, 1e-12):
                run = tb.simulate(
                    body, omega0, duration=duration, dt=duration / 10, method="adaptive",
                    rtol=rtol, atol=rtol * 1e-2,
                )  # fmt: skip
                errors.append(np.max(np.abs(run.omega[-1] - exact.omega[-1])))
            for dt in (1e-2, 1e-3):
                run = tb.simulate(
                    body, omega0, duration=duration, dt=dt, method="rk4", record_every=10**7
                )
                errors.append(np.max(np.abs(run.omega[-1] - exact.omega[-1])))
            shown = "".join(f"{e:>15.1e}" for e in errors)
            print(f"{omega0!s:>20s} {duration:6.0f} {shown}")


if __name__ == "__main__":
    main()
