"""The compiled core imports only numpy, numba and a few standard modules; the
file packages (config, scenario, sweep) import neither their package back nor
another module's private names.

import-linter (``make contracts``) forbids named packages; these tests allow a
fixed list instead, so a new dependency cannot slip into ``tumble.core``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import tumble.config
import tumble.core
import tumble.scenario
import tumble.sweep

CORE = Path(tumble.core.__file__).parent
# numpy, numba and a few standard modules (ctypes: the user-torque callback read
# back as arrays when numba's JIT is disabled; hashlib and pathlib: the cache keys
# of the kernels specialised for one torque).
ALLOWED = {
    "numpy", "numba", "tumble", "__future__", "functools", "math", "os", "typing", "ctypes",
    "hashlib", "pathlib", "collections", "contextlib",
}  # fmt: skip


def test_core_imports_only_numpy_and_numba() -> None:
    seen: dict[str, set[str]] = {}
    for path in sorted(CORE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""] if node.level == 0 else ["tumble.core"]
            else:
                continue
            for name in names:
                seen.setdefault(name, set()).add(path.name)
    outside = {n for n in seen if n.split(".")[0] not in ALLOWED}
    inside_tumble = {
        n for n in seen if n.split(".")[0] == "tumble" and not n.startswith("tumble.core")
    }
    assert not outside, f"tumble.core imports {outside}"
    assert not inside_tumble, f"tumble.core imports the outer package: {inside_tumble}"
    assert "numba" in seen  # the scan does see the kernels' imports


FILE_PACKAGES = (tumble.config, tumble.scenario, tumble.sweep)


def test_file_packages_import_no_private_name_of_another_module() -> None:
    found = []
    for package in FILE_PACKAGES:
        for path in sorted(Path(package.__file__).parent.glob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("tumble"):
                    found += [
                        f"{path.name}: {node.module}.{alias.name}"
                        for alias in node.names
                        if alias.name.startswith("_") and not alias.name.startswith("__")
                    ]
    assert not found, f"private names imported from other modules: {found}"


def test_modules_of_the_file_packages_do_not_import_their_package() -> None:
    # The package's __init__ holds the entry points, which import the modules:
    # a module importing it back would make a cycle.
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph("tumble")
    cycles = [
        f"{module} -> {package.__name__}"
        for package in FILE_PACKAGES
        for module in graph.find_children(package.__name__)
        if package.__name__ in graph.find_modules_directly_imported_by(module)
    ]
    assert not cycles, f"modules importing their own package: {cycles}"
