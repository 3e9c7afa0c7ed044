"""The one message of a lookup by name (:func:`tumble.errors.unknown_choice`):
what was expected, the names, the value received, the nearest name."""

from __future__ import annotations

import pytest

import tumble as tb
from tumble.errors import InputError, nearest, unknown_choice


def test_the_message_names_what_the_choices_the_value_and_the_nearest() -> None:
    error = unknown_choice("strnag", ["rk4", "strang"], "`method`")
    assert isinstance(error, InputError)
    assert str(error) == (
        "Expected `method` to be one of rk4, strang, got 'strnag'. Did you mean strang?"
    )


def test_without_a_near_name_the_message_ends_at_the_value() -> None:
    assert str(unknown_choice(42, ["rk4"], "`method`")) == (
        "Expected `method` to be one of rk4, got 42."
    )


def test_an_alternative_and_a_hint_take_their_places() -> None:
    hint = "That is a built-in sweep."
    error = unknown_choice(
        "flip-map", ["gyroscope"], "a built-in scenario", alternative="a .toml file", hint=hint
    )
    assert str(error) == (
        "Expected a built-in scenario to be one of gyroscope, or a .toml file, got "
        "'flip-map'. That is a built-in sweep."
    )


def test_the_nearest_name_ignores_case_and_underscores_against_hyphens() -> None:
    assert nearest("Solid_Cylindr", ["box", "solid-cylinder"]) == "solid-cylinder"
    assert nearest("chunk-size", ["seed", "chunk_size"]) == "chunk_size"
    assert nearest("zzz", ["box"]) is None


def test_a_long_value_is_cut_and_a_line_break_escaped() -> None:
    message = str(unknown_choice("n" * 5000 + "\n", ["box"], "a shape"))
    assert "\n" not in message and len(message) < 120
    assert message.endswith(
        "got 'nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn'...."
    )


def test_an_unknown_method_has_one_message_wherever_it_is_named() -> None:
    # simulate, simulate_batch and the files' `method` share one check.
    from tumble.config.registries import method_choice
    from tumble.integrators import method_names

    body = tb.MassProperties(1.0, [0, 0, 0], [[1.0, 0, 0], [0, 2.0, 0], [0, 0, 3.0]])
    expected = str(unknown_choice("rk5", method_names(), "`method`"))
    assert expected.endswith("got 'rk5'. Did you mean rk4?")
    with pytest.raises(InputError) as from_simulate:
        tb.simulate(body, [0.1, 1.0, 0.1], duration=1.0, dt=0.1, method="rk5")
    with pytest.raises(InputError) as from_files:
        method_choice("rk5")
    assert str(from_simulate.value) == str(from_files.value) == expected
    batch = str(unknown_choice("rk5", method_names(batch=True), "`method`"))
    with pytest.raises(InputError) as from_batch:
        tb.simulate_batch([1.0, 2.0, 3.0], [[0.1, 1.0, 0.1]], duration=1.0, dt=0.1, method="rk5")
    assert str(from_batch.value) == batch


def test_a_quoted_message_of_another_tool_loses_its_terminal_colours() -> None:
    from tumble.errors import uncoloured
    from tumble.torques.user import _first_line

    # numba writes its typing errors in bold when it believes it writes to a terminal.
    bold = "Failed in nopython mode pipeline\n\x1b[1m\x1b[1;31mUnknown attribute 'x'\x1b[0m\n..."
    assert uncoloured("\x1b[1mbold\x1b[0m and \x1b[1;38;5;208mcolour\x1b[0m") == "bold and colour"
    assert _first_line(TypeError(bold)) == "TypeError: Unknown attribute 'x'"
