"""Drag per body axis: AxisDrag (τᵢ = −cᵢ ωᵢ) and QuadraticDrag (τᵢ = −cᵢ ωᵢ |ωᵢ|)
against their closed forms on a ball, against an independent integration on a
body whose axes are not principal, in batches and scenario files, and their
refusals."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import cumulative_simpson
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import reference
from tumble.scenario import ScenarioError, parse, run
from tumble.torques import TORQUES, AxisDrag, QuadraticDrag, from_description

BALL = tb.shapes.solid_sphere(2.0, 0.1)  # three equal moments I = 0.4 m r² = 0.008 kg·m²
MOMENT = 0.008

# Step and error allowed for each method on these decays, whose rate λ = c / I (or
# c ω0 / I) is at most 1/s over 2 s. RK4's global error on ω̇ = −λ ω is about
# |ω0| T λ⁵ dt⁴ / 120 ≈ 3 · 2 · 1e-8 / 120 = 5e-10 at dt = 0.01 (measured 3e-11;
# 4.5e-10 for the quadratic decay from 10 rad/s),
# so 1e-8 holds it with room and fails a method an order lower (its error,
# ~T λ⁴ dt³ |ω0| / 24 ≈ 2.5e-7, is above). The adaptive method at rtol 1e-10
# keeps each step's error near 1e-10 of |ω| ≤ 10 rad/s, over ~100 steps: 1e-8.
METHODS: dict[str, tuple[dict[str, Any], float]] = {
    "rk4": ({"dt": 0.01}, 1e-8),
    "adaptive": ({"dt": 0.01, "rtol": 1e-10}, 1e-8),
}


@pytest.mark.parametrize("method", list(METHODS))
def test_linear_drag_decays_each_axis_of_a_ball_on_its_own(method: str) -> None:
    # Equal moments: ω × I ω = 0, so each rate obeys I ω̇ᵢ = −cᵢ ωᵢ alone and
    # ωᵢ(t) = ωᵢ(0) exp(−cᵢ t / I). Distinct cᵢ: a coefficient applied to the
    # wrong axis, or the wrong sign, is off by 0.1 rad/s or more.
    options, tolerance = METHODS[method]
    c = np.array([0.008, 0.004, 0.002])
    omega0 = np.array([1.0, -2.0, 3.0])
    traj = tb.simulate(BALL, omega0, duration=2.0, torque=AxisDrag(c), method=method, **options)
    exact = omega0 * np.exp(-np.outer(traj.t, c) / MOMENT)
    assert traj.method == method
    assert np.max(np.abs(traj.omega - exact)) < tolerance


@pytest.mark.parametrize("method", list(METHODS))
def test_quadratic_drag_on_a_ball_slows_as_one_over_time(method: str) -> None:
    # About one axis I ω̇ = −c ω |ω|: ω(t) = ω0 / (1 + c |ω0| t / I), for either
    # sense of turning (here ω0 = −10 rad/s, so the torque must stay opposite ω).
    # The other axes have no drag and keep their rates exactly.
    options, tolerance = METHODS[method]
    c = 0.0008
    omega0 = np.array([0.5, -10.0, 0.25])
    drag = QuadraticDrag([0.0, c, 0.0])
    traj = tb.simulate(BALL, omega0, duration=2.0, torque=drag, method=method, **options)
    exact = omega0[1] / (1 + c * abs(omega0[1]) * traj.t / MOMENT)
    assert np.max(np.abs(traj.omega[:, 1] - exact)) < tolerance
    assert np.array_equal(traj.omega[:, [0, 2]], np.broadcast_to(omega0[[0, 2]], (len(traj.t), 2)))


@pytest.mark.parametrize(
    ("model", "power"),
    [(AxisDrag([0.002, 0.01, 0.004]), 2), (QuadraticDrag([0.002, 0.01, 0.004]), 3)],
    ids=["linear", "quadratic"],
)
def test_energy_of_an_asymmetric_body_falls_by_the_drags_power(
    model: AxisDrag | QuadraticDrag, power: int
) -> None:
    # dE/dt = ω · τ = −Σ cᵢ |ωᵢ|^p (p = 2 linear, 3 quadratic): negative while the
    # body turns, so E falls at every sample (by ≳ 2e-6 J a sample, far above the
    # adaptive method's error, 1e-10 of E ≈ 0.1 J); and E(t) − E(0) is the work
    # of the drag, −∫ Σ cᵢ |ωᵢ|^p dt. Simpson's rule on samples 1 ms apart errs by
    # ~T dt⁴ max|P⁗| / 180 ≈ 1e-11 J (measured 5e-12): 1e-9 J is room, while a
    # coefficient on the wrong axis changes the work by ~1e-3 J.
    brick = tb.shapes.box(2.0, [0.1, 0.2, 0.3])
    traj = tb.simulate(brick, [0.3, 3.0, 0.2], duration=2.0, dt=1e-3, torque=model)
    assert traj.method == "adaptive" and traj.drift == {}
    energy = traj.energy
    assert np.all(np.diff(energy) < 0)
    power_lost = np.abs(traj.omega) ** power @ np.asarray(model.coefficients)
    work = cumulative_simpson(power_lost, x=traj.t, initial=0.0)
    assert np.max(np.abs(energy - energy[0] + work)) < 1e-9
    assert energy[-1] < 0.2 * energy[0]  # the drag is felt: most of E is gone


@pytest.mark.parametrize("model_class", [AxisDrag, QuadraticDrag])
def test_drag_acts_about_the_body_axes_when_they_are_not_principal(
    model_class: type[AxisDrag | QuadraticDrag],
) -> None:
    # A body given by a tensor whose principal axes are turned from its own axes:
    # the drag is per body axis, so the kernels (in principal axes) must turn ω
    # into body axes and the torque back. scipy's DOP853 in body axes with the
    # full tensor (tests/reference.py) is the oracle; RK4 at dt = 1 ms on rates
    # of ~3 rad/s errs by ~T |ω|⁵ dt⁴ ≈ 1e-10, so 1e-8 is room, while drag about
    # the principal axes instead differs by ~1e-2.
    turn = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    tensor = turn @ np.diag([0.02, 0.03, 0.045]) @ turn.T
    body = tb.MassProperties(1.0, [0, 0, 0], tensor)
    c = np.array([0.004, 0.001, 0.008])
    omega0 = np.array([0.5, 2.5, -1.0])
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    quadratic = model_class is QuadraticDrag

    def drag(t: float, w: np.ndarray, a: np.ndarray) -> np.ndarray:
        return -c * w * (np.abs(w) if quadratic else 1.0)

    traj = tb.simulate(body, omega0, duration=1.0, dt=1e-3, torque=model_class(c), method="rk4")
    omega, _ = reference(body, omega0, q0, 1.0, torque=drag)
    assert np.max(np.abs(traj.omega[-1] - omega)) < 1e-8
    principal = tb.simulate(
        tb.shapes.box(1.0, [0.1, 0.2, 0.3]),
        omega0,
        duration=1.0,
        dt=1e-3,
        torque=model_class(c),
        method="rk4",
    )
    assert np.max(np.abs(principal.omega[-1] - omega)) > 1e-3  # another body, to see it differ


@pytest.mark.parametrize("model_class", [AxisDrag, QuadraticDrag])
def test_a_batch_takes_drag_per_body_and_shared(
    model_class: type[AxisDrag | QuadraticDrag],
) -> None:
    # Three bodies given by tensors (each its own principal axes), one row of
    # coefficients per body, then one row shared: each body as simulate gives it
    # alone. The same arithmetic up to FMA contraction in the vectorised
    # kernels: round-off amplified over 500 steps, ≲ 1e-12.
    rotations = Rotation.random(3, random_state=5).as_matrix()
    moments = np.array([[1.0, 2.0, 2.5], [0.5, 0.7, 1.0], [2.0, 2.0, 3.0]])
    tensors = np.einsum("nij,nj,nkj->nik", rotations, moments, rotations)
    omega = np.random.default_rng(5).normal(size=(3, 3))
    per_body = np.array([[0.1, 0.0, 0.3], [0.05, 0.2, 0.01], [0.0, 0.0, 0.0]])
    for coefficients in (per_body, per_body[1]):
        batch = tb.simulate_batch(
            tensors,
            omega,
            duration=0.5,
            dt=1e-3,
            torque=model_class(coefficients),
            record_every=250,
        )
        for k in range(3):
            alone = tb.simulate(
                tb.MassProperties(1.0, [0, 0, 0], tensors[k]),
                omega[k],
                duration=0.5,
                dt=1e-3,
                method="rk4",
                record_every=250,
                torque=model_class(coefficients if coefficients.ndim == 1 else coefficients[k]),
            )
            assert batch.omega_history is not None
            assert_allclose(batch.omega_history[:, k], alone.omega, atol=1e-12)
    name = model_class.__name__
    with pytest.raises(
        tb.InputError,
        match=rf"Expected per-body {name} values of shape \(3, 3\) for 3 bodies, got \(2, 3\)\.",
    ):
        tb.simulate_batch(tensors, omega, duration=0.1, dt=1e-3, torque=model_class(per_body[:2]))
    with pytest.raises(tb.InputError, match=r"Expected one torque for one body, got per-body"):
        tb.simulate(BALL, [0, 0, 1.0], duration=0.1, torque=model_class(per_body))


def test_the_registry_names_both_and_says_what_they_are() -> None:
    assert TORQUES["drag"] is AxisDrag and TORQUES["quadratic-drag"] is QuadraticDrag
    for model in (AxisDrag([1, 2, 3]), QuadraticDrag([1, 2, 3])):
        assert not model.conservative and model.depends_on == frozenset({"omega"})
        assert model.in_batches and model.in_files
        assert model.conserves(BALL) == frozenset()
        again = from_description(model.describe())  # as a trajectory file keeps it
        assert type(again) is type(model)
        assert np.array_equal(again.coefficients, model.coefficients)
    assert repr(AxisDrag("1, 2, 3 mN*m*s")) == "AxisDrag([0.001, 0.002, 0.003] N·m·s)"
    assert {"drag_1", "drag_3", "quadratic_drag_2"} <= set(tb.sweep.PARAMETERS)


SPUN = """\
[scenario]
name = "spun"

[body]
shape = "solid-sphere"
mass = "2 kg"
radius = "10 cm"

[initial]
omega = "1, -2, 3 rad/s"

[[torques]]
type = "drag"
coefficients = "8, 4, 2 mN*m*s"

[simulation]
duration = "2 s"
dt = "10 ms"
method = "rk4"
"""


def test_a_scenario_file_names_the_drag_by_its_registry_name() -> None:
    # The file's model is AxisDrag([8, 4, 2] mN·m·s) on the ball of the first test:
    # the same closed form, the same RK4 error bound (1e-8).
    result = run(parse(SPUN, source="spun.toml"))
    traj = result.trajectory
    exact = np.array([1.0, -2.0, 3.0]) * np.exp(-np.outer(traj.t, [8e-3, 4e-3, 2e-3]) / MOMENT)
    assert np.max(np.abs(traj.omega - exact)) < 1e-8
    quadratic = SPUN.replace('"drag"', '"quadratic-drag"').replace("mN*m*s", "g*m^2")
    traj = run(parse(quadratic, source="spun.toml")).trajectory
    assert_allclose(traj.omega[-1, 2], 3.0 / (1 + 2e-3 * 3.0 * 2.0 / MOMENT), atol=1e-8)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            '"8, 4, 2 mN*m*s"',
            '"8, -4, 2 mN*m*s"',
            r"line 14, `torques\[0\]\.coefficients`: Expected `coefficients` >= 0 N·m·s, "
            r"got coefficients\[1\] = -0\.004\.",
        ),
        (
            '"8, 4, 2 mN*m*s"',
            '"8, 4 mN*m*s"',
            r"`torques\[0\]\.coefficients`: Expected `coefficients` to have shape \(3,\), "
            r"got \(2,\)\.",
        ),
    ],
)
def test_a_scenario_file_refuses_bad_coefficients(old: str, new: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse(SPUN.replace(old, new), source="spun.toml")


@pytest.mark.parametrize(
    ("model_class", "value", "message"),
    [
        (
            AxisDrag,
            [0.1, -0.2, 0.3],
            r"Expected `coefficients` >= 0 N·m·s, got coefficients\[1\] = -0\.2\.",
        ),
        (
            QuadraticDrag,
            [-1.0, 0, 0],
            r"Expected `coefficients` >= 0 kg·m², got coefficients\[0\] = -1\.0\.",
        ),
        (AxisDrag, [0.1, 0.2], r"Expected `coefficients` to have shape \(3,\), got \(2,\)\."),
        (QuadraticDrag, 0.1, r"Expected `coefficients` to be an array of shape \(3,\), got 0\.1\."),
        (AxisDrag, [[0.1, 0.2]], r"Expected `coefficients` to have shape \(n, 3\), got \(1, 2\)\."),
        (
            AxisDrag,
            "1, 2, 3 m",
            r"Expected `coefficients` to be a damping in N\*m\*s, got .*\[length\]",
        ),
        (
            QuadraticDrag,
            "1, 2, 3 m",
            r"Expected `coefficients` to be an inertia in kg\*m\^2, got .*\[length\]",
        ),
        (AxisDrag, [0.1, float("nan"), 0.3], r"Expected `coefficients` to be finite, got"),
    ],
    ids=[
        "negative",
        "negative-quadratic",
        "two",
        "number",
        "rows-of-two",
        "length",
        "length-quadratic",
        "nan",
    ],
)
def test_bad_coefficients_are_refused(
    model_class: type[AxisDrag | QuadraticDrag], value: Any, message: str
) -> None:
    with pytest.raises(tb.InputError, match=message):
        model_class(value)
