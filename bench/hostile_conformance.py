"""The hostile requests of ``tumble conform`` and ``tumble.conformance`` (the catalogue's
conformance family): steps and horizons that cannot work, names of nothing, bodies no
body is, outputs that would destroy an input, and the right answers it must give."""

from __future__ import annotations

from hostile_case import Case, command, library

__all__ = ["conformance"]

#: A run short enough for a catalogue: tumble's RK4 on the major-axis spin for 0.1 s.
QUICK = ("--engines", "tumble/rk4", "--scenario", "major-spin", "--duration", "0.1")


def conformance() -> list[Case]:
    """Requests of the conformance suite."""
    refusals = [
        command("conform/dt-zero", "conform", *QUICK, "--dt", "0"),
        command("conform/dt-negative", "conform", *QUICK, "--dt", "-1e-3"),
        command("conform/dt-nan", "conform", *QUICK, "--dt", "nan"),
        command("conform/dt-inf", "conform", *QUICK, "--dt", "inf"),
        command("conform/dt-a-mass", "conform", *QUICK, "--dt", "1 kg"),
        command("conform/dt-empty-item", "conform", *QUICK, "--dt", "1e-3,"),
        command("conform/dt-longer-than-run", "conform", *QUICK, "--dt", "1"),
        command(
            "conform/steps-beyond-limit", "conform", *QUICK[:4], "--duration", "1e4", "--dt", "1e-6"
        ),
        command("conform/duration-zero", "conform", *QUICK[:4], "--duration", "0"),
        command("conform/duration-text", "conform", *QUICK[:4], "--duration", "long"),
        command("conform/unknown-scenario", "conform", "--scenario", "wobble"),
        command("conform/unknown-engine", "conform", "--engines", "havok"),
        command("conform/unknown-variant", "conform", "--engines", "mujoco/rk5"),
        command("conform/empty-engines", "conform", "--engines", ","),
        command("conform/inertia-not-a-body", "conform", *QUICK, "--inertia", "1, 1, 5"),
        command("conform/inertia-negative", "conform", *QUICK, "--inertia", "-1, 2, 3"),
        command("conform/inertia-two-values", "conform", *QUICK, "--inertia", "1, 2"),
        command("conform/omega-nan", "conform", *QUICK, "--omega", "nan, 0, 1"),
        command(
            "conform/omega-on-a-pivot", "conform", "--scenario", "heavy-top", "--omega", "0, 0, 1"
        ),
        command(
            "conform/output-is-a-file",
            "conform",
            *QUICK,
            "-o",
            "kept.txt",
            files={"kept.txt": b"keep me"},
        ),
        command(
            "conform/output-holds-other-work",
            "conform",
            *QUICK,
            "-o",
            "work",
            "--force",
            files={"work/notes.txt": b"mine"},
        ),
        library(
            "conformance/scenario-zero-duration",
            "result = tb.conformance.Scenario((1, 2, 3), (0, 0, 1), 0.0)",
        ),
        library(
            "conformance/pivot-without-gravity",
            "result = tb.conformance.Scenario((1, 1, 2), (0, 0, 5), pivot=(0, 0, -0.1))",
        ),
        library(
            "conformance/sweep-no-steps",
            "result = tb.conformance.sweep(['tumble/rk4'], 'major-spin', [])",
        ),
    ]
    results = [
        command(
            "conform/json-rk4-major-spin",
            "conform",
            *QUICK,
            "--dt",
            "1e-3",
            "--json",
            expect="result",
            # Fourth order at |ω| dt = 0.02 over 0.1 s: the attitude within 1e-9 rad.
            check="json.loads(run.stdout)['attitude_error_max'] < 1e-9",
        ),
        library(
            "conformance/user-body-in-grams",
            "result = tb.conformance.run(['tumble/rk4'], tb.conformance.Scenario("
            "'1000, 2000, 3000 g*m^2', '0, 0, 60 rpm', '1 s'), dt='1 ms')",
            expect="result",
            # A spin about a principal axis: energy kept to round-off, no flips.
            check="abs(result.table['energy_drift_max'][0]) < 1e-12 "
            "and result.table['flips'][0] == 0",
        ),
    ]
    return refusals + results
