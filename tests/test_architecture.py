"""The compiled core imports only numpy, numba and a few standard modules.

import-linter (``make contracts``) forbids named packages; this test allows a
fixed list instead, so a new dependency cannot slip into ``tumble.core``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import tumble.core

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
