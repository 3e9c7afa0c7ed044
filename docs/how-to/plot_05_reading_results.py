"""
Reading results in pandas, polars, xarray and DuckDB
====================================================

tumble writes trajectories as Parquet files: one row per sample, SI units, and a
description of the run in the file's metadata. ``Trajectory.to_parquet`` writes
one, ``tumble run`` writes one into every run folder (``trajectory.parquet``),
and any tool that reads Parquet reads them. Here a heavy top is simulated and
saved, a run folder is written by the command line, and both are read back with
pandas, polars, xarray and DuckDB.
"""

# %%
# Simulate and save
# -----------------
#
# A 1 kg disk (radius 10 cm) on a pivot 10 cm along its axis, spinning at 50 rad/s,
# released at rest with its axis 60° from the vertical: a heavy symmetric top, which
# nods (nutates) between a tilt of 60° and a larger one while it precesses.

import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import duckdb
import numpy as np
import pandas as pd
import polars as pl
import pyarrow.parquet as pq
import xarray as xr

import tumble as tb

pd.set_option("display.width", 120)
pd.set_option("display.max_columns", 12)
pd.set_option("display.precision", 5)
workdir = tempfile.TemporaryDirectory()  # removed when the page is done
folder = Path(workdir.name)

disk = tb.shapes.solid_cylinder("1 kg", radius="10 cm", height="1 cm")
tilt0 = math.radians(60)
top = tb.simulate(
    disk, [0, 0, "50 rad/s"], attitude0=[math.cos(tilt0 / 2), math.sin(tilt0 / 2), 0, 0],
    duration=2.0, dt=1e-3, pivot=[0, 0, -0.1], gravity=[0, 0, -9.81],
)  # fmt: skip
path = folder / "top.parquet"
top.to_parquet(path)
print(top)

# %%
# The columns are ``t`` (s), ``omega_x``, ``omega_y``, ``omega_z`` (rad/s, body
# axes) and the attitude quaternion ``q_w``, ``q_x``, ``q_y``, ``q_z`` (body →
# space, scalar first); a body carrying rotors or dampers adds a column for each of
# their values, and torques with a potential energy (gravity about a pivot) add
# ``potential_energy`` (J). The file's key-value metadata ``tumble`` holds the
# body, the pivot, the torque models (``torques``: each one's ``type`` and SI
# values; ``gravity`` is their total uniform gravity), the method and what the
# motion conserves, as JSON:

meta = json.loads(pq.read_schema(path).metadata[b"tumble"])
print({key: meta[key] for key in ("mass", "pivot", "torques", "method", "dt", "conserved")})

# %%
# ``tb.Trajectory.read_parquet`` reads the file back into a whole
# :class:`tumble.Trajectory`, with its energy, angular momentum and drift:

again = tb.Trajectory.read_parquet(path)
print(f"{len(again.t)} samples, drift {again.drift}")

# %%
# pandas
# ------
#
# The tilt of the symmetry axis (body z) from the vertical is the nutation angle
# :math:`\theta`; from the quaternion, :math:`\cos\theta = R_{zz} = 1 - 2(q_x^2 + q_y^2)`.

frame = pd.read_parquet(path)
frame["tilt_deg"] = np.degrees(np.arccos(1 - 2 * (frame.q_x**2 + frame.q_y**2)))
print(frame.head())
print(frame.tilt_deg.describe())

# %%
# polars
# ------

lazy = pl.scan_parquet(path).with_columns(
    (1 - 2 * (pl.col("q_x") ** 2 + pl.col("q_y") ** 2)).arccos().degrees().alias("tilt_deg")
)
print(lazy.filter(pl.col("t") <= 0.5).select("t", "omega_z", "tilt_deg").collect().tail(3))
extremes = [pl.col("tilt_deg").min().alias("smallest"), pl.col("tilt_deg").max().alias("largest")]
print(lazy.select(extremes).collect())

# %%
# xarray
# ------
#
# Vectors become one variable with a dimension for their components, indexed by
# time, so that selection and interpolation read naturally:

dataset = xr.Dataset(
    {
        "omega": (("t", "axis"), frame[["omega_x", "omega_y", "omega_z"]].to_numpy()),
        "quaternion": (("t", "component"), frame[["q_w", "q_x", "q_y", "q_z"]].to_numpy()),
        "tilt": ("t", frame.tilt_deg.to_numpy()),
    },
    coords={"t": frame.t.to_numpy(), "axis": ["x", "y", "z"], "component": list("wxyz")},
)
dataset.t.attrs["units"], dataset.omega.attrs["units"], dataset.tilt.attrs["units"] = (
    "s", "rad/s", "deg",
)  # fmt: skip
print(dataset)
print(dataset.omega.sel(axis="x").interp(t=[0.1, 0.2, 0.3]).values)

# %%
# DuckDB
# ------
#
# DuckDB queries the Parquet file in place with SQL. The turning points of the
# nutation:

query = f"""
    SELECT min(degrees(acos(1 - 2 * (q_x * q_x + q_y * q_y)))) AS smallest_deg,
           max(degrees(acos(1 - 2 * (q_x * q_x + q_y * q_y)))) AS largest_deg
    FROM read_parquet('{path}')
"""
smallest, largest = duckdb.sql(query).fetchall()[0]
print(f"the axis nods between {smallest:.4f}° and {largest:.4f}° from the vertical")

# %%
# The exact turning points of a heavy symmetric top released at rest
# (:func:`tumble.theory.gyroscope`; Goldstein, *Classical Mechanics* §5.7):

theory = tb.theory.gyroscope(disk, pivot=[0, 0, -0.1], spin_rate="50 rad/s", tilt="60 deg")
print("theory:", np.degrees(theory.nutation_limits), "deg")
# Samples every 1 ms over a nutation period of the printed length: the sampled
# extremes miss the true ones by at most about 1e-3°.
print(f"nutation period {theory.nutation_period:.4f} s")
assert np.allclose([smallest, largest], np.degrees(theory.nutation_limits), atol=1e-3)

# %%
# A run folder
# ------------
#
# ``tumble run`` writes ``trajectory.parquet`` (the same columns; its metadata also
# holds the scenario) and ``summary.json`` (the comparison with theory and the
# drift) into a run folder. Here the built-in ``gyroscope`` scenario, without the
# figures and the 3D viewer (``python -m tumble`` is the ``tumble`` command):

run_folder = folder / "gyroscope"
subprocess.run(
    [sys.executable, "-m", "tumble", "run", "gyroscope", "-o", str(run_folder),
     "--no-figures", "--no-viewer", "--quiet"],
    check=True,
)  # fmt: skip
print(sorted(p.name for p in run_folder.iterdir()))

summary = json.loads((run_folder / "summary.json").read_text())
comparisons = pd.DataFrame(summary["comparisons"])
print(comparisons[["quantity", "theory", "measured", "relative_error", "unit"]].head())

# %%
# DuckDB reads several files in one query; ``filename = true`` says which row came
# from which:

print(
    duckdb.sql(f"""
        SELECT parse_filename(filename) AS file, count(*) AS samples, max(t) AS seconds,
               max(degrees(acos(1 - 2 * (q_x * q_x + q_y * q_y)))) AS largest_tilt_deg
        FROM read_parquet(['{path}', '{run_folder / "trajectory.parquet"}'], filename = true)
        GROUP BY file ORDER BY file
    """)
)
