"""The package face: one table of public names (``tumble._PUBLIC``) makes
``__all__``, ``dir(tumble)``, the lazy loader and what type checkers see; no
module of the package imports the package root back."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import tumble

PACKAGE = Path(tumble.__file__).parent
SUBMODULES = {path.stem for path in PACKAGE.glob("*.py")} | {
    path.parent.name for path in PACKAGE.glob("*/__init__.py")
}


def _type_checking_imports() -> dict[str, str]:
    """``{name: module it is imported from}`` of the ``if TYPE_CHECKING:`` block of
    ``tumble/__init__.py`` (a submodule, ``from tumble import x``, as ``tumble.x``)."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text())
    blocks = [
        node
        for node in tree.body
        if isinstance(node, ast.If)
        and isinstance(node.test, ast.Name)
        and node.test.id == "TYPE_CHECKING"
    ]
    assert len(blocks) == 1
    names: dict[str, str] = {}
    for node in ast.walk(blocks[0]):
        if isinstance(node, ast.Import):
            raise AssertionError(
                f"expected `from ... import x as x`, got `import` on line {node.lineno}"
            )
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                # "x as x": the name is re-exported for strict type checkers.
                assert alias.asname == alias.name, (
                    f"line {node.lineno}: {alias.name} needs `as {alias.name}`"
                )
                module = node.module or ""
                names[alias.name] = f"tumble.{alias.name}" if module == "tumble" else module
    return names


def test_the_type_checking_imports_are_the_table() -> None:
    assert _type_checking_imports() == tumble._PUBLIC


def test_all_and_dir_are_the_table() -> None:
    assert set(tumble.__all__) == set(tumble._PUBLIC) - tumble._OPTIONAL
    assert len(tumble.__all__) == len(set(tumble.__all__))
    assert set(dir(tumble)) == set(tumble._PUBLIC)
    # Only sympy's module is optional (a development dependency).
    assert {"symbolic"} == tumble._OPTIONAL


def test_every_public_name_resolves_to_where_the_table_says() -> None:
    for name, where in tumble._PUBLIC.items():
        value = getattr(tumble, name)
        if where == f"tumble.{name}":
            assert value is sys.modules[where]
        else:
            assert value is getattr(sys.modules[where], name), name


def test_an_unknown_name_is_an_attribute_error() -> None:
    try:
        tumble.simulation_batch  # noqa: B018
    except AttributeError as error:
        assert str(error) == "module 'tumble' has no attribute 'simulation_batch'"
    else:
        raise AssertionError("expected an AttributeError")


def test_import_tumble_loads_neither_numba_nor_pint() -> None:
    check = (
        "import sys, tumble; "
        "heavy = [m for m in ('numba', 'pint', 'scipy', 'pydantic', 'sympy') if m in sys.modules]; "
        "print(heavy, tumble.__version__)"
    )
    done = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("[] ")


def test_no_module_imports_the_package_root() -> None:
    # `import tumble` and `from tumble import name` read the package's face; a
    # module inside the package reads the module that defines the name instead
    # (`from tumble._version import __version__`), so no import goes through
    # tumble/__init__.py. `from tumble import shapes` imports a submodule: allowed.
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path == PACKAGE / "__init__.py":
            continue
        where = path.relative_to(PACKAGE)
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                found += [f"{where}:{node.lineno}" for a in node.names if a.name == "tumble"]
            elif isinstance(node, ast.ImportFrom):
                root = (node.level == 0 and node.module == "tumble") or (
                    node.module is None and node.level >= len(where.parts)
                )
                if root:
                    found += [
                        f"{where}:{node.lineno} ({alias.name})"
                        for alias in node.names
                        if alias.name not in SUBMODULES
                    ]
    assert found == []


def test_the_rotordynamics_namespace_offers_the_rotors_names_themselves() -> None:
    # One object under each name: the namespace gathers, it does not wrap.
    assert tumble.rotordynamics.RigidRotor is tumble.theory.RigidRotor
    assert tumble.rotordynamics.Bearing is tumble.theory.Bearing
    assert tumble.rotordynamics.run_up is tumble.models.run_up
    assert tumble.rotordynamics.RunUp is tumble.models.RunUp
    assert set(tumble.rotordynamics.__all__) == {
        "Bearing",
        "RigidRotor",
        "RunUp",
        "Whirl",
        "run_up",
    }
