"""From measured rates to a body: the inertia ratios, principal axes and motion of
a body flying free or under air drag, fitted to a gyroscope's samples (a phone
thrown in the tennis-racket experiment, a spacecraft's coasting telemetry).

* :func:`tumble.identify` — the fit of one window (:class:`BodyFit`): nonlinear
  least squares of the exact torque-free motion, or of the motion under linear or
  quadratic air drag (``torque=``; ``"auto"`` chooses by the Bayesian information
  criterion), with the sensor's axes, its bias and the motion at the window's
  start, from a start found without a guess.
* :func:`tumble.identify_many` — every throw of a recording fitted alone, then all
  together (:class:`ThrowFits`, :class:`JointFit`): one body, one sensor, one drag
  shared by the throws, each with its own start; throws that disagree are flagged
  as outliers, and a held-out end of each throw measures the forecast.
* :func:`free_flight`, :func:`free_flights` — the torque-free part of a
  recording, or every one of its throws, by a rule from Euler's equations
  (``|ω̇| ≤ |ω|²`` for any physical body); :func:`read_windows` — windows chosen
  by hand, from a CSV file.
* :func:`synthetic_phone`, :func:`synthetic_throws` — a thrown phone's recording,
  and a racquet's many throws under drag, made in code with their truth;
  :func:`example_recording_path`, :func:`example_throws_path` — the same, shipped
  as phyphox CSV files.
* :func:`read_recording` — samples from a phyphox export, a CSV or a Parquet
  file, in rad/s.

Rates no torque-free body shows (``|ω̇| > |ω|²/√3``, as rates in deg/s read as
rad/s are) are refused; a recording sampled far faster than its motion needs is
averaged to fewer samples first (:mod:`tumble.identification.decimation`).
"""

from __future__ import annotations

from tumble.identification.flight import free_flight, free_flights, noise_level
from tumble.identification.joint import JointFit
from tumble.identification.many import ThrowFits
from tumble.identification.phone import PhoneRecording, synthetic_phone
from tumble.identification.recordings import Recording, example_recording_path, read_recording
from tumble.identification.result import PARAMETERS, BodyFit
from tumble.identification.throws import ThrowsRecording, example_throws_path, synthetic_throws
from tumble.identification.windows import read_windows

__all__ = [
    "PARAMETERS",
    "BodyFit",
    "JointFit",
    "PhoneRecording",
    "Recording",
    "ThrowFits",
    "ThrowsRecording",
    "example_recording_path",
    "example_throws_path",
    "free_flight",
    "free_flights",
    "noise_level",
    "read_recording",
    "read_windows",
    "synthetic_phone",
    "synthetic_throws",
]
