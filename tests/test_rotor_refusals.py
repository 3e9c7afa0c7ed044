"""A rigid rotor on elastic bearings refuses what it cannot answer: bearings that
are not Bearing objects, values whose matrices overflow float64, run-ups of too
many steps, results larger than the memory budget; and keeps its memory bounded
for many speeds."""

from __future__ import annotations

import re
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import tumble as tb
from tumble.cli import app
from tumble.models import run_up
from tumble.scenario import builtin_text
from tumble.theory import Bearing, RigidRotor

ROD = tb.shapes.solid_cylinder(10.0, 0.05, 0.6)


def symmetric(k: float = 1e6, a: float = 0.2, c: float = 0.0) -> RigidRotor:
    return RigidRotor(ROD, [Bearing(-a, k, c), Bearing(a, k, c)])


@pytest.mark.parametrize(
    ("bearings", "shown"),
    [(5, "5"), (None, "None"), (Bearing(0.2, 1e6), r"Bearing\(position=0\.2"), ("ab", "'ab'"),
     ([Bearing(-0.2, 1e6), (0.2, 1e6)], r"\[Bearing\(")],
    ids=["number", "none", "one-bearing", "text", "tuple-inside"],
)  # fmt: skip
def test_bearings_that_are_not_a_list_of_bearing_objects_are_refused(bearings, shown) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(
        tb.InputError,
        match=rf"^Expected `bearings` to be a list of tumble\.theory\.Bearing objects, got {shown}",
    ):
        RigidRotor(ROD, bearings)


def test_a_rotor_without_transverse_inertia_is_refused() -> None:
    point = tb.MassProperties(1.0, [0, 0, 0], np.zeros((3, 3)))
    with pytest.raises(
        tb.InputError,
        match=r"^Expected the rotor's moment of inertia about the axes perpendicular to `axis` "
        r"> 0 kg·m² \(the inertia of its tilt\), got 0\.0\.$",
    ):
        RigidRotor(point, [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)])


@pytest.mark.parametrize(
    ("bearings", "message"),
    [
        ([Bearing(-0.2, 1e308), Bearing(0.2, 1e308)],
         r"^Expected bearings whose stiffness matrix .* is finite in float64, got stiffness up to "
         r"1e\+308 N/m at arms up to 0\.2 m from the centre of mass: it overflows\.$"),
        ([Bearing("1e200 m", 1e6), Bearing(0.2, 1e6)],
         r"^Expected bearings whose stiffness matrix .* got stiffness up to 1e\+06 N/m at arms "
         r"up to 1e\+200 m"),
        ([Bearing(-0.2, 1e6, 1e308), Bearing(0.2, 1e6, 1e308)],
         r"^Expected bearings whose damping matrix .* got damping up to 1e\+308 N·s/m"),
        # The tilt stiffness Σk a² underflows: the rotor would be free to tilt.
        ([Bearing(-1e-200, 1e6), Bearing(1e-200, 1e6)],
         r"^Expected bearings far enough apart to hold the rotor's tilt in float64, got "
         r"positions \[-1e-200, 1e-200\] m"),
        ([Bearing(-0.2, 1e6), Bearing(-0.2 + 1e-9, 1e6)],
         r"^Expected bearings far enough apart .* got positions \[-0\.2, -0\.199999999\] m"),
    ],
    ids=["stiffness", "position", "damping", "underflow", "coincident"],
)  # fmt: skip
def test_bearings_whose_matrices_overflow_are_refused(bearings, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(tb.InputError, match=message):
        RigidRotor(ROD, bearings)


def test_bearings_close_together_but_resolved_are_accepted() -> None:
    # 10 µm apart at arms of 0.2 m: the scaled stiffness's smallest eigenvalue is
    # ~ (1e-5 / 0.4)² / 2 ≈ 3e-10, above the floor; the tilt frequency is then
    # √(K_θ_eff / I_t), small but resolved, and the response finite.
    rotor = RigidRotor(ROD, [Bearing(-0.2, 1e6), Bearing(-0.2 + 1e-5, 1e6)])
    assert np.all(np.isfinite(rotor.unbalance_response([100.0, 300.0], 1e-4)))


def test_speeds_and_unbalances_whose_response_overflows_are_refused() -> None:
    rotor = symmetric()
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a speed, `unbalance` and `position` whose steady orbits are finite in "
        r"float64, got 1e\+200 rad/s with 0\.0001 kg·m at 0\.0 m: they overflow\.$",
    ):
        rotor.unbalance_response([100.0, 1e200], 1e-4)
    with pytest.raises(tb.InputError, match=r"got 100\.0 rad/s with 1e\+308 kg·m at 0\.0 m"):
        rotor.unbalance_orbits(100.0, 1e308)
    disk = RigidRotor(tb.shapes.thin_disk(10.0, 0.1), [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)])
    with pytest.raises(
        tb.InputError,
        match=r"^Expected `speeds` whose gyroscopic terms I_p Ω / I_t are finite in float64, got "
        r"a speed of 1e\+308 rad/s with I_p / I_t = 2: it overflows\.$",
    ):
        disk.frequencies(1e308)


@pytest.mark.parametrize("backward", ["no", "false", 0, 1, 1.0, [True]])
def test_critical_speeds_refuses_a_backward_that_is_not_a_bool(backward) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(
        tb.InputError, match=r"^Expected `backward` to be None, True or False, got .*\.$"
    ):
        symmetric().critical_speeds(backward=backward)


def test_critical_speeds_takes_numpy_bools() -> None:
    rotor = symmetric()
    assert_allclose(rotor.critical_speeds(backward=np.True_), rotor.critical_speeds(True))
    assert_allclose(rotor.critical_speeds(backward=np.False_), rotor.critical_speeds(False))


@pytest.mark.parametrize(
    ("call", "what"),
    [
        (lambda r, s: r.frequencies(s), r"the natural frequencies at 100000 speeds \(32 bytes"),
        (lambda r, s: r.whirl(s), r"the whirl \(.*\) at 100000 speeds \(329 bytes"),
        (lambda r, s: r.state_matrices(s), r"the state matrices at 100000 speeds \(512 bytes"),
        (lambda r, s: r.unbalance_orbits(s, 1e-4), r"the unbalance orbits at 100000 speeds \(64"),
        (lambda r, s: r.unbalance_response(s, 1e-4), r"the unbalance response at 100000 speeds \(16"),
    ],
    ids=["frequencies", "whirl", "state-matrices", "orbits", "response"],
)  # fmt: skip
def test_results_larger_than_the_memory_budget_are_refused_before_the_work(
    call: Callable[[RigidRotor, np.ndarray], object], what: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 MiB")
    speeds = np.linspace(0.0, 3000.0, 100_000)
    with pytest.raises(
        tb.RequestTooLargeError,
        match=rf"^Expected a request that fits in the memory budget of 1 MiB \(TUMBLE_MEMORY_BUDGET "
        rf"= 1 MiB\), got {what}.*Ask for fewer speeds at once\.$",
    ):
        call(symmetric(), speeds)
    # One speed fits whatever the chunks' size.
    assert symmetric().frequencies(100.0).shape == (4,)


def test_many_speeds_take_memory_for_their_result_only() -> None:
    # 1e5 speeds: their (n, 8, 8) state matrices in one stack would take 51 MB;
    # in chunks of CHUNK speeds the peak is the result (3.2 MB of frequencies,
    # the input's 0.8 MB) and one chunk's matrices and eigenvalues (~3 MB).
    rotor = symmetric(c=100.0)
    speeds = np.linspace(0.0, 3000.0, 100_000)
    tracemalloc.start()
    try:
        frequencies = rotor.frequencies(speeds)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 16e6
    # The same numbers as speed by speed.
    assert_allclose(frequencies[[0, 4095, 4096, 99_999]],
                    [rotor.frequencies(s) for s in speeds[[0, 4095, 4096, 99_999]]], rtol=1e-12)  # fmt: skip
    whirl = rotor.whirl(speeds[:9000])
    assert_allclose(whirl.frequencies, frequencies[:9000], rtol=1e-12)
    response = rotor.unbalance_response(speeds[:9000], 1e-4)
    assert_allclose(response[[10, 5000, 8999]],
                    rotor.unbalance_response(speeds[[10, 5000, 8999]], 1e-4), rtol=1e-12)  # fmt: skip


@pytest.mark.parametrize(
    ("options", "error", "message"),
    [
        ({"duration": 1.0, "dt": 1e-12}, tb.RequestTooLargeError,
         r"^Expected at most max_steps = 5e\+07 steps, got duration / dt = 1 s / 1e-12 s = "
         r"1e\+12 steps: use a larger dt or a shorter duration, or raise `max_steps=`\.$"),
        ({"duration": 1e9}, tb.RequestTooLargeError,
         r"^Expected at most max_steps = 5e\+07 steps, got duration / dt = 1e\+09 s / 6\.15e-05 s "
         r"= 1\.63e\+13 steps"),
        ({"duration": 1.0, "max_steps": 1000}, tb.RequestTooLargeError,
         r"^Expected at most max_steps = 1000 steps, got duration / dt = 1 s / 6\.15e-05 s = "
         r"1\.63e\+04 steps"),
        ({"duration": 1.0, "max_steps": 0}, tb.InputError,
         r"^Expected `max_steps` to be an integer >= 1 or None, got 0\.$"),
        ({"duration": 1.0, "max_steps": 1e6}, tb.InputError,
         r"^Expected `max_steps` to be an integer >= 1 or None, got 1000000\.0\.$"),
        ({"speed": 1e300, "acceleration": 1e308, "duration": 10.0}, tb.InputError,
         r"^Expected the spin at the end of the run to be finite, got 1e\+300 rad/s \+ 1e\+308 "
         r"rad/s² × 10\.0 s = inf rad/s\.$"),
    ],
    ids=["small-dt", "long-duration", "max-steps", "zero", "float", "overflow"],
)  # fmt: skip
def test_run_ups_of_too_many_steps_bad_limits_or_overflowing_spins_are_refused(  # type: ignore[no-untyped-def]
    options, error, message
) -> None:
    with pytest.raises(error, match=message) as refusal:
        run_up(symmetric(), 1e-4, **options)
    assert type(refusal.value) is error  # a bad value is not a request too large


def test_run_up_within_max_steps_runs() -> None:
    # 0.01 s at the default step (6.15e-5 s: 200 a turn of the fastest mode) is 163 steps.
    run = run_up(symmetric(), 1e-4, duration=0.01, samples=11, max_steps=163)
    assert run.trajectory.steps == 163


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ([('stiffness = "2e6 N/m"', "stiffness = 1e308"), ('stiffness = "3e6 N/m"', "stiffness = 1e308")],
         r"line \d+, `rotordynamics`: Expected bearings whose stiffness matrix .* got stiffness up to "
         r"1e\+308 N/m"),
        ([('position = "-25 cm"', 'position = "1e200 m"')],
         r"line \d+, `rotordynamics`: Expected bearings whose stiffness matrix .* at arms up to 1e\+200 m"),
        ([('duration = "2 s"', 'duration = "1e9 s"')],
         r"line \d+, `rotordynamics`: Expected at most max_steps = 5e\+07 steps, got duration / dt = "
         r"1e\+09 s"),
    ],
    ids=["stiffness", "position", "duration"],
)  # fmt: skip
def test_the_cli_refuses_an_overflowing_rotor_scenario_in_one_line(
    changes: list[tuple[str, str]], message: str, tmp_path: Path
) -> None:
    text = builtin_text("rotor-on-bearings")
    for old, new in changes:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "rotor.toml"
    path.write_text(text)
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.output
    assert re.search(message, lines[0]), lines[0]


def test_a_run_up_of_something_other_than_a_rigid_rotor_is_refused() -> None:
    body = tb.shapes.solid_cylinder(1.0, 0.05, 0.4)
    with pytest.raises(
        tb.InputError,
        match=r"Expected `rotor` to be a tumble.theory.RigidRotor, got MassProperties\.",
    ):
        run_up(body, 1e-4, duration=1.0)
