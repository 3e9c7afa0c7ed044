"""A Dask scheduler's address is checked when it is read (scheme, host, IPv6 in
brackets, port 1 to 65535), and what answers there within the sweep's timeout
must be a Dask scheduler: a server that stays silent or speaks another protocol
is one clear line, never a hang; tls:// without Dask's TLS settings too."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

import tumble as tb
from test_sweep import SMALL, write
from tumble.sweep import dask_backend, run_sweep
from tumble.sweep.build import parse_sweep
from tumble.sweep.schema import SweepError, check_address


@pytest.mark.parametrize(
    "address",
    [
        "tcp://127.0.0.1:8786",
        "tcp://[::1]:8786",
        "tls://[2001:db8::17]:1",
        "tcp://scheduler.example.org:65535",
        " tcp://host-1:8786 ",
    ],
)
def test_addresses_of_schedulers_are_accepted(address: str) -> None:
    assert check_address(address) == address.strip()


@pytest.mark.parametrize(
    ("address", "message"),
    [
        (
            "tcp://127.0.0.1:0",
            r"Expected the port of the Dask scheduler address 'tcp://127.0.0.1:0' to be from 1 "
            r"to 65535, got 0\.",
        ),
        (
            "tcp://[::1]:99999",
            r"Expected the port of the Dask scheduler address 'tcp://\[::1\]:99999' to be from 1 "
            r"to 65535, got 99999\.",
        ),
        (
            "tcp://::1:8786",
            r"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got "
            r"'tcp://::1:8786': write an IPv6 address in brackets, as in 'tcp://\[::1\]:8786'\.",
        ),
        (
            "tcp://[::g]:8786",
            r"Expected an IPv6 address in the brackets of the Dask scheduler address "
            r"'tcp://\[::g\]:8786', got '::g'\.",
        ),
        (
            "tcp://127.0.0.1:٨٧٨٦",  # Arabic-Indic digits, which int() would read
            r"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got "
            r"'tcp://127.0.0.1:٨٧٨٦'\.",
        ),
        (
            "http://127.0.0.1:8786",
            r"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got "
            r"'http://127.0.0.1:8786'\.",
        ),
        (
            "tcp://" + "h" * 100 + ":1:2",
            r"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got "
            r"'tcp://h{54}'\.\.\.\.$",
        ),
    ],
)
def test_addresses_that_name_no_scheduler_are_refused(address: str, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        check_address(address)


def test_the_files_scheduler_and_timeout_are_checked() -> None:
    with pytest.raises(
        SweepError,
        match=r"line 41, `dask.scheduler`: Expected the port of the Dask scheduler address "
        r"'tcp://127.0.0.1:0' to be from 1 to 65535, got 0\.",
    ):
        parse_sweep(SMALL + '\n[dask]\nscheduler = "tcp://127.0.0.1:0"\n')
    with pytest.raises(
        SweepError, match=r"line 41, `dask.timeout`: Expected `timeout` > 0 s, got 0"
    ):
        parse_sweep(SMALL + "\n[dask]\ntimeout = 0\n")
    plan = parse_sweep(SMALL + '\n[dask]\ntimeout = "250 ms"\n')
    assert plan.timeout == pytest.approx(0.25)
    assert parse_sweep(SMALL).timeout is None  # dask_backend.CONNECT_TIMEOUT
    assert dask_backend.CONNECT_TIMEOUT == 10.0


@pytest.fixture
def server(request: pytest.FixtureRequest) -> Iterator[str]:
    """A server on the loopback that is not a Dask scheduler: it accepts and stays
    silent ("silent"), or answers every request as an HTTP server would ("http");
    its address, tcp://HOST:PORT."""
    family, host = (
        (socket.AF_INET6, "::1") if "ipv6" in request.param else (socket.AF_INET, "127.0.0.1")
    )
    listener = socket.socket(family)
    listener.bind((host, 0))
    listener.listen()
    port = listener.getsockname()[1]
    accepted: list[socket.socket] = []

    def serve() -> None:
        while True:
            try:
                connection, _ = listener.accept()
            except OSError:
                return
            accepted.append(connection)
            if request.param == "http":
                connection.recv(65536)
                connection.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield f"tcp://[{host}]:{port}" if family == socket.AF_INET6 else f"tcp://{host}:{port}"
    listener.close()
    for connection in accepted:
        connection.close()


def sweep_at(tmp_path: Path, address: str) -> subprocess.CompletedProcess[str]:
    """`tumble sweep` at ``address`` with a timeout of 1 s, in its own process (the
    subprocess's own timeout only stops a hang)."""
    source = write(tmp_path, SMALL + '\n[dask]\ntimeout = "1 s"\n', "small.toml")
    return subprocess.run(
        [sys.executable, "-m", "tumble", "sweep", str(source), "-o", str(tmp_path / "out"),
         "--scheduler", address],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip


@pytest.mark.parametrize("server", ["silent", "silent-ipv6"], indirect=True)
def test_a_server_that_says_nothing_is_refused_within_the_timeout(
    tmp_path: Path, server: str
) -> None:
    done = sweep_at(tmp_path, server)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"error: Expected a Dask scheduler at {server}, got no answer within 1 s: is a Dask "
        "scheduler listening there? ([dask] timeout sets the wait.)"
    ]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("server", ["http"], indirect=True)
def test_a_server_of_another_protocol_is_refused(tmp_path: Path, server: str) -> None:
    done = sweep_at(tmp_path, server)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"error: Expected a Dask scheduler at {server}, got an answer in another protocol: is "
        "a Dask scheduler listening there?"
    ]


def test_tls_without_tls_settings_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected Dask's TLS settings for the scheduler at tls://127.0.0.1:8786 \(its "
        r"distributed.comm.tls.ca-file, .client.cert and .client.key\), got none: set them in "
        r"Dask's configuration, or use tcp://\.$",
    ):
        run_sweep(parse_sweep(SMALL), tmp_path / "out", scheduler="tls://127.0.0.1:8786")
    assert not (tmp_path / "out").exists()


def test_a_scheduler_at_an_ipv6_address_is_reached(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import distributed

    monkeypatch.setattr(dask_backend, "WORKER_TIMEOUT", 1.0)
    with distributed.LocalCluster(n_workers=0, host="[::1]", dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        assert address.startswith("tcp://[::1]:")
        with pytest.raises(
            tb.InputError,
            match=rf"^Expected a Dask scheduler with workers at {re.escape(address)}, got none "
            r"within 1 s\.$",
        ):
            run_sweep(parse_sweep(SMALL), tmp_path / "out", scheduler=address)
