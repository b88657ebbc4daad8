"""Helpers shared by the CLI subcommands: default outputs, warnings, bounded numbers."""

from __future__ import annotations

import sys
from pathlib import Path


def default_out(config: Path) -> Path:
    """``outputs/<config stem>/`` under the current folder."""
    return Path("outputs") / Path(config).stem


def warn(command: str, warnings) -> None:
    """Print plausibility warnings on the console (stderr), one line each."""
    for w in warnings:
        print(f"springcad {command}: warning: {w}", file=sys.stderr, flush=True)


def bounded(lo: float, hi: float, unit: str = "", integer: bool = False, lo_open: bool = False,
            hi_open: bool = False):
    """An argparse ``type`` accepting a finite number in [lo, hi] (either end may be open)."""
    import argparse
    import math

    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a {'whole number' if integer else 'number'}") from None
        low_ok = value > lo if lo_open else value >= lo
        high_ok = value < hi if hi_open else value <= hi
        if not (math.isfinite(value) and low_ok and high_ok):
            bound = f"greater than {lo:g}" if lo_open else f"from {lo:g}"
            top = f"less than {hi:g}" if hi_open else f"{hi:g}"
            raise argparse.ArgumentTypeError(f"{text}: must be {bound} to {top}{unit}")
        return value

    return parse


def add_cache_flag(parser) -> None:
    """``--no-cache``: compute everything again and store nothing (:mod:`springcad.cache`)."""
    parser.add_argument("--no-cache", action="store_true",
                        help="compute every result again and store nothing in the result cache "
                             "(default: reuse designs, FEA, checks and files of equal inputs "
                             "from $SPRINGCAD_CACHE_DIR or ~/.cache/springcad)")


def cache_of(args) -> bool | None:
    """The API's ``cache`` option for ``--no-cache``: False, else None (the default)."""
    return False if getattr(args, "no_cache", False) else None
