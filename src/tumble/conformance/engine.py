"""One physics engine stepping one rigid body: the adapter every engine implements.

An adapter is a subclass of :class:`Engine` registered with
:func:`register_engine`. It builds one rigid body from mass properties given in
its principal axes (:class:`EngineBody`), sets its attitude and angular
velocity, steps it at a fixed ``dt`` and reads the state back; the suite
(:func:`tumble.conformance.run`) does the rest. Engines that integrate a whole
run at once (an ODE solver with its own steps) override :meth:`Engine.simulate`
instead.

Every adapter declares in which axes its engine stores the angular velocity
(:attr:`Engine.omega_frame`), reads back the mass and inertia the engine really
uses (:meth:`Engine.inertia`: the suite refuses to run an engine whose values
differ from those given) and reports what the engine did on its own: warnings,
resets, sleeping bodies (:meth:`Engine.failure`, :attr:`Engine.notes`).
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib.util
import math
import os
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.errors import InputError, uncoloured, unknown_choice

__all__ = [
    "ENGINES",
    "EXTRA",
    "Engine",
    "EngineBody",
    "NativeOutput",
    "Samples",
    "engine_class",
    "engine_names",
    "missing_modules",
    "register_engine",
    "split_name",
]

Array = NDArray[np.float64]

#: The optional extra that installs the engines of the suite.
EXTRA = "engines"

#: Every registered engine adapter by its engine name ("mujoco"), in registration order.
ENGINES: dict[str, type[Engine]] = {}


@dataclass(frozen=True, eq=False)
class EngineBody:
    """The body an engine builds, in its principal axes; SI units.

    The body's own axes are its principal axes and its origin is its centre of
    mass. With a ``pivot``, that body point is held fixed at the origin of
    space by a ball joint and ``gravity`` acts at the centre of mass.

    Attributes
    ----------
    mass : kg.
    moments : (3,) principal moments of inertia about the centre of mass, kg·m²,
        about body x, y, z (not necessarily ascending).
    pivot : (3,) body point held fixed at the space origin, m, or None (a free body).
    gravity : (3,) gravitational acceleration in space axes, m/s² (zeros: none).
    """

    mass: float
    moments: Array
    pivot: Array | None = None
    gravity: Array = field(default_factory=lambda: np.zeros(3))

    @property
    def inertia(self) -> Array:
        """(3, 3) inertia about the centre of mass in body axes, kg·m²."""
        return np.diag(self.moments)

    @property
    def pivot_inertia(self) -> Array:
        """(3, 3) inertia about the pivot in body axes (the centre of mass without one), kg·m²."""
        if self.pivot is None:
            return self.inertia
        r = np.asarray(self.pivot)
        return self.inertia + self.mass * (float(r @ r) * np.eye(3) - np.outer(r, r))


@dataclass(eq=False)
class Samples:
    """What an engine did over a run: its state at the sample times.

    Attributes
    ----------
    t : (n,) sample times, s.
    quaternion : (n, 4) attitude, scalar first, body → space.
    omega : (n, 3) angular velocity in body axes, rad/s.
    failed_at : time of the first failure, s (NaN if none); samples stop there.
    failure : what failed ("" if nothing).
    wall_time : seconds of wall time the stepping took (building excluded).
    steps : steps taken.
    """

    t: Array
    quaternion: Array
    omega: Array
    failed_at: float = float("nan")
    failure: str = ""
    wall_time: float = 0.0
    steps: int = 0


class Engine:
    """Base of the engine adapters.

    A subclass sets the class attributes and implements :meth:`build`,
    :meth:`inertia`, :meth:`set_state`, :meth:`step` and :meth:`state` (and,
    as needed, :meth:`failure` and :meth:`close`), or overrides
    :meth:`simulate` whole. The variant it runs is ``variant``; notes for
    the user (a setting the adapter changed, such as sleeping turned off) go to
    ``notes``.
    """

    #: The engine's name, the part of "engine/variant" before the slash.
    name: ClassVar[str] = ""
    #: Its variants, each with one line on what it runs; "" is the plain name.
    variants: ClassVar[dict[str, str]] = {}
    #: The Python modules it imports: missing ones make the suite skip it.
    modules: ClassVar[tuple[str, ...]] = ()
    #: The pip extra that installs them.
    extra: ClassVar[str] = EXTRA
    #: In which axes the engine stores the angular velocity (:meth:`set_state`, :meth:`state`).
    omega_frame: ClassVar[Literal["body", "space"]] = "body"
    #: Whether it can hold a body on a pivot (a ball joint) under gravity.
    holds_pivot: ClassVar[bool] = False
    #: How it builds a pivot, one line (shown by the documentation).
    pivot_method: ClassVar[str] = ""
    #: Its floating-point type.
    precision: ClassVar[str] = "float64"

    def __init__(self, variant: str = "") -> None:
        if variant not in self.variants:
            raise unknown_choice(variant, list(self.variants), f"the variant of {self.name}")
        self.variant = variant
        self.notes: list[str] = []

    @property
    def full_name(self) -> str:
        """ "engine/variant", or the engine's name for its plain variant."""
        return f"{self.name}/{self.variant}" if self.variant else self.name

    # -- what an adapter implements ------------------------------------------------
    def build(self, body: EngineBody, dt: float) -> None:
        """Create the engine's world with this one body, stepping at ``dt`` (s)."""
        raise NotImplementedError

    def inertia(self) -> tuple[float, Array]:
        """The mass (kg) and the (3, 3) inertia about the centre of mass in body axes
        (kg·m²) that the engine uses, read back from it."""
        raise NotImplementedError

    def set_state(self, quaternion: Array, omega: Array) -> None:
        """Set the attitude (scalar first, body → space) and the angular velocity (rad/s,
        in :attr:`omega_frame` axes); with a pivot, the linear velocity that keeps the
        pivot still, without one, none."""
        raise NotImplementedError

    def step(self, count: int) -> None:
        """Advance ``count`` steps of ``dt``."""
        raise NotImplementedError

    def state(self) -> tuple[Array, Array]:
        """The attitude (scalar first, body → space) and the angular velocity (rad/s, in
        :attr:`omega_frame` axes) now."""
        raise NotImplementedError

    def failure(self) -> str:
        """What the engine reported as a failure since :meth:`build` ("" if nothing):
        a warning, a reset of the state."""
        return ""

    def close(self) -> None:
        """Release the engine's resources (a server, a window)."""

    # -- what the suite calls ------------------------------------------------------
    def body_omega(self, quaternion: Array, omega: Array) -> Array:
        """ω in body axes from a state of the engine (its :attr:`omega_frame`)."""
        if self.omega_frame == "body":
            return np.asarray(omega, dtype=float)
        return np.asarray(rotation(quaternion).inv().apply(omega), dtype=float)

    def engine_omega(self, quaternion: Array, omega_body: Array) -> Array:
        """ω in the engine's :attr:`omega_frame` axes from ω in body axes."""
        if self.omega_frame == "body":
            return np.asarray(omega_body, dtype=float)
        return np.asarray(rotation(quaternion).apply(omega_body), dtype=float)

    def simulate(
        self,
        body: EngineBody,
        quaternion0: Array,
        omega0: Array,
        dt: float,
        steps: int,
        every: int,
        progress: Callable[[int], object] | None = None,
    ) -> Samples:
        """Run ``steps`` steps of ``dt`` from the given state (ω in body axes), recording
        every ``every``-th step; stop at the first failure. The engine has been built."""
        self.set_state(np.asarray(quaternion0, float), self.engine_omega(quaternion0, omega0))
        limit = divergence_limit(body, omega0)
        times, quaternions, omegas = [0.0], [np.asarray(quaternion0, float)], [np.asarray(omega0)]
        failed_at, failure, done = float("nan"), "", 0
        start = time.perf_counter()
        while done < steps:
            count = min(every, steps - done)
            self.step(count)
            done += count
            q, w = self.state()
            # The engine's own report first; then a state that is no motion (checked
            # before ω is turned into body axes, which a non-finite attitude cannot do;
            # |ω| is the same in either axes).
            failure = self.failure() or diverged(q, w, limit)
            if failure:
                failed_at = done * dt
                break
            times.append(done * dt)
            quaternions.append(np.asarray(q, float) / np.linalg.norm(q))
            omegas.append(self.body_omega(q, w))
            if progress is not None:
                progress(count)
        wall = time.perf_counter() - start
        return Samples(
            np.array(times), np.array(quaternions), np.array(omegas), failed_at, failure, wall, done
        )


class NativeOutput:
    """What an engine's native code prints (to the process's stdout and stderr, file
    descriptors 1 and 2) while a block runs, kept instead of shown: the warnings of an
    engine that has no other way to report them (DART's "Non-finite joint
    accelerations", PyBullet's build banner) become its adapter's report, not noise in
    the user's terminal. One temporary file serves every block of an adapter.

    Use ``with output:`` around the engine's calls; :attr:`lines` then holds what they
    printed (from the last block), :attr:`first` the first line printed since
    :meth:`reset`.
    """

    def __init__(self) -> None:
        self._sink: Any = None
        self.lines: list[str] = []
        self.first = ""

    def __enter__(self) -> NativeOutput:
        if self._sink is None:
            self._sink = tempfile.TemporaryFile()
        sys.stdout.flush()
        sys.stderr.flush()
        self._saved = (os.dup(1), os.dup(2))
        os.dup2(self._sink.fileno(), 1)
        os.dup2(self._sink.fileno(), 2)
        return self

    def __exit__(self, *exc: object) -> None:
        _flush_native()
        for descriptor, saved in zip((1, 2), self._saved, strict=True):
            os.dup2(saved, descriptor)
            os.close(saved)
        sink = self._sink
        size = sink.tell()
        self.lines = []
        if size:
            sink.seek(0)
            text = sink.read(min(size, 65536)).decode("utf-8", errors="replace")
            self.lines = [" ".join(line.split()) for line in text.splitlines() if line.strip()]
            sink.seek(0)
            sink.truncate()
        if self.lines and not self.first:
            self.first = _plain(self.lines[0])

    def reset(self) -> None:
        """Forget what was printed (a new run)."""
        self.lines, self.first = [], ""

    def close(self) -> None:
        """Remove the temporary file."""
        if self._sink is not None:
            self._sink.close()
            self._sink = None


def _flush_native() -> None:
    """Flush C's stdio buffers, so that what native code printed lands in the capture."""
    with contextlib.suppress(OSError, AttributeError):  # no C library here to flush
        ctypes.CDLL(None).fflush(None)


def _plain(line: str) -> str:
    """A printed line without terminal colour codes."""
    return uncoloured(line).strip()


def rotation(quaternion: Array) -> Rotation:
    """scipy's Rotation of a scalar-first quaternion body → space."""
    return Rotation.from_quat(np.asarray(quaternion, dtype=float), scalar_first=True)


def divergence_limit(body: EngineBody, omega0: Array) -> float:
    """A rate no motion of this body can reach, rad/s: 10³ times the largest |ω| that its
    initial energy allows about the pivot (or the centre of mass), gravity's height
    included (a fall from above the pivot to below it)."""
    inertia = body.pivot_inertia
    smallest = float(np.linalg.eigvalsh(inertia)[0])
    energy = 0.5 * float(omega0 @ inertia @ omega0)
    if body.pivot is not None:
        energy += 2.0 * body.mass * float(np.linalg.norm(body.gravity) * np.linalg.norm(body.pivot))
    return 1e3 * max(np.sqrt(2.0 * energy / smallest), 1e-9)


def diverged(quaternion: Array, omega: Array, limit: float) -> str:
    """Why this state is no motion of the body ("" if it may be); cheap enough to call at
    every sample (two dot products)."""
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is what is looked for
        squares, rates = float(quaternion @ quaternion), float(omega @ omega)
    if not (math.isfinite(squares) and math.isfinite(rates)):
        return "the state is not finite"
    if not squares > 0.0:
        return "the attitude quaternion is zero"
    if rates > limit * limit:
        return f"|ω| = {math.sqrt(rates):.3g} rad/s, beyond any motion of this energy"
    return ""


def register_engine(cls: type[Engine]) -> type[Engine]:
    """Class decorator: add an engine adapter to :data:`ENGINES` under ``cls.name``."""
    if not cls.name or "/" in cls.name:
        raise InputError(
            f"Expected an engine adapter with a `name` without '/', got {cls.__name__}."
        )
    if not cls.variants:
        raise InputError(f"Expected an engine adapter with `variants`, got none in {cls.__name__}.")
    ENGINES[cls.name] = cls
    return cls


def split_name(full_name: str) -> tuple[str, str]:
    """("engine", "variant") of "engine/variant" (variant "" for a plain name)."""
    engine, _, variant = str(full_name).strip().partition("/")
    return engine, variant


def engine_names() -> list[str]:
    """Every "engine/variant" name of the registry, installed or not."""
    return [
        f"{name}/{variant}" if variant else name
        for name, cls in ENGINES.items()
        for variant in cls.variants
    ]


def engine_class(full_name: str) -> type[Engine]:
    """The adapter class of "engine/variant"; an InputError for an unknown name."""
    name, variant = split_name(full_name)
    if name not in ENGINES or variant not in ENGINES[name].variants:
        raise unknown_choice(full_name, engine_names(), "the engine")
    return ENGINES[name]


def missing_modules(cls: type[Engine]) -> list[str]:
    """The modules of an adapter that are not installed."""
    return [module for module in cls.modules if importlib.util.find_spec(module) is None]
