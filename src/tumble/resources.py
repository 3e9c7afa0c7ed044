"""The memory budget of a request, checked before any work.

A simulation keeps its recorded samples in memory. Before it starts,
:func:`check_memory` compares the memory they will take with the budget and
refuses, with the estimate and how to ask for less, a request that cannot fit,
instead of failing deep inside numpy (or being killed by the operating system)
after minutes of work.

The budget is half of the memory this process may use: the machine's memory,
or the limit of its container (cgroup) when that is lower. Set the environment
variable ``TUMBLE_MEMORY_BUDGET`` to another amount (``"64 GiB"``, ``"500 MB"``,
or a number of bytes) to change it; it is read at each call.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from tumble.errors import InputError, RequestTooLargeError

__all__ = [
    "BUDGET_VARIABLE",
    "DEFAULT_FRACTION",
    "check_memory",
    "format_bytes",
    "machine_memory",
    "memory_budget",
]

#: The environment variable that sets the memory budget.
BUDGET_VARIABLE = "TUMBLE_MEMORY_BUDGET"

#: The share of the usable memory a request may take by default: the rest is
#: left for the process's other data, its temporaries and the other programs.
DEFAULT_FRACTION = 0.5

# cgroup v2, then v1: the memory limit of the container this process runs in.
_CGROUP_LIMITS = (
    Path("/sys/fs/cgroup/memory.max"),
    Path("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
)


def machine_memory() -> int:
    """The memory this process may use, bytes: the physical memory, or the
    limit of its container when that is lower."""
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # not a POSIX system
        physical = 8 * 2**30
    usable = int(physical)
    for limit in _CGROUP_LIMITS:
        try:
            text = limit.read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            usable = min(usable, int(text))
    return usable


def memory_budget() -> tuple[float, str]:
    """The memory a request may take, bytes, and where that number comes from
    (for messages).

    Raises
    ------
    InputError
        A ``TUMBLE_MEMORY_BUDGET`` that is not a positive amount of memory.
    """
    text = os.environ.get(BUDGET_VARIABLE, "").strip()
    if text:
        return _parse_amount(text), f"{BUDGET_VARIABLE} = {text}"
    usable = machine_memory()
    return DEFAULT_FRACTION * usable, (
        f"half of the {format_bytes(usable)} this process may use; set {BUDGET_VARIABLE} "
        "to change it"
    )


def _parse_amount(text: str) -> float:
    """Bytes from ``"64 GiB"``, ``"500 MB"`` or a plain number of bytes."""
    from tumble.units import ureg

    try:
        value = float(text)
    except ValueError:
        try:
            value = float(ureg.Quantity(text).to("byte").magnitude)
        except Exception:  # pint raises several kinds for text it cannot read
            value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise InputError(
            f"Expected {BUDGET_VARIABLE} to be an amount of memory > 0 such as '16 GiB', "
            f"got {text!r}."
        )
    return value


def format_bytes(amount: float) -> str:
    """``1.5 GiB``: an amount of memory for people."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(amount) < 1024 or unit == "PiB":
            # Three significant digits, without an exponent from 1000 to 1023.
            return f"{amount:.3g} {unit}" if abs(amount) < 1000 else f"{amount:.0f} {unit}"
        amount /= 1024
    raise AssertionError("unreachable")


def check_memory(needed: float, what: str, advice: str) -> None:
    """Refuse a request that needs ``needed`` bytes when the budget is smaller.

    ``what`` describes the request (e.g. "9.1e+11 samples of 8 values"),
    ``advice`` how to ask for less.

    Raises
    ------
    RequestTooLargeError
        With the estimate, the budget and the advice.
    """
    budget, source = memory_budget()
    if needed > budget:
        raise RequestTooLargeError(
            f"Expected a request that fits in the memory budget of {format_bytes(budget)} "
            f"({source}), got {what}: about {format_bytes(needed)}. {advice}"
        )
