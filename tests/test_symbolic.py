"""``tumble.symbolic`` against tumble's numbers, and against itself.

Oracles:

* the numeric API at random values: ``tb.point_masses`` (inertia about the
  origin and the centre of mass), ``tumble.shapes`` (the solids),
  ``theory.skew_rod`` (L(t), τ(t) and magnitudes), ``tb.required_torque``
  (Euler's equations in any body frame), ``theory.gyrocompass`` (θ̈(θ) and
  both frequencies, and where it refuses a slow spin);
* internal consistency, exact in sympy: τ = dL/dt and |L|² = L·L for the skew rod,
  L = I(t) ω from the point-mass inertia, the principal form of Euler's
  equations and their covariance under a rotation of the body axes, the
  linearised gyrocompass equation.

Numeric comparisons allow 1e-13 relative: a few roundings in each formula.
"""

from __future__ import annotations

import importlib
import math
import sys

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble import shapes, symbolic, theory

SEEDS = [0, 1, 2]
RTOL = 1e-13


def as_float(matrix: sp.Matrix) -> np.ndarray:
    return np.array(matrix.evalf(30).tolist(), dtype=float)


# ----------------------------------------------------------------- import
def test_without_sympy_the_import_says_how_to_install_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "sympy", None)  # import sympy now raises ImportError
    monkeypatch.delitem(sys.modules, "tumble.symbolic")
    with pytest.raises(ImportError, match=r"tumble\.symbolic needs sympy, .*pip install sympy"):
        importlib.import_module("tumble.symbolic")


# ----------------------------------------------------------------- point masses
@pytest.mark.parametrize("seed", SEEDS)
def test_point_masses_match_tumble(seed: int) -> None:
    rng = np.random.default_rng(seed)
    masses = rng.uniform(0.1, 3.0, 5)
    positions = rng.uniform(-1.0, 1.0, (5, 3))
    mp = tb.point_masses(masses, positions)
    about_origin = symbolic.inertia_of_point_masses(masses, positions)  # numpy arrays too
    assert_allclose(
        as_float(about_origin), mp.inertia_about([0.0, 0.0, 0.0]), rtol=RTOL, atol=1e-15
    )
    center = symbolic.center_of_mass(list(masses), positions.tolist())
    assert_allclose(as_float(center).ravel(), mp.center_of_mass, rtol=RTOL)
    about_center = symbolic.inertia_of_point_masses(
        list(masses), positions.tolist(), about=list(center)
    )
    assert_allclose(as_float(about_center), mp.inertia, rtol=RTOL, atol=1e-14)


def test_point_mass_products_of_inertia_carry_a_minus_sign() -> None:
    m, x, y, z = sp.symbols("m x y z", real=True)
    tensor = symbolic.inertia_of_point_masses([m], [(x, y, z)])
    assert tensor == sp.Matrix(
        [
            [m * (y**2 + z**2), -m * x * y, -m * x * z],
            [-m * x * y, m * (x**2 + z**2), -m * y * z],
            [-m * x * z, -m * y * z, m * (x**2 + y**2)],
        ]
    ).applyfunc(sp.expand)
    # Exact with rationals: a unit mass at (1, 2, 3).
    assert symbolic.inertia_of_point_masses([1], [(1, 2, 3)]) == sp.Matrix(
        [[13, -2, -3], [-2, 10, -6], [-3, -6, 5]]
    )


# ----------------------------------------------------------------- solids
SOLIDS = [
    (symbolic.solid_cuboid, lambda m, a, b, c: shapes.box(m, (a, b, c)), 4),
    (symbolic.solid_cylinder, shapes.solid_cylinder, 3),
    (symbolic.solid_sphere, shapes.solid_sphere, 2),
    (symbolic.solid_cone, shapes.solid_cone, 3),
]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize(("exact", "numeric", "count"), SOLIDS)
def test_solids_match_tumble_shapes(exact, numeric, count: int, seed: int) -> None:
    values = np.random.default_rng(seed).uniform(0.05, 2.0, count)
    expected = numeric(*values).inertia
    assert_allclose(as_float(exact(*values)), expected, rtol=RTOL, atol=1e-16)


def test_solids_in_symbols() -> None:
    m, r, h = sp.symbols("m r h", positive=True)
    transverse = 3 * m * (r**2 / 20 + h**2 / 80)
    expected = sp.diag(transverse, transverse, 3 * m * r**2 / 10)
    assert sp.simplify(symbolic.solid_cone() - expected) == sp.zeros(3, 3)
    assert sp.simplify(symbolic.solid_sphere()[0, 0] - sp.Rational(2, 5) * m * r**2) == 0
    assert symbolic.solid_cylinder(mass=2, radius=sp.Rational(1, 2), height=1)[2, 2] == sp.Rational(
        1, 4
    )
    # Exact rationals give exact results.
    assert symbolic.solid_cuboid(12, 1, 2, 3) == sp.diag(13, 10, 5)


# ----------------------------------------------------------------- skew rod
@pytest.mark.parametrize("seed", SEEDS)
def test_skew_rod_matches_theory(seed: int) -> None:
    rng = np.random.default_rng(seed)
    mass, ell = rng.uniform(0.1, 2.0, 2)
    omega = rng.uniform(-50.0, 50.0)
    alpha = rng.uniform(-1.5, 1.5)
    rod = symbolic.skew_rod()
    symbols = {s.name: s for s in rod["angular_momentum"].free_symbols}
    values = {
        symbols["m"]: mass,
        symbols["ell"]: ell,
        symbols["omega"]: omega,
        symbols["alpha"]: alpha,
    }
    t = symbols["t"]
    f_l = sp.lambdify(t, rod["angular_momentum"].subs(values), "numpy")
    f_tau = sp.lambdify(t, rod["torque"].subs(values), "numpy")
    numeric = theory.skew_rod(mass, ell, alpha, omega)
    times = rng.uniform(0.0, 2.0, 4)
    scale = 2 * mass * ell**2 * abs(omega)
    for time in times:
        assert_allclose(np.ravel(f_l(time)), numeric.angular_momentum_at(time), atol=RTOL * scale)
        assert_allclose(
            np.ravel(f_tau(time)), numeric.torque_at(time), atol=RTOL * scale * abs(omega)
        )
    assert abs(float(rod["angular_momentum_norm"].subs(values))) == pytest.approx(
        numeric.angular_momentum, rel=RTOL
    )
    assert float(rod["angular_momentum_axial"].subs(values)) == pytest.approx(
        numeric.angular_momentum_axial, rel=RTOL
    )
    assert abs(float(rod["angular_momentum_transverse"].subs(values))) == pytest.approx(
        numeric.angular_momentum_transverse, rel=RTOL
    )
    assert abs(float(rod["torque_norm"].subs(values))) == pytest.approx(numeric.torque, rel=RTOL)


def test_skew_rod_is_consistent() -> None:
    rod = symbolic.skew_rod()
    momentum, torque = rod["angular_momentum"], rod["torque"]
    symbols = {s.name: s for s in momentum.free_symbols}
    m, ell, w, a, t = (symbols[n] for n in ("m", "ell", "omega", "alpha", "t"))
    # τ = dL/dt; the magnitudes square to L·L and τ·τ.
    assert sp.simplify(torque - momentum.diff(t)) == sp.zeros(3, 1)
    assert sp.simplify(momentum.dot(momentum) - rod["angular_momentum_norm"] ** 2) == 0
    assert sp.simplify(torque.dot(torque) - rod["torque_norm"] ** 2) == 0
    assert sp.simplify(momentum[2] - rod["angular_momentum_axial"]) == 0
    transverse2 = momentum[0] ** 2 + momentum[1] ** 2
    assert sp.simplify(transverse2 - rod["angular_momentum_transverse"] ** 2) == 0
    # L = I(t) ω with I(t) of the two point masses where they are at time t.
    r = sp.rot_ccw_axis3(w * t) * sp.Matrix([ell * sp.cos(a), 0, ell * sp.sin(a)])
    inertia = symbolic.inertia_of_point_masses([m, m], [list(r), list(-r)])
    assert sp.simplify(inertia * sp.Matrix([0, 0, w]) - momentum) == sp.zeros(3, 1)
    # The brief's forms: |L| = 2 m ℓ² ω cos α, |τ| = 2 m ℓ² ω² sin α cos α.
    assert rod["angular_momentum_norm"] == 2 * m * ell**2 * w * sp.cos(a)
    assert rod["torque_norm"] == 2 * m * ell**2 * w**2 * sp.sin(a) * sp.cos(a)


def test_skew_rod_with_given_values() -> None:
    rod = symbolic.skew_rod(
        mass=sp.Rational(1, 4), half_length=sp.Rational(1, 10), omega=10, alpha=sp.pi / 6, t=0
    )
    # 2 · ¼ · 1/100 · 10 · cos 30° = √3/40.
    assert sp.simplify(rod["angular_momentum_norm"] - sp.sqrt(3) / 40) == 0
    assert rod["angular_momentum"][1] == 0


# ----------------------------------------------------------------- Euler's equations
def test_euler_equations_in_the_principal_frame_are_the_textbook_form() -> None:
    equations = symbolic.euler_equations()
    t = sp.Symbol("t", real=True)
    i1, i2, i3 = sp.symbols("I_1 I_2 I_3", positive=True)
    w1, w2, w3 = (sp.Function(f"omega_{k}")(t) for k in (1, 2, 3))
    tau = [sp.Function(f"tau_{k}")(t) for k in (1, 2, 3)]
    textbook = [
        i1 * w1.diff(t) + (i3 - i2) * w2 * w3,
        i2 * w2.diff(t) + (i1 - i3) * w3 * w1,
        i3 * w3.diff(t) + (i2 - i1) * w1 * w2,
    ]
    for equation, left, right in zip(equations, textbook, tau, strict=True):
        assert sp.expand(equation.lhs - left) == 0
        assert equation.rhs == right


@pytest.mark.parametrize("seed", SEEDS)
def test_euler_equations_of_a_full_tensor_match_required_torque(seed: int) -> None:
    rng = np.random.default_rng(seed)
    moments = np.sort(rng.uniform(0.5, 2.0, 3))
    rotation = Rotation.random(random_state=seed).as_matrix()
    tensor = rotation @ np.diag(moments) @ rotation.T
    tensor = 0.5 * (tensor + tensor.T)
    mp = tb.MassProperties(1.0, [0.0, 0.0, 0.0], tensor)
    omega, omega_dot = rng.uniform(-3.0, 3.0, (2, 3))
    t = sp.Symbol("t", real=True)
    # ω(t) = ω0 + ω̇0 t: at t = 0 its value and derivative are omega and omega_dot.
    w = [sp.Float(omega[k]) + sp.Float(omega_dot[k]) * t for k in range(3)]
    equations = symbolic.euler_equations(sp.Matrix(tensor.tolist()), omega=w, torque=[0, 0, 0], t=t)
    left = np.array([float(eq.lhs.subs(t, 0)) for eq in equations])
    assert_allclose(left, tb.required_torque(mp, omega, omega_dot), rtol=1e-12, atol=1e-13)


def test_euler_equations_turn_with_the_body_axes() -> None:
    """With I' = R I Rᵀ and ω' = R ω, each side turns by R: the equations are frame-free."""
    t = sp.Symbol("t", real=True)
    i1, i2, i3 = sp.symbols("I_1 I_2 I_3", positive=True)
    # A rotation with rational entries (3-4-5 and 5-12-13 triangles), so that the
    # check is exact arithmetic.
    about_z = sp.Matrix([[3, -4, 0], [4, 3, 0], [0, 0, 5]]) / 5
    about_x = sp.Matrix([[13, 0, 0], [0, 5, -12], [0, 12, 5]]) / 13
    rotation = about_z * about_x
    w = sp.Matrix([sp.Function(f"w_{k}")(t) for k in (1, 2, 3)])
    principal = symbolic.euler_equations(i1, i2, i3, omega=list(w), torque=[0, 0, 0], t=t)
    turned = symbolic.euler_equations(
        rotation * sp.diag(i1, i2, i3) * rotation.T, omega=list(rotation * w), torque=[0, 0, 0], t=t
    )
    left = sp.Matrix([eq.lhs for eq in principal])
    left_turned = sp.Matrix([eq.lhs for eq in turned])
    assert sp.simplify(left_turned - rotation * left) == sp.zeros(3, 1)


# ----------------------------------------------------------------- gyrocompass
def test_gyrocompass_equation_is_the_documented_one() -> None:
    derived = symbolic.gyrocompass_equation()
    i_ab, i_s, big_omega, spin = (
        derived.gimbal_moment,
        derived.axial_moment,
        derived.platform_rate,
        derived.spin,
    )
    theta, t = derived.theta, derived.t
    spin_momentum = i_s * spin
    expected = -spin_momentum * big_omega * sp.sin(theta) + i_ab * big_omega**2 * sp.sin(
        theta
    ) * sp.cos(theta)
    assert sp.simplify(derived.equation.lhs - i_ab * theta.diff(t, 2)) == 0
    assert sp.simplify(derived.equation.rhs - expected) == 0
    assert sp.simplify(derived.angular_acceleration - expected / i_ab) == 0
    assert sp.simplify(derived.spin_rate - (derived.psi.diff(t) + big_omega * sp.cos(theta))) == 0
    beta2 = spin_momentum * big_omega / i_ab
    assert sp.simplify(derived.oscillation_frequency**2 - beta2) == 0
    assert sp.simplify(derived.small_angle_frequency**2 - (beta2 - big_omega**2)) == 0
    assert derived.stability_condition == sp.StrictGreaterThan(spin_momentum, i_ab * big_omega)


@pytest.mark.parametrize("seed", SEEDS)
def test_gyrocompass_matches_theory(seed: int) -> None:
    rng = np.random.default_rng(seed)
    disk = tb.shapes.solid_cylinder(
        rng.uniform(0.5, 2.0), rng.uniform(0.02, 0.1), rng.uniform(0.005, 0.05)
    )
    spin, platform = rng.uniform(20.0, 200.0), rng.uniform(0.5, 3.0)
    compass = theory.gyrocompass(disk, spin, platform)
    derived = symbolic.gyrocompass_equation()
    values = {
        derived.gimbal_moment: compass.gimbal_moment,
        derived.axial_moment: compass.axial_moment,
        derived.platform_rate: platform,
        derived.spin: spin,
    }
    q = sp.Symbol("q")
    f = sp.lambdify(q, derived.angular_acceleration.subs(values).subs(derived.theta, q), "numpy")
    angles = rng.uniform(-math.pi, math.pi, 6)
    # The two terms nearly cancel near θ = ±π/2 only when β ≈ Ω, not here: relative 1e-12.
    scale = compass.oscillation_frequency**2
    assert_allclose(f(angles), compass.angular_acceleration(angles), rtol=0, atol=1e-12 * scale)
    assert float(derived.oscillation_frequency.subs(values)) == pytest.approx(
        compass.oscillation_frequency, rel=RTOL
    )
    assert float(derived.small_angle_frequency.subs(values)) == pytest.approx(
        compass.small_oscillation_frequency, rel=RTOL
    )


def test_gyrocompass_stability_condition_is_where_theory_refuses() -> None:
    derived = symbolic.gyrocompass_equation()
    disk = tb.shapes.solid_cylinder(1.0, 0.05, 0.02)
    inertia = np.diag(disk.inertia)
    for spin, stable in ((1.0, False), (1.1, True)):  # the limit I_AB Ω / I_s = 1.0533 rad/s
        values = {
            derived.gimbal_moment: inertia[0],
            derived.axial_moment: inertia[2],
            derived.platform_rate: 2.0,
            derived.spin: spin,
        }
        assert bool(derived.stability_condition.subs(values)) is stable
        if stable:
            theory.gyrocompass(disk, spin, 2.0)
        else:
            with pytest.raises(tb.InputError, match=r"Expected \|`spin_rate`\| > I_AB"):
                theory.gyrocompass(disk, spin, 2.0)


# ----------------------------------------------------------------- errors
@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: symbolic.inertia_of_point_masses([1], [(0, 0)]),
            r"Expected `positions\[0\]` to have 3 coordinates, got 2\.",
        ),
        (
            lambda: symbolic.inertia_of_point_masses([1, 2], [(0, 0, 1)]),
            r"Expected `positions` to hold 2 points \(one per mass\), got 1\.",
        ),
        (
            lambda: symbolic.inertia_of_point_masses([-1], [(0, 0, 1)]),
            r"Expected `masses\[0\]` > 0, got -1\.",
        ),
        (
            lambda: symbolic.inertia_of_point_masses([], []),
            r"Expected `masses` to hold at least one mass, got none\.",
        ),
        (
            lambda: symbolic.inertia_of_point_masses("1", [(0, 0, 1)]),
            r"Expected `masses` to be a sequence of masses, got '1'\.",
        ),
        (
            lambda: symbolic.inertia_of_point_masses([1], [(0, 0, 1)], about=(0, 0)),
            r"Expected `about` to have 3 coordinates, got 2\.",
        ),
        (lambda: symbolic.solid_cylinder(mass=-1), r"Expected `mass` > 0, got -1\."),
        (lambda: symbolic.solid_sphere(radius=0), r"Expected `radius` > 0, got 0\."),
        (
            lambda: symbolic.solid_cone(height=object()),
            r"Expected `height` to be a number or a sympy expression, got <object object",
        ),
        (
            lambda: symbolic.euler_equations(1, 2),
            r"Expected three principal moments or one 3 × 3 inertia tensor, got 2 arguments\.",
        ),
        (
            lambda: symbolic.euler_equations(sp.Matrix([[1, 2, 0], [0, 1, 0], [0, 0, 1]])),
            r"Expected a symmetric inertia tensor, got \[\[1, 2, 0\], \[0, 1, 0\], \[0, 0, 1\]\]\.",
        ),
        (
            lambda: symbolic.euler_equations(sp.eye(2)),
            r"Expected a 3 × 3 inertia tensor, got shape \(2, 2\)\.",
        ),
    ],
)
def test_bad_input_is_refused(call, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()


def test_positions_must_be_points() -> None:
    with pytest.raises(
        tb.InputError, match=r"Expected `positions` to be a sequence of points, got 3"
    ):
        symbolic.inertia_of_point_masses([1], 3)
