"""The heavy symmetric (Lagrange) top in closed form, against independent oracles.

- a DOP853 integration of Euler's equations with the attitude as a matrix
  (``tests/reference.py``, rtol 1e-13) for general initial conditions;
- Woodhouse's separatrix, where the motion is elementary;
- the sleeping top, a steady rotation;
- the conservation laws at the turning points of the tilt;
- mpmath (Jacobi's sn and quadrature at 40 digits) a million nutation periods on.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import minimize_scalar
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from tumble.body import RigidBody
from tumble.errors import InputError
from tumble.theory.motions import lagrange_top

G = 9.81
UP = np.array([0.0, 0.0, 1.0])


def disk_top(lever: float = 0.06) -> tuple[tb.MassProperties, np.ndarray]:
    """A 0.5 kg disk (radius 4 cm, height 2 cm) on a pivot ``lever`` below its
    centre of mass (above it for a negative lever: a hanging top)."""
    return tb.shapes.solid_cylinder(0.5, 0.04, 0.02), np.array([0.0, 0.0, -lever])


def tilted(tilt: float) -> np.ndarray:
    """The attitude Rz(0) Rx(θ) Rz(0): body +z tilted by θ from space +z."""
    return np.array([math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0])


def start(tilt: float, tilt_rate: float, precession_rate: float, spin: float) -> np.ndarray:
    """ω0 in body axes for the attitude :func:`tilted` (θ̇, φ̇ sin θ, ω_s)."""
    return np.array([tilt_rate, precession_rate * math.sin(tilt), spin])


def exact_run(mp_, pivot, omega0, q0, gravity, times):
    return tb.simulate(
        mp_,
        omega0,
        attitude0=q0,
        duration=times[-1],
        dt=times[1] - times[0],
        pivot=pivot,
        gravity=gravity,
        method="exact",
    )


def nutation_period(mp_, pivot, omega0, q0, gravity) -> float:
    body = RigidBody(mp_, pivot=np.asarray(pivot, float))
    return lagrange_top(body, np.asarray(gravity, float), omega0, q0).mean_rates()[0]


def rotated_top() -> tuple[tb.MassProperties, np.ndarray, Rotation]:
    """A symmetric top whose symmetry axis is not body z: the disk turned by
    ``turn``, with the pivot on the turned axis."""
    disk, pivot = disk_top(0.05)
    turn = Rotation.from_rotvec([0.4, -0.9, 0.3])
    matrix = turn.as_matrix()
    body = tb.MassProperties(
        disk.mass, matrix @ disk.center_of_mass, matrix @ disk.inertia @ matrix.T
    )
    return body, matrix @ pivot, turn


Z_DOWN = (0.0, 0.0, -G)
CASES = {
    # tilt, θ̇0, φ̇0, spin (rad/s), lever (m; < 0 hangs)
    "rising start": (0.7, 2.0, 1.0, 60.0, 0.06),
    "falling start": (0.7, -2.0, 1.0, 60.0, 0.06),
    "looping precession": (1.1, 0.5, -3.0, 80.0, 0.06),
    "slow top past 90°": (1.2, 0.0, 0.0, 8.0, 0.06),
    "hanging top": (2.5, 1.5, 2.0, 30.0, -0.06),
    "zero spin (spherical pendulum)": (1.0, 0.3, 1.5, 0.0, 0.06),
    "through the upper pole": (0.0, 1.2, 0.0, 50.0, 0.06),
    "through the lower pole": (math.pi, 1.2, 0.0, 20.0, 0.06),
    "hanging through its lowest point": (0.0, 1.2, 0.0, 20.0, -0.06),
}


@pytest.mark.parametrize("case", CASES)
def test_closed_form_matches_a_reference_integration(case: str) -> None:
    tilt, tilt_rate, precession_rate, spin, lever = CASES[case]
    disk, pivot = disk_top(lever)
    q0 = tilted(tilt)
    omega0 = start(tilt, tilt_rate, precession_rate, spin)
    if tilt in (0.0, math.pi):  # on the vertical: the rate across it is θ̇ along x
        omega0 = np.array([tilt_rate, 0.0, spin])
    period = nutation_period(disk, pivot, omega0, q0, Z_DOWN)
    assert math.isfinite(period) and period > 0
    times = np.linspace(0.0, 10 * period, 401)
    run = exact_run(disk, pivot, omega0, q0, Z_DOWN, times)
    w_ref, a_ref = reference(disk, omega0, q0, times[-1], pivot, Z_DOWN, times=times)
    # DOP853 at rtol 1e-13 keeps ~1e-12 relative over ten nutation periods (a few
    # thousand steps); 1e-10 leaves a margin of 100 for its error, not ours.
    scale = np.max(np.linalg.norm(w_ref, axis=1))
    assert np.max(np.abs(run.omega - w_ref)) < 1e-10 * scale
    assert attitude_error(run.quaternion, a_ref) < 1e-10


def test_a_body_whose_symmetry_axis_is_not_body_z_under_slanted_gravity() -> None:
    body, pivot, turn = rotated_top()
    gravity = (1.5, -2.0, -9.4)
    q0 = Rotation.from_rotvec([0.3, 0.8, -0.2]).as_quat(scalar_first=True)
    omega0 = turn.apply([1.3, -0.7, 70.0])
    period = nutation_period(body, pivot, omega0, q0, gravity)
    times = np.linspace(0.0, 10 * period, 301)
    run = exact_run(body, pivot, omega0, q0, gravity, times)
    assert run.method == "exact"
    w_ref, a_ref = reference(body, omega0, q0, times[-1], pivot, gravity, times=times)
    # As above: the reference's own error is ~1e-12 relative.
    assert np.max(np.abs(run.omega - w_ref)) < 1e-10 * np.linalg.norm(omega0)
    assert attitude_error(run.quaternion, a_ref) < 1e-10


def test_auto_chooses_the_closed_form_for_a_symmetric_top() -> None:
    disk, pivot = disk_top()
    run = tb.simulate(disk, [1.0, 0.0, 60.0], attitude0=tilted(0.5), duration=1.0, dt=0.01,
                      pivot=pivot, gravity=Z_DOWN)  # fmt: skip
    assert run.method == "exact" and run.steps == 0
    assert "Lagrange top" in run.reason


def woodhouse(lever: float = 0.06):
    """Woodhouse's separatrix: θ0 = 60°, θ̇0 = 0, φ̇0 = 2γ/√3, ω_s = √3 A γ / C
    with γ = √(m g l / A), A and C about the pivot."""
    disk, pivot = disk_top(lever)
    inertia = disk.inertia_about(pivot)
    transverse, axial = inertia[0, 0], inertia[2, 2]
    gamma = math.sqrt(disk.mass * G * lever / transverse)
    tilt = math.pi / 3
    omega0 = start(tilt, 0.0, 2 * gamma / math.sqrt(3), math.sqrt(3) * transverse * gamma / axial)
    return disk, pivot, tilt, omega0, gamma


def test_woodhouse_separatrix_against_its_elementary_solution() -> None:
    disk, pivot, tilt, omega0, gamma = woodhouse()
    times = np.linspace(0.0, 12.0 / gamma, 241)
    run = exact_run(disk, pivot, omega0, tilted(tilt), Z_DOWN, times)
    axis = Rotation.from_quat(run.quaternion, scalar_first=True).apply([0.0, 0.0, 1.0])
    x = gamma * times
    # cos θ = 1 / (1 + sech γt); φ = √3 γt / 2 + atan(tanh(γt/2) / √3) (from
    # φ̇ = (b − a u)/(1 − u²) with this u: ∫ dx / (2 cosh x + 1) = (2/√3) atan(tanh(x/2)/√3)).
    cos_tilt = 1.0 / (1.0 + 1.0 / np.cosh(x))
    precession = math.sqrt(3) * x / 2 + np.arctan(np.tanh(x / 2) / math.sqrt(3))
    azimuth = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
    # The separatrix is unstable: a round-off δ in the constants grows as e^{γt}
    # (e^12 ≈ 1.6e5), so ~1e-16 at t = 0 reaches ~1e-11; 1e-9 leaves a margin.
    assert np.max(np.abs(axis[:, 2] - cos_tilt)) < 1e-9
    assert np.max(np.abs((azimuth - azimuth[0]) - precession)) < 1e-9
    # And the reference integration agrees over the first stretch.
    _, a_ref = reference(disk, omega0, tilted(tilt), times[-1], pivot, Z_DOWN, times=times)
    assert attitude_error(run.quaternion, a_ref) < 1e-9


def test_sleeping_top_is_a_steady_rotation() -> None:
    disk, pivot = disk_top()
    spin = 200.0  # well above the sleeping limit 2 √(m g l A) / C ≈ 36 rad/s
    times = np.linspace(0.0, 2.0, 101)
    run = exact_run(disk, pivot, [0.0, 0.0, spin], [1.0, 0, 0, 0], Z_DOWN, times)
    assert np.array_equal(run.omega, np.tile([0.0, 0.0, spin], (len(times), 1)))
    expected = Rotation.from_rotvec(np.outer(spin * times, UP))
    assert attitude_error(run.quaternion, expected.as_matrix()) < 1e-13 * spin * times[-1]


def test_nearly_sleeping_fast_top_stays_near_the_vertical() -> None:
    disk, pivot = disk_top()
    q0 = tilted(1e-6)
    omega0 = np.array([0.0, 0.0, 200.0])
    period = nutation_period(disk, pivot, omega0, q0, Z_DOWN)
    times = np.linspace(0.0, 10 * period, 201)
    run = exact_run(disk, pivot, omega0, q0, Z_DOWN, times)
    axis = Rotation.from_quat(run.quaternion, scalar_first=True).apply([0.0, 0.0, 1.0])
    # A stable sleeping top: the tilt stays of the order of its start.
    assert np.max(np.arccos(np.clip(axis[:, 2], -1, 1))) < 3e-6
    w_ref, a_ref = reference(disk, omega0, q0, times[-1], pivot, Z_DOWN, times=times)
    assert np.max(np.abs(run.omega - w_ref)) < 1e-10 * 200.0
    assert attitude_error(run.quaternion, a_ref) < 1e-10


@pytest.mark.parametrize("case", ["rising start", "looping precession", "hanging top"])
def test_rates_at_the_turning_points_follow_the_conservation_laws(case: str) -> None:
    tilt, tilt_rate, precession_rate, spin, lever = CASES[case]
    disk, pivot = disk_top(lever)
    q0 = tilted(tilt)
    omega0 = start(tilt, tilt_rate, precession_rate, spin)
    gyro = tb.theory.gyroscope(disk, pivot, omega0=omega0, attitude0=q0)
    inertia = disk.inertia_about(pivot)
    transverse, axial = inertia[0, 0], inertia[2, 2]
    torque = disk.mass * G * lever  # m g l
    vertical_momentum = float(inertia @ omega0 @ Rotation.from_quat(q0, scalar_first=True)
                              .inv().apply(UP))  # fmt: skip
    energy = 0.5 * omega0 @ inertia @ omega0 + torque * math.cos(tilt)

    def euler(t: float) -> np.ndarray:
        q = gyro.at(t)[1]
        return Rotation.from_quat(q, scalar_first=True).as_euler("ZXZ")

    period = gyro.nutation_period
    for theta, sign in zip(gyro.nutation_limits, (1.0, -1.0), strict=True):
        # The time of the turning point, from the motion itself.
        found = minimize_scalar(
            lambda t, s=sign: s * gyro.tilt_at(t), bounds=(0.0, period), method="bounded",
            options={"xatol": 1e-12},
        )  # fmt: skip
        t0 = found.x
        assert gyro.tilt_at(t0) == pytest.approx(theta, abs=1e-12)
        # φ̇ and ψ̇ by central differences (error ~h² |φ⃛| ~ 1e-8) ...
        h = 1e-4 * period
        before, after = euler(t0 - h), euler(t0 + h)
        steps = np.angle(np.exp(1j * (after - before))) / (2 * h)
        # ... against the conserved p_φ = A φ̇ sin² θ + C ω_s cos θ and ω_s = ψ̇ + φ̇ cos θ.
        phi_dot = (vertical_momentum - axial * spin * math.cos(theta)) / (
            transverse * math.sin(theta) ** 2
        )
        psi_dot = spin - phi_dot * math.cos(theta)
        scale = abs(phi_dot) + abs(psi_dot)
        assert steps[0] == pytest.approx(phi_dot, abs=1e-6 * scale)
        assert steps[2] == pytest.approx(psi_dot, abs=1e-6 * scale)
        # The energy there (θ̇ = 0) is the initial one.
        there = (
            0.5 * transverse * (phi_dot * math.sin(theta)) ** 2
            + 0.5 * axial * spin**2
            + torque * math.cos(theta)
        )
        assert there == pytest.approx(energy, rel=1e-12)


def mpmath_top(tilt, tilt_rate, precession_rate, spin, transverse, axial, torque, t):
    """cos θ, φ and ψ at ``t`` from the initial state, at 40 digits: the cubic's
    roots by ``polyroots``, u by Jacobi's sn, φ and ψ by quadrature over whole
    periods and the remainder."""
    with mp.workdps(40):
        tilt, tilt_rate, precession_rate, spin = map(
            mp.mpf, (tilt, tilt_rate, precession_rate, spin)
        )
        beta = 2 * mp.mpf(torque) / transverse
        a = mp.mpf(axial) * spin / transverse
        u0 = mp.cos(tilt)
        b = precession_rate * mp.sin(tilt) ** 2 + a * u0
        alpha = tilt_rate**2 + precession_rate**2 * mp.sin(tilt) ** 2 + beta * u0
        roots = sorted(
            mp.re(r)
            for r in mp.polyroots([beta, -(alpha + a * a), 2 * a * b - beta, alpha - b * b],
                                  maxsteps=200, extraprec=200)
        )  # fmt: skip
        u1, u2, u3 = roots
        m = (u2 - u1) / (u3 - u1)
        p = mp.sqrt(beta * (u3 - u1)) / 2
        tau0 = mp.ellipf(mp.asin(mp.sqrt((u0 - u1) / (u2 - u1))), m)
        if tilt_rate > 0:  # u̇0 = −θ̇0 sin θ0
            tau0 = -tau0

        def u(s):
            return u1 + (u2 - u1) * mp.ellipfun("sn", p * s + tau0, m=m) ** 2

        def phi_dot(s):
            us = u(s)
            return (b - a * us) / (1 - us * us)

        period = 2 * mp.ellipk(m) / p
        turns = mp.floor(mp.mpf(t) / period)
        rest = mp.mpf(t) - turns * period
        whole = mp.quad(phi_dot, [0, period / 4, period / 2, 3 * period / 4, period])
        part = mp.quad(phi_dot, mp.linspace(0, rest, 5))
        whole_u = mp.quad(lambda s: phi_dot(s) * u(s), [0, period / 2, period])
        part_u = mp.quad(lambda s: phi_dot(s) * u(s), mp.linspace(0, rest, 5))
        phi = turns * whole + part
        psi = spin * mp.mpf(t) - (turns * whole_u + part_u)
        return float(u(mp.mpf(t))), phi, psi, float(period)


def test_accuracy_a_million_nutation_periods_on_against_mpmath() -> None:
    tilt, tilt_rate, precession_rate, spin, lever = CASES["rising start"]
    disk, pivot = disk_top(lever)
    inertia = disk.inertia_about(pivot)
    args = (tilt, tilt_rate, precession_rate, spin, inertia[0, 0], inertia[2, 2])
    torque = disk.mass * G * lever
    gyro = tb.theory.gyroscope(
        disk, pivot, spin, tilt, tilt_rate=tilt_rate, precession_rate0=precession_rate
    )
    t = 1e6 * gyro.nutation_period + 0.3 * gyro.nutation_period
    cos_tilt, phi, psi, period = mpmath_top(*args, torque, t)
    assert period == pytest.approx(gyro.nutation_period, rel=1e-14)
    q = gyro.at(t)[1]
    with mp.workdps(40):
        expected = Rotation.from_euler(
            "ZXZ", [float(phi % (2 * mp.pi)), math.acos(cos_tilt), float(psi % (2 * mp.pi))]
        )
    error = (Rotation.from_quat(q, scalar_first=True) * expected.inv()).magnitude()
    # The phase is carried in double-double, so u(t) is exact to round-off; φ and
    # ψ grow by a whole-period increment each period, known to a few ulps, so
    # after a million periods they are off by a few ε of their size (measured:
    # 1.25e-9 rad for |φ| + |ψ| ≈ 2e7 rad, 0.3 ε).
    assert error < 4 * np.finfo(float).eps * float(abs(phi) + abs(psi))
    # t itself is known to half an ulp (~ε t): u = cos θ is right to that
    # resolution, |δu| ≤ |u̇| ε t with |u̇| = |θ̇ sin θ| ≤ |ω⊥| (measured: 2.6e-10).
    transverse_rate = np.max(np.hypot(*gyro.at(np.linspace(0, period, 101))[0][:, :2].T))
    eps = np.finfo(float).eps
    assert abs(math.cos(gyro.tilt_at(t)) - cos_tilt) < 4 * eps * t * transverse_rate


def test_gyroscope_refuses_an_initial_state_given_twice() -> None:
    disk, pivot = disk_top()
    with pytest.raises(InputError, match=r"spin_rate.*or as `omega0` and `attitude0`, got "
                       r"`spin_rate`, `tilt`, `omega0`"):  # fmt: skip
        tb.theory.gyroscope(disk, pivot, 100.0, 0.5, omega0=[0, 0, 100.0])


def test_gyroscope_refuses_omega0_without_an_attitude() -> None:
    disk, pivot = disk_top()
    with pytest.raises(InputError, match=r"or as `omega0` and `attitude0`, got `omega0`\."):
        tb.theory.gyroscope(disk, pivot, omega0=[0, 0, 100.0])


def test_gyroscope_refuses_no_initial_state() -> None:
    disk, pivot = disk_top()
    with pytest.raises(InputError, match=r"got spin_rate=None, tilt=None"):
        tb.theory.gyroscope(disk, pivot)


@pytest.mark.parametrize(
    ("lever", "gravity", "ending"),
    [
        (0.06, (0.0, 0.0, 0.0), "no gravity"),
        (None, (0.0, 0.0, -G), "another body"),
    ],
)
def test_the_closed_form_refuses_what_is_not_a_heavy_symmetric_top(lever, gravity, ending):
    disk, pivot = disk_top(0.06)
    if lever is None:  # the pivot off the symmetry axis
        pivot = np.array([0.01, 0.0, -0.06])
    body = RigidBody(disk, pivot=pivot)
    with pytest.raises(
        InputError,
        match=r"^Expected a symmetric top \(two equal moments about the pivot, the pivot and "
        r"the centre of mass on the symmetry axis\) under gravity for the closed form, got "
        + ending
        + r"\.$",
    ):
        lagrange_top(body, np.array(gravity), np.array([0.0, 0.0, 50.0]), tilted(0.5))


@pytest.mark.parametrize(
    ("lever", "tilt", "limit"),
    [
        (0.06, 0.0, 0.0),  # upright, fast enough to sleep
        (-0.06, 0.0, 0.0),  # hanging below the pivot, body z up
        (-0.06, math.pi, math.pi),  # body z down, the centre of mass above the pivot
    ],
)
def test_a_sleeping_top_stays_where_it_is(lever, tilt, limit) -> None:
    # ω along the axis, the axis exactly on the vertical: a steady rotation, so
    # the tilt's limits are the tilt itself (spin 200 rad/s is well above the
    # sleeping limit 2 √(m g l A) / C ≈ 36 rad/s of the upright case).
    disk, pivot = disk_top(lever)
    q0 = [1.0, 0.0, 0.0, 0.0] if tilt == 0.0 else [0.0, 1.0, 0.0, 0.0]
    gyro = tb.theory.gyroscope(disk, pivot, omega0=[0.0, 0.0, 200.0], attitude0=q0)
    assert gyro.nutation_limits == (limit, limit)
    np.testing.assert_allclose(gyro.tilt_at([0.0, 0.5, 1.0]), limit, atol=1e-15)


@pytest.mark.parametrize("weight", [1e-200, 1e-320])
def test_a_vanishing_gravity_gives_the_free_top(weight: float) -> None:
    # |g| = 1e-200 m/s² squares to 0: the closed form must use |g| itself, not
    # its square root of squares, and give the free motion about the pivot (the
    # torque-free closed form) to round-off.
    cylinder = tb.shapes.solid_cylinder(1.0, 0.04, 0.02)
    kwargs = {"pivot": [0, 0, -0.04], "duration": 1.0, "dt": 0.01, "method": "exact"}
    heavy = tb.simulate(cylinder, [0.3, 0.0, 100.0], gravity=[0, 0, -weight], **kwargs)
    free = tb.simulate(cylinder, [0.3, 0.0, 100.0], gravity=[0, 0, 0], **kwargs)
    assert_allclose(heavy.omega, free.omega, rtol=0, atol=1e-12)
    assert_allclose(np.abs(np.sum(heavy.quaternion * free.quaternion, axis=1)), 1.0, atol=1e-12)
