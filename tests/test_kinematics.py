"""Angular momentum, kinetic energy and required torque against first principles.

Oracles: the definitions over point masses (L = Σ m r × v with v = ω × r,
T = Σ ½ m |v|²), the closed forms of the rotating skew rod from the lecture
notes, and the rate of change of the space-frame angular momentum along a
prescribed motion integrated to high precision.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from strategies import omegas, point_clouds


def scale_of(masses: np.ndarray, positions: np.ndarray, omega: np.ndarray) -> float:
    return float(masses.sum() * (1 + np.abs(positions).max()) ** 2 * (1 + np.abs(omega).max()) ** 2)


@given(point_clouds(), omegas)
def test_angular_momentum_is_the_sum_of_r_cross_mv(
    cloud: tuple[np.ndarray, np.ndarray], omega: np.ndarray
) -> None:
    masses, positions = cloud
    mp = tb.point_masses(masses, positions)
    d = positions - mp.center_of_mass
    expected = sum(m * np.cross(r, np.cross(omega, r)) for m, r in zip(masses, d, strict=True))
    assert_allclose(
        tb.angular_momentum(mp, omega), expected, atol=1e-11 * scale_of(masses, positions, omega)
    )


@given(point_clouds(), omegas, st.tuples(*(st.floats(-3, 3) for _ in range(3))))
def test_angular_momentum_about_a_fixed_point(
    cloud: tuple[np.ndarray, np.ndarray], omega: np.ndarray, point: tuple[float, float, float]
) -> None:
    masses, positions = cloud
    mp = tb.point_masses(masses, positions)
    d = positions - np.array(point)  # the body turns about `point`, which stays fixed
    expected = sum(m * np.cross(r, np.cross(omega, r)) for m, r in zip(masses, d, strict=True))
    got = tb.angular_momentum(mp, omega, about=point)
    assert_allclose(got, expected, atol=1e-11 * scale_of(masses, positions + 3, omega))
    energy = sum(0.5 * m * np.sum(np.cross(omega, r) ** 2) for m, r in zip(masses, d, strict=True))
    # ω ∥ r makes the energy vanish by cancellation: tolerance relative to the terms' size.
    assert tb.kinetic_energy(mp, omega, about=point) == pytest.approx(
        energy, rel=1e-10, abs=1e-13 * scale_of(masses, positions + 3, omega)
    )


@given(point_clouds(), omegas)
def test_kinetic_energy_is_the_sum_of_half_m_v_squared(
    cloud: tuple[np.ndarray, np.ndarray], omega: np.ndarray
) -> None:
    masses, positions = cloud
    mp = tb.point_masses(masses, positions)
    d = positions - mp.center_of_mass
    expected = sum(
        0.5 * m * np.sum(np.cross(omega, r) ** 2) for m, r in zip(masses, d, strict=True)
    )
    assert tb.kinetic_energy(mp, omega) == pytest.approx(
        expected, rel=1e-10, abs=1e-11 * scale_of(masses, positions, omega)
    )


def test_stacks_of_omega_give_stacks_of_results() -> None:
    mp = tb.shapes.box(2.0, (0.1, 0.2, 0.3))
    omega = np.array([[1.0, 2.0, 3.0], [0.0, -1.0, 4.0]])
    assert_allclose(
        tb.angular_momentum(mp, omega), [tb.angular_momentum(mp, w) for w in omega], rtol=1e-15
    )
    assert_allclose(
        tb.kinetic_energy(mp, omega), [tb.kinetic_energy(mp, w) for w in omega], rtol=1e-15
    )
    assert_allclose(
        tb.required_torque(mp, omega, [0, 0, 1.0]),
        [tb.required_torque(mp, w, [0, 0, 1.0]) for w in omega],
        rtol=1e-15,
    )


# ------------------------------------------------------- the rotating skew rod
@pytest.mark.parametrize("alpha", [0.0, 0.2, np.pi / 6, np.pi / 4, 1.3, np.pi / 2])
def test_skew_rod_angular_momentum_and_torque(alpha: float) -> None:
    # Lecture notes §1: masses m at ±ℓ on a massless rod at angle α to the plane
    # perpendicular to ω (ω along z): |L| = 2mℓ²ω cos α, its horizontal part
    # L_h = 2mℓ²ω sin α cos α, and the torque to keep ω constant |τ| = ω L_h.
    m, ell, omega = 0.3, 0.25, 12.0
    u = np.array([np.cos(alpha), 0.0, np.sin(alpha)])
    rod = tb.point_masses([m, m], [ell * u, -ell * u])
    w = np.array([0.0, 0.0, omega])
    L = tb.angular_momentum(rod, w)
    scale = 2 * m * ell**2 * omega  # round-off of products of O(1) factors: 1e-14 of it
    assert np.linalg.norm(L) == pytest.approx(
        2 * m * ell**2 * omega * np.cos(alpha), abs=1e-14 * scale
    )
    assert np.hypot(L[0], L[1]) == pytest.approx(
        2 * m * ell**2 * omega * np.sin(alpha) * np.cos(alpha), abs=1e-14 * scale
    )
    # L lies in the plane of the rod and ω, perpendicular to the rod.
    assert L @ u == pytest.approx(0.0, abs=1e-14 * scale)
    tau = tb.required_torque(rod, w, [0, 0, 0])
    assert np.linalg.norm(tau) == pytest.approx(
        2 * m * ell**2 * omega**2 * np.sin(alpha) * np.cos(alpha), abs=1e-14 * scale * omega
    )
    # The torque is horizontal and perpendicular to the rod's plane: it turns L_h round.
    assert tau[2] == pytest.approx(0.0, abs=1e-14 * scale * omega)
    assert tau[0] == pytest.approx(0.0, abs=1e-14 * scale * omega)


def test_skew_rod_accepts_units() -> None:
    rod = tb.point_masses(["300 g", "300 g"], ["0, 0, 25 cm", "0, 0, -25 cm"]).transformed(
        Rotation.from_euler("y", 60, degrees=True)
    )
    tau = tb.required_torque(rod, [0, 0, "3000 rpm"], [0, 0, 0])
    omega = 3000 * 2 * np.pi / 60
    # rod at 60° from z, i.e. α = 30° to the horizontal plane
    expected = 2 * 0.3 * 0.25**2 * omega**2 * np.sin(np.pi / 6) * np.cos(np.pi / 6)
    assert np.linalg.norm(tau) == pytest.approx(expected, rel=1e-12)


# ----------------------------------------------- torque as dL/dt in space axes
def test_required_torque_is_the_rate_of_change_of_space_angular_momentum() -> None:
    # Prescribe ω(t) = ω0 + ω̇ t in body axes, integrate the attitude dR/dt = R [ω]×
    # to 1e-13, and differentiate L_space = R I ω numerically: R(0)ᵀ dL/dt at t = 0
    # must equal I ω̇ + ω × I ω. Central differences with h = 1e-3 have a truncation
    # error h²/6 |L'''| ≈ 1e-6 relative here; we allow 1e-5.
    mp = tb.MassProperties(
        1.3, [0, 0, 0], [[0.6, -0.05, 0.02], [-0.05, 0.9, 0.04], [0.02, 0.04, 1.2]]
    )
    omega0 = np.array([0.7, -1.1, 2.0])
    omega_dot = np.array([0.3, 0.5, -0.8])

    def attitude(t_end: float) -> np.ndarray:
        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            matrix = y.reshape(3, 3)
            w = omega0 + omega_dot * t
            skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
            return (matrix @ skew).ravel()

        sol = solve_ivp(
            rhs, (0.0, t_end), np.eye(3).ravel(), method="DOP853", rtol=1e-13, atol=1e-15
        )
        return sol.y[:, -1].reshape(3, 3)

    def space_momentum(t: float) -> np.ndarray:
        return attitude(t) @ mp.inertia @ (omega0 + omega_dot * t)

    h = 1e-3
    derivative = (space_momentum(h) - space_momentum(-h)) / (2 * h)
    expected = tb.required_torque(mp, omega0, omega_dot)
    assert_allclose(derivative, expected, rtol=1e-5, atol=1e-5 * np.linalg.norm(expected))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda mp: tb.angular_momentum(mp, [1.0, 2.0]),
            r"Expected `omega` to have shape \(3,\), got \(2,\)",
        ),
        (
            lambda mp: tb.angular_momentum(mp, "1, 2, 3 kg"),
            r"Expected `omega` to be an angular velocity in rad/s, got",
        ),
        (
            lambda mp: tb.angular_momentum("box", [1, 2, 3]),
            r"Expected `mp` to be a MassProperties, got str",
        ),
        (lambda mp: tb.kinetic_energy(mp, [1.0, np.nan, 0]), r"Expected `omega` to be finite"),
        (
            lambda mp: tb.required_torque(mp, [1, 2, 3], "1, 2, 3 rad/s"),
            r"Expected `omega_dot` to be an angular acceleration in rad/s\^2, got",
        ),
        (
            lambda mp: tb.angular_momentum(mp, [1, 2, 3], about=[0, 0]),
            r"Expected `about` to have shape \(3,\)",
        ),
    ],
)
def test_kinematics_reject_bad_input(call: object, message: str) -> None:
    mp = tb.shapes.box(1.0, (1, 2, 3))
    with pytest.raises(tb.InputError, match=message):
        call(mp)  # type: ignore[operator]


def test_stacks_of_different_lengths_are_an_error() -> None:
    mp = tb.shapes.box(1.0, (1, 2, 3))
    with pytest.raises(
        tb.InputError,
        match=r"Expected `omega_dot` to have the shape of `omega` \(2, 3\) \(or \(3,\)\), got \(3, 3\)",
    ):
        tb.required_torque(mp, np.ones((2, 3)), np.zeros((3, 3)))
