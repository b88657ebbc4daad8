"""Domain exceptions raised by springcad.

Every error a user can cause carries one clear message that names what is
wrong and what is allowed. The CLI maps these to exit status 2.
"""


class SpringcadError(Exception):
    """Base class of all springcad errors."""


class ConfigError(SpringcadError, ValueError):
    """A job config key has a value that is not allowed."""

    def __init__(self, key: str, value, allowed: str, hint: str = ""):
        self.key = key
        self.value = value
        self.allowed = allowed
        msg = f"config key '{key}' = {value!r}: {allowed}"
        if hint:
            msg += f" ({hint})"
        super().__init__(msg)


class DesignError(SpringcadError, ValueError):
    """The spec asks for a spring no geometry in the envelope can deliver."""


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
