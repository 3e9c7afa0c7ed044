"""Recordings read from files: phyphox's exports, plain CSV, Parquet; the columns
and units found or given; a clear error for every file that cannot be read; and
the shipped example, which must stay what synthetic_phone(0) makes."""

from __future__ import annotations

import math
import zipfile
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from tumble.errors import InputError
from tumble.identification import synthetic_phone
from tumble.identification.recordings import (
    PHYPHOX_COLUMNS,
    example_recording_path,
    phyphox_csv,
    read_recording,
)


@pytest.fixture(scope="module")
def example() -> tuple[np.ndarray, np.ndarray]:
    """The shipped recording's samples as its file holds them."""
    recording = read_recording(example_recording_path())
    return recording.t, recording.omega


def table(header: list[str] | None, t: np.ndarray, omega: np.ndarray, sep: str = ",") -> str:
    rows = [
        sep.join(f"{v:.17g}" for v in (time, *rate)) for time, rate in zip(t, omega, strict=True)
    ]
    return "\n".join(([sep.join(header)] if header else []) + rows) + "\n"


def test_the_shipped_example_is_synthetic_phone_0_to_the_printed_precision() -> None:
    recording = read_recording(example_recording_path())
    truth = synthetic_phone(0)
    assert recording.columns == PHYPHOX_COLUMNS and recording.note == ""
    assert recording.t.shape == truth.t.shape
    # %.6f times (half a µs) and %.9g rates (half a unit in the 9th digit).
    assert_allclose(recording.t, truth.t, rtol=0, atol=5.01e-7)
    assert np.all(np.abs(recording.omega - truth.omega) <= 5.01e-9 * np.abs(truth.omega) + 1e-300)
    assert example_recording_path().read_text() == phyphox_csv(recording.t, recording.omega)


def test_phyphox_locales_semicolons_with_decimal_commas_and_tabs(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    text = phyphox_csv(t, omega)
    semicolons = tmp_path / "semicolons.csv"
    semicolons.write_text(text.replace(",", ";").replace(".", ","))
    tabs = tmp_path / "tabs.csv"
    tabs.write_text(text.replace(",", "\t"))
    for path in (semicolons, tabs):
        recording = read_recording(path)
        assert recording.columns == PHYPHOX_COLUMNS
        assert_array_equal(recording.t, t)
        assert_array_equal(recording.omega, omega)


def test_phyphox_zip_export_reads_its_table(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    path = tmp_path / "Gyroscope rotation rate 2025-01-01.zip"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("Raw Data.csv", phyphox_csv(t, omega))
        archive.writestr("meta/device.csv", '"property","value"\n"model","phone"\n')
        archive.writestr("meta/time.csv", '"event","experiment time"\n"START",0\n')
    recording = read_recording(path)
    assert_array_equal(recording.omega, omega)


def test_columns_found_given_by_name_or_position(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    path = tmp_path / "wide.csv"
    wide = np.column_stack([np.arange(t.size), t, omega, np.linalg.norm(omega, axis=1)])
    lines = ["index,time_s,gx,gy,gz,absolute"] + [
        ",".join(f"{v:.17g}" for v in row) for row in wide
    ]
    path.write_text("\n".join(lines) + "\n")
    found = read_recording(path)  # the time column and the three after it
    assert found.columns == ("time_s", "gx", "gy", "gz")
    assert_array_equal(found.omega, omega)
    by_name = read_recording(path, columns="time_s, gz, gy, gx")
    assert_array_equal(by_name.omega, omega[:, ::-1])
    assert_array_equal(read_recording(path, columns=["TIME_S", "gx", "gy", "gz"]).t, t)
    by_position = read_recording(path, columns="1,2,3,4")
    assert by_position.columns == ("time_s", "gx", "gy", "gz")
    assert_array_equal(read_recording(path, columns=[1, 4, 3, 2]).omega, omega[:, ::-1])


def test_a_name_without_its_unit_picks_the_column(tmp_path: Path) -> None:
    path = tmp_path / "phyphox.csv"
    path.write_text(phyphox_csv(np.arange(5.0), np.ones((5, 3))))
    recording = read_recording(path, columns="time, gyroscope x, gyroscope y, gyroscope z")
    assert recording.columns == PHYPHOX_COLUMNS


def test_a_file_without_a_header_is_read_by_position(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    path = tmp_path / "bare.csv"
    path.write_text(table(None, t, omega))
    recording = read_recording(path, units="rad/s")
    assert_array_equal(recording.omega, omega)
    assert recording.note == "no header row: columns 0, 1, 2, 3 read as t, ωx, ωy, ωz"


@pytest.mark.parametrize("unit", ["deg/s", "°/s", "dps"])
def test_a_header_in_degrees_converts(
    unit: str, example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    path = tmp_path / "degrees.csv"
    header = ["Time (ms)", *(f"{axis} ({unit})" for axis in "xyz")]
    path.write_text(table(header, t * 1e3, np.degrees(omega)), encoding="utf-8")
    recording = read_recording(path)
    assert recording.note == ""
    assert_allclose(recording.t, t, rtol=1e-15)
    assert_allclose(recording.omega, omega, rtol=1e-14, atol=1e-300)


def test_units_given_convert_and_units_told_from_the_magnitude_say_so(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    t, omega = example
    fast = omega * 60.0  # 720 rad/s at most: beyond any throw, as deg/s it is 12.6 rad/s
    path = tmp_path / "plain.csv"
    path.write_text(table(["t", "wx", "wy", "wz"], t, fast))
    given = read_recording(path, units="deg/s")
    assert given.note == ""
    assert_allclose(given.omega, np.radians(fast), rtol=1e-15)
    told = read_recording(path)
    assert_allclose(told.omega, np.radians(fast), rtol=1e-15)
    largest = np.abs(fast).max()
    assert told.note == (
        f"read as deg/s: the largest rate, {largest:.4g}, would be "
        f"{largest / (2 * math.pi):.3g} turns/s in rad/s; --units rad/s to keep rad/s"
    )
    kept = read_recording(path, units="rad/s")
    assert_array_equal(kept.omega, fast)
    path.write_text(table(["t", "wx", "wy", "wz"], t, omega))
    slow = read_recording(path)
    assert_array_equal(slow.omega, omega)
    assert slow.note.startswith("read as rad/s (no unit stated; the largest rate, 12.04, is 1.92")


def test_parquet(example: tuple[np.ndarray, np.ndarray], tmp_path: Path) -> None:
    t, omega = example
    path = tmp_path / "rates.parquet"
    columns = {"t": t, "omega_x": omega[:, 0], "omega_y": omega[:, 1], "omega_z": omega[:, 2]}
    pq.write_table(pa.table(columns), path)
    recording = read_recording(path)
    assert recording.columns == ("t", "omega_x", "omega_y", "omega_z")
    assert_array_equal(recording.t, t)
    assert_array_equal(recording.omega, omega)
    # A Parquet file is known by its first bytes whatever its name.
    renamed = path.rename(tmp_path / "rates.bin")
    assert_array_equal(read_recording(renamed, columns="0,1,2,3").omega, omega)


def test_not_a_number_is_left_to_the_fit(tmp_path: Path) -> None:
    import tumble as tb

    path = tmp_path / "gap.csv"
    t = np.arange(40) * 0.01
    omega = np.ones((40, 3))
    omega[5, 1] = np.nan
    path.write_text(table(["t", "wx", "wy", "wz"], t, omega))
    recording = read_recording(path, units="rad/s")
    with pytest.raises(
        InputError, match=r"Expected finite times and rates, got 1 sample that is not .*sample 5"
    ):
        tb.identify(recording.t, recording.omega)


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


GOOD = "t,wx,wy,wz\n0,1,2,3\n0.1,1,2,3\n"


@pytest.mark.parametrize(
    ("name", "text", "kwargs", "message"),
    [
        ("gaps.csv", "t,wx,wy,wz\n0,1,2,3\n0.1,1,x2,3\n", {},
         r"^Expected numbers in '.*gaps\.csv', got 'x2' at line 3, column 'wy'\.$"),
        ("empty.csv", "\n\n", {},
         r"^Expected a header row and rows of samples in '.*empty\.csv', got an empty file\.$"),
        ("header.csv", "t,wx,wy,wz\n", {},
         r"^Expected rows of samples after the header of '.*header\.csv', got none\.$"),
        ("short.csv", "t,wx,wy,wz\n0,1,2,3\n0.1,1,2\n", {},
         r"^Expected 4 cells in each row of '.*short\.csv' \(as in its header\), got 3 in line 3\.$"),
        ("names.csv", GOOD, {"columns": "time,wx,wy,wz"},
         r"^Expected a column named 'time' in '.*names\.csv', got columns 't', 'wx', 'wy', 'wz'\.$"),
        ("positions.csv", GOOD, {"columns": [0, 1, 2, 7]},
         r"^Expected column positions 0 to 3 in '.*positions\.csv', got 7 \(the columns are 't', 'wx', 'wy', 'wz'\)\.$"),
        ("count.csv", GOOD, {"columns": "t,wx,wy"},
         r"^Expected `columns` to be 4 names or positions \(t, ωx, ωy, ωz\), got 3: 't,wx,wy'\.$"),
        ("twice.csv", GOOD, {"columns": "t,wx,wx,wz"},
         r"^Expected 4 different columns, got 't,wx,wx,wz'\.$"),
        ("notime.csv", "a,b,c,d\n0,1,2,3\n", {},
         r"^Expected a time column \(named 't' or 'time…'\) in '.*notime\.csv', got columns 'a', 'b', 'c', 'd' \(choose four with `columns`, --columns t,wx,wy,wz\)\.$"),
        ("narrow.csv", "t,wx,wy\n0,1,2\n", {},
         r"^Expected three rate columns after the time column 't' in '.*narrow\.csv', got columns 't', 'wx', 'wy' \(choose four"),
        ("accel.csv", "Time (s),ax (m/s^2),ay (m/s^2),az (m/s^2)\n0,1,2,3\n", {},
         r"^Expected angular rates in rad/s or deg/s, got the column 'ax \(m/s\^2\)' in '.*accel\.csv' \(unit 'm/s\^2'\)\.$"),
        ("mixed.csv", "t,x (rad/s),y (deg/s),z (rad/s)\n0,1,2,3\n", {},
         r"^Expected the three rate columns in one unit, got 'x \(rad/s\)', 'y \(deg/s\)', 'z \(rad/s\)'\.$"),
        ("clock.csv", "t (h),x,y,z\n0,1,2,3\n", {},
         r"^Expected the time column in s or ms, got 't \(h\)' in '.*clock\.csv' \(unit 'h'\)\.$"),
        ("stated.csv", "t,x (rad/s),y (rad/s),z (rad/s)\n0,1,2,3\n", {"units": "deg/s"},
         r"^Expected `units` to agree with the header of '.*stated\.csv', which states rad/s, got 'deg/s' \(leave it out to read rad/s\)\.$"),
        ("units.csv", GOOD, {"units": "rpm"},
         r"^Expected `units` to be 'rad/s' or 'deg/s', got 'rpm'\.$"),
    ],
)  # fmt: skip
def test_errors_name_the_value_what_was_expected_and_what_was_received(
    name: str, text: str, kwargs: dict[str, object], message: str, tmp_path: Path
) -> None:
    with pytest.raises(InputError, match=message):
        read_recording(write(tmp_path, name, text), **kwargs)  # type: ignore[arg-type]


def test_files_that_are_no_recording(tmp_path: Path) -> None:
    with pytest.raises(
        InputError,
        match=r"^Expected a recording file \(CSV or Parquet\), got '.*nothere\.csv' \(no such file\)\.$",
    ):
        read_recording(tmp_path / "nothere.csv")
    with pytest.raises(
        InputError, match=r"^Expected a recording file \(CSV or Parquet\), got '.*', a folder\.$"
    ):
        read_recording(tmp_path)
    binary = tmp_path / "image.png"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    with pytest.raises(
        InputError,
        match=r"^Expected a CSV or Parquet file, got '.*image\.png', which is neither \(binary data\)\.$",
    ):
        read_recording(binary)
    damaged = tmp_path / "damaged.zip"
    damaged.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(
        InputError,
        match=r"^Expected a CSV or Parquet file, got '.*damaged\.zip', a damaged zip file\.$",
    ):
        read_recording(damaged)
    broken = tmp_path / "broken.parquet"
    broken.write_bytes(b"PAR1 not really")
    with pytest.raises(
        InputError,
        match=r"^Expected a CSV or Parquet file, got '.*broken\.parquet', which is not valid Parquet",
    ):
        read_recording(broken)
    sheet = tmp_path / "export.xlsx"
    with zipfile.ZipFile(sheet, "w") as archive:
        archive.writestr("[Content_Types].xml", "<Types/>")
    with pytest.raises(
        InputError,
        match=r"^Expected a CSV or Parquet file, got '.*export\.xlsx', a spreadsheet \(export it as CSV\)\.$",
    ):
        read_recording(sheet)
    several = tmp_path / "several.zip"
    with zipfile.ZipFile(several, "w") as archive:
        archive.writestr("Accelerometer.csv", GOOD)
        archive.writestr("Magnetometer.csv", GOOD)
    with pytest.raises(
        InputError,
        match=r"^Expected a zip file with one CSV table of data \(as phyphox exports\), got '.*several\.zip' with 2: 'Accelerometer\.csv', 'Magnetometer\.csv'",
    ):
        read_recording(several)
    strings = tmp_path / "strings.parquet"
    pq.write_table(
        pa.table({"t": [0.0, 1.0], "x": ["a", "b"], "y": [1.0, 2.0], "z": [1.0, 2.0]}), strings
    )
    with pytest.raises(
        InputError,
        match=r"^Expected numbers in the column 'x' of '.*strings\.parquet', got values of type string\.$",
    ):
        read_recording(strings)


def test_an_unreadable_file_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # The file system refuses the read (as for a file without read permission,
    # which the superuser running CI could still read).
    locked = write(tmp_path, "locked.csv", GOOD)

    def refuse(self: Path, *args: object, **kwargs: object) -> object:
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "open", refuse)
    with pytest.raises(
        InputError,
        match=r"^Expected a readable recording file, got '.*locked\.csv': Permission denied\.$",
    ):
        read_recording(locked)


def test_files_named_zip_that_hold_no_table(tmp_path: Path) -> None:
    junk = write(tmp_path, "junk.zip", "this is no zip file\n")
    with pytest.raises(
        InputError,
        match=r"^Expected a zip file, as the name '.*junk\.zip' says, got a file that is not one "
        r"\(a CSV table is read from a file named \.csv\)\.$",
    ):
        read_recording(junk)
    empty = tmp_path / "empty.zip"
    zipfile.ZipFile(empty, "w").close()
    with pytest.raises(
        InputError,
        match=r"^Expected a zip file with one CSV table of data \(as phyphox exports\), got "
        r"'.*empty\.zip', an empty zip file\.$",
    ):
        read_recording(empty)
    meta = tmp_path / "meta.zip"
    with zipfile.ZipFile(meta, "w") as archive:
        archive.writestr("meta/device.csv", "a,b\n")
        archive.writestr("notes.txt", "thrown twice")
    with pytest.raises(
        InputError,
        match=r"^Expected a zip file with one CSV table of data \(as phyphox exports\), got "
        r"'.*meta\.zip', which holds none \(it holds 'meta/device\.csv', 'notes\.txt'\)\.$",
    ):
        read_recording(meta)


def test_a_damaged_table_inside_a_zip_file(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    # The CRC of the table is wrong: found as the table is read.
    path = tmp_path / "crc.zip"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as archive:
        archive.writestr("Gyroscope.csv", phyphox_csv(*example))
    data = bytearray(path.read_bytes())
    data[data.index(b"0.000000,") + 2] ^= 1  # a digit of the first time
    path.write_bytes(bytes(data))
    with pytest.raises(
        InputError,
        match=r"^Expected a CSV or Parquet file, got '.*crc\.zip', a damaged zip file\.$",
    ):
        read_recording(path)


def big_table(rows: int) -> str:
    t = np.arange(rows) * 0.002
    return table(list(PHYPHOX_COLUMNS), t, np.full((rows, 3), 0.5))


@pytest.mark.parametrize("kind", ["csv", "zip", "parquet"])
def test_a_recording_beyond_the_memory_budget_is_refused_before_it_is_read(
    kind: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # 20000 rows: half a MB of text, more than a budget of 1 MB holds at the
    # memory tumble fit takes a sample. The zip file is small: its table's size
    # is what counts.
    rows = 20_000
    if kind == "csv":
        path = write(tmp_path, "big.csv", big_table(rows))
        what = r"the recording '.*big\.csv' of \d+(\.\d+)? KiB, about 2\.\d+e\+04 samples"
    elif kind == "zip":
        path = tmp_path / "big.zip"
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("Gyroscope.csv", big_table(rows))
        assert path.stat().st_size < 200_000
        what = (
            r"the recording '.*big\.zip:Gyroscope\.csv' of \d+(\.\d+)? KiB \(uncompressed\), "
            r"about 2\.\d+e\+04 samples"
        )
    else:
        path = tmp_path / "big.parquet"
        t = np.arange(rows) * 0.002
        pq.write_table(pa.table({"t": t, "x": t, "y": t, "z": t}), path)
        what = r"the recording '.*big\.parquet', about 2e\+04 samples"
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 MB")
    with pytest.raises(
        InputError,
        match=r"^Expected a request that fits in the memory budget of 977 KiB \(TUMBLE_MEMORY_BUDGET "
        rf"= 1 MB\), got {what}: about \d+(\.\d+)? MiB\. Cut the recording to the throw and the "
        r"free flight \(a few seconds\)\.$",
    ):
        read_recording(path)
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 GB")
    assert read_recording(path).t.size == rows


def test_a_table_that_understates_its_rows_is_refused_as_it_is_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Long rows first (64 KiB of them), then short ones: the estimate from the
    # first rows is far too low, and the rows read decide.
    long_rows = "".join(
        f"{k * 0.001:.17f},{1 / 3:.17f},{1 / 7:.17f},{1 / 9:.17f}\n" for k in range(1000)
    )
    short_rows = "1,0,0,0\n" * 150_000
    path = write(tmp_path, "uneven.csv", "t,x,y,z\n" + long_rows + short_rows)
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "60 MB")
    with pytest.raises(
        InputError,
        match=r"got the recording '.*uneven\.csv' \(read so far\), about 1\.\d+e\+05 samples",
    ):
        read_recording(path)


def test_rows_the_block_reader_refuses_are_read_line_by_line(
    example: tuple[np.ndarray, np.ndarray], tmp_path: Path
) -> None:
    # Rows with a trailing separator (more cells than the header), blank and
    # separator-only lines, a Latin-1 byte beyond the first block, and a time
    # with a digit separator that Python reads: all read as the plain table is.
    t, omega = example
    plain = read_recording(write(tmp_path, "plain.csv", phyphox_csv(t, omega)))
    text = phyphox_csv(t, omega)
    lines = text.splitlines()
    trailing = "\n".join([lines[0]] + [line + "," for line in lines[1:]]) + "\n"
    blanks = "\n".join([*lines[:10], "", ",,,", "  ", *lines[10:]]) + "\n"
    latin = "\n".join([*lines[:1500], lines[1500] + ",\xb0", *lines[1501:]]) + "\n"
    for name, content, encoding in (
        ("trailing.csv", trailing, "utf-8"),
        ("blanks.csv", blanks, "utf-8"),
        ("latin.csv", latin, "latin-1"),
    ):
        path = tmp_path / name
        path.write_bytes(content.encode(encoding))
        recording = read_recording(path)
        assert_array_equal(recording.t, plain.t)
        assert_array_equal(recording.omega, plain.omega)


def test_a_long_table_is_read_exactly(tmp_path: Path) -> None:
    # Beyond the first block of 64 KiB, and in several blocks of the reader;
    # with a BOM and no header. Oracle: the numbers written with 17 digits.
    generator = np.random.default_rng(4)
    t = np.cumsum(generator.uniform(0.001, 0.003, 60_000))
    omega = generator.normal(size=(60_000, 3))
    path = tmp_path / "long.csv"
    path.write_bytes(b"\xef\xbb\xbf" + table(None, t, omega).encode())
    recording = read_recording(path, units="rad/s")
    assert_array_equal(recording.t, t)
    assert_array_equal(recording.omega, omega)
    semicolons = tmp_path / "semicolons.csv"
    semicolons.write_text(table(["t", "x", "y", "z"], t, omega, sep=";").replace(".", ","))
    recording = read_recording(semicolons, units="rad/s")
    assert_array_equal(recording.t, t)
    assert_array_equal(recording.omega, omega)
