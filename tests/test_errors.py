"""The one message of a lookup by name (:func:`tumble.errors.unknown_choice`):
what was expected, the names, the value received, the nearest name."""

from __future__ import annotations

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
