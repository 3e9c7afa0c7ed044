"""Simulation of a rigid body's rotation: :func:`simulate`.

The body turns freely about its centre of mass, or about a ``pivot`` (a body
point held fixed in space) under ``gravity``, with optional torque models from
:mod:`tumble.torques` and parts inside it (:mod:`tumble.parts`: rotors,
dampers). The body model (:class:`tumble.body.RigidBody`) gives the principal
frame the kernels work in; the torque is bound to the body
(:func:`tumble.torques.bind`); the integrator comes from the registry
(:mod:`tumble.integrators`), which also decides ``method="auto"``; results are
reported in the user's body axes as a :class:`~tumble.trajectory.Trajectory`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.body import RigidBody, body_model
from tumble.errors import InputError, RequestTooLargeError
from tumble.integrators import INTEGRATORS, Integrator, auto_choice, get_integrator
from tumble.integrators.limits import (
    check_internal_stability,
    check_record_every,
    check_recording,
)
from tumble.integrators.problem import Problem, Samples, Schedule
from tumble.integrators.steps import (
    MAX_STEPS,
    Progress,
    time_step,
    too_coarse,
    warn_if_coarse,
)
from tumble.kinematics import as_attitude
from tumble.massprops import MassProperties, as_mass_properties, readonly
from tumble.parts import InternalPart, check_parts, value_columns
from tumble.recent import UNKEYED, RecentCache, plain_key
from tumble.resources import DEFAULT_MAX_STEPS, SMALL_REQUEST, budget_is_set
from tumble.torques import TORQUES, BoundTorque, TorqueModel, bind
from tumble.trajectory import Trajectory
from tumble.units import to_si, vector_to_si

Array = NDArray[np.float64]

__all__ = ["SETUP_CACHE_SIZE", "PlannedRun", "Setup", "prepare", "simulate"]


def simulate(
    mp: MassProperties,
    omega0: Any,
    *,
    attitude0: Any = None,
    duration: Any,
    dt: Any = None,
    pivot: Any = None,
    gravity: Any = None,
    torque: TorqueModel | None = None,
    method: str = "auto",
    record_every: int = 1,
    progress: Callable[[int, int], object] | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    internal: Any = None,
    max_steps: int | None = DEFAULT_MAX_STEPS,
) -> Trajectory:
    """Simulate the rotation of a rigid body under Euler's equations.

    Parameters
    ----------
    mp : the body's mass properties.
    omega0 : (3,) initial angular velocity in body coordinates, rad/s (or quantities).
    attitude0 : initial attitude, a unit quaternion ``[w, x, y, z]`` rotating
        body coordinates into space coordinates (normalised here), or a scipy
        ``Rotation``; default the identity.
    duration : simulated time, s, > 0.
    dt : integration step (rk4, strang, splitting) or sampling interval (exact,
        adaptive), s, > 0. Default: 1/200 of a turn of the fastest rotation (see
        ``DEFAULT_STEPS_PER_TURN``). It is shortened slightly so a whole number
        of steps spans ``duration``.
    pivot : None for a free body (rotation about the centre of mass), or a body
        point (3,), m, held fixed in space; then the dynamics use the inertia
        about the pivot and gravity acts at the centre of mass.
    gravity : (3,) gravitational acceleration in space coordinates, m/s², e.g.
        ``[0, 0, -9.81]``. Required with a pivot (pass zeros to mean none); on a
        free body it exerts no torque about the centre of mass.
    torque : a torque model from :mod:`tumble.torques`, or a sum of them.
    method : a name from the integrator registry (:data:`tumble.integrators.INTEGRATORS`):

        * ``"exact"``: torque-free bodies (free, or on a pivot without gravity):
          the closed-form solution, sampled every ``dt``; no stepping error.
          With parts: rotors without motors on one principal axis of the
          platform (:func:`tumble.theory.motions.gyrostat_solution`). Under
          gravity: a symmetric top on a pivot (two equal moments about the
          pivot, the pivot and the centre of mass on the symmetry axis), for
          any ω0 and attitude (:func:`tumble.theory.motions.lagrange_top`).
        * ``"splitting"``: fourth-order symplectic splitting (Yoshida's
          composition of ``"strang"``): exact rotations of the free motion
          composed with torque kicks (:mod:`tumble.core.splitting`); |L| kept
          to round-off when torque-free, bounded energy error under gravity;
          exact free motion for a symmetric body.
        * ``"strang"``: the same splitting at second order.
        * ``"rk4"``: classical Runge–Kutta, fixed step, quaternion renormalised.
        * ``"adaptive"``: Dormand–Prince 5(4) with step-size control to
          ``rtol``/``atol`` and dense output at every ``dt``.
        * ``"auto"``: exact when torque-free or for a symmetric top under
          gravity, splitting when the torque is otherwise conservative
          (gravity about a pivot), adaptive otherwise.

        ``Trajectory.reason`` says which ran and why.
    record_every : keep every k-th step (the final state is always kept).
    progress : None or a callable ``progress(done, total)`` (steps, or samples
        for the adaptive method).
    rtol, atol : tolerances of the adaptive method: each step's local error in
        each component of the state (ω in rad/s, or the momenta of a body carrying
        parts in kg·m²/s, and the quaternion) is kept below ``atol + rtol ·
        |value|`` (root-mean-square over the components).
    internal : the parts the body carries (:class:`tumble.Rotor`,
        :class:`tumble.KaneDamper`), in order; ``mp`` holds each of them as if
        locked to the body (its mass and all its inertia). The trajectory's
        angular momentum and energy include theirs, ``rotor_speed`` gives the
        rotors' relative spin rates. Methods: ``rk4`` and ``adaptive`` for any
        parts, the splittings for rotors; ``"auto"`` picks the splitting for
        rotors without torques that act from outside or depend on ω, else the
        adaptive method.
    max_steps : the most steps the run may take (default 5e7,
        :data:`tumble.resources.DEFAULT_MAX_STEPS`; None: up to 2^53): a
        fixed-step run that needs more is refused before it starts; an
        adaptive run (whose steps follow the motion: on a stiff problem, its
        fastest time scale) stops when it has tried that many. The closed
        forms take none.

    Returns
    -------
    Trajectory

    Raises
    ------
    InputError
        Bad values (see the messages), a body with a zero principal moment, an
        unknown method.
    IntegrationError
        The state became NaN or infinite; the message names the step and time.
    RequestTooLargeError
        Before any work, when the recorded samples would not fit in the memory
        budget (half of the machine's memory; :mod:`tumble.resources`), or the
        run would take more than 2^53 steps or ``max_steps``; during an
        adaptive run, when it has tried ``max_steps`` steps.

    Warns
    -----
    CoarseStepWarning
        When ``dt`` gives fewer than ``MIN_STEPS_PER_TURN`` steps per turn of
        the fastest rotation.

    Notes
    -----
    A call that describes a motion set up before (the same mass properties and
    parts, the same values of the other arguments, no ``torque`` model) reuses
    that setup (``tumble.simulation.prepare`` keeps the last ``SETUP_CACHE_SIZE``).
    A call that asks for a run made before (its setup kept, and the same
    duration, steps and tolerances, given as plain numbers or strings) reuses
    the run checked and made ready, when its samples take at most 1 MiB: a
    short run repeated costs little more than its steps. It still warns of a
    coarse step and is held to a memory budget set since.

    Examples
    --------
    The tennis-racket flip: spun near its intermediate axis, a free body
    turns over (ω along that axis changes sign) while its angular momentum
    stays fixed in space.

    >>> import numpy as np
    >>> import tumble as tb
    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> traj = tb.simulate(body, [0.1, 1.0, 0.1], duration=30.0)
    >>> traj.method
    'exact'
    >>> print(f"ω_y from {traj.omega[0, 1]:.2f} down to {traj.omega[:, 1].min():.2f} rad/s")
    ω_y from 1.00 down to -1.00 rad/s
    >>> np.allclose(traj.angular_momentum, traj.angular_momentum[0])
    True

    A physical pendulum: a 2 kg ball of radius 10 cm hanging 20 cm below a
    pivot swings at ``√(m g d / I_pivot)`` for small amplitudes:

    >>> from scipy.spatial.transform import Rotation
    >>> ball = tb.shapes.solid_sphere(2.0, 0.1)
    >>> swing = tb.simulate(
    ...     ball, [0, 0, 0], attitude0=Rotation.from_rotvec([0.02, 0, 0]),
    ...     pivot=[0, 0, 0.2], gravity=[0, 0, -9.81], duration=3.0, dt=0.005,
    ... )
    >>> rate = tb.analysis.oscillation_frequency(swing.t, swing.omega[:, 0])
    >>> print(f"{rate:.2f} rad/s, theory {np.sqrt(2 * 9.81 * 0.2 / (0.008 + 2 * 0.2**2)):.2f}")
    6.68 rad/s, theory 6.68
    """
    arguments = (duration, dt, record_every, rtol, atol, max_steps)
    motion = (mp, omega0, attitude0, pivot, gravity, torque, method, internal)
    key, held = _motion_key(motion, arguments)
    run = None if key is None else _RUNS.get(key, held)
    # A method asked for by name: the one registered under it now.
    if run is not None and (method == "auto" or INTEGRATORS.get(method) is run.setup.integrator):
        if progress is not None:
            _check_run_options(rtol, atol, progress)
        if budget_is_set():  # small requests are checked against a budget set since
            check_recording(*run.recording)
    else:
        record_every = check_record_every(record_every)
        # A run's key begins with its setup's: a run keyed finds both at once.
        setup_key = _motion_key(motion) if key is None else (key[: -len(arguments)], held)
        setup = _prepared(setup_key, motion)
        total_time = _duration(duration)
        _check_run_options(rtol, atol, progress)
        run = setup.plan(total_time, dt, record_every, rtol=rtol, atol=atol, max_steps=max_steps)
        if key is not None and run.needed <= SMALL_REQUEST:
            _RUNS.put(key, held, run)
    if run.coarse is not None:
        # The warning names the line that called simulate: three frames up.
        warn_if_coarse(*run.coarse, stacklevel=3)
    setup, schedule = run.setup, run.schedule
    samples = run.steps(progress)
    reason = setup.reason
    if setup.integrator.kind == "adaptive" and method == "auto":
        reason += f" (rtol {rtol:g}, atol {atol:g})"
    return _trajectory(mp, pivot, setup, schedule, samples, reason)


def _duration(duration: Any) -> float:
    """``duration`` in s, > 0."""
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    return total_time


def _check_run_options(rtol: Any, atol: Any, progress: Any) -> None:
    """Refuse tolerances that are not positive numbers (checked whatever the
    method, though only the adaptive one reads them: a value that cannot be
    right is refused, not ignored), and a ``progress`` that is not callable."""
    for name, value in (("rtol", rtol), ("atol", atol)):
        if isinstance(value, bool) or not (
            isinstance(value, float | int) and math.isfinite(value) and value > 0
        ):
            raise InputError(f"Expected `{name}` > 0, got {value!r}.")
    if rtol < 1e-15:
        raise InputError(f"Expected `rtol` >= 1e-15 (round-off), got {rtol!r}.")
    if progress is not None and not callable(progress):
        raise InputError(
            f"Expected `progress` to be None or a function (done, total), got {progress!r}."
        )


def most_steps(max_steps: Any) -> float:
    """``max_steps`` (an integer >= 1, or None: 2^53) as the float the kernels read.

    Raises
    ------
    InputError
        A ``max_steps`` that is not an integer >= 1 or None.
    """
    if max_steps is None:
        return float(MAX_STEPS)
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
        raise InputError(f"Expected `max_steps` to be an integer >= 1 or None, got {max_steps!r}.")
    return float(max_steps)


def _trajectory(
    mp: MassProperties, pivot: Any, setup: Setup, schedule: Schedule, samples: Samples, reason: str
) -> Trajectory:
    """The :class:`~tumble.trajectory.Trajectory` of a run: its samples (body axes)
    with the body, the integrator and why, and what the motion conserves."""
    body = setup.body
    return Trajectory.of_fields(
        # A copy: the schedule is kept for the next call of the same motion.
        t=schedule.times.copy(),
        omega=samples.omega,
        quaternion=samples.quaternion,
        mass_properties=mp,
        # A copy: the model, shared by the calls for this body, keeps its own read-only.
        pivot=None if pivot is None else np.array(body.reference_point),
        method=setup.integrator.name,
        reason=reason,
        dt=schedule.step,
        steps=samples.steps,
        conserved=setup.conserved,
        torque=setup.model,
        internal=body.parts,
        internal_values=samples.values,
        invariant_values={},
        potential=None,
    )


@dataclass(frozen=True, eq=False)
class Setup:
    """What :func:`simulate` integrates and how, before any step: the body model,
    the torque bound to it, the integrator and why, the initial state (body axes,
    read-only), the total uniform gravity (m/s², space axes) and the torque model
    as given (``gravity`` included), which the trajectory keeps for its energy.

    :func:`prepare` keeps the last :data:`SETUP_CACHE_SIZE` for calls that
    describe the same motion again: a setup is never changed once made."""

    body: RigidBody
    torque: BoundTorque
    integrator: Integrator
    reason: str
    omega0: Array
    attitude0: Array
    gravity: Array
    model: TorqueModel | None = None

    @cached_property
    def weight(self) -> float:
        """The body's weight under :attr:`gravity`, N (0 without gravity)."""
        return self.body.mass_properties.mass * math.hypot(*self.gravity.tolist())

    @cached_property
    def problem(self) -> Problem:
        """What the integrator's driver takes: the body, its bound torque, the initial state."""
        return Problem(self.body, self.torque, self.omega0, self.attitude0)

    @cached_property
    def conserved(self) -> tuple[str, ...]:
        """What the motion conserves (:meth:`RigidBody.conserved`)."""
        return self.body.conserved(self.torque.terms)

    def fastest_rate(self) -> float:
        """The fastest rate a step must resolve, rad/s (:meth:`RigidBody.fastest_rate`)."""
        return self.body.fastest_rate(
            self.omega0, self.weight, exact_spin=self.integrator.exact_symmetric_spin
        )

    def step_size(self, dt: Any, duration: float) -> float:
        """The step :func:`simulate` takes (s) for ``dt`` (None: the default,
        1/``DEFAULT_STEPS_PER_TURN`` of a turn of the fastest rotation)."""
        return time_step(dt, self.fastest_rate(), duration)

    def plan(
        self,
        duration: float,
        dt: Any,
        record_every: int,
        *,
        rtol: float,
        atol: float,
        max_steps: int | None,
    ) -> PlannedRun:
        """A run of ``duration`` s (arguments as :func:`simulate`'s, ``duration`` and
        ``record_every`` checked), checked before any work: the samples within the
        memory budget, the steps within ``max_steps``, a fixed step within the
        stability of the parts' own motion; and what a ``dt`` given too coarse
        for the fastest rotation (or, for the splittings around the exact free
        motion, for the pendulum swing) warns of.

        Raises
        ------
        InputError
            A ``dt`` that is not a positive time, a ``max_steps`` that is not an
            integer >= 1 or None.
        RequestTooLargeError, IntegrationError
            As :func:`simulate`.
        """
        integrator, body = self.integrator, self.body
        fastest = self.fastest_rate()
        step = time_step(dt, fastest, duration)
        internal, names = body.internal_rate()
        if dt is None and integrator.kind == "stepping" and internal > 0:
            # The default step resolves the parts' own motion too: one step per 1/rate,
            # well within the stability interval (2.78 for RK4).
            step = min(step, 1.0 / internal)
        recording = (duration, step, record_every, len(value_columns(body.parts)))
        needed = check_recording(*recording)
        most = most_steps(max_steps)
        schedule = Schedule.build(
            duration, step, record_every, rtol=rtol, atol=atol, most_steps=most
        )
        if integrator.kind == "stepping" and schedule.n_steps > most:
            raise RequestTooLargeError(
                f"Expected at most max_steps = {most:.6g} steps, got duration / dt = "
                f"{duration:.6g} s / {schedule.step:.3g} s = {schedule.n_steps} steps: use a "
                "larger dt or a shorter duration, or raise `max_steps=`."
            )
        check_internal_stability(internal, names, integrator.kind, schedule.step, duration, most)
        coarse = None
        if dt is not None and integrator.kind == "stepping":
            if integrator.exact_free_motion:  # only the torque needs resolving
                rate, what = body.pendulum_rate(self.weight), "the pendulum swing"
            else:
                rate, what = fastest, "the fastest rotation"
            if too_coarse(schedule.step, rate):
                coarse = (schedule.step, rate, what)
        return PlannedRun(self, schedule, coarse, recording, needed)


@dataclass(frozen=True, eq=False)
class PlannedRun:
    """A run of a :class:`Setup`, checked before any step (:meth:`Setup.plan`): its
    schedule; what its step, given too coarse, warns of (the step, s, the rate it
    must resolve, rad/s, and what turns at that rate; None when it does not warn);
    the arguments of its memory check
    (:func:`tumble.integrators.limits.check_recording`) and the memory its
    samples take, bytes. :func:`simulate` keeps the last
    :data:`SETUP_CACHE_SIZE` small ones for calls that ask for them again."""

    setup: Setup
    schedule: Schedule
    coarse: tuple[float, float, str] | None
    recording: tuple[float, float, int, int]
    needed: float

    @cached_property
    def steps(self) -> Callable[[Progress], Samples]:
        """``steps(progress) -> Samples``: the integrator's driver made ready for
        this run (:meth:`tumble.integrators.Integrator.ready_run`), from the
        initial state at each call."""
        return self.setup.integrator.ready_run(self.setup.problem, self.schedule)


def prepare(
    mp: MassProperties,
    omega0: Any,
    *,
    attitude0: Any = None,
    pivot: Any = None,
    gravity: Any = None,
    torque: TorqueModel | None = None,
    method: str = "auto",
    internal: Any = None,
) -> Setup:
    """Validate :func:`simulate`'s description of a motion and choose its
    integrator (arguments as there), without integrating: what a caller needs
    to know beforehand, such as whether ``dt`` will be a step or a sampling
    interval (``prepare(...).integrator.kind``).

    Raises
    ------
    InputError
        As :func:`simulate`.
    """
    motion = (mp, omega0, attitude0, pivot, gravity, torque, method, internal)
    return _prepared(_motion_key(motion), motion)


def _prepared(setup_key: tuple[Any, tuple[Any, ...]], motion: tuple[Any, ...]) -> Setup:
    """:func:`prepare` of ``motion`` (its arguments in order), whose key and held
    objects are ``setup_key`` (:func:`_motion_key`'s)."""
    mp, omega0, attitude0, pivot, gravity, torque, method, internal = motion
    key, held = setup_key
    if key is not None:
        kept = _SETUPS.get(key, held)
        # A method asked for by name: the one registered under it now.
        if kept is not None and (method == "auto" or INTEGRATORS.get(method) is kept.integrator):
            return kept
    mp = as_mass_properties(mp)
    if torque is not None and not isinstance(torque, TorqueModel):
        raise InputError(
            f"Expected `torque` to be a model from tumble.torques, got {type(torque).__name__}."
        )
    chosen = None if method == "auto" else get_integrator(method)
    # Copies, read-only: the setup is kept, and omega0 may be the caller's own array.
    omega = readonly(vector_to_si(omega0, "angular_velocity", "omega0"))
    q0 = readonly(as_attitude(attitude0))
    model, gravities = _torque_model(torque, gravity)
    if pivot is not None and gravity is None and not gravities:
        raise InputError(
            "Expected `gravity` with `pivot`, got none (a pivot without gravity is a free "
            "rotation about that point: pass gravity=[0, 0, 0] to mean it)."
        )
    parts = check_parts(internal)
    body = body_model(mp, None if pivot is None else vector_to_si(pivot, "length", "pivot"), parts)
    body.check_simulable()
    bound = bind(model, body, omega)
    chosen, reason = _integrator_for(chosen, body, bound)
    total = readonly(sum(gravities, np.zeros(3)))
    setup = Setup(body, bound, chosen, reason, omega, q0, total, model)
    if key is not None:
        _SETUPS.put(key, held, setup)
    return setup


#: The types of the values that name a run besides its setup (:func:`_motion_key`):
#: the duration, dt, rtol and atol; and max_steps.
_PLAIN = frozenset({float, int, str, type(None)})
_STEP_COUNTS = frozenset({int, type(None)})

#: How many setups :func:`prepare` keeps for calls that describe the same motion
#: again, and how many runs :func:`simulate` keeps for calls that ask for the same
#: run again: the most recently made.
SETUP_CACHE_SIZE = 64

_SETUPS: RecentCache[Setup] = RecentCache(SETUP_CACHE_SIZE)
_RUNS: RecentCache[PlannedRun] = RecentCache(SETUP_CACHE_SIZE)


def _motion_key(
    motion: tuple[Any, ...], arguments: tuple[Any, ...] = ()
) -> tuple[Any, tuple[Any, ...]]:
    """The key of :func:`prepare`'s arguments ``motion`` (in order) and the objects
    its entry holds, or (None, ()) for a motion whose setup is not kept: one under a
    torque model, or given by anything but mass properties, parts and plain values
    (:func:`tumble.recent.plain_key`). Mass properties and parts are immutable;
    their identities name them, with the values of ``mp`` (as
    :func:`tumble.body.body_model`'s key). What the registries give is held as
    well: the model of ``gravity``, and for ``method="auto"`` every integrator, so
    that one registered since makes a new setup (a method asked for by name is
    looked up again, :func:`prepare`).

    With :func:`simulate`'s ``arguments`` (duration, dt, record_every, rtol, atol,
    max_steps), the key of a run, which begins with its setup's; (None, ()) also
    where they are not plain values. They name it as the checks read them: 1 is
    1.0 (none of them may be -0.0), but ``record_every`` is an int and
    ``max_steps`` an int or None."""
    # One function and one flat tuple, made and compared in as few steps as may
    # be: a short run repeated spends a good part of its time here.
    mp, omega0, attitude0, pivot, gravity, torque, method, internal = motion
    parts = () if internal is None else internal
    if (
        type(mp) is not MassProperties
        or torque is not None
        or type(method) is not str
        or (type(parts) is not list and type(parts) is not tuple)
    ):
        return None, ()
    if arguments:
        duration, dt, record_every, rtol, atol, max_steps = arguments
        if (
            type(record_every) is not int
            or type(max_steps) not in _STEP_COUNTS
            or type(duration) not in _PLAIN
            or type(dt) not in _PLAIN
            or type(rtol) not in _PLAIN
            or type(atol) not in _PLAIN
        ):
            return None, ()
    for part in parts:
        if not isinstance(part, InternalPart):
            return None, ()
    key = (
        id(mp),
        mp.mass,
        mp.center_of_mass.tobytes(),
        mp.inertia.tobytes(),
        method,
        plain_key(omega0),
        None if attitude0 is None else plain_key(attitude0),
        None if pivot is None else plain_key(pivot),
        None if gravity is None else plain_key(gravity),
        len(parts),
        *map(id, parts),
        *arguments,
    )
    if UNKEYED in key[5:9]:
        return None, ()
    held = (mp, *parts) if gravity is None else (mp, *parts, TORQUES.get("gravity"))
    return key, (*held, *INTEGRATORS.values()) if method == "auto" else held


def _torque_model(
    torque: TorqueModel | None, gravity: Any
) -> tuple[TorqueModel | None, list[Array]]:
    """The torque model a run is under, the ``gravity`` keyword as the registry's
    uniform gravity (m/s², space axes) added to ``torque``, and the uniform
    gravities its terms declare."""
    model = torque
    if gravity is not None:
        field = vector_to_si(gravity, "acceleration", "gravity")
        weight_field = TORQUES["gravity"](field)  # type: ignore[call-arg]
        model = weight_field if torque is None else weight_field + torque
    terms = () if model is None else model.terms
    return model, [g for g in (term.uniform_gravity() for term in terms) if g is not None]


def _integrator_for(
    chosen: Integrator | None, body: RigidBody, bound: BoundTorque
) -> tuple[Integrator, str]:
    """The integrator that runs this body under this torque, and why: the one
    asked for (None: ``"auto"``'s choice), refused with the methods that would
    integrate it when it does not."""
    if chosen is None:
        chosen, reason = auto_choice(bound, body)
    else:
        reason = "requested"
        why = chosen.refuses(body, bound)
        if why is not None:
            parts = body.parts
            kinds = sorted({part.kind for part in parts})
            able = [n for n, entry in INTEGRATORS.items() if entry.refuses(body, bound) is None]
            what = f"a body carrying {', '.join(kinds)} parts" if parts else "this motion"
            raise InputError(
                f"Expected a method that integrates {what} ({', '.join(['auto', *able])}), "
                f"got {chosen.name!r}: {why}."
            )
    if chosen.kicks and "omega" in bound.depends_on:
        reason += (
            f" (its kicks hold the torque, which depends on ω here: {chosen.name} is first "
            "order in it)"
        )
    return chosen, reason
