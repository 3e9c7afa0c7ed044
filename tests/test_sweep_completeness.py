"""An interrupted sweep's store says what it lacks: reading it warns, names the
missing bodies and the command that resumes it, and never shows a body that was
not computed as a result (no made-up zero flips); resuming completes it. Stores
written before the store kept its completeness are still read."""

from __future__ import annotations

import json
import re
import shlex
import shutil
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from test_sweep import ARRAYS, SMALL, assert_same_bits, stored, write
from tumble.cli import app
from tumble.sweep import IncompleteSweepWarning, open_results, run_sweep
from tumble.sweep import metrics as sweep_metrics

#: SMALL's chunks hold 18 bodies (120 bodies in 7 chunks, the last of 12).
CHUNK = 18


@pytest.fixture(scope="module")
def whole(tmp_path_factory: pytest.TempPathFactory) -> dict[str, np.ndarray]:
    folder = tmp_path_factory.mktemp("whole")
    run_sweep(write(folder, SMALL, "small.toml"), folder / "out")
    return stored(folder / "out")


def stop_at(monkeypatch: pytest.MonkeyPatch, source: Path, folder: Path, chunk: int) -> None:
    """Run the sweep ``source`` into ``folder`` and stop it with an error in chunk
    ``chunk``: in this process the chunks run in order, and those before are done."""
    real = sweep_metrics.compute_chunk

    def failing(plan, index):  # type: ignore[no-untyped-def]
        if index == chunk:
            raise RuntimeError("stopped")
        return real(plan, index)

    monkeypatch.setattr(sweep_metrics, "compute_chunk", failing)
    with pytest.raises(RuntimeError, match="stopped"):
        run_sweep(source, folder)
    monkeypatch.undo()


def interrupted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, after: int) -> Path:
    """The small sweep stopped in chunk ``after``: chunks 0 to after - 1 are done."""
    folder = tmp_path / "out"
    stop_at(monkeypatch, write(tmp_path, SMALL, "small.toml"), folder, after)
    return folder


def open_quietly(folder: Path) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return open_results(folder)


def test_an_interrupted_sweep_warns_and_shows_no_result_for_the_bodies_never_computed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, whole: dict[str, np.ndarray]
) -> None:
    folder = interrupted(tmp_path, monkeypatch, after=3)
    done = 3 * CHUNK
    with pytest.warns(IncompleteSweepWarning) as caught:
        group = open_results(folder)
    (warning,) = caught
    assert str(warning.message) == (
        f"Expected a complete sweep in {str(folder)!r}, got 66 of 120 bodies never "
        "computed: their metrics read NaN (-1 for counts) and `computed` is False for "
        f"them. Run `tumble sweep {shlex.quote(str(folder / 'sweep.toml'))} -o "
        f"{shlex.quote(str(folder))}` again to finish it."
    )
    assert group.attrs["complete"] is False
    computed = np.asarray(group["computed"][:])
    assert computed.dtype == bool
    assert computed[:done].all() and not computed[done:].any()
    flips = np.asarray(group["metrics/flips"][:])
    # The bodies never computed are no result: not 0 flips, which a real body can have.
    assert (flips[~computed] == -1).all()
    assert (whole["metrics/flips"] >= 0).all()
    for name in ARRAYS:
        values = np.asarray(group[name][:])
        assert values[computed].tobytes() == whole[name][computed].tobytes(), name
        if values.dtype.kind == "f":
            assert np.isnan(values[~computed]).all(), name
    # The chunks done are kept; running again finishes the rest and the warning is gone.
    summary = run_sweep(folder / "sweep.toml", folder)
    assert (summary.chunks_run, summary.chunks_reused) == (4, 3)
    group = open_quietly(folder)
    assert group.attrs["complete"] is True
    assert np.asarray(group["computed"][:]).all()
    assert_same_bits(stored(folder), whole)


def test_the_command_the_warning_gives_resumes_the_sweep(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, whole: dict[str, np.ndarray]
) -> None:
    folder = interrupted(tmp_path, monkeypatch, after=1)
    with pytest.warns(
        IncompleteSweepWarning, match=r"got 102 of 120 bodies never computed"
    ) as caught:
        open_results(folder)
    command = re.search(r"Run `tumble sweep (.*)` again", str(caught[0].message))
    assert command is not None
    arguments = shlex.split(command.group(1))
    assert arguments[1] == "-o" and Path(arguments[2]) == folder
    result = CliRunner().invoke(app, ["sweep", *arguments, "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["chunks_run"] == 6
    open_quietly(folder)
    assert_same_bits(stored(folder), whole)


def test_a_chunk_written_but_not_marked_counts_as_computed_and_is_redone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, whole: dict[str, np.ndarray]
) -> None:
    # What a run killed between a chunk's arrays and its marker leaves: its bodies
    # are whole (`computed`), and the next run redoes the chunk, to the same bits.
    folder = interrupted(tmp_path, monkeypatch, after=3)
    (folder / "chunks" / "00000002.done").unlink()
    with pytest.warns(IncompleteSweepWarning, match=r"got 66 of 120 bodies never computed"):
        open_results(folder)
    summary = run_sweep(folder / "sweep.toml", folder)
    assert (summary.chunks_run, summary.chunks_reused) == (5, 2)
    open_quietly(folder)
    assert_same_bits(stored(folder), whole)


def _as_written_before_completeness(folder: Path) -> None:
    """Turn a store into one of the layout before it kept its completeness: no
    `computed` array, no `complete` attribute, counts filled with 0."""
    store = folder / "results.zarr"
    shutil.rmtree(store / "computed")
    meta = store / "zarr.json"
    group = json.loads(meta.read_text())
    del group["attributes"]["complete"]
    meta.write_text(json.dumps(group))
    flips = store / "metrics" / "flips" / "zarr.json"
    array = json.loads(flips.read_text())
    array["fill_value"] = 0
    flips.write_text(json.dumps(array))


def test_a_store_written_before_completeness_was_kept_is_read_and_resumed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, whole: dict[str, np.ndarray]
) -> None:
    folder = tmp_path / "out"
    run_sweep(write(tmp_path, SMALL, "small.toml"), folder)
    _as_written_before_completeness(folder)
    # Every chunk's marker: complete, read as it is, without a warning.
    group = open_quietly(folder)
    assert "computed" not in group
    assert_same_bits(stored(folder), whole)
    # A marker missing: the reader cannot tell those bodies from results, and says so.
    for marker in sorted((folder / "chunks").glob("*.done"))[4:]:
        marker.unlink()
    for chunk in (4, 5, 6):
        (folder / "results.zarr" / "metrics" / "flips" / "c" / str(chunk)).unlink()
    with pytest.warns(
        IncompleteSweepWarning,
        match=r"got 48 of 120 bodies never computed: this store was written "
        r"before tumble marked the bodies computed, and their values read as its fill values "
        r"\(0 for counts\)\. Run `tumble sweep .*` again to finish it\.",
    ):
        open_results(folder)
    # Resumed, it gains `computed`; stopped again, its counts still read 0 where missing.
    stop_at(monkeypatch, folder / "sweep.toml", folder, 5)
    with pytest.warns(
        IncompleteSweepWarning,
        match=r"got 30 of 120 bodies never computed: their metrics read NaN \(0 for counts\) "
        r"and `computed` is False for them\.",
    ):
        group = open_results(folder)
    assert np.asarray(group["computed"][:]).tolist() == [True] * 90 + [False] * 30
    summary = run_sweep(folder / "sweep.toml", folder)
    assert (summary.chunks_run, summary.chunks_reused) == (2, 5)
    group = open_quietly(folder)
    assert np.asarray(group["computed"][:]).all()
    assert_same_bits(stored(folder), whole)
