"""Two writers of one output, as real processes: one wins, the other is refused
with one line naming the first, nothing is lost and nothing computed twice."""

from __future__ import annotations

import json
import re
import socket
from pathlib import Path

import pytest

from writers import (
    RUN,
    SWEEP,
    check_run_folder,
    finish,
    leftovers,
    scenario,
    tumble,
    wait_for,
)

HOST = re.escape(socket.gethostname())


def in_use(what: str, folder: str, pid: int | str = r"\d+") -> str:
    """The refusal of a second writer, as a pattern."""
    return (
        rf"error: Expected {what} '{re.escape(folder)}' to be free to write, got one being "
        rf"written by pid {pid} on {HOST} since \d{{4}}-\d\d-\d\d \d\d:\d\d:\d\d [+-]\d{{4}}: "
        r"wait for it to end, or write elsewhere\."
    )


@pytest.mark.parametrize("trial", range(3))
def test_two_runs_at_once_into_one_folder_one_wins(tmp_path: Path, trial: int) -> None:
    source = scenario(tmp_path, RUN, 500.0, "busy.toml")
    args = ("run", source, "-o", "same", "--json", "--no-figures")
    first, second = tumble(*args, cwd=tmp_path), tumble(*args, cwd=tmp_path)
    results = [finish(first), finish(second)]
    wins = [r for r in results if r[0] == 0]
    refusals = [r for r in results if r[0] != 0]
    assert len(wins) == 1 and len(refusals) == 1, results
    code, out, err = refusals[0]
    # Started together, the second meets the first at work; should the first
    # have finished before the second started, it finds its folder.
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert re.fullmatch(in_use("the run folder", "same"), err.strip()) or err.strip() == (
        "error: Expected an empty or new output folder, got 'same', which holds files "
        "(use --force to replace them)."
    )
    summary = check_run_folder(tmp_path / "same")
    printed = json.loads(wins[0][1])  # the winner's run is the one in the folder
    assert summary["elapsed_s"] == printed["elapsed_s"] and summary["steps"] == printed["steps"]
    assert leftovers(tmp_path) == []


def test_two_runs_at_once_into_their_default_folders_keep_both(tmp_path: Path) -> None:
    # Started in the same second, they would name the same runs/NAME-TIME folder.
    source = scenario(tmp_path, RUN, 500.0, "busy.toml")
    args = ("run", source, "--json", "--no-figures")
    first, second = tumble(*args, cwd=tmp_path), tumble(*args, cwd=tmp_path)
    results = [finish(first), finish(second)]
    assert [code for code, _, _ in results] == [0, 0], results
    printed = [json.loads(out) for _, out, _ in results]
    assert printed[0]["folder"] != printed[1]["folder"]
    for run in printed:  # each run is in the folder it names
        assert check_run_folder(tmp_path / run["folder"])["elapsed_s"] == run["elapsed_s"]
    assert leftovers(tmp_path) == []


@pytest.mark.slow  # two commands in processes of their own: 4 s
def test_a_run_started_while_another_writes_its_folder_is_refused_naming_it(
    tmp_path: Path,
) -> None:
    source = scenario(tmp_path, RUN, 4e5, "busy.toml")  # seconds of work
    first = tumble("run", source, "-o", "same", "--force", "--json", cwd=tmp_path)
    wait_for(tmp_path / ".same.lock", first)
    second = tumble("run", source, "-o", "same", "--force", "--json", cwd=tmp_path)
    code, out, err = finish(second)
    assert (code, out) == (2, ""), err
    assert re.fullmatch(in_use("the run folder", "same", first.pid), err.strip()), err
    code, out, err = finish(first)
    assert code == 0, err
    summary = check_run_folder(tmp_path / "same")
    assert summary["scenario"] == json.loads(out)["scenario"]
    assert leftovers(tmp_path) == []


def sweep_results(results: list[tuple[int, str, str]], chunks: int) -> None:
    """Every sweep that ran finished, the others were refused with the one line;
    the chunks were computed once in all."""
    computed = 0
    for code, out, err in results:
        if code == 0:
            computed += json.loads(out)["chunks_run"]
        else:
            assert code == 2 and out == "" and len(err.splitlines()) == 1, err
            assert re.fullmatch(in_use("the sweep's output folder", "same"), err.strip()), err
    assert computed == chunks


@pytest.mark.slow  # two sweeps in processes of their own: 3.5 s
def test_two_sweeps_at_once_into_one_folder_compute_each_chunk_once(tmp_path: Path) -> None:
    source = scenario(tmp_path, SWEEP, 300.0, "small.toml")
    args = ("sweep", source, "-o", "same", "--json")
    first, second = tumble(*args, cwd=tmp_path), tumble(*args, cwd=tmp_path)
    results = [finish(first), finish(second)]
    assert sum(code == 0 for code, _, _ in results) >= 1, results
    sweep_results(results, 7)
    assert leftovers(tmp_path) == []


@pytest.mark.slow  # two sweeps in subprocesses: 10 s and more
def test_a_sweep_started_while_another_runs_into_its_folder_is_refused(tmp_path: Path) -> None:
    source = scenario(tmp_path, SWEEP, 6000.0, "small.toml")  # seconds of work
    args = ("sweep", source, "-o", "same", "--json")
    first = tumble(*args, cwd=tmp_path)
    wait_for(tmp_path / "same" / "chunks" / "00000000.done", first)  # at work, chunk 1 of 7 done
    second = tumble(*args, cwd=tmp_path)
    code, out, err = finish(second)
    assert (code, out) == (2, ""), (code, out, err)
    assert re.fullmatch(in_use("the sweep's output folder", "same", first.pid), err.strip()), err
    results = [finish(first), (code, out, err)]
    sweep_results(results, 7)
    # After it: the sweep is done, and found so.
    third = finish(tumble(*args, cwd=tmp_path))
    assert third[0] == 0 and json.loads(third[1])["chunks_reused"] == 7
    assert leftovers(tmp_path) == []
