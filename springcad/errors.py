"""Domain exceptions raised by springcad.

Every error a user can cause carries one clear message that names what is
wrong and what is allowed. The CLI maps them to exit statuses
(:data:`EXIT_OK` ... :data:`EXIT_INTERNAL`): a failed verification or check
is 1, every other :class:`SpringcadError` (bad input, a part the CAD kernel,
mesher or solver cannot make) is 2, anything else is an internal error, 3.
"""

from __future__ import annotations

import reprlib

#: exit statuses of the ``springcad`` command (README "Exit status")
EXIT_OK = 0
EXIT_CHECK_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 3

_repr = reprlib.Repr()
_repr.maxstring, _repr.maxother, _repr.maxlong, _repr.maxlevel = 60, 60, 30, 2
_repr.maxlist = _repr.maxdict = 4


def show(value) -> str:
    """A short, one-line repr of any value (huge ints, deep nesting and long strings cut)."""
    try:
        text = _repr.repr(value)
    except (RecursionError, ValueError):
        text = f"<{type(value).__name__}>"
    return text.replace("\n", "\\n")


def one_line(text: str, limit: int = 400) -> str:
    """``text`` on one line, at most ``limit`` characters (for console messages)."""
    flat = " ".join(str(text).split())
    return flat if len(flat) <= limit else flat[:limit - 3] + "..."


class SpringcadError(Exception):
    """Base class of all springcad errors."""


class ConfigError(SpringcadError, ValueError):
    """A job config key has a value that is not allowed."""

    def __init__(self, key: str, value, allowed: str, hint: str = ""):
        self.key = key
        self.value = value
        self.allowed = allowed
        msg = f"config key '{key}' = {show(value)}: {allowed}"
        if hint:
            msg += f" ({hint})"
        super().__init__(msg)


class OptionError(ConfigError):
    """An option of a stage (a parameter of :mod:`springcad.api`, a flag of the CLI) has a
    value that is not allowed. ``key`` is the public parameter name; the message names the
    option as the caller spells it (``spelled_as``, see :func:`springcad.options.spell`)."""

    def __init__(self, key: str, value, allowed: str, hint: str = "", spelled_as: str = ""):
        self.key, self.value, self.allowed = key, value, allowed
        msg = f"option {spelled_as or key} = {show(value)}: {allowed}"
        SpringcadError.__init__(self, msg + (f" ({hint})" if hint else ""))


class ConfigFileError(ConfigError):
    """The config file itself cannot be used (unreadable, not UTF-8, not TOML)."""

    def __init__(self, path, problem: str):
        self.key, self.value, self.allowed = "file", str(path), problem
        SpringcadError.__init__(self, f"config file '{path}' {problem}")


class DesignError(SpringcadError, ValueError):
    """The spec asks for a spring no geometry in the envelope can deliver.

    Attributes:
        key_changes: a spring refusal's changes of the user's own keys, each
            ``(spring name, key, now, value)`` in the config's units
            (:func:`springcad.design.feasibility.nearest_changes`); empty otherwise.
        disk_changes: a spring refusal's changes of several keys at once, each
            ``(spring name, clause, spec, surface)``: the clause as the refusal prints it,
            the spring spec it makes (:func:`springcad.design.feasibility.larger_disk`)
            and the ``manufacturing.surface`` it needs with it (None: the job's own).
        material_changes: a spring refusal's other materials, each ``(spring name,
            clause, material name, design stress MPa)``
            (:func:`springcad.design.feasibility.material_changes`).
    """

    key_changes: tuple = ()
    disk_changes: tuple = ()
    material_changes: tuple = ()

    def carrying_changes_to(self, other: "DesignError") -> "DesignError":
        """``other`` (this refusal reworded) with this refusal's changes, returned."""
        other.key_changes, other.disk_changes = self.key_changes, self.disk_changes
        other.material_changes = self.material_changes
        return other


class RemedyError(DesignError):
    """A hardware part cannot be made as the job sets it, with the config changes that
    might make it.

    Attributes:
        head: what failed, with its numbers.
        remedies: ``(changes, text)`` pairs, most likely first: ``changes`` maps dotted
            config keys (``"hardware.fastener_diameter_mm"``, ``"springs.A.max_thickness_mm"``)
            to new values, ``text`` shows them as ``key = value (now old)``. The job design
            (:func:`springcad.design.job.design_job`) tries each with the design search and
            names only those under which the whole job designs.
        fallback: a last remedy in words, not checked (may be empty).
    """

    def __init__(self, head: str, remedies, fallback: str = ""):
        self.head, self.remedies, self.fallback = head, list(remedies), fallback
        uses = [t for _, t in self.remedies] + ([fallback] if fallback else [])
        super().__init__(head + ("; use " + " or ".join(uses) if uses else ""))


def change_text(key: str, value, now, note: str = "") -> str:
    """``key = value (now old; note)`` with numbers as ``%g`` and strings quoted as in TOML."""
    def show_value(v) -> str:
        return f'"{v}"' if isinstance(v, str) else f"{v:g}"
    return f"{key} = {show_value(value)} (now {show_value(now)}{'; ' + note if note else ''})"


class SpecInfeasible(DesignError):
    """No choice of the free parameters can help: the spec itself breaks a bound that holds
    for every layout (the energy a disk can store, the tip balls' torque cap, no flexure
    count fitting at any contact radius). The design search stops trying layouts on it."""


class GeometryError(SpringcadError):
    """The CAD kernel could not make or validate a part."""


class MeshingError(SpringcadError):
    """A solid could not be meshed, or the mesh lost a feature."""


class SolverError(SpringcadError):
    """A finite-element solve failed (singular system, large residual)."""


class DataError(SpringcadError, ValueError):
    """Measured bench data is malformed or implausible."""


class OutputExistsError(SpringcadError):
    """An output folder exists and would be overwritten."""


class OutputPathError(SpringcadError):
    """An output path cannot be used: it is a file, lies under a file or is not writable."""


class NoSpaceError(OutputPathError):
    """The disk holding the output has not enough free space (nothing is left behind)."""


class CheckFailed(SpringcadError):
    """A verification or check ran and failed (exit status 1; the outputs say why).

    The family of every failed verdict: :class:`fea.verdict.VerificationFailed` (a spring
    or the stack misses its stiffness target or stress limit) and
    :class:`springcad.geometry.checks.ChecksFailed` (a part fails a geometry or
    manufacturability check) are ``CheckFailed``, so callers catch one class.
    """


class StageError(SpringcadError):
    """A third-party library (CAD kernel, mesher, solver) failed inside a pipeline stage.

    Args:
        stage: pipeline stage, e.g. "solids", "exports", "verify".
        subject: the part or spring being worked on when it failed ("" if unknown).
        cause: the library's exception.
        advice: what to change.
    """

    def __init__(self, stage: str, subject: str, cause: BaseException, advice: str):
        self.stage, self.subject, self.cause = stage, subject, cause
        where = f" on {subject}" if subject else ""
        what = one_line(f"{type(cause).__name__}: {cause}", 200)
        super().__init__(f"stage '{stage}' failed{where} ({what}); {advice}")


class Interrupted(BaseException):
    """SIGTERM arrived (raised from the signal handler, like KeyboardInterrupt for SIGINT)."""
