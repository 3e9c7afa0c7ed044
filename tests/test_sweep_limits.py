"""A sweep's size is bounded before anything is built or written: its work (bodies
× steps), its store and its plan are estimated from the file and refused past
limits that the file's [limits] raises, with the estimate in the message."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import pytest
from typer.testing import CliRunner

from test_sweep import SMALL, sweep_text
from tumble.cli import app
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import body_bytes
from tumble.sweep.schema import SweepError

#: SMALL has 3 × 10 grid points × 4 draws = 120 bodies and 150 steps of 0.01 s.
LONG = {"duration = 1.5": 'duration = "1e9 s"'}


def test_a_sweep_of_too_many_body_steps_is_refused_with_its_estimate() -> None:
    # 120 bodies × 1e11 steps: years of work on one machine.
    with pytest.raises(
        SweepError,
        match=r"^<sweep>, `limits.max_body_steps`: Expected at most max_body_steps = 1e\+12 "
        r"body-steps \(bodies × steps per body\), got 120 bodies × 1e\+11 steps = 1\.2e\+13: "
        r"raise `max_body_steps` in \[limits\] to run it, or ask for fewer bodies or steps\.$",
    ):
        parse_sweep(sweep_text(SMALL, **LONG))


def test_the_limit_of_body_steps_is_raised_in_the_file() -> None:
    text = sweep_text(SMALL, **LONG) + "\n[limits]\nmax_body_steps = 1e14\n"
    plan = parse_sweep(text)  # checked only: not run
    assert plan.n_steps == 10**11 and plan.n_bodies == 120
    lower = SMALL + "\n[limits]\nmax_body_steps = 17_999\n"  # 120 × 150 = 18000
    with pytest.raises(
        SweepError,
        match=r"line 41, `limits.max_body_steps`: Expected at most max_body_steps = 17999 "
        r"body-steps \(bodies × steps per body\), got 120 bodies × 150 steps = 18000",
    ):
        parse_sweep(lower)
    assert parse_sweep(SMALL + "\n[limits]\nmax_body_steps = 18_000\n").n_bodies == 120


def test_a_closed_form_counts_one_evaluation_a_body() -> None:
    # The exact method evaluates each body once, whatever the duration.
    exact = sweep_text(SMALL, **LONG, **{"dt = 0.01": 'dt = 0.01\nmethod = "exact"'})
    exact = exact.replace("[vary.damping]\nstart = 0\nstop = 0.02\nnum = 10\n", "")
    exact = exact.replace(
        '[vary.body_torque_1]\ndistribution = "uniform"\nmin = -0.05\nmax = 0.05\n', ""
    )
    assert parse_sweep(exact).n_steps == 10**11
    with pytest.raises(
        SweepError,
        match=r"Expected at most max_body_steps = 10 body-steps \(bodies × steps per body\), "
        r"got 12 bodies × 1 evaluation of the closed form = 12:",
    ):
        parse_sweep(exact + "\n[limits]\nmax_body_steps = 10\n")


def test_a_store_too_large_is_refused_with_its_estimate() -> None:
    # 3e9 bodies of one step each: few body-steps, but hundreds of GB of results.
    text = sweep_text(
        SMALL, **{"samples = 4": "samples = 100_000_000", "duration = 1.5": "duration = 0.01"}
    )
    per_body = body_bytes(parse_sweep(SMALL))
    assert per_body == 8 * 5 + 8 * (3 + 3 + 3 + 4) + 4 + 8 * 4 + 1  # parameters, states, metrics
    with pytest.raises(
        SweepError,
        match=r"^<sweep>, `limits.max_store_bytes`: Expected results of at most max_store_bytes "
        r"= 1e\+11 bytes \(93\.1 GiB\), got 3e\+09 bodies × 181 bytes = 5\.43e\+11 bytes "
        r"\(506 GiB\) uncompressed: raise `max_store_bytes` in \[limits\] to run it \(the disk "
        r"must hold it\), or ask for fewer bodies or outputs\.$",
    ):
        parse_sweep(text)
    plan = parse_sweep(text + "\n[limits]\nmax_store_bytes = 1e12\n")
    assert plan.n_bodies == 3 * 10**9


def test_a_plan_too_large_to_write_is_refused_before_it_is_built() -> None:
    # A 1e7 × 1e7 grid: 1e14 bodies, and 2e7 grid values, which sweep.json and the
    # store's attributes would list (hundreds of MB) before any work.
    text = sweep_text(
        SMALL,
        **{
            "values = [1.2, 1.5, 1.8]": "start = 1.2\nstop = 1.8\nnum = 1_000_000",
            "num = 10\n": "num = 1_000_000\n",
        },
    )
    tracemalloc.start()
    try:
        with pytest.raises(
            SweepError,
            match=r"^<sweep>, line 16, `vary`: Expected at most 1e\+06 grid values in all "
            r"\(sweep\.json and the store list them\), got 2e\+06 \(ratio_2: 1000000, damping: "
            r"1000000\): draw a parameter at random \(`distribution`, `min`, `max`\) to sample "
            r"it finely\.$",
        ):
            parse_sweep(text)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    # Nothing of the grid's size was allocated: its 2e6 values would take 16 MB.
    assert peak < 4_000_000
    with pytest.raises(
        SweepError, match=r"`vary.damping.num`: Expected a value less than or equal to 1000000"
    ):
        parse_sweep(sweep_text(SMALL, **{"num = 10\n": "num = 10_000_000\n"}))


@pytest.mark.parametrize(
    ("table", "message"),
    [
        (
            "max_body_steps = 0",
            r"`limits.max_body_steps`: Expected a value greater than or equal to 1",
        ),
        (
            'max_body_steps = "1e12"',
            r"`limits.max_body_steps`: Expected a valid number, got '1e12'",
        ),
        ("max_store_bytes = inf", r"`limits.max_store_bytes`: Expected a finite number"),
        (
            "max_steps = 5",
            r"`limits.max_steps`: Expected the key to be one of max_body_steps, max_store_bytes",
        ),
    ],
)
def test_limits_are_checked(table: str, message: str) -> None:
    with pytest.raises(SweepError, match=message):
        parse_sweep(f"{SMALL}\n[limits]\n{table}\n")


def test_the_command_line_refuses_a_runaway_sweep_in_one_line_before_writing(
    tmp_path: Path,
) -> None:
    source = tmp_path / "long.toml"
    source.write_text(sweep_text(SMALL, **LONG), encoding="utf-8")
    result = CliRunner().invoke(app, ["sweep", str(source), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    (line,) = result.stderr.strip().splitlines()
    assert line.startswith(
        "error: long.toml, `limits.max_body_steps`: Expected at most max_body_steps = 1e+12 "
        "body-steps (bodies × steps per body), got 120 bodies × 1e+11 steps = 1.2e+13: raise "
    )
    assert not (tmp_path / "out").exists()
