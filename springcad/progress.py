"""The one progress protocol of every long library step.

A step that takes long (building a stack, checking it, exporting, FEA, a synthesis
sweep) accepts ``progress``: a callable ``progress(message, fraction=None)`` that it
calls with a short message and, where it knows it, the share of the step done
(0-1). A step that counts items (a sweep's candidates) says so in the message's
:class:`Count` form, which a progress bar reads back. Library code never prints; the
CLI decides what to show (:mod:`springcad.cli.progress`).
"""

from __future__ import annotations

import re
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Protocol


class Progress(Protocol):
    """``progress(message, fraction=None)``: a step's short message and its done share (0-1)."""

    def __call__(self, message: str, fraction: float | None = None) -> None: ...


def no_progress(message: str, fraction: float | None = None) -> None:
    """The default: report nothing."""


#: the progress of the step running in this context (:func:`reporting`)
_AMBIENT: ContextVar = ContextVar("springcad_progress", default=None)


@contextmanager
def reporting(progress: Progress | None):
    """Within the block, :func:`report` forwards to ``progress``: for messages from deep
    inside a step whose inner functions take no progress argument (the design search's
    plate choice and refusal, called from many places)."""
    token = _AMBIENT.set(progress)
    try:
        yield
    finally:
        _AMBIENT.reset(token)


def ambient() -> Progress | None:
    """The progress of the enclosing :func:`reporting` block (None outside one)."""
    return _AMBIENT.get()


def report(message: str, fraction: float | None = None) -> None:
    """Send ``message`` to the progress of the enclosing :func:`reporting` block, if any."""
    progress = _AMBIENT.get()
    if progress is not None:
        progress(message, fraction)


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


@dataclass(frozen=True)
class Count:
    """How far a counting step is: ``done`` of ``total`` items, ``done_before`` of them
    finished by an earlier run (a resumed sweep).

    A counting step reports ``progress(count.message(), count.fraction)``; a renderer
    that wants the numbers reads them back with :meth:`parse` (the message is the one
    protocol's plain text, so any progress callable can print it).
    """

    done: int
    total: int
    label: str = "items"
    done_before: int = 0

    _FORM = re.compile(r"^(\d+)/(\d+) (\S+)(?: \((\d+) from an earlier run\))?$")

    @property
    def fraction(self) -> float:
        return self.done / self.total if self.total else 1.0

    def message(self) -> str:
        """``"600/1000 candidates (200 from an earlier run)"``."""
        resumed = f" ({self.done_before} from an earlier run)" if self.done_before else ""
        return f"{self.done}/{self.total} {self.label}{resumed}"

    @classmethod
    def parse(cls, message: str) -> "Count | None":
        """The count a :meth:`message` holds, or None for any other message."""
        m = cls._FORM.match(message)
        if m is None:
            return None
        return cls(int(m[1]), int(m[2]), m[3], int(m[4] or 0))
