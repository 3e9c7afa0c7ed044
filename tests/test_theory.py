"""Closed-form results of ``tumble.theory`` against independent oracles.

Oracles, none of which calls tumble's simulator:

* sympy: the skew rod's L = Σ m r × ṙ and its bearing statics; the Lagrange
  equations of the heavy top and of the gimballed gyrocompass, derived from a
  rotation matrix and its angular velocity;
* Newton's law summed over point masses (rotor loads);
* scipy's DOP853 at rtol 1e-12 on Euler's equations, the rotation-matrix
  kinematics and gravity about a pivot, written out here (flip period, free
  symmetric top, axis stability, heavy top, gyrocompass);
* the time integral ∮ dω2 / ω̇2 by 40-digit quadrature (mpmath), near the
  separatrix where DOP853 loses the phase of the flips;
* eigenvalues of the linearised Euler equations (axis stability);
* conservation of energy and of the vertical angular momentum at the turning
  points of the heavy top;
* limiting cases: the fast-top approximations approach the exact values as the
  spin grows, the gyrocompass's small-angle and pendulum limits.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from reference import attitude_error, reference
from strategies import point_clouds, principal_moments, rotations
from tumble import theory

# DOP853 at rtol 1e-12 over a few periods keeps a relative error of ~1e-11 in
# the state and locates events to ~1e-11 of the period; the assertions below
# allow 1e-8 (1e-7 near a separatrix, where errors are amplified).
ODE = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-14}


# ----------------------------------------------------------------- helpers
def hat(w: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def rigid_rhs(
    inertia: np.ndarray, torque: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
) -> Callable[[float, np.ndarray], np.ndarray]:
    """Euler's equations I ω̇ + ω × I ω = τ in body axes, with Ṙ = R [ω]× (body → space)."""
    inverse = np.linalg.inv(inertia)

    def rhs(_: float, y: np.ndarray) -> np.ndarray:
        w, rot = y[:3], y[3:].reshape(3, 3)
        tau = np.zeros(3) if torque is None else torque(w, rot)
        return np.concatenate((inverse @ (tau - np.cross(w, inertia @ w)), (rot @ hat(w)).ravel()))

    return rhs


def euler_rhs(moments: np.ndarray) -> Callable[[float, np.ndarray], list[float]]:
    i1, i2, i3 = moments

    def rhs(_: float, w: np.ndarray) -> list[float]:
        return [
            (i2 - i3) * w[1] * w[2] / i1,
            (i3 - i1) * w[2] * w[0] / i2,
            (i1 - i2) * w[0] * w[1] / i3,
        ]

    return rhs


def rotate(vector: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    # Copies: scipy's Rotation.apply refuses read-only arrays.
    return Rotation.from_rotvec(angle * np.array(axis) / np.linalg.norm(axis)).apply(
        np.array(vector)
    )


def body_angular_velocity(rot: sp.Matrix, t: sp.Symbol) -> sp.Matrix:
    """ω in body axes from [ω]× = Rᵀ Ṙ (R: body → space)."""
    skew = rot.T * rot.diff(t)
    return sp.Matrix([skew[2, 1], skew[0, 2], skew[1, 0]]).applyfunc(sp.simplify)


def measured_flip_period(moments: np.ndarray, omega0: np.ndarray, expected: float) -> float:
    """Spacing of the upward zero crossings of the middle component of ω (once per period)."""
    order = np.argsort(moments)
    crossing = lambda _, w: w[1]  # noqa: E731
    crossing.direction = 1  # type: ignore[attr-defined]
    options = {**ODE, "atol": 1e-14 * np.abs(omega0).max()}
    sol = solve_ivp(
        euler_rhs(moments[order]), (0.0, 2.6 * expected), omega0[order], events=crossing, **options
    )
    times = sol.t_events[0]
    assert len(times) >= 2
    return float(np.mean(np.diff(times)))


def symmetric_body(mass: float, transverse: float, axial: float, com_z: float = 0.0):
    return tb.MassProperties(mass, [0.0, 0.0, com_z], np.diag([transverse, transverse, axial]))


# ================================================================= skew rod
m_, ell_, alpha_, w_, t_, d_ = sp.symbols("m ell alpha omega t d", real=True)


@functools.cache
def sympy_skew_rod():
    """L(t) and τ(t) = dL/dt of the two masses, from L = Σ m r × ṙ."""
    r = sp.rot_ccw_axis3(w_ * t_) * sp.Matrix([ell_ * sp.cos(alpha_), 0, ell_ * sp.sin(alpha_)])
    momentum = sp.zeros(3, 1)
    for position in (r, -r):
        momentum += m_ * position.cross(position.diff(t_))
    momentum = sp.simplify(momentum)
    return momentum, sp.simplify(momentum.diff(t_))


def test_skew_rod_magnitudes_are_those_derived_with_sympy() -> None:
    momentum, torque = sympy_skew_rod()
    # |L| = 2 m ℓ² ω cos α, its part along ω 2 m ℓ² ω cos² α, |τ| = ω L_h
    assert sp.simplify(momentum[2] - 2 * m_ * ell_**2 * w_ * sp.cos(alpha_) ** 2) == 0
    transverse2 = sp.simplify(momentum[0] ** 2 + momentum[1] ** 2)
    expected_h = 2 * m_ * ell_**2 * w_ * sp.sin(alpha_) * sp.cos(alpha_)
    assert sp.simplify(transverse2 - expected_h**2) == 0
    assert (
        sp.simplify(transverse2 + momentum[2] ** 2 - (2 * m_ * ell_**2 * w_ * sp.cos(alpha_)) ** 2)
        == 0
    )
    assert sp.simplify(torque.dot(torque) - (w_ * expected_h) ** 2) == 0
    assert sp.simplify(torque[2]) == 0


@pytest.mark.parametrize(
    ("mass", "ell", "alpha", "omega"),
    [(0.25, 0.1, math.radians(30), 314.0), (2.0, 0.5, -0.4, -3.0), (1.0, 1.0, 1.2, 7.5)],
)
def test_skew_rod_vectors_follow_the_sympy_solution(
    mass: float, ell: float, alpha: float, omega: float
) -> None:
    momentum, torque = sympy_skew_rod()
    values = {m_: mass, ell_: ell, alpha_: alpha, w_: omega}
    f_l = sp.lambdify(t_, momentum.subs(values), "numpy")
    f_tau = sp.lambdify(t_, torque.subs(values), "numpy")
    rod = theory.skew_rod(mass, ell, alpha, omega)
    times = np.linspace(0.0, 3.0, 7)
    expected_l = np.array([np.ravel(f_l(t)) for t in times])
    expected_tau = np.array([np.ravel(f_tau(t)) for t in times])
    scale = 2 * mass * ell**2 * abs(omega)
    # A few roundings in each product: 1e-13 of the scale.
    assert_allclose(rod.angular_momentum_at(times), expected_l, atol=1e-13 * scale)
    assert_allclose(rod.torque_at(times), expected_tau, atol=1e-13 * scale * abs(omega))
    assert_allclose(rod.angular_momentum_vector, expected_l[0], atol=1e-13 * scale)
    assert_allclose(rod.torque_at(0.0), rod.torque_vector, atol=0)
    assert rod.angular_momentum == pytest.approx(np.linalg.norm(expected_l[0]), rel=1e-13)
    assert rod.angular_momentum_axial == pytest.approx(expected_l[0, 2], rel=1e-13)
    assert rod.angular_momentum_transverse == pytest.approx(np.hypot(*expected_l[0, :2]), rel=1e-13)
    assert rod.torque == pytest.approx(np.linalg.norm(expected_tau[0]), rel=1e-13)


def test_skew_rod_bearing_forces_solve_the_statics_derived_with_sympy() -> None:
    _, torque = sympy_skew_rod()
    fx, fy, gx, gy = sp.symbols("fx fy gx gy", real=True)
    top, bottom = sp.Matrix([fx, fy, 0]), sp.Matrix([gx, gy, 0])
    # No net force (the centre of mass is fixed); the moment of the two about the
    # origin equals the torque that dL/dt needs.
    equations = list(top + bottom) + list(
        sp.Matrix([0, 0, d_ / 2]).cross(top) + sp.Matrix([0, 0, -d_ / 2]).cross(bottom) - torque
    )
    solution = sp.solve(equations, [fx, fy, gx, gy], dict=True)[0]
    values = {m_: 0.3, ell_: 0.2, alpha_: 0.5, w_: 40.0, d_: 0.35}
    rod = theory.skew_rod(0.3, 0.2, 0.5, 40.0, bearing_separation=0.35)
    for t in (0.0, 0.01, 0.1):
        expected = np.array(
            [
                [
                    float(solution[fx].subs(values).subs(t_, t)),
                    float(solution[fy].subs(values).subs(t_, t)),
                    0.0,
                ],
                [
                    float(solution[gx].subs(values).subs(t_, t)),
                    float(solution[gy].subs(values).subs(t_, t)),
                    0.0,
                ],
            ]
        )
        assert_allclose(rod.bearing_forces_at(t), expected, atol=1e-12 * rod.bearing_force)
    assert rod.bearing_force == pytest.approx(rod.torque / 0.35, rel=1e-15)
    assert rod.bearing_forces_at([0.0, 1.0]).shape == (2, 2, 3)


def test_skew_rod_takes_quantities_and_matches_the_rotor_loads_of_its_point_masses() -> None:
    rod = theory.skew_rod("250 g", "10 cm", "30 deg", "3000 rpm", bearing_separation="20 cm")
    omega = 3000 * 2 * math.pi / 60
    assert rod.torque == pytest.approx(
        2 * 0.25 * 0.01 * omega**2 * math.sin(math.pi / 6) * math.cos(math.pi / 6), rel=1e-14
    )
    a = math.radians(30)
    first = 0.1 * np.array([math.cos(a), 0.0, math.sin(a)])
    loads = theory.rotor_loads(
        tb.point_masses([0.25, 0.25], [first, -first]), omega, bearings=(0.1, -0.1)
    )
    assert_allclose(loads.torque, rod.torque_vector, atol=1e-12 * rod.torque)
    assert_allclose(loads.angular_momentum, rod.angular_momentum_vector, rtol=1e-13)
    assert_allclose(loads.bearing_forces, rod.bearing_forces, atol=1e-12 * rod.bearing_force)
    assert_allclose(loads.force, 0.0, atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"mass": 0.0}, r"Expected `mass` > 0 kg, got 0\.0\."),
        ({"half_length": -1.0}, r"Expected `half_length` > 0 m, got -1\.0\."),
        ({"bearing_separation": 0.0}, r"Expected `bearing_separation` > 0 m, got 0\.0\."),
        ({"alpha": "3 kg"}, r"Expected `alpha` to be an angle"),
        ({"omega": math.nan}, r"Expected `omega` to be finite"),
    ],
)
def test_skew_rod_refuses_bad_input(kwargs: dict[str, object], message: str) -> None:
    arguments: dict[str, object] = {"mass": 1.0, "half_length": 1.0, "alpha": 0.3, "omega": 2.0}
    arguments.update(kwargs)
    with pytest.raises(tb.InputError, match=message):
        theory.skew_rod(**arguments)  # type: ignore[arg-type]


def test_skew_rod_bearing_forces_need_a_separation() -> None:
    with pytest.raises(tb.InputError, match=r"Expected `bearing_separation` to have been given"):
        theory.skew_rod(1.0, 1.0, 0.3, 2.0).bearing_forces_at(0.0)


# ================================================================= rotor loads
unit_vectors = st.tuples(*(st.floats(-1, 1) for _ in range(3))).filter(
    lambda v: np.linalg.norm(v) > 0.1
)


@given(
    point_clouds(),
    unit_vectors,
    st.tuples(*(st.floats(-2, 2) for _ in range(3))),
    st.floats(-50, 50),
    st.tuples(st.floats(-3, 3), st.floats(-3, 3)).filter(lambda s: abs(s[0] - s[1]) > 0.1),
)
def test_rotor_loads_are_newtons_law_summed_over_point_masses(
    cloud: tuple[np.ndarray, np.ndarray],
    axis: tuple[float, float, float],
    point: tuple[float, float, float],
    omega: float,
    bearings: tuple[float, float],
) -> None:
    masses, positions = cloud
    mp = tb.point_masses(masses, positions)
    n = np.array(axis) / np.linalg.norm(axis)
    w = omega * n
    arm = positions - np.array(point)
    forces = masses[:, None] * np.cross(w, np.cross(w, arm))  # m a, a = ω × (ω × r)
    loads = theory.rotor_loads(mp, omega, axis=axis, point=point, bearings=bearings)
    scale = masses.sum() * (1 + np.abs(arm).max()) ** 2 * (1 + abs(omega)) ** 2
    assert_allclose(loads.force, forces.sum(axis=0), atol=1e-11 * scale)
    assert_allclose(loads.torque, np.cross(arm, forces).sum(axis=0), atol=1e-11 * scale)
    momentum = (masses[:, None] * np.cross(arm, np.cross(w, arm))).sum(axis=0)
    assert_allclose(loads.angular_momentum, momentum, atol=1e-11 * scale)
    # Statics of the shaft: the bearing forces sum to the force and their moments
    # about the point to the torque; neither has an axial part.
    f = loads.bearing_forces
    assert f is not None
    assert_allclose(f.sum(axis=0), loads.force, atol=1e-11 * scale)
    moment = sum(np.cross(s * n, fk) for s, fk in zip(bearings, f, strict=True))
    assert_allclose(moment, loads.torque, atol=1e-10 * scale)
    assert_allclose(f @ n, 0.0, atol=1e-10 * scale)


def test_a_balanced_rotor_needs_no_loads_and_an_offset_one_feels_m_omega2_r() -> None:
    wheel = tb.shapes.solid_cylinder(2.0, 0.1, 0.03)
    balanced = theory.rotor_loads(wheel, "3000 rpm", bearings=(-0.1, 0.1))
    assert_allclose(balanced.torque, 0.0, atol=1e-12)
    assert_allclose(balanced.bearing_forces, 0.0, atol=1e-12)
    offset = wheel.transformed(translation=[0.001, 0.0, 0.0])
    loads = theory.rotor_loads(offset, 100.0, bearings=(-0.1, 0.1))
    assert np.linalg.norm(loads.force) == pytest.approx(2.0 * 100.0**2 * 0.001, rel=1e-14)
    assert_allclose(loads.bearing_forces[0], loads.bearing_forces[1], rtol=1e-14)
    assert theory.rotor_loads(wheel, 1.0).bearing_forces is None


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: theory.rotor_loads("disk", 1.0),
            r"Expected `mp` to be a MassProperties, got str\.",
        ),  # type: ignore[arg-type]
        (
            lambda: theory.rotor_loads(tb.shapes.solid_sphere(1, 1), 1.0, axis=(0, 0, 0)),
            r"Expected `axis` to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.",
        ),
        (
            lambda: theory.rotor_loads(tb.shapes.solid_sphere(1, 1), 1.0, bearings=(0.5, 0.5)),
            r"Expected `bearings` to be two different axial positions, got 0\.5 twice\.",
        ),
        (
            lambda: theory.rotor_loads(tb.shapes.solid_sphere(1, 1), 1.0, bearings=(0.5,)),
            r"Expected `bearings` to have shape \(2,\), got \(1,\)\.",
        ),
    ],
)
def test_rotor_loads_refuses_bad_input(call: Callable[[], object], message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()


# ================================================================= flip period
@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ([1.0, 2.0, 3.0], [0.1, 0.2, 2.0]),  # about the largest axis
        ([1.0, 2.0, 3.0], [2.0, 0.2, 0.1]),  # about the smallest axis
        ([1.0, 2.0, 3.0], [0.01, 1.0, 0.01]),  # flipping, near the intermediate axis
        ([3.0, 1.0, 2.0], [0.3, 1.0, -0.2]),  # moments in any order
        ([0.2, 0.5, 0.6], [-1.0, 3.0, 0.7]),
        ([1.0, 1.0, 1.5], [1.0, 0.5, 2.0]),  # oblate symmetric top
        ([1.0, 1.5, 1.5], [2.0, 0.5, 1.0]),  # prolate symmetric top
    ],
)
def test_flip_period_is_the_period_of_eulers_equations(
    moments: list[float], omega0: list[float]
) -> None:
    inertia, omega = np.array(moments), np.array(omega0)
    period = theory.flip_period(inertia, omega)
    assert period == pytest.approx(measured_flip_period(inertia, omega, period), rel=1e-8)


def period_by_quadrature(moments: list[float], omega0: list[float]) -> float:
    """Period from the time integral ∮ dω2 / ω̇2 at 40 digits (side L² > 2 E I2).

    Energy and |L| give ω1² and ω3² as functions of ω2; Euler's second equation
    gives ω̇2 = (I3 − I1) ω1 ω3 / I2. With ω2 = A2 sin φ the half period is
    ∫ I2 A2 cos φ dφ / ((I3 − I1) |ω1 ω3|) over [−π/2, π/2], whose integrand is smooth.
    """
    import mpmath

    with mpmath.workdps(40):
        i1, i2, i3 = (mpmath.mpf(v) for v in moments)
        w1, w2, w3 = (mpmath.mpf(v) for v in omega0)
        energy2 = i1 * w1**2 + i2 * w2**2 + i3 * w3**2
        momentum2 = (i1 * w1) ** 2 + (i2 * w2) ** 2 + (i3 * w3) ** 2
        amplitude2 = (energy2 * i3 - momentum2) / (i2 * (i3 - i2))
        ratio1 = i2 * (i3 - i2) / (i1 * (i3 - i1))  # ω1² = ratio1 (A2² − ω2²)

        def integrand(phi: mpmath.mpf) -> mpmath.mpf:
            w2_phi2 = amplitude2 * mpmath.sin(phi) ** 2
            w3_2 = (momentum2 - energy2 * i1 - i2 * (i2 - i1) * w2_phi2) / (i3 * (i3 - i1))
            return i2 / ((i3 - i1) * mpmath.sqrt(ratio1) * mpmath.sqrt(w3_2))

        # The integrand peaks near ±π/2 as the separatrix nears: split there.
        half = mpmath.quad(integrand, mpmath.linspace(-mpmath.pi / 2, mpmath.pi / 2, 9))
        return float(2 * half)


@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ([1.0, 2.0, 3.0], [0.1, 0.2, 2.0]),
        ([1.0, 2.0, 3.0], [1e-3, 1.0, 2e-3]),  # L² − 2EI2 = 1.1e-5 of L²
        ([1.0, 2.0, 3.0], [1e-7, 1.0, 2e-7]),  # 1.1e-13 of L²: flips take 1e-3 of the period
    ],
)
def test_flip_period_near_the_separatrix_by_quadrature(
    moments: list[float], omega0: list[float]
) -> None:
    # DOP853 loses the phase of the flips here (REFERENCES.md); 40-digit quadrature of
    # the time integral does not. Agreement to 1e-12: a few roundings of the closed form.
    period = theory.flip_period(moments, omega0)
    assert period == pytest.approx(period_by_quadrature(moments, omega0), rel=1e-12)


@settings(max_examples=20)
@given(
    st.tuples(st.floats(0.1, 1.0), st.floats(0.05, 1.0), st.floats(0.05, 1.0)),
    st.tuples(*(st.floats(-3, 3) for _ in range(3))),
)
def test_flip_period_of_random_bodies(
    gaps: tuple[float, float, float], omega0: tuple[float, float, float]
) -> None:
    # I1 < I2 < I3 with I1 + I2 > I3: I2 = I1 + g2, I3 = I2 + g3 with g2 + g3 < I1.
    i1 = gaps[0] + gaps[1] + gaps[2]
    inertia = np.array([i1, i1 + gaps[1], i1 + gaps[1] + gaps[2]])
    omega = np.array(omega0)
    assume(np.abs(omega).min() > 0.05)
    period = theory.flip_period(inertia, omega)
    assume(period < 100 * 2 * math.pi / np.linalg.norm(omega))  # not too close to the separatrix
    assert period == pytest.approx(measured_flip_period(inertia, omega, period), rel=1e-8)


def test_flip_period_of_a_symmetric_top_is_the_body_precession_period() -> None:
    # Euler: I1 = I2 = I⊥ gives ω⊥ turning at Ω = (I_s − I⊥) ω_s / I⊥.
    assert theory.flip_period([2.0, 2.0, 3.0], [1.0, 0.2, 4.0]) == pytest.approx(
        2 * math.pi / (0.5 * 4.0), rel=1e-14
    )
    assert theory.flip_period([3.0, 2.0, 3.0], [1.0, -4.0, 0.2]) == pytest.approx(
        2 * math.pi / (1 / 3 * 4.0), rel=1e-14
    )


@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ([1.0, 2.0, 3.0], [0.0, 5.0, 0.0]),  # the intermediate axis: on the separatrix
        ([3.0, 4.0, 6.0], [2.0, 0.7, 1.0]),  # the separatrix: 3·2²·(4−3) = 6·1²·(6−4), exactly
        ([4.0, 3.0, 6.0], [0.7, 2.0, 1.0]),  # the same, in another order
        ([1.0, 2.0, 3.0], [0.0, 0.0, 0.0]),
        ([2.0, 2.0, 3.0], [1.0, 1.0, 0.0]),  # in the plane of equal moments
        ([2.0, 3.0, 3.0], [0.0, 1.0, -2.0]),
        ([1.0, 1.0, 1.0], [1.0, 2.0, 3.0]),  # a sphere
    ],
)
def test_flip_period_is_infinite_on_the_separatrix_and_where_nothing_wobbles(
    moments: list[float], omega0: list[float]
) -> None:
    assert theory.flip_period(moments, omega0) == math.inf


@pytest.mark.parametrize("axis", [0, 2])
def test_flip_period_on_a_stable_axis_is_the_wobble_period_and_the_limit_of_nearby_motions(
    axis: int,
) -> None:
    moments = np.array([1.0, 2.0, 3.0])
    omega = np.zeros(3)
    omega[axis] = 5.0
    wobble = theory.axis_stability(moments, 5.0).oscillation_frequencies[axis]
    assert theory.flip_period(moments, omega) == pytest.approx(2 * math.pi / wobble, rel=1e-15)
    for offset in (1e-3, 1e-6, 1e-9):
        nearby = omega + offset
        assert theory.flip_period(moments, nearby) == pytest.approx(
            2 * math.pi / wobble, rel=10 * offset
        )


def test_flip_period_of_extreme_angular_velocities() -> None:
    # Squares of these components underflow in floating point; the period does not.
    assert theory.flip_period([1.0, 1.0, 2.0], [0.0, 1.0, 1e-182]) == pytest.approx(
        2 * math.pi / 1e-182, rel=1e-14
    )
    slow = theory.flip_period([1.0, 2.0, 3.0], [1e-200, 2e-200, 3e-200])
    assert slow == pytest.approx(1e200 * theory.flip_period([1.0, 2.0, 3.0], [1, 2, 3]), rel=1e-14)
    # 1 − k² = 2e-400 and 1e-400 on the two sides of the separatrix, λ = √(1/3):
    # there K(k²) = ln(4 / √(1 − k²)) up to ~1e-397.
    near = theory.flip_period([1.0, 2.0, 3.0], [1e-200, 1.0, 1e-200])
    quarter = math.log(4) + 200 * math.log(10) - 0.5 * math.log(2)
    assert near == pytest.approx(4 * quarter * math.sqrt(3), rel=1e-14)
    other = theory.flip_period([1.0, 2.0, 3.0], [1e-200, 1.0, 0.0])
    assert other == pytest.approx(4 * (math.log(4) + 200 * math.log(10)) * math.sqrt(3), rel=1e-14)
    assert theory.flip_period([1.0, 2.0, 3.0], [0.0, 1e300, 1e-300]) < 1e-290
    # A prolate top turning about a transverse axis with a subnormal spin about its
    # symmetry axis: Ω = (Is − I⊥) ωs / I⊥ ≈ 1.6e-324 rad/s, a period 2π/|Ω| beyond
    # the float range: inf, not a division by an underflowed λ.
    assert theory.flip_period([2.0, 3.0, 3.0], [5e-324, 0.0, 1.0]) == math.inf


@given(principal_moments(), rotations(), st.tuples(*(st.floats(-3, 3) for _ in range(3))))
def test_flip_period_does_not_depend_on_the_body_axes(
    moments: np.ndarray, rotation: Rotation, omega0: tuple[float, float, float]
) -> None:
    assume(moments[0] > 1e-3 * moments[2])
    matrix = rotation.as_matrix()
    body = tb.MassProperties(1.0, [0, 0, 0], matrix @ np.diag(moments) @ matrix.T)
    omega = np.array(omega0)
    expected = theory.flip_period(moments, omega)
    got = theory.flip_period(body, matrix @ omega)
    # The principal axes of the rotated tensor carry round-off (~1e-15), which the
    # period amplifies near the separatrix by ~1/((1 − k²) ln(1/(1 − k²))): keep
    # 1 − k² > 1e-9, where the period is below 4√3 (ln 4 + ½ ln 1e9) ≈ 80 rad of
    # |ω| (at 200, 1 − k² reached 1e-24 and the periods differed by 1.4e-5).
    assume(np.linalg.norm(omega) > 0 and max(got, expected) * np.linalg.norm(omega) < 80)
    assert got == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize(
    ("moments", "omega0", "message"),
    [
        (
            [0.0, 1.0, 1.0],
            [1, 0, 0],
            r"Expected `moments` to be three principal moments > 0 kg·m² .*got \[0, 1, 1\]\.",
        ),
        (
            [1.0, 1.0, 3.0],
            [1, 0, 0],
            r"Expected `moments` to satisfy the triangle inequality I1 \+ I2 >= I3, got \[1, 1, 3\] kg·m²",
        ),
        ([1.0, 2.0], [1, 0, 0], r"Expected `moments` to have shape \(3,\), got \(2,\)\."),
        ([1.0, 2.0, 2.5], [1, 0], r"Expected `omega0` to have shape \(3,\), got \(2,\)\."),
        ([1.0, 2.0, 2.5], "1, 2, 3 m", r"Expected `omega0` to be an angular velocity"),
    ],
)
def test_flip_period_refuses_bad_input(moments: list[float], omega0: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        theory.flip_period(moments, omega0)


def test_flip_period_refuses_a_thin_rod() -> None:
    with pytest.raises(
        tb.InputError, match=r"Expected `moments` to be three principal moments > 0"
    ):
        theory.flip_period(tb.shapes.thin_rod(1.0, 1.0), [1.0, 0.0, 0.0])


# ================================================================= free symmetric top
@pytest.mark.parametrize(
    ("moments", "omega0"),
    [
        ([1.0, 1.0, 1.6], [0.3, -0.4, 2.0]),  # oblate
        ([1.0, 1.0, 1.6], [0.3, -0.4, -2.0]),  # spinning the other way
        ([0.5, 1.0, 1.0], [2.0, 0.5, 0.25]),  # prolate, symmetry axis x
    ],
)
def test_free_symmetric_top_cones_follow_eulers_equations(
    moments: list[float], omega0: list[float]
) -> None:
    inertia, omega = np.diag(moments), np.array(omega0)
    top = theory.free_symmetric_top(moments, omega)
    momentum = inertia @ omega  # space = body at t = 0
    duration = 3.0
    sol = solve_ivp(
        rigid_rhs(inertia),
        (0, duration),
        np.concatenate((omega, np.eye(3).ravel())),
        dense_output=True,
        **ODE,
    )
    for t in np.linspace(0.3, duration, 5):
        y = sol.sol(t)
        w, rot = y[:3], y[3:].reshape(3, 3)
        # In the body, ω turns about the symmetry axis at Ω.
        assert_allclose(w, rotate(omega, top.axis, top.body_precession_rate * t), atol=1e-9)
        # In space, the symmetry axis turns about L at L / I⊥.
        assert_allclose(
            rot @ top.axis, rotate(top.axis, momentum, top.space_precession_rate * t), atol=1e-9
        )
    # Angles and rates from their definitions.
    angle = lambda a, b: math.acos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1))  # noqa: E731
    assert top.body_cone_half_angle == pytest.approx(angle(omega, top.axis), abs=1e-12)
    assert top.space_cone_half_angle == pytest.approx(angle(omega, momentum), abs=1e-12)
    assert top.nutation_angle == pytest.approx(angle(top.axis, momentum), abs=1e-12)
    assert top.angular_momentum == pytest.approx(np.linalg.norm(momentum), rel=1e-14)
    assert top.spin_rate == pytest.approx(abs(omega @ top.axis), rel=1e-14)
    # ω = (L / I⊥) L̂ − Ω ê_s (Landau & Lifshitz §33).
    decomposition = (
        top.space_precession_rate * momentum / np.linalg.norm(momentum)
        - top.body_precession_rate * top.axis
    )
    assert_allclose(decomposition, omega, atol=1e-13)


@given(
    rotations(),
    st.floats(0.2, 2.0),
    st.floats(0.1, 1.9),
    st.tuples(*(st.floats(-3, 3) for _ in range(3))),
)
def test_free_symmetric_top_of_a_rotated_body(
    rotation: Rotation, transverse: float, ratio: float, omega0: tuple[float, float, float]
) -> None:
    matrix = rotation.as_matrix()
    body = tb.MassProperties(
        1.0, [0, 0, 0], matrix @ np.diag([transverse, transverse, ratio * transverse]) @ matrix.T
    )
    omega = np.array(omega0)
    top = theory.free_symmetric_top(body, omega)
    reference = theory.free_symmetric_top(
        [transverse, transverse, ratio * transverse], matrix.T @ omega
    )
    assert top.body_precession_rate == pytest.approx(
        reference.body_precession_rate, rel=1e-9, abs=1e-12
    )
    assert top.space_precession_rate == pytest.approx(
        reference.space_precession_rate, rel=1e-9, abs=1e-12
    )
    assume(abs(top.spin_rate) > 1e-6)
    assert_allclose(top.axis, matrix @ reference.axis, atol=1e-9)


def test_free_symmetric_top_of_a_sphere_and_a_transverse_spin() -> None:
    sphere = theory.free_symmetric_top([2.0, 2.0, 2.0], [0.0, 3.0, 4.0])
    assert sphere.body_precession_rate == 0.0
    assert sphere.space_precession_rate == pytest.approx(5.0)
    assert sphere.body_cone_half_angle == 0.0 and sphere.space_cone_half_angle == 0.0
    flat = theory.free_symmetric_top([1.0, 1.0, 2.0], [3.0, 4.0, 0.0])  # ω ⊥ axis: steady
    assert flat.body_precession_rate == 0.0
    assert flat.body_cone_half_angle == pytest.approx(math.pi / 2)
    assert flat.space_cone_half_angle == pytest.approx(0.0, abs=1e-15)


def test_free_symmetric_top_refuses_an_asymmetric_body() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"Expected `moments` to have two equal principal moments \(a symmetric top\), got \[1, 2, 2\.5\] kg·m²\.",
    ):
        theory.free_symmetric_top([1.0, 2.0, 2.5], [1.0, 0.0, 0.0])


# ================================================================= axis stability
@given(principal_moments(), st.floats(0.1, 100.0))
def test_axis_stability_is_the_linearised_euler_equations(moments: np.ndarray, spin: float) -> None:
    assume(moments[0] > 1e-3 * moments[2])
    result = theory.axis_stability(moments, spin)
    rhs = euler_rhs(moments)
    for k in range(3):
        steady = np.zeros(3)
        steady[k] = spin
        # Jacobian of Euler's equations by central differences (exact: they are quadratic).
        jacobian = np.column_stack(
            [(np.array(rhs(0, steady + e)) - np.array(rhs(0, steady - e))) / 2 for e in np.eye(3)]
        )
        eigen = np.linalg.eigvals(jacobian)
        scale = spin * (1 + moments[2] / moments[0])
        assert np.abs(eigen.real).max() == pytest.approx(result.growth_rates[k], abs=1e-9 * scale)
        assert np.abs(eigen.imag).max() == pytest.approx(
            result.oscillation_frequencies[k], abs=1e-9 * scale
        )
    assert result.stable.tolist() == (result.growth_rates == 0).tolist()


def test_axis_stability_growth_and_wobble_measured_by_integration() -> None:
    moments, spin = np.array([1.0, 2.0, 3.0]), 4.0
    result = theory.axis_stability(moments, spin)
    assert result.stable.tolist() == [True, False, True]
    gamma = result.growth_rates[1]
    assert gamma == pytest.approx(spin * math.sqrt(1 * 1 / 3), rel=1e-15)
    # Unstable axis: log|δω| grows at γ once the decaying mode has died out.
    sol = solve_ivp(
        euler_rhs(moments), (0, 12 / gamma), [1e-9, spin, 0.0], dense_output=True, **ODE
    )
    t1, t2 = 8 / gamma, 12 / gamma
    slope = (math.log(abs(sol.sol(t2)[0])) - math.log(abs(sol.sol(t1)[0]))) / (t2 - t1)
    # The decaying e^{−γt} mode shifts the slope by ~e^{−16}/4 relative; the deviation
    # stays below 1e-4 of the spin, so the nonlinear terms are ~1e-8 of it.
    assert slope == pytest.approx(gamma, rel=1e-6)
    # Stable axes: δω wobbles at the frequency (amplitude 1e-6: nonlinear shift ~1e-12).
    for k in (0, 2):
        omega0 = np.full(3, 1e-6 * spin)
        omega0[k] = spin
        crossing = lambda _, w, k=k: w[(k + 1) % 3]  # noqa: E731
        crossing.direction = 1  # type: ignore[attr-defined]
        sol = solve_ivp(
            euler_rhs(moments),
            (0, 40 / result.oscillation_frequencies[k]),
            omega0,
            events=crossing,
            **ODE,
        )
        measured = 2 * math.pi / np.mean(np.diff(sol.t_events[0]))
        assert measured == pytest.approx(result.oscillation_frequencies[k], rel=1e-8)


def test_axis_stability_of_a_body_uses_its_principal_axes() -> None:
    box = tb.shapes.box(1.0, (0.1, 0.2, 0.3)).transformed(
        rotation=Rotation.from_euler("xyz", [10, 20, 30], degrees=True)
    )
    result = theory.axis_stability(box, "60 rpm")
    moments, axes = box.principal()
    assert_allclose(result.moments, moments)
    assert_allclose(result.axes, axes)
    assert result.spin_rate == pytest.approx(2 * math.pi)
    symmetric = theory.axis_stability([1.0, 1.0, 1.5], 2.0)
    assert symmetric.stable.all() and symmetric.growth_rates.max() == 0.0


def test_axis_stability_refuses_bad_moments() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"Expected `moments` to be three principal moments > 0 kg·m² .*got \[-1, 1, 1\]\.",
    ):
        theory.axis_stability([-1.0, 1.0, 1.0], 1.0)


# ================================================================= heavy top
g_ = 9.81


def top_body(lever: float = 0.06) -> tuple[tb.MassProperties, np.ndarray]:
    """A 0.5 kg disk (r 4 cm, h 2 cm) on a pivot `lever` below its centre of mass."""
    disk = tb.shapes.solid_cylinder(0.5, 0.04, 0.02)
    return disk, np.array([0.0, 0.0, -lever])


def pivot_inertia(mass: float, lever: float) -> np.ndarray:
    # Disk about its centre: I⊥ = m (3 r² + h²)/12, I_s = m r²/2; parallel axes to the pivot.
    transverse = mass * (3 * 0.04**2 + 0.02**2) / 12 + mass * lever**2
    return np.diag([transverse, transverse, mass * 0.04**2 / 2])


def integrate_top(
    lever: float, tilt: float, omega_body: np.ndarray, duration: float, **kwargs: object
):
    """The top about its pivot: Euler's equations with the gravity torque r_c × Rᵀ(−m g ẑ)."""
    mass = 0.5
    arm = np.array([0.0, 0.0, lever])
    torque = lambda _, rot: np.cross(arm, rot.T @ np.array([0.0, 0.0, -mass * g_]))  # noqa: E731
    rot0 = Rotation.from_rotvec([tilt, 0.0, 0.0]).as_matrix()  # z-x-z with φ = ψ = 0
    y0 = np.concatenate((omega_body, rot0.ravel()))
    return solve_ivp(
        rigid_rhs(pivot_inertia(mass, lever), torque), (0, duration), y0, **ODE, **kwargs
    )  # type: ignore[arg-type]


def tilt_of(y: np.ndarray) -> np.ndarray:
    return np.arccos(np.clip(y[3 + 8], -1.0, 1.0))  # R[2, 2] = cos θ


@pytest.mark.slow  # a symbolic derivation: 3 s
def test_heavy_top_equations_from_the_lagrangian_with_sympy() -> None:
    """θ equation of the Lagrange top, derived from R = Rz(φ) Rx(θ) Rz(ψ)."""
    t = sp.Symbol("t")
    ip, i_s, mgl, big_omega, w3 = sp.symbols("I_p I_s mgl Omega omega_3", positive=True)
    phi, theta, psi = (sp.Function(n)(t) for n in ("phi", "theta", "psi"))
    rot = sp.rot_ccw_axis3(phi) * sp.rot_ccw_axis1(theta) * sp.rot_ccw_axis3(psi)
    w = body_angular_velocity(rot, t)
    lagrangian = sp.Rational(1, 2) * (w.T * sp.diag(ip, ip, i_s) * w)[0] - mgl * rot[2, 2]
    equation = sp.diff(lagrangian.diff(theta.diff(t)), t) - lagrangian.diff(theta)
    steady = {
        theta.diff(t, 2): 0,
        phi.diff(t, 2): 0,
        psi.diff(t, 2): 0,
    }
    equation = equation.subs(steady).subs(
        {theta.diff(t): 0, psi.diff(t): w3 - big_omega * sp.cos(theta), phi.diff(t): big_omega}
    )
    # Steady precession: sin θ (I⊥' cos θ Ω² − I_s ω3 Ω + m g l) = 0, the quadratic in theory.gyroscope.
    quadratic = ip * sp.cos(theta) * big_omega**2 - i_s * w3 * big_omega + mgl
    assert sp.simplify(equation + sp.sin(theta) * quadratic) == 0


@pytest.mark.parametrize("which", [0, 1])
@pytest.mark.parametrize(
    ("lever", "tilt"),
    [(0.06, math.radians(30)), (0.06, math.radians(120)), (-0.05, math.radians(50))],
)
def test_steady_precession_rates_keep_the_tilt_constant(
    which: int, lever: float, tilt: float
) -> None:
    disk, pivot = top_body(lever)
    spin = 150.0
    gyro = theory.gyroscope(disk, pivot, spin, tilt)
    assert gyro.precession_rates is not None
    rate = gyro.precession_rates[which]
    duration = 2 * math.pi / abs(rate)
    sol = integrate_top(
        lever, tilt, np.array([0.0, rate * math.sin(tilt), spin]), duration, dense_output=True
    )
    times = np.linspace(0, duration, 200)
    y = sol.sol(times)
    # θ stays put to integration accuracy; the axis turns about the vertical at Ω.
    assert_allclose(tilt_of(y), tilt, atol=1e-8)
    axis_x, axis_y = y[3 + 2], y[3 + 5]  # R[0, 2], R[1, 2] = sin θ sin φ, −sin θ cos φ
    azimuth = np.unwrap(np.arctan2(axis_x, -axis_y))
    assert_allclose(azimuth, rate * times, atol=1e-7 * abs(rate) * duration)


@pytest.mark.parametrize(
    ("lever", "tilt", "spin"),
    [
        (0.06, math.radians(30), 150.0),
        (0.06, math.radians(80), 40.0),
        (-0.05, math.radians(60), 60.0),
        (0.06, math.radians(150), -80.0),
    ],
)
def test_released_top_tilt_is_the_exact_solution(lever: float, tilt: float, spin: float) -> None:
    disk, pivot = top_body(lever)
    gyro = theory.gyroscope(disk, pivot, spin, tilt)
    turning = lambda _, y: y[3 + 6] * y[1] - y[3 + 7] * y[0]  # noqa: E731  d R[2,2]/dt = R20 ω_y − R21 ω_x
    duration = 3.2 * gyro.nutation_period
    sol = integrate_top(
        lever, tilt, np.array([0.0, 0.0, spin]), duration, dense_output=True, events=turning
    )
    times = np.linspace(0, duration, 301)
    # Both are accurate to ~1e-11 rad; 1e-8 leaves room for the ODE over three periods.
    assert_allclose(gyro.tilt_at(times), tilt_of(sol.sol(times)), atol=1e-8)
    events = sol.t_events[0][sol.t_events[0] > 1e-6 * duration]
    # Turning points alternate between the two limits, half a period apart.
    assert_allclose(np.diff(events), gyro.nutation_period / 2, rtol=1e-8)
    reached = tilt_of(np.array(sol.y_events[0]).T)
    low, high = gyro.nutation_limits
    assert_allclose(np.sort([reached.min(), reached.max()]), [low, high], atol=1e-8)
    assert tilt in (low, high)
    assert gyro.tilt_at(2.5).shape == () and gyro.tilt_at([1.0, 2.0]).shape == (2,)


@pytest.mark.parametrize("lever", [1e-7, -1e-7, 1e-30, -1e-120, 1e-200, 1e-300, 3e-310])
def test_top_under_vanishing_weight_is_the_first_order_solution(lever: float) -> None:
    # With m g l → 0 the closed form's large root u3 ~ 1/β leaves the float range;
    # it must still give the motion to first order in l. Oracle: Euler's
    # equations linearised about the steady spin n (A ω̇⊥ = (A − C) n J ω⊥ + τ⊥,
    # τ = −m g l e3 × k, k turning as e^{−i n t} in the body), solved in closed
    # form: z = ω1 + i ω2 = (−i m g l κ0 / A) e^{−iμt} (e^{i(μ−n)t} − 1) / (i(μ−n)),
    # μ = (A − C) n / A, κ0 = k1 + i k2 at t = 0.
    mass, transverse, axial, spin = 0.5, 1.0, 0.6, 2.0
    body = symmetric_body(mass, transverse, axial, com_z=lever)
    gyro = theory.gyroscope(body, [0, 0, 0], spin, 1.0)
    times = np.linspace(0.0, 7.0, 15)
    omega, attitude = gyro.at(times)
    k = Rotation.from_quat(attitude[0], scalar_first=True).inv().apply([0.0, 0.0, 1.0])
    mu = (transverse - axial) * spin / transverse
    z = (
        -1j * mass * g_ * lever * (k[0] + 1j * k[1]) / transverse
        * np.exp(-1j * mu * times) * (np.exp(1j * (mu - spin) * times) - 1) / (1j * (mu - spin))
    )  # fmt: skip
    # The neglected terms are smaller by ~β / (C n / A)² = 6.8 l (bound: 20 l); the
    # closed form's round-off is a few ε |ω|, from terms of order n that cancel.
    beta = 2 * mass * g_ * abs(lever) / transverse
    second_order = 3 * beta / (axial * spin / transverse) ** 2
    tolerance = 4 * np.finfo(float).eps * spin + second_order * np.abs(z).max()
    assert np.abs(omega[:, 0] + 1j * omega[:, 1] - z).max() <= tolerance
    assert_allclose(omega[:, 2], spin, rtol=1e-15)
    # The tilt ranges over twice the fast top's nutation amplitude (to first order),
    # from the release downwards (the axis falls; with l < 0 body z rises). With
    # l < 0 the tilt is π minus the angle from the lowest point: a few ulps of π.
    low, high = gyro.nutation_limits
    assert (low if lever > 0 else high) == pytest.approx(1.0, abs=1e-15)
    assert high - low == pytest.approx(2 * gyro.nutation_amplitude, rel=second_order, abs=1e-15)
    period = 2 * math.pi * transverse / (axial * spin)  # the torque-free nutation
    assert gyro.nutation_period == pytest.approx(period, rel=second_order + 1e-14)


@settings(max_examples=40)
@given(
    st.floats(1e-3, 1.0),
    st.floats(0.05, 1.95),
    st.floats(-0.3, 0.3),
    st.floats(0.5, 3.0),
    st.floats(0.01, math.pi - 0.01),
    st.floats(1.0, 300.0),
)
@example(1.0, 1.0, 2.225073858507203e-309, 0.5, 1.0, 2.0)  # a subnormal m g l
def test_released_top_turning_points_conserve_energy_and_vertical_momentum(
    transverse: float, ratio: float, lever: float, mass: float, tilt: float, spin: float
) -> None:
    body = symmetric_body(mass, transverse, ratio * transverse, com_z=lever)
    gyro = theory.gyroscope(body, [0, 0, 0], spin, tilt)
    i_p = transverse + mass * lever**2
    spin_momentum = ratio * transverse * spin
    p_phi = spin_momentum * math.cos(tilt)  # φ̇ = 0 at release
    energy = mass * g_ * lever * math.cos(tilt)
    assert gyro.transverse_moment == pytest.approx(i_p, rel=1e-14)
    for theta in gyro.nutation_limits:
        # At a turning point θ̇ = 0: φ̇ from p_φ, then the energy must be the initial one.
        if abs(math.sin(theta)) < 1e-6:
            continue
        phi_dot = (p_phi - spin_momentum * math.cos(theta)) / (i_p * math.sin(theta) ** 2)
        energy_there = 0.5 * i_p * (phi_dot * math.sin(theta)) ** 2 + mass * g_ * lever * math.cos(
            theta
        )
        # Both energy terms are of order m g l, and θ is accurate to ~1e-15 with
        # |sin θ| > 0.01; a round-off δθ in θ adds ~I⊥' (a δθ)², a = I_s ω_s / I⊥'.
        floor = 1e-28 * i_p * (spin_momentum / i_p) ** 2
        assert energy_there == pytest.approx(energy, abs=1e-9 * mass * g_ * abs(lever) + floor)


def test_fast_top_approximations_improve_as_the_spin_grows() -> None:
    disk, pivot = top_body()
    errors = []
    for spin in (400.0, 800.0, 1600.0, 3200.0, 6400.0):
        gyro = theory.gyroscope(disk, pivot, spin, "40 deg")
        assert gyro.precession_rates is not None and gyro.small_nutation_frequencies is not None
        low, high = gyro.nutation_limits
        errors.append(
            [
                abs(gyro.precession_rate / gyro.precession_rates[0] - 1),
                abs(2 * gyro.nutation_amplitude / (high - low) - 1),
                abs(gyro.nutation_frequency * gyro.nutation_period / (2 * math.pi) - 1),
                abs(gyro.nutation_frequency / gyro.small_nutation_frequencies[0] - 1),
            ]
        )
    errors_array = np.array(errors)
    # Each error falls by ~4× when the spin doubles (they are O(1/ω²)).
    assert np.all(errors_array[1:] < 0.35 * errors_array[:-1])
    assert errors_array[-1].max() < 1e-3


@pytest.mark.slow  # long integrations: 3 s
def test_small_nutation_about_steady_precession_measured_by_integration() -> None:
    disk, pivot = top_body()
    tilt, spin = math.radians(45), 200.0
    gyro = theory.gyroscope(disk, pivot, spin, tilt)
    assert gyro.precession_rates is not None and gyro.small_nutation_frequencies is not None
    rate = gyro.precession_rates[0]
    # Nudge the steady state by 1e-6 rad/s in θ̇: a nutation of amplitude ~1e-8 rad.
    omega = np.array([1e-6, rate * math.sin(tilt), spin])
    frequency = gyro.small_nutation_frequencies[0]
    turning = lambda _, y: y[3 + 6] * y[1] - y[3 + 7] * y[0]  # noqa: E731
    sol = integrate_top(0.06, tilt, omega, 20 * 2 * math.pi / frequency, events=turning)
    measured = math.pi / np.mean(np.diff(sol.t_events[0]))
    assert measured == pytest.approx(frequency, rel=1e-6)


def test_gyroscope_special_cases() -> None:
    disk, _ = top_body()
    # No lever: a free symmetric top released with ω along its axis stays put.
    free = theory.gyroscope(disk, [0, 0, 0], 30.0, 0.7)
    assert free.precession_rate == 0.0
    assert_allclose(free.nutation_limits, 0.7, rtol=1e-15)
    assert_allclose(free.tilt_at([0.0, 1.0, 2.0]), 0.7, atol=1e-15)
    # Upright and fast enough to sleep: no nutation.
    sleeping = theory.gyroscope(disk, [0, 0, -0.06], 500.0, 0.0)
    assert sleeping.nutation_limits == (0.0, 0.0) and sleeping.tilt_at(1.0) == 0.0
    # Upright below the sleeping-top limit (I_s² ω² < 4 I⊥' m g l): a separatrix.
    slow = theory.gyroscope(disk, [0, 0, -0.06], 5.0, 0.0)
    assert slow.nutation_period == math.inf and slow.tilt_at(3.0) == 0.0
    assert slow.nutation_limits[1] > 0.1
    # Too slow for steady precession at 30°.
    assert theory.gyroscope(disk, [0, 0, -0.06], 5.0, "30 deg").precession_rates is None
    # Quantities at the edge.
    a = theory.gyroscope(disk, "0, 0, -6 cm", "3000 rpm", "30 deg", gravity="9.81 m/s^2")
    b = theory.gyroscope(disk, [0, 0, -0.06], 100 * math.pi, math.pi / 6)
    assert a.precession_rate == pytest.approx(b.precession_rate, rel=1e-14)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: theory.gyroscope(tb.shapes.box(1, (1, 2, 3)), [0, 0, -1], 10, 0.3),
            r"Expected `mp` to be symmetric about body z",
        ),
        (
            lambda: theory.gyroscope(tb.shapes.thin_rod(1, 1), [0, 0, -1], 10, 0.3),
            r"Expected `mp` to have a moment about its symmetry axis z > 0 kg·m²",
        ),
        (
            lambda: theory.gyroscope(tb.shapes.solid_cylinder(1, 1, 1), [0.1, 0, -1], 10, 0.3),
            r"Expected `pivot` on the symmetry axis .* 0\.1 m off the axis\.",
        ),
        (
            lambda: theory.gyroscope(tb.shapes.solid_cylinder(1, 1, 1), [0, 0, -1], 0, 0.3),
            r"Expected `spin_rate` ≠ 0 rad/s .*got 0\.0\.",
        ),
        (
            lambda: theory.gyroscope(tb.shapes.solid_cylinder(1, 1, 1), [0, 0, -1], 10, 4.0),
            r"Expected `tilt` in \[0, π\] rad \(0 = upright\), got 4\.0\.",
        ),
        (
            lambda: theory.gyroscope(
                tb.shapes.solid_cylinder(1, 1, 1), [0, 0, -1], 10, 0.3, gravity=-9.81
            ),
            r"Expected `gravity` >= 0 m/s² \(its magnitude\), got -9\.81\.",
        ),
        (
            lambda: theory.gyroscope(None, [0, 0, -1], 10, 0.3),
            r"Expected `mp` to be a MassProperties, got NoneType\.",
        ),  # type: ignore[arg-type]
    ],
)
def test_gyroscope_refuses_bad_input(call: Callable[[], object], message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()


# ================================================================= gyrocompass
@functools.cache
def sympy_gyrocompass():
    """Lagrange equations of the disk in the gimbal, R = Rz(Ω t) Rx(θ) Rz(ψ)."""
    t = sp.Symbol("t")
    i_ab, i_s, big_omega = sp.symbols("I_AB I_s Omega", positive=True)
    theta, psi = sp.Function("theta")(t), sp.Function("psi")(t)
    rot = sp.rot_ccw_axis3(big_omega * t) * sp.rot_ccw_axis1(theta) * sp.rot_ccw_axis3(psi)
    w = body_angular_velocity(rot, t)
    kinetic = sp.simplify(sp.Rational(1, 2) * (w.T * sp.diag(i_ab, i_ab, i_s) * w)[0])
    equations = [sp.diff(kinetic.diff(q.diff(t)), t) - kinetic.diff(q) for q in (theta, psi)]
    accelerations = sp.solve(equations, [theta.diff(t, 2), psi.diff(t, 2)], dict=True)[0]
    return t, (i_ab, i_s, big_omega), theta, psi, accelerations


@pytest.mark.slow  # a symbolic derivation: 3 s
def test_gyrocompass_equation_from_the_lagrangian_with_sympy() -> None:
    t, (i_ab, i_s, big_omega), theta, psi, acc = sympy_gyrocompass()
    w_s = sp.Symbol("omega_s", positive=True)
    # The spin ω_s = ψ̇ + Ω cos θ is the conserved quantity (ψ is cyclic).
    spin_sub = {psi.diff(t): w_s - big_omega * sp.cos(theta)}
    theta_dd = sp.simplify(acc[theta.diff(t, 2)].subs(spin_sub))
    expected = -i_s * w_s * big_omega * sp.sin(theta) / i_ab + big_omega**2 * sp.sin(
        theta
    ) * sp.cos(theta)
    assert sp.simplify(theta_dd - expected) == 0
    spin_rate = sp.simplify(
        (psi.diff(t) + big_omega * sp.cos(theta)).diff(t).subs(acc).subs(spin_sub)
    )
    assert spin_rate == 0
    # The same as the method, at a few angles.
    disk = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)
    compass = theory.gyrocompass(disk, 100.0, 2.0)
    values = {i_ab: compass.gimbal_moment, i_s: compass.axial_moment, big_omega: 2.0, w_s: 100.0}
    f = sp.lambdify(theta, expected.subs(values), "numpy")
    angles = np.array([0.1, 1.0, 2.5, -0.7])
    assert_allclose(compass.angular_acceleration(angles), f(angles), rtol=1e-14)


@pytest.mark.parametrize("amplitude", [0.01, 0.5, 1.5, 2.5, 3.0])
@pytest.mark.parametrize(("spin", "platform"), [(100.0, 2.0), (6.0, 2.0), (-50.0, 1.0)])
def test_gyrocompass_period_measured_on_the_lagrange_equations(
    amplitude: float, spin: float, platform: float
) -> None:
    t, (i_ab, i_s, big_omega), theta, psi, acc = sympy_gyrocompass()
    disk = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)
    compass = theory.gyrocompass(disk, spin, platform)
    # Spin and Ω in the same sense: θ measured from +z. Opposite senses: L_s settles
    # along −z, so θ from −z, i.e. the disk's axis at π − θ.
    aligned = spin * platform > 0
    values = {i_ab: compass.gimbal_moment, i_s: compass.axial_moment, big_omega: platform}
    q, qd, pd = sp.symbols("q qd pd")

    def numeric(expr: sp.Expr) -> sp.Expr:
        # Derivatives first: replacing θ(t) first would turn θ̇ into d(q)/dt = 0.
        return expr.subs(values).subs({theta.diff(t): qd, psi.diff(t): pd}).subs(theta, q)

    f = sp.lambdify(
        (q, qd, pd), [numeric(acc[theta.diff(t, 2)]), numeric(acc[psi.diff(t, 2)])], "numpy"
    )

    def rhs(_: float, y: np.ndarray) -> list[float]:
        a_theta, a_psi = f(y[0], y[1], y[3])
        return [y[1], a_theta, y[3], a_psi]

    start = amplitude if aligned else math.pi - amplitude
    y0 = [start, 0.0, 0.0, spin - platform * math.cos(start)]  # ψ̇ from the total spin
    turning = lambda _, y: y[1]  # noqa: E731
    expected = compass.period(amplitude)
    sol = solve_ivp(rhs, (0, 2.3 * expected), y0, events=turning, **ODE)
    events = sol.t_events[0][sol.t_events[0] > 1e-6 * expected]
    assert 2 * np.mean(np.diff(events)) == pytest.approx(expected, rel=1e-8)


def test_gyrocompass_limits() -> None:
    disk = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)
    compass = theory.gyrocompass(disk, 100.0, 2.0)
    # β = √(L_s Ω / I_AB) = √(ω_s Ω I_s / I_AB); with the Ω² term √(β² − Ω²).
    beta = math.sqrt(100.0 * 2.0 * compass.axial_moment / compass.gimbal_moment)
    assert compass.oscillation_frequency == pytest.approx(beta, rel=1e-15)
    assert compass.small_oscillation_frequency == pytest.approx(math.sqrt(beta**2 - 4.0), rel=1e-15)
    assert compass.period(0.0) == pytest.approx(
        2 * math.pi / compass.small_oscillation_frequency, rel=1e-14
    )
    # Released near upside down, the axis lingers: the period grows like ln(1/(π − θ0)).
    near = [compass.period(math.pi - gap) for gap in (1e-2, 1e-4, 1e-8)]
    assert near[0] < near[1] < near[2] < compass.period(math.pi)
    # Ω² ≪ β²: the pendulum's 4 K(sin²(θ0/2)) / β; the difference shrinks like Ω/ω_s.
    from scipy.special import ellipk

    gaps = []
    for spin in (1e2, 1e4, 1e6):
        fast = theory.gyrocompass(disk, spin, 2.0)
        pendulum = 4 * ellipk(math.sin(1.0) ** 2) / fast.oscillation_frequency
        gaps.append(abs(fast.period(2.0) / pendulum - 1))
    assert gaps[1] < 0.02 * gaps[0] and gaps[2] < 0.02 * gaps[1]
    assert theory.gyrocompass(disk, "955 rpm", "0.5 turn/s").spin_rate == pytest.approx(
        955 * 2 * math.pi / 60
    )


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: theory.gyrocompass(tb.shapes.solid_cylinder(1.0, 0.05, 0.02), 1.0, 2.0),
            r"Expected \|`spin_rate`\| > I_AB \|Ω\| / I_s = 1\.05333 rad/s for the spin axis to oscillate about the direction of Ω, got 1\.0",
        ),
        (
            lambda: theory.gyrocompass(tb.shapes.box(1, (1, 2, 3)), 100.0, 2.0),
            r"Expected `mp` to be symmetric about body z",
        ),
        (
            lambda: theory.gyrocompass(
                tb.shapes.solid_cylinder(1.0, 0.05, 0.02), 100.0, 2.0
            ).period(4.0),
            r"Expected `amplitude` in \[0, π\] rad, got 4\.0\.",
        ),
    ],
)
def test_gyrocompass_refuses_bad_input(call: Callable[[], object], message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()


# ------------------------------------------------------------- free_motion
def test_free_motion_at_any_times_matches_a_reference_integration() -> None:
    axes = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    body = tb.MassProperties(1.0, [0, 0, 0], axes @ np.diag([1.0, 2.0, 3.0]) @ axes.T)
    omega0 = np.array([0.3, 1.0, -0.5])
    q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
    motion = theory.free_motion(body, omega0, q0)
    times = np.array([7.5, 0.0, 3.25, 12.0])  # any order, no stepping
    omega, quaternion = motion.at(times)
    order = np.argsort(times)
    w_ref, a_ref = reference(body, omega0, q0, 12.0, times=times[order])
    # DOP853 at rtol 1e-13 over 12 s: ~1e-12; the exact solution is better.
    assert np.max(np.abs(omega[order] - w_ref)) < 1e-11
    assert attitude_error(quaternion[order], a_ref) < 1e-11
    w_one, q_one = motion.at(3.25)
    assert w_one.shape == (3,) and q_one.shape == (4,)
    assert_allclose(w_one, omega[2], atol=0)


def test_free_motion_errors() -> None:
    with pytest.raises(tb.InputError, match=r"Expected `mp` to be a MassProperties, got list"):
        theory.free_motion([1, 2, 3], [0, 0, 1])
    motion = theory.free_motion(tb.shapes.solid_sphere(1.0, 0.1), [0, 0, 1])
    with pytest.raises(tb.InputError, match=r"Expected `t` to be finite times in s, got nan"):
        motion.at(float("nan"))
