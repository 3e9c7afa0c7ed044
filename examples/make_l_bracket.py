"""Write ``l_bracket.stl``: an L-shaped aluminium bracket in millimetres.

The profile, in the body xy plane, is a 60 mm leg along x and a 40 mm leg
along y, both 8 mm thick; it is extruded 30 mm along z. Its products of
inertia are not zero (it has no symmetry plane through x or y), which makes it
a good first look at the minus sign of ``I_xy = −Σ m x y``::

    tumble inertia examples/l_bracket.stl --units mm --density "2700 kg/m^3"

The mesh is built by hand (12 vertices, 20 triangles, outward normals) so the
file is small and readable; run this script to write it again.
"""

from pathlib import Path

import numpy as np
import trimesh

PROFILE_MM = [(0, 0), (60, 0), (60, 8), (8, 8), (8, 40), (0, 40)]  # counter-clockwise
DEPTH_MM = 30.0


def l_bracket() -> trimesh.Trimesh:
    """The bracket as a closed, outward-wound triangle mesh (coordinates in mm)."""
    n = len(PROFILE_MM)
    bottom = [(x, y, 0.0) for x, y in PROFILE_MM]
    top = [(x, y, DEPTH_MM) for x, y in PROFILE_MM]
    vertices = np.array(bottom + top, dtype=float)
    faces = []
    # The profile is star-shaped from its corner vertex 0, so a fan covers it.
    for k in range(1, n - 1):
        faces.append((0, k + 1, k))  # bottom cap, seen from -z
        faces.append((n, n + k, n + k + 1))  # top cap, seen from +z
    for k in range(n):
        j = (k + 1) % n
        faces.append((k, j, n + j))
        faces.append((k, n + j, n + k))
    return trimesh.Trimesh(vertices, np.array(faces), process=False)


if __name__ == "__main__":
    path = Path(__file__).with_name("l_bracket.stl")
    mesh = l_bracket()
    assert mesh.is_watertight and mesh.volume > 0
    path.write_bytes(trimesh.exchange.stl.export_stl_ascii(mesh).encode())
    print(f"wrote {path} ({len(mesh.faces)} triangles, volume {mesh.volume:.0f} mm³)")
