"""Shapes: dimensions are validated, and thin bodies match point-mass quadratures.

The closed forms themselves are re-derived with sympy in test_shapes_symbolic.py;
here the thin idealisations are checked against point masses placed by a rule
that integrates quadratics exactly, an oracle independent of both.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

import tumble as tb
from tumble import shapes


def test_thin_ring_equals_points_on_a_circle() -> None:
    # n >= 3 equally spaced points reproduce every quadratic moment of a circle.
    m, r, n = 2.0, 0.3, 7
    angles = 2 * np.pi * np.arange(n) / n
    points = np.c_[r * np.cos(angles), r * np.sin(angles), np.zeros(n)]
    assert_allclose(
        shapes.thin_ring(m, r).inertia,
        tb.point_masses(np.full(n, m / n), points).inertia,
        atol=1e-15 * m * r * r,
    )


def test_thin_rod_equals_two_point_gauss_quadrature() -> None:
    # Two-point Gauss-Legendre at ±L/(2√3) integrates z² over the rod exactly.
    m, length = 1.7, 0.9
    z = length / (2 * np.sqrt(3))
    points = tb.point_masses([m / 2, m / 2], [[0, 0, z], [0, 0, -z]])
    assert_allclose(
        shapes.thin_rod(m, length).inertia, points.inertia, rtol=1e-14, atol=1e-15 * m * length**2
    )


def test_spherical_shell_equals_the_six_vertices_of_an_octahedron() -> None:
    # The octahedron's vertices are a spherical 3-design: exact for quadratics.
    m, r = 0.8, 0.25
    points = r * np.vstack([np.eye(3), -np.eye(3)])
    assert_allclose(
        shapes.spherical_shell(m, r).inertia,
        tb.point_masses(np.full(6, m / 6), points).inertia,
        rtol=1e-14,
    )


def test_thin_disk_equals_a_polar_quadrature() -> None:
    # ∫ over the disk of quadratics: radial Gauss-Legendre in ρ² (exact for the
    # polynomial ρ³ dρ) times equally spaced angles (exact for cos², sin²).
    m, r = 1.2, 0.4
    nodes, weights = np.polynomial.legendre.leggauss(3)
    rho = r * np.sqrt((nodes + 1) / 2)  # u = ρ²/r² uniform in [0, 1] for area
    angles = 2 * np.pi * np.arange(5) / 5
    masses, points = [], []
    for rad, w in zip(rho, weights, strict=True):
        for a in angles:
            masses.append(m * w / 2 / len(angles))
            points.append([rad * np.cos(a), rad * np.sin(a), 0.0])
    assert_allclose(
        shapes.thin_disk(m, r).inertia,
        tb.point_masses(masses, points).inertia,
        atol=1e-15 * m * r * r,
    )


def test_flat_bodies_sit_on_the_triangle_inequality() -> None:
    # A flat body has I1 + I2 = I3 exactly (perpendicular-axis theorem).
    for body in (shapes.thin_disk(1.0, 0.3), shapes.thin_ring(1.0, 0.3)):
        i1, i2, i3 = body.principal()[0]
        assert i1 + i2 == pytest.approx(i3, rel=1e-15)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: shapes.box(-1.0, (1, 2, 3)), r"Expected `mass` > 0 kg, got -1.0"),
        (lambda: shapes.box(1.0, (1, 0, 3)), r"Expected `size\[1\]` > 0 m, got 0.0"),
        (lambda: shapes.box(1.0, (1, 2)), r"Expected `size` to have shape \(3,\), got \(2,\)"),
        (lambda: shapes.solid_cylinder(1.0, -0.1, 1.0), r"Expected `radius` > 0 m, got -0.1"),
        (
            lambda: shapes.solid_cylinder(1.0, 0.1, "2 kg"),
            r"Expected `height` to be a length in m, got 2 kg",
        ),
        (
            lambda: shapes.hollow_cylinder(1.0, 0.3, 0.2, 1.0),
            r"Expected 0 <= `inner_radius` <= `outer_radius` = 0.2 m, got 0.3",
        ),
        (lambda: shapes.hollow_cylinder(1.0, -0.1, 0.2, 1.0), r"Expected 0 <= `inner_radius`"),
        (
            lambda: shapes.hollow_sphere(1.0, 0.3, 0.2),
            r"Expected 0 <= `inner_radius` <= `outer_radius` = 0.2 m",
        ),
        (lambda: shapes.solid_sphere(1.0, np.nan), r"Expected `radius` to be finite, got nan"),
        (lambda: shapes.spherical_shell(0.0, 1.0), r"Expected `mass` > 0 kg, got 0.0"),
        (lambda: shapes.solid_cone(1.0, 0.1, 0.0), r"Expected `height` > 0 m, got 0.0"),
        (lambda: shapes.thin_rod(1.0, -2.0), r"Expected `length` > 0 m, got -2.0"),
        (lambda: shapes.thin_disk(1.0, 0.0), r"Expected `radius` > 0 m, got 0.0"),
        (lambda: shapes.thin_ring("1 m", 1.0), r"Expected `mass` to be a mass in kg, got 1 m"),
        (lambda: shapes.ellipsoid(1.0, (1, 2, -3)), r"Expected `semi_axes\[2\]` > 0 m, got -3.0"),
        (
            lambda: shapes.torus(1.0, 0.1, 0.2),
            r"Expected `minor_radius` <= `major_radius` = 0.1 m \(a self-intersecting torus has no single solid\), got 0.2",
        ),
        (lambda: shapes.capsule(1.0, 0.1, -0.5), r"Expected `cylinder_height` >= 0 m, got -0.5"),
        (
            lambda: shapes.regular_tetrahedron(1.0, "1 s"),
            r"Expected `edge` to be a length in m, got 1 s",
        ),
    ],
)
def test_shapes_reject_bad_dimensions(call: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        call()  # type: ignore[operator]


def test_thin_walled_limits_are_valid() -> None:
    # inner == outer is the thin-walled limit, computed without cancellation.
    tube = shapes.hollow_cylinder(1.0, 0.2, 0.2, 0.0001)
    assert tube.inertia[2, 2] == pytest.approx(0.2**2, rel=1e-15)  # thin tube: m r²
    shell = shapes.hollow_sphere(1.0, 0.2, 0.2)
    assert_allclose(shell.inertia, shapes.spherical_shell(1.0, 0.2).inertia, rtol=1e-15)


@pytest.mark.parametrize(
    ("call", "shown"),
    [
        # I = m (b² + c²) / 12 = 1e-300 · 2e-400 / 12: below float64's range, 0.
        (lambda: shapes.box(1e-300, [1e-200, 1e-200, 1e-200]), r"\[0\.0, 0\.0, 0\.0\]"),
        # 1e-200 · 1e-120 / 6 ≈ 1.7e-321: subnormal, with 4 of its 16 digits left.
        (
            lambda: shapes.box(1e-200, [1e-60, 1e-60, 1e-60]),
            r"\[1\.67e-321, 1\.67e-321, 1\.67e-321\]",
        ),
        (lambda: shapes.solid_sphere(1e-300, 1e-10), r".* for a mass of 1e-300 kg"),
    ],
)
def test_shapes_refuse_moments_that_underflow_float64(call: object, shown: str) -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected moments of inertia of at least 2\.23e-308 kg·m², float64's smallest "
        r"full-precision number, got " + shown,
    ):
        call()  # type: ignore[operator]


def test_a_thin_rods_zero_axial_moment_is_not_an_underflow() -> None:
    # The thin rod's axial moment is exactly 0 by definition; its others, m L² / 12.
    rod = shapes.thin_rod(1e-100, 1e-100)
    assert rod.principal()[0].tolist() == pytest.approx([0.0, 1e-300 / 12, 1e-300 / 12], rel=1e-15)


@pytest.mark.parametrize(
    "call",
    [
        lambda: shapes.box(1e300, [1e200, 1, 1]),
        lambda: shapes.ellipsoid(1e300, [1e200, 1, 1]),
        lambda: shapes.solid_sphere(1e300, 1e200),
    ],
)
def test_shapes_refuse_moments_beyond_float64_without_numpy_warnings(call: object) -> None:
    # m (b² + c²) / 12 with m = 1e300 and b = 1e200: beyond 1.8e308, inf. Refused as
    # such, and with no "overflow encountered" warning printed before it (the
    # warnings filter turns any warning into an error here).
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(
            tb.InputError,
            match=r"^Expected moments of inertia within float64's range, got \[.*inf.*\] kg·m² "
            r"for a mass of 1e\+300 kg: the body is too heavy or too large for SI in float64\.$",
        ):
            call()  # type: ignore[operator]


def test_large_shapes_whose_moments_float64_holds_are_computed() -> None:
    # 2 m r² / 5 of a ball: a hollow sphere whose hole is 1e-20 of its radius,
    # and a capsule whose cylinder is 1e-103 of its radius, are balls to 1e-16.
    # Neither may overflow on the way (r⁵ of 1e80 m would), nor raise.
    hollow = shapes.hollow_sphere("1 kg", "1e60 m", "1e80 m")
    assert hollow.inertia[0, 0] == pytest.approx(0.4e160, rel=1e-15)
    capsule = shapes.capsule("1 kg", "1e103 m", "1 m")
    assert capsule.principal()[0] == pytest.approx([0.4e206] * 3, rel=1e-15)
