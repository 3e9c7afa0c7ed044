"""An independent reference integration of a rigid body, for the oracle tests.

Euler's equations in the *body* axes with the full inertia tensor and the
attitude as a rotation matrix, integrated by scipy's DOP853 — written without
any of tumble's kernels (no principal frame, no quaternions), so an error in
either is not shared.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation


def reference(
    mp,
    omega0,
    q0,
    duration,
    pivot=None,
    gravity=(0.0, 0.0, 0.0),
    rtol=1e-13,
    torque: Callable | None = None,
    times=None,
):
    """Body ω and attitude matrix at ``duration`` (or at each of ``times``).

    I ω̇ = τ − ω × I ω about the centre of mass or the pivot, with
    τ = r × (Aᵀ m g) + torque(t, ω, A) (body axes), and Ȧ = A [ω]×.
    """
    inertia = mp.inertia if pivot is None else mp.inertia_about(pivot)
    inverse = np.linalg.inv(inertia)
    lever = np.zeros(3) if pivot is None else mp.center_of_mass - np.asarray(pivot)
    weight = mp.mass * np.asarray(gravity, dtype=float)

    def rhs(t, y):
        w = y[:3]
        a = y[3:].reshape(3, 3)
        tau = np.cross(lever, a.T @ weight)
        if torque is not None:
            tau = tau + torque(t, w, a)
        w_dot = inverse @ (tau - np.cross(w, inertia @ w))
        skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([w_dot, (a @ skew).ravel()])

    a0 = Rotation.from_quat(q0, scalar_first=True).as_matrix()
    sol = solve_ivp(
        rhs,
        (0, duration),
        np.concatenate([omega0, a0.ravel()]),
        method="DOP853",
        rtol=rtol,
        atol=1e-14,
        t_eval=times,
    )
    if times is not None:
        return sol.y[:3].T, sol.y[3:].T.reshape(-1, 3, 3)
    return sol.y[:3, -1], sol.y[3:, -1].reshape(3, 3)


def attitude_error(q, matrix) -> float:
    """Angle (rad) between quaternion rotations and rotation matrices (largest)."""
    return float(
        np.max(
            (
                Rotation.from_quat(q, scalar_first=True) * Rotation.from_matrix(matrix).inv()
            ).magnitude()
        )
    )


def gyrostat_reference(
    mp,
    omega0,
    q0,
    duration,
    rotors=(),
    dampers=(),
    torque: Callable | None = None,
    times=None,
    rtol=1e-13,
    breaks=(),
):
    """A free body carrying rotors and Kane dampers, written from the balance of
    angular momentum with *velocities* as the state, in body axes with the full
    tensor (no principal frame, no momenta, no quaternion).

    ``rotors``: tuples ``(axis, J, speed0, motor(t))``; ``dampers``: ``(J, D)``;
    ``mp`` holds every part as if locked. With ω the body rate, Ω_r the rotors'
    relative rates and ω_d the spheres' absolute rates (body axes)::

        H = (I − Σ J_r a aᵀ − Σ J_d 1) ω + Σ J_r (a·ω + Ω_r) a + Σ J_d ω_d
        dH/dt (inertial) = τ          J_r (a·ω̇ + Ω̇_r) = u_r
        J_d (ω̇_d + ω × ω_d) = D (ω − ω_d)

    Returns ω (n, 3), the attitude matrices (n, 3, 3), the rotor rates (n, k)
    and the sphere rates (n, 3 d) at ``times`` (or at ``duration`` alone).
    ``breaks``: times where a motor's torque jumps; the integration restarts
    there, so no step straddles a jump.
    """
    inertia = np.asarray(mp.inertia, dtype=float)
    axes = [np.asarray(a, dtype=float) / np.linalg.norm(a) for a, *_ in rotors]
    platform = inertia.copy()
    for a, (_, j, *_) in zip(axes, rotors, strict=True):
        platform -= j * np.outer(a, a)
    for j, _ in dampers:
        platform -= j * np.eye(3)
    solve = np.linalg.inv(platform)
    k = len(rotors)

    def rhs(t, y):
        w = y[:3]
        a_matrix = y[3:12].reshape(3, 3)
        speeds = y[12 : 12 + k]
        spheres = y[12 + k :].reshape(-1, 3)
        h = platform @ w
        for a, (_, j, *_), speed in zip(axes, rotors, speeds, strict=True):
            h = h + j * (a @ w + speed) * a
        for (j, _), sphere in zip(dampers, spheres, strict=True):
            h = h + j * sphere
        tau = np.zeros(3) if torque is None else torque(t, w, a_matrix)
        # The body's own balance: I_p ω̇ = τ − ω × H − Σ u a − Σ J_d (ω̇_d + ω × ω_d).
        rhs_w = tau - np.cross(w, h)
        motors = [motor(t) for _, _, _, motor in rotors]
        for a, u in zip(axes, motors, strict=True):
            rhs_w = rhs_w - u * a
        sphere_rates = []
        for (j, d), sphere in zip(dampers, spheres, strict=True):
            coupling = d * (w - sphere)
            sphere_dot = coupling / j - np.cross(w, sphere)
            rhs_w = rhs_w - j * sphere_dot
            sphere_rates.append(sphere_dot)
        w_dot = solve @ rhs_w
        speed_rates = [
            u / j - a @ w_dot for a, (_, j, *_), u in zip(axes, rotors, motors, strict=True)
        ]
        skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([w_dot, (a_matrix @ skew).ravel(), speed_rates, *sphere_rates])

    a0 = Rotation.from_quat(q0, scalar_first=True).as_matrix()
    start = np.concatenate(
        [omega0, a0.ravel(), [speed for _, _, speed, _ in rotors], *([omega0] * len(dampers))]
    )
    edges = [0.0, *sorted(b for b in breaks if 0 < b < duration), duration]
    wanted = np.array([duration]) if times is None else np.asarray(times, dtype=float)
    pieces = []
    for first, last in itertools.pairwise(edges):
        inside = wanted[(wanted >= first) & ((wanted < last) | (last == duration))]
        sol = solve_ivp(
            rhs, (first, last), start, method="DOP853", rtol=rtol, atol=1e-14,
            t_eval=np.union1d(inside, [last]), max_step=duration / 50,
        )  # fmt: skip
        pieces.append(sol.y[:, : inside.size].T)
        start = sol.y[:, -1]
    y = np.concatenate(pieces)[: wanted.size]
    return y[:, :3], y[:, 3:12].reshape(-1, 3, 3), y[:, 12 : 12 + k], y[:, 12 + k :]


def spring_mass_reference(mp, mass, position, direction, stiffness, damping, omega0, q0,
                          duration, displacement=0.0, times=None, rtol=1e-12):  # fmt: skip
    """A free body carrying a point mass on a spring, by Newton–Euler: the hub about
    its own centre of mass and the mass relative to it (the two-body problem,
    reduced mass μ), joined by the slot's constraint force, solved for at each
    step (no Lagrangian, no momenta, no inertia about the moving centre of mass).

    With d = d0 + x n from the hub's centre of mass to the mass (body axes) and F
    the force of the hub on the mass, ``F = (−k x − c ẋ) n + f``, f ⟂ n::

        μ (ẍ n + 2 ω × ẋ n + ω̇ × d + ω × (ω × d)) = F
        I_h ω̇ + ω × I_h ω = −d × F

    Returns ω (n, 3), the attitude matrices (n, 3, 3), x (n,) and ẋ (n,).
    """
    total = mp.mass
    reduced = mass * (total - mass) / total
    n = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    rest = (total / (total - mass)) * (np.asarray(position, dtype=float) - mp.center_of_mass)
    inertia = mp.inertia - reduced * (rest @ rest * np.eye(3) - np.outer(rest, rest))
    helper = np.eye(3)[int(np.argmin(np.abs(n)))]
    u1 = np.cross(n, helper)
    u1 /= np.linalg.norm(u1)
    u2 = np.cross(n, u1)

    def rhs(t, y):
        w = y[:3]
        a = y[3:12].reshape(3, 3)
        x, v = y[12], y[13]
        d = rest + x * n
        along = -stiffness * x - damping * v
        # Unknowns (ω̇, ẍ, f1, f2): six linear equations.
        system = np.zeros((6, 6))
        right = np.zeros(6)
        system[:3, :3] = -reduced * np.array(
            [[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]]
        )  # μ ω̇ × d = −μ [d]× ω̇
        system[:3, 3] = reduced * n
        system[:3, 4] = -u1
        system[:3, 5] = -u2
        right[:3] = along * n - reduced * (2 * v * np.cross(w, n) + np.cross(w, np.cross(w, d)))
        system[3:, :3] = inertia
        system[3:, 4] = np.cross(d, u1)
        system[3:, 5] = np.cross(d, u2)
        right[3:] = -np.cross(w, inertia @ w) - along * np.cross(d, n)
        solution = np.linalg.solve(system, right)
        skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([solution[:3], (a @ skew).ravel(), [v, solution[3]]])

    a0 = Rotation.from_quat(q0, scalar_first=True).as_matrix()
    start = np.concatenate([omega0, a0.ravel(), [displacement, 0.0]])
    sol = solve_ivp(rhs, (0, duration), start, method="DOP853", rtol=rtol, atol=1e-14,
                    t_eval=times, max_step=duration / 50)  # fmt: skip
    y = sol.y.T
    return y[:, :3], y[:, 3:12].reshape(-1, 3, 3), y[:, 12], y[:, 13]


def taylor_gyrostat(platform, axis, h, omega0, times, digits=30) -> np.ndarray:
    """ω (n, 3), rad/s, at ``times`` (s) of a torque-free gyrostat: a platform of
    principal moments ``platform`` (kg·m², body axes principal) whose rotors'
    absolute momentum ``h`` (kg·m²/s, constant without motors) lies along the
    principal ``axis``, from ``omega0`` (rad/s). Ḣ = H × ω with H = I_p ω + h a,
    integrated by mpmath's Taylor-series method (odefun) at ``digits`` digits:
    near a separatrix, where DOP853's 1e-13 grows with the motion's sensitivity
    to its state. The numbers given (floats, or mpmath numbers formed at that
    precision) are taken as exact."""
    import mpmath

    with mpmath.workdps(digits):
        a = [mpmath.mpf(v) for v in axis]
        moments = [mpmath.mpf(v) for v in platform]
        momentum = mpmath.mpf(h)

        def rate(t, m):
            w = [(m[k] - momentum * a[k]) / moments[k] for k in range(3)]
            return [m[1] * w[2] - m[2] * w[1], m[2] * w[0] - m[0] * w[2], m[0] * w[1] - m[1] * w[0]]

        start = [moments[k] * mpmath.mpf(omega0[k]) + momentum * a[k] for k in range(3)]
        solution = mpmath.odefun(rate, 0, start)
        rows = [solution(mpmath.mpf(float(t))) for t in times]
        return np.array(
            [[float((m[k] - momentum * a[k]) / moments[k]) for k in range(3)] for m in rows]
        )
