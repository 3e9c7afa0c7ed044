"""Loads of a rotor speeding up under gravity, and of a body on a pivot, against
engmech's verified benchmarks and the particles' own accelerations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb

G = 9.80665


def test_engmechs_unbalanced_rotor_speeding_up_under_gravity() -> None:
    # engmech 0.7.0, benchmarks/v08-unbalanced-rotor.yaml (checked there against a
    # hand derivation): a light shaft along x in a ball bearing at A (0, 0, 0) and a
    # radial bearing at B (0.6, 0, 0), 100 rad/s speeding up at 200 rad/s², m1 =
    # 0.2 kg at (0.2, 0.05, 0), m2 = 0.3 kg at (0.45, 0, 0.04), gravity −z.
    rotor = tb.point_masses([0.2, 0.3], [[0.2, 0.05, 0.0], [0.45, 0.0, 0.04]])
    loads = tb.theory.rotor_loads(rotor, 100.0, axis=(1, 0, 0), bearings=(0.0, 0.6),
                                  omega_dot=200.0, gravity=(0, 0, -G))  # fmt: skip
    # engmech states its values to 1e-5 relative (0.001 %).
    assert loads.drive_torque == pytest.approx(0.2940665, rel=1e-5)
    assert_allclose(
        loads.bearing_forces[0], [0.0, -67.26666667, -26.62361458], rtol=1e-5, atol=1e-9
    )
    assert_allclose(loads.bearing_forces[1], [0.0, -35.13333333, -86.47306042], rtol=1e-5)


def test_engmechs_precessing_gyroscope_on_a_ball_joint() -> None:
    # engmech 0.7.0, examples/gyroscope.yaml: a 2 kg disk of radius 100 mm spinning at
    # 150 rad/s about a horizontal shaft along x, its centre 150 mm from a ball joint,
    # precessing at Ω = 2 g l / (r² ω_s): R = (−m Ω² l, 0, m g), no moment.
    disk = tb.shapes.thin_disk(2.0, 0.1).transformed(
        rotation=Rotation.from_rotvec([0, math.pi / 2, 0]), translation=[0.15, 0, 0]
    )
    precession = 2 * G * 0.15 / (0.1**2 * 150.0)
    loads = tb.theory.pivot_loads(disk, [150.0, 0, precession], [0, precession * 150.0, 0],
                                  gravity=[0, 0, -G])  # fmt: skip
    # engmech prints −1.154046 for −m Ω² l = −1.15404461: 1.2e-6 from it, hence 2e-6.
    assert_allclose(loads.force, [-1.154046, 0.0, 19.6133], rtol=2e-6, atol=1e-12)
    assert loads.force[0] == pytest.approx(-2.0 * precession**2 * 0.15, rel=1e-14)
    # The moment balances to round-off of the gyroscopic terms (I_s ω_s Ω ~ 1.5 N·m).
    assert_allclose(loads.torque, 0.0, atol=1e-13)


def particle_loads(masses, positions, omega, omega_dot, gravity):  # type: ignore[no-untyped-def]
    """The support's force and moment about the origin from each particle's own
    acceleration a_i = ω̇ × r_i + ω × (ω × r_i): no inertia tensor involved."""
    force, moment = np.zeros(3), np.zeros(3)
    for m, r in zip(masses, positions, strict=True):
        a = np.cross(omega_dot, r) + np.cross(omega, np.cross(omega, r))
        force += m * a - m * gravity
        moment += np.cross(r, m * a - m * gravity)
    return force, moment


@pytest.mark.parametrize("seed", range(5))
def test_pivot_loads_equal_the_sum_over_particles(seed: int) -> None:
    rng = np.random.default_rng(seed)
    masses = rng.uniform(0.1, 2.0, 5)
    positions = rng.normal(size=(5, 3))
    omega, omega_dot, gravity = rng.normal(size=(3, 3)) * [[10], [50], [9.8]]
    body = tb.point_masses(masses, positions)
    loads = tb.theory.pivot_loads(body, omega, omega_dot, gravity=gravity)
    force, moment = particle_loads(masses, positions, omega, omega_dot, gravity)
    # Sums of a few products of O(100) numbers: round-off near 1e-13 of the largest.
    assert_allclose(loads.force, force, rtol=1e-12, atol=1e-11)
    assert_allclose(loads.torque, moment, rtol=1e-12, atol=1e-11)
    # About another pivot: the moment shifts by the lever of the force.
    pivot = rng.normal(size=3)
    shifted = tb.theory.pivot_loads(body, omega, omega_dot, pivot=pivot, gravity=gravity)
    force, moment = particle_loads(masses, positions - pivot, omega, omega_dot, gravity)
    assert_allclose(shifted.torque, moment, rtol=1e-12, atol=1e-11)


@pytest.mark.parametrize("seed", range(5))
def test_bearing_forces_and_drive_make_up_the_particles_loads(seed: int) -> None:
    rng = np.random.default_rng(10 + seed)
    masses = rng.uniform(0.1, 2.0, 4)
    positions = rng.normal(size=(4, 3))
    axis = rng.normal(size=3)
    n = axis / np.linalg.norm(axis)
    w, w_dot, gravity = 30.0, -80.0, rng.normal(size=3) * 9.8
    body = tb.point_masses(masses, positions)
    loads = tb.theory.rotor_loads(body, w, axis=axis, bearings=(-0.3, 0.5), omega_dot=w_dot,
                                  gravity=gravity)  # fmt: skip
    force, moment = particle_loads(masses, positions, w * n, w_dot * n, gravity)
    a, b = loads.bearing_forces
    assert_allclose(a + b, force, rtol=1e-12, atol=1e-10)
    assert abs(b @ n) < 1e-10 * np.abs(force).max()  # the second bearing is radial
    supplied = np.cross(-0.3 * n, a) + np.cross(0.5 * n, b) + loads.drive_torque * n
    assert_allclose(supplied, moment, rtol=1e-12, atol=1e-10)


def test_the_defaults_give_the_loads_of_a_steady_rotation() -> None:
    # Without ω̇ and gravity: F = m ω × (ω × r_c), τ = ω × I ω, no drive, radial bearings.
    body = tb.shapes.box(3.0, (0.2, 0.3, 0.5)).transformed(
        rotation=Rotation.from_rotvec([0.1, 0.2, 0.0]), translation=[0.01, -0.02, 0.0]
    )
    loads = tb.theory.rotor_loads(body, 50.0, bearings=(0.2, -0.2))
    w = np.array([0.0, 0.0, 50.0])
    assert loads.drive_torque == 0.0 and loads.omega_dot == 0.0
    assert_allclose(loads.torque, np.cross(w, body.inertia_about([0, 0, 0]) @ w))
    assert_allclose(loads.force, 3.0 * np.cross(w, np.cross(w, body.center_of_mass)))
    assert_allclose(loads.bearing_forces[:, 2], 0.0, atol=1e-12)


def test_refusals() -> None:
    body = tb.shapes.solid_sphere(1.0, 0.1)
    with pytest.raises(tb.InputError, match=r"`omega_dot`"):
        tb.theory.rotor_loads(body, 10.0, omega_dot="3 m")
    with pytest.raises(tb.InputError, match=r"`gravity`"):
        tb.theory.rotor_loads(body, 10.0, gravity=(0, -9.8))
    with pytest.raises(tb.InputError, match=r"`omega`"):
        tb.theory.pivot_loads(body, [1, 2], [0, 0, 0])
