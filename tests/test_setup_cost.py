"""What makes a short simulation's set-up cheap keeps every answer and every check:
the body model shared between calls, the plain-number paths of the unit
conversion, the memory check of small requests."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import tumble as tb
from tumble.body import BODY_CACHE_SIZE, RigidBody, body_model
from tumble.errors import InputError, RequestTooLargeError
from tumble.resources import BUDGET_VARIABLE, SMALL_REQUEST, check_memory
from tumble.units import to_si, ureg, vector_to_si

BODY = tb.MassProperties(
    2.0, [0.0, 0.0, 0.1], [[3.0, -1.0, 0.0], [-1.0, 3.0, 0.0], [0.0, 0.0, 5.0]]
)


def test_the_same_body_pivot_and_parts_share_one_model() -> None:
    wheel = tb.Rotor([0, 0, 1], 0.1, speed=10.0)
    model = body_model(BODY, None, (wheel,))
    assert body_model(BODY, None, (wheel,)) is model
    assert body_model(BODY, None, (tb.Rotor([0, 0, 1], 0.1, speed=10.0),)) is not model
    assert body_model(BODY) is not model
    assert body_model(BODY, np.array([0.0, 0.0, 0.0])) is body_model(BODY, [0.0, 0.0, 0.0])


def test_a_shared_model_answers_as_a_new_one() -> None:
    pivot = np.array([0.0, 0.0, -0.2])
    shared, fresh = body_model(BODY, pivot), RigidBody(BODY, pivot)
    assert np.array_equal(shared.moments, fresh.moments)
    assert np.array_equal(shared.axes, fresh.axes)
    assert np.array_equal(shared.inertia, fresh.inertia)
    # The kernels' arguments keep their type: writable arrays, as a new model's.
    assert shared.moments.flags.writeable and shared.axes.flags.writeable


def test_a_mass_properties_changed_in_place_is_a_new_model() -> None:
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    before = body_model(body)
    body.inertia.flags.writeable = True
    body.inertia[2, 2] = 2.5
    body.__dict__.pop("_principal_cached", None)
    after = body_model(body)
    assert after is not before
    assert after.moments.tolist() == [1.0, 2.0, 2.5]


def test_the_model_keeps_its_own_copy_of_the_pivot() -> None:
    pivot = np.array([0.0, 0.0, 0.3])
    model = body_model(BODY, pivot)
    pivot[2] = 1.0
    assert model.reference_point.tolist() == [0.0, 0.0, 0.3]
    assert not model.reference_point.flags.writeable
    assert body_model(BODY, pivot) is not model


def test_the_cache_keeps_the_latest_bodies_only() -> None:
    bodies = [
        tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.0 + k / 100])) for k in range(3)
    ]
    first = body_model(bodies[0])
    for k in range(BODY_CACHE_SIZE):
        body_model(bodies[1], [0.0, 0.0, float(k)])
    assert body_model(bodies[0]) is not first


def test_repeated_simulations_give_the_same_bits() -> None:
    wheel = tb.Rotor([0, 1, 0], 0.05, speed=20.0)
    runs = [
        tb.simulate(BODY, [0.3, 1.0, 0.2], duration=1.0, dt=0.01, method="rk4", internal=[wheel])
        for _ in range(2)
    ]
    assert np.array_equal(runs[0].omega, runs[1].omega)
    assert np.array_equal(runs[0].quaternion, runs[1].quaternion)
    assert np.array_equal(runs[0].rotor_speed, runs[1].rotor_speed)


@pytest.mark.parametrize("value", [1.5, 3, np.float64(-2.0), np.int64(7)])
def test_plain_numbers_convert_as_before(value: float) -> None:
    assert to_si(value, "time", "t") == float(value)
    assert to_si(str(float(value)), "time", "t") == float(value)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (math.nan, r"^Expected `t` to be finite, got nan\.$"),
        (10**400, r"^Expected `t` to be within float range \(\|x\| < 1\.8e308\), got an integer"),
        (True, r"^Expected `t` to be a scalar, got True\.$"),
    ],
)
def test_plain_numbers_that_are_no_time_are_refused_as_before(value: object, message: str) -> None:
    with pytest.raises(InputError, match=message):
        to_si(value, "time", "t")


def test_plain_vectors_convert_as_before() -> None:
    for value in ([1, 2.5, np.float64(3.0)], (0.0, -1.0, 2.0)):
        fast = vector_to_si(value, "length", "v")
        assert fast.dtype == np.float64 and fast.flags.writeable
        assert fast.tolist() == [float(v) for v in value]
    with pytest.raises(InputError, match=r"^Expected `v` to be finite, got \[1\.0, nan, 2\.0\]\.$"):
        vector_to_si([1.0, math.nan, 2.0], "length", "v")
    with pytest.raises(InputError, match=r"^Expected `v` to have shape \(3,\), got \(2,\)\.$"):
        vector_to_si([1.0, 2.0], "length", "v")
    with pytest.raises(InputError, match=r"^Expected `v` to be within float range"):
        vector_to_si([1.0, 10**400, 2.0], "length", "v")


def test_a_small_request_does_not_read_the_machine(monkeypatch: pytest.MonkeyPatch) -> None:
    def unreadable() -> None:
        raise AssertionError("read the machine's limits")

    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    monkeypatch.setattr("tumble.resources.usable_memory", unreadable)
    check_memory(SMALL_REQUEST, lambda: unreadable() or "", "")
    with pytest.raises(AssertionError):
        check_memory(SMALL_REQUEST + 1, "more", "")


def test_a_small_request_is_checked_against_a_budget_that_is_set(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv(BUDGET_VARIABLE, "100 B")
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected a request that fits in the memory budget of 100 B \("
        r"TUMBLE_MEMORY_BUDGET = 100 B\), got 12 recorded samples of 8 values \(0\.1 s at dt = "
        r"0\.01 s, every 1 step\): about 3 KiB\. Record less often",
    ):
        tb.simulate(BODY, [0.0, 1.0, 0.0], duration=0.1, dt=0.01, method="rk4")


def test_what_a_run_returns_is_its_own_to_change() -> None:
    pivot = [0.0, 0.0, -0.2]
    runs = [
        tb.simulate(BODY, [0.0, 1.0, 0.0], pivot=pivot, gravity=[0, 0, -9.81], duration=0.1)
        for _ in range(2)
    ]
    assert runs[0].pivot is not runs[1].pivot
    runs[0].pivot[2] = 5.0  # the shared model keeps its own
    assert body_model(BODY, pivot).reference_point.tolist() == pivot
    assert runs[1].pivot.tolist() == pivot


def test_the_orbit_plane_is_found_once_and_handed_out_as_copies() -> None:
    from scipy.spatial.transform import Rotation

    orbit = tb.torques.GravityGradient(0.001, orbit_normal=[0, 1, 1], radial0=[1, 0, 0])
    e1, e2 = orbit.plane()
    assert e1.flags.writeable and e2.flags.writeable
    assert np.allclose(
        Rotation.from_rotvec([0, 0, 0.1]).apply(e1),
        Rotation.from_rotvec([0, 0, 0.1]).apply(orbit.plane()[0]),
    )
    assert np.isclose(e1 @ e2, 0.0) and np.isclose(np.linalg.norm(e2), 1.0)


# ------------------------------------------------------------------ a motion described again
WHEEL = tb.Rotor([0, 1, 0], 0.05, speed=20.0)


def test_the_same_motion_described_again_shares_its_setup() -> None:
    from tumble.simulation import prepare

    setup = prepare(BODY, [0.3, 1.0, 0.2], internal=[WHEEL], method="rk4")
    # The same values however they are written: a list, a tuple, an array; 1 is 1.0.
    for omega0 in ((0.3, 1.0, 0.2), np.array([0.3, 1.0, 0.2])):
        assert prepare(BODY, omega0, internal=(WHEEL,), method="rk4") is setup
    assert prepare(BODY, [0.3, 1, 0.2], internal=[WHEEL], method="rk4") is setup
    others = [
        prepare(BODY, [0.3, 1.0, 0.25], internal=[WHEEL], method="rk4"),
        prepare(BODY, [0.3, 1.0, 0.2], internal=[WHEEL], method="adaptive"),
        prepare(BODY, [0.3, 1.0, 0.2], internal=[WHEEL], method="rk4", attitude0=[1, 0, 0, 0]),
        prepare(BODY, [0.3, 1.0, 0.2], internal=[tb.Rotor([0, 1, 0], 0.05, speed=20.0)]),
        prepare(BODY, [0.3, 1.0, 0.2], method="rk4"),
        prepare(BODY, [0.3, 1.0, 0.2], internal=[WHEEL], method="rk4", gravity=[0, 0, 0]),
    ]
    assert all(other is not setup for other in others)
    # A torque model is named by no key: each call binds it anew.
    push = tb.torques.ConstantBodyTorque([0.0, 0.0, 0.1])
    assert prepare(BODY, [0.3, 1.0, 0.2], torque=push) is not prepare(
        BODY, [0.3, 1.0, 0.2], torque=push
    )


def test_a_kept_setup_is_read_only_and_leaves_the_callers_arrays_alone() -> None:
    from tumble.simulation import prepare

    omega0 = np.array([0.1, 2.0, 0.0])
    setup = prepare(BODY, omega0, internal=[WHEEL], method="rk4")
    assert omega0.flags.writeable
    omega0[0] = 5.0  # the caller's array changes; the setup kept its own copy
    assert setup.omega0.tolist() == [0.1, 2.0, 0.0]
    assert not any(a.flags.writeable for a in (setup.omega0, setup.attitude0, setup.gravity))
    assert prepare(BODY, omega0, internal=[WHEEL], method="rk4") is not setup


def test_minus_zero_is_not_zero_in_a_key() -> None:
    from tumble.recent import UNKEYED, plain_key

    assert plain_key([0.0, 1.0, 2.0]) != plain_key([-0.0, 1.0, 2.0])
    assert plain_key([0, 1, 2]) == plain_key((0.0, 1.0, 2.0))
    assert plain_key(1.5) != plain_key([1.5])
    assert plain_key(None) is None and plain_key("250 g") == "250 g"
    for value in (
        True,
        [1.0, True, 0.0],
        [np.float64(1.0)],
        [0.0] * 5,
        np.zeros(5),
        [10**400],
        object(),
    ):
        assert plain_key(value) is UNKEYED
    # An int is named by its float64, rounded as the unit conversion rounds it.
    assert plain_key([2**53 + 1, 0, 0]) == plain_key([float(2**53 + 1), 0.0, 0.0])


def test_a_mass_properties_changed_in_place_is_a_new_setup() -> None:
    from tumble.simulation import prepare

    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    before = prepare(body, [0.0, 1.0, 0.1], method="rk4")
    body.inertia.flags.writeable = True
    body.inertia[2, 2] = 2.5
    body.__dict__.pop("_principal_cached", None)
    after = prepare(body, [0.0, 1.0, 0.1], method="rk4")
    assert after is not before
    assert after.body.moments.tolist() == [1.0, 2.0, 2.5]


def test_an_integrator_registered_since_makes_a_new_setup(monkeypatch: pytest.MonkeyPatch) -> None:
    import dataclasses

    from tumble.integrators import INTEGRATORS
    from tumble.simulation import prepare

    before = prepare(BODY, [0.0, 1.0, 0.1], method="rk4")
    again = dataclasses.replace(INTEGRATORS["rk4"])
    monkeypatch.setitem(INTEGRATORS, "rk4", again)
    after = prepare(BODY, [0.0, 1.0, 0.1], method="rk4")
    assert after is not before and after.integrator is again


def test_the_cache_of_setups_keeps_the_latest_only() -> None:
    from tumble.simulation import SETUP_CACHE_SIZE, prepare

    first = prepare(BODY, [0.0, 1.0, 0.3], method="rk4")
    for k in range(SETUP_CACHE_SIZE):
        prepare(BODY, [0.0, 1.0, 1.0 + k], method="rk4")
    assert prepare(BODY, [0.0, 1.0, 0.3], method="rk4") is not first


def test_a_run_again_changes_nothing_of_the_last() -> None:
    # The schedule is kept between runs of one setup: each trajectory has its own times.
    def run(dt: float) -> tb.Trajectory:
        return tb.simulate(BODY, [0.3, 1.0, 0.2], duration=1.0, dt=dt, internal=[WHEEL])

    first = run(0.01)
    first.t[:] = -1.0
    second, third = run(0.01), run(0.02)
    fresh = tb.simulate(
        BODY,
        [0.3, 1.0, 0.2],
        duration=1.0,
        dt=0.01,
        internal=[tb.Rotor([0, 1, 0], 0.05, speed=20.0)],
    )
    assert np.array_equal(second.t, fresh.t) and np.array_equal(second.omega, fresh.omega)
    assert np.array_equal(second.quaternion, fresh.quaternion)
    assert np.array_equal(second.rotor_speed, fresh.rotor_speed)
    assert len(third.t) == 51


def test_a_coarse_step_warns_at_every_call_that_asks_for_it() -> None:
    from tumble.errors import CoarseStepWarning

    for _ in range(2):
        with pytest.warns(
            CoarseStepWarning, match=r"steps per turn of the fastest rotation"
        ) as seen:
            tb.simulate(BODY, [0.0, 30.0, 0.0], duration=1.0, dt=0.05, method="rk4")
        assert seen[0].filename == __file__  # the line that called simulate


def test_a_body_in_its_principal_axes_changes_axes_as_the_product_would() -> None:
    body = body_model(tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0])))
    vectors = np.array([[0.3, -1.0, 2.5], [1e-300, 4.0, -0.0]])
    for turned, product in ((body.to_principal(vectors), vectors @ body.axes),
                            (body.from_principal(vectors), vectors @ body.axes.T)):  # fmt: skip
        assert np.array_equal(turned, product) and turned is not vectors


def test_an_integrator_registered_since_makes_a_new_automatic_choice(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import dataclasses

    from tumble.integrators import INTEGRATORS
    from tumble.simulation import prepare

    wheel = [tb.Rotor([0, 1, 0], 0.05, speed=20.0)]
    before = prepare(BODY, [0.0, 1.0, 0.1], internal=wheel)
    assert before.integrator.name == "splitting"
    again = dataclasses.replace(INTEGRATORS["splitting"])
    monkeypatch.setitem(INTEGRATORS, "splitting", again)
    after = prepare(BODY, [0.0, 1.0, 0.1], internal=wheel)
    assert after is not before and after.integrator is again


def test_a_large_run_again_is_held_to_the_memory_budget_of_now(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # 5001 samples of 8 values, 32 B each: 1.3 MB, above the 1 MiB a run again keeps.
    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    tb.simulate(BODY, [0.0, 1.0, 0.5], duration=50.0, dt=0.01, method="rk4")  # kept
    monkeypatch.setenv(BUDGET_VARIABLE, "1 MB")
    with pytest.raises(RequestTooLargeError, match=r"^Expected a request that fits in the memory"):
        tb.simulate(BODY, [0.0, 1.0, 0.5], duration=50.0, dt=0.01, method="rk4")


def test_a_small_run_again_is_held_to_a_budget_set_since(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    tb.simulate(BODY, [0.0, 1.0, 0.75], duration=0.1, dt=0.01, method="rk4")  # kept
    monkeypatch.setenv(BUDGET_VARIABLE, "100 B")
    with pytest.raises(RequestTooLargeError, match=r"^Expected a request that fits in the memory"):
        tb.simulate(BODY, [0.0, 1.0, 0.75], duration=0.1, dt=0.01, method="rk4")


def test_the_budget_variable_is_read_at_each_call(monkeypatch: pytest.MonkeyPatch) -> None:
    # Where os.environ answers at once whether a name is set, and where it cannot
    # (then tumble.resources reads the variable by the public os.environ.get).
    from tumble import resources

    for environment in (resources._ENVIRONMENT, None):
        monkeypatch.setattr(resources, "_ENVIRONMENT", environment)
        monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
        assert not resources.budget_is_set()
        monkeypatch.setenv(BUDGET_VARIABLE, "  ")
        assert not resources.budget_is_set()  # blanks set nothing
        monkeypatch.setenv(BUDGET_VARIABLE, "1 GiB")
        assert resources.budget_is_set()


def test_a_motion_new_is_keyed_once(monkeypatch: pytest.MonkeyPatch) -> None:
    # The run's key begins with its setup's: a call that keeps neither makes it once.
    from tumble import simulation

    keyed = []  # whether each call made a key

    def counted(*arguments: Any) -> Any:
        key, held = motion_key(*arguments)
        keyed.append(key is not None)
        return key, held

    motion_key = simulation._motion_key
    monkeypatch.setattr(simulation, "_motion_key", counted)
    made = tb.simulate(BODY, [0.0, 1.0, 0.8125], duration=0.1, dt=0.01, method="rk4")
    assert keyed == [True]
    again = tb.simulate(BODY, [0.0, 1.0, 0.8125], duration=0.1, dt=0.01, method="rk4")
    assert keyed == [True, True] and np.array_equal(again.omega, made.omega)  # kept: keyed
    # Arguments that name no run (a duration as a quantity): refused as a run's key
    # before any key is made, and the setup keyed by itself.
    tb.simulate(BODY, [0.0, 1.0, 0.8125], duration=ureg.Quantity(0.1, "s"), dt=0.01, method="rk4")
    assert keyed == [True, True, False, True]


def test_a_trajectory_of_its_fields_is_the_one_its_constructor_makes() -> None:
    import dataclasses

    wheel = tb.Rotor([0, 0, 1], 0.1, speed=10.0)
    made = tb.simulate(BODY, [0.0, 1.0, 0.5], duration=0.2, dt=0.01, internal=[wheel], method="rk4")
    fields = {field.name: getattr(made, field.name) for field in dataclasses.fields(made)}
    again = tb.Trajectory(**fields)
    for name, value in fields.items():
        assert getattr(again, name) is value, name
    assert np.array_equal(made.energy, again.energy) and made.rotor_speed.shape == (21, 1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.dt = 0.5  # type: ignore[misc]
    assert dataclasses.replace(made, dt=0.5).dt == 0.5


def test_a_trajectory_of_fields_missing_or_unknown_is_refused() -> None:
    with pytest.raises(
        InputError,
        match=r"^Expected every field of a Trajectory, got 14 missing \(conserved, dt, internal, "
        r"internal_values, invariant_values, mass_properties, method, omega, pivot, potential, "
        r"quaternion, reason, steps, torque\) and 1 unknown \(speed\)\.$",
    ):
        tb.Trajectory.of_fields(t=np.zeros(1), speed=1.0)
    made = tb.simulate(BODY, [0.0, 1.0, 0.5], duration=0.2, dt=0.01, method="rk4")
    fields = {name: getattr(made, name) for name in ("t", "omega", "quaternion")}
    with pytest.raises(InputError, match=r"got 12 missing \(.*\) and 0 unknown \(none\)\.$"):
        tb.Trajectory.of_fields(**fields)


def _plans_counted(monkeypatch: pytest.MonkeyPatch) -> list[float]:
    """The durations of the runs planned anew from now on (:meth:`Setup.plan`)."""
    from tumble.simulation import Setup

    planned: list[float] = []
    plan = Setup.plan

    def counted(self: Setup, duration: float, *args: object, **kwargs: object) -> object:
        planned.append(duration)
        return plan(self, duration, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(Setup, "plan", counted)
    return planned


def test_a_run_of_many_samples_is_not_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    planned = _plans_counted(monkeypatch)
    # 5001 samples of 8 values: 1.3 MB while the run ends, over the 1 MiB kept.
    for _ in range(2):
        tb.simulate(BODY, [0.0, 1.0, 0.6], duration=50.0, dt=0.01, method="rk4")
        tb.simulate(BODY, [0.0, 1.0, 0.6], duration=0.5, dt=0.01, method="rk4")
    assert planned == [50.0, 0.5, 50.0]


def test_a_run_asked_for_again_is_kept_whatever_the_plain_values_look_like(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    planned = _plans_counted(monkeypatch)
    wheel = [tb.Rotor([0, 1, 0], 0.05, speed=20.0)]
    first = tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.01, internal=wheel)
    # 1 is 1.0, a tuple is a list; the same run each time.
    again = [
        tb.simulate(BODY, (0.0, 1, 0.4), duration=1, dt=0.01, internal=tuple(wheel)),
        tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.01, internal=wheel, rtol=1e-10),
    ]
    assert planned == [1.0]
    for run in again:
        assert np.array_equal(run.omega, first.omega) and np.array_equal(run.t, first.t)
        assert np.array_equal(run.rotor_speed, first.rotor_speed)
        assert run.reason == first.reason and run.method == first.method
    # Each of these is planned anew: a new value, a quantity, a new max_steps, atol.
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=2.0, dt=0.01, internal=wheel)
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.02, internal=wheel)
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.01, internal=wheel, record_every=2)
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=ureg.Quantity(1.0, "s"), dt=0.01, internal=wheel)
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.01, internal=wheel, max_steps=10**6)
    tb.simulate(BODY, [0.0, 1.0, 0.4], duration=1.0, dt=0.01, internal=wheel, atol=1e-9)
    assert planned == [1.0, 2.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    # A progress report runs the kept run, reporting.
    reports: list[tuple[int, int]] = []
    reported = tb.simulate(
        BODY,
        [0.0, 1.0, 0.4],
        duration=1.0,
        dt=0.01,
        internal=wheel,
        progress=lambda done, total: reports.append((done, total)),
    )
    assert len(planned) == 7 and reports == [(100, 100)]
    assert np.array_equal(reported.omega, first.omega)


def test_a_kept_run_refuses_a_progress_that_cannot_be_called() -> None:
    tb.simulate(BODY, [0.0, 1.0, 0.45], duration=1.0, dt=0.01, method="rk4")
    with pytest.raises(InputError, match=r"^Expected `progress` to be None or a function"):
        tb.simulate(BODY, [0.0, 1.0, 0.45], duration=1.0, dt=0.01, method="rk4", progress=3)


def test_a_max_steps_that_is_no_integer_is_refused_after_one_that_is() -> None:
    tb.simulate(BODY, [0.0, 1.0, 0.8], duration=1.0, dt=0.01, method="rk4", max_steps=1000)
    with pytest.raises(
        InputError, match=r"^Expected `max_steps` to be an integer >= 1 or None, got 1000\.0\.$"
    ):
        tb.simulate(BODY, [0.0, 1.0, 0.8], duration=1.0, dt=0.01, method="rk4", max_steps=1000.0)


def test_a_gravity_model_registered_since_makes_a_new_setup(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from tumble.simulation import prepare
    from tumble.torques import TORQUES

    before = prepare(BODY, [0.0, 1.0, 0.1], pivot=[0, 0, -0.1], gravity=[0, 0, -9.81])

    class Heavier(TORQUES["gravity"]):  # type: ignore[misc, valid-type]
        pass

    monkeypatch.setitem(TORQUES, "gravity", Heavier)
    after = prepare(BODY, [0.0, 1.0, 0.1], pivot=[0, 0, -0.1], gravity=[0, 0, -9.81])
    assert after is not before and type(after.model) is Heavier


def test_a_read_only_attitude_turns_without_a_kernel_of_its_own() -> None:
    from tumble.core.quaternion import multiply_right

    attitude = np.array([[1.0, 0.0, 0.0, 0.0]])
    attitude.flags.writeable = False
    turned = body_model(BODY).attitude_to_principal(attitude)  # BODY's axes are turned
    assert turned.flags.writeable
    assert not any("readonly" in str(signature) for signature in multiply_right.signatures)


def test_a_kept_run_that_does_not_stay_finite_is_refused_each_time() -> None:
    # ω of 1e160 rad/s: its squares overflow in the first step of a body and its
    # wheel, as the kernel takes it in one call (100 steps, no progress asked).
    wheel = [tb.Rotor([0, 1, 0], 0.05, speed=20.0)]
    for _ in range(2):
        with (
            pytest.raises(
                tb.IntegrationError,
                match=r"^Expected the integration to stay finite, got NaN or inf at step 1 ",
            ),
            pytest.warns(tb.CoarseStepWarning),
        ):
            tb.simulate(
                BODY, [1e160, 1.0, 0.0], duration=1.0, dt=0.01, internal=wheel, method="rk4"
            )


def test_an_integrator_without_a_ready_driver_runs_its_own() -> None:
    from tumble.integrators.problem import Samples
    from tumble.simulation import prepare

    setup = prepare(BODY, [0.0, 1.0, 0.3], method="adaptive", internal=[WHEEL])
    assert setup.integrator.ready is None
    run = setup.plan(1.0, 0.1, 1, rtol=1e-10, atol=1e-12, max_steps=None)
    samples = run.steps(None)
    again = setup.integrator.run(setup.integrator, setup.problem, run.schedule, None)
    assert isinstance(samples, Samples) and samples.steps == again.steps
    assert np.array_equal(samples.omega, again.omega)


@pytest.mark.parametrize("internal", [None, [WHEEL]], ids=["rigid", "wheel"])
def test_a_run_is_the_same_in_one_call_of_its_kernel_or_in_chunks(internal: object) -> None:
    from tumble.integrators.steps import PROGRESS_CHUNK

    # Without progress reports, a run of at most PROGRESS_CHUNK steps is one call of
    # its kernel, and a longer one is stepped in chunks, as every run that reports.
    # The kernel numbers each step from the first: both ways give the same bits.
    reports: list[int] = []
    for steps in (PROGRESS_CHUNK, PROGRESS_CHUNK + 7):
        arguments = {"duration": steps * 1e-4, "dt": 1e-4, "record_every": 997}
        quiet = tb.simulate(BODY, [0.3, 1.0, 0.2], method="rk4", internal=internal, **arguments)
        reports.clear()
        told = tb.simulate(
            BODY,
            [0.3, 1.0, 0.2],
            method="rk4",
            internal=internal,
            progress=lambda done, total: reports.append(done),
            **arguments,
        )
        assert quiet.steps == told.steps == steps and reports[-1] == steps
        assert np.array_equal(quiet.omega, told.omega)
        assert np.array_equal(quiet.quaternion, told.quaternion)
        assert np.array_equal(quiet.internal_values, told.internal_values)


def test_the_machine_code_of_a_compiled_function_computes_as_the_function() -> None:
    import numba

    from tumble.integrators.steps import compiled_for

    @numba.njit
    def doubled(x: np.ndarray, out: np.ndarray) -> None:
        out[:] = 2.0 * x

    x, out, expected = np.array([1.0, -2.5, 3.0]), np.empty(3), np.empty(3)
    doubled(x, expected)
    machine = compiled_for(doubled, (x, out))
    machine(x, out)
    assert machine is not doubled and np.array_equal(out, expected)
    # Plain Python (numba's NUMBA_DISABLE_JIT): the function itself.
    assert compiled_for(doubled.py_func, (x, out)) is doubled.py_func

    class WithoutMachineCode:  # a dispatcher whose compile returns nothing to call
        def compile(self, signature: object) -> None:
            return None

    dispatcher = WithoutMachineCode()
    assert compiled_for(dispatcher, (x, out)) is dispatcher
    # A dispatcher given its signatures compiles no more: its compile raises, even
    # for a signature it has.
    typed = numba.njit("void(float64[:], float64[:])")(doubled.py_func)
    assert compiled_for(typed, (x, out)) is typed


def test_the_types_of_arrays_kept_are_numbas() -> None:
    import numba

    from tumble.integrators.steps import _argument_type

    grid = np.arange(12.0).reshape(3, 4)
    read_only = np.zeros(3)
    read_only.flags.writeable = False
    arrays = [
        np.zeros(3),
        grid,
        grid.T,
        grid[:, ::2],
        read_only,
        np.zeros(3, np.int32),
        np.zeros(5),
    ]
    for array in arrays + [a.copy() for a in arrays]:  # the second time from what is kept
        assert _argument_type(array) == numba.typeof(array)
    for value in (0.5, 7, True):
        assert _argument_type(value) == numba.typeof(value)
    # Records are typed by numba each time: an aligned struct and a packed one of the
    # same fields are equal dtypes to numpy, not to numba.
    fields = {"names": ["a", "b"], "formats": ["f8", "f8"]}
    packed, aligned = np.zeros(2, np.dtype(fields)), np.zeros(2, np.dtype(fields, align=True))
    assert _argument_type(packed) == numba.typeof(packed)
    assert _argument_type(aligned) == numba.typeof(aligned)


@pytest.mark.parametrize(
    ("parts", "machine_codes"),
    [([tb.Rotor([0, 1, 0], 0.05, speed=20.0)], 2), ([tb.KaneDamper(0.1, 1.0)], 1), (None, 1)],
    ids=["rotor", "damper", "rigid"],
)
def test_a_run_repeated_calls_its_machine_code_from_its_second_run(
    monkeypatch: pytest.MonkeyPatch, parts: list[Any] | None, machine_codes: int
) -> None:
    # The first run goes through numba's dispatch; the second finds the machine code
    # of the kernel and, where the parts' values are read compiled, of the reading
    # (a damper's are read in Python; a rigid body's need no reading); the later
    # runs find nothing more.
    from tumble.integrators.drivers import stepping
    from tumble.integrators.steps import compiled_for

    found = []

    def recorded(function: object, arguments: tuple[object, ...]) -> object:
        found.append(function)
        return compiled_for(function, arguments)

    monkeypatch.setattr(stepping, "compiled_for", recorded)
    body = tb.MassProperties(2.0, [0.0, 0.0, 0.0], np.diag([3.0, 4.0, 5.0]))  # a new key
    runs = []
    for count in (0, machine_codes, machine_codes, machine_codes):
        runs.append(
            tb.simulate(body, [0.3, 1.0, 0.2], duration=1.0, dt=0.01, method="rk4", internal=parts)
        )
        assert len(found) == count
    # The machine code computes as the dispatch: the same bits.
    for run in runs[1:]:
        assert np.array_equal(run.omega, runs[0].omega)
        assert np.array_equal(run.quaternion, runs[0].quaternion)
        assert np.array_equal(run.internal_values, runs[0].internal_values)
