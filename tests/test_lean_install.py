"""``make demo`` installs tumble with its runtime dependencies only: the Makefile says
so, and the built-in scenario runs with every package of the extras out of reach."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from importlib.metadata import packages_distributions
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Runs the command line with an import hook that refuses the modules named in argv[1].
BLOCKING_RUN = """
import importlib.abc, sys
blocked = set(sys.argv[1].split(","))
class Refuse(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.partition(".")[0] in blocked:
            raise ImportError(f"{name} belongs to an extra, not to the runtime")
sys.meta_path.insert(0, Refuse())
from tumble.cli import main
sys.argv = ["tumble", *sys.argv[2:]]
main()
"""


def normalised(requirement: str) -> str:
    """The distribution's name of a requirement, normalised (PEP 503)."""
    name = re.split(r"[\[<>=!~; ]", requirement, maxsplit=1)[0]
    return re.sub(r"[-_.]+", "-", name).lower()


def extras_only_modules() -> set[str]:
    """The top-level modules installed here that a distribution named by an extra of
    pyproject.toml, and not by the runtime dependencies, provides (MuJoCo's module
    comes from three distributions, one of them named by the extras)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    runtime = {normalised(r) for r in project["dependencies"]}
    extras = {normalised(r) for group in project["optional-dependencies"].values() for r in group}
    extras -= runtime
    modules = set()
    for module, distributions in packages_distributions().items():
        names = {normalised(d) for d in distributions}
        if names & extras:
            modules.add(module)
    return modules


def test_the_demo_installs_the_runtime_dependencies_only() -> None:
    makefile = (ROOT / "Makefile").read_text()
    demo = re.search(r"^demo:(.*)$", makefile, flags=re.M)
    assert demo is not None and demo.group(1).split() == ["$(RUNTIME)"]
    runtime = re.search(r"^\$\(RUNTIME\):.*\n((?:\t.*\n)+)", makefile, flags=re.M)
    assert runtime is not None
    installs = [line for line in runtime.group(1).splitlines() if "pip install" in line]
    assert installs[-1].strip().endswith("pip install --quiet -e ."), installs


@pytest.mark.slow  # a whole run in a fresh process: half a minute
def test_the_built_in_scenario_runs_without_any_extra(tmp_path: Path) -> None:
    blocked = extras_only_modules()
    # The extras' packages are installed here (the tests need them): the hook must have
    # something to refuse, or this test would prove nothing.
    assert {"mujoco", "sphinx", "pytest", "pybullet"} <= blocked
    run = subprocess.run(
        [
            sys.executable,
            "-c",
            BLOCKING_RUN,
            ",".join(sorted(blocked)),
            "run",
            "-o",
            str(tmp_path / "run"),
            "--quiet",
            "--no-viewer",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert (tmp_path / "run" / "report.html").is_file()
