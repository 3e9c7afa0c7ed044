"""The symmetries of a body that give its motion in closed form: a gyrostat, a
symmetric gyrostat, a Lagrange top.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from tumble.massprops import PHYSICAL_TOLERANCE

if TYPE_CHECKING:
    from tumble.body.protocol import BodyModel

__all__ = ["Symmetry"]

Array = NDArray[np.float64]


class Symmetry:
    """The tests of a body (:class:`tumble.body.RigidBody`) for the motions that
    :mod:`tumble.theory.motions` solves in closed form."""

    def gyrostat_axis(self: BodyModel) -> Array | None:
        """The unit axis (body axes) on which every part lies, when every part is
        a rotor free of motors and that axis is a principal axis of the platform
        (a gyrostat whose rotor momentum is constant along a principal axis: its
        free motion is in closed form, :mod:`tumble.core.gyrostat`); None for
        any other body."""
        axes = [part.gyrostatic_axis for part in self.parts]
        if not axes or any(a is None for a in axes):
            return None
        axis = axes[0]
        assert axis is not None
        if any(abs(abs(float(a @ axis)) - 1.0) > 1e-12 for a in axes if a is not None):
            return None
        turned = self.platform_inertia @ axis
        off = turned - float(axis @ turned) * axis
        if math.hypot(*off) > 1e-12 * float(np.trace(self.platform_inertia)):
            return None
        return np.asarray(axis, dtype=float)

    def symmetric_gyrostat_axis(self: BodyModel) -> int | None:
        """The index (0 or 2) of the principal axis of symmetry of a body whose
        platform moments are equal about the other two and whose parts are rotors
        on that axis, free of motors (a symmetric gyrostat: its free motion is a
        steady precession, in closed form); None for any other body."""
        moments = self.moments
        if moments[0] == moments[1] and moments[1] != moments[2]:
            axis = 2
        elif moments[1] == moments[2] and moments[0] != moments[1]:
            axis = 0
        else:
            return None
        for part in self.parts:
            along = part.gyrostatic_axis
            if along is None or abs(abs(float(self.to_principal(along)[axis])) - 1.0) > 1e-12:
                return None
        return axis

    def is_symmetric_top(self: BodyModel) -> bool:
        """True for a body on a pivot with two equal principal moments about the
        pivot and its centre of mass on the third axis (a Lagrange top): then
        the component of L along that axis is conserved under gravity."""
        if self.pivot is None:
            return False
        size = float(np.linalg.norm(self.lever))
        if size == 0.0:
            return False
        moments, axes = self.moments, self.axes
        along = np.abs(axes.T @ (self.lever / size))
        close = PHYSICAL_TOLERANCE * float(moments.sum())
        for axis, (i, j) in ((0, (1, 2)), (2, (0, 1))):
            if abs(moments[i] - moments[j]) <= close and along[axis] >= 1 - 1e-9:
                return True
        return False

    def symmetric_top_axis(self: BodyModel) -> Array | None:
        """The unit symmetry axis (body axes, from the pivot towards the centre of
        mass) of a Lagrange top without parts: a body on a pivot whose principal
        moments about the pivot are equal about two axes (as
        :func:`tumble.massprops.principal_decomposition` makes repeated moments
        equal) and whose centre of mass lies on the third, off the pivot. Its
        motion under uniform gravity is in closed form
        (:mod:`tumble.core.lagrange`). None for any other body."""
        if self.pivot is None or self.parts:
            return None
        size = float(np.linalg.norm(self.lever))
        if size == 0.0:
            return None
        moments, axes = self.moments, self.axes
        if moments[0] == moments[2]:  # every axis through the pivot is principal
            return np.asarray(self.lever / size)
        for axis, (i, j) in ((0, (1, 2)), (2, (0, 1))):
            if moments[i] == moments[j]:
                along = float(axes[:, axis] @ self.lever) / size
                if abs(along) >= 1.0 - 1e-12:
                    return np.asarray(axes[:, axis] * math.copysign(1.0, along))
        return None
