"""MassProperties: validation, parallel axes, principal axes, moves and assemblies.

The oracle for every tensor here is the definition ``I = Σ m (|d|² E − d dᵀ)``
summed directly over point masses, independent of the code under test.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from strategies import bodies, point_clouds, rotations


def direct_inertia(masses: np.ndarray, positions: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Σ m (|d|² E − d dᵀ) about ``point``, written out term by term."""
    total = np.zeros((3, 3))
    for m, r in zip(masses, positions, strict=True):
        d = r - point
        for i in range(3):
            for j in range(3):
                total[i, j] += m * ((d @ d if i == j else 0.0) - d[i] * d[j])
    return total


# Round-off of sums of n products of O(|r|² m) terms: a few ulp of the largest term.
def scale_of(masses: np.ndarray, positions: np.ndarray) -> float:
    return float(masses.sum() * (1.0 + np.max(np.abs(positions))) ** 2)


# ----------------------------------------------------------------- point masses
def test_products_of_inertia_carry_a_minus_sign() -> None:
    # Two 1 kg masses at (1, 1, 0) and (-1, -1, 0): Σ m x y = 2 kg m², so I_xy = −2.
    mp = tb.point_masses([1.0, 1.0], [[1.0, 1.0, 0.0], [-1.0, -1.0, 0.0]])
    assert mp.inertia[0, 1] == -2.0
    assert mp.inertia[1, 0] == -2.0
    assert mp.inertia[0, 0] == 2.0  # Σ m (y² + z²)
    assert mp.inertia[2, 2] == 4.0  # Σ m (x² + y²)


@given(point_clouds())
def test_point_masses_match_the_definition(cloud: tuple[np.ndarray, np.ndarray]) -> None:
    masses, positions = cloud
    mp = tb.point_masses(masses, positions)
    com = (masses[:, None] * positions).sum(axis=0) / masses.sum()
    assert_allclose(mp.mass, masses.sum(), rtol=1e-14)
    assert_allclose(mp.center_of_mass, com, atol=1e-12 * (1 + np.abs(positions).max()))
    assert_allclose(
        mp.inertia, direct_inertia(masses, positions, com), atol=1e-12 * scale_of(masses, positions)
    )


def test_single_point_mass_has_zero_inertia() -> None:
    mp = tb.point_masses([2.0], [[1.0, 2.0, 3.0]])
    assert np.all(mp.inertia == 0.0)
    assert_allclose(
        mp.inertia_about([0, 0, 0]),
        direct_inertia(np.array([2.0]), np.array([[1.0, 2, 3]]), np.zeros(3)),
    )


def test_collinear_point_masses_are_valid_with_a_zero_moment() -> None:
    mp = tb.point_masses([1.0, 3.0, 2.0], [[0, 0, -1], [0, 0, 0.5], [0, 0, 2]])
    moments, axes = mp.principal()
    assert moments[0] == pytest.approx(0.0, abs=1e-15)
    assert moments[1] == pytest.approx(moments[2], rel=1e-15)
    assert_allclose(np.abs(axes[:, 0]), [0, 0, 1], atol=1e-15)


@pytest.mark.parametrize(
    ("masses", "positions", "message"),
    [
        (
            [1.0, -2.0],
            [[0, 0, 0], [1, 0, 0]],
            r"Expected every entry of `masses` > 0 kg, got masses\[1\] = -2.0",
        ),
        ([1.0, 0.0], [[0, 0, 0], [1, 0, 0]], r"masses\[1\] = 0.0"),
        (
            [1.0, 2.0],
            [[0, 0, 0]],
            r"Expected `positions` to have shape \(2, 3\) to match `masses`, got \(1, 3\)",
        ),
        ([], np.zeros((0, 3)), r"Expected `masses` to hold at least one mass, got none"),
        ([1.0], [[0, 0]], r"Expected `positions` to have shape \(n, 3\), got \(1, 2\)"),
        ([1.0], [[0, np.nan, 0]], r"Expected `positions` to be finite"),
        (["1 m"], [[0, 0, 0]], r"Expected `masses` to be a mass in kg, got 1 m"),
    ],
)
def test_point_masses_reject_bad_input(masses: object, positions: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.point_masses(masses, positions)


# ------------------------------------------------------------------ validation
GOOD_INERTIA = np.diag([1.0, 2.0, 2.5])


@pytest.mark.parametrize(
    ("mass", "com", "inertia", "message"),
    [
        (0.0, [0, 0, 0], GOOD_INERTIA, r"Expected `mass` > 0 kg, got 0.0"),
        (-1.0, [0, 0, 0], GOOD_INERTIA, r"Expected `mass` > 0 kg, got -1.0"),
        (np.nan, [0, 0, 0], GOOD_INERTIA, r"Expected `mass` to be finite, got nan"),
        (np.inf, [0, 0, 0], GOOD_INERTIA, r"Expected `mass` to be finite, got inf"),
        ("3 cm", [0, 0, 0], GOOD_INERTIA, r"Expected `mass` to be a mass in kg, got 3 cm"),
        (1.0, [0, 0], GOOD_INERTIA, r"Expected `center_of_mass` to have shape \(3,\), got \(2,\)"),
        (1.0, [0, np.inf, 0], GOOD_INERTIA, r"Expected `center_of_mass` to be finite"),
        (1.0, [0, 0, 0], np.eye(2), r"Expected `inertia` to have shape \(3, 3\), got \(2, 2\)"),
        (1.0, [0, 0, 0], np.diag([1.0, np.nan, 1.0]), r"Expected `inertia` to be finite"),
        (
            1.0,
            [0, 0, 0],
            [[1, 0.2, 0], [0.1, 1, 0], [0, 0, 1]],
            r"Expected `inertia` to be symmetric, got inertia\[0, 1\] = 0.2 but inertia\[1, 0\] = 0.1",
        ),
        (
            1.0,
            [0, 0, 0],
            np.diag([-1.0, 2.0, 2.0]),
            r"Expected the principal moments of `inertia` to be >= 0, got \[-1, 2, 2\]",
        ),
        (
            1.0,
            [0, 0, 0],
            np.diag([1.0, 1.0, 2.5]),
            r"triangle inequality I1 \+ I2 >= I3, got I1 \+ I2 = 2 < I3 = 2.5",
        ),
    ],
)
def test_mass_properties_reject_bad_input(
    mass: object, com: object, inertia: object, message: str
) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.MassProperties(mass, com, inertia)


def test_input_error_is_a_value_error() -> None:
    with pytest.raises(ValueError):
        tb.MassProperties(-1.0, [0, 0, 0], GOOD_INERTIA)


def test_triangle_inequality_is_checked_in_any_axes() -> None:
    # diag(1, 1, 2.5) rotated: the entries look harmless, the moments are not.
    rotation = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    with pytest.raises(tb.InputError, match="triangle inequality"):
        tb.MassProperties(1.0, [0, 0, 0], rotation @ np.diag([1.0, 1.0, 2.5]) @ rotation.T)


def test_flat_and_linear_bodies_are_valid_at_the_tolerance() -> None:
    # A flat body has I1 + I2 == I3 exactly; computed in another frame it may miss
    # by round-off, which the relative tolerance (1e-9 of the trace) admits.
    rotation = Rotation.from_euler("zyx", [0.1, 0.2, 0.3]).as_matrix()
    flat = rotation @ np.diag([1.0, 2.0, 3.0]) @ rotation.T
    tb.MassProperties(1.0, [0, 0, 0], flat)
    tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0 * (1 + 1e-10)]))
    with pytest.raises(tb.InputError, match="triangle inequality"):
        tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 3.0 * (1 + 1e-6)]))
    tb.MassProperties(1.0, [0, 0, 0], np.diag([-1e-12, 1.0, 1.0]))  # a rod, with round-off


def test_units_at_the_edge() -> None:
    mp = tb.MassProperties(
        "250 g", ["1 cm", "0 m", "-2 mm"], np.diag([1.0, 2.0, 2.5]) * tb.units.ureg("g*cm^2")
    )
    assert mp.mass == pytest.approx(0.25, rel=1e-15)
    assert_allclose(mp.center_of_mass, [0.01, 0.0, -0.002], rtol=1e-15)
    assert_allclose(mp.inertia, np.diag([1.0, 2.0, 2.5]) * 1e-7, rtol=1e-15)


def test_mass_properties_are_immutable() -> None:
    mp = tb.MassProperties(1.0, [0, 0, 0], GOOD_INERTIA)
    with pytest.raises(dataclasses.FrozenInstanceError):
        mp.mass = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        mp.inertia[0, 0] = 5.0
    moments, _ = mp.principal()
    with pytest.raises(ValueError, match="read-only"):
        moments[0] = 5.0


def test_repr_names_the_quantities_and_units() -> None:
    text = repr(tb.shapes.box(2.0, (1.0, 2.0, 3.0)))
    assert "mass           = 2 kg" in text
    assert "about the centre of mass, body axes (kg·m²)" in text
    assert "principal moments = [0.833333, 1.66667, 2.16667] kg·m²" in text  # m(b²+c²)/12 ...


# --------------------------------------------------------------- parallel axes
@given(point_clouds(), st.tuples(*(st.floats(-5, 5) for _ in range(3))))
# A tensor of subnormal entries (2.5e-323 kg·m²), not positive semi-definite once
# rounded to their grid: still a valid body, not a negative moment.
@example(cloud=(np.array([0.01]), np.array([[2.7362288e-145] * 3])), point=(0.0, 0.0, 0.0))
def test_inertia_about_a_point_matches_the_definition(
    cloud: tuple[np.ndarray, np.ndarray], point: tuple[float, float, float]
) -> None:
    masses, positions = cloud
    p = np.array(point)
    mp = tb.point_masses(masses, positions)
    assert_allclose(
        mp.inertia_about(p),
        direct_inertia(masses, positions, p),
        atol=1e-12 * scale_of(masses, positions) * (1 + np.abs(p).max()) ** 2,
    )


@given(bodies())
def test_inertia_about_the_center_of_mass_is_the_central_inertia(mp: tb.MassProperties) -> None:
    assert_allclose(
        mp.inertia_about(mp.center_of_mass), mp.inertia, atol=1e-15 * np.abs(mp.inertia).max()
    )


@given(bodies(), st.tuples(*(st.floats(-5, 5) for _ in range(3))))
def test_central_inertia_is_the_minimum_trace(
    mp: tb.MassProperties, point: tuple[float, float, float]
) -> None:
    # Steiner: moving away from the centre of mass adds 2 m |d|² to the trace.
    d = np.array(point) - mp.center_of_mass
    shifted = mp.inertia_about(point)
    assert np.trace(shifted) == pytest.approx(
        np.trace(mp.inertia) + 2 * mp.mass * d @ d, rel=1e-12, abs=1e-12
    )


# -------------------------------------------------------------- principal axes
@given(bodies())
def test_principal_axes_diagonalise_the_inertia(mp: tb.MassProperties) -> None:
    moments, axes = mp.principal()
    assert np.all(np.diff(moments) >= 0)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
    assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
    # Repeated moments are snapped to their mean (within 1e-9 of the trace), so the
    # reconstruction holds to that tolerance; with well-separated moments it holds
    # to round-off of eigh (a few ulp of the trace).
    trace = np.trace(mp.inertia)
    separated = np.min(np.diff(np.linalg.eigvalsh(mp.inertia))) > 1e-8 * trace
    tolerance = 1e-13 * trace if separated else 2e-9 * trace
    assert_allclose(axes @ np.diag(moments) @ axes.T, mp.inertia, atol=tolerance)


@given(bodies())
def test_every_valid_body_satisfies_the_triangle_inequality(mp: tb.MassProperties) -> None:
    i1, i2, i3 = mp.principal()[0]
    assert i1 >= -1e-9 * (i1 + i2 + i3)
    assert i1 + i2 >= i3 - 1e-9 * (i1 + i2 + i3)


@given(point_clouds(min_size=2))
def test_point_clouds_satisfy_the_triangle_inequality(cloud: tuple[np.ndarray, np.ndarray]) -> None:
    i1, i2, i3 = tb.point_masses(*cloud).principal()[0]
    assert i1 + i2 >= i3 - 1e-9 * (i1 + i2 + i3)


@given(bodies(), rotations())
def test_principal_moments_are_invariant_under_rotation(
    mp: tb.MassProperties, rotation: Rotation
) -> None:
    moved = mp.transformed(rotation)
    assert_allclose(moved.principal()[0], mp.principal()[0], atol=1e-12 * np.trace(mp.inertia))


def test_principal_axes_follow_a_rotation_of_the_body() -> None:
    mp = tb.MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.5]))
    rotation = Rotation.from_rotvec([0.4, -1.2, 0.7])
    _, axes = mp.transformed(rotation).principal()
    # Distinct moments: axes are the rotated body axes, each up to sign.
    for k in range(3):
        assert abs(axes[:, k] @ rotation.as_matrix()[:, k]) == pytest.approx(1.0, abs=1e-12)


def test_a_stack_already_principal_gives_what_the_general_rule_gives() -> None:
    # A stack of diagonal tensors, ascending and apart, takes a shortcut; the
    # general rule (eigh, then the signs) must give the same bits: forced here by
    # one tensor of the stack that is not diagonal.
    from tumble.massprops import principal_decomposition

    diagonal = np.sort(np.random.default_rng(5).uniform(0.1, 5.0, (500, 3)), axis=1)
    tensors = np.einsum("ni,ij->nij", diagonal, np.eye(3))
    moments, axes = principal_decomposition(tensors)
    mixed = tensors.copy()
    mixed[0, 0, 1] = mixed[0, 1, 0] = 1e-3
    general_moments, general_axes = principal_decomposition(mixed)
    assert np.array_equal(moments[1:], general_moments[1:])
    assert np.array_equal(axes[1:], general_axes[1:])
    assert np.array_equal(axes, np.broadcast_to(np.eye(3), axes.shape))


def test_sphere_axes_are_the_body_axes() -> None:
    moments, axes = tb.shapes.solid_sphere(1.0, 0.5).principal()
    assert np.all(moments == moments[0])
    assert np.array_equal(axes, np.eye(3))


@pytest.mark.parametrize(
    "diagonal", [[1.0, 1.0, 1.5], [1.0, 1.5, 1.5], [1.5, 1.0, 1.0], [1.0, 1.5, 1.0]]
)
def test_symmetric_top_axes_are_the_body_axes_in_ascending_order(diagonal: list[float]) -> None:
    moments, axes = tb.MassProperties(1.0, [0, 0, 0], np.diag(diagonal)).principal()
    assert_allclose(moments, sorted(diagonal), rtol=1e-15)
    # Each column is a body axis whose diagonal entry is that moment.
    for k in range(3):
        axis = int(np.argmax(np.abs(axes[:, k])))
        assert abs(axes[axis, k]) == 1.0
        assert diagonal[axis] == moments[k]
    assert np.linalg.det(axes) == pytest.approx(1.0)


@given(rotations())
def test_repeated_moments_give_the_symmetry_axis_and_are_stable(rotation: Rotation) -> None:
    # A symmetric top in arbitrary axes: the symmetry axis is well defined and is
    # found; perturbing the tensor below the tolerance changes nothing.
    matrix = rotation.as_matrix()
    inertia = matrix @ np.diag([1.0, 1.0, 1.7]) @ matrix.T
    moments, axes = tb.MassProperties(1.0, [0, 0, 0], inertia).principal()
    assert moments[0] == moments[1]
    assert abs(axes[:, 2] @ matrix[:, 2]) == pytest.approx(1.0, abs=1e-12)
    noise = 1e-13 * np.array([[1.0, 0.3, -0.2], [0.3, -0.5, 0.1], [-0.2, 0.1, 0.4]])
    _, perturbed = tb.MassProperties(1.0, [0, 0, 0], inertia + noise).principal()
    assert_allclose(perturbed, axes, atol=1e-9)


def test_near_sphere_axes_are_stable() -> None:
    noise = 1e-14 * np.array([[1.0, 0.3, -0.2], [0.3, -0.5, 0.1], [-0.2, 0.1, 0.4]])
    _, axes = tb.MassProperties(1.0, [0, 0, 0], 0.4 * np.eye(3) + noise).principal()
    assert np.array_equal(axes, np.eye(3))


# ----------------------------------------------------------- moves, assemblies
@given(point_clouds(), rotations(), st.tuples(*(st.floats(-5, 5) for _ in range(3))))
def test_transformed_equals_moving_the_points(
    cloud: tuple[np.ndarray, np.ndarray],
    rotation: Rotation,
    translation: tuple[float, float, float],
) -> None:
    masses, positions = cloud
    moved_positions = rotation.apply(positions) + np.array(translation)
    expected = tb.point_masses(masses, moved_positions)
    for rot in (rotation, rotation.as_matrix()):
        got = tb.point_masses(masses, positions).transformed(rotation=rot, translation=translation)
        assert_allclose(
            got.center_of_mass,
            expected.center_of_mass,
            atol=1e-12 * (1 + np.abs(moved_positions).max()),
        )
        assert_allclose(got.inertia, expected.inertia, atol=1e-12 * scale_of(masses, positions))


@pytest.mark.parametrize(
    ("rotation", "message"),
    [
        (
            np.diag([1.0, 1.0, -1.0]),
            r"Expected `rotation` to be a proper rotation matrix \(orthonormal, det \+1\), got det = -1",
        ),
        (2 * np.eye(3), r"got det = 8 and max \|RᵀR − E\| = 3"),
        (np.eye(2), r"Expected `rotation` to have shape \(3, 3\), got \(2, 2\)"),
        (Rotation.random(2, random_state=0), r"Expected `rotation` to be a single rotation, got 2"),
    ],
)
def test_transformed_rejects_bad_rotations(rotation: object, message: str) -> None:
    with pytest.raises(tb.InputError, match=message):
        tb.shapes.box(1.0, (1, 2, 3)).transformed(rotation=rotation)


def test_transformed_rejects_bad_translation() -> None:
    with pytest.raises(
        tb.InputError, match=r"Expected `translation` to be a length in m, got 1 kg"
    ):
        tb.shapes.box(1.0, (1, 2, 3)).transformed(translation=["1 kg", 0, 0])


@given(point_clouds(min_size=2), st.data())
def test_assembly_is_additive(cloud: tuple[np.ndarray, np.ndarray], data: st.DataObject) -> None:
    masses, positions = cloud
    split = data.draw(st.integers(1, len(masses) - 1))
    whole = tb.point_masses(masses, positions)
    parts = tb.point_masses(masses[:split], positions[:split]) + tb.point_masses(
        masses[split:], positions[split:]
    )
    assert parts.mass == pytest.approx(whole.mass, rel=1e-14)
    assert_allclose(
        parts.center_of_mass, whole.center_of_mass, atol=1e-12 * (1 + np.abs(positions).max())
    )
    assert_allclose(parts.inertia, whole.inertia, atol=1e-12 * scale_of(masses, positions))


def test_sum_of_parts_and_dumbbell() -> None:
    # Two spheres joined: I = 2 (2/5 m r²) + 2 m d² across the line joining them.
    m, r, d = 1.5, 0.1, 0.4
    ball = tb.shapes.solid_sphere(m, r)
    parts = [ball.transformed(translation=[0, 0, d]), ball.transformed(translation=[0, 0, -d])]
    dumbbell = sum(parts)
    assert isinstance(dumbbell, tb.MassProperties)
    assert_allclose(
        np.diag(dumbbell.inertia),
        [2 * (0.4 * m * r**2 + m * d**2)] * 2 + [0.8 * m * r**2],
        rtol=1e-14,
    )


def test_adding_something_else_is_a_type_error() -> None:
    with pytest.raises(TypeError):
        tb.shapes.box(1.0, (1, 2, 3)) + 3  # type: ignore[operator]


def test_pickling_keeps_values_and_read_only_arrays() -> None:
    import pickle

    mp = tb.shapes.box(2.0, (1.0, 2.0, 3.0)).transformed(translation=[1, 2, 3])
    copy = pickle.loads(pickle.dumps(mp))
    assert copy.mass == mp.mass
    assert np.array_equal(copy.inertia, mp.inertia)
    assert np.array_equal(copy.center_of_mass, mp.center_of_mass)
    assert not copy.inertia.flags.writeable


def test_round_off_negative_moments_are_reported_as_zero() -> None:
    # -1e-10 is within the validation tolerance (1e-9 of the trace): round-off
    # of a rod's zero moment, which principal() must not report as negative.
    moments, _ = tb.MassProperties(1.0, [0, 0, 0], np.diag([-1e-10, 1.0, 1.0])).principal()
    assert moments[0] == 0.0


def test_inertia_about_a_point_that_overflows_is_an_error() -> None:
    mp = tb.MassProperties(1.0, [1e200, 0, 0], GOOD_INERTIA)
    with pytest.raises(
        tb.InputError,
        match=r"Expected `point` within float range of the centre of mass, got \[0.0, 0.0, 0.0\] m",
    ):
        mp.inertia_about([0, 0, 0])


def test_axisymmetric_moments_of_a_cylinder() -> None:
    from tumble.massprops import as_mass_properties, axisymmetric_moments

    # Solid cylinder about its axis z: Is = m r²/2, I⊥ = m (3 r² + h²)/12.
    m, r, h = 2.0, 0.1, 0.3
    axial, transverse = axisymmetric_moments(tb.shapes.solid_cylinder(m, r, h))
    assert axial == pytest.approx(m * r**2 / 2, rel=1e-15)
    assert transverse == pytest.approx(m * (3 * r**2 + h**2) / 12, rel=1e-15)
    with pytest.raises(tb.InputError, match=r"Expected `body` to be a MassProperties, got int\."):
        as_mass_properties(3, "body")
