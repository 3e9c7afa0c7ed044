"""The integrators, in one registry.

Each entry of :data:`INTEGRATORS` says what an integrator is (kind, order,
what it preserves, which torques and which internal parts it handles, when
``method="auto"`` picks it) and gives its compiled kernels: for one body
(``single``), for batches (``batch``) and for batches measured as they step
(``metrics``), each a factory ``factory(torque_function, identity) -> kernel``
that specialises the kernel for one simulation's torque
(:mod:`tumble.core.torques`) (a stepping integrator's ``metrics`` factory also
takes the keywords ``principal_axis`` and ``attitude`` of
:func:`tumble.core.stepping.metrics_kernel`); and for bodies carrying parts (rotors, dampers:
:mod:`tumble.core.parts`) ``parts_single``, ``parts_batch`` and ``parts_metrics``, factories
``factory(torque_function, drive_function, layout, identity) -> kernel``. Everything
that needs to know which methods exist — :func:`tumble.simulate` and its
``"auto"`` choice, :func:`tumble.simulate_batch`, the scenario and sweep files,
the sweep engine, the tests — reads this registry.

A new integrator is its kernels and one :func:`register_integrator` call.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import Any, Literal

from tumble.core import adaptive, freebody, part_blocks, splitting, stepping
from tumble.core import parts as part_kernels
from tumble.core.rk4 import rk4_step
from tumble.errors import InputError, unknown_choice
from tumble.integrators import drivers
from tumble.torques import BoundTorque

__all__ = [
    "INTEGRATORS",
    "Integrator",
    "any_part",
    "auto_choice",
    "batch_integrators",
    "check_method",
    "get_integrator",
    "gyrostatic_part",
    "method_names",
    "methods_for",
    "register_integrator",
    "splittable_part",
]

#: How ``dt`` is used: a fixed step (``"stepping"``), the sampling interval of a
#: solution evaluated at any time (``"sampling"``), or the sampling interval of
#: a method that chooses its own steps (``"adaptive"``).
Kind = Literal["stepping", "sampling", "adaptive"]

KernelFactory = Callable[[Any, str], Any]
PartsKernelFactory = Callable[[Any, Any, Any, str], Any]


def any_part(part_class: Any) -> bool:
    """Every kind of part: the Runge–Kutta methods integrate any part's equations."""
    return True


def splittable_part(part_class: Any) -> bool:
    """Parts whose momentum is fixed in the body between kicks and that move no
    mass (:attr:`tumble.parts.InternalPart.splittable`: rotors)."""
    return bool(part_class.splittable)


def gyrostatic_part(part_class: Any) -> bool:
    """Parts that may make a gyrostat, whose free motion is in closed form
    (:attr:`tumble.parts.InternalPart.gyrostatic`: rotors without motors)."""
    return bool(part_class.gyrostatic)


@dataclass(frozen=True, eq=False)
class Integrator:
    """One integrator of the registry.

    Attributes
    ----------
    name : its value of ``method``.
    summary : one line: what it is.
    kind : see :data:`Kind`.
    order : its order of accuracy (0 for an exact solution).
    preserves : what it keeps exactly or bounded, in words.
    torque_free_only : True when its batch and sweep kernels take torque-free
        bodies only (a closed form; for one body ``applies`` says which
        torques it takes).
    exact_symmetric_spin : True when its free flow turns a symmetric body
        exactly (a step need not resolve the spin about the symmetry axis).
    exact_free_motion : True when its free flow is the exact torque-free motion
        of any body (a step need not resolve the rotation at all).
    measures_without_attitude : True when its metrics kernel may leave the
        attitude where the torque does not read it (``attitude=False`` of
        :meth:`kernel`): a step of it that failed shows in ω, not only in q.
        The splittings mark a step beyond the range of their sines
        (:data:`tumble.core.trig.LARGEST_ANGLE`) by a NaN quaternion alone.
    kicks : True when it applies the torque in kicks that hold the attitude and
        the torque: exact for torques whose τ depends on the attitude and time
        only (:attr:`tumble.torques.TorqueModel.depends_on`), first order in
        one whose τ depends on ω.
    auto : None, or ``auto(torque) -> reason or None``: why ``method="auto"``
        picks it for this bound torque (the first entry with a reason wins, among
        those that handle the body's parts).
    single, batch, metrics : kernel factories (see the module's docstring), or None.
    takes_part : None (bodies without parts only), or ``takes_part(part_class) ->
        bool``: the kinds of part (:data:`tumble.parts.PARTS`) it integrates
        (:func:`any_part`, :func:`splittable_part`, :func:`gyrostatic_part`).
    applies : None, or ``applies(body, torque) -> None or why not``: a narrower
        rule on the bodies and bound torques it integrates (the exact solution
        needs a torque-free body, a gyrostat if it carries rotors, or a
        symmetric top under uniform gravity).
    parts_single, parts_batch, parts_metrics : kernel factories for bodies carrying
        parts (one body, a batch, a batch measured as it steps: :mod:`tumble.core.parts`),
        or None.
    run : the single-body driver of its kind (:mod:`tumble.integrators.drivers`).
    ready : None, or ``ready(integrator, problem, schedule) -> run(progress)``: its
        driver made ready for one problem and schedule, called for each run of
        them (:meth:`ready_run`; None: ``run`` itself, with those arguments).
    """

    name: str
    summary: str
    kind: Kind
    order: int
    preserves: str
    run: Callable[..., Any]
    torque_free_only: bool = False
    exact_symmetric_spin: bool = False
    exact_free_motion: bool = False
    kicks: bool = False
    measures_without_attitude: bool = False
    auto: Callable[[BoundTorque], str | None] | None = None
    single: KernelFactory | None = None
    batch: KernelFactory | None = None
    metrics: KernelFactory | None = None
    takes_part: Callable[[Any], bool] | None = None
    applies: Callable[[Any, BoundTorque], str | None] | None = None
    parts_single: PartsKernelFactory | None = None
    parts_batch: PartsKernelFactory | None = None
    parts_metrics: PartsKernelFactory | None = None
    ready: Callable[..., Callable[[Any], Any]] | None = None
    _kernels: dict[tuple[str, str, Any, int | None, bool], Any] = field(
        default_factory=dict, repr=False
    )
    _lock: Any = field(default_factory=threading.Lock, repr=False)

    @property
    def supports_batch(self) -> bool:
        return self.batch is not None

    def ready_run(self, problem: Any, schedule: Any) -> Callable[[Any], Any]:
        """``run(progress) -> Samples``: its driver for this problem and schedule
        (:mod:`tumble.integrators.problem`), made ready for runs that repeat them."""
        if self.ready is None:
            return partial(self.run, self, problem, schedule)
        return self.ready(self, problem, schedule)

    def handles(self, parts: Any) -> bool:
        """True when it integrates a body carrying these parts (instances of
        :class:`tumble.parts.InternalPart`)."""
        parts = tuple(parts)
        if not parts:
            return True
        takes = self.takes_part
        return takes is not None and all(takes(type(part)) for part in parts)

    def refuses(self, body: Any, torque: BoundTorque) -> str | None:
        """Why it does not integrate this body (:class:`tumble.body.RigidBody`)
        under this bound torque, or None."""
        parts = tuple(getattr(body, "parts", ()))
        if not self.handles(parts):
            kinds = sorted({part.kind for part in parts})
            return f"it does not integrate bodies carrying {', '.join(kinds)} parts"
        return None if self.applies is None else self.applies(body, torque)

    def kernel(
        self,
        role: Literal["single", "batch", "metrics", "parts_single", "parts_batch", "parts_metrics"],
        torque: BoundTorque,
        layout: Any = None,
        *,
        principal_axis: int | None = None,
        attitude: bool = True,
    ) -> Any:
        """The compiled kernel ``role`` specialised for ``torque`` (and, for bodies
        carrying parts, their ``layout``: :func:`tumble.parts.pack_parts`), built
        once per process; compiled on first call, or loaded from the on-disk
        cache. Hints for a stepping integrator's metrics kernel, which the other
        kernels ignore: ``principal_axis``, the axis 0, 1 or 2 that every nominal
        axis lies on, none of them zero, or None for any axes; ``attitude=False``
        for a kernel that leaves the quaternions as given, for a torque that does
        not depend on the attitude (:func:`tumble.core.stepping.metrics_kernel`;
        only where ``measures_without_attitude``).
        """
        factory = getattr(self, role)
        if factory is None:
            raise InputError(f"Expected an integrator with a {role} kernel, got {self.name!r}.")
        if role != "metrics" or self.kind != "stepping":
            principal_axis, attitude = None, True
        attitude = attitude or not self.measures_without_attitude
        if not attitude and "attitude" in torque.depends_on:
            reading = [type(t).__name__ for t in torque.terms if "attitude" in t.depends_on]
            raise InputError(
                "Expected a torque independent of the attitude for a metrics kernel "
                f"without it, got {' and '.join(reading)}, "
                + ("which depends on it." if len(reading) == 1 else "which depend on it.")
            )
        key = (role, torque.identity, layout, principal_axis, attitude)
        with self._lock:
            kernel = self._kernels.get(key)
            if kernel is None:
                if role.startswith("parts"):
                    kernel = factory(torque.function, torque.drive, layout, torque.identity)
                elif role == "metrics" and self.kind == "stepping":
                    kernel = factory(
                        torque.function,
                        torque.identity,
                        principal_axis=principal_axis,
                        attitude=attitude,
                    )
                else:
                    kernel = factory(torque.function, torque.identity)
                self._kernels[key] = kernel
        return kernel


#: Every registered integrator by name, in the order ``"auto"`` considers them.
INTEGRATORS: dict[str, Integrator] = {}


def register_integrator(integrator: Integrator) -> Integrator:
    """Add an integrator to :data:`INTEGRATORS` (replacing one of the same name)."""
    if integrator.name == "auto":
        raise InputError("Expected an integrator name other than 'auto', got 'auto'.")
    INTEGRATORS[integrator.name] = integrator
    return integrator


def batch_integrators() -> list[str]:
    """Names of the integrators with batch kernels."""
    return [name for name, entry in INTEGRATORS.items() if entry.supports_batch]


def method_names(*, batch: bool = False, measured: bool = False) -> list[str]:
    """The values ``method`` may take: ``"auto"`` and every integrator; for
    batches (``batch``), the integrators with batch kernels; for batches measured
    as they step (``measured``: sweeps), those with measuring kernels."""
    if measured:
        return [name for name, entry in INTEGRATORS.items() if entry.metrics is not None]
    if batch:
        return batch_integrators()
    return ["auto", *INTEGRATORS]


def check_method(name: Any, *, batch: bool = False, measured: bool = False) -> str:
    """``name`` if ``method`` may take it (:func:`method_names`): the one check of a
    method's name, for :func:`tumble.simulate`, :func:`tumble.simulate_batch`,
    scenario files and sweeps.

    Raises
    ------
    InputError
        Another value; the message lists the names and suggests the nearest.
    """
    names = method_names(batch=batch, measured=measured)
    if not isinstance(name, str) or name not in names:
        raise unknown_choice(name, names, "`method`")
    return name


def methods_for(parts: Any, role: str) -> list[str]:
    """The names of the integrators that have a kernel ``role`` (``"parts_batch"``,
    ``"parts_metrics"`` …) and integrate bodies carrying ``parts``, in the
    registry's order: what a refusal lists."""
    parts = tuple(parts)
    return [
        name
        for name, entry in INTEGRATORS.items()
        if getattr(entry, role) is not None and entry.handles(parts)
    ]


def get_integrator(name: str, *, batch: bool = False) -> Integrator:
    """The integrator ``name`` (for batches: one with batch kernels).

    Raises
    ------
    InputError
        A name :func:`check_method` refuses, or ``"auto"``, which names none.
    """
    entry = INTEGRATORS.get(name) if type(name) is str else None
    if entry is not None and (entry.supports_batch or not batch):
        return entry
    check_method(name, batch=batch)
    if name == "auto":
        raise InputError(
            "Expected the name of an integrator, got 'auto', which chooses one (auto_choice)."
        )
    return INTEGRATORS[name]


def auto_choice(torque: BoundTorque, body: Any = None) -> tuple[Integrator, str]:
    """The integrator ``method="auto"`` picks for this bound torque and body
    (:class:`tumble.body.RigidBody`, with its parts), and why."""
    for entry in INTEGRATORS.values():
        if body is not None and entry.refuses(body, torque) is not None:
            continue
        reason = entry.auto(torque) if entry.auto is not None else None
        if reason is not None:
            return entry, f"auto: {reason}"
    raise InputError("Expected an integrator that 'auto' can choose, got none registered.")


def _exact_when(torque: BoundTorque) -> str | None:
    if torque.torque_free:
        return (
            "torque-free, so the exact solution (Jacobi elliptic functions; with rotors, "
            "those of the gyrostat, or a steady precession for a symmetric one)"
        )
    # Only gravity: the body passed _exact_applies, so it is a symmetric top.
    return (
        "uniform gravity on a symmetric top about its pivot, so the exact solution "
        "(the Lagrange top: Jacobi elliptic functions and Carlson's integrals)"
    )


def _only_gravity(torque: BoundTorque) -> bool:
    """True when every term is uniform gravity
    (:meth:`tumble.torques.TorqueModel.uniform_gravity`)."""
    return bool(torque.terms) and all(term.uniform_gravity() is not None for term in torque.terms)


def _exact_applies(body: Any, torque: BoundTorque) -> str | None:
    if not torque.torque_free:
        if _only_gravity(torque) and body.symmetric_top_axis() is not None:
            return None
        return (
            "its closed forms solve torque-free bodies and a symmetric top under uniform "
            "gravity (two equal moments about the pivot, the pivot and the centre of mass "
            "on the symmetry axis, no parts) only, and this motion has "
            + (
                "gravity on a body that is not such a top"
                if _only_gravity(torque)
                else " + ".join(type(term).__name__ for term in torque.terms)
            )
        )
    if not getattr(body, "parts", ()) or body.gyrostat_axis() is not None:
        return None
    return (
        "the closed form of a body with parts needs a gyrostat: rotors without motors, "
        "all on one principal axis of the platform"
    )


def _splitting_when(torque: BoundTorque) -> str | None:
    if not torque.conservative:
        return None
    return (
        "the torque is conservative, so the symplectic splitting (bounded energy error)"
        if torque.terms
        else "torque-free with rotors, so the symplectic splitting of the gyrostat"
    )


def _adaptive_when(torque: BoundTorque) -> str | None:
    # Chosen last: for torques the others do not take, or, with conservative
    # torques or none, for parts they refuse (dampers, rotors driven by motors).
    why = (
        "non-conservative torques"
        if not torque.conservative
        else "parts the closed form and the splitting do not take (dampers, or rotors "
        "driven by motors)"
    )
    return f"{why}, so the adaptive Dormand–Prince 5(4)"


register_integrator(
    Integrator(
        name="exact",
        summary="the closed-form torque-free motion, sampled every dt; no stepping error",
        kind="sampling",
        order=0,
        preserves="everything, to round-off",
        run=drivers.run_exact,
        batch=freebody.exact_batch_kernel,
        metrics=freebody.exact_metrics_kernel,
        torque_free_only=True,
        auto=_exact_when,
        takes_part=gyrostatic_part,
        applies=_exact_applies,
    )
)


def _splitting(
    name: str, order: int, summary: str, auto: Any = None, *, exact_flow: bool = False
) -> Integrator:
    """An entry for the splitting of order 2 (Strang) or 4 (Yoshida's composition),
    around the rotations of the free motion or (``exact_flow``) its exact flow."""
    steps = {
        (2, False): splitting.strang_step,
        (4, False): splitting.yoshida_step,
        (2, True): splitting.exact_strang_step,
        (4, True): splitting.exact_yoshida_step,
    }
    step = steps[order, exact_flow]
    # One body at a time, the C library's sines are the faster (the same map).
    one_body = {
        (2, False): splitting.strang_step_one_body,
        (4, False): splitting.yoshida_step_one_body,
    }.get((order, exact_flow), step)
    common: dict[str, Any] = {
        "name": name,
        "summary": summary,
        "kind": "stepping",
        "order": order,
        "run": drivers.run_stepping,
        "ready": drivers.ready_stepping,
        "exact_symmetric_spin": True,
        "kicks": True,
        "auto": auto,
        "single": partial(stepping.single_kernel, one_body, variables=splitting.MOMENTUM),
        "batch": partial(
            stepping.batch_kernel,
            step,
            variables=splitting.MOMENTUM,
            advance=splitting.block_advance,
        ),
        "metrics": partial(
            stepping.metrics_kernel,
            step,
            variables=splitting.MOMENTUM,
            advance=splitting.block_advance,
        ),
    }
    if exact_flow:
        return Integrator(
            preserves="the free motion exactly, so the error comes from the torque alone; "
            "|L| to round-off when torque-free; bounded energy error under gravity",
            exact_free_motion=True,
            **common,
        )
    part_step = part_kernels.make_strang_step if order == 2 else part_kernels.make_yoshida_step
    body_step = part_blocks.strang_body_step if order == 2 else part_blocks.yoshida_body_step
    return Integrator(
        preserves="|L| to round-off when torque-free; bounded energy error under gravity; "
        "a symmetric body's free motion exactly; with rotors, L to round-off",
        takes_part=splittable_part,
        parts_single=partial(part_kernels.single_kernel, part_step),
        parts_batch=partial(part_blocks.block_kernel, body_step),
        parts_metrics=partial(part_blocks.block_measuring_kernel, body_step),
        **common,
    )


def _register_splittings() -> None:
    """The four splittings: rotations or the exact free flow, orders 2 and 4."""
    for name, order, summary, auto, exact_flow in (
        (
            "splitting",
            4,
            "fourth-order symplectic splitting (Yoshida's composition of strang)",
            _splitting_when,
            False,
        ),
        (
            "strang",
            2,
            "second-order symplectic splitting: exact rotations and torque kicks",
            None,
            False,
        ),
        (
            "splitting-exact",
            4,
            "fourth-order splitting around the exact free motion (Yoshida's "
            "composition of strang-exact): steps set by the torque, not by the rotation",
            None,
            True,
        ),
        (
            "strang-exact",
            2,
            "second-order splitting: the exact free motion (Jacobi elliptic "
            "functions) and torque kicks",
            None,
            True,
        ),
    ):
        register_integrator(_splitting(name, order, summary, auto, exact_flow=exact_flow))


_register_splittings()
register_integrator(
    Integrator(
        name="rk4",
        summary="classical Runge–Kutta, fixed step, quaternion renormalised",
        kind="stepping",
        order=4,
        preserves="the unit quaternion",
        run=drivers.run_stepping,
        ready=drivers.ready_stepping,
        single=partial(stepping.single_kernel, rk4_step),
        batch=partial(stepping.batch_kernel, rk4_step),
        metrics=partial(stepping.metrics_kernel, rk4_step),
        measures_without_attitude=True,
        takes_part=any_part,
        parts_single=partial(part_kernels.single_kernel, part_kernels.make_rk4_step),
        parts_batch=partial(part_blocks.block_kernel, part_blocks.rk4_body_step),
        parts_metrics=partial(part_blocks.block_measuring_kernel, part_blocks.rk4_body_step),
    )
)
register_integrator(
    Integrator(
        name="adaptive",
        summary="Dormand–Prince 5(4) with step-size control and dense output every dt",
        kind="adaptive",
        order=5,
        preserves="the unit quaternion; errors within rtol and atol per step",
        run=drivers.run_adaptive,
        auto=_adaptive_when,
        single=adaptive.single_kernel,
        takes_part=any_part,
        parts_single=part_kernels.adaptive_kernel,
    )
)
