"""`tumble run`, `tumble list`, `tumble show`: output, run folders, one-line errors."""

from __future__ import annotations

import errno
import json
import os
import re
import tempfile
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tumble import sweep
from tumble.cli import app
from tumble.scenario import builtin_names, builtin_text

runner = CliRunner()

# A fast scenario for the command line's own behaviour (the physics is tested elsewhere).
QUICK = """
[scenario]
name = "quick"
title = "A quick free top"

[body]
shape = "box"
mass = "1 kg"
size = "10, 20, 30 cm"

[initial]
omega = "3, 0.1, 0.1 rad/s"    # about x, the intermediate axis: it flips

[simulation]
duration = "5 s"

[output]
samples = 500
figures = false
viewer = false
"""
FULL = QUICK.replace("figures = false\nviewer = false", "viewer_frames = 20")


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def quick(tmp_path: Path) -> Path:
    path = tmp_path / "quick.toml"
    path.write_text(QUICK)
    return path


def test_list_names_every_builtin_on_one_line() -> None:
    code, out, _ = invoke("list")
    assert code == 0
    lines = out.splitlines()
    names = builtin_names()
    assert [line.split()[0] for line in lines[: len(names)]] == names
    assert lines[0].startswith("gyroscope ") and "precession" in lines[0]


def test_show_prints_the_toml_to_copy(tmp_path: Path) -> None:
    code, out, _ = invoke("show", "skew-rod")
    assert code == 0
    assert out == builtin_text("skew-rod")
    code, out, err = invoke("show", "skewrod")
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected a built-in scenario or sweep to be one of {SCENARIOS}, {SWEEPS}, "
        "got 'skewrod'. Did you mean skew-rod?"
    ]


# Found by glob: a built-in added to the package is listed with no edit here.
SCENARIOS = ", ".join(builtin_names())
SWEEPS = ", ".join(sweep.builtin_sweeps())


def test_show_prints_a_builtin_sweep() -> None:
    from tumble.sweep import show_sweep

    code, out, _ = invoke("show", "flip-map")
    assert code == 0 and out == show_sweep("flip-map")


@pytest.mark.parametrize(
    ("name", "hint"),
    [
        # A file of one's own: show prints only what tumble ships.
        ("base.toml", ". That is a file of your own: `tumble show` prints the files tumble ships."),
        ("gyroscope.toml", ". Did you mean gyroscope?"),
        ("flip-map.toml", ". Did you mean flip-map?"),
        ("nothing-like-it", "."),
    ],
)
def test_show_refuses_what_is_not_a_builtin_without_offering_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, hint: str
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "base.toml").write_text(QUICK)
    code, out, err = invoke("show", name)
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected a built-in scenario or sweep to be one of {SCENARIOS}, {SWEEPS}, "
        f"got {name!r}{hint}"
    ]


def test_show_cuts_a_long_name() -> None:
    code, _, err = invoke("show", "n" * 5000)
    assert code == 2
    assert f"got {'n' * 60!r}...." in err and len(err) < 500


def test_run_a_folder_says_it_is_a_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir").mkdir()
    code, _, err = invoke("run", "adir")
    assert code == 2
    assert err.strip() == "error: Expected a scenario file, got 'adir' (a folder)."


def test_run_a_builtin_sweep_points_to_tumble_sweep() -> None:
    code, _, err = invoke("run", "flip-map")
    assert code == 2
    assert err.strip() == (
        f"error: Expected a built-in scenario to be one of {SCENARIOS}, or a .toml file, got "
        "'flip-map'. That is a built-in sweep: run it with `tumble sweep flip-map`."
    )


@pytest.mark.parametrize("suffix", ["", ".toml"])
def test_run_cuts_a_long_name(suffix: str) -> None:
    code, _, err = invoke("run", "n" * 5000 + suffix)
    assert code == 2
    assert f"got {'n' * 60!r}..." in err and len(err) < 500


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_deeply_nested_toml_is_one_line(tmp_path: Path, command: str) -> None:
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 1000 + "]" * 1000 + "\n")
    code, _, err = invoke(command, str(path), "-o", str(tmp_path / "out"))
    assert code == 2
    assert re.fullmatch(
        r"error: \S*deep\.toml: Expected arrays and inline tables nested at most a few hundred "
        r"levels deep, got 1000 levels\.",
        err.strip(),
    )


def test_a_file_with_a_byte_order_mark_runs(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + QUICK.encode())
    code, _, err = invoke("run", str(path), "-o", str(tmp_path / "out"), "--quiet")
    assert code == 0, err


def test_run_a_file_writes_the_folder_and_prints_the_report(quick: Path, tmp_path: Path) -> None:
    quick.write_text(FULL)
    out_dir = tmp_path / "out"
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 0, err
    assert "A quick free top" in out
    assert "Theory (flip-period) vs simulation" in out
    assert f"Report: {out_dir / 'report.html'}" in out.replace("\n", "")
    for name in ("trajectory.parquet", "summary.json", "report.html", "viewer.html", "omega.png"):
        assert (out_dir / name).is_file()


def test_run_prints_why_nothing_was_compared(quick: Path, tmp_path: Path) -> None:
    # ω along z, a principal axis of the box: a steady spin, nothing to compare.
    quick.write_text(QUICK.replace('"3, 0.1, 0.1 rad/s"', '"0, 0, 3 rad/s"'))
    code, out, err = invoke("run", str(quick), "-o", str(tmp_path / "out"))
    assert code == 0, err
    assert "Theory" not in out
    assert re.search(
        r"Note: no theory comparison: the body spins about a principal axis \(I1 = [\d.]+ "
        r"kg·m²\), where the free-body solution is a steady spin; nothing to compare\.",
        " ".join(out.split()),
    ), out


@pytest.mark.parametrize(
    ("flags", "figures", "viewer"),
    [(["--no-figures"], False, True), (["--no-viewer"], True, False),
     (["--no-figures", "--no-viewer"], False, False)],
)  # fmt: skip
def test_figures_and_the_viewer_can_be_left_out(
    quick: Path, tmp_path: Path, flags: list[str], figures: bool, viewer: bool
) -> None:
    quick.write_text(FULL)
    out_dir = tmp_path / "out"
    code, _, err = invoke("run", str(quick), "-o", str(out_dir), "-q", *flags)
    assert code == 0, err
    assert (out_dir / "omega.png").is_file() == figures
    assert (out_dir / "viewer.html").is_file() == viewer
    summary = json.loads((out_dir / "summary.json").read_text())
    assert ("omega.png" in summary["files"]) == figures
    assert ("<img" in (out_dir / "report.html").read_text()) == figures


def test_json_prints_the_summary(quick: Path, tmp_path: Path) -> None:
    code, out, _ = invoke("run", str(quick), "-o", str(tmp_path / "j"), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["scenario"] == "quick"
    assert summary["report"] == str(tmp_path / "j" / "report.html")
    assert summary["comparisons"][0]["quantity"] == "flip period"
    assert summary["comparisons"][0]["relative_error"] < 1e-6
    # A free body: the energy and the vector L are conserved, and only they are shown.
    assert set(summary["drift"]) == {"energy", "angular_momentum_vector"}


def test_quiet_prints_nothing(quick: Path, tmp_path: Path) -> None:
    code, out, err = invoke("run", str(quick), "-o", str(tmp_path / "q"), "--quiet")
    assert code == 0 and out == "" and err == ""


def test_rerun_into_a_folder_asks_for_force(quick: Path, tmp_path: Path) -> None:
    out_dir = tmp_path / "again"
    assert invoke("run", str(quick), "-o", str(out_dir), "-q")[0] == 0
    stamp = (out_dir / "summary.json").stat().st_mtime_ns
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected an empty or new output folder, got {str(out_dir)!r}, which holds files "
        "(use --force to replace them)."
    ]
    assert (out_dir / "summary.json").stat().st_mtime_ns == stamp  # untouched
    code, _, _ = invoke("run", str(quick), "-o", str(out_dir), "--force", "-q")
    assert code == 0 and (out_dir / "summary.json").stat().st_mtime_ns != stamp


def test_default_folder_is_under_runs(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, _ = invoke("run", str(quick))
    assert code == 0
    (folder,) = (tmp_path / "runs").iterdir()
    assert folder.name.startswith("quick-")
    assert f"Report: runs/{folder.name}/report.html" in out.replace("\n", "")
    # A second run in the same second gets its own folder.
    assert invoke("run", str(quick), "-q")[0] == 0
    assert len(list((tmp_path / "runs").iterdir())) == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            QUICK.replace('mass = "1 kg"', 'mass = "1 m"'),
            r"^error: .*quick\.toml, line 8, `body\.mass`: Expected `mass` to be a mass in kg, got 1 m \(dimensions \[length\]\)\.$",
        ),
        (
            QUICK.replace("[output]", "[ouptut]"),
            r"^error: .*quick\.toml, line 17, `ouptut`: Expected the key to be one of .*, got 'ouptut'\. Did you mean output\?$",
        ),
        (
            QUICK.replace('duration = "5 s"', 'duration = "0 s"'),
            r"^error: .*`simulation\.duration`: Expected `duration` > 0 s, got 0\.0\.$",
        ),
        (
            QUICK.replace("[body]", "[body"),
            r"^error: .*quick\.toml: Expected valid TOML, got an error: .*\(at line 6, column 6\)\.$",
        ),
    ],
)
def test_user_errors_are_one_line_and_exit_2(text: str, message: str, tmp_path: Path) -> None:
    path = tmp_path / "quick.toml"
    path.write_text(text)
    code, out, err = invoke("run", str(path), "-o", str(tmp_path / "out"))
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert re.match(message, lines[0]), lines[0]
    assert not (tmp_path / "out").exists()  # nothing written before the error


def test_missing_file_and_unknown_scenario() -> None:
    code, _, err = invoke("run", "nothere.toml")
    assert code == 2
    assert err.strip() == "error: Expected a scenario file, got 'nothere.toml' (no such file)."
    code, _, err = invoke("run", "gyroskope")
    assert code == 2 and err.strip().endswith("got 'gyroskope'. Did you mean gyroscope?")


def test_debug_shows_the_traceback(tmp_path: Path) -> None:
    from tumble.scenario import ScenarioError

    result = runner.invoke(app, ["--debug", "run", "nothere.toml"])
    assert isinstance(result.exception, ScenarioError)


def test_progress_bar_appears_for_slow_runs(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tumble.cli.progress import LazyProgress

    shown: list[str] = []
    monkeypatch.setattr(LazyProgress, "DELAY", 0.0)
    original = LazyProgress._show

    def spy(self: LazyProgress) -> bool:
        visible = original(self)
        if visible:
            shown.append(self.description)
        return visible

    monkeypatch.setattr(LazyProgress, "_show", spy)
    assert invoke("run", str(quick), "-o", str(tmp_path / "p"))[0] == 0
    assert shown and any(d.startswith("writing") for d in shown)
    shown.clear()
    assert invoke("run", str(quick), "-o", str(tmp_path / "p2"), "--quiet")[0] == 0
    assert shown == []


def test_list_and_show_include_example_sweeps() -> None:
    sweep = pytest.importorskip("tumble.sweep")
    examples = sweep.builtin_sweeps()
    if not examples:
        pytest.skip("no example sweeps shipped")
    code, out, _ = invoke("list")
    assert code == 0
    for name in examples:
        assert any(line.split()[:2] == [name, "sweep:"] for line in out.splitlines())
    name = next(iter(examples))
    code, out, _ = invoke("show", name)
    assert code == 0 and out == sweep.show_sweep(name)


# ----------------------------------------------------------- a hostile file system
@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make any simulation fail loudly: the output must be refused before it."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("simulated before checking the output")

    monkeypatch.setattr("tumble.scenario.run", refuse)


def only_entries(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.mark.usefixtures("no_simulation")
def test_an_output_under_a_file_is_refused_before_simulating(quick: Path, tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("")
    out_dir = tmp_path / "notes.txt" / "run"
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected the run folder in a folder, got {str(out_dir)!r}, which is under "
        f"the file {str(tmp_path / 'notes.txt')!r}."
    ]
    assert only_entries(tmp_path) == ["notes.txt", "quick.toml"]


@pytest.mark.usefixtures("no_simulation")
def test_a_device_as_the_output_is_refused_before_simulating(quick: Path) -> None:
    code, _, err = invoke("run", str(quick), "-o", "/dev/null/x")
    assert code == 2
    assert err.strip().splitlines() == [
        "error: Expected the run folder in a folder, got '/dev/null/x', which is under the "
        "file '/dev/null'."
    ]


@pytest.mark.usefixtures("no_simulation")
def test_a_folder_that_cannot_be_written_is_refused_before_simulating(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The permission is mocked: the superuser (CI) may write anywhere.
    locked = tmp_path / "locked"
    locked.mkdir()
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: Path(p) != locked and real(p, mode))
    code, _, err = invoke("run", str(quick), "-o", str(locked / "run"))
    assert code == 2
    assert err.strip().splitlines() == [
        f"error: Expected the run folder in a folder that can be written, got "
        f"{str(locked / 'run')!r}: {str(locked)!r} cannot be written (permission denied, or a "
        "read-only file system)."
    ]
    assert only_entries(locked) == []


def test_a_permission_lost_while_writing_is_one_line_and_leaves_nothing(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The folder passed the check, then the permission went (or the superuser
    # met a read-only mount): the staging folder cannot even be made.
    import tempfile

    real = tempfile.mkdtemp

    def denied(*args: object, **kwargs: object) -> str:
        if kwargs.get("suffix") == ".tumble.partial":  # the staging folder, not the check's probe
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(tempfile, "mkdtemp", denied)
    out_dir = tmp_path / "run"
    code, _, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2
    assert err.strip().splitlines() == [
        f"error: Expected to write the run folder {str(out_dir)!r}, got: Permission denied "
        "(choose a folder you can write to)."
    ]
    assert only_entries(tmp_path) == ["quick.toml"]


def full_disk_at(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Raise ENOSPC when a file called ``name`` is written (by its temporary)."""
    real = Path.write_bytes

    def write(self: Path, data: bytes) -> int:
        if self.name.startswith(f".{name}."):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, data)

    monkeypatch.setattr(Path, "write_bytes", write)


def test_a_full_disk_while_writing_is_one_line_and_leaves_no_partial_folder(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    full_disk_at("report.html", monkeypatch)  # after the Parquet file
    out_dir = tmp_path / "run"
    code, out, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"error: Expected to write the run folder {str(out_dir)!r}, got: No space left on "
        "device (free some space or write elsewhere)."
    ]
    assert only_entries(tmp_path) == ["quick.toml"]


def test_warnings_come_before_the_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # dt of 0.1 s at 3 rad/s: about 20 steps a turn at most, a CoarseStepWarning;
    # then the disk fills while the report is written.
    path = tmp_path / "coarse.toml"
    path.write_text(
        QUICK.replace('duration = "5 s"', 'duration = "5 s"\ndt = "0.2 s"\nmethod = "rk4"')
    )
    full_disk_at("report.html", monkeypatch)
    code, _, err = invoke("run", str(path), "-o", str(tmp_path / "run"))
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 2
    assert lines[0].startswith("warning: ") and "steps per turn" in lines[0]
    assert lines[1].startswith("error: Expected to write the run folder")


def test_a_failed_write_removes_the_folders_it_created_above_the_run(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    full_disk_at("report.html", monkeypatch)
    (tmp_path / "kept").mkdir()
    out_dir = tmp_path / "kept" / "new" / "deeper" / "run"
    code, _, err = invoke("run", str(quick), "-o", str(out_dir))
    assert code == 2 and "No space left on device" in err
    assert only_entries(tmp_path) == ["kept", "quick.toml"]
    assert list((tmp_path / "kept").iterdir()) == []


def test_a_full_disk_while_replacing_a_run_keeps_the_old_one(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out_dir = tmp_path / "run"
    assert invoke("run", str(quick), "-o", str(out_dir), "-q")[0] == 0
    before = {p.name: p.read_bytes() for p in out_dir.iterdir()}
    full_disk_at("summary.json", monkeypatch)
    code, _, err = invoke("run", str(quick), "-o", str(out_dir), "--force")
    assert code == 2 and "No space left on device" in err
    assert {p.name: p.read_bytes() for p in out_dir.iterdir()} == before
    assert only_entries(tmp_path) == ["quick.toml", "run"]


def test_a_request_beyond_the_memory_budget_is_one_line(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "10 kB")
    code, _, err = invoke("run", str(quick), "-o", str(tmp_path / "run"))
    assert code == 2
    (line,) = err.strip().splitlines()
    assert re.fullmatch(
        r"error: .*quick\.toml, line \d+, `simulation`: Expected a request that fits in the "
        r"memory budget of 9\.77 KiB \(TUMBLE_MEMORY_BUDGET = 10 kB\), got [\d.e+]+ recorded "
        r"samples of 8 values .*: about [\d.]+ KiB\. Ask for fewer samples in \[output\], or a "
        r"shorter duration or a larger dt in \[simulation\]\.",
        line,
    )
    assert only_entries(tmp_path) == ["quick.toml"]


def test_errors_of_the_standard_output_are_one_line(tmp_path: Path) -> None:
    # /dev/full: every write fails with ENOSPC.
    import subprocess
    import sys

    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full here")
    with open("/dev/full", "w") as full:
        done = subprocess.run(
            [sys.executable, "-c", "from tumble.cli import main; main()", "list"],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            check=False,
        )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "error: Expected to read or write the output, got: No space left on device."
    ]


def test_running_out_of_memory_is_one_line(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def exhausted(*args: object, **kwargs: object) -> None:
        raise MemoryError("Unable to allocate 7.28 TiB")

    monkeypatch.setattr("tumble.scenario.run", exhausted)
    code, _, err = invoke("run", str(quick), "-o", str(tmp_path / "run"))
    assert code == 2
    assert err.strip().splitlines() == [
        "error: Expected the request to fit in memory, got a MemoryError (Unable to allocate "
        "7.28 TiB): record fewer samples, or run a sweep, which streams its results to disk."
    ]


def test_warm_up_runs_each_scenario_and_keeps_nothing(
    quick: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", None)  # TMPDIR is read again
    code, out, err = invoke("warm-up", str(quick))
    assert code == 0, err
    assert re.fullmatch(r"quick: ready \(\d+\.\d s\)\n", out)
    assert only_entries(tmp_path) == ["quick.toml"]


def test_warm_up_of_an_unknown_scenario_is_one_line() -> None:
    code, out, err = invoke("warm-up", "gyroscop")
    assert code == 2 and out == ""
    (line,) = err.strip().splitlines()
    assert line.startswith("error: ") and "gyroscope" in line
