"""Progress on the console (stderr): the library's progress messages, and a bar for sweeps.

:func:`console` renders the one progress protocol of the library
(:class:`springcad.progress.Progress`: ``progress(message, fraction=None)``);
:class:`ProgressBar` renders the same protocol for a sweep: its counts
(:class:`springcad.progress.Count` messages) as a bar, other messages as lines.
"""

from __future__ import annotations

import sys
import time

from springcad.progress import Count


def console(quiet: bool = False, indent: str | None = None, stream=None):
    """A :class:`~springcad.progress.Progress` that prints each message on stderr.

    Args:
        quiet: print nothing.
        indent: print ``indent + message``; None prints ``[elapsed s pct%] message``.
        stream: where to print (default stderr).
    """
    t0 = time.perf_counter()

    def report(message: str, fraction: float | None = None) -> None:
        if quiet:
            return
        if indent is not None:
            line = f"{indent}{message}"
        else:
            pct = "" if fraction is None else f" {100 * fraction:3.0f}%"
            line = f"[{time.perf_counter() - t0:6.1f} s{pct}] {message}"
        print(line, file=stream or sys.stderr, flush=True)

    return report


def _clock(seconds: float) -> str:
    if seconds != seconds or seconds == float("inf"):
        return "--:--"
    seconds = int(round(seconds))
    h, rem = divmod(seconds, 3600)
    m, s = divmod(rem, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m:02d}:{s:02d}"


class ProgressBar:
    """A :class:`~springcad.progress.Progress` for sweeps: ``bar(message, fraction=None)``.

    A :class:`~springcad.progress.Count` message (the sweep's candidates) draws the bar;
    any other message is printed on its own line. The elapsed time runs from the first
    count; the rate counts only this run's candidates (a resumed run does not look
    faster than it is). On a terminal the bar is redrawn in place; otherwise a line is
    printed every ``every_s`` seconds and at the end.
    """

    def __init__(self, label: str = "candidates", stream=None, width: int = 28,
                 every_s: float = 5.0):
        self.label, self.stream, self.width, self.every_s = label, stream or sys.stderr, width, every_s
        self._last = -1e9
        self._t0: float | None = None
        self._open = False  # a bar drawn in place, not yet ended by a newline
        self._tty = hasattr(self.stream, "isatty") and self.stream.isatty()

    def line(self, done: int, total: int, elapsed_s: float, done_before: int) -> str:
        frac = done / total if total else 1.0
        fill = int(round(self.width * frac))
        new = done - done_before
        rate = new / elapsed_s if elapsed_s > 0 else float("nan")
        left = (total - done) / rate if rate and rate == rate and rate > 0 else float("nan")
        resumed = f" ({done_before} from an earlier run)" if done_before else ""
        return (f"[{'#' * fill}{'.' * (self.width - fill)}] {done}/{total} {self.label}"
                f"{resumed}  {rate:,.0f}/s  elapsed {_clock(elapsed_s)}  left {_clock(left)}")

    def __call__(self, message: str, fraction: float | None = None) -> None:
        count = Count.parse(message)
        if count is None:
            self.stream.write(("\n" if self._open else "") + message + "\n")
            self._open = False
            self.stream.flush()
            return
        now = time.monotonic()
        if self._t0 is None:
            self._t0 = now
        final = count.done >= count.total
        if not self._tty and not final and now - self._last < self.every_s:
            return
        self._last = now
        text = self.line(count.done, count.total, now - self._t0, count.done_before)
        if self._tty:
            self.stream.write("\r" + text + ("\n" if final else ""))
            self._open = not final
        else:
            self.stream.write(text + "\n")
        self.stream.flush()
