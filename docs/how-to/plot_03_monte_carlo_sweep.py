"""
A Monte-Carlo sweep on all cores and on a Dask cluster
======================================================

A sweep runs thousands to millions of torque-free (or simply forced) bodies from
one TOML file: a base that every body shares, and the parameters to vary, on grids
or drawn at random. Each body is stepped by the batched compiled kernels and
measured as it goes (flips, time of the first flip, largest nutation, energy and
:math:`|\\mathbf L|` drift); the results go to a Zarr store, chunked by bodies.

Here: the intermediate-axis flip mapped over the middle moment and the size of the
initial perturbation, run in this process on all cores, read back and drawn, checked
against the closed form, then run again on a Dask cluster.
"""

# %%
# The sweep file
# --------------
#
# A body with principal moments :math:`I_1 = 1` kg·m², :math:`I_2 = r I_1` and
# :math:`I_3 = 2 I_1` spins at 1 turn/s about its intermediate axis 2, with ω tilted
# from that axis by a small angle (``perturbation``) towards axis 3
# (``perturbation_azimuth = 0``). The grid: 60 values of :math:`r = I_2 / I_1` times
# 60 perturbations from 0.01° to 10° on a log scale, 3600 bodies, each stepped
# 2000 times by RK4. The built-in ``flip-map`` sweep is the same map at full size
# (``tumble show flip-map`` prints it). Numbers are SI; strings carry their units.

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import tumble as tb
from tumble.sweep import open_results, run_sweep

SWEEP = """
[sweep]
name = "small-flip-map"
description = "Time of the first flip over I2/I1 and the perturbation angle"
seed = 1
chunk_size = 1024        # bodies per chunk of work and of the Zarr store

[base]
duration = "20 s"
dt = "10 ms"
method = "rk4"
moment_1 = "1 kg*m^2"
ratio_3 = 2.0
spin_axis = 2
spin_rate = "1 turn/s"
perturbation_azimuth = "0 deg"

[vary.ratio_2]           # I2 / I1, a grid
start = 1.05
stop = 1.95
num = 60

[vary.perturbation]      # angle between ω and axis 2 at t = 0
start = 0.01
stop = 10
num = 60
scale = "log"
unit = "deg"

[outputs]
metrics = ["flips", "first_flip_time", "max_nutation", "energy_drift", "momentum_drift"]
"""

workdir = tempfile.TemporaryDirectory()  # removed when the page is done
folder = Path(workdir.name)
sweep_file = folder / "small-flip-map.toml"
sweep_file.write_text(SWEEP, encoding="utf-8")
print(f"{sweep_file.name}: {len(SWEEP.splitlines())} lines")

# %%
# Run it on all cores
# -------------------
#
# :func:`tumble.sweep.run_sweep` runs the chunks in this process, each on all the
# cores numba may use, and returns a summary (also written to ``summary.json``):

summary = run_sweep(sweep_file, folder / "in-process")
print(f"{summary.bodies} bodies × {summary.steps} steps in {summary.seconds:.2f} s "
      f"({summary.backend}), {summary.chunks} chunks")  # fmt: skip
for name, values in summary.metrics.items():
    print(f"{name:16} mean {values['mean']:.3g}  min {values['min']:.3g}  "
          f"max {values['max']:.3g} {values['unit']}")  # fmt: skip
print(sorted(path.name for path in (folder / "in-process").iterdir()))

# %%
# The per-body results
# --------------------
#
# :func:`tumble.sweep.open_results` opens the Zarr store read-only: the varied
# parameters under ``parameters/``, the metrics under ``metrics/``, and the initial
# and final states (``initial/omega``, ``final/quaternion``, ...) unless the file's
# ``[outputs]`` turns them off. Each array has one row per body. A sweep without
# ``final_state`` (this one keeps them) whose torque does not depend on the attitude steps
# ω alone: the measures need nothing else, and RK4 then does about half the work
# a step (``bench/sweep.py``).

results = open_results(folder / "in-process")
ratio = results["parameters/ratio_2"][:]
perturbation = results["parameters/perturbation"][:]  # rad
first_flip = results["metrics/first_flip_time"][:]  # s, NaN where none
flips = results["metrics/flips"][:]
omega0 = results["initial/omega"][:]  # rad/s, principal axes
print(results.tree())

# %%
# A map of the flip
# -----------------
#
# The bodies come in grid order; ``np.unique`` recovers each one's place in the
# grid whatever that order is.

ratios, column = np.unique(ratio, return_inverse=True)
angles, row = np.unique(perturbation, return_inverse=True)
grid_first = np.full((len(angles), len(ratios)), np.nan)  # s
grid_flips = np.zeros((len(angles), len(ratios)))
grid_first[row, column] = first_flip
grid_flips[row, column] = flips

fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained", sharey=True)
image = axes[0].pcolormesh(ratios, np.degrees(angles), grid_first, shading="nearest", norm="log")
bar = fig.colorbar(image, ax=axes[0], label="time of the first flip (s)")
bar.set_ticks([2, 3, 5, 10], labels=["2", "3", "5", "10"], minor=False)
bar.ax.minorticks_off()
image = axes[1].pcolormesh(ratios, np.degrees(angles), grid_flips, shading="nearest", cmap="magma")
fig.colorbar(image, ax=axes[1], label="flips in 20 s")
axes[0].set_ylabel("perturbation (deg)")
for ax in axes:
    ax.set_yscale("log")
    ax.set_xlabel("$I_2 / I_1$ ($I_3 = 2 I_1$)")

# %%
# The smaller the perturbation, the longer the body takes to leave the axis: the
# deviation grows like :math:`e^{\gamma t}` with
# :math:`\gamma = \omega \sqrt{(I_2 - I_1)(I_3 - I_2) / (I_1 I_3)}`
# (:func:`tumble.theory.axis_stability`), so the time of the first flip grows like
# :math:`\ln(1/\varepsilon) / \gamma` for a perturbation :math:`\varepsilon`: it is
# longest where :math:`\gamma` is smallest, near :math:`I_2 = I_1` and
# :math:`I_2 = I_3`.
#
# Checked against the closed form
# -------------------------------
#
# With the perturbation towards axis 3, :math:`\omega_1(0) = 0`, so
# :math:`\dot\omega_2(0) = (I_3 - I_1)\,\omega_3\omega_1 / I_2 = 0`: :math:`\omega_2`
# starts at an extremum of its Jacobi function and first crosses zero a quarter of
# its period later, :math:`T/4` with :math:`T = 4K(k)/\lambda`
# (:func:`tumble.theory.flip_period`; Landau & Lifshitz, *Mechanics* §37).

quarter = np.array([
    tb.theory.flip_period([1.0, r, 2.0], w) / 4 for r, w in zip(ratio, omega0, strict=True)
])  # fmt: skip
error = np.abs(first_flip / quarter - 1)
print(f"largest relative error of the first flip time against T/4: {error.max():.1e}")
# RK4 at 100 steps a turn over up to 10 s, and the crossing found by linear
# interpolation between steps where ω2 is nearly linear: both errors are far
# below 1e-5.
assert error.max() < 1e-5

# %%
# Run it again in the same folder and nothing is computed: every chunk is found
# done (a sweep that was interrupted, even killed, resumes the same way and gives
# the same bits). A changed sweep file is refused for that folder unless
# ``force=True``.

again = run_sweep(sweep_file, folder / "in-process")
print(f"chunks run {again.chunks_run}, reused {again.chunks_reused}")

# %%
# On a Dask cluster
# -----------------
#
# ``run_sweep`` takes ``scheduler="tcp://HOST:PORT"``, the address of a Dask
# scheduler: the plan is sent to every worker once, each task names only its chunk
# indices, and the results come back to this process, which writes them (the
# workers need no access to the output folder). Here a cluster inside this process,
# one worker on the loopback interface, stands in for a real one:

import dask  # noqa: E402
import distributed  # noqa: E402

with (
    dask.config.set({"temporary-directory": str(folder)}),  # its scratch files
    distributed.LocalCluster(
        n_workers=1, processes=False, host="127.0.0.1", protocol="tcp", dashboard_address=None
    ) as cluster,
):
    on_dask = run_sweep(sweep_file, folder / "dask", scheduler=cluster.scheduler_address)
print(f"{on_dask.backend}: {on_dask.bodies} bodies in {on_dask.seconds:.2f} s")

same = np.array_equal(
    open_results(folder / "dask")["metrics/first_flip_time"][:], first_flip, equal_nan=True
)
print("the same results as in-process:", same)
# The chunks are computed by the same kernels in the same order: the same bits.
assert same

# %%
# On a real cluster, pass the scheduler's address; or let tumble start a local
# cluster of worker processes with ``workers=N`` (on 127.0.0.1 only, with its
# scratch files inside the output folder). A ``[dask]`` table in the sweep file
# (``workers = 4`` or ``scheduler = "tcp://..."``) does the same. This block is
# not run here:
#
# .. code-block:: python
#
#    run_sweep("my-sweep.toml", "my-sweep", workers=4)
#    run_sweep("my-sweep.toml", "my-sweep", scheduler="tcp://10.0.0.5:8786")
#
# The command line
# ----------------
#
# ``tumble sweep`` does the same and also writes ``report.html``, the maps of the
# file's ``[report]`` table:
#
# .. code-block:: console
#
#    $ tumble show flip-map > my-sweep.toml          # a built-in sweep, to edit
#    $ tumble sweep my-sweep.toml -o my-sweep         # in this process, on all cores
#    $ tumble sweep my-sweep.toml -o my-sweep --workers 4
#    $ tumble sweep my-sweep.toml -o my-sweep --scheduler tcp://10.0.0.5:8786
#
# :doc:`/reference/cli` lists every option.
