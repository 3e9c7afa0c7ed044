"""Every registered part kind writes its momentum and energy twice: in numpy, for
the Python side (``InternalPart.momentum``, ``momenta``, ``kinetic_energy``, read by
``RigidBody.angular_momentum`` and ``kinetic_energy``), and compiled, for the kernels
(:class:`tumble.core.parts.PartEquations`: ``momentum``, ``inertia``, ``energy``,
``values``). The tests hold both sides to each other for every kind of the registry:
a body's ω, which the kernels solve from the total momentum the Python side gives,
comes back as it went in, as do the part's values read back from the kernels' state,
and twice the energy the kernels' shares give (ω · H plus them) is twice the Python
side's."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble.body import RigidBody
from tumble.core.parts import part_energy, part_model
from tumble.parts import PARTS

#: One part of each registered kind, on a body that can hold it. A kind registered
#: without an entry here fails the test below: both of its sides must be checked.
EXAMPLES = {
    "rotor": lambda: tb.Rotor([0.2, 0.1, 1.0], 0.05, speed=30.0),
    "kane-damper": lambda: tb.KaneDamper(0.05, 0.02),
    "spring-mass-damper": lambda: tb.SpringMassDamper(0.1, [0.3, 0, 0], [0, 1, 0], 5.0, 0.1),
}

BODY = tb.MassProperties(2.0, [0, 0, 0], [[1.0, 0.05, 0.0], [0.05, 1.5, -0.02], [0.0, -0.02, 2.0]])
OMEGA = np.array([0.3, -0.2, 1.1])


def test_every_registered_kind_has_an_example() -> None:
    assert set(PARTS) <= set(EXAMPLES), f"no example of {sorted(set(PARTS) - set(EXAMPLES))}"


def moved(part: tb.parts.InternalPart) -> np.ndarray:
    """The part moving relative to the body: its values at rest with the body, moved."""
    return np.asarray(part.initial_values(OMEGA) + 0.1 * np.arange(1, part.size + 1))


def kernel_state(body: RigidBody, values: np.ndarray) -> np.ndarray:
    """The kernels' state of the body turning at OMEGA with its part at ``values``:
    the total momentum and the part's momenta (the Python side's), in the
    principal-platform frame the kernels work in."""
    (part,) = body.parts
    return np.concatenate(
        [
            body.to_principal(body.angular_momentum(OMEGA, values)),
            [1.0, 0.0, 0.0, 0.0],
            part.to_kernel(part.momenta(OMEGA, values), body),
        ]
    )


@pytest.mark.parametrize("kind", sorted(EXAMPLES))
def test_a_parts_values_come_back_from_the_kernels_state(kind: str) -> None:
    # Compiled (PartEquations.values) where the kind has them, else in Python.
    body = RigidBody(BODY, parts=(EXAMPLES[kind](),))
    values = moved(body.parts[0])
    omega, quaternion, back = body.from_kernel_state(kernel_state(body, values)[None])
    # Round-off of the 3 × 3 solve for ω and of a momentum less ω's share: 1e-14 of
    # |ω| and of the values.
    assert_allclose(omega[0], OMEGA, rtol=0, atol=1e-14 * np.linalg.norm(OMEGA))
    assert_allclose(back[0], values, rtol=0, atol=1e-14 * np.abs(values).max())
    assert quaternion[0].tolist() == body.attitude_from_principal([1.0, 0, 0, 0]).tolist()


@pytest.mark.parametrize("kind", sorted(EXAMPLES))
def test_the_compiled_and_the_python_physics_of_a_part_agree(kind: str) -> None:
    body = RigidBody(BODY, parts=(EXAMPLES[kind](),))
    values = moved(body.parts[0])
    energy = body.kinetic_energy(OMEGA, values)
    state = kernel_state(body, values)
    packed = np.ascontiguousarray(body.packed_parts)
    velocity = part_model(body.layout).velocity(state, 1.0 / body.moments, packed, 0)
    # The body's ω solved from H less the parts' compiled momentum (and, for a part
    # that moves mass, its compiled inertia): round-off of a 3 × 3 solve, 1e-14 of |ω|.
    assert_allclose(velocity, body.to_principal(OMEGA), rtol=0, atol=1e-14 * np.linalg.norm(OMEGA))
    shares = part_energy(body.layout)
    if shares is None:  # a kind whose energy the kernels do not measure
        assert PARTS[kind].equations.energy is None
        return
    twice = float(np.dot(velocity, state[:3])) + shares(state, packed, 0, velocity)
    # 2E = ω · H + the parts' shares, against twice the Python side's ½ ω·I_p ω + the
    # part's own: round-off of sums of a few terms of order 1, 1e-14 relative.
    assert twice == pytest.approx(2.0 * float(energy), rel=1e-14)
