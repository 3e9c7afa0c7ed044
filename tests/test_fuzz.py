"""Fuzz tests: a damaged input file loads (and runs), or it is refused with an InputError.

Each test starts from files that load — the built-in scenarios and sweeps,
small closed meshes, a STEP part — and damages them (:mod:`fuzzing`): keys
dropped, renamed or retyped, quantities in the wrong units, numbers made NaN,
infinite, huge, tiny, negative or zero, arrays resized, bytes truncated,
inserted or replaced; for meshes, vertices made NaN, infinite or huge, faces
pointing outside the vertices, triangles dropped or flipped. The property, the
contract of tumble's errors: the call returns, or raises
:class:`tumble.InputError` (ScenarioError, SweepError, MeshError,
IntegrationError, ...) with a one-line message in the template "Expected ...,
got ..."; never another exception type, never a hang.

Under the everyday profiles the tests share a few hundred examples, so that
they add well under a minute to the suite. The ``fuzz`` profile
(``tests/conftest.py``) runs all of its examples in every test, tens of
thousands in all, with a deadline per example so that a hang fails instead of
stalling; run it by hand, with hypothesis's counts of examples and outcomes::

    TUMBLE_HYPOTHESIS=fuzz .venv/bin/pytest tests/test_fuzz.py --hypothesis-show-statistics

``TUMBLE_FUZZ_EXAMPLES=N`` sets the examples per test of that profile (5000 by
default: 35,250 in all, 11 minutes on two cores; the counts of the last run are
in bench/RESULTS.md). Scenarios run in a
child process that times each run itself (:class:`fuzzing.ScenarioRunner`,
``RUN_LIMIT``): a compiled kernel cannot be interrupted, and the first run of a
kernel also compiles it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import re
import tempfile
import tomllib
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh
from hypothesis import event, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from trimesh import creation

import tumble
import tumble.scenario as scenario
from fuzzing import (
    MESH_FORMATS,
    ScenarioRunner,
    corrupted_bytes,
    damaged_meshes,
    mesh_bytes,
    mutated_documents,
    toml_text,
    values,
)
from tumble import InputError, MeshError
from tumble.mesh import mesh_mass_properties, step
from tumble.scenario import ScenarioError
from tumble.scenario.bodies import Attitude
from tumble.scenario.loaded import BUILTINS as SCENARIOS
from tumble.sweep import load_sweep
from tumble.sweep.build import parse_sweep
from tumble.sweep.engine import BUILTINS as SWEEPS
from tumble.sweep.metrics import compute_chunk
from tumble.sweep.schema import SweepError
from tumble.units import length_scale, to_si

FUZZ = settings.get_current_profile_name() == "fuzz"


def examples(share: float, fuzz_share: float = 1.0) -> int:
    """The examples of one test: ``share`` of the profile's (at least 5) under the
    everyday profiles, ``fuzz_share`` of them under the fuzz profile."""
    total = settings.default.max_examples
    return max(5, round(total * (fuzz_share if FUZZ else share)))


# ------------------------------------------------------------ the property
def check_message(message: str) -> None:
    """An InputError's message is one line in tumble's template."""
    assert len(message.splitlines()) == 1, f"a message of several lines: {message!r}"
    assert "Expected" in message, f"a message outside the template: {message!r}"


def loads_or_refuses(call: Callable[[], Any], where: str) -> Any:
    """``call()``'s value, or None when it raised an InputError with a one-line message
    in tumble's template; the outcome is counted as a hypothesis event (shown
    by ``--hypothesis-show-statistics``). Warnings are fine: they are how a
    value that is odd but valid is reported."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            value = call()
        except InputError as exc:
            check_message(str(exc))
            event(f"{where}: refused ({type(exc).__name__})")
            return None
    event(f"{where}: accepted")
    return value


# ------------------------------------------------------------ files
@pytest.fixture(scope="module")
def folder() -> Iterator[Path]:
    """A folder for the damaged files, one file per test overwritten by each example
    (hypothesis runs many examples per test, so function-scoped tmp_path does not fit)."""
    with tempfile.TemporaryDirectory(prefix="tumble-fuzz-") as name:
        yield Path(name)


def _quick(document: dict[str, Any]) -> dict[str, Any]:
    """A built-in scenario that runs in milliseconds and writes nothing: at most 50
    samples, no figures, no viewer (their durations are kept: their theory
    checks need them, and compiled they take at most 0.4 s)."""
    output = document.setdefault("output", {})
    output.update(samples=min(output.get("samples", 50), 50), figures=False, viewer=False)
    return document


SCENARIO_DOCUMENTS = {
    name: _quick(tomllib.loads(scenario.builtin_text(name))) for name in scenario.builtin_names()
}
SWEEP_DOCUMENTS = {name: tomllib.loads(SWEEPS.text(name)) for name in SWEEPS.names()}

#: Body-steps of the one chunk each sweep example computes: 0.1 s of kernels at
#: most, where a chunk of the built-in sweeps' 4 bodies × 8000 steps takes ~3 ms.
CHUNK_WORK = 200_000
CHUNK_BODIES = 4


def _compute_one_chunk(plan: Any) -> None:
    """The last chunk of a plan cut into chunks of 4 bodies, if it is cheap."""
    small = dataclasses.replace(plan, chunk_size=min(plan.chunk_size, CHUNK_BODIES))
    if small.n_steps * CHUNK_BODIES <= CHUNK_WORK:
        compute_chunk(small, small.n_chunks - 1)


@pytest.fixture(scope="module", autouse=True)
def compiled() -> None:
    """Compile the kernels the built-in files use before the first example, so that
    the fuzz profile's deadline times examples, not the compiler (a kernel
    compiles in seconds; numba caches it on disk for the next session)."""
    if settings.default.deadline is None:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, document in SCENARIO_DOCUMENTS.items():
            scenario.run(scenario.parse(toml_text(document), name, SCENARIOS.folder()))
        for document in SWEEP_DOCUMENTS.values():
            for method in ("rk4", "splitting", "strang", "exact"):
                base = {**document["base"], "method": method}
                text = toml_text({**document, "base": base})
                with contextlib.suppress(InputError):  # exact: refuses the rotors' torque
                    _compute_one_chunk(parse_sweep(text, "warm-up.toml"))


# ------------------------------------------------------------ scenarios
scenario_names = st.sampled_from(sorted(SCENARIO_DOCUMENTS))


@settings(max_examples=examples(0.5))
@given(name=scenario_names, data=st.data())
def test_damaged_scenario_files_load_or_are_refused(
    folder: Path, name: str, data: st.DataObject
) -> None:
    """Scenario files with keys, values, units and arrays damaged either validate or
    are refused with a ScenarioError naming the file."""
    path = folder / "damaged.toml"
    path.write_text(toml_text(data.draw(mutated_documents(SCENARIO_DOCUMENTS[name]))))
    loads_or_refuses(lambda: scenario.load(path), "load")


@settings(max_examples=examples(0.25))
@given(name=scenario_names, data=st.data())
def test_corrupted_scenario_bytes_load_or_are_refused(
    folder: Path, name: str, data: st.DataObject
) -> None:
    """Scenario files truncated, with random or non-UTF-8 bytes, or replaced by random
    bytes either validate or are refused (invalid UTF-8, invalid TOML, the schema)."""
    path = folder / "corrupted.toml"
    path.write_bytes(data.draw(corrupted_bytes(toml_text(SCENARIO_DOCUMENTS[name]).encode())))
    loads_or_refuses(lambda: scenario.load(path), "load")


#: Mostly numbers changed with their units kept: values that pass the checks of
#: their kind and reach the run (the other mutations mostly end at validation,
#: which the tests above cover).
RUN_MUTATIONS = ("rescale", "rescale", "rescale", "rescale", "drop", "resize", "units", "retype")


#: Seconds a scenario's run may take in the runner: far above a run of the
#: built-in files (0.4 s at most, compiled), above the compile time of the
#: kernels it may need (5 to 25 s on two busy cores) and above the longest run
#: a scenario allows (5e7 steps; measured 2.3 s with RK4, 11 s adaptive with a
#: damper, 23 s with the splitting).
RUN_LIMIT = 60.0


@pytest.fixture(scope="module")
def runner() -> Iterator[ScenarioRunner]:
    worker = ScenarioRunner(RUN_LIMIT)
    yield worker
    worker.close()


# The runner times each run: hypothesis's deadline would also count the compiler.
@settings(max_examples=examples(0.5), deadline=None)
@given(name=scenario_names, data=st.data())
def test_damaged_scenarios_run_or_are_refused(
    folder: Path, runner: ScenarioRunner, name: str, data: st.DataObject
) -> None:
    """A damaged scenario that validates also runs, or is refused while it is built or
    run (a mesh with holes, a theory that does not fit, an integration that
    diverges, too many steps): the values validation lets through are ones the
    run can take, within a bounded time."""
    text = toml_text(
        data.draw(mutated_documents(SCENARIO_DOCUMENTS[name], operations=RUN_MUTATIONS))
    )
    outcome, phase, detail = runner.run(text, str(folder))
    if outcome == "refused":
        check_message(detail)
    assert outcome in ("accepted", "refused"), f"{outcome} ({phase}): {detail}"
    event(f"{phase}: {outcome}" + (f" ({detail.split(':')[0]})" if outcome != "accepted" else ""))


# ------------------------------------------------------------ sweeps
sweep_names = st.sampled_from(sorted(SWEEP_DOCUMENTS))


def _load_and_compute(path: Path) -> None:
    plan = loads_or_refuses(lambda: load_sweep(path), "load")
    if plan is not None:
        loads_or_refuses(lambda: _compute_one_chunk(plan), "chunk")


@settings(max_examples=examples(0.25))
@given(name=sweep_names, data=st.data())
def test_damaged_sweep_files_load_or_are_refused(
    folder: Path, name: str, data: st.DataObject
) -> None:
    """Damaged sweep files either become a plan, whose last chunk (of 4 bodies) is
    computed where that is cheap, or are refused with a SweepError."""
    path = folder / "damaged-sweep.toml"
    path.write_text(toml_text(data.draw(mutated_documents(SWEEP_DOCUMENTS[name]))))
    _load_and_compute(path)


@settings(max_examples=examples(0.15))
@given(name=sweep_names, data=st.data())
def test_corrupted_sweep_bytes_load_or_are_refused(
    folder: Path, name: str, data: st.DataObject
) -> None:
    """Sweep files with corrupted bytes either load or are refused."""
    path = folder / "corrupted-sweep.toml"
    path.write_bytes(data.draw(corrupted_bytes(toml_text(SWEEP_DOCUMENTS[name]).encode())))
    _load_and_compute(path)


# ------------------------------------------------------------ meshes
def _two_boxes_one_hollow() -> trimesh.Trimesh:
    """A box with a box-shaped cavity (an inward-wound inner shell) beside a small box:
    three closed parts, for the checks of parts and cavities."""
    outer = creation.box(extents=(2.0, 2.0, 2.0))
    inner = creation.box(extents=(1.0, 1.0, 1.0))
    inner.invert()
    beside = creation.box(extents=(0.5, 0.5, 0.5))
    beside.apply_translation((3.0, 0.0, 0.0))
    return trimesh.util.concatenate([outer, inner, beside])


MESHES: dict[str, trimesh.Trimesh] = {
    "box": creation.box(extents=(0.1, 0.2, 0.3)),
    "icosphere": creation.icosphere(subdivisions=1),
    "hexagonal prism": creation.cylinder(radius=1.0, height=2.0, sections=6),
    "hollow box and a box": _two_boxes_one_hollow(),
    "satellite": trimesh.load_mesh(SCENARIOS.folder() / "satellite.stl", process=False),
}
SUFFIX = {"stl-ascii": "stl"}

#: Arguments of from_mesh as a user passes them (three examples in four), or damaged:
#: any value for density or mass (or neither, or both), units, merge_tolerance and
#: shell_thickness.
valid_arguments = st.sampled_from(
    [
        {"density": 2700.0},
        {"mass": "2 kg"},
        {"density": "1 g/cm^3", "units": "mm"},
        {"mass": 1.0, "merge_tolerance": 0.0},
        {"density": 1000.0, "shell_thickness": "2 mm"},
    ]
)
damaged_arguments = st.sampled_from([("density",), ("mass",), (), ("density", "mass")]).flatmap(
    lambda given: st.fixed_dictionaries(
        dict.fromkeys(given, values()),
        optional=dict.fromkeys(("units", "merge_tolerance", "shell_thickness"), values()),
    )
)
mesh_arguments = st.integers(0, 3).flatmap(lambda k: valid_arguments if k else damaged_arguments)


@settings(max_examples=examples(0.5))
@given(
    name=st.sampled_from(sorted(MESHES)),
    file_format=st.sampled_from(MESH_FORMATS),
    data=st.data(),
)
def test_damaged_meshes_load_or_are_refused(
    folder: Path, name: str, file_format: str, data: st.DataObject
) -> None:
    """Meshes with non-finite or huge vertices, faces out of range, holes, flipped or
    degenerate triangles, in every format, with arguments as given or damaged,
    either give mass properties or are refused with a MeshError or InputError."""
    mesh = MESHES[name]
    vertices, faces = data.draw(damaged_meshes(np.asarray(mesh.vertices), np.asarray(mesh.faces)))
    path = folder / f"damaged.{SUFFIX.get(file_format, file_format)}"
    path.write_bytes(mesh_bytes(vertices, faces, file_format))
    arguments = data.draw(mesh_arguments)
    loads_or_refuses(lambda: tumble.from_mesh(path, **arguments), "mesh")


def _exported(mesh: trimesh.Trimesh, file_format: str) -> bytes:
    if file_format in MESH_FORMATS:
        return mesh_bytes(np.asarray(mesh.vertices), np.asarray(mesh.faces).tolist(), file_format)
    return bytes(mesh.export(file_type=file_format))


MESH_FILES = {
    (name, file_format): _exported(mesh, file_format)
    for name, mesh in MESHES.items()
    for file_format in (*MESH_FORMATS, "glb")
}


@settings(max_examples=examples(0.25))
@given(key=st.sampled_from(sorted(MESH_FILES)), data=st.data())
def test_corrupted_mesh_files_load_or_are_refused(
    folder: Path, key: tuple[str, str], data: st.DataObject
) -> None:
    """Mesh files (STL, OBJ, OFF, PLY, GLB) truncated or with random bytes either load
    or are refused."""
    file_format = key[1]
    path = folder / f"corrupted.{SUFFIX.get(file_format, file_format)}"
    path.write_bytes(data.draw(corrupted_bytes(MESH_FILES[key])))
    loads_or_refuses(lambda: tumble.from_mesh(path, density=2700.0, units="mm"), "mesh")


STEP = Path(__file__).parent / "data" / "bracket_with_hole.step"


# Each example reads the file in a child process (0.5 to 1 s): few of them.
@settings(max_examples=examples(0.03, fuzz_share=0.05))
@given(data=st.data())
@pytest.mark.slow  # STEP files damaged and read many times: 6 s
def test_corrupted_step_files_load_or_are_refused(folder: Path, data: st.DataObject) -> None:
    """A STEP file with bytes inserted, dropped or truncated either loads or is refused;
    OpenCASCADE crashing on it is refused too, and this process lives on."""
    path = folder / "corrupted.step"
    path.write_bytes(data.draw(corrupted_bytes(STEP.read_bytes())))
    loads_or_refuses(lambda: tumble.from_mesh(path, density=2700.0), "step")


# ------------------------------------------------------------ what fuzzing found
# Each input below once raised another exception than InputError (or gave a silent
# wrong answer); each test pins the message or the answer that replaced it.
def test_an_integer_beyond_float_range_is_refused() -> None:
    """TOML integers have no size limit; float() of one beyond 1.8e308 raised OverflowError."""
    with pytest.raises(
        InputError,
        match=r"^Expected `mass` to be within float range \(\|x\| < 1\.8e308\), got an integer "
        r"of 401 digits\.$",
    ):
        to_si(10**400, "mass", "mass")


def test_a_ragged_array_is_not_a_scalar() -> None:
    """numpy's ndim() of a ragged nesting raised ValueError."""
    with pytest.raises(
        InputError, match=r"^Expected `units` to be a scalar, got \[\[1\], \{\}, 2\]\.$"
    ):
        to_si([[1], {}, 2], "length", "units")


@pytest.mark.parametrize("units", ["{", "\b"])
def test_a_unit_pint_cannot_parse_is_refused(units: str) -> None:
    """pint's parser raised tokenize.TokenError for "{" and AssertionError for "\\b"."""
    with pytest.raises(
        InputError,
        match=rf"^Expected `units` to be a length unit such as 'mm' or 'inch', got {re.escape(repr(units))}\.$",
    ):
        length_scale(units)


SHORT = """
[scenario]
name = "short"

[body]
shape = "box"
mass = "1 kg"
size = "1, 2, 3 m"

[simulation]
duration = 5e-324
"""


def test_a_duration_too_short_to_space_its_samples_is_refused() -> None:
    """A subnormal duration divided by the samples is 0 s: the sampling divided by it."""
    with pytest.raises(
        ScenarioError,
        match=r"^short\.toml, line 11, `simulation\.duration`: Expected `duration` long enough "
        r"to space \[output\] samples = 2000 apart, got 5e-324 s \(duration / samples rounds to "
        r"0 s\)\.$",
    ):
        scenario.parse(SHORT, "short.toml")


def test_a_run_of_too_many_steps_without_dt_is_refused() -> None:
    """Without dt the step follows the fastest rotation: ω = 1e6 rad/s made 6e7 steps
    (1e9 rad/s: hours) where a scenario with dt is limited to 5e7."""
    text = scenario.builtin_text("skew-rod").replace('"0, 0, 20 rad/s"', '"0, 0, 1e6 rad/s"')
    text = text.replace('duration = "2 s"', 'duration = "2 s"\nmethod = "rk4"')
    with pytest.raises(
        ScenarioError,
        match=r"^skew-rod\.toml, line \d+, `simulation`: Expected at most 5e7 steps, got "
        r"6\.37e\+07 \(dt follows the fastest rotation when it is not given\)",
    ):
        scenario.run(scenario.parse(text, "skew-rod.toml"))


def _quaternion(**attitude: Any) -> np.ndarray:
    return np.array(Attitude(**attitude).quaternion_wxyz())


def test_attitudes_of_huge_angles_and_vectors_are_the_rotations_they_name() -> None:
    """The rotation vector θ n of an angle of 1e308 rad had an infinite length (NaN
    quaternion), and an axis or a quaternion with entries of 1e308 a norm of inf
    (the identity, silently); cos and sin of the half angle and vectors scaled
    before their norm are exact."""
    half = 0.5 * 1e308
    assert_allclose(
        _quaternion(axis=[1, 0, 0], angle=1e308), [math.cos(half), math.sin(half), 0, 0]
    )
    assert_allclose(
        _quaternion(axis=[1e308, 1e308, 0], angle=1.0), _quaternion(axis=[1, 1, 0], angle=1.0)
    )
    assert_allclose(
        _quaternion(axis=[1e-200, 0, 0], angle=1.0), _quaternion(axis=[1, 0, 0], angle=1.0)
    )
    assert_allclose(_quaternion(quaternion=[1e308, 1e308, 0, 0]), [0.5**0.5, 0.5**0.5, 0, 0])


def test_inertia_tensors_near_the_float_limit_are_checked() -> None:
    """Entries near 1.8e308: the symmetric part overflowed to inf (and was accepted,
    triangle inequality broken), eigvalsh failed to converge (LinAlgError), and
    an infinite trace made every tolerance infinite."""
    with pytest.raises(
        InputError,
        match=r"^Expected the principal moments of `inertia` to satisfy the triangle "
        r"inequality I1 \+ I2 >= I3, got I1 \+ I2 = 2 < I3 = 1\.7e\+308 kg·m²",
    ):
        tumble.MassProperties(1.0, [0, 0, 0], np.diag([1.7e308, 1.0, 1.0]))
    with pytest.raises(
        InputError,
        match=r"^Expected the principal moments of `inertia` to be >= 0, got \[-1e\+300, "
        r"1\.7e\+308, 1\.7e\+308\] kg·m²",
    ):
        tumble.MassProperties(1.0, [0, 0, 0], np.diag([1.7e308, 1.7e308, -1e300]))
    mp = tumble.MassProperties(1.0, [0, 0, 0], np.diag([1e308, 1e308, 1e308]))
    assert np.array_equal(mp.inertia, np.diag([1e308, 1e308, 1e308]))


BOX = creation.box(extents=(1.0, 1.0, 1.0))
BOX_FACES = np.asarray(BOX.faces, dtype=np.int64)


def test_a_mesh_wider_than_float_range_is_refused() -> None:
    """Corners at ±7.5e307 are finite, their distance is not: the integrals became NaN."""
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to fit in float range \(a diagonal below 1\.8e308 m\), got "
        r"vertices from \[-7\.5e\+307, -7\.5e\+307, -7\.5e\+307\] to \[7\.5e\+307, 7\.5e\+307, "
        r"7\.5e\+307\]\.$",
    ):
        mesh_mass_properties(np.asarray(BOX.vertices) * 1.5e308, BOX_FACES, density=1.0)


@pytest.mark.parametrize(("scale", "shown"), [(1e300, r"1e\+300"), (1e-300, r"1e-300")])
def test_an_inertia_beyond_float_range_is_refused(scale: float, shown: str) -> None:
    """A 1 kg mesh 1e300 m across has an inertia of 1e600 kg·m² (size**2 raised
    OverflowError), one 1e-300 m across 1e-600 (silently 0)."""
    with pytest.raises(
        InputError,
        match=r"^Expected the inertia of mesh within float range \(normal floats, 2\.2e-308 to "
        rf"1\.8e308 kg·m²\), got about 1 kg × \({shown} m\)²\.$",
    ):
        mesh_mass_properties(np.asarray(BOX.vertices) * scale, BOX_FACES, mass=1.0)


def test_a_mesh_near_the_float_limit_keeps_its_mass_properties() -> None:
    """The mean of coordinates near 1.5e308 overflowed (NaN integrals); the centre of
    the box replaces it: a cube of side a ≈ 1e300 m and 1e-300 kg, I = m a² / 6 (a
    as stored: coordinates near 1.5e308 round it by 2e-8)."""
    vertices = np.asarray(BOX.vertices) * 1e300 + 1.5e308
    side = vertices[:, 0].max() - vertices[:, 0].min()
    mp = mesh_mass_properties(vertices, BOX_FACES, mass=1e-300)
    assert_allclose(mp.center_of_mass, [1.5e308] * 3, rtol=1e-15)
    assert_allclose(np.diag(mp.inertia), [1e-300 * side * side / 6] * 3, rtol=1e-12)


def test_a_flat_mesh_whose_volume_overflows_is_refused_in_units_of_its_size() -> None:
    """A plate 1e200 m across and 1e190 m thick encloses 1e590 m³ (size**3 raised
    OverflowError in the message): the volume is given in units of the size."""
    vertices = np.asarray(BOX.vertices) * np.array([1e200, 1e200, 1e190])
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to enclose a volume, got a signed volume of 1e-10 × \(1e\+200 "
        r"m\)³ \(flat or self-cancelling\)\.$",
    ):
        mesh_mass_properties(vertices, BOX_FACES, density=1.0)


def test_holes_in_a_tiny_mesh_are_measured() -> None:
    """The diagonal of a mesh 1e-300 m across underflowed to 0 (ZeroDivisionError)."""
    with pytest.raises(
        MeshError,
        match=r"^Expected mesh to be closed \(watertight\), got 3 boundary edges \(edges of "
        r"only one triangle, 3\.41e-300 m long in all, 2 of the mesh's diagonal\)",
    ):
        mesh_mass_properties(np.asarray(BOX.vertices) * 1e-300, BOX_FACES[:-1], density=1.0)


def test_a_step_reader_that_crashes_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """OpenCASCADE ended the process with a segmentation fault on a STEP file with
    bytes inserted in an entity's name; it now reads in a child process. The
    crash is simulated: whether a damaged file crashes depends on its version."""
    monkeypatch.setattr(
        step, "_CONVERSION", "import signal\nos.kill(os.getpid(), signal.SIGSEGV)\n"
    )
    path = tmp_path / "part.step"
    path.write_bytes(STEP.read_bytes())
    with pytest.raises(
        InputError,
        match=r"^Expected `mesh` to be a readable STEP file, got '.*part\.step': OpenCASCADE "
        r"crashed reading it \(signal 11\)\.$",
    ):
        tumble.from_mesh(path, density=2700.0)


def test_a_step_file_with_bytes_in_an_entity_name_is_refused(tmp_path: Path) -> None:
    """The file that crashed OpenCASCADE 7.8 (cascadio 0.1.1): refused, whether the
    reader crashes on it or not."""
    data = STEP.read_bytes()
    path = tmp_path / "damaged.step"
    path.write_bytes(data[:21460] + b"\x8e\xff\xb5\xe8\xec\xb3\xe9\xf9" + data[21460:])
    with pytest.raises(InputError, match=r"^Expected `mesh` to be a readable STEP file"):
        tumble.from_mesh(path, density=2700.0)


SWEEP = SWEEPS.text("flip-map")


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'dt = "5 ms"',
            "dt = 5e-324",
            r"`base\.dt`: Expected at most 2\*\*53 steps per body \(duration / dt\), got inf "
            r"from duration = 40\.0 s and dt = 5e-324 s\.$",
        ),
        (
            "samples = 1 ",
            "samples = 1180591620717411 ",
            r"`sweep\.samples`: Expected at most 2\*\*53 bodies \(grid points × samples\), got "
            r"3\.87e\+19\.$",
        ),
    ],
)
def test_sweeps_beyond_exact_counts_are_refused(old: str, new: str, message: str) -> None:
    """duration / dt of inf raised OverflowError (math.ceil); 4e19 bodies raised it in
    numpy's int64 body indices."""
    assert old in SWEEP
    with pytest.raises(SweepError, match=r"^sweep\.toml, line \d+, " + message):
        parse_sweep(SWEEP.replace(old, new), "sweep.toml")


def test_a_key_with_a_line_break_is_shown_on_one_line() -> None:
    """TOML's quoted keys may hold line breaks; messages named them as written."""
    text = '"a\\nb" = 1\n' + SWEEP
    with pytest.raises(SweepError) as caught:
        parse_sweep(text, "sweep.toml")
    assert str(caught.value) == (
        "sweep.toml, `a\\nb`: Expected the key to be one of sweep, base, vary, internal, "
        "outputs, report, dask, limits, got 'a\\nb'."
    )


# ------------------------------------------------------------ float limits
# Inputs the fuzz tests found at float64's limits, each a built-in scenario with one
# value changed, and what it gives: None when it runs, else the end of the refusal.
# Each once raised another exception (OverflowError, ZeroDivisionError, scipy's
# "zero norm quaternions" from NaN samples).
PHASE_LOST = (
    "where a turn is below float64's round-off: ask for a shorter duration or slower rates."
)
LIMIT_INPUTS = {
    "a 1e300 kg body, exactly": ("tennis-racket", 'mass = "0.5 kg"', "mass = 1e300", None),
    "a dual spin at 1.8e308 rad/s, exactly": (
        "dual-spin",
        'omega = "1e-4, 0.5, 0 rad/s"',
        'omega = "1.7976931348623157e+308, 0.5, 0 rad/s"',
        "got about inf rad (its rates times t = 300 s), " + PHASE_LOST,
    ),
    "a rotor at 1e102 rad/s, exactly": (
        "dual-spin",
        'speed = "100 rpm"',
        "speed = -1e102",
        "got about 5.25e+102 rad (its rates times t = 300 s), " + PHASE_LOST,
    ),
    "a top of 1e308 kg": ("gyroscope", 'mass = "1 kg"', "mass = 1e308", None),
    "a top of 1e-300 kg": ("gyroscope", 'mass = "1 kg"', "mass = 1e-300", None),
    "a rotor of 1.8e306 m radius": (
        "dual-spin",
        'radius = "30 cm"',
        'radius = "1.7976931348623157e+308 cm"',
        "`internal[0]`: Expected a rotor whose moment of inertia 0.5 m r² is within float64's "
        "range, got m = 20 kg and r = 1.79769e+306 m.",
    ),
    "a gravity of 1.8e308 m/s^2": (
        "gyroscope",
        'gravity = "0, 0, -9.81 m/s^2"',
        'gravity = "1.7976931348623157e+308, 0, -9.81 m/s^2"',
        "Expected the closed-form motion to stay finite, got NaN or inf at t = 0 s (sample 0): "
        "its momentum or energy is beyond float64's range, or t is too long to keep its "
        "phase; use SI values of an ordinary size or a shorter duration.",
    ),
    "a reversed orbit": (
        "gravity-gradient",
        "orbit_normal = [0, 0, 1]",
        "orbit_normal = [0, 0, -1]",
        None,
    ),
}


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # the overflows on the way
@pytest.mark.parametrize(
    ("name", "old", "new", "refusal"),
    [pytest.param(*case, id=label) for label, case in LIMIT_INPUTS.items()],
)
def test_values_at_the_float_limits_run_or_are_refused(
    name: str, old: str, new: str, refusal: str | None
) -> None:
    """Each runs to its report's rows, or is refused with a one-line InputError."""
    text = scenario.builtin_text(name)
    assert old in text
    text = text.replace(old, new).replace("[output]", "[output]\nfigures = false\nviewer = false")
    if refusal is None:
        loaded = scenario.parse(text, f"{name}.toml", SCENARIOS.folder())
        result = scenario.run(loaded)
        assert result.runs and all(np.isfinite(run.omega).all() for run in result.runs.values())
    else:
        # Refused when the file is read (a part's values are checked together as
        # the file is validated) or when it runs.
        with pytest.raises(InputError) as caught:
            scenario.run(scenario.parse(text, f"{name}.toml", SCENARIOS.folder()))
        check_message(str(caught.value))
        assert str(caught.value).endswith(refusal)
