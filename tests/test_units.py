"""Units at the public edge: conversions against known factors, and every error message."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble.units import length_scale, to_si, ureg, vector_to_si


@pytest.mark.parametrize(
    ("value", "kind", "expected"),
    [
        ("250 g", "mass", 0.25),
        ("3 cm", "length", 0.03),
        ("1 inch", "length", 0.0254),  # exact by definition
        ("3000 rpm", "angular_velocity", 3000 * 2 * math.pi / 60),
        ("30 deg", "angle", math.pi / 6),
        ("2700 kg/m^3", "density", 2700.0),
        ("2.7 g/cm^3", "density", 2700.0),
        ("5 g*cm^2", "inertia", 5e-7),
        ("0.5", "mass", 0.5),  # a bare number is SI
        (2, "time", 2.0),
        (ureg.Quantity(2, "ms"), "time", 0.002),
    ],
)
def test_to_si_converts(value: object, kind: str, expected: float) -> None:
    assert to_si(value, kind, "x") == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize(
    ("value", "kind", "message"),
    [
        ("3 cm", "mass", r"Expected `x` to be a mass in kg, got 3 cm \(dimensions \[length\]\)"),
        ("3 kg", "angular_velocity", r"Expected `x` to be an angular velocity in rad/s, got 3 kg"),
        ("2 m", "angle", r"Expected `x` to be an angle in rad, got 2 m"),
        (
            "foo bar",
            "mass",
            r"Expected `x` to be a number or a quantity such as '250 g', got 'foo bar'",
        ),
        ("nan", "mass", r"Expected `x` to be finite, got 'nan' \(nan\)"),
        (float("inf"), "mass", r"Expected `x` to be finite, got inf"),
        ([1, 2], "mass", r"Expected `x` to be a scalar, got \[1, 2\]"),
        (True, "mass", r"Expected `x` to be a scalar, got True"),
        (None, "mass", r"Expected `x` to be a number or a quantity such as '250 g', got None"),
    ],
)
def test_to_si_errors(value: object, kind: str, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        to_si(value, kind, "x")


@pytest.mark.parametrize(
    "value",
    [
        "10, 20, 30 cm",
        "10 cm, 20 cm, 300 mm",
        "(0.1, 0.2, 0.3)",
        ["10 cm", 0.2, "30 cm"],
        ureg.Quantity(np.array([10.0, 20.0, 30.0]), "cm"),
        np.array([0.1, 0.2, 0.3]),
    ],
)
def test_vector_to_si_forms(value: object) -> None:
    assert_allclose(vector_to_si(value, "length", "size"), [0.1, 0.2, 0.3], rtol=1e-15)


def test_vector_to_si_matrix_rows_as_strings() -> None:
    got = vector_to_si(["1, 2, 3 mm", "4, 5, 6 mm"], "length", "p", (-1, 3))
    assert_allclose(got, [[1e-3, 2e-3, 3e-3], [4e-3, 5e-3, 6e-3]], rtol=1e-15)


@pytest.mark.parametrize(
    ("value", "shape", "message"),
    [
        ([1.0, 2.0], (3,), r"Expected `v` to have shape \(3,\), got \(2,\)"),
        ([[1.0, 2.0], [3.0]], (3,), r"Expected `v` to be a rectangular array"),
        ("1 kg, 2, 3", (3,), r"Expected `v` to be a length in m, got 1 kg"),
        ([1.0, float("inf"), 2.0], (3,), r"Expected `v` to be finite"),
        (np.array([1.0, np.nan, 2.0]), (3,), r"Expected `v` to be finite"),
        (
            "12",
            (3,),
            r"Expected `v` to be comma-separated values such as '10, 20, 30 mm', got '12'",
        ),
        (5.0, (3,), r"Expected `v` to be an array of shape \(3,\), got 5.0"),
        (np.zeros((2, 2)), (-1, 3), r"Expected `v` to have shape \(n, 3\), got \(2, 2\)"),
    ],
)
def test_vector_to_si_errors(value: object, shape: tuple[int, ...], message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        vector_to_si(value, "length", "v", shape)


def test_length_scale() -> None:
    assert length_scale("mm") == pytest.approx(1e-3, rel=1e-15)
    assert length_scale("inch") == pytest.approx(0.0254, rel=1e-15)
    with pytest.raises(tb.InputError, match=r"Expected `units` to be a length in m, got 1 kg"):
        length_scale("kg")
    with pytest.raises(
        tb.InputError,
        match=r"Expected `units` to be a length unit such as 'mm' or 'inch', got 'furlongz'",
    ):
        length_scale("furlongz")
    with pytest.raises(tb.InputError, match=r"Expected `units` to be a positive length unit, got"):
        length_scale(ureg.Quantity(-1, "mm"))


@pytest.mark.parametrize(
    ("value", "kind", "message"),
    [
        ("250 percent", "mass", r"Expected `x` to be a mass in kg, got 250 %"),
        ("50 cm/m", "length", r"Expected `x` to be a length in m, got 50.0 cm/m"),
        (
            "1 Hz",
            "angular_velocity",
            r"hertz is ambiguous for an angular velocity: write '1 turn/s'",
        ),
        ("1 g / 0", "mass", r"got '1 g / 0' \(a division by zero\)\.$"),
        ("(1 g", "mass", r"got '\(1 g' \(unbalanced parentheses\)\.$"),
        ("3 +", "mass", r"got '3 \+' \(not a valid expression\)\.$"),
        (
            "2 furlongz",
            "mass",
            r"got '2 furlongz' \('furlongz' is not defined in the unit registry\)",
        ),
        ("10**400 g", "mass", r"got '10\*\*400 g' \(too long or a runaway power\)"),
        ("9**9**9 g", "mass", r"\(too long or a runaway power\)"),
        ("1" * 300, "mass", r"got '1{60}'\.\.\. \(too long or a runaway power\)"),
        (
            np.complex128(1 + 5j),
            "mass",
            r"Expected `x` to be a real number, got np.complex128\(1\+5j\)",
        ),
        (np.True_, "mass", r"Expected `x` to be a scalar, got np.True_"),
    ],
)
def test_to_si_refuses_what_it_would_misread(value: object, kind: str, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        to_si(value, kind, "x")


# What pint's tokenizer drops or multiplies without a word, each of which it
# would read as another value: refused, naming what cannot be read.
@pytest.mark.parametrize(
    ("value", "kind", "message"),
    [
        ("3 🍕", "length", r"got '3 🍕', which holds '🍕': not part of a number or a unit\.$"),
        ("2 ☃", "mass", r"got '2 ☃', which holds '☃'"),
        ("3 ✓ cm", "length", r"got '3 ✓ cm', which holds '✓'"),
        ("10 ☃", "time", r"which holds '☃'"),
        ("3 m#x", "length", r"which holds '#'"),
        ("3 = m", "length", r"which holds '='"),
        ("3 [m]", "length", r"which holds '\[', '\]'"),
        ("3 m!", "length", r"which holds '!'"),
        (
            "3 m, 4",
            "length",
            r"which holds ',': .* \(one value, with a decimal point and no thousands separator\)",
        ),
        ("1,5 kg", "mass", r"which holds ','"),
        ("3..2 m", "length", r"with the numbers 3\. and \.2 side by side"),
        (
            "3 4 m",
            "length",
            r"with the numbers 3 and 4 side by side \(pint would multiply them: write one "
            r"number, or an operator between them\)\.$",
        ),
        ("3 m 4", "length", r"got '3 m 4', with the number 4 after 'm' \(pint would multiply"),
        ("3 kg 2 m", "mass", r"with the number 2 after 'kg'"),
        ("(2)3 kg", "mass", r"with the number 3 after '\)'"),
        ("1e400 m", "length", r"^Expected `x` to be finite, got '1e400 m' \(inf\)\.$"),
        ("\b", "mass", r"which holds '\\x08'"),
        ("m" * 70, "mass", r"got 'm{60}'\.\.\. \("),
    ],
)
def test_to_si_refuses_what_pint_would_drop_or_multiply(
    value: str, kind: str, message: str
) -> None:
    with pytest.raises(tb.InputError, match=message):
        to_si(value, kind, "x")


@pytest.mark.parametrize(
    ("value", "kind", "expected"),
    [
        ("−3 kg", "mass", -3.0),  # a Unicode minus: pint alone would drop it, giving +3
        ("2 N·m", "torque", 2.0),
        ("2 N×m", "torque", 2.0),
        ("5 %", "dimensionless", 0.05),
        ("10 cm²", "dimensionless", None),
        ("2 (3) kg", "mass", 6.0),
        ("3kg", "mass", 3.0),
        ("2^3 g", "mass", 0.008),
        ("3 µg", "mass", 3e-9),
        ("90 °", "angle", math.pi / 2),
        ("250\u00a0g", "mass", 0.25),  # a no-break space
        ("250\u202fg", "mass", 0.25),  # a narrow no-break space: the SI brochure's own
        ("1.5 kg*m^-2", "dimensionless", None),
    ],
)
def test_to_si_reads_typography_people_type(value: str, kind: str, expected: float | None) -> None:
    if expected is None:  # not dimensionless: read, then refused for its dimensions
        with pytest.raises(
            tb.InputError, match=r"to be a dimensionless number, got .* \(dimensions "
        ):
            to_si(value, kind, "x")
    else:
        assert to_si(value, kind, "x") == pytest.approx(expected, rel=1e-15)


def test_unknown_symbols_are_refused_everywhere_units_are_read() -> None:
    with pytest.raises(tb.InputError, match=r"Expected `mass` .* got '2 ☃', which holds '☃'"):
        tb.shapes.solid_sphere("2 ☃", "1 m")
    with pytest.raises(tb.InputError, match=r"Expected `duration` .* which holds '☃'"):
        tb.simulate(tb.shapes.box(1.0, [1, 2, 3]), [0, 0, 1], duration="10 ☃", dt=0.1)
    with pytest.raises(tb.InputError, match=r"Expected `size` .* which holds '✓'"):
        vector_to_si("1, 2, 3 ✓ cm", "length", "size")
    with pytest.raises(tb.InputError, match=r"got 'm🍕'"):
        length_scale("m🍕")


def test_turns_per_second_are_two_pi_radians_per_second() -> None:
    assert to_si("2 turn/s", "angular_velocity", "w") == pytest.approx(4 * math.pi, rel=1e-15)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (
            "10, 20 cm, 30 cm",
            r"Expected `v` to have a unit on every value or one unit after the last, got '10, 20 cm, 30 cm'",
        ),
        ("10 cm, 20, 30 mm", r"a unit on every value or one unit after the last"),
        (
            np.array([1 + 5j, 0, 0]),
            r"Expected `v` to hold real numbers, got an array of dtype complex128",
        ),
        (
            np.array([True, False, True]),
            r"Expected `v` to hold real numbers, got an array of dtype bool",
        ),
    ],
)
def test_vector_to_si_refuses_what_it_would_misread(value: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        vector_to_si(value, "length", "v")


def test_pint_is_imported_without_dask_which_still_imports_afterwards() -> None:
    # In a fresh interpreter: importing the units must not import dask (pint would,
    # for dask arrays tumble never makes), and dask must import as usual after.
    import subprocess
    import sys

    check = (
        "import sys; import tumble.units as u; assert 'dask' not in sys.modules; "
        "assert u.to_si('250 g', 'mass', 'm') == 0.25; "
        "import dask.array; assert sys.modules['dask'] is not None; print('ok')"
    )
    done = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"


def test_messages_about_large_arrays_name_the_first_bad_value_instead_of_all() -> None:
    # A recording of 3000 samples with one NaN: the message says where, not 9000 numbers.
    rates = np.ones((3000, 3))
    rates[5, 0] = np.nan
    with pytest.raises(
        tb.InputError,
        match=r"^Expected `omega` to be finite, got nan at index \[5, 0\] \(1 of its 9000 values "
        r"are NaN or infinite\)\.$",
    ):
        vector_to_si(rates, "angular_velocity", "omega", (-1, 3))
    with pytest.raises(tb.InputError) as refused:
        vector_to_si(ureg.Quantity(np.ones((3000, 3)), "m"), "angular_velocity", "omega", (-1, 3))
    assert len(str(refused.value)) < 200
    # A small array is still shown whole.
    with pytest.raises(tb.InputError, match=r"got \[1\.0, nan, 3\.0\]\.$"):
        vector_to_si(np.array([1.0, np.nan, 3.0]), "length", "v")
