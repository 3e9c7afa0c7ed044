"""Files read within bounds: a FIFO or a device is refused before it is opened (it
would block the reader), a sparse or oversized mesh before a byte of it is read,
and the reason of every refusal is said."""

from __future__ import annotations

import os
import re
import struct
import subprocess
import sys
from pathlib import Path

import pytest
import trimesh
from typer.testing import CliRunner

import tumble
from tumble.cli import app
from tumble.errors import InputError, RequestTooLargeError
from tumble.mesh import check_mesh_file

runner = CliRunner()


def invoke(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def sparse_stl(path: Path, triangles: int) -> Path:
    """A binary STL whose header declares ``triangles`` and whose size agrees,
    of 84 real bytes: the rest is a hole, which reads as zeros."""
    with open(path, "wb") as stream:
        stream.write(b"sparse".ljust(80) + struct.pack("<I", triangles))
        stream.truncate(84 + 50 * triangles)
    return path


@pytest.fixture
def no_reading(monkeypatch: pytest.MonkeyPatch) -> None:
    """Any reading of a mesh by trimesh fails the test: the refusal must come first."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("trimesh was asked to read the file")

    monkeypatch.setattr(trimesh, "load", refuse)
    monkeypatch.setattr(trimesh, "load_mesh", refuse)


def run_cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """The command line in a child process: a regression that blocks on a FIFO
    fails on the timeout instead of hanging the test run."""
    return subprocess.run(
        [sys.executable, "-m", "tumble", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "COLUMNS": "200"},
        check=False,
    )


# ------------------------------------------------------------ sparse and large meshes
@pytest.mark.usefixtures("no_reading")
def test_a_sparse_binary_stl_is_refused_before_it_is_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # 2 GB declared by 84 real bytes; a budget large enough that only the holes refuse it.
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 PiB")
    path = sparse_stl(tmp_path / "f.stl", 40_000_000)
    assert os.stat(path).st_size == 2_000_000_084
    with pytest.raises(
        InputError,
        match=r"^Expected `mesh` to be a file of data, got '.*f\.stl', a sparse file of "
        # The data: the file system's first block (its size varies with the system).
        r"1\.86 GiB of which [\d.]+ KiB hold data \(the rest reads as zeros, no mesh\)\.$",
    ):
        tumble.from_mesh(path, density=1.0)
    with pytest.raises(InputError, match=r"^Expected the mesh of link 'arm' to be a file of data"):
        check_mesh_file(path, "the mesh of link 'arm'")


@pytest.mark.usefixtures("no_reading")
def test_a_mesh_beyond_the_memory_budget_is_refused_before_it_is_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A real (dense) binary STL of 20 000 triangles, 1 MB: 20 MB to read, by
    # MEMORY_PER_BYTE, against a budget of 10 MB.
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "10 MB")
    path = tmp_path / "big.stl"
    with open(path, "wb") as stream:
        stream.write(b"big".ljust(80) + struct.pack("<I", 20_000))
        stream.write(b"\x01" * 50 * 20_000)
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected a request that fits in the memory budget of 9\.54 MiB "
        r"\(TUMBLE_MEMORY_BUDGET = 10 MB\), got `mesh` '.*big\.stl', a binary STL of 20000 "
        r"triangles: about 19\.1 MiB\. Use a mesh of fewer triangles",
    ):
        tumble.from_mesh(path, density=1.0)
    text = tmp_path / "big.obj"
    text.write_bytes(b"v 0 0 0\n" * 100_000)  # 800 kB of text: 16 MB to read
    with pytest.raises(RequestTooLargeError, match=r"got `mesh` '.*big\.obj' of 781 KiB: about"):
        tumble.from_mesh(text, density=1.0)


def test_a_mesh_within_the_budget_is_still_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "10 MB")
    path = tmp_path / "box.stl"
    path.write_bytes(trimesh.exchange.stl.export_stl(trimesh.creation.box(extents=(1, 2, 3))))
    # The box's volume, 6 m³, at unit density: exact for the polyhedron.
    assert tumble.from_mesh(path, density=1.0).mass == pytest.approx(6.0, rel=1e-12)


def test_inertia_refuses_a_sparse_stl_in_one_line(tmp_path: Path) -> None:
    path = sparse_stl(tmp_path / "f.stl", 40_000_000)
    code, out, err = invoke("inertia", str(path), "--mass", "1 kg")
    assert (code, out) == (2, "")
    (line,) = err.strip().splitlines()
    assert re.fullmatch(
        rf"error: Expected `mesh` to be a file of data, got {re.escape(repr(str(path)))}, a "
        r"sparse file of 1\.86 GiB of which [\d.]+ KiB hold data \(the rest reads as zeros, "
        r"no mesh\)\.",
        line,
    )


def test_a_reader_error_without_words_still_gives_a_reason(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "m.stl"
    path.write_bytes(b"solid x\nendsolid x\n")

    def out_of_memory(*args: object, **kwargs: object) -> None:
        raise MemoryError()  # str() of it is empty

    monkeypatch.setattr(trimesh, "load_mesh", out_of_memory)
    with pytest.raises(
        RequestTooLargeError,
        match=r"^Expected `mesh` to be a mesh file that fits in memory, got '.*m\.stl': the "
        r"system ran out of memory reading it \(use a mesh of fewer triangles\)\.$",
    ):
        tumble.from_mesh(path, density=1.0)

    def silent(*args: object, **kwargs: object) -> None:
        raise KeyError()

    monkeypatch.setattr(trimesh, "load_mesh", silent)
    with pytest.raises(InputError, match=r"got '.*m\.stl': KeyError$"):
        tumble.from_mesh(path, density=1.0)


# ------------------------------------------------------------ FIFOs and devices
@pytest.mark.usefixtures("no_reading")
def test_a_fifo_or_a_device_is_not_a_mesh(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo.stl"
    os.mkfifo(fifo)
    with pytest.raises(
        InputError, match=r"^Expected `mesh` to be a regular file, got '.*fifo\.stl', a FIFO\.$"
    ):
        tumble.from_mesh(fifo, density=1.0)
    with pytest.raises(InputError, match=r"got '/dev/zero', a character device\.$"):
        check_mesh_file("/dev/zero")


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ("fit", "{fifo}.csv", "-q", "--no-figures", "-o", "out"),
            "error: Expected the recording to be a regular file, got '{fifo}.csv', a FIFO.",
        ),
        (
            ("inertia", "{fifo}.stl", "--mass", "1 kg"),
            "error: Expected `mesh` to be a regular file, got '{fifo}.stl', a FIFO.",
        ),
        (
            ("inertia", "{fifo}", "--mass", "1 kg"),  # no suffix: a file because it exists
            "error: Expected `mesh` to be a regular file, got '{fifo}', a FIFO.",
        ),
        (
            ("run", "{fifo}.toml", "-q", "-o", "out"),
            "error: Expected a scenario file, got '{fifo}.toml' (a FIFO).",
        ),
    ],
)
def test_a_fifo_is_refused_by_every_command_that_reads_a_file(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    fifo = "pipe"
    for suffix in (".csv", ".stl", "", ".toml"):
        os.mkfifo(tmp_path / f"{fifo}{suffix}")
    done = run_cli(*(a.format(fifo=fifo) for a in args), cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [message.format(fifo=fifo)]
    assert not (tmp_path / "out").exists()


def test_a_fifo_recording_is_refused_by_the_library(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "r.csv")
    # In a child process: a regression that opens the FIFO fails on the timeout.
    code = (
        "from tumble.identification.recordings import read_recording\n"
        "try:\n    read_recording('r.csv')\nexcept ValueError as error:\n    print(error)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
        timeout=120, check=False,
    )  # fmt: skip
    assert done.stdout.strip() == (
        "Expected the recording to be a regular file, got 'r.csv', a FIFO."
    ), done.stderr


# ------------------------------------------------------------ values given twice
def test_a_joint_given_twice_is_refused(tmp_path: Path) -> None:
    robot = tmp_path / "r.urdf"
    robot.write_text(
        '<robot name="r"><link name="base"><inertial><mass value="1"/>'
        '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<link name="arm"><inertial><mass value="1"/><origin xyz="1 0 0"/>'
        '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="a" type="continuous"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/></joint></robot>'
    )
    code, out, err = invoke("inertia", str(robot), "--joints", "a=1", "--joints", "a=-1")
    assert (code, out) == (2, "")
    assert err.strip().splitlines() == [
        "error: Expected each joint once in --joints, got 'a' twice: '1' and '-1'."
    ]
    assert invoke("inertia", str(robot), "--joints", "a=1")[0] == 0
