"""
The command line and scenario files
===================================

The ``tumble`` command runs whole simulations from TOML scenario files and writes
a run folder with the trajectory, a comparison with theory and a report; it also
computes mass properties and runs sweeps. This page writes a small scenario, runs
it, reads what it wrote, and shows what a mistake in a file looks like.

The commands, in a shell:

.. code-block:: console

   $ tumble list                          # the built-in scenarios and sweeps
   $ tumble show heavy-top > top.toml     # a built-in scenario as TOML, to edit
   $ tumble run top.toml -o runs/top      # simulate, compare with theory, write a folder
   $ tumble run top.toml -o runs/top --force --no-figures --no-viewer --quiet
   $ tumble run top.toml --json           # the summary as JSON on stdout
   $ tumble inertia solid-cone --mass "250 g" --radius "3 cm" --height "8 cm"
   $ tumble sweep flip-map -o flip-map    # many bodies into a Zarr store
   $ tumble warm-up --all                 # compile every built-in scenario's kernels
   $ tumble --debug run top.toml          # a traceback instead of the one-line error

:doc:`/reference/cli` lists every option of every command, and
:doc:`/reference/scenario-keys` every key of a scenario file.
"""

# %%
# Running the command from Python
# -------------------------------
#
# ``python -m tumble`` is the ``tumble`` command installed with the package. This
# page runs it in a child process with the same Python, as a shell would run
# ``tumble``:

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ENTRY = [sys.executable, "-m", "tumble"]
workdir = tempfile.TemporaryDirectory()  # removed when the page is done
folder = Path(workdir.name)


def tumble(*arguments, expect=0):
    """Run ``tumble ARGUMENTS`` in ``folder``; print its output and its exit code,
    which must be ``expect``."""
    done = subprocess.run(
        [*ENTRY, *arguments], cwd=folder, capture_output=True, text=True,
        env={**os.environ, "COLUMNS": "100"},  # the width of its tables
    )  # fmt: skip
    print(done.stdout + done.stderr, end="")
    print(f"[exit code {done.returncode}]")
    assert done.returncode == expect


tumble("list")

# %%
# ``tumble show NAME`` prints a built-in scenario, a complete file to start from:

shown = subprocess.run([*ENTRY, "show", "heavy-top"], capture_output=True, text=True, check=True)
print("\n".join(shown.stdout.splitlines()[:24]))

# %%
# A scenario file
# ---------------
#
# A toy top built from two parts: a brass disk on a steel axle, spun at 3000 rpm on
# the axle's lower tip and released 20° from the vertical. Every value takes units
# as a string; plain numbers are SI.

SCENARIO = """\
[scenario]
name = "toy-top"
title = "A toy top: a brass disk on a steel axle, spinning on its tip"

[[body.parts]]
shape = "solid-cylinder"       # the disk: symmetry axis along z
mass = "60 g"
radius = "2.5 cm"
height = "4 mm"
translation = "0, 0, 1 cm"     # its pose in the assembly

[[body.parts]]
shape = "solid-cylinder"       # the axle, 6 cm long, centred on the origin
mass = "8 g"
radius = "1.5 mm"
height = "6 cm"

[initial]
omega = "0, 0, 3000 rpm"                   # body axes
attitude = { euler_zxz = "0, 20, 0 deg" }  # precession, nutation, spin

[environment]
pivot = "0, 0, -3 cm"          # the axle's lower tip, held fixed
gravity = "0, 0, -9.81 m/s^2"  # space axes, z up

[simulation]
duration = "2 s"               # dt and method are optional (method = "auto")

[theory]
model = "gyroscope"            # compare with the heavy symmetric top
"""
(folder / "toy-top.toml").write_text(SCENARIO, encoding="utf-8")
print(f"toy-top.toml: {len(SCENARIO.splitlines())} lines")

# %%
# Run it
# ------
#
# ``-o`` names the run folder (default ``runs/NAME-YYYYmmdd-HHMMSS``);
# ``--no-figures`` and ``--no-viewer`` skip the PNG figures and the 3D viewer, for a
# faster run. The table compares each quantity of the theory with the simulation:
# the exact closed forms agree to the printed relative errors, while the classic
# approximations (the steady and fast-top formulas) show how far off they are for
# this top.

tumble("run", "toy-top.toml", "-o", "toy-top", "--no-figures", "--no-viewer")
print(sorted(path.name for path in (folder / "toy-top").iterdir()))

# %%
# The folder holds ``trajectory.parquet`` (the samples, read with any Parquet
# reader), ``summary.json`` (the same comparison and the drift of the conserved
# quantities, as numbers) and ``report.html`` (one self-contained page). Without
# ``--no-figures`` and ``--no-viewer`` it also holds the PNG figures and
# ``viewer.html``.

summary = json.loads((folder / "toy-top" / "summary.json").read_text())
print(summary["method"], "—", summary["reason"])
for row in summary["comparisons"]:
    if "exact" in row["quantity"]:
        print(f"{row['quantity']:32} relative error {row['relative_error']:.1e}")
        # The exact closed form against the exact solution, sampled every dt:
        # the measurements from samples limit the agreement, not the theory.
        assert row["relative_error"] < 1e-6

# %%
# Errors
# ------
#
# Every mistake is one line on stderr naming the file, the line, the key and what
# was expected, and the exit code is 2. A typo in a key:

(folder / "typo.toml").write_text(SCENARIO.replace("radius =", "raduis =", 1), encoding="utf-8")
tumble("run", "typo.toml", "-o", "typo", "--no-figures", "--no-viewer", expect=2)

# %%
# A value in the wrong units:

(folder / "units.toml").write_text(SCENARIO.replace('"2 s"', '"2 kg"'), encoding="utf-8")
tumble("run", "units.toml", "-o", "units", "--no-figures", "--no-viewer", expect=2)

# %%
# A run folder that already holds files is refused before anything is simulated,
# unless ``--force`` (which replaces an earlier run folder, never a folder of other
# files):

tumble("run", "toy-top.toml", "-o", "toy-top", "--no-figures", "--no-viewer", expect=2)

# %%
# One command writes a folder at a time: a second ``tumble run``, ``fit`` or
# ``sweep`` into a folder that another is writing is refused at once, with the pid,
# host and start of the first (``error: Expected the run folder 'toy-top' to be free
# to write, got one being written by pid 4242 on lab-pc since 2026-05-09 14:02:11
# +0200: wait for it to end, or write elsewhere.``). What a killed command left
# half-written (a ``.NAME.XXXXXXXX.tumble.partial`` folder beside its output) is removed
# by the next one.

# %%
# ``tumble --debug ...`` shows the full traceback instead of the one line, for
# reporting a problem; its last line is the same message:

debug = subprocess.run(
    [*ENTRY, "--debug", "run", "typo.toml", "-o", "typo", "--no-figures", "--no-viewer"],
    cwd=folder, capture_output=True, text=True,
)  # fmt: skip
print(f"{len(debug.stderr.splitlines())} lines, ending with:")
print(debug.stderr.strip().splitlines()[-1])

# %%
# Mass properties and sweeps
# --------------------------
#
# ``tumble inertia`` prints the mass, the centre of mass, the inertia tensor and the
# principal axes of a solid (with its dimensions as options) or of a mesh file
# (with ``--units`` and ``--density`` or ``--mass``):

tumble("inertia", "solid-cylinder", "--mass", "60 g", "--radius", "2.5 cm",
                 "--height", "4 mm", "--about", "0, 0, -4 cm")  # fmt: skip

# %%
# ``tumble sweep FILE.toml -o DIR`` runs a sweep file (``--workers N`` on a local Dask
# cluster, ``--scheduler tcp://HOST:PORT`` on an existing one) into a Zarr store,
# with ``summary.json`` and a ``report.html`` of maps. The same ``--json``,
# ``--quiet`` and ``--force`` apply.
