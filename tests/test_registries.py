"""The torque, integrator and theory-check registries.

Every registered integrator is run against the exact torque-free solution and
against an independent DOP853 integration of a forced body (tests/reference.py),
its batch kernels against its single-body kernel; a torque model, an
integrator and a theory check defined in this module alone (registered for one
test) are then used by simulate, simulate_batch and scenario files without any
other change.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from tumble import scenario
from tumble.checks import (
    THEORY_CHECKS,
    Case,
    Comparison,
    Curve,
    Panel,
    TheoryCheck,
    choose_check,
    comparison_row,
    register_check,
)
from tumble.core import stepping
from tumble.core._jit import njit
from tumble.core.dynamics import normalised, rates
from tumble.integrators import INTEGRATORS, Integrator, drivers, register_integrator
from tumble.torques import TORQUES, Parameter, TorqueModel, register_torque

AXES = Rotation.from_rotvec([0.3, -0.5, 0.8])
TUMBLER = tb.MassProperties(
    1.0, [0.0, 0.0, 0.0], AXES.as_matrix() @ np.diag([1.0, 2.0, 3.0]) @ AXES.as_matrix().T
)
Q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
OMEGA0 = np.array([0.3, 1.0, -0.5])
DURATION = 5.0

# A forced, damped, asymmetric body: a body torque, a space torque and damping.
FORCING = (
    tb.torques.ConstantBodyTorque([0.05, -0.02, 0.01])
    + tb.torques.ConstantSpaceTorque([0.0, 0.03, -0.01])
    + tb.torques.LinearDamping(0.02)
)


def forcing_reference(t: float, w: np.ndarray, a: np.ndarray) -> np.ndarray:
    return np.array([0.05, -0.02, 0.01]) + a.T @ np.array([0.0, 0.03, -0.01]) - 0.02 * w


def step_and_tolerance(entry: Integrator) -> tuple[dict[str, Any], float]:
    """Keyword arguments of simulate and the error allowed, from what the registry
    says of the integrator.

    A method of order p has a global error ≈ C T dt^p with C of the order of
    |ω|^(p+1) ≈ 1 for these bodies (|ω| ≈ 1.2 rad/s): at dt = 10^(−8/p) over
    T = 5 s that is ~5e-8, so 1e-6 leaves room for C up to 20 and fails any
    method an order lower (its error is then ≥ 1e-4). The adaptive method at
    rtol 1e-10 keeps local errors at 1e-10, amplified by the ~100 steps and the
    flow's sensitivity: 1e-8. The exact solution: round-off, 1e-12.
    """
    if entry.kind == "sampling":
        return {"dt": 0.05}, 1e-12
    if entry.kind == "adaptive":
        return {"dt": 0.05, "rtol": 1e-10, "atol": 1e-12}, 1e-8
    return {"dt": 10.0 ** (-8.0 / entry.order)}, 1e-6


def check_free_motion(name: str) -> None:
    entry = INTEGRATORS[name]
    options, tolerance = step_and_tolerance(entry)
    run = tb.simulate(
        TUMBLER, OMEGA0, attitude0=Q0, duration=DURATION, method=name, record_every=50, **options
    )
    exact = tb.theory.free_motion(TUMBLER, OMEGA0, Q0)
    omega, quaternion = exact.at(run.t)
    assert np.max(np.abs(run.omega - omega)) < tolerance
    assert (
        attitude_error(
            run.quaternion, Rotation.from_quat(quaternion, scalar_first=True).as_matrix()
        )
        < tolerance
    )
    assert run.method == name and run.conserved_quantities == ("energy", "angular_momentum_vector")


def check_forced_motion(name: str) -> None:
    entry = INTEGRATORS[name]
    options, tolerance = step_and_tolerance(entry)
    run = tb.simulate(
        TUMBLER, OMEGA0, attitude0=Q0, duration=DURATION, torque=FORCING, method=name, **options
    )
    times = run.t[:: max(1, len(run.t) // 7)]
    w_ref, a_ref = reference(TUMBLER, OMEGA0, Q0, DURATION, torque=forcing_reference, times=times)
    rows = np.searchsorted(run.t, times)
    assert np.max(np.abs(run.omega[rows] - w_ref)) < tolerance
    assert attitude_error(run.quaternion[rows], a_ref) < tolerance
    # Driven and damped: nothing is conserved, so no drift is reported.
    assert run.drift == {}


def check_batch(name: str) -> None:
    # Three bodies given by tensors (non-principal axes) with per-body torques:
    # the batch kernels against the single-body kernel of the same method, step
    # for step. The same arithmetic up to FMA contraction and reassociation in
    # the vectorised kernels: round-off, amplified over 200 steps to ≲ 1e-12.
    rng = np.random.default_rng(3)
    rotations = Rotation.random(3, random_state=4).as_matrix()
    moments = np.array([[1.0, 2.0, 2.5], [0.5, 0.7, 1.0], [2.0, 2.0, 3.0]])
    tensors = np.einsum("nij,nj,nkj->nik", rotations, moments, rotations)
    omega = rng.normal(size=(3, 3))
    body_torques = rng.normal(scale=0.1, size=(3, 3))
    damping = np.array([0.0, 0.01, 0.05])
    torque = tb.torques.ConstantBodyTorque(body_torques) + tb.torques.LinearDamping(damping)
    free = INTEGRATORS[name].torque_free_only  # a closed form: torque-free bodies
    batch = tb.simulate_batch(
        tensors, omega, duration=0.2, dt=1e-3, method=name, torque=None if free else torque,
        record_every=100,
    )  # fmt: skip
    for k in range(3):
        alone = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], tensors[k]), omega[k], duration=0.2, dt=1e-3,
            method=name, record_every=100,
            torque=None if free else tb.torques.ConstantBodyTorque(body_torques[k])
            + tb.torques.LinearDamping(damping[k]),
        )  # fmt: skip
        assert_allclose(batch.omega_history[:, k], alone.omega, atol=1e-12)
        assert_allclose(batch.quaternion_history[:, k], alone.quaternion, atol=1e-12)


@pytest.mark.parametrize("name", list(INTEGRATORS))
def test_every_integrator_follows_the_exact_free_motion(name: str) -> None:
    check_free_motion(name)


@pytest.mark.parametrize(
    "name", [n for n, entry in INTEGRATORS.items() if not entry.torque_free_only]
)
def test_every_integrator_follows_a_reference_integration_of_a_forced_body(name: str) -> None:
    check_forced_motion(name)


@pytest.mark.parametrize("name", [n for n, entry in INTEGRATORS.items() if entry.supports_batch])
def test_every_batch_integrator_equals_separate_simulations(name: str) -> None:
    check_batch(name)


def check_order(name: str) -> None:
    # Against the exact solution (round-off 1e-15) on the free tumbler, at steps
    # where the error is far above round-off (dt = 10^(−4/p): errors ~1e-5 to
    # 1e-8) and in the asymptotic range: halving dt divides it by 2^p, within 15 %.
    # A method whose free flow is exact errs only through the torque: it runs the
    # tumbler as a heavy top instead, against DOP853 at rtol 1e-13 (~1e-12).
    entry = INTEGRATORS[name]
    coarse = 10.0 ** (-4.0 / entry.order)
    pivot, gravity = (None, None)
    if entry.exact_free_motion:
        pivot, gravity = [0.0, 0.0, -0.1], [0.0, 0.0, -9.81]
        coarse = 0.1  # errors 1e-5 (order 4) to 1e-3 (order 2), in the asymptotic range
    exact, _ = (
        reference(TUMBLER, OMEGA0, [1.0, 0, 0, 0], 2.0, pivot, gravity)
        if entry.exact_free_motion
        else (tb.theory.free_motion(TUMBLER, OMEGA0).at(2.0)[0], None)
    )
    errors = [
        np.max(
            np.abs(
                tb.simulate(
                    TUMBLER, OMEGA0, duration=2.0, dt=dt, method=name, pivot=pivot,
                    gravity=gravity,
                ).omega[-1]
                - exact
            )
        )
        for dt in (coarse, coarse / 2)
    ]  # fmt: skip
    assert errors[1] > 1e-10  # far above the oracle's error
    assert errors[0] / errors[1] == pytest.approx(2.0**entry.order, rel=0.15)


@pytest.mark.parametrize(
    "name", [n for n, entry in INTEGRATORS.items() if entry.kind == "stepping"]
)
def test_every_stepping_integrator_converges_at_its_order(name: str) -> None:
    check_order(name)


def test_torque_free_integrators_refuse_torques() -> None:
    for name, entry in INTEGRATORS.items():
        if entry.torque_free_only:
            with pytest.raises(
                tb.InputError,
                match=rf"Expected a method that integrates this motion \(auto, .*\), got "
                rf"'{name}': its closed forms solve torque-free bodies and a symmetric top .* "
                r"only, and this motion has ConstantBodyTorque",
            ):
                tb.simulate(TUMBLER, OMEGA0, duration=1.0, method=name, torque=FORCING)
            # Gravity about a pivot: only on a symmetric top with its pivot on the axis.
            with pytest.raises(
                tb.InputError,
                match=r"this motion has gravity on a body that is not such a top\.",
            ):
                tb.simulate(
                    TUMBLER, OMEGA0, duration=1.0, method=name, pivot=[0, 0, 0.1],
                    gravity=[0, 0, -9.81],
                )  # fmt: skip


# ============================================================ a torque model added here
@njit(inline="always")
def oscillating_kernel(t, w, q, params, row, column, context):  # type: ignore[no-untyped-def]
    """``A cos(ν t) â``: fields â (3, principal axes), A (N·m), ν (rad/s)."""
    size = params[row + 3, column] * math.cos(params[row + 4, column] * t)
    return (
        size * params[row, column],
        size * params[row + 1, column],
        size * params[row + 2, column],
        0.0,
    )


@dataclass(frozen=True, eq=False, repr=False)
class OscillatingTorque(TorqueModel):
    """A torque ``A cos(ν t)`` along a body axis: a number, or one per body of a batch."""

    axis: Any
    amplitude: Any
    rate: Any

    name = "test-oscillating"
    summary = "a torque A cos(ν t) along a body axis"
    parameters = (
        Parameter("axis", "dimensionless", (3,), "unit axis in body axes"),
        Parameter("amplitude", "torque", (), "amplitude A", sweep=("oscillation_amplitude",)),
        Parameter("rate", "angular_velocity", (), "angular frequency ν"),
    )
    fields = ("axis_1", "axis_2", "axis_3", "amplitude", "rate")
    kernel = staticmethod(oscillating_kernel)
    depends_on = frozenset({"time"})
    in_batches = True

    def pack(self, body: Any, omega0: Any) -> np.ndarray:
        n = self.per_body or 1
        axis = np.broadcast_to(body.to_principal(self.axis), (n, 3)).T
        return np.vstack(
            [axis, np.broadcast_to(self.amplitude, (1, n)), np.broadcast_to(self.rate, (1, n))]
        )


@pytest.fixture
def oscillating() -> Iterator[type[OscillatingTorque]]:
    register_torque(OscillatingTorque)
    yield OscillatingTorque
    TORQUES.pop(OscillatingTorque.name)


def sphere_spin(t: np.ndarray, amplitude: float, rate: float, inertia: float) -> np.ndarray:
    """ω_z of a sphere from 1 rad/s under A cos(ν t) about z: 1 + A sin(ν t) / (I ν)."""
    return 1.0 + amplitude * np.sin(rate * t) / (inertia * rate)


def test_a_torque_model_added_here_runs_in_simulate_and_simulate_batch(oscillating) -> None:
    sphere = tb.shapes.solid_sphere(2.0, 0.1)
    inertia = 0.4 * 2.0 * 0.1**2  # 2/5 m r²
    model = oscillating([0, 0, 1], "0.01 N*m", 3.0)
    assert "test-oscillating" in TORQUES
    for method in ("rk4", "splitting", "adaptive"):
        run = tb.simulate(
            sphere, [0, 0, 1.0], duration=3.0, dt=1e-3, torque=model, method=method, rtol=1e-12
        )
        # Fourth-order methods at dt = 1e-3 on a torque varying at 3 rad/s: the
        # error is ~(ν dt)⁴ |Δω| ≈ 1e-13; the adaptive method at rtol 1e-12 keeps
        # its ~100 local errors of 1e-12 below 1e-10 in all.
        expected = sphere_spin(run.t, 0.01, 3.0, inertia)
        assert np.max(np.abs(run.omega[:, 2] - expected)) < 1e-10
        assert run.drift == {}  # not a model that declares anything conserved
    # auto: a torque that is not conservative goes to the adaptive method.
    assert tb.simulate(sphere, [0, 0, 1.0], duration=0.1, torque=model).method == "adaptive"
    amplitudes = np.array([0.0, 0.01, -0.02])
    batch = tb.simulate_batch(
        np.full((3, 3), inertia), np.tile([0.0, 0.0, 1.0], (3, 1)), duration=2.0, dt=1e-3,
        torque=oscillating([0, 0, 1], amplitudes, 3.0),
    )  # fmt: skip
    assert_allclose(batch.omega[:, 2], sphere_spin(2.0, amplitudes, 3.0, inertia), atol=1e-10)
    # A scenario file names it by its registry name, its parameters with units.
    text = """
        [scenario]
        name = "driven"
        [body]
        shape = "solid-sphere"
        mass = "2 kg"
        radius = "10 cm"
        [initial]
        omega = "0, 0, 1 rad/s"
        [[torques]]
        type = "test-oscillating"
        axis = [0, 0, 1]
        amplitude = "10 mN*m"
        rate = "3 rad/s"
        [simulation]
        duration = "3 s"
        dt = "1 ms"
        method = "rk4"
    """
    result = scenario.run(scenario.parse(text.replace("\n        ", "\n")))
    traj = result.trajectory
    # RK4 at dt = 1 ms, as above: ~1e-13.
    assert_allclose(traj.omega[:, 2], sphere_spin(traj.t, 0.01, 3.0, inertia), atol=1e-12)
    # Sweep files take a model's parameters per body when every one has a sweep
    # name; this one's axis and rate have none, so sweeps leave it out.
    assert "oscillation_amplitude" not in tb.sweep.PARAMETERS


def test_an_unregistered_name_is_refused_by_its_registry() -> None:
    with pytest.raises(
        tb.InputError, match=r"Expected a torque model with a `name`, got TorqueModel"
    ):
        register_torque(TorqueModel)


# ============================================================ an integrator added here
@njit(inline="always")
def midpoint_step(torque, t, dt, state, coefficients, params, column, context):  # type: ignore[no-untyped-def]
    """The explicit midpoint rule (second order), quaternion renormalised."""
    a = rates(torque, t, state, coefficients, params, column, context)
    h = 0.5 * dt
    middle = (
        state[0] + h * a[0], state[1] + h * a[1], state[2] + h * a[2], state[3] + h * a[3],
        state[4] + h * a[4], state[5] + h * a[5], state[6] + h * a[6],
    )  # fmt: skip
    b = rates(torque, t + h, middle, coefficients, params, column, context)
    return normalised(
        (
            state[0] + dt * b[0], state[1] + dt * b[1], state[2] + dt * b[2],
            state[3] + dt * b[3], state[4] + dt * b[4], state[5] + dt * b[5],
            state[6] + dt * b[6],
        )
    )  # fmt: skip


MIDPOINT = Integrator(
    name="midpoint",
    summary="explicit midpoint rule (a test integrator)",
    kind="stepping",
    order=2,
    preserves="the unit quaternion",
    run=drivers.run_stepping,
    # The stepping loops of the core run any one-step scheme: the step is all a
    # new integrator of this kind writes.
    single=partial(stepping.single_kernel, midpoint_step),
    batch=partial(stepping.batch_kernel, midpoint_step),
)


@pytest.fixture
def midpoint() -> Iterator[Integrator]:
    register_integrator(MIDPOINT)
    yield MIDPOINT
    INTEGRATORS.pop(MIDPOINT.name)


def test_an_integrator_added_here_is_wired_and_tested(midpoint: Integrator) -> None:
    # The same oracle tests every registered integrator gets.
    check_free_motion("midpoint")
    check_forced_motion("midpoint")
    check_batch("midpoint")
    check_order("midpoint")
    # A scenario file names it, and the scenario runs it (a stepping method: dt a step).
    text = scenario.builtin_text("tennis-racket").replace(
        'method = "exact"', 'method = "midpoint"\ndt = "1 ms"', 1
    )
    result = scenario.run(scenario.parse(text))
    assert result.trajectory.method == "midpoint" and result.trajectory.steps == 20_000
    # Second order at dt = 1 ms (|ω| 10 rad/s: 0.01 rad a step, local errors ~1e-6
    # rad/s): the flip period measured on it agrees with the closed form to 3e-6;
    # 1e-4 leaves room for a constant 30× larger and fails a first-order method.
    (period,) = [row for row in result.comparisons if row["quantity"] == "flip period"]
    assert period["relative_error"] < 1e-4
    with pytest.raises(
        tb.InputError,
        match=r"one of exact, splitting, strang, splitting-exact, strang-exact, rk4, midpoint, got 'adaptive'",
    ):
        tb.simulate_batch(
            [[1.0, 2.0, 2.5]], [[0.1, 1.0, 0.0]], duration=1.0, dt=0.1, method="adaptive"
        )


# ============================================================ a theory check added here
class EnergyCheck(TheoryCheck):
    """A free body keeps its kinetic energy ½ ω0 · I ω0."""

    name = "test-energy"
    needs = "a free body"

    def fits(self, case: Case) -> bool:
        return case.free

    def compare(self, case: Case, trajectory: tb.Trajectory) -> Comparison:
        expected = float(tb.kinetic_energy(case.mass_properties, case.omega0))
        measured = float(np.mean(trajectory.energy))
        curve = Curve("energy", trajectory.t, trajectory.energy)
        return Comparison(
            [comparison_row("kinetic energy", expected, measured, "J")],
            [Panel("Energy", "E (J)", [curve], name="energy")],
        )


@pytest.fixture
def energy_check() -> Iterator[TheoryCheck]:
    check = register_check(EnergyCheck())
    yield check
    THEORY_CHECKS.pop(check.name)


def test_a_theory_check_added_here_is_named_by_scenario_files(energy_check: TheoryCheck) -> None:
    text = scenario.builtin_text("tennis-racket").replace(
        'model = "flip-period"', 'model = "test-energy"', 1
    )
    result = scenario.run(scenario.parse(text))
    assert result.theory == "test-energy"
    (row,) = result.comparisons
    # The exact solution keeps the energy to round-off: 1e-15 relative.
    assert row["quantity"] == "kinetic energy" and row["relative_error"] < 1e-13
    assert [panel.name for panel in result.panels] == ["energy"]
    with pytest.raises(tb.InputError, match=r"Expected a free body for 'test-energy', got another"):
        choose_check("test-energy", Case(TUMBLER, OMEGA0, Q0, torque=FORCING))
    with pytest.raises(
        tb.InputError, match=r"Expected `model` to be one of auto, none, .*, got 'energy'\."
    ):
        choose_check("energy", Case(TUMBLER, OMEGA0, Q0))
