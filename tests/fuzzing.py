"""hypothesis strategies that damage valid input files: TOML documents and triangle meshes.

Fuzzing starts from files that load, so that most examples get past the first
check and reach the deeper ones, and changes them the way files go wrong:

* :func:`mutated_documents` — a TOML document (as data) with keys dropped,
  renamed or added, values retyped, quantities given other units, numbers made
  NaN, infinite, huge, tiny, negative or zero, arrays resized; :func:`toml_text`
  writes it back as TOML.
* :func:`corrupted_bytes` — a file's bytes truncated, with random or non-UTF-8
  bytes inserted or overwritten, lines repeated or dropped, or replaced whole.
* :func:`damaged_meshes` — a closed triangle mesh with vertices made NaN,
  infinite or huge, faces pointing outside the vertices, triangles dropped,
  flipped or made degenerate, written as binary or ASCII STL, OBJ, OFF or PLY
  (:func:`mesh_bytes`).
* :class:`ScenarioRunner` — scenarios run in a child process, timed from outside.
"""

from __future__ import annotations

import copy
import json
import math
import multiprocessing
import re
import struct
import time
import traceback
from collections.abc import Iterator
from multiprocessing.connection import Connection
from typing import Any

import numpy as np
from hypothesis import strategies as st

__all__ = [
    "MESH_FORMATS",
    "OPERATIONS",
    "ScenarioRunner",
    "corrupted_bytes",
    "damaged_meshes",
    "mesh_bytes",
    "mutated_documents",
    "toml_text",
    "values",
]

Path = tuple[str | int, ...]

# ------------------------------------------------------------------ TOML text
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def _key(name: str) -> str:
    return name if _BARE_KEY.fullmatch(name) else _string(name)


def _string(text: str) -> str:
    # json escapes quotes, backslashes and control characters as TOML does,
    # except DEL, which TOML also requires escaped.
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, list):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(str(k))} = {_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML for {type(value).__name__}")


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def toml_text(document: dict[str, Any]) -> str:
    """A document as TOML: its tables as ``[name]``, its arrays of tables as
    ``[[name]]``, everything below them inline (``tomllib.loads`` gives the
    document back)."""
    lines = [
        f"{_key(k)} = {_value(v)}"
        for k, v in document.items()
        if not isinstance(v, dict) and not _is_table_array(v)
    ]
    for name, value in document.items():
        if isinstance(value, dict):
            lines += ["", f"[{_key(name)}]"]
            lines += [f"{_key(str(k))} = {_value(v)}" for k, v in value.items()]
        elif _is_table_array(value):
            for table in value:
                lines += ["", f"[[{_key(name)}]]"]
                lines += [f"{_key(str(k))} = {_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ values
#: Numbers at the edges of float64 and of physics: NaN, infinities, the largest
#: and smallest (subnormal) floats, zero of both signs, negative values.
SPECIAL_NUMBERS: tuple[float, ...] = (
    math.nan,
    math.inf,
    -math.inf,
    1.7976931348623157e308,
    -1e308,
    1e300,
    1e20,
    5e-324,
    -5e-324,
    1e-300,
    0.0,
    -0.0,
    -1.0,
    1.0,
    2.0,
    0.5,
)

#: Units of every kind tumble reads, and some it never should (offset
#: temperatures, frequency, percent, an unknown word, nothing).
UNITS: tuple[str, ...] = (
    "kg",
    "g",
    "m",
    "cm",
    "mm",
    "inch",
    "s",
    "ms",
    "min",
    "rad",
    "deg",
    "rad/s",
    "rpm",
    "turn/s",
    "Hz",
    "kg*m^2",
    "kg/m^3",
    "N*m",
    "N*m*s",
    "N/m",
    "N*s/m",
    "m/s^2",
    "kg*m^2/s",
    "degC",
    "%",
    "furlong",
    "blorp",
    "",
)

numbers = st.one_of(
    st.sampled_from(SPECIAL_NUMBERS),
    st.floats(),
    st.integers(-(2**70), 2**70),
    st.integers(-5, 5),
)


def _number_text(value: float | int) -> str:
    return repr(value) if isinstance(value, float) else str(value)


quantities = st.builds(
    lambda number, unit: f"{_number_text(number)} {unit}".strip(),
    numbers,
    st.sampled_from(UNITS),
)
vector_strings = st.builds(
    lambda items, unit: ", ".join(_number_text(v) for v in items) + (f" {unit}" if unit else ""),
    st.lists(numbers, min_size=0, max_size=5),
    st.sampled_from(UNITS),
)
scalars = st.one_of(
    numbers,
    quantities,
    vector_strings,
    st.booleans(),
    st.text(max_size=12),
    st.sampled_from(["", " ", "auto", "none", "exact", "rk4", "rotor", "box", "space", "1e999"]),
)


def values(keys: tuple[str, ...] = ()) -> st.SearchStrategy[Any]:
    """Any TOML value: numbers (special ones often), quantities with units of any
    kind, comma-separated vectors, text, booleans, and arrays and tables of them
    two levels deep (tables keyed by ``keys`` or random names)."""
    names = st.sampled_from(keys) | st.text(max_size=8) if keys else st.text(max_size=8)

    def tables(inner: st.SearchStrategy[Any]) -> st.SearchStrategy[dict[str, Any]]:
        return st.lists(st.tuples(names, inner), max_size=3).map(dict)

    nested = st.lists(scalars, max_size=5) | tables(scalars)
    return scalars | nested | st.lists(scalars | nested, max_size=4) | tables(scalars | nested)


# ------------------------------------------------------------------ documents
def _paths(node: Any, prefix: Path = ()) -> Iterator[Path]:
    """Every key and array entry below ``node``, parents before children."""
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in items:
        path = (*prefix, key)
        yield path
        if isinstance(value, dict | list):
            yield from _paths(value, path)


def _keys(node: Any) -> set[str]:
    found: set[str] = set()
    for path in _paths(node):
        if isinstance(path[-1], str):
            found.add(path[-1])
    return found


def _parent(document: dict[str, Any], path: Path) -> Any:
    node: Any = document
    for part in path[:-1]:
        node = node[part]
    return node


def _typo(draw: st.DrawFn, name: str) -> str:
    """``name`` with one character dropped, doubled, swapped or changed in case."""
    if not name:
        return "x"
    k = draw(st.integers(0, len(name) - 1))
    edit = draw(st.sampled_from(["drop", "double", "swap", "case"]))
    if edit == "drop":
        return name[:k] + name[k + 1 :] or "x"
    if edit == "double":
        return name[:k] + name[k] + name[k:]
    if edit == "swap" and k + 1 < len(name):
        return name[:k] + name[k + 1] + name[k] + name[k + 2 :]
    return name.upper()


def _retyped(draw: st.DrawFn, value: Any) -> Any:
    """The same value in another TOML type: a string, a number, an array or a table."""
    kind = draw(st.sampled_from(["string", "number", "list", "table", "first"]))
    if kind == "string":
        if isinstance(value, list):
            return ", ".join(str(v) for v in value)
        return str(value)
    if kind == "number":
        match = re.match(r"\s*[-+]?[\d.]+(e[-+]?\d+)?", str(value))
        return float(match.group(0)) if match else draw(numbers)
    if kind == "list":
        return [value]
    if kind == "table":
        return {"value": value}
    if isinstance(value, list | dict) and value:
        return next(iter(value.values())) if isinstance(value, dict) else value[0]
    return value


def _reunited(draw: st.DrawFn, value: Any) -> Any:
    """A quantity (or every quantity of an array) with another unit: "5 kg" as a time."""
    if isinstance(value, list):
        return [_reunited(draw, v) for v in value]
    if not isinstance(value, str):
        return f"{_number_text(value)} {draw(st.sampled_from(UNITS))}".strip()
    match = re.match(r"^(.*[\d.])\s*([A-Za-z%*/^ ]*)$", value.strip())
    body = match.group(1) if match else value
    return f"{body} {draw(st.sampled_from(UNITS))}".strip()


_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|[-+]?(nan|inf)")


def _rescaled(draw: st.DrawFn, value: Any) -> Any:
    """The same value with one of its numbers changed, its units kept ("250 g" as
    "1e+300 g", "nan g", "-0.0 g"): a value that may pass the check of its units and
    reach the checks of its range, or the code behind them."""
    if isinstance(value, bool):
        return value
    if isinstance(value, int | float):
        return draw(numbers)
    if isinstance(value, list) and value:
        k = draw(st.integers(0, len(value) - 1))
        return [*value[:k], _rescaled(draw, value[k]), *value[k + 1 :]]
    if isinstance(value, str):
        found = list(_NUMBER.finditer(value))
        if found:
            match = draw(st.sampled_from(found))
            number = _number_text(draw(numbers))
            return value[: match.start()] + number + value[match.end() :]
    return value


def _resized(draw: st.DrawFn, value: Any) -> Any:
    """An array (or a comma-separated string) with an entry dropped or repeated."""
    if isinstance(value, str) and "," in value:
        parts = value.split(",")
        if draw(st.booleans()) and len(parts) > 1:
            del parts[draw(st.integers(0, len(parts) - 1))]
        else:
            parts.insert(draw(st.integers(0, len(parts))), draw(st.sampled_from(parts)))
        return ",".join(parts)
    if isinstance(value, list):
        items = list(value)
        if items and draw(st.booleans()):
            del items[draw(st.integers(0, len(items) - 1))]
        else:
            extra = draw(st.sampled_from(items)) if items else draw(scalars)
            items.insert(draw(st.integers(0, len(items))), copy.deepcopy(extra))
        return items
    return [value, value]


#: The mutations, each a way files go wrong: a key dropped, renamed (a typo, another
#: key of the file, random text), replaced by any value, a number changed with its
#: units kept, units swapped, a value retyped or resized, a key added.
OPERATIONS = ("drop", "rename", "replace", "rescale", "units", "retype", "resize", "add")


@st.composite
def mutated_documents(
    draw: st.DrawFn,
    document: dict[str, Any],
    max_mutations: int = 3,
    operations: tuple[str, ...] = OPERATIONS,
) -> dict[str, Any]:
    """``document`` (TOML data) with one to ``max_mutations`` mutations, each at a
    random key or array entry, drawn from ``operations`` (:data:`OPERATIONS`)."""
    document = copy.deepcopy(document)
    vocabulary = tuple(sorted(_keys(document)))
    for _ in range(1 + draw(st.integers(0, max_mutations - 1))):
        paths = list(_paths(document))
        if not paths:
            break
        # Mostly values rather than whole tables: a table replaced by junk fails
        # at its first check, a damaged value reaches the checks behind it.
        leaves = [p for p in paths if not isinstance(_parent(document, p)[p[-1]], dict | list)]
        path = draw(st.sampled_from(leaves if leaves and draw(st.integers(0, 4)) else paths))
        parent = _parent(document, path)
        key = path[-1]
        operation = draw(st.sampled_from(operations))
        if operation == "drop":
            del parent[key]
        elif operation == "rename" and isinstance(key, str):
            how = draw(st.sampled_from(["typo", "other", "random"]))
            if how == "typo":
                name = _typo(draw, key)
            elif how == "other":
                name = draw(st.sampled_from(vocabulary))
            else:
                name = draw(st.text(max_size=10))
            parent[name] = parent.pop(key)
        elif operation == "replace":
            parent[key] = draw(values(vocabulary))
        elif operation == "rescale":
            parent[key] = _rescaled(draw, parent[key])
        elif operation == "units":
            parent[key] = _reunited(draw, parent[key])
        elif operation == "retype":
            parent[key] = _retyped(draw, parent[key])
        elif operation == "resize":
            parent[key] = _resized(draw, parent[key])
        else:  # add a sibling key (or an array entry)
            value = draw(values(vocabulary))
            if isinstance(parent, dict):
                parent[draw(st.sampled_from(vocabulary) | st.text(max_size=8))] = value
            else:
                parent.append(value)
    return document


# ------------------------------------------------------------------ bytes
@st.composite
def corrupted_bytes(draw: st.DrawFn, data: bytes) -> bytes:
    """``data`` truncated at a random byte, with random or non-UTF-8 bytes inserted
    or written over it, a slice dropped or repeated, or replaced whole by random
    bytes."""
    n = len(data)
    at = draw(st.integers(0, n))
    junk = draw(
        st.binary(min_size=1, max_size=16)
        | st.sampled_from([b"\xff", b"\xc3", b"\x80\x80", b"\xed\xa0\x80", b"\x00", b"\r", b"\n["])
    )
    how = draw(
        st.sampled_from(["truncate", "insert", "overwrite", "drop", "repeat", "replace", "flip"])
    )
    if how == "truncate":
        return data[:at]
    if how == "insert":
        return data[:at] + junk + data[at:]
    if how == "overwrite":
        return data[:at] + junk + data[at + len(junk) :]
    if how == "drop":
        return data[:at] + data[at + draw(st.integers(1, 64)) :]
    if how == "repeat":
        end = min(n, at + draw(st.integers(1, 200)))
        return data[:end] + data[at:end] * draw(st.integers(1, 3)) + data[end:]
    if how == "flip" and n:
        k = min(at, n - 1)
        return data[:k] + bytes([data[k] ^ (1 << draw(st.integers(0, 7)))]) + data[k + 1 :]
    return draw(st.binary(max_size=max(n, 1)))


# ------------------------------------------------------------------ meshes
MESH_FORMATS = ("stl", "stl-ascii", "obj", "off", "ply")


def mesh_bytes(vertices: np.ndarray, faces: list[list[int]], file_format: str) -> bytes:
    """The file of a mesh, written as given: non-finite coordinates, indices out of
    range and polygons of any size are kept (a format that stores triangles only,
    STL, takes the vertices of each face in turn, skipping indices out of range)."""
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    if file_format in ("stl", "stl-ascii"):
        corners = [
            [vertices[i] for i in face if -len(vertices) <= i < len(vertices)][:3] for face in faces
        ]
        triangles = [c for c in corners if len(c) == 3]
        if file_format == "stl":
            out = [b"binary STL".ljust(80), struct.pack("<I", len(triangles))]
            with np.errstate(over="ignore"):  # beyond single precision: inf, as the file holds
                for triangle in triangles:
                    out.append(np.zeros(3, "<f4").tobytes())
                    out.append(np.asarray(triangle, dtype="<f4").tobytes() + b"\0\0")
            return b"".join(out)
        lines = ["solid fuzz"]
        for triangle in triangles:
            lines += ["facet normal 0 0 0", "outer loop"]
            lines += ["vertex " + " ".join(repr(float(x)) for x in p) for p in triangle]
            lines += ["endloop", "endfacet"]
        return ("\n".join([*lines, "endsolid fuzz"]) + "\n").encode()
    points = [" ".join(repr(float(x)) for x in p) for p in vertices]
    if file_format == "obj":
        lines = [f"v {p}" for p in points] + [
            "f " + " ".join(str(i + 1) for i in face) for face in faces
        ]
    elif file_format == "off":
        lines = ["OFF", f"{len(points)} {len(faces)} 0", *points]
        lines += [f"{len(face)} " + " ".join(map(str, face)) for face in faces]
    else:
        lines = [
            "ply",
            "format ascii 1.0",
            f"element vertex {len(points)}",
            "property float x",
            "property float y",
            "property float z",
            f"element face {len(faces)}",
            "property list uchar int vertex_indices",
            "end_header",
            *points,
        ]
        lines += [f"{len(face)} " + " ".join(map(str, face)) for face in faces]
    return ("\n".join(lines) + "\n").encode()


_MESH_DAMAGE = (
    "coordinate",
    "scale",
    "index",
    "drop_face",
    "flip_face",
    "degenerate",
    "polygon",
    "drop_vertex",
    "no_faces",
    "duplicate_face",
)


@st.composite
def damaged_meshes(
    draw: st.DrawFn, vertices: np.ndarray, faces: np.ndarray, max_damage: int = 2
) -> tuple[np.ndarray, list[list[int]]]:
    """A closed mesh (``vertices`` (n, 3), ``faces`` (k, 3)) with zero to
    ``max_damage`` defects: a coordinate made NaN, infinite, huge or tiny, the
    whole mesh scaled to the ends of float range, a face index out of range,
    triangles dropped, flipped, repeated or made degenerate, a polygon of more
    or fewer corners, a vertex removed, no faces at all."""
    points = np.array(vertices, dtype=float)
    polygons = [list(map(int, face)) for face in faces]
    for _ in range(draw(st.integers(0, max_damage))):
        damage = draw(st.sampled_from(_MESH_DAMAGE))
        n, k = len(points), len(polygons)
        if damage == "coordinate" and n:
            row, column = draw(st.integers(0, n - 1)), draw(st.integers(0, 2))
            points[row, column] = draw(st.sampled_from(SPECIAL_NUMBERS) | st.floats())
        elif damage == "scale":
            with np.errstate(over="ignore", under="ignore", invalid="ignore"):
                points = points * draw(st.sampled_from([0.0, 1e-300, 1e-160, 1e30, 1e160, 1e300]))
        elif damage == "index" and k:
            face = draw(st.integers(0, k - 1))
            corner = draw(st.integers(0, len(polygons[face]) - 1)) if polygons[face] else None
            bad = draw(st.sampled_from([n, n + 1, -1, -n - 1, 2**31, 2**40]))
            if corner is not None:
                polygons[face][corner] = bad
        elif damage == "drop_face" and k:
            del polygons[draw(st.integers(0, k - 1))]
        elif damage == "flip_face" and k:
            polygons[draw(st.integers(0, k - 1))].reverse()
        elif damage == "degenerate" and k:
            face = polygons[draw(st.integers(0, k - 1))]
            if len(face) > 1:
                face[1] = face[0]
        elif damage == "polygon" and k and n:
            face = polygons[draw(st.integers(0, k - 1))]
            if draw(st.booleans()) or len(face) < 2:
                face.append(draw(st.integers(0, n - 1)))
            else:
                face.pop()
        elif damage == "drop_vertex" and n:
            points = np.delete(points, draw(st.integers(0, n - 1)), axis=0)
        elif damage == "no_faces":
            polygons = []
        elif damage == "duplicate_face" and k:
            polygons.append(list(polygons[draw(st.integers(0, k - 1))]))
    return points, polygons


# ------------------------------------------------------------------ runs
def _integrator_kind(loaded: Any) -> str:
    """The kind of integrator (``stepping``, ``sampling``, ``adaptive``) a scenario's
    run will use, found as :func:`tumble.scenario.run` finds it."""
    from tumble.scenario.build import initial_state, internal_parts, mass_properties, torque_model
    from tumble.simulation import prepare

    spec = loaded.spec
    if "gyrocompass" in spec.model_tables():
        return "gyrocompass"
    mp = mass_properties(spec.body, loaded.folder, loaded)
    parts, added = internal_parts(spec, loaded)
    state = initial_state(spec)
    setup = prepare(
        mp if added is None else mp + added,
        state.omega,
        attitude0=state.attitude,
        pivot=spec.environment.pivot,
        gravity=spec.environment.gravity,
        torque=torque_model(spec, loaded),
        method=spec.simulation.method,
        internal=parts,
    )
    return str(setup.integrator.kind)


def _serve(connection: Connection) -> None:
    """The child process of :class:`ScenarioRunner`: validate and run each scenario
    text it receives, and answer ``(outcome, phase or kind, detail)``."""
    import warnings

    import tumble.scenario as scenario
    from tumble import InputError

    warnings.simplefilter("ignore")
    while (request := connection.recv()) is not None:
        text, folder = request
        phase = "load"
        try:
            loaded = scenario.parse(text, "run.toml", folder)
            phase = "run"
            connection.send(("integrator", _integrator_kind(loaded), ""))
            scenario.run(loaded)
        except InputError as exc:
            connection.send(("refused", phase, f"{type(exc).__name__}: {exc}"))
        except Exception as exc:
            connection.send(("raised", phase, "".join(traceback.format_exception(exc))))
        else:
            connection.send(("accepted", phase, ""))


class ScenarioRunner:
    """Runs scenario texts in a child process, stopped when a run takes longer than
    ``limit`` seconds.

    The compiled kernels cannot be interrupted from Python, and a run's work is
    not always bounded (:func:`tumble.scenario.run` bounds the steps of the
    stepping methods, not those of the adaptive one), so a run is timed from
    outside. The child lives from run to run (it keeps its compiled kernels)
    until a run times out or crashes it; the next run starts another.
    """

    def __init__(self, limit: float) -> None:
        self.limit = limit
        self._process: Any = None
        self._connection: Connection | None = None

    def run(self, text: str, folder: str) -> tuple[str, str, str]:
        """``(outcome, phase or kind, detail)``: ``accepted``, ``refused`` (with the
        error's type and message), ``raised`` (with the traceback),
        ``timeout`` or ``crashed`` (with the kind of
        integrator the run had, when it was found)."""
        connection = self._start()
        connection.send((text, folder))
        kind = "unknown"
        end = time.monotonic() + self.limit
        while True:
            left = end - time.monotonic()
            if left <= 0 or not connection.poll(left):
                self.close()
                return ("timeout", kind, f"no answer within {self.limit:g} s")
            try:
                outcome, phase, detail = connection.recv()
            except EOFError:
                code = self._process.exitcode
                self.close()
                return ("crashed", kind, f"the child ended with exit code {code}")
            if outcome != "integrator":
                return (outcome, phase, detail)
            kind = phase

    def _start(self) -> Connection:
        if self._connection is None:
            context = multiprocessing.get_context("spawn")  # no threads or locks inherited
            self._connection, child = context.Pipe()
            self._process = context.Process(target=_serve, args=(child,), daemon=True)
            self._process.start()
            child.close()
        return self._connection

    def close(self) -> None:
        """Stop the child (at once: it may be inside a kernel)."""
        if self._process is not None:
            self._process.kill()
            self._process.join()
        if self._connection is not None:
            self._connection.close()
        self._process = self._connection = None
