"""STEP files, tessellated by OpenCASCADE (through cascadio) in a child process.

OpenCASCADE's STEP reader can end the process that calls it with a
segmentation fault on a damaged file (a few bytes inserted into an entity's
name are enough). Run in a child process, such a crash ends the child only and
becomes an :class:`~tumble.InputError` that names the file. The messages
OpenCASCADE prints on the standard output stay out of the user's terminal too.
The child writes a GLB file (in metres), which trimesh reads as it would have
read the STEP file.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tumble.errors import InputError

__all__ = ["STEP_SUFFIXES", "tessellate_step"]

#: The file name endings read as STEP.
STEP_SUFFIXES = (".step", ".stp")

# Exit codes of the child besides 0 (done): cascadio missing, the reader refused the file.
_MISSING, _REFUSED = 3, 4

_CHILD = f"""
import sys
try:
    import cascadio
except ImportError as exc:
    sys.stderr.write(str(exc))
    sys.exit({_MISSING})
status = cascadio.step_to_glb(sys.argv[1], sys.argv[2], merge_primitives=True)
sys.exit(0 if status == 0 else {_REFUSED})
"""


def tessellate_step(step: Path, glb: Path) -> None:
    """Write the triangles of the STEP file ``step`` to the GLB file ``glb``.

    Raises
    ------
    InputError
        cascadio is not installed, OpenCASCADE cannot read the file, or it
        crashed reading it.
    """
    done = subprocess.run(
        [sys.executable, "-c", _CHILD, str(step), str(glb)],
        capture_output=True,
        text=True,
        errors="replace",
        check=False,
    )
    if done.returncode == 0 and glb.is_file():
        return
    if done.returncode == _MISSING:
        raise InputError(
            f"Reading {str(step)!r} needs a package that is not installed: {done.stderr.strip()}."
        )
    if done.returncode in (0, _REFUSED):
        why = "OpenCASCADE could not read it"
    elif done.returncode < 0:
        why = f"OpenCASCADE crashed reading it (signal {-done.returncode})"
    else:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        why = f"OpenCASCADE failed reading it (exit code {done.returncode}: {last})"
    raise InputError(f"Expected `mesh` to be a readable STEP file, got {str(step)!r}: {why}.")
