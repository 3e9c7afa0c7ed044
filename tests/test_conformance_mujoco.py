"""The MuJoCo adapter against MuJoCo itself and against the exact motion."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

import tumble as tb
from conformance_checks import convention_errors, read_back_error
from tumble.conformance.engines.mujoco_engine import MujocoEngine

VARIANTS = list(MujocoEngine.variants)


@pytest.mark.parametrize("variant", VARIANTS)
def test_angular_velocity_is_in_body_axes(variant: str) -> None:
    # The free joint's qvel[3:6] is the local (body) angular velocity: it matches the rate
    # finite-differenced from the attitude over one step of 1e-4 s to O(|ω|² dt) ~ 1e-3
    # (measured 3e-13 to 5e-5), and read as space axes it is 0.8 away.
    declared, other = convention_errors(MujocoEngine(variant))
    assert declared < 2e-3
    assert other > 0.1


@pytest.mark.parametrize("variant", VARIANTS)
def test_mass_and_inertia_read_back(variant: str) -> None:
    # MuJoCo keeps the diaginertia as given, in float64: no error at all.
    mass_error, inertia_error = read_back_error(MujocoEngine(variant))
    assert mass_error < 1e-15 and inertia_error < 1e-15


def test_observed_orders_of_rk4_and_euler() -> None:
    # A dt sweep on intermediate-slow: MuJoCo's RK4 converges at order 4 ± 0.3, its
    # semi-implicit Euler at 1 ± 0.2 (measured 3.99 and 0.99).
    result = tb.conformance.sweep(
        ["mujoco/rk4", "mujoco/euler"], "intermediate-slow", [0.02, 0.01, 0.005, 0.0025], 5.0
    )
    order = result.table.drop_duplicates("engine").set_index("engine")["order"]
    assert order["mujoco/rk4"] == pytest.approx(4.0, abs=0.3)
    assert order["mujoco/euler"] == pytest.approx(1.0, abs=0.2)


def test_euler_gains_and_implicit_loses_energy_on_a_fast_tumble() -> None:
    # Semi-implicit Euler gains energy, the implicit integrators damp the gyroscopic
    # motion (measured over 20 s at 1 ms: +59 %, −31 %, RK4 −2e-10).
    result = tb.conformance.run(["mujoco"], "intermediate-fast", dt=1e-3, duration=20.0)
    drift = result.table.set_index("engine")["energy_drift_final"]
    assert 0.3 < drift["mujoco/euler"] < 0.9
    assert -0.5 < drift["mujoco/implicit"] < -0.15
    assert -0.5 < drift["mujoco/implicitfast"] < -0.15
    assert abs(drift["mujoco/rk4"]) < 1e-8


def test_a_stable_spin_blown_up_by_euler_is_reported_as_mujoco_s_reset() -> None:
    # The major-axis spin gains energy under Euler until it flips (about 27 s) and the
    # accelerations overflow: MuJoCo warns (mjWARN_BADQACC) and resets the state, which
    # the adapter reports (measured at 35.94 s). RK4 keeps it to round-off.
    result = tb.conformance.run(
        ["mujoco/euler", "mujoco/rk4"], "major-spin", dt=1e-3, duration=45.0
    )
    table = result.table.set_index("engine")
    assert 30.0 < table.loc["mujoco/euler", "failed_at"] < 40.0
    assert "mjWARN_BADQACC" in table.loc["mujoco/euler", "failure"]
    assert np.isnan(table.loc["mujoco/rk4", "failed_at"])
    assert table.loc["mujoco/rk4", "flips"] == table.loc["mujoco/rk4", "flips_exact"]


def test_heavy_top_on_a_ball_joint_follows_the_lagrange_top() -> None:
    # The top on a ball joint under gravity against tumble's exact Lagrange top: RK4's
    # error at dt = 1 ms is O(dt⁴) (measured 2e-10 rad over 5 s); Euler's O(dt) (3e-3).
    result = tb.conformance.run(["mujoco/rk4", "mujoco/euler"], "heavy-top", dt=1e-3, duration=5.0)
    table = result.table.set_index("engine")
    assert table.loc["mujoco/rk4", "attitude_error_max"] < 1e-8
    assert 1e-4 < table.loc["mujoco/euler", "attitude_error_max"] < 1e-1
