"""What the scenario tests share: editing a scenario's text, reading its rows."""

from __future__ import annotations


def edited(old: str, new: str, text: str) -> str:
    """``text`` with its first ``old`` replaced by ``new`` (which must be there)."""
    assert old in text, old
    return text.replace(old, new, 1)


def rows(result: object) -> dict[str, dict]:
    """The theory-vs-simulation rows of a run, by quantity."""
    return {row["quantity"]: row for row in result.comparisons}  # type: ignore[attr-defined]
