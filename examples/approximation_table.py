"""Where the textbook approximations stop holding: the tables in docs/approximations.md.

For the heavy gyroscope (a thin disk of 1 kg and radius 0.1 m on a pivot 0.1 m
along its axis) the fast-top formulas are compared with tumble.theory's exact
values over spin rate and tilt; for the gyrocompass (the same disk, platform at
0.5 rad/s) the small-angle frequency β with the exact large-amplitude one. Each
cell is the relative error in per cent; values above 1 % are marked with *.

Run from the repository root::

    .venv/bin/python examples/approximation_table.py > docs/approximation_tables.txt
"""

from __future__ import annotations

import math

import tumble as tb

DISK = tb.shapes.thin_disk(1.0, 0.1)
PIVOT = [0.0, 0.0, -0.1]
SPINS = (20.0, 50.0, 100.0, 200.0, 500.0, 1000.0)  # rad/s
TILTS = (10.0, 30.0, 60.0, 90.0, 120.0)  # degrees from the upward vertical


def cell(error: float) -> str:
    if not math.isfinite(error):
        return "      —"
    return f"{100 * error:6.2f}" + ("*" if error > 0.01 else " ")


def gyroscope_errors(spin: float, tilt: float) -> tuple[float, float, float]:
    """Relative errors of the fast-top precession rate, nutation frequency and
    nutation half-amplitude against the exact values for a top released from rest."""
    top = tb.theory.gyroscope(DISK, PIVOT, spin, math.radians(tilt))
    low, high = top.nutation_limits
    exact_amplitude = 0.5 * (high - low)
    precession = math.nan
    if top.precession_rates is not None:
        precession = abs(top.precession_rate / top.precession_rates[0] - 1)
    frequency = abs(top.nutation_frequency * top.nutation_period / (2 * math.pi) - 1)
    amplitude = abs(top.nutation_amplitude / exact_amplitude - 1) if exact_amplitude else math.nan
    return precession, frequency, amplitude


def main() -> None:
    names = (
        "precession rate m g l / (I_s ω_s) vs the slow steady root",
        "nutation frequency I_s ω_s / I⊥ vs the exact period of θ(t)",
        "nutation half-amplitude m g l I⊥ sin θ0 / (I_s ω_s)² vs the exact turning points",
    )
    for k, name in enumerate(names):
        print(f"Heavy gyroscope: {name} (error in %, * above 1 %)")
        print("spin rad/s | " + " ".join(f"{t:6.0f}°" for t in TILTS))
        for spin in SPINS:
            print(f"{spin:10.0f} | " + " ".join(cell(gyroscope_errors(spin, t)[k]) for t in TILTS))
        print()
    print("Gyrocompass: small-angle β = √(L_s Ω / I_AB) vs the exact frequency 2π / period(θ0)")
    amplitudes = (5.0, 20.0, 45.0, 90.0, 135.0, 170.0)
    print("spin rad/s | " + " ".join(f"{a:6.0f}°" for a in amplitudes))
    for spin in (20.0, 50.0, 100.0, 300.0, 1000.0):
        compass = tb.theory.gyrocompass(DISK, spin, 0.5)
        row = []
        for amplitude in amplitudes:
            exact = 2 * math.pi / compass.period(math.radians(amplitude))
            row.append(cell(abs(compass.oscillation_frequency / exact - 1)))
        print(f"{spin:10.0f} | " + " ".join(row))


if __name__ == "__main__":
    main()
