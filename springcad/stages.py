"""Pipeline stages: a third-party failure inside one becomes a :class:`StageError`.

Used by the public API (:mod:`springcad.api`) and the CLI alike, so a CAD-kernel,
mesher or solver failure reads the same from a notebook and from the console:
the stage, the part being worked on and what to change.
"""

from __future__ import annotations

import contextlib
import re

from springcad.errors import SpringcadError, StageError
from springcad.options import spell

#: exceptions that mean a bug in springcad, never a property of the input: they stay
#: internal errors (exit 3, traceback logged) even inside a stage
PROGRAMMING_ERRORS = (TypeError, AttributeError, NameError, KeyError, IndexError, ImportError,
                      AssertionError, NotImplementedError, RecursionError, SyntaxError)

#: what to change when a library fails inside a stage (``{name}`` and ``{name=value}``
#: name an option as the caller spells it, see :func:`advice`)
ADVICE = {
    "design": "the design math broke down for this spec; move the radii, thickness, stiffness "
              "and deflection toward the templates' values",
    "verify": "the mesher or solver could not handle this geometry; try wider flexures (lower "
              "design stress), a thicker rim, {levels=3} or {mesher=pytetwild}",
    "solids": "the CAD kernel could not make this part; check the hardware sizes (fasteners, "
              "shaft, spacers) against the spring radii, or move them toward the templates'",
    "checks": "the CAD kernel could not check this part; check the hardware sizes against the "
              "spring radii",
    "exports": "a file could not be written from this part; check the free space and the "
               "names in the config",
    "fit": "the fit could not run on this record; check the units ({torque_unit}, "
           "{angle_unit}), the sign of the torque and angle columns and that it holds "
           "loading-unloading cycles",
    "simulate": "the bench simulation failed; check {stiffness_Nm_per_rad}, {backlash_rad} "
                "and the other options",
}


def advice(name: str) -> str:
    """What to change after a failure in stage ``name``, its options spelled for the caller."""
    def option(match) -> str:
        key, _, value = match.group(1).partition("=")
        return spell(key, int(value) if value.isdigit() else value or None)

    return re.sub(r"\{(\w+(?:=\w+)?)\}", option, ADVICE.get(name, ""))


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
    except Exception as err:
        raise StageError(name, subject(), err, advice(name)) from err
