"""Batches of bodies that carry internal parts (:mod:`tumble.parts`): the state
conversions and packing, per body, for the parts' batch kernels
(:func:`tumble.core.part_blocks.block_kernel`), and their driver."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tumble.batch.result import BatchResult, Progress
from tumble.body import ZERO_MOMENT, BodyBatch
from tumble.core._jit import FINITE
from tumble.errors import InputError, IntegrationError
from tumble.integrators import Integrator, methods_for
from tumble.integrators.steps import PROGRESS_CHUNK
from tumble.parts import pack_parts, spin_columns
from tumble.torques import TorqueModel, bind
from tumble.units import vector_to_si

__all__ = ["PartsBatch"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PartsBatch:
    """N bodies carrying the same parts, ready for the parts' batch kernels
    (:func:`tumble.core.part_blocks.block_kernel`): each body in the principal frame of
    its platform inertia (the locked inertia less the parts' spin inertia), the
    state ``y`` (7 + m, N) holding H, q and the parts' momenta, as
    :meth:`tumble.body.RigidBody.kernel_state` does for one.
    """

    bodies: BodyBatch
    parts: tuple[Any, ...]
    y: Array
    packed: Array
    layout: Any
    method: str

    @classmethod
    def build(
        cls,
        inertia: Array,
        omega: Array,
        q0: Array,
        parts: tuple[Any, ...],
        speeds: Any,
        method: str,
    ) -> PartsBatch:
        """From the locked ``inertia`` ((N, 3) or (N, 3, 3), kg·m²), ω0 (N, 3) rad/s,
        the attitudes (N, 4), the parts and the speeds of the parts that have one
        (None or (N, k): those of the parts that spin, :attr:`tumble.parts.InternalPart.spin`)."""
        n = len(omega)
        locked = inertia if inertia.ndim == 3 else np.einsum("ni,ij->nij", inertia, np.eye(3))
        for part in parts:
            if part.not_in_batches is not None:
                raise InputError(
                    f"Expected parts that simulate_batch takes, got a {type(part).__name__} "
                    f"({part.not_in_batches})."
                )
        spinning = [k for k, part in enumerate(parts) if part.spin is not None]
        if speeds is not None:
            speeds = vector_to_si(speeds, "angular_velocity", "rotor_speed", (n, len(spinning)))
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
        # H = I_p ω + each part's momentum at t = 0, then each part's momenta.
        momentum = np.einsum("nij,nj->ni", platform, omega)
        blocks = []
        for k, part in enumerate(parts):
            values = part.initial_values(omega)
            if speeds is not None and k in spinning:
                values = np.array(values)
                values[:, part.spin] = speeds[:, spinning.index(k)]
            momentum = momentum + part.momentum(omega, values)
            blocks.append(part.to_kernel(part.momenta(omega, values), bodies).T)
        y = np.concatenate(
            [bodies.to_principal(momentum).T, bodies.attitude_to_principal(q0).T, *blocks]
        )
        layout, packed = pack_parts(bodies, parts)
        return cls(
            bodies, parts, np.ascontiguousarray(y), np.ascontiguousarray(packed), layout, method
        )

    def values(self, y: Array) -> tuple[Array, Array, Array]:
        """ω (N, 3) and the attitude (N, 4), body axes, and the parts' values
        (N, m), from kernel states (7 + m, N): ω as the kernels solve for it."""
        from tumble.core.parts import velocities

        bodies = self.bodies
        moments = np.ascontiguousarray(bodies.moments.T)
        principal = velocities(self.layout)(np.ascontiguousarray(y), moments, self.packed)
        omega = bodies.from_principal(principal)
        values, k = [], 7
        for part in self.parts:
            momenta = part.from_kernel(np.ascontiguousarray(y[k : k + part.size].T), bodies)
            values.append(part.values_from(omega, momenta))
            k += part.size
        return omega, bodies.attitude_from_principal(y[3:7].T.copy()), np.concatenate(values, 1)

    def check_method(self, integrator: Integrator, torque: TorqueModel | None, role: str) -> None:
        """Refuse an integrator without a kernel ``role`` for these parts, and torques
        that act through the rotors (a batch has no allocation to share them)."""
        kinds = {part.kind for part in self.parts}
        if not integrator.handles(self.parts) or getattr(integrator, role) is None:
            able = methods_for(self.parts, role)
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

    def measure(
        self,
        integrator: Integrator,
        torque: TorqueModel | None,
        dt: float,
        n_steps: int,
        axis: Array,
        *,
        energy: bool = True,
        first_body: int = 0,
        where: str = "",
    ) -> tuple[Array, Array]:
        """Advance the bodies in place by ``n_steps`` steps of ``dt`` s, measuring each
        after every step about its nominal axis ``axis`` (3, N; unit vectors, body
        axes): the measures (``N_METRICS``, N) of :mod:`tumble.core.metrics` with
        the total angular momentum H for L and the energy of the body and its parts
        (:func:`tumble.core.part_measures.measuring_kernel`), and twice each body's energy
        at the start (N,), J. ``energy=False`` for measures without the energy
        (its rows then hold that of the body alone, ``ω · H``: the parts may
        lack its equation). ``first_body`` and ``where`` name the bodies in
        errors, as :meth:`tumble.batch.Batch.check_finite` does.

        Raises
        ------
        InputError
            A method without a measuring kernel for these parts, a part kind
            without its energy's equation.
        IntegrationError
            A body's state became NaN or infinite.
        """
        from tumble.core.metrics import N_METRICS
        from tumble.core.parts import part_energy

        self.check_method(integrator, torque, "parts_metrics")
        if energy and part_energy(self.layout) is None:
            missing = sorted({p.kind for p in self.parts if p.equations.energy is None})
            raise InputError(
                f"Expected parts whose energy can be measured (PartEquations.energy), got "
                f"{', '.join(missing)} parts without it."
            )
        n = self.y.shape[1]
        bound = bind(torque, self.bodies, bodies=n)
        kernel = integrator.kernel("parts_metrics", bound, self.layout)
        moments = np.ascontiguousarray(self.bodies.moments.T)
        turned = np.ascontiguousarray(self.bodies.to_principal(np.asarray(axis).T).T)
        metrics = np.empty((N_METRICS, n))
        twice = np.empty(n)
        status = np.full(n, FINITE, dtype=np.int64)
        kernel(
            self.y,
            moments,
            self.packed,
            bound.params,
            bound.context,
            turned,
            0.0,
            dt,
            n_steps,
            metrics,
            twice,
            status,
        )
        bad = np.flatnonzero(status != FINITE)
        if bad.size:
            k = int(bad[0])
            place = f" {where}" if where else ""
            raise IntegrationError(
                f"Expected the integration to stay finite, got NaN or inf for {bad.size} "
                f"bodies{place} (first: body {first_body + k}, at step {int(status[k])}) with "
                f"dt = {dt:.3g} s: reduce dt."
            )
        return metrics, twice

    def run(
        self,
        integrator: Integrator,
        torque: TorqueModel | None,
        dt: float,
        n_steps: int,
        record_every: int | None,
        progress: Progress,
    ) -> BatchResult:
        """Advance the bodies ``n_steps`` steps of ``dt`` s; the result as
        :func:`simulate_batch` returns it."""
        self.check_method(integrator, torque, "parts_batch")
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
            kernel(
                self.y,
                moments,
                self.packed,
                bound.params,
                bound.context,
                done * dt,
                dt,
                count,
                status,
            )
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
        rotors = spin_columns(self.parts)
        if record_every is None:
            return BatchResult(
                omega,
                quaternion,
                np.array([n_steps * dt]),
                None,
                None,
                dt,
                self.method,
                values,
                None,
                rotors,
            )
        return BatchResult(
            omega,
            quaternion,
            np.asarray(times),
            np.stack([h[0] for h in history]),
            np.stack([h[1] for h in history]),
            dt,
            self.method,
            values,
            np.stack([h[2] for h in history]),
            rotors,
        )
