"""Torque models that declare a potential energy: a user's conservative torque,
and gravity through the same mechanism.

A body-fixed magnetic dipole m in a uniform space-fixed field B, written in this
module alone as a :class:`tumble.torques.UserTorque` with its potential
U = −m·B_body, keeps T + U to round-off under RK4, follows an independent DOP853
integration, and its energy appears in the drift report and survives a
trajectory file. Gravity's energy is the heavy top's closed form, as before;
the heavy top's closed form is chosen by what a model declares, not by its class.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
import pyarrow.parquet as pq
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.body import RigidBody
from tumble.core import torques as kernels
from tumble.report.html import drift_html
from tumble.torques import TorqueModel

# An asymmetric body given in axes that are not its principal ones, so that the
# user's functions see the body's own axes while the kernels work in principal axes.
AXES = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
BODY = tb.MassProperties(1.0, [0.0, 0.0, 0.0], AXES @ np.diag([1.0, 2.0, 2.6]) @ AXES.T)
OMEGA0 = np.array([0.4, -0.7, 0.9])  # rad/s, body axes
Q0 = Rotation.from_rotvec([0.2, 0.1, -0.4]).as_quat(scalar_first=True)
MOMENT = np.array([0.8, -0.3, 0.5])  # A·m², body axes
FIELD = np.array([0.0, 0.6, 1.2])  # T, space axes
PARAMS = [*MOMENT, *FIELD]
DURATION = 5.0


# ------------------------------------------------------------------ the dipole
@numba.njit
def field_in_body(q, params):
    """B_body = Rᵀ B, R the rotation of q = [w, x, y, z] (body → space); B is
    params[3:6] (space axes)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    bx, by, bz = params[3], params[4], params[5]
    return (
        (1 - 2 * (y * y + z * z)) * bx + 2 * (x * y + w * z) * by + 2 * (x * z - w * y) * bz,
        2 * (x * y - w * z) * bx + (1 - 2 * (x * x + z * z)) * by + 2 * (y * z + w * x) * bz,
        2 * (x * z + w * y) * bx + 2 * (y * z - w * x) * by + (1 - 2 * (x * x + y * y)) * bz,
    )


@numba.njit
def dipole_torque(t, omega, quaternion, params, out):
    # τ = m × B_body (N·m, body axes); m = params[0:3] (A·m², body axes).
    b1, b2, b3 = field_in_body(quaternion, params)
    out[0] = params[1] * b3 - params[2] * b2
    out[1] = params[2] * b1 - params[0] * b3
    out[2] = params[0] * b2 - params[1] * b1


@numba.njit
def dipole_energy(t, quaternion, params):
    # U = −m · B_body, J.
    b1, b2, b3 = field_in_body(quaternion, params)
    return -(params[0] * b1 + params[1] * b2 + params[2] * b3)


@numba.njit
def fading_dipole_energy(t, quaternion, params):
    # A field that fades in time: U depends on t, so T + U is not conserved.
    return math.exp(-t) * dipole_energy(t, quaternion, params)


@numba.njit
def damped_dipole_torque(t, omega, quaternion, params, out):
    # The dipole plus a viscous drag −c ω (c = params[6], N·m·s): reads ω (and not t,
    # which passed to the helper would count as read).
    dipole_torque(0.0, omega, quaternion, params, out)
    for i in range(3):
        out[i] -= params[6] * omega[i]


def dipole() -> tb.torques.UserTorque:
    return tb.torques.UserTorque(dipole_torque, PARAMS, potential=dipole_energy)


def reference_motion(times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ω (body axes) and q at ``times``: Euler's equations I ω̇ = m × Rᵀ B − ω × I ω
    with the full inertia tensor of the body's own axes, and q̇ = ½ q ⊗ (0, ω), by
    scipy's DOP853 at rtol 1e-13 — none of tumble's kernels."""
    inertia = BODY.inertia
    inverse = np.linalg.inv(inertia)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        w, q = y[:3], y[3:]
        matrix = Rotation.from_quat(q, scalar_first=True).as_matrix()
        torque = np.cross(MOMENT, matrix.T @ FIELD)
        w_dot = inverse @ (torque - np.cross(w, inertia @ w))
        q0, q1, q2, q3 = q
        q_dot = 0.5 * np.array(
            [
                -q1 * w[0] - q2 * w[1] - q3 * w[2],
                q0 * w[0] + q2 * w[2] - q3 * w[1],
                q0 * w[1] + q3 * w[0] - q1 * w[2],
                q0 * w[2] + q1 * w[1] - q2 * w[0],
            ]
        )
        return np.concatenate([w_dot, q_dot])

    solution = solve_ivp(
        rhs, (0.0, times[-1]), np.concatenate([OMEGA0, Q0]), method="DOP853",
        rtol=1e-13, atol=1e-14, t_eval=times,
    )  # fmt: skip
    return solution.y[:3].T, solution.y[3:].T


def energy_by_hand(omega: np.ndarray, quaternion: np.ndarray) -> np.ndarray:
    """T + U = ½ ω·I ω − m·Rᵀ B at each sample, J."""
    kinetic = 0.5 * np.einsum("ni,ij,nj->n", omega, BODY.inertia, omega)
    field = Rotation.from_quat(quaternion, scalar_first=True).inv().apply(FIELD)
    return kinetic - field @ MOMENT


@pytest.fixture(scope="module")
def rk4_run() -> tb.Trajectory:
    return tb.simulate(
        BODY, OMEGA0, attitude0=Q0, duration=DURATION, dt=1e-3, method="rk4",
        torque=dipole(), record_every=10,
    )  # fmt: skip


# ------------------------------------------------------------------ (a) the dipole
def test_the_dipole_is_conservative_and_reads_only_the_attitude() -> None:
    model = dipole()
    assert model.conservative and model.depends_on == frozenset({"attitude"})
    assert "potential=dipole_energy" in repr(model)
    # The potential, evaluated in one compiled pass, against the formula.
    q = Rotation.random(5, random_state=1).as_quat(scalar_first=True)
    expected = -Rotation.from_quat(q, scalar_first=True).inv().apply(FIELD) @ MOMENT
    body = RigidBody(BODY)
    assert_allclose(model.potential_energy(body, np.zeros(5), q), expected, rtol=1e-14)


def test_the_dipole_keeps_its_energy_under_rk4(rk4_run: tb.Trajectory) -> None:
    run = rk4_run
    # The trajectory's energy is T + U, as written by hand here.
    assert_allclose(run.energy, energy_by_hand(run.omega, run.quaternion), rtol=1e-13, atol=1e-14)
    field = Rotation.from_quat(run.quaternion, scalar_first=True).inv().apply(FIELD)
    assert_allclose(run.potential_energy, -field @ MOMENT, rtol=1e-13, atol=1e-14)
    # The motion exchanges energy between T and U (|U| up to |m||B| ≈ 1.3 J) ...
    kinetic = run.energy - run.potential_energy
    assert np.ptp(kinetic) > 0.1
    # ... while T + U stays, to round-off. RK4 is fourth order: its energy error over
    # a fixed time goes as dt^4, which the halving of the step below shows (a factor
    # 2^4 = 16). At dt = 1e-2 it is ~2e-10 here, so at dt = 1e-3 the truncation leaves
    # ~2e-14, as much as the round-off of 5000 steps (~√5000 × 1e-16 ≈ 1e-14): a bound
    # of 1e-12 is 30 times both.
    change = np.abs(run.energy - run.energy[0]) / np.max(np.abs(run.energy))
    assert np.max(change) < 1e-12
    assert run.drift["energy"] == pytest.approx(np.max(change), rel=1e-6, abs=1e-16)
    coarse, fine = (
        tb.simulate(
            BODY, OMEGA0, attitude0=Q0, duration=DURATION, dt=dt, method="rk4", torque=dipole()
        ).drift["energy"]
        for dt in (1e-2, 5e-3)
    )
    assert 12 < coarse / fine < 20 and coarse < 1e-9


def test_the_dipole_follows_an_independent_integration(rk4_run: tb.Trajectory) -> None:
    run = rk4_run
    rows = np.arange(0, len(run.t), 50)
    omega, quaternion = reference_motion(run.t[rows])
    # RK4's global error goes as dt^4: ~1e-9 (rad/s, rad) at dt = 1e-2 for this motion,
    # so ~1e-13 at dt = 1e-3; DOP853 at rtol 1e-13 over 5 s is within ~1e-12. 1e-11
    # leaves a factor of ten above both.
    assert np.max(np.abs(run.omega[rows] - omega)) < 1e-11
    angle = (
        Rotation.from_quat(run.quaternion[rows], scalar_first=True)
        * Rotation.from_quat(quaternion, scalar_first=True).inv()
    ).magnitude()
    assert np.max(angle) < 1e-11


def test_auto_takes_the_splitting_for_the_conservative_dipole() -> None:
    run = tb.simulate(
        BODY, OMEGA0, attitude0=Q0, duration=DURATION, dt=1e-3, torque=dipole(), record_every=10
    )
    assert run.method == "splitting"
    assert run.reason == "auto: the torque is conservative, so the symplectic splitting " + (
        "(bounded energy error)"
    )
    # A fourth-order symplectic method, its kicks exact for a torque of the attitude
    # alone: its energy error stays within C dt^4 without growing, C of the order of
    # RK4's here (~2e-14 at this step, above): 1e-12 as for RK4.
    assert run.drift["energy"] < 1e-12


# ------------------------------------------------------------------ (b) drift report
def test_the_drift_report_lists_the_dipoles_energy(rk4_run: tb.Trajectory) -> None:
    assert rk4_run.conserved_quantities == ("energy",)
    assert set(rk4_run.drift) == {"energy"}
    assert "relative drift: energy" in repr(rk4_run)
    page = drift_html(rk4_run.drift)
    assert "kinetic plus potential energy, J" in page and "Nothing is conserved" not in page


def test_a_potential_of_time_or_a_torque_of_omega_conserves_nothing() -> None:
    fading = tb.torques.UserTorque(dipole_torque, PARAMS, potential=fading_dipole_energy)
    damped = tb.torques.UserTorque(damped_dipole_torque, [*PARAMS, 0.05], potential=dipole_energy)
    assert fading.depends_on == frozenset({"attitude"})
    assert damped.depends_on == frozenset({"attitude", "omega"})
    for model in (fading, damped):
        assert not model.conservative
        run = tb.simulate(
            BODY, OMEGA0, attitude0=Q0, duration=2.0, dt=1e-3, torque=model, method="rk4"
        )
        assert run.drift == {} and run.conserved_quantities == ()
        # The energy still adds the declared potential.
        kinetic = 0.5 * np.einsum("ni,ij,nj->n", run.omega, BODY.inertia, run.omega)
        assert_allclose(run.potential_energy, run.energy - kinetic, rtol=1e-12, atol=1e-14)
        if model is fading:
            expected = np.exp(-run.t) * (energy_by_hand(run.omega, run.quaternion) - kinetic)
            assert_allclose(run.potential_energy, expected, rtol=1e-12, atol=1e-14)
        else:
            # Drag takes energy out: T + U falls, by ∫ c |ω|² dt > 0.
            assert run.energy[-1] < run.energy[0] - 1e-3


def test_a_torque_without_a_potential_stays_unconservative() -> None:
    model = tb.torques.UserTorque(dipole_torque, PARAMS)
    assert not model.conservative and model.depends_on == frozenset({"attitude"})
    run = tb.simulate(BODY, OMEGA0, attitude0=Q0, duration=0.5, dt=1e-2, torque=model)
    assert run.method == "adaptive" and run.drift == {}
    assert np.all(run.potential_energy == 0.0)


def test_a_user_potential_survives_a_trajectory_file(rk4_run: tb.Trajectory, tmp_path) -> None:
    path = tmp_path / "dipole.parquet"
    rk4_run.to_parquet(path)
    back = tb.Trajectory.read_parquet(path)
    # The function cannot be stored, its potential energy is: energy and drift stay.
    assert back.torque is None
    assert np.array_equal(back.energy, rk4_run.energy)
    assert back.drift == rk4_run.drift and back.conserved_quantities == ("energy",)
    assert np.array_equal(back.samples(slice(None, None, 7)).energy, rk4_run.energy[::7])
    meta = json.loads(pq.read_schema(path).metadata[b"tumble"])
    assert meta["torques"] == [
        {
            "type": "user",
            "function": "dipole_torque",
            "params": PARAMS,
            "potential": "dipole_energy",
            "actuator": "external",
        }
    ]
    assert meta["gravity"] == [0.0, 0.0, 0.0]


# ------------------------------------------------------------------ (c) gravity
DISK = tb.shapes.solid_cylinder(1.0, 0.1, 0.02)
PIVOT = np.array([0.0, 0.0, -0.1])
GRAVITY = np.array([0.0, 0.0, -9.81])


def heavy_top_energy(run: tb.Trajectory) -> np.ndarray:
    """½ ω·I_pivot ω − m g·(R r), r from the pivot to the centre of mass, J."""
    inertia = DISK.inertia_about(PIVOT)
    kinetic = 0.5 * np.einsum("ni,ij,nj->n", run.omega, inertia, run.omega)
    lever = Rotation.from_quat(run.quaternion, scalar_first=True).apply(DISK.center_of_mass - PIVOT)
    return kinetic - DISK.mass * lever @ GRAVITY


@pytest.mark.parametrize("method", ["auto", "rk4"])
def test_gravitys_energy_is_the_heavy_tops(method: str, tmp_path) -> None:
    run = tb.simulate(
        DISK, [0.3, 0.0, 50.0], attitude0=[0.9, 0.3, 0.0, 0.0], duration=0.5, dt=1e-3,
        pivot=PIVOT, gravity=GRAVITY, method=method,
    )  # fmt: skip
    if method == "auto":
        assert run.method == "exact" and "the Lagrange top" in run.reason
    assert_allclose(run.energy, heavy_top_energy(run), rtol=1e-14)
    assert_allclose(run.gravity, GRAVITY, rtol=0)
    assert run.conserved_quantities == (
        "energy", "angular_momentum_vertical", "angular_momentum_axial",
    )  # fmt: skip
    # Its file lists gravity among the torques, and reads back with the same energy,
    # as does a file written before the torques were listed (gravity alone).
    path = tmp_path / "top.parquet"
    run.to_parquet(path)
    back = tb.Trajectory.read_parquet(path)
    assert np.array_equal(back.energy, run.energy) and back.drift == run.drift
    table = pq.read_table(path)
    meta = json.loads(table.schema.metadata[b"tumble"])
    assert meta["torques"] == [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}]
    del meta["torques"]
    older = tmp_path / "older.parquet"
    pq.write_table(
        table.drop_columns(["potential_energy"]).replace_schema_metadata(
            {"tumble": json.dumps(meta)}
        ),
        older,
    )
    old = tb.Trajectory.read_parquet(older)
    assert old.potential is None and old.torque is not None
    assert np.array_equal(old.energy, run.energy)
    assert_allclose(old.gravity, GRAVITY, rtol=0)


@dataclass(frozen=True, eq=False, repr=False)
class Weight(TorqueModel):
    """Uniform gravity written in this module alone: a model that declares its
    uniform gravity and its potential, whatever its class."""

    acceleration: Any = (0.0, 0.0, -9.81)

    name = "test-weight"
    fields = ("r1", "r2", "r3", "wx", "wy", "wz")
    kernel = staticmethod(kernels.gravity_about_pivot)
    depends_on = frozenset({"attitude"})
    conservative = True

    def pack(self, body: Any, omega0: Any) -> np.ndarray:
        weight = body.mass_properties.mass * np.asarray(self.acceleration, dtype=float)
        return np.concatenate([body.to_principal(body.lever), weight])

    def potential_energy(self, body: Any, t: np.ndarray, quaternion: np.ndarray) -> np.ndarray:
        lever = Rotation.from_quat(quaternion, scalar_first=True).apply(body.lever)
        return -body.mass_properties.mass * lever @ np.asarray(self.acceleration, dtype=float)

    def uniform_gravity(self) -> np.ndarray:
        return np.asarray(self.acceleration, dtype=float)

    def conserves(self, body: Any) -> frozenset[str]:
        return frozenset({"energy", "angular_momentum_vertical", "angular_momentum_axial"})


def test_the_heavy_tops_closed_form_is_chosen_by_what_a_model_declares() -> None:
    kwargs = {"attitude0": [0.9, 0.3, 0.0, 0.0], "duration": 0.5, "dt": 1e-3, "pivot": PIVOT}
    run = tb.simulate(DISK, [0.3, 0.0, 50.0], torque=Weight(tuple(GRAVITY)), **kwargs)
    assert run.method == "exact" and "the Lagrange top" in run.reason
    same = tb.simulate(DISK, [0.3, 0.0, 50.0], gravity=GRAVITY, **kwargs)
    assert np.array_equal(run.omega, same.omega) and np.array_equal(run.energy, same.energy)
    assert_allclose(run.gravity, GRAVITY, rtol=0)


# ------------------------------------------------------------------ (d) errors
def plain_energy(t, quaternion, params):
    return 0.0


@numba.njit
def untyped_energy(t, quaternion, params):
    return quaternion.no_such_attribute


@numba.njit
def vector_energy(t, quaternion, params):
    return quaternion[1:]


@numba.njit
def pair_energy(t, quaternion, params):
    return 1.0, 2.0


@pytest.mark.parametrize(
    ("potential", "message"),
    [
        (3.0, r"^Expected `potential` to be None or a function compiled with numba\.njit, got float 3\.0\.$"),
        ("U", r"^Expected `potential` to be None or a function compiled with numba\.njit, got str 'U'\.$"),
        (plain_energy, r"^Expected `potential` to be None or a function compiled with numba\.njit, got function 'plain_energy'\.$"),
        (untyped_energy, r"^Expected `potential\(t, quaternion, params\)` \('untyped_energy'\) to compile and run on a test state \(t = 0, identity attitude\), got TypingError: Unknown attribute 'no_such_attribute' of type array\(float64, 1d, C\)$"),
        (vector_energy, r"^Expected `potential\(t, quaternion, params\)` \('vector_energy'\) to return a number \(J\), got an array of shape \(3,\) on a test state \(t = 0, identity attitude\)\.$"),
        (pair_energy, r"^Expected `potential\(t, quaternion, params\)` \('pair_energy'\) to return a number \(J\), got tuple \(1\.0, 2\.0\) on a test state \(t = 0, identity attitude\)\.$"),
    ],
)  # fmt: skip
def test_potential_errors(potential: Any, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.torques.UserTorque(dipole_torque, PARAMS, potential=potential)


@numba.njit
def torque_of_time_through_a_helper(t, omega, quaternion, params, out):
    dipole_torque(t, omega, quaternion, params, out)


def test_an_argument_passed_to_a_helper_counts_as_read() -> None:
    # The helper may read t: only an argument that no instruction loads is unread.
    model = tb.torques.UserTorque(torque_of_time_through_a_helper, PARAMS, potential=dipole_energy)
    assert model.depends_on == frozenset({"time", "omega", "attitude"})
    assert not model.conservative
