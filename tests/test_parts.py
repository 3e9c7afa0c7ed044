"""Bodies carrying rotors and Kane dampers: against an independent integration,
closed forms, conservation laws, schedules and limits, files and every error."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, gyrostat_reference
from tumble.parts import KaneDamper, Rotor

# A hub whose body axes are not principal, two wheels on skew axes away from
# the centre of mass and a damper sphere: every part locked into MP.
AXES = Rotation.from_rotvec([0.2, -0.4, 0.7])
HUB = tb.MassProperties(
    80.0, [0.05, -0.02, 0.1], AXES.as_matrix() @ np.diag([6.0, 9.0, 12.0]) @ AXES.as_matrix().T
)


def wheel(axis, position, mass=3.0, radius=0.23, height=0.04):
    """A disc turned so its symmetry axis lies along ``axis``, at ``position``:
    its mass properties (locked) and its moment about its axis."""
    disc = tb.shapes.solid_cylinder(mass, radius, height)
    turn, _ = Rotation.align_vectors([axis], [[0.0, 0.0, 1.0]])
    return disc.transformed(turn, position), float(disc.inertia[2, 2])


AXIS_1 = np.array([1.0, 0.2, 0.0])
AXIS_2 = np.array([0.0, 1.0, 0.5])
WHEEL_1, J1 = wheel(AXIS_1, [0.3, 0.0, 0.0])
WHEEL_2, J2 = wheel(AXIS_2, [0.0, -0.3, 0.1])
SPHERE = tb.shapes.solid_sphere(4.0, 0.1).transformed(None, [0.0, 0.0, 0.4])
JD = float(SPHERE.inertia[0, 0])
GYROSTAT = HUB + WHEEL_1 + WHEEL_2
WITH_DAMPER = GYROSTAT + SPHERE
SCHEDULE = [(0.0, 0.02), (3.0, -0.01), (7.0, 0.0)]
OMEGA0 = np.array([0.3, -0.5, 0.8])
Q0 = Rotation.from_rotvec([0.1, 0.5, -0.3]).as_quat(scalar_first=True)


def motor(t: float) -> float:
    return 0.02 if t < 3.0 else (-0.01 if t < 7.0 else 0.0)


def rotors() -> list[Rotor]:
    return [Rotor(AXIS_1, J1, speed=40.0, torque=SCHEDULE), Rotor(AXIS_2, J2, speed=-25.0)]


REFERENCE_ROTORS = [(AXIS_1, J1, 40.0, motor), (AXIS_2, J2, -25.0, lambda t: 0.0)]


# ------------------------------------------------------------------ the oracle
# Over 10 s (|ω| ~ 1 rad/s, rotors at 25–40 rad/s, a torque schedule with two
# switches on step boundaries). The reference (DOP853, rtol 1e-13) is good to
# ~1e-12; RK4 at 1 ms errs by ~(ω dt)⁴ per unit time, ~1e-12; the fourth-order
# splitting at 1 ms and Strang at 0.1 ms by ~1e-11 and ~1e-9 (their error
# constants are larger, REFERENCES.md); the adaptive method at rtol 1e-12 by
# ~1e-11. Rotor speeds are ~40 rad/s: their tolerance is 40× larger.
@pytest.mark.parametrize(
    ("method", "dt", "damper", "tolerance"),
    [
        ("rk4", 1e-3, True, 1e-10),
        ("adaptive", 1e-2, True, 1e-10),
        ("rk4", 1e-3, False, 1e-10),
        ("adaptive", 1e-2, False, 1e-10),
        ("splitting", 1e-3, False, 1e-10),
        ("strang", 1e-4, False, 2e-9),
    ],
)
def test_a_gyrostat_follows_an_independent_integration(
    method: str, dt: float, damper: bool, tolerance: float
) -> None:
    parts = [*rotors(), KaneDamper(JD, 0.3)] if damper else rotors()
    body = WITH_DAMPER if damper else GYROSTAT
    traj = tb.simulate(
        body, OMEGA0, attitude0=Q0, duration=10.0, dt=dt, method=method, internal=parts,
        rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    omega, matrices, speeds, spheres = gyrostat_reference(
        body, OMEGA0, Q0, 10.0, rotors=REFERENCE_ROTORS,
        dampers=[(JD, 0.3)] if damper else [], times=traj.t,
    )  # fmt: skip
    assert np.max(np.abs(traj.omega - omega)) < tolerance
    assert attitude_error(traj.quaternion, matrices) < tolerance
    assert np.max(np.abs(traj.rotor_speed - speeds)) < 40 * tolerance
    if damper:
        assert np.max(np.abs(traj.internal_values[:, 2:] - spheres)) < tolerance


def test_the_total_angular_momentum_is_the_reference_s() -> None:
    # H = I_p ω + Σ J (a·ω + Ω) a + J_d ω_d (body axes), written out here.
    parts = [*rotors(), KaneDamper(JD, 0.3)]
    traj = tb.simulate(
        WITH_DAMPER, OMEGA0, attitude0=Q0, duration=1.0, dt=1e-2, method="rk4", internal=parts
    )
    a1 = AXIS_1 / np.linalg.norm(AXIS_1)
    a2 = AXIS_2 / np.linalg.norm(AXIS_2)
    platform = WITH_DAMPER.inertia - J1 * np.outer(a1, a1) - J2 * np.outer(a2, a2) - JD * np.eye(3)
    w = traj.omega
    speeds = traj.rotor_speed
    sphere = traj.internal_values[:, 2:]
    h = (
        w @ platform
        + J1 * (w @ a1 + speeds[:, 0])[:, None] * a1
        + J2 * (w @ a2 + speeds[:, 1])[:, None] * a2
        + JD * sphere
    )
    expected = np.einsum("nij,nj->ni", traj.rotation.as_matrix(), h)
    assert_allclose(traj.angular_momentum, expected, rtol=0, atol=1e-13)
    energy = (
        0.5 * np.einsum("ni,ij,nj->n", w, platform, w)
        + 0.5 * J1 * (w @ a1 + speeds[:, 0]) ** 2
        + 0.5 * J2 * (w @ a2 + speeds[:, 1]) ** 2
        + 0.5 * JD * np.sum(sphere**2, axis=1)
    )
    assert_allclose(traj.energy, energy, rtol=1e-14)


# ------------------------------------------------------------------ closed forms
@pytest.mark.parametrize(("method", "angle_tolerance"), [("rk4", 1e-12), ("adaptive", 1e-10),
                                                         ("splitting", 1e-12), ("strang", 1e-12)])  # fmt: skip
def test_wheel_spin_up_follows_the_closed_form(method: str, angle_tolerance: float) -> None:
    # One wheel along principal axis 3 of a body at rest, motor torque u:
    # ω̇3 = −u / (I3 − J), Ω̇ = u / J + u / (I3 − J), the body turning about
    # axis 3 by −u t² / (2 (I3 − J)). ω and Ω are linear in t, so every method
    # gets them to round-off (in the kernels' momenta, H stays 0 and h = u t).
    # The angle is quadratic in t: the splittings turn about axis 3 only, by
    # the midpoint rule's angle, exact for a linear ω3; RK4's error in it is
    # ~(ω3 dt)⁵ per step: all to 1e-12; the adaptive method's error follows its
    # rtol (1e-12 a step, 42 steps): 1e-10.
    hub = tb.MassProperties(50.0, [0, 0, 0], np.diag([10.0, 12.0, 15.0]))
    disc = tb.MassProperties(2.0, [0, 0, 0], np.diag([0.3, 0.3, 0.5]))
    u = 0.1
    run = tb.simulate(
        hub + disc, [0, 0, 0], duration=10.0, dt=0.01, method=method,
        internal=[Rotor([0, 0, 1], 0.5, torque=u)], rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    t = run.t
    platform = 15.5 - 0.5
    assert_allclose(run.omega[:, 2], -u * t / platform, rtol=0, atol=1e-13)
    assert_allclose(run.omega[:, :2], 0.0, atol=1e-15)
    assert_allclose(run.rotor_speed[:, 0], (u / 0.5 + u / platform) * t, rtol=0, atol=1e-11)
    expected = Rotation.from_rotvec(np.outer(-u * t**2 / (2 * platform), [0, 0, 1]))
    assert np.max((run.rotation * expected.inv()).magnitude()) < angle_tolerance
    # The motor's work ∫ u Ω dt: E = ½ (I3 − J) ω3² + h² / (2 J) = ½ u² t² (1/J + 1/(I3 − J)).
    assert_allclose(
        run.energy, 0.5 * u**2 * t**2 * (1 / 0.5 + 1 / platform), rtol=1e-12, atol=1e-15
    )
    assert run.drift.keys() == {"angular_momentum_vector"}


def test_a_symmetric_gyrostat_precesses_at_the_closed_form_rate() -> None:
    # A rotor on the symmetry axis of a symmetric body, free: ω3 stays, and
    # (ω1, ω2) turns in the body at λ = ((I3 − I1) ω3 + J Ω) / I1 (I locked; the
    # gyrostat's Euler equations with h = J Ω constant). Exact in the splitting
    # (every stage is a rotation about axis 3 or about L), to 1e-12 over 20 s.
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 2.0, 3.0]))
    j, speed = 0.2, 50.0
    w0 = np.array([0.1, 0.0, 0.7])
    rate = ((3.0 - 2.0) * w0[2] + j * speed) / 2.0
    # RK4 at 1 ms: a phase error ~(λ dt)⁴ λ t / 120 ~ 5e-10 rad over 20 s, on an
    # amplitude of 0.1 rad/s: 1e-10.
    for method, dt, tolerance in (("splitting", 0.02, 1e-12), ("rk4", 1e-3, 1e-10)):
        run = tb.simulate(
            body, w0, duration=20.0, dt=dt, method=method, internal=[Rotor([0, 0, 1], j, speed)]
        )
        phase = rate * run.t
        assert_allclose(run.omega[:, 0], 0.1 * np.cos(phase), rtol=0, atol=tolerance)
        assert_allclose(run.omega[:, 1], 0.1 * np.sin(phase), rtol=0, atol=tolerance)
        assert_allclose(run.omega[:, 2], 0.7, atol=1e-13)
        assert_allclose(run.rotor_speed[:, 0], speed, atol=1e-11)


@pytest.mark.parametrize(
    ("moments", "axis"), [((2.0, 2.0, 3.0), (0, 0, 1)), ((3.0, 2.0, 2.0), (1, 0, 0))]
)
def test_the_exact_symmetric_gyrostat_follows_an_independent_integration(moments, axis) -> None:
    # Oblate and prolate, body axes turned away from the principal ones, a free
    # rotor on the axis of symmetry: the closed form (a steady precession) against
    # DOP853 at rtol 1e-13 over 30 s: 1e-11.
    turn = Rotation.from_rotvec([0.3, -0.4, 0.2])
    body = tb.MassProperties(
        10.0, [0, 0, 0], turn.as_matrix() @ np.diag(moments) @ turn.as_matrix().T
    )
    rotor_axis = turn.apply(axis)
    w0 = turn.apply([0.2, -0.1, 0.7])
    run = tb.simulate(body, w0, attitude0=Q0, duration=30.0, dt=0.1,
                      internal=[Rotor(rotor_axis, 0.2, speed=50.0)])  # fmt: skip
    assert run.method == "exact" and run.steps == 0
    omega, matrices, speeds, _ = gyrostat_reference(
        body, w0, Q0, 30.0, rotors=[(rotor_axis, 0.2, 50.0, lambda t: 0.0)], times=run.t
    )
    assert np.max(np.abs(run.omega - omega)) < 1e-11
    assert attitude_error(run.quaternion, matrices) < 1e-11
    assert np.max(np.abs(run.rotor_speed[:, 0] - speeds[:, 0])) < 1e-10


# Locked moments, rotor axis, ω0 and rotor speed, both in principal axes. The
# cases cover both normal forms of the closed form (tumble.core.gyrostat): four
# real roots (s = sn²) with each placement of sn, cn, dn in x and y, and a
# complex pair (s = cn); the rotor on each principal axis; the platform moment
# about the rotor equal to another (locked 3.2 less J = 0.2: a root at infinity);
# a start with H1 = 0; a motion near a steady spin (m = 3.6e-6); and nearly
# prolate platforms whose H passes close to a principal axis (Euler angles
# about it would turn abruptly: the closed form takes them about another).
GYROSTATS = [
    ((1.0, 2.99, 3.0), (0, 0, 1), (0.02, 0.5, 2.0), 1.0),
    ((1.0, 2.99, 3.0), (0, 1, 0), (0.02, 0.5, 2.0), 1.0),
    ((2.0, 3.0, 4.0), (0, 0, 1), (0.2, -0.1, 0.7), 5.0),
    ((2.0, 3.0, 4.0), (1, 0, 0), (0.2, -0.1, 0.7), 5.0),
    ((2.0, 3.0, 4.0), (0, 1, 0), (0.2, -0.1, 0.7), 5.0),
    ((2.0, 3.0, 3.2), (0, 0, 1), (0.3, 0.5, 0.4), 5.0),
    ((2.0, 3.0, 4.0), (0, 0, -1), (0.9, 0.1, 0.1), -1.0),
    ((2.0, 3.0, 4.0), (0, 0, 1), (0.0, 0.9, 0.2), -3.0),
    ((2.0, 3.0, 4.0), (0, 1, 0), (0.5, 0.3, 0.4), -2.0),
    ((2.0, 3.0, 4.0), (1, 0, 0), (0.9, 0.1, 0.1), -1.0),
]


@pytest.mark.parametrize(("moments", "axis", "w0", "speed"), GYROSTATS)
def test_the_exact_gyrostat_follows_an_independent_integration(moments, axis, w0, speed) -> None:
    # Three unequal platform moments, a free rotor on one principal axis, body
    # axes turned away from the principal ones: the closed form (Jacobi
    # elliptic functions, the attitude by Chebyshev panels) against DOP853 at
    # rtol 1e-13 over 30 s (several periods): 1e-11 (the reference's own error
    # is ~1e-12).
    turn = Rotation.from_rotvec([0.3, -0.4, 0.2])
    body = tb.MassProperties(
        10.0, [0, 0, 0], turn.as_matrix() @ np.diag(moments) @ turn.as_matrix().T
    )
    rotor_axis, omega0 = turn.apply(axis), turn.apply(w0)
    run = tb.simulate(body, omega0, attitude0=Q0, duration=30.0, dt=0.1,
                      internal=[Rotor(rotor_axis, 0.2, speed=speed)])  # fmt: skip
    assert run.method == "exact" and run.steps == 0 and "gyrostat" in run.reason
    omega, matrices, speeds, _ = gyrostat_reference(
        body, omega0, Q0, 30.0, rotors=[(rotor_axis, 0.2, speed, lambda t: 0.0)], times=run.t
    )
    assert np.max(np.abs(run.omega - omega)) < 1e-11
    assert attitude_error(run.quaternion, matrices) < 1e-11
    assert np.max(np.abs(run.rotor_speed[:, 0] - speeds[:, 0])) < 1e-10


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1)])
def test_the_exact_gyrostat_agrees_with_the_splitting_over_hundreds_of_periods(axis) -> None:
    # Over 2000 s (~300 periods of ω) the closed form is compared with the
    # fourth-order splitting at dt = 5 ms, an independent method: their
    # difference falls 16-fold when the step is halved (from 3.4e-8 to 2.1e-9
    # rad in the worst case, measured), so it is the splitting's own error and
    # the closed form's phase and precession angle do not drift: 5e-9.
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))
    rotor = Rotor(axis, 0.2, speed=5.0)
    exact = tb.simulate(body, [0.2, -0.1, 0.7], duration=2000.0, dt=10.0, internal=[rotor])
    stepped = tb.simulate(body, [0.2, -0.1, 0.7], duration=2000.0, dt=0.005,
                          record_every=2000, internal=[rotor], method="splitting")  # fmt: skip
    assert exact.method == "exact"
    assert np.max(np.abs(exact.omega - stepped.omega)) < 5e-9
    turn = Rotation.from_quat(exact.quaternion, scalar_first=True).inv() * Rotation.from_quat(
        stepped.quaternion, scalar_first=True
    )
    assert np.max(turn.magnitude()) < 5e-9


@pytest.mark.parametrize(
    ("w0", "speed"),
    [
        ((0.0, 0.0, 0.7), 5.0),  # ω along the rotor: H parallel to ω, a steady spin
        ((0.2, -0.1, 0.7), -0.7),  # J (a·ω + Ω) = 0: the platform turns as a rigid body
    ],
)
def test_the_exact_gyrostat_s_special_motions_follow_an_independent_integration(w0, speed):
    # Body axes principal, so the rotor's momentum is exactly zero in the
    # second case: against DOP853 at rtol 1e-13 over 30 s, as above.
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))
    run = tb.simulate(body, w0, attitude0=Q0, duration=30.0, dt=0.1,
                      internal=[Rotor([0, 0, 1], 0.2, speed=speed)])  # fmt: skip
    assert run.method == "exact"
    omega, matrices, speeds, _ = gyrostat_reference(
        body, w0, Q0, 30.0, rotors=[((0, 0, 1), 0.2, speed, lambda t: 0.0)], times=run.t
    )
    assert np.max(np.abs(run.omega - omega)) < 1e-11
    assert attitude_error(run.quaternion, matrices) < 1e-11
    assert np.max(np.abs(run.rotor_speed[:, 0] - speeds[:, 0])) < 1e-10


def test_the_exact_gyrostat_follows_an_independent_integration_near_the_separatrix() -> None:
    # Rotor on axis 3 with h = 0.1 kg·m²/s: ω = (0, 1, −0.125) rad/s is the
    # unstable steady spin (ω ∥ H: I2 ω3 = I3 ω3 + h, platform moments 3 and
    # 3.8). 1e-3 rad/s off it the motion passes 1.5e-6 (in 1 − m) from the
    # separatrix and swings ω2 through 1.9 rad/s. Against DOP853 over 30 s: the
    # reference's error grows with the motion's sensitivity to its state, and
    # the roots' round-off with 1/ε: 3e-11 (measured 9e-12).
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))
    w0, rotor = (1e-3, 1.0, -0.125), ((0, 0, 1), 0.2, 0.625)
    run = tb.simulate(body, w0, duration=30.0, dt=0.1, internal=[Rotor(*rotor)])
    assert run.method == "exact" and np.ptp(run.omega[:, 1]) > 1.8
    omega, matrices, _, _ = gyrostat_reference(
        body, w0, np.array([1.0, 0, 0, 0]), 30.0, rotors=[(*rotor, lambda t: 0.0)], times=run.t
    )
    assert np.max(np.abs(run.omega - omega)) < 3e-11
    assert attitude_error(run.quaternion, matrices) < 3e-11


@pytest.mark.parametrize(
    ("solution", "axis", "message"),
    [
        # A rotor off every principal axis: its momentum turns the platform's
        # principal frame away from any closed form.
        (
            "gyrostat_solution",
            [0, 1, 1],
            r"^Expected a gyrostat for the exact solution \(rotors without motors, all on one principal axis of the platform\), got another body\.$",
        ),
        # Three unequal moments: no axis of symmetry, so no steady precession.
        (
            "symmetric_gyrostat",
            [0, 0, 1],
            r"^Expected a symmetric gyrostat \(two equal platform moments, rotors without motors on the axis of symmetry\) for the exact solution, got another body\.$",
        ),
    ],
)
def test_the_exact_gyrostats_refuse_another_body(solution, axis, message) -> None:
    from tumble.body import RigidBody
    from tumble.theory import motions

    body = RigidBody(tb.MassProperties(20.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0])),
                     parts=(Rotor(axis, 0.1, speed=5.0),))  # fmt: skip
    with pytest.raises(tb.InputError, match=message):
        getattr(motions, solution)(
            body, np.array([0.1, 0.2, 0.3]), np.array([1.0, 0, 0, 0]), np.array([0.0, 1.0])
        )


def test_a_rotor_stabilises_a_spin_about_the_intermediate_axis() -> None:
    # Locked moments 4 < 6 < 8, spin 1 rad/s about axis 2: alone it flips; with a
    # rotor of h = J Ω_rel = 4 kg·m²/s > (I3 − I2) Ω along it, it stays
    # (tumble.theory.gyrostat_stability; its frequencies are tested in
    # test_theory_gyrostats.py).
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))
    w0 = np.array([0.01, 1.0, 0.0])
    free = tb.simulate(body, w0, duration=60.0, dt=0.01, method="rk4")
    assert np.min(free.omega[:, 1]) < -0.9  # flipped
    rotor = Rotor([0, 1, 0], 0.5, speed=8.0)
    held = tb.simulate(body, w0, duration=60.0, dt=0.01, method="splitting", internal=[rotor])
    assert np.min(held.omega[:, 1]) > 0.99
    assert tb.theory.gyrostat_stability(body, 1.0, 4.0, axis=(0, 1, 0)).stable


# ------------------------------------------------------------------ conservation
def test_the_splitting_keeps_l_to_round_off_and_bounds_the_energy_over_a_million_steps() -> None:
    # A torque-free gyrostat (asymmetric body, rotors on skew axes, non-principal
    # body axes): every stage of the splitting is an exact rotation, so the
    # space-frame H changes by round-off only: a few ulps a step (its sines and
    # cosines within 2 ulp, c² + s² within 2 ε, so H and q turn by angles equal
    # to ~1e-16), 1e6 steps of 3 sub-steps of 7 turns each: measured 1.4e-12,
    # bound 3e-12; it is symplectic, so the energy error oscillates without growing:
    # the largest error in the last tenth is no larger than twice that in the first.
    parts = [Rotor(AXIS_1, J1, speed=40.0), Rotor(AXIS_2, J2, speed=-25.0)]
    run = tb.simulate(
        GYROSTAT, OMEGA0, attitude0=Q0, duration=1e4, dt=1e-2, method="splitting",
        internal=parts, record_every=1000,
    )  # fmt: skip
    assert run.steps == 1_000_000
    assert run.drift["angular_momentum_vector"] < 3e-12
    energy = np.abs(run.relative_change("energy"))
    tenth = len(energy) // 10
    assert energy.max() < 1e-8  # the splitting's error at this step (~(ω dt)⁴ · its constant)
    assert energy[-tenth:].max() < 2 * energy[: tenth + 1].max() + 1e-15


@pytest.mark.parametrize("method", ["rk4", "adaptive"])
def test_a_kane_damper_keeps_l_loses_energy_and_ends_in_a_major_axis_spin(method: str) -> None:
    # A prolate body spun about its minor axis (Explorer 1) with a damper: the
    # fluid's torque is internal, so |H| stays (RK4 at 5 ms, |ω| = 2 rad/s, over
    # 1000 s: ~1e-11; the adaptive method at rtol 1e-11 likewise; 1e-10 asked);
    # dE/dt = −D |ω − ω_d|² <= 0, so the energy falls at every sample (to
    # round-off of E, 1e-12 relative); the end is a rigid spin about the major
    # axis of the locked body with E = |H|² / (2 I_max) (the nutation decays with
    # a time constant of ~60 s here: after 1000 s, to 1e-6).
    hub = tb.MassProperties(30.0, [0, 0, 0], np.diag([1.0, 3.0, 3.2]))
    sphere = tb.shapes.solid_sphere(10.0, 0.158)
    body = hub + sphere
    damper = KaneDamper(float(sphere.inertia[0, 0]), 0.05)
    run = tb.simulate(
        body, [2.0, 0.05, 0.02], duration=1000.0, dt=0.005, method=method, internal=[damper],
        rtol=1e-11, atol=1e-14, record_every=10,
    )  # fmt: skip
    size = np.linalg.norm(run.angular_momentum, axis=1)
    assert np.max(np.abs(size - size[0])) / size[0] < 1e-10
    assert np.all(np.diff(run.energy) <= 1e-12 * run.energy[0])
    moments, axes = body.principal()
    final = run.energy[-1]
    assert final == pytest.approx(size[-1] ** 2 / (2 * moments[2]), rel=1e-6)
    along = abs(run.omega[-1] @ axes[:, 2]) / np.linalg.norm(run.omega[-1])
    assert along > 1 - 1e-6
    assert run.energy[0] / final > 2.5  # most of the energy went into heat
    assert run.conserved_quantities == ("angular_momentum_vector",)


# ------------------------------------------------------------------ motors and limits
BOX = tb.MassProperties(20.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))


@pytest.mark.parametrize("method", ["rk4", "adaptive", "splitting"])
def test_a_torque_schedule_gives_the_rotor_exactly_its_impulse(method: str) -> None:
    # 0.2 N·m from 0 to 0.5 s, then nothing: the rotor's axial momentum
    # J (a·ω + Ω) changes by 0.2 × 0.5 = 0.1 kg·m²/s exactly (ḣ = u), whatever
    # the body does; the switch falls on a step boundary (and between two
    # adaptive calls), so to round-off.
    rotor = Rotor([0, 0, 1], 0.1, speed=10.0, torque=[(0.0, 0.2), ("0.5 s", 0.0)])
    run = tb.simulate(
        BOX, [0.3, -0.2, 0.5], duration=2.0, dt=0.01, method=method, internal=[rotor],
        rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    h = 0.1 * (run.omega[:, 2] + run.rotor_speed[:, 0])
    after = run.t >= 0.5
    assert_allclose(h[after] - h[0], 0.1, rtol=0, atol=1e-13)
    assert_allclose(rotor.motor_torque([0.0, 0.49, 0.5, 3.0]), [0.2, 0.2, 0.0, 0.0])
    assert run.conserved_quantities == ("angular_momentum_vector",)


def test_the_motor_torque_and_the_speed_are_held_within_the_rotor_s_limits() -> None:
    # Asked 1 N·m with at most 0.25 N·m: the spin-up of the closed form at
    # 0.25 N·m until the rotor reaches 30 rad/s, then the motor stops pushing.
    rotor = Rotor([0, 0, 1], 0.5, torque=1.0, max_torque="0.25 N*m", max_speed=30.0)
    run = tb.simulate(BOX, [0, 0, 0], duration=80.0, dt=0.01, method="rk4", internal=[rotor])
    platform = 4.0 - 0.5
    rate = 0.25 / 0.5 + 0.25 / platform  # Ω̇ under 0.25 N·m
    early = run.t < 20.0
    assert_allclose(run.rotor_speed[early, 0], rate * run.t[early], rtol=1e-12)
    # Held at the limit within one step's gain.
    assert np.max(run.rotor_speed[:, 0]) < 30.0 + rate * 0.01
    assert run.rotor_speed[-1, 0] == pytest.approx(30.0, abs=rate * 0.01)


def test_a_torque_through_the_rotors_moves_momentum_from_the_wheels_to_the_body() -> None:
    # Three wheels on skew axes asked for a body torque v (actuator="rotors"):
    # the motor torques u = −P v share it out, so Σ ḣ a = −v while the total
    # H (zero here) stays: the wheels' momentum along their axes changes by −v t.
    axes = np.array([[1.0, 0.1, 0.0], [0.0, 1.0, 0.3], [0.2, 0.0, 1.0]])
    wheels = [Rotor(a, 0.05) for a in axes]
    v = np.array([0.01, -0.02, 0.015])
    run = tb.simulate(
        BOX, [0, 0, 0], duration=5.0, dt=0.01, method="rk4", internal=wheels,
        torque=tb.torques.ConstantBodyTorque(v, actuator="rotors"),
    )  # fmt: skip
    unit = axes / np.linalg.norm(axes, axis=1)[:, None]
    h = 0.05 * (run.omega @ unit.T + run.rotor_speed)  # (n, 3) axial momenta
    assert_allclose(h @ unit, -np.outer(run.t, v), rtol=0, atol=1e-13)
    assert np.max(np.abs(run.angular_momentum)) < 1e-14
    # The body's own momentum I_p ω (body axes) is +v t.
    platform = BOX.inertia - 0.05 * sum(np.outer(a, a) for a in unit)
    assert_allclose(run.omega @ platform, np.outer(run.t, v), rtol=0, atol=1e-13)


def test_reaction_wheels_slew_a_body_to_a_target_and_keep_its_momentum() -> None:
    # Rest to rest by 60° about z with three wheels under quaternion feedback:
    # the body ends at the target (to 1e-6 rad after 15 time constants) with
    # the wheels at rest again, and the total H stays zero throughout.
    wheels = [Rotor(a, 0.05, max_torque=0.5, max_speed=500.0) for a in np.eye(3)]
    target = Rotation.from_euler("z", 60, degrees=True)
    control = tb.torques.AttitudeController(target, 4.0, 12.0, actuator="rotors")
    run = tb.simulate(
        BOX, [0, 0, 0], duration=120.0, dt=0.02, method="rk4", internal=wheels, torque=control
    )
    assert (target.inv() * run.rotation[-1]).magnitude() < 1e-6
    assert np.max(np.abs(run.rotor_speed[-1])) < 1e-5
    assert np.max(np.abs(run.angular_momentum)) < 1e-13
    assert np.max(np.abs(run.rotor_speed[:, 2])) > 1.0  # the z wheel did the work


# ------------------------------------------------------------------ files and views
def test_a_trajectory_with_parts_round_trips_through_parquet(tmp_path) -> None:
    parts = [*rotors(), KaneDamper(JD, 0.3)]
    run = tb.simulate(
        WITH_DAMPER, OMEGA0, attitude0=Q0, duration=1.0, dt=0.01, method="rk4", internal=parts
    )
    path = tmp_path / "gyrostat.parquet"
    run.to_parquet(path)
    back = tb.Trajectory.read_parquet(path)
    assert [type(p) for p in back.internal] == [Rotor, Rotor, KaneDamper]
    assert_allclose(back.internal_values, run.internal_values, rtol=0, atol=0)
    assert_allclose(back.angular_momentum, run.angular_momentum, rtol=1e-14)
    assert_allclose(back.energy, run.energy, rtol=1e-15)
    import pyarrow.parquet as pq

    names = pq.read_table(path).column_names
    assert {"rotor_1_speed", "rotor_2_speed", "damper_1_omega_x"} <= set(names)
    assert_allclose(back.internal[0].schedule[0], [0.0, 3.0, 7.0])
    half = run.samples(slice(0, 50))
    assert half.internal_values.shape == (50, 5) and half.rotor_speed.shape == (50, 2)
    assert "3 internal parts" in repr(run)


def test_a_trajectory_without_parts_has_no_rotor_speeds() -> None:
    run = tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, dt=0.1, method="rk4")
    assert run.rotor_speed.shape == (len(run.t), 0)
    assert run.internal == ()


def test_auto_chooses_the_splitting_for_rotors_and_the_adaptive_method_for_dampers() -> None:
    free = tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, internal=[Rotor([0, 1, 1], 0.1)])
    assert free.method == "splitting" and "gyrostat" in free.reason
    principal = tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, internal=[Rotor([0, 0, 1], 0.1)])
    assert principal.method == "exact" and "gyrostat" in principal.reason
    symmetric = tb.MassProperties(20.0, [0, 0, 0], np.diag([2.0, 2.0, 4.0]))
    steady = tb.simulate(symmetric, [0.1, 0.2, 0.3], duration=1.0,
                         internal=[Rotor([0, 0, 1], 0.1, speed=20.0)])  # fmt: skip
    assert steady.method == "exact" and "steady precession" in steady.reason
    damped = tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, internal=[KaneDamper(0.1, 0.1)])
    assert damped.method == "adaptive"
    assert damped.reason == (
        "auto: parts the closed form and the splitting do not take (dampers, or rotors "
        "driven by motors), so the adaptive Dormand–Prince 5(4) (rtol 1e-10, atol 1e-12)"
    )
    pushed = tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, internal=[KaneDamper(0.1, 0.1)],
                         torque=tb.torques.LinearDamping(0.01))  # fmt: skip
    assert pushed.reason.startswith(
        "auto: non-conservative torques, so the adaptive Dormand–Prince 5(4)"
    )


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("make", "message"),
    [
        (
            lambda: Rotor([0, 0, 0], 0.1),
            r"Expected `axis` of a Rotor to be a non-zero vector, got \[0.0, 0.0, 0.0\]",
        ),
        (lambda: Rotor([0, 0, 1], -0.1), r"Expected `inertia` of a Rotor > 0 kg·m², got -0.1"),
        (lambda: Rotor([0, 0, 1], "2 kg"), r"`inertia`"),
        (lambda: Rotor([0, 0, 1], 0.1, speed="5 m"), r"`speed`"),
        (
            lambda: Rotor([0, 0, 1], 0.1, torque=[(1.0, 0.1), (0.5, 0.0)]),
            r"increasing times, got times \[1.0, 0.5\] s",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, torque="fast"),
            r"`torque`.*a list of \(time, torque\) pairs",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, max_torque=0),
            r"Expected `max_torque` of a Rotor > 0 N·m, got 0.0",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, max_speed=-1),
            r"Expected `max_speed` of a Rotor > 0 rad/s, got -1.0",
        ),
        (lambda: Rotor([0, 0, 1], 0.1, speed=float("nan")), r"Expected `speed` to be finite"),
        (
            lambda: Rotor([0, 0, 1], 0.1, torque=[[0.0, 1.0], [float("inf"), 0.0]]),
            r"Expected `torque` to be finite, got inf\.",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, torque="3 kg"),
            r"\(a Rotor's `torque` is a torque or a list of \(time, torque\) pairs\)$",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, speed=100, max_speed=10),
            r"Expected `speed` of a Rotor within its `max_speed` \(10.0 rad/s\), got 100.0 rad/s\.",
        ),
        (
            lambda: Rotor([0, 0, 1], 0.1, speed="-3000 rpm", max_speed="2000 rpm"),
            r"Expected `speed` of a Rotor within its `max_speed` \(209.4\d* rad/s\), got -314.1\d* rad/s\.",
        ),
        (
            lambda: tb.SpringMassDamper(1.0, [0, 0, 0], [1, 0, 0], 1.0, geometry="banana"),
            r"unexpected keyword argument 'geometry'",
        ),
        (lambda: KaneDamper(0.0, 0.1), r"Expected `inertia` of a KaneDamper > 0 kg·m², got 0.0"),
        (lambda: KaneDamper(0.1, -1.0), r"Expected `damping` of a KaneDamper >= 0 N·m·s, got -1.0"),
        (
            lambda: tb.torques.AttitudeController([0, 0, 0, 0], 1.0, 1.0),
            r"Expected `target` to be a non-zero quaternion",
        ),
        (
            lambda: tb.torques.AttitudeController([1, 0, 0, 0], 0.0, 1.0),
            r"Expected `stiffness` > 0 N·m, got 0.0",
        ),
        (
            lambda: tb.torques.AttitudeController([1, 0, 0, 0], 1.0, 1.0, actuator="jets"),
            r"Expected `actuator` of AttitudeController to be one of external, rotors, got 'jets'",
        ),
        (lambda: tb.torques.LinearDamping(0.1, actuator="rotors"), r"unexpected keyword"),
    ],
)
def test_bad_parts_are_refused_with_a_clear_message(make, message) -> None:
    with pytest.raises((tb.InputError, TypeError), match=message):
        make()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"internal": [Rotor([0, 0, 1], 5.0)]},
            r"Expected internal parts whose spin inertia the body can hold.*got \[-1.0, 2.0, 3.0\] kg·m² left",
        ),
        ({"internal": [KaneDamper(2.5, 0.1)]}, r"spin inertia the body can hold"),
        (
            {"internal": Rotor([0, 1, 1], 0.1), "method": "exact"},
            r"Expected a method that integrates a body carrying rotor parts \(auto, splitting, strang, rk4, adaptive\), got 'exact': the closed form of a body with parts needs a gyrostat: rotors without motors, all on one principal axis of the platform\.",
        ),
        (
            {"internal": Rotor([0, 0, 1], 0.1, torque=0.1), "method": "exact"},
            r"got 'exact': the closed form of a body with parts needs a gyrostat: rotors without motors, all on one principal axis",
        ),
        (
            {"internal": [KaneDamper(0.1, 0.1)], "method": "splitting"},
            r"carrying kane-damper parts \(auto, rk4, adaptive\), got 'splitting'",
        ),
        (
            {"internal": "wheel"},
            r"Expected `internal` to be a list of parts \(KaneDamper, SpringMassDamper, Rotor\), got str",
        ),
        (
            {"internal": [Rotor([0, 0, 1], 0.1), 3]},
            r"Expected `internal\[1\]` to be a part \(KaneDamper, SpringMassDamper, Rotor\), got int",
        ),
        (
            {"torque": tb.torques.ConstantBodyTorque([0, 0, 1], actuator="rotors")},
            r"Expected rotors in the body for ConstantBodyTorque\(\[0.0, 0.0, 1.0\] N·m, actuator='rotors'\), which acts through them, got none",
        ),
    ],
)
def test_bad_bodies_with_parts_are_refused(kwargs, message) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate(BOX, [0.1, 0.2, 0.3], duration=1.0, dt=0.1, **kwargs)


def test_a_rotor_prints_its_motor_torque_as_a_number() -> None:
    rotor = tb.Rotor(axis=[0, 0, 1], inertia=0.01, speed=10, torque="1 mN*m")
    assert repr(rotor) == (
        "Rotor(axis=[0.0, 0.0, 1.0], inertia=0.01 kg·m², speed=10.0 rad/s, torque=0.001 N·m)"
    )
