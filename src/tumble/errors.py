"""Exceptions raised by tumble for bad input.

Every message follows one template: name the value, state what was expected,
show what was received, e.g. ``Expected `mass` > 0 kg, got -1.0.``
"""

from __future__ import annotations

__all__ = ["InputError", "MeshError"]


class InputError(ValueError):
    """A value given to tumble is invalid: wrong shape, units, range or physics."""


class MeshError(InputError):
    """A triangle mesh cannot bound a solid: open, non-manifold, badly wound or empty."""
