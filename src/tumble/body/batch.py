"""N free bodies at once, each about its centre of mass, in their principal frames
(:func:`tumble.simulate_batch`, the sweeps)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.body.frames import compose
from tumble.massprops import principal_decomposition

__all__ = ["BodyBatch"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class BodyBatch:
    """N free bodies at once, each turning about its centre of mass.

    Attributes
    ----------
    moments : (N, 3) principal moments, kg·m², ascending per body when given
        as tensors, in the order given otherwise.
    axes : None when the body axes are principal axes, else (N, 3, 3) each
        body's principal axes as columns in its body coordinates.
    """

    moments: Array
    axes: Array | None = None

    @classmethod
    def from_inertia(cls, inertia: Array) -> BodyBatch:
        """From (N, 3) principal moments or (N, 3, 3) inertia tensors (kg·m²)."""
        if inertia.ndim == 2:
            return cls(inertia)
        tensors = 0.5 * (inertia + np.swapaxes(inertia, 1, 2))
        moments, axes = principal_decomposition(tensors)
        # Principal axes that are every body's own axes need no turning.
        return cls(moments, None if np.all(axes == np.eye(3)) else axes)

    def __len__(self) -> int:
        return len(self.moments)

    @property
    def inertia_principal(self) -> Array:
        """(N, 3, 3) each body's inertia in its principal axes (diagonal), kg·m²."""
        return np.asarray(np.einsum("ni,ij->nij", self.moments, np.eye(3)))

    @cached_property
    def principal_rotation(self) -> Rotation | None:
        """The rotations principal axes → body axes, or None."""
        return None if self.axes is None else Rotation.from_matrix(self.axes)

    def to_principal(self, vectors: Any) -> Array:
        """Body-axes vectors ((3,) shared or (N, 3)) in each body's principal axes."""
        values = np.asarray(vectors, dtype=float)
        if self.axes is None:
            return values
        values = np.broadcast_to(values, (len(self), 3))
        return np.asarray(np.einsum("nji,nj->ni", self.axes, values))

    def from_principal(self, vectors: Array) -> Array:
        """(N, 3) principal-axes vectors in each body's axes."""
        if self.axes is None:
            return vectors
        return np.asarray(np.einsum("nij,nj->ni", self.axes, vectors))

    def attitude_to_principal(self, quaternions: Array) -> Array:
        """(N, 4) quaternions body → space as principal → space."""
        if self.principal_rotation is None:
            return quaternions
        return compose(quaternions, self.principal_rotation)

    def attitude_from_principal(self, quaternions: Array) -> Array:
        """(N, 4) quaternions principal → space as body → space."""
        if self.principal_rotation is None:
            return quaternions
        return compose(quaternions, self.principal_rotation.inv())
