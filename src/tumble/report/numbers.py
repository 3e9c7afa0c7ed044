"""Numbers written into the viewer's page, rounded to what a screen can show."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["DIGITS", "rounded"]

#: Significant digits kept in the page's numbers: far below a pixel at any zoom.
DIGITS = 5


def rounded(values: Any) -> Any:
    """``values`` as nested lists, rounded to :data:`DIGITS` significant digits
    of their largest magnitude (non-finite values as 0)."""
    array = np.asarray(values, dtype=float)
    scale = float(np.max(np.abs(array))) if array.size else 0.0
    if scale == 0.0 or not np.isfinite(scale):
        return np.nan_to_num(array).tolist()
    decimals = max(0, DIGITS - int(np.floor(np.log10(scale))) - 1)
    return np.round(array, decimals).tolist()
