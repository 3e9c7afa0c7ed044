"""Exceptions raised by tumble for bad input.

Every message follows one template: name the value, state what was expected,
show what was received, e.g. ``Expected `mass` > 0 kg, got -1.0.``
"""

from __future__ import annotations

__all__ = ["CoarseStepWarning", "InputError", "IntegrationError", "MeshError"]


class InputError(ValueError):
    """A value given to tumble is invalid: wrong shape, units, range or physics."""


class MeshError(InputError):
    """A triangle mesh cannot bound a solid: open, non-manifold, badly wound or empty."""


class IntegrationError(InputError):
    """The integration produced NaN or infinity (usually: ``dt`` far too large)."""


class CoarseStepWarning(UserWarning):
    """The time step is too coarse for the fastest rotation of the body."""
