"""Exact, symbolic counterparts of tumble's numbers, derived with sympy.

For checking a derivation by hand, teaching, and as an independent oracle:

* :func:`inertia_of_point_masses`, :func:`center_of_mass` — ``I = Σ m (r² E − r rᵀ)``,
  products of inertia ``I_xy = −Σ m x y``.
* :func:`solid_cuboid`, :func:`solid_cylinder`, :func:`solid_sphere`,
  :func:`solid_cone` — inertia tensors about the centre of mass, obtained by
  integrating a uniform density over the solid (the conventions of
  :mod:`tumble.shapes`).
* :func:`skew_rod` — L = Σ m r × ṙ and τ = dL/dt of the rotating skew rod.
* :func:`euler_equations` — ``I ω̇ + ω × (I ω) = τ`` in the principal frame or
  any body frame.
* :func:`gyrocompass_equation` — the gimballed gyroscope on a turning platform,
  from its Lagrangian.

sympy is needed (a development dependency of tumble, not a runtime one):
``pip install sympy``.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

try:
    import sympy as sp  # type: ignore[import-untyped]
except ImportError as exc:  # sympy is optional for tumble's numeric API
    raise ImportError(
        "tumble.symbolic needs sympy, which is not installed: pip install sympy"
    ) from exc

from tumble.errors import InputError

__all__ = [
    "GyrocompassEquation",
    "center_of_mass",
    "euler_equations",
    "gyrocompass_equation",
    "inertia_of_point_masses",
    "skew_rod",
    "solid_cone",
    "solid_cuboid",
    "solid_cylinder",
    "solid_sphere",
]


# ----------------------------------------------------------------- helpers
def _expression(value: Any, name: str, default: Any) -> Any:
    """A sympy expression from a number, a string or an expression (``default`` for None)."""
    if value is None:
        return default
    try:
        return sp.sympify(value, strict=not isinstance(value, str))
    except (sp.SympifyError, TypeError, SyntaxError) as error:
        raise InputError(
            f"Expected `{name}` to be a number or a sympy expression, got {value!r} ({error})."
        ) from None


def _value(value: Any, name: str, default: Any) -> Any:
    """As :func:`_expression`, refusing a value known to be zero or negative."""
    expr = _expression(value, name, default)
    if expr.is_positive is False:
        raise InputError(f"Expected `{name}` > 0, got {expr}.")
    return expr


def _point(value: Any, name: str) -> Any:
    """A 3 × 1 sympy Matrix from a sequence of three expressions."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, str) or not isinstance(value, Sequence | sp.MatrixBase):
        raise InputError(f"Expected `{name}` to be three coordinates, got {value!r}.")
    items = list(value)
    if len(items) != 3:
        raise InputError(f"Expected `{name}` to have 3 coordinates, got {len(items)}.")
    return sp.Matrix([_expression(v, f"{name}[{k}]", None) for k, v in enumerate(items)])


def _points(masses: Any, positions: Any) -> tuple[list[Any], list[Any]]:
    if isinstance(masses, np.ndarray):
        masses = masses.tolist()
    if isinstance(positions, np.ndarray):
        positions = positions.tolist()
    if isinstance(masses, str) or not isinstance(masses, Sequence | sp.MatrixBase):
        raise InputError(f"Expected `masses` to be a sequence of masses, got {masses!r}.")
    if isinstance(positions, str) or not isinstance(positions, Sequence | sp.MatrixBase):
        raise InputError(f"Expected `positions` to be a sequence of points, got {positions!r}.")
    weights = [_value(m, f"masses[{k}]", None) for k, m in enumerate(masses)]
    if not weights:
        raise InputError("Expected `masses` to hold at least one mass, got none.")
    if isinstance(positions, sp.MatrixBase):
        rows = [positions.row(k) for k in range(positions.rows)]
    else:
        rows = list(positions)
    if len(rows) != len(weights):
        raise InputError(
            f"Expected `positions` to hold {len(weights)} points (one per mass), got {len(rows)}."
        )
    return weights, [_point(r, f"positions[{k}]") for k, r in enumerate(rows)]


def _pythagoras(expr: Any, angles: Sequence[Any]) -> Any:
    """``expr`` expanded with ``sin² a = 1 − cos² a`` for each angle: a fast, exact
    trigonometric simplification (sympy's general ``simplify`` takes seconds here)."""
    expr = sp.expand(expr)
    for angle in angles:
        expr = sp.expand(expr.subs(sp.sin(angle) ** 2, 1 - sp.cos(angle) ** 2))
    return expr


def _second_moment_tensor(r: Any) -> Any:
    """``r² E − r rᵀ`` of a 3 × 1 position."""
    return (r.T * r)[0] * sp.eye(3) - r * r.T


# ----------------------------------------------------------------- point masses
def center_of_mass(masses: Any, positions: Any) -> Any:
    """Centre of mass ``Σ m r / Σ m`` of point masses, a 3 × 1 sympy Matrix.

    ``masses``: n numbers or expressions (positive where the sign is known);
    ``positions``: n points of three coordinates (or an n × 3 Matrix).
    """
    weights, points = _points(masses, positions)
    total = sp.Add(*weights)
    return sp.simplify(
        sum((m * r for m, r in zip(weights, points, strict=True)), sp.zeros(3, 1)) / total
    )


def inertia_of_point_masses(masses: Any, positions: Any, about: Any = None) -> Any:
    """Exact inertia tensor of point masses, ``I = Σ m ((r·r) E − r rᵀ)``, a 3 × 3 sympy Matrix.

    Positions are measured from ``about`` (default the origin of the
    coordinates; pass :func:`center_of_mass` for the tensor about the centre of
    mass, as :attr:`tumble.MassProperties.inertia` holds). Diagonal:
    ``I_xx = Σ m (y² + z²)``; products of inertia carry a minus sign,
    ``I_xy = −Σ m x y``.

    Raises
    ------
    InputError
        If the counts differ, a point has not three coordinates, or a mass is
        known to be non-positive.
    """
    weights, points = _points(masses, positions)
    origin = sp.zeros(3, 1) if about is None else _point(about, "about")
    tensor = sp.zeros(3, 3)
    for m, r in zip(weights, points, strict=True):
        tensor += m * _second_moment_tensor(r - origin)
    return tensor.applyfunc(sp.expand)


# ----------------------------------------------------------------- solids
_M, _A, _B, _C = sp.symbols("m a b c", positive=True)
_R, _H = sp.symbols("r h", positive=True)


def _integrate_solid(position: Any, jacobian: Any, limits: list[tuple[Any, Any, Any]]) -> Any:
    """Volume, first moments and inertia (per unit density) about the origin of a solid.

    ``position`` is the point (3 × 1) as a function of the integration
    variables, ``jacobian`` the volume element, ``limits`` innermost first.
    """

    def integral(expr: Any) -> Any:
        return sp.integrate(sp.expand(expr * jacobian), *limits)

    volume = integral(sp.Integer(1))
    first = sp.Matrix([integral(p) for p in position])
    second = _second_moment_tensor(position)
    tensor = sp.zeros(3, 3)
    for i in range(3):
        for j in range(i, 3):
            tensor[i, j] = tensor[j, i] = integral(second[i, j])
    return volume, first, tensor


def _about_center(mass: Any, volume: Any, first: Any, tensor: Any) -> Any:
    """Inertia about the centre of mass of a uniform solid of the given mass
    (parallel-axis theorem from the origin's tensor)."""
    density = mass / volume
    center = first / volume
    return (density * tensor - mass * _second_moment_tensor(center)).applyfunc(sp.simplify)


@functools.cache
def _cuboid() -> Any:
    x, y, z = sp.symbols("x y z", real=True)
    limits = [(x, -_A / 2, _A / 2), (y, -_B / 2, _B / 2), (z, -_C / 2, _C / 2)]
    return _about_center(_M, *_integrate_solid(sp.Matrix([x, y, z]), 1, limits))


@functools.cache
def _cylinder() -> Any:
    s, phi, z = sp.symbols("s phi z", real=True)
    position = sp.Matrix([s * sp.cos(phi), s * sp.sin(phi), z])
    limits = [(s, 0, _R), (phi, 0, 2 * sp.pi), (z, -_H / 2, _H / 2)]
    return _about_center(_M, *_integrate_solid(position, s, limits))


@functools.cache
def _sphere() -> Any:
    rho, polar, phi = sp.symbols("rho theta phi", real=True)
    position = sp.Matrix(
        [
            rho * sp.sin(polar) * sp.cos(phi),
            rho * sp.sin(polar) * sp.sin(phi),
            rho * sp.cos(polar),
        ]
    )
    limits = [(rho, 0, _R), (polar, 0, sp.pi), (phi, 0, 2 * sp.pi)]
    return _about_center(_M, *_integrate_solid(position, rho**2 * sp.sin(polar), limits))


@functools.cache
def _cone() -> Any:
    # Base of radius r on z = 0, apex at z = h; the centre of mass at z = h/4 is
    # found by the integration, and the tensor moved to it, apex then at +3h/4.
    s, phi, z = sp.symbols("s phi z", real=True)
    position = sp.Matrix([s * sp.cos(phi), s * sp.sin(phi), z])
    limits = [(s, 0, _R * (1 - z / _H)), (phi, 0, 2 * sp.pi), (z, 0, _H)]
    return _about_center(_M, *_integrate_solid(position, s, limits))


def solid_cuboid(mass: Any = None, a: Any = None, b: Any = None, c: Any = None) -> Any:
    """Inertia of a uniform solid cuboid with full edges a, b, c along x, y, z, about
    its centre (as :func:`tumble.shapes.box`): ``diag(m (b² + c²), m (a² + c²),
    m (a² + b²)) / 12``, derived by integration.

    Each argument is a number or a sympy expression; left out, it stays the
    positive symbol ``m``, ``a``, ``b`` or ``c``. Returns a 3 × 3 sympy Matrix.
    """
    values = {
        _M: _value(mass, "mass", _M),
        _A: _value(a, "a", _A),
        _B: _value(b, "b", _B),
        _C: _value(c, "c", _C),
    }
    return _cuboid().xreplace(values)


def solid_cylinder(mass: Any = None, radius: Any = None, height: Any = None) -> Any:
    """Inertia of a uniform solid cylinder, symmetry axis z, about its centre of mass
    (as :func:`tumble.shapes.solid_cylinder`): ``I_zz = m r² / 2``,
    ``I_xx = I_yy = m (3 r² + h²) / 12``, derived by integration.

    Arguments left out stay the positive symbols ``m``, ``r``, ``h``.
    """
    values = {
        _M: _value(mass, "mass", _M),
        _R: _value(radius, "radius", _R),
        _H: _value(height, "height", _H),
    }
    return _cylinder().xreplace(values)


def solid_sphere(mass: Any = None, radius: Any = None) -> Any:
    """Inertia of a uniform solid sphere about its centre: ``2 m r² / 5 E``, derived
    by integration. Arguments left out stay the positive symbols ``m``, ``r``."""
    values = {_M: _value(mass, "mass", _M), _R: _value(radius, "radius", _R)}
    return _sphere().xreplace(values)


def solid_cone(mass: Any = None, radius: Any = None, height: Any = None) -> Any:
    """Inertia of a uniform solid right circular cone, axis z, apex at +z, about its
    centre of mass (h/4 above the base; as :func:`tumble.shapes.solid_cone`):
    ``I_zz = 3 m r² / 10``, ``I_xx = I_yy = m (3 r² / 20 + 3 h² / 80)``, derived by
    integration. Arguments left out stay the positive symbols ``m``, ``r``, ``h``.
    """
    values = {
        _M: _value(mass, "mass", _M),
        _R: _value(radius, "radius", _R),
        _H: _value(height, "height", _H),
    }
    return _cone().xreplace(values)


# ----------------------------------------------------------------- skew rod
def skew_rod(
    mass: Any = None,
    half_length: Any = None,
    omega: Any = None,
    alpha: Any = None,
    t: Any = None,
) -> dict[str, Any]:
    """Angular momentum and torque of the rotating skew rod, derived from L = Σ m r × ṙ.

    Two point masses m at ±r(t) on a massless rod through the origin, at angle α
    to the plane perpendicular to the spin axis z, turn at the constant rate ω:
    ``r(t) = Rz(ω t) ℓ (cos α, 0, sin α)`` (the convention of
    :func:`tumble.theory.skew_rod`).

    Parameters
    ----------
    mass, half_length, omega, alpha, t : numbers or sympy expressions; left out,
        the symbols ``m``, ``ell`` (positive) and ``omega``, ``alpha``, ``t`` (real).

    Returns
    -------
    dict of sympy expressions:

    * ``"angular_momentum"``: L(t), 3 × 1, in space coordinates,
      ``2 m ℓ² ω cos α (−sin α cos ωt, −sin α sin ωt, cos α)``;
    * ``"angular_momentum_norm"``: ``2 m ℓ² ω cos α`` (|L| where ω cos α ≥ 0; its
      absolute value in general);
    * ``"angular_momentum_axial"``: ``2 m ℓ² ω cos² α``, the part along ω;
    * ``"angular_momentum_transverse"``: ``2 m ℓ² ω sin α cos α``, the part
      perpendicular to ω (signed), which sweeps a circle at ω;
    * ``"torque"``: τ(t) = dL/dt, 3 × 1;
    * ``"torque_norm"``: ``2 m ℓ² ω² sin α cos α`` (|τ| up to its sign).
    """
    m = _value(mass, "mass", sp.Symbol("m", positive=True))
    ell = _value(half_length, "half_length", sp.Symbol("ell", positive=True))
    w = _expression(omega, "omega", sp.Symbol("omega", real=True))
    a = _expression(alpha, "alpha", sp.Symbol("alpha", real=True))
    time = _expression(t, "t", sp.Symbol("t", real=True))
    clock = sp.Dummy("t", real=True)
    position = sp.rot_ccw_axis3(w * clock) * sp.Matrix([ell * sp.cos(a), 0, ell * sp.sin(a)])
    momentum = sp.zeros(3, 1)
    for r in (position, -position):
        momentum += m * r.cross(r.diff(clock))
    angles = (w * clock, a)
    momentum = momentum.applyfunc(lambda e: sp.factor_terms(_pythagoras(e, angles)))
    torque = momentum.diff(clock).applyfunc(lambda e: sp.factor_terms(_pythagoras(e, angles)))
    scale = 2 * m * ell**2 * w
    return {
        "angular_momentum": momentum.xreplace({clock: time}),
        "angular_momentum_norm": scale * sp.cos(a),
        "angular_momentum_axial": scale * sp.cos(a) ** 2,
        "angular_momentum_transverse": scale * sp.sin(a) * sp.cos(a),
        "torque": torque.xreplace({clock: time}),
        "torque_norm": scale * w * sp.sin(a) * sp.cos(a),
    }


# ----------------------------------------------------------------- Euler's equations
def euler_equations(
    *inertia: Any, omega: Any = None, torque: Any = None, t: Any = None
) -> list[Any]:
    """Euler's equations ``I ω̇ + ω × (I ω) = τ``, all in body coordinates.

    Call with three principal moments, ``euler_equations(I1, I2, I3)`` (the
    principal frame: ``I1 ω̇1 + (I3 − I2) ω2 ω3 = τ1`` and cyclic), with one
    3 × 3 symmetric inertia tensor (any body frame), or with nothing (the
    positive symbols ``I_1, I_2, I_3``).

    Parameters
    ----------
    omega : three expressions of ``t`` for ω in body coordinates; default the
        functions ``omega_1(t), omega_2(t), omega_3(t)``.
    torque : three expressions for τ in body coordinates; default the
        functions ``tau_1(t), tau_2(t), tau_3(t)``.
    t : the time symbol; default ``t`` (real).

    Returns
    -------
    list of three ``sympy.Eq`` (left side ``I ω̇ + ω × (I ω)``, right side τ).

    Raises
    ------
    InputError
        If neither three moments nor one 3 × 3 symmetric tensor are given.
    """
    time = _expression(t, "t", sp.Symbol("t", real=True))
    if len(inertia) == 0:
        tensor = sp.diag(*sp.symbols("I_1 I_2 I_3", positive=True))
    elif len(inertia) == 3:
        tensor = sp.diag(*[_value(v, f"I{k + 1}", None) for k, v in enumerate(inertia)])
    elif len(inertia) == 1:
        tensor = sp.Matrix(inertia[0])
        if tensor.shape != (3, 3):
            raise InputError(f"Expected a 3 × 3 inertia tensor, got shape {tensor.shape}.")
        if not (tensor - tensor.T).applyfunc(sp.simplify).is_zero_matrix:
            raise InputError(f"Expected a symmetric inertia tensor, got {tensor.tolist()}.")
    else:
        raise InputError(
            "Expected three principal moments or one 3 × 3 inertia tensor, "
            f"got {len(inertia)} arguments."
        )
    if omega is None:
        w = sp.Matrix([sp.Function(f"omega_{k}")(time) for k in (1, 2, 3)])
    else:
        w = _point(omega, "omega")
    if torque is None:
        tau = sp.Matrix([sp.Function(f"tau_{k}")(time) for k in (1, 2, 3)])
    else:
        tau = _point(torque, "torque")
    left = tensor * w.diff(time) + w.cross(tensor * w)
    return [sp.Eq(sp.expand(left[k]), tau[k], evaluate=False) for k in range(3)]


# ----------------------------------------------------------------- gyrocompass
@dataclass(frozen=True, eq=False)
class GyrocompassEquation:
    """The gimballed gyroscope on a platform turning at Ω (see :func:`gyrocompass_equation`).

    Attributes (sympy expressions in the symbols below)
    ----------
    equation : ``Eq(I_AB θ̈, −L_s Ω sin θ + I_AB Ω² sin θ cos θ)``, L_s = I_s ω_s.
    angular_acceleration : θ̈ as a function of θ.
    spin_rate : ``ψ̇ + Ω cos θ``, the spin ω_s about the disk's axis, conserved
        (ψ is cyclic).
    small_angle_frequency : ``√(Ω (L_s − I_AB Ω) / I_AB)``, the exact frequency of
        small oscillations (from the linearised equation), real only when
        ``stability_condition`` holds.
    oscillation_frequency : β = ``√(L_s Ω / I_AB)``: the small-angle frequency with
        the Ω² term dropped, valid for small θ (sin θ ≈ θ) and ``I_AB Ω ≪ L_s``
        (ω_s ≫ Ω when I_AB ~ I_s); its relative error is about I_AB Ω / (2 L_s).
    stability_condition : ``L_s > I_AB Ω``: the direction of Ω is stable.
    t, theta, psi : the time symbol and the angle functions θ(t), ψ(t).
    gimbal_moment, axial_moment, platform_rate, spin : the positive symbols
        I_AB, I_s, Ω and ω_s.
    """

    equation: Any
    angular_acceleration: Any
    spin_rate: Any
    small_angle_frequency: Any
    oscillation_frequency: Any
    stability_condition: Any
    t: Any
    theta: Any
    psi: Any
    gimbal_moment: Any
    axial_moment: Any
    platform_rate: Any
    spin: Any


@functools.cache
def gyrocompass_equation() -> GyrocompassEquation:
    """The equation of motion of the gyrocompass, derived from its Lagrangian.

    A disk (moment I_s about its spin axis, I_AB about any transverse axis
    through its centre) is pivoted at its centre in a massless gimbal free to
    turn about a horizontal axis AB (body x at ψ = 0); the mount turns about the
    vertical z at a constant rate Ω. The attitude is
    ``R = Rz(Ω t) Rx(θ) Rz(ψ)``, the body angular velocity comes from
    ``[ω]× = Rᵀ Ṙ`` and the Lagrangian is the kinetic energy
    ``T = ½ ωᵀ diag(I_AB, I_AB, I_s) ω``. ψ is cyclic, so
    ``ω_s = ∂T/∂ψ̇ / I_s = ψ̇ + Ω cos θ`` is conserved; with it the θ equation
    ``d/dt ∂T/∂θ̇ = ∂T/∂θ`` becomes

        ``I_AB θ̈ = −L_s Ω sin θ + I_AB Ω² sin θ cos θ``,  L_s = I_s ω_s,

    the equation of :func:`tumble.theory.gyrocompass` (the lecture notes drop
    the Ω² term). Linearised about θ = 0 it gives the exact small-angle
    frequency ``√(β² − Ω²)``, with ``β = √(L_s Ω / I_AB)``, stable when
    ``L_s > I_AB Ω``; β alone is the small-angle frequency when also
    ``I_AB Ω ≪ L_s``.
    """
    t = sp.Symbol("t", real=True)
    i_ab, i_s, big_omega, spin = sp.symbols("I_AB I_s Omega omega_s", positive=True)
    theta, psi = sp.Function("theta")(t), sp.Function("psi")(t)
    rotation = sp.rot_ccw_axis3(big_omega * t) * sp.rot_ccw_axis1(theta) * sp.rot_ccw_axis3(psi)
    angles = (big_omega * t, theta, psi)
    skew = (rotation.T * rotation.diff(t)).applyfunc(lambda e: _pythagoras(e, angles))
    w = sp.Matrix([skew[2, 1], skew[0, 2], skew[1, 0]])
    kinetic = _pythagoras(sp.Rational(1, 2) * (w.T * sp.diag(i_ab, i_ab, i_s) * w)[0], angles)
    spin_rate = sp.expand(kinetic.diff(psi.diff(t)) / i_s)
    theta_equation = sp.diff(kinetic.diff(theta.diff(t)), t) - kinetic.diff(theta)
    # ψ̇ from the conserved spin: ψ̇ = ω_s − (spin_rate − ψ̇).
    psi_rate = spin - (spin_rate - psi.diff(t))
    theta_equation = sp.expand(theta_equation.subs(psi.diff(t), psi_rate))
    # The equation is linear in θ̈: a θ̈ + b = 0.
    theta_dd = theta.diff(t, 2)
    coefficient = theta_equation.diff(theta_dd)
    acceleration = sp.expand(-theta_equation.subs(theta_dd, 0) / coefficient)
    momentum = i_s * spin
    rhs = sp.expand(i_ab * acceleration)
    x = sp.Dummy("x", real=True)
    stiffness = -sp.diff(acceleration.subs(theta, x), x).subs(x, 0)
    return GyrocompassEquation(
        equation=sp.Eq(i_ab * theta.diff(t, 2), rhs),
        angular_acceleration=acceleration,
        spin_rate=spin_rate,
        small_angle_frequency=sp.sqrt(sp.factor(sp.simplify(stiffness))),
        oscillation_frequency=sp.sqrt(momentum * big_omega / i_ab),
        stability_condition=sp.StrictGreaterThan(momentum, i_ab * big_omega),
        t=t,
        theta=theta,
        psi=psi,
        gimbal_moment=i_ab,
        axial_moment=i_s,
        platform_rate=big_omega,
        spin=spin,
    )
