"""The progress bar of long commands: it appears only once a run has taken about a second."""

from __future__ import annotations

from typing import Any

__all__ = ["LazyProgress"]


class LazyProgress:
    """A rich progress bar on stderr that appears only once a run has taken about a second."""

    DELAY = 1.0

    def __init__(self, enabled: bool) -> None:
        import time

        self.enabled = enabled
        self.start = time.monotonic()
        self.bar: Any = None
        self.task: Any = None
        self.description = "simulating"

    def __enter__(self) -> LazyProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()

    def _show(self) -> bool:
        import time

        if not self.enabled:
            return False
        if self.bar is None and time.monotonic() - self.start > self.DELAY:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                TextColumn("{task.percentage:>3.0f}%"),
                TimeElapsedColumn(),
                TextColumn("left"),
                TimeRemainingColumn(),
                console=Console(stderr=True),
                transient=True,
            )
            self.bar.start()
            self.task = self.bar.add_task(self.description, total=None)
        return self.bar is not None

    def steps(self, done: int, total: int) -> None:
        """The library's progress callback: steps done of total."""
        if self._show():
            self.bar.update(self.task, description="simulating", completed=done, total=total)

    def chunks(self, done: int, total: int) -> None:
        """A sweep's progress callback: chunks done of total."""
        if self._show():
            self.bar.update(self.task, description="chunks", completed=done, total=total)

    def stage(self, name: str) -> None:
        """A stage of writing the run folder."""
        self.description = f"writing {name}"
        if self._show():
            self.bar.update(self.task, description=self.description, total=None)
