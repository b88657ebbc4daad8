"""The one progress protocol of every long library step.

A step that takes long (building a stack, checking it, exporting, FEA) accepts
``progress``: a callable ``progress(message, fraction=None)`` that it calls
with a short message and, where it knows it, the share of the step done
(0-1). Library code never prints; the CLI decides what to show.
"""

from __future__ import annotations

from typing import Protocol


class Progress(Protocol):
    """``progress(message, fraction=None)``: a step's short message and its done share (0-1)."""

    def __call__(self, message: str, fraction: float | None = None) -> None: ...


def no_progress(message: str, fraction: float | None = None) -> None:
    """The default: report nothing."""


class Tracker:
    """A progress callable that forwards to another and remembers what was last reported.

    The last message names the part or spring a failing stage worked on
    (:meth:`subject`, for :func:`springcad.stages.stage`).

    Args:
        progress: the callable to forward to (default: report nothing).
    """

    def __init__(self, progress: Progress | None = None):
        self.progress = progress or no_progress
        self.last = ""
        self.spring = ""

    def __call__(self, message: str, fraction: float | None = None) -> None:
        self.last = message
        if message.startswith("verifying spring "):
            self.spring = message.split()[2]
        self.progress(message, fraction)

    def subject(self, stage: str):
        """A callable naming what stage ``stage`` worked on when it failed ("" if unknown)."""
        def subject() -> str:
            if stage == "verify":
                return f"spring {self.spring}" if self.spring else ""
            if stage == "solids":
                return (f"the part after {self.last.split()[-1]}" if self.last.startswith("built ")
                        else "the first part")
            return f"the step after '{self.last}'" if self.last else ""
        return subject
