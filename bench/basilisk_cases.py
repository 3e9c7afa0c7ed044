"""Three rigid-body cases set up in Basilisk (``bsk`` 2.12.1), for side-by-side runs with tumble.

Cases (all SI units):

* :func:`reaction_wheels` — a hub with three balanced reaction wheels, a motor-torque
  pulse on ``0 <= t < 0.5 s`` and a free coast to 20 s;
* :func:`gravity_gradient` — a boom satellite librating in a circular orbit about a
  point-mass Earth, with Basilisk's ``GravityGradientEffector``;
* :func:`spin_up` — one wheel spun up from rest by a constant motor torque (closed form
  in :func:`spin_up_closed_form`, checked in the self-test at the bottom).

Each function returns a dict of NumPy arrays plus ``wall_s`` (seconds spent inside
``ExecuteSimulation`` calls only) and ``setup_s`` (building the simulation and
``InitializeSimulation``). Output conventions, as in tumble:

* ``t`` [s]; ``omega`` = ω_BN in body (B) coordinates [rad/s];
* ``quaternion`` scalar-first ``[w, x, y, z]``, rotating body coordinates into inertial
  coordinates (``v_N = q ⊗ v_B ⊗ q*``), sign-continuous along the run (first sample has
  ``w >= 0``);
* ``position`` [m] and ``angular_momentum`` [N·m·s] in inertial (N) coordinates.

Basilisk conventions found (and how they are used here)
-------------------------------------------------------

Hub and wheel mass properties. In Basilisk 2.12.1 a ``BalancedWheels`` (and
``JitterSimple``) wheel contributes NO mass and NO inertia to the spacecraft:
``ReactionWheelStateEffector::updateEffectorMassProps`` only accumulates ``mass``,
``rWcB_B`` and ``IRWPntWc_B`` for ``JitterFullyCoupled`` wheels
(src/simulation/dynamics/reactionWheels/reactionWheelStateEffector.cpp, AVSLab/basilisk).
The balanced wheel enters the equations of motion only through its spin inertia ``Js``
about ``gsHat_B``: ``matrixD -= Js gs gsᵀ``, ``vecRot -= gs u + Js Ω ω × gs``
(``updateContributions``), ``Ω̇ = u/Js − gsᵀω̇`` (``computeDerivatives``), and in the
momentum/energy bookkeeping only the relative-spin terms ``Js Ω gs`` and
``½ Js Ω² + Js Ω gsᵀω`` (``updateEnergyMomContributions``). ``Jt``, ``Jg``, ``mass``
and ``rWB_B`` are ignored for balanced wheels. Basilisk issue #600 ("Include mass and inertia
contributions for balanced reaction wheels", open) says so in words: "the wheels'
constant mass and inertia contributions are ignored under the assumption that they are
absorbed into the hub's mass properties. Therefore, it is up to the user to augment the
hub's mass and inertia". PR #1545 (open, not in 2.12.1) adds an opt-in
``includeWheelMassProperties`` flag, default ``False`` so that existing simulations that
"include these properties in the hub" are unchanged; the 2.12.1 wheel has no such
attribute. So, in 2.12.1, ``mHub``/``r_BcB_B``/``IHubPntBc_B`` must be the properties of
hub PLUS wheels (each wheel's full inertia ``diag(Js, Jt, Jg)`` in its own axes, its mass,
and the parallel-axis terms), about the composite centre of mass. :func:`composite_hub`
folds the wheels into the hub that way; the default ``wheel_model="balanced"`` uses it.
``wheel_model="fully_coupled"`` instead gives the bare hub to Basilisk and uses
``JitterFullyCoupled`` wheels with zero imbalance (``U_s = U_d = 0``, hence ``d = 0``,
``J13 = 0``), for which the effector itself adds ``mass``, ``rWB_B`` and
``diag(Js, Jt, Jg)``: the same physical system, a cross-check of the convention (the
self-test finds the two agree to round-off). A hub that EXCLUDES the wheels, with the
effector adding them, is right only for ``JitterFullyCoupled`` (or with PR #1545's
flag); with ``BalancedWheels`` it silently drops the wheels' mass and inertia, and the
spin-up closed form fails (ω̇_z = −u/14.5 instead of −u/15). The C++ was read on the
``develop`` branch of AVSLab/basilisk (the 2.12.1 source revision 67d8946 was not
available); the behaviour was confirmed numerically on the installed 2.12.1 wheel.

Wheel transverse inertia. ``Js`` is about ``gsHat_B``, ``Jt`` about ``w2Hat_B`` and
``Jg`` about ``w3Hat_B`` (``RWConfigPayload.h``; ``IRWPntWc_W = [[Js,0,J13],[0,Jt,0],
[J13,0,Jg]]``). ``simIncludeRW.rwFactory.create(..., Js=...)`` silently sets
``Jt = Jg = Js/2`` and takes ``Omega`` in RPM, so both are overwritten here after
``create``.

Attitude. ``sigma_BN`` are the MRPs of B relative to N: ``MRP2C(sigma_BN)`` is [BN],
mapping N-coordinates to B-coordinates (Basilisk ``RigidBodyKinematics``; the C++ uses
``dcm_NB = sigmaBN.toRotationMatrix()``). The quaternion wanted here maps B to N, i.e.
represents [NB] = [BN]ᵀ; for σ = ê tan(φ/4) (B rotated by φ about ê from N) that is
q = (cos φ/2, ê sin φ/2) = ((1 − σ²), 2σ)/(1 + σ²) (:func:`mrp_to_quaternion`). Basilisk
switches to the shadow set when |σ| > 1, which flips the sign of q; the output is made
sign-continuous. :func:`check_quaternion_convention` verifies this numerically with a
steady spin about +z (ω = 0.1 rad/s for 1 s must give q = (cos 0.05, 0, 0, sin 0.05)).

Motor torque. ``u`` is the torque of the hub on the wheel about ``+gsHat_B``:
``Js (Ω̇ + gsᵀω̇) = u`` and the hub feels ``−u gs`` (reactionWheelStateEffector.cpp).
It is commanded through an ``ArrayMotorTorqueMsg`` (``motorTorque[i]``, N·m) subscribed
to ``rwMotorCmdInMsg``; the effector reads it in its ``UpdateState`` (``ReadInputs``,
``ConfigureRWRequests``: saturation is off for ``u_max <= 0``, speed limit off for
``Omega_max < 0``, power limit off for ``P_max < 0``) and holds it (zero-order hold) while
the spacecraft integrates. The effector is added to the task with a higher priority
than the spacecraft (as in Basilisk's scenarioAttitudeFeedbackRW), so in each task tick
at t_k it reads the command first and the spacecraft then integrates [t_{k−1}, t_k]
with it. Switching off at exactly 0.5 s: ``ExecuteSimulation`` to stop time 0.5 s
(whose tick integrated [0.5 − dt, 0.5] with the torque on), write a zero command to the
same message, ``ExecuteSimulation`` to the end (the tick at 0.5 + dt reads zero and
integrates [0.5, 0.5 + dt] without torque). 0.5 s must therefore be a whole number of
steps. The self-test checks it with the exact linear invariant of each axisymmetric
wheel, ``Δ[Js (Ω_i + ω_i)] = u_i · 0.5 s``.

Energy and momentum. ``totRotAngMomPntC_N`` and ``totRotEnergy`` are members of the
``Spacecraft`` (``Spacecraft::computeEnergyMomentum``, called after every integration
step): hub ``I_Bc ω + m r_BcB × (ω × r_BcB)`` plus each effector's contribution, minus
``m_sc c × ċ``, rotated to N; the energy is ``½ ωᵀI ω`` plus the effector terms minus
``½ m_sc ċ²``, i.e. the kinetic energy relative to the centre of mass (motion of the
centre of mass excluded). They are logged with ``scObject.logger([...], period)``
only when asked (``conserved=True``): the logger is Python-side work that a timed
run compared with another simulator's must not do unless both do it.

Integrators. ``integrator="rk4"`` (Basilisk's default ``svIntegratorRK4``: one fixed
step of ``dt`` per task tick), ``"rkf45"``/``"rkf78"`` (``svIntegratorRKF45``/``RKF78``,
``setIntegrator``). The adaptive ones are restarted every task tick with a trial step
equal to ``dt`` (``svIntegratorAdaptiveRungeKutta::integrate`` starts from
``timeStep = desiredTimeStep``), shrink it until each state's error is within
``relTol·|state| + absTol`` and never step past the tick: their steps are <= dt and
end exactly on every tick. ``tolerance`` sets ``relTol`` and ``abs_tolerance`` (default
``tolerance``) sets ``absTol`` (Basilisk defaults 1e-4 and 1e-8).

Recording. Recorders and loggers run in a separate task of period ``record_dt`` with a
lower priority than the dynamics task, so they sample after the dynamics tick at the
same time and cost nothing on the other ticks (``scObject.logger`` is a Python module:
a dynamics-task logger would call into Python every step). ``record_dt=None`` records
every step when the run has at most :data:`MAX_DEFAULT_SAMPLES` steps and otherwise the
smallest whole number of steps giving at most that many samples; ``record_dt`` must be
a whole number of steps. Samples start at t = 0 and include the final time when the run
is a whole number of recording periods.
"""

from __future__ import annotations

import math
import time
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]
WheelModel = Literal["balanced", "fully_coupled"]

#: Earth's gravitational parameter used by :func:`gravity_gradient` [m³/s²].
MU_EARTH = 3.986004418e14

#: Integrator names accepted by the cases.
INTEGRATORS = ("rk4", "rkf45", "rkf78")

#: Default record_dt: every step up to this many steps, coarser beyond.
MAX_DEFAULT_SAMPLES = 20_000

_DYN_TASK = "dynamics"
_LOG_TASK = "logging"


# --- conventions -------------------------------------------------------------------------


def mrp_to_quaternion(sigma_bn: ArrayLike) -> Array:
    """Convert Basilisk's MRPs σ_BN (shape (n, 3)) to quaternions (n, 4).

    The result is scalar-first ``[w, x, y, z]`` and rotates body coordinates into
    inertial coordinates (it represents [NB] = MRP2C(σ_BN)ᵀ). Consecutive rows are made
    sign-continuous (Basilisk's MRP shadow-set switch flips the sign of q); the first
    row has ``w >= 0``.
    """
    sigma = np.atleast_2d(np.asarray(sigma_bn, dtype=np.float64))
    s2 = np.einsum("ij,ij->i", sigma, sigma)
    q = np.empty((sigma.shape[0], 4))
    q[:, 0] = (1.0 - s2) / (1.0 + s2)
    q[:, 1:] = 2.0 * sigma / (1.0 + s2)[:, None]
    dots = np.einsum("ij,ij->i", q[1:], q[:-1])
    flips = np.concatenate(([q[0, 0] < 0.0], dots < 0.0))
    sign = np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)
    return q * sign[:, None]


def quaternion_to_mrp(q: ArrayLike) -> Array:
    """Convert one scalar-first quaternion (body → inertial) to Basilisk's σ_BN (3,)."""
    qv = np.asarray(q, dtype=np.float64)
    qv = qv / np.linalg.norm(qv)
    if qv[0] < 0.0:
        qv = -qv
    out: Array = qv[1:] / (1.0 + qv[0])
    return out


def quaternion_to_matrix(q: ArrayLike) -> Array:
    """Rotation matrix R (3, 3) of a scalar-first unit quaternion: ``v_N = R v_B``."""
    w, x, y, z = np.asarray(q, dtype=np.float64)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def composite_hub(
    hub_mass: float,
    hub_inertia: ArrayLike,
    wheel_mass: ArrayLike,
    wheel_position: ArrayLike,
    wheel_axis: ArrayLike,
    js: ArrayLike,
    jt: ArrayLike,
) -> tuple[float, Array, Array]:
    """Fold axisymmetric wheels into a hub whose centre of mass is at the body origin B.

    Args:
        hub_mass: hub mass without wheels [kg].
        hub_inertia: (3, 3) hub inertia about its centre of mass (= B), body axes [kg·m²].
        wheel_mass: (k,) wheel masses [kg].
        wheel_position: (k, 3) wheel centres relative to B, body axes [m].
        wheel_axis: (k, 3) spin axes, body axes (normalised here).
        js: (k,) wheel inertias about the spin axis [kg·m²].
        jt: (k,) wheel inertias about any transverse axis (Jt = Jg) [kg·m²].

    Returns:
        ``(m, r_c, I_c)``: total mass [kg], centre of mass relative to B [m] and inertia
        about that centre of mass in body axes [kg·m²] — Basilisk's ``mHub``,
        ``r_BcB_B`` and ``IHubPntBc_B`` for ``BalancedWheels``.
    """
    masses = np.asarray(wheel_mass, dtype=np.float64)
    pos = np.atleast_2d(np.asarray(wheel_position, dtype=np.float64))
    axes = np.atleast_2d(np.asarray(wheel_axis, dtype=np.float64))
    axes = axes / np.linalg.norm(axes, axis=1)[:, None]
    total = hub_mass + float(masses.sum())
    inertia_b = np.array(hub_inertia, dtype=np.float64)
    eye = np.eye(3)
    j_s = np.asarray(js, dtype=np.float64).ravel()
    j_t = np.asarray(jt, dtype=np.float64).ravel()
    for m, r, g, s, t in zip(masses, pos, axes, j_s, j_t, strict=True):
        own = t * eye + (s - t) * np.outer(g, g)
        inertia_b += own + m * (r @ r * eye - np.outer(r, r))
    c = (masses[:, None] * pos).sum(axis=0) / total
    inertia_c = inertia_b - total * (c @ c * eye - np.outer(c, c))
    return total, c, inertia_c


# --- Basilisk plumbing ------------------------------------------------------------------


def _nanos(seconds: float) -> int:
    """Seconds to Basilisk's integer nanoseconds."""
    return round(seconds * 1e9)


def _steps(span: float, dt: float, what: str) -> int:
    """Number of steps of ``dt`` in ``span``; ``span`` must be a whole number of steps."""
    n = round(span / dt)
    if n < 1 or abs(n * _nanos(dt) - _nanos(span)) > 0:
        raise ValueError(f"{what} = {span!r} s is not a whole number of steps of {dt!r} s")
    return n


def _record_nanos(dt: float, n_steps: int, record_dt: float | None) -> int:
    """Recording period in nanoseconds, a whole number of dynamics steps."""
    if record_dt is None:
        every = max(1, math.ceil(n_steps / MAX_DEFAULT_SAMPLES))
    else:
        every = _steps(record_dt, dt, "record_dt")
    return every * _nanos(dt)


def _new_sim(dt: float, record_nanos: int) -> tuple[Any, Any]:
    """A simulation with a dynamics task (period dt) and a logging task (record period)."""
    from Basilisk.utilities import SimulationBaseClass

    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("process")
    # Higher task priority runs first at coincident times: dynamics, then logging.
    proc.addTask(sim.CreateNewTask(_DYN_TASK, _nanos(dt)), 100)
    proc.addTask(sim.CreateNewTask(_LOG_TASK, record_nanos), 10)
    return sim, proc


def _set_integrator(
    sc: Any, integrator: str, tolerance: float | None, abs_tolerance: float | None
) -> None:
    """Select Basilisk's integrator for the spacecraft ``sc``."""
    from Basilisk.simulation import svIntegrators

    name = integrator.lower()
    if name == "rk4":
        if tolerance is not None or abs_tolerance is not None:
            raise ValueError("tolerance applies to rkf45 and rkf78 only")
        sc.setIntegrator(svIntegrators.svIntegratorRK4(sc))
        return
    if name not in ("rkf45", "rkf78"):
        raise ValueError(f"integrator must be one of {INTEGRATORS}, not {integrator!r}")
    cls = svIntegrators.svIntegratorRKF45 if name == "rkf45" else svIntegrators.svIntegratorRKF78
    integ = cls(sc)
    if tolerance is not None:
        integ.setRelativeTolerance(tolerance)
        integ.setAbsoluteTolerance(tolerance if abs_tolerance is None else abs_tolerance)
    elif abs_tolerance is not None:
        integ.setAbsoluteTolerance(abs_tolerance)
    sc.setIntegrator(integ)


def _column(values: Any) -> list[list[float]]:
    """A 3-vector as Basilisk's column list ``[[x], [y], [z]]``."""
    return [[float(v)] for v in np.asarray(values, dtype=np.float64).ravel()]


def _execute(sim: Any, stop_s: float) -> float:
    """Run ``sim`` to ``stop_s`` seconds; return the wall time of ExecuteSimulation [s]."""
    sim.ConfigureStopTime(_nanos(stop_s))
    start = time.perf_counter()
    sim.ExecuteSimulation()
    return time.perf_counter() - start


def _states(log: Any) -> dict[str, Array]:
    """t, omega, quaternion and position from a recorder of ``scStateOutMsg``."""
    return {
        "t": np.asarray(log.times(), dtype=np.float64) * 1e-9,
        "omega": np.array(log.omega_BN_B, dtype=np.float64),
        "quaternion": mrp_to_quaternion(np.array(log.sigma_BN, dtype=np.float64)),
        "position": np.array(log.r_CN_N, dtype=np.float64),
        "velocity": np.array(log.v_CN_N, dtype=np.float64),
    }


def _add_wheels(
    sc: Any,
    sim: Any,
    model: WheelModel,
    axes: ArrayLike,
    positions: ArrayLike,
    js: float,
    jt: float,
    mass: float,
    omega0: ArrayLike,
) -> tuple[Any, Any]:
    """Attach wheels to ``sc``; return the effector and the factory (kept alive)."""
    from Basilisk.architecture import messaging
    from Basilisk.simulation import reactionWheelStateEffector
    from Basilisk.utilities import simIncludeRW

    rw_model = messaging.BalancedWheels if model == "balanced" else messaging.JitterFullyCoupled
    factory = simIncludeRW.rwFactory()
    axes_a = np.atleast_2d(np.asarray(axes, dtype=np.float64))
    pos_a = np.atleast_2d(np.asarray(positions, dtype=np.float64))
    om_a = np.asarray(omega0, dtype=np.float64).ravel()
    for axis, pos, om in zip(axes_a, pos_a, om_a, strict=True):
        rw = factory.create(
            "custom",
            [float(a) for a in axis],
            Js=float(js),
            rWB_B=[float(p) for p in pos],
            RWModel=rw_model,
            useMaxTorque=False,  # u_max = -1: no torque saturation
        )
        rw.Jt = float(jt)  # the factory sets Jt = Jg = Js/2
        rw.Jg = float(jt)
        rw.mass = float(mass)
        rw.Omega = float(om)  # rad/s (the factory's Omega keyword is in RPM)
        rw.Omega_max = -1.0  # no speed limit
        rw.P_max = -1.0  # no power limit
        rw.U_s = 0.0  # balanced: no static or dynamic imbalance
        rw.U_d = 0.0
    effector = reactionWheelStateEffector.ReactionWheelStateEffector()
    factory.addToSpacecraft("rw", effector, sc)
    # Higher model priority than the spacecraft: read the command, then integrate.
    sim.AddModelToTask(_DYN_TASK, effector, 20)
    return effector, factory


def _make_spacecraft(
    sim: Any,
    mass: float,
    r_c: ArrayLike,
    inertia_c: ArrayLike,
    omega0: ArrayLike,
    sigma0: ArrayLike | None = None,
    r0: ArrayLike | None = None,
    v0: ArrayLike | None = None,
) -> Any:
    """A Basilisk spacecraft hub with the given mass properties and initial state."""
    from Basilisk.simulation import spacecraft

    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sc"
    sc.hub.mHub = float(mass)
    sc.hub.r_BcB_B = _column(r_c)
    sc.hub.IHubPntBc_B = np.asarray(inertia_c, dtype=np.float64).tolist()
    sc.hub.sigma_BNInit = _column(np.zeros(3) if sigma0 is None else sigma0)
    sc.hub.omega_BN_BInit = _column(omega0)
    sc.hub.r_CN_NInit = _column(np.zeros(3) if r0 is None else r0)
    sc.hub.v_CN_NInit = _column(np.zeros(3) if v0 is None else v0)
    sim.AddModelToTask(_DYN_TASK, sc, 10)
    return sc


def _motor_command(torques: ArrayLike) -> tuple[Any, Any]:
    """A stand-alone ``ArrayMotorTorqueMsg`` holding ``torques`` [N·m], and its payload type."""
    from Basilisk.architecture import messaging

    payload = messaging.ArrayMotorTorqueMsgPayload()
    payload.motorTorque = np.asarray(torques, dtype=np.float64).ravel().tolist()
    return messaging.ArrayMotorTorqueMsg().write(payload), messaging.ArrayMotorTorqueMsgPayload


# --- the cases ---------------------------------------------------------------------------


def _wheels_and_logs(
    sim: Any, sc: Any, wheels: tuple[Any, ...], torques: ArrayLike, conserved: bool
) -> tuple[Any, Any, tuple[Any, Any, Any]]:
    """Add the wheels (``(model, axes, positions, js, jt, mass, speeds)``, see
    :func:`_add_wheels`) to the spacecraft with their motor command (``torques``,
    N·m), the recorders of the state, the wheel speeds and, with ``conserved``, the
    conserved quantities (a Python-side logger: work a run without it does not do),
    and initialise the simulation; the command message, its payload type and the
    three recorders (the third None without ``conserved``)."""
    model, axes, positions, js, jt, mass, speeds = wheels
    effector, _factory = _add_wheels(sc, sim, model, axes, positions, js, jt, mass, speeds)
    cmd_msg, payload_type = _motor_command(torques)
    effector.rwMotorCmdInMsg.subscribeTo(cmd_msg)
    logs = (
        sc.scStateOutMsg.recorder(),
        effector.rwSpeedOutMsg.recorder(),
        sc.logger(["totRotAngMomPntC_N", "totRotEnergy"]) if conserved else None,
    )
    for log in logs:
        if log is not None:
            sim.AddModelToTask(_LOG_TASK, log)
    sim.InitializeSimulation()
    return cmd_msg, payload_type, logs


def _conserved(log: Any) -> dict[str, Array]:
    """``angular_momentum`` and ``energy`` from the logger of the conserved quantities,
    none without one."""
    if log is None:
        return {}
    return {
        "angular_momentum": np.array(log.totRotAngMomPntC_N, dtype=np.float64),
        "energy": np.array(log.totRotEnergy, dtype=np.float64),
    }


def reaction_wheels(
    dt: float,
    duration: float = 20.0,
    record_dt: float | None = None,
    integrator: str = "rk4",
    tolerance: float | None = None,
    abs_tolerance: float | None = None,
    wheel_model: WheelModel = "balanced",
    torque_off: float = 0.5,
    conserved: bool = False,
) -> dict[str, Any]:
    """Hub with three balanced reaction wheels, torque pulse then coast.

    Hub without wheels: 750 kg, centre of mass at B, inertia diag(900, 800, 600) kg·m².
    Wheels: spin axes body x, y, z; Js = 0.15, Jt = Jg = 0.08 kg·m², 9 kg each, centres
    at 0.5 m along their axes; initial relative speeds Ω = (100, −200, 300) rad/s.
    Initial ω_BN_B = (0.05, −0.03, 0.02) rad/s, identity attitude, body origin B at
    (0, 0, 0) with the system centre of mass at rest (Basilisk's ``r_CN_NInit`` and
    ``v_CN_NInit`` are the centre of mass's), no gravity. Motor torques
    u = (0.2, −0.1, 0.15) N·m for 0 <= t < ``torque_off``, then 0.

    Args:
        dt: dynamics task period (the RK4 step) [s]; ``torque_off`` and ``duration`` must
            be whole numbers of steps.
        duration: run length [s].
        record_dt: sampling period of the recorders [s] (see the module docstring).
        integrator: ``"rk4"``, ``"rkf45"`` or ``"rkf78"``.
        tolerance: relative tolerance of the adaptive integrators.
        abs_tolerance: absolute tolerance of the adaptive integrators (default
            ``tolerance``).
        wheel_model: ``"balanced"`` (BalancedWheels, wheels folded into the hub) or
            ``"fully_coupled"`` (JitterFullyCoupled with zero imbalance, bare hub).
        torque_off: time at which the motor torque switches to zero [s].
        conserved: also log H and the energy (``angular_momentum``, ``energy``), by a
            Python-side logger that costs time of its own.

    Returns:
        dict with ``t`` (n,) [s], ``omega`` (n, 3) [rad/s, B], ``quaternion`` (n, 4)
        [B → N], ``wheel_speed`` (n, 3) [rad/s, relative to the hub],
        ``angular_momentum`` (n, 3) [N·m·s, about the system centre of mass, N axes],
        ``energy`` (n,) [J, rotational kinetic energy], ``position`` (n, 3) [m, centre
        of mass, N], ``velocity`` (n, 3) [m/s, centre of mass, N], ``wall_s``,
        ``setup_s``, ``steps`` and the parameters ``js``, ``motor_torque``,
        ``torque_off``, ``hub_mass_bsk``, ``hub_inertia_bsk``, ``hub_com_bsk`` (what was
        given to Basilisk's hub), ``inertia_total`` (hub + wheels about the system centre
        of mass, body axes) and ``com_total`` (system centre of mass relative to B).
    """
    t0 = time.perf_counter()
    n_on = _steps(torque_off, dt, "torque_off")
    n_steps = _steps(duration, dt, "duration")
    if n_on >= n_steps:
        raise ValueError("torque_off must be before the end of the run")

    hub_mass, hub_inertia = 750.0, np.diag([900.0, 800.0, 600.0])
    axes = np.eye(3)
    positions = 0.5 * np.eye(3)
    js, jt, mw = 0.15, 0.08, 9.0
    omega_wheels0 = np.array([100.0, -200.0, 300.0])
    u_on = np.array([0.2, -0.1, 0.15])

    m_all, c_all, i_all = composite_hub(
        hub_mass, hub_inertia, np.full(3, mw), positions, axes, np.full(3, js), np.full(3, jt)
    )
    if wheel_model == "balanced":
        m_bsk, c_bsk, i_bsk = m_all, c_all, i_all
    elif wheel_model == "fully_coupled":
        m_bsk, c_bsk, i_bsk = hub_mass, np.zeros(3), hub_inertia
    else:
        raise ValueError(f"wheel_model must be 'balanced' or 'fully_coupled', not {wheel_model!r}")

    sim, _ = _new_sim(dt, _record_nanos(dt, n_steps, record_dt))
    omega0 = np.array([0.05, -0.03, 0.02])
    # Basilisk's r_CN_NInit / v_CN_NInit are the system centre of mass: it starts at rest
    # and at c, so that the body origin B starts at (0, 0, 0).
    sc = _make_spacecraft(sim, m_bsk, c_bsk, i_bsk, omega0, r0=c_all)
    _set_integrator(sc, integrator, tolerance, abs_tolerance)
    wheels = (wheel_model, axes, positions, js, jt, mw, omega_wheels0)
    cmd_msg, payload_type, (state_log, speed_log, conserved_log) = _wheels_and_logs(
        sim, sc, wheels, u_on, conserved
    )
    setup_s = time.perf_counter() - t0

    wall = _execute(sim, n_on * dt)
    off = payload_type()
    off.motorTorque = [0.0, 0.0, 0.0]
    cmd_msg.write(off)
    wall += _execute(sim, n_steps * dt)

    out: dict[str, Any] = _states(state_log)
    out["wheel_speed"] = np.array(speed_log.wheelSpeeds, dtype=np.float64)[:, :3]
    out.update(_conserved(conserved_log))
    out.update(
        wall_s=wall,
        setup_s=setup_s,
        steps=n_steps,
        js=js,
        motor_torque=u_on,
        torque_off=n_on * dt,
        hub_mass_bsk=m_bsk,
        hub_inertia_bsk=i_bsk,
        hub_com_bsk=c_bsk,
        inertia_total=i_all,
        com_total=c_all,
    )
    return out


def gravity_gradient(
    dt: float,
    duration: float | None = None,
    record_dt: float | None = None,
    integrator: str = "rk4",
    tolerance: float | None = None,
    abs_tolerance: float | None = None,
) -> dict[str, Any]:
    """Boom satellite librating under gravity-gradient torque in a circular orbit.

    Point-mass Earth (μ = :data:`MU_EARTH`, no J2, no other bodies), orbit radius
    7000 km, n = √(μ/r³). Satellite: 100 kg, inertia about its centre of mass
    diag(5, 50, 52) kg·m². Initial r = (7000e3, 0, 0) m, v = (0, √(μ/r), 0) m/s (orbit
    normal +z), attitude a 5° rotation about +z (body → inertial), ω_BN_B = (0, 0, n).
    The spacecraft's own gravity field (``gravField``) makes it orbit; a
    ``GravityGradientEffector`` with the same planet applies the torque.

    Args:
        dt: dynamics task period [s].
        duration: run length [s]; default three orbital periods, rounded to a whole
            number of steps (the returned ``t`` ends at the time actually reached).
        record_dt: sampling period of the recorders [s].
        integrator: ``"rk4"``, ``"rkf45"`` or ``"rkf78"``.
        tolerance: relative tolerance of the adaptive integrators.
        abs_tolerance: absolute tolerance of the adaptive integrators.

    Returns:
        dict with ``t`` (n,) [s], ``omega`` (n, 3) [rad/s, B], ``quaternion`` (n, 4)
        [B → N], ``position`` (n, 3) [m, N, centre of mass], ``velocity`` (n, 3)
        [m/s, N, centre of mass], ``n`` [rad/s], ``wall_s``,
        ``setup_s``, ``steps``, ``inertia`` (3, 3) and ``mu``.
    """
    from Basilisk.simulation import GravityGradientEffector
    from Basilisk.utilities import simIncludeGravBody

    t0 = time.perf_counter()
    radius = 7000e3
    n = math.sqrt(MU_EARTH / radius**3)
    if duration is None:
        duration = 3 * 2 * math.pi / n
    n_steps = max(1, round(duration / dt))
    inertia = np.diag([5.0, 50.0, 52.0])
    angle = math.radians(5.0)
    q0 = np.array([math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)])

    sim, _ = _new_sim(dt, _record_nanos(dt, n_steps, record_dt))
    sc = _make_spacecraft(
        sim,
        100.0,
        np.zeros(3),
        inertia,
        np.array([0.0, 0.0, n]),
        sigma0=quaternion_to_mrp(q0),
        r0=np.array([radius, 0.0, 0.0]),
        v0=np.array([0.0, math.sqrt(MU_EARTH / radius), 0.0]),
    )
    _set_integrator(sc, integrator, tolerance, abs_tolerance)

    grav = simIncludeGravBody.gravBodyFactory()
    earth = grav.createEarth()
    earth.isCentralBody = True
    earth.mu = MU_EARTH  # point mass (createEarth has no spherical harmonics)
    grav.addBodiesTo(sc)

    gg = GravityGradientEffector.GravityGradientEffector()
    gg.ModelTag = "gravityGradient"
    gg.addPlanetName(earth.planetName)
    sc.addDynamicEffector(gg)
    sim.AddModelToTask(_DYN_TASK, gg, 5)

    state_log = sc.scStateOutMsg.recorder()
    sim.AddModelToTask(_LOG_TASK, state_log)
    sim.InitializeSimulation()
    setup_s = time.perf_counter() - t0

    wall = _execute(sim, n_steps * dt)
    out: dict[str, Any] = _states(state_log)
    out.update(
        n=n,
        wall_s=wall,
        setup_s=setup_s,
        steps=n_steps,
        inertia=inertia,
        mu=MU_EARTH,
    )
    return out


def spin_up(
    dt: float,
    duration: float = 10.0,
    record_dt: float | None = None,
    integrator: str = "rk4",
    tolerance: float | None = None,
    abs_tolerance: float | None = None,
    wheel_model: WheelModel = "balanced",
    conserved: bool = False,
) -> dict[str, Any]:
    """One wheel on the body z axis spun up from rest by a constant motor torque.

    Hub without the wheel: 50 kg, centre of mass at B, inertia diag(10, 12, 15) kg·m².
    Wheel: spin axis body z, Js = 0.5, Jt = Jg = 0.3 kg·m², 2 kg, centred at B.
    Everything at rest, identity attitude; motor torque u = 0.1 N·m throughout.

    Args:
        dt: dynamics task period [s].
        duration: run length [s], a whole number of steps.
        record_dt: sampling period of the recorders [s].
        integrator: ``"rk4"``, ``"rkf45"`` or ``"rkf78"``.
        tolerance: relative tolerance of the adaptive integrators.
        abs_tolerance: absolute tolerance of the adaptive integrators.
        wheel_model: as in :func:`reaction_wheels`.
        conserved: as in :func:`reaction_wheels`.

    Returns:
        dict with ``t`` (n,) [s], ``omega`` (n, 3) [rad/s, B], ``quaternion`` (n, 4)
        [B → N], ``wheel_speed`` (n, 1) [rad/s, relative], ``angular_momentum`` (n, 3)
        [N·m·s, N axes; zero by the physics] and ``energy`` (n,) [J] as in
        :func:`reaction_wheels`, ``wall_s``, ``setup_s``, ``steps`` and the parameters
        ``u``, ``js``, ``iz`` (z moment of hub + wheel about the centre of mass).
    """
    t0 = time.perf_counter()
    n_steps = _steps(duration, dt, "duration")
    hub_mass, hub_inertia = 50.0, np.diag([10.0, 12.0, 15.0])
    js, jt, mw, u = 0.5, 0.3, 2.0, 0.1
    axes, positions = np.array([[0.0, 0.0, 1.0]]), np.zeros((1, 3))
    if wheel_model == "balanced":
        m_bsk, c_bsk, i_bsk = composite_hub(
            hub_mass, hub_inertia, [mw], positions, axes, [js], [jt]
        )
    elif wheel_model == "fully_coupled":
        m_bsk, c_bsk, i_bsk = hub_mass, np.zeros(3), hub_inertia
    else:
        raise ValueError(f"wheel_model must be 'balanced' or 'fully_coupled', not {wheel_model!r}")

    sim, _ = _new_sim(dt, _record_nanos(dt, n_steps, record_dt))
    sc = _make_spacecraft(sim, m_bsk, c_bsk, i_bsk, np.zeros(3))
    _set_integrator(sc, integrator, tolerance, abs_tolerance)
    wheels = (wheel_model, axes, positions, js, jt, mw, [0.0])
    # The command message is held here: the effector reads it through its subscription.
    _command, _, (state_log, speed_log, conserved_log) = _wheels_and_logs(
        sim, sc, wheels, [u], conserved
    )
    setup_s = time.perf_counter() - t0

    wall = _execute(sim, n_steps * dt)
    out: dict[str, Any] = _states(state_log)
    del out["position"], out["velocity"]
    out["wheel_speed"] = np.array(speed_log.wheelSpeeds, dtype=np.float64)[:, :1]
    out.update(_conserved(conserved_log))
    out.update(wall_s=wall, setup_s=setup_s, steps=n_steps, u=u, js=js, iz=hub_inertia[2, 2] + js)
    return out


def spin_up_closed_form(
    t: ArrayLike, u: float = 0.1, js: float = 0.5, iz: float = 15.5
) -> dict[str, Array]:
    """Closed form of :func:`spin_up`: ω (n, 3), Ω (n,), quaternion (n, 4) at times ``t``.

    With I_z the z moment of hub + wheel about the centre of mass and Js the wheel's spin
    inertia: ω_z = −u t/(I_z − Js), Ω = u t/Js + u t/(I_z − Js), ω_x = ω_y = 0, attitude a
    rotation about z by −u t²/(2 (I_z − Js)).
    """
    tt = np.asarray(t, dtype=np.float64)
    k = u / (iz - js)
    omega = np.zeros((tt.size, 3))
    omega[:, 2] = -k * tt
    angle = -0.5 * k * tt**2
    quat = np.zeros((tt.size, 4))
    quat[:, 0] = np.cos(angle / 2)
    quat[:, 3] = np.sin(angle / 2)
    return {"omega": omega, "wheel_speed": u * tt / js + k * tt, "quaternion": quat}


def check_quaternion_convention(spin_rate: float = 0.1, duration: float = 1.0) -> float:
    """Spin a bare hub about body z at ``spin_rate`` [rad/s]; return max |q − q_expected|.

    A body spinning about +z at rate ω for time t is rotated about +z by ω t from N,
    so the body → inertial quaternion must be (cos ωt/2, 0, 0, sin ωt/2); also checks
    that ``quaternion_to_matrix(q)`` equals ``MRP2C(sigma_BN)ᵀ``.
    """
    from Basilisk.utilities import RigidBodyKinematics

    sim, _ = _new_sim(0.01, _nanos(0.01))
    sc = _make_spacecraft(
        sim, 1.0, np.zeros(3), np.diag([1.0, 2.0, 3.0]), np.array([0.0, 0.0, spin_rate])
    )
    log = sc.scStateOutMsg.recorder()
    sim.AddModelToTask(_LOG_TASK, log)
    sim.InitializeSimulation()
    _execute(sim, duration)
    st = _states(log)
    half = 0.5 * spin_rate * st["t"]
    expected = np.column_stack([np.cos(half), 0 * half, 0 * half, np.sin(half)])
    err = float(np.abs(st["quaternion"] - expected).max())
    sigma = np.array(log.sigma_BN)[-1]
    dcm_bn = np.array(RigidBodyKinematics.MRP2C(sigma))
    err_dcm = float(np.abs(quaternion_to_matrix(st["quaternion"][-1]) - dcm_bn.T).max())
    return max(err, err_dcm)


# --- self-test ---------------------------------------------------------------------------


def _rel(a: Array, b: Array) -> float:
    """|a − b| / |b|."""
    return float(np.linalg.norm(np.asarray(a) - np.asarray(b)) / np.linalg.norm(b))


def _quat_angle(q: Array, r: Array) -> Array:
    """Rotation angle [rad] of r* ⊗ q for unit quaternions (rows), sign-insensitive.

    Uses atan2 of the vector and scalar parts (arccos of the dot product loses half the
    digits near zero: its floor is ~4e-8 rad).
    """
    q, r = np.atleast_2d(q), np.atleast_2d(r)
    w = np.einsum("ij,ij->i", q, r)
    v = r[:, :1] * q[:, 1:] - q[:, :1] * r[:, 1:] - np.cross(r[:, 1:], q[:, 1:])
    angle: Array = 2.0 * np.arctan2(np.linalg.norm(v, axis=1), np.abs(w))
    return angle


def _timing(res: dict[str, Any]) -> str:
    """Wall time, per-step wall time and setup time of one run."""
    per_step = 1e6 * res["wall_s"] / res["steps"]
    return f"{res['wall_s']:8.4f} {per_step:8.2f} {res['setup_s']:7.3f}"


def _print_wheels(res: dict[str, Any], label: str) -> None:
    """One row of conservation errors and timings for :func:`reaction_wheels`."""
    h, e, t = res["angular_momentum"], res["energy"], res["t"]
    i_off = int(np.searchsorted(t, res["torque_off"] - 1e-12))
    axial = res["js"] * (res["wheel_speed"] + res["omega"])
    impulse = np.abs(axial[-1] - axial[0] - res["motor_torque"] * res["torque_off"]).max()
    d_norm = abs(np.linalg.norm(h[-1]) / np.linalg.norm(h[0]) - 1)
    d_max = max(_rel(x, h[0]) for x in h)
    print(
        f"  {label:<27}{d_norm:9.1e}{_rel(h[-1], h[0]):9.1e}{d_max:9.1e}"
        f"{abs(e[-1] / e[i_off] - 1):9.1e}{e[-1] - e[i_off]:10.1e}{impulse:9.1e}  {_timing(res)}"
    )


def _libration_integral(g: dict[str, Any]) -> Array:
    """Planar pitch-libration integral ½ I_z θ̇² + (3/2) n² (I_y − I_x) sin²θ [J].

    θ is the angle of body x from the radial direction about the orbit normal z; it is
    conserved while the orbit stays circular and the motion planar.
    """
    inertia, n = g["inertia"], g["n"]
    r, v = g["position"], g["velocity"]
    orbit_rate = np.cross(r, v)[:, 2] / np.einsum("ij,ij->i", r, r)
    yaw = 2 * np.arctan2(g["quaternion"][:, 3], g["quaternion"][:, 0])
    theta = yaw - np.arctan2(r[:, 1], r[:, 0])
    theta_dot = g["omega"][:, 2] - orbit_rate
    integral: Array = (
        0.5 * inertia[2, 2] * theta_dot**2
        + 1.5 * n**2 * (inertia[1, 1] - inertia[0, 0]) * np.sin(theta) ** 2
    )
    return integral


def _main() -> None:
    """Self-test: conventions, conservation, closed form, timings."""
    err = check_quaternion_convention()
    print(f"quaternion convention (steady spin about +z, and MRP2C(σ)ᵀ): max error {err:.1e}")

    print("\nreaction_wheels: 20 s, torque on [0, 0.5 s]. Relative changes start → end of |H|")
    print("and of the vector H (totRotAngMomPntC_N), largest over the run of |H(t) − H(0)|/|H(0)|,")
    print("relative and absolute change of totRotEnergy from 0.5 s to the end, and the wheel")
    print("impulse error max_i |Δ[Js(Ω_i + ω_i)] − u_i·0.5 s| (0 iff torque on [0, 0.5]).")
    print(
        f"  {'run':<27}{'d|H|':>9}{'dH':>9}{'max dH':>9}{'dE/E':>9}{'dE [J]':>10}"
        f"{'impulse':>9}  {'wall [s]':>8} {'µs/step':>8} {'setup':>7}"
    )
    runs: dict[str, dict[str, Any]] = {}
    wheel_runs: list[tuple[str, float, float | None, float | None, WheelModel]] = [
        ("rk4", 0.1, None, None, "balanced"),
        ("rk4", 0.01, None, None, "balanced"),
        ("rk4", 0.001, None, None, "balanced"),
        ("rk4", 0.001, None, 1.0, "balanced"),
        ("rk4", 0.001, None, None, "fully_coupled"),
        ("rkf45", 0.1, 1e-10, None, "balanced"),
        ("rkf78", 0.1, 1e-12, None, "balanced"),
    ]
    for integ, dt, tol, rec, model in wheel_runs:
        label = f"{integ} dt={dt:g}" + (f" tol={tol:g}" if tol else "")
        label += (f" rec={rec:g}" if rec else "") + (" f.coupled" if model != "balanced" else "")
        runs[label] = res = reaction_wheels(
            dt, record_dt=rec, integrator=integ, tolerance=tol, wheel_model=model, conserved=True
        )
        _print_wheels(res, label)
    a, b = runs["rk4 dt=0.001"], runs["rk4 dt=0.001 f.coupled"]
    print(
        "  balanced wheels folded into the hub vs JitterFullyCoupled (zero imbalance) on the bare"
        f" hub, dt=0.001:\n    max|Δω| {np.abs(a['omega'] - b['omega']).max():.1e} rad/s,"
        f" max|ΔΩ| {np.abs(a['wheel_speed'] - b['wheel_speed']).max():.1e} rad/s,"
        f" max angle {_quat_angle(a['quaternion'], b['quaternion']).max():.1e} rad,"
        f" max|ΔH| {np.abs(a['angular_momentum'] - b['angular_momentum']).max():.1e} N·m·s,"
        f" max|ΔE| {np.abs(a['energy'] - b['energy']).max():.1e} J"
    )
    ref = runs["rkf78 dt=0.1 tol=1e-12"]
    for label in ("rk4 dt=0.1", "rk4 dt=0.01", "rk4 dt=0.001"):
        r = runs[label]
        idx = np.searchsorted(r["t"], ref["t"] - 1e-9)
        print(
            f"  {label} vs rkf78 tol=1e-12 at common times: max|Δω| "
            f"{np.abs(r['omega'][idx] - ref['omega']).max():.1e} rad/s, max angle "
            f"{_quat_angle(r['quaternion'][idx], ref['quaternion']).max():.1e} rad"
        )

    print("\ngravity_gradient: 3 orbits (rounded to whole steps). Relative change of the orbital")
    print("angular momentum |r × v| and of the pitch-libration integral, start → end (the")
    print("rotational H is not conserved: the gravity-gradient torque is external to it).")
    print(
        f"  {'run':<23}{'t_end':>9}{'d|h_orb|':>10}{'dJ':>9}{'max dJ':>9}{'pitch range [deg]':>20}"
        f"{'|r|-r0 [m]':>11}  {'wall [s]':>8} {'µs/step':>8} {'setup':>7}"
    )
    for integ, dt, tol in (("rk4", 10.0, None), ("rk4", 1.0, None), ("rkf78", 10.0, 1e-12)):
        g = gravity_gradient(dt, integrator=integ, tolerance=tol)
        h = np.linalg.norm(np.cross(g["position"], g["velocity"]), axis=1)
        jac = _libration_integral(g)
        pitch = np.degrees(
            2 * np.arctan2(g["quaternion"][:, 3], g["quaternion"][:, 0])
            - np.arctan2(g["position"][:, 1], g["position"][:, 0])
        )
        pitch = (pitch + 180.0) % 360.0 - 180.0
        r_dev = np.abs(np.linalg.norm(g["position"], axis=1) - 7000e3).max()
        label = f"{integ} dt={dt:g}" + (f" tol={tol:g}" if tol else "")
        print(
            f"  {label:<23}{g['t'][-1]:9.0f}{abs(h[-1] / h[0] - 1):10.1e}"
            f"{abs(jac[-1] / jac[0] - 1):9.1e}{np.abs(jac / jac[0] - 1).max():9.1e}"
            f"{pitch.min():+10.4f}{pitch.max():+10.4f}{r_dev:11.1e}  {_timing(g)}"
        )
    print(f"  n = {g['n']:.9e} rad/s; ω_x, ω_y stay {np.abs(g['omega'][:, :2]).max():.0e}")

    print("\nspin_up: 10 s, u = 0.1 N·m, I_z = 15.5, Js = 0.5; largest errors against the closed")
    print("form, and largest |H| (totRotAngMomPntC_N; zero by the physics).")
    print(
        f"  {'run':<27}{'|Δω| [rad/s]':>13}{'|ΔΩ| [rad/s]':>13}{'angle [rad]':>12}"
        f"{'|H| [N·m·s]':>12}  {'wall [s]':>8} {'µs/step':>8} {'setup':>7}"
    )
    spin_runs: list[tuple[str, float, float | None, WheelModel]] = [
        ("rk4", 0.1, None, "balanced"),
        ("rk4", 0.01, None, "balanced"),
        ("rk4", 0.01, None, "fully_coupled"),
        ("rkf78", 0.1, 1e-12, "balanced"),
    ]
    for integ, dt, tol, model in spin_runs:
        sp = spin_up(dt, integrator=integ, tolerance=tol, wheel_model=model, conserved=True)
        cf = spin_up_closed_form(sp["t"], sp["u"], sp["js"], sp["iz"])
        label = f"{integ} dt={dt:g}" + (f" tol={tol:g}" if tol else "")
        label += " f.coupled" if model != "balanced" else ""
        print(
            f"  {label:<27}{np.abs(sp['omega'] - cf['omega']).max():13.1e}"
            f"{np.abs(sp['wheel_speed'][:, 0] - cf['wheel_speed']).max():13.1e}"
            f"{_quat_angle(sp['quaternion'], cf['quaternion']).max():12.1e}"
            f"{np.linalg.norm(sp['angular_momentum'], axis=1).max():12.1e}  {_timing(sp)}"
        )


if __name__ == "__main__":
    _main()
