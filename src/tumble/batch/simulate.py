"""Many free bodies at once: :func:`simulate_batch`, validated and run on the
batch driver (:mod:`tumble.batch.driver`), or by the kernels of bodies carrying
parts (:mod:`tumble.batch.parts`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.batch.driver import Batch, step_batch
from tumble.batch.memory import check_batch_memory
from tumble.batch.parts import PartsBatch
from tumble.batch.result import BatchResult, Progress
from tumble.body import ZERO_MOMENT, BodyBatch
from tumble.errors import InputError
from tumble.integrators import Integrator, get_integrator
from tumble.integrators.limits import check_internal_stability, check_record_every
from tumble.integrators.steps import whole_steps
from tumble.massprops import PHYSICAL_TOLERANCE, check_symmetric
from tumble.parts import check_parts, internal_rate, value_columns
from tumble.torques import TORQUES, BoundTorque, TorqueModel, bind
from tumble.units import to_si, vector_to_si

__all__ = ["simulate_batch"]

Array = NDArray[np.float64]


def simulate_batch(
    inertia: Any,
    omega0: Any,
    *,
    attitude0: Any = None,
    duration: Any,
    dt: Any,
    method: str = "rk4",
    torque: TorqueModel | None = None,
    record_every: int | None = None,
    progress: Progress = None,
    internal: Any = None,
    rotor_speed: Any = None,
) -> BatchResult:
    """Simulate N free bodies at once, in parallel.

    Parameters
    ----------
    inertia : (N, 3) principal moments (the body axes are principal axes) or
        (N, 3, 3) inertia tensors about the centres of mass, kg·m², symmetric
        as :class:`tumble.MassProperties` requires.
    omega0 : (N, 3) initial angular velocities in body coordinates, rad/s.
    attitude0 : None (identity) or (N, 4) quaternions ``[w, x, y, z]``, body → space.
    duration, dt : s, > 0; dt is shortened slightly so whole steps span duration.
    method : an integrator of the registry with batch kernels
        (:func:`tumble.integrators.batch_integrators`): ``"rk4"`` (vectorised
        across bodies: the fastest per step), ``"splitting"`` or ``"strang"``
        (as in :func:`tumble.simulate`), or ``"exact"`` for torque-free
        bodies (the closed form at each recorded time, from the initial state,
        O(1) a body whatever the duration; ``dt`` then only sets the recorded
        times).
    torque : a torque model that batches accept (its class's ``in_batches``:
        constant body and space torques and linear damping), each either one
        value for all bodies or one per body (``ConstantBodyTorque(array (N,
        3))``, ``LinearDamping(array (N,))``). Gravity needs a pivot, user
        functions a single body: use :func:`tumble.simulate` for those.
    record_every : None to keep only the final states (memory stays O(N)), or k
        (an integer >= 1) to also keep every k-th state, and the last.
    progress : None or ``progress(done, total)`` in steps.
    internal : Rotor and KaneDamper parts (:mod:`tumble.parts`) that every body
        carries, as in :func:`tumble.simulate`: ``inertia`` holds them as if
        locked. Methods ``"rk4"`` (in blocks of bodies), and
        ``"splitting"``/``"strang"`` for rotors (one compiled body per thread).
    rotor_speed : None (each Rotor's own ``speed``) or (N, k) the k Rotors'
        initial speeds relative to each body, rad/s (a map over the rotors'
        momentum, as for the dual-spin condition).

    Returns
    -------
    BatchResult — the same states as N separate :func:`tumble.simulate` calls with
    the same method and ``dt``, to round-off.

    Raises
    ------
    InputError
        Bad values (see the messages), a torque batches do not take, a torque
        with ``method="exact"``.
    RequestTooLargeError
        Before any work, when the bodies and their records would not fit in
        the memory budget (:func:`tumble.resources.check_batch_memory`), or the run would take
        more than 2^53 steps.
    IntegrationError
        A body's state became NaN or infinite (the message names the first).

    Examples
    --------
    Two bodies of principal moments (1, 2, 3) kg·m², spun near their
    intermediate axis at two perturbations, for 10 s:

    >>> import numpy as np
    >>> import tumble as tb
    >>> moments = [[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]]
    >>> omega0 = [[0.1, 1.0, 0.1], [0.0, 1.0, 0.01]]
    >>> batch = tb.simulate_batch(moments, omega0, duration=10.0, dt=0.01)
    >>> batch.omega.shape, batch.method
    ((2, 3), 'rk4')

    The same state as :func:`tumble.simulate` with the same method and step:

    >>> body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    >>> one = tb.simulate(body, omega0[0], duration=10.0, dt=0.01, method="rk4")
    >>> np.allclose(batch.omega[0], one.omega[-1])
    True

    Torque-free, each body keeps |L| = |I ω|:

    >>> np.allclose(np.linalg.norm(batch.omega * moments, axis=1),
    ...             np.linalg.norm(np.multiply(omega0, moments), axis=1))
    True
    """
    integrator = get_integrator(method, batch=True)
    values, omega, q0, bodies = _bodies(inertia, omega0, attitude0, integrator)
    total_time, step = _times(duration, dt)
    _check_torque(torque)
    record_every = check_record_every(record_every, optional=True)
    parts = check_parts(internal)
    n = len(bodies)
    n_steps = whole_steps(total_time, step)
    check_batch_memory(n, n_steps, record_every, len(value_columns(parts)))
    step = total_time / n_steps
    if parts:
        return _run_with_parts(
            integrator,
            values,
            omega,
            q0,
            parts,
            rotor_speed,
            torque,
            step,
            n_steps,
            total_time,
            record_every,
            progress,
        )
    if rotor_speed is not None:
        raise InputError("Expected `rotor_speed` with Rotor parts in `internal`, got no parts.")
    bound = bind(torque, bodies, bodies=n)
    if integrator.torque_free_only and not bound.torque_free:
        raise InputError(
            f"Expected torque-free bodies for method {method!r} (the closed form), got "
            f"{torque!r}: use 'rk4' or a splitting."
        )
    return _run_rigid(
        integrator, bodies, omega, q0, bound, step, n_steps, total_time, record_every, progress
    )


def _bodies(
    inertia: Any, omega0: Any, attitude0: Any, integrator: Integrator
) -> tuple[Array, Array, Array, BodyBatch]:
    """The validated inertias ((N, 3) or (N, 3, 3), kg·m²), ω0 (N, 3) rad/s and
    attitudes (N, 4) of a batch, and its bodies in their principal frames."""
    values = vector_to_si(
        inertia, "inertia", "inertia", (-1, 3) if np.ndim(inertia) == 2 else (-1, 3, 3)
    )
    if values.ndim == 3:
        check_symmetric(values)
    n = values.shape[0]
    omega = vector_to_si(omega0, "angular_velocity", "omega0", (n, 3))
    q0 = _attitudes(attitude0, n)
    if integrator.kind == "sampling" and values.ndim == 2:
        # The closed form needs the moments ascending: the decomposition of the
        # diagonal tensors orders them, with axes that make a proper rotation.
        values = np.einsum("ni,ij->nij", values, np.eye(3))
    bodies = BodyBatch.from_inertia(values)
    _check_moments(bodies.moments)
    return values, omega, q0, bodies


def _times(duration: Any, dt: Any) -> tuple[float, float]:
    """The duration and the step asked for, s, each > 0."""
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    step = to_si(dt, "time", "dt")
    if step <= 0:
        raise InputError(f"Expected `dt` > 0 s, got {step!r}.")
    return total_time, step


def _check_torque(torque: Any) -> None:
    """Refuse anything but a torque model of the models batches accept."""
    if torque is not None and not isinstance(torque, TorqueModel):
        raise InputError(
            f"Expected `torque` to be a model from tumble.torques, got {type(torque).__name__}."
        )
    for term in () if torque is None else torque.terms:
        if not term.in_batches:
            accepted = ", ".join(name for name, cls in TORQUES.items() if cls.in_batches)
            raise InputError(
                f"Expected `torque` of models that batches accept ({accepted}), got {term!r} "
                "(use simulate for it)."
            )


def _run_with_parts(
    integrator: Integrator,
    values: Array,
    omega: Array,
    q0: Array,
    parts: tuple[Any, ...],
    rotor_speed: Any,
    torque: TorqueModel | None,
    step: float,
    n_steps: int,
    total_time: float,
    record_every: int | None,
    progress: Progress,
) -> BatchResult:
    """Bodies carrying parts (:mod:`tumble.batch.parts`), after the check that the
    step keeps the parts' own motion stable."""
    with_parts = PartsBatch.build(values, omega, q0, parts, rotor_speed, integrator.name)
    # The dampers' rates are fastest on the body of the smallest platform moment.
    lightest = with_parts.bodies.moments[int(np.argmin(with_parts.bodies.moments[:, 0]))]
    rate, names = internal_rate(parts, np.diag(lightest))
    check_internal_stability(rate, names, integrator.kind, step, total_time, math.inf)
    return with_parts.run(integrator, torque, step, n_steps, record_every, progress)


def _run_rigid(
    integrator: Integrator,
    bodies: BodyBatch,
    omega: Array,
    q0: Array,
    bound: BoundTorque,
    step: float,
    n_steps: int,
    total_time: float,
    record_every: int | None,
    progress: Progress,
) -> BatchResult:
    """Rigid bodies by the batch driver, their states turned back into body axes."""
    n = len(bodies)
    # Copies: the kernels step these in place, and a body already in principal
    # axes would otherwise share the caller's arrays.
    w = np.array(bodies.to_principal(omega).T, order="C")
    q = np.array(bodies.attitude_to_principal(q0).T, order="C")
    batch = Batch(np.ascontiguousarray(bodies.moments.T), w, q, bound)
    run = step_batch(integrator, batch, step, n_steps, record_every=record_every, progress=progress)

    def to_body(ws: Array, qs: Array) -> tuple[Array, Array]:
        return bodies.from_principal(ws.T.copy()), bodies.attitude_from_principal(qs.T.copy())

    final_w, final_q = to_body(w, q)
    if record_every is None:
        return BatchResult(
            final_w,
            final_q,
            np.array([total_time]),
            None,
            None,
            step,
            integrator.name,
            np.zeros((n, 0)),
        )
    pairs = [to_body(a, b) for a, b in zip(run.omega_history, run.quaternion_history, strict=True)]
    return BatchResult(
        final_w,
        final_q,
        np.asarray(run.times),
        np.stack([p[0] for p in pairs]),
        np.stack([p[1] for p in pairs]),
        step,
        integrator.name,
        np.zeros((n, 0)),
    )


def _attitudes(attitude0: Any, n: int) -> Array:
    """(n, 4) unit quaternions (identity when None)."""
    if attitude0 is None:
        return np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    q0 = vector_to_si(attitude0, "dimensionless", "attitude0", (n, 4))
    norms = np.linalg.norm(q0, axis=1)
    if np.any(norms < 1e-12):
        k = int(np.argmin(norms))
        raise InputError(
            f"Expected `attitude0` to hold non-zero quaternions, got attitude0[{k}] = "
            f"{q0[k].tolist()}."
        )
    return np.asarray(q0 / norms[:, None])


def _check_moments(moments: Array) -> None:
    """Positive moments satisfying the triangle inequality, for every body."""
    # Column by column: reductions along the short axis of (N, 3) are ~10× slower.
    first, second, third = moments[:, 0], moments[:, 1], moments[:, 2]
    low = np.minimum(np.minimum(first, second), third)
    high = np.maximum(np.maximum(first, second), third)
    bad = np.flatnonzero(~(low > ZERO_MOMENT * high))
    if bad.size:
        k = int(bad[0])
        raise InputError(
            f"Expected every body to have positive principal moments, got body {k} with "
            f"{moments[k].tolist()} kg·m²."
        )
    # The two smaller moments sum to the total less the largest.
    short = (first + second + third) - high < high * (1 - PHYSICAL_TOLERANCE)
    broken = np.flatnonzero(short)
    if broken.size:
        k = int(broken[0])
        raise InputError(
            f"Expected principal moments satisfying I1 + I2 >= I3, got body {k} with "
            f"{moments[k].tolist()} kg·m²."
        )
