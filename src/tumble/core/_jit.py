"""The one place where numba is configured for the compiled core.

Every kernel is decorated with :data:`njit` (or :data:`njit_parallel`,
:data:`njit_vector`) from this module, so compilation options are set once:

* ``cache=True`` writes compiled machine code next to the sources, so only the
  first process pays the compile time (about a second per kernel).
* ``TUMBLE_NUMBA_CACHE=0`` disables that cache (read-only installs, debugging).
* ``NUMBA_DISABLE_JIT=1`` (numba's own switch) runs every kernel as plain
  Python, which the test suite uses once so coverage sees the kernels.

Kernels specialised for one combination of torque models are closures built by
a factory (:func:`specialise`): the torque functions are compile-time constants
of the closure, so the compiler inlines them and vectorises across bodies. numba
keys its on-disk cache of a closure by pickling the closure's cells, which for
compiled functions changes in every process; :func:`specialise` keys it by a
stable description of what was compiled instead.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
from collections.abc import Callable
from functools import cache, lru_cache, partial
from pathlib import Path
from typing import Any

import numba
from numba.core.caching import FunctionCache

CACHE = os.environ.get("TUMBLE_NUMBA_CACHE", "1").strip().lower() not in {"0", "false", "no", "off"}

#: Serial kernels: no fastmath, so IEEE semantics (NaN, inf, summation order) hold.
njit: Any = partial(numba.njit, cache=CACHE, nogil=True, error_model="numpy")

#: Kernels that split their outer loop across threads with ``numba.prange``.
njit_parallel: Any = partial(
    numba.njit, cache=CACHE, nogil=True, error_model="numpy", parallel=True
)

prange: Any = numba.prange

#: The floating-point freedoms of the kernels vectorised across bodies: the
#: compiler may contract to FMA and reassociate, but NaN and infinity keep their
#: meaning (no 'nnan'/'ninf'), so a diverging state is still detected.
VECTOR_FASTMATH = frozenset({"contract", "arcp", "nsz", "reassoc", "afn"})

#: Kernels vectorised across bodies, in parallel over blocks of them.
njit_vector: Any = partial(
    numba.njit,
    cache=CACHE,
    nogil=True,
    error_model="numpy",
    parallel=True,
    fastmath=set(VECTOR_FASTMATH),
)

#: The work on one block of a kernel vectorised across bodies, with the same
#: freedoms, called from the kernel's parallel loop. A function of its own, not
#: inlined into that loop: numba's analyses of a parallel loop take time that
#: grows faster than the loop's body (a splitting's measuring kernel, a few
#: thousand lines once inlined, took over a minute to compile there and takes
#: seconds so). Not cached itself: the kernels that call it are, with it.
njit_block: Any = partial(
    numba.njit, cache=False, nogil=True, error_model="numpy", fastmath=set(VECTOR_FASTMATH)
)

#: The work on one block of a batch kernel's steps, inlined into the kernel's
#: parallel loop, whose analysis stays quick for a loop of steps alone. Compiled as a
#: function of its own and called, the work on a block under a torque ran 3.5×
#: slower in the process that compiled it than in a process that loaded the kernel
#: from the cache (``bench/compiled_here.py``); inlined, it runs as fast in both.
njit_block_inline: Any = partial(njit_block, inline="always")

#: The statuses kernels return: every step stayed finite (else the number of
#: the first step that did not).
FINITE = -1


@cache
def core_stamp() -> str:
    """A digest of the size and modification time of every source file of the
    compiled core: part of every specialised kernel's cache key, so editing any
    kernel the closures inline invalidates them (numba itself checks only the
    file that defines the closure)."""
    digest = hashlib.sha256()
    for path in sorted(Path(__file__).parent.glob("*.py")):
        status = path.stat()
        digest.update(f"{path.name}:{status.st_mtime_ns}:{status.st_size};".encode())
    return digest.hexdigest()


def file_stamp(function: Any) -> str:
    """``module.qualname@mtime:size`` of a (compiled) function's source file, or its
    name alone when it has no file (then its kernels are not cached on disk).

    Read once per function and process, as :func:`core_stamp`: it describes the
    code this process loaded (and binding a torque to a body asks for it at
    every simulation)."""
    python = getattr(function, "py_func", function)
    try:
        return _read_stamp(python)
    except TypeError:  # not hashable: read each time
        return _read_stamp.__wrapped__(python)


@lru_cache(maxsize=1024)
def _read_stamp(python: Any) -> str:
    name = f"{python.__module__}.{python.__qualname__}"
    try:
        status = os.stat(python.__code__.co_filename)
    except OSError:
        return name
    return f"{name}@{status.st_mtime_ns}:{status.st_size}"


def own_name(identity: str) -> Callable[[Any], Any]:
    """Give a closure a qualified name of its own per ``identity`` (what its code
    depends on, as for :func:`specialise`), before it is compiled.

    numba names a compiled function's symbols after its qualified name and a
    counter of the process that compiled it, so two closures of one factory
    compiled in different processes can share symbol names; a process that
    loads both from the cache (in a kernel that calls them) then runs one body
    for both (numba issue #10486). Every closure compiled into a cached kernel
    and not inlined into it (the kernels themselves, the work on one block)
    takes a name of its own so."""

    def rename(function: Any) -> Any:
        tag = hashlib.sha256(identity.encode()).hexdigest()[:16]
        function.__qualname__ = f"{function.__qualname__}_{tag}"
        return function

    return rename


def specialise(decorator: Any, identity: str) -> Callable[[Any], Any]:
    """Compile a closure with ``decorator`` (:data:`njit`, :data:`njit_parallel` or
    :data:`njit_vector`), cached on disk under ``identity``.

    ``identity`` must name everything the closure's code depends on besides its
    own bytecode and argument types: the factory, the compiled functions it
    closes over and their source stamps (:func:`file_stamp`), and any constant.
    """

    def compile_closure(function: Any) -> Any:
        dispatcher = decorator(cache=False)(own_name(identity)(function))
        if CACHE and not numba.config.DISABLE_JIT:  # type: ignore[attr-defined]
            # numba raises RuntimeError when it finds no writable cache location:
            # then the closure compiles in each process.
            with contextlib.suppress(RuntimeError):
                dispatcher._cache = _IdentityCache(function, f"{identity}|{core_stamp()}")
        return dispatcher

    return compile_closure


class _IdentityCache(FunctionCache):
    """numba's function cache keyed by an identity string instead of the pickled
    closure cells (which hold compiled functions, pickled differently per process)."""

    def __init__(self, function: Any, identity: str) -> None:
        self._identity = identity
        super().__init__(function)

    def _index_key(self, sig: Any, codegen: Any) -> tuple[Any, ...]:
        code = self._py_func.__code__.co_code
        return (
            sig,
            codegen.magic_tuple(),
            (hashlib.sha256(code).hexdigest(), hashlib.sha256(self._identity.encode()).hexdigest()),
        )
