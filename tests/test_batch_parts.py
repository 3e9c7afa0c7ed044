"""simulate_batch(internal=...): bodies carrying rotors and Kane dampers in a
batch move as separate simulate() calls do, and the dual-spin condition holds
body by body; every error has its message."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.errors import IntegrationError
from tumble.parts import KaneDamper, Rotor, SpringMassDamper

N = 5
RNG = np.random.default_rng(11)
TURNS = Rotation.random(N, random_state=3).as_matrix()
SECOND = RNG.uniform(1.0, 2.5, (N, 3))  # ∫x², ∫y², ∫z²: always a valid body
MOMENTS = SECOND.sum(axis=1, keepdims=True) - SECOND
# Locked inertia tensors in body axes that are not principal, one per body.
INERTIA = np.einsum("nij,nj,nkj->nik", TURNS, MOMENTS, TURNS)
OMEGA = RNG.normal(size=(N, 3))
ATTITUDE = Rotation.random(N, random_state=4).as_quat(scalar_first=True)
SPEEDS = RNG.uniform(-20.0, 20.0, (N, 2))


def rotors(speeds=(30.0, -10.0)) -> list[Rotor]:
    return [
        Rotor([1.0, 0.2, 0.0], 0.1, speed=speeds[0], torque=[(0.0, 0.01), (0.5, 0.0)]),
        Rotor([0.0, 0.0, 1.0], 0.05, speed=speeds[1]),
    ]


@pytest.mark.parametrize(
    ("method", "damper"), [("rk4", True), ("rk4", False), ("splitting", False), ("strang", False)]
)
def test_a_batch_with_parts_moves_as_separate_simulations(method, damper) -> None:
    # Each body its own locked inertia, attitude and rotor speeds; a motor
    # schedule with a switch at 0.5 s, on a step boundary. The batch kernel runs
    # the same compiled step as simulate() for one body: agreement to round-off
    # after 2000 steps, 1e-13 (rotor speeds ~20 rad/s: 1e-12).
    extra = [KaneDamper(0.1, 0.2)] if damper else []
    batch = tb.simulate_batch(
        INERTIA, OMEGA, attitude0=ATTITUDE, duration=2.0, dt=1e-3, method=method,
        internal=[*rotors(), *extra], rotor_speed=SPEEDS, record_every=500,
    )  # fmt: skip
    assert batch.internal_values.shape == (N, 5 if damper else 2)
    assert batch.internal_history.shape == (5, N, 5 if damper else 2)
    for k in range(N):
        one = tb.simulate(
            tb.MassProperties(10.0, [0, 0, 0], INERTIA[k]), OMEGA[k], attitude0=ATTITUDE[k],
            duration=2.0, dt=1e-3, method=method, internal=[*rotors(SPEEDS[k]), *extra],
            record_every=500,
        )  # fmt: skip
        assert_allclose(batch.omega_history[:, k], one.omega, rtol=0, atol=1e-13)
        assert_allclose(batch.quaternion_history[:, k], one.quaternion, rtol=0, atol=1e-13)
        assert_allclose(batch.internal_history[:, k], one.internal_values, rtol=0, atol=1e-12)
        assert_allclose(batch.rotor_speed[k], one.rotor_speed[-1], rtol=0, atol=1e-12)


# Locked inertia whose principal axes are the body axes, ascending and apart, which
# stays so once the rotors' spin inertia (along x and z) is taken out.
DIAGONAL = np.einsum("ni,ij->nij", np.sort(MOMENTS, axis=1) + np.array([0.0, 0.5, 1.0]), np.eye(3))


@pytest.mark.parametrize(
    "inertia", [DIAGONAL, np.broadcast_to(INERTIA[0], INERTIA.shape)], ids=["diagonal", "same"]
)
def test_bodies_whose_principal_frames_agree_move_as_separate_simulations(inertia) -> None:
    # The batch's shortcuts for them: no turning between body and principal axes
    # when those are the body axes ("diagonal"), one pseudo-inverse of the rotors'
    # axes for every body when all are turned alike ("same"). Agreement as above;
    # the rotors' relative speeds, h / J − a·ω with J = 0.05 kg·m², carry the
    # round-off of h twentyfold: 1e-13 of their ~16 rad/s (measured 7e-14).
    def wheels(speeds):
        return [Rotor([0.0, 0.0, 1.0], 0.1, speed=speeds[0]), Rotor([1.0, 0.0, 0.0], 0.05,
                speed=speeds[1], torque=[(0.0, 0.01), (0.5, 0.0)])]  # fmt: skip

    batch = tb.simulate_batch(
        inertia, OMEGA, attitude0=ATTITUDE, duration=1.0, dt=1e-3, internal=wheels((0, 0)),
        rotor_speed=SPEEDS, record_every=500,
    )  # fmt: skip
    for k in range(N):
        one = tb.simulate(
            tb.MassProperties(10.0, [0, 0, 0], inertia[k]), OMEGA[k], attitude0=ATTITUDE[k],
            duration=1.0, dt=1e-3, internal=wheels(SPEEDS[k]), record_every=500,
        )  # fmt: skip
        assert_allclose(batch.omega_history[:, k], one.omega, rtol=0, atol=1e-13)
        assert_allclose(batch.quaternion_history[:, k], one.quaternion, rtol=0, atol=1e-13)
        assert_allclose(batch.internal_history[:, k], one.internal_values, rtol=1e-13, atol=0)


def test_the_rotor_speed_decides_the_dual_spin_stability_body_by_body() -> None:
    # Locked moments 4 < 6 < 8, spin 1 rad/s about the intermediate axis, a
    # rotor along it (J = 0.5): stable iff (h − (I3 − I2) Ω)(h + (I2 − I1) Ω) > 0
    # with h = J Ω_rel (tumble.theory.gyrostat_stability), i.e. |h| > 2 kg·m²/s
    # here. Relative speeds either side of both thresholds (h = ±2 at ±4 rad/s):
    # over 60 s (the unstable ones grow ~e^0.1 t from a 1 % wobble), the stable
    # bodies keep |(ω1, ω3)| within 10 % of the spin (3 % next to a threshold,
    # h = 2.25), the others pass 30 % (50 % next to one, h = 1.75).
    relative = np.array([[-10.0], [-4.5], [-3.5], [0.0], [3.5], [4.5], [8.0]])
    n = len(relative)
    batch = tb.simulate_batch(
        np.tile([4.0, 6.0, 8.0], (n, 1)), np.tile([0.01, 1.0, 0.0], (n, 1)), duration=60.0,
        dt=0.01, method="splitting", record_every=100, internal=[Rotor([0, 1, 0], 0.5)],
        rotor_speed=relative,
    )  # fmt: skip
    history = batch.omega_history
    wobble = np.hypot(history[:, :, 0], history[:, :, 2]).max(axis=0)
    body = tb.MassProperties(10.0, [0, 0, 0], np.diag([4.0, 6.0, 8.0]))
    verdicts = []
    for k in range(n):
        h = 0.5 * relative[k, 0]
        stable = tb.theory.gyrostat_stability(body, 1.0, h, axis=(0, 1, 0)).stable
        verdicts.append(stable)
        assert (wobble[k] < 0.1) if stable else (wobble[k] > 0.3), (h, wobble[k])
    assert verdicts == [True, True, False, False, False, True, True]


def test_a_batch_with_a_damper_keeps_each_body_s_momentum_and_loses_energy() -> None:
    # The Kane damper's torques are internal: |H| of every body to 1e-10 over
    # 50 s of RK4 at 1 ms (RK4's error in H, ~(ω dt)⁴ per unit time, ~1e-12);
    # the energy falls (each body's, from its parts' values).
    damper = KaneDamper(0.1, 0.5)
    batch = tb.simulate_batch(
        INERTIA, OMEGA, duration=50.0, dt=1e-3, internal=[damper], record_every=5000
    )
    for k in range(N):
        body = tb.body.RigidBody(tb.MassProperties(10.0, [0, 0, 0], INERTIA[k]), parts=(damper,))
        values = batch.internal_history[:, k]
        omega = batch.omega_history[:, k]
        momentum = np.linalg.norm(body.angular_momentum(omega, values), axis=1)
        assert np.max(np.abs(momentum - momentum[0])) < 1e-10 * momentum[0]
        energy = body.kinetic_energy(omega, values)
        assert np.all(np.diff(energy) < 0.0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"internal": [SpringMassDamper(0.1, [0, 0, 0.2], [1, 0, 0], 1.0, 0.1)]},
            r"^Expected parts that simulate_batch takes, got a SpringMassDamper "
            r"\(its mass moves each body's centre of mass: use simulate\)\.$",
        ),
        (
            {"rotor_speed": np.zeros((N, 1))},
            r"^Expected `rotor_speed` with Rotor parts in `internal`, got no parts\.$",
        ),
        (
            {"internal": rotors(), "rotor_speed": np.zeros((N, 3))},
            r"rotor_speed",
        ),
        (
            {"internal": rotors(), "method": "exact"},
            r"^Expected a method that integrates batches carrying rotor parts \(splitting, "
            r"strang, rk4\), got 'exact'\.$",
        ),
        (
            {"internal": [KaneDamper(0.1, 0.1)], "method": "splitting"},
            r"^Expected a method that integrates batches carrying kane-damper parts \(rk4\), "
            r"got 'splitting'\.$",
        ),
        (
            {
                "internal": rotors(),
                "torque": tb.torques.ConstantBodyTorque([0, 0, 1e-3], actuator="rotors"),
            },
            r"^Expected torques that act on the bodies from outside in a batch with parts, got "
            r"ConstantBodyTorque\(.*actuator='rotors'\), which acts through the rotors "
            r"\(use simulate\)\.$",
        ),
        (
            {"internal": [Rotor([0, 0, 1], 50.0)]},
            r"^Expected internal parts whose spin inertia every body can hold .* got body 0 "
            r"with \[.*\] kg·m² left\.$",
        ),
    ],
)
def test_bad_batches_with_parts_are_refused(kwargs, message) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.simulate_batch(INERTIA, OMEGA, duration=1.0, dt=0.1, **kwargs)


def test_a_diverging_batch_with_parts_names_the_body_and_the_step() -> None:
    # RK4 at dt = 1 s on rates of ~60 rad/s: the state overflows in a few steps.
    with pytest.raises(
        IntegrationError,
        match=r"^Expected every body's state to stay finite, got body 0 non-finite at step \d+ "
        r"\(t = [0-9.]+ s\)\.$",
    ):
        tb.simulate_batch([[2.0, 3.0, 4.0]], [[30.0, 50.0, 20.0]], duration=2000.0, dt=1.0,
                          internal=[Rotor([0, 0, 1], 0.1, speed=5.0)])  # fmt: skip
