"""STEP files, tessellated by OpenCASCADE (through cascadio) in a child process.

OpenCASCADE's STEP reader can end the process that calls it with a
segmentation fault on a damaged file (a few bytes inserted into an entity's
name are enough). Run in a child process, such a crash ends the child only and
becomes an :class:`~tumble.InputError` that names the file. The messages
OpenCASCADE prints on the standard output stay out of the user's terminal too.
The child writes a GLB file (in metres), which trimesh reads as it would have
read the STEP file.

The child is bounded, so that no file can take the machine:

* a time limit, :data:`DEFAULT_TIME_LIMIT` seconds unless the environment
  variable ``TUMBLE_STEP_TIME_LIMIT`` (seconds, or a time such as
  ``"10 min"``) or the ``time_limit`` argument says otherwise;
* a memory limit (the address space it may add to what it holds once
  started), the memory budget of :func:`tumble.resources.memory_budget`
  (``TUMBLE_MEMORY_BUDGET``) unless the ``memory_limit`` argument says otherwise;
* it ends with the process that started it: on Linux the kernel kills it when
  its parent ends, however that ends (``PR_SET_PDEATHSIG``), and the parent
  kills its process group when it stops waiting for it (a limit, an exception,
  Ctrl-C).

Numbers OpenCASCADE would read as NaN or infinity are refused before it runs:
it meshes a NaN coordinate for minutes.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tumble.errors import (
    QUOTED_PATH_LENGTH,
    InputError,
    MeshError,
    RequestTooLargeError,
    quoted,
)
from tumble.resources import BUDGET_VARIABLE, format_bytes, memory_budget

__all__ = ["DEFAULT_TIME_LIMIT", "STEP_SUFFIXES", "TIME_LIMIT_VARIABLE", "tessellate_step"]

#: The file name endings read as STEP.
STEP_SUFFIXES = (".step", ".stp")

#: The environment variable that sets the time limit of a conversion.
TIME_LIMIT_VARIABLE = "TUMBLE_STEP_TIME_LIMIT"

#: The time a conversion may take by default, s: OpenCASCADE meshes parts and
#: assemblies of thousands of faces in seconds.
DEFAULT_TIME_LIMIT = 300.0

# The chord tolerance of the tessellation, relative to the size of each edge
# and face: the triangles, and so the relative error of the mass properties, do
# not depend on the unit of the file (an absolute tolerance asks a part written
# in kilometres for a million times more segments along each curve, and
# gigabytes). 5e-4 meshes a hole of radius 5 mm as finely as 0.01 mm would.
_TOLERANCE = 5e-4

# Exit codes of the child besides 0 (done): cascadio missing, the reader refused
# the file, its parent ended before it could be tied to it, out of memory.
_MISSING, _REFUSED, _ORPHANED, _OUT_OF_MEMORY = 3, 4, 5, 6

# A child that ends abnormally having used this share of its memory limit ran
# into it: a child stopped by the limit has used 0.9 to 0.97 of it (measured),
# one crashing on a damaged file the ~0.15 GB of the interpreter and libraries.
_AT_THE_LIMIT = 0.75

# What the child runs before converting: tied to its parent's life, then its
# address space limited to what it holds now plus its memory limit (what it holds
# now is mostly libraries mapped but never read, so that the limit is about the
# memory the conversion takes). sys.argv: step, glb, parent's pid, limit (bytes,
# 0: none).
_START = f"""
import os, sys
if sys.platform.startswith("linux"):
    import ctypes, signal
    ctypes.CDLL(None).prctl(1, signal.SIGKILL, 0, 0, 0)  # 1: PR_SET_PDEATHSIG
if os.getppid() != int(sys.argv[3]):  # the parent ended before the line above
    sys.exit({_ORPHANED})
try:
    import cascadio
except ImportError as exc:
    sys.stderr.write(str(exc))
    sys.exit({_MISSING})
limit = int(sys.argv[4])
if limit > 0:
    import resource
    try:
        with open("/proc/self/statm") as statm:
            size, resident = (int(n) * os.sysconf("SC_PAGE_SIZE") for n in statm.read().split()[:2])
    except OSError:  # not Linux: the limit is on the whole address space
        size = resident = 0
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    allowed = limit + size - resident
    if hard != resource.RLIM_INFINITY:
        allowed = min(allowed, hard)
    resource.setrlimit(resource.RLIMIT_AS, (allowed, hard))
"""

# The conversion itself (a separate piece so that tests can put a slow one in its place).
_CONVERSION = f"""
try:
    status = cascadio.step_to_glb(
        sys.argv[1], sys.argv[2], merge_primitives=True, tol_relative=True,
        tol_linear={_TOLERANCE!r},
    )
except MemoryError:
    sys.exit({_OUT_OF_MEMORY})
sys.exit(0 if status == 0 else {_REFUSED})
"""

# STEP text that OpenCASCADE would read as a number that is not finite: "NaN",
# "inf", "infinity" (with a sign or not), and reals whose exponent has three
# digits (1.E999 overflows). Strings ('...', quotes doubled inside) and comments
# are matched too, so as to be skipped: a name may say "NaN".
_NOT_FINITE = re.compile(
    rb"'(?:[^']|'')*'|/\*.*?\*/"
    rb"|(?<![\w.])([+-]?(?:nan|inf(?:inity)?)|[+-]?\d+\.\d*e[+-]?\d{3,})(?![\w(.])",
    re.IGNORECASE | re.DOTALL,
)
# Text that any of them contains: most files have none, and are not scanned.
_SUSPECT = re.compile(rb"nan|inf|e[+-]?\d{3}", re.IGNORECASE)


def tessellate_step(
    step: Path,
    glb: Path,
    *,
    time_limit: float | None = None,
    memory_limit: float | None = None,
) -> None:
    """Write the triangles of the STEP file ``step`` to the GLB file ``glb``.

    Parameters
    ----------
    step, glb : the file to read, the file to write (in metres).
    time_limit : the longest the conversion may take, s; default
        ``TUMBLE_STEP_TIME_LIMIT`` or :data:`DEFAULT_TIME_LIMIT`.
    memory_limit : the most memory the conversion may add to the child
        process, bytes; default the memory budget
        (:func:`tumble.resources.memory_budget`).

    Raises
    ------
    MeshError
        A number in the file that is not finite (NaN, inf, an overflowing exponent).
    RequestTooLargeError
        The conversion reached its memory limit (the message names it and how to raise it).
    InputError
        cascadio is not installed, OpenCASCADE cannot read the file, crashed
        reading it, or did not finish within the time limit (the message names
        it and how to raise it); a ``TUMBLE_STEP_TIME_LIMIT`` that is not a
        time > 0.
    """
    seconds, time_source = _time_limit(time_limit)
    if memory_limit is None:
        memory, memory_source = memory_budget()
        more_memory = f"set {BUDGET_VARIABLE} to a larger amount"
    else:
        memory, memory_source = float(memory_limit), "the `memory_limit` argument"
        more_memory = "give a larger `memory_limit`"
        if not memory > 0:
            raise InputError(f"Expected `memory_limit` > 0 bytes, got {memory_limit!r}.")
    more_time = (
        "give a longer `time_limit`"
        if time_limit is not None
        else f"set {TIME_LIMIT_VARIABLE} to more seconds"
    )
    _check_numbers(step)
    name = quoted(step, QUOTED_PATH_LENGTH)
    with tempfile.TemporaryFile() as errors:
        child = subprocess.Popen(
            [
                sys.executable,
                "-c",
                _START + _CONVERSION,
                str(step),
                str(glb),
                str(os.getpid()),
                str(int(memory)) if math.isfinite(memory) else "0",
            ],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=errors,
            start_new_session=True,  # its own process group, killed as one
            # glibc's malloc reserves 64 MB of address space per thread (OpenCASCADE
            # meshes on every core): two arenas keep the memory limit about memory.
            env={"MALLOC_ARENA_MAX": "2", **os.environ},
        )
        try:
            ended = _wait(child, seconds)
        finally:
            if child.returncode is None:  # over the time limit, or interrupted
                _kill(child)
        errors.seek(0)
        message = errors.read().decode(errors="replace").strip()
    if ended is None:
        raise InputError(
            f"Expected OpenCASCADE to read {name} within its time limit of {seconds:g} s "
            f"({time_source}), got a conversion still running then: {more_time} to let it "
            "finish."
        )
    code, peak = ended
    if code == 0 and glb.is_file():
        return
    if code == _MISSING:
        raise InputError(f"Reading {name} needs a package that is not installed: {message}.")
    if code == _OUT_OF_MEMORY or (code not in (0, _REFUSED) and peak >= _AT_THE_LIMIT * memory):
        raise RequestTooLargeError(
            f"Expected OpenCASCADE to read {name} within its memory limit of "
            f"{format_bytes(memory)} ({memory_source}), got a conversion that reached it: "
            f"{more_memory} to let it finish."
        )
    if code in (0, _REFUSED):
        why = "OpenCASCADE could not read it"
    elif code < 0:
        why = f"OpenCASCADE crashed reading it (signal {-code})"
    else:
        last = (message.splitlines() or ["no message"])[-1]
        why = f"OpenCASCADE failed reading it (exit code {code}: {last})"
    raise InputError(f"Expected `mesh` to be a readable STEP file, got {name}: {why}.")


def _time_limit(given: float | None) -> tuple[float, str]:
    """The time limit, s, and where it comes from (for messages)."""
    if given is not None:
        seconds, source, text = float(given), "the `time_limit` argument", repr(given)
    else:
        text = os.environ.get(TIME_LIMIT_VARIABLE, "").strip()
        if not text:
            return DEFAULT_TIME_LIMIT, "the default"
        source = f"{TIME_LIMIT_VARIABLE} = {text}"
        try:
            seconds = float(text)
        except ValueError:
            from tumble.units import to_si

            try:
                seconds = to_si(text, "time", TIME_LIMIT_VARIABLE)
            except InputError:
                seconds = math.nan
        text = repr(text)
    if not (seconds > 0 and math.isfinite(seconds)):
        raise InputError(
            f"Expected {TIME_LIMIT_VARIABLE} to be a time > 0 s such as '600' or '10 min', "
            f"got {text}."
        )
    return seconds, source


def _check_numbers(step: Path) -> None:
    """Refuse a STEP file with a number that is not finite, naming it and its line."""
    try:
        data = step.read_bytes()
    except OSError:
        return  # OpenCASCADE's reader says what is wrong with the file
    if not _SUSPECT.search(data):
        return
    for match in _NOT_FINITE.finditer(data):
        token = match.group(1)
        if token is not None and not math.isfinite(float(token)):
            line = data.count(b"\n", 0, match.start()) + 1
            raise MeshError(
                f"Expected finite numbers in the STEP file {quoted(step, QUOTED_PATH_LENGTH)}, got "
                f"{token.decode()} at line {line}."
            )


def _wait(child: subprocess.Popen[bytes], seconds: float) -> tuple[int, float] | None:
    """Wait for ``child`` at most ``seconds``: its exit code (``-signal`` when a
    signal ended it) and its peak resident memory, bytes; None if still running.

    ``os.wait4`` rather than ``Popen.wait``: it gives this child's own peak
    memory, which tells a child stopped by its memory limit from one that crashed.
    """
    if not hasattr(os, "wait4"):  # not POSIX: no peak memory
        try:
            return child.wait(timeout=seconds), 0.0
        except subprocess.TimeoutExpired:
            return None
    deadline = time.monotonic() + seconds
    pause = 0.001
    while True:
        pid, status, usage = os.wait4(child.pid, os.WNOHANG)
        if pid == child.pid:
            child.returncode = os.waitstatus_to_exitcode(status)
            # ru_maxrss is in KiB on Linux, in bytes on macOS.
            scale = 1 if sys.platform == "darwin" else 1024
            return child.returncode, float(usage.ru_maxrss * scale)
        left = deadline - time.monotonic()
        if left <= 0:
            return None
        time.sleep(min(pause, left))
        pause = min(2 * pause, 0.05)


def _kill(child: subprocess.Popen[bytes]) -> None:
    """Kill ``child``'s process group (it leads it) and reap it."""
    with contextlib.suppress(ProcessLookupError):  # ended meanwhile
        if hasattr(os, "killpg"):
            os.killpg(child.pid, signal.SIGKILL)
        else:
            child.kill()
    child.wait()
