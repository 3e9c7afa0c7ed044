"""Many free bodies at once: :func:`simulate_batch`, and the batch driver sweeps share.

:func:`step_batch` is the one driver of the compiled batch kernels: it steps N
bodies (structure of arrays, principal frames) in chunks, with progress, the
check that every state stayed finite, optional recording and optional per-body
measures taken while stepping (:mod:`tumble.core.metrics`). Both
:func:`simulate_batch` and the sweep engine (:mod:`tumble.sweep`) run on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.batch.parts import PartsBatch
from tumble.batch.result import BatchResult, Progress
from tumble.body import ZERO_MOMENT, BodyBatch
from tumble.core._jit import FINITE
from tumble.core.metrics import N_METRICS
from tumble.errors import InputError, IntegrationError
from tumble.integrators import Integrator, get_integrator
from tumble.integrators.limits import check_internal_stability, check_record_every
from tumble.integrators.steps import PROGRESS_CHUNK, whole_steps
from tumble.massprops import PHYSICAL_TOLERANCE, check_symmetric
from tumble.parts import check_parts, internal_rate, value_columns
from tumble.resources import check_memory
from tumble.torques import TORQUES, BoundTorque, TorqueModel, bind
from tumble.units import to_si, vector_to_si

__all__ = [
    "PEAK_PER_VALUE",
    "PER_BODY",
    "PER_RECORD",
    "Batch",
    "BatchResult",
    "BatchRun",
    "check_batch_memory",
    "measure_batch",
    "simulate_batch",
    "step_batch",
]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Batch:
    """N bodies ready for the batch kernels, in their principal frames (the arrays
    C-contiguous; the state is advanced in place).

    Attributes
    ----------
    inertia : (3, N) principal moments, kg·m².
    w : (3, N) angular velocities, rad/s; ``q`` (4, N) quaternions, principal → space.
    torque : the torque bound to the batch (:func:`tumble.torques.bind`).
    """

    inertia: Array
    w: Array
    q: Array
    torque: BoundTorque

    def __len__(self) -> int:
        return int(self.w.shape[1])

    def check_finite(self, status: NDArray[np.int64], dt: float, first: int, where: str) -> None:
        """Raise IntegrationError when a body's state is not finite or its kernel
        status says it stopped; ``first`` numbers the first body, ``where`` says
        where the bodies are (e.g. "of chunk 3")."""
        w, q = self.w, self.q
        diverged = ~(np.isfinite(w).all(axis=0) & np.isfinite(q).all(axis=0)) | (status != FINITE)
        if np.any(diverged):
            k = int(np.flatnonzero(diverged)[0])
            place = f" {where}" if where else ""
            raise IntegrationError(
                f"Expected the integration to stay finite, got NaN or inf for "
                f"{int(diverged.sum())} bodies{place} (first: body {first + k}) with "
                f"dt = {dt:.3g} s: reduce dt."
            )


@dataclass(frozen=True, eq=False)
class BatchRun:
    """What :func:`step_batch` recorded: the times (s) and the principal-frame
    states (lists of (3, N) and (4, N) arrays, the initial state first)."""

    times: list[float]
    omega_history: list[Array]
    quaternion_history: list[Array]


def step_batch(
    integrator: Integrator,
    batch: Batch,
    dt: float,
    n_steps: int,
    *,
    record_every: int | None = None,
    progress: Progress = None,
    first_body: int = 0,
    where: str = "",
) -> BatchRun:
    """Advance a batch in place by ``n_steps`` steps of ``dt`` s with the
    integrator's batch kernel, in chunks (of ``record_every`` steps, or of
    ``PROGRESS_CHUNK``).

    Parameters
    ----------
    record_every : None, or k to keep the state every k steps.
    progress : None or ``progress(done, n_steps)`` after each chunk of steps.
    first_body, where : see :meth:`Batch.check_finite`.

    Raises
    ------
    IntegrationError
        A body's state became NaN or infinite (the message names the first).
    """
    status = np.full(len(batch), FINITE, dtype=np.int64)
    run = BatchRun([0.0], [], [])
    if record_every is not None:
        run.omega_history.append(batch.w.copy())
        run.quaternion_history.append(batch.q.copy())
    kernel = integrator.kernel("batch", batch.torque)
    torque = batch.torque
    # A closed form jumps to each recorded time (or to the end) in one call, and
    # from the initial state: a restart from each rounded record would carry
    # the round-off on, amplified near a separatrix.
    sampling = integrator.kind == "sampling"
    start = (batch.w.copy(), batch.q.copy()) if sampling and record_every is not None else None
    chunk = record_every or (n_steps if sampling else PROGRESS_CHUNK)
    done = 0
    while done < n_steps:
        count = min(chunk, n_steps - done)
        if start is None:
            kernel(batch.w, batch.q, batch.inertia, torque.params, torque.context, done * dt,
                   dt, count, status)  # fmt: skip
        else:
            batch.w[:], batch.q[:] = start
            kernel(batch.w, batch.q, batch.inertia, torque.params, torque.context, 0.0, dt,
                   done + count, status)  # fmt: skip
        done += count
        if np.any(status != FINITE):
            break
        if record_every is not None:
            run.times.append(done * dt)
            run.omega_history.append(batch.w.copy())
            run.quaternion_history.append(batch.q.copy())
        if progress is not None:
            progress(done, n_steps)
    batch.check_finite(status, dt, first_body, where)
    return run


def measure_batch(
    integrator: Integrator,
    batch: Batch,
    dt: float,
    n_steps: int,
    axis: Array,
    *,
    first_body: int = 0,
    where: str = "",
    final_state: bool = True,
) -> Array:
    """Advance a batch in place by ``n_steps`` steps of ``dt`` s, measuring each
    body about its nominal axis ``axis`` (3, N) after every step: the measures
    (``N_METRICS``, N) of :mod:`tumble.core.metrics`. One call of the
    integrator's metrics kernel: the measures keep running extremes and the
    first flip in registers, not in arrays. ``final_state=False`` says the
    caller does not need the final states: a closed form (``"exact"``) then
    measures without stepping and leaves them, and a stepping method that can
    (:attr:`~tumble.integrators.Integrator.measures_without_attitude`: RK4),
    where the torque does not depend on the attitude, leaves ``q`` as it was
    and advances only ω, which is all the measures need: its kernel drops the
    quaternion's arithmetic, about half of an RK4 step. The measures are the
    same either way, to round-off.

    Raises
    ------
    IntegrationError
        As :func:`step_batch`.
    """
    status = np.full(len(batch), FINITE, dtype=np.int64)
    metrics = np.empty((N_METRICS, len(batch)))
    torque = batch.torque
    if integrator.torque_free_only and not torque.torque_free:
        raise InputError(
            f"Expected torque-free bodies for method {integrator.name!r} (the closed form), "
            "got a torque: use 'rk4' or a splitting."
        )
    if integrator.kind == "sampling":
        kernel = integrator.kernel("metrics", torque)
        # The closed form needs the moments ascending: where they are not, the
        # principal frames of the diagonal tensors order them (a proper
        # relabelling of the axes).
        ordered = bool(np.all(np.diff(batch.inertia, axis=0) >= 0.0))
        bodies = BodyBatch(batch.inertia.T.copy()) if ordered else BodyBatch.from_inertia(
            np.einsum("in,ij->nij", batch.inertia, np.eye(3))
        )  # fmt: skip
        w = np.ascontiguousarray(bodies.to_principal(batch.w.T).T)
        turned = np.ascontiguousarray(bodies.to_principal(axis.T).T)
        moments = np.ascontiguousarray(bodies.moments.T)
        kernel(w, batch.q, moments, torque.params, torque.context, turned, 0.0, dt, n_steps,
               metrics, status)  # fmt: skip
        if final_state:  # the measures leave the states; the closed form advances them
            q = np.ascontiguousarray(bodies.attitude_to_principal(batch.q.T).T)
            advance = integrator.kernel("batch", torque)
            advance(w, q, moments, torque.params, torque.context, 0.0, dt, n_steps, status)
            batch.w[:] = bodies.from_principal(w.T).T
            batch.q[:] = bodies.attitude_from_principal(q.T).T
    else:
        kernel = integrator.kernel(
            "metrics", torque, principal_axis=_principal_axis_of(axis),
            attitude=final_state or "attitude" in torque.depends_on,
        )  # fmt: skip
        kernel(batch.w, batch.q, batch.inertia, torque.params, torque.context, axis, 0.0, dt,
               n_steps, metrics, status)  # fmt: skip
    batch.check_finite(status, dt, first_body, where)
    return metrics


def _principal_axis_of(axis: Array) -> int | None:
    """The principal axis (0, 1 or 2) on which every nominal axis of ``axis`` (3, N)
    lies, its two other rows all zero and none of its own (a sweep's spin axes);
    None if there is none. Such axes are measured by a kernel of fewer operations
    (:func:`tumble.core.stepping.metrics_kernel`)."""
    zero = [not np.any(row) for row in axis]
    if sum(zero) != 2:
        return None
    k = zero.index(False)
    return k if bool(np.all(axis[k] != 0.0)) else None


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
        locked. Methods ``"rk4"``, and ``"splitting"``/``"strang"`` for rotors;
        one compiled body per thread.
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
    total_time = to_si(duration, "time", "duration")
    if total_time <= 0:
        raise InputError(f"Expected `duration` > 0 s, got {total_time!r}.")
    step = to_si(dt, "time", "dt")
    if step <= 0:
        raise InputError(f"Expected `dt` > 0 s, got {step!r}.")
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
    record_every = check_record_every(record_every, optional=True)
    parts = check_parts(internal)
    n_steps = whole_steps(total_time, step)
    check_batch_memory(n, n_steps, record_every, len(value_columns(parts)))
    step = total_time / n_steps
    if parts:
        with_parts = PartsBatch.build(values, omega, q0, parts, rotor_speed, method)
        # The dampers' rates are fastest on the body of the smallest platform moment.
        lightest = with_parts.bodies.moments[int(np.argmin(with_parts.bodies.moments[:, 0]))]
        rate, names = internal_rate(parts, np.diag(lightest))
        check_internal_stability(rate, names, integrator.kind, step, total_time, math.inf)
        return with_parts.run(integrator, torque, step, n_steps, record_every, progress)
    if rotor_speed is not None:
        raise InputError("Expected `rotor_speed` with Rotor parts in `internal`, got no parts.")
    bound = bind(torque, bodies, bodies=n)
    if integrator.torque_free_only and not bound.torque_free:
        raise InputError(
            f"Expected torque-free bodies for method {method!r} (the closed form), got "
            f"{torque!r}: use 'rk4' or a splitting."
        )

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
        return BatchResult(final_w, final_q, np.array([total_time]), None, None, step, method,
                           np.zeros((n, 0)))  # fmt: skip
    pairs = [to_body(a, b) for a, b in zip(run.omega_history, run.quaternion_history, strict=True)]
    return BatchResult(
        final_w,
        final_q,
        np.asarray(run.times),
        np.stack([p[0] for p in pairs]),
        np.stack([p[1] for p in pairs]),
        step,
        method,
        np.zeros((n, 0)),
    )


#: Memory a batch takes, bytes: per body (its tensors, frames and states, with
#: copies), per recorded value of a body (the records, their stacking and
#: their conversion to body axes: measured 3.0 to 3.3 times the 8 bytes kept),
#: and per record whatever the number of bodies (the arrays' own headers and
#: copies: measured 1.1 KiB).
PER_BODY = 400
PEAK_PER_VALUE = 4 * 8
PER_RECORD = 1536


def check_batch_memory(
    bodies: int, n_steps: int, record_every: int | None, part_values: int
) -> None:
    """Refuse, before any work, a batch whose states and records cannot fit in
    the memory budget (:mod:`tumble.resources`).

    Raises
    ------
    RequestTooLargeError
        With the estimate, and the advice to record less or run a sweep.
    """
    records = 1 if record_every is None else n_steps / record_every + 2
    values = 7 + part_values
    needed = bodies * (PER_BODY + records * values * PEAK_PER_VALUE)
    if record_every is not None:
        needed += records * PER_RECORD
    what = f"{bodies} bodies"
    advice = "Ask for fewer bodies at once"
    if record_every is not None:
        what += (
            f" × {records:.3g} records of {values} values ({n_steps} steps, every {record_every})"
        )
        advice = (
            "Record less often (record_every, or None for the final states only), or ask for "
            "fewer bodies at once"
        )
    check_memory(
        needed,
        what,
        f"{advice}; or run a sweep (tumble.sweep.run_sweep, `tumble sweep`), which streams "
        "its results to disk as it goes.",
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
