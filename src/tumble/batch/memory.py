"""The memory a batch takes, checked before any work against the budget of
:mod:`tumble.resources`."""

from __future__ import annotations

from tumble.resources import check_memory

__all__ = ["PEAK_PER_VALUE", "PER_BODY", "PER_RECORD", "check_batch_memory"]

#: Memory a batch takes, bytes: per body (its tensors, frames and states, with
#: copies), per recorded value of a body (the records, their stacking and
#: their conversion to body axes: measured 3.0 to 3.3 times the 8 bytes kept),
#: and per record whatever the number of bodies (the arrays' own headers and
#: copies: measured 1.1 KiB).
PER_BODY = 400
PEAK_PER_VALUE = 4 * 8
PER_RECORD = 1536


def check_batch_memory(
    bodies: int, n_steps: int, record_every: int | None, part_values: int
) -> None:
    """Refuse, before any work, a batch whose states and records cannot fit in
    the memory budget (:mod:`tumble.resources`).

    Raises
    ------
    RequestTooLargeError
        With the estimate, and the advice to record less or run a sweep.
    """
    records = 1 if record_every is None else n_steps / record_every + 2
    values = 7 + part_values
    needed = bodies * (PER_BODY + records * values * PEAK_PER_VALUE)
    if record_every is not None:
        needed += records * PER_RECORD
    what = f"{bodies} bodies"
    advice = "Ask for fewer bodies at once"
    if record_every is not None:
        what += (
            f" × {records:.3g} records of {values} values ({n_steps} steps, every {record_every})"
        )
        advice = (
            "Record less often (record_every, or None for the final states only), or ask for "
            "fewer bodies at once"
        )
    check_memory(
        needed,
        what,
        f"{advice}; or run a sweep (tumble.sweep.run_sweep, `tumble sweep`), which streams "
        "its results to disk as it goes.",
    )
