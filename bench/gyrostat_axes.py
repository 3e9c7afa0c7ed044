"""Accuracy: the splittings of a dual-spin body against the gyrostat's closed form.

A body of locked moments 4, 6, 8 kg·m² carrying a rotor (J = 0.5 kg·m², no
motor) on its intermediate axis, two initial spins and four rotor speeds, 20 s:
the largest error of ω (rad/s) and of the attitude (rad) of ``strang`` and
``splitting`` at two steps, against ``method="exact"``. Run on another tree
(``PYTHONPATH=…/src``) to compare its splitting with this one's.

Run from the repository root::

    .venv/bin/python bench/gyrostat_axes.py
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

import tumble as tb
from machine import describe

BODY = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))
DURATION = 20.0
STEPS = (0.05, 0.01)


def run(method: str, dt: float, speed: float, omega0: list[float]) -> tb.Trajectory:
    return tb.simulate(BODY, omega0, duration=DURATION, dt=dt, method=method,
                       record_every=round(DURATION / dt),
                       internal=[tb.Rotor([0, 1, 0], 0.5, speed=speed)])  # fmt: skip


def error(stepped: tb.Trajectory, exact: tb.Trajectory) -> float:
    """The larger of the ω error (rad/s) and the attitude error (rad) at the end."""
    turn = Rotation.from_quat(exact.quaternion, scalar_first=True).inv() * Rotation.from_quat(
        stepped.quaternion, scalar_first=True
    )
    return max(float(np.max(np.abs(stepped.omega - exact.omega))), float(np.max(turn.magnitude())))


def main() -> None:
    print(describe({}))
    heads = [f"{method} {dt:g}" for method in ("strang", "splitting") for dt in STEPS]
    print(f"{'omega0':>16s} {'speed':>6s} " + " ".join(f"{h:>15s}" for h in heads))
    worst = np.zeros(len(heads))
    for omega0 in ([0.01, 1.0, 0.0], [0.3, 0.5, 0.2]):
        for speed in (-8.0, -2.0, 2.0, 8.0):
            exact = run("exact", DURATION, speed, omega0)
            row = [
                error(run(method, dt, speed, omega0), exact)
                for method in ("strang", "splitting")
                for dt in STEPS
            ]
            worst = np.maximum(worst, row)
            print(f"{omega0!s:>16s} {speed:6.1f} " + " ".join(f"{e:15.2e}" for e in row))
    print(f"{'worst':>23s} " + " ".join(f"{e:15.2e}" for e in worst))


if __name__ == "__main__":
    main()
