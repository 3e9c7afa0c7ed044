"""Sphinx helpers of tumble's site: pages generated from the code, and docstrings
made safe for reStructuredText.

* ``reference/scenario-keys.rst`` is written from the scenario and sweep schemas
  (pydantic models), the torque, integrator and theory registries and the part
  types, so the list of keys cannot drift from what the parser accepts.
* ``reference/cli.rst`` is written from the command-line application's own help.
* The ``import-layers`` directive draws the layers of the import-linter
  contract in ``pyproject.toml``, top first, so the architecture page follows
  the contract that ``lint-imports`` checks; a module the contract names and the
  page does not describe (or the reverse) fails the build.
* In docstrings, ``|L|`` (a norm) would read as a substitution: bars outside
  literals and math are escaped.
* MathJax's files are copied from the ``sphinx-mathjax-offline`` wheel into the
  built site, so its math renders with no network.
"""

from __future__ import annotations

import importlib.util
import inspect
import re
import shutil
import textwrap
import types
import typing
from pathlib import Path
from typing import Any

#: The part of MathJax 3 a page of CHTML math loads (4 of its 24 MB).
MATHJAX_FILES = ("tex-chtml.js", "output/chtml/fonts/woff-v2", "input/tex/extensions", "ui", "a11y")

GENERATED_NOTICE = ".. This page is generated from the code when the site is built.\n\n"


# ------------------------------------------------------------------ docstrings
_SPANS = re.compile(r"(``.+?``|:[a-z:]+:`.+?`|`[^`]+?`)", re.DOTALL)


def escape_bars(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Escape ``|`` outside literals, roles and literal or math blocks (``|L|`` is
    a norm, not a substitution), in place."""
    kept: list[bool] = []  # lines of a block, left as they are
    in_block, block_indent = False, 0
    for line in lines:
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if in_block and stripped and indent <= block_indent:
            in_block = False
        kept.append(in_block)
        if (stripped.startswith(".. ") and "::" in stripped) or stripped.endswith("::"):
            in_block, block_indent = True, indent
    text = "\n".join("" if keep else line for line, keep in zip(lines, kept, strict=True))
    pieces = _SPANS.split(text)
    for k in range(0, len(pieces), 2):
        pieces[k] = re.sub(r"(?<!\\)\|", r"\\|", pieces[k])
    escaped = "".join(pieces).split("\n")
    for number, keep in enumerate(kept):
        if not keep:
            lines[number] = escaped[number]


# ------------------------------------------------------------------ scenario keys
def _kind(metadata: list[Any]) -> tuple[str, tuple[int, ...]] | None:
    """The physical kind and shape a tumble field validator converts to, read from
    the validator's closure (``scalar_field`` / ``vector_field``)."""
    for item in metadata:
        func = getattr(item, "func", None)
        if not inspect.isfunction(func):
            continue
        names = inspect.getclosurevars(func).nonlocals
        if "kind" in names:
            return names["kind"], tuple(names.get("shape", ()))
    return None


def _describe(annotation: Any, metadata: list[Any] | None = None) -> str:
    """A reader's name for the values a field takes."""
    from tumble.units import SI_UNITS

    found = _kind(metadata or [])
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        base, *extra = typing.get_args(annotation)
        return _describe(base, [*extra, *(metadata or [])])
    if found is not None:
        kind, shape = found
        unit = SI_UNITS.get(kind, "")
        what = kind.replace("_", " ")
        if kind == "dimensionless":
            return "3 numbers" if shape == (3,) else "number"
        if shape == (3,) or (not shape and typing.get_origin(annotation) is tuple):
            return f"{what} vector ({unit}, or a string with units)"
        if shape and shape[0] == -1:
            return f"list of {what} values ({unit}, or strings with units)"
        if shape:
            return f"{shape[0]} {what} values ({unit}, or strings with units)"
        return f"{what} ({unit}, or a string with units)" if unit else what
    if origin in (typing.Union, types.UnionType):
        parts = [_describe(arg, metadata) for arg in typing.get_args(annotation)]
        return " or ".join(p for p in parts if p != "none") or "none"
    if annotation is type(None):
        return "none"
    if origin is typing.Literal:
        return " | ".join(f"``{v!r}``".replace("'", '"') for v in typing.get_args(annotation))
    if origin is list:
        (item,) = typing.get_args(annotation) or (Any,)
        return f"list of {_describe(item)}"
    if origin is dict:
        return "table"
    if inspect.isclass(annotation) and hasattr(annotation, "model_fields"):
        return "table"
    names = {str: "string", int: "integer", float: "number", bool: "true or false"}
    if annotation in names:
        return names[annotation]
    if annotation is Any:
        return "see the table's description"
    text = getattr(annotation, "__name__", str(annotation))
    return {"StrictStr": "string", "StrictInt": "integer", "StrictBool": "true or false"}.get(
        text, text
    )


def _default(field: Any) -> str:
    if field.is_required():
        return "required"
    value = field.get_default(call_default_factory=True)
    if value is None:
        return "none"
    if hasattr(value, "model_fields"):
        return "(table)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'``"{value}"``'
    return f"``{value!r}``".replace("'", '"')


def _table(title: str, model: Any, skip: tuple[str, ...] = ()) -> list[str]:
    rows = [
        (f"``{name}``", _describe(field.annotation, list(field.metadata)), _default(field))
        for name, field in model.model_fields.items()
        if name not in skip
    ]
    doc = inspect.cleandoc(model.__doc__ or "")
    out = [title, "-" * len(title), "", doc, ""] if title else [doc, ""]
    if rows:
        out += [".. list-table::", "   :header-rows: 1", "   :widths: 20 55 25", ""]
        out += ["   * - key", "     - value", "     - default"]
        for key, value, default in rows:
            out += [f"   * - {key}", f"     - {value}", f"     - {default}"]
        out.append("")
    return out


def _model_tables() -> list[str]:
    """The table of each model kind of the registry, and the arrays of tables inside it."""
    import typing

    from pydantic import BaseModel

    from tumble.scenario.model_kinds import MODEL_KINDS

    lines = []
    for kind in MODEL_KINDS.values():
        former = "".join(f" (formerly ``[{name}]``)" for name in kind.former_tables)
        lines += _table(f"``[{kind.table}]``{former}", kind.settings)
        for name, field in kind.settings.model_fields.items():
            if typing.get_origin(field.annotation) is not list:
                continue
            (inner,) = typing.get_args(field.annotation)
            if isinstance(inner, type) and issubclass(inner, BaseModel):
                lines += _table(f"``[[{kind.table}.{name}]]``", inner)
    return lines


def scenario_keys() -> str:
    """The page of every key of scenario and sweep files."""
    from tumble.checks import THEORY_CHECKS
    from tumble.config import parts as internal
    from tumble.integrators import INTEGRATORS
    from tumble.parts import PARTS
    from tumble.scenario import bodies, schema
    from tumble.sweep import schema as sweep_schema
    from tumble.torques import TORQUES

    lines = [
        GENERATED_NOTICE + ".. _scenario-keys:",
        "",
        "Scenario and sweep file keys",
        "============================",
        "",
        "Every key a scenario file (``tumble run FILE.toml``) or a sweep file",
        "(``tumble sweep FILE.toml``) accepts. Quantities are numbers in SI units or",
        'strings with units (``"250 g"``, ``"3000 rpm"``, ``"0, 0, -10 cm"``); an unknown',
        "key is an error that names the key and suggests the nearest known one.",
        "``tumble show NAME`` prints a built-in scenario to start from.",
        "",
        "Scenario files",
        "**************",
        "",
    ]
    for key, model in (
        ("[scenario]", schema.Info),
        ("[initial]", schema.Initial),
        ("[environment]", schema.Environment),
        ("[simulation]", schema.Simulation),
        ("[theory]", schema.Theory),
        ("[output]", schema.Output),
    ):
        lines += _table(f"``{key}``", model)
    lines += _model_tables()
    lines += ["The methods of ``[simulation] method``:", ""]
    lines += [f"* ``{name}``: {entry.summary}" for name, entry in INTEGRATORS.items()]
    lines += ["", "The closed forms of ``[theory] model`` (besides ``auto`` and ``none``):", ""]
    lines += [f"* ``{name}``" for name in THEORY_CHECKS]
    lines += ["", "``[body]``", "----------", "", inspect.cleandoc(bodies.__doc__ or ""), ""]
    for title, model in (
        ("A solid of tumble's shapes", bodies.ShapeBody),
        ("A mesh or CAD file", bodies.MeshBody),
        ("Point masses", bodies.PointsBody),
        ("Given mass properties", bodies.InertiaBody),
        ("An assembly of parts", bodies.PartsBody),
        ("An attitude (``rotation``, ``[initial] attitude``)", bodies.Attitude),
    ):
        lines += [f"**{title}**", "", *_table("", model)]
    lines += ["``[[internal]]``", "----------------", ""]
    lines += [inspect.cleandoc(internal.__doc__ or ""), ""]
    for name, part in PARTS.items():
        lines += [f'``type = "{name}"``: {part.summary}', ""]
        lines += _parameter_table(part.keys_in_files())
    lines += ["``[[torques]]``", "---------------", ""]
    lines += [inspect.cleandoc(schema.Torque.__doc__ or ""), ""]
    for name, model in TORQUES.items():
        if not model.in_files:
            continue
        lines += [f'``type = "{name}"``: {model.summary}', ""]
        lines += _parameter_table(model.parameters)
    lines += ["Sweep files", "***********", "", ".. currentmodule:: tumble.sweep", ""]
    lines += [inspect.cleandoc(sweep_schema.__doc__ or ""), ""]
    for key, model in (
        ("[sweep]", sweep_schema.SweepTable),
        ("[base]", sweep_schema.Base),
        ("[vary.NAME]", sweep_schema.Vary),
        ("[outputs]", sweep_schema.Outputs),
        ("[report]", sweep_schema.Report),
        ("[[report.maps]]", sweep_schema.MapTable),
        ("[dask]", sweep_schema.DaskTable),
        ("[limits]", sweep_schema.Limits),
    ):
        lines += _table(f"``{key}``", model)
    return "\n".join(lines) + "\n"


def _parameter_table(parameters: Any) -> list[str]:
    """The keys of a plugin's table in files (a torque model's, a part's)."""
    if not parameters:
        return []
    lines = [".. list-table::", "   :header-rows: 1", "   :widths: 20 20 60", ""]
    lines += ["   * - key", "     - value", "     - meaning"]
    for parameter in parameters:
        unit = _unit_of(parameter.kind)
        shape = "vector" if parameter.shape else "number" if parameter.kind else "as written"
        lines += [
            f"   * - ``{parameter.name}``",
            f"     - {shape} ({unit})" if unit else f"     - {shape}",
            f"     - {parameter.description}",
        ]
    return [*lines, ""]


def _unit_of(kind: str) -> str:
    from tumble.units import SI_UNITS

    return SI_UNITS.get(kind, "")


# ------------------------------------------------------------------ command line
def command_line() -> str:
    """The page of every command and option, from the application's help."""
    import typer

    from tumble.cli.app import app

    group = typer.main.get_command(app)
    width = {"terminal_width": 88, "max_content_width": 88}
    context = group.make_context("tumble", [], resilient_parsing=True, **width)
    lines = [
        GENERATED_NOTICE + ".. _cli:",
        "",
        "Command line",
        "============",
        "",
        "``tumble`` and its commands, as ``tumble COMMAND --help`` prints them. Errors",
        "print one line and exit with status 2 (``tumble --debug COMMAND`` shows the",
        "traceback).",
        "",
        ".. code-block:: text",
        "",
        textwrap.indent(_help(group, context), "   "),
        "",
    ]
    for name in group.list_commands(context):
        command = group.get_command(context, name)
        sub = command.make_context(name, [], parent=context, resilient_parsing=True, **width)
        lines += [f"``tumble {name}``", "-" * (len(name) + 11), "", ".. code-block:: text", ""]
        lines += [textwrap.indent(_help(command, sub), "   "), ""]
    return "\n".join(lines) + "\n"


def _help(command: Any, context: Any) -> str:
    """A command's help as plain text (typer draws it with rich, to a console)."""
    import contextlib
    import io

    captured = io.StringIO()
    with contextlib.redirect_stdout(captured):
        text = command.get_help(context)
    return re.sub(r"\x1b\[[0-9;]*m", "", (text or "") + captured.getvalue()).rstrip()


def _write_if_changed(path: Path, text: str) -> None:
    """Write ``path`` only when its text changes, so Sphinx rereads only what changed."""
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def generate_pages(app: Any) -> None:
    reference = Path(app.srcdir) / "reference"
    _write_if_changed(reference / "scenario-keys.rst", scenario_keys())
    _write_if_changed(reference / "cli.rst", command_line())


# ------------------------------------------------------------------ import layers
#: The project file whose import-linter contracts the architecture page draws.
PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"

#: The layers diagram: the column where descriptions start and the width of a line.
LAYER_COLUMN, LAYER_WIDTH = 28, 100


def contract_layers(pyproject: Path = PYPROJECT) -> tuple[str, list[str]]:
    """The container and the layers, top first, of the one ``layers`` contract in
    ``pyproject``'s ``[tool.importlinter]`` (each layer as written there, such as
    ``"scenario | sweep"``)."""
    import tomllib

    config = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    contracts = config["tool"]["importlinter"]["contracts"]
    (contract,) = [c for c in contracts if c.get("type") == "layers"]
    (container,) = contract["containers"]
    return container, [str(layer) for layer in contract["layers"]]


def layer_modules(layer: str) -> list[str]:
    """The modules of one layer, as the contract writes it: ``a | b`` (independent)
    or ``a : b`` (siblings), an optional one in parentheses."""
    return [name.strip().strip("()").strip() for name in re.split(r"[|:]", layer)]


def layer_descriptions(lines: list[str]) -> dict[str, str]:
    """``module: text`` lines (an indented line continues the one before) as a
    dictionary from the module to its text."""
    found: dict[str, str] = {}
    last = None
    for line in lines:
        if not line.strip():
            continue
        if line[0].isspace() and last is not None:
            found[last] += " " + line.strip()
            continue
        name, _, text = line.partition(":")
        last = name.strip()
        found[last] = text.strip()
    return found


def layers_diagram(
    layers: list[str], descriptions: dict[str, str], container: str = "tumble"
) -> tuple[str, list[str]]:
    """The layers drawn as text, top first: each layer as the contract writes it,
    then its modules' descriptions joined by ``;``; and the problems, one line
    each: a module of the contract with no description, or a description of a
    module the contract does not name."""
    problems = []
    named = [module for layer in layers for module in layer_modules(layer)]
    for module in named:
        if module not in descriptions:
            problems.append(
                f"The layers contract names {container}.{module}, which the page does not "
                f"describe: add a line `{module}: what it holds`."
            )
    for module in descriptions:
        if module not in named:
            problems.append(
                f"The page describes {container}.{module}, which the layers contract does "
                "not name: remove its line or add it to the contract."
            )
    rows = []
    for layer in layers:
        label = layer.strip()
        text = "; ".join(descriptions.get(module, "") for module in layer_modules(layer))
        indent = " " * LAYER_COLUMN
        if len(label) + 2 <= LAYER_COLUMN:
            first = label.ljust(LAYER_COLUMN)
        else:
            rows.append(label)
            first = indent
        rows += textwrap.wrap(
            text, LAYER_WIDTH, initial_indent=first, subsequent_indent=indent,
            break_on_hyphens=False,
        ) or [first.rstrip()]  # fmt: skip
    return "\n".join(rows), problems


#: The page whose ``import-layers`` directive describes each module.
ARCHITECTURE = PYPROJECT.parent / "docs" / "explanation" / "architecture.md"


def architecture_layers(page: Path = ARCHITECTURE) -> tuple[str, list[str]]:
    """The layers diagram as the site draws it on the architecture page (from its
    ``import-layers`` block and the contract), and its problems
    (:func:`layers_diagram`)."""
    text = page.read_text(encoding="utf-8")
    found = re.search(r"^```\{import-layers\}\n(.*?)^```", text, re.MULTILINE | re.DOTALL)
    if found is None:
        raise ValueError(f"Expected an import-layers block in {page}, got none.")
    container, layers = contract_layers()
    return layers_diagram(layers, layer_descriptions(found.group(1).splitlines()), container)


def _import_layers_directive() -> type:
    """The ``import-layers`` directive (Sphinx is imported only when the site is built)."""
    from docutils import nodes
    from sphinx.util import logging
    from sphinx.util.docutils import SphinxDirective

    logger = logging.getLogger(__name__)

    class ImportLayers(SphinxDirective):
        """The layers of ``pyproject.toml``'s layers contract as a text block; its
        content describes each module, ``module: text``."""

        has_content = True

        def run(self) -> list[Any]:
            self.env.note_dependency(str(PYPROJECT))
            container, layers = contract_layers()
            text, problems = layers_diagram(
                layers, layer_descriptions(list(self.content)), container
            )
            for problem in problems:
                logger.warning(problem, location=self.get_location())
            block = nodes.literal_block(text, text, language="text")
            self.set_source_info(block)
            return [block]

    return ImportLayers


# ------------------------------------------------------------------ math offline
def copy_mathjax(app: Any, error: Exception | None) -> None:
    """Copy MathJax into the built site's ``_static/mathjax`` (``mathjax_path``)."""
    if error is not None or app.builder.format != "html":
        return
    spec = importlib.util.find_spec("sphinx-mathjax-offline")
    if spec is None or spec.origin is None:
        raise RuntimeError("sphinx-mathjax-offline is not installed: pip install -e '.[docs]'")
    source = Path(spec.origin).parent / "static" / "mathjax"
    target = Path(app.outdir) / "_static" / "mathjax"
    for name in MATHJAX_FILES:
        origin, destination = source / name, target / name
        destination.parent.mkdir(parents=True, exist_ok=True)
        if origin.is_dir():
            shutil.copytree(origin, destination, dirs_exist_ok=True)
        else:
            shutil.copy2(origin, destination)


# ------------------------------------------------------------------ references
#: The modules whose ``__all__`` the reference documents, besides ``tumble``'s own.
PUBLIC_MODULES = (
    "theory", "analysis", "identification", "torques", "shapes", "models", "rotordynamics",
    "robots", "conformance", "sweep", "units",
)  # fmt: skip

#: Libraries whose names docstrings mention: with no network there is no
#: inventory of their names, so a reference to one is shown as a literal.
EXTERNAL = frozenset(
    ("numpy", "np", "scipy", "pint", "pandas", "pyarrow", "polars", "xarray", "duckdb",
     "zarr", "dask", "distributed", "matplotlib", "plotly", "trimesh", "cascadio", "numba",
     "pydantic", "typer", "rich", "typing", "collections", "pathlib", "os", "concurrent",
     "builtins")
)  # fmt: skip


def public_names() -> list[str]:
    """Every name the reference documents: ``tumble.X`` for X in ``tumble.__all__``
    and ``tumble.M.Y`` for Y in the ``__all__`` of each public module M, but for a
    class or function a later module offers again (:mod:`tumble.rotordynamics`
    gathers names of :mod:`tumble.theory` and :mod:`tumble.models`): it is
    documented once, under its first name, and the gathering module's page links
    there."""
    import importlib
    import inspect

    import tumble

    names = [f"tumble.{name}" for name in tumble.__all__]
    offered: set[int] = set()
    for module in PUBLIC_MODULES:
        space = importlib.import_module(f"tumble.{module}")
        for name in space.__all__:
            value = getattr(space, name)
            if inspect.isclass(value) or inspect.isfunction(value):
                if id(value) in offered:
                    continue
                offered.add(id(value))
            names.append(f"tumble.{module}.{name}")
    return names


def quiet_internal_references(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """Show a reference to tumble's internals or to an external library as its
    text; a reference to a documented name that does not resolve still warns."""
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "")
    root = target.split(".")[0]
    if root in EXTERNAL:
        return contnode
    if root == "tumble":
        documented = app.config.tumble_public_names
        modules = {f"tumble.{module}" for module in PUBLIC_MODULES}
        if not any(
            target == name or (target.startswith(name + ".") and name not in modules)
            for name in documented
        ):
            return contnode
    return None


def _list_public_names(app: Any, config: Any) -> None:
    config.tumble_public_names = public_names()


def setup(app: Any) -> dict[str, Any]:
    app.add_config_value("tumble_public_names", [], "env")
    app.connect("config-inited", _list_public_names)
    app.connect("missing-reference", quiet_internal_references)
    app.connect("builder-inited", generate_pages)
    app.connect("autodoc-process-docstring", escape_bars)
    app.connect("build-finished", copy_mathjax)
    app.add_directive("import-layers", _import_layers_directive())
    return {"parallel_read_safe": True, "parallel_write_safe": True}
