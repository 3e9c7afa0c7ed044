"""``tumble inertia``: the mass properties of a solid or a mesh file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from tumble.cli.app import app, run_command

if TYPE_CHECKING:
    from tumble.massprops import MassProperties

__all__ = ["inertia"]

MESH_SUFFIXES = {".stl", ".obj", ".ply", ".glb", ".gltf", ".off"}

#: Robot descriptions: URDF and MJCF (tumble.robots).
ROBOT_SUFFIXES = {".urdf", ".xacro", ".xml"}


# Options shared by the shapes; each maps to the shape function's parameter of the same name.
_SHAPE_OPTIONS = (
    "radius",
    "inner_radius",
    "outer_radius",
    "height",
    "length",
    "size",
    "semi_axes",
    "major_radius",
    "minor_radius",
    "cylinder_height",
    "edge",
)


@app.command()
def inertia(
    body: Annotated[
        str,
        typer.Argument(
            metavar="SHAPE-or-MESH",
            help="A solid (box, solid-cylinder, hollow-cylinder, solid-sphere, spherical-shell, "
            "hollow-sphere, solid-cone, thin-rod, thin-disk, thin-ring, ellipsoid, torus, capsule, "
            "regular-tetrahedron) or a mesh file (STL, OBJ, PLY, GLB, STEP).",
        ),
    ],
    mass: Annotated[str | None, typer.Option(help="Mass, e.g. '250 g' (SI if no unit).")] = None,
    density: Annotated[
        str | None, typer.Option(help="Density of a mesh, e.g. '2700 kg/m^3'.")
    ] = None,
    units: Annotated[
        str | None, typer.Option(help="Length unit of a mesh file, e.g. 'mm'.")
    ] = None,
    merge_tolerance: Annotated[
        str | None,
        typer.Option(
            help="Mesh: weld seam vertices closer than this, e.g. '0.001 mm' (default 1e-9 "
            "of the diagonal; 0: none)."
        ),
    ] = None,
    shell_thickness: Annotated[
        str | None,
        typer.Option(help="Mesh: its surface as a thin shell of this wall, e.g. '2 mm'."),
    ] = None,
    radius: Annotated[str | None, typer.Option(help="Radius, e.g. '3 cm'.")] = None,
    inner_radius: Annotated[str | None, typer.Option(help="Inner radius.")] = None,
    outer_radius: Annotated[str | None, typer.Option(help="Outer radius.")] = None,
    height: Annotated[str | None, typer.Option(help="Height along the axis (z).")] = None,
    length: Annotated[str | None, typer.Option(help="Length of a thin rod.")] = None,
    size: Annotated[
        str | None, typer.Option(help="Box edges along x, y, z, e.g. '10, 20, 30 cm'.")
    ] = None,
    semi_axes: Annotated[
        str | None, typer.Option(help="Ellipsoid semi-axes, e.g. '1, 2, 3 cm'.")
    ] = None,
    major_radius: Annotated[
        str | None, typer.Option(help="Torus: radius of the tube's centre circle.")
    ] = None,
    minor_radius: Annotated[str | None, typer.Option(help="Torus: radius of the tube.")] = None,
    cylinder_height: Annotated[
        str | None, typer.Option(help="Capsule: height of the cylindrical part.")
    ] = None,
    edge: Annotated[str | None, typer.Option(help="Edge of a regular tetrahedron.")] = None,
    about: Annotated[
        str | None,
        typer.Option(help="Also give the inertia about this body point, e.g. '0, 0, -5 cm'."),
    ] = None,
    joints: Annotated[
        list[str] | None,
        typer.Option(
            "--joints",
            metavar="NAME=VALUE",
            help="A robot file: a joint's value, e.g. 'elbow=30 deg' (rad or m if no unit); "
            "repeat for more; joints not given are at 0.",
            show_default=False,
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Mass, centre of mass, inertia tensor, principal moments and axes of a solid, a mesh,
    or a whole robot (URDF or MJCF) at a joint configuration."""
    options = {
        "radius": radius,
        "inner_radius": inner_radius,
        "outer_radius": outer_radius,
        "height": height,
        "length": length,
        "size": size,
        "semi_axes": semi_axes,
        "major_radius": major_radius,
        "minor_radius": minor_radius,
        "cylinder_height": cylinder_height,
        "edge": edge,
    }
    given = {k: v for k, v in options.items() if v is not None}

    def work() -> None:
        from tumble.errors import InputError
        from tumble.units import vector_to_si

        mesh_options = {"merge_tolerance": merge_tolerance, "shell_thickness": shell_thickness}
        if Path(body).suffix.lower() in ROBOT_SUFFIXES:
            given_options = {**given, **{k: v for k, v in mesh_options.items() if v}}
            given_options |= {
                k: v for k, v in (("mass", mass), ("density", density), ("units", units)) if v
            }
            label, mp = _robot_body(body, joints or [], given_options)
        elif joints:
            raise InputError(
                f"Expected --joints only with a robot file (.urdf, .xacro, .xml), got {body!r}."
            )
        else:
            label, mp = _build_body(
                body,
                mass=mass,
                density=density,
                units=units,
                dimensions=given,
                mesh_options={k: v for k, v in mesh_options.items() if v is not None},
            )
        point = vector_to_si(about, "length", "--about") if about is not None else None
        if as_json:
            typer.echo(json.dumps(_inertia_json(label, mp, point), indent=2))
        else:
            _print_inertia(label, mp, point)

    run_command(work)


def _robot_body(
    body: str, joints: list[str], options: dict[str, Any]
) -> tuple[str, MassProperties]:
    """A robot file's mass properties at the ``--joints`` given (NAME=VALUE)."""
    from tumble.errors import InputError
    from tumble.robots import load

    extra = [name for name, value in options.items() if value is not None]
    if extra:
        raise InputError(
            f"Expected no {_option(extra[0])} for a robot file, got one: its links "
            "declare their masses."
        )
    values: dict[str, str] = {}
    for item in joints:
        name, sign, value = item.partition("=")
        if not sign or not name.strip():
            raise InputError(f"Expected --joints NAME=VALUE, e.g. 'elbow=30 deg', got {item!r}.")
        if name.strip() in values:  # the last one would win, silently
            raise InputError(
                f"Expected each joint once in --joints, got {name.strip()!r} twice: "
                f"{values[name.strip()]!r} and {value.strip()!r}."
            )
        values[name.strip()] = value.strip()
    robot = load(body)
    return f"{body} (robot {robot.name!r}, root link {robot.root!r})", robot.mass_properties(values)


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


def _build_body(
    body: str,
    *,
    mass: str | None,
    density: str | None,
    units: str | None,
    dimensions: dict[str, str],
    mesh_options: dict[str, str] | None = None,
) -> tuple[str, MassProperties]:
    from tumble.errors import InputError
    from tumble.shapes import SHAPE_KINDS

    shape_name = body.strip().lower().replace("_", "-")
    if shape_name in SHAPE_KINDS:
        kind = SHAPE_KINDS[shape_name]
        accepted = ", ".join(_option(p) for p in ["mass", *kind.dimensions])
        extra = [p for p in dimensions if p not in kind.dimensions]
        if density is not None or units is not None:
            extra += ["density"] if density is not None else []
            extra += ["units"] if units is not None else []
        extra += list(mesh_options or {})
        if extra:
            raise InputError(f"Expected only {accepted} for {shape_name}, got {_option(extra[0])}.")
        missing = [
            p
            for p in ["mass", *kind.dimensions]
            if (p == "mass" and mass is None) or (p != "mass" and p not in dimensions)
        ]
        if missing:
            raise InputError(
                f"Expected {_option(missing[0])} for {shape_name} (it takes {accepted})."
            )
        return shape_name, kind.function(mass, **dimensions)
    from tumble.errors import unknown_choice
    from tumble.mesh.step import STEP_SUFFIXES

    path = Path(body)
    try:
        exists = path.exists()
    except OSError:  # a name too long for the system: not a file, and not a shape
        exists = False
    if path.suffix.lower() in (*MESH_SUFFIXES, *STEP_SUFFIXES) or exists:
        from tumble.mesh import from_mesh  # numba and trimesh: only for meshes

        if dimensions:
            raise InputError(
                f"Expected --density or --mass (and --units) for a mesh, "
                f"got {_option(next(iter(dimensions)))}."
            )
        return str(path), from_mesh(
            path, density=density, mass=mass, units=units, **(mesh_options or {})
        )
    raise unknown_choice(body, list(SHAPE_KINDS), "a shape", alternative="a mesh file")


def _inertia_json(label: str, mp: MassProperties, point: Any) -> dict[str, Any]:
    moments, axes = mp.principal()
    result: dict[str, Any] = {
        "body": label,
        "mass": mp.mass,
        "center_of_mass": mp.center_of_mass.tolist(),
        "inertia": mp.inertia.tolist(),
        "principal_moments": moments.tolist(),
        "principal_axes": axes.tolist(),
        "units": {"mass": "kg", "length": "m", "inertia": "kg*m^2"},
        "conventions": "inertia about the centre of mass in body axes; I_xy = -sum(m x y); "
        "principal axes are the columns of principal_axes (det +1)",
    }
    if point is not None:
        result["about"] = {"point": point.tolist(), "inertia": mp.inertia_about(point).tolist()}
    return result


def _print_inertia(label: str, mp: MassProperties, point: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    moments, axes = mp.principal()

    console.print(f"[bold]Mass properties of {label}[/bold]", highlight=False)
    summary = Table(show_header=False)
    summary.add_column("quantity", style="bold")
    summary.add_column("value", justify="right")
    summary.add_column("unit")
    summary.add_row("mass", f"{mp.mass:.6g}", "kg")
    summary.add_row("centre of mass", _vector_text(mp.center_of_mass), "m (body coordinates)")
    console.print(summary)

    def tensor_table(title: str, tensor: Any) -> Table:
        scale = float(abs(tensor).max())
        console.print(f"[bold]{title}[/bold]", highlight=False)
        table = Table()
        table.add_column("")
        for axis in "xyz":
            table.add_column(axis, justify="right")
        for name, row in zip("xyz", tensor, strict=True):
            table.add_row(name, *(f"{_clean(v, scale):.6g}" for v in row))
        return table

    console.print(
        tensor_table("Inertia tensor about the centre of mass, body axes (kg·m²)", mp.inertia)
    )
    if point is not None:
        console.print(
            tensor_table(
                f"Inertia tensor about the point {_vector_text(point)} m (kg·m²)",
                mp.inertia_about(point),
            )
        )
    console.print("[bold]Principal moments (kg·m²) and axes (columns, body coordinates)[/bold]")
    principal = Table()
    principal.add_column("")
    for k in range(3):
        principal.add_column(f"I{k + 1}", justify="right")
    principal.add_row("moment", *(f"{v:.6g}" for v in moments), style="bold")
    for name, row in zip("xyz", axes, strict=True):
        principal.add_row(f"axis {name}", *(f"{_clean(v):.6f}" for v in row))
    console.print(principal)
    console.print("Products of inertia carry the minus sign: I_xy = −Σ m x y.", style="dim")


def _clean(value: float, scale: float = 1.0) -> float:
    """Show round-off (below 1e-12 of the scale) as 0 rather than as -1e-19."""
    return 0.0 if abs(value) <= 1e-12 * scale else float(value)


def _vector_text(vector: Any) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in vector) + "]"
