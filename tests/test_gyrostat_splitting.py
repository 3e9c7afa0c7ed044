"""The splittings of a body whose rotors lie on one principal axis of the
platform: the turn about the rotors' momentum folded into the turns about that
axis, the turns about H made once a step when nothing drives the rotors, and
the kicks of idle rotors left out (:func:`tumble.core.parts.gyrostat_flow`)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.body import BodyBatch
from tumble.core.parts import along_principal_axis, momentum_axis
from tumble.errors import IntegrationError
from tumble.parts import KaneDamper, Rotor, pack_parts

#: Locked moments about the centre of mass (kg·m²), distinct.
BODY = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0]))
OMEGA0 = [0.2, -0.1, 0.7]


def layout_of(*parts):  # type: ignore[no-untyped-def]
    bodies = BodyBatch.from_inertia(np.tile([4.0, 5.5, 8.0], (3, 1)))
    return pack_parts(bodies, parts)[0]


@pytest.mark.parametrize(
    ("axis", "index"), [((1, 0, 0), 0), ((0, 1, 0), 1), ((0, 0, 1), 2), ((0, 0, -1), 2)]
)
def test_rotors_on_one_principal_axis_are_marked_with_it(axis, index) -> None:
    layout = layout_of(Rotor(axis, 0.5), Rotor(axis, 0.1))
    assert momentum_axis(layout) == index
    assert all(equations.idle for equations, _, _ in layout)


@pytest.mark.parametrize(
    "parts",
    [
        (Rotor((0, 0.6, 0.8), 0.5),),  # off every principal axis
        (Rotor((1e-12, 1, 0), 0.5),),  # off it by any amount
        (Rotor((1, 0, 0), 0.5), Rotor((0, 1, 0), 0.5)),  # on two axes
        (Rotor((1, 0, 0), 0.5), KaneDamper(0.05, 0.02)),  # a damper's momentum moves
    ],
)
def test_other_parts_take_the_general_splitting(parts) -> None:
    assert momentum_axis(layout_of(*parts)) is None


def test_bodies_whose_rotors_lie_on_different_axes_take_the_general_splitting() -> None:
    # Two bodies of a batch, the rotor on axis 1 of one and axis 2 of the other.
    packed = np.zeros((11, 2))
    packed[0, 0] = packed[1, 1] = 1.0
    rotor_layout = layout_of(Rotor((1, 0, 0), 0.5))
    general = tuple((e._replace(principal_axis=None), size, rows) for e, size, rows in rotor_layout)
    assert momentum_axis(along_principal_axis(general, packed)) is None
    packed[1, 1], packed[0, 1] = 0.0, -1.0  # both on axis 1, one reversed
    assert momentum_axis(along_principal_axis(general, packed)) == 0


def test_a_rotor_with_a_motor_is_not_idle() -> None:
    layout = layout_of(Rotor((0, 1, 0), 0.5, torque=0.01))
    assert momentum_axis(layout) == 1
    assert not layout[0][0].idle


def run(axis, method, dt, duration=20.0, torque=None, body=BODY, speed=5.0, omega0=OMEGA0):  # type: ignore[no-untyped-def]
    return tb.simulate(body, omega0, duration=duration, dt=dt, method=method, torque=torque,
                       record_every=round(duration / dt), internal=[Rotor(axis, 0.2, speed=speed)])  # fmt: skip


def angle_between(a, b) -> float:  # type: ignore[no-untyped-def]
    turn = Rotation.from_quat(a.quaternion, scalar_first=True).inv() * Rotation.from_quat(
        b.quaternion, scalar_first=True
    )
    return float(np.max(turn.magnitude()))


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1)])
@pytest.mark.parametrize(("method", "order"), [("strang", 2), ("splitting", 4)])
def test_the_turns_about_the_rotor_axis_converge_at_the_method_s_order(axis, method, order):
    # Against the gyrostat's closed form over 20 s (~3 periods of ω): halving dt
    # divides the error by 2^order. The errors here (5e-6 to 3e-11) are above
    # the closed form's 1e-11 of |H| and round-off, which could move the
    # smallest ratio by some 5 %: within 5 % of 2^order (measured: within 0.4 %).
    exact = run(axis, "exact", 20.0)
    assert exact.method == "exact"
    errors = []
    for dt in (0.02, 0.01):
        stepped = run(axis, method, dt)
        assert momentum_axis(stepped.body.layout) == int(np.argmax(np.abs(axis)))  # folded
        errors.append(
            max(float(np.max(np.abs(stepped.omega - exact.omega))), angle_between(stepped, exact))
        )
    assert errors[1] < 1e-4
    assert errors[0] / errors[1] == pytest.approx(2.0**order, rel=0.05)


@pytest.mark.parametrize("method", ["strang", "splitting"])
def test_a_symmetric_gyrostat_moves_exactly_whatever_the_step(method) -> None:
    # Moments (2, 2, 4) with the rotor on the symmetry axis 3: the free motion is
    # a steady precession, and the turns about axis 3 and about H are exact, the
    # middle turn's coefficient 1/I1 − 1/I2 zero. At dt = 0.5 s (a quarter
    # turn of ω a step) the steps agree with the closed form to round-off over
    # 40 steps: 1e-12.
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([2.0, 2.0, 4.0]))
    exact = run((0, 0, 1), "exact", 20.0, body=body)
    with pytest.warns(tb.CoarseStepWarning):  # 5 steps a turn: the warning says so
        stepped = run((0, 0, 1), method, 0.5, body=body)
    assert np.max(np.abs(stepped.omega - exact.omega)) < 1e-12
    assert angle_between(stepped, exact) < 1e-12


@pytest.mark.parametrize("axis", [(0, 1, 0), (0, 0, 1)])
def test_momentum_and_its_length_are_kept_to_round_off(axis) -> None:
    # Every turn keeps |H| and H in space: after 2000 steps both within 2000
    # roundings of ε |H| (measured: 8e-15 |H|).
    stepped = tb.simulate(BODY, OMEGA0, duration=20.0, dt=0.01, method="splitting",
                          internal=[Rotor(axis, 0.2, speed=5.0)])  # fmt: skip
    space = stepped.angular_momentum
    size = np.linalg.norm(space[0])
    assert np.max(np.abs(space - space[0])) < 2000 * 2.2e-16 * size
    lengths = np.linalg.norm(stepped.body_momentum, axis=1)
    assert np.max(np.abs(lengths - size)) < 2000 * 2.2e-16 * size


@pytest.mark.parametrize("method", ["strang", "splitting"])
@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0.6, 0.8)])
def test_the_turns_about_h_made_once_a_step_are_the_same_map(axis, method) -> None:
    # Torque-free, the turns about H are made once after a step's sub-steps;
    # under a torque of exactly zero (a torque all the same) each sub-step makes
    # its own. The two maps are the same: they agree to round-off after 2000
    # steps (1e-12; measured 2.5e-14).
    free = run(axis, method, 0.01)
    zero = run(axis, method, 0.01, torque=tb.torques.ConstantBodyTorque([0.0, 0.0, 0.0]))
    assert np.max(np.abs(free.omega - zero.omega)) < 1e-12
    assert angle_between(free, zero) < 1e-12


@pytest.mark.parametrize("axis", [(0, 1, 0), (0, 0, 1)])
def test_a_rotor_turning_past_the_largest_angle_is_refused(axis) -> None:
    # H = 0 (the platform turns against a rotor of J Ω = 2e15 kg·m²/s), so the
    # turn about H bounds nothing; the turn about the rotor's axis, at
    # b = J (a·ω + Ω) / I_p ~ 7e14 rad/s, would be 2e14 rad in a step, beyond the
    # 2^45 the sines are accurate for: the step does not stay finite.
    speed = 1e16
    spin = -0.2 * speed / (3.0 if axis[1] else 4.0)  # H = I_locked ω + J Ω a = 0
    omega0 = np.array(axis, dtype=float) * spin
    with (
        pytest.raises(IntegrationError, match=r"stay finite, got NaN or inf at step 1"),
        pytest.warns(tb.CoarseStepWarning),
    ):
        tb.simulate(BODY, omega0, duration=1.0, dt=1.0, method="strang",
                    internal=[Rotor(axis, 0.2, speed=speed)])  # fmt: skip


@pytest.mark.parametrize("method", ["strang", "splitting"])
def test_idle_rotors_take_a_torque_through_the_rotors(method) -> None:
    # A rotor without a motor is idle, but a torque through the rotors
    # (actuator="rotors") still drives it: the splittings keep its kicks. The
    # rotor on axis 3 is spun by −0.01 N·m (the body by +0.01) for 10 s, its
    # speed changing by some 0.5 rad/s; without its kicks it would not change,
    # and ω would differ by ~0.05 rad/s. Against RK4 at the same step (its own
    # error ~1e-10), within the splitting's error: 1e-4 rad/s (measured: Strang
    # 1.7e-6, Yoshida 4e-11).
    drive = tb.torques.ConstantBodyTorque([0.0, 0.0, 0.01], actuator="rotors")
    runs = [
        tb.simulate(
            BODY,
            OMEGA0,
            duration=10.0,
            dt=0.01,
            method=name,
            torque=drive,
            record_every=1000,
            internal=[Rotor((0, 0, 1), 0.2, speed=5.0)],
        )
        for name in (method, "rk4")
    ]
    assert runs[0].body.layout[0][0].idle
    gained = runs[0].rotor_speed[-1, 0] - runs[0].rotor_speed[0, 0]
    assert abs(gained) > 0.1
    assert np.max(np.abs(runs[0].rotor_speed - runs[1].rotor_speed)) < 1e-4
    assert np.max(np.abs(runs[0].omega - runs[1].omega)) < 1e-4
