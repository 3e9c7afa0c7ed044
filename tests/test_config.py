"""The configuration layer shared by scenario and sweep files: the lines of keys,
the one-line messages made from pydantic's errors, reading files and built-ins."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import pytest
from pydantic import Field, StrictInt, StrictStr, ValidationError, model_validator

import tumble as tb
from tumble.config import (
    Builtins,
    ConfigError,
    StrictModel,
    dotted,
    key_error,
    key_lines,
    line_of,
    parse_toml,
    read_source,
    validate_toml,
    where,
)
from tumble.scenario import ScenarioError
from tumble.sweep import SweepError


# ------------------------------------------------------------------ a toy schema
class Inner(StrictModel):
    count: Annotated[StrictInt, Field(ge=1)] = 1
    label: Annotated[StrictStr, Field(pattern=r"^[a-z]+$")] = "a"
    low: float = 0.0
    high: float = 1.0

    @model_validator(mode="after")
    def _ordered(self) -> Inner:
        if self.high < self.low:
            raise key_error("high", f"Expected `high` >= `low` ({self.low}), got {self.high}.")
        return self


class Item(StrictModel):
    name: StrictStr


class Top(StrictModel):
    inner: Inner
    items: list[Item] = Field(default_factory=list)

    @model_validator(mode="before")
    @classmethod
    def _no_secrets(cls, data: Any) -> Any:
        if isinstance(data, dict) and "secret" in data.get("inner", {}):
            raise key_error(("inner", "secret"), "Expected no `secret`, got one.")
        return data


def check(text: str, **options: Any) -> Top:
    return validate_toml(Top, text, "t.toml", error=ConfigError, **options)


# ------------------------------------------------------------------ key lines
def test_key_lines_follow_tables_arrays_of_tables_and_dotted_keys() -> None:
    text = (
        "# a comment with [brackets] and key = value\n"  # 1
        "top = 1\n"  # 2
        "[a]\n"  # 3
        'x = "# not a comment"  # a comment\n'  # 4
        "b.c = 2\n"  # 5
        "[[parts]]\n"  # 6
        "y = [1,\n"  # 7
        "  2]\n"  # 8
        "z = { p = 1, q = 2 }\n"  # 9
        "[[parts]]\n"  # 10
        "[parts.pose]\n"  # 11
        "w = 3\n"  # 12
    )
    lines = key_lines(text)
    assert lines[("top",)] == 2
    assert lines[("a",)] == 3 and lines[("a", "x")] == 4 and lines[("a", "b", "c")] == 5
    assert lines[("parts", 0)] == 6 and lines[("parts", 0, "y")] == 7
    assert lines[("parts", 0, "z", "q")] == 9
    assert lines[("parts", 1)] == 10
    assert lines[("parts", 1, "pose", "w")] == 12
    assert ("2]",) not in lines  # the second line of an array is no key
    # A key written nowhere is found at its nearest table.
    assert line_of(lines, ("a", "missing")) == 3
    assert line_of(lines, ("nowhere",)) is None


def test_dotted_paths_show_indices_in_brackets() -> None:
    assert dotted(("body", "parts", 0, "radius")) == "body.parts[0].radius"
    assert dotted(()) == ""


def test_where_names_the_source_line_and_path() -> None:
    text = "[a]\nx = 1\n"
    assert where(text, "f.toml", ("a", "x")) == "f.toml, line 2, `a.x`"
    assert where(text, "f.toml", ("b", "y")) == "f.toml, `b.y`"
    assert where(text, "f.toml", ()) == "f.toml"


# ------------------------------------------------------------------ messages
@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "[inner]\ncount = 2\ncuont = 3\n",
            r"^t\.toml, line 3, `inner\.cuont`: Expected the key to be one of count, label, low, high, got 'cuont'\. Did you mean count\?$",
        ),
        (
            "[inner]\n[other]\n",
            r"^t\.toml, line 2, `other`: Expected the key to be one of inner, items, got 'other'\.$",
        ),
        (
            "[[items]]\nname = 'x'\n",
            r"^t\.toml, `inner`: Expected the table \[inner\], which is missing\.$",
        ),
        (
            "[inner]\n[[items]]\nname = 'x'\n[[items]]\n",
            r"^t\.toml, line 4, `items\[1\]\.name`: Expected the key `name`, which is missing\.$",
        ),
        (
            "[inner]\nlow = 2\nhigh = 1\n",
            r"^t\.toml, line 3, `inner\.high`: Expected `high` >= `low` \(2\.0\), got 1\.0\.$",
        ),
        (
            "[inner]\nsecret = 1\n",
            r"^t\.toml, line 2, `inner\.secret`: Expected no `secret`, got one\.$",
        ),
        (
            "[inner]\ncount = 0\n",
            r"^t\.toml, line 2, `inner\.count`: Expected a valid value: input should be greater than or equal to 1\.$",
        ),
        ("[inner\n", r"^t\.toml: Expected valid TOML, got an error: .*\(at line 1, column 7\)\.$"),
    ],
)
def test_first_error_is_one_line_with_file_line_and_key(text: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        check(text)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "[inner]\ncount = 0\n",
            r"`inner\.count`: Expected a value greater than or equal to 1, got 0\.$",
        ),
        ("[inner]\ncount = '2'\n", r"`inner\.count`: Expected a valid integer, got '2'\.$"),
        ("[inner]\ncount = true\n", r"`inner\.count`: Expected a valid integer, got true\.$"),
        ("[inner]\ncount = [1]\n", r"`inner\.count`: Expected a valid integer, got an array\.$"),
        (
            "[inner]\ncount = { a = 1 }\n",
            r"`inner\.count`: Expected a valid integer, got a table\.$",
        ),
        (
            "[inner]\nlabel = 'A'\n",
            r"`inner\.label`: Expected a string that should match pattern '\^\[a-z\]\+\$', got 'A'\.$",
        ),
        ("items = 3\n[inner]\n", r"`items`: Expected a valid list, got 3\.$"),
        (
            "[inner]\n[[items]]\nname = 'x'\n[[items]]\n",
            r"`items\[1\]\.name`: Expected the key `name`, which is missing\.$",
        ),
    ],
)
def test_pydantic_messages_name_what_was_given(text: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        check(text, name_input=True)


def test_a_message_that_is_not_an_expectation_is_wrapped() -> None:
    class Odd(StrictModel):
        value: int = 0

        @model_validator(mode="after")
        def _odd(self) -> Odd:
            if self.value % 2 == 0:
                raise ValueError("even numbers are refused")
            return self

    with pytest.raises(
        ConfigError, match=r"^t\.toml: Expected a valid value: even numbers are refused\.$"
    ):
        validate_toml(Odd, "value = 2\n", "t.toml")
    with pytest.raises(
        ConfigError,
        match=r"^t\.toml: Expected a valid value \(even numbers are refused\), got a table\.$",
    ):
        validate_toml(Odd, "value = 2\n", "t.toml", name_input=True)


def test_other_problems_are_counted_and_an_unknown_key_comes_first() -> None:
    text = "[inner]\ncount = 0\nlabel = 'A'\nlo = 1\n"
    # The unknown key stops its table before the others are checked.
    with pytest.raises(
        ConfigError, match=r"`inner\.lo`: Expected the key to be one of .*Did you mean low\?$"
    ):
        check(text, count_others=True)
    two = "[inner]\ncount = 0\n[[items]]\nname = 1\n"
    with pytest.raises(ConfigError, match=r"`inner\.count`: .* 1\. \(1 more problem\)$"):
        check(two, count_others=True)
    three = two + "[[items]]\nname = 2\n"
    with pytest.raises(ConfigError, match=r"`inner\.count`: .* 1\. \(2 more problems\)$"):
        check(three, count_others=True)
    with pytest.raises(ConfigError, match=r"`inner\.count`: .* 1\.$"):
        check(three)
    unknown_last = "[inner]\ncount = 0\n[[items]]\nname = 'x'\nnmae = 'y'\n"
    with pytest.raises(
        ConfigError,
        match=r"`items\[0\]\.nmae`: Expected the key to be one of name, got 'nmae'\. Did you mean name\? \(1 more problem\)$",
    ):
        check(unknown_last, count_others=True)


def test_key_path_drops_what_no_file_writes() -> None:
    def without_tags(loc: tuple[Any, ...]) -> list[Any]:
        return [part for part in loc if part != "int"]

    class Tagged(StrictModel):
        value: int | str = 0

    with pytest.raises(ConfigError, match=r"`value\.int`: "):
        validate_toml(Tagged, "value = 1.5\n", "t.toml")
    with pytest.raises(ConfigError, match=r"line 1, `value`: "):
        validate_toml(Tagged, "value = 1.5\n", "t.toml", key_path=without_tags)


def test_models_are_frozen() -> None:
    top = check("[inner]\ncount = 2\n")
    assert top.inner.count == 2
    with pytest.raises(ValidationError, match=r"Instance is frozen"):
        top.inner.count = 3  # type: ignore[misc]


def test_parse_toml_raises_the_class_asked_for() -> None:
    assert parse_toml("a = 1\n", "x") == {"a": 1}
    with pytest.raises(SweepError, match=r"^x: Expected valid TOML, got an error: "):
        parse_toml("a = \n", "x", SweepError)


def test_file_errors_are_input_errors() -> None:
    for error in (ConfigError, ScenarioError, SweepError):
        assert issubclass(error, tb.InputError)
    assert issubclass(ScenarioError, ConfigError) and issubclass(SweepError, ConfigError)


# ------------------------------------------------------------------ files and built-ins
@pytest.fixture
def shelf(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Builtins:
    """Built-in files of a made-up kind in a temporary package."""
    package = tmp_path / "shelfpkg"
    (package / "files").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "files" / "beta.toml").write_text("[thing]\ntitle = 'Beta'\n")
    (package / "files" / "alpha.toml").write_text(
        "[thing]\ndescription = '''First line\nsecond line'''\n"
    )
    (package / "files" / "gamma.toml").write_text("[thing]\ntitle = ''\n")
    (package / "files" / "notes.txt").write_text("not a built-in")
    monkeypatch.syspath_prepend(str(tmp_path))
    return Builtins(
        kind="thing",
        package="shelfpkg",
        folder_name="files",
        error=SweepError,
        order=("gamma",),
        describe=("title", "description"),
    )


def test_builtins_are_listed_in_order_and_described(shelf: Builtins) -> None:
    assert shelf.names() == ["gamma", "alpha", "beta"]
    assert shelf.description("beta") == "Beta"
    assert shelf.description("alpha") == "First line"
    assert shelf.description("gamma") == ""
    assert shelf.text("beta") == "[thing]\ntitle = 'Beta'\n"


def test_an_unknown_builtin_lists_the_names(shelf: Builtins) -> None:
    with pytest.raises(
        SweepError,
        match=r"^Expected a built-in thing to be one of gamma, alpha, beta, or a \.toml file, got 'betta'\. Did you mean beta\?$",
    ):
        shelf.text("betta")
    with pytest.raises(
        SweepError,
        match=r"^Expected a built-in thing to be one of gamma, alpha, beta, or a \.toml file, got 'zzz'\.$",
    ):
        read_source("zzz", shelf)


def test_a_source_is_a_file_or_a_builtin(
    shelf: Builtins, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    builtin = read_source("alpha", shelf)
    assert builtin.name == "builtin:alpha" and builtin.file is None
    assert builtin.folder == shelf.folder() and builtin.text.startswith("[thing]")
    path = tmp_path / "mine.toml"
    path.write_text("a = 1\n")
    mine = read_source(path, shelf)
    assert (mine.name, mine.file, mine.folder, mine.text) == (str(path), path, tmp_path, "a = 1\n")
    # An existing file is read whatever its suffix; the name is the path as given.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "plain").write_text("b = 2\n")
    plain = read_source("plain", shelf)
    assert (plain.name, plain.text, plain.folder) == ("plain", "b = 2\n", tmp_path)


def test_missing_and_unreadable_files_are_named(shelf: Builtins, tmp_path: Path) -> None:
    with pytest.raises(
        SweepError, match=r"^Expected a thing file, got 'nothere\.toml' \(no such file\)\.$"
    ):
        read_source("nothere.toml", shelf)
    folder = tmp_path / "folder.toml"
    folder.mkdir()
    with pytest.raises(
        SweepError, match=r"^Expected a thing file, got '.*folder\.toml' \(a folder\)\.$"
    ):
        read_source(folder, shelf)
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"a = '\xff'\n")
    with pytest.raises(
        SweepError,
        match=r"^Expected a readable UTF-8 file, got '.*bad\.toml': .*codec can't decode",
    ):
        read_source(bad, shelf)


def test_methods_are_read_from_the_integrator_registry() -> None:
    from tumble.config.registries import method_choice
    from tumble.integrators import INTEGRATORS

    assert method_choice("auto") == "auto"
    for name in INTEGRATORS:
        assert method_choice(name) == name
    with pytest.raises(
        tb.InputError,
        match=r"Expected `method` to be one of auto, exact, splitting, strang, splitting-exact, strang-exact, rk4, adaptive, got 'strnag'\. Did you mean strang\?",
    ):
        method_choice("strnag")
    # Files for batches may name only integrators with batch kernels that measure.
    with pytest.raises(
        tb.InputError,
        match=r"Expected `method` to be one of exact, splitting, strang, splitting-exact, strang-exact, rk4, got 'adaptive'\.$",
    ):
        method_choice("adaptive", batch=True)


# ------------------------------------------------------------------ hostile files
def test_toml_nested_beyond_the_parser_names_the_depth() -> None:
    # Python's TOML parser recurses once per level: 1000 levels exhaust its stack.
    text = "a = " + "[" * 1000 + "]" * 1000 + "\n"
    with pytest.raises(
        SweepError,
        match=r"^deep\.toml: Expected arrays and inline tables nested at most a few hundred "
        r"levels deep, got 1000 levels\.$",
    ):
        parse_toml(text, "deep.toml", SweepError)


def test_the_depth_counts_brackets_outside_strings_and_comments() -> None:
    text = (
        "[table]\ns = \"[[[{\"\nt = '''[[['''\n# [[[[\n"
        + "a = "
        + "[{b = " * 600
        + "1"
        + "}]" * 600
        + "\n"
    )
    with pytest.raises(ConfigError, match=r"got 1200 levels\.$"):
        parse_toml(text, "deep.toml")


def test_a_byte_order_mark_is_read_as_nothing() -> None:
    # Editors on Windows begin UTF-8 files with U+FEFF; TOML does not allow it.
    assert parse_toml("\ufeffa = 1\n", "bom.toml") == {"a": 1}


def test_a_file_with_a_byte_order_mark_is_read(shelf: Builtins, tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf[inner]\ncount = 2\n")
    source = read_source(path, shelf)
    assert validate_toml(Top, source.text, source.name).inner.count == 2


def test_a_folder_is_not_a_file(
    shelf: Builtins, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir").mkdir()
    with pytest.raises(SweepError, match=r"^Expected a thing file, got 'adir' \(a folder\)\.$"):
        read_source("adir", shelf)


def test_a_long_name_is_cut_in_the_message(shelf: Builtins) -> None:
    name = "n" * 5000
    for given in (name, f"{name}.toml"):
        with pytest.raises(SweepError) as caught:
            read_source(given, shelf)
        assert len(str(caught.value)) < 300
        assert f"got {name[:60]!r}..." in str(caught.value)


def test_a_builtin_of_another_kind_says_how_to_run_it() -> None:
    from tumble.scenario import load
    from tumble.sweep import load_sweep

    with pytest.raises(
        ScenarioError,
        match=r"^Expected a built-in scenario to be one of .*, or a \.toml file, got 'flip-map'\. That is "
        r"a built-in sweep: run it with `tumble sweep flip-map`\.$",
    ):
        load("flip-map")
    with pytest.raises(
        SweepError,
        match=r"^Expected a built-in sweep to be one of .*, or a \.toml file, got 'gyroscope'\. That is "
        r"a built-in scenario: run it with `tumble run gyroscope`\.$",
    ):
        load_sweep("gyroscope")
