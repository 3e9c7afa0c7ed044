"""The base of every table of a configuration file: strict, frozen pydantic models.

A typo in a key must not be ignored silently (the value would fall back to its
default and the run would answer another question than the one asked), so an
unknown key is an error, and its message suggests the nearest known key.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, model_validator

from tumble.config.errors import unknown_key

__all__ = ["StrictModel"]


class StrictModel(BaseModel):
    """Frozen, and an unknown key is an error that suggests the nearest known one."""

    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        # Before pydantic's own "extra" check, whose message names neither the
        # known keys nor the nearest one.
        if isinstance(data, dict):
            known = list(cls.model_fields)
            for key in data:
                if key not in known:
                    raise unknown_key(str(key), known)
        return data
