"""From measured rates to a body: the inertia ratios, principal axes and motion of
a torque-free body fitted to a gyroscope's samples (a phone thrown in the
tennis-racket experiment, a spacecraft's coasting telemetry).

* :func:`tumble.identify` — the fit (:class:`BodyFit`): nonlinear least squares of the
  exact torque-free motion, with the sensor's axes, its bias and the motion at
  the window's start, from a start found without a guess.
* :func:`free_flight` — the torque-free part of a recording, by a rule from
  Euler's equations (``|ω̇| ≤ |ω|²`` for any physical body).
* :func:`synthetic_phone` — a thrown phone's recording made in code, with its
  truth; :func:`example_recording_path` — the same, shipped as a phyphox CSV.
* :func:`read_recording` — samples from a phyphox export, a CSV or a Parquet
  file, in rad/s.

Rates no torque-free body shows (``|ω̇| > |ω|²/√3``, as rates in deg/s read as
rad/s are) are refused; a recording sampled far faster than its motion needs is
averaged to fewer samples first (:mod:`tumble.identification.decimation`).
"""

from __future__ import annotations

from tumble.identification.flight import free_flight, noise_level
from tumble.identification.phone import PhoneRecording, synthetic_phone
from tumble.identification.recordings import Recording, example_recording_path, read_recording
from tumble.identification.result import PARAMETERS, BodyFit

__all__ = [
    "PARAMETERS",
    "BodyFit",
    "PhoneRecording",
    "Recording",
    "example_recording_path",
    "free_flight",
    "noise_level",
    "read_recording",
    "synthetic_phone",
]
