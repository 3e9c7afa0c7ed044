"""The state of the parts a body carries, and its mapping to and from the
kernels' state (:mod:`tumble.core.parts`).
"""

from __future__ import annotations

import itertools
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from tumble.parts import pack_parts

if TYPE_CHECKING:
    from tumble.body.protocol import BodyModel

__all__ = ["PartsState"]

Array = NDArray[np.float64]


class PartsState:
    """The parts' values and the kernels' state of a body carrying parts
    (:class:`tumble.body.RigidBody`)."""

    @cached_property
    def _packed(self: BodyModel) -> tuple[Any, Array]:
        layout, packed = pack_parts(self, self.parts)
        packed.flags.writeable = False
        return layout, packed

    @cached_property
    def _reading(self: BodyModel) -> tuple[Any, tuple[Array, ...], bool, bool]:
        """What :meth:`from_kernel_state` hands the kernels: the compiled reading of
        the layout (:func:`tumble.core.parts.readout`), its arrays (the moments, the
        packed parts, the principal axes and the quaternion from the principal frame
        to the body's, contiguous), whether the principal axes turn at all, and
        whether every part's values are read compiled."""
        from tumble.core.parts import part_values, readout

        arrays = (self.moments, self.packed_parts, self.axes, self._principal_quaternions[1])
        contiguous = tuple(np.array(a, dtype=float, order="C") for a in arrays)
        compiled = part_values(self.layout) is not None
        return readout(self.layout), contiguous, not self._axes_are_body_axes, compiled

    @property
    def compiled_reading(self: BodyModel) -> tuple[Any, tuple[Any, ...]] | None:
        """``(read, arguments)``: the compiled reading of kernel states
        (:func:`tumble.core.parts.readout`) and its arguments after the states and
        before the three arrays it writes, ``read(states, *arguments, omega,
        quaternion, values)`` (as :meth:`from_kernel_state`, for C-contiguous float64
        states); None where a part's values are read back in Python."""
        read, arrays, turned, compiled = self._reading
        return (read, (*arrays, turned)) if compiled else None

    @property
    def layout(self: BodyModel) -> Any:
        """The kernels' layout of its parts (:func:`tumble.parts.pack_parts`)."""
        return self._packed[0]

    @property
    def packed_parts(self: BodyModel) -> Array:
        """(rows, 1) its parts packed for the kernels (:func:`tumble.parts.pack_parts`)."""
        return self._packed[1]

    def initial_values(self: BodyModel, omega0: Array) -> Array:
        """(..., m) the parts' values at t = 0 for the body's ω0 (..., 3)
        (:meth:`tumble.parts.InternalPart.initial_values`); m, here and below, is
        the sum of the parts' sizes."""
        omega0 = np.asarray(omega0, dtype=float)
        pieces = [part.initial_values(omega0) for part in self.parts]
        return np.concatenate(pieces, axis=-1) if pieces else np.zeros((*omega0.shape[:-1], 0))

    def split_values(
        self: BodyModel, values: Array | None, omega: Array | None = None
    ) -> list[Array]:
        """The parts' values (..., m), cut per part; None: their initial
        values for ω (..., 3) (a damper turning with the body)."""
        if values is None:
            start = np.zeros(3) if omega is None else omega
            return [part.initial_values(start) for part in self.parts]
        cuts = np.cumsum([0, *(part.size for part in self.parts)])
        return [values[..., a:b] for a, b in itertools.pairwise(cuts)]

    def kernel_state(self: BodyModel, omega0: Array, attitude0: Array) -> Array:
        """(7 + m,) the state the parts' kernels integrate (:mod:`tumble.core.parts`):
        H, q (principal-platform frame), then the parts' momenta, from ω0 (rad/s,
        body axes) and the attitude (body → space)."""
        total, momenta = self._initial_momenta(omega0)
        pieces = [part.to_kernel(own, self) for part, own in zip(self.parts, momenta, strict=True)]
        momentum = self.to_principal(total)
        return np.concatenate(
            [momentum, self.attitude_to_principal(np.asarray(attitude0, dtype=float)), *pieces]
        )

    def _initial_momenta(self: BodyModel, omega0: Array) -> tuple[Array, list[Array]]:
        """The angular momentum (3,) at t = 0 (body axes, kg·m²/s) and each part's
        momenta (:meth:`tumble.parts.InternalPart.momenta`) for ω0 (3,), rad/s:
        what :meth:`fastest_rate` and :meth:`kernel_state` both read, computed
        once for the last ω0 asked."""
        omega0 = np.asarray(omega0, dtype=float)
        key = (omega0.shape, omega0.tobytes())
        last = self.__dict__.get("_last_start")
        if last is not None and last[0] == key:
            return last[1], list(last[2])
        momenta = tuple(part.momenta(omega0, part.initial_values(omega0)) for part in self.parts)
        total = self.angular_momentum(omega0)
        total.flags.writeable = False
        self.__dict__["_last_start"] = (key, total, momenta)
        return total, list(momenta)

    def from_kernel_state(self: BodyModel, states: Array) -> tuple[Array, Array, Array]:
        """ω (n, 3) and the attitude (n, 4), body axes, and the parts' values
        (n, m), from kernel states (n, 7 + m): ω as the kernels solve for it, and
        the values compiled where every part has them
        (:func:`tumble.core.parts.readout`)."""
        states = np.ascontiguousarray(states, dtype=float)
        read, arrays, turned, compiled = self._reading
        n, size = states.shape
        omega, quaternion = np.empty((n, 3)), np.empty((n, 4))
        found = np.empty((n, size - 7 if compiled else 0))
        read(states, *arrays, turned, omega, quaternion, found)
        if compiled or not self.parts:
            return omega, quaternion, found
        values, k = [], 7
        for part in self.parts:
            momenta = part.from_kernel(states[:, k : k + part.size], self)
            values.append(part.values_from(omega, momenta))
            k += part.size
        parts = np.concatenate(values, axis=1) if values else np.zeros((len(states), 0))
        return omega, quaternion, parts
