"""``tumble fit``: the fit of the shipped recording recovers its truth, the folder
holds what replays it, the columns and units are read as asked, and every user
error is one line on stderr with exit code 2."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from tumble.cli import app
from tumble.identification import synthetic_phone
from tumble.identification.recordings import example_recording_path, read_recording

runner = CliRunner()


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def printed_ratios(out: str) -> list[tuple[float, float]]:
    """(value, standard error) of I1/I3 and I2/I3 as the table prints them."""
    rows = re.findall(r"(I[12]/I3)\s*│\s*([-0-9.e]+)\s*│\s*([-0-9.e]+)", out)
    assert [name for name, _, _ in rows] == ["I1/I3", "I2/I3"], out
    return [(float(value), float(error)) for _, value, error in rows]


@pytest.fixture(scope="module")
def example_fit(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """``tumble fit`` of the shipped recording (no argument), with its figures."""
    folder = tmp_path_factory.mktemp("fit") / "phone"
    code, out, err = invoke("fit", "-o", str(folder))
    assert code == 0, err
    return folder, out


@pytest.fixture(scope="module")
def samples() -> tuple[np.ndarray, np.ndarray]:
    recording = read_recording(example_recording_path())
    return recording.t, recording.omega


def write_csv(path: Path, header: list[str], columns: list[np.ndarray]) -> Path:
    rows = np.column_stack(columns)
    lines = [",".join(header)] + [",".join(f"{v:.17g}" for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_shipped_example_recovers_the_truth(example_fit: tuple[Path, str]) -> None:
    folder, out = example_fit
    assert out.startswith("No recording given: fitted the example shipped with tumble, ")
    truth = synthetic_phone(0).moment_ratios
    for (value, error), true in zip(printed_ratios(out), truth, strict=True):
        assert abs(value - true) < 3 * error, (value, error, true)
    assert "Window fitted: " in out and "(found: the free flight)" in out
    assert f"Fit folder: {folder}" in out.replace("\n", "")
    files = sorted(p.name for p in folder.iterdir())
    assert files == sorted(
        ["fit.json", "fitted-scenario.toml", "omega.png", "residuals.png", "polhode.png"]
    )
    for name in ("omega", "residuals", "polhode"):
        assert (folder / f"{name}.png").read_bytes().startswith(b"\x89PNG")
    summary = json.loads((folder / "fit.json").read_text())
    assert summary["files"] == files
    assert summary["recording"] == "phone-flip.csv"
    printed = printed_ratios(out)
    for k in range(2):
        assert f"{summary['moment_ratios'][k]:.5f}" == f"{printed[k][0]:.5f}"
    errors = np.sqrt(np.diag(summary["covariance"]))
    np.testing.assert_allclose(errors[:2], summary["moment_ratios_standard_error"], rtol=1e-12)
    assert summary["parameters"][:2] == ["r1", "r2"] and len(summary["parameters"]) == 11
    # The noise of the synthetic gyroscope is 0.01 rad/s: the residual is that noise.
    assert summary["residual_rms"] == pytest.approx(0.01, rel=0.1)
    assert summary["noise"] == pytest.approx(0.01, rel=0.1)


def test_the_fitted_scenario_replays_the_fitted_motion(example_fit: tuple[Path, str]) -> None:
    import tumble as tb
    from tumble.scenario import load, run

    folder, _ = example_fit
    recording = read_recording(example_recording_path())
    fit = tb.identify(recording.t, recording.omega)
    result = run(load(folder / "fitted-scenario.toml"))
    traj = result.trajectory
    assert traj.t[-1] == pytest.approx(fit.window[1] - fit.window[0], rel=1e-12)
    expected = fit.principal_rates(traj.t + fit.window[0])
    assert np.max(np.abs(traj.omega - expected)) <= 1e-9 * np.max(np.abs(expected))
    assert result.theory == "flip-period"


def test_quiet_without_figures_writes_the_rest(tmp_path: Path) -> None:
    code, out, err = invoke("fit", "--quiet", "--no-figures", "-o", str(tmp_path / "out"))
    assert (code, out, err) == (0, "", "")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "fit.json",
        "fitted-scenario.toml",
    ]


def test_the_default_folder_is_under_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "my throw.csv"
    path.write_text(example_recording_path().read_text())
    code, out, _ = invoke("fit", str(path), "--no-figures", "--no-bias", "--torque", "free")
    assert code == 0
    (folder,) = (tmp_path / "runs").iterdir()
    assert folder.name.startswith("my-throw-fit-")
    assert f"Replay: tumble run runs/{folder.name}/fitted-scenario.toml" in out.replace("\n", "")
    assert re.search(r"bias x\s*│\s*0\s*│\s*not fitted", out)
    summary = json.loads((folder / "fit.json").read_text())
    assert summary["bias_fitted"] is False and summary["bias"] == [0.0, 0.0, 0.0]
    assert len(summary["parameters"]) == 8


def test_columns_by_name_and_by_position_give_the_same_fit(
    samples: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = samples
    # Columns out of order, among others: no time column comes first.
    path = write_csv(
        tmp_path / "log.csv",
        ["gz", "gy", "gx", "seconds", "temperature"],
        [omega[:, 2], omega[:, 1], omega[:, 0], t, np.full(t.size, 21.0)],
    )
    ratios = []
    for columns in ("seconds,gx,gy,gz", "3,2,1,0"):
        folder = tmp_path / columns.replace(",", "-")
        code, out, err = invoke(
            "fit", str(path), "--columns", columns, "--units", "rad/s", "--no-figures",
            "-o", str(folder),
        )  # fmt: skip
        assert code == 0, err
        ratios.append(json.loads((folder / "fit.json").read_text())["moment_ratios"])
        assert "note:" not in out
    assert ratios[0] == ratios[1]
    code, _, err = invoke("fit", str(path), "--no-figures", "-o", str(tmp_path / "auto"))
    assert code == 2
    assert err.startswith("error: Expected a time column (named 't' or 'time…') in ")


def test_rates_in_degrees_given_or_told_from_their_size(
    samples: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = samples
    path = write_csv(tmp_path / "degrees.csv", ["t", "x", "y", "z"], [t, *np.degrees(omega).T])
    code, out, err = invoke(
        "fit", str(path), "--units", "deg/s", "--no-figures", "-o", str(tmp_path / "given")
    )
    assert code == 0, err
    assert "note:" not in out
    given = json.loads((tmp_path / "given" / "fit.json").read_text())
    code, out, err = invoke("fit", str(path), "--no-figures", "-o", str(tmp_path / "told"))
    assert code == 0, err
    told = json.loads((tmp_path / "told" / "fit.json").read_text())
    largest = np.abs(np.degrees(omega)).max()
    assert (
        f"note: read as deg/s: the largest rate, {largest:.4g}, would be "
        f"{largest / (2 * np.pi):.3g} turns/s in rad/s; --units rad/s to keep rad/s"
    ) in out.replace("\n", " ")
    assert told["note"].startswith("read as deg/s")
    assert told["moment_ratios"] == given["moment_ratios"]
    truth = synthetic_phone(0).moment_ratios
    errors = np.array(given["moment_ratios_standard_error"])
    assert np.all(np.abs(np.array(given["moment_ratios"]) - truth) < 3 * errors)


def test_a_parquet_recording_and_a_given_window(
    samples: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = samples
    path = tmp_path / "phone.parquet"
    columns = {"time": t, "wx": omega[:, 0], "wy": omega[:, 1], "wz": omega[:, 2]}
    pq.write_table(pa.table(columns), path)
    truth = synthetic_phone(0)
    # The free flight, a little inside the release and the catch.
    window = f"{truth.release + 0.01},{truth.catch - 0.01}"
    code, out, err = invoke(
        "fit", str(path), "--window", window, "--no-figures", "-o", str(tmp_path / "out")
    )
    assert code == 0, err
    assert "(as given)" in out
    for (value, error), true in zip(printed_ratios(out), truth.moment_ratios, strict=True):
        assert abs(value - true) < 3 * error
    summary = json.loads((tmp_path / "out" / "fit.json").read_text())
    assert summary["window_found"] is False
    assert truth.release + 0.01 <= summary["window"][0] < summary["window"][1] <= truth.catch


def test_an_earlier_fit_is_replaced_only_with_force(tmp_path: Path) -> None:
    folder = tmp_path / "out"
    assert invoke("fit", "-q", "-o", str(folder))[0] == 0
    code, out, err = invoke("fit", "-q", "--no-figures", "-o", str(folder))
    assert (code, out) == (2, "")
    assert err == (
        f"error: Expected an empty or new output folder, got {str(folder)!r}, which holds files "
        "(use --force to replace them).\n"
    )
    code, _, _ = invoke("fit", "-q", "--no-figures", "--force", "-o", str(folder))
    assert code == 0
    # The figures of the earlier fit are gone with it.
    assert sorted(p.name for p in folder.iterdir()) == ["fit.json", "fitted-scenario.toml"]
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    code, _, err = invoke("fit", "-q", "--force", "-o", str(other))
    assert code == 2 and "(one holding fit.json)" in err
    assert (other / "notes.txt").read_text() == "mine"


def too_few(tmp_path: Path) -> str:
    path = tmp_path / "few.csv"
    path.write_text("t,wx,wy,wz\n" + "".join(f"{k / 100},1,2,3\n" for k in range(10)))
    return str(path)


def not_a_number(tmp_path: Path) -> str:
    path = tmp_path / "cells.csv"
    path.write_text("t,wx,wy,wz\n0,1,2,3\n0.01,1,two,3\n")
    return str(path)


def a_file(tmp_path: Path) -> str:
    path = tmp_path / "taken"
    path.write_text("")
    return str(path)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (lambda p: ["nothere.csv"],
         r"^error: Expected a recording file \(CSV or Parquet\), got 'nothere\.csv' \(no such file\)\.$"),
        (lambda p: [not_a_number(p)],
         r"^error: Expected numbers in '.*cells\.csv', got 'two' at line 3, column 'wy'\.$"),
        (lambda p: [too_few(p), "--units", "rad/s"],
         r"^error: Expected at least 30 samples, got 10\.$"),
        (lambda p: ["--window", "1.3"],
         r"^error: Expected --window START,END in s \(two numbers\), got '1\.3'\.$"),
        (lambda p: ["--window", "3,2"],
         r"^error: Expected `window` start < end, both finite, got \(3\.0, 2\.0\)\.$"),
        (lambda p: ["--columns", "t,wx"],
         r"^error: Expected `columns` to be 4 names or positions \(t, ωx, ωy, ωz\), got 2: 't,wx'\.$"),
        (lambda p: ["-o", a_file(p)],
         r"^error: Expected the fit folder to be a folder, got '.*taken', which is a file\.$"),
        (lambda p: ["-o", a_file(p) + "/out"],
         r"^error: Expected the fit folder in a folder, got '.*taken/out', which is under the file '.*taken'\.$"),
        (lambda p: ["--units", "rpm"],
         r"^error: Expected --units to be 'rad/s' or 'deg/s', got 'rpm'\.$"),
        (lambda p: ["--loss", "l2"],
         r"^error: Expected --loss to be one of linear, soft_l1, huber, cauchy, arctan, got 'l2'\.$"),
    ],
)  # fmt: skip
def test_user_errors_are_one_line_and_exit_2(args: object, message: str, tmp_path: Path) -> None:
    import subprocess
    import sys

    arguments = args(tmp_path)  # type: ignore[operator]
    if arguments[0] in ("--units", "--loss"):
        # Usage errors are click's: through the script's entry point, as a user meets them.
        done = subprocess.run(
            [sys.executable, "-m", "tumble", "fit", *arguments],
            capture_output=True, text=True, check=False, cwd=tmp_path,
        )  # fmt: skip
        code, out, err = done.returncode, done.stdout, done.stderr
    else:
        output = [] if "-o" in arguments else ["-o", str(tmp_path / "out")]
        code, out, err = invoke("fit", *arguments, "--no-figures", *output)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert re.match(message, lines[0]), lines[0]
    assert not (tmp_path / "out").exists()


def test_debug_shows_the_traceback() -> None:
    from tumble.errors import InputError

    result = runner.invoke(app, ["--debug", "fit", "nothere.csv"])
    assert isinstance(result.exception, InputError)


def test_a_full_disk_while_writing_is_one_line_and_leaves_no_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno
    import os

    real = Path.write_bytes

    def write(self: Path, data: bytes) -> int:
        if self.name.startswith(".fit.json."):  # the last file written
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, data)

    monkeypatch.setattr(Path, "write_bytes", write)
    folder = tmp_path / "deep" / "out"
    code, out, err = invoke("fit", "--no-figures", "-o", str(folder))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected to write the fit folder {str(folder)!r}, got: No space left "
        "on device (free some space or write elsewhere)."
    ]
    assert list(tmp_path.iterdir()) == []


def test_ratios_just_outside_the_triangle_inequality_replay_the_nearest_body() -> None:
    import dataclasses

    import tumble as tb
    from tumble.report.fit import fitted_scenario
    from tumble.scenario import parse

    recording = read_recording(example_recording_path())
    fit = tb.identify(recording.t, recording.omega)
    # A flat plate's ratios, with noise that puts their sum just below 1.
    plate = dataclasses.replace(fit, moment_ratios=np.array([0.3, 0.6999]))
    text = fitted_scenario(plate, "plate-fit", "plate.csv")
    assert "their sum is 0.9999" in text
    body = parse(text).spec.body
    assert np.diag(body.inertia) == pytest.approx([0.3001, 0.6999, 1.0], rel=1e-12)


def test_every_loss_of_the_library_is_taken_and_named_in_the_help(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import tumble.identification.fit
    from tumble.errors import InputError
    from tumble.identification.validation import LOSSES

    code, out, _ = invoke("fit", "--help")
    assert code == 0
    for loss in LOSSES:
        assert loss in out
    # Each reaches the fit as given (the fit itself is the library's, tested there).
    given = []

    def identify(*args: object, loss: str, **kwargs: object) -> None:
        given.append(loss)
        raise InputError("stop here")

    monkeypatch.setattr(tumble.identification.fit, "identify", identify)
    for loss in LOSSES:
        code, _, err = invoke("fit", "--loss", loss, "--no-figures", "-o", str(tmp_path / "out"))
        assert (code, err) == (2, "error: stop here\n")
    assert given == list(LOSSES)


@pytest.mark.slow  # the fits tried before the refusal: 10 s and more
def test_rates_too_small_for_any_body_are_refused(
    samples: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    # The shipped recording with a header that says rad/s of rates in radians
    # twice over (np.radians applied to rad/s): refused, one line.
    from tumble.identification.recordings import phyphox_csv

    t, omega = samples
    path = tmp_path / "twice.csv"
    path.write_text(phyphox_csv(t, np.radians(omega)))
    code, out, err = invoke("fit", str(path), "--no-figures", "-o", str(tmp_path / "out"))
    assert code == 2 and out == ""
    (line,) = err.strip().splitlines()
    assert re.match(
        r"^error: Expected a sensor bias smaller than the rates measured, got a fit whose bias "
        r"\([\d.]+ rad/s\) exceeds the rates' median \([\d.]+ rad/s\): the rates look too small "
        r"for their unit .* were they in deg/s read as rad/s \(57\.3 times\), or in turn/s "
        r"\(6\.28 times\)\?",
        line,
    ), line
    assert not (tmp_path / "out").exists()


def test_a_recording_beyond_the_memory_budget_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "100 kB")
    code, out, err = invoke("fit", "--no-figures", "-o", str(tmp_path / "out"))
    assert code == 2 and out == ""
    (line,) = err.strip().splitlines()
    assert re.match(
        r"^error: Expected a request that fits in the memory budget of 97\.7 KiB "
        r"\(TUMBLE_MEMORY_BUDGET = 100 kB\), got the recording '.*phone-flip\.csv' of 8\d(\.\d)? KiB, "
        r"about 1\.8\de\+03 samples: about .*\. Cut the recording to the throw",
        line,
    ), line
    assert not (tmp_path / "out").exists()


@pytest.mark.slow  # 74000 samples written, read, averaged and fitted: 10 s and more
def test_a_recording_sampled_far_too_fast_is_averaged_and_says_so(tmp_path: Path) -> None:
    # The phone at 20 kHz: 74000 samples, averaged 4 at a time. Oracle: the truth.
    from tumble.identification.recordings import phyphox_csv

    phone = synthetic_phone(0, rate=20_000.0)
    path = tmp_path / "fast.csv"
    path.write_text(phyphox_csv(phone.t, phone.omega))
    code, out, err = invoke("fit", str(path), "--no-figures", "-o", str(tmp_path / "out"))
    assert code == 0, err
    assert re.search(
        r"note: averaged 4 samples at a time \(7\d{4} samples at about 20 kHz to 1\d{4}; each "
        r"average spans 0\.00\d+ rad of turn at most\)",
        out.replace("\n", " "),
    ), out
    summary = json.loads((tmp_path / "out" / "fit.json").read_text())
    assert summary["fit_note"].startswith("averaged 4 samples at a time")
    errors = np.array(summary["moment_ratios_standard_error"])
    assert np.all(np.abs(np.array(summary["moment_ratios"]) - phone.moment_ratios) < 3 * errors)
    # The noise of the averages, σ/2, is what the residuals are compared with.
    assert summary["noise"] == pytest.approx(phone.noise / 2, rel=0.1)
    assert summary["residual_rms"] == pytest.approx(phone.noise / 2, rel=0.15)
