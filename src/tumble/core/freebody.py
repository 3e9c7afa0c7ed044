"""Exact angular velocity of a torque-free rigid body (Jacobi elliptic functions).

In the principal frame, with ``I1 ≤ I2 ≤ I3``, energy E and ``L = |L|``, on the
side of the separatrix where ``L² > 2 E I2`` (rotation about the axis of I3):

    ω1 = s A1 cn(λ t + τ0 | m),  ω2 = A2 sn(λ t + τ0 | m),  ω3 = s A3 dn(λ t + τ0 | m)

    A1² = (2EI3 − L²) / (I1 (I3 − I1)),  A2² = (2EI3 − L²) / (I2 (I3 − I2)),
    A3² = (L² − 2EI1) / (I3 (I3 − I1)),  λ² = (I3 − I2)(L² − 2EI1) / (I1 I2 I3),
    m = (I2 − I1)(2EI3 − L²) / ((I3 − I2)(L² − 2EI1)),  s = sign ω3(0)

(Landau & Lifshitz, Mechanics §37; each amplitude relation was checked
against Euler's equations by differentiation). On the other side the same
formulas hold for the relabelled body ``(I3, I2, I1)`` with ``(ω3, −ω2, ω1)``,
which obeys the same Euler equations (the relabelling is odd, and flipping ω2
restores the cyclic signs), run with ``λ → −λ``: its moments descend, so the
signed differences in the amplitude relations change sign.

Near the separatrix the differences are formed without cancellation from the
components themselves, e.g. ``L² − 2EI2 = I1 ω1² (I1 − I2) + I3 ω3² (I3 − I2)``,
so ``1 − m = (I3 − I1)(L² − 2EI2) / ((I3 − I2)(L² − 2EI1))`` keeps its digits.
"""

from __future__ import annotations

import math

import numpy as np

from tumble.core._jit import njit, njit_parallel, prange, specialise
from tumble.core.elliptic import (
    dd_add,
    dd_mul,
    dd_sqrt,
    ellipj_mc,
    ellipk_mc,
    elliprf,
    fast_two_sum,
    jacobi_from_table,
    jacobi_table,
    two_prod,
    two_sum,
)
from tumble.core.quaternion import multiply


@njit
def incomplete_first_kind(phi, m, mc):  # type: ignore[no-untyped-def]
    """F(φ | m) for −π ≤ φ ≤ π, via Carlson: F = sin φ R_F(cos²φ, cos²φ + mc sin²φ, 1)."""
    sign = 1.0
    if phi < 0.0:
        phi = -phi
        sign = -1.0
    if phi > 0.5 * math.pi:
        # F(π − φ) = 2K − F(φ)
        rest = math.pi - phi
        s = math.sin(rest)
        c = math.cos(rest)
        return sign * (2.0 * ellipk_mc(mc) - s * elliprf(c * c, c * c + mc * s * s, 1.0))
    s = math.sin(phi)
    c = math.cos(phi)
    return sign * s * elliprf(c * c, c * c + mc * s * s, 1.0)


@njit
def incomplete_first_kind_of(sine, cosine, mc):  # type: ignore[no-untyped-def]
    """F(φ | m) for −π ≤ φ ≤ π from sin φ and cos φ (sin² + cos² = 1) and
    mc = 1 − m, as :func:`incomplete_first_kind`. Near φ = ±π/2 and m → 1,
    where dF/dφ = 1/√(1 − m sin²φ) grows to 1/√mc, a small cos φ keeps digits
    that φ itself, rounded near π/2, would lose."""
    s = abs(sine)
    c = abs(cosine)
    value = s * elliprf(c * c, c * c + mc * s * s, 1.0)
    if cosine < 0.0:  # F(π − φ) = 2K − F(φ)
        value = 2.0 * ellipk_mc(mc) - value
    return -value if sine < 0.0 else value


@njit(inline="always")
def _dd_difference_product(ia, ib, ic, id, wa, wb):  # type: ignore[no-untyped-def]
    """``Ia ωa² (Ia − Ib) + Ic ωb² (Ic − Id)`` in double-double (the energy
    differences such as L² − 2EI1), every product and difference carried."""
    d1 = two_sum(ia, -ib)
    d2 = two_sum(ic, -id)
    sa = two_prod(wa, wa)
    sb = two_prod(wb, wb)
    pa = dd_mul(sa[0], sa[1], ia, 0.0)
    pb = dd_mul(sb[0], sb[1], ic, 0.0)
    x = dd_mul(pa[0], pa[1], d1[0], d1[1])
    y = dd_mul(pb[0], pb[1], d2[0], d2[1])
    return dd_add(x[0], x[1], y[0], y[1])


@njit(inline="always")
def _dd_divide(ah, al, bh, bl):  # type: ignore[no-untyped-def]
    """a / b in double-double: the double quotient and one correction."""
    q = ah / bh
    p, e = two_prod(q, bh)
    return fast_two_sum(q, ((ah - p) - e + al - q * bl) / bh)


@njit
def _rate_and_mc_double_double(i1, i2, i3, w1, w2, w3):  # type: ignore[no-untyped-def]
    """|λ| = √((I3 − I2)(L² − 2EI1)/(I1 I2 I3)) and
    ``mc = (I3 − I1)(L² − 2EI2) / ((I3 − I2)(L² − 2EI1))``, each in
    double-double, so the phase λ t and the period 4K(m) stay exact to far
    below a double's rounding at 1e6 periods."""
    lower = _dd_difference_product(i2, i1, i3, i1, w2, w3)  # L² − 2EI1
    middle = _dd_difference_product(i1, i2, i3, i2, w1, w3)  # L² − 2EI2
    d32 = two_sum(i3, -i2)
    d31 = two_sum(i3, -i1)
    numerator = dd_mul(d32[0], d32[1], lower[0], lower[1])
    product = two_prod(i1, i2)
    denominator = dd_mul(product[0], product[1], i3, 0.0)
    squared = _dd_divide(numerator[0], numerator[1], denominator[0], denominator[1])
    rate = dd_sqrt(squared[0], squared[1])
    top = dd_mul(d31[0], d31[1], middle[0], middle[1])
    mc = _dd_divide(top[0], top[1], numerator[0], numerator[1])
    return rate[0], rate[1], mc[0], mc[1]


@njit(inline="always")
def _side_constants(i1, i2, i3, w1, w2, w3):  # type: ignore[no-untyped-def]
    """The amplitudes A1, A2, A3, the sign s of ω3, mc, the phase u0 and
    L² − 2EI1 on the side L² ≥ 2 E I2 of the body (i1, i2, i3) (the module
    docstring's formulas, each difference formed from the components)."""
    p1 = i1 * w1 * w1
    p2 = i2 * w2 * w2
    p3 = i3 * w3 * w3
    upper = p1 * (i3 - i1) + p2 * (i3 - i2)  # 2EI3 − L²
    lower = p2 * (i2 - i1) + p3 * (i3 - i1)  # L² − 2EI1
    middle = p1 * (i1 - i2) + p3 * (i3 - i2)  # L² − 2EI2
    a1 = math.sqrt(upper / (i1 * (i3 - i1)))
    a2 = math.sqrt(upper / (i2 * (i3 - i2)))
    a3 = math.sqrt(lower / (i3 * (i3 - i1)))
    denominator = (i3 - i2) * lower
    m = (i2 - i1) * upper / denominator
    mc = (i3 - i1) * middle / denominator
    s = 1.0 if w3 >= 0.0 else -1.0
    sn0 = w2 / a2 if a2 > 0.0 else 0.0
    cn0 = s * w1 / a1 if a1 > 0.0 else 1.0
    phase = incomplete_first_kind(math.atan2(sn0, cn0), m, mc)
    return a1, a2, a3, s, mc, phase, lower


@njit
def _solve_side(i1, i2, i3, w1, w2, w3, times, out, k1, k2, k3, flip2, direction):  # type: ignore[no-untyped-def]
    """ω(t) on the side L² ≥ 2 E I2 of the body (i1, i2, i3); writes component a
    to ``out[:, k_a]``, with ω2 negated if ``flip2``. ``direction`` is +1 for
    ascending moments and −1 for descending ones (the relabelled body), whose
    signed differences reverse the sense of the motion along the solution."""
    a1, a2, a3, s, mc, phase, _ = _side_constants(i1, i2, i3, w1, w2, w3)
    rate_hi, rate_lo, mc_hi, mc_lo = _rate_and_mc_double_double(i1, i2, i3, w1, w2, w3)
    table = jacobi_table(mc_hi, mc_lo) if mc > 0.0 else np.zeros(1)
    rate_hi *= direction
    rate_lo *= direction
    for n in range(times.shape[0]):
        # u = λ t + τ0 in double-double: at 1e6 periods a double λ t alone
        # would be off by ~1e-9 of a period.
        u_hi, u_lo = two_prod(rate_hi, times[n])
        u_hi, u_lo = dd_add(u_hi, u_lo + rate_lo * times[n], phase, 0.0)
        if mc > 0.0:
            sn, cn, dn = jacobi_from_table(u_hi, table, u_lo)
        else:
            sn, cn, dn = ellipj_mc(u_hi + u_lo, mc)
        out[n, k1] = s * a1 * cn
        out[n, k2] = -a2 * sn if flip2 else a2 * sn
        out[n, k3] = s * a3 * dn


@njit
def free_omega(moments, omega0, times):  # type: ignore[no-untyped-def]
    """Exact principal-frame angular velocity of a torque-free body at ``times``.

    Parameters
    ----------
    moments : (3,) principal moments, ascending, kg·m², all > 0.
    omega0 : (3,) angular velocity at t = 0 in the principal frame, rad/s.
    times : (n,) s, any order and sign.

    Returns
    -------
    (n, 3) ω(t), rad/s. A rotation exactly about a principal axis (including
    the unstable middle one) and a spherical body keep ω constant.
    """
    i1, i2, i3 = moments[0], moments[1], moments[2]
    w1, w2, w3 = omega0[0], omega0[1], omega0[2]
    out = np.empty((times.shape[0], 3))
    zeros = 0
    for component in (w1, w2, w3):
        if component == 0.0:
            zeros += 1
    on_axis = zeros >= 2
    if on_axis or i1 == i3:
        for n in range(times.shape[0]):
            out[n, 0] = w1
            out[n, 1] = w2
            out[n, 2] = w3
        return out
    middle = i1 * w1 * w1 * (i1 - i2) + i3 * w3 * w3 * (i3 - i2)  # L² − 2EI2
    if middle >= 0.0 and i3 > i2:
        _solve_side(i1, i2, i3, w1, w2, w3, times, out, 0, 1, 2, False, 1.0)
    else:
        # The other side, or the prolate case I2 = I3: relabel to (I3, I2, I1), (ω3, −ω2, ω1).
        _solve_side(i3, i2, i1, w3, -w2, w1, times, out, 2, 1, 0, True, -1.0)
    return out


#: Gauss–Legendre rule on [-1, 1] for the precession integral: 16 nodes
#: integrate the smooth periodic integrand on a panel to round-off.
_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(16)

#: Panel width in the elliptic argument u = λ t: near the separatrix the flips
#: take a u-interval of order 1 while the half period 2K grows like ln(1/mc),
#: so panels of fixed width in u resolve them at any distance from it.
_PANEL_U = 0.25


@njit
def _phi_rate(moments, w, momentum):  # type: ignore[no-untyped-def]
    """φ̇ = L (I1 ω1² + I2 ω2²) / (I1² ω1² + I2² ω2²) (Landau & Lifshitz §37)."""
    a = moments[0] * w[0] * w[0]
    b = moments[1] * w[1] * w[1]
    return momentum * (a + b) / (moments[0] * a + moments[1] * b)


@njit
def _phi_integral(moments, omega0, momentum, start, stop):  # type: ignore[no-untyped-def]
    """∫ φ̇ dt from ``start`` to ``stop`` (one Gauss–Legendre panel), rad."""
    first = _about_first_axis(moments, omega0)
    half = 0.5 * (stop - start)
    middle = 0.5 * (stop + start)
    times = middle + half * _GL_NODES
    w = free_omega(moments, omega0, times)
    total = 0.0
    for k in range(times.shape[0]):
        total += _GL_WEIGHTS[k] * _phi_rate_about(moments, w[k], momentum, first)
    return half * total


@njit
def elliptic_rate_and_mc(moments, omega0):  # type: ignore[no-untyped-def]
    """|λ| (1/s) and 1 − m of the side of the separatrix the motion is on.

    The half period of ω1², ω2² (and of φ̇) is ``2 K(m) / |λ|``.
    """
    i1, i2, i3 = moments[0], moments[1], moments[2]
    w1, w2, w3 = omega0[0], omega0[1], omega0[2]
    middle = i1 * w1 * w1 * (i1 - i2) + i3 * w3 * w3 * (i3 - i2)
    if not (middle >= 0.0 and i3 > i2):
        i1, i3 = i3, i1
        w1, w3 = w3, w1
    lower = i2 * w2 * w2 * (i2 - i1) + i3 * w3 * w3 * (i3 - i1)
    rate = math.sqrt((i3 - i2) * lower / (i1 * i2 * i3))
    mc = (i3 - i1) * middle / ((i3 - i2) * lower)
    return rate, mc


#: Degree of the Chebyshev expansion of φ on each panel: the integrand is
#: analytic on a neighbourhood of the panel (panels ``_PANEL_U`` wide in u), so
#: degree 16 reaches round-off, as the 16-point Gauss–Legendre rule does.
_CHEB_DEGREE = 16

#: cos(π i k / degree), the discrete cosine transform of the Lobatto samples.
_CHEB_COSINES = np.cos(
    np.pi * np.outer(np.arange(_CHEB_DEGREE + 1), np.arange(_CHEB_DEGREE + 1)) / _CHEB_DEGREE
)


@njit
def panel_nodes(width, panels):  # type: ignore[no-untyped-def]
    """The Chebyshev–Lobatto points (panels · (degree + 1),) of the panels
    [j w, (j+1) w], s, where :func:`panel_series` samples the integrand."""
    n = _CHEB_DEGREE
    times = np.empty(panels * (n + 1))
    for j in range(panels):
        for k in range(n + 1):
            times[j * (n + 1) + k] = (j + 0.5 * (math.cos(math.pi * k / n) + 1.0)) * width
    return times


@njit
def panel_series(rates, width, panels):  # type: ignore[no-untyped-def]
    """Chebyshev coefficients (panels, degree + 2) of the integral of a rate
    from the start of each panel [j w, (j+1) w], in x ∈ [−1, 1]
    (t = start + (x + 1) w / 2), from the rate's samples ``rates`` at
    :func:`panel_nodes`.

    The interpolating series of the samples is integrated term by term
    (Numerical Recipes §5.9, ``chebint``), and the constant term makes the
    integral vanish at the panel's start.
    """
    n = _CHEB_DEGREE
    out = np.zeros((panels, n + 2))
    c = np.empty(n + 3)
    for j in range(panels):
        for i in range(n + 1):
            total = 0.0
            for k in range(n + 1):
                weight = 0.5 if k == 0 or k == n else 1.0
                total += weight * rates[j * (n + 1) + k] * _CHEB_COSINES[i, k]
            c[i] = 2.0 * total / n
        c[n] *= 0.5  # the series is c0/2 + Σ c_i T_i with the last term halved
        c[n + 1] = 0.0
        c[n + 2] = 0.0
        # ∫ (c0/2 + Σ c_i T_i) dx = C0/2 + Σ_{i>=1} C_i T_i, C_i = (c_{i-1} − c_{i+1}) / 2i,
        # times dt/dx = w/2.
        alternating = 0.0
        for i in range(1, n + 2):
            out[j, i] = 0.25 * width * (c[i - 1] - c[i + 1]) / i
            alternating += out[j, i] if i % 2 == 0 else -out[j, i]
        out[j, 0] = -2.0 * alternating  # zero at x = −1
    return out


@njit(inline="always")
def _clenshaw(coefficients, j, x):  # type: ignore[no-untyped-def]
    """c0/2 + Σ c_i T_i(x) for row j of ``coefficients``."""
    b1 = 0.0
    b2 = 0.0
    for i in range(coefficients.shape[1] - 1, 0, -1):
        b1, b2 = 2.0 * x * b1 - b2 + coefficients[j, i], b1
    return x * b1 - b2 + 0.5 * coefficients[j, 0]


@njit
def periodic_integral(series, period, times):  # type: ignore[no-untyped-def]
    """∫₀ᵗ of a rate of period ``period`` (s) at ``times``, from its
    :func:`panel_series` over one period: whole periods times the integral
    over one, plus the panels before t, plus the series of t's panel."""
    panels = series.shape[0]
    width = period / panels
    cumulative = np.empty(panels + 1)
    cumulative[0] = 0.0
    for j in range(panels):
        cumulative[j + 1] = cumulative[j] + _clenshaw(series, j, 1.0)
    out = np.empty(times.shape[0])
    for n in range(times.shape[0]):
        t = times[n]
        turns = math.floor(t / period)
        rest = t - turns * period
        j = min(int(rest / width), panels - 1)
        x = 2.0 * (rest - j * width) / width - 1.0
        out[n] = turns * cumulative[panels] + cumulative[j] + _clenshaw(series, j, x)
    return out


@njit
def free_precession_angle(moments, omega0, times):  # type: ignore[no-untyped-def]
    """The angle φ(t) − φ(0) through which the body precesses about L, rad.

    ``φ̇`` is periodic with the half period ``P = 2K/|λ|`` of ω1², ω2². Over one
    P, cut into panels ``_PANEL_U`` wide in u, its integral is expanded once
    in Chebyshev series (degree ``_CHEB_DEGREE``, to round-off; the expansion
    stands in for the elliptic integral of the third kind, as quadrature does
    in ACM TOMS 903); each time then costs one series evaluation:
    ``φ(t) = turns · φ(P) + cumulative(panel) + series(panel, t)``. On the
    separatrix itself (P infinite) every time is integrated from 0 by
    16-point Gauss–Legendre panels.

    Euler angles about the third axis, or about the first
    (:func:`_about_first_axis`). Parameters as :func:`free_omega`; not for
    rotations exactly about a principal axis or a spherical body (the caller
    handles those).
    """
    w0 = omega0
    momentum = math.sqrt(
        (moments[0] * w0[0]) ** 2 + (moments[1] * w0[1]) ** 2 + (moments[2] * w0[2]) ** 2
    )
    rate, mc = elliptic_rate_and_mc(moments, omega0)
    first = _about_first_axis(moments, omega0)  # the Euler angles' axis (free_attitude)
    out = np.empty(times.shape[0])
    if mc <= 0.0:
        for n in range(times.shape[0]):
            t = times[n]
            panels = max(1, int(math.ceil(abs(t) * rate / _PANEL_U)))  # noqa: RUF046 (numba)
            total = 0.0
            for j in range(panels):
                total += _phi_integral(
                    moments, omega0, momentum, t * j / panels, t * (j + 1) / panels
                )
            out[n] = total
        return out
    period = 2.0 * ellipk_mc(mc) / rate
    panels = max(8, int(math.ceil(2.0 * ellipk_mc(mc) / _PANEL_U)))  # noqa: RUF046 (numba)
    nodes = panel_nodes(period / panels, panels)
    w = free_omega(moments, omega0, nodes)
    rates = np.empty(nodes.shape[0])
    for k in range(nodes.shape[0]):
        rates[k] = _phi_rate_about(moments, w[k], momentum, first)
    return periodic_integral(panel_series(rates, period / panels, panels), period, times)


@njit(inline="always")
def _attitude(frame, phi, l1, l2, l3):  # type: ignore[no-untyped-def]
    """``frame ⊗ qz(φ) ⊗ qx(θ) ⊗ qz(ψ)`` with ``cos θ = L3/|L|`` and
    ``tan ψ = L1/L2`` (L in principal axes): the attitude of :func:`free_attitude`."""
    theta = math.atan2(math.hypot(l1, l2), l3)
    psi = math.atan2(l1, l2)
    a0, a3 = math.cos(0.5 * phi), math.sin(0.5 * phi)
    b0, b1 = math.cos(0.5 * theta), math.sin(0.5 * theta)
    c0, c3 = math.cos(0.5 * psi), math.sin(0.5 * psi)
    # qz(φ) ⊗ qx(θ) = (a0 b0, a0 b1, a3 b1, a3 b0), then ⊗ qz(ψ)
    p0, p1, p2, p3 = a0 * b0, a0 * b1, a3 * b1, a3 * b0
    return multiply(
        frame[0],
        frame[1],
        frame[2],
        frame[3],
        p0 * c0 - p3 * c3,
        c0 * p1 + p2 * c3,
        c0 * p2 - p1 * c3,
        p0 * c3 + c0 * p3,
    )


#: The body's axes taken cyclically, (x', y', z') = (2, 3, 1): a proper rotation
#: (2π/3 about (1, 1, 1)/√3), as a quaternion from those axes to the body's.
_CYCLE = (0.5, 0.5, 0.5, 0.5)


@njit(inline="always")
def _about_first_axis(moments, w):  # type: ignore[no-untyped-def]
    """True when the Euler angles are better taken about the first principal
    axis than about the third. With either axis, φ̇ has the denominator
    L² − L_k², smallest where L2 = 0, where ``L1² ∝ (2EI3 − L²) I1`` and
    ``L3² ∝ (L² − 2EI1) I3``: the axis whose component is the smaller there is
    the one L stays farthest from. About the other, a nearly prolate (or
    oblate) body's L passes close to the axis, where the angles turn abruptly
    and φ̇ has a peak that no quadrature of fixed panels resolves. Both
    differences are sums of terms of one sign."""
    i1, i2, i3 = moments[0], moments[1], moments[2]
    w1, w2, w3 = w[0], w[1], w[2]
    upper = i1 * w1 * w1 * (i3 - i1) + i2 * w2 * w2 * (i3 - i2)  # 2EI3 − L²
    lower = i2 * w2 * w2 * (i2 - i1) + i3 * w3 * w3 * (i3 - i1)  # L² − 2EI1
    return lower * i3 > upper * i1


@njit(inline="always")
def _phi_rate_about(moments, w, momentum, first):  # type: ignore[no-untyped-def]
    """φ̇ of Euler angles about the third axis (:func:`_phi_rate`), or about the
    first (``first``: the same formula in the axes (2, 3, 1))."""
    if not first:
        return _phi_rate(moments, w, momentum)
    a = moments[1] * w[1] * w[1]
    b = moments[2] * w[2] * w[2]
    return momentum * (a + b) / (moments[1] * a + moments[2] * b)


@njit(inline="always")
def _attitude_about(frame, phi, l1, l2, l3, first):  # type: ignore[no-untyped-def]
    """:func:`_attitude` about the third axis, or about the first (``first``):
    the attitude of the axes (2, 3, 1), turned back to the body's axes."""
    if not first:
        return _attitude(frame, phi, l1, l2, l3)
    r = _attitude(frame, phi, l2, l3, l1)
    c0, c1, c2, c3 = _CYCLE
    return multiply(r[0], r[1], r[2], r[3], c0, -c1, -c2, -c3)


@njit
def free_attitude(moments, omega0, frame, times):  # type: ignore[no-untyped-def]
    """ω (n, 3) and the attitude quaternions (n, 4), principal → space, at ``times``.

    With z-x-z Euler angles about the fixed L (Landau & Lifshitz §37), the
    attitude is ``frame ⊗ qz(φ) ⊗ qx(θ) ⊗ qz(ψ)``, where ``frame`` (4,) turns
    space axes with z along L into space axes (:func:`momentum_frame`),
    ``cos θ = L3/|L|``, ``tan ψ = L1/L2`` and φ from
    :func:`free_precession_angle`; or the same with the axes taken as (2, 3, 1)
    (about the first axis: :func:`_about_first_axis`). Not for
    rotations exactly about a principal axis or a spherical body.
    """
    first = _about_first_axis(moments, omega0)
    w = free_omega(moments, omega0, times)
    phi = free_precession_angle(moments, omega0, times)
    out = np.empty((times.shape[0], 4))
    for n in range(times.shape[0]):
        r = _attitude_about(
            frame, phi[n], moments[0] * w[n, 0], moments[1] * w[n, 1], moments[2] * w[n, 2], first
        )
        for i in range(4):
            out[n, i] = r[i]
    return w, out


@njit(inline="always")
def _turns_steadily(moments, w):  # type: ignore[no-untyped-def]
    """True when ω stays constant: a rotation about a principal axis, or a spherical body."""
    zeros = 0
    for i in range(3):
        if w[i] == 0.0:
            zeros += 1
    return zeros >= 2 or moments[0] == moments[2]


@njit(inline="always")
def _turn_steadily(w, q, t):  # type: ignore[no-untyped-def]
    """q turned in place about the constant body axis ω by |ω| t."""
    rate = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    if rate == 0.0:
        return
    half = 0.5 * rate * t
    scale = math.sin(half) / rate
    r = multiply(q[0], q[1], q[2], q[3], math.cos(half), w[0] * scale, w[1] * scale, w[2] * scale)
    norm = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3])
    for i in range(4):
        q[i] = r[i] / norm


@njit(inline="always")
def momentum_frame(moments, w, q):  # type: ignore[no-untyped-def]
    """The quaternion (4,) that turns space axes with z along L into space axes,
    of the attitude q (principal → space) and ω (principal axes), with the
    Euler angles of :func:`free_attitude` (φ = 0 now)."""
    l1, l2, l3 = moments[0] * w[0], moments[1] * w[1], moments[2] * w[2]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    if _about_first_axis(moments, w):  # the axes (2, 3, 1)
        l1, l2, l3 = l2, l3, l1
        c0, c1, c2, c3 = _CYCLE
        q0, q1, q2, q3 = multiply(q0, q1, q2, q3, c0, c1, c2, c3)
    theta, psi = math.atan2(math.hypot(l1, l2), l3), math.atan2(l1, l2)
    b0, b1 = math.cos(0.5 * theta), math.sin(0.5 * theta)
    c0, c3 = math.cos(0.5 * psi), math.sin(0.5 * psi)
    # q ⊗ (qx(θ) ⊗ qz(ψ))⁻¹, where qx(θ) ⊗ qz(ψ) = (b0 c0, b1 c0, −b1 c3, b0 c3).
    return np.array(multiply(q0, q1, q2, q3, b0 * c0, -b1 * c0, b1 * c3, -b0 * c3))


@njit
def advance_exact(moments, w, q, t):  # type: ignore[no-untyped-def]
    """One torque-free body advanced exactly by ``t`` s: ω (3,) rad/s and the
    attitude q (4,), principal → space, of the body with ascending principal
    ``moments`` (kg·m²), replaced in place. A rotation about a principal axis
    (or of a spherical body) turns q about the constant ω; any other motion is
    :func:`free_attitude` from the frame whose z axis is along L."""
    if _turns_steadily(moments, w):
        _turn_steadily(w, q, t)
        return
    frame = momentum_frame(moments, w, q)
    omega, attitude = free_attitude(moments, w.copy(), frame, np.array([t]))
    for i in range(3):
        w[i] = omega[0, i]
    for i in range(4):
        q[i] = attitude[0, i]


#: A step longer than this many Gauss–Legendre panels takes the periodic
#: expansion of φ over a whole period (:func:`advance_exact`) instead.
_MAX_STEP_PANELS = 8


@njit
def free_step(moments, w, q, h):  # type: ignore[no-untyped-def]
    """:func:`advance_exact` for a step ``h`` (s, either sign) short against the
    period, as a splitting takes: the precession angle by 16-point
    Gauss–Legendre panels over [0, h] (each ``_PANEL_U`` wide in u = λ t at
    most, so to round-off), instead of the expansion over a whole period. ω
    (3,) and q (4,) are replaced in place."""
    if _turns_steadily(moments, w):
        _turn_steadily(w, q, h)
        return
    rate, _ = elliptic_rate_and_mc(moments, w)
    panels = max(1, int(math.ceil(abs(h) * rate / _PANEL_U)))  # noqa: RUF046 (numba)
    if panels > _MAX_STEP_PANELS:
        advance_exact(moments, w, q, h)
        return
    nodes = _GL_NODES.shape[0]
    width = h / panels
    times = np.empty(panels * nodes + 1)
    for j in range(panels):
        for k in range(nodes):
            times[j * nodes + k] = width * (j + 0.5 + 0.5 * _GL_NODES[k])
    times[-1] = h
    omega = free_omega(moments, w, times)
    momentum = math.sqrt(
        (moments[0] * w[0]) ** 2 + (moments[1] * w[1]) ** 2 + (moments[2] * w[2]) ** 2
    )
    first = _about_first_axis(moments, w)
    phi = 0.0
    for n in range(panels * nodes):
        phi += _GL_WEIGHTS[n % nodes] * _phi_rate_about(moments, omega[n], momentum, first)
    phi *= 0.5 * width
    frame = momentum_frame(moments, w, q)
    last = omega[-1]
    r = _attitude_about(
        frame, phi, moments[0] * last[0], moments[1] * last[1], moments[2] * last[2], first
    )
    for i in range(3):
        w[i] = last[i]
    for i in range(4):
        q[i] = r[i]


def exact_batch_kernel(torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, t0, dt, n_steps, status)``: N
    torque-free bodies ((3, N), (4, N), moments (3, N), principal frames)
    advanced in place exactly by ``n_steps · dt`` s (:func:`advance_exact`), in
    parallel, O(1) a body whatever the duration. ``torque`` is unused (the
    bodies are torque-free); ``status`` is left as is."""

    @specialise(njit_parallel, f"freebody.exact_batch|{identity}")
    def batch(w, q, inertia, params, context, t0, dt, n_steps, status):  # type: ignore[no-untyped-def]
        t = dt * n_steps
        for body in prange(w.shape[1]):
            one_w = w[:, body].copy()
            one_q = q[:, body].copy()
            advance_exact(inertia[:, body].copy(), one_w, one_q, t)
            w[:, body] = one_w
            q[:, body] = one_q

    return batch


@njit
def free_components(moments, omega0):  # type: ignore[no-untyped-def]
    """The closed form of :func:`free_omega` as data: ω_j(t) = c_j f_j(λ t + u0),
    with f_j sn, cn or dn. Returns the kinds (3,) (0: cn, 1: sn, 2: dn), the
    signed amplitudes c (3,) rad/s, λ (signed, 1/s), u0, and mc = 1 − m. Not
    for a rotation exactly about a principal axis or a spherical body."""
    i1, i2, i3 = moments[0], moments[1], moments[2]
    w1, w2, w3 = omega0[0], omega0[1], omega0[2]
    kinds = np.empty(3, dtype=np.int64)
    amplitudes = np.empty(3)
    middle = i1 * w1 * w1 * (i1 - i2) + i3 * w3 * w3 * (i3 - i2)
    ascending = middle >= 0.0 and i3 > i2
    if not ascending:  # the relabelled body (I3, I2, I1) with (ω3, −ω2, ω1), as in free_omega
        i1, i3 = i3, i1
        w1, w2, w3 = w3, -w2, w1
    a1, a2, a3, s, mc, phase, lower = _side_constants(i1, i2, i3, w1, w2, w3)
    rate = math.sqrt((i3 - i2) * lower / (i1 * i2 * i3))
    if ascending:
        kinds[0], kinds[1], kinds[2] = 0, 1, 2
        amplitudes[0], amplitudes[1], amplitudes[2] = s * a1, a2, s * a3
    else:
        kinds[0], kinds[1], kinds[2] = 2, 1, 0
        amplitudes[0], amplitudes[1], amplitudes[2] = s * a3, -a2, s * a1
        rate = -rate
    return kinds, amplitudes, rate, phase, mc


@njit
def _jacobi(kind, u, mc):  # type: ignore[no-untyped-def]
    sn, cn, dn = ellipj_mc(u, mc)
    return cn if kind == 0 else (sn if kind == 1 else dn)


@njit
def _lattice_in(first, period, lo, hi):  # type: ignore[no-untyped-def]
    """How many of the points first + n·period lie strictly inside (lo, hi)."""
    if not math.isfinite(period):
        return 1 if lo < first < hi else 0
    return max(0, math.ceil((hi - first) / period) - math.floor((lo - first) / period) - 1)


@njit
def _extreme(kind, lo, hi, mc, quarter, lowest):  # type: ignore[no-untyped-def]
    """The least (``lowest``) or greatest value of cn, sn or dn on [lo, hi]:
    the extremum where the window holds one of its points, else an end (the
    functions are monotone between consecutive extrema). ``quarter`` is K (inf
    on the separatrix, where cn = dn = sech and sn = tanh)."""
    # Where each function reaches its maxima and minima, and their values.
    if kind == 0:
        top, bottom, at_top, at_bottom, period = 1.0, -1.0, 0.0, 2.0 * quarter, 4.0 * quarter
    elif kind == 1:
        top, bottom, at_top, at_bottom, period = 1.0, -1.0, quarter, 3.0 * quarter, 4.0 * quarter
    else:
        top, bottom, at_top, at_bottom, period = (1.0, math.sqrt(mc), 0.0, quarter, 2.0 * quarter)
    if not math.isfinite(quarter):  # sech has its maximum at 0 only; tanh none
        period = math.inf
        at_top = 0.0 if kind != 1 else math.inf
        at_bottom = math.inf
    target, where = (bottom, at_bottom) if lowest else (top, at_top)
    if math.isfinite(where) and _lattice_in(where, period, lo, hi) > 0:
        return target  # (an extremum exactly at an end is that end's value)
    ends = (_jacobi(kind, lo, mc), _jacobi(kind, hi, mc))
    return min(ends) if lowest else max(ends)


@njit
def free_metrics(moments, omega0, axis, duration):  # type: ignore[no-untyped-def]
    """The sweep's measures of :mod:`tumble.core.metrics` over [0, ``duration``]
    (s), in closed form: (flips, first flip time, least a·L/|L|, 0, 0) for the
    nominal ``axis`` a, a principal axis (a unit vector, ascending principal
    ``moments``, ω0 in the principal frame). With ω_j = c_j f_j(λ t + u0):
    the flips are the zeros of f_j in the open window of u (cn at K + 2nK, sn
    at 2nK, dn none), the first flip the first of them, and the largest
    nutation the extremum of c_j f_j on the window; energy and |L| are kept
    exactly."""
    j = 0
    for i in range(3):
        if abs(axis[i]) > abs(axis[j]):
            j = i
    sign = 1.0 if axis[j] > 0.0 else -1.0
    size = math.sqrt(
        (moments[0] * omega0[0]) ** 2
        + (moments[1] * omega0[1]) ** 2
        + (moments[2] * omega0[2]) ** 2
    )
    zeros = 0
    for i in range(3):
        if omega0[i] == 0.0:
            zeros += 1
    if size == 0.0:
        return 0.0, math.inf, 1.0, 0.0, 0.0
    if zeros >= 2 or moments[0] == moments[2]:  # ω constant
        return 0.0, math.inf, sign * moments[j] * omega0[j] / size, 0.0, 0.0
    kinds, amplitudes, rate, phase, mc = free_components(moments, omega0)
    kind = kinds[j]
    amplitude = sign * amplitudes[j]
    quarter = ellipk_mc(mc) if mc > 0.0 else math.inf
    end = phase + rate * duration
    lo, hi = min(phase, end), max(phase, end)
    flips = 0.0
    first = math.inf
    if kind != 2:
        # Zeros: cn at K + 2nK, sn at 2nK (sn at 0 only on the separatrix).
        zero = quarter if kind == 0 else 0.0
        period = 2.0 * quarter
        if kind == 0 and not math.isfinite(quarter):
            zero = math.inf
        if math.isfinite(zero):
            flips = float(_lattice_in(zero, period, lo, hi))
            if flips > 0.0:
                if math.isfinite(period):
                    steps = (phase - zero) / period
                    n = math.floor(steps) + 1 if rate > 0.0 else math.ceil(steps) - 1
                    first = (zero + n * period - phase) / rate
                else:
                    first = (zero - phase) / rate
    least = _extreme(kind, lo, hi, mc, quarter, amplitude > 0.0)
    return flips, first, moments[j] * amplitude * least / size, 0.0, 0.0


def exact_metrics_kernel(torque, identity):  # type: ignore[no-untyped-def]
    """``batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status)``:
    the measures of :mod:`tumble.core.metrics` of N torque-free bodies over
    ``n_steps · dt`` s in closed form (:func:`free_metrics`), in parallel.
    Unlike the stepping kernels it leaves the states as they are (the caller
    advances them with :func:`exact_batch_kernel` when it keeps them). Moments
    ascending, nominal axes principal axes (unit vectors, principal frames)."""

    @specialise(njit_parallel, f"freebody.exact_metrics|{identity}")
    def batch(w, q, inertia, params, context, axis, t0, dt, n_steps, out, status):  # type: ignore[no-untyped-def]
        t = dt * n_steps
        for body in prange(w.shape[1]):
            values = free_metrics(
                inertia[:, body].copy(), w[:, body].copy(), axis[:, body].copy(), t
            )
            for row in range(5):
                out[row, body] = values[row]

    return batch
