"""The gyrocompass model of ``tumble.models`` against independent oracles.

Oracles, none of which calls tumble's integrators:

* sympy.physics.mechanics: the disk in its gimbal on the turning platform,
  by Lagrange's method (platform about the vertical, with damping) and by
  Kane's method (on the Earth at latitude λ, the spin axis held horizontal);
  θ̈, the constant spin, the disk's attitude and angular velocity;
* scipy's DOP853 at rtol 1e-12 on the Lagrange equations (θ, ψ) for the
  attitude;
* ``tumble.theory.gyrocompass``: β, the exact small-angle frequency and the
  exact period of any amplitude (Carlson's R_F), itself checked against
  DOP853 in tests/test_theory.py;
* the rate of change of the attitude by central differences (ω_space);
* the linear damped oscillator in closed form, and the energy balance
  dJ/dt = −c θ̇² integrated by Simpson's rule.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from numpy.testing import assert_allclose
from scipy.integrate import simpson, solve_ivp
from scipy.interpolate import CubicHermiteSpline
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble import models, theory
from tumble.errors import CoarseStepWarning, IntegrationError
from tumble.integrators import steps
from tumble.models import EARTH_ROTATION_RATE, gyrocompass

ODE = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12}
DISK = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)  # I_s = 1.25e-3, I_AB ≈ 6.58e-4 kg·m²
I_S, I_AB = DISK.inertia[2, 2], DISK.inertia[0, 0]
SPIN_20K_RPM = 20000 * 2 * math.pi / 60


def upward_crossings(run: models.GyrocompassRun, level: float) -> np.ndarray:
    """Times where θ rises through ``level``, from the cubic Hermite spline of (θ, θ̇):
    its error is O(dt⁴), far below the stepping error at the steps used here."""
    spline = CubicHermiteSpline(run.trajectory.t, run.angle - level, run.angle_rate)
    roots = spline.roots(extrapolate=False)
    return np.asarray(roots[spline(roots, 1) > 0])


def measured_period(run: models.GyrocompassRun, level: float) -> float:
    times = upward_crossings(run, level)
    assert len(times) >= 3
    return float((times[-1] - times[0]) / (len(times) - 1))


# ====================================================== equations of motion
@functools.cache
def lagrange_vertical():
    """The notes' apparatus: N inertial, P turning about N.z at Ω, the gimbal G
    about P.x by θ, the disk D about G.z by ψ; a torque −c θ̇ about AB."""
    t = me.dynamicsymbols._t
    theta, psi = me.dynamicsymbols("theta psi")
    i_ab, i_s, big_omega, c = sp.symbols("I_AB I_s Omega c", real=True)
    n = me.ReferenceFrame("N")
    p = n.orientnew("P", "Axis", (big_omega * t, n.z))
    g = p.orientnew("G", "Axis", (theta, p.x))
    d = g.orientnew("D", "Axis", (psi, g.z))
    centre = me.Point("O")
    centre.set_vel(n, 0)
    disk = me.RigidBody("disk", centre, d, 1, (me.inertia(g, i_ab, i_ab, i_s), centre))
    method = me.LagrangesMethod(
        me.Lagrangian(n, disk), [theta, psi], forcelist=[(g, -c * theta.diff(t) * p.x)], frame=n
    )
    method.form_lagranges_equations()
    rhs = method.rhs()  # θ̇, ψ̇, θ̈, ψ̈
    return {
        "symbols": (t, theta, psi, i_ab, i_s, big_omega, c),
        "rhs": rhs,
        "attitude": n.dcm(d),  # body → space
        "omega_space": d.ang_vel_in(n).to_matrix(n),
    }


def test_vertical_platform_equation_from_lagranges_method() -> None:
    derived = lagrange_vertical()
    t, theta, psi, i_ab, i_s, big_omega, c = derived["symbols"]
    w_s = sp.Symbol("omega_s", real=True)
    rhs = derived["rhs"]
    spin_sub = {psi.diff(t): w_s - big_omega * sp.cos(theta)}  # the total spin ω_s
    theta_dd = sp.simplify(rhs[2].subs(spin_sub))
    documented = (
        -i_s * w_s * big_omega * sp.sin(theta)
        + i_ab * big_omega**2 * sp.sin(theta) * sp.cos(theta)
        - c * theta.diff(t)
    ) / i_ab
    assert sp.simplify(theta_dd - documented) == 0
    # The spin ω_s = ψ̇ + Ω cos θ is constant: its derivative vanishes on the motion.
    spin_rate = (rhs[3] - big_omega * sp.sin(theta) * theta.diff(t)).subs(spin_sub)
    assert sp.simplify(spin_rate) == 0
    # The model's θ̈ at a few states, for signed rates and with damping.
    for spin, rate, damping in ((100.0, 2.0, 0.0), (-40.0, 3.0, 2e-3), (6.0, -2.0, 5e-4)):
        run = gyrocompass(DISK, spin, rate, 0.3, duration=1e-3, damping=damping)
        q, qd = sp.symbols("q qd")
        values = {i_ab: I_AB, i_s: I_S, big_omega: rate, c: damping, w_s: spin}
        expr = theta_dd.subs(values).subs(theta.diff(t), qd).subs(theta, q)
        f = sp.lambdify((q, qd), expr, "numpy")
        angles = np.array([0.1, 1.0, 2.5, -0.7, 3.1])
        rates = np.array([0.0, 1.5, -3.0, 0.2, 10.0])
        expected = f(angles, rates)
        scale = I_S * abs(spin * rate) / I_AB + rate**2 + damping / I_AB * 10.0
        assert_allclose(run.angular_acceleration(angles, rates), expected, atol=1e-14 * scale)
        assert np.all(run.trajectory.omega[:, 2] == spin)


@functools.cache
def kane_earth():
    """A gyrocompass on the Earth: N has axes east, north, up at t = 0; the
    ground P turns at Ω about the polar axis (cos λ north + sin λ up); the
    gimbal G turns about the local vertical, the heading θ east of north
    (a turn of −θ about up); the disk D spins about G.y, the horizontal axis
    at heading θ. Generalised speeds: u1 = θ̇ and u2 = the total spin."""
    t = me.dynamicsymbols._t
    theta, psi = me.dynamicsymbols("theta psi")
    u1, u2 = me.dynamicsymbols("u1 u2")
    i_ab, i_s, big_omega, lam, c = sp.symbols("I_AB I_s Omega lambda c", real=True)
    n = me.ReferenceFrame("N")
    p = n.orientnew("P", "Axis", (big_omega * t, sp.cos(lam) * n.y + sp.sin(lam) * n.z))
    g = p.orientnew("G", "Axis", (-theta, p.z))
    d = g.orientnew("D", "Axis", (psi, g.y))
    centre = me.Point("O")
    centre.set_vel(n, 0)
    disk = me.RigidBody("disk", centre, d, 1, (me.inertia(g, i_ab, i_s, i_ab), centre))
    kinematics = [u1 - theta.diff(t), u2 - (psi.diff(t) + p.ang_vel_in(n).dot(g.y))]
    method = me.KanesMethod(n, q_ind=[theta, psi], u_ind=[u1, u2], kd_eqs=kinematics)
    # The bearings' viscous torque on the gimbal about the vertical: −c θ̇ about "down".
    method.kanes_equations([disk], [(g, c * u1 * p.z)])
    return {
        "symbols": (t, theta, psi, u1, u2, i_ab, i_s, big_omega, lam, c),
        "rhs": method.rhs(),  # θ̇, ψ̇, u̇1, u̇2
        "attitude": n.dcm(d),
        "omega_space": d.ang_vel_in(n).to_matrix(n),
    }


def test_earth_equation_from_kanes_method() -> None:
    derived = kane_earth()
    _, theta, _, u1, u2, i_ab, i_s, big_omega, lam, c = derived["symbols"]
    rhs = derived["rhs"]
    assert sp.simplify(rhs[3]) == 0  # the total spin is constant
    # θ̈ is the notes' equation with Ω → Ω cos λ: the vertical part drops out.
    w_s, q, qd = sp.symbols("omega_s q qd", real=True)
    effective = big_omega * sp.cos(lam)
    expected = (
        -i_s * w_s * effective * sp.sin(q) / i_ab
        + effective**2 * sp.sin(q) * sp.cos(q)
        - c * qd / i_ab
    )
    theta_dd = rhs[2].subs({u2: w_s, u1: qd}).subs(theta, q)
    assert sp.simplify(sp.expand_trig(theta_dd - expected)) == 0
    for latitude in (-0.5, 0.0, math.radians(52), 0.5 * math.pi):
        run = gyrocompass(
            DISK, SPIN_20K_RPM, EARTH_ROTATION_RATE, 0.3, duration=1.0, latitude=latitude,
            damping=1e-4,
        )  # fmt: skip
        assert run.effective_platform_rate == pytest.approx(
            EARTH_ROTATION_RATE * math.cos(latitude), rel=1e-15, abs=1e-20
        )
        values = {i_ab: I_AB, i_s: I_S, big_omega: EARTH_ROTATION_RATE, lam: latitude, c: 1e-4}
        # The simplified form (shown equal above): Kane's raw one still holds t.
        f = sp.lambdify((q, qd), expected.subs(values).subs(w_s, SPIN_20K_RPM), "numpy")
        angles = np.array([0.1, 1.0, 2.5, -0.7])
        rates = np.array([0.0, 0.3, -0.1, 0.02])
        scale = I_S * SPIN_20K_RPM * EARTH_ROTATION_RATE / I_AB + 1e-4 / I_AB
        assert_allclose(
            run.angular_acceleration(angles, rates), f(angles, rates), atol=1e-14 * scale
        )


# ====================================================== the disk's full attitude
def test_attitude_and_angular_velocity_follow_the_lagrange_equations() -> None:
    derived = lagrange_vertical()
    t, theta, psi, i_ab, i_s, big_omega, c = derived["symbols"]
    spin, rate, damping, theta0 = 30.0, 1.5, 1e-4, 1.0
    values = {i_ab: I_AB, i_s: I_S, big_omega: rate, c: damping}
    q, p_, qd, pd = sp.symbols("q p qd pd")

    def numeric(expr: sp.Expr) -> sp.Expr:
        # Derivatives first: replacing θ(t) first would turn θ̇ into d(q)/dt = 0.
        return (
            expr.subs(values).subs({theta.diff(t): qd, psi.diff(t): pd}).subs({theta: q, psi: p_})
        )

    f = sp.lambdify((q, qd, pd), [numeric(derived["rhs"][2]), numeric(derived["rhs"][3])])
    attitude = sp.lambdify((t, q, p_), numeric(derived["attitude"]))
    omega_space = sp.lambdify((t, q, qd, pd), numeric(derived["omega_space"]))

    def rhs(_: float, y: np.ndarray) -> list[float]:
        a_theta, a_psi = f(y[0], y[1], y[3])
        return [y[1], a_theta, y[3], a_psi]

    duration = 2.0
    run = gyrocompass(DISK, spin, rate, theta0, duration=duration, dt=2e-4, damping=damping)
    times = run.trajectory.t[::500]
    y0 = [theta0, 0.0, 0.0, spin - rate * math.cos(theta0)]  # ψ̇ from the total spin
    sol = solve_ivp(rhs, (0, duration), y0, t_eval=times, **ODE)
    matrices = run.trajectory.rotation[::500].as_matrix()
    # RK4 at β dt ≈ 2e-3 keeps θ to ~1e-12 rad; DOP853 at rtol 1e-12 keeps ψ (60 rad)
    # and θ̇ to ~1e-11: bounds of 1e-10 leave room for both.
    for k, time in enumerate(times):
        expected = np.array(attitude(time, sol.y[0, k], sol.y[2, k]), dtype=float)
        assert_allclose(matrices[k], expected, atol=1e-10)
        w_expected = np.ravel(omega_space(time, sol.y[0, k], sol.y[1, k], sol.y[3, k]))
        assert_allclose(run.trajectory.omega_space[500 * k], w_expected, atol=1e-10 * spin)
    assert_allclose(run.angle[::500], sol.y[0], atol=1e-11)
    assert_allclose(run.angle_rate[::500], sol.y[1], atol=1e-10)


def test_earth_attitude_follows_kanes_frames() -> None:
    derived = kane_earth()
    t, theta, psi, u1, u2, i_ab, i_s, big_omega, lam, c = derived["symbols"]
    # An exaggerated ground rate, so that the Earth's turning shows in the attitude.
    spin, rate, latitude, damping = 40.0, 0.8, math.radians(40), 1e-4
    values = {i_ab: I_AB, i_s: I_S, big_omega: rate, lam: latitude, c: damping}
    q, p_, qd, pd, v = sp.symbols("q p qd pd v")

    def numeric(expr: sp.Expr) -> sp.Expr:
        return (
            expr.subs(values)
            .subs({theta.diff(t): qd, psi.diff(t): pd, u1: qd, u2: v})
            .subs({theta: q, psi: p_})
        )

    # Kane's unsimplified rates still hold t (in terms that cancel): pass it.
    rates = sp.lambdify((t, q, qd, v), [numeric(derived["rhs"][1]), numeric(derived["rhs"][2])])
    attitude = sp.lambdify((t, q, p_), numeric(derived["attitude"]))
    omega_space = sp.lambdify((t, q, qd, pd), numeric(derived["omega_space"]))

    def rhs(time: float, y: np.ndarray) -> list[float]:
        psi_dot, theta_dd = rates(time, y[0], y[1], spin)
        return [y[1], theta_dd, psi_dot]

    duration = 1.5
    run = gyrocompass(
        DISK, spin, rate, 0.4, angle_rate0=0.5, duration=duration, dt=2e-4, latitude=latitude,
        damping=damping,
    )  # fmt: skip
    times = run.trajectory.t[::500]
    sol = solve_ivp(rhs, (0, duration), [0.4, 0.5, 0.0], t_eval=times, **ODE)
    # The documented body axes at θ = ψ = 0 are (down, west, north); Kane's disk
    # frame D there is (east, north, up), spinning about D.y: body = D · C.
    body_in_d = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
    matrices = run.trajectory.rotation[::500].as_matrix()
    for k, time in enumerate(times):
        expected = np.array(attitude(time, sol.y[0, k], sol.y[2, k]), dtype=float) @ body_in_d
        # As for the vertical platform: ~1e-12 from RK4, ~1e-11 from DOP853.
        assert_allclose(matrices[k], expected, atol=1e-10)
        psi_dot = spin - rate * math.cos(latitude) * math.cos(sol.y[0, k])
        w_expected = np.ravel(omega_space(time, sol.y[0, k], sol.y[1, k], psi_dot))
        assert_allclose(run.trajectory.omega_space[500 * k], w_expected, atol=1e-10 * spin)
    assert_allclose(run.angle[::500], sol.y[0], atol=1e-11)
    assert np.all(run.trajectory.omega[:, 2] == spin)


def test_omega_space_is_the_rate_of_the_attitude() -> None:
    # Central differences of the attitude: log(R(t + h) R(t − h)ᵀ) / 2h = ω_space(t)
    # + C h² + O(h⁴). Doubling h must quadruple the error, and Richardson's
    # (4 D(h) − D(2h)) / 3 must cancel it down to the O(h⁴) rest: (|ω| h)⁴ ≈ 1e-10.
    cases = [
        {"latitude": None, "platform_rate": 1.5, "angle0": 1.0},
        {"latitude": math.radians(40), "platform_rate": 0.8, "angle0": 2.0},
    ]
    for case in cases:
        run = gyrocompass(
            DISK, 30.0, case["platform_rate"], case["angle0"], angle_rate0=0.5, duration=1.0,
            dt=1e-4, latitude=case["latitude"],
        )  # fmt: skip
        traj = run.trajectory
        rot, h = traj.rotation, traj.dt
        middle = np.arange(2, len(traj.t) - 2)
        near = (rot[middle + 1] * rot[middle - 1].inv()).as_rotvec() / (2 * h)
        far = (rot[middle + 2] * rot[middle - 2].inv()).as_rotvec() / (4 * h)
        exact = traj.omega_space[middle]
        ratio = np.max(np.abs(far - exact)) / np.max(np.abs(near - exact))
        assert ratio == pytest.approx(4.0, rel=1e-3)
        scale = float(np.max(np.linalg.norm(traj.omega_space, axis=1)))
        assert np.max(np.abs((4 * near - far) / 3 - exact)) < 1e-10 * scale


@pytest.mark.parametrize("latitude", [None, math.radians(-25)])
def test_omega_space_is_platform_plus_gimbal_plus_spin(latitude: float | None) -> None:
    # ω_space = Ω_P + θ̇ ê_AB + ψ̇ ŝ: the platform, the gimbal about AB (turning with
    # the platform) and the spin relative to the gimbal, ψ̇ = ω_s − Ω cos θ.
    spin = 30.0
    run = gyrocompass(
        DISK, spin, 0.9, 0.7, angle_rate0=-0.4, duration=2.0, dt=1e-3, latitude=latitude
    )
    traj = run.trajectory
    platform = Rotation.from_rotvec(np.outer(traj.t, run.platform_angular_velocity))
    # Copies: scipy's Rotation.apply refuses read-only arrays.
    gimbal_axis = platform.apply(np.array(run.gimbal_axis))
    spin_axis = traj.rotation.apply([0.0, 0.0, 1.0])
    relative_spin = spin - run.effective_platform_rate * np.cos(run.angle)
    expected = (
        run.platform_angular_velocity
        + run.angle_rate[:, None] * gimbal_axis
        + relative_spin[:, None] * spin_axis
    )
    assert_allclose(traj.omega_space, expected, atol=1e-13 * spin)
    # AB stays perpendicular to the spin axis, and θ is the angle, about AB, of the
    # spin axis from the platform's reference direction.
    reference = platform.apply(np.array(run.reference_direction))
    assert_allclose(np.einsum("ij,ij->i", gimbal_axis, spin_axis), 0.0, atol=1e-14)
    sine = np.einsum("ij,ij->i", np.cross(reference, spin_axis), gimbal_axis)
    cosine = np.einsum("ij,ij->i", reference, spin_axis)
    assert_allclose(np.arctan2(sine, cosine), np.angle(np.exp(1j * run.angle)), atol=1e-13)


# ====================================================== against the theory
@pytest.mark.parametrize(("spin", "rate"), [(100.0, 2.0), (6.0, 2.0), (-50.0, 1.0), (-30.0, -2.0)])
def test_small_oscillation_is_at_the_exact_small_angle_frequency(spin: float, rate: float) -> None:
    compass = theory.gyrocompass(DISK, spin, rate)
    exact = compass.small_oscillation_frequency  # √(β² − Ω²)
    period = 2 * math.pi / exact
    centre = 0.0 if spin * rate > 0 else math.pi  # L_s settles along Ω
    amplitude = 1e-3
    run = gyrocompass(DISK, spin, rate, centre + amplitude, duration=5.2 * period, dt=period / 2000)
    measured = 2 * math.pi / measured_period(run, centre)
    # The amplitude lowers the frequency by ≈ θ0²/16 = 6.3e-8 (pendulum-like); RK4 at
    # 2000 steps a period errs by ~1e-12 and the spline by less.
    assert measured == pytest.approx(exact, rel=2e-7)
    # Dropping the Ω² term (β = √(L_s Ω / I_AB)) is off by 1 − √(1 − Ω²/β²):
    beta = compass.oscillation_frequency
    gap = 1 - math.sqrt(1 - rate**2 / beta**2)
    assert abs(measured / beta - 1) == pytest.approx(gap, rel=1e-3)
    assert gap > 1e-3  # far outside the tolerance above, for these slow spins


def test_fast_spin_oscillates_at_beta() -> None:
    # The Earth case: Ω²/β² ≈ 2e-8, so β and √(β² − Ω²) agree well within 1e-6.
    rate = EARTH_ROTATION_RATE
    compass = theory.gyrocompass(DISK, SPIN_20K_RPM, rate)
    assert rate**2 / compass.oscillation_frequency**2 < 1e-7
    period = 2 * math.pi / compass.oscillation_frequency
    run = gyrocompass(DISK, SPIN_20K_RPM, rate, 1e-3, duration=5.2 * period, latitude=0.0)
    measured = 2 * math.pi / measured_period(run, 0.0)
    assert measured == pytest.approx(compass.oscillation_frequency, rel=1e-6)


@pytest.mark.parametrize("amplitude", [1.0, 2.5, 3.0])
@pytest.mark.parametrize(("spin", "rate"), [(100.0, 2.0), (6.0, 2.0), (-50.0, 1.0)])
def test_large_swing_period_is_the_exact_one(amplitude: float, spin: float, rate: float) -> None:
    compass = theory.gyrocompass(DISK, spin, rate)
    expected = compass.period(amplitude)
    centre = 0.0 if spin * rate > 0 else math.pi
    run = gyrocompass(
        DISK, spin, rate, centre + amplitude, duration=3.2 * expected, dt=expected / 2000
    )
    measured = measured_period(run, centre)
    # RK4 at 2000 steps a period: ≤ 1e-10 of the period even at θ0 = 3 (where the
    # axis lingers near the top and the error is largest); the spline adds ~1e-13.
    assert measured == pytest.approx(expected, rel=1e-8)
    # The small-angle period 2π/√(β² − Ω²) is short by 6 % at 1 rad, 30–40 % at 2.5
    # rad and 55–60 % at 3 rad, exactly as the elliptic integral says.
    small = 2 * math.pi / compass.small_oscillation_frequency
    assert 1 - small / measured == pytest.approx(1 - small / expected, rel=1e-7)
    assert 1 - small / measured > {1.0: 0.025, 2.5: 0.3, 3.0: 0.5}[amplitude]


# ====================================================== conserved quantity
@pytest.mark.parametrize("latitude", [None, math.radians(35)])
def test_the_jacobi_integral_is_conserved_and_the_energy_is_not(latitude: float | None) -> None:
    spin, rate = 50.0, 1.5
    run = gyrocompass(DISK, spin, rate, 2.0, duration=5.0, dt=5e-4, latitude=latitude)
    traj = run.trajectory
    # J = T − Ω_P · L from the trajectory's own energy and angular momentum (built
    # from the attitude and ω), against the closed form in θ, θ̇ the run reports.
    from_trajectory = traj.energy - traj.angular_momentum @ run.platform_angular_velocity
    energy_scale = 0.5 * I_S * spin**2
    assert_allclose(run.jacobi_integral, from_trajectory, atol=1e-14 * energy_scale)
    # Conserved to RK4's error (β dt ≈ 0.01: ~1e-12 per period), on the scale of the
    # swing's own energy L_s Ω; the energy in space changes by a fair part of it.
    swing = I_S * abs(spin * run.effective_platform_rate)
    drift = np.ptp(run.jacobi_integral)
    assert drift < 1e-9 * swing
    assert np.ptp(traj.energy) > 0.1 * swing


def test_damping_dissipates_the_jacobi_integral_at_c_theta_dot_squared() -> None:
    damping = 2e-4
    run = gyrocompass(DISK, 50.0, 1.5, 2.0, duration=4.0, dt=2e-4, damping=damping)
    lost = -damping * simpson(run.angle_rate**2, x=run.trajectory.t)
    # Simpson's rule on 20001 samples errs by ~dt⁴; RK4's drift is ~1e-12 of L_s Ω.
    swing = I_S * 50.0 * 1.5
    assert run.jacobi_integral[-1] - run.jacobi_integral[0] == pytest.approx(
        lost, abs=1e-10 * swing
    )
    assert lost < -0.05 * swing  # a real loss, not round-off


# ====================================================== the Earth case
def test_earth_geometry_spin_axis_horizontal_at_heading_theta() -> None:
    latitude = math.radians(52)
    run = gyrocompass(
        DISK, SPIN_20K_RPM, EARTH_ROTATION_RATE, 1.0, duration=60.0, latitude=latitude
    )
    assert_allclose(
        run.platform_angular_velocity,
        EARTH_ROTATION_RATE * np.array([0.0, math.cos(latitude), math.sin(latitude)]),
        rtol=1e-15,
    )
    assert_allclose(run.gimbal_axis, [0.0, 0.0, -1.0], atol=0)  # down
    assert_allclose(run.reference_direction, [0.0, 1.0, 0.0], atol=0)  # north
    traj = run.trajectory
    # The local axes (east, north, up) turn with the Earth about its polar axis.
    ground = Rotation.from_rotvec(np.outer(traj.t, run.platform_angular_velocity))
    east, north, up = (ground.apply(axis) for axis in np.eye(3))
    spin_axis = traj.rotation.apply([0.0, 0.0, 1.0])
    assert_allclose(np.einsum("ij,ij->i", spin_axis, up), 0.0, atol=1e-14)
    heading = np.arctan2(
        np.einsum("ij,ij->i", spin_axis, east), np.einsum("ij,ij->i", spin_axis, north)
    )
    assert_allclose(heading, np.angle(np.exp(1j * run.angle)), atol=1e-13)


def test_earth_period_uses_the_horizontal_part_of_the_earths_rate() -> None:
    periods = {}
    for degrees in (0.0, 60.0):
        effective = EARTH_ROTATION_RATE * math.cos(math.radians(degrees))
        expected = theory.gyrocompass(DISK, SPIN_20K_RPM, effective).period(0.5)
        run = gyrocompass(
            DISK, SPIN_20K_RPM, EARTH_ROTATION_RATE, 0.5, duration=3.2 * expected,
            dt=expected / 2000, latitude=f"{degrees} deg",
        )  # fmt: skip
        periods[degrees] = measured_period(run, 0.0)
        assert periods[degrees] == pytest.approx(expected, rel=1e-8)
    # β ∝ √(cos λ): at 60° (cos = ½) the period is √2 longer (Ω² ≪ β² at 2e-8).
    assert periods[60.0] / periods[0.0] == pytest.approx(math.sqrt(2), rel=1e-7)


def test_a_damped_earth_compass_settles_north() -> None:
    latitude = math.radians(52)
    effective = EARTH_ROTATION_RATE * math.cos(latitude)
    beta = math.sqrt(I_S * SPIN_20K_RPM * effective / I_AB)
    damping = 0.6 * beta * I_AB  # a damping ratio of 0.3: settles in a few swings
    duration = 60.0 / beta
    for spin, north in ((SPIN_20K_RPM, 0.0), (-SPIN_20K_RPM, math.pi)):
        # From 170° off: the spin's angular momentum ends up pointing north.
        run = gyrocompass(
            DISK, spin, EARTH_ROTATION_RATE, north + math.radians(170), duration=duration,
            latitude=latitude, damping=damping,
        )  # fmt: skip
        # Decay e^{−ζ β t} with ζ β t = 18 at the end: 1e-8 of the start.
        assert abs(run.angle[-1] - north) < 1e-6
        assert abs(run.angle_rate[-1]) < 1e-6 * beta
        traj = run.trajectory
        momentum = traj.angular_momentum[-1]
        ground = Rotation.from_rotvec(traj.t[-1] * run.platform_angular_velocity)
        local_north = ground.apply([0.0, 1.0, 0.0])
        assert momentum @ local_north / np.linalg.norm(momentum) > 1 - 1e-10


def test_small_damped_swing_is_the_linear_damped_oscillator() -> None:
    latitude = math.radians(30)
    effective = EARTH_ROTATION_RATE * math.cos(latitude)
    w0 = theory.gyrocompass(DISK, SPIN_20K_RPM, effective).small_oscillation_frequency
    zeta = 0.05
    run = gyrocompass(
        DISK, SPIN_20K_RPM, EARTH_ROTATION_RATE, 1e-3, duration=20 * 2 * math.pi / w0,
        latitude=latitude, damping=2 * zeta * w0 * I_AB, dt=2 * math.pi / w0 / 1000,
    )  # fmt: skip
    t = run.trajectory.t
    wd = w0 * math.sqrt(1 - zeta**2)
    linear = 1e-3 * np.exp(-zeta * w0 * t) * (np.cos(wd * t) + zeta * w0 / wd * np.sin(wd * t))
    # sin θ ≈ θ − θ³/6 shifts the frequency by ≈ A²/16 of w0 at amplitude
    # A = θ0 e^{−ζ w0 t}: a phase of at most ∫ A² w0 / 16 dt = θ0² / (32 ζ) ≈ 6e-7 rad,
    # so an error below θ0 · 6e-7 = 6e-10 rad; RK4 at 1000 steps a swing adds ~1e-14.
    assert_allclose(run.angle, linear, atol=1e-9)


# ====================================================== the run and its trajectory
def test_trajectory_describes_the_disk_and_records_every_kth_step(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    moved = DISK.transformed(translation=[0.1, -0.2, 0.3])
    full = gyrocompass(moved, 40.0, 2.0, 0.5, duration=0.5, dt=1e-3)
    monkeypatch.setattr(steps, "PROGRESS_CHUNK", 7)
    calls: list[tuple[int, int]] = []
    every = gyrocompass(
        moved, 40.0, 2.0, 0.5, duration=0.5, dt=1e-3, record_every=3,
        progress=lambda done, total: calls.append((done, total)),
    )  # fmt: skip
    assert calls[0] == (7, 500) and calls[-1] == (500, 500) and len(calls) == math.ceil(500 / 7)
    # Rows 0, 3, 6, ... 498 and the final state at 500: chunks change nothing.
    assert_allclose(every.trajectory.t, np.append(full.trajectory.t[::3], 0.5), rtol=1e-15)
    assert np.array_equal(every.angle[:-1], full.angle[::3])
    assert every.angle[-1] == full.angle[-1]
    assert_allclose(every.trajectory.quaternion[-1], full.trajectory.quaternion[-1], atol=0)
    traj = full.trajectory
    assert_allclose(traj.pivot, moved.center_of_mass, atol=0)
    assert np.all(traj.gravity == 0.0)
    assert (traj.method, traj.reason, traj.steps) == ("rk4", "gyrocompass model", 500)
    assert traj.dt == pytest.approx(1e-3, rel=1e-12)
    assert traj.mass_properties is moved
    assert_allclose(np.linalg.norm(traj.quaternion, axis=1), 1.0, atol=1e-15)
    # No sign flips between samples, as for a stepped attitude.
    assert np.all(np.einsum("ij,ij->i", traj.quaternion[1:], traj.quaternion[:-1]) > 0)
    path = tmp_path / "gyrocompass.parquet"
    traj.to_parquet(path)
    back = tb.Trajectory.read_parquet(path)
    assert_allclose(back.omega, traj.omega, atol=0)
    assert_allclose(back.pivot, traj.pivot, atol=0)


def test_samples_keeps_every_kth_step_of_the_default_step() -> None:
    # The default step is 1/200 of a turn at the fastest rate of θ: asked for
    # about 40 samples, the run keeps every (steps // 40)-th step and the last.
    full = gyrocompass(DISK, 400.0, 2.0, 0.5, duration=0.5)
    steps = full.trajectory.steps
    kept = gyrocompass(DISK, 400.0, 2.0, 0.5, duration=0.5, samples=40)
    every = steps // 40
    assert steps > 400 and kept.trajectory.steps == steps
    assert np.array_equal(kept.angle[:-1], full.angle[::every][: len(kept.angle) - 1])
    assert kept.angle[-1] == full.angle[-1]
    assert 40 <= len(kept.angle) <= 42


def test_quantities_at_the_edge_give_the_si_run() -> None:
    with_units = gyrocompass(
        DISK, "20000 rpm", "7.292115e-5 rad/s", "170 deg", angle_rate0="0.01 rad/s",
        duration="1 min", dt="0.05 s", latitude="52 deg", damping="1e-4 N*m*s",
    )  # fmt: skip
    plain = gyrocompass(
        DISK, SPIN_20K_RPM, EARTH_ROTATION_RATE, math.radians(170), angle_rate0=0.01,
        duration=60.0, dt=0.05, latitude=math.radians(52), damping=1e-4,
    )  # fmt: skip
    assert_allclose(with_units.angle, plain.angle, rtol=1e-14)
    assert_allclose(with_units.trajectory.quaternion, plain.trajectory.quaternion, atol=1e-14)
    assert with_units.latitude == pytest.approx(math.radians(52), rel=1e-15)


def test_a_coarse_step_warns_and_a_diverging_one_raises() -> None:
    with pytest.warns(CoarseStepWarning, match=r"dt = 0\.5 s gives .* steps per turn"):
        gyrocompass(DISK, 100.0, 2.0, 0.5, duration=5.0, dt=0.5)
    # c / I_AB ≈ 1.5e4 1/s at dt = 1 s: RK4 multiplies θ̇ by ~1e15 a step.
    with (
        pytest.warns(CoarseStepWarning),
        pytest.raises(
            IntegrationError,
            match=r"Expected the integration to stay finite, got NaN or inf at step \d+",
        ),
    ):
        gyrocompass(DISK, 100.0, 2.0, 0.5, duration=100.0, dt=1.0, damping=10.0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"mp": "disk"}, r"Expected `mp` to be a MassProperties, got str\."),
        ({"mp": tb.shapes.box(1, (1, 2, 3))}, r"Expected `mp` to be symmetric about body z"),
        (
            {"mp": tb.shapes.thin_rod(1, 1)},
            r"Expected `mp` to have a moment about its symmetry axis z > 0 kg·m²",
        ),
        (
            {"latitude": 2.0},
            r"Expected `latitude` in \[-π/2, π/2\] rad \(−90° to 90°, positive north\), got 2\.0\.",
        ),
        ({"latitude": "-91 deg"}, r"Expected `latitude` in \[-π/2, π/2\] rad .*got -1\.588"),
        ({"damping": -1.0}, r"Expected `damping` >= 0 N·m·s, got -1\.0\."),
        ({"damping": "1 kg"}, r"Expected `damping`"),
        ({"duration": 0.0}, r"Expected `duration` > 0 s, got 0\.0\."),
        ({"dt": -1e-3}, r"Expected `dt` > 0 s, got -0\.001\."),
        ({"record_every": 0}, r"Expected `record_every` to be an integer >= 1, got 0\."),
        ({"record_every": 2.0}, r"Expected `record_every` to be an integer >= 1, got 2\.0\."),
        ({"samples": 0}, r"Expected `samples` to be an integer >= 1, got 0\."),
        ({"samples": 10.0}, r"Expected `samples` to be an integer >= 1, got 10\.0\."),
        (
            {"samples": 10, "record_every": 3},
            r"Expected one of `record_every` and `samples`, got both \(3, 10\)\.",
        ),
        ({"spin_rate": "3 kg"}, r"Expected `spin_rate`"),
        ({"platform_rate": math.inf}, r"Expected `platform_rate` to be finite, got inf\."),
        ({"angle0": math.nan}, r"Expected `angle0` to be finite, got nan\."),
        ({"angle_rate0": "1 m"}, r"Expected `angle_rate0`"),
    ],
)
def test_gyrocompass_refuses_bad_input(kwargs: dict[str, object], message: str) -> None:
    arguments: dict[str, object] = {
        "mp": DISK, "spin_rate": 100.0, "platform_rate": 2.0, "angle0": 0.3, "duration": 1.0,
    }  # fmt: skip
    arguments.update(kwargs)
    call: Callable[..., object] = gyrocompass
    with pytest.raises(tb.InputError, match=message):
        call(**arguments)


def test_repr_says_what_ran() -> None:
    run = gyrocompass(DISK, 100.0, 2.0, 0.5, duration=0.1, latitude="10 deg")
    text = repr(run)
    assert text.startswith("GyrocompassRun(") and "latitude 10°" in text
    assert f"{len(run.angle)} samples over 0.1 s" in text
