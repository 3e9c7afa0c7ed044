"""
A user torque in numba
======================

When no built-in model of :mod:`tumble.torques` fits, write the torque as a Python
function compiled with numba and wrap it in :class:`tumble.torques.UserTorque`.
The integrators call it at every stage of every step from compiled code, with no
Python in the loop. This page writes two: a motor torque fixed in the body,
checked against the linear spin-up it must give, and a magnetic torque that
depends on the attitude, given with its potential energy so that the trajectory's
energy includes it, checked against the exact period of a pendulum.
"""

# %%
# The signature
# -------------
#
# The function takes five arguments and returns nothing::
#
#     function(t, omega, quaternion, params, out)
#
# * ``t``: the time, s (a float);
# * ``omega``: the angular velocity, rad/s, in **body axes** (those of the body's
#   :class:`tumble.MassProperties`, principal or not), a (3,) array;
# * ``quaternion``: the attitude ``[w, x, y, z]``, rotating body coordinates into
#   space coordinates, a (4,) array;
# * ``params``: your parameters, a (k,) float64 array: the plain numbers given to
#   ``UserTorque(function, params)``, passed through unchanged (use SI units);
# * ``out``: a (3,) array, zero on entry, into which the function writes the torque
#   on the body about its centre of mass (or the pivot), N·m, in **body axes**.
#
# Decorate it with ``numba.njit``. ``UserTorque`` calls it once on a test state,
# so a wrong signature fails at once rather than in the middle of a run.
#
# A torque that derives from a potential energy :math:`U(t, q)` (a conservative
# torque) may give it too, as a second function compiled with numba that returns
# a number, in joules::
#
#     potential(t, quaternion, params) -> float
#
# with the same ``t``, ``quaternion`` (body → space) and ``params``:
# ``UserTorque(function, params, potential=potential)``. The trajectory's
# ``energy`` is then :math:`T + U` (``potential_energy`` is :math:`U` alone), and
# its file keeps :math:`U` in a ``potential_energy`` column. The torque must be
# :math:`U`'s gradient: a rotation by :math:`\delta\theta` about a body axis
# :math:`\mathbf e` changes :math:`U` by :math:`-\boldsymbol\tau\cdot\mathbf e\,
# \delta\theta`; tumble trusts the two functions to agree.
#
# A motor torque about the symmetry axis
# --------------------------------------
#
# A solid cylinder (a rotor, symmetry axis along body z) spun up by a constant
# torque :math:`\tau` about that axis, while it also wobbles. For a symmetric body
# (:math:`I_1 = I_2`) Euler's third equation,
# :math:`I_3\dot\omega_3 = \tau + (I_1 - I_2)\,\omega_1\omega_2 = \tau`
# (Goldstein, *Classical Mechanics* §5.5), gives a linear spin-up whatever the wobble,
#
# .. math::
#
#    \omega_3(t) = \omega_3(0) + \frac{\tau\, t}{I_3},
#
# and the first two give a transverse :math:`\omega_\perp` that turns about the axis
# with a constant length.

import math

import numba
import numpy as np
from scipy.special import ellipk

import tumble as tb


@numba.njit
def axial_motor(t, omega, quaternion, params, out):
    # params[0]: the motor torque about body z, N·m.
    out[2] = params[0]


rotor = tb.shapes.solid_cylinder("2 kg", radius="10 cm", height="5 cm")
torque = 0.05  # N·m
omega0 = [0.5, 0.0, 10.0]  # rad/s, body axes: a spin with a wobble
run = tb.simulate(
    rotor, omega0, duration=10.0, dt=0.01, torque=tb.torques.UserTorque(axial_motor, [torque])
)
print(run.method, "—", run.reason)

i3 = rotor.inertia[2, 2]
expected = omega0[2] + torque * run.t / i3
print(f"ω3 at the end: {run.omega[-1, 2]:.9f} rad/s, τ t / I3 gives {expected[-1]:.9f} rad/s")
print(f"largest |ω3 − (ω3(0) + τ t / I3)|: {np.max(np.abs(run.omega[:, 2] - expected)):.1e} rad/s")
transverse = np.hypot(run.omega[:, 0], run.omega[:, 1])
print(f"|ω⊥| from {transverse.min():.12f} to {transverse.max():.12f} rad/s")
# ω3' is constant, which every Runge–Kutta method integrates exactly: only the
# adaptive method's tolerance (rtol 1e-10 per step) and round-off remain.
assert np.allclose(run.omega[:, 2], expected, rtol=1e-8, atol=0)
assert np.allclose(transverse, transverse[0], rtol=1e-8)

# %%
# ``"auto"`` chose the adaptive method: without a potential energy, a user torque
# counts as not conservative. tumble reads from the function's code which of
# ``t``, ``omega`` and ``quaternion`` it uses (an argument passed on to a helper
# counts as used); ``axial_motor`` uses none:

print(sorted(tb.torques.UserTorque(axial_motor, [torque]).depends_on))

# %%
# Every ``method`` but ``"exact"`` accepts a user torque; the splittings hold it
# fixed during each kick, which is first order in a torque that depends on ω.
#
# The built-in :class:`tumble.torques.ConstantBodyTorque` is the same torque, and
# gives the same motion:

built_in = tb.simulate(
    rotor, omega0, duration=10.0, dt=0.01, torque=tb.torques.ConstantBodyTorque([0, 0, torque])
)
print(f"largest difference in ω: {np.max(np.abs(built_in.omega - run.omega)):.1e} rad/s")
# The same equations, the same method and tolerances: round-off apart.
assert np.allclose(built_in.omega, run.omega, rtol=1e-9, atol=1e-9)

# %%
# Prefer a built-in model where one exists: built-in models can also go into
# scenario files, sweeps and (most of them) :func:`tumble.simulate_batch`; a user
# function goes into :func:`tumble.simulate` only.
#
# A torque that depends on the attitude: a compass needle
# -------------------------------------------------------
#
# A magnetised needle, its dipole moment :math:`\mathbf m` along body x, in a
# uniform field :math:`\mathbf B` fixed in space, feels
# :math:`\boldsymbol\tau = \mathbf m \times \mathbf B`. Both vectors must be in body
# axes, so the function turns :math:`\mathbf B` into body coordinates with the
# transpose of the attitude's rotation matrix,
# :math:`\mathbf B_\text{body} = \mathsf R^{\mathsf T}\mathbf B_\text{space}`. A
# helper compiled with ``numba.njit`` can be called from the torque function.
# The torque derives from the potential energy
# :math:`U = -\mathbf m\cdot\mathbf B_\text{body}` (J), a function of the
# attitude alone, which ``needle_energy`` gives.


@numba.njit
def to_body(q, v):
    """Space coordinates → body coordinates: Rᵀ v, R the rotation of the unit
    quaternion q = [w, x, y, z] (body → space)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    return (
        (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y + w * z) * v[1] + 2 * (x * z - w * y) * v[2],
        2 * (x * y - w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z + w * x) * v[2],
        2 * (x * z + w * y) * v[0] + 2 * (y * z - w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2],
    )


@numba.njit
def magnet_in_field(t, omega, quaternion, params, out):
    # params: the dipole moment along body x, A·m², then B in space axes, T.
    _, by, bz = to_body(quaternion, params[1:4])
    # m × B with m = (params[0], 0, 0).
    out[1] = -params[0] * bz
    out[2] = params[0] * by


@numba.njit
def needle_energy(t, quaternion, params):
    # U = −m · B_body, J (m along body x).
    bx, _, _ = to_body(quaternion, params[1:4])
    return -params[0] * bx


# %%
# A needle 6 cm long, moment 0.05 A·m², in a field of 50 µT along space x (the
# order of the Earth's), released at rest 60° away from the field, turning about
# body z. It swings like a pendulum, :math:`I_z\ddot\theta = -mB\sin\theta`, whose
# period at amplitude :math:`\theta_0` is exactly
#
# .. math::
#
#    T = \frac{4}{\omega_0} K\!\left(\sin^2\frac{\theta_0}{2}\right),
#    \qquad \omega_0 = \sqrt{\frac{mB}{I_z}},
#
# with :math:`K(m)` the complete elliptic integral of the first kind (Landau &
# Lifshitz, *Mechanics* §11; scipy's ``ellipk`` takes the parameter :math:`m`).

needle = tb.shapes.box("20 g", "6, 0.6, 0.2 cm")
moment, field = 0.05, [50e-6, 0.0, 0.0]  # A·m², T
theta0 = math.radians(60)
start = [math.cos(theta0 / 2), 0.0, 0.0, math.sin(theta0 / 2)]  # 60° about z
magnet = tb.torques.UserTorque(magnet_in_field, [moment, *field], potential=needle_energy)
swing = tb.simulate(needle, [0, 0, 0], attitude0=start, duration=60.0, dt=0.01, torque=magnet)
print(magnet, "—", swing.method, "—", swing.reason)

omega_small = math.sqrt(moment * 50e-6 / needle.inertia[2, 2])
period_exact = 4 * ellipk(math.sin(theta0 / 2) ** 2) / omega_small
period_run = 2 * math.pi / tb.analysis.oscillation_frequency(swing.t, swing.omega[:, 2])
print(f"period: simulated {period_run:.6f} s, exact {period_exact:.6f} s, "
      f"small-angle 2π/ω0 = {2 * math.pi / omega_small:.6f} s")  # fmt: skip
# The fourth-order splitting at 100 steps a second on a swing of ~10 s, and maxima
# located to a fraction of the 0.01 s sampling over several swings: 1e-5 of the
# period is ample.
assert abs(period_run / period_exact - 1) < 1e-5

# %%
# The torque and its potential read only the attitude, so the model is conservative:
# ``"auto"`` took the symplectic splitting, and the drift report lists the energy.
# Kinetic and potential energy trade places as the needle swings (at 60° from the
# field, :math:`U = -mB\cos 60^\circ`; through the field, :math:`U = -mB`), while
# their sum stays:

potential = swing.potential_energy
kinetic = swing.energy - potential
swing_energy = moment * 50e-6 / 2  # m B (1 − cos 60°), J
print(f"U from {potential.min():.6e} to {potential.max():.6e} J, "
      f"T up to {kinetic.max():.6e} J (m B (1 − cos 60°) = {swing_energy:.6e} J)")  # fmt: skip
print("relative drift:", swing.drift)
assert swing.conserved_quantities == ("energy",)
# A symplectic method keeps the energy error bounded, without growth over the
# swings: of the order of (ω0 dt)^4 ≈ 2e-9 for a fourth-order method at this step.
assert swing.drift["energy"] < 1e-9
assert abs(kinetic.max() / swing_energy - 1) < 1e-6

# %%
# The heading swings between ±60° (read from the quaternion, a rotation about z):

heading = np.degrees(2 * np.arctan2(swing.quaternion[:, 3], swing.quaternion[:, 0]))
print(f"heading from {heading.min():.4f}° to {heading.max():.4f}°")

# %%
# Rules of thumb
# --------------
#
# * Only one ``UserTorque`` per sum: compute both torques in one function. It adds
#   to built-in models with ``+`` (``UserTorque(...) + tb.torques.LinearDamping(...)``).
# * Keep the function free of Python objects (numba's ``nopython`` mode): numbers
#   and arrays in, the torque in ``out``. One compiled function serves any
#   ``params``; each new function costs its own compilation once per process (a
#   fraction of a second).
# * ``actuator="rotors"`` makes the body's rotors produce the torque instead of
#   an outside agent, so the total angular momentum stays.
# * Give the potential energy of a conservative torque (``potential=``): the
#   energy and its drift then mean what they should. A potential that reads ``t``,
#   or a torque that reads ``omega``, makes the model not conservative (the energy
#   still includes :math:`U`, but nothing is reported as conserved).
