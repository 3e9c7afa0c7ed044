"""The compiled core imports only numpy, numba and a few standard modules; the
file packages (config, scenario, sweep) import neither their package back nor
another module's private names.

import-linter (``make contracts``) forbids named packages; these tests allow a
fixed list instead, so a new dependency cannot slip into ``tumble.core``.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

import tumble.config
import tumble.core
import tumble.scenario
import tumble.sweep

CORE = Path(tumble.core.__file__).parent
# numpy, numba and a few standard modules (ctypes: the user-torque callback read
# back as arrays when numba's JIT is disabled; hashlib and pathlib: the cache keys
# of the kernels specialised for one torque; sys: whether numba was imported before
# the kernels, when their optimisation level is set).
ALLOWED = {
    "numpy", "numba", "tumble", "__future__", "functools", "math", "os", "typing", "ctypes",
    "hashlib", "pathlib", "collections", "contextlib", "sys",
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


PACKAGE = Path(tumble.__file__).parent

#: The one declared exception to the layers: the notebook helpers
#: (MassProperties._repr_html_, Trajectory._repr_html_, .plot(), .view()) import
#: the report lazily, on call. pyproject.toml's layers contract declares the same.
NOTEBOOK_HELPERS = {
    ("tumble.massprops", "tumble.report.html"),
    ("tumble.trajectory", "tumble.report"),
    ("tumble.trajectory", "tumble.report.html"),
}


def test_no_module_imports_a_private_name_of_another() -> None:
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("tumble"):
                found += [
                    f"{path.relative_to(PACKAGE)}: {node.module}.{alias.name}"
                    for alias in node.names
                    if alias.name.startswith("_") and not alias.name.startswith("__")
                ]
    assert not found, f"private names imported from other modules: {found}"


def test_the_import_graph_has_no_cycle_but_the_notebook_helpers() -> None:
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph("tumble", exclude_type_checking_imports=True)
    for importer, imported in NOTEBOOK_HELPERS:
        assert graph.direct_import_exists(importer=importer, imported=imported), (
            f"the declared exception {importer} -> {imported} is gone: remove it here and "
            "in pyproject.toml"
        )
        graph.remove_import(importer=importer, imported=imported)
    # Tarjan's strongly connected components: a component of more than one
    # module is a cycle.
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        on_stack.add(module)
        for child in graph.find_modules_directly_imported_by(module):
            if child not in index:
                visit(child)
                low[module] = min(low[module], low[child])
            elif child in on_stack:
                low[module] = min(low[module], index[child])
        if low[module] == index[module]:
            component = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                component.append(top)
                if top == module:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for module in sorted(graph.modules):
        if module not in index:
            visit(module)
    assert not cycles, f"import cycles: {cycles}"
    assert len(graph.modules) > 50  # the graph does see the package


def test_the_formatter_lays_out_every_line_of_the_package() -> None:
    # No statement is kept out of the formatter's hands (`# fmt: skip`, `# fmt: off`):
    # a module too long to read is split by concern, not packed into fewer lines.
    kept = {
        f"{path.relative_to(PACKAGE)}:{number}"
        for path in PACKAGE.rglob("*.py")
        for number, line in enumerate(path.read_text().splitlines(), start=1)
        if re.search(r"#\s*fmt:\s*(skip|off)\b", line)
    }
    assert kept == set()


def test_no_module_names_a_concrete_part_or_torque_outside_its_package() -> None:
    # Everything reads the registries (tumble.parts.PARTS, tumble.torques.TORQUES):
    # outside tumble/parts and tumble/torques no module imports a registered
    # class, so none can construct it or dispatch on it (isinstance, issubclass,
    # type() ==). The package root's table of public names is where they are
    # offered to users.
    from tumble.parts import PARTS
    from tumble.torques import TORQUES

    concrete = {cls.__name__ for cls in (*PARTS.values(), *TORQUES.values())}
    source = Path(tumble.config.__file__).parents[1]
    found = []
    for path in sorted(source.rglob("*.py")):
        inside = path.relative_to(source).parts
        if inside[0] in {"parts", "torques"} or inside == ("__init__.py",):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                names = {alias.name for alias in node.names}
            elif isinstance(node, ast.Attribute):
                names = {node.attr}
            else:
                continue
            for name in sorted(names & concrete):
                found.append(f"{'/'.join(inside)}:{node.lineno}: {name}")
    assert found == []


def test_no_module_dispatches_on_a_part_or_torque_kind_by_its_name() -> None:
    # Outside tumble/parts and tumble/torques, code that applies to some kinds asks what
    # the kind declares (its `closed_forms`, `gyrostatic`, `dissipative`, ...), never
    # its name: no part's `kind` or torque's `name` compared with a registered name, no
    # isinstance or issubclass of a class looked up by name in PARTS or TORQUES.
    from tumble.parts import PARTS
    from tumble.torques import TORQUES

    names = set(PARTS) | set(TORQUES)
    source = Path(tumble.config.__file__).parents[1]
    found = []

    def named(node: ast.AST) -> bool:
        return isinstance(node, ast.Constant) and node.value in names

    def looked_up(node: ast.AST) -> bool:
        return (
            isinstance(node, ast.Subscript)
            and isinstance(node.value, ast.Name)
            and node.value.id in {"PARTS", "TORQUES"}
        )

    for path in sorted(source.rglob("*.py")):
        inside = path.relative_to(source).parts
        if inside[0] in {"parts", "torques"}:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Compare):
                sides = [node.left, *node.comparators]
                attributes = any(
                    isinstance(side, ast.Attribute) and side.attr in {"kind", "name"}
                    for side in sides
                )
                if attributes and any(named(side) for side in sides):
                    found.append(f"{'/'.join(inside)}:{node.lineno}")
            elif (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id in {"isinstance", "issubclass"}
                and any(looked_up(arg) for arg in ast.walk(node) if arg is not node)
            ):
                found.append(f"{'/'.join(inside)}:{node.lineno}")
    assert found == []


def test_every_closed_form_a_kind_declares_is_a_registered_check() -> None:
    from tumble.checks import THEORY_CHECKS
    from tumble.parts import PARTS
    from tumble.torques import TORQUES

    declared = {
        (kind.__name__, check)
        for kind in (*PARTS.values(), *TORQUES.values())
        for check in kind.closed_forms
    }
    assert {(kind, check) for kind, check in declared if check not in THEORY_CHECKS} == set()
    # And the checks that apply to parts or torques find them: the built-ins declare
    # the rotor's two, the damper's, and the torques' three.
    assert {check for _, check in declared} == {
        "dual-spin",
        "slew",
        "energy-sink",
        "libration",
        "rotor-loads",
    }


def test_no_function_grows_past_80_lines_of_code() -> None:
    source = Path(tumble.config.__file__).parents[1]
    long = set()
    for path in sorted(source.rglob("*.py")):
        inside = "/".join(path.relative_to(source).parts)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            body = node.body
            documented = (
                isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            )
            first = body[1] if documented and len(body) > 1 else body[0]
            if (node.end_lineno or node.lineno) - first.lineno + 1 > 80:
                long.add(f"{inside}:{node.name}")
    # More than 80 lines of code (the docstring not counted): split by concern.
    assert long == set()
