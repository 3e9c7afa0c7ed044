"""Requests that cannot fit are refused before any work, with the estimate and the fix."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import tumble as tb
from tumble.batch import PEAK_PER_VALUE as BATCH_PEAK
from tumble.batch import PER_BODY, PER_RECORD
from tumble.errors import RequestTooLargeError
from tumble.integrators.limits import PEAK_PER_VALUE
from tumble.resources import (
    BUDGET_VARIABLE,
    format_bytes,
    machine_memory,
    memory_budget,
    usable_memory,
)

BOX = tb.shapes.box(1.0, [0.1, 0.2, 0.3])


@pytest.fixture
def budget(monkeypatch: pytest.MonkeyPatch) -> float:
    """A fixed budget of 1 GiB, whatever the machine."""
    monkeypatch.setenv(BUDGET_VARIABLE, "1 GiB")
    return float(2**30)


def never(*args: object) -> None:
    raise AssertionError("work started before the request was checked")


def test_a_billion_seconds_at_a_millisecond_is_refused_with_its_size(budget: float) -> None:
    # 1e12 steps recorded: 1e12 + 2 samples of t, ω, q (8 values), each taking
    # PEAK_PER_VALUE bytes at the end of the run: 2.56e14 B = 233 TiB.
    expected = format_bytes((1e12 + 2) * 8 * PEAK_PER_VALUE)
    assert expected == "233 TiB"
    with pytest.raises(
        RequestTooLargeError,
        match=re.escape(
            "Expected a request that fits in the memory budget of 1 GiB (TUMBLE_MEMORY_BUDGET "
            "= 1 GiB), got 1e+12 recorded samples of 8 values (1e+09 s at dt = 0.001 s, every "
            "1 step): about 233 TiB. Record less often (record_every), or ask for a shorter "
            "duration or a larger dt."
        ),
    ):
        tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1e9, dt=1e-3, progress=never)


def test_the_same_run_recording_less_often_fits(budget: float) -> None:
    run = tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1.0, dt=1e-3, record_every=100)
    assert len(run.t) == 11


def test_a_million_bodies_recorded_at_every_step_are_refused_with_the_sweep_advice(
    budget: float,
) -> None:
    n = 10**6
    inertia = np.tile([1.0, 2.0, 3.0], (n, 1))
    omega = np.tile([0.1, 2.0, 0.1], (n, 1))
    # 1e7 steps, a record each (+ the first and the last), 7 values a record.
    needed = n * (PER_BODY + (1e7 + 2) * 7 * BATCH_PEAK) + (1e7 + 2) * PER_RECORD
    with pytest.raises(
        RequestTooLargeError,
        match=re.escape(
            f"got 1000000 bodies × 1e+07 records of 7 values (10000000 steps, every 1): about "
            f"{format_bytes(needed)}. Record less often (record_every, or None for the final "
            "states only), or ask for fewer bodies at once; or run a sweep (tumble.sweep.run_sweep, "
            "`tumble sweep`), which streams its results to disk as it goes."
        ),
    ):
        tb.simulate_batch(inertia, omega, duration=1e4, dt=1e-3, record_every=1, progress=never)


def test_a_batch_of_only_final_states_is_sized_by_its_bodies(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Each body: its arrays, and its final state (7 values).
    needed = 1000 * (PER_BODY + 7 * BATCH_PEAK)
    monkeypatch.setenv(BUDGET_VARIABLE, str(needed - 1))
    inertia = np.tile([1.0, 2.0, 3.0], (1000, 1))
    with pytest.raises(
        RequestTooLargeError,
        match=r"got 1000 bodies: about [\d.]+ KiB\. Ask for fewer bodies at once; or run a sweep",
    ):
        tb.simulate_batch(inertia, inertia, duration=1.0, dt=0.1, progress=never)
    monkeypatch.setenv(BUDGET_VARIABLE, str(needed))
    tb.simulate_batch(inertia, inertia, duration=1.0, dt=0.1)


def test_more_steps_than_float_times_can_count_are_refused() -> None:
    with pytest.raises(
        RequestTooLargeError,
        match=r"Expected at most 2\^53 steps \(step times are counted in float64\), got "
        r"duration / dt = 1e\+09 s / 1e-300 s = inf steps: use a larger dt or a shorter "
        r"duration\.",
    ):
        tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1e9, dt=1e-300, record_every=10**9)
    with pytest.raises(RequestTooLargeError, match=r"= 1e\+17 steps: use a larger dt"):
        tb.simulate_batch(
            [[1.0, 2.0, 3.0]], [[1.0, 2.0, 3.0]], duration=1e14, dt=1e-3, progress=never
        )


@pytest.mark.parametrize(
    ("text", "expected"),
    [("16 GiB", 16 * 2**30), ("500 MB", 5e8), ("123456", 123456.0), (" 2 kB ", 2000.0)],
)
def test_the_budget_is_read_from_the_environment(
    text: str, expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(BUDGET_VARIABLE, text)
    assert memory_budget() == (
        pytest.approx(expected, rel=1e-15),
        f"{BUDGET_VARIABLE} = {text.strip()}",
    )


# "3 🍕 GiB" and "1,5 GiB": pint alone would read 3 GiB and 15 GiB.
@pytest.mark.parametrize(
    "text", ["lots", "-1 GB", "0", "3 m", "nan", "inf B", "3 🍕 GiB", "1,5 GiB"]
)
def test_a_budget_that_is_no_amount_of_memory_is_refused(
    text: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(BUDGET_VARIABLE, text)
    with pytest.raises(
        tb.InputError,
        match=re.escape(
            f"Expected TUMBLE_MEMORY_BUDGET to be an amount of memory > 0 such as '16 GiB', "
            f"got {text!r}."
        ),
    ):
        memory_budget()


def test_the_default_budget_is_half_the_usable_memory(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    usable, why = usable_memory()
    assert machine_memory() == usable
    budget, source = memory_budget()
    assert usable > 0 and budget == usable / 2
    assert source == (
        f"half of the {format_bytes(usable)} this process may use, {why}; set "
        "TUMBLE_MEMORY_BUDGET to change it"
    )


def fake_cgroups(root: Path, memberships: str, limits: dict[str, str]) -> Path:
    """A /proc/self/cgroup holding ``memberships`` and, under ``root`` (the place of
    /sys/fs/cgroup), the limit files ``limits`` (path relative to it: content)."""
    proc = root / "proc"
    proc.mkdir()
    (proc / "cgroup").write_text(memberships)
    for name, text in limits.items():
        path = root / "cgroup" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return proc


@pytest.mark.parametrize(
    ("memberships", "limits", "expected", "file"),
    [
        # cgroup v2, the limit on the process's own cgroup, nested below the root.
        ("0::/jobs/run-7\n", {"memory.max": "max\n", "jobs/run-7/memory.max": "1048576\n"},
         2**20, "jobs/run-7/memory.max"),
        # v2: a parent's limit applies to every cgroup below it.
        ("0::/jobs/run-7\n", {"jobs/memory.max": "2097152\n", "jobs/run-7/memory.max": "max\n"},
         2**21, "jobs/memory.max"),
        # cgroup v1: the memory controller's hierarchy, nested; others ignored.
        ("4:memory:/batch/42\n3:cpuset:/\n",
         {"memory/memory.limit_in_bytes": "9223372036854771712\n",
          "memory/batch/42/memory.limit_in_bytes": "3145728\n"},
         3 * 2**20, "memory/batch/42/memory.limit_in_bytes"),
        # A container whose own cgroup is the root of its mount (a path of the host).
        ("0::/docker/abc\n", {"memory.max": "4194304\n"}, 2**22, "memory.max"),
    ],
)  # fmt: skip
def test_a_container_limit_lowers_the_usable_memory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, memberships: str, limits: dict[str, str],
    expected: int, file: str,
) -> None:  # fmt: skip
    proc = fake_cgroups(tmp_path, memberships, limits)
    monkeypatch.setattr("tumble.resources._PROC_SELF", proc)
    monkeypatch.setattr("tumble.resources._CGROUP_ROOT", tmp_path / "cgroup")
    usable, why = usable_memory()
    assert usable == expected == machine_memory()
    assert why == f"the memory limit of its cgroup, {tmp_path / 'cgroup' / file}"


def test_without_a_container_limit_the_machine_s_memory_is_usable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    proc = fake_cgroups(tmp_path, "0::/a\n", {"memory.max": "max\n", "a/memory.max": "max\n"})
    monkeypatch.setattr("tumble.resources._PROC_SELF", proc)
    monkeypatch.setattr("tumble.resources._CGROUP_ROOT", tmp_path / "cgroup")
    usable, why = usable_memory()
    assert why == "the machine's memory"
    assert usable > 2**20


# The child runs a recording of about 10 GiB (4e7 steps of t, ω, q at 32 bytes
# a value) under an address-space limit of 3 GiB (`ulimit -v`).
LIMITED_CHILD = """
import sys
import tumble as tb
from tumble.errors import RequestTooLargeError
box = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
try:
    tb.simulate(box, [1.0, 2.0, 3.0], duration=float(sys.argv[1]), dt=1e-3, method="rk4")
except RequestTooLargeError as error:
    print("refused:", error)
else:
    print("ran")
"""


def run_limited(duration: float) -> str:
    """What the child says after a run of ``duration`` s under a 3 GiB address space."""
    import os
    import resource
    import subprocess
    import sys

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, resource.RLIM_INFINITY))

    env = {k: v for k, v in os.environ.items() if k != BUDGET_VARIABLE}
    done = subprocess.run(
        [sys.executable, "-c", LIMITED_CHILD, str(duration)], preexec_fn=limit, env=env,
        capture_output=True, text=True, timeout=600,  # a safety net, not a measure
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip()


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc (Linux)")
def test_an_address_space_limit_lowers_the_budget() -> None:
    said = run_limited(4e4)
    assert said.startswith("refused: Expected a request that fits in the memory budget of "), said
    assert re.search(
        r"this process may use, its address-space limit \(ulimit -v\) of 3 GiB less the "
        r"[\d.]+ [KMG]iB it has mapped; set TUMBLE_MEMORY_BUDGET to change it\), got 4e\+07 "
        r"recorded samples",
        said,
    ), said
    # A run that fits in what is left runs.
    assert run_limited(10.0) == "ran"


@pytest.mark.parametrize(
    ("amount", "text"),
    [
        (0, "0 B"),
        (1023, "1023 B"),
        (1536, "1.5 KiB"),
        (2**40, "1 TiB"),
        (2**60, "1024 PiB"),
    ],
)
def test_amounts_of_memory_read_as_people_write_them(amount: float, text: str) -> None:
    assert format_bytes(amount) == text


# ----------------------------------------------------------------------- sweeps
SWEEP = """
[sweep]
name = "roomy"
seed = 1
samples = 10
chunk_size = 5

[base]
duration = 1.0
dt = 0.01
moment_1 = 1.0
ratio_3 = 2.0
spin_axis = 2
spin_rate = "1 rad/s"

[vary.ratio_2]
values = [1.2, 1.5]
"""


def test_a_sweep_whose_chunks_cannot_fit_asks_for_smaller_chunks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tumble.sweep import run_sweep
    from tumble.sweep.build import parse_sweep

    monkeypatch.setenv(BUDGET_VARIABLE, "100 B")
    with pytest.raises(
        RequestTooLargeError,
        match=r"got chunks of 5 bodies: about [\d.]+ KiB\. Ask for a smaller chunk_size in "
        r"\[sweep\]: the chunks stream to disk one by one\.",
    ):
        run_sweep(parse_sweep(SWEEP), tmp_path / "out", progress=never)
    assert not (tmp_path / "out").exists()


def test_a_sweep_short_of_disk_space_warns_that_it_can_resume(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import shutil

    from tumble.sweep import run_sweep
    from tumble.sweep.build import parse_sweep

    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=100))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_sweep(parse_sweep(SWEEP), tmp_path / "out")
    messages = [str(w.message) for w in caught if "free" in str(w.message)]
    assert len(messages) == 1
    assert re.fullmatch(
        r"The sweep's 4 chunks to compute take up to [\d.]+ KiB uncompressed, and "
        r"'.*out' has 100 B free: if the disk fills, free some space and run the sweep again "
        r"\(it resumes\)\.",
        messages[0],
    )


def test_a_few_bodies_recorded_often_are_sized_by_their_records(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # One body, 1e6 records: the arrays of each record cost ~1.1 KiB whatever
    # the number of bodies (measured), more than the body's 7 values.
    needed = PER_BODY + (1e6 + 2) * (7 * BATCH_PEAK + PER_RECORD)
    monkeypatch.setenv(BUDGET_VARIABLE, str(needed - 1))
    with pytest.raises(RequestTooLargeError, match=r"got 1 bodies × 1e\+06 records"):
        tb.simulate_batch(
            [[1.0, 2.0, 3.0]], [[1.0, 2.0, 3.0]], duration=1e3, dt=1e-3, record_every=1,
            progress=never,
        )  # fmt: skip


def test_a_gyrocompass_recording_too_much_is_refused_before_it_starts(budget: float) -> None:
    # 1e4 s at 1 µs, every step kept: 1e10 + 1 samples of t, ω, q and θ, θ̇, χ.
    expected = format_bytes((1e10 + 1) * 11 * PEAK_PER_VALUE)
    with pytest.raises(
        RequestTooLargeError,
        match=re.escape(
            f"got 1e+10 recorded samples of 11 values (1e+04 s at dt = 1e-06 s, every 1 step): "
            f"about {expected}. Record less often (record_every or samples), or ask for a "
            "shorter duration or a larger dt."
        ),
    ):
        tb.models.gyrocompass(
            tb.shapes.solid_cylinder(1.0, 0.1, 0.02), 100.0, 2.0, 0.3, duration=1e4, dt=1e-6,
            progress=never,
        )  # fmt: skip


def test_a_fixed_step_run_beyond_max_steps_is_refused_before_it_starts() -> None:
    with pytest.raises(
        RequestTooLargeError,
        match=re.escape(
            "Expected at most max_steps = 1000 steps, got duration / dt = 10 s / 0.001 s = "
            "10000 steps: use a larger dt or a shorter duration, or raise `max_steps=`."
        ),
    ):
        tb.simulate(BOX, [1.0, 2.0, 3.0], duration=10.0, dt=1e-3, method="rk4", max_steps=1000,
                    progress=never)  # fmt: skip


def test_an_adaptive_run_stops_at_max_steps() -> None:
    # ω of 1e7 rad/s about a non-principal direction: the steps follow the
    # motion (~1e-8 s), so 10 s would take ~1e9 of them; it stops at 1e4.
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected the adaptive integration to end within 1e\+04 steps \(max_steps\), got "
        r"1e\+04 steps to t = [\d.e-]+ s of 10 s: the motion is too fast or too stiff for it;",
    ):
        tb.simulate(BOX, [1e7, 1.0, 0.0], duration=10.0, dt=1.0, method="adaptive",
                    max_steps=10_000)  # fmt: skip
    # Below the limit it runs, and says how many steps it took.
    run = tb.simulate(BOX, [1.0, 1.0, 0.0], duration=10.0, dt=0.01, method="adaptive",
                      max_steps=10_000)  # fmt: skip
    assert 0 < run.steps <= 10_000


@pytest.mark.parametrize("value", [0, -3, 1.5, True, "10"])
def test_max_steps_is_a_positive_integer(value: object) -> None:
    with pytest.raises(
        tb.InputError,
        match=rf"^Expected `max_steps` to be an integer >= 1 or None, got {re.escape(repr(value))}\.$",
    ):
        tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1.0, max_steps=value)  # type: ignore[arg-type]


def test_the_default_max_steps_is_finite_and_shared_with_the_scenarios() -> None:
    import inspect

    from tumble.resources import DEFAULT_MAX_STEPS
    from tumble.scenario.schema import MAX_STEPS

    default = inspect.signature(tb.simulate).parameters["max_steps"].default
    assert default == DEFAULT_MAX_STEPS == MAX_STEPS == 50_000_000
    assert "max_steps : the most steps the run may take (default 5e7" in (tb.simulate.__doc__ or "")


def test_a_fixed_step_run_beyond_the_default_max_steps_is_refused_before_it_starts() -> None:
    with pytest.raises(
        RequestTooLargeError,
        match=re.escape(
            "Expected at most max_steps = 5e+07 steps, got duration / dt = 100000 s / 0.001 s = "
            "100000000 steps: use a larger dt or a shorter duration, or raise `max_steps=`."
        ),
    ):
        tb.simulate(BOX, [1.0, 2.0, 3.0], duration=1e5, dt=1e-3, method="rk4",
                    record_every=10**6, progress=never)  # fmt: skip


def test_the_adaptive_method_stops_at_max_steps() -> None:
    # A mild damper (D (1/J + 1/I_p) ≈ 2.1 1/s, far inside any step's stability)
    # at rtol 1e-10 takes 150 steps over 10 s: with room for 30 it
    # stops at max_steps, saying how to raise it. (A stiff part is refused
    # before any step: tests/test_spring_mass.py.)
    body = tb.MassProperties(1.0, [0, 0, 0], np.diag([2.0, 2.0, 1.0]))
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected the adaptive integration to end within 30 steps \(max_steps\), got "
        r"30 steps to t = [\d.e-]+ s of 10 s: .* or raise `max_steps=` \(default 5e7\)\.$",
    ):
        tb.simulate(body, [0.01, 0.0, 1.0], duration=10.0, method="adaptive", max_steps=30,
                    internal=[tb.KaneDamper(0.05, 0.1)])  # fmt: skip
