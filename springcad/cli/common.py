"""Helpers shared by the CLI subcommands: default outputs, warnings, stage boundaries."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path

from springcad.errors import SpringcadError, StageError

#: exceptions that mean a bug in springcad, never a property of the input: they stay
#: internal errors (exit 3, traceback logged) even inside a stage
PROGRAMMING_ERRORS = (TypeError, AttributeError, NameError, KeyError, IndexError, ImportError,
                      AssertionError, NotImplementedError, RecursionError, SyntaxError)

#: what to change when a library fails inside a stage
ADVICE = {
    "design": "the design math broke down for this spec; move the radii, thickness, stiffness "
              "and deflection toward the templates' values",
    "verify": "the mesher or solver could not handle this geometry; try wider flexures (lower "
              "design stress), a thicker rim, --levels 3 or --mesher pytetwild",
    "solids": "the CAD kernel could not make this part; check the hardware sizes (fasteners, "
              "shaft, spacers) against the spring radii, or move them toward the templates'",
    "checks": "the CAD kernel could not check this part; check the hardware sizes against the "
              "spring radii",
    "exports": "a file could not be written from this part; check the free space and the "
               "names in the config",
    "fit": "the fit could not run on this record; check the units (--torque-unit, "
           "--angle-unit), the sign of the torque and angle columns and that it holds "
           "loading-unloading cycles",
    "simulate": "the bench simulation failed; check --stiffness, --backlash-rad and the other "
                "options",
}


def default_out(config: Path) -> Path:
    """``outputs/<config stem>/`` under the current folder."""
    return Path("outputs") / Path(config).stem


def warn(command: str, warnings) -> None:
    """Print plausibility warnings on the console (stderr), one line each."""
    for w in warnings:
        print(f"springcad {command}: warning: {w}", file=sys.stderr, flush=True)


@contextlib.contextmanager
def stage(name: str, subject=lambda: ""):
    """Turn a third-party failure (CAD kernel, mesher, solver, numerics) inside a stage
    into a :class:`StageError` naming the stage, the part and what to change.

    Args:
        name: stage name (a key of :data:`ADVICE`).
        subject: callable returning the part or spring being worked on.
    """
    try:
        yield
    except (SpringcadError, *PROGRAMMING_ERRORS):
        raise
    except Exception as err:  # noqa: BLE001 - OCP, gmsh, scipy, numpy failures
        raise StageError(name, subject(), err, ADVICE.get(name, "")) from err


def bounded(lo: float, hi: float, unit: str = "", integer: bool = False, lo_open: bool = False):
    """An argparse ``type`` accepting a finite number in [lo, hi] (or (lo, hi])."""
    import argparse
    import math

    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a {'whole number' if integer else 'number'}") from None
        low_ok = value > lo if lo_open else value >= lo
        if not (math.isfinite(value) and low_ok and value <= hi):
            bound = f"greater than {lo:g}" if lo_open else f"from {lo:g}"
            raise argparse.ArgumentTypeError(f"{text}: must be {bound} to {hi:g}{unit}")
        return value

    return parse
