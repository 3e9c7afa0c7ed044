"""Checks every engine adapter of tumble.conformance passes, against the engine itself.

* :func:`convention_errors`: the angular velocity an adapter reads back, in the
  axes it declares, against the rate finite-differenced from the attitude over
  one short step (the other axes must disagree, so the check can fail).
* :func:`read_back_error`: the inertia the engine uses against the one given.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from tumble.conformance.engine import Engine, EngineBody

#: A body whose three moments differ and obey the triangle inequality, kg·m² and kg.
BODY = EngineBody(mass=2.0, moments=np.array([0.3, 0.5, 0.7]))
#: An attitude far from the identity, so that body and space axes differ.
ATTITUDE = Rotation.from_rotvec([0.9, -0.4, 1.3]).as_quat(scalar_first=True)
#: ω in body axes, rad/s: no principal axis, so the body's axes move in a step.
OMEGA = np.array([1.0, -2.0, 1.5])


def finite_difference_rate(q0: np.ndarray, q1: np.ndarray, dt: float) -> np.ndarray:
    """Body-axes rate that turns attitude q0 into q1 in dt: rotvec(R0⁻¹ R1) / dt (first
    order in dt, exact for a constant rate)."""
    r0 = Rotation.from_quat(q0, scalar_first=True)
    r1 = Rotation.from_quat(q1, scalar_first=True)
    return np.asarray((r0.inv() * r1).as_rotvec() / dt)


def convention_errors(engine: Engine, dt: float = 1e-4) -> tuple[float, float]:
    """Relative errors of the adapter's ω (converted to body axes by its declared
    convention) and of the other convention, against the finite-differenced rate of one
    step of ``dt`` from :data:`ATTITUDE`, :data:`OMEGA`.

    The difference of the rate over a step is O(|ω̇| dt) = O(|ω|² dt) ≈ 1e-3 relative at
    dt = 1e-4, well below the O(1) difference between body and space axes here.
    """
    engine.build(BODY, dt)
    engine.set_state(ATTITUDE, engine.engine_omega(ATTITUDE, OMEGA))
    engine.step(1)
    q1, w1 = engine.state()
    rate = finite_difference_rate(ATTITUDE, np.asarray(q1, float), dt)
    declared = engine.body_omega(q1, w1)
    as_stored = np.asarray(w1, float)
    r1 = Rotation.from_quat(np.asarray(q1, float), scalar_first=True)
    # Read as the other convention would read it: stored space rates taken as body ones,
    # or stored body rates turned from space axes into body axes.
    other = r1.inv().apply(as_stored) if engine.omega_frame == "body" else as_stored
    scale = float(np.linalg.norm(OMEGA))
    engine.close()
    return (
        float(np.linalg.norm(declared - rate) / scale),
        float(np.linalg.norm(other - rate) / scale),
    )


def read_back_error(engine: Engine, body: EngineBody = BODY) -> tuple[float, float]:
    """Relative errors of the mass and of the inertia the engine reads back."""
    engine.build(body, 1e-3)
    mass, inertia = engine.inertia()
    engine.close()
    return (
        abs(mass - body.mass) / body.mass,
        float(np.linalg.norm(inertia - body.inertia) / np.linalg.norm(body.inertia)),
    )
