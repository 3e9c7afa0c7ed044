"""The memory budget of a request, checked before any work, and the most
steps a run may take (:data:`DEFAULT_MAX_STEPS`).

A simulation keeps its recorded samples in memory. Before it starts,
:func:`check_memory` compares the memory they will take with the budget and
refuses, with the estimate and how to ask for less, a request that cannot fit,
instead of failing deep inside numpy (or being killed by the operating system)
after minutes of work.

The budget is half of the memory this process may use (:func:`usable_memory`):
the smallest of the machine's memory, the memory limit of its cgroup (v1 or
v2, its own or an ancestor's), and what its resource limits leave: the
address-space limit (``ulimit -v``) less the address space it has mapped
already (the compiled kernels' code and libraries take hundreds of MB), the
data limit (``ulimit -d``) less its data. Set the environment variable
``TUMBLE_MEMORY_BUDGET`` to another amount (``"64 GiB"``, ``"500 MB"``, or a
number of bytes) to change it; it is read at each call.

A request of at most :data:`SMALL_REQUEST` bytes is checked against
``TUMBLE_MEMORY_BUDGET`` when it is set, and otherwise passes without reading
the machine's limits (files under ``/proc`` and ``/sys``: 0.1 ms, the most of
a short simulation's set-up).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable
from pathlib import Path

from tumble.errors import InputError, RequestTooLargeError

__all__ = [
    "BUDGET_VARIABLE",
    "DEFAULT_FRACTION",
    "DEFAULT_MAX_STEPS",
    "DEFAULT_MAX_STEPS_TEXT",
    "SMALL_REQUEST",
    "budget_is_set",
    "check_memory",
    "format_bytes",
    "machine_memory",
    "memory_budget",
    "usable_memory",
]

#: The environment variable that sets the memory budget.
BUDGET_VARIABLE = "TUMBLE_MEMORY_BUDGET"

#: The share of the usable memory a request may take by default: the rest is
#: left for the process's other data, its temporaries and the other programs.
DEFAULT_FRACTION = 0.5

#: The most integration steps a run may take unless it asks for more
#: (:func:`tumble.simulate`'s ``max_steps``; the limit of scenario files): a
#: few seconds to a minute of the compiled kernels. An adaptive run on a stiff
#: problem, whose steps follow its fastest time scale, stops there rather than
#: run for hours. ``DEFAULT_MAX_STEPS_TEXT`` is how messages write it.
DEFAULT_MAX_STEPS = 50_000_000
DEFAULT_MAX_STEPS_TEXT = f"{DEFAULT_MAX_STEPS:.0e}".replace("e+0", "e")

#: Requests of at most this many bytes fit the default budget of any machine
#: that runs tumble: a process that has imported numpy and numba has mapped
#: hundreds of MB already, so half of what it may use is far above 1 MiB, and a
#: process whose limits leave it less fails on its next allocation, checked or
#: not. :func:`check_memory` does not read the machine's limits for them.
SMALL_REQUEST = 2**20

# Where the kernel shows this process's cgroups and status, and where the cgroup
# hierarchies are mounted.
_PROC_SELF = Path("/proc/self")
_CGROUP_ROOT = Path("/sys/fs/cgroup")

# The memory limit file of each hierarchy: (its mount under the root, the file,
# cgroup v2 or v1). v2 is mounted at the root, or at "unified" beside v1's
# controllers (the hybrid layout).
_HIERARCHIES = (
    ("", "memory.max", "v2"),
    ("unified", "memory.max", "v2"),
    ("memory", "memory.limit_in_bytes", "v1"),
)


def usable_memory() -> tuple[int, str]:
    """The memory this process may use, bytes, and where that number comes from.

    The smallest of: the machine's physical memory; the memory limit of the
    cgroup this process is in or of any cgroup above it (v2 ``memory.max``, v1
    ``memory.limit_in_bytes``; each applies to everything below it); its
    address-space limit (``RLIMIT_AS``, ``ulimit -v``) less its mapped address
    space (``VmSize``: a limit on address space counts what is mapped, not what
    is used); its data limit (``RLIMIT_DATA``, ``ulimit -d``) less its data
    (``VmData``).
    """
    try:
        physical = int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # not a POSIX system
        physical = 8 * 2**30
    candidates = [(physical, "the machine's memory"), *_cgroup_limits(), *_process_limits()]
    return min(candidates, key=lambda candidate: candidate[0])


def machine_memory() -> int:
    """The memory this process may use, bytes (:func:`usable_memory`)."""
    return usable_memory()[0]


def _cgroup_limits() -> list[tuple[int, str]]:
    """The memory limits (bytes, and the file that sets each) of this process's
    cgroups and their ancestors, in every hierarchy mounted under ``_CGROUP_ROOT``."""
    paths = {"v2": "/", "v1": "/"}
    try:
        lines = (_PROC_SELF / "cgroup").read_text().splitlines()
    except OSError:
        lines = []
    for line in lines:  # "hierarchy-id:controllers:path"
        controllers, _, path = line.partition(":")[2].partition(":")
        if controllers == "":
            paths["v2"] = path
        elif "memory" in controllers.split(","):
            paths["v1"] = path
    found = []
    for mount, name, version in _HIERARCHIES:
        parts = [part for part in paths[version].split("/") if part]
        if ".." in parts:  # a cgroup outside this namespace: only its root is visible
            parts = []
        # The cgroup, then each ancestor up to the mount's root: a path of the
        # host that the container's mount does not show is skipped.
        for depth in range(len(parts), -1, -1):
            file = _CGROUP_ROOT.joinpath(mount, *parts[:depth], name)
            try:
                text = file.read_text().strip()
            except OSError:
                continue
            if text.isdigit():
                found.append((int(text), f"the memory limit of its cgroup, {file}"))
    return found


def _process_limits() -> list[tuple[int, str]]:
    """What this process's address-space and data limits leave it, bytes, with
    the limit and what it uses already (none where no limit is set)."""
    try:
        import resource
    except ImportError:  # not a POSIX system
        return []
    try:
        status = (_PROC_SELF / "status").read_text()
    except OSError:
        status = ""
    used = {}
    for line in status.splitlines():
        key, _, value = line.partition(":")
        fields = value.split()
        if len(fields) == 2 and fields[0].isdigit() and fields[1] == "kB":
            used[key] = int(fields[0]) * 1024
    found = []
    for which, flag, what, field, verb in (
        (resource.RLIMIT_AS, "ulimit -v", "address-space", "VmSize", "it has mapped"),
        (resource.RLIMIT_DATA, "ulimit -d", "data", "VmData", "of data it holds"),
    ):
        soft, _ = resource.getrlimit(which)
        if soft == resource.RLIM_INFINITY or soft < 0:
            continue
        taken = used.get(field, 0)
        found.append(
            (
                max(soft - taken, 0),
                f"its {what} limit ({flag}) of {format_bytes(soft)} less the "
                f"{format_bytes(taken)} {verb}",
            )
        )
    return found


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
    usable, why = usable_memory()
    return DEFAULT_FRACTION * usable, (
        f"half of the {format_bytes(usable)} this process may use, {why}; set "
        f"{BUDGET_VARIABLE} to change it"
    )


@functools.lru_cache(maxsize=16)
def _parse_amount(text: str) -> float:
    """Bytes from ``"64 GiB"``, ``"500 MB"`` or a plain number of bytes (read once
    per text)."""
    from tumble.units import quantity

    try:
        value = float(text)
    except ValueError:
        try:
            value = float(quantity(text, BUDGET_VARIABLE).to("byte").magnitude)
        except Exception:  # an unreadable text, or one that is no amount of memory
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


def budget_is_set() -> bool:
    """Whether ``TUMBLE_MEMORY_BUDGET`` is set (to more than blanks): then even a
    small request is checked (:func:`check_memory`)."""
    if _ENVIRONMENT is not None and _BUDGET_KEY not in _ENVIRONMENT:
        return False
    value = os.environ.get(BUDGET_VARIABLE)
    return value is not None and value.strip() != ""


# ``os.environ.get`` of a name that is not set raises KeyError and catches it twice
# inside ``os`` (``Mapping.get`` over ``_Environ.__getitem__``): 11 µs when the
# processor's caches are cold, a tenth of a short run repeated (bench/cold_call.py).
# The mapping keeps its entries in a dict by their encoded names (``_data``,
# ``encodekey``: CPython's ``os`` since 3.2), which tells at once that the name is not
# there; where it has not both, the public path alone.
_ENCODED: Callable[[str], object] | None = getattr(os.environ, "encodekey", None)
_DATA = getattr(os.environ, "_data", None)
_ENVIRONMENT: dict[object, object] | None = None
_BUDGET_KEY: object = None
if isinstance(_DATA, dict) and _ENCODED is not None:
    _ENVIRONMENT, _BUDGET_KEY = _DATA, _ENCODED(BUDGET_VARIABLE)


def check_memory(needed: float, what: str | Callable[[], str], advice: str) -> None:
    """Refuse a request that needs ``needed`` bytes when the budget is smaller.

    ``what`` describes the request (e.g. "9.1e+11 samples of 8 values"; or a
    function that writes it, called only for the message), ``advice`` how to
    ask for less.

    Raises
    ------
    RequestTooLargeError
        With the estimate, the budget and the advice.
    """
    if needed <= SMALL_REQUEST and not budget_is_set():
        return
    budget, source = memory_budget()
    if needed > budget:
        what = what if isinstance(what, str) else what()
        raise RequestTooLargeError(
            f"Expected a request that fits in the memory budget of {format_bytes(budget)} "
            f"({source}), got {what}: about {format_bytes(needed)}. {advice}"
        )
