"""Sweeps: per-body metrics against closed forms and single-body simulations,
deterministic chunks, resumable output (also after SIGKILL), and the sweep file's errors."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    N_METRICS,
)
from tumble.errors import CoarseStepWarning, IntegrationError, OutputError
from tumble.report import write_sweep_report
from tumble.sweep import load_sweep, open_results, run_sweep, show_sweep
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import compute_chunk
from tumble.sweep.plan import Plan
from tumble.sweep.schema import SweepError

#: A small sweep with grid, random and per-body torque parameters: 3 × 10
#: grid points × 4 draws = 120 bodies in 7 chunks (the last one partial).
SMALL = """
[sweep]
name = "small"
seed = 3
samples = 4
chunk_size = 18

[base]
duration = 1.5
dt = 0.01
moment_1 = 1.0
ratio_3 = 2.0
spin_axis = 2
spin_rate = "1 turn/s"

[vary.ratio_2]
values = [1.2, 1.5, 1.8]

[vary.damping]
start = 0
stop = 0.02
num = 10

[vary.perturbation]
distribution = "spherical"
min = 0
max = 10
unit = "deg"

[vary.perturbation_azimuth]
distribution = "uniform"
min = 0
max = "360 deg"

[vary.body_torque_1]
distribution = "uniform"
min = -0.05
max = 0.05
"""

ARRAYS = (
    "parameters/ratio_2",
    "parameters/damping",
    "parameters/perturbation",
    "parameters/perturbation_azimuth",
    "parameters/body_torque_1",
    "initial/moments",
    "initial/omega",
    "final/omega",
    "final/quaternion",
    "metrics/flips",
    "metrics/first_flip_time",
    "metrics/max_nutation",
    "metrics/energy_drift",
    "metrics/momentum_drift",
)


def sweep_text(base: str = SMALL, **replace: str) -> str:
    text = base
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    return text


def write(tmp_path: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def stored(folder: Path) -> dict[str, np.ndarray]:
    group = open_results(folder)
    return {name: np.asarray(group[name][:]) for name in ARRAYS}


def assert_same_bits(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> None:
    for name in a:
        assert a[name].dtype == b[name].dtype, name
        assert a[name].tobytes() == b[name].tobytes(), f"{name} differs"


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, np.ndarray]]:
    """The small sweep run once, uninterrupted, in this process."""
    folder = tmp_path_factory.mktemp("reference")
    source = write(folder, SMALL, "small.toml")
    summary = run_sweep(source, folder / "out")
    assert summary.chunks == 7 and summary.chunks_run == 7 and summary.bodies == 120
    assert write_sweep_report(summary) == folder / "out" / "report.html"
    return source, stored(folder / "out")


# ------------------------------------------------------------------ oracles
def flip_sweep(method: str = "rk4", dt: float = 1e-3) -> Plan:
    # ω tilted from axis 2 towards axis 3 only (azimuth 0), so ω1 = 0 at t = 0: in
    # the Jacobi solution (L² > 2 E I2 there) cn = 0, ω2 is at its extreme, and
    # ω2 first crosses zero after exactly a quarter period.
    return parse_sweep(
        f"""
        [sweep]
        name = "flip"
        [base]
        duration = 12.0
        dt = {dt}
        method = "{method}"
        moment_1 = 1.0
        moment_3 = 2.0
        spin_axis = 2
        spin_rate = "1 turn/s"
        perturbation_azimuth = 0
        [vary.moment_2]
        values = [1.2, 1.5, 1.8]
        [vary.perturbation]
        values = ["1 deg", "5 deg", "20 deg"]
        """
    )


@pytest.mark.parametrize("method", ["rk4", "splitting", "exact"])
def test_first_flip_is_a_quarter_of_the_flip_period(method: str) -> None:
    # Oracle: Landau & Lifshitz §37 via tb.theory.flip_period; flips then follow every
    # half period (12 s spans 2 to 7 of them here). RK4 and the splitting at dt = 1e-3 s
    # (1000 steps a turn) keep the phase to ~1e-10, and the linear interpolation at a
    # zero of sn errs by O(dt³); the closed form counts the zeros of sn itself.
    plan = flip_sweep(method)
    result = compute_chunk(plan, 0)
    bodies = plan.bodies(plan.chunk_parameters(0))
    for k in range(plan.n_bodies):
        period = tb.theory.flip_period(bodies.moments[k], bodies.omega[k])
        first = result["metrics/first_flip_time"][k]
        assert first == pytest.approx(period / 4, rel=1e-8)
        expected = math.floor((plan.duration - period / 4) / (period / 2)) + 1
        assert result["metrics/flips"][k] == expected
        # Half a period after the start ω2 = −ω2(0) with the same |ω3| (sn = −1, cn = 0,
        # dn = k'): the axis is then as far from L as it began close to it.
        momentum = bodies.moments[k] * bodies.omega[k]
        start = math.acos(momentum[1] / np.linalg.norm(momentum))
        assert result["metrics/max_nutation"][k] == pytest.approx(math.pi - start, abs=1e-6)


@pytest.mark.parametrize("method", ["rk4", "exact"])
def test_largest_nutation_of_a_stable_spin_matches_the_closed_form(method: str) -> None:
    # Spun near the largest axis 3: L and E conserved, the angle between axis 3 and L
    # is largest where ω3 is smallest, which is where ω1 = 0 (cn = 0 in the Jacobi
    # solution): there I2 ω2² + I3 ω3² = 2E and I2² ω2² + I3² ω3² = L², so
    # cos θ_max = I3 ω3 / |L| = sqrt(I3 (L² − 2 E I2) / (I3 − I2)) / |L|.
    # Sampled every step (dt = 1e-3 s), the maximum of a smooth angle is missed by
    # at most ½ θ'' (dt/2)², below 1e-6 rad here; the closed form takes the
    # extremum of the Jacobi function itself.
    plan = parse_sweep(
        f"""
        [sweep]
        name = "nutation"
        [base]
        duration = 8.0
        dt = 1e-3
        method = "{method}"
        moment_1 = 1.0
        moment_2 = 1.5
        moment_3 = 2.0
        spin_axis = 3
        spin_rate = "1 turn/s"
        perturbation = "15 deg"
        [vary.perturbation_azimuth]
        values = ["0 deg", "30 deg", "90 deg", "200 deg"]
        """
    )
    result = compute_chunk(plan, 0)
    bodies = plan.bodies(plan.chunk_parameters(0))
    for k in range(plan.n_bodies):
        inertia, omega = bodies.moments[k], bodies.omega[k]
        momentum2 = float(np.sum((inertia * omega) ** 2))
        energy2 = float(np.sum(inertia * omega**2))
        assert plan.duration > tb.theory.flip_period(inertia, omega)  # a whole period seen
        cosine = math.sqrt(
            inertia[2] * (momentum2 - energy2 * inertia[1]) / (inertia[2] - inertia[1])
        )
        expected = math.acos(cosine / math.sqrt(momentum2))
        assert result["metrics/max_nutation"][k] == pytest.approx(expected, abs=1e-6)
        assert result["metrics/flips"][k] == 0
        assert math.isnan(result["metrics/first_flip_time"][k])


def test_the_closed_form_metrics_need_no_fine_step() -> None:
    # The flip sweep in closed form at dt = 1e-3 s and at dt = 3 s (longer than
    # a turn; for the closed form it only sets the final time): the same
    # counts, first flips and nutation, to round-off, and no drift at all.
    fine = compute_chunk(flip_sweep("exact"), 0)
    coarse = compute_chunk(flip_sweep("exact", dt=3.0), 0)
    assert_allclose(coarse["metrics/flips"], fine["metrics/flips"])
    assert_allclose(coarse["metrics/first_flip_time"], fine["metrics/first_flip_time"], rtol=1e-12)
    assert_allclose(coarse["metrics/max_nutation"], fine["metrics/max_nutation"], atol=1e-12)
    assert np.all(fine["metrics/energy_drift"] == 0.0)
    assert np.all(fine["metrics/momentum_drift"] == 0.0)


def test_the_closed_form_refuses_a_sweep_with_torques() -> None:
    plan = parse_sweep(sweep_text(SMALL, **{"moment_1 = 1.0": 'moment_1 = 1.0\nmethod = "exact"'}))
    with pytest.raises(
        tb.InputError,
        match=r"^Expected torque-free bodies for method 'exact' \(the closed form\), got a "
        r"torque: use 'rk4' or a splitting\.$",
    ):
        compute_chunk(plan, 0)


def test_symmetric_top_nutation_is_constant_and_exact_with_splitting() -> None:
    # A symmetric top (I1 = I2) keeps the angle between its axis and L:
    # tan θ = I1 sin p / (I3 cos p) for ω tilted by p from the axis. The splitting
    # moves a symmetric body exactly, so θ, E and |L| hold to round-off.
    plan = parse_sweep(
        """
        [sweep]
        name = "top"
        [base]
        duration = 5.0
        dt = 0.02
        method = "splitting"
        moment_1 = 1.0
        moment_2 = 1.0
        moment_3 = 1.7
        spin_axis = 3
        spin_rate = 9.0
        [vary.perturbation]
        start = 0.01
        stop = 1.2
        num = 5
        """
    )
    result = compute_chunk(plan, 0)
    p = plan.chunk_parameters(0)["perturbation"]
    expected = np.arctan2(1.0 * np.sin(p), 1.7 * np.cos(p))
    assert_allclose(result["metrics/max_nutation"], expected, atol=1e-12)
    assert np.all(result["metrics/energy_drift"] < 1e-13)
    assert np.all(result["metrics/momentum_drift"] < 1e-13)


@pytest.mark.parametrize("method", ["rk4", "splitting", "strang", "splitting-exact"])
def test_chunk_equals_single_body_simulations(method: str) -> None:
    # Per-body random perturbations, damping and body torques: each sampled body
    # must end where tb.simulate takes it alone with the same method and dt (same
    # arithmetic; FMA contraction in the vectorised kernel: round-off, 1e-12), and
    # its metrics must equal those measured on simulate's full history.
    plan = parse_sweep(
        sweep_text(SMALL, **{"moment_1 = 1.0": f'moment_1 = 1.0\nmethod = "{method}"'})
    )
    index = 3
    result = compute_chunk(plan, index)
    values = plan.chunk_parameters(index)
    bodies = plan.bodies(values)
    for k in (0, 7, 17):
        torque = tb.torques.ConstantBodyTorque(
            [values["body_torque_1"][k], 0.0, 0.0]
        ) + tb.torques.LinearDamping(values["damping"][k])
        traj = tb.simulate(
            tb.MassProperties(1.0, [0, 0, 0], np.diag(bodies.moments[k])),
            bodies.omega[k],
            duration=plan.duration,
            dt=plan.dt,
            method=method,
            torque=torque,
        )
        assert_allclose(result["final/omega"][k], traj.omega[-1], rtol=0, atol=1e-12)
        angle = (
            Rotation.from_quat(result["final/quaternion"][k], scalar_first=True)
            * Rotation.from_quat(traj.quaternion[-1], scalar_first=True).inv()
        ).magnitude()
        assert angle < 1e-12
        along = traj.omega[:, 1]  # spin axis 2
        crossings = np.flatnonzero(along[:-1] * along[1:] < 0)
        assert result["metrics/flips"][k] == len(crossings)
        if len(crossings):
            j = crossings[0]
            first = traj.t[j] + (traj.t[j + 1] - traj.t[j]) * along[j] / (along[j] - along[j + 1])
            assert result["metrics/first_flip_time"][k] == pytest.approx(first, abs=1e-12)
        momentum = traj.omega * bodies.moments[k]
        size = np.linalg.norm(momentum, axis=1)
        nutation = np.max(np.arccos(np.clip(momentum[:, 1] / size, -1, 1)))
        assert result["metrics/max_nutation"][k] == pytest.approx(nutation, abs=1e-9)
        energy = np.sum(momentum * traj.omega, axis=1)
        drift = np.max(np.abs(energy - energy[0])) / energy[0]
        assert result["metrics/energy_drift"][k] == pytest.approx(drift, rel=1e-6, abs=1e-15)
        assert result["parameters/damping"][k] == values["damping"][k]


# -------------------------------------------------------------- determinism
def test_chunks_depend_only_on_the_sweep_and_their_index() -> None:
    plan = parse_sweep(SMALL)
    later = plan.chunk_parameters(5)
    for index in (0, 6, 2):
        plan.chunk_parameters(index)
    again = parse_sweep(SMALL).chunk_parameters(5)
    for name in later:
        assert later[name].tobytes() == again[name].tobytes()
    # Body b is grid point b // samples, draw b % samples.
    start, stop = plan.chunk_range(5)
    assert (start, stop) == (90, 108)
    ratio, damping = plan.grid_indices(start, stop)
    assert_allclose(later["ratio_2"], np.array([1.2, 1.5, 1.8])[ratio])
    assert np.array_equal(ratio * 10 + damping, np.arange(start, stop) // 4)


def test_random_draws_follow_their_distributions() -> None:
    plan = parse_sweep(
        """
        [sweep]
        name = "draws"
        samples = 200000
        chunk_size = 200000
        [base]
        duration = 1
        dt = 0.01
        moment_1 = 1
        ratio_2 = 2
        ratio_3 = 2.5
        spin_rate = 1
        [vary.perturbation]
        distribution = "spherical"
        min = 0
        max = "180 deg"
        [vary.perturbation_azimuth]
        distribution = "uniform"
        min = 0
        max = "360 deg"
        [vary.spin_rate]
        distribution = "loguniform"
        min = 0.1
        max = 10
        """.replace("spin_rate = 1\n", "")
    )
    values = plan.chunk_parameters(0)
    directions = plan.bodies(values).omega / values["spin_rate"][:, None]
    # Isotropic directions: the mean direction vanishes (σ = 1/√(3n) per component)
    # and each component squared averages 1/3.
    assert np.all(np.abs(directions.mean(axis=0)) < 5 / math.sqrt(3 * plan.n_bodies))
    assert_allclose(np.mean(directions**2, axis=0), 1 / 3, atol=5e-3)
    log_rate = np.log10(values["spin_rate"])
    assert log_rate.min() >= -1 and log_rate.max() <= 1
    assert abs(log_rate.mean()) < 0.01


# ------------------------------------------------------- output and resuming
def test_sweep_writes_store_summary_and_report(
    reference: tuple[Path, dict[str, np.ndarray]],
) -> None:
    source, arrays = reference
    folder = source.parent / "out"
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["bodies"] == 120 and summary["chunks"] == 7
    flips = arrays["metrics/flips"]
    assert summary["metrics"]["flips"]["fraction_flipped"] == pytest.approx(np.mean(flips > 0))
    assert summary["metrics"]["max_nutation"]["max"] == pytest.approx(
        arrays["metrics/max_nutation"].max()
    )
    page = (folder / "report.html").read_text()
    # Default maps: each of the 5 metrics over the first two varied parameters.
    assert page.count("data:image/png;base64,") == 5
    # The run report's stylesheet: one for every page.
    from tumble.report.html import stylesheet

    assert f"<style>{stylesheet()}</style>" in page
    group = open_results(folder)
    assert group["metrics/first_flip_time"].attrs["units"] == "s"
    assert group["final/omega"].chunks == (18, 3)
    assert all(np.isfinite(arrays[name]).all() for name in ARRAYS if "first_flip" not in name)


def test_rerun_skips_finished_chunks(reference: tuple[Path, dict[str, np.ndarray]]) -> None:
    source, arrays = reference
    calls: list[tuple[int, int]] = []
    summary = run_sweep(source, source.parent / "out", progress=lambda d, t: calls.append((d, t)))
    assert summary.chunks_run == 0 and summary.chunks_reused == 7
    assert calls == [(7, 7)]
    assert_same_bits(stored(source.parent / "out"), arrays)


def test_sigkill_mid_run_then_resume_gives_identical_bits(
    tmp_path: Path, reference: tuple[Path, dict[str, np.ndarray]]
) -> None:
    # A process killed with SIGKILL right after its third chunk's marker; the
    # re-run computes the four missing chunks and the store holds the same bits
    # as an uninterrupted run's.
    source, arrays = reference
    folder = tmp_path / "out"
    script = textwrap.dedent(
        f"""
        import os, signal
        from tumble.sweep import run_sweep

        def progress(done, total):
            if done == 3:
                os.kill(os.getpid(), signal.SIGKILL)

        run_sweep({str(source)!r}, {str(folder)!r}, progress=progress)
        """
    )
    killed = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=600)
    assert killed.returncode == -9, killed.stderr.decode()
    assert len(list((folder / "chunks").glob("*.done"))) == 3
    assert not (folder / "summary.json").exists()
    summary = run_sweep(source, folder)
    assert (summary.chunks_run, summary.chunks_reused) == (4, 3)
    assert_same_bits(stored(folder), arrays)


def test_torn_chunk_without_marker_is_redone(
    tmp_path: Path, reference: tuple[Path, dict[str, np.ndarray]]
) -> None:
    # What a kill during a chunk's writes can leave: some of its arrays written (or
    # garbage), no marker. The chunk is not trusted; the next run rewrites it.
    source, arrays = reference
    folder = tmp_path / "out"
    run_sweep(source, folder)
    (folder / "chunks" / "00000004.done").unlink()
    (folder / "results.zarr" / "metrics" / "flips" / "c" / "4").write_bytes(b"torn")
    group = open_results(folder)
    assert group.read_only
    summary = run_sweep(source, folder)
    assert (summary.chunks_run, summary.chunks_reused) == (1, 6)
    assert_same_bits(stored(folder), arrays)


def test_changed_sweep_is_refused_then_forced(
    tmp_path: Path, reference: tuple[Path, dict[str, np.ndarray]]
) -> None:
    source, _ = reference
    folder = tmp_path / "out"
    run_sweep(source, folder)
    changed = write(tmp_path, sweep_text(SMALL, **{"dt = 0.01": "dt = 0.005"}), "changed.toml")
    with pytest.raises(
        tb.InputError,
        match=r"Expected the sweep that '.*out' holds, got a changed sweep \(dt, n_steps differ\): "
        r"run it into another folder, or use --force",
    ):
        run_sweep(changed, folder)
    summary = run_sweep(changed, folder, force=True)
    assert summary.chunks_run == 7 and summary.steps == 300
    # Comments, names and maps do not change the results: not a different sweep.
    renamed = write(
        tmp_path,
        "# a comment\n" + sweep_text(changed.read_text(), **{'"small"': '"other"'}),
        "r.toml",
    )
    assert run_sweep(renamed, folder).chunks_reused == 7


def test_folder_with_other_files_is_refused(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    source = write(tmp_path, SMALL, "small.toml")
    with pytest.raises(
        tb.InputError,
        match=r"Expected a new or empty output folder, or one holding a sweep's results, got "
        r"'.*' with notes.txt, small.toml \(no sweep.json\)",
    ):
        run_sweep(source, tmp_path)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_diverging_bodies_are_reported(tmp_path: Path) -> None:
    text = sweep_text(SMALL, **{"dt = 0.01": "dt = 0.75", "duration = 1.5": "duration = 300"})
    text = text.replace('spin_rate = "1 turn/s"', 'spin_rate = "40 turn/s"')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseStepWarning)
        plan = parse_sweep(text)
    with pytest.raises(
        IntegrationError,
        match=r"Expected the integration to stay finite, got NaN or inf for \d+ bodies of chunk 0 "
        r"\(first: body \d+\) with dt = 0.75 s: reduce dt",
    ):
        run_sweep(plan, tmp_path / "out")


def test_coarse_step_warns() -> None:
    with pytest.warns(CoarseStepWarning, match=r"dt = 0.1 s gives 10.0 steps per turn"):
        parse_sweep(sweep_text(SMALL, **{"dt = 0.01": "dt = 0.1"}))


# ------------------------------------------------------------------ built-in
def test_metric_names_agree() -> None:
    from typing import get_args

    from tumble.sweep.schema import MetricName

    assert get_args(MetricName) == tuple(tb.sweep.METRICS)


def test_flip_map_is_shipped_and_valid() -> None:
    assert "flip-map" in tb.sweep.builtin_sweeps()
    text = show_sweep("flip-map")
    plan = parse_sweep(text)
    assert plan.n_bodies == 181 * 181
    assert plan.varied == ("ratio_2", "perturbation")
    assert plan.maps[0].metric == "first_flip_time"
    assert load_sweep("flip-map").identity() == plan.identity()


def test_unknown_builtin_is_refused() -> None:
    with pytest.raises(
        SweepError,
        match=r"Expected a built-in sweep to be one of dual-spin-map, flip-map, or a .toml file, got 'flip-mop'. "
        r"Did you mean flip-map\?",
    ):
        load_sweep("flip-mop")
    with pytest.raises(
        SweepError, match=r"Expected a sweep file, got 'missing.toml' \(no such file\)"
    ):
        load_sweep("missing.toml")


# -------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    ("replace", "message"),
    [
        (
            {"seed = 3": "seed = 3\nseeed = 4"},
            r"<sweep>, line 5, `sweep.seeed`: Expected the key to be one of name, description, seed, "
            r"samples, chunk_size, got 'seeed'. Did you mean seed\?",
        ),
        (
            {"[vary.damping]": "[vary.dampng]"},
            r"line 19, `vary.dampng`: Expected a parameter to be one of moment_1, .*, got 'dampng'. "
            r"Did you mean damping\?",
        ),
        (
            {"samples = 4": "samples = 0"},
            r"line 5, `sweep.samples`: Expected a value greater than or equal to 1, got 0.",
        ),
        (
            {"samples = 4": 'samples = "4"'},
            r"line 5, `sweep.samples`: Expected a valid integer, got '4'.",
        ),
        (
            {"dt = 0.01\n": ""},
            r"<sweep>, line 8, `base.dt`: Expected the key `dt`, which is missing.",
        ),
        (
            {"[base]": "[basis]"},
            r"`basis`: Expected the key to be one of sweep, base, vary, internal, outputs, report, "
            r"dask, limits, got 'basis'",
        ),
        (
            {"dt = 0.01": "dt = true"},
            r"line 10, `base.dt`: Expected a number or a quantity such as '2 rad/s', got true.",
        ),
        (
            {"dt = 0.01": 'dt = "10 m"'},
            r"line 10, `base.dt`: Expected `dt` to be a time in s, got 10 m",
        ),
        (
            {"dt = 0.01": "dt = -0.01"},
            r"line 10, `base.dt`: Expected `dt` > 0 s, got -0.01.",
        ),
        (
            {"dt = 0.01": 'dt = 0.01\nmethod = "euler"'},
            r"line 11, `base.method`: Expected `method` to be one of exact, splitting, strang, splitting-exact, strang-exact, rk4, got 'euler'.",
        ),
        (
            {"spin_axis = 2": "spin_axis = 4"},
            r"line 13, `base.spin_axis`: Expected 1, 2 or 3, got 4.",
        ),
        (
            {
                "spin_axis = 2\n": "",
                "[vary.ratio_2]": '[vary.spin_axis]\nvalues = [1, "x"]\n[vary.ratio_2]',
            },
            r"line 16, `vary.spin_axis.values\[1\]`: Expected `spin_axis` to be 1, 2 or 3, got 'x'.",
        ),
        (
            {"ratio_3 = 2.0": "ratio_3 = 2.0\nmoment_3 = 2.0"},
            r"`base.ratio_3`: Expected one of `moment_3` and `ratio_3`, not both, got both.",
        ),
        (
            {"moment_1 = 1.0": "damping = 0.1"},
            r"`vary.damping`: Expected `damping` in \[base\] or in \[vary\], not both, got both.",
        ),
        (
            {"ratio_3 = 2.0\n": ""},
            r"`base`: Expected `moment_3` or `ratio_3` in \[base\] or \[vary\], got neither.",
        ),
        (
            {"values = [1.2, 1.5, 1.8]": "values = [1.2, 1.5, 3.5]"},
            r"line 16, `vary.ratio_2`: Expected principal moments satisfying the triangle "
            r"inequality \(I1 \+ I2 >= I3 and cyclic\) for every body, got I1, I2, I3 = 1, 3.5, 2 "
            r"kg·m² at moment_1 = 1, ratio_2 = 3.5, ratio_3 = 2.",
        ),
        (
            {"values = [1.2, 1.5, 1.8]": "values = [1.2, -1.5]"},
            r"`vary.ratio_2`: Expected `ratio_2` > 0 for every body, got -1.5.",
        ),
        (
            {"values = [1.2, 1.5, 1.8]": "values = []"},
            r"line 17, `vary.ratio_2.values`: Expected at least one value, got none.",
        ),
        (
            {"values = [1.2, 1.5, 1.8]": "values = [1.2]\nstart = 1"},
            r"line 16, `vary.ratio_2`: Expected a grid \(`values`, or `start`, `stop`, `num`\) or "
            r"a random draw \(`distribution`, `min`, `max`\), got `values`, `start`.",
        ),
        (
            {"num = 10": 'num = 10\nscale = "log"'},
            r"`vary.damping.start`: Expected `start` and `stop` > 0 for a log scale, got 0.0 and 0.02.",
        ),
        (
            {"num = 10\n": ""},
            r"`vary.damping.num`: Expected `num` with `start`, `stop`, `num`, which is missing.",
        ),
        (
            {"min = -0.05\n": ""},
            r"`vary.body_torque_1.min`: Expected `min` with `distribution`, `min`, `max`, which "
            r"is missing.",
        ),
        (
            {"values = [1.2, 1.5, 1.8]": 'values = [1.2, "1.5 kg"]'},
            r"line 17, `vary.ratio_2.values\[1\]`: Expected `ratio_2` to be a dimensionless number, got 1.5 kg",
        ),
        (
            {'max = "360 deg"': 'max = "360 m"'},
            r"`vary.perturbation_azimuth.max`: Expected `max` to be an angle in rad, got 360 m",
        ),
        (
            {"min = -0.05": "min = 0.06"},
            r"`vary.body_torque_1.max`: Expected `max` >= `min` \(0.06\), got 0.05.",
        ),
        (
            {'distribution = "uniform"\nmin = -0.05': 'distribution = "spherical"\nmin = -0.05'},
            r"`vary.body_torque_1.distribution`: Expected a 'spherical' draw only for an angle, got "
            r"it for `body_torque_1` \(torque\).",
        ),
        (
            {"max = 10\nunit": "max = 200\nunit"},
            r"`vary.perturbation.min`: Expected polar angles in \[0, π\] for a 'spherical' draw, got "
            r"\[0.0, 3.49\d+\] rad.",
        ),
        (
            {'distribution = "spherical"': 'distribution = "gaussian"'},
            r"`vary.perturbation.distribution`: Expected 'uniform', 'loguniform' or 'spherical', got "
            r"'gaussian'.",
        ),
        (
            {"[vary.ratio_2]": '[outputs]\nmetrics = ["flips", "flops"]\n[vary.ratio_2]'},
            r"`outputs.metrics\[1\]`: Expected 'flips', 'first_flip_time', 'max_nutation', "
            r"'energy_drift' or 'momentum_drift', got 'flops'.",
        ),
        (
            {
                "[vary.ratio_2]": '[report]\nmaps = [{x = "ratio_2", y = "spin_rate", metric = "flips"}]\n[vary.ratio_2]'
            },
            r"`report.maps\[0\].y`: Expected a varied parameter \(ratio_2, damping, perturbation, "
            r"perturbation_azimuth, body_torque_1\), got 'spin_rate'.",
        ),
        (
            {"[vary.ratio_2]": '[dask]\nscheduler = "localhost:8786"\n[vary.ratio_2]'},
            r"`dask.scheduler`: Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', "
            r"got 'localhost:8786'.",
        ),
        (
            {
                "[vary.ratio_2]": '[dask]\nscheduler = "tcp://127.0.0.1:8786"\nworkers = 2\n[vary.ratio_2]'
            },
            r"line 16, `dask`: Expected at most one of `scheduler` and `workers` in \[dask\], got both.",
        ),
        (
            {"num = 10": "num = 100_000_000"},
            r"`vary.damping.num`: Expected a value less than or equal to 1000000, got 100000000.",
        ),
        (
            {"[sweep]": "[sweep\n"},
            r"<sweep>: Expected valid TOML, got an error: ",
        ),
        (
            {'name = "small"': 'name = "a/b"'},
            r"`sweep.name`: Expected a string that should match pattern",
        ),
    ],
)
def test_sweep_file_errors(replace: dict[str, str], message: str) -> None:
    with pytest.raises(SweepError, match=message):
        parse_sweep(sweep_text(SMALL, **replace))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"workers": 0}, r"Expected `workers` to be an integer >= 1, got 0."),
        ({"workers": True}, r"Expected `workers` to be an integer >= 1, got True."),
        (
            {"workers": 2, "scheduler": "tcp://127.0.0.1:8786"},
            r"Expected at most one of `workers` and `scheduler`, got workers=2 and "
            r"scheduler='tcp://127.0.0.1:8786'.",
        ),
        (
            {"scheduler": "8786"},
            r"Expected a Dask scheduler address such as 'tcp://127.0.0.1:8786', got '8786'.",
        ),
    ],
)
def test_run_sweep_argument_errors(tmp_path: Path, kwargs: dict, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        run_sweep(parse_sweep(SMALL), tmp_path / "out", **kwargs)
    assert not (tmp_path / "out").exists()


def test_output_path_that_is_a_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(
        OutputError,
        match=r"Expected the sweep's output folder to be a folder, got '.*file', which is a file.",
    ):
        run_sweep(parse_sweep(SMALL), tmp_path / "file")


@pytest.mark.parametrize(
    ("replace", "message"),
    [
        (
            {
                "spin_axis = 2\n": "",
                "[vary.ratio_2]": '[vary.spin_axis]\nvalues = [1, 2]\nunit = "deg"\n\n[vary.ratio_2]',
            },
            r"`vary.spin_axis.unit`: Expected no `unit` for `spin_axis`, got 'deg'.",
        ),
        (
            {
                "spin_axis = 2\n": "",
                "[vary.ratio_2]": "[vary.spin_axis]\nstart = 1\nstop = 3\nnum = 3\n\n[vary.ratio_2]",
            },
            r"`vary.spin_axis`: Expected `values` for `spin_axis` \(a list of axes 1, 2, 3\), got 'start'.",
        ),
        (
            {'distribution = "uniform"\nmin = -0.05': 'distribution = "loguniform"\nmin = -0.05'},
            r"`vary.body_torque_1.min`: Expected `min` > 0 for a loguniform draw, got -0.05.",
        ),
    ],
)
def test_more_sweep_file_errors(replace: dict, message: str) -> None:
    with pytest.raises(SweepError, match=message):
        parse_sweep(sweep_text(SMALL, **replace))


def test_a_map_of_a_metric_not_computed_is_refused() -> None:
    text = (
        SMALL
        + '\n[outputs]\nmetrics = ["flips"]\n\n[report]\nmaps = [{ x = "ratio_2", y = "damping", metric = "max_nutation" }]\n'
    )
    with pytest.raises(
        SweepError, match=r"Expected a metric listed in \[outputs\] \(flips\), got "
    ):
        parse_sweep(text)


def test_an_unreadable_sweep_file_is_named(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_bytes(b"[sweep]\nname = '\xff\xfe'\n")
    with pytest.raises(SweepError, match=r"Expected a readable UTF-8 file, got '.*bad.toml'"):
        load_sweep(path)


def test_folders_that_cannot_hold_or_are_not_sweeps(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(
        OutputError,
        match=r"Expected the sweep's output folder in a folder, got '.*file/out', which is "
        r"under the file '.*file'.",
    ):
        run_sweep(parse_sweep(SMALL), tmp_path / "file" / "out")
    with pytest.raises(
        tb.InputError, match=r"Expected a sweep's output folder, got '.*' \(no results.zarr\)."
    ):
        open_results(tmp_path)


def test_a_sweep_half_done_by_another_version_is_not_resumed(tmp_path: Path) -> None:
    folder = tmp_path / "out"
    run_sweep(parse_sweep(SMALL), folder)
    identity = folder / "sweep.json"
    record = json.loads(identity.read_text())
    record["tumble_version"] = "0.0.1"
    identity.write_text(json.dumps(record))
    next(iter(sorted((folder / "chunks").glob("*.done")))).unlink()
    with pytest.raises(
        tb.InputError,
        match=r"Expected results from this version of tumble \(.*\) to resume, got '0.0.1'",
    ):
        run_sweep(parse_sweep(SMALL), folder)


def test_a_full_disk_mid_sweep_is_one_error_and_the_sweep_resumes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tumble.sweep.store import SweepStore

    folder = tmp_path / "out"
    real = SweepStore._array

    def filling(self: SweepStore, name: str) -> object:
        # The disk fills once two chunks are done.
        return _FullArray() if len(self.done()) >= 2 else real(self, name)

    monkeypatch.setattr(SweepStore, "_array", filling)
    with pytest.raises(
        OutputError,
        match=r"Expected to write chunk \d+ of the sweep to '.*results\.zarr', got: No space left "
        r"on device \(free some space or write elsewhere\)\. The chunks done \(2\) are kept: run "
        r"the same sweep again to resume\.",
    ):
        run_sweep(parse_sweep(SMALL), folder)
    monkeypatch.undo()
    summary = run_sweep(parse_sweep(SMALL), folder)
    assert summary.chunks_reused == 2 and summary.chunks_run == summary.chunks - 2
    whole = run_sweep(parse_sweep(SMALL), tmp_path / "whole")
    for name in ARRAYS:
        assert_array_equal(open_results(folder)[name][:], open_results(whole.folder)[name][:])


class _FullArray:
    """A Zarr array on a full disk."""

    def __setitem__(self, key: object, value: object) -> None:
        import errno
        import os

        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def _spun_near_two_axes(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (n, 3) and ω (n, 3) of n bodies, the first half spun at 6
    rad/s near the intermediate axis 2 (they flip), the rest near axis 3."""
    moments = np.column_stack([np.ones(n), rng.uniform(1.2, 1.8, n), np.full(n, 2.0)])
    omega = rng.normal(0, 0.3, (n, 3))
    omega[: n // 2, 1] = 6.0
    omega[n // 2 :, 2] = 6.0
    return moments, omega


def _on_principal_axis(k: int, n: int) -> np.ndarray:
    """Nominal axes (3, n) on principal axis k, every third of the opposite sense."""
    axis = np.zeros((3, n))
    axis[k] = np.where(np.arange(n) % 3 == 0, -1.0, 1.0)
    return axis


def _measured_by(  # type: ignore[no-untyped-def]
    kernel, torque, moments: np.ndarray, omega: np.ndarray, axis: np.ndarray, dt: float, steps: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ω (3, n), q (4, n) and the measures (N_METRICS, n) after ``steps`` steps of
    ``dt`` s of a metrics ``kernel``, from the bodies' ω (n, 3) and the identity
    attitude."""
    n = len(moments)
    w, q = omega.T.copy(), np.vstack([np.ones(n), np.zeros((3, n))])
    out = np.empty((N_METRICS, n))
    kernel(w, q, moments.T.copy(), torque.params, torque.context, axis, 0.0, dt, steps, out,
           np.zeros(n, dtype=np.int64))  # fmt: skip
    return w, q, out


# RK4 measures in its stepping loop, a splitting through its whole-block advance.
# The methods and axes are those of the sweeps above and of the tests below, so
# that these kernels (a minute or more each to compile) are compiled once for all.
@pytest.mark.parametrize(("method", "principal"), [("rk4", 1), ("splitting", 2)])
def test_the_kernel_for_nominal_axes_on_a_principal_axis_measures_as_the_kernel_for_any(
    method: str, principal: int
) -> None:
    # Oracle: the kernel for nominal axes in any direction (itself checked against
    # numpy by the test below) on the same bodies. The steps are the same code, so
    # the states agree bit for bit; with the other two components of every axis
    # exactly zero, b · L = b_k L_k is zero only where L_k is (short of an
    # underflow, 1e-308 of |L₀|) and has its sign or the opposite throughout, so
    # the flips agree exactly. The rest is
    # the same arithmetic rounded in another order (b_k L_k squared against
    # b_k|b_k| times L_k², |L|² contracted into FMAs otherwise): see each
    # tolerance. Axes of both senses; bodies that flip and bodies that do not; a
    # block and a ragged remainder.
    from tumble.batch import Batch, measure_batch
    from tumble.batch.driver import _principal_axis_of
    from tumble.body import BodyBatch
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    n, steps, dt = 200, 300, 0.01
    moments, omega = _spun_near_two_axes(n, np.random.default_rng(11))
    axis = _on_principal_axis(principal, n)
    assert _principal_axis_of(axis) == principal
    integrator = get_integrator(method, batch=True)
    torque = bind(None, BodyBatch(moments), bodies=n)
    states, measures = [], []
    for kernel in (
        integrator.kernel("metrics", torque),
        integrator.kernel("metrics", torque, principal_axis=principal),
    ):
        w, q, out = _measured_by(kernel, torque, moments, omega, axis, dt, steps)
        states.append((w, q))
        measures.append(out)
    assert np.isfinite(measures[0][FIRST_FLIP]).any()  # some bodies flipped
    assert_array_equal(states[1][0], states[0][0])
    assert_array_equal(states[1][1], states[0][1])
    assert_array_equal(measures[1][FLIPS], measures[0][FLIPS])
    eps = np.finfo(float).eps
    # The first flip's time is (t − dt) + dt · before / (before − after): the
    # ratio (before and after of opposite signs) to a few ε either way, the sum
    # rounded to an ε of t ≤ 3 s.
    assert_allclose(
        measures[1][FIRST_FLIP], measures[0][FIRST_FLIP], rtol=0, atol=4 * eps * steps * dt
    )
    # The signed squared cosine is three roundings from L either way (b_k L_k,
    # its square; b_k|b_k|, L_k², their product), |L|² two: a few ε of a cosine
    # ≤ 1, whichever of two steps within them is the least.
    assert_allclose(measures[1][MIN_COS], measures[0][MIN_COS], rtol=0, atol=8 * eps)
    # The same sum for |L|², its products contracted into FMAs otherwise: its
    # extreme and |L₀|² each to 2 ε of |L|², so
    # |L| − |L₀| to 2 ε of |L|; twice that for the square roots' own rounding.
    momentum = np.linalg.norm(moments * omega, axis=1)
    assert_allclose(
        measures[1][MOMENTUM_DEVIATION], measures[0][MOMENTUM_DEVIATION], rtol=0,
        atol=4 * eps * momentum.max(),
    )  # fmt: skip
    # The energy's three products and sums are contracted into FMAs as the
    # compiler sees fit in each kernel: the same 2E to an ε or two of it.
    twice_energy = np.sum(moments * omega**2, axis=1)
    assert_allclose(
        measures[1][ENERGY_DEVIATION], measures[0][ENERGY_DEVIATION], rtol=0,
        atol=4 * np.finfo(float).eps * twice_energy.max(),
    )  # fmt: skip
    # measure_batch picks that kernel: the same measures again.
    batch = Batch(moments.T.copy(), omega.T.copy(), np.vstack([np.ones(n), np.zeros((3, n))]),
                  torque)  # fmt: skip
    assert_array_equal(measure_batch(integrator, batch, dt, steps, axis), measures[1])


@pytest.mark.parametrize(("principal", "forced"), [(None, False), (1, True)])
def test_the_metrics_kernel_without_the_attitude_measures_as_the_kernel_with_it(
    principal: int | None, forced: bool
) -> None:
    # Oracle: the kernel with the attitude (itself checked against numpy above) on
    # the same bodies, torque-free or under a body torque and a linear damping
    # (which read ω, not the attitude; the torques of the small sweep above, so
    # that the kernel with the attitude is compiled once for both). Euler's
    # equations do not read q, so ω is the same
    # arithmetic in both kernels; the compiler may contract and order it apart in
    # the loop without the quaternion (bit for bit here when measured), and the
    # bodies near the intermediate axis would grow an ε into some 1e3 ε over
    # 3 s: ω to 1e-12 of its size. That growth is a shift of phase along the
    # orbit, not a change of its energy or |L| (the round-off of the integrals
    # themselves stays at ε), so the drifts, extremes over the orbit, stay
    # within a few ε. The flips are the same sign changes (a · L is
    # far from round-off where it crosses); the other measures to round-off of
    # the quantities they are differences of, as in the test above.
    from tumble.batch import Batch, measure_batch
    from tumble.body import BodyBatch
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    n, steps, dt = 200, 300, 0.01
    rng = np.random.default_rng(17)
    moments, omega = _spun_near_two_axes(n, rng)
    if principal is None:
        axis = rng.normal(size=(3, n))
        axis /= np.linalg.norm(axis, axis=0)
    else:
        axis = _on_principal_axis(principal, n)
    q0 = np.vstack([np.ones(n), np.zeros((3, n))])
    integrator = get_integrator("rk4", batch=True)
    model = (
        tb.torques.ConstantBodyTorque(rng.uniform(-0.05, 0.05, (n, 3)))
        + tb.torques.LinearDamping(rng.uniform(0.01, 0.1, n))
        if forced
        else None
    )
    torque = bind(model, BodyBatch(moments), bodies=n)
    states, measures = [], []
    for attitude in (True, False):
        kernel = integrator.kernel("metrics", torque, principal_axis=principal, attitude=attitude)
        w, q, out = _measured_by(kernel, torque, moments, omega, axis, dt, steps)
        states.append((w, q))
        measures.append(out)
    with_attitude, without = measures
    assert np.isfinite(with_attitude[FIRST_FLIP]).any()  # some bodies flipped
    assert not np.array_equal(states[0][1], q0)  # the kernel with it turned the bodies
    assert_array_equal(states[1][1], q0)  # the one without left q as given
    size = np.linalg.norm(omega, axis=1)
    assert_allclose(states[1][0], states[0][0], rtol=0, atol=1e-12 * size.max())
    assert_array_equal(without[FLIPS], with_attitude[FLIPS])
    assert_allclose(without[FIRST_FLIP], with_attitude[FIRST_FLIP], rtol=0, atol=1e-12)
    assert_allclose(without[MIN_COS], with_attitude[MIN_COS], rtol=0, atol=1e-12)
    eps = np.finfo(float).eps
    twice_energy = np.sum(moments * omega**2, axis=1)
    assert_allclose(
        without[ENERGY_DEVIATION], with_attitude[ENERGY_DEVIATION], rtol=0,
        atol=64 * eps * twice_energy.max(),
    )  # fmt: skip
    momentum = np.linalg.norm(moments * omega, axis=1)
    assert_allclose(
        without[MOMENTUM_DEVIATION], with_attitude[MOMENTUM_DEVIATION], rtol=0,
        atol=64 * eps * momentum.max(),
    )  # fmt: skip
    # measure_batch takes the kernel without the attitude when the final states
    # are not wanted, and the one with it when they are.
    for final_state, expected, turned in ((False, without, False), (True, with_attitude, True)):
        batch = Batch(moments.T.copy(), omega.T.copy(), q0.copy(), torque)
        assert_array_equal(
            measure_batch(integrator, batch, dt, steps, axis, final_state=final_state), expected
        )
        assert np.array_equal(batch.q, q0) is not turned


def test_a_torque_that_reads_the_attitude_keeps_it_in_the_metrics_kernel() -> None:
    # A torque fixed in space turns with the body: the measures need q, so
    # measure_batch keeps it whatever final_state says, and a kernel without it
    # is refused.
    from tumble.batch import Batch, measure_batch
    from tumble.body import BodyBatch
    from tumble.errors import InputError
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    n, steps, dt = 8, 50, 0.01
    moments = np.tile([1.0, 1.5, 2.0], (n, 1))
    omega = np.tile([0.1, 6.0, 0.1], (n, 1))
    axis = np.zeros((3, n))
    axis[1] = 1.0
    push = tb.torques.ConstantSpaceTorque([0.5, 0.0, 0.0]) + tb.torques.LinearDamping(0.01)
    torque = bind(push, BodyBatch(moments), bodies=n)
    rk4 = get_integrator("rk4", batch=True)
    with pytest.raises(
        InputError,
        match=r"Expected a torque independent of the attitude for a metrics kernel without it, "
        r"got ConstantSpaceTorque, which depends on it\.",
    ):
        rk4.kernel("metrics", torque, attitude=False)
    orbiting = bind(push + tb.torques.GravityGradient(1e-3), BodyBatch(moments), bodies=n)
    with pytest.raises(
        InputError, match=r"got ConstantSpaceTorque and GravityGradient, which depend on it\."
    ):
        rk4.kernel("metrics", orbiting, attitude=False)
    runs = []
    for final_state in (True, False):
        batch = Batch(moments.T.copy(), omega.T.copy(), np.vstack([np.ones(n), np.zeros((3, n))]),
                      torque)  # fmt: skip
        runs.append((measure_batch(rk4, batch, dt, steps, axis, final_state=final_state), batch))
    assert_array_equal(runs[1][0], runs[0][0])
    assert_array_equal(runs[1][1].q, runs[0][1].q)
    assert_array_equal(runs[1][1].w, runs[0][1].w)


def test_only_a_stepping_integrators_metrics_kernel_is_specialised_for_a_principal_axis() -> None:
    # The closed form measures about any axis in its own frame: the hint names
    # the same kernel there, and for a stepping integrator's batch kernel.
    from tumble.body import BodyBatch
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    torque = bind(None, BodyBatch(np.array([[1.0, 2.0, 3.0]])), bodies=1)
    exact = get_integrator("exact", batch=True)
    assert exact.kernel("metrics", torque, principal_axis=1) is exact.kernel("metrics", torque)
    rk4 = get_integrator("rk4", batch=True)
    assert rk4.kernel("batch", torque, principal_axis=1) is rk4.kernel("batch", torque)
    assert rk4.kernel("metrics", torque, principal_axis=1) is not rk4.kernel("metrics", torque)
    # So is the attitude's: the closed form leaves the states to measure_batch.
    assert exact.kernel("metrics", torque, attitude=False) is exact.kernel("metrics", torque)
    assert rk4.kernel("batch", torque, attitude=False) is rk4.kernel("batch", torque)
    assert rk4.kernel("metrics", torque, attitude=False) is not rk4.kernel("metrics", torque)
    # The splittings keep it: they mark a step beyond their sines' range by a NaN
    # quaternion alone, which a kernel without the attitude would not see.
    for name in ("strang", "splitting"):
        splitting = get_integrator(name, batch=True)
        assert not splitting.measures_without_attitude
        assert splitting.kernel("metrics", torque, attitude=False) is splitting.kernel(
            "metrics", torque
        )


def test_nominal_axes_lie_on_a_principal_axis_only_where_two_rows_are_zero() -> None:
    from tumble.batch.driver import _principal_axis_of

    on_axis_3 = np.zeros((3, 4))
    on_axis_3[2] = [1.0, -1.0, 1.0, 0.5]
    assert _principal_axis_of(on_axis_3) == 2
    on_axis_3[2, 3] = 0.0  # a body without a nominal axis: its a · L is 0, not L3
    assert _principal_axis_of(on_axis_3) is None
    mixed = np.zeros((3, 2))
    mixed[0, 0] = mixed[1, 1] = 1.0
    assert _principal_axis_of(mixed) is None
    assert _principal_axis_of(np.zeros((3, 2))) is None
    assert _principal_axis_of(np.full((3, 2), 0.5)) is None


@pytest.mark.parametrize(
    ("method", "dt"),
    [("rk4", 0.01), ("splitting", 0.01), ("splitting", 0.2), ("strang", 0.01), ("strang", 0.2)],
)
def test_the_measures_about_any_nominal_axis_match_the_stepped_states(
    method: str, dt: float
) -> None:
    # Oracle: the same bodies stepped by the plain batch kernel, their state after
    # each number of steps k taken by a run of k steps from the start, and the
    # measures taken from those states in numpy, by their definitions
    # (tumble.core.metrics): sign changes of a · L, the first one interpolated
    # linearly, min a·L/|L|, max |2E − 2E0|, max ||L| − |L0||. Nominal axes that
    # are no principal axis, and bodies with a block's worth and a ragged
    # remainder (200 = 128 + 72). The splittings' whole-block advances measure
    # through their observer, and their states are the plain kernel's bit for bit
    # (asserted: the same turns, and the sines with and without their reduction
    # agree bit for bit where both apply, whichever bodies share a block); at
    # dt = 0.2 s their turns reach 1.2 rad a sub-step, past the small angles, so
    # the sines reduce theirs. RK4 steps in the measuring loop
    # itself, which the compiler contracts and reorders apart from the plain
    # kernel: its states differ by 4e-13 of |ω| after the 600 steps (measured).
    # So the tolerances are round-off's: the cosine and the first flip's time to
    # 1e-12 (a · L is far from zero where it crosses).
    from tumble.batch import Batch, measure_batch, step_batch
    from tumble.body import BodyBatch
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    n, steps = 200, 600
    rng = np.random.default_rng(5)
    moments = np.column_stack([np.ones(n), rng.uniform(1.2, 1.8, n), np.full(n, 2.0)])
    # Half spun near the intermediate axis 2 (they flip), half near axis 3 (they do not).
    spin = np.where(np.arange(n) < n // 2, 1, 2)
    omega = rng.normal(0, 0.3, (n, 3))
    omega[np.arange(n), spin] = 6.0
    axis = rng.normal(size=(n, 3))
    axis[np.arange(n), spin] += 3.0
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)

    def batch() -> Batch:
        q = np.zeros((4, n))
        q[0] = 1.0
        torque = bind(None, BodyBatch(moments), bodies=n)
        return Batch(moments.T.copy(), omega.T.copy(), q, torque)

    integrator = get_integrator(method, batch=True)
    bodies = batch()
    measured = measure_batch(integrator, bodies, dt, steps, np.ascontiguousarray(axis.T))

    def after(k: int) -> np.ndarray:
        stepped = batch()
        if k:
            step_batch(integrator, stepped, dt, k)
        return stepped.w

    w = np.stack([after(k) for k in range(steps + 1)])  # (steps + 1, 3, n)
    if method != "rk4":
        assert np.array_equal(bodies.w, w[-1])
    momentum = moments.T[None] * w
    along = np.einsum("kin,ni->kn", momentum, axis)
    size = np.linalg.norm(momentum, axis=1)
    twice_energy = np.sum(momentum * w, axis=1)
    times = dt * np.arange(steps + 1)
    flipped = 0
    for k in range(n):
        crossings = np.flatnonzero(along[:-1, k] * along[1:, k] < 0)
        assert measured[FLIPS, k] == len(crossings)
        if len(crossings):
            flipped += 1
            j = crossings[0]
            first = times[j] + dt * along[j, k] / (along[j, k] - along[j + 1, k])
            assert measured[FIRST_FLIP, k] == pytest.approx(first, abs=1e-12)
        else:
            assert measured[FIRST_FLIP, k] == math.inf
        assert measured[MIN_COS, k] == pytest.approx(np.min(along[:, k] / size[:, k]), abs=1e-12)
        # The deviations are differences of nearly equal numbers: each side is
        # rounded (FMA in the kernel, numpy's order here) to a few ε of 2E or |L|,
        # and the two RK4 trajectories' round-off moves RK4's error in 2E by
        # ~10 ε; the splittings' trajectories are the same. (The splittings keep
        # |L| to round-off, so their |L| deviation is itself a few ε: RK4's,
        # 1e-9 of |L|, is the case that tells a measure from none.)
        energy = np.max(np.abs(twice_energy[:, k] - twice_energy[0, k]))
        scale = (64 if method == "rk4" else 8) * np.finfo(float).eps
        assert measured[ENERGY_DEVIATION, k] == pytest.approx(
            energy, abs=scale * twice_energy[0, k]
        )
        drift = np.max(np.abs(size[:, k] - size[0, k]))
        assert measured[MOMENTUM_DEVIATION, k] == pytest.approx(drift, abs=scale * size[0, k])
    assert 0 < flipped < n  # both kinds of body are in the test


def _measured(method: str, moments: np.ndarray, omega: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The five measures of ``measure_batch`` for bodies (N, 3) over 600 steps of 10 ms."""
    from tumble.batch import Batch, measure_batch
    from tumble.body import BodyBatch
    from tumble.integrators import get_integrator
    from tumble.torques import bind

    n = len(moments)
    q = np.zeros((4, n))
    q[0] = 1.0
    batch = Batch(moments.T.copy(), omega.T.copy(), q, bind(None, BodyBatch(moments), bodies=n))
    integrator = get_integrator(method, batch=True)
    return measure_batch(integrator, batch, 0.01, 600, np.ascontiguousarray(axis.T))


@pytest.mark.parametrize("method", ["rk4", "splitting"])
@pytest.mark.parametrize("power", [-340, 340])
@pytest.mark.parametrize("principal", [False, True])
def test_the_measures_scale_exactly_with_the_moments(
    method: str, power: int, principal: bool
) -> None:
    # Oracle: Euler's equations are homogeneous in I, so moments scaled by 2^±340
    # (|L| about 1e±102) give the same ω(t) bit for bit (a power of two scales
    # without rounding): the flips, the first flip and the cosine are equal, and
    # 2E, |L| and their deviations scale by 2^power exactly. The nutation's
    # running fraction is compared by products of two |L|²-sized numbers, which
    # here would overflow (|L|⁴ ~ 1e408) or underflow (1e-408) were the nominal
    # axis not divided by |L₀| first. Nominal axes in any direction, and on
    # principal axis 2 (row 1), measured by the kernel for such axes (whose flips
    # follow L2 itself, |L|-sized).
    from tumble.batch.driver import _principal_axis_of
    from tumble.core.metrics import ENERGY_DEVIATION, MOMENTUM_DEVIATION

    n = 150
    rng = np.random.default_rng(8)
    moments = np.column_stack([np.ones(n), rng.uniform(1.2, 1.8, n), np.full(n, 2.0)])
    omega = rng.normal(0, 0.3, (n, 3))
    omega[:, 1] = 6.0
    axis = rng.normal(size=(n, 3))
    axis[:, 1] += 3.0
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    if principal:
        axis = np.tile([0.0, 1.0, 0.0], (n, 1))
    assert _principal_axis_of(axis.T) == (1 if principal else None)
    plain = _measured(method, moments, omega, axis)
    scaled = _measured(method, moments * 2.0**power, omega, axis)
    unchanged = [r for r in range(len(plain)) if r not in (ENERGY_DEVIATION, MOMENTUM_DEVIATION)]
    np.testing.assert_array_equal(scaled[unchanged], plain[unchanged])
    np.testing.assert_array_equal(scaled[ENERGY_DEVIATION], plain[ENERGY_DEVIATION] * 2.0**power)
    np.testing.assert_array_equal(
        scaled[MOMENTUM_DEVIATION], plain[MOMENTUM_DEVIATION] * 2.0**power
    )
    assert np.all(plain[0] > 0)  # every body flipped: the cosines went negative


@pytest.mark.parametrize("method", ["rk4", "splitting"])
def test_a_body_at_rest_measures_no_motion(method: str) -> None:
    # Oracle: a free body at rest stays at rest: L = 0 throughout, so no flip,
    # no first flip, no deviation; its cosine is 1 by definition (no angle
    # between the nominal axis and a zero L). Two bodies at rest beside one that
    # moves, in the same block.

    moments = np.array([[1.0, 1.5, 2.0]] * 3)
    omega = np.array([[0.0, 0.0, 0.0], [0.1, 6.0, 0.1], [0.0, 0.0, 0.0]])
    axis = np.array([[0.0, 1.0, 0.0]] * 3)
    measured = _measured(method, moments, omega, axis)
    at_rest = [0, 2]
    assert np.all(measured[FLIPS, at_rest] == 0)
    assert np.all(measured[FIRST_FLIP, at_rest] == math.inf)
    assert np.all(measured[MIN_COS, at_rest] == 1.0)
    assert np.all(measured[ENERGY_DEVIATION, at_rest] == 0.0)
    assert np.all(measured[MOMENTUM_DEVIATION, at_rest] == 0.0)
    assert measured[FLIPS, 1] > 0  # the moving one, spun near its intermediate axis, flips
