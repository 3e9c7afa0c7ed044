"""One chunk of a sweep: its bodies stepped and measured by the compiled kernels.

:func:`compute_chunk` is all a worker runs: it needs the plan and a chunk
index, and returns plain arrays keyed by their name in the Zarr store. No
history is kept: the measures are accumulated step by step inside the kernels
(:mod:`tumble.core.metrics`, run by :func:`tumble.batch.measure_batch`).
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.sweep.plan import Plan

__all__ = ["body_bytes", "compute_chunk", "output_arrays"]

#: numba's default threading layer runs one parallel kernel at a time per
#: process; a Dask worker with several threads must not start two at once.
_KERNEL_LOCK = threading.Lock()


def output_arrays(plan: Plan) -> dict[str, tuple[tuple[int, ...], str, str, str]]:
    """The arrays a sweep writes: name → (shape per body, dtype, unit, description)."""
    from tumble.sweep.plan import METRICS, PARAMETERS

    arrays: dict[str, tuple[tuple[int, ...], str, str, str]] = {}
    for name in plan.varied:
        kind, meaning = PARAMETERS[name]
        dtype = "int8" if kind == "axis" else "float64"
        arrays[f"parameters/{name}"] = ((), dtype, _unit(kind), meaning)
    if plan.initial_state:
        arrays["initial/moments"] = ((3,), "float64", "kg*m^2", "principal moments I1, I2, I3")
        arrays["initial/omega"] = ((3,), "float64", "rad/s", "angular velocity, principal axes")
    if plan.final_state:
        arrays["final/omega"] = ((3,), "float64", "rad/s", "angular velocity, principal axes")
        arrays["final/quaternion"] = (
            (4,),
            "float64",
            "",
            "attitude [w, x, y, z], principal axes -> space (identity at t = 0)",
        )
    for name in plan.metrics:
        unit, meaning = METRICS[name]
        arrays[f"metrics/{name}"] = ((), "int32" if name == "flips" else "float64", unit, meaning)
    return arrays


def body_bytes(plan: Plan) -> int:
    """Bytes a body takes in the store, uncompressed: its outputs
    (:func:`output_arrays`) and its ``computed`` flag (one byte)."""
    return 1 + sum(
        int(np.prod(shape, dtype=np.int64)) * np.dtype(dtype).itemsize
        for shape, dtype, _, _ in output_arrays(plan).values()
    )


def _unit(kind: str) -> str:
    from tumble.units import SI_UNITS

    return "" if kind == "axis" else SI_UNITS[kind]


def compute_chunk(plan: Plan, index: int) -> dict[str, NDArray[np.generic]]:
    """Simulate and measure the bodies of chunk ``index``.

    Returns
    -------
    dict: the arrays of :func:`output_arrays` for these bodies.

    Raises
    ------
    tumble.IntegrationError
        If a body's state became NaN or infinite (the message names the body).
    """
    from tumble.batch import Batch, measure_batch
    from tumble.body import BodyBatch
    from tumble.core.metrics import (
        ENERGY_DEVIATION,
        FIRST_FLIP,
        FLIPS,
        MIN_COS,
        MOMENTUM_DEVIATION,
    )
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    start, stop = plan.chunk_range(index)
    n = stop - start
    values = plan.chunk_parameters(index)
    bodies = plan.bodies(values)
    if plan.parts:
        out, twice_energy, momentum, (omega, quaternion) = _measure_with_parts(
            plan, bodies, start, index
        )
    else:
        w = np.ascontiguousarray(bodies.omega.T)
        q = np.zeros((4, n))
        q[0] = 1.0
        torque = bind(bodies.torque, BodyBatch(bodies.moments), bodies=n)
        batch = Batch(np.ascontiguousarray(bodies.moments.T), w, q, torque)
        integrator = get_integrator(plan.method, batch=True)
        with _KERNEL_LOCK:
            out = measure_batch(
                integrator,
                batch,
                plan.dt,
                plan.n_steps,
                bodies.axis,
                first_body=start,
                where=f"of chunk {index}",
                final_state=plan.final_state,
            )
        omega, quaternion = w.T, q.T
        twice_energy = np.sum(bodies.moments * bodies.omega**2, axis=1)
        momentum = np.linalg.norm(bodies.moments * bodies.omega, axis=1)

    result: dict[str, NDArray[np.generic]] = {}
    for name in plan.varied:
        result[f"parameters/{name}"] = (
            values[name].astype(np.int8) if name == "spin_axis" else values[name]
        )
    if plan.initial_state:
        result["initial/moments"] = bodies.moments
        result["initial/omega"] = bodies.omega
    if plan.final_state:
        result["final/omega"] = np.ascontiguousarray(omega)
        result["final/quaternion"] = np.ascontiguousarray(quaternion)
    tiny = np.finfo(float).tiny
    measured = {
        "flips": lambda: out[FLIPS].astype(np.int32),
        "first_flip_time": lambda: np.where(np.isinf(out[FIRST_FLIP]), np.nan, out[FIRST_FLIP]),
        "max_nutation": lambda: np.arccos(np.clip(out[MIN_COS], -1.0, 1.0)),
        "energy_drift": lambda: out[ENERGY_DEVIATION] / np.maximum(twice_energy, tiny),
        "momentum_drift": lambda: out[MOMENTUM_DEVIATION] / np.maximum(momentum, tiny),
    }
    for name in plan.metrics:
        result[f"metrics/{name}"] = measured[name]()
    return result


def _measure_with_parts(
    plan: Plan, bodies: Any, start: int, index: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], tuple[Any, Any]]:
    """The measures of a chunk of bodies carrying the plan's parts
    (:meth:`tumble.batch.PartsBatch.measure`), twice their energies and the size of
    their angular momenta at the start, and their final ω and attitudes (body axes,
    the bodies' principal axes)."""
    from tumble.batch.parts import PartsBatch
    from tumble.integrators import get_integrator

    n = len(bodies.omega)
    q0 = np.zeros((n, 4))
    q0[:, 0] = 1.0
    batch = PartsBatch.build(bodies.moments, bodies.omega, q0, plan.parts, None, plan.method)
    momentum = np.linalg.norm(batch.y[:3], axis=0)
    integrator = get_integrator(plan.method, batch=True)
    with _KERNEL_LOCK:
        out, twice_energy = batch.measure(
            integrator,
            bodies.torque,
            plan.dt,
            plan.n_steps,
            bodies.axis,
            energy="energy_drift" in plan.metrics,
            first_body=start,
            where=f"of chunk {index}",
        )
    omega, quaternion, _ = batch.values(batch.y)
    return out, twice_energy, momentum, (omega, quaternion)
