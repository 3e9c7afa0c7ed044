"""Many throws in one recording: the synthetic recording against its own truth (the exact
torque-free motion, the energy drag takes), every free flight found in it, and windows
chosen by hand, checked and read from CSV files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import simpson

from tumble.errors import InputError
from tumble.identification import (
    ThrowsRecording,
    example_throws_path,
    free_flight,
    free_flights,
    read_windows,
    synthetic_throws,
)
from tumble.identification.recordings import PHYPHOX_COLUMNS, phyphox_csv, read_recording
from tumble.identification.result import principal_rates
from tumble.identification.windows import check_windows


@pytest.fixture(scope="module")
def throws() -> ThrowsRecording:
    """Thirty throws under the default drag and noise."""
    return synthetic_throws(30, seed=1)


def flight_rates(recording: ThrowsRecording, window: tuple[float, float]) -> np.ndarray:
    """The samples of a throw's free flight, less the bias, in the principal axes, rad/s."""
    start, end = window
    inside = (recording.t >= start - 1e-9) & (recording.t <= end + 1e-9)
    return (recording.omega[inside] - recording.bias) @ recording.axes


# ------------------------------------------------------------------ the recording
def test_torque_free_throws_are_the_exact_motion() -> None:
    # tumble.simulate (adaptive, 1e-12) against the Jacobi elliptic solution: measured
    # 5e-11 rad/s at most over 0.79 s of 7–12 rad/s; asked 1e-9.
    recording = synthetic_throws(6, seed=3, drag=(0.0, 0.0, 0.0), noise=0.0)
    moments = np.array([*recording.moment_ratios, 1.0])
    for window, omega0 in zip(recording.windows, recording.omega0, strict=True):
        rates = flight_rates(recording, window)
        times = np.arange(len(rates)) / 100.0
        assert len(rates) == 80
        assert_allclose(rates, principal_rates(moments, omega0, times), rtol=0, atol=1e-9)


def test_drag_takes_the_energy_its_torque_dissipates() -> None:
    # Under τ_i = −c_i ω_i the energy per I3, E = ½ Σ r_i ω_i², falls at Σ (c_i/I3) ω_i²:
    # the loss over each flight equals that rate's integral (Simpson's rule, error of
    # order h⁴ ω⁗: measured 4e-7 relative; asked 1e-5), and E falls at every sample.
    recording = synthetic_throws(6, seed=3, noise=0.0)
    moments = np.array([*recording.moment_ratios, 1.0])
    assert_allclose(recording.drag, [0.05, 0.12, 0.15])
    for window, omega0 in zip(recording.windows, recording.omega0, strict=True):
        rates = flight_rates(recording, window)
        assert_allclose(rates[0], omega0, rtol=0, atol=1e-12)
        energy = 0.5 * np.sum(moments * rates**2, axis=1)
        times = np.arange(len(rates)) / 100.0
        dissipated = simpson(np.sum(recording.drag * rates**2, axis=1), x=times)
        assert np.all(np.diff(energy) < 0)
        assert_allclose(energy[0] - energy[-1], dissipated, rtol=1e-5)


def test_the_noise_is_white_of_the_given_size_and_the_truth_does_not_depend_on_it() -> None:
    noisy = synthetic_throws(10, seed=2)
    clean = synthetic_throws(10, seed=2, noise=0.0)
    noise = (noisy.omega - clean.omega).ravel()
    # n ≈ 5800 draws: the sample σ is within 5 of its standard errors σ/√(2n) (5 %),
    # the mean within 5 σ/√n, and neighbours uncorrelated within 5/√n.
    assert noise.size > 5000
    assert abs(noise.std() / noisy.noise - 1.0) < 5.0 / np.sqrt(2 * noise.size)
    assert abs(noise.mean()) < 5.0 * noisy.noise / np.sqrt(noise.size)
    steps = noisy.omega - clean.omega
    lag = np.sum(steps[1:] * steps[:-1]) / np.sum(steps**2)
    assert abs(lag) < 5.0 / np.sqrt(noise.size)
    assert noisy.windows == clean.windows
    assert_allclose(noisy.omega0, clean.omega0, rtol=0, atol=0)


def test_the_recording_is_evenly_sampled_with_throws_held_between() -> None:
    recording = synthetic_throws(8, seed=4)
    t = recording.t
    assert_allclose(np.diff(t), 0.01, rtol=0, atol=1e-12)
    assert len(recording.windows) == 8 and recording.omega0.shape == (8, 3)
    # Releases about the intermediate axis, 7–12 rad/s, the others within ±1 and ±1.5.
    assert np.all((np.abs(recording.omega0[:, 1]) >= 7) & (np.abs(recording.omega0[:, 1]) <= 12))
    assert np.all(np.abs(recording.omega0[:, 0]) <= 1.0)
    assert np.all(np.abs(recording.omega0[:, 2]) <= 1.5)
    assert {np.sign(w) for w in recording.omega0[:, 1]} == {-1.0, 1.0}
    # Each flight: 80 samples; between two, at least 0.8 s held plus the catch and the
    # spin-up, where the hand turns it at 0.3√3 rad/s at most (plus noise, 5σ).
    starts = np.array([start for start, _ in recording.windows])
    ends = np.array([end for _, end in recording.windows])
    assert_allclose(ends - starts, 0.79, atol=1e-9)
    assert np.all(starts[1:] - ends[:-1] >= 0.8 + 0.06 + 0.04 - 1e-9)
    held = np.ones(len(t), dtype=bool)
    for start, end in recording.windows:
        held &= (t < start - 0.06 - 1e-9) | (t > end + 0.04 + 1e-9)
    speed = np.linalg.norm(recording.omega[held] - recording.bias, axis=1)
    assert speed.max() <= 0.3 * np.sqrt(3) + 5 * np.sqrt(3) * recording.noise
    # The same seed, the same recording; another seed, another.
    again = synthetic_throws(8, seed=4)
    assert np.array_equal(again.omega, recording.omega)
    assert not np.array_equal(synthetic_throws(8, seed=5).omega0, recording.omega0)


def test_the_shipped_example_is_synthetic_throws_12_0_to_the_printed_precision() -> None:
    recording = read_recording(example_throws_path())
    truth = synthetic_throws(12, seed=0)
    assert recording.columns == PHYPHOX_COLUMNS and recording.note == ""
    assert recording.t.shape == truth.t.shape
    # %.6f times (half a µs) and %.9g rates (half a unit in the 9th digit).
    assert_allclose(recording.t, truth.t, rtol=0, atol=5.01e-7)
    assert np.all(np.abs(recording.omega - truth.omega) <= 5.01e-9 * np.abs(truth.omega) + 1e-300)
    assert example_throws_path().read_text() == phyphox_csv(truth.t, truth.omega)


# ------------------------------------------------------------------ free flights
def test_free_flights_finds_every_throw_inside_its_flight(throws: ThrowsRecording) -> None:
    found = free_flights(throws.t, throws.omega)
    assert len(found) == len(throws.windows) == 30
    assert found == sorted(found)
    for (start, end), (release, last) in zip(found, throws.windows, strict=True):
        assert release <= start < end <= last
        # Measured 91 %: 3 samples dropped after the release, 4 before the catch (the
        # last flight sample's difference reaches into the catch's impact). Asked 85 %.
        assert (end - start) / (last - release) > 0.85


def test_free_flight_is_the_longest_of_the_free_flights() -> None:
    shorter = synthetic_throws(2, seed=1)
    longer = synthetic_throws(1, seed=2, samples=120)
    t = np.concatenate([shorter.t, shorter.t[-1] + 0.01 + longer.t])
    omega = np.concatenate([shorter.omega, longer.omega])
    found = free_flights(t, omega)
    assert len(found) == 3
    start, end = free_flight(t, omega)
    assert (start, end) == found[2]
    release, last = longer.windows[0]
    assert release + shorter.t[-1] + 0.01 <= start < end <= last + shorter.t[-1] + 0.01 + 1e-9


def test_free_flights_skips_flights_too_short() -> None:
    # Throws of 30 samples keep at most 30 − 7 < MIN_FLIGHT after their edges are dropped.
    short = synthetic_throws(3, seed=0, samples=30)
    with pytest.raises(
        InputError, match=r"^Expected a free flight of at least 30 samples .* got 2"
    ):
        free_flights(short.t, short.omega)
    # Joined to a recording of full throws, only those are found.
    full = synthetic_throws(2, seed=1)
    t = np.concatenate([full.t, full.t[-1] + 0.01 + short.t])
    omega = np.concatenate([full.omega, short.omega])
    found = free_flights(t, omega)
    assert len(found) == 2
    assert all(r <= s and e <= last for (s, e), (r, last) in zip(found, full.windows, strict=True))


def test_a_recording_held_in_the_hand_has_no_free_flight() -> None:
    t = np.arange(500) / 100.0
    omega = 0.3 * np.sin(2 * np.pi * np.array([0.9, 1.3, 0.7]) * t[:, None] + [0.1, 2.0, 4.0])
    with pytest.raises(InputError, match=r"^Expected a free flight of at least 30 samples"):
        free_flights(t, omega)


# ------------------------------------------------------------------ windows by hand
TIMES = np.arange(1000) / 100.0  # 0 to 9.99 s


def test_check_windows_sorts_them_by_start() -> None:
    windows = check_windows([(5, 6.5), np.array([1.0, 2.0])], TIMES)
    assert windows == [(1.0, 2.0), (5.0, 6.5)]
    assert all(isinstance(value, float) for window in windows for value in window)


@pytest.mark.parametrize(
    ("windows", "message"),
    [
        ([], r"^Expected at least one window \(start, end\), got none\.$"),
        ([(1, 2), (3,)], r"^Expected window 2 to be \(start, end\) in s, got \(3,\)\.$"),
        ([(1, 2), "ab"], r"^Expected window 2 to be \(start, end\) in s, got 'ab'\.$"),
        ([(2, 1)], r"^Expected window 1 to have finite start < end, got 2\.0–1\.0 s\.$"),
        ([(1, float("nan"))], r"^Expected window 1 to have finite start < end, got 1\.0–nan s"),
        (
            [(1, 2), (9, 10.5)],
            r"^Expected window 2 inside the recording \(0–9\.99 s\), got 9–10\.5 s\.$",
        ),
        ([(-0.5, 2)], r"^Expected window 1 inside the recording \(0–9\.99 s\), got -0\.5–2 s"),
        (
            [(1, 2), (3, 3.2)],
            r"^Expected at least 30 samples in window 2, got 21 in 3–3\.2 s\.$",
        ),
        (
            [(4, 5), (1, 2), (1.5, 3)],
            r"^Expected windows that do not overlap, got window 2 \(1–2 s\) and window 3 "
            r"\(1\.5–3 s\)\.$",
        ),
        (
            [(3, 4), (1, 3)],
            r"^Expected windows that do not overlap, got window 2 \(1–3 s\) and window 1 "
            r"\(3–4 s\)\.$",
        ),
    ],
)
def test_check_windows_refuses(windows: list, message: str) -> None:
    with pytest.raises(InputError, match=message):
        check_windows(windows, TIMES)


def test_read_windows_reads_the_start_and_end_columns(
    throws: ThrowsRecording, tmp_path: Path
) -> None:
    path = tmp_path / "windows.csv"
    rows = [f"{i}, {start!r}, {end!r} ,throw" for i, (start, end) in enumerate(throws.windows)]
    path.write_text("\n".join(["number, start , end ,note", *rows]) + "\n")
    windows = read_windows(path)
    assert windows == list(throws.windows)
    assert check_windows(windows[::-1], throws.t) == list(throws.windows)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", r"^Expected a CSV file of windows with columns start,end, got '.*', which is empty"),
        ("start,end\n", r"^Expected at least one window in '.*', got a header only\.$"),
        (
            "begin,finish,note\n1,2,a\n",
            r"^Expected columns named start and end in '.*', got columns 'begin', 'finish', "
            r"'note'\.$",
        ),
        (
            "start,end\n1,2\n\n3,x\n",
            r"^Expected numbers \(s\) for start and end in '.*', got '3', 'x' in row 2 after "
            r"the header\.$",
        ),
        ("start,end\n1,\n", r"got '1', '' in row 1 after the header\.$"),
        (
            "start,end\n1,2\n3,4,5,6\n",
            r"^Expected a CSV file of windows, got '.*', which is not one \(Error tokenizing",
        ),
    ],
)
def test_read_windows_refuses(text: str, message: str, tmp_path: Path) -> None:
    path = tmp_path / "windows.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_windows(path)


def test_read_windows_refuses_what_is_not_a_file_of_text(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"^Expected a CSV file of windows, got '.*' \(no such"):
        read_windows(tmp_path / "missing.csv")
    with pytest.raises(InputError, match=r"^Expected a CSV file of windows, got '.*' \(a folder\)"):
        read_windows(tmp_path)
    binary = tmp_path / "windows.png"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\xff\xfe")
    with pytest.raises(
        InputError, match=r"^Expected a CSV file of windows, got '.*', which is not"
    ):
        read_windows(binary)
