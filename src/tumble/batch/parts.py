"""Batches of bodies that carry internal parts (Rotor, KaneDamper): the state
conversions and packing, per body, for the parts' batch kernels
(:func:`tumble.core.parts.batch_kernel`), and their driver."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.batch.result import BatchResult, Progress
from tumble.body import ZERO_MOMENT, BodyBatch
from tumble.core._jit import FINITE
from tumble.errors import InputError, IntegrationError
from tumble.integrators import INTEGRATORS, Integrator
from tumble.integrators.drivers import PROGRESS_CHUNK
from tumble.parts import KaneDamper, Rotor, layout_of
from tumble.parts.packing import padded_schedule
from tumble.torques import TorqueModel, bind
from tumble.units import vector_to_si

__all__ = ["PartsBatch"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PartsBatch:
    """N bodies carrying the same Rotor and KaneDamper parts, ready for the
    parts' batch kernels (:func:`tumble.core.parts.batch_kernel`): each body in
    the principal frame of its platform inertia (the locked inertia less the
    parts' spin inertia), the state ``y`` (7 + m, N) holding H, q and the
    parts' momenta, as :meth:`tumble.body.RigidBody.kernel_state` does for one.
    """

    bodies: BodyBatch
    parts: tuple[Any, ...]
    y: Array
    packed: Array
    layout: tuple[tuple[int, ...], int]
    method: str

    @classmethod
    def build(
        cls, inertia: Array, omega: Array, q0: Array, parts: tuple[Any, ...], speeds: Any,
        method: str,
    ) -> PartsBatch:  # fmt: skip
        """From the locked ``inertia`` ((N, 3) or (N, 3, 3), kg·m²), ω0 (N, 3) rad/s,
        the attitudes (N, 4), the parts and the rotors' speeds (None or (N, k))."""
        n = len(omega)
        locked = inertia if inertia.ndim == 3 else np.einsum("ni,ij->nij", inertia, np.eye(3))
        for part in parts:
            if not isinstance(part, Rotor | KaneDamper):
                raise InputError(
                    f"Expected Rotor and KaneDamper parts in simulate_batch, got a "
                    f"{type(part).__name__} (its mass moves each body's centre of mass: use "
                    "simulate)."
                )
        rotors = [part for part in parts if isinstance(part, Rotor)]
        if speeds is None:
            speed = np.tile([rotor.speed for rotor in rotors], (n, 1))
        else:
            speed = vector_to_si(speeds, "angular_velocity", "rotor_speed", (n, len(rotors)))
        platform = locked - sum(part.spin_inertia() for part in parts)
        bodies = BodyBatch.from_inertia(platform)
        low = np.flatnonzero(~(bodies.moments[:, 0] > ZERO_MOMENT * bodies.moments[:, 2]))
        if low.size:
            k = int(low[0])
            raise InputError(
                "Expected internal parts whose spin inertia every body can hold (each "
                "rotor's J a aᵀ and each damper's J 1 taken from the body's inertia must leave "
                f"positive principal moments), got body {k} with "
                f"{np.round(bodies.moments[k], 12).tolist()} kg·m² left."
            )
        # H = I ω + Σ J Ω a at t = 0 (the dampers turn with the body), then each
        # part's momentum: a rotor's J (a·ω + Ω), a damper's J ω (principal axes).
        momentum = np.einsum("nij,nj->ni", locked, omega)
        blocks = []
        k = 0
        for part in parts:
            if isinstance(part, Rotor):
                momentum += part.inertia * speed[:, k : k + 1] * part.axis
                blocks.append(part.inertia * (omega @ part.axis + speed[:, k])[None, :])
                k += 1
            else:
                blocks.append(part.inertia * bodies.to_principal(omega).T)
        y = np.concatenate(
            [bodies.to_principal(momentum).T, bodies.attitude_to_principal(q0).T, *blocks]
        )
        layout = layout_of(parts)
        return cls(bodies, parts, np.ascontiguousarray(y), _pack(bodies, parts, layout), layout,
                   method)  # fmt: skip

    def values(self, y: Array) -> tuple[Array, Array, Array]:
        """ω (N, 3) and the attitude (N, 4), body axes, and the parts' values
        (N, m), from kernel states (7 + m, N)."""
        bodies = self.bodies
        inside = y[:3].T.copy()
        row = 7
        momenta = []
        for part in self.parts:
            if isinstance(part, Rotor):
                h = y[row]
                inside -= h[:, None] * bodies.to_principal(part.axis)
                momenta.append(h[:, None])
                row += 1
            else:
                block = y[row : row + 3].T
                inside -= block
                momenta.append(bodies.from_principal(block.copy()))
                row += 3
        omega = bodies.from_principal(inside / bodies.moments)
        parts = [part.values_from(omega, m) for part, m in zip(self.parts, momenta, strict=True)]
        return omega, bodies.attitude_from_principal(y[3:7].T.copy()), np.concatenate(parts, axis=1)

    def run(
        self, integrator: Integrator, torque: TorqueModel | None, dt: float, n_steps: int,
        record_every: int | None, progress: Progress,
    ) -> BatchResult:  # fmt: skip
        """Advance the bodies ``n_steps`` steps of ``dt`` s; the result as
        :func:`simulate_batch` returns it."""
        kinds = {part.kind for part in self.parts}
        if not integrator.handles(kinds) or integrator.parts_batch is None:
            able = [
                name for name, entry in INTEGRATORS.items()
                if entry.parts_batch is not None and entry.handles(kinds)
            ]  # fmt: skip
            raise InputError(
                f"Expected a method that integrates batches carrying "
                f"{', '.join(sorted(kinds))} parts ({', '.join(able)}), got {self.method!r}."
            )
        for term in () if torque is None else torque.terms:
            if getattr(term, "actuator", "external") == "rotors":
                raise InputError(
                    f"Expected torques that act on the bodies from outside in a batch with "
                    f"parts, got {term!r}, which acts through the rotors (use simulate)."
                )
        n = self.y.shape[1]
        bound = bind(torque, self.bodies, bodies=n)
        kernel = integrator.kernel("parts_batch", bound, self.layout)
        moments = np.ascontiguousarray(self.bodies.moments.T)
        status = np.full(n, FINITE, dtype=np.int64)
        history = [self.values(self.y)] if record_every is not None else []
        times = [0.0]
        chunk = record_every or PROGRESS_CHUNK
        done = 0
        while done < n_steps:
            count = min(chunk, n_steps - done)
            kernel(self.y, moments, self.packed, bound.params, bound.context, done * dt, dt,
                   count, status)  # fmt: skip
            done += count
            if np.any(status != FINITE):
                break
            if record_every is not None:
                times.append(done * dt)
                history.append(self.values(self.y))
            if progress is not None:
                progress(done, n_steps)
        bad = np.flatnonzero(status != FINITE)
        if bad.size:
            k = int(bad[0])
            raise IntegrationError(
                f"Expected every body's state to stay finite, got body {k} non-finite at step "
                f"{int(status[k])} (t = {int(status[k]) * dt:.6g} s)."
            )
        omega, quaternion, values = self.values(self.y)
        rotors = tuple(k for k, part in enumerate(self._columns()) if isinstance(part, Rotor))
        if record_every is None:
            return BatchResult(omega, quaternion, np.array([n_steps * dt]), None, None, dt,
                               self.method, values, None, rotors)  # fmt: skip
        return BatchResult(
            omega, quaternion, np.asarray(times),
            np.stack([h[0] for h in history]), np.stack([h[1] for h in history]),
            dt, self.method, values, np.stack([h[2] for h in history]), rotors,
        )  # fmt: skip

    def _columns(self) -> list[Any]:
        """The part owning each column of the values."""
        return [part for part in self.parts for _ in range(part.size)]


def _pack(bodies: BodyBatch, parts: tuple[Any, ...], layout: tuple[tuple[int, ...], int]) -> Array:
    """The parts packed for the kernels, one column per body (each in its
    platform's principal frame), as :func:`tumble.parts.pack_parts` packs one."""
    _, longest = layout
    n = len(bodies)
    rotors = [part for part in parts if isinstance(part, Rotor)]
    axes = np.zeros((n, 0, 3))
    if rotors:
        turned = [bodies.to_principal(np.broadcast_to(rotor.axis, (n, 3))) for rotor in rotors]
        axes = np.stack(turned, axis=1)
    allocation = np.asarray(
        np.linalg.pinv(np.swapaxes(axes, 1, 2)) if rotors else np.zeros((n, 0, 3)), dtype=float
    )
    rows: list[Array] = []
    k = 0
    for part in parts:
        if isinstance(part, Rotor):
            shared = [part.inertia, part.max_torque, part.max_speed]
            rows += [axes[:, k].T, np.tile(np.array(shared)[:, None], (1, n)), allocation[:, k].T]
            rows += [np.tile(padded_schedule(part, longest)[:, None], (1, n))]
            k += 1
        else:
            rows.append(np.tile([[part.inertia], [part.damping]], (1, n)))
    return np.ascontiguousarray(np.concatenate(rows, axis=0))
