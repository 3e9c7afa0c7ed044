"""Many throws of one body in one gyroscope recording, with air drag:
:func:`synthetic_throws`.

The experiment of the tennis-racket flip repeated: a racquet carrying a phone,
held, thrown spinning about its intermediate axis, caught, held again, and
thrown again, `count` times in one recording. Its principal axes are turned
from the sensor's by a fixed rotation, the gyroscope has a bias and white
noise and samples evenly. Each free flight is simulated by tumble's own
integrator (:func:`tumble.simulate`, adaptive Dormand–Prince at 1e-12) under
linear air drag per principal axis (:class:`tumble.torques.AxisDrag`), so a fit
of the throws has a true answer to be checked against.

:func:`example_throws_path` is the recording shipped with tumble,
``synthetic_throws(12, seed=0)`` in phyphox's CSV format, written by::

    python -c "from tumble.identification.throws import synthetic_throws, example_throws_path; \\
    from tumble.identification.recordings import phyphox_csv; r = synthetic_throws(12, seed=0); \\
    example_throws_path().write_text(phyphox_csv(r.t, r.omega))"
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

__all__ = ["THROWS_EXAMPLE", "ThrowsRecording", "example_throws_path", "synthetic_throws"]

Array = NDArray[np.float64]

#: The file name of the many-throw recording shipped with tumble (in this package's ``data``).
THROWS_EXAMPLE = "throws-drag.csv"

#: The racquet's moments over the largest, ``(I1/I3, I2/I3)``, and its largest, kg·m².
RACQUET_RATIOS = (0.067, 0.94)
RACQUET_I3 = 0.0125

#: The rotation from the sensor's axes to the racquet's principal axes (a rotation vector, rad).
RACQUET_TURN = (0.3, -0.5, 0.8)

#: The gyroscope's bias, rad/s, sensor axes.
SENSOR_BIAS = (0.01, -0.005, 0.003)

#: Durations, s: holding before a throw (drawn between these), the spin-up, the catch.
HOLD = (0.8, 1.2)
SPIN_UP = 0.06
CATCH = 0.04


@dataclass(frozen=True, eq=False)
class ThrowsRecording:
    """Gyroscope samples of many throws of one body and the truth they were made from.

    Attributes
    ----------
    t : (n,) sample times, s (even).
    omega : (n, 3) measured rates in the sensor's axes, rad/s.
    moment_ratios : (2,) true ``(I1/I3, I2/I3)``.
    axes : (3, 3) true principal axes as columns in the sensor's axes.
    bias : (3,) the gyroscope's bias, rad/s.
    noise : the gyroscope's noise σ per component, rad/s.
    drag : (3,) the linear drag per principal axis over I3, ``c_i / I3``, 1/s
        (the torque ``τ_i = −c_i ω_i``).
    windows : ((release, end), ...) per throw, s: the release and the last
        sample of its free flight.
    omega0 : (count, 3) true ω at each release, principal axes, rad/s.
    """

    t: Array
    omega: Array
    moment_ratios: Array
    axes: Array
    bias: Array
    noise: float
    drag: Array
    windows: tuple[tuple[float, float], ...]
    omega0: Array


def example_throws_path() -> Path:
    """The many-throw recording shipped with tumble: a racquet thrown 12 times
    under air drag, ``synthetic_throws(12, seed=0)`` in phyphox's CSV format (rad/s)."""
    return Path(str(resources.files("tumble.identification") / "data" / THROWS_EXAMPLE))


def synthetic_throws(
    count: int = 30,
    seed: int = 0,
    *,
    drag: tuple[float, float, float] = (0.05, 0.12, 0.15),
    noise: float = 0.0035,
    rate: float = 100.0,
    samples: int = 80,
) -> ThrowsRecording:
    """One recording of a racquet carrying a phone thrown ``count`` times about
    its intermediate axis under linear air drag.

    Parameters
    ----------
    count : the number of throws.
    seed : the random generator's seed (holding times, releases, impacts, noise).
    drag : linear drag per principal axis over I3, ``c_i / I3``, 1/s (moments
        ascending); zeros for torque-free throws.
    noise : the gyroscope's white noise σ per component, rad/s.
    rate : the sampling rate, Hz (even throughout).
    samples : samples of each free flight, the release included.

    Returns
    -------
    ThrowsRecording: before each throw 0.8–1.2 s held (the hand turning it by a
    few tenths of rad/s), a 0.06 s spin-up, the free flight from ω0 (about the
    intermediate axis 7–12 rad/s of either sign, about the others up to ±1 and
    ±1.5 rad/s), a 0.04 s catch with an impact; after the last, held again.
    """
    # Imported here: the simulator is needed only to make a recording, not to fit one.
    from tumble.massprops import MassProperties
    from tumble.torques import TORQUES

    generator = np.random.default_rng(seed)
    moments = np.array([*RACQUET_RATIOS, 1.0]) * RACQUET_I3
    ratios = moments[:2] / moments[2]
    axes = Rotation.from_rotvec(RACQUET_TURN).as_matrix()
    coefficients = np.array(drag, dtype=float)
    body = MassProperties(1.0, np.zeros(3), np.diag(moments))
    drag_torque = TORQUES["drag"](coefficients * moments[2])  # type: ignore[call-arg]
    torque = drag_torque if np.any(coefficients) else None

    holds, starts, flights, knocks = _flights(count, generator, body, torque, rate, samples)
    flights = [flight @ axes.T for flight in flights]  # the true rates in the sensor's axes
    holds.append(round(generator.uniform(*HOLD) * rate))
    t, omega, windows = _recording(holds, flights, knocks, generator, rate)
    offset = np.array(SENSOR_BIAS)
    # The noise is drawn last, so the same seed gives the same truth at every noise level.
    measured = omega + offset + noise * generator.standard_normal(omega.shape)
    return ThrowsRecording(
        t=t,
        omega=measured,
        moment_ratios=ratios,
        axes=axes,
        bias=offset,
        noise=noise,
        drag=coefficients,
        windows=tuple(windows),
        omega0=np.array(starts).reshape(count, 3),
    )


def _flights(
    count: int,
    generator: np.random.Generator,
    body: Any,
    torque: Any,
    rate: float,
    samples: int,
) -> tuple[list[int], list[Array], list[Array], list[Array]]:
    """Each throw's time held before it (samples), its ω0 (body axes, rad/s), its free
    flight's true rates (``samples`` of them, body axes) and the direction of the
    impact that ends it, drawn in that order from ``generator``."""
    from tumble.simulation import simulate

    step = 1.0 / rate
    holds, starts, flights, knocks = [], [], [], []
    for _ in range(count):
        holds.append(round(generator.uniform(*HOLD) * rate))
        omega0 = np.array(
            [
                generator.uniform(-1.0, 1.0),
                generator.uniform(7.0, 12.0) * generator.choice([-1.0, 1.0]),
                generator.uniform(-1.5, 1.5),
            ]
        )
        run = simulate(
            body,
            omega0,
            duration=(samples - 1) * step,
            dt=step,
            torque=torque,
            method="adaptive",
            rtol=1e-12,
            atol=1e-12,
        )
        starts.append(omega0)
        flights.append(np.asarray(run.omega)[:samples])
        direction = generator.standard_normal(3)
        knocks.append(direction / np.linalg.norm(direction))
    return holds, starts, flights, knocks


def _recording(
    holds: list[int],
    flights: list[Array],
    knocks: list[Array],
    generator: np.random.Generator,
    rate: float,
) -> tuple[Array, Array, list[tuple[float, float]]]:
    """The times (s), the true rates (rad/s, the sensor's axes) and the flights'
    windows of the whole recording: the hand's slow turning between the throws, each
    throw's spin-up from it, its flight, and its catch with an impact."""
    step = 1.0 / rate
    spin_up = max(round(SPIN_UP * rate), 1)
    catch = max(round(CATCH * rate), 1)
    samples = len(flights[0]) if flights else 0
    length = sum(holds) + len(flights) * (spin_up + samples + catch)
    t = np.arange(length, dtype=float) * step
    # The hand turns the body slowly (a few tenths of rad/s, about 1 Hz).
    phases = generator.uniform(0.0, 2.0 * np.pi, 3)
    hand = 0.3 * np.sin(2.0 * np.pi * np.array([0.9, 1.3, 0.7]) * t[:, None] + phases)

    omega = hand.copy()
    windows = []
    index = 0
    for hold, flight, knock in zip(holds, flights, knocks, strict=False):
        index += hold
        # The throw: a steady spin-up from the hand's rate, ending at the release.
        rising = np.arange(spin_up)[:, None] / spin_up
        part = slice(index, index + spin_up)
        omega[part] = (1.0 - rising) * hand[part] + rising * flight[0]
        index += spin_up
        omega[index : index + samples] = flight
        windows.append((float(t[index]), float(t[index + samples - 1])))
        index += samples
        # The catch: spun down to the hand's rate, with an impact 0.01 s after the flight.
        falling = np.arange(1, catch + 1)[:, None] / catch
        part = slice(index, index + catch)
        after = t[part, None] - windows[-1][1]
        impact = 8.0 * np.exp(-(((after - 0.01) / 0.004) ** 2)) * knock
        omega[part] = (1.0 - falling) * flight[-1] + falling * hand[part] + impact
        index += catch
    return t, omega, windows
