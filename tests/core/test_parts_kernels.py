"""The kernels of bodies carrying parts on small cases worked by hand (also run
with NUMBA_DISABLE_JIT=1, so the kernels run as Python)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tumble.core import parts
from tumble.core._jit import FINITE, file_stamp, njit
from tumble.core.dampers import DAMPER_EQUATIONS
from tumble.core.parts import part_model
from tumble.core.rotor import ROTOR_EQUATIONS
from tumble.core.torques import combine, constant_body_torque

FREE = combine(())
#: A body torque in rows 0-2, acting on the body or asked of the rotors.
PUSH = combine([(constant_body_torque, 0)])


#: A Kane damper in a layout: its equations, 3 state entries, 2 rows.
DAMPER = (DAMPER_EQUATIONS, 3, 2)


def rotor(n_schedule=1):  # type: ignore[no-untyped-def]
    """A rotor in a layout: its equations, 1 state entry, 9 + 2 n rows."""
    return (ROTOR_EQUATIONS, 1, 9 + 2 * n_schedule)


def rotor_rows(axis, inertia, times=(0.0,), torques=(0.0,), max_torque=math.inf,
               max_speed=math.inf, allocation=(0.0, 0.0, 0.0)):  # fmt: skip
    return [*axis, inertia, max_torque, max_speed, *allocation, *times, *torques]


def rates(layout, y, moments, packed, torque=FREE, drive=FREE, params=None, t=0.0):
    params = np.zeros((3, 1)) if params is None else params
    system = (moments, 1.0 / moments, packed, 0, params, 0, 0.0)
    dy = np.empty_like(y)
    model = part_model(layout)
    parts.part_rates(torque, drive, model.velocity, model.rates, t, t, y, dy, system)
    return dy


def test_rates_of_a_rotor_and_a_damper_worked_by_hand() -> None:
    # Platform moments (1, 2, 3); a rotor along 3 (J = 0.5, h = 2, motor 0.1 N·m)
    # and a damper (J = 0.2, D = 0.4, σ = (0.1, 0, 0)). H = (1, 2, 3):
    # ω = (H − h a − σ) / p = (0.9, 1.0, 1/3).
    layout = (rotor(), DAMPER)
    moments = np.array([1.0, 2.0, 3.0])
    packed = np.array([*rotor_rows((0, 0, 1), 0.5, torques=(0.1,)), 0.2, 0.4])[:, None]
    y = np.array([1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.1, 0.0, 0.0])
    w = np.array([0.9, 1.0, 1.0 / 3.0])
    assert_allclose(part_model(layout).velocity(y, 1.0 / moments, packed, 0), w, rtol=1e-15)
    dy = rates(layout, y, moments, packed)
    h = y[:3]
    assert_allclose(dy[:3], -np.cross(w, h), rtol=1e-15)  # Ḣ = −ω × H
    assert_allclose(dy[3:7], 0.5 * np.array([0.0, *w]), rtol=1e-15)  # q̇ at q = 1
    assert dy[7] == 0.1  # ḣ = u
    sigma = y[8:11]
    expected = 0.4 * (w - sigma / 0.2) - np.cross(w, sigma)
    assert_allclose(dy[8:11], expected, rtol=1e-15)


def test_a_torque_asked_of_the_rotors_is_shared_out_and_clipped() -> None:
    # Two rotors along x and y with allocation rows (1, 0, 0), (0, 1, 0): a body
    # torque v = (0.3, −0.5, 0) asks u = −v of them; the second is clipped to 0.4.
    layout = (rotor(), rotor())
    moments = np.array([1.0, 1.0, 1.0])
    packed = np.array(
        [*rotor_rows((1, 0, 0), 0.1, allocation=(1, 0, 0)),
         *rotor_rows((0, 1, 0), 0.1, allocation=(0, 1, 0), max_torque=0.4)]
    )[:, None]  # fmt: skip
    y = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    params = np.array([[0.3, -0.5, 0.0]]).T.copy()
    dy = rates(layout, y, moments, packed, drive=PUSH, params=params)
    assert_allclose(dy[7:], [-0.3, 0.4])
    assert_allclose(dy[:3], 0.0)  # the rotors' torques are internal: Ḣ = 0


def test_a_rotor_at_its_largest_speed_gets_no_more_torque() -> None:
    layout = (rotor(),)
    moments = np.array([1.0, 1.0, 1.0])
    packed = np.array(rotor_rows((0, 0, 1), 0.5, torques=(0.2,), max_speed=10.0))[:, None]
    # h = J (a·ω + Ω) with ω = 0 (H = h a): Ω = h / J.
    at_limit = np.array([0.0, 0.0, 5.0, 1.0, 0.0, 0.0, 0.0, 5.0])
    below = np.array([0.0, 0.0, 4.0, 1.0, 0.0, 0.0, 0.0, 4.0])
    assert rates(layout, at_limit, moments, packed)[7] == 0.0
    assert rates(layout, below, moments, packed)[7] == 0.2


def test_the_schedule_is_read_at_the_hold_time() -> None:
    layout = (rotor(2),)
    moments = np.array([1.0, 1.0, 1.0])
    packed = np.array(rotor_rows((0, 0, 1), 0.5, times=(0.0, 1.0), torques=(0.2, -0.1)))[:, None]
    y = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    assert [rates(layout, y, moments, packed, t=t)[7] for t in (0.0, 0.999, 1.0, 5.0)] == [
        0.2, 0.2, -0.1, -0.1,
    ]  # fmt: skip


def run_steps(step, layout, y, moments, packed, dt, n):
    # The kernel's key names the step and the layout (single_kernel adds them) and
    # the torque: FREE, of this file. The same in every process, so that numba's
    # cache serves the next run of the tests.
    run = parts.single_kernel(step, FREE, FREE, layout, f"{file_stamp(run_steps)}|free")
    out = np.empty((n + 1, y.size))
    out[0] = y
    params = np.zeros((3, 1))
    return run(y, moments, packed, params, 0.0, dt, n, 0, 1, out), out


def test_rk4_and_the_splitting_spin_a_rotor_up_exactly() -> None:
    # A rotor on principal axis 3 of a body at rest, u = 0.1 N·m: h = u t, H = 0,
    # the body turning the other way about axis 3 at ω3 = −u t / p3, by the angle
    # −u t² / (2 p3): the splittings by the midpoint rule, exact for a linear ω3;
    # RK4 on q̇ = ½ q ⊗ (0, ω(t)) with an error ~(ω3 dt)⁵ a step: 1e-10.
    layout = (rotor(),)
    moments = np.array([2.0, 3.0, 4.0])
    packed = np.array(rotor_rows((0, 0, 1), 0.5, torques=(0.1,)))[:, None]
    for step, tolerance in (
        (parts.parts_rk4_step, 1e-10), (parts.strang_step, 1e-14), (parts.yoshida_step, 1e-14)
    ):  # fmt: skip
        y = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
        status, out = run_steps(step, layout, y, moments, packed, 0.1, 50)
        assert status == FINITE
        assert_allclose(out[:, 7], 0.1 * 0.1 * np.arange(51), rtol=1e-14, atol=1e-16)
        assert_allclose(out[:, :3], 0.0, atol=1e-17)
        angle = 2 * np.arctan2(out[-1, 6], out[-1, 3])
        assert angle == pytest.approx(-0.1 * 5.0**2 / (2 * 4.0), rel=tolerance)


def test_the_splitting_turns_h_about_the_rotor_axis_and_keeps_its_length() -> None:
    # A free gyrostat: each stage of the splitting is a rotation, so |H| stays
    # to round-off over many steps of an asymmetric body.
    layout = (rotor(),)
    moments = np.array([2.0, 3.0, 4.0])
    axis = np.array([0.6, 0.0, 0.8])
    packed = np.array(rotor_rows(axis, 0.3))[:, None]
    y = np.array([0.5, -1.0, 2.0, 1.0, 0.0, 0.0, 0.0, 3.0])
    status, out = run_steps(parts.yoshida_step, layout, y, moments, packed, 0.05, 2000)
    assert status == FINITE
    size = np.linalg.norm(out[:, :3], axis=1)
    assert np.max(np.abs(size - size[0])) < 1e-13
    assert np.all(out[:, 7] == 3.0)  # the rotor's momentum only changes in kicks


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning")  # NaN, as plain Python
def test_a_state_that_blows_up_is_reported_with_its_step() -> None:
    layout = (rotor(),)
    moments = np.array([1.0, 1.0, 1.0])
    packed = np.array(rotor_rows((0, 0, 1), 0.5, torques=(math.inf,)))[:, None]
    y = np.array([0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    status, _ = run_steps(parts.parts_rk4_step, layout, y, moments, packed, 0.1, 5)
    assert status == 1
    assert_allclose(y, [0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])  # left as before the step


@njit(inline="always")
def _doubled_momentum(y, k, parts, row, rows, pc):  # type: ignore[no-untyped-def]
    h = 2.0 * y[k]
    return h * parts[row, pc], h * parts[row + 1, pc], h * parts[row + 2, pc]


def test_kinds_that_share_their_rates_compile_apart() -> None:
    # A kind with the rotor's rates but its own momentum: the kernels' cache keys
    # name every function of a kind, so it never gets the rotor's compiled code.
    doubled = ROTOR_EQUATIONS._replace(momentum=_doubled_momentum)
    rotor_layout, doubled_layout = (rotor(),), ((doubled, 1, 11),)
    assert parts.layout_identity(rotor_layout) != parts.layout_identity(doubled_layout)
    # H = (0, 0, 3), h = 1 along axis 3, moments (1, 1, 2): ω3 = (3 − h) / 2 for
    # the rotor, (3 − 2 h) / 2 for the kind that counts its momentum twice.
    states = np.array([[0.0, 0.0, 3.0, 1.0, 0.0, 0.0, 0.0, 1.0]]).T.copy()
    moments = np.array([[1.0, 1.0, 2.0]]).T.copy()
    packed = np.array(rotor_rows((0, 0, 1), 0.5))[:, None]
    assert parts.velocities(rotor_layout)(states, moments, packed)[0, 2] == 1.0
    assert parts.velocities(doubled_layout)(states, moments, packed)[0, 2] == 0.5
