"""Exact angular momentum of a torque-free gyrostat whose rotor momentum lies
along a principal axis of the platform (Jacobi elliptic functions).

Relabel the platform's principal axes cyclically so that the rotors' constant
axial momentum ``h`` lies along axis 3; the moments ``I1, I2, I3`` (kg·m²) are
then in any order, with ``I1 ≠ I2`` (else the body is a symmetric gyrostat, a
steady precession). In the body, ``H = (x, y, z) = (I1 ω1, I2 ω2, I3 ω3 + h)``
obeys ``Ḣ = H × ω``, so

    ż = k x y,   k = 1/I2 − 1/I1,

and the two integrals ``|H|²`` and ``I1 ω1² + I2 ω2² + I3 ω3²`` give x² and y²
as quadratics in z:

    x² = Q1(z) = x0² + b1 (z − z0) + c1 (z − z0)²,   c1 = I1 (I3 − I2) / (I3 (I2 − I1)),
    y² = Q2(z) = y0² + b2 (z − z0) + c2 (z − z0)²,   c2 = I2 (I1 − I3) / (I3 (I2 − I1)),

with ``b1 = 2 I1 ((I3 − I2) ω3 + h) / (I2 − I1)`` and
``b2 = −2 I2 ((I3 − I1) ω3 + h) / (I2 − I1)`` (the derivatives at z0,
so no integral is formed by difference). Hence ``ż² = k² Q1(z) Q2(z)``: z
oscillates between two adjacent real roots p < q of the quartic, and x (y)
changes sign where z meets a root of Q1 (Q2). (Elipe & Lanchares solve the
torque-free gyrostat with one rotor from the same quartic; Wittenburg,
*Dynamics of Multibody Systems*, treats the constant-h gyrostat. The
derivation here was checked against the equations of motion by integration,
``tests/core/test_gyrostat.py``.)

A real Möbius map ``z = z0 + (α s + β) / (γ s + δ)`` turns the quartic into
Jacobi's normal form:

* **Four real roots** (one may be at infinity, when ``c1`` or ``c2`` vanishes):
  ``s = sn²(u | m)``, with p ↦ 0, q ↦ 1, and of the two other roots the one met
  last going up from q (through infinity) ↦ ∞, the other ↦ 1/m (the cross
  ratio, > 1 since a Möbius map keeps the cyclic order). A root's factor
  ``(z − r)`` is then ``w``, ``1 − w``, ``1 − m w`` or 1 over ``(γ s + δ)``
  for the images 0, 1, 1/m, ∞, so x and y are a constant times a product of
  sn, cn, dn over ``(γ s + δ)``: the signs come with the functions.
* **Two real roots and a complex pair** ``b̂ ± i â`` (the pair's quadratic
  never vanishes, so its variable keeps its sign): ``s = cn(u | m)``, with
  ``cn = ((q − z) B − (z − p) A) / ((q − z) B + (z − p) A)``,
  ``A² = (q − b̂)² + â²``, ``B² = (p − b̂)² + â²``,
  ``m = ((q − p)² − (A − B)²) / (4 A B)`` (Byrd & Friedman 259.00); the real
  roots' variable is a constant times ``sn / (γ s + δ)``, the other's times
  ``dn / (γ s + δ)``.

In both, ``u = λ t + u0``: the constants X, Y of x and y are fixed by Q1 and
Q2 at one interior point, λ by ``ż = k x y`` (``λ = k X Y / (2 det)`` for
``s = sn²``, ``−k X Y / det`` for ``s = cn``, ``det = α δ − β γ``), and u0 by
the signs of x0, y0. z repeats after ``u`` advances by ``2K`` (``s = sn²``)
or ``4K`` (``s = cn``).

Accuracy: against an independent integration, 1e-11 of |H| away from a
separatrix. Next to an unstable steady spin (ω ∥ H, at a distance ε in ω), the
quantities that vanish there are formed without cancellation, as the rigid
body's solution forms them (:mod:`tumble.core.freebody`): b1 and b2, which
vanish at a steady spin about axis 2 or 1, from ω3 and h in double-double
(``(I3 − I2) ω3 + h``, not from the rounded z0); 1 − m as mc itself; the
initial phase from sn and cn (``1 − sn²`` as a ratio of differences of roots,
never by subtraction), where F(φ | m) is steepest, 1/√mc; the products of
differences of roots as products, not as differences of products; and the map
near s = 1 from its values there, where its pole may lie close by. The
solution then keeps the digits the state holds: at ε = 1e-6 rad/s, 30 s, within
1e-10 rad/s of an integration at 30 digits (``tests/test_theory_gyrostats.py``),
where roots formed by subtraction from the rounded state are off by 2e-6. A state near
the separatrix but far from the steady spin (two close roots that are both far
from z0) still loses the digits of their difference.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit
from tumble.core.elliptic import (
    dd_add,
    dd_mul,
    ellipk_mc,
    jacobi_from_table,
    jacobi_table,
    two_prod,
    two_sum,
)
from tumble.core.freebody import incomplete_first_kind_of

__all__ = ["GYROSTAT_SIZE", "gyrostat_constants", "gyrostat_momentum", "gyrostat_period"]

#: Entries of the constants array of :func:`gyrostat_constants`.
GYROSTAT_SIZE = 20

_CN = 1.0  # mode: s = cn
_TINY = float(np.finfo(np.float64).tiny)  # the smallest normal double
_SN2 = 0.0  # mode: s = sn²


def _quadratic_roots(c: float, b: float, a: float) -> list[complex]:
    """The roots d of ``c d² + b d + a`` (one when c = 0), without cancellation."""
    if c == 0.0:
        return [] if b == 0.0 else [complex(-a / b)]
    disc = b * b - 4.0 * c * a
    if disc < 0.0:
        real, imag = -b / (2.0 * c), math.sqrt(-disc) / (2.0 * abs(c))
        return [complex(real, imag), complex(real, -imag)]
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    if q == 0.0:
        return [complex(0.0), complex(0.0)]
    return [complex(q / c), complex(a / q)]


def _cyclic_key(root: float, top: float) -> tuple[int, float]:
    """The order in which roots are met going up from ``top`` through infinity."""
    if math.isinf(root):
        return (1, 0.0)
    return (0, root) if root > top else (2, root)


def _plus_product(a, b, w, h):  # type: ignore[no-untyped-def]
    """``(a − b) w + h`` rounded once: the difference, the product and the sum
    carried in double-double (it vanishes at a steady spin)."""
    d_hi, d_lo = two_sum(a, -b)
    p_hi, p_lo = dd_mul(d_hi, d_lo, w, 0.0)
    s_hi, s_lo = dd_add(p_hi, p_lo, h, 0.0)
    return s_hi + s_lo


def gyrostat_constants(moments, h, w1, w2, w3):  # type: ignore[no-untyped-def]
    """The constants (:data:`GYROSTAT_SIZE`,) of the solution of the module
    docstring for the relabelled moments ``(I1, I2, I3)`` (kg·m², ``I1 ≠ I2``),
    the rotors' momentum ``h`` along axis 3 (kg·m²/s) and ω0 = ``(w1, w2, w3)``
    (rad/s; H0 = ``(I1 ω1, I2 ω2, I3 ω3 + h)``), for :func:`gyrostat_momentum`;
    None when H is constant in the body (a steady rotation: ω parallel to H,
    the caller's case)."""
    i1, i2, i3 = (float(v) for v in moments)
    x0, y0 = i1 * w1, i2 * w2
    z_hi, z_lo = two_prod(i3, w3)
    z0 = sum(dd_add(z_hi, z_lo, h, 0.0))
    k = 1.0 / i2 - 1.0 / i1
    c1 = i1 * (i3 - i2) / (i3 * (i2 - i1))
    c2 = i2 * (i1 - i3) / (i3 * (i2 - i1))
    b1 = 2.0 * i1 * _plus_product(i3, i2, w3, h) / (i2 - i1)
    b2 = -2.0 * i2 * _plus_product(i3, i1, w3, h) / (i2 - i1)
    roots1 = _quadratic_roots(c1, b1, x0 * x0)
    roots2 = _quadratic_roots(c2, b2, y0 * y0)
    # Roots of each quadratic in d = z − z0, tagged by their quadratic (0: x, 1: y);
    # a vanishing leading coefficient puts a root at infinity.
    tagged = [(r, 0) for r in roots1] + [(r, 1) for r in roots2]
    tagged += [(complex(math.inf), 0)] * (2 - len(roots1))
    tagged += [(complex(math.inf), 1)] * (2 - len(roots2))
    real = [(r.real, tag) for r, tag in tagged if r.imag == 0.0]
    # The motion is on the side of d = 0 where Q1 Q2 ≥ 0; a root at d = 0 (x0 or
    # y0 zero) bounds it on the side the product grows to.
    growth = b1 * y0 * y0 + b2 * x0 * x0  # (Q1 Q2)'(z0) when one factor is zero
    below = [r for r, _ in real if r < 0.0 or (r == 0.0 and growth > 0.0)]
    above = [r for r, _ in real if r > 0.0 or (r == 0.0 and growth <= 0.0)]
    if not below or not above or x0 == y0 == 0.0:
        return None
    p, q = max(below), min(above)
    if not (math.isfinite(p) and math.isfinite(q)) or p == q:
        return None
    ends = [next(t for r, t in real if r == p), next(t for r, t in real if r == q)]
    rest = list(tagged)
    for end in (p, q):
        rest.remove(next(item for item in rest if item[0].imag == 0.0 and item[0].real == end))
    out = np.zeros(GYROSTAT_SIZE)
    if all(r.imag == 0.0 for r, _ in rest):
        others = [(r.real, t) for r, t in rest]
        values, initial, det, at_one = _real_roots(p, q, ends, others, c1, b1, x0, c2, b2, y0)
    else:
        values, initial, det, at_one = _complex_pair(p, q, rest[0][0], rest[0][1], c1, c2)
    out[:18] = values
    out[18:] = at_one
    if out[10] <= 0.0:
        # On the separatrix to round-off (mc = 0: the asymptotic motion, an
        # infinite period). Which side the state lies on is below the round-off
        # of its numbers; the smallest mc follows the asymptotic motion for
        # u ≈ 2K ≈ 700, where a state 1e-16 off it leaves after u ≈ 40.
        out[10] = _TINY
    out[10] = min(out[10], 1.0)
    out[9] = 1.0 - out[10]
    out[5] = z0
    _sign_amplitudes(out, x0, y0)
    big_x, big_y = out[6], out[7]
    out[8] = k * big_x * big_y / (2.0 * det) if out[0] == _SN2 else -k * big_x * big_y / det
    out[11] = _initial_phase(out, x0, y0, *initial)
    return out


def _sign_amplitudes(constants, x0, y0):  # type: ignore[no-untyped-def]
    """A variable with neither sn nor cn (a factor dn or 1) never changes sign:
    its amplitude carries the sign it starts with."""
    alpha, beta, gamma, delta = constants[1:5]
    s0 = -beta / alpha if alpha != 0.0 else 0.0
    denominator = math.copysign(1.0, gamma * s0 + delta)
    powers = constants[12:18].reshape(2, 3)
    for tag, value in enumerate((x0, y0)):
        if not (powers[tag, 0] or powers[tag, 1]):
            constants[6 + tag] *= math.copysign(1.0, value) * denominator


def _quadratic(c: float, b: float, a: float, d: float) -> float:
    return a + d * (b + c * d)


def _real_roots(p, q, ends, others, c1, b1, x0, c2, b2, y0):  # type: ignore[no-untyped-def]
    """Constants for four real roots: ``s = sn²`` (module docstring), the first
    18 of :func:`gyrostat_constants`; sn² and cn² at d = 0 (``s0 = −β/α`` and
    ``1 − s0``, each a ratio of products of differences of roots, without
    cancellation where s0 nears 0 or 1); ``α δ − β γ``, as a product; and
    ``α + β``, ``γ + δ``, the map's numerator and denominator at s = 1 (from
    the roots: near s = 1, :func:`gyrostat_momentum` evaluates the map from them
    and cn²)."""
    (r1, t1), (r2, t2) = sorted(others, key=lambda item: _cyclic_key(item[0], q))
    if math.isinf(r2):
        alpha, beta, gamma, delta = q - p, p, 0.0, 1.0
        initial = (-p / (q - p), q / (q - p))
        det, at_one = q - p, (q, 1.0)
    else:
        alpha, beta, gamma, delta = r2 * (q - p), -p * (q - r2), q - p, -(q - r2)
        initial = (p * (q - r2) / (r2 * (q - p)), q * (r2 - p) / (r2 * (q - p)))
        det, at_one = (q - p) * (q - r2) * (p - r2), (q * (r2 - p), r2 - p)
    # mc = 1 − 1/w(r1), w the inverse map, written as a product of differences.
    if math.isinf(r1):
        mc = (p - r2) / (q - r2)
    elif math.isinf(r2):
        mc = (r1 - q) / (r1 - p)
    else:
        mc = -(r1 - q) * (r2 - p) / ((r1 - p) * (q - r2))
    m = 1.0 - mc
    # Each variable is a product of the factors of its roots: image 0 → sn,
    # 1 → cn, 1/m → dn, ∞ → 1.
    powers = np.zeros((2, 3))
    powers[ends[0], 0] += 1.0
    powers[ends[1], 1] += 1.0
    powers[t1, 2] += 1.0
    half = 0.5  # an interior point, where no factor vanishes
    d = (alpha * half + beta) / (gamma * half + delta)
    squares = (half, 1.0 - half, 1.0 - m * half)
    amplitudes = []
    for tag, (c, b, a) in enumerate(((c1, b1, x0 * x0), (c2, b2, y0 * y0))):
        factor = 1.0
        for j in range(3):
            if powers[tag, j]:
                factor *= squares[j]
        amplitudes.append(math.sqrt(_quadratic(c, b, a, d) * (gamma * half + delta) ** 2 / factor))
    del t2  # the root at ∞'s image contributes no factor
    constants = [_SN2, alpha, beta, gamma, delta, 0.0, *amplitudes, 0.0, m, mc, 0.0]
    return [*constants, *powers.ravel()], initial, det, at_one


def _complex_pair(p, q, pair, tag, c1, c2):  # type: ignore[no-untyped-def]
    """Constants for two real roots and a complex pair: ``s = cn`` (Byrd &
    Friedman 259.00); and, as :func:`_real_roots` gives them, sn and cn at
    d = 0, ``α δ − β γ``, and ``α + β``, ``γ + δ`` (which this form does not
    use: its denominator ``A (1 + c) + B (1 − c)`` never nears zero)."""
    middle, height = pair.real, abs(pair.imag)
    big_a = math.hypot(q - middle, height)
    big_b = math.hypot(p - middle, height)
    # z − z0 = (q B (1 − c) + p A (1 + c)) / (B (1 − c) + A (1 + c)); c = cn: 1 ↦ p, −1 ↦ q.
    alpha, beta = p * big_a - q * big_b, q * big_b + p * big_a
    gamma, delta = big_a - big_b, big_a + big_b
    m = ((q - p) ** 2 - (big_a - big_b) ** 2) / (4.0 * big_a * big_b)
    # Near the separatrix the pair nears the segment [p, q] (â → 0): A − (q − b̂)
    # and B − (b̂ − p) vanish, and with them mc = ((A + B)² − (q − p)²) / 4AB,
    # β (c = 0 at z0, close to the separatrix's hyperbolic point) and β − b̂ δ
    # (the pair's variable there). Each is formed from â² / (A + q − b̂) and
    # â² / (B + b̂ − p), without cancellation.
    if p < middle < q:
        short_a = height**2 / (big_a + q - middle)
        short_b = height**2 / (big_b + middle - p)
        beta = q * short_b + p * short_a + middle * (q - p)
        lean = (q - middle) * short_b - (middle - p) * short_a
    else:
        short_a, short_b = big_a - (q - middle), big_b - (middle - p)
        lean = (q - middle) * big_b + (p - middle) * big_a
    mc = (short_a + short_b) * (big_a + big_b + q - p) / (4.0 * big_a * big_b)
    powers = np.zeros((2, 3))
    powers[1 - tag, 0] = 1.0  # the real roots' variable: sn
    powers[tag, 2] = 1.0  # the complex pair's: dn
    # At c = 0 (d = β/δ), with sn = 1 and dn² = mc: the real roots' variable
    # squared is c (d − p)(d − q) = −c A B (q − p)² / δ², the pair's
    # c ((d − b̂)² + â²) = c ((β − b̂ δ)² + â² δ²) / δ² (β − b̂ δ as `lean`).
    real, complex_ = (c2, c1) if tag == 0 else (c1, c2)
    squares = [
        -real * big_a * big_b * (q - p) ** 2,
        complex_ * (lean**2 + (height * delta) ** 2) / mc,
    ]
    amplitudes = [math.sqrt(squares[1 if which == tag else 0]) for which in (0, 1)]
    # sn² = (1 − cn)(1 + cn) = (2 p A / α)(−2 q B / α) at c = −β/α.
    initial = (2.0 * math.sqrt(-p * q * big_a * big_b) / abs(alpha), -beta / alpha)
    det, at_one = -2.0 * big_a * big_b * (q - p), (2.0 * p * big_a, 2.0 * big_a)
    constants = [_CN, alpha, beta, gamma, delta, 0.0, *amplitudes, 0.0, m, mc, 0.0]
    return [*constants, *powers.ravel()], initial, det, at_one


def _initial_phase(constants, x0, y0, first, second):  # type: ignore[no-untyped-def]
    """u0 = F(am u0 | m): the phase whose sn, cn, dn give z0 and the signs of
    x0, y0, from sn² and cn² at d = 0 (``s = sn²``) or sn and cn (``s = cn``),
    as the normal forms give them: near a turning point of z, where F is
    steepest, cn holds digits that the angle φ = am u0 would lose."""
    mode, alpha, beta, gamma, delta = constants[:5]
    mc = constants[10]
    powers = constants[12:18].reshape(2, 3)
    signs = (math.copysign(1.0, x0), math.copysign(1.0, y0))
    s0 = -beta / alpha if alpha != 0.0 else 0.0  # d = 0
    denominator = math.copysign(1.0, gamma * s0 + delta)
    if mode == _SN2:
        sn, cn = math.sqrt(min(max(first, 0.0), 1.0)), math.sqrt(min(max(second, 0.0), 1.0))
        # The variable holding sn fixes its sign; cn's sign comes from its own
        # variable, or (sn and cn in one variable) is free: u0 and u0 + 2K give one motion.
        for tag in (0, 1):
            if powers[tag, 0]:
                sn *= signs[tag] * denominator
            elif powers[tag, 1]:
                cn *= signs[tag] * denominator
    else:
        sn, cn = min(first, 1.0), min(max(second, -1.0), 1.0)
        for tag in (0, 1):
            if powers[tag, 0]:
                sn *= signs[tag]
    return incomplete_first_kind_of(sn, cn, mc)


@njit
def gyrostat_momentum(constants, times):  # type: ignore[no-untyped-def]
    """H = (x, y, z) (n, 3), kg·m²/s, in the relabelled principal axes at
    ``times`` (s), from :func:`gyrostat_constants`."""
    mode = constants[0]
    alpha, beta, gamma, delta = constants[1], constants[2], constants[3], constants[4]
    z0, big_x, big_y, rate = constants[5], constants[6], constants[7], constants[8]
    mc, phase = constants[10], constants[11]
    top, bottom = constants[18], constants[19]  # α + β and γ + δ: the map at s = 1
    table = jacobi_table(mc, 0.0)
    out = np.empty((times.shape[0], 3))
    for n in range(times.shape[0]):
        u_hi, u_lo = two_prod(rate, times[n])
        u_hi, u_lo = dd_add(u_hi, u_lo, phase, 0.0)
        sn, cn, dn = jacobi_from_table(u_hi, table, u_lo)
        if mode == _SN2 and sn * sn > 0.5:
            # Near s = 1 (z near q) γ s + δ may nearly vanish (the pole of the
            # map next to 1/m, close to 1 near a separatrix): from s = 1 by cn².
            c = cn * cn
            numerator = top - alpha * c
            denominator = bottom - gamma * c
        else:
            s = sn * sn if mode == _SN2 else cn
            numerator = alpha * s + beta
            denominator = gamma * s + delta
        values = (sn, cn, dn)
        fx = 1.0
        fy = 1.0
        for j in range(3):
            if constants[12 + j] != 0.0:
                fx *= values[j]
            if constants[15 + j] != 0.0:
                fy *= values[j]
        out[n, 0] = big_x * fx / denominator
        out[n, 1] = big_y * fy / denominator
        out[n, 2] = z0 + numerator / denominator
    return out


def gyrostat_period(constants) -> float:  # type: ignore[no-untyped-def]
    """The period of z (and of x², y²), s."""
    turns = 2.0 if constants[0] == _SN2 else 4.0
    return float(turns * ellipk_mc(constants[10]) / abs(constants[8]))
