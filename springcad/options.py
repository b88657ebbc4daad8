"""The public options of the stages, declared once: names, defaults and allowed values.

The API's signatures (:mod:`springcad.api`), the CLI's flags (:mod:`springcad.cli`) and
the core's option records (:class:`fea.study.VerifyOptions`, the bench reader in
:mod:`springcad.fit.data`) take their defaults from here, and bad values are refused by
:func:`check_choice` and :func:`check_number` with a :class:`~springcad.errors.ConfigError`
(an :class:`~springcad.errors.OptionError`) naming the public parameter, so the doors
cannot drift apart.

A message names an option the way the caller spells it (:func:`spell`):
``angle_unit='deg'`` from Python, ``--angle-unit deg`` from the command line. The doors
declare their spelling with :func:`spelled` (the API: ``"parameter"``, the CLI:
``"flag"``); code called below both doors keeps the command line's spelling.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import math
from dataclasses import dataclass

from springcad.errors import OptionError

# ----------------------------------------------------------------------------- verify
#: FEA models: plane stress x 3D factor, plane stress only, quadratic tets
MODELS = ("2d3d", "2d", "3d")
#: meshers: gmsh (exact face, nested levels) or fTetWild on the CAD solid (3D only)
MESHERS = ("gmsh", "pytetwild")
#: cam load models: smooth tangential traction patch, or a rigid cam
LOADS = ("traction", "rigid_cam")
#: mesh levels of the convergence study (inclusive)
LEVELS_RANGE = (3, 5)
#: accepted stiffness error against the target (%, both ends open)
TOLERANCE_PCT_RANGE = (0.0, 50.0)


@dataclass(frozen=True)
class VerifyDefaults:
    """Defaults of the FEA verification (``sc.verify``, ``springcad verify``, ``build``).

    Attributes:
        model: one of :data:`MODELS`.
        levels: mesh levels of the convergence study.
        mesher: one of :data:`MESHERS`.
        tolerance_pct: accepted stiffness error against the target (%).
        correct: scale the flexure widths until the FEA stiffness meets the target.
        load: cam load model, one of :data:`LOADS`.
        support_study: also compare rim supports on the full ring.
        contact: also run the cam contact sweep over +-theta_max.
    """

    model: str = "2d3d"
    levels: int = 3
    mesher: str = "gmsh"
    tolerance_pct: float = 1.0
    correct: bool = True
    load: str = "traction"
    support_study: bool = False
    contact: bool = True


VERIFY = VerifyDefaults()

# ----------------------------------------------------------------------------- bench records
ANGLE_UNITS = ("rad", "deg")
TORQUE_UNITS = ("Nm", "Nmm")


@dataclass(frozen=True)
class BenchDefaults:
    """Defaults of the bench CSV reader (``sc.fit_record(path)``, ``springcad fit``).

    Attributes:
        time_col: time column (s).
        torque_col: torque column (``torque_unit``).
        deflection_col: optical deflection column (``angle_unit``).
        angle_unit: unit of every angle column, one of :data:`ANGLE_UNITS`.
        torque_unit: unit of the torque column, one of :data:`TORQUE_UNITS`.
    """

    time_col: str = "time_s"
    torque_col: str = "torque_Nm"
    deflection_col: str = "deflection_rad"
    angle_unit: str = "rad"
    torque_unit: str = "Nm"


BENCH = BenchDefaults()

# ----------------------------------------------------------------------------- cache
@dataclass(frozen=True)
class CacheDefaults:
    """Defaults of the result cache (:mod:`springcad.cache`; ``cache=`` of the API,
    ``--no-cache`` of the CLI).

    Attributes:
        enabled: reuse stored designs, FEA results, checks and files of equal inputs.
        max_mb: size bound of the cache folder (MB); least recently used entries go first.
    """

    enabled: bool = True
    max_mb: float = 2048.0


CACHE = CacheDefaults()

#: run a build's independent export steps in a second process (the FEA outputs' renders
#: beside the part exports; :mod:`springcad.parallel`; ``$SPRINGCAD_PARALLEL=0`` turns it off)
PARALLEL = True

# ----------------------------------------------------------------------------- export
#: drawing revision of a build (``sc.export_build``, ``springcad build --revision``)
REVISION = "A"


def check_revision(revision) -> None:
    """The drawing revision rule: 1 to 8 ASCII letters or digits.

    Raises:
        OptionError: a ConfigError naming ``revision``.
    """
    if not (isinstance(revision, str) and 1 <= len(revision) <= 8 and revision.isascii()
            and revision.isalnum()):
        raise refuse("revision", revision, "is 1 to 8 ASCII letters or digits")


#: DXF versions of a build's cutting profiles (``sc.export_build(dxf_version=...)``,
#: ``springcad build --dxf-version``): R2010 (AC1024) the default, R12 (AC1009) for CAM
#: that reads nothing newer; both hold LINE, ARC and CIRCLE entities only
DXF_VERSIONS = ("R2010", "R12")
DXF_VERSION = DXF_VERSIONS[0]


def check_dxf_version(version) -> None:
    """A build's DXF version is one of :data:`DXF_VERSIONS`.

    Raises:
        OptionError: a ConfigError naming ``dxf_version``.
    """
    if version not in DXF_VERSIONS:
        raise refuse("dxf_version", version, f"is one of {', '.join(DXF_VERSIONS)}")


# ----------------------------------------------------------------------------- synthesis
@dataclass(frozen=True)
class SynthesisDefaults:
    """Defaults of ``sc.synthesize``/``springcad synthesize`` (and ``explore``'s Dask run).

    Attributes:
        batch_size: candidates per Dask task and per Parquet part.
        finalists: screened stacks given the full design per round.
        max_finalists: most stacks given the full design in all.
        verify_top: full-design-feasible finalists given build's FEA and checks.
        fea_model: FEA model of the finalists (build's).
    """

    batch_size: int = 2000
    finalists: int = 8
    max_finalists: int = 40
    verify_top: int = 2
    fea_model: str = VERIFY.model


SYNTHESIS = SynthesisDefaults()


@dataclass(frozen=True)
class ExploreDefaults:
    """Defaults of ``sc.explore``/``springcad explore``: the design-space map's grid
    (:class:`springcad.synthesis.explore.ExploreGrid` takes them from here).

    Attributes:
        stiffness_Nm_per_rad: (min, max, count), log-spaced stack stiffnesses (N*m/rad).
        deflection_rad: (min, max, count), log-spaced stack deflections (rad).
        max_disks: stacks of 1 ... max_disks identical disks.
        envelope_radius_mm: envelope radius, bushing included (mm; 4xS1's).
        thickness_mm, contact_radius_mm: disk parameters tried at every target (mm).
        material: built-in material name.
        stress_concentration: first beam stress = yield / this (the paper's 912 MPa).
    """

    stiffness_Nm_per_rad: tuple[float, float, int] = (5.0, 500.0, 24)
    deflection_rad: tuple[float, float, int] = (0.05, 3.0, 24)
    max_disks: int = 6
    envelope_radius_mm: float = 35.05
    thickness_mm: tuple[float, ...] = (3.0, 4.5, 6.0)
    contact_radius_mm: tuple[float, ...] = (4.5, 5.5, 6.5, 7.5, 9.0)
    material: str = "420_ht"
    stress_concentration: float = 1344.0 / 912.0


EXPLORE = ExploreDefaults()

# ----------------------------------------------------------------------------- spelling
#: flags whose name is not the parameter's with dashes
_FLAG_NAMES = {"target_stiffness_Nm_per_rad": "--target-stiffness",
               "stiffness_Nm_per_rad": "--stiffness", "design": "--config",
               "data_dir": "--data", "templates_dir": "--templates", "verify": "--no-verify",
               "render": "--no-render"}
_SPELLING = contextvars.ContextVar("springcad_option_spelling", default=None)


@contextlib.contextmanager
def spelled(style: str, keep: bool = False):
    """Messages raised inside name options as ``style`` spells them.

    Args:
        style: ``"parameter"`` (Python API) or ``"flag"`` (command line).
        keep: keep a spelling an outer door already declared (the API called by the CLI).
    """
    if style not in ("parameter", "flag"):
        raise ValueError(f"spelling {style!r} is not 'parameter' or 'flag'")
    token = None if keep and _SPELLING.get() is not None else _SPELLING.set(style)
    try:
        yield
    finally:
        if token is not None:
            _SPELLING.reset(token)


def api_door(func):
    """Decorate a public API function: messages raised inside it name parameters, unless
    an outer door (the CLI) has declared its own spelling."""
    @functools.wraps(func)
    def door(*args, **kwargs):
        with spelled("parameter", keep=True):
            return func(*args, **kwargs)
    return door


def spell(name: str, value=None) -> str:
    """An option as the caller spells it: ``angle_unit='deg'`` or ``--angle-unit deg``.

    Args:
        name: the public parameter name.
        value: the value to show with it; None for the name alone (``True`` shows a
            switch as its bare flag).
    """
    if _SPELLING.get() == "parameter":
        return name if value is None else f"{name}={value!r}"
    return _flag(name, value)


def _flag(name: str, value=None) -> str:
    """The command line's spelling of option ``name`` set to ``value``: a switch whose flag
    turns it off (``--no-verify``) is its bare flag for ``False``."""
    flag = _FLAG_NAMES.get(name, "--" + name.replace("_", "-"))
    if flag.startswith("--no-") and isinstance(value, bool):
        return flag if value is False else f"without {flag}"
    if value is None or value is True:
        return flag
    return f"{flag} {value}"


def written(name: str, value) -> str:
    """An option as a written document (build.json, report.html, a drawing) names it:
    the parameter, then the flag, ``verify=False / --no-verify``.

    A document is read by users of either door, and the API and the CLI write the same
    document for the same job, so it does not depend on the caller's spelling.
    """
    return f"{name}={value!r} / {_flag(name, value)}"


# ----------------------------------------------------------------------------- checks
def refuse(name: str, value, allowed: str, hint: str = "") -> OptionError:
    """The error for option ``name`` (public parameter name) with a value not allowed."""
    return OptionError(name, value, allowed, hint, spelled_as=spell(name))


def check_choice(name: str, value, allowed: tuple) -> None:
    """Refuse a value that is not one of ``allowed``.

    Raises:
        OptionError: a ConfigError naming the parameter, the value and the choices.
    """
    if not isinstance(value, str) or value not in allowed:
        raise refuse(name, value, "is one of " + ", ".join(repr(a) for a in allowed))


def check_number(name: str, value, low: float, high: float, *, integer: bool = False,
                 low_open: bool = False, high_open: bool = False, unit: str = "") -> None:
    """Refuse a value that is not a finite number in the range (ends open or closed).

    Raises:
        OptionError: a ConfigError naming the parameter, the value and the range.
    """
    kind = "an integer" if integer else "a number"
    ok = (isinstance(value, int) if integer else isinstance(value, (int, float)))
    ok = ok and not isinstance(value, bool) and math.isfinite(value)
    ok = ok and (value > low if low_open else value >= low)
    ok = ok and (value < high if high_open else value <= high)
    if not ok:
        bracket = ("(" if low_open else "[") + f"{low:g}, {high:g}" + (")" if high_open else "]")
        raise refuse(name, value, f"is {kind} in {bracket}{unit}")


def check_verify(model: str, levels: int, mesher: str, tolerance_pct: float, load: str) -> None:
    """The verification's options, checked once for every door.

    Raises:
        OptionError: a ConfigError naming the parameter (``model``, ``levels``,
            ``mesher``, ``tolerance_pct``, ``load``) and what is allowed.
    """
    check_choice("model", model, MODELS)
    check_number("levels", levels, *LEVELS_RANGE, integer=True)
    check_choice("mesher", mesher, MESHERS)
    if mesher == "pytetwild" and model != "3d":
        raise refuse("mesher", mesher, "makes 3D meshes only", f"use {spell('model', '3d')} with it")
    check_number("tolerance_pct", tolerance_pct, *TOLERANCE_PCT_RANGE, low_open=True,
                 high_open=True, unit=" %")
    check_choice("load", load, LOADS)
