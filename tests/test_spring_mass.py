"""A point mass on a spring inside a free body (tumble.SpringMassDamper): its kinetic
energy against the sum over the masses (sympy), its motion against a Newton–Euler
integration and a closed form, the conservation laws, files and errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, spring_mass_reference
from tumble.errors import IntegrationError

AXES = Rotation.from_rotvec([0.2, 0.3, -0.1])
HUB = tb.MassProperties(
    30.0, [0.05, 0, 0], AXES.as_matrix() @ np.diag([1.0, 3.0, 3.2]) @ AXES.as_matrix().T
)
MASS = 0.5
POSITION = np.array([0.1, 0.3, -0.1])
DIRECTION = np.array([0.2, 0.1, 1.0])
BODY = HUB + tb.point_masses([MASS], [POSITION])
OMEGA0 = np.array([0.8, 0.3, -0.4])
Q0 = Rotation.from_rotvec([0.1, -0.2, 0.3]).as_quat(scalar_first=True)


def spring(stiffness: float = 5.0, damping: float = 0.3, displacement: float = 0.05):
    return tb.SpringMassDamper(MASS, POSITION, DIRECTION, stiffness, damping, displacement)


def test_the_kinetic_energy_is_the_sum_over_the_masses() -> None:
    # A hub (mass M, inertia J about its centre of mass) and a particle m at
    # d = d0 + x n from it, about their common centre of mass: the sum of
    # ½ m v² and the hub's ½ ωᵀ J ω equals the reduced form the kernels use.
    big, small = sp.symbols("M m", positive=True)
    x, xd = sp.symbols("x xdot", real=True)
    w = sp.Matrix(sp.symbols("w1:4", real=True))
    d0 = sp.Matrix(sp.symbols("a1:4", real=True))
    n = sp.Matrix(sp.symbols("n1:4", real=True))
    hub = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"J{min(i, j)}{max(i, j)}"))
    d = d0 + x * n
    share = small / (big + small)
    v_hub = w.cross(-share * d) - share * xd * n
    v_mass = w.cross((1 - share) * d) + (1 - share) * xd * n
    summed = (w.T * hub * w)[0] / 2 + big * v_hub.dot(v_hub) / 2 + small * v_mass.dot(v_mass) / 2
    mu = big * small / (big + small)
    inertia = hub + mu * (d.dot(d) * sp.eye(3) - d * d.T)
    reduced = (w.T * inertia * w)[0] / 2 + xd * w.dot(mu * d0.cross(n)) + mu * xd**2 * n.dot(n) / 2
    assert sp.simplify(sp.expand(summed - reduced)) == 0


@pytest.mark.parametrize(("method", "dt"), [("rk4", 1e-3), ("adaptive", 0.05)])
def test_it_follows_a_newton_euler_integration(method: str, dt: float) -> None:
    # Skewed body axes, the mass off every axis, a slanted slot: over 20 s the
    # reference (DOP853, rtol 1e-12) and both methods agree to ~1e-13; 1e-11 asked.
    run = tb.simulate(
        BODY, OMEGA0, attitude0=Q0, duration=20.0, dt=dt, method=method, internal=[spring()],
        rtol=1e-12, atol=1e-14, record_every=50 if method == "rk4" else 1,
    )  # fmt: skip
    omega, matrices, x, speed = spring_mass_reference(
        BODY, MASS, POSITION, DIRECTION, 5.0, 0.3, OMEGA0, Q0, 20.0, displacement=0.05,
        times=run.t,
    )  # fmt: skip
    assert np.max(np.abs(run.omega - omega)) < 1e-11
    assert attitude_error(run.quaternion, matrices) < 1e-11
    assert np.max(np.abs(run.internal_values[:, 0] - x)) < 1e-11
    assert np.max(np.abs(run.internal_values[:, 1] - speed)) < 1e-11
    # The angular momentum the trajectory reports, against the reference's own
    # H = I_h ω + μ d × (ω × d + ẋ n) about the moving centre of mass.
    total = BODY.mass
    mu = MASS * (total - MASS) / total
    n = DIRECTION / np.linalg.norm(DIRECTION)
    rest = total / (total - MASS) * (POSITION - BODY.center_of_mass)
    hub = BODY.inertia - mu * (rest @ rest * np.eye(3) - np.outer(rest, rest))
    d = rest + x[:, None] * n
    h = omega @ hub + mu * np.cross(d, np.cross(omega, d) + speed[:, None] * n)
    assert_allclose(run.angular_momentum, np.einsum("nij,nj->ni", matrices, h), atol=1e-11)


def test_without_rotation_the_mass_oscillates_at_the_reduced_mass_frequency() -> None:
    # The slot through the centres of mass (d0 ∥ n) and no rotation: no torque
    # couples, and x = x0 cos(√(k/μ) t) with μ = m (M − m)/M. RK4 at 1 ms on
    # √(k/μ) ≈ 3.2 rad/s over 10 s: ~1e-12.
    hub = tb.MassProperties(10.0, [0, 0, 0], np.diag([1.0, 1.2, 1.4]))
    body = hub + tb.point_masses([1.0], [[0.5, 0, 0]])
    part = tb.SpringMassDamper(1.0, [0.5, 0, 0], [1, 0, 0], stiffness=10.0, displacement=0.02)
    run = tb.simulate(body, [0, 0, 0], duration=10.0, dt=1e-3, method="rk4", internal=[part])
    frequency = math.sqrt(10.0 / (1.0 * 10.0 / 11.0))
    assert_allclose(run.internal_values[:, 0], 0.02 * np.cos(frequency * run.t), atol=1e-12)
    assert np.max(np.abs(run.omega)) < 1e-15


def test_without_damping_the_energy_stays_and_with_it_falls_toward_a_major_axis_spin() -> None:
    # A prolate body spun near its minor axis (x) with a 1 kg mass sliding along x
    # off that axis: |H| stays to 1e-10 (RK4 at 5 ms over 3000 s) either way.
    # Undamped, the energy (kinetic and elastic) stays to 1e-10; damped, it falls
    # at every sample, more than halfway from its start to |H|² / (2 I_max), the
    # energy of a spin about the major axis (the last stretch of that approach is
    # slow: the spring is off resonance with the flat spin's wobble).
    hub = tb.MassProperties(30.0, [0, 0, 0], np.diag([1.0, 3.0, 3.2]))
    body = hub + tb.point_masses([1.0], [[0.0, 0.4, 0.0]])
    for damping in (0.0, 1.0):
        part = tb.SpringMassDamper(1.0, [0.0, 0.4, 0.0], [1, 0, 0], 6.0, damping)
        run = tb.simulate(body, [2.0, 0.05, 0.02], duration=3000.0, dt=0.005, method="rk4",
                          internal=[part], record_every=100)  # fmt: skip
        size = np.linalg.norm(run.angular_momentum, axis=1)
        assert np.max(np.abs(size - size[0])) / size[0] < 1e-10
        if damping == 0.0:
            assert run.conserved_quantities == ("energy", "angular_momentum_vector")
            assert run.drift["energy"] < 1e-10
        else:
            assert run.conserved_quantities == ("angular_momentum_vector",)
            assert np.all(np.diff(run.energy) <= 1e-12 * run.energy[0])
            lowest = size[0] ** 2 / (2 * body.principal()[0][2])
            assert run.energy[-1] - lowest < 0.5 * (run.energy[0] - lowest)


def test_a_trajectory_with_a_spring_round_trips_through_parquet(tmp_path) -> None:
    run = tb.simulate(BODY, OMEGA0, duration=1.0, dt=0.01, method="rk4", internal=[spring()])
    run.to_parquet(tmp_path / "spring.parquet")
    back = tb.Trajectory.read_parquet(tmp_path / "spring.parquet")
    assert isinstance(back.internal[0], tb.SpringMassDamper)
    assert_allclose(back.internal_values, run.internal_values, rtol=0, atol=0)
    assert_allclose(back.energy, run.energy, rtol=1e-14)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (
            lambda: tb.SpringMassDamper(0, POSITION, DIRECTION, 1.0),
            r"Expected `mass` of a SpringMassDamper > 0 kg, got 0\.0",
        ),
        (
            lambda: tb.SpringMassDamper(1.0, POSITION, [0, 0, 0], 1.0),
            r"Expected `direction` of a SpringMassDamper to be a non-zero vector",
        ),
        (
            lambda: tb.SpringMassDamper(1.0, POSITION, DIRECTION, -1.0),
            r"Expected `stiffness` of a SpringMassDamper > 0 N/m, got -1\.0",
        ),
        (
            lambda: tb.SpringMassDamper(1.0, POSITION, DIRECTION, 1.0, -0.1),
            r"Expected `damping` of a SpringMassDamper >= 0 N·s/m, got -0\.1",
        ),
        (lambda: tb.SpringMassDamper(1.0, "3 kg", DIRECTION, 1.0), r"`position`"),
    ],
)
def test_bad_springs_are_refused(make, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        make()


def test_a_spring_not_yet_attached_to_a_body_has_no_coupling() -> None:
    # Its reduced mass and rest position depend on the body that carries it.
    with pytest.raises(
        tb.InputError, match=r"^Expected a SpringMassDamper attached to a body, got a bare one\.$"
    ):
        spring().coupling()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"internal": [spring(), spring()]},
            r"Expected at most one SpringMassDamper in a body, got 2",
        ),
        (
            {"internal": [spring()], "pivot": [0, 0, 0], "gravity": [0, 0, -9.81]},
            r"Expected a free body for a SpringMassDamper .*, got a pivot",
        ),
        (
            {"internal": [tb.SpringMassDamper(40.0, POSITION, DIRECTION, 1.0)]},
            r"Expected the body's mass \(30\.5 kg\) to hold the SpringMassDamper's mass and more, got 40\.0 kg",
        ),
        (
            {"internal": [spring()], "method": "splitting"},
            r"carrying spring-mass-damper parts \(auto, rk4, adaptive\), got 'splitting'",
        ),
    ],
)
def test_bad_bodies_with_a_spring_are_refused(kwargs, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(BODY, OMEGA0, duration=1.0, dt=0.1, **kwargs)


@pytest.mark.parametrize(
    ("stiffness", "damping"), [(10.0, 0.0), (10.0, 2.0), (10.0, 50.0), (1e6, 1e4)]
)
def test_the_internal_rate_is_the_largest_eigenvalue_of_the_slot_oscillator(
    stiffness: float, damping: float
) -> None:
    # Oracle: the eigenvalues of the first-order system of μ ẍ + c ẋ + k x = 0; the
    # slot through the centres of mass (d0 ∥ n): no coupling to the platform.
    body = tb.MassProperties(11.0, [0, 0, 0], np.diag([1.0, 1.2, 1.4]))
    part = tb.SpringMassDamper(1.0, [0.5, 0, 0], [1, 0, 0], stiffness, damping).attached(body)
    reduced = 1.0 * 10.0 / 11.0
    system = np.array([[0.0, 1.0], [-stiffness / reduced, -damping / reduced]])
    largest = np.max(np.abs(np.linalg.eigvals(system)))
    own, pull = part.internal_rates(body.inertia)
    assert own == pytest.approx(largest, rel=1e-12)
    assert pull == 0.0


def test_a_spring_across_the_centre_of_mass_oscillates_at_its_internal_rate() -> None:
    # Oracle: the oscillation measured in a simulation. A slot off the centre of
    # mass (d0 not along n) makes the body rock as the mass moves: the spring moves
    # less than μ, μ' = μ − gᵀ I_p⁻¹ g, and oscillates faster than √(k/μ) (14.96
    # against 10.49 rad/s here). RK4 at 1 ms over 5 s and an amplitude of 0.1 mm
    # (second-order terms ~1e-4 of the first): the frequency to 1e-6.
    hub = tb.MassProperties(10.0, [0, 0, 0], np.diag([0.05, 0.06, 0.07]))
    body = hub + tb.point_masses([1.0], [[0.1, 0.3, 0]])
    part = tb.SpringMassDamper(1.0, [0.1, 0.3, 0], [1, 0, 0], stiffness=100.0, displacement=1e-4)
    run = tb.simulate(body, [0, 0, 0], duration=5.0, dt=1e-3, method="rk4", internal=[part])
    measured = tb.analysis.oscillation_frequency(run.t, run.internal_values[:, 0])
    own, _ = part.attached(body).internal_rates(body.inertia)
    assert own == pytest.approx(measured, rel=1e-6)
    assert own > 1.4 * math.sqrt(100.0 / (1.0 * 10.0 / 11.0))


def test_a_step_beyond_rk4s_stability_for_the_spring_is_refused_and_would_diverge(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The slot oscillator of the test above at k = 1e6 N/m: √(k/μ) ≈ 1049 1/s.
    # RK4 is stable for dt × rate <= 2.785 on the real axis and 2.83 on the
    # imaginary axis: at 2.5 the run keeps the spring's energy bounded; at 3.2
    # it is refused, and, with the check removed, it does diverge.
    hub = tb.MassProperties(10.0, [0, 0, 0], np.diag([1.0, 1.2, 1.4]))
    body = hub + tb.point_masses([1.0], [[0.5, 0, 0]])
    part = tb.SpringMassDamper(1.0, [0.5, 0, 0], [1, 0, 0], stiffness=1e6, displacement=0.02)
    rate = math.sqrt(1e6 / (10.0 / 11.0))
    stable = tb.simulate(
        body, [0, 0, 0], duration=1.0, dt=2.5 / rate, method="rk4", internal=[part]
    )
    assert np.max(np.abs(stable.internal_values[:, 0])) <= 0.02 * (1 + 1e-9)
    with pytest.raises(
        tb.InputError,
        match=r"^Expected dt within the stability of the method for the SpringMassDamper's own "
        r"rate \(1\.05e\+03 1/s\): dt × rate <= 2\.78, got dt = 0\.00305 s, dt × rate = 3\.2 "
        r"\(the run would diverge\); use dt <= 0\.00265 s, or less damping or stiffness\.$",
    ):
        tb.simulate(body, [0, 0, 0], duration=1.0, dt=3.2 / rate, method="rk4", internal=[part])
    monkeypatch.setattr(tb.simulation, "check_internal_stability", lambda *args: None)
    with pytest.raises(tb.InputError, match=r"NaN or inf"):
        tb.simulate(body, [0, 0, 0], duration=1.0, dt=3.2 / rate, method="rk4", internal=[part])


def test_a_stiff_kane_damper_is_refused_before_any_step() -> None:
    # D (1/J + 1/I_p) with D = 1e12 N·m·s and J = 1e-4 kg·m²: ~1e16 1/s, so
    # Dormand–Prince (stable to |h λ| = 3.3) needs ~3e15 steps for 1 s: refused
    # at once rather than stopped after 5e7 steps.
    box = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
    with pytest.raises(
        tb.RequestTooLargeError,
        match=r"^Expected the adaptive integration to end within 5e\+07 steps \(max_steps\), got "
        r"at least 3\.1e\+15 steps: the KaneDamper's own rate \(1\.02e\+16 1/s\) holds an "
        r"explicit method's step under 3\.22e-16 s \(a stiff part\)",
    ):
        tb.simulate(
            box, [0.1, 2, 0.1], duration=1, method="adaptive", internal=[tb.KaneDamper(1e-4, 1e12)]
        )


@pytest.mark.parametrize("inertias", [(0.3,), (0.4, 0.4), (0.05, 0.2, 0.1)])
def test_the_dampers_rate_bounds_the_coupled_system_and_is_exact_for_one(
    inertias: tuple[float, ...],
) -> None:
    # Oracle: the eigenvalues of the platform (moment I_p about one axis) and the
    # spheres coupled by D_i (ω − ω_i): d/dt (ω, ω_i) = M⁻¹ K with M = diag(I_p, J_i).
    # The bound max D_i/J_i + Σ D_i/I_p holds for any number, and is the largest
    # eigenvalue itself for one damper.
    from tumble.parts import internal_rate

    dampers = [tb.KaneDamper(j, 1.0 + k) for k, j in enumerate(inertias)]
    locked = np.diag([1.0, 2.0, 3.0])
    platform = locked - sum(j for j in inertias) * np.eye(3)
    smallest = float(np.linalg.eigvalsh(platform)[0])
    n = len(dampers)
    coupling = np.zeros((n + 1, n + 1))
    for k, damper in enumerate(dampers, start=1):
        coupling[[0, k], [0, k]] += damper.damping
        coupling[[0, k], [k, 0]] -= damper.damping
    masses = np.diag([smallest, *inertias])
    largest = np.max(np.abs(np.linalg.eigvals(np.linalg.solve(masses, coupling))))
    rate, names = internal_rate(dampers, platform)
    assert names == ["KaneDamper"] * n
    if n == 1:
        assert rate == pytest.approx(largest, rel=1e-12)
    else:
        assert largest <= rate < 2.0 * largest


def test_two_dampers_beyond_rk4s_stability_together_are_refused() -> None:
    # Each alone (D/J + D/I_p = 2.5 + 5 = 7.5 1/s) would allow dt = 0.3 s; together
    # they pull the platform (I_p = 0.2 kg·m²) at 10 1/s, the bound 12.5 1/s: the
    # coupled system's largest rate is 11.4 1/s, and dt × 11.4 = 3.4 diverges.
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    dampers = [tb.KaneDamper(0.4, 1.0), tb.KaneDamper(0.4, 1.0)]
    with pytest.raises(
        IntegrationError,
        match=r"^Expected dt within the stability of the method for the KaneDamper's own rate "
        r"\(12\.5 1/s\): dt × rate <= 2\.78, got dt = 0\.3 s",
    ):
        tb.simulate(body, [0.1, 0.2, 3.0], duration=3.0, dt=0.3, method="rk4", internal=dampers)


def test_simulate_batch_refuses_a_step_beyond_the_dampers_stability() -> None:
    # One damper: D/J + D/I_p = 100 + 1.01 1/s on the lightest platform (I_p = 0.99).
    inertia = np.tile([1.0, 2.0, 3.0], (4, 1))
    omega = np.tile([0.1, 1.0, 0.1], (4, 1))
    damper = tb.KaneDamper(0.01, 1.0)
    with pytest.raises(IntegrationError, match=r"KaneDamper's own rate \(101 1/s\)"):
        tb.simulate_batch(inertia, omega, duration=1.0, dt=0.04, internal=[damper])
    stable = tb.simulate_batch(inertia, omega, duration=1.0, dt=0.02, internal=[damper])
    assert np.all(np.isfinite(stable.omega))


def test_the_default_step_resolves_a_fast_damper() -> None:
    # A body nearly at rest with a damper of rate 101 1/s: the default step is
    # 1 / rate, not the rotation's, so the run is stable and keeps |L|.
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    run = tb.simulate(body, [1e-3, 0, 0], duration=1.0, method="rk4",
                      internal=[tb.KaneDamper(0.01, 1.0)])  # fmt: skip
    assert run.dt <= 1.0 / (1 / 0.01 + 1 / 0.99)
    assert np.max(run.relative_change("angular_momentum_vector")) < 1e-12
