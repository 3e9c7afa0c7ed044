"""Output locations checked before any work; errors of the file system as one clear
error; one writer of an output at a time, and what a killed writer left removed."""

from __future__ import annotations

import errno
import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import warnings
from pathlib import Path

import pytest

from tumble.errors import OutputError, OutputInUseError
from tumble.files import check_output, output_error, replaced, write_text
from tumble.locks import OutputLock


def test_a_folder_that_is_a_file_and_a_file_that_is_a_folder_are_refused(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(
        OutputError, match=r"Expected the output to be a folder, got '.*file', which is a file\."
    ):
        check_output(tmp_path / "file", "the output", folder=True)
    with pytest.raises(
        OutputError, match=r"Expected the output to be a file, got '.*', which is a folder\."
    ):
        check_output(tmp_path, "the output", folder=False)


@pytest.mark.parametrize("depth", [1, 3])
def test_a_path_under_a_file_names_the_file(tmp_path: Path, depth: int) -> None:
    (tmp_path / "notes.txt").write_text("")
    target = tmp_path.joinpath("notes.txt", *(["sub"] * (depth - 1)), "out")
    with pytest.raises(
        OutputError,
        match=r"Expected the output in a folder, got '.*out', which is under the file "
        r"'.*notes\.txt'\.",
    ) as caught:
        check_output(target, "the output", folder=True)
    assert caught.value.path == str(target)


def test_a_device_is_not_a_folder() -> None:
    with pytest.raises(OutputError, match=r"which is under the file '/dev/null'"):
        check_output("/dev/null/x", "the run folder", folder=True)


def test_folders_that_cannot_be_written_are_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A mocked permission check: the superuser may write anywhere, so a chmod
    # alone cannot make the case under CI (the test below does it as a user).
    locked = tmp_path / "locked"
    locked.mkdir()
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: Path(p) != locked and real(p, mode))
    with pytest.raises(
        OutputError,
        match=r"Expected the output in a folder that can be written, got '.*locked/new/out': "
        r"'.*locked' cannot be written \(permission denied, or a read-only file system\)\.",
    ):
        check_output(locked / "new" / "out", "the output", folder=False)
    with pytest.raises(
        OutputError,
        match=r"Expected the output to be a folder that can be written, got '.*locked' "
        r"\(permission denied",
    ):
        check_output(locked, "the output", folder=True)


@pytest.mark.skipif(os.geteuid() == 0, reason="the superuser may write anywhere")
def test_a_read_only_folder_is_refused(tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    with pytest.raises(OutputError, match=r"'.*locked' cannot be written"):
        check_output(locked / "out", "the output", folder=True)


def test_a_name_too_long_for_the_file_system_is_refused(tmp_path: Path) -> None:
    # Room is left for the prefix and suffix of the temporary names beside it.
    longest = os.pathconf(tmp_path, "PC_NAME_MAX")
    with pytest.raises(
        OutputError,
        match=rf"Expected the output with names of at most {longest - 24} bytes, got .* has "
        rf"{longest + 45} bytes \(use a shorter name\)\.",
    ):
        check_output(tmp_path / ("x" * (longest + 45)), "the output", folder=True)
    check_output(tmp_path / ("x" * (longest - 24)), "the output", folder=True)
    # Only the output itself gets a temporary name: the folders made above it,
    # and a folder written into (a sweep's), may take the whole length.
    check_output(tmp_path / ("y" * longest) / "out", "the output", folder=True)
    check_output(tmp_path / ("z" * longest), "the output", folder=True, staged=False)
    with pytest.raises(OutputError, match=rf"names of at most {longest} bytes, got .* has "):
        check_output(tmp_path / ("z" * (longest + 1)), "the output", folder=True, staged=False)


def test_a_broken_link_is_refused_as_the_output_and_above_it(tmp_path: Path) -> None:
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "gone")
    with pytest.raises(
        OutputError,
        match=r"Expected the output at a path that exists or can be made, got '.*link', a "
        r"broken symbolic link \(remove it or write elsewhere\)\.",
    ):
        check_output(link, "the output", folder=True)
    with pytest.raises(
        OutputError, match=r"got '.*link/run', which is under the broken link '.*link'\."
    ):
        check_output(link / "run", "the output", folder=True)


def test_a_folder_where_nothing_can_be_created_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Permissions can say yes where creating fails (the superuser on /proc, a
    # read-only mount): the check tries to create a folder there.
    import tempfile

    real = tempfile.mkdtemp

    def refused(*args: object, **kwargs: object) -> str:
        if kwargs.get("dir") == tmp_path:
            raise OSError(errno.EROFS, os.strerror(errno.EROFS))
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(tempfile, "mkdtemp", refused)
    with pytest.raises(OutputError, match=r"'.*' cannot be written \(permission denied"):
        check_output(tmp_path / "run", "the output", folder=True)


def test_missing_folders_above_a_writable_one_are_accepted(tmp_path: Path) -> None:
    check_output(tmp_path / "a" / "b" / "c", "the output", folder=True)
    check_output(tmp_path / "a" / "b" / "file.parquet", "the output", folder=False)
    assert not (tmp_path / "a").exists()  # checking creates nothing


@pytest.mark.parametrize(
    ("code", "advice"),
    [
        (errno.ENOSPC, "free some space or write elsewhere"),
        (errno.EACCES, "choose a folder you can write to"),
        (errno.EROFS, "the file system is read-only: write elsewhere"),
        (errno.ENAMETOOLONG, "use a shorter name"),
    ],
)
def test_an_error_of_the_file_system_names_the_path_the_cause_and_the_fix(
    code: int, advice: str
) -> None:
    cause = OSError(code, os.strerror(code))
    error = output_error(cause, "/data/run", "the run folder")
    assert str(error) == (
        f"Expected to write the run folder '/data/run', got: {os.strerror(code)} ({advice})."
    )
    assert error.cause is cause and error.path == "/data/run"


def test_a_full_disk_while_writing_leaves_the_old_file_and_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "summary.json"
    write_text(target, "old")

    def full(self: Path, data: bytes) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(Path, "write_bytes", full)
    with pytest.raises(
        OutputError,
        match=r"Expected to write the file '.*summary\.json', got: No space left on device",
    ):
        write_text(target, "new")
    monkeypatch.undo()
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_a_missing_folder_for_an_atomic_file_is_one_error(tmp_path: Path) -> None:
    with (
        pytest.raises(
            OutputError,
            match=r"Expected to write the file '.*missing/x\.txt', got: No such file or directory",
        ),
        replaced(tmp_path / "missing" / "x.txt"),
    ):
        pass


# ------------------------------------------------------------ one writer at a time
#: A process that claims an output, says so, and holds it until its stdin closes;
#: with "fork", it first forks a child that sleeps (and says its pid) once the
#: child is running (its fork handlers, which close the lock file, have run).
HOLDER = """
import os, sys, time
from tumble.locks import OutputLock
claim = OutputLock(sys.argv[1], "the run folder", inside=sys.argv[2] == "inside")
claim.acquire()
running, started = os.pipe()
child = os.fork() if sys.argv[3] == "fork" else None
if child == 0:
    os.write(started, b"1")
    time.sleep(600)
    os._exit(0)
if child:
    os.read(running, 1)
print("held", child, flush=True)
sys.stdin.read()
claim.release()
"""


def hold(
    target: Path, *, inside: bool = False, fork: bool = False
) -> tuple[subprocess.Popen[str], int | None]:
    """Start a process that holds the claim on ``target``; it and its child's pid."""
    process = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(target), "inside" if inside else "beside",
         "fork" if fork else "no"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert process.stdout is not None
    said, child = process.stdout.readline().split()
    assert said == "held"
    return process, None if child == "None" else int(child)


def refusal(folder: Path, pid: int) -> str:
    """The refusal of a second writer of ``folder`` while ``pid`` writes it."""
    return (
        rf"Expected the run folder '{re.escape(str(folder))}' to be free to write, got one "
        rf"being written by pid {pid} on {re.escape(socket.gethostname())} since "
        r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d [+-]\d{4}: wait for it to end, or write elsewhere\."
    )


def test_a_second_writer_is_refused_naming_the_first(tmp_path: Path) -> None:
    target = tmp_path / "new" / "out"
    holder, _ = hold(target)
    try:
        with pytest.raises(OutputInUseError, match=refusal(target, holder.pid)):
            OutputLock(target, "the run folder").acquire()
    finally:
        holder.communicate("")  # it releases its claim and ends
    assert holder.returncode == 0
    # Released: the lock file is gone, and so are the folders made for it.
    assert os.listdir(tmp_path) == []
    with OutputLock(target, "the run folder"):
        record = json.loads((tmp_path / "new" / ".out.lock").read_text())
        assert (record["pid"], record["host"]) == (os.getpid(), socket.gethostname())
    assert os.listdir(tmp_path) == []


def test_the_lock_of_a_killed_writer_is_taken_over(tmp_path: Path) -> None:
    target = tmp_path / "out"
    holder, _ = hold(target)
    holder.kill()
    holder.wait()
    record = json.loads((tmp_path / ".out.lock").read_text())
    assert record["pid"] == holder.pid  # left behind, with its owner's name
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # taken over without a word on this host
        with OutputLock(target, "the run folder"):
            assert json.loads((tmp_path / ".out.lock").read_text())["pid"] == os.getpid()
    assert os.listdir(tmp_path) == []


def test_a_child_of_a_killed_writer_does_not_keep_its_claim(tmp_path: Path) -> None:
    # A forked child inherits the open lock file; were it to keep the lock, the
    # output would stay claimed as long as the child lives.
    target = tmp_path / "out"
    holder, child = hold(target, fork=True)
    assert child is not None
    try:
        holder.kill()
        holder.wait()
        with OutputLock(target, "the run folder"):
            pass
    finally:
        os.kill(child, signal.SIGKILL)


def test_the_claim_is_reentrant_in_its_thread_and_refused_to_others(tmp_path: Path) -> None:
    target = tmp_path / "out"
    errors: list[BaseException] = []

    def other() -> None:
        try:
            OutputLock(target, "the run folder").acquire()
        except OutputInUseError as exc:
            errors.append(exc)

    with OutputLock(target, "the run folder"), OutputLock(target, "the run folder"):
        thread = threading.Thread(target=other)
        thread.start()
        thread.join()
        assert (tmp_path / ".out.lock").exists()  # the inner release keeps the claim
    assert not (tmp_path / ".out.lock").exists()
    assert [str(e) for e in errors] == [
        f"Expected the run folder {str(target)!r} to be free to write, got one being written "
        f"by another thread of this process (pid {os.getpid()}): wait for it to end, or write "
        "elsewhere."
    ]


def test_a_long_name_is_cut_in_the_refusal(tmp_path: Path) -> None:
    target = tmp_path / ("x" * 200)
    holder, _ = hold(target)
    try:
        with pytest.raises(OutputInUseError) as caught:
            OutputLock(target, "the run folder").acquire()
    finally:
        holder.communicate("")
    shown = str(target)[:200]  # tumble.errors.QUOTED_PATH_LENGTH
    assert str(caught.value).startswith(f"Expected the run folder '{shown}'... to be free")


def test_what_killed_writers_left_beside_an_output_is_removed(tmp_path: Path) -> None:
    def staged(name: str, kind: str = "tumble.partial") -> Path:
        folder = tmp_path / f".{name}.a1b2c3_4.{kind}"
        folder.mkdir()
        (folder / "summary.json").write_text("{}")
        return folder

    left = [staged("dead"), staged("out"), staged("out", "tumble.old")]
    kept = [staged("unknown")]  # no lock file: nothing tells whether its writer lives
    # Named as ours, but no folder of tumble's: a user's or another program's.
    kept.append(staged("out", "partial"))
    dead, _ = hold(tmp_path / "dead")
    dead.kill()
    dead.wait()
    live, _ = hold(tmp_path / "live")
    kept.append(staged("live"))  # its writer lives
    try:
        (tmp_path / ".out.a1b2c3_4.tumble.old" / "out").mkdir()  # a replaced run, moved aside
        (tmp_path / ".notes.txt.a1b2c3_4.partial").write_text("")  # a file being written
        with OutputLock(tmp_path / "out", "the run folder"):
            assert [p.name for p in left if p.exists()] == []
            assert all(p.exists() for p in kept)
            # The writer was killed in the middle of its replacement: the old
            # folder is back, as if it had never begun.
            assert (tmp_path / "out").is_dir()
            assert (tmp_path / ".notes.txt.a1b2c3_4.partial").is_file()
            assert not (tmp_path / ".dead.lock").exists()
            assert (tmp_path / ".live.lock").exists()
    finally:
        live.communicate("")


def test_temporary_files_left_in_a_folder_written_into_are_removed(tmp_path: Path) -> None:
    folder = tmp_path / "sweep"
    holder, _ = hold(folder, inside=True)
    holder.kill()
    holder.wait()
    (folder / "results.zarr" / "metrics" / "c").mkdir(parents=True)
    left = [
        folder / ".summary.json.a1b2c3_4.partial",
        folder / "results.zarr" / "metrics" / "c" / "3.0123456789abcdef.partial",
    ]
    kept = [folder / "notes.partial", folder / "results.zarr" / "metrics" / "c" / "3"]
    for path in [*left, *kept]:
        path.write_text("")
    own = ("summary.json", "results.zarr")
    with OutputLock(folder, "the sweep's output folder", inside=True, own=own):
        assert not any(p.exists() for p in left)
        assert all(p.exists() for p in kept)
        assert json.loads((folder / ".tumble.lock").read_text())["pid"] == os.getpid()
    assert not (folder / ".tumble.lock").exists()


def test_without_file_locks_a_live_owner_on_this_host_holds_the_claim(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import fcntl

    def unsupported(*args: object) -> None:
        raise OSError(errno.ENOLCK, os.strerror(errno.ENOLCK))

    monkeypatch.setattr(fcntl, "flock", unsupported)
    target = tmp_path / "out"
    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                           capture_output=True, text=True, check=True)  # fmt: skip
    for pid, host, free in [
        (os.getppid(), socket.gethostname(), False),  # alive here
        (int(ended.stdout), socket.gethostname(), True),  # ended
        (os.getppid(), "elsewhere", False),  # cannot be seen: taken as alive
    ]:
        record = {"pid": pid, "host": host, "since": "2026-01-01 00:00:00 +0000"}
        (tmp_path / ".out.lock").write_text(json.dumps(record))
        claim = OutputLock(target, "the run folder")
        if free:
            with claim:
                pass
        else:
            with pytest.raises(OutputInUseError, match=f"by pid {pid} on {host} since 2026"):
                claim.acquire()


def test_a_lock_left_on_another_host_is_taken_over_with_a_note(tmp_path: Path) -> None:
    record = {"pid": 1234, "host": "elsewhere", "since": "2026-01-01 00:00:00 +0000"}
    (tmp_path / ".out.lock").write_text(json.dumps(record))
    with (
        pytest.warns(
            UserWarning,
            match=r"Took over the lock of the run folder '.*out' that pid 1234 on elsewhere "
            r"left \(since 2026-01-01 00:00:00 \+0000\): no process holds it any more\.",
        ),
        OutputLock(tmp_path / "out", "the run folder"),
    ):
        pass


def test_a_lock_held_without_a_record_is_refused_saying_so(tmp_path: Path) -> None:
    # Another program (or a tumble that died while writing its record) holds it.
    script = (
        "import fcntl, os, sys\n"
        "fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT)\n"
        "fcntl.flock(fd, fcntl.LOCK_EX)\n"
        "print('held', flush=True)\n"
        "sys.stdin.read()\n"
    )
    lock = tmp_path / ".out.lock"
    holder = subprocess.Popen(
        [sys.executable, "-c", script, str(lock)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        with pytest.raises(OutputInUseError) as caught:
            OutputLock(tmp_path / "out", "the run folder").acquire()
    finally:
        holder.communicate("")
    assert str(caught.value) == (
        f"Expected the run folder {str(tmp_path / 'out')!r} to be free to write, got one being "
        f"written by another process (its lock file {str(lock)!r} does not say which): wait "
        "for it to end, or write elsewhere."
    )


def test_files_of_other_programs_beside_an_output_are_never_touched(tmp_path: Path) -> None:
    # A lock file of another program's (held with lockf, which flock does not see,
    # or not held at all), a user's hidden file named like a lock, and a folder
    # named like a temporary one but not made by tumble: all kept as they are.
    import fcntl

    foreign = tmp_path / ".bar.lock"
    foreign.write_text("12345\n")
    notes = tmp_path / ".foo.lock"
    notes.write_text("my notes")
    folder = tmp_path / ".foo.20240101.partial"
    folder.mkdir()
    (folder / "data.csv").write_text("1,2,3")
    with open(foreign, "r+") as held:
        fcntl.lockf(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with OutputLock(tmp_path / "out", "the run folder"):
            pass
    assert foreign.read_text() == "12345\n"
    assert notes.read_text() == "my notes"
    assert (folder / "data.csv").read_text() == "1,2,3"


def test_a_file_of_another_kind_where_the_lock_file_goes_is_refused(tmp_path: Path) -> None:
    (tmp_path / ".out.lock").write_text("not a lock of tumble's")
    with pytest.raises(
        OutputError,
        match=r"^Expected the lock file '.*/\.out\.lock' of the run folder '.*out' to be "
        r"tumble's or absent, got a file of another kind \(move it away, or write elsewhere\)\.$",
    ):
        OutputLock(tmp_path / "out", "the run folder").acquire()
    assert (tmp_path / ".out.lock").read_text() == "not a lock of tumble's"
    assert not (tmp_path / "out").exists()
