"""Independent symbolic oracle for ``tumble.shapes``.

Every inertia tensor here is derived with sympy by integrating a uniform density over the
body's geometry (volume, surface or line integrals); nothing is copied from a table or from
tumble's source.  Convention: I_ij = ∫ ρ (r² δ_ij − x_i x_j) dV about the centre of mass, in
body axes, SI units.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp

from tumble import shapes

# Symbols shared by all derivations (positive so that sympy can simplify sqrt, |det|, ...).
m = sp.Symbol("m", positive=True)
a, b, c = sp.symbols("a b c", positive=True)
R, r, h, L = sp.symbols("R r h L", positive=True)
r_in, r_out = sp.symbols("r_in r_out", positive=True)

# Integration variables.
x, y, z = sp.symbols("x y z", real=True)
s, t, u, v, w = sp.symbols("s t u v w", real=True)
theta, phi, rho = sp.symbols("theta phi rho", real=True)

TWO_PI = 2 * sp.pi


# ---------------------------------------------------------------------------------------------
# Generic integration helpers
# ---------------------------------------------------------------------------------------------


def _integrate(expr, limits):
    """Integrate ``expr`` over the nested ``limits`` (innermost first) and simplify."""
    return sp.simplify(sp.integrate(sp.expand(expr), *limits))


def _measure_and_moments(pos, jac, limits, full=True):
    """Integrate 1 and x_i x_j (times the Jacobian ``jac``) over a parametrised region.

    ``pos`` is the position (x, y, z) as functions of the integration variables, ``limits``
    the nested integration limits.  Returns (measure, S) with S_ij = ∫ x_i x_j dμ.  With
    ``full=False`` the body is assumed axisymmetric about z: only S_xx and S_zz are
    integrated, S_yy = S_xx is set by symmetry and the products of inertia are set to zero.
    """
    measure = _integrate(jac, limits)
    S = sp.zeros(3, 3)
    if full:
        for i in range(3):
            for j in range(i, 3):
                S[i, j] = S[j, i] = _integrate(pos[i] * pos[j] * jac, limits)
    else:
        S[0, 0] = S[1, 1] = _integrate(pos[0] ** 2 * jac, limits)
        S[2, 2] = _integrate(pos[2] ** 2 * jac, limits)
    return measure, S


def _first_moments(pos, jac, limits):
    """Integrate x_i (times the Jacobian) over the region: the un-normalised COM."""
    return sp.Matrix([_integrate(p * jac, limits) for p in pos])


def _inertia_from_moments(mass, measure, S):
    """Inertia ρ (tr(S) 1 − S) with uniform density ρ = mass / measure."""
    density = mass / measure
    return (density * (S.trace() * sp.eye(3) - S)).applyfunc(sp.simplify)


def _cyl(radial, z_expr=None):
    """Cylindrical-coordinate position (s cos t, s sin t, z) with optional shifted z."""
    return (radial * sp.cos(t), radial * sp.sin(t), z if z_expr is None else z_expr)


def _sph(radius, x_scale=1, y_scale=1, z_scale=1, z_offset=0):
    """Spherical-coordinate position (ρ sinθ cosφ, ρ sinθ sinφ, ρ cosθ), optionally scaled."""
    return (
        x_scale * radius * sp.sin(theta) * sp.cos(phi),
        y_scale * radius * sp.sin(theta) * sp.sin(phi),
        z_scale * radius * sp.cos(theta) + z_offset,
    )


# ---------------------------------------------------------------------------------------------
# Derivations: each returns (dimension symbols, inertia Matrix in m and those symbols)
# ---------------------------------------------------------------------------------------------


@functools.cache
def box_inertia():
    """Cartesian triple integral over [-a/2, a/2] × [-b/2, b/2] × [-c/2, c/2], full tensor."""
    limits = [(x, -a / 2, a / 2), (y, -b / 2, b / 2), (z, -c / 2, c / 2)]
    vol, S = _measure_and_moments((x, y, z), sp.Integer(1), limits, full=True)
    return (a, b, c), _inertia_from_moments(m, vol, S)


@functools.cache
def solid_cylinder_inertia():
    """Cylindrical integral, s ∈ [0, R], t ∈ [0, 2π], z ∈ [-h/2, h/2], Jacobian s."""
    limits = [(s, 0, R), (t, 0, TWO_PI), (z, -h / 2, h / 2)]
    vol, S = _measure_and_moments(_cyl(s), s, limits, full=False)
    return (R, h), _inertia_from_moments(m, vol, S)


@functools.cache
def hollow_cylinder_inertia():
    """Cylindrical integral, s ∈ [r_in, r_out], t ∈ [0, 2π], z ∈ [-h/2, h/2], Jacobian s."""
    limits = [(s, r_in, r_out), (t, 0, TWO_PI), (z, -h / 2, h / 2)]
    vol, S = _measure_and_moments(_cyl(s), s, limits, full=False)
    return (r_in, r_out, h), _inertia_from_moments(m, vol, S)


@functools.cache
def solid_sphere_inertia():
    """Spherical integral, ρ ∈ [0, R], θ ∈ [0, π], φ ∈ [0, 2π], Jacobian ρ² sinθ."""
    limits = [(rho, 0, R), (theta, 0, sp.pi), (phi, 0, TWO_PI)]
    vol, S = _measure_and_moments(_sph(rho), rho**2 * sp.sin(theta), limits, full=False)
    return (R,), _inertia_from_moments(m, vol, S)


@functools.cache
def hollow_sphere_inertia():
    """Spherical integral, ρ ∈ [r_in, r_out], θ ∈ [0, π], φ ∈ [0, 2π], Jacobian ρ² sinθ."""
    limits = [(rho, r_in, r_out), (theta, 0, sp.pi), (phi, 0, TWO_PI)]
    vol, S = _measure_and_moments(_sph(rho), rho**2 * sp.sin(theta), limits, full=False)
    return (r_in, r_out), _inertia_from_moments(m, vol, S)


@functools.cache
def spherical_shell_inertia():
    """Surface integral over the sphere of radius R, area element R² sinθ dθ dφ."""
    limits = [(theta, 0, sp.pi), (phi, 0, TWO_PI)]
    area, S = _measure_and_moments(_sph(R), R**2 * sp.sin(theta), limits, full=False)
    return (R,), _inertia_from_moments(m, area, S)


def _cone_limits():
    """Cone with base (radius R) at z = 0 and apex at z = h: s ∈ [0, R (1 − z/h)]."""
    return [(s, 0, R * (1 - z / h)), (t, 0, TWO_PI), (z, 0, h)]


@functools.cache
def cone_com_height():
    """COM height of the cone with base at z = 0: ∫ z dV / ∫ dV (cylindrical, Jacobian s)."""
    limits = _cone_limits()
    vol = _integrate(s, limits)
    return sp.simplify(_first_moments(_cyl(s), s, limits)[2] / vol)


@functools.cache
def solid_cone_inertia():
    """Cylindrical integral over the cone, z measured from the COM, full tensor."""
    z_com = cone_com_height()
    vol, S = _measure_and_moments(_cyl(s, z - z_com), s, _cone_limits(), full=True)
    return (R, h), _inertia_from_moments(m, vol, S)


@functools.cache
def thin_rod_inertia():
    """Line integral along the z axis, z ∈ [-L/2, L/2], line element dz."""
    length, S = _measure_and_moments((0, 0, z), sp.Integer(1), [(z, -L / 2, L / 2)], full=True)
    return (L,), _inertia_from_moments(m, length, S)


@functools.cache
def thin_disk_inertia():
    """Surface integral over the disk s ≤ R in the plane z = 0, area element s ds dt."""
    limits = [(s, 0, R), (t, 0, TWO_PI)]
    area, S = _measure_and_moments(_cyl(s, sp.Integer(0)), s, limits, full=True)
    return (R,), _inertia_from_moments(m, area, S)


@functools.cache
def thin_ring_inertia():
    """Line integral over the circle of radius R in the plane z = 0, line element R dt."""
    area, S = _measure_and_moments(_cyl(R, sp.Integer(0)), R, [(t, 0, TWO_PI)], full=True)
    return (R,), _inertia_from_moments(m, area, S)


@functools.cache
def ellipsoid_inertia():
    """Unit ball mapped by diag(a, b, c): spherical integral with Jacobian a b c ρ² sinθ."""
    limits = [(rho, 0, 1), (theta, 0, sp.pi), (phi, 0, TWO_PI)]
    pos = _sph(rho, x_scale=a, y_scale=b, z_scale=c)
    vol, S = _measure_and_moments(pos, a * b * c * rho**2 * sp.sin(theta), limits, full=True)
    return (a, b, c), _inertia_from_moments(m, vol, S)


@functools.cache
def torus_inertia():
    """Solid torus via ((R + ρ cosφ) cos t, (R + ρ cosφ) sin t, ρ sinφ), ρ ∈ [0, r].

    Jacobian ρ (R + ρ cosφ); every integrand is a polynomial in ρ, cos and sin.
    """
    ring = R + rho * sp.cos(phi)
    pos = (ring * sp.cos(t), ring * sp.sin(t), rho * sp.sin(phi))
    limits = [(t, 0, TWO_PI), (phi, 0, TWO_PI), (rho, 0, r)]
    vol, S = _measure_and_moments(pos, rho * ring, limits, full=False)
    return (R, r), _inertia_from_moments(m, vol, S)


@functools.cache
def capsule_inertia():
    """Cylinder (|z| ≤ h/2, s ≤ r) plus two solid hemispherical caps of radius r.

    The caps are integrated in spherical coordinates centred on (0, 0, ±h/2), θ ∈ [0, π/2]
    for the top cap and θ ∈ [π/2, π] for the bottom cap; all about the capsule centre.
    """
    cyl_limits = [(s, 0, r), (t, 0, TWO_PI), (z, -h / 2, h / 2)]
    vol_c, S_c = _measure_and_moments(_cyl(s), s, cyl_limits, full=False)
    jac = rho**2 * sp.sin(theta)
    top_limits = [(rho, 0, r), (theta, 0, sp.pi / 2), (phi, 0, TWO_PI)]
    vol_t, S_t = _measure_and_moments(_sph(rho, z_offset=h / 2), jac, top_limits, full=False)
    bot_limits = [(rho, 0, r), (theta, sp.pi / 2, sp.pi), (phi, 0, TWO_PI)]
    vol_b, S_b = _measure_and_moments(_sph(rho, z_offset=-h / 2), jac, bot_limits, full=False)
    vol = sp.simplify(vol_c + vol_t + vol_b)
    S = (S_c + S_t + S_b).applyfunc(sp.simplify)
    return (r, h), _inertia_from_moments(m, vol, S)


TETRA_VERTICES = sp.Matrix([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])


def _tetra_param():
    """Affine map of the unit simplex (u, v, w) onto the tetrahedron with edge a.

    The vertices (±1, ±1, ±1) with an even number of minus signs have edge 2√2, so they are
    scaled by k = a / (2√2).  Returns (position, |Jacobian|, limits).
    """
    k = a / (2 * sp.sqrt(2))
    v0 = TETRA_VERTICES.row(0).T
    edges = sp.Matrix.hstack(*[TETRA_VERTICES.row(i).T - v0 for i in (1, 2, 3)])
    pos = k * (v0 + edges * sp.Matrix([u, v, w]))
    jac = sp.simplify(sp.Abs(k**3 * edges.det()))
    limits = [(w, 0, 1 - u - v), (v, 0, 1 - u), (u, 0, 1)]
    return tuple(pos), jac, limits


@functools.cache
def tetrahedron_com():
    """∫ x_i dV over the tetrahedron (should vanish: the vertices sum to zero)."""
    pos, jac, limits = _tetra_param()
    return _first_moments(pos, jac, limits)


@functools.cache
def regular_tetrahedron_inertia():
    """Integral over the unit simplex mapped affinely onto the tetrahedron, full tensor."""
    pos, jac, limits = _tetra_param()
    vol, S = _measure_and_moments(pos, jac, limits, full=True)
    return (a,), _inertia_from_moments(m, vol, S)


# ---------------------------------------------------------------------------------------------
# Evaluation and comparison helpers
# ---------------------------------------------------------------------------------------------


def _evaluate(derivation, mass, dims):
    """Substitute exact rationals of the float inputs and evaluate to float64 (40 digits first).

    The floats are converted with sp.Rational, which is exact, so the result is the correctly
    rounded value of the derived formula at exactly the inputs tumble receives.
    """
    syms, tensor = derivation()
    subs = {m: sp.Rational(mass)}
    subs.update({sym: sp.Rational(val) for sym, val in zip(syms, dims, strict=True)})
    return np.array(tensor.subs(subs).evalf(40).tolist(), dtype=float)


def _check(mp, expected, mass, dims):
    """Compare a tumble MassProperties-like object with the oracle tensor, mass and COM.

    Tolerance: both sides are exact closed forms evaluated in float64, so they should agree
    to a few ulp; rtol=1e-12 leaves ~4 orders of magnitude of headroom for different but
    equivalent operation orders, while any wrong coefficient (errors ≥ 1e-3 relative) fails.
    Off-diagonal entries are exactly zero in the oracle, so they need an absolute floor:
    atol = 1e-15 · m · (largest dimension)², i.e. a few ulp of the tensor's natural scale.
    """
    largest = max(dims)
    scale = mass * largest**2
    inertia = np.asarray(mp.inertia, dtype=float)
    assert inertia.shape == (3, 3)
    np.testing.assert_allclose(inertia, expected, rtol=1e-12, atol=1e-15 * scale)
    np.testing.assert_allclose(float(mp.mass), mass, rtol=1e-15)
    com = np.asarray(mp.center_of_mass, dtype=float)
    assert com.shape == (3,)
    np.testing.assert_allclose(com, np.zeros(3), rtol=0, atol=1e-15 * largest)


# ---------------------------------------------------------------------------------------------
# Parametrised comparisons: (shape name, derivation, how to call tumble, parameter sets)
# Each parameter set is (mass, dims) with dims in the order of the derivation's symbols.
# ---------------------------------------------------------------------------------------------

CASES = {
    "box": (
        box_inertia,
        lambda mass, d: shapes.box(mass, tuple(d)),
        [(2.75, (0.31, 1.7, 0.043)), (0.0123, (3.3, 0.47, 1.19)), (913.0, (1.0, 1.0, 2.5))],
    ),
    "solid_cylinder": (
        solid_cylinder_inertia,
        lambda mass, d: shapes.solid_cylinder(mass, *d),
        [(1.37, (0.21, 0.9)), (0.05, (0.77, 0.013)), (48.2, (0.35, 0.6062177826491071))],
    ),
    "hollow_cylinder": (
        hollow_cylinder_inertia,
        lambda mass, d: shapes.hollow_cylinder(mass, *d),
        [(3.3, (0.12, 0.19, 1.45)), (0.71, (0.001, 0.43, 0.027)), (12.0, (0.5, 0.5001, 0.3))],
    ),
    "solid_sphere": (
        solid_sphere_inertia,
        lambda mass, d: shapes.solid_sphere(mass, *d),
        [(5.97, (0.637,)), (0.0027, (0.02,)), (1234.5, (3.1,))],
    ),
    "spherical_shell": (
        spherical_shell_inertia,
        lambda mass, d: shapes.spherical_shell(mass, *d),
        [(0.45, (0.11,)), (17.3, (2.93,))],
    ),
    "hollow_sphere": (
        hollow_sphere_inertia,
        lambda mass, d: shapes.hollow_sphere(mass, *d),
        [(2.2, (0.3, 0.41)), (0.093, (0.005, 0.077)), (64.0, (1.999, 2.0))],
    ),
    "solid_cone": (
        solid_cone_inertia,
        lambda mass, d: shapes.solid_cone(mass, *d),
        [(1.9, (0.23, 0.71)), (0.33, (0.9, 0.12)), (7.7, (0.5, 0.5))],
    ),
    "thin_rod": (
        thin_rod_inertia,
        lambda mass, d: shapes.thin_rod(mass, *d),
        [(0.42, (1.37,)), (12.5, (0.083,))],
    ),
    "thin_disk": (
        thin_disk_inertia,
        lambda mass, d: shapes.thin_disk(mass, *d),
        [(0.31, (0.155,)), (8.8, (1.42,))],
    ),
    "thin_ring": (
        thin_ring_inertia,
        lambda mass, d: shapes.thin_ring(mass, *d),
        [(0.064, (0.29,)), (3.75, (2.2,))],
    ),
    "ellipsoid": (
        ellipsoid_inertia,
        lambda mass, d: shapes.ellipsoid(mass, tuple(d)),
        [(4.4, (0.7, 0.25, 0.13)), (0.017, (0.031, 0.52, 0.2)), (99.0, (1.5, 1.5, 0.4))],
    ),
    "torus": (
        torus_inertia,
        lambda mass, d: shapes.torus(mass, *d),
        [(2.6, (0.45, 0.07)), (0.39, (0.12, 0.12)), (15.0, (1.3, 0.61))],
    ),
    "capsule": (
        capsule_inertia,
        lambda mass, d: shapes.capsule(mass, *d),
        [(1.15, (0.08, 0.37)), (22.0, (0.6, 0.11)), (0.3, (0.013, 1.9))],
    ),
    "regular_tetrahedron": (
        regular_tetrahedron_inertia,
        lambda mass, d: shapes.regular_tetrahedron(mass, *d),
        [(0.8, (0.27,)), (41.0, (1.93,))],
    ),
}

PARAMS = [
    pytest.param(name, mass, dims, id=f"{name}-{i}")
    for name, (_, _, sets) in CASES.items()
    for i, (mass, dims) in enumerate(sets)
]


@pytest.mark.parametrize(("name", "mass", "dims"), PARAMS)
def test_inertia_matches_symbolic_integral(name, mass, dims):
    derivation, make, _ = CASES[name]
    expected = _evaluate(derivation, mass, dims)
    _check(make(mass, dims), expected, mass, dims)


# ---------------------------------------------------------------------------------------------
# Checks on the oracle itself
# ---------------------------------------------------------------------------------------------


def test_cone_com_is_quarter_height_above_base():
    """Own-integral sanity check: a cone with its base at z = 0 has its COM at h/4."""
    assert sp.simplify(cone_com_height() - h / 4) == 0


def test_tetrahedron_centroid_at_origin_and_inertia_isotropic():
    """The parametrised tetrahedron is centred, and its full tensor is c·m·a²·1."""
    assert tetrahedron_com().applyfunc(sp.simplify) == sp.zeros(3, 1)
    _, tensor = regular_tetrahedron_inertia()
    diag = tensor[0, 0]
    assert sp.simplify(tensor - diag * sp.eye(3)) == sp.zeros(3, 3)
    coeff = sp.simplify(diag / (m * a**2))
    assert coeff.free_symbols == set()
    assert coeff.is_positive


@pytest.mark.parametrize(
    "derivation",
    [box_inertia, solid_cone_inertia, ellipsoid_inertia, regular_tetrahedron_inertia],
    ids=["box", "solid_cone", "ellipsoid", "regular_tetrahedron"],
)
def test_integrated_products_of_inertia_vanish(derivation):
    """Products of inertia were integrated (not assumed) and vanish for these symmetric bodies."""
    _, tensor = derivation()
    for i in range(3):
        for j in range(3):
            if i != j:
                assert sp.simplify(tensor[i, j]) == 0


# ---------------------------------------------------------------------------------------------
# Limiting cases (tumble against tumble, and against the oracle)
# ---------------------------------------------------------------------------------------------


def _assert_same(mp1, mp2, rtol=1e-12, scale=1.0):
    """Compare mass, COM and inertia of two mass-property objects."""
    np.testing.assert_allclose(float(mp1.mass), float(mp2.mass), rtol=rtol)
    np.testing.assert_allclose(
        np.asarray(mp1.center_of_mass, dtype=float),
        np.asarray(mp2.center_of_mass, dtype=float),
        rtol=rtol,
        atol=1e-15 * scale,
    )
    np.testing.assert_allclose(
        np.asarray(mp1.inertia, dtype=float),
        np.asarray(mp2.inertia, dtype=float),
        rtol=rtol,
        atol=1e-15 * float(mp1.mass) * scale**2,
    )


@pytest.mark.parametrize(("mass", "radius"), [(2.3, 0.41), (0.07, 1.6)])
def test_hollow_sphere_with_zero_inner_radius_is_solid_sphere(mass, radius):
    _assert_same(
        shapes.hollow_sphere(mass, 0.0, radius), shapes.solid_sphere(mass, radius), scale=radius
    )
    _check(
        shapes.hollow_sphere(mass, 0.0, radius),
        _evaluate(solid_sphere_inertia, mass, (radius,)),
        mass,
        (radius,),
    )


@pytest.mark.parametrize(("mass", "radius", "height"), [(1.1, 0.2, 0.93), (6.0, 0.77, 0.05)])
def test_hollow_cylinder_with_zero_inner_radius_is_solid_cylinder(mass, radius, height):
    _assert_same(
        shapes.hollow_cylinder(mass, 0.0, radius, height),
        shapes.solid_cylinder(mass, radius, height),
        scale=max(radius, height),
    )
    _check(
        shapes.hollow_cylinder(mass, 0.0, radius, height),
        _evaluate(solid_cylinder_inertia, mass, (radius, height)),
        mass,
        (radius, height),
    )


@pytest.mark.parametrize(("mass", "radius"), [(0.9, 0.15), (31.0, 1.05)])
def test_capsule_with_zero_cylinder_is_solid_sphere(mass, radius):
    _assert_same(shapes.capsule(mass, radius, 0.0), shapes.solid_sphere(mass, radius), scale=radius)
    _check(
        shapes.capsule(mass, radius, 0.0),
        _evaluate(solid_sphere_inertia, mass, (radius,)),
        mass,
        (radius,),
    )


def test_oracle_limits_agree_symbolically():
    """The oracle's own hollow/capsule derivations reduce to the solid ones symbolically."""
    _, hs = hollow_sphere_inertia()
    _, ss = solid_sphere_inertia()
    assert (hs.subs({r_in: 0, r_out: R}) - ss).applyfunc(sp.simplify) == sp.zeros(3, 3)
    _, hc = hollow_cylinder_inertia()
    _, sc = solid_cylinder_inertia()
    assert (hc.subs({r_in: 0, r_out: R}) - sc).applyfunc(sp.simplify) == sp.zeros(3, 3)
    _, cap = capsule_inertia()
    assert (cap.subs({h: 0, r: R}) - ss).applyfunc(sp.simplify) == sp.zeros(3, 3)
    _, tor = torus_inertia()
    _, ring = thin_ring_inertia()
    assert (tor.subs(r, 0) - ring).applyfunc(sp.simplify) == sp.zeros(3, 3)


@pytest.mark.parametrize(("mass", "major"), [(1.7, 0.6), (0.25, 2.4)])
def test_thin_torus_approaches_thin_ring(mass, major):
    """Torus with r/R = 1e-3 differs from the thin ring by O((r/R)²) ~ 1e-6 relative."""
    minor = 1e-3 * major
    torus = shapes.torus(mass, major, minor)
    ring = shapes.thin_ring(mass, major)
    np.testing.assert_allclose(float(torus.mass), float(ring.mass), rtol=1e-15)
    np.testing.assert_allclose(
        np.asarray(torus.inertia, dtype=float),
        np.asarray(ring.inertia, dtype=float),
        rtol=1e-5,
        atol=1e-15 * mass * major**2,
    )
    # And the difference is not zero: the tube's own extent must show up at O((r/R)²).
    diff = np.abs(np.asarray(torus.inertia) - np.asarray(ring.inertia)).max()
    assert 1e-8 * mass * major**2 < diff


# ---------------------------------------------------------------------------------------------
# Units at the edge
# ---------------------------------------------------------------------------------------------


def test_solid_cylinder_accepts_unit_strings():
    with_units = shapes.solid_cylinder("250 g", "3 cm", "80 mm")
    plain = shapes.solid_cylinder(0.25, 0.03, 0.08)
    _assert_same(with_units, plain, rtol=1e-14, scale=0.08)
