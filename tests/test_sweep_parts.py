"""Sweeps of bodies carrying parts (``[[internal]]`` in a sweep file): each
chunk's measures against the same bodies simulated one by one, whose energy is
summed by the parts' own methods in Python (an implementation independent of the
compiled energy shares of :func:`tumble.core.parts.part_energy`); the rotor's
energy conserved; every refusal."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import tumble as tb
from tumble.batch.parts import PartsBatch
from tumble.body import RigidBody
from tumble.core.metrics import (
    ENERGY_DEVIATION,
    FIRST_FLIP,
    FLIPS,
    MIN_COS,
    MOMENTUM_DEVIATION,
    N_METRICS,
)
from tumble.core.part_measures import measuring_kernel
from tumble.core.parts import make_rk4_step
from tumble.core.torques import combine
from tumble.integrators import get_integrator
from tumble.report import write_sweep_report
from tumble.sweep import open_results, run_sweep
from tumble.sweep.build import parse_sweep
from tumble.sweep.metrics import compute_chunk
from tumble.sweep.schema import SweepError

RATIOS = (1.2, 1.5, 1.8)
ROTOR = """
[[internal]]
type = "rotor"
axis = [0, 1, 0]
inertia = "0.05 kg*m^2"
speed = "2 rad/s"
"""
DAMPER = """
[[internal]]
type = "kane-damper"
inertia = "0.02 kg*m^2"
damping = "0.01 N*m*s"
"""
METRIC_NAMES = ("flips", "first_flip_time", "max_nutation", "energy_drift", "momentum_drift")


def sweep_text(parts: str, method: str = "rk4", metrics: tuple[str, ...] = METRIC_NAMES) -> str:
    """Three bodies spun 3° off their intermediate axis 2, carrying ``parts``."""
    listed = ", ".join(f'"{name}"' for name in metrics)
    return (
        textwrap.dedent(f"""
        [sweep]
        name = "parts"
        seed = 1
        chunk_size = 2

        [base]
        duration = "20 s"
        dt = "2 ms"
        method = "{method}"
        moment_1 = "1 kg*m^2"
        ratio_3 = 2.0
        spin_axis = 2
        spin_rate = "1 rad/s"
        perturbation = "3 deg"

        [vary.ratio_2]
        values = {list(RATIOS)}
        """)
        + textwrap.dedent(parts)
        + textwrap.dedent(f"""
        [outputs]
        metrics = [{listed}]
        final_state = true
        """)
    )


def measured_one_by_one(
    internal: list[object], ratio: float, method: str
) -> tuple[dict[str, float], tb.Trajectory]:
    """The sweep's measures of one body, from its history in tb.simulate: flips and
    the nutation from H in body axes about axis 2, the energy from Trajectory.energy
    (the parts' Python methods)."""
    mp = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, ratio, 2.0]))
    tilt = np.radians(3.0)
    # perturbation_azimuth 0: the tilt towards the next axis, 3.
    omega0 = np.array([0.0, np.cos(tilt), np.sin(tilt)])
    traj = tb.simulate(mp, omega0, internal=internal, duration=20.0, dt=2e-3, method=method)
    space = traj.angular_momentum
    body = np.einsum("nji,nj->ni", traj.rotation.as_matrix(), space)
    along = body[:, 1]
    size = np.linalg.norm(body, axis=1)
    crossings = np.flatnonzero(np.sign(along[1:]) * np.sign(along[:-1]) < 0)
    first = np.nan
    if crossings.size:
        k = crossings[0]
        first = traj.t[k] + 2e-3 * along[k] / (along[k] - along[k + 1])
    energy = traj.energy
    return {
        "flips": float(crossings.size),
        "first_flip_time": first,
        "max_nutation": float(np.max(np.arccos(np.clip(along / size, -1, 1)))),
        "energy_drift": float(np.max(np.abs(energy - energy[0])) / energy[0]),
        "momentum_drift": float(np.max(np.abs(size - size[0])) / size[0]),
    }, traj


@pytest.mark.parametrize("method", ["rk4", "splitting"])
def test_a_chunk_of_bodies_with_parts_measures_as_their_histories(method: str) -> None:
    parts = ROTOR + (DAMPER if method == "rk4" else "")  # the splittings take rotors only
    plan = parse_sweep(sweep_text(parts, method))
    internal: list[object] = [tb.Rotor([0, 1, 0], 0.05, speed=2.0)]
    if method == "rk4":
        internal.append(tb.KaneDamper(inertia=0.02, damping=0.01))
    arrays = {**compute_chunk(plan, 0), **{
        f"{k}:1": v for k, v in compute_chunk(plan, 1).items()
    }}  # fmt: skip
    for k, ratio in enumerate(RATIOS):
        chunk, j = ("", k) if k < 2 else (":1", k - 2)
        expected, traj = measured_one_by_one(internal, ratio, method)
        got = {name: float(arrays[f"metrics/{name}{chunk}"][j]) for name in METRIC_NAMES}
        # The same steps in the same order as tb.simulate: ω and the attitude equal to
        # round-off over 10 000 steps.
        assert_allclose(arrays[f"final/omega{chunk}"][j], traj.omega[-1], rtol=0, atol=1e-12)
        assert_allclose(
            arrays[f"final/quaternion{chunk}"][j], traj.quaternion[-1], rtol=0, atol=1e-12
        )
        assert got["flips"] == expected["flips"]
        # The interpolated time of the first flip, and the nutation and drifts, from
        # the same states summed otherwise: round-off of sums over 1e4 steps.
        assert_allclose(got["first_flip_time"], expected["first_flip_time"], rtol=1e-9)
        assert_allclose(got["max_nutation"], expected["max_nutation"], rtol=1e-9)
        assert_allclose(got["energy_drift"], expected["energy_drift"], rtol=1e-6, atol=1e-13)
        assert got["momentum_drift"] < 1e-13  # internal torques keep H
    # Where the rotor stabilises the spin, no flips; where it does not, two.
    assert arrays["metrics/flips"].tolist() == [2, 2] or method != "rk4"


def test_undamped_parts_keep_the_energy_of_a_free_body() -> None:
    # A rotor without a motor and a Kane damper without damping: T = ½ ω·I_p ω +
    # h²/(2J) + σ²/(2J_s) is conserved, and RK4 at 2 ms on rates of 1/s keeps it to
    # ~(dt)⁴ per unit time; the energy without the parts' shares (ω · H alone)
    # would swing by a part in ten. (The layout of the chunk test above: its
    # kernel is reused.)
    plan = parse_sweep(sweep_text(ROTOR + DAMPER.replace("0.01 N*m*s", "0 N*m*s")))
    drift = compute_chunk(plan, 0)["metrics/energy_drift"]
    assert np.all(drift < 1e-10)
    assert np.all(drift > 0)  # measured, not left at zero


def test_a_sweep_with_parts_runs_to_its_store(tmp_path: Path) -> None:
    path = tmp_path / "parts.toml"
    path.write_text(sweep_text(ROTOR + DAMPER))
    summary = run_sweep(path, tmp_path / "out")
    assert summary.bodies == 3
    assert write_sweep_report(summary).is_file()  # its maps drawn
    results = open_results(tmp_path / "out")
    assert results["metrics/flips"][:].tolist() == [2, 2, 0]


def test_the_parts_are_part_of_a_sweeps_identity() -> None:
    plain = parse_sweep(sweep_text(""))
    with_rotor = parse_sweep(sweep_text(ROTOR))
    assert "parts" not in plain.identity()  # the sweeps without parts keep theirs
    assert with_rotor.identity()["parts"][0]["type"] == "rotor"
    assert with_rotor.identity()["parts"][0]["inertia"] == 0.05


def test_the_spring_energy_share_matches_the_parts_own_energy() -> None:
    # A spring–mass damper is not swept (its mass moves each body's centre of mass),
    # but its compiled energy share is: the measuring kernel run on one body, as
    # tb.simulate steps it, gives 2 E₀ and the largest |2E − 2E₀| of the Python
    # energy of the trajectory (the kinetic energy over the masses, with sympy in
    # tests/test_spring_mass.py, and the spring's).
    spring = tb.SpringMassDamper(
        mass=0.3, position=[0.0, 0.4, 0.0], direction=[1.0, 0.0, 0.0], stiffness=6.0, damping=1.0,
        displacement=0.05,
    )  # fmt: skip
    mp = tb.MassProperties(2.0, [0, 0, 0], np.diag([1.0, 1.4, 2.0]))
    omega0 = np.array([0.3, 0.2, 1.0])
    traj = tb.simulate(mp, omega0, internal=[spring], duration=5.0, dt=1e-3, method="rk4")
    body = RigidBody(traj.mass_properties, None, tuple(traj.internal))
    y = body.kernel_state(omega0, np.array([1.0, 0, 0, 0]))[:, None].copy()
    free = combine(())
    kernel = measuring_kernel(make_rk4_step, free, free, body.layout, "test")
    out = np.empty((N_METRICS, 1))
    twice = np.empty(1)
    status = np.empty(1, dtype=np.int64)
    axis = np.array([[0.0], [0.0], [1.0]])
    kernel(y, body.moments[:, None].copy(), body.packed_parts.copy(), np.zeros((3, 1)), 0.0,
           axis, 0.0, 1e-3, 5000, out, twice, status)  # fmt: skip
    energy = traj.energy
    # Round-off of two sums of a few terms of order 1 J.
    assert_allclose(twice[0], 2 * energy[0], rtol=1e-13)
    assert_allclose(out[ENERGY_DEVIATION, 0], 2 * np.max(np.abs(energy - energy[0])), rtol=1e-9)
    # The damper dissipates: the deviation compared is far above round-off.
    assert energy[-1] < 0.995 * energy[0]


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize(
    ("parts", "method", "message"),
    [
        (
            '[[internal]]\ntype = "rotor"\naxis = [0, 1, 0]\nmass = "1 kg"\nradius = "10 cm"\n',
            "rk4",
            r"line \d+, `internal\[0\]`: Expected parts held in the swept moments \(given by "
            r"their `inertia`\), got a rotor given by its mass",
        ),
        (
            '[[internal]]\ntype = "spring-mass-damper"\nmass = "1 kg"\nposition = "0, 0.4, 0 m"'
            '\naxis = [1, 0, 0]\nstiffness = "6 N/m"\ndamping = "1 N*s/m"\n',
            "rk4",
            r"`internal\[0\]`: Expected parts that batches take, got a spring-mass-damper \(its "
            r"mass moves each body's centre of mass\)\.",
        ),
        (ROTOR + DAMPER, "splitting",
         r"`base\.method`: Expected a method that measures bodies carrying kane-damper, rotor "
         r"parts \(rk4\), got 'splitting'\."),
        (ROTOR, "exact", r"`base\.method`: Expected a method that measures bodies carrying "
         r"rotor parts \(splitting, strang, rk4\), got 'exact'\."),
        ('[[internal]]\ntype = "rotor"\naxis = [0, 1, 0]\ninertia = "1.3 kg*m^2"\n', "rk4",
         r"`internal`: Expected internal parts whose spin inertia every body can hold .* got "
         r"\[-?[0-9.e-]+, .*\] kg·m² left at the smallest moments \[1\.0, 1\.2, 2\.0\] kg·m²\."),
        ('[[internal]]\ntype = "rotor"\naxis = [0, 0, 0]\ninertia = "0.1 kg*m^2"\n', "rk4",
         r"`internal\[0\]`: Expected `axis` of a Rotor to be a non-zero vector, got \[0\.0, "
         r"0\.0, 0\.0\]\."),
        ('[[internal]]\ntype = "flywheel"\n', "rk4", r"`internal\[0\]\.type`: Expected `type` to be one of kane-damper, "
         r"spring-mass-damper, rotor, got 'flywheel'\."),
    ],
)  # fmt: skip
def test_a_sweep_refuses_parts_it_cannot_measure(parts: str, method: str, message: str) -> None:
    with pytest.raises(SweepError, match=message):
        parse_sweep(sweep_text(parts, method))


def _damped_batch(damping: float) -> PartsBatch:
    """Two bodies carrying a Kane damper of J = 0.02 kg·m² and ``damping`` N·m·s."""
    inertia = np.array([[1.0, 1.5, 2.0], [1.0, 1.2, 2.0]])
    omega = np.array([[0.1, 1.0, 0.1], [0.1, 1.0, 0.1]])
    q0 = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    damper = tb.KaneDamper(inertia=0.02, damping=damping)
    return PartsBatch.build(inertia, omega, q0, (damper,), None, "rk4")


AXES = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]])


def test_measuring_a_batch_refuses_what_it_cannot_measure() -> None:
    # A method without a measuring kernel for the parts: the methods that have one.
    with pytest.raises(
        tb.InputError,
        match=r"^Expected a method that integrates batches carrying kane-damper parts \(rk4\), "
        r"got 'rk4'\.$",
    ):
        _damped_batch(0.01).measure(get_integrator("adaptive"), None, 0.01, 10, AXES)
    # A kind without its energy's equation: refused for the energy, measured without
    # it; the other measures are those of the kind with it (the same steps).
    rk4 = get_integrator("rk4", batch=True)
    full, _ = _damped_batch(0.01).measure(rk4, None, 0.01, 10, AXES)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(tb.KaneDamper, "equations", tb.KaneDamper.equations._replace(energy=None))
        batch = _damped_batch(0.01)
        with pytest.raises(
            tb.InputError,
            match=r"^Expected parts whose energy can be measured \(PartEquations\.energy\), got "
            r"kane-damper parts without it\.$",
        ):
            batch.measure(rk4, None, 0.01, 10, AXES)
        out, _ = batch.measure(rk4, None, 0.01, 10, AXES, energy=False)
    others = [FLIPS, FIRST_FLIP, MIN_COS, MOMENTUM_DEVIATION]
    assert_array_equal(out[others], full[others])


def test_measuring_a_batch_names_the_first_body_that_diverged() -> None:
    # D/J = 5e7 /s against dt = 0.01 s: RK4 is unstable for the damper from the
    # first steps, for both bodies.
    batch = _damped_batch(1e6)
    with pytest.raises(
        tb.IntegrationError,
        match=r"^Expected the integration to stay finite, got NaN or inf for 2 bodies of "
        r"chunk 3 \(first: body 40, at step \d+\) with dt = 0\.01 s: reduce dt\.$",
    ):
        batch.measure(get_integrator("rk4", batch=True), None, 0.01, 1000, AXES,
                      first_body=40, where="of chunk 3")  # fmt: skip
