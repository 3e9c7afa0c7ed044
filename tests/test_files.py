"""Output locations checked before any work; errors of the file system as one clear error."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import pytest

from tumble.errors import OutputError
from tumble.files import check_output, output_error, replaced, write_text


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
