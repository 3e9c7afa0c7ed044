"""hypothesis strategies for valid bodies, rotations and angular velocities."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

import tumble as tb

finite = st.floats(min_value=-10.0, max_value=10.0, allow_nan=False, allow_infinity=False)
positive = st.floats(min_value=0.01, max_value=10.0, allow_nan=False, allow_infinity=False)


@st.composite
def rotations(draw: st.DrawFn) -> Rotation:
    """A rotation from a random quaternion away from zero (uniform enough for properties)."""
    q = draw(arrays(float, 4, elements=st.floats(-1, 1, allow_nan=False)))
    if np.linalg.norm(q) < 0.1:
        q = np.array([1.0, 0.0, 0.0, 0.0])
    return Rotation.from_quat(q, scalar_first=True)


@st.composite
def point_clouds(
    draw: st.DrawFn, min_size: int = 1, max_size: int = 8
) -> tuple[np.ndarray, np.ndarray]:
    """Masses (n,) kg and positions (n, 3) m of a rigid set of point masses."""
    n = draw(st.integers(min_size, max_size))
    masses = draw(arrays(float, n, elements=positive))
    positions = draw(arrays(float, (n, 3), elements=finite))
    return masses, positions


@st.composite
def principal_moments(draw: st.DrawFn) -> np.ndarray:
    """Principal moments of some real body: I1 = b + c, I2 = a + c, I3 = a + b with
    a, b, c >= 0 the second moments ∫x², ∫y², ∫z² — every valid set arises so."""
    a, b, c = (draw(st.floats(0.0, 10.0)) for _ in range(3))
    if a + b + c < 1e-3:
        a = 1.0
    return np.sort([b + c, a + c, a + b])


@st.composite
def bodies(draw: st.DrawFn) -> tb.MassProperties:
    """A valid body: random moments, random principal axes, random centre of mass."""
    moments = draw(principal_moments())
    rotation = draw(rotations()).as_matrix()
    com = draw(arrays(float, 3, elements=finite))
    mass = draw(positive)
    return tb.MassProperties(mass, com, rotation @ np.diag(moments) @ rotation.T)


omegas = arrays(float, 3, elements=finite)
