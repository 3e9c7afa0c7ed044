"""simulate_batch(): the same motion as separate simulate() calls, for many bodies at once."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.errors import IntegrationError


def random_bodies(n: int, seed: int = 7) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    second = rng.uniform(0.1, 1.0, size=(n, 3))  # ∫x², ∫y², ∫z²: always a valid body
    moments = np.column_stack(
        [second[:, 1] + second[:, 2], second[:, 0] + second[:, 2], second[:, 0] + second[:, 1]]
    )
    omega = rng.normal(size=(n, 3))
    attitude = Rotation.random(n, random_state=seed).as_quat(scalar_first=True)
    return moments, omega, attitude


def test_batch_equals_separate_simulations_for_principal_moments() -> None:
    # 1030 bodies span three blocks of 512 (one partial). The batch kernel may
    # contract to FMA, so agreement is to round-off: 1e-12 after 500 steps.
    moments, omega, attitude = random_bodies(1030)
    batch = tb.simulate_batch(moments, omega, attitude0=attitude, duration=0.5, dt=1e-3)
    for k in (0, 511, 512, 1029):
        one = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])),
            omega[k],
            attitude0=attitude[k],
            duration=0.5,
            dt=1e-3,
        )
        assert_allclose(batch.omega[k], one.omega[-1], atol=1e-12)
        assert_allclose(batch.quaternion[k], one.quaternion[-1], atol=1e-12)


def test_batch_equals_separate_simulations_for_tensors() -> None:
    moments, omega, attitude = random_bodies(40, seed=3)
    axes = Rotation.random(40, random_state=4).as_matrix()
    tensors = axes @ (moments[:, :, None] * np.eye(3)) @ np.swapaxes(axes, 1, 2)
    batch = tb.simulate_batch(
        tensors, omega, attitude0=attitude, duration=0.3, dt=1e-3, record_every=100
    )
    for k in (0, 17, 39):
        one = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], tensors[k]),
            omega[k],
            attitude0=attitude[k],
            duration=0.3,
            dt=1e-3,
            record_every=100,
        )
        assert_allclose(batch.omega_history[:, k], one.omega, atol=1e-12)
        # q and −q are the same attitude: compare rotations.
        angle = (
            Rotation.from_quat(batch.quaternion_history[:, k], scalar_first=True)
            * Rotation.from_quat(one.quaternion, scalar_first=True).inv()
        ).magnitude()
        assert np.max(angle) < 1e-11
    assert_allclose(batch.t, one.t, atol=1e-15)


def test_batch_conserves_energy_and_momentum_per_body() -> None:
    moments, omega, attitude = random_bodies(2000, seed=11)
    batch = tb.simulate_batch(moments, omega, attitude0=attitude, duration=2.0, dt=1e-3)
    energy0 = 0.5 * np.sum(moments * omega**2, axis=1)
    energy = 0.5 * np.sum(moments * batch.omega**2, axis=1)
    # RK4 drift over 2000 steps of |ω| dt ≲ 4e-3: far below 1e-9 relative.
    assert np.max(np.abs(energy - energy0) / energy0) < 1e-9
    assert_allclose(np.linalg.norm(batch.quaternion, axis=1), 1.0, atol=1e-14)


def test_batch_with_a_space_torque_and_damping() -> None:
    moments, omega, attitude = random_bodies(5, seed=2)
    torque = tb.torques.ConstantSpaceTorque([0.1, 0.0, -0.2]) + tb.torques.LinearDamping(0.05)
    batch = tb.simulate_batch(
        moments, omega, attitude0=attitude, duration=0.5, dt=1e-3, torque=torque
    )
    for k in range(5):
        one = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])),
            omega[k],
            attitude0=attitude[k],
            duration=0.5,
            dt=1e-3,
            torque=torque,
        )
        assert_allclose(batch.omega[k], one.omega[-1], atol=1e-12)


@numba.njit
def _user_torque(t, omega, quaternion, params, out):
    out[0] = 1.0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"inertia": [[1.0, 2.0, 0.0]]},
            r"Expected every body to have positive principal moments, got body 0",
        ),
        (
            {"inertia": [[1.0, 1.0, 3.0]]},
            r"Expected principal moments satisfying I1 \+ I2 >= I3, got body 0",
        ),
        ({"omega0": [[1.0, 2.0]]}, r"Expected `omega0` to have shape \(1, 3\), got \(1, 2\)"),
        (
            {"attitude0": [[0.0, 0.0, 0.0, 0.0]]},
            r"Expected `attitude0` to hold non-zero quaternions, got attitude0\[0\]",
        ),
        ({"duration": -1.0}, r"Expected `duration` > 0 s, got -1.0"),
        ({"dt": 0.0}, r"Expected `dt` > 0 s, got 0.0"),
        (
            {"method": "adaptive"},
            r"Expected `method` to be one of exact, splitting, strang, splitting-exact, strang-exact, rk4, got 'adaptive'",
        ),
        (
            {"torque": tb.torques.Gravity()},
            r"Expected `torque` of models that batches accept \(constant-body, constant-space, damping, rotor-momentum, drag, quadratic-drag, gravity-gradient\), got Gravity\(\[0.0, 0.0, -9.81\] m/s²\) \(use simulate for it\)",
        ),
        ({"torque": 3.0}, r"Expected `torque` to be a model from tumble.torques, got float"),
        ({"record_every": 0}, r"Expected `record_every` to be None or an integer >= 1, got 0"),
        # A fraction of a step, a string and a bool are refused as simulate refuses them.
        (
            {"record_every": 2.5},
            r"^Expected `record_every` to be None or an integer >= 1, got 2\.5\.$",
        ),
        (
            {"record_every": "2"},
            r"^Expected `record_every` to be None or an integer >= 1, got '2'\.$",
        ),
        (
            {"record_every": True},
            r"^Expected `record_every` to be None or an integer >= 1, got True\.$",
        ),
        (
            {"inertia": [[[1.0, 0.1, 0.0], [0.2, 2.0, 0.0], [0.0, 0.0, 2.5]]]},
            r"^Expected `inertia` to be symmetric, got body 0 with inertia\[0, 0, 1\] = 0\.1 "
            r"but inertia\[0, 1, 0\] = 0\.2 kg·m²\.$",
        ),
        (
            {"torque": tb.torques.LinearDamping([0.1, 0.2])},
            r"Expected per-body LinearDamping values of shape \(1,\) for 1 bodies, got \(2,\)",
        ),
        (
            {"torque": tb.torques.ConstantBodyTorque([[1, 0, 0], [0, 1, 0]])},
            r"Expected per-body ConstantBodyTorque values of shape \(1, 3\) for 1 bodies, got \(2, 3\)",
        ),
        (
            {"torque": tb.torques.UserTorque(_user_torque)},
            r"Expected `torque` of models that batches accept .*, got UserTorque\(_user_torque",
        ),
    ],
)
def test_batch_rejects_bad_input(kwargs: dict, message: str) -> None:
    arguments = {
        "inertia": [[1.0, 2.0, 2.5]],
        "omega0": [[0.1, 1.0, 0.0]],
        "duration": 1.0,
        "dt": 1e-2,
    }
    arguments.update(kwargs)
    with pytest.raises(tb.InputError, match=message):
        tb.simulate_batch(arguments.pop("inertia"), arguments.pop("omega0"), **arguments)


@pytest.mark.parametrize("method", ["rk4", "adaptive", "strang", "splitting"])
def test_a_free_body_s_kernels_equal_those_of_a_zero_torque(method: str) -> None:
    # A free body's torque is recognised while the kernels compile and its terms
    # dropped: (0 − 0 ω)/I + c ω ω is c ω ω exactly, and a kick of zero torque
    # adds exactly zero to L (no signed zeros arise from these bodies), so a single
    # body's results are the same bits. Two forms differ by round-off only: the
    # batch kernels, which may contract to FMA differently in the two forms, and
    # the fourth-order splitting, whose free step merges its rotations about
    # axis 1 and about L (the same map, other roundings): a few ε a step over 500
    # steps (batch) or 50 (single) of |ω| ~ 1: 1e-13.
    rng = np.random.default_rng(7)
    moments = np.sort(rng.uniform(1.0, 3.0, size=(50, 3)), axis=1)
    omega = rng.normal(size=(50, 3))
    zero = tb.torques.ConstantBodyTorque([0.0, 0.0, 0.0])
    if method != "adaptive":
        options = {"duration": 0.5, "dt": 1e-3, "method": method}
        free = tb.simulate_batch(moments, omega, **options)
        held = tb.simulate_batch(moments, omega, torque=zero, **options)
        assert_allclose(free.omega, held.omega, rtol=0, atol=1e-13)
        assert_allclose(free.quaternion, held.quaternion, rtol=0, atol=1e-13)
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[0]))
    options = {"duration": 0.5, "dt": 1e-2, "method": method}
    free_run = tb.simulate(body, omega[0], **options)
    held_run = tb.simulate(body, omega[0], torque=zero, **options)
    if method == "splitting":
        assert_allclose(free_run.omega, held_run.omega, rtol=0, atol=1e-13)
        assert_allclose(free_run.quaternion, held_run.quaternion, rtol=0, atol=1e-13)
        assert not np.array_equal(free_run.quaternion, held_run.quaternion)  # merged
    else:
        assert np.array_equal(free_run.omega, held_run.omega)
        assert np.array_equal(free_run.quaternion, held_run.quaternion)


@pytest.mark.parametrize("method", ["strang", "splitting"])
def test_the_splittings_follow_a_symmetric_body_exactly_at_any_angle_a_step(method) -> None:
    # I1 = I2: ω3 constant, (ω1, ω2) turning at Ω = (I3 − I1)/I1 ω3 in the body
    # (Landau & Lifshitz §33) and the attitude q(t) of the closed form; the
    # splitting is exact for such a body, whatever the step, and its sines are
    # evaluated by the reduction of angles up to 2^45 rad. Steps turning (ω1, ω2)
    # by up to 6e5 rad, 6e6 rad in all: a phase known to ulp(6e6) = 9e-10 rad
    # (measured 1e-9 relative): 1e-8.
    moments = np.array([[1.0, 1.0, 1.6]] * 3)
    omega = np.array([[0.3, 0.0, 1.0], [0.3, 0.2, 1e3], [1e-3, 0.0, 1e5]])
    batch = tb.simulate_batch(moments, omega, duration=100.0, dt=10.0, method=method)
    exact = tb.simulate_batch(moments, omega, duration=100.0, dt=10.0, method="exact")
    assert_allclose(batch.omega, exact.omega, rtol=1e-8, atol=0)
    assert_allclose(
        np.abs(np.sum(batch.quaternion * exact.quaternion, axis=1)), 1.0, rtol=0, atol=1e-8
    )


@pytest.mark.parametrize("method", ["strang", "splitting"])
def test_a_splitting_step_turning_past_the_largest_angle_is_refused(method) -> None:
    # |h| |L| / I1 = 1e14 rad > 2^45: beyond the angles the sines are accurate for,
    # a step that does not stay finite, in a batch and for one body.
    with pytest.raises(IntegrationError, match=r"got NaN or inf for 1 bodies \(first: body 1\)"):
        tb.simulate_batch(
            [[1.0, 2.0, 2.5], [1.0, 2.0, 2.5]], [[0.1, 1.0, 0.0], [1e14, 1.0, 0.0]],
            duration=1.0, dt=1.0, method=method,
        )  # fmt: skip
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.5]))
    with (
        pytest.raises(IntegrationError, match=r"stay finite, got NaN or inf at step 1"),
        pytest.warns(tb.CoarseStepWarning),
    ):
        tb.simulate(body, [1e14, 1.0, 0.0], duration=1.0, dt=1.0, method=method)


def test_batch_divergence_is_reported() -> None:
    with pytest.raises(tb.IntegrationError, match=r"got NaN or inf for 1 bodies \(first: body 1\)"):
        tb.simulate_batch(
            [[1.0, 2.0, 2.5], [1.0, 2.0, 2.5]],
            [[0.1, 0.1, 0.1], [0.1, 300.0, 0.1]],
            duration=2000.0,
            dt=2.0,
        )


@pytest.mark.parametrize("method", ["rk4", "splitting", "strang", "splitting-exact"])
def test_per_body_torques_equal_separate_simulations(method) -> None:
    # Tensors (non-principal body axes), per-body body torques, space torques and
    # damping: each body must move as simulate() moves it alone with its own model.
    rng = np.random.default_rng(11)
    n = 5
    rotations = Rotation.random(n, random_state=3)
    moments = np.sort(rng.uniform(0.5, 1.0, size=(n, 3)), axis=1)
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    tensors = np.einsum("nij,nj,nkj->nik", rotations.as_matrix(), moments, rotations.as_matrix())
    omega0 = rng.normal(size=(n, 3))
    body = rng.normal(scale=0.1, size=(n, 3))
    space = rng.normal(scale=0.1, size=(n, 3))
    damping = rng.uniform(0.0, 0.05, size=n)
    model = (
        tb.torques.ConstantBodyTorque(body)
        + tb.torques.ConstantSpaceTorque(space)
        + tb.torques.LinearDamping(damping)
    )
    batch = tb.simulate_batch(tensors, omega0, duration=2.0, dt=1e-2, method=method, torque=model)
    assert batch.method == method
    for k in range(n):
        alone = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], tensors[k]),
            omega0[k],
            duration=2.0,
            dt=1e-2,
            method=method,
            torque=tb.torques.ConstantBodyTorque(body[k])
            + tb.torques.ConstantSpaceTorque(space[k])
            + tb.torques.LinearDamping(damping[k]),
        )
        # Same kernels and arithmetic, up to the eigen-decomposition (numpy's batched
        # eigh vs one at a time) and fast-math contractions: round-off, amplified by
        # the flow over 200 steps to < 1e-12.
        assert_allclose(batch.omega[k], alone.omega[-1], atol=1e-12)
        assert_allclose(
            Rotation.from_quat(batch.quaternion[k], scalar_first=True).as_matrix(),
            alone.rotation[-1].as_matrix(),
            atol=1e-12,
        )


def test_batch_splitting_keeps_l_to_round_off() -> None:
    # Torque-free splitting in a batch: |L| is unchanged by every rotation.
    rng = np.random.default_rng(2)
    moments = np.column_stack([np.ones(300), rng.uniform(1.1, 2.0, 300), np.full(300, 2.1)])
    omega0 = rng.normal(size=(300, 3))
    batch = tb.simulate_batch(moments, omega0, duration=100.0, dt=1e-2, method="splitting")
    before = np.linalg.norm(moments * omega0, axis=1)
    after = np.linalg.norm(moments * batch.omega, axis=1)
    # 1e4 steps, ~10 rounded operations each: random walk ≈ 1e-16·√1e5 ≈ 3e-14.
    assert np.max(np.abs(after / before - 1)) < 1e-13


def test_batch_splitting_reports_divergence() -> None:
    with pytest.raises(tb.IntegrationError, match=r"got NaN or inf for 1 bodies \(first: body 1\)"):
        tb.simulate_batch(
            [[1.0, 2.0, 2.5], [1.0, 2.0, 2.5]],
            [[0.1, 1.0, 0.0], [0.1, 1.0, 0.0]],
            duration=1.0,
            dt=0.1,
            method="splitting",
            torque=tb.torques.ConstantBodyTorque([[0, 0, 0], [1e308, 1e308, 0]]),
        )


# ------------------------------------------------------------------ the closed form
def test_the_exact_batch_equals_separate_exact_simulations() -> None:
    # Asymmetric, oblate and prolate bodies, a sphere, spins exactly about a
    # principal axis (the unstable middle one too), and tensors whose axes are
    # not principal: the same closed form per body, evaluated once at t = 50 s,
    # agrees with simulate(method="exact") to round-off: the attitude is
    # composed in compiled code here and by scipy there, 1e-13 after ~50 rad.
    moments, omega, attitude = random_bodies(40)
    moments[:4] = [[1.0, 1.0, 2.0], [1.0, 2.0, 2.0], [2.0, 2.0, 2.0], [1.0, 2.0, 3.0]]
    omega[3:6] = [[0.0, 1.0, 0.0], [0.0, 0.0, 2.0], [0.5, 0.0, 0.0]]
    turns = Rotation.random(40, random_state=8).as_matrix()
    tensors = np.einsum("nij,nj,nkj->nik", turns, moments, turns)
    for inertia in (moments, tensors):
        batch = tb.simulate_batch(
            inertia, omega, attitude0=attitude, duration=50.0, dt=0.5, method="exact"
        )
        for k in range(40):
            body = np.diag(inertia[k]) if inertia.ndim == 2 else inertia[k]
            one = tb.simulate(tb.MassProperties(1.0, [0, 0, 0], body), omega[k],
                              attitude0=attitude[k], duration=50.0, dt=50.0, method="exact")  # fmt: skip
            assert_allclose(batch.omega[k], one.omega[-1], rtol=0, atol=1e-13)
            sign = np.sign(batch.quaternion[k] @ one.quaternion[-1])
            assert_allclose(sign * batch.quaternion[k], one.quaternion[-1], rtol=0, atol=1e-13)


def test_the_exact_batch_records_every_kth_state() -> None:
    # Recorded every 5 s, each record the closed form from the initial state,
    # as simulate() evaluates it: the attitude composed in compiled code here
    # and by scipy there, round-off after ~50 rad: 1e-12.
    moments, omega, attitude = random_bodies(20)
    batch = tb.simulate_batch(moments, omega, attitude0=attitude, duration=50.0, dt=0.5,
                              method="exact", record_every=10)  # fmt: skip
    assert_allclose(batch.t, np.linspace(0.0, 50.0, 11))
    for k in range(20):
        one = tb.simulate(tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])), omega[k],
                          attitude0=attitude[k], duration=50.0, dt=5.0, method="exact")  # fmt: skip
        assert_allclose(batch.omega_history[:, k], one.omega, rtol=0, atol=1e-12)
        dots = np.abs(np.einsum("ni,ni->n", batch.quaternion_history[:, k], one.quaternion))
        assert np.max(np.abs(dots - 1.0)) < 1e-12


def test_the_exact_batch_refuses_a_torque() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected torque-free bodies for method 'exact' \(the closed form\), got "
        r"LinearDamping\(.*\): use 'rk4' or a splitting\.$",
    ):
        tb.simulate_batch([[1.0, 2.0, 3.0]], [[0.1, 0.2, 0.3]], duration=1.0, dt=0.1,
                          method="exact", torque=tb.torques.LinearDamping(0.1))  # fmt: skip


@pytest.mark.parametrize("method", ["rk4", "splitting", "exact"])
def test_the_callers_initial_arrays_are_left_as_they_were(method: str) -> None:
    # One body already in principal axes, and Fortran-ordered (N, 3) arrays: the
    # layouts whose transposes are C-contiguous views of the caller's memory.
    one = np.array([[0.1, 2.0, 0.1]])
    many = np.asfortranarray([[0.1, 2.0, 0.1], [0.2, 1.0, 0.3]])
    attitudes = np.asfortranarray([[1.0, 0.0, 0.0, 0.0], [0.6, 0.8, 0.0, 0.0]])
    for omega0, q0 in ((one, None), (many, attitudes)):
        before_w, before_q = omega0.copy(), None if q0 is None else q0.copy()
        n = len(omega0)
        tb.simulate_batch([[1.0, 2.0, 3.0]] * n, omega0, attitude0=q0, duration=1.0, dt=1e-2,
                          method=method)  # fmt: skip
        assert np.array_equal(omega0, before_w)
        if q0 is not None:
            assert np.array_equal(q0, before_q)


def test_a_non_symmetric_tensor_is_refused_naming_its_body() -> None:
    # The second of three bodies has I_yz = 0.3 but I_zy = 0.31: refused, as
    # MassProperties refuses it, not silently averaged. A difference of 1e-12
    # of the largest entry (round-off in a tensor formed by rotations) is
    # within the tolerance MassProperties takes (1e-9) and is accepted there too.
    tensors = np.tile(np.diag([1.0, 2.0, 2.5]), (3, 1, 1))
    tensors[:, 1, 2] = tensors[:, 2, 1] = 0.3
    tensors[1, 2, 1] = 0.31
    omega = [[0.1, 1.0, 0.0]] * 3
    message = (
        r"^Expected `inertia` to be symmetric, got body 1 with inertia\[1, 1, 2\] = 0\.3 "
        r"but inertia\[1, 2, 1\] = 0\.31 kg·m²\.$"
    )
    with pytest.raises(tb.InputError, match=message):
        tb.simulate_batch(tensors, omega, duration=1.0, dt=0.1)
    with pytest.raises(tb.InputError, match=r"^Expected `inertia` to be symmetric, got inertia"):
        tb.MassProperties(1.0, [0, 0, 0], tensors[1])
    with pytest.raises(tb.InputError, match=message):  # a body carrying parts too
        tb.simulate_batch(tensors, omega, duration=1.0, dt=0.1,
                          internal=[tb.Rotor([0, 0, 1], 0.1, speed=1.0)])  # fmt: skip
    tensors[1, 2, 1] = 0.3 * (1 + 1e-12)
    batch = tb.simulate_batch(tensors, omega, duration=1.0, dt=0.1)
    one = tb.simulate(tb.MassProperties(1.0, [0, 0, 0], tensors[1]), omega[1], duration=1.0,
                      dt=0.1, method="rk4")  # fmt: skip
    assert_allclose(batch.omega[1], one.omega[-1], rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("duration", "dt", "every"),
    [(1.0, 1e-3, 250), (1.0, 3e-3, 7), (0.7, 0.1, 3), (2.0, 0.03, 100), (0.5, 0.025, 1)],
)
def test_each_record_is_labelled_with_the_time_of_its_state(duration, dt, every) -> None:
    # Steps that divide the duration, steps that do not (dt shortened to whole
    # steps), intervals that do not divide the steps (the end is recorded after
    # a shorter interval) and one longer than the run: the times and states of
    # simulate(), record for record. RK4 in both, the batch kernel contracted
    # to FMA: round-off, 1e-12.
    moments, omega, attitude = random_bodies(3, seed=5)
    batch = tb.simulate_batch(moments, omega, attitude0=attitude, duration=duration, dt=dt,
                              record_every=np.int64(every))  # fmt: skip
    assert batch.t[-1] == pytest.approx(duration, rel=1e-15)
    for k in range(3):
        one = tb.simulate(tb.MassProperties(1.0, [0, 0, 0], np.diag(moments[k])), omega[k],
                          attitude0=attitude[k], duration=duration, dt=dt, method="rk4",
                          record_every=every)  # fmt: skip
        assert_allclose(batch.t, one.t, rtol=1e-15, atol=0)
        assert_allclose(batch.omega_history[:, k], one.omega, rtol=0, atol=1e-12)
        assert_allclose(batch.omega_history[-1, k], batch.omega[k], rtol=0, atol=0)


def test_the_exact_batch_s_history_is_the_closed_form_near_the_separatrix() -> None:
    # I = (1, 2, 3) kg·m², ω0 1e-6 rad/s from a spin about the intermediate axis
    # (a separatrix), 100 s (two flips), recorded every 10 steps of 0.01 s. Each
    # record is the closed form evaluated from the initial state, as simulate()
    # and tb.theory.free_motion evaluate it. How well the motion is determined:
    # a change of the state by round-off (1e-16 relative) moves it by 1e-16 of
    # |ω| along the separatrix, 1e-10 of its 1e-6 distance from it, which shifts
    # the flips by 1e-10 of their phase: evaluations by different roundings may
    # differ by ~1e-10 rad/s, ~1e-10 rad in attitude (measured: 2e-17 from
    # free_motion, 8e-15 from simulate). Restarting each interval from the
    # rounded state before (1e-16 a record, 1000 records) walks 1.6e-3 rad/s away.
    moments = np.array([1.0, 2.0, 3.0])
    omega = np.array([1e-6, 1.0, 1e-6])
    batch = tb.simulate_batch([moments], [omega], duration=100.0, dt=0.01, method="exact",
                              record_every=10)  # fmt: skip
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag(moments))
    w, q = tb.theory.free_motion(body, omega).at(batch.t)
    assert np.ptp(w[:, 1]) > 1.9  # it flips
    assert_allclose(batch.omega_history[:, 0], w, rtol=0, atol=1e-9)
    turn = Rotation.from_quat(batch.quaternion_history[:, 0], scalar_first=True).inv()
    assert np.max((turn * Rotation.from_quat(q, scalar_first=True)).magnitude()) < 1e-9
    one = tb.simulate(body, omega, duration=100.0, dt=0.1, method="exact")
    assert_allclose(batch.omega_history[:, 0], one.omega, rtol=0, atol=1e-9)
