"""A synthetic phone thrown about its intermediate axis, recorded by its
gyroscope: :func:`synthetic_phone`.

The classroom experiment of the tennis-racket flip, made in code with a known
truth: a box of a phone's proportions, its principal axes turned a few degrees
from the sensor's (a real phone's mass is not uniform), held in the hand, thrown
spinning about its intermediate axis, caught, and held again; the gyroscope has
a bias and white noise and samples at an uneven rate, as a phone's does. The
free flight is the exact torque-free motion, so a fit of it has a true answer
to be checked against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble.identification.result import principal_rates

__all__ = ["PhoneRecording", "synthetic_phone"]

Array = NDArray[np.float64]

#: The phone: a box of 75 × 160 × 8 mm (x: width, y: length, z: thickness).
PHONE_SIZE = (0.075, 0.160, 0.008)


@dataclass(frozen=True)
class PhoneRecording:
    """Gyroscope samples of a thrown phone and the truth they were made from.

    Attributes
    ----------
    t : (n,) sample times, s (uneven).
    omega : (n, 3) measured rates in the sensor's axes, rad/s.
    moment_ratios : (2,) true ``(I1/I3, I2/I3)``.
    axes : (3, 3) true principal axes as columns in the sensor's axes.
    omega0 : (3,) true ω at the release, principal axes, rad/s.
    bias : (3,) the gyroscope's bias, rad/s.
    noise : the gyroscope's noise σ per component, rad/s.
    release, catch : times of the throw's end and of the catch, s.
    """

    t: Array
    omega: Array
    moment_ratios: Array
    axes: Array
    omega0: Array
    bias: Array
    noise: float
    release: float
    catch: float


def synthetic_phone(
    seed: int = 0,
    *,
    spin: float = 12.0,
    perturbation: float = 0.02,
    flight: float = 1.6,
    noise: float = 0.01,
    bias: tuple[float, float, float] = (0.02, -0.015, 0.01),
    rate: float = 500.0,
) -> PhoneRecording:
    """A recording of a phone thrown spinning about its intermediate axis.

    Parameters
    ----------
    seed : the random generator's seed (noise, jitter, the hand's motion).
    spin : rate about the intermediate axis at the release, rad/s.
    perturbation : the other two components at the release, as a fraction of
        ``spin`` (the closer to 0, the longer between flips).
    flight : duration of the free flight, s.
    noise : the gyroscope's white noise σ per component, rad/s.
    bias : the gyroscope's constant bias, rad/s.
    rate : mean sampling rate, Hz (each interval varies by ±15 %).

    Returns
    -------
    PhoneRecording: 1.2 s held, a 0.06 s throw, the free flight, a 0.04 s catch
    with an impact, 0.8 s held.
    """
    generator = np.random.default_rng(seed)
    a, b, c = PHONE_SIZE
    # Principal moments of the box, ascending: about y (length), x (width), z.
    moments = np.array([a * a + c * c, b * b + c * c, a * a + b * b]) / 12.0
    ratios = moments[:2] / moments[2]
    # Principal axes as columns in the sensor's axes: the box's y, x, −z (a proper
    # rotation), turned by a few degrees, the phone's uneven mass.
    box = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    turn = Rotation.from_euler("xyz", [4.0, -3.0, 6.0], degrees=True).as_matrix()
    axes = turn @ box
    omega0 = spin * np.array([perturbation, 1.0, 0.7 * perturbation])

    held, throw, catch, after = 1.2, 0.06, 0.04, 0.8
    total = held + throw + flight + catch + after
    steps = (1.0 + 0.15 * generator.uniform(-1.0, 1.0, int(total * rate) + 10)) / rate
    t = np.cumsum(steps)
    t = t[t <= total] - t[0]

    release = held + throw
    landing = release + flight
    in_flight = (t >= release) & (t < landing)
    omega = np.empty((t.size, 3))
    omega[in_flight] = (
        principal_rates(np.array([*ratios, 1.0]), omega0, t[in_flight] - release) @ axes.T
    )
    start = axes @ omega0
    end = axes @ principal_rates(np.array([*ratios, 1.0]), omega0, np.array([flight]))[0]
    phases = generator.uniform(0, 2 * np.pi, 6)
    now = t[~in_flight, None]
    # The hand turns the phone slowly (a few tenths of rad/s, about 1 Hz).
    hand = 0.3 * np.sin(2 * np.pi * np.array([0.9, 1.3, 0.7]) * now + phases[:3])
    # The throw: a steady spin-up, ending at the release.
    spun_up = (now - held) / throw
    thrown = (1 - spun_up) * hand + spun_up * start
    # The catch: spun down, with an impact.
    spun_down = (now - landing) / catch
    knock = 8.0 * np.exp(-(((now - landing - 0.01) / 0.004) ** 2))
    caught = (1 - spun_down) * end + spun_down * hand + knock * np.cos(phases[3:])
    omega[~in_flight] = np.where(
        now < held,
        hand,
        np.where(now < release, thrown, np.where(now < landing + catch, caught, hand)),
    )
    offset = np.array(bias, dtype=float)
    measured = omega + offset + noise * generator.standard_normal(omega.shape)
    return PhoneRecording(
        t=t,
        omega=measured,
        moment_ratios=ratios,
        axes=axes,
        omega0=omega0,
        bias=offset,
        noise=noise,
        release=release,
        catch=landing,
    )
