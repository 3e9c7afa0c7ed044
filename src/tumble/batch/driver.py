"""The batch driver: :func:`step_batch` steps N bodies (structure of arrays,
principal frames) with the registry's compiled batch kernels, in chunks, with
progress, the check that every state stayed finite and optional recording;
:func:`measure_batch` steps them measuring each body as it goes
(:mod:`tumble.core.metrics`). Both :func:`tumble.simulate_batch` and the sweep
engine (:mod:`tumble.sweep`) run on them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from tumble.batch.result import Progress
from tumble.body import BodyBatch
from tumble.core._jit import FINITE
from tumble.core.metrics import N_METRICS
from tumble.errors import InputError, IntegrationError
from tumble.integrators import Integrator
from tumble.integrators.steps import PROGRESS_CHUNK
from tumble.torques import BoundTorque

__all__ = ["Batch", "BatchRun", "measure_batch", "step_batch"]

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
            kernel(
                batch.w,
                batch.q,
                batch.inertia,
                torque.params,
                torque.context,
                done * dt,
                dt,
                count,
                status,
            )
        else:
            batch.w[:], batch.q[:] = start
            kernel(
                batch.w,
                batch.q,
                batch.inertia,
                torque.params,
                torque.context,
                0.0,
                dt,
                done + count,
                status,
            )
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
        bodies = (
            BodyBatch(batch.inertia.T.copy())
            if ordered
            else BodyBatch.from_inertia(np.einsum("in,ij->nij", batch.inertia, np.eye(3)))
        )
        w = np.ascontiguousarray(bodies.to_principal(batch.w.T).T)
        turned = np.ascontiguousarray(bodies.to_principal(axis.T).T)
        moments = np.ascontiguousarray(bodies.moments.T)
        kernel(
            w,
            batch.q,
            moments,
            torque.params,
            torque.context,
            turned,
            0.0,
            dt,
            n_steps,
            metrics,
            status,
        )
        if final_state:  # the measures leave the states; the closed form advances them
            q = np.ascontiguousarray(bodies.attitude_to_principal(batch.q.T).T)
            advance = integrator.kernel("batch", torque)
            advance(w, q, moments, torque.params, torque.context, 0.0, dt, n_steps, status)
            batch.w[:] = bodies.from_principal(w.T).T
            batch.q[:] = bodies.attitude_from_principal(q.T).T
    else:
        kernel = integrator.kernel(
            "metrics",
            torque,
            principal_axis=_principal_axis_of(axis),
            attitude=final_state or "attitude" in torque.depends_on,
        )
        kernel(
            batch.w,
            batch.q,
            batch.inertia,
            torque.params,
            torque.context,
            axis,
            0.0,
            dt,
            n_steps,
            metrics,
            status,
        )
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
