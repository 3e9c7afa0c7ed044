"""The documentation pages that quote computed tables stay in step with the code."""

from __future__ import annotations

import contextlib
import io
import re
import runpy
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))

import tumble_docs  # noqa: E402


def test_the_approximation_tables_match_the_script() -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        runpy.run_path(str(ROOT / "examples" / "approximation_table.py"), run_name="__main__")
    page = (ROOT / "docs" / "approximations.md").read_text(encoding="utf-8")
    assert out.getvalue().strip() in page
    # The reading on the page relies on these rows: the fast-top precession within
    # 1.2 % at 200 rad/s, and β's error passing 1 % near 20° of swing.
    assert "       200 |   1.22*   1.07*   0.62    0.00    0.61" in page
    assert "       100 |   0.17    0.89    4.10*  18.07*  52.72* 143.71*" in page


def test_the_readme_draws_the_layers_as_the_architecture_page_does() -> None:
    # The architecture page draws the layers from pyproject.toml's contract when
    # the site is built; the README quotes the same drawing.
    text, problems = tumble_docs.architecture_layers()
    assert problems == []
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert f"```text\n{text}\n```" in readme, (
        "README.md's layers differ from the contract: paste "
        "tumble_docs.architecture_layers()[0] (docs/_ext) into its Architecture section"
    )


@pytest.mark.slow  # four recipes compiled in a fresh process: 10 s and more
def test_the_architecture_page_recipes_run(tmp_path: Path) -> None:
    # The page's extension recipes (a torque model, an integrator, a part kind, a
    # model), run in a fresh process: their registrations stay out of this one.
    # Each block prints what it shows; the part kind's wheel takes energy away; the
    # torsion pendulum swings at its closed form's frequency (RK4 at 1 ms, as in
    # tests/test_model_registry.py: within 1e-6).
    page = (ROOT / "docs" / "explanation" / "architecture.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", page, flags=re.S)
    assert len(blocks) == 4
    script = tmp_path / "recipes.py"
    script.write_text("\n\n".join(blocks), encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path, check=False
    )
    assert done.returncode == 0, done.stderr
    *_, wheel, model = done.stdout.strip().splitlines()
    first, last = (float(x) for x in wheel.split())
    assert last < first
    assert model.startswith("damped frequency ω_d ")
    assert float(model.split()[-1]) < 1e-6
