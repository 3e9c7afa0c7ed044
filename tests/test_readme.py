"""The README's Python examples run, and the numbers they quote are right."""

from __future__ import annotations

import contextlib
import io
import os
import re
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{k}" for k in range(len(BLOCKS))])
def test_readme_example_runs(code: str, tmp_path: Path) -> None:
    # Run where a reader would (beside examples/), but write files into a scratch folder.
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    # The skew-rod block prints each tumble result next to its closed form.
    for line in out.getvalue().splitlines():
        numbers = line.split()
        if len(numbers) == 2 and all(re.fullmatch(r"[-+0-9.e]+", n) for n in numbers):
            assert float(numbers[0]) == pytest.approx(float(numbers[1]), rel=1e-12)


def test_readme_quotes_the_right_numbers() -> None:
    import tumble as tb

    cone = tb.shapes.solid_cone(0.25, 0.03, 0.08)
    assert cone.inertia.diagonal().tolist() == pytest.approx(
        [9.375e-05, 9.375e-05, 6.75e-05], rel=1e-12
    )
    bracket = tb.from_mesh(ROOT / "examples/l_bracket.stl", density=2700, units="mm")
    # 22 080 mm³ of aluminium (the L profile's area 60·8 + 8·32 = 736 mm² × 30 mm).
    assert bracket.mass == pytest.approx(2700 * 736 * 30e-9, rel=1e-12)
    assert BLOCKS, "README has Python examples"
    assert len(BLOCKS) >= 5


def test_the_torques_listed_are_those_files_may_use() -> None:
    from tumble.config.registries import torque_types

    text = (ROOT / "README.md").read_text()
    start = text.index("Torques go in `[[torques]]` tables (")
    sentence = text[start : text.index("), and the parts", start)]
    assert re.findall(r'`(?:type = )?"([a-z-]+)"`', sentence) == torque_types()
