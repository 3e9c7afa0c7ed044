"""``tumble fit --windows`` and ``--all``: many throws of one body fitted alone and
together recover the body they were made from, the folder holds the table, the joint
fit, the report and what replays it, and every user error is one line with exit code 2."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from tumble.cli import app
from tumble.identification.recordings import phyphox_csv
from tumble.identification.throws import ThrowsRecording, synthetic_throws

runner = CliRunner()

#: The racquet of synthetic_throws and of the shipped many-throw recording.
TRUE_RATIOS = (0.067, 0.94)


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def write_throws(folder: Path, throws: ThrowsRecording) -> tuple[Path, Path]:
    """The recording as phyphox writes it, and its true windows as a windows file."""
    recording = folder / "throws.csv"
    recording.write_text(phyphox_csv(throws.t, throws.omega))
    windows = folder / "windows.csv"
    rows = "".join(f"{start!r},{end!r}\n" for start, end in throws.windows)
    windows.write_text("start,end\n" + rows)
    return recording, windows


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, ThrowsRecording]:
    """A recording of two throws, for the errors (refused before any fit)."""
    folder = tmp_path_factory.mktemp("small")
    throws = synthetic_throws(2, seed=1)
    write_throws(folder, throws)
    return folder, throws


@pytest.fixture(scope="module")
def three(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str, ThrowsRecording]:
    """``tumble fit --windows`` of three throws under drag, the last 40 % of each held out
    (the default), with the figures and the report."""
    folder = tmp_path_factory.mktemp("three")
    throws = synthetic_throws(3, seed=2)
    recording, windows = write_throws(folder, throws)
    out = folder / "out"
    code, printed, err = invoke(
        "fit", str(recording), "--windows", str(windows), "--torque", "drag", "-o", str(out)
    )
    assert code == 0, err
    return out, printed, throws


@pytest.mark.slow  # three throws fitted whole and in part, and drawn: 20 s and more
def test_three_throws_recover_the_body_and_fill_the_folder(
    three: tuple[Path, str, ThrowsRecording],
) -> None:
    from tumble.scenario import parse
    from tumble.scenario.bodies import InertiaBody

    out, printed, throws = three
    files = sorted(p.name for p in out.iterdir())
    assert files == sorted(
        [
            "fit.json",
            "fitted-scenario.toml",
            "joint.json",
            "ratios.png",
            "report.html",
            "residuals.png",
            "throws.csv",
            "throws.parquet",
        ]
    )
    listing = json.loads((out / "fit.json").read_text())
    assert listing["files"] == files and listing["hold_out"] == 0.4
    assert listing["windows"] == [list(window) for window in throws.windows]
    # In CSV an empty text is an empty field, which pandas reads as missing.
    table = pd.read_csv(out / "throws.csv", dtype={"reason": "string", "torque": "string"})
    table[["reason", "torque"]] = table[["reason", "torque"]].fillna("")
    pd.testing.assert_frame_equal(table, pd.read_parquet(out / "throws.parquet"), check_dtype=False)
    assert table["throw"].tolist() == [1, 2, 3] and table["fitted"].all()
    summary = json.loads((out / "joint.json").read_text())
    joint = summary["joint"]
    # Oracle: the truth the recording was made from. The standard errors come from the
    # covariance of residuals that are the sensor's white noise alone, so the truth lies
    # within 3 of them in each ratio but for 0.3 % of noise draws (a fixed seed here).
    errors = np.array(joint["moment_ratios_standard_error"])
    assert np.all(np.abs(np.array(joint["moment_ratios"]) - TRUE_RATIOS) < 3 * errors)
    drag = np.array(joint["torque_parameters"])
    drag_errors = np.array(joint["torque_parameters_standard_error"])
    assert np.all(np.abs(drag - throws.drag) < 3 * drag_errors)
    assert joint["torque"] == "drag" and joint["torque_units"] == "1/s"
    assert sorted(joint["throws"] + joint["outliers"]) == [1, 2, 3]
    assert joint["outlier_count"] == len(joint["outliers"])
    assert table["outlier"].tolist() == [n in joint["outliers"] for n in (1, 2, 3)]
    # Each joint throw's held-out end is forecast; the forecast follows the measured
    # rates to well under their size (a wrong body drifts by tens of % in 0.3 s).
    forecast = table["forecast_error"].to_numpy()
    joint_rows = np.isin(table["throw"], joint["throws"])
    assert np.all(forecast[joint_rows] < 0.1) and summary["forecast_error_median"] < 0.1
    # The joint body replays: its moments are the joint ratios.
    body = parse((out / "fitted-scenario.toml").read_text()).spec.body
    assert isinstance(body, InertiaBody)
    assert np.diag(body.inertia) == pytest.approx([*joint["moment_ratios"], 1.0], rel=1e-12)
    page = (out / "report.html").read_text()
    assert page.count('alt="throws"') == 1  # the three throws in one row
    assert 'alt="ratios"' in page and 'alt="residuals"' in page
    # Printed: a row per throw with its ratios, the joint fit, the forecast and the files.
    text = printed.replace("\n", " ")
    for row in table.itertuples():
        shown = rf"\b{row.throw}\s+{row.start:.4g}–{row.end:.4g}\s+drag\s+0\.06\d*\(\d+\)\s+0\.9"
        assert re.search(shown, text), text
    assert re.search(r"I1/I3\s+│\s+" + f"{joint['moment_ratios'][0]:.4f}", text)
    assert "Forecast of the held-out last 40 % of each throw, median error: " in text
    assert f"Fit folder: {out}" in text and f"Replay: tumble run {out}" in text


@pytest.mark.slow  # the twelve throws of the shipped recording fitted: a minute and more
def test_every_throw_of_the_shipped_recording(tmp_path: Path) -> None:
    out = tmp_path / "all"
    code, printed, err = invoke(
        "fit", "--all", "--torque", "drag", "--hold-out", "0", "--no-figures", "-q", "-o", str(out)
    )
    assert (code, printed, err) == (0, "", "")
    listing = json.loads((out / "fit.json").read_text())
    assert listing["windows_found"] is True and len(listing["windows"]) == 12
    assert "ratios.png" not in listing["files"] and "report.html" in listing["files"]
    # The free flights found lie inside the true ones (the release and the catch cut off).
    truth = synthetic_throws(12, seed=0)
    for (start, end), (release, last) in zip(listing["windows"], truth.windows, strict=True):
        assert release - 1e-9 <= start < end <= last + 1e-9
    joint = json.loads((out / "joint.json").read_text())["joint"]
    # As above: noise-only residuals, the truth within 3 standard errors of each ratio.
    errors = np.array(joint["moment_ratios_standard_error"])
    assert np.all(np.abs(np.array(joint["moment_ratios"]) - TRUE_RATIOS) < 3 * errors)
    # Twelve throws know the body better than one: 1e-3 is a single throw's error.
    assert np.all(errors < 1e-3)
    assert len(joint["throws"]) >= 10


@pytest.mark.slow  # uses the fit of three throws
def test_a_many_throw_folder_is_replaced_only_with_force(
    three: tuple[Path, str, ThrowsRecording], tmp_path: Path
) -> None:
    folder = tmp_path / "out"
    shutil.copytree(three[0], folder)
    code, out, err = invoke("fit", "--all", "-q", "-o", str(folder))
    assert (code, out) == (2, "")
    assert err == (
        f"error: Expected an empty or new output folder, got {str(folder)!r}, which holds files "
        "(use --force to replace them).\n"
    )
    # Its fit.json lists what it wrote: --force replaces it as it does a single fit's.
    code, _, err = invoke("fit", "-q", "--no-figures", "--force", "-o", str(folder))
    assert code == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["fit.json", "fitted-scenario.toml"]


def overlapping(folder: Path, throws: ThrowsRecording) -> str:
    (start, end), _ = throws.windows
    path = folder / "overlapping.csv"
    path.write_text(f"start,end\n{start},{end}\n{end - 0.1},{end + 0.5}\n")
    return str(path)


def outside(folder: Path, throws: ThrowsRecording) -> str:
    path = folder / "outside.csv"
    path.write_text(f"start,end\n{throws.windows[0][0]},{throws.windows[0][1]}\n90,91\n")
    return str(path)


def short(folder: Path, throws: ThrowsRecording) -> str:
    start = throws.windows[0][0]
    path = folder / "short.csv"
    path.write_text(f"start,end\n{start},{start + 0.1}\n")  # 11 samples at 100 Hz
    return str(path)


def no_columns(folder: Path, throws: ThrowsRecording) -> str:
    path = folder / "columns.csv"
    path.write_text("from,to\n1,2\n")
    return str(path)


def not_numbers(folder: Path, throws: ThrowsRecording) -> str:
    path = folder / "words.csv"
    path.write_text("start,end\n1,2\nthree,4\n")
    return str(path)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (
            lambda f, t: ["--windows", str(f / "windows.csv"), "--all"],
            r"Expected one of --window, --windows and --all, got --windows and --all\.$",
        ),
        (
            lambda f, t: ["--window", "1,2", "--all"],
            r"Expected one of --window, --windows and --all, got --window and --all\.$",
        ),
        (
            lambda f, t: ["--window", "1,2", "--windows", str(f / "windows.csv")],
            r"Expected one of --window, --windows and --all, got --window and --windows\.$",
        ),
        (
            lambda f, t: ["--hold-out", "0.3"],
            r"Expected --hold-out with --windows or --all \(a fit of many throws\), got "
            r"--hold-out 0\.3 alone\.$",
        ),
        (
            lambda f, t: ["--all", "--hold-out", "0.9"],
            r"Expected --hold-out a fraction in \[0, 0\.9\), got 0\.9\.$",
        ),
        (
            lambda f, t: ["--windows", overlapping(f, t)],
            r"Expected windows that do not overlap, got window 1 \([\d.]+–[\d.]+ s\) and "
            r"window 2 \([\d.]+–[\d.]+ s\)\.$",
        ),
        (
            lambda f, t: ["--windows", outside(f, t)],
            r"Expected window 2 inside the recording \(0–[\d.]+ s\), got 90–91 s\.$",
        ),
        (
            lambda f, t: ["--windows", short(f, t)],
            r"Expected at least 30 samples in window 1, got 11 in [\d.]+–[\d.]+ s\.$",
        ),
        (
            lambda f, t: ["--windows", no_columns(f, t)],
            r"Expected columns named start and end in '.*columns\.csv', got columns 'from', "
            r"'to'\.$",
        ),
        (
            lambda f, t: ["--windows", not_numbers(f, t)],
            r"Expected numbers \(s\) for start and end in '.*words\.csv', got 'three', '4' in "
            r"row 2 after the header\.$",
        ),
        (
            lambda f, t: ["--windows", str(f / "nothere.csv")],
            r"Expected a CSV file of windows, got '.*nothere\.csv' \(no such file\)\.$",
        ),
    ],
)
def test_bad_options_and_windows_are_one_line_and_exit_2(
    options: object, message: str, small: tuple[Path, ThrowsRecording], tmp_path: Path
) -> None:
    folder, throws = small
    arguments = options(folder, throws)  # type: ignore[operator]
    out = tmp_path / "out"
    code, printed, err = invoke(
        "fit", str(folder / "throws.csv"), *arguments, "--torque", "drag", "-o", str(out)
    )
    assert code == 2 and printed == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert re.match("^error: " + message, lines[0]), lines[0]
    assert not out.exists()


def test_the_table_gives_each_value_to_its_error_in_its_last_digits() -> None:
    from tumble.cli.fit_many import concise

    # Two significant digits of the error fix the decimals of the value.
    assert concise(0.066387, 0.00037) == "0.06639(37)"
    assert concise(0.0673, 0.002) == "0.0673(20)"
    assert concise(12.34, 1.5) == "12.3(15)"
    assert concise(1.0, 0.0) == "1.000000"  # no error: six decimals, none shown
