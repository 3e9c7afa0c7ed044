"""The kernels of bodies carrying parts on small cases worked by hand (also run
with NUMBA_DISABLE_JIT=1, so the kernels run as Python)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tumble.core import part_blocks, part_measures, parts
from tumble.core._jit import FINITE, file_stamp, njit
from tumble.core.dampers import DAMPER_EQUATIONS
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    N_METRICS,
)
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
    velocity, layout_rates = model.velocity, model.rates

    # Through a function of its own, not cached, where part_rates is inlined as in
    # the kernels: called from Python, numba would compile part_rates on its own and
    # add it to its cache's index, whose earlier keys name functions (the layouts')
    # that may have been collected since, and it could not write the index.
    @njit(cache=False)
    def evaluate(t, y, dy, system):  # type: ignore[no-untyped-def]
        parts.part_rates(torque, drive, velocity, layout_rates, t, t, y, dy, system)

    evaluate(t, y, dy, system)
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
        (parts.make_rk4_step, 1e-10), (parts.make_strang_step, 1e-14), (parts.make_yoshida_step, 1e-14)
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
    status, out = run_steps(parts.make_yoshida_step, layout, y, moments, packed, 0.05, 2000)
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
    status, _ = run_steps(parts.make_rk4_step, layout, y, moments, packed, 0.1, 5)
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


def test_a_trajectory_is_read_back_in_body_axes() -> None:
    # H = (0, 0, 3), h = 1 along principal axis 3, moments (1, 1, 2): ω = (0, 0, 1)
    # in the principal frame (worked above), and q = (cos 0.3, 0, 0, sin 0.3).
    layout = (rotor(),)
    c, s = math.cos(0.3), math.sin(0.3)
    states = np.array([[0.0, 0.0, 3.0, c, 0.0, 0.0, s, 1.0]] * 2)
    moments = np.array([1.0, 1.0, 2.0])
    packed = np.array(rotor_rows((0, 0, 1), 0.5))[:, None]
    readout = parts.readout(layout)

    def read(*arguments):  # type: ignore[no-untyped-def]
        omega, quaternion, values = np.empty((2, 3)), np.empty((2, 4)), np.empty((2, 1))
        readout(*arguments, omega, quaternion, values)
        return omega, quaternion, values

    # Principal axes that are the body's: ω and q as they are; the rotor's spin rate
    # relative to the body h / J − a·ω = 1 / 0.5 − 1 = 1 rad/s, in either frame.
    turn = np.array([1.0, 0, 0, 0])
    omega, quaternion, values = read(states, moments, packed, np.eye(3), turn, False)
    assert omega.tolist() == [[0.0, 0.0, 1.0]] * 2
    assert quaternion.tolist() == states[:, 3:7].tolist()
    assert values.tolist() == [[1.0]] * 2
    # Principal axis 3 along body x (axes' columns: body y, body z, body x), a turn of
    # 120° about (1, 1, 1): ω = (1, 0, 0) in body axes, q ⊗ turn⁻¹ as the quaternion.
    axes = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    back = np.array([0.5, -0.5, -0.5, -0.5])  # the conjugate of the principal frame's turn
    omega, quaternion, values = read(states, moments, packed, axes, back, True)
    assert omega.tolist() == [[1.0, 0.0, 0.0]] * 2
    assert values.tolist() == [[1.0]] * 2
    w, x, y, z = c * 0.5 + s * 0.5, -c * 0.5 + s * 0.5, -c * 0.5 - s * 0.5, -c * 0.5 + s * 0.5
    # The product of unit quaternions, renormalised: to round-off, 2 ulp.
    assert_allclose(quaternion, [[w, x, y, z]] * 2, rtol=0, atol=4e-16)


def _batch_states(kernel, y, moments, packed, params, dt, n):
    y = y.copy()
    status = np.full(y.shape[1], FINITE, dtype=np.int64)
    kernel(y, moments, packed, params, 0.0, 0.0, dt, n, status)
    return y, status


def _bodies(n, shared, rng, damper=True):  # type: ignore[no-untyped-def]
    """States (11, n) of bodies carrying a rotor with a motor schedule and a Kane
    damper (without it, (8, n)), their platform moments (3, n) and their parts
    (shared or one column each); body 70 thrown at 1e154 rad/s."""
    y = np.zeros((11 if damper else 8, n))
    y[:3] = rng.normal(size=(3, n))
    y[3:7] = rng.normal(size=(4, n))
    y[3:7] /= np.linalg.norm(y[3:7], axis=0)
    y[7] = rng.uniform(-1.0, 1.0, n)
    y[:3, 70] = 1e154
    moments = rng.uniform(1.0, 3.0, (3, n))
    columns = 1 if shared else n
    packed = np.empty((15 if damper else 13, columns))  # the rotor 9 + 2·2 rows, the damper 2
    for c in range(columns):
        torques = (0.2, -0.1) if shared else (rng.uniform(-0.2, 0.2), 0.05)
        rotor_part = rotor_rows((0.6, 0.0, 0.8), 0.5, times=(0.0, 0.35), torques=torques)
        damper_part = [0.2, rng.uniform(0.1, 0.5)] if damper else []
        packed[:, c] = [*rotor_part, *damper_part]
    return y, moments, packed


#: Each method's blocked step, its one-body step, and the parts it takes: RK4 a
#: rotor and a damper, the splittings (which take parts that kick) a rotor.
METHODS = {
    "rk4": (part_blocks.rk4_body_step, parts.make_rk4_step, True),
    "strang": (part_blocks.strang_body_step, parts.make_strang_step, False),
    "yoshida": (part_blocks.yoshida_body_step, parts.make_yoshida_step, False),
}


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning")  # NaN, as plain Python
@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("shared", [True, False])
def test_the_blocked_batch_steps_each_body_as_its_own_kernel(method, shared) -> None:
    # 150 bodies (two whole blocks and a part of one) carrying a rotor with a motor
    # schedule (and, for RK4, a Kane damper), under a body torque with one column
    # per body; their parts shared or one column each. The blocked kernel against
    # the kernel that steps one body per thread (the step of simulate()): the same
    # operations, with the compiler free to contract and reorder them across the
    # block, and, for the splittings, the vectorised sines where one body turns by
    # the C library's (both within 2 ulp of the true values). Every operation is a
    # rotation or a sum of bounded terms, so the differences, of order ε on
    # states of order 1, add up over the steps: equal to 1e-14 after 100 steps
    # (measured: 8e-15 for the splittings). Body 70 is thrown at 1e154 rad/s
    # with an unbounded motor: its first step is not finite, in both kernels, at
    # the same step, and it keeps its state before it.
    block_step, one_body_step, damper = METHODS[method]
    layout = (rotor(2), DAMPER) if damper else (rotor(2),)
    n = 150
    rng = np.random.default_rng(7)
    y, moments, packed = _bodies(n, shared, rng, damper)
    params = rng.normal(scale=0.1, size=(3, n))
    identity = f"{file_stamp(test_the_blocked_batch_steps_each_body_as_its_own_kernel)}|push"
    blocked = part_blocks.block_kernel(block_step, PUSH, FREE, layout, identity)
    one_by_one = parts.batch_kernel(one_body_step, PUSH, FREE, layout, identity)
    got, got_status = _batch_states(blocked, y, moments, packed, params, 0.01, 100)
    want, want_status = _batch_states(one_by_one, y, moments, packed, params, 0.01, 100)
    assert got_status[70] == want_status[70] == 1
    assert np.all(np.delete(got_status, 70) == FINITE)
    assert_allclose(got[:, 70], y[:, 70], rtol=0)  # kept as before the step
    assert_allclose(got, want, rtol=0, atol=1e-14)
    assert np.abs(got - y).max() > 0.1  # the bodies moved


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning")  # NaN, as plain Python
@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
@pytest.mark.parametrize("method", METHODS)
def test_the_blocked_measures_are_each_bodys_own(method) -> None:
    # The measures of a sweep (tumble.core.metrics) taken after every step by the
    # blocked kernel against the kernel that steps and measures one body per
    # thread, on the bodies above about random nominal axes over 400 steps, enough
    # for flips: the same counts, the rest to round-off (the times of the first
    # flips, interpolated between two steps of 0.01 s from values of order 1, to
    # 1e-12 s; the others, sums and extremes of values of order 1, to 1e-13). Body
    # 70 fails at its first step in both, its measures those of its start.
    block_step, one_body_step, damper = METHODS[method]
    layout = (rotor(2), DAMPER) if damper else (rotor(2),)
    n = 150
    rng = np.random.default_rng(8)
    y, moments, packed = _bodies(n, False, rng, damper)
    axis = rng.normal(size=(3, n))
    axis /= np.linalg.norm(axis, axis=0)
    params = np.zeros((3, 1))
    identity = f"{file_stamp(test_the_blocked_measures_are_each_bodys_own)}|free"
    results = []
    for kernel in (
        part_blocks.block_measuring_kernel(block_step, FREE, FREE, layout, identity),
        part_measures.measuring_kernel(one_body_step, FREE, FREE, layout, identity),
    ):
        state = y.copy()
        out = np.empty((N_METRICS, n))
        twice = np.empty(n)
        status = np.full(n, FINITE, dtype=np.int64)
        kernel(state, moments, packed, params, 0.0, axis, 0.0, 0.01, 400, out, twice, status)
        results.append((state, out, twice, status))
    (got, got_out, got_twice, got_status), (want, want_out, want_twice, want_status) = results
    assert_allclose(got_status, want_status, rtol=0)
    assert got_status[70] == 1
    assert_allclose(got, want, rtol=0, atol=1e-13)
    assert np.array_equal(got_out[FLIPS], want_out[FLIPS])
    assert got_out[FLIPS].max() >= 2  # some bodies flip
    assert_allclose(got_out[FIRST_FLIP], want_out[FIRST_FLIP], rtol=0, atol=1e-12)
    rest = [MIN_COS, ENERGY_DEVIATION, MOMENTUM_DEVIATION]
    assert_allclose(got_out[rest], want_out[rest], rtol=0, atol=1e-13)
    # Twice the starting energy: body 70's is 1e308, the others of order 1.
    assert_allclose(got_twice, want_twice, rtol=1e-15, atol=1e-13)


@pytest.mark.parametrize("method", ["strang", "yoshida"])
@pytest.mark.parametrize("torque", ["free", "push"])
def test_rotors_on_a_principal_axis_step_in_blocks_as_one_by_one(method, torque) -> None:
    # The splittings' step for rotors on a principal axis (here the intermediate
    # one, the layout marked as tumble.parts.pack_parts marks it, the rotor idle:
    # no motor): the turn about its momentum joined to the axis' turns; torque-
    # free, the turns about H made once a step and the kicks left out; under a
    # body torque, neither. Blocked against one body per thread, as above: equal
    # to 1e-14 after 100 steps (measured: 2.4e-15 to 8.3e-15).
    block_step, one_body_step, _ = METHODS[method]
    layout = ((ROTOR_EQUATIONS._replace(principal_axis=1, idle=True), 1, 11),)
    n = 150
    rng = np.random.default_rng(9)
    y = np.zeros((8, n))
    y[:3] = rng.normal(size=(3, n))
    y[3:7] = rng.normal(size=(4, n))
    y[3:7] /= np.linalg.norm(y[3:7], axis=0)
    y[7] = rng.uniform(-2.0, 2.0, n)
    moments = np.sort(rng.uniform(1.0, 3.0, (3, n)), axis=0)
    packed = np.array(rotor_rows((0.0, 1.0, 0.0), 0.5))[:, None]
    params = rng.normal(scale=0.1, size=(3, n))
    kind = FREE if torque == "free" else PUSH
    name = test_rotors_on_a_principal_axis_step_in_blocks_as_one_by_one
    identity = f"{file_stamp(name)}|{torque}"
    blocked = part_blocks.block_kernel(block_step, kind, FREE, layout, identity)
    one_by_one = parts.batch_kernel(one_body_step, kind, FREE, layout, identity)
    got, got_status = _batch_states(blocked, y, moments, packed, params, 0.01, 100)
    want, want_status = _batch_states(one_by_one, y, moments, packed, params, 0.01, 100)
    assert np.all(got_status == FINITE) and np.all(want_status == FINITE)
    assert_allclose(got, want, rtol=0, atol=1e-14)
    assert np.abs(got - y).max() > 0.1  # the bodies moved
