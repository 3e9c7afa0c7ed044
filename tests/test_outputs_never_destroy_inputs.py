"""Outputs that never destroy what is there: a FIFO, a device or a socket is never
replaced by a file, and ``--force`` replaces an earlier run's (or fit's) own folder
only, never the input being run nor a file the run did not write."""

from __future__ import annotations

import json
import os
import shutil
import socket
import stat
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tumble.cli import app
from tumble.errors import InputError, OutputError
from tumble.files import (
    check_output,
    check_regular_file,
    check_replaceable,
    write_bytes,
    write_text,
)
from tumble.identification.recordings import example_recording_path
from tumble.locks import OutputLock, staged_folder

runner = CliRunner()

QUICK = """
[scenario]
name = "quick"

[body]
shape = "box"
mass = "1 kg"
size = "10, 20, 30 cm"

[initial]
omega = "3, 0.1, 0.1 rad/s"

[simulation]
duration = "1 s"

[output]
samples = 50
figures = false
viewer = false
"""


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def is_fifo(path: Path) -> bool:
    return stat.S_ISFIFO(os.lstat(path).st_mode)


# ------------------------------------------------------------ special files
def test_the_null_device_is_refused_as_an_output_before_any_write() -> None:
    # Only the check: were it to let /dev/null through, nothing is written to it here.
    with pytest.raises(
        OutputError,
        match=r"^Expected the report to be a regular file or a new path, got '/dev/null', "
        r"a character device\.$",
    ):
        check_output("/dev/null", "the report", folder=False)
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_a_fifo_is_refused_as_an_output_file_and_as_an_output_folder(fifo: Path) -> None:
    with pytest.raises(
        OutputError,
        match=r"^Expected the report to be a regular file or a new path, got '.*pipe', a FIFO\.$",
    ):
        check_output(fifo, "the report", folder=False)
    with pytest.raises(
        OutputError,
        match=r"^Expected the run folder to be a folder or a new path, got '.*pipe', a FIFO\.$",
    ):
        check_output(fifo, "the run folder", folder=True)
    assert is_fifo(fifo)


@pytest.mark.parametrize("write", [write_text, write_bytes])
def test_the_writers_never_replace_a_fifo(fifo: Path, write: object) -> None:
    data = "text" if write is write_text else b"bytes"
    with pytest.raises(
        OutputError,
        match=r"^Expected the file to be a regular file or a new path, got '.*pipe', a FIFO\.$",
    ):
        write(fifo, data)  # type: ignore[operator]
    assert is_fifo(fifo)
    assert sorted(os.listdir(fifo.parent)) == ["pipe"]  # no temporary file left


def test_a_socket_is_refused_as_an_output(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # a short path: sockets' names are limited to ~100 bytes
    with socket.socket(socket.AF_UNIX) as server:
        server.bind("s")
        with pytest.raises(OutputError, match=r"got 's', a socket\.$"):
            write_text("s", "x")
        assert stat.S_ISSOCK(os.lstat("s").st_mode)


def test_a_link_to_a_fifo_is_refused(fifo: Path) -> None:
    link = fifo.with_name("link")
    link.symlink_to(fifo)
    with pytest.raises(OutputError, match=r"got '.*link', a FIFO\.$"):
        write_text(link, "x")
    assert is_fifo(fifo) and link.is_symlink()


def test_a_regular_file_and_a_new_path_are_still_written(tmp_path: Path) -> None:
    write_text(tmp_path / "new.txt", "one")
    write_text(tmp_path / "new.txt", "two")
    assert (tmp_path / "new.txt").read_text() == "two"


def test_a_staged_folder_never_replaces_a_fifo(fifo: Path) -> None:
    with pytest.raises(OutputError, match=r"got '.*pipe', a FIFO\."):
        OutputLock(fifo, "the run folder").acquire()
    # Even without the lock's check, the move leaves anything but a folder alone.
    with pytest.raises(OSError), staged_folder(fifo) as staging:
        (staging / "summary.json").write_text("{}")
    assert is_fifo(fifo)


def test_run_and_sweep_outputs_refuse_a_fifo(fifo: Path, tmp_path: Path) -> None:
    scenario = tmp_path / "quick.toml"
    scenario.write_text(QUICK)
    code, out, err = invoke("run", str(scenario), "-o", str(fifo), "-q")
    assert (code, out) == (2, "")
    assert err.strip().splitlines() == [
        f"error: Expected the run folder to be a folder or a new path, got {str(fifo)!r}, a FIFO."
    ]
    code, _, err = invoke("fit", "-q", "--no-figures", "-o", str(fifo))
    assert code == 2 and err.strip().endswith(f"got {str(fifo)!r}, a FIFO.")
    code, _, err = invoke("sweep", "flip-map", "-q", "-o", str(fifo))
    assert code == 2 and err.strip().endswith(f"got {str(fifo)!r}, a FIFO.")
    assert is_fifo(fifo)


def test_a_file_to_read_must_be_a_regular_file(fifo: Path, tmp_path: Path) -> None:
    with pytest.raises(
        InputError, match=r"^Expected the recording to be a regular file, got '.*pipe', a FIFO\.$"
    ):
        check_regular_file(fifo, "the recording")
    check_regular_file(tmp_path / "missing", "the recording")  # left to the caller's message
    with pytest.raises(InputError, match=r"got '/dev/zero', a character device\.$"):
        check_regular_file("/dev/zero", "the mesh")


# ------------------------------------------------------------ --force
def test_run_force_never_deletes_the_scenario_it_runs(tmp_path: Path) -> None:
    folder = tmp_path / "R"
    scenario = tmp_path / "s.toml"
    scenario.write_text(QUICK)
    assert invoke("run", str(scenario), "-o", str(folder), "-q")[0] == 0
    moved = folder / "s.toml"
    shutil.move(scenario, moved)
    before = sorted(os.listdir(folder))
    code, out, err = invoke("run", str(moved), "-o", str(folder), "--force", "-q")
    assert (code, out) == (2, "")
    assert err.strip().splitlines() == [
        f"error: Expected the run folder to hold none of the files read, got {str(folder)!r}, "
        f"which holds {str(moved)!r}: name another folder."
    ]
    assert sorted(os.listdir(folder)) == before and moved.read_text() == QUICK


def test_run_force_never_deletes_a_file_the_run_did_not_write(tmp_path: Path) -> None:
    folder = tmp_path / "R"
    scenario = tmp_path / "s.toml"
    scenario.write_text(QUICK)
    assert invoke("run", str(scenario), "-o", str(folder), "-q")[0] == 0
    (folder / "notes.txt").write_text("mine")
    code, _, err = invoke("run", str(scenario), "-o", str(folder), "--force", "-q")
    assert code == 2
    assert err.strip().splitlines() == [
        f"error: Expected the run folder to hold only the files its summary.json lists to "
        f"replace it whole, got {str(folder)!r}, which holds 'notes.txt' too: move it away, "
        "or name another folder."
    ]
    assert (folder / "notes.txt").read_text() == "mine"
    # An earlier run's own folder is still replaced.
    (folder / "notes.txt").unlink()
    assert invoke("run", str(scenario), "-o", str(folder), "--force", "-q")[0] == 0
    listed = json.loads((folder / "summary.json").read_text())["files"]
    assert sorted(os.listdir(folder)) == sorted(listed)


def test_fit_force_never_deletes_the_recording_it_fits(tmp_path: Path) -> None:
    folder = tmp_path / "F"
    assert invoke("fit", "-q", "--no-figures", "-o", str(folder))[0] == 0
    recording = folder / "r.csv"
    shutil.copy(example_recording_path(), recording)
    before = sorted(os.listdir(folder))
    code, out, err = invoke(
        "fit", str(recording), "-q", "--no-figures", "-o", str(folder), "--force"
    )
    assert (code, out) == (2, "")
    assert err.strip().splitlines() == [
        f"error: Expected the fit folder to hold none of the files read, got {str(folder)!r}, "
        f"which holds {str(recording)!r}: name another folder."
    ]
    assert sorted(os.listdir(folder)) == before


def test_fit_force_never_deletes_a_recording_named_as_a_fits_file(tmp_path: Path) -> None:
    # A recording whose name the fit's own record lists is still an input.
    folder = tmp_path / "F"
    assert invoke("fit", "-q", "--no-figures", "-o", str(folder))[0] == 0
    recording = folder / "fitted-scenario.toml"
    shutil.copy(example_recording_path(), recording)
    code, _, err = invoke(
        "fit", str(recording), "--columns", "0,1,2,3", "-q", "--no-figures", "-o", str(folder),
        "--force",
    )  # fmt: skip
    assert code == 2 and "to hold none of the files read" in err
    assert recording.read_bytes() == example_recording_path().read_bytes()


def test_fit_force_never_deletes_other_files(tmp_path: Path) -> None:
    folder = tmp_path / "F"
    assert invoke("fit", "-q", "--no-figures", "-o", str(folder))[0] == 0
    (folder / "sub").mkdir()
    code, _, err = invoke("fit", "-q", "--no-figures", "-o", str(folder), "--force")
    assert code == 2
    assert err.strip().endswith(
        f"got {str(folder)!r}, which holds 'sub' too: move it away, or name another folder."
    )
    assert (folder / "sub").is_dir()


def test_check_replaceable_follows_links_to_inputs(tmp_path: Path) -> None:
    folder = tmp_path / "R"
    folder.mkdir()
    (folder / "summary.json").write_text('{"files": ["summary.json", "s.toml"]}')
    (folder / "s.toml").write_text("")
    (tmp_path / "link.toml").symlink_to(folder / "s.toml")
    with pytest.raises(OutputError, match=r"which holds '.*link\.toml': name another folder\.$"):
        check_replaceable(folder, "the run folder", listed_in="summary.json",
                          inputs=[tmp_path / "link.toml"])  # fmt: skip
    # Listed, and no input: replaceable.
    check_replaceable(folder, "the run folder", listed_in="summary.json", inputs=[])
    check_replaceable(tmp_path / "new", "the run folder", listed_in="summary.json")
