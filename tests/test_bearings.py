"""A rigid rotor on elastic bearings: whirl frequencies, critical speeds and the
unbalance response against closed forms and a model assembled here."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
import sympy
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

import tumble as tb
from tumble.theory import Bearing, RigidRotor

DISK = tb.shapes.thin_disk(10.0, 0.1)  # I_p = 0.05 > I_t = 0.025 kg·m²
ROD = tb.shapes.solid_cylinder(10.0, 0.05, 0.6)  # I_t = 0.30625 > I_p = 0.0125 kg·m²
SPEEDS = np.linspace(0.0, 3000.0, 7)


def symmetric(body: tb.MassProperties, k: float = 1e6, a: float = 0.2) -> RigidRotor:
    return RigidRotor(body, [Bearing(-a, k), Bearing(a, k)])


@pytest.mark.parametrize("body", [DISK, ROD], ids=["disk", "rod"])
def test_a_symmetric_rotor_whirls_at_the_closed_forms(body: tb.MassProperties) -> None:
    # Friswell et al. §3.5: cylindrical √(Σk/m) at any speed; conical
    # (±I_p Ω + √(I_p² Ω² + 4 I_t K_θ)) / 2 I_t, backward (−) and forward (+).
    rotor = symmetric(body)
    m, polar = body.mass, body.inertia[2, 2]
    transverse = body.inertia[0, 0]
    k_theta = 2 * 1e6 * 0.2**2
    whirl = rotor.whirl(SPEEDS)
    for i, speed in enumerate(SPEEDS):
        root = math.sqrt(polar**2 * speed**2 + 4 * transverse * k_theta)
        expected = sorted(
            [math.sqrt(2e6 / m)] * 2
            + [(s * polar * speed + root) / (2 * transverse) for s in (-1, 1)]
        )
        # Eigenvalues of an 8 × 8 matrix of entries up to 1e8: a few ε relative.
        assert_allclose(whirl.frequencies[i], expected, rtol=1e-9)
        conical_forward = (polar * speed + root) / (2 * transverse)
        j = int(np.argmin(np.abs(whirl.frequencies[i] - conical_forward)))
        assert whirl.forward[i, j] or speed == 0
        assert whirl.forward[i].sum() == 2  # one of each pair
    assert_allclose(whirl.damping_ratios, 0.0, atol=1e-9)
    assert rotor.frequencies(1000.0).shape == (4,)


def assembled(body: tb.MassProperties, bearings: list[tuple[float, tuple[float, float], tuple[float, float]]],
              speed: float) -> np.ndarray:  # fmt: skip
    """The damped natural frequencies of a model assembled here by virtual work: each
    bearing at arm a from the centre of mass sees the shaft point S q with
    S = [[1, 0, 0, a], [0, 1, −a, 0]] for q = (x, y, α, β) (α, β tilts about x, y),
    and adds Sᵀ diag(k) S and Sᵀ diag(c) S; the spin's angular momentum I_p Ω along
    the tilted axis (β, −α, 1) gives the moments −I_p Ω β̇ about x and +I_p Ω α̇
    about y. The quadratic eigenproblem is solved by scipy in companion form."""
    m, transverse, polar = body.mass, body.inertia[0, 0], body.inertia[2, 2]
    centre = body.center_of_mass[2]
    stiffness, damping = np.zeros((4, 4)), np.zeros((4, 4))
    for position, k, c in bearings:
        a = position - centre
        s = np.array([[1.0, 0, 0, a], [0, 1.0, -a, 0]])
        stiffness += s.T @ np.diag(k) @ s
        damping += s.T @ np.diag(c) @ s
    gyro = np.zeros((4, 4))
    gyro[2, 3], gyro[3, 2] = polar * speed, -polar * speed
    mass = np.diag([m, m, transverse, transverse])
    zero, one = np.zeros((4, 4)), np.eye(4)
    left = np.block([[one, zero], [zero, mass]])
    right = np.block([[zero, one], [-stiffness, -(damping + gyro)]])
    values = scipy.linalg.eigvals(right, left)
    return np.sort(values.imag[values.imag > 0])


@pytest.mark.parametrize(
    ("body", "bearings"),
    [
        (DISK.transformed(translation=[0, 0, 0.05]), [(-0.2, (1e6, 1e6), (0, 0)), (0.3, (2e6, 2e6), (0, 0))]),
        (ROD, [(-0.25, (1e6, 3e6), (0, 0)), (0.2, (2e6, 5e5), (0, 0))]),
        (ROD.transformed(translation=[0, 0, -0.1]), [(-0.3, (1e6, 2e6), (300.0, 100.0)), (0.2, (1.5e6, 1e6), (50.0, 500.0))]),
    ],
    ids=["coupled", "anisotropic", "damped"],
)  # fmt: skip
def test_coupled_anisotropic_and_damped_rotors_match_a_model_assembled_here(body, bearings) -> None:  # type: ignore[no-untyped-def]
    rotor = RigidRotor(body, [Bearing(p, k, c) for p, k, c in bearings])
    for speed in (0.0, 800.0, 2500.0):
        assert_allclose(rotor.frequencies(speed), assembled(body, bearings, speed), rtol=1e-9)
        # whirl() solves for the eigenvectors too: the same eigenvalues.
        assert_allclose(rotor.whirl(speed).frequencies[0], rotor.frequencies(speed), rtol=1e-12)


def test_critical_speeds() -> None:
    # Symmetric and uncoupled: √(Σk/m) and, for I_t > I_p, √(K_θ / (I_t − I_p)).
    rod = symmetric(ROD)
    transverse, polar = ROD.inertia[0, 0], ROD.inertia[2, 2]
    assert_allclose(rod.critical_speeds(),
                    [math.sqrt(2e6 / 10.0), math.sqrt(2e6 * 0.04 / (transverse - polar))], rtol=1e-9)  # fmt: skip
    # A disk (I_p > I_t) has only the cylindrical one.
    assert_allclose(symmetric(DISK).critical_speeds(), [math.sqrt(2e6 / 10.0)], rtol=1e-9)
    # Anisotropic and coupled: at each critical speed a forward whirl frequency
    # equals the spin (the definition), checked on the whirl at that speed.
    rotor = RigidRotor(ROD.transformed(translation=[0, 0, 0.05]),
                       [Bearing(-0.25, (1e6, 3e6)), Bearing(0.2, (2e6, 5e5))])  # fmt: skip
    speeds = rotor.critical_speeds()  # anisotropic: every root, both senses
    assert len(speeds) == 4  # each mode crosses the 1× line once here
    assert_allclose(rotor.critical_speeds(backward=True), speeds, rtol=0)
    forward = rotor.critical_speeds(backward=False)
    assert set(forward) <= set(speeds) and len(forward) >= 1
    # Each of them is a peak of the undamped unbalance response (the orbit grows
    # without bound there): the response 0.1 % either side is smaller than 0.01 % off.
    for speed in speeds:
        sides = rotor.unbalance_response(speed * np.array([0.999, 0.9999, 1.0001, 1.001]), 1e-4)
        assert sides[[1, 2]].max() > sides[[0, 3]].max()
    whirl = rotor.whirl(speeds)
    for i, speed in enumerate(speeds):
        j = int(np.argmin(np.abs(whirl.frequencies[i] - speed)))
        assert whirl.frequencies[i, j] == pytest.approx(speed, rel=1e-8)
        assert whirl.forward[i, j] == (speed in forward)


def test_unbalance_response_of_a_symmetric_rotor_in_closed_form() -> None:
    # Uncoupled symmetric rotor, unbalance U at axial position u from the centre:
    # translation U Ω² / (K − m Ω² + i Ω C), tilt U u Ω² / (K_θ − (I_t − I_p) Ω² + i Ω C_θ);
    # a bearing at arm a moves on the circle of radius |x + a γ|.
    k, c, a, u, unbalance = 1e6, 200.0, 0.2, 0.1, 1e-4
    rotor = RigidRotor(ROD, [Bearing(-a, k, c), Bearing(a, k, c)])
    speeds = np.linspace(10.0, 900.0, 40)
    transverse, polar = ROD.inertia[0, 0], ROD.inertia[2, 2]
    w = speeds
    x = unbalance * w**2 / (2 * k - 10.0 * w**2 + 1j * w * 2 * c)
    tilt = (
        unbalance
        * u
        * w**2
        / (2 * k * a * a - (transverse - polar) * w**2 + 1j * w * 2 * c * a * a)
    )
    expected = np.column_stack([np.abs(x - a * tilt), np.abs(x + a * tilt)])
    # One 4 × 4 complex solve a speed: a few ε relative.
    assert_allclose(rotor.unbalance_response(speeds, unbalance, position=u), expected, rtol=1e-9)
    # Isotropic bearings: circular orbits (|x| = |y|, a quarter turn apart).
    orbits = rotor.unbalance_orbits(speeds, unbalance, position=u)
    assert_allclose(np.abs(orbits[..., 0]), np.abs(orbits[..., 1]), rtol=1e-9)


def test_anisotropic_bearings_give_elliptical_orbits() -> None:
    rotor = RigidRotor(ROD, [Bearing(-0.2, (1e6, 4e6), 100.0), Bearing(0.2, (1e6, 4e6), 100.0)])
    orbits = rotor.unbalance_orbits([300.0], "1e-4 kg*m")[0]
    major = rotor.unbalance_response([300.0], 1e-4)[0]
    # The ellipse Re((X, Y) e^{iθ}) sampled: its largest radius is the major semi-axis.
    theta = np.linspace(0, 2 * np.pi, 20001)
    for k in range(2):
        points = np.real(np.outer(np.exp(1j * theta), orbits[k]))
        assert np.max(np.linalg.norm(points, axis=1)) == pytest.approx(major[k], rel=1e-7)
    assert abs(abs(orbits[0, 0]) - abs(orbits[0, 1])) > 0.1 * abs(orbits[0, 0])


def test_refusals() -> None:
    with pytest.raises(tb.InputError, match=r"^Expected `stiffness` >= 0, got -1\.0\.$"):
        Bearing(0.0, -1.0)
    with pytest.raises(
        tb.InputError, match=r"^Expected `damping` >= 0 along x and y, got \[1\.0, -2\.0\]\.$"
    ):
        Bearing(0.0, 1e6, "1, -2 N*s/m")
    with pytest.raises(
        tb.InputError, match=r"stiffness along x at two or more axial positions .*, got 1\.$"
    ):
        RigidRotor(ROD, [Bearing(0.1, 1e6), Bearing(0.1, 2e6)])
    # Held along x only: free to move along y (its frequencies 0, its response infinite).
    with pytest.raises(
        tb.InputError,
        match=r"^Expected bearings with stiffness along y at two or more axial positions \(to "
        r"hold the rotor's tilt\), got 0\.$",
    ):
        RigidRotor(ROD, [Bearing(-0.2, (1e6, 0.0)), Bearing(0.2, (1e6, 0.0))])
    with pytest.raises(
        tb.InputError, match=r"^Expected `speeds` to be finite, got \[0\.0, nan\]\.$"
    ):
        symmetric(ROD).frequencies([0.0, float("nan")])
    with pytest.raises(tb.InputError, match=r"^Expected `speeds` to be finite, got nan\.$"):
        symmetric(ROD).frequencies(float("nan"))
    with pytest.raises(tb.InputError, match=r"^Expected `speeds` to be an angular velocity"):
        symmetric(ROD).frequencies(["1000 rpm", "3 kg"])
    # Speeds with units, one by one in a list.
    assert_allclose(symmetric(ROD).frequencies(["1000 rpm", "2000 rpm"]),
                    symmetric(ROD).frequencies(np.array([1000.0, 2000.0]) * math.pi / 30))  # fmt: skip
    tilted = ROD.transformed(rotation=Rotation.from_rotvec([0.1, 0, 0]))
    with pytest.raises(tb.InputError, match=r"to be a principal axis of the body"):
        RigidRotor(tilted, [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)])
    with pytest.raises(tb.InputError, match=r"^Expected an axisymmetric rotor"):
        RigidRotor(tb.shapes.box(1.0, (0.1, 0.2, 0.5)), [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)])
    with pytest.raises(tb.InputError, match=r"centre of mass on its axis"):
        RigidRotor(
            ROD.transformed(translation=[0.01, 0, 0]), [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)]
        )
    with pytest.raises(tb.InputError, match=r"Bearing objects"):
        RigidRotor(ROD, [(-0.2, 1e6), (0.2, 1e6)])


def test_a_run_at_constant_speed_settles_on_the_steady_unbalance_orbits() -> None:
    # Anisotropic, damped, coupled: after the free vibration has decayed (damping
    # ratios ≥ 0.08 over 1 s at ≥ 280 rad/s: e^{-22} and less), the orbit is
    # Re(A e^{iφ}) with A from the steady solve, φ = Ω t.
    from tumble.models import run_up

    rotor = RigidRotor(ROD.transformed(translation=[0, 0, 0.05]),
                       [Bearing(-0.25, (1e6, 3e6), 4000.0), Bearing(0.2, (2e6, 5e5), 3000.0)])  # fmt: skip
    assert rotor.whirl(400.0).damping_ratios.min() > 0.08
    run = run_up(rotor, 1e-4, duration=1.0, speed=400.0, position=0.1, samples=1001)
    steady = rotor.unbalance_orbits(400.0, 1e-4, position=0.1)[0]
    tail = run.t > 0.9
    expected = np.real(steady[None, :, :] * np.exp(1j * 400.0 * run.t[tail])[:, None, None])
    # RK4 at 200 steps a turn of the fastest mode (1276 rad/s): the forced response
    # is off by O((Ω h)⁴) = (400 × 2.5e-5)⁴ = 1e-8 (3e-10 measured); the transient
    # left is e^{-22}.
    assert_allclose(run.orbits[tail], expected, atol=1e-6 * np.abs(steady).max())


def test_a_run_up_peaks_after_the_critical_speed_and_below_the_steady_peak() -> None:
    # Friswell et al. §3.6: through a resonance at a finite rate the peak is late
    # and lower than the steady one; far below it the response is the steady one.
    from tumble.models import run_up

    rotor = RigidRotor(ROD, [Bearing(-0.2, 1e6, 100.0), Bearing(0.2, 1e6, 100.0)])
    critical = rotor.critical_speeds()[0]
    run = run_up(rotor, 1e-4, duration=2.0, speed=0.0, acceleration=400.0, samples=8001)
    amplitude = run.amplitude[:, 0]
    peak = int(np.argmax(amplitude))
    assert run.speed[peak] > critical
    speeds = np.linspace(0.9 * critical, 1.1 * critical, 2001)
    assert amplitude[peak] < rotor.unbalance_response(speeds, 1e-4)[:, 0].max()
    early = (run.speed > 0.4 * critical) & (run.speed < 0.5 * critical)
    steady = rotor.unbalance_response(run.speed[early], 1e-4)[:, 0]
    # At half the critical speed the slow sweep follows the steady response within
    # the beat of the decaying start-up transient (a few per cent here).
    assert_allclose(amplitude[early], steady, rtol=0.1)


def test_run_up_refusals() -> None:
    from tumble.models import run_up

    rotor = symmetric(ROD)
    with pytest.raises(tb.InputError, match=r"^Expected `duration` > 0 s, got 0\.0\.$"):
        run_up(rotor, 1e-4, duration=0.0)
    with pytest.raises(tb.InputError, match=r"^Expected `samples` to be an integer >= 2, got 1\.$"):
        run_up(rotor, 1e-4, duration=1.0, samples=1)
    with pytest.raises(
        tb.InputError, match=r"^Expected `rotor` to be a tumble\.theory\.RigidRotor"
    ):
        run_up(ROD, 1e-4, duration=1.0)  # type: ignore[arg-type]
    with pytest.raises(
        tb.InputError,
        match=r"^Expected the spin not to reverse during the run, got 100\.0 rad/s at the start "
        r"and -100\.0 rad/s at the end\.$",
    ):
        run_up(rotor, 1e-4, duration=1.0, speed=100.0, acceleration=-200.0)


def test_a_run_up_reports_progress_and_gives_the_rotors_attitude() -> None:
    # A rotor spinning about the body's x axis: its frame is (y, z, x). To first
    # order in the tilts the axis points along n + β e_x − α e_y, the shaft's
    # displacement per unit arm (x + a β, y − a α); the body turns at φ̇ about it.
    from tumble.models import run_up

    body = tb.shapes.solid_cylinder(10.0, 0.05, 0.6).transformed(
        rotation=Rotation.from_rotvec([0.0, math.pi / 2, 0.0]).as_matrix()
    )
    rotor = RigidRotor(body, [Bearing(-0.2, (1e6, 2e6), 300.0), Bearing(0.25, 1e6, 300.0)],
                       axis=(1, 0, 0))  # fmt: skip
    assert_allclose(rotor.frame, [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)
    # An axis a round-off away from a body axis has that axis's frame (the
    # bearings' x and y stay where they were), and each frame is right-handed.
    for axis, expected in (
        ((1e-17, 0, 1), np.eye(3)),
        ((0, 1, 1e-17), [[0, 1, 0], [0, 0, 1], [1, 0, 0]]),
    ):
        frame = RigidRotor(ROD if axis[2] == 1 else ROD.transformed(rotation=Rotation.from_rotvec([-math.pi / 2, 0, 0]).as_matrix()),
                           [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)], axis=axis).frame  # fmt: skip
        assert_allclose(frame, expected, atol=1e-15)
        assert np.linalg.det(frame) == pytest.approx(1.0)
    calls: list[tuple[int, int]] = []
    run = run_up(rotor, 1e-4, duration=0.5, speed=100.0, acceleration=600.0, samples=501,
                 progress=lambda done, total: calls.append((done, total)))  # fmt: skip
    assert calls and calls[-1][0] == calls[-1][1] == run.trajectory.steps
    traj = run.trajectory
    assert_allclose(traj.t, run.t)
    alpha, beta = run.state[:, 2], run.state[:, 3]
    axis = traj.rotation.apply([1.0, 0.0, 0.0])  # space axes are the body's at rest
    expected = np.column_stack([np.ones_like(alpha), beta, -alpha])
    tilt = np.abs(run.state[:, 2:]).max()
    assert tilt > 1e-6
    # Second order in the tilts: the axis off by ~tilt² at most.
    assert_allclose(axis, expected / np.linalg.norm(expected, axis=1)[:, None], atol=tilt**2)
    spin = traj.omega @ [1.0, 0.0, 0.0]
    assert_allclose(spin, run.speed, rtol=tilt)
    # The spin angle: the body's y axis turned by φ = Ω₀ t + Ω̇ t²/2 about x.
    turned = traj.rotation.apply([0.0, 1.0, 0.0])
    phi = 100.0 * run.t + 300.0 * run.t**2
    assert_allclose(turned[:, 1:], np.column_stack([np.cos(phi), np.sin(phi)]), atol=2 * tilt)
    assert traj.conserved_quantities == () and traj.drift == {}


def test_a_zero_axis_is_refused() -> None:
    with pytest.raises(
        tb.InputError,
        match=r"^Expected `axis` to be a non-zero vector, got \[0\.0, 0\.0, 0\.0\]\.$",
    ):
        RigidRotor(ROD, [Bearing(-0.2, 1e6), Bearing(0.2, 1e6)], axis=(0, 0, 0))


def complex_whirl(
    body: tb.MassProperties, bearings: list[tuple[float, float, float]], speed: float
) -> tuple[np.ndarray, np.ndarray]:
    """The damped natural frequencies (ascending) and whether each mode whirls
    forward, for a rotor on isotropic bearings (position, k, c), derived here in
    complex coordinates.

    A bearing at arm a from the centre of mass sees the shaft at
    w = (x + a β) + i (y − a α) = z + a ψ, with z = x + i y and ψ = β − i α, and
    pushes on it with F = F_x + i F_y = −k w − c ẇ. The force moves the centre:
    m z̈ = Σ F. Its moment about the centre, a e_z × F = (−a F_y, a F_x), has
    M_y − i M_x = a F. The angular momentum I_t (α̇, β̇, 0) + I_p Ω (β, −α, 1) (the
    spin along the tilted axis) changes at the moment: I_t α̈ + I_p Ω β̇ = M_x and
    I_t β̈ − I_p Ω α̇ = M_y, so I_t ψ̈ − i I_p Ω ψ̇ = Σ a F. With z = Z e^{st},
    ψ = Ψ e^{st} the two complex equations hold for the roots s of

        det [[m s² + C s + K,  C_a s + K_a],
             [C_a s + K_a,  I_t s² − i I_p Ω s + C_θ s + K_θ]] = 0

    (K = Σk, K_a = Σk a, K_θ = Σk a², C alike), a quartic with complex
    coefficients. Each root s is a mode z ∝ e^{Re(s) t} e^{i Im(s) t}: its orbit
    turns from x to y when Im s > 0, and the spin turns from x to y when Ω > 0,
    so the mode whirls forward (with the spin) when Im(s) Ω > 0. The real
    system's eigenvalues are the four roots and their conjugates: the frequencies
    are |Im s|.
    """
    s = sympy.symbols("s")
    m, transverse, polar = body.mass, body.inertia[0, 0], body.inertia[2, 2]
    arms = [(p - body.center_of_mass[2], k, c) for p, k, c in bearings]

    def total(power: int, which: int) -> sympy.Float:
        return sympy.Float(sum(b[which] * b[0] ** power for b in arms), 30)

    big_k, k_a, k_theta = (total(n, 1) for n in range(3))
    big_c, c_a, c_theta = (total(n, 2) for n in range(3))
    one = lambda value: sympy.Float(value, 30)  # noqa: E731
    determinant = (one(m) * s**2 + big_c * s + big_k) * (
        one(transverse) * s**2 - sympy.I * one(polar * speed) * s + c_theta * s + k_theta
    ) - (c_a * s + k_a) ** 2
    roots = np.array([complex(r) for r in sympy.Poly(sympy.expand(determinant), s).nroots(n=30)])
    order = np.argsort(np.abs(roots.imag))
    return np.abs(roots.imag[order]), roots.imag[order] * speed > 0


@pytest.mark.parametrize(
    ("body", "bearings"),
    [
        (ROD, [(-0.2, 1e6, 0.0), (0.2, 1e6, 0.0)]),
        (DISK.transformed(translation=[0, 0, 0.05]), [(-0.2, 1e6, 0.0), (0.3, 2e6, 0.0)]),
        (ROD.transformed(translation=[0, 0, -0.1]), [(-0.3, 1e6, 300.0), (0.2, 1.5e6, 50.0)]),
    ],
    ids=["symmetric-rod", "coupled-disk", "damped-rod"],
)  # fmt: skip
def test_whirl_directions_follow_the_spin_at_either_sign(body, bearings) -> None:  # type: ignore[no-untyped-def]
    rotor = RigidRotor(body, [Bearing(p, k, c) for p, k, c in bearings])
    speeds = np.array([500.0, 1500.0, 3000.0, -500.0, -1500.0, -3000.0])
    whirl = rotor.whirl(speeds)
    for i, speed in enumerate(speeds):
        frequencies, forward = complex_whirl(body, bearings, speed)
        # Eigenvalues of an 8 × 8 matrix of entries up to 1e8 against 30-digit roots:
        # a few ε relative of the largest.
        assert_allclose(whirl.frequencies[i], frequencies, rtol=1e-9)
        # Modes of one frequency (the cylindrical pair of a symmetric rotor) may come
        # in either order: compare the number of forward ones at each frequency.
        for f in np.unique(np.round(frequencies, 6)):
            ours = np.abs(whirl.frequencies[i] - f) <= 1e-6 * f
            theirs = np.abs(frequencies - f) <= 1e-6 * f
            assert whirl.forward[i, ours].sum() == forward[theirs].sum(), (speed, f)
        # The directions flip with the spin: forward at Ω is backward at −Ω.
        assert whirl.forward[i].sum() == 2
