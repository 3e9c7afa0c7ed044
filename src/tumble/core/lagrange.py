"""The heavy symmetric (Lagrange) top in closed form, compiled.

A body with moments A, A, C about a fixed pivot on its symmetry axis e, its
centre of mass on that axis, under uniform gravity. Let k be the unit vertical
pointing away from the centre of mass's lowest position (k = up when the
centre of mass is above the pivot along +e, else down), ``β = 2 m g |l| / A``
and, in the body frame with e third, ω = (ω1, ω2, n) and k = (k1, k2, u) with
``u = cos θ``. The spin n, ``b = L·k / A`` and the energy are constant, and
(Goldstein §5.7; Whittaker §71; Landau & Lifshitz §35)

    u̇² = f(u) = (1 − u²)(α − β u) − (b − a u)²,   a = C n / A,

a cubic with roots ``−1 ≤ u1 ≤ u2 ≤ 1 ≤ u3`` (f(±1) = −(b ∓ a)² ≤ 0), so

    u(t) = u1 + (u2 − u1) sn²(p t + τ0 | m),  m = (u2 − u1)/(u3 − u1),  p = √(β (u3 − u1)) / 2.

With z-x-z Euler angles about k (precession φ, tilt θ, spin ψ; body → space
``Rz(φ) Rx(θ) Rz(ψ)``):

    φ̇ + ψ̇ = n − a + (b + a)/(1 + u),   φ̇ − ψ̇ = −(n − a) + (b − a)/(1 − u),

so the attitude quaternion ``(c cos α₊, s cos α₋, s sin α₋, c sin α₊)``
(``c = cos θ/2``, ``s = sin θ/2``, ``α± = (φ ± ψ)/2``) needs only the two
integrals ``J± = ∫ dt / (1 ± u)``: elliptic integrals of the third kind,
written with Carlson's R_J and R_C so that every term is positive (DLMF
19.25.14 for ``1 − u``; for ``1 + u``, whose characteristic is negative, the
companion form of DLMF 19.7.9, which avoids the cancellation between F and R_J
when the axis passes close to the lowest point). Each sample is O(1): the
phase ``p t + τ0`` is carried in double-double and reduced to the half period
2K, whose whole count multiplies the complete integrals.

The roots are found from expansions that keep their differences: the cubic
about u0 (``f(u0 + x) = d + f1 x + f2 x² + β x³`` with ``d = u̇0² ≥ 0``,
every coefficient from the state itself), whose large root x3 is isolated and
whose pair x1 ≤ 0 ≤ x2 solves a quadratic with a discriminant that is a sum of
squares (steady precession: a double root); and the cubic about u = 1 in
``w = 1 − u`` (constant term ``−(b − a)² ≤ 0``), whose pair near the pole gives
``1 − u2`` and ``u3 − u2`` without cancellation (the sleeping top, the
separatrix ``u2 = u3 = 1``). When the axis passes exactly through a pole
(``b = a``, or ``b = −a`` at the lowest point), the Euler angles turn
smoothly with a signed θ instead: ``sin θ/2 ∝ cn``, ``cos θ/2 ∝ sn``.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit
from tumble.core.elliptic import (
    dd_add,
    ellipk_mc,
    elliprc,
    elliprf,
    elliprj,
    inverse_period,
    jacobi_from_table,
    jacobi_table,
    two_prod,
)
from tumble.core.quaternion import multiply

__all__ = [
    "CONSTANTS",
    "top_constants",
    "top_mean_rates",
    "top_motion",
    "top_start",
    "top_turning_points",
]

# Layout of the constants from :func:`top_constants`.
_P, _TAU0, _MC, _D, _TOP, _BOT, _INV31, _E, _EP, _A, _N, _PSI0 = range(12)
_UPPER, _LOWER, _K, _INV_HI, _INV_LO, _DJM, _DJP, _JM0, _JP0, _THETA0 = range(12, 22)
#: Length of the constants array.
CONSTANTS = 22

# Newton's method on the cubic: at most this many steps (it converges
# monotonically from above the largest root; quadratically once near it).
_MAX_NEWTON = 200


@njit(inline="always")
def _cubic(x, d, f1, f2, beta):  # type: ignore[no-untyped-def]
    """f(u0 + x) and its derivative, from the expansion about u0."""
    return d + x * (f1 + x * (f2 + beta * x)), f1 + x * (2.0 * f2 + 3.0 * beta * x)


@njit
def _largest_root_scaled(d, f1, f2, beta, start):  # type: ignore[no-untyped-def]
    """``q = β x3``, where x3 is the largest root of ``d + f1 x + f2 x² + β x³``
    (β > 0, three real roots), by Newton's method from ``start`` = β x above it:
    the cubic is convex right of its inflection point (the mean of the roots), so
    the iterates decrease to it. The cubic and its slope are evaluated divided by
    x² (the same Newton steps), so that x3 ~ −f2/β may exceed the float range
    when the weight's term β is tiny: q stays of the order of the other terms."""
    q = start
    for _ in range(_MAX_NEWTON):
        if not q > 0.0:
            break
        ratio = beta / q  # 1 / x
        value = q + f2 + ratio * (f1 + ratio * d)  # f / x²
        slope = 3.0 + (2.0 * f2 + ratio * f1) / q  # f' / (β x²)
        if not slope > 0.0 or not value > 0.0:
            break
        step = value / slope
        q -= step
        if not step > 1e-16 * abs(q + step):
            break
    return q


@njit
def _polish(x, d, f1, f2, beta):  # type: ignore[no-untyped-def]
    """A simple root of the cubic refined by Newton's method (a few steps)."""
    for _ in range(8):
        value, slope = _cubic(x, d, f1, f2, beta)
        if slope == 0.0:
            break
        step = value / slope
        x -= step
        if not abs(step) > 1e-16 * abs(x):
            break
    return x


@njit
def _lowest(z, e_bottom, g_bottom, a, beta):  # type: ignore[no-untyped-def]
    """``1 + u1`` to full relative accuracy: the smallest root of the cubic about
    u = −1, ``−(b + a)² + 2 (G' + a (b + a)) z − (2β + G' + a²) z² + β z³`` with
    ``G' = α + β`` (a sum of positive terms), by Newton's method from the estimate
    ``z`` (``1 + u0 + x1``, which loses digits when the axis nears the lowest point)."""
    c1 = 2.0 * (g_bottom + a * e_bottom)
    c2 = -(2.0 * beta + g_bottom + a * a)
    c0 = -e_bottom * e_bottom
    if not z > 0.0:
        z = -c0 / c1 if c1 > 0.0 else 0.0
    for _ in range(8):
        value = c0 + z * (c1 + z * (c2 + beta * z))
        slope = c1 + z * (2.0 * c2 + 3.0 * beta * z)
        if not slope > 0.0:
            break
        step = value / slope
        if z - step <= 0.0:
            z *= 0.5
            continue
        z -= step
        if not abs(step) > 1e-16 * z:
            break
    return z


@njit(inline="always")
def _pair_about_start(d, f1, f2, beta, w0, z0, e_bottom):  # type: ignore[no-untyped-def]
    """The pair of roots x1 ≤ 0 ≤ x2 of the cubic about u0 (x = u − u0), the
    amplitude u2 − u1 and q = β x3 (:func:`top_constants`' notation), deflating the
    isolated root x3 ≥ 1 − u0: Q x² − B x − d = 0 with Q = β x3, B = f1 + d / x3;
    B² + 4 Q d ≥ 0. The large root enters only as q (it may itself exceed the
    float range)."""
    q = _largest_root_scaled(d, f1, f2, beta, max(beta * w0, beta * z0 - f2))
    big_b = f1 + (d * (beta / q) if q > 0.0 else 0.0)
    root = math.hypot(big_b, 2.0 * math.sqrt(q * d))  # no underflow of B² when the weight is tiny
    if big_b >= 0.0:
        x2 = (big_b + root) / (2.0 * q)
        x1 = -2.0 * d / (big_b + root) if big_b + root > 0.0 else 0.0
    else:
        x1 = (big_b - root) / (2.0 * q)
        x2 = -2.0 * d / (big_b - root)
    amplitude = root / q  # u2 − u1
    if e_bottom == 0.0:
        x1 = -z0  # the axis passes through the lowest point: u1 = −1 exactly
    return x1, x2, amplitude, q


@njit(inline="always")
def _pair_about_pole(far, e_top, g, a, beta):  # type: ignore[no-untyped-def]
    """``(1 − u2, β (u3 − u2))``: the pair of roots about u = 1 in w = 1 − u,
    deflating ``far`` = w1 = 1 − u1, times β: β w² + s1 w + s0 = 0, s0 = −(b −
    a)²/w1 ≤ 0, so s1² − 4 β s0 ≥ 0; its roots 1 − u2 ≥ 0 and 1 − u3 ≤ 0 differ
    by root_w / β."""
    s0 = -e_top * e_top / far
    s1 = (2.0 * (g - a * e_top) - e_top * e_top / far) / far
    root_w = math.hypot(s1, 2.0 * math.sqrt(-beta * s0))
    if s1 <= 0.0:
        w_2 = (root_w - s1) / (2.0 * beta)
        top = 0.0 if w_2 <= 0.0 else w_2
    else:
        top = -2.0 * s0 / (s1 + root_w)  # the product of the roots over 1 − u3
        top = 0.0 if top <= 0.0 else top
    return top, root_w


@njit(inline="always")
def _start_argument(below, above, amplitude, beta, scaled31, scaled32):  # type: ignore[no-untyped-def]
    """|τ0|, the argument at t = 0, from u0 − u1 (``below``) and u2 − u0
    (``above``): sn² = (u0 − u1)/D, cn² = (u2 − u0)/D, dn² = (u3 − u0)/(u3 − u1);
    zero when the tilt is constant (D = 0)."""
    if amplitude <= 0.0:
        return 0.0
    sn2 = min(below / amplitude, 1.0)
    cn2 = min(above / amplitude, 1.0)
    dn2 = (beta * above + scaled32) / scaled31
    return math.sqrt(sn2) * elliprf(cn2, dn2, 1.0)


@njit(inline="always")
def _periods(c):  # type: ignore[no-untyped-def]
    """Into ``c``: K and 1 / 4K in double-double (infinite K at mc = 0, the
    separatrix), and the integrals p J∓ over a half period 2K of the argument."""
    mc, p, amplitude, top, bottom = c[_MC], c[_P], c[_D], c[_TOP], c[_BOT]
    if mc <= 0.0:
        c[_K] = math.inf
        return
    big_k = ellipk_mc(mc)
    fh, fl = inverse_period(mc, 0.0)  # 1 / 4K
    c[_K], c[_INV_HI], c[_INV_LO] = big_k, 2.0 * fh, 2.0 * fl
    if c[_E] != 0.0:
        far_u = top + amplitude  # 1 − u1
        n_top = amplitude / far_u
        whole = big_k + n_top / 3.0 * elliprj(0.0, mc, 1.0, top / far_u)
        c[_DJM] = 2.0 * whole / (far_u * p)
    if c[_EP] != 0.0:
        inverse31 = c[_INV31]
        reach = 1.0 + bottom * inverse31  # (u3 + 1) / (u3 − u1)
        whole = 0.5 * math.pi / math.sqrt(bottom * (bottom + amplitude) * reach)
        whole += elliprj(0.0, mc, 1.0, reach) * inverse31 / 3.0
        c[_DJP] = 2.0 * whole / p


@njit
def top_constants(beta, a, spin, k1, k2, k3, w1, w2):  # type: ignore[no-untyped-def]
    """The constants of the closed-form Lagrange top (the module docstring's
    notation), from its state at t = 0 in the body frame with the symmetry axis
    third: the unit vertical k (k1, k2, k3), the transverse ω (w1, w2) and the
    spin n (rad/s); ``β = 2 m g |l| / A`` (1/s², > 0) and ``a = C n / A`` (rad/s).

    Returns an array of :data:`CONSTANTS` values for :func:`top_motion`. Not
    for a body at rest on the vertical with no transverse rate (a sleeping top:
    a steady rotation, for the caller).
    """
    c = np.zeros(CONSTANTS)
    s2 = k1 * k1 + k2 * k2  # sin² θ0
    u0 = k3
    w0 = s2 / (1.0 + u0) if u0 > 0.0 else 1.0 - u0  # 1 − u0
    z0 = s2 / (1.0 - u0) if u0 < 0.0 else 1.0 + u0  # 1 + u0
    transverse = w1 * w1 + w2 * w2  # θ̇² + φ̇² sin² θ
    along = w1 * k1 + w2 * k2  # b − a u0 = φ̇ sin² θ
    rate = k1 * w2 - k2 * w1  # u̇0
    d = rate * rate
    f1 = 2.0 * a * along - 2.0 * u0 * transverse - beta * s2
    f2 = 2.0 * beta * u0 - transverse - a * a
    e_top = along - a * w0  # b − a
    e_bottom = along + a * z0  # b + a
    g = transverse - beta * w0  # α − β

    x1, x2, amplitude, q = _pair_about_start(d, f1, f2, beta, w0, z0, e_bottom)
    # Near the separatrix (u2, u3 → 1) the pair about the pole is the closer one:
    # x3 − x2 < x2 − x1, times β.
    near_pole = e_top == 0.0 or (q - beta * x2) < beta * (x2 - x1)
    if near_pole and e_bottom != 0.0:
        x1 = min(_polish(x1, d, f1, f2, beta), 0.0)
    far = w0 - x1
    top, scaled32 = _pair_about_pole(far, e_top, g, a, beta)
    if near_pole:
        amplitude = far - top
        below, above = -x1, w0 - top  # u0 − u1, u2 − u0
        if above < below:
            # Near the upper turning point w0 − top loses digits, and τ0 would lose
            # half of them (cn ∝ √(u2 − u0)): take u2 − u0 from the product of the
            # roots about u0 instead, d = β (u0 − u1)(u2 − u0)(u3 − u0).
            above = d / (below * q) if below * q > 0.0 else 0.0
    else:
        below, above = -x1, x2
    below = max(below, 0.0)
    above = max(above, 0.0)
    bottom = z0 + x1
    if e_bottom == 0.0:
        bottom = 0.0
    elif bottom < 0.5 * z0:
        # The difference lost digits; u1 is then far from u0 (u2 − u1 ≥ u0 − u1 >
        # (1 + u0)/2), so a simple root that Newton's method refines from here.
        bottom = _lowest(bottom, e_bottom, transverse + beta * z0, a, beta)
    scaled31 = beta * amplitude + scaled32  # β (u3 − u1)
    mc = scaled32 / scaled31
    p = 0.5 * math.sqrt(scaled31)
    inverse31 = beta / scaled31  # 1 / (u3 − u1): may underflow to 0 harmlessly

    upper = e_top == 0.0 and top == 0.0
    tau0 = _start_argument(below, above, amplitude, beta, scaled31, scaled32)
    if amplitude > 0.0 and (rate < 0.0 or (rate == 0.0 and upper and s2 == 0.0)):
        tau0 = -tau0
    if s2 == 0.0:  # on the vertical: θ̇0 = |ω⊥| ≥ 0 along the node line ψ0
        psi0 = math.atan2(-w2, w1)
        theta0 = 0.0 if u0 > 0.0 else math.pi
    else:
        psi0 = math.atan2(k1, k2)
        theta0 = math.atan2(math.sqrt(s2), u0)
    lower = 0.0
    if e_bottom == 0.0 and bottom == 0.0:
        lower = 1.0 if tau0 > 0.0 else -1.0

    c[_P], c[_TAU0], c[_MC], c[_D] = p, tau0, mc, amplitude
    c[_TOP], c[_BOT], c[_INV31] = top, bottom, inverse31
    c[_E], c[_EP], c[_A], c[_N], c[_PSI0] = e_top, e_bottom, a, spin, psi0
    c[_UPPER], c[_LOWER], c[_THETA0] = 1.0 if upper else 0.0, lower, theta0
    _periods(c)
    if amplitude > 0.0:
        sn, cn, dn = _jacobi(tau0, c)
        c[_JM0], c[_JP0] = _integrals(sn, cn, dn, tau0, c)
    return c


@njit(inline="always")
def _jacobi(r, c):  # type: ignore[no-untyped-def]
    """sn, cn, dn of a reduced argument |r| ≤ K."""
    mc = c[_MC]
    if mc > 0.0:
        return jacobi_from_table(r, jacobi_table(mc, 0.0, False))
    return math.tanh(r), 1.0 / math.cosh(r), 1.0 / math.cosh(r)


@njit(inline="always")
def _integrals(sn, cn, dn, r, c):  # type: ignore[no-untyped-def]
    """p J− and p J+ from argument 0 to r (|r| ≤ K): ``∫ dv / (1 ∓ u)``, with
    u = u1 + D sn²(v); zero where their coefficient b ∓ a vanishes."""
    amplitude, top, bottom, inverse31 = c[_D], c[_TOP], c[_BOT], c[_INV31]
    minus = 0.0
    plus = 0.0
    s3 = sn * sn * sn
    if c[_E] != 0.0:
        far = top + amplitude  # 1 − u1
        n_top = amplitude / far
        ratio = (top + amplitude * cn * cn) / far
        minus = r + n_top / 3.0 * s3 * elliprj(cn * cn, dn * dn, 1.0, ratio)
        minus /= far
    if c[_EP] != 0.0:
        scaled = 1.0 + bottom * sn * sn * inverse31
        plus = (
            sn
            / math.sqrt(bottom)
            * elliprc(bottom * cn * cn * dn * dn, (bottom + amplitude * sn * sn) * scaled)
        )
        plus += s3 * elliprj(cn * cn, dn * dn, 1.0, scaled) * inverse31 / 3.0
    return minus, plus


@njit(inline="always")
def _reduced(v_hi, v_lo, mc, inv_hi, inv_lo, two_k):  # type: ignore[no-untyped-def]
    """``(k, r)``: the argument v = v_hi + v_lo (double-double) as v = 2K k + r with
    r in [−K, K] (``inv_hi + inv_lo`` = 1 / 2K, ``two_k`` = 2K); at mc = 0 (no
    period) k = 0 and r = v."""
    if mc <= 0.0:
        return 0.0, v_hi + v_lo
    x_hi, x_lo = two_prod(v_hi, inv_hi)
    x_lo += v_hi * inv_lo + v_lo * inv_hi
    turns = math.floor(x_hi + 0.5)
    fraction = (x_hi - turns) + x_lo
    if fraction > 0.5:
        turns += 1.0
        fraction -= 1.0
    elif fraction < -0.5:
        turns -= 1.0
        fraction += 1.0
    return turns, fraction * two_k


@njit(inline="always")
def _tilt_rate(s, h, sn_v, cn_v, dn, half, p, amplitude, upper, lower):  # type: ignore[no-untyped-def]
    """θ̇ = 2 (d/dt sin θ/2) / cos θ/2 = −2 (d/dt cos θ/2) / sin θ/2 (rad/s), from
    the half-angle the axis is farther from its pole: ``s`` = sin θ/2, ``h`` =
    cos θ/2 and the Jacobi functions of the unreduced argument
    (:func:`top_motion`'s notation)."""
    if abs(h) >= abs(s):
        if upper or s == 0.0:
            ds = -half * p * sn_v * dn
        else:
            ds = -amplitude * p * cn_v * sn_v * dn / (2.0 * s)
        return 2.0 * ds / h
    if lower != 0.0 or h == 0.0:
        dh = lower * half * p * cn_v * dn
    else:
        dh = amplitude * p * sn_v * cn_v * dn / (2.0 * h)
    return -2.0 * dh / s


@njit
def top_motion(c, times, table, left, right, out_w, out_q):  # type: ignore[no-untyped-def]
    """ω (n, 3), body frame with the symmetry axis third, rad/s, and the attitude
    quaternions (n, 4) ``left ⊗ q(t) ⊗ right`` at ``times`` (s), where q(t) is
    the attitude ``Rz(φ) Rx(θ) Rz(ψ)`` of that frame in a space frame whose z is
    the vertical k, with φ(0) = 0 (``left`` is then the attitude at t = 0 times
    ``(Rx(θ0) Rz(ψ0))⁻¹``), from :func:`top_constants` ``c``; ``table`` is
    ``jacobi_table(mc, 0)`` (any array when mc = 0)."""
    p, tau0, mc, amplitude = c[_P], c[_TAU0], c[_MC], c[_D]
    top, bottom = c[_TOP], c[_BOT]
    e_top, e_bottom, a, spin, psi0 = c[_E], c[_EP], c[_A], c[_N], c[_PSI0]
    upper, lower = c[_UPPER] != 0.0, c[_LOWER]
    two_k, inv_hi, inv_lo = 2.0 * c[_K], c[_INV_HI], c[_INV_LO]
    half = math.sqrt(0.5 * amplitude)
    for i in range(times.shape[0]):
        t = times[i]
        # v = p t + τ0 in double-double, reduced to r in [−K, K] with v = 2K k + r.
        v_hi, v_lo = two_prod(p, t)
        v_hi, v_lo = dd_add(v_hi, v_lo, tau0, 0.0)
        turns, r = _reduced(v_hi, v_lo, mc, inv_hi, inv_lo, two_k)
        if mc > 0.0:
            sn, cn, dn = jacobi_from_table(r, table)
        else:
            sn, cn, dn = math.tanh(r), 1.0 / math.cosh(r), 1.0 / math.cosh(r)
        if amplitude > 0.0:
            minus, plus = _integrals(sn, cn, dn, r, c)
        else:
            minus, plus = r, r  # u constant: ∫ dv/(1 ∓ u) · (1 ∓ u) = v, scaled below
        parity = -1.0 if turns % 2.0 != 0.0 else 1.0
        sn_v, cn_v = parity * sn, parity * cn  # sn, cn of the unreduced argument
        # s = sin θ/2, c = cos θ/2: signed where the axis passes through a pole.
        s = half * cn_v if upper else math.sqrt(0.5 * (top + amplitude * cn * cn))
        h = lower * half * sn_v if lower != 0.0 else math.sqrt(0.5 * (bottom + amplitude * sn * sn))
        norm = math.sqrt(s * s + h * h)
        s /= norm
        h /= norm
        tilt_rate = _tilt_rate(s, h, sn_v, cn_v, dn, half, p, amplitude, upper, lower)
        # φ̇ sin θ = (b − a u) / sin θ, from the pole the axis is nearer.
        if abs(h) >= abs(s):
            across = a * s / h
            if e_top != 0.0:
                across += 0.5 * e_top / (s * h)
        else:
            across = -a * h / s
            if e_bottom != 0.0:
                across += 0.5 * e_bottom / (s * h)
        if amplitude > 0.0:
            j_minus = (turns * c[_DJM] * p + minus - c[_JM0]) / p
            j_plus = (turns * c[_DJP] * p + plus - c[_JP0]) / p
        else:
            j_minus = (v_hi + v_lo - tau0) / (p * (top + amplitude)) if e_top != 0.0 else 0.0
            j_plus = (v_hi + v_lo - tau0) / (p * bottom) if e_bottom != 0.0 else 0.0
        secular = (spin - a) * t
        alpha_plus = 0.5 * (psi0 + secular + e_bottom * j_plus)
        alpha_minus = 0.5 * (-psi0 - secular + e_top * j_minus)
        psi = alpha_plus - alpha_minus
        sp, cp = math.sin(psi), math.cos(psi)
        out_w[i, 0] = across * sp + tilt_rate * cp
        out_w[i, 1] = across * cp - tilt_rate * sp
        out_w[i, 2] = spin
        ca, sa = math.cos(alpha_minus), math.sin(alpha_minus)
        cb, sb = math.cos(alpha_plus), math.sin(alpha_plus)
        r0, r1, r2, r3 = multiply(
            left[0], left[1], left[2], left[3], h * cb, s * ca, s * sa, h * sb
        )
        r0, r1, r2, r3 = multiply(r0, r1, r2, r3, right[0], right[1], right[2], right[3])
        out_q[i, 0], out_q[i, 1], out_q[i, 2], out_q[i, 3] = r0, r1, r2, r3


@njit
def top_mean_rates(c):  # type: ignore[no-untyped-def]
    """The nutation period (s; the time between two lowest points of the axis),
    and the mean precession and spin rates φ̇, ψ̇ over it (rad/s, about k), of
    the top of :func:`top_constants` ``c``. On a separatrix (an infinite
    period) the rates are those the motion tends to."""
    p, mc, a, spin = c[_P], c[_MC], c[_A], c[_N]
    e_top, e_bottom, top, bottom, amplitude = c[_E], c[_EP], c[_TOP], c[_BOT], c[_D]
    if mc > 0.0 and amplitude > 0.0:
        period = 2.0 * c[_K] / p
        minus = e_top * c[_DJM] / period if e_top != 0.0 else 0.0
        plus = e_bottom * c[_DJP] / period if e_bottom != 0.0 else 0.0
    else:
        period = math.inf if amplitude > 0.0 else 2.0 * c[_K] / p
        # u stays at (or tends to) u2.
        minus = e_top / top if e_top != 0.0 else 0.0
        plus = e_bottom / (2.0 - top) if e_bottom != 0.0 else 0.0
        if amplitude == 0.0:
            minus = e_top / top if e_top != 0.0 else 0.0
            plus = e_bottom / bottom if e_bottom != 0.0 else 0.0
    precession = 0.5 * (minus + plus)
    return period, precession, spin - a - 0.5 * (minus - plus)


@njit
def top_turning_points(c):  # type: ignore[no-untyped-def]
    """The tilt's turning points θ_min, θ_max from the vertical k, rad, each as
    ``2 atan2(√(1 − u), √(1 + u))`` with both factors sums of positive terms, so
    that neither loses digits near a pole."""
    top, bottom, amplitude = c[_TOP], c[_BOT], c[_D]
    low = 2.0 * math.atan2(math.sqrt(top), math.sqrt(bottom + amplitude))  # u2
    high = 2.0 * math.atan2(math.sqrt(top + amplitude), math.sqrt(bottom))  # u1
    return low, high


@njit
def top_start(c):  # type: ignore[no-untyped-def]
    """θ0 and ψ0 (rad): the Euler angles about k the motion starts from (φ0 = 0)."""
    return c[_THETA0], c[_PSI0]
