"""The library's half of the catalogue of hostile requests (bench/hostile_catalogue.py),
run in this process: every bad request is refused with an InputError (or the
TypeError Python itself gives a meaningless operation), every valid one at an
edge is answered and passes its check against an independent oracle.

``bench/hostile.py`` replays the whole catalogue, the command line's half
included, each request in a process of its own with a time and a memory limit.
"""

from __future__ import annotations

import builtins
import sys
from pathlib import Path

import numpy as np
import pint
import pytest

import tumble as tb
from tumble.units import ureg

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))

from hostile_case import lost_inputs, make_inputs
from hostile_catalogue import CATALOGUE, Case

# A FIFO blocks whoever opens it: requests given one run only in the bench, each
# in a process of its own with a time limit, never here.
LIBRARY = [case for case in CATALOGUE if case.surface == "library" and not case.fifos]


def test_the_catalogue_holds_at_least_300_requests_each_with_what_must_come_of_it() -> None:
    assert len(CATALOGUE) >= 300
    assert len({case.name for case in CATALOGUE}) == len(CATALOGUE)
    assert {case.surface for case in CATALOGUE} == {"cli", "library"}
    for case in CATALOGUE:
        assert case.expect in ("refusal", "result"), case.name
        assert (case.expect == "result") == bool(case.check), case.name


@pytest.mark.parametrize("case", LIBRARY, ids=[case.name for case in LIBRARY])
def test_the_library_refuses_each_bad_request_and_answers_each_valid_one_right(
    case: Case, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # As the bench runs them: within a budget of 1 GiB, which a request beyond
    # it must be refused by, before the work.
    monkeypatch.setenv("TUMBLE_MEMORY_BUDGET", "1 GiB")
    kept = make_inputs(case, tmp_path)
    scope = {"tb": tb, "np": np, "pint": pint, "ureg": ureg, "Path": Path, "tmp": tmp_path}
    code = compile(str(case.call), case.name, "exec")
    if case.expect == "refusal":
        kinds = (tb.InputError, *(getattr(builtins, kind) for kind in case.refusals))
        with pytest.raises(kinds) as refused:
            exec(code, scope)
        assert str(refused.value).strip(), "a refusal must say why"
    else:
        exec(code, scope)
        assert eval(case.check, scope), f"{case.name} gave {scope.get('result')!r}"
    assert lost_inputs(tmp_path, kept) == [], "a request must leave its inputs as they were"
