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
