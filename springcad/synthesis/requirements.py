"""Requirement schema for ``springcad synthesize``: what the stack must do, not how.

Sections of a requirements TOML (units in key names; see
``templates/requirements_4xS1.toml``):

``[requirement]``    name, description, stiffness_Nm_per_rad, stiffness_tolerance_pct,
                     deflection_deg or deflection_rad (each direction)
``[envelope]``       max_outer_radius_mm (bushing included), max_axial_length_mm
``[materials]``      names (built-in table), yield_margin, fatigue_margin (optional),
                     stress_concentration
``[objective]``      minimise: mass, axial_length, backlash, edm_cut_length;
                     or maximise: energy_density, fatigue_margin
``[search]``         the design space: max_disks, thickness_mm, contact_radius_mm,
                     outer_radius_fractions, n_flexures or fewer_flexures, inputs, mixed,
                     compliance_splits,
                     min_tip_radius_mm, tip_radius_mm
``[duty]``           as in a job config (preset, or blocks in fractions of theta_max; the
                     surface is ``manufacturing.surface``): every stack is ranked only if
                     its disks meet it; passed through to the winner's job
``[manufacturing]``, ``[hardware]``  as in a job config (passed through to the winner's job)

A bad value raises :class:`~springcad.errors.ConfigError` naming the key, the value
and what is allowed, as :mod:`springcad.config` does. Internally N*mm, mm, rad, MPa.
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path

from springcad.config import CONNECTIONS, HardwareSpec, ManufacturingSpec, job_from_dict
from springcad.config.specs import DutySpec
from springcad.design import contact_fatigue, duty, fatigue
from springcad.design.contact_stress import von_mises_peak
from springcad.errors import ConfigError
from springcad.materials import Material, material_table
from springcad.synthesis.candidates import SCREENING_MODEL
from springcad.units import NMM_PER_NM


# requirement-table validators (a job config validates from its schema in
# springcad/config/schema.py; a requirements file is its own format)
def _number(table: dict, key: str, prefix: str, *, positive=True, allow_zero=False,
            lo=None, hi=None, integer=False):
    full = f"{prefix}.{key}" if prefix else key
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(full, value, "must be a number")
    if integer and (not isinstance(value, int)):
        raise ConfigError(full, value, "must be a whole number")
    if not math.isfinite(value):
        raise ConfigError(full, value, "must be finite")
    if positive and (value < 0 or (value == 0 and not allow_zero)):
        raise ConfigError(full, value, "must be greater than zero" if not allow_zero
                          else "must be zero or greater")
    if lo is not None and value < lo:
        raise ConfigError(full, value, f"must be at least {lo}")
    if hi is not None and value > hi:
        raise ConfigError(full, value, f"must be at most {hi}")
    return value


def _choice(table: dict, key: str, prefix: str, allowed: tuple[str, ...]):
    value = table[key]
    if value not in allowed:
        raise ConfigError(f"{prefix}.{key}", value, f"must be one of {', '.join(allowed)}")
    return value


def _check_keys(table: dict, prefix: str, allowed: set[str]):
    for key in table:
        if key not in allowed:
            hint = ""
            stem = key.rsplit("_", 1)[0]
            similar = sorted(k for k in allowed if k.startswith(stem.split("_")[0]))
            if similar:
                hint = f"did you mean {' or '.join(similar)}? units are part of the key name"
            raise ConfigError(f"{prefix}.{key}" if prefix else key, table[key],
                              f"is not a known key; allowed: {', '.join(sorted(allowed))}", hint)

#: objectives and whether a smaller value is better
OBJECTIVES = {"mass": True, "axial_length": True, "backlash": True, "edm_cut_length": True,
              "energy_density": False, "fatigue_margin": False}
#: the column of the candidate table each objective reads
OBJECTIVE_COLUMNS = {"mass": "mass_kg", "axial_length": "axial_length_mm",
                     "backlash": "backlash_nominal_rad", "edm_cut_length": "edm_cut_length_mm",
                     "energy_density": "energy_density_J_per_cm3", "fatigue_margin": "fatigue_margin"}


@dataclass(frozen=True)
class SearchSpace:
    """Which stacks to enumerate.

    Attributes:
        max_disks: stacks of 1 ... max_disks disks.
        thickness_mm: disk thicknesses z to try (mm).
        contact_radius_mm: contact radii r_c to try (mm); one r_c per stack so the
            camshafts of shaft-to-shaft joints fit both neighbours.
        outer_radius_fractions: disk outer radius R_o as fractions of the largest the
            envelope allows (the bushing of a stack of 3+ disks taken off) (-).
        n_flexures: flexure counts to try; empty = derived from the largest count that
            fits (the design rule of :func:`springcad.design.search.design_spring`) by
            ``fewer_flexures``.
        fewer_flexures: when ``n_flexures`` is empty, try N = N_max - k for each k
            (fewer flexures leave a thicker rim for the fastener holes).
        inputs: input connections to try ("shaft", "rim").
        mixed: also enumerate stacks of two designs (n_a of A then n_b of B).
        compliance_splits: share of the stack compliance taken by the A group of a
            mixed stack (-); every disk is designed for the same peak torque.
        min_tip_radius_mm: smallest tip-ball radius (mm).
        tip_radius_mm: fixed tip-ball radius (mm), as the paper's hardware (0.3 mm): balls
            are not sized for the peak load and the torque-cap rule is not applied; the
            calibrated peak stress (tip-neck fillet included) decides, as in a job config
            with ``tip_radius_mm``. None (default): balls sized for the peak load.
        flexure: "auto" (straight where it reaches, else serpentine) or "straight" (only
            straight flexures: no serpentine turns, whose concave edges raise the stress).
    """

    max_disks: int = 6
    thickness_mm: tuple[float, ...] = (3.0, 4.5, 6.0)
    contact_radius_mm: tuple[float, ...] = (4.5, 5.5, 6.5, 7.5)
    outer_radius_fractions: tuple[float, ...] = (1.0,)
    n_flexures: tuple[int, ...] = ()
    fewer_flexures: tuple[int, ...] = (0,)
    inputs: tuple[str, ...] = ("shaft", "rim")
    mixed: bool = True
    compliance_splits: tuple[float, ...] = (0.25, 0.5, 0.75)
    min_tip_radius_mm: float = 0.3
    tip_radius_mm: float | None = None
    flexure: str = "auto"


@dataclass(frozen=True)
class Requirements:
    """A validated synthesis request in internal units (N*mm, mm, rad, MPa).

    Attributes:
        target_stiffness_Nmm_per_rad: target stack stiffness (N*mm/rad).
        stiffness_tolerance: accepted |K / K_target - 1| (-), used by the FEA check.
        deflection_rad: deflection the stack must reach in each direction (rad).
        max_outer_radius_mm: largest envelope radius, bushing included (mm).
        max_axial_length_mm: largest stack height, spacers included (mm).
        materials: candidate materials.
        yield_margin: required yield strength / *predicted* peak stress of the real
            geometry (:mod:`springcad.design.stress`: curved-beam flank, root and neck
            fillets, calibrated to FEA) (-).
        fatigue_margin: required fully reversed fatigue margin S_e / predicted peak
            (:mod:`springcad.design.fatigue`), or None (not required) (-).
        stress_concentration: sets the beam stress every candidate is first designed to,
            sigma = yield / (yield_margin * stress_concentration); screening and the full
            design then lower it (``stress_derating``) until the predicted peak keeps the
            margins (-).
        objective: one of :data:`OBJECTIVES`.
        search: the design space.
        manufacturing_table, hardware_table: the TOML tables, passed to the winner's job.
    """

    name: str
    description: str
    target_stiffness_Nmm_per_rad: float
    stiffness_tolerance: float
    deflection_rad: float
    max_outer_radius_mm: float
    max_axial_length_mm: float
    materials: tuple[Material, ...]
    yield_margin: float
    stress_concentration: float
    objective: str
    search: SearchSpace
    manufacturing: ManufacturingSpec
    hardware: HardwareSpec
    manufacturing_table: dict = field(default_factory=dict)
    hardware_table: dict = field(default_factory=dict)
    source: str = ""
    fatigue_margin: float | None = None
    duty: DutySpec | None = None
    """A declared duty (fractions of each disk's theta_max): a peak-stress limit per material."""
    duty_table: dict = field(default_factory=dict)
    surface: str = fatigue.DEFAULT_SURFACE
    """``manufacturing.surface``: the cut faces' surface condition (fatigue surface factor)."""

    @property
    def peak_torque_Nmm(self) -> float:
        return self.target_stiffness_Nmm_per_rad * self.deflection_rad

    def design_stress_MPa(self, material: Material) -> float:
        """Stress every flexure of ``material`` is designed to (MPa)."""
        return material.yield_strength_MPa / (self.yield_margin * self.stress_concentration)

    def endurance_limit_MPa(self, material: Material) -> float:
        """Corrected endurance limit S_e of the part (MPa; NaN without fatigue data)."""
        check = fatigue.check(material.name, 1.0, self.surface)
        return check.endurance_limit_MPa if check is not None else float("nan")

    def required_yield_margin(self, material: Material) -> float:
        """The yield margin that also keeps the fatigue margin (-): yield / allowed peak.

        The fatigue requirement S_e / peak >= fatigue_margin is a peak-stress limit like
        the yield one, so the synthesis (and the winner's job, as ``safety_factor``)
        asks for max(yield_margin, fatigue_margin x yield / S_e).
        """
        margin = self.yield_margin
        if self.fatigue_margin is not None:
            margin = max(margin, self.fatigue_margin * material.yield_strength_MPa
                         / self.endurance_limit_MPa(material))
        if self.duty is not None:  # fractions of theta_max: the same limit for every disk
            check = duty.check(self.duty, material.name, 1.0, 1.0)
            margin = max(margin, material.yield_strength_MPa / check.allowed_peak_MPa)
        return margin

    def contact_allowed_MPa(self, material: Material) -> float:
        """Largest tip-ball contact von Mises at theta_max (MPa): yield / yield margin, and
        with a duty c_vm x the p0 its contact fatigue allows
        (:func:`springcad.design.contact_fatigue.allowable_p0_MPa`), as the design sizes
        its balls for a declared duty."""
        allowed = material.yield_strength_MPa / self.yield_margin
        if self.duty is not None:  # fractions of theta_max: the same limit for every disk
            p0 = contact_fatigue.allowable_p0_MPa(self.duty, material.name, 1.0)
            if math.isfinite(p0):
                allowed = min(allowed, von_mises_peak(round(material.poisson_ratio, 6))[0] * p0)
        return allowed

    def allowed_peak_MPa(self, material: Material) -> float:
        """Largest predicted peak stress a disk of ``material`` may carry (MPa)."""
        return material.yield_strength_MPa / self.required_yield_margin(material)

    def fatigue_limited(self, material: Material) -> bool:
        """Whether the fatigue margin, not the yield margin, sets the allowed peak."""
        return self.required_yield_margin(material) > self.yield_margin

    @property
    def minimise(self) -> bool:
        return OBJECTIVES[self.objective]

    @property
    def objective_column(self) -> str:
        return OBJECTIVE_COLUMNS[self.objective]

    def fingerprint(self) -> str:
        """A hash of everything that changes the candidate table (for resuming runs)."""
        d = asdict(self)
        d["screening_model"] = SCREENING_MODEL
        d.pop("source")
        d.pop("name")
        d.pop("description")
        return hashlib.sha256(json.dumps(d, sort_keys=True, default=str).encode()).hexdigest()[:16]


# --------------------------------------------------------------------------- parsing
def _floats(table: dict, key: str, prefix: str, lo=None, hi=None) -> tuple[float, ...]:
    value = table[key]
    if not isinstance(value, list) or not value:
        raise ConfigError(f"{prefix}.{key}", value, "must be a non-empty list of numbers")
    return tuple(float(_number({key: v}, key, prefix, lo=lo, hi=hi)) for v in value)


def _search(table: dict, max_radius_mm: float) -> SearchSpace:
    p = "search"
    d = SearchSpace()
    _check_keys(table, p, set(asdict(d)))
    kw = {}
    if "max_disks" in table:
        kw["max_disks"] = _number(table, "max_disks", p, integer=True, lo=1, hi=20)
    if "thickness_mm" in table:
        kw["thickness_mm"] = _floats(table, "thickness_mm", p, lo=0.5, hi=50)
    if "contact_radius_mm" in table:
        kw["contact_radius_mm"] = _floats(table, "contact_radius_mm", p, lo=0.5,
                                          hi=0.9 * max_radius_mm)
    if "outer_radius_fractions" in table:
        kw["outer_radius_fractions"] = _floats(table, "outer_radius_fractions", p, lo=0.2, hi=1.0)
    if "n_flexures" in table:
        v = table["n_flexures"]
        if not isinstance(v, list) or not all(isinstance(n, int) and not isinstance(n, bool)
                                              and 2 <= n <= 400 for n in v):
            raise ConfigError(f"{p}.n_flexures", v, "must be a list of whole numbers 2-400 "
                              "(empty: the largest count that fits)")
        kw["n_flexures"] = tuple(v)
    if "fewer_flexures" in table:
        v = table["fewer_flexures"]
        if not isinstance(v, list) or not v or not all(
                isinstance(k, int) and not isinstance(k, bool) and 0 <= k <= 100 for k in v):
            raise ConfigError(f"{p}.fewer_flexures", v, "must be a non-empty list of whole "
                              "numbers 0-100 (0: the largest count that fits)")
        kw["fewer_flexures"] = tuple(dict.fromkeys(v))
    if "inputs" in table:
        v = table["inputs"]
        if not isinstance(v, list) or not v or any(x not in CONNECTIONS for x in v):
            raise ConfigError(f"{p}.inputs", v, f"must be a non-empty list of {', '.join(CONNECTIONS)}")
        kw["inputs"] = tuple(dict.fromkeys(v))
    if "mixed" in table:
        if not isinstance(table["mixed"], bool):
            raise ConfigError(f"{p}.mixed", table["mixed"], "must be true or false")
        kw["mixed"] = table["mixed"]
    if "compliance_splits" in table:
        kw["compliance_splits"] = _floats(table, "compliance_splits", p, lo=0.05, hi=0.95)
    if "flexure" in table:
        if table["flexure"] not in ("auto", "straight"):
            raise ConfigError(f"{p}.flexure", table["flexure"], "must be one of auto, straight")
        kw["flexure"] = table["flexure"]
    if "min_tip_radius_mm" in table:
        kw["min_tip_radius_mm"] = _number(table, "min_tip_radius_mm", p, lo=0.05, hi=5)
    if "tip_radius_mm" in table:
        kw["tip_radius_mm"] = float(_number(table, "tip_radius_mm", p, lo=0.05, hi=5))
    return SearchSpace(**{**asdict(d), **kw})


def _materials(table: dict) -> tuple[tuple[Material, ...], float, float, float | None]:
    p = "materials"
    _check_keys(table, p, {"names", "yield_margin", "stress_concentration", "fatigue_margin"})
    known = material_table()
    names = table.get("names", ["420_ht"])
    if not isinstance(names, list) or not names or any(n not in known for n in names):
        raise ConfigError(f"{p}.names", names,
                          f"must be a non-empty list of built-in materials ({', '.join(known)})")
    fatigue_margin = None
    if "fatigue_margin" in table:
        fatigue_margin = float(_number(table, "fatigue_margin", p, lo=0.05, hi=10.0))
        missing = [n for n in names if n not in fatigue.fatigue_table()]
        if missing:
            raise ConfigError(f"{p}.fatigue_margin", fatigue_margin,
                              f"cannot be checked for {', '.join(missing)}: no fatigue data "
                              f"(springcad/data/fatigue.csv has {', '.join(fatigue.fatigue_table())})")
    margin = _number(table, "yield_margin", p, lo=1.0, hi=10.0) if "yield_margin" in table else 1.0
    kt = (_number(table, "stress_concentration", p, lo=1.0, hi=5.0)
          if "stress_concentration" in table else 1.0)
    if margin * kt <= 1.0:
        raise ConfigError(f"{p}.yield_margin", margin,
                          "times stress_concentration must exceed 1 (the design stress must stay "
                          "below the yield strength); raise yield_margin or stress_concentration")
    return (tuple(known[n] for n in dict.fromkeys(names)), float(margin), float(kt),
            fatigue_margin)


def requirements_from_dict(data: dict, name: str = "requirements",
                           source: str = "") -> Requirements:
    """Validate a parsed requirements TOML.

    Raises:
        ConfigError: the first key whose value is not allowed.
    """
    _check_keys(data, "", {"requirement", "envelope", "materials", "objective", "search",
                           "manufacturing", "hardware", "duty"})
    p = "requirement"
    req = data.get("requirement")
    if not isinstance(req, dict):
        raise ConfigError(p, req, "a [requirement] table with stiffness_Nm_per_rad and "
                                  "deflection_deg is required")
    _check_keys(req, p, {"name", "description", "stiffness_Nm_per_rad",
                         "stiffness_tolerance_pct", "deflection_deg", "deflection_rad"})
    if "stiffness_Nm_per_rad" not in req:
        raise ConfigError(f"{p}.stiffness_Nm_per_rad", None, "is required (target stack stiffness)")
    k = _number(req, "stiffness_Nm_per_rad", p)
    tol = (_number(req, "stiffness_tolerance_pct", p, lo=0.1, hi=40)
           if "stiffness_tolerance_pct" in req else 5.0)
    if ("deflection_deg" in req) == ("deflection_rad" in req):
        raise ConfigError(f"{p}.deflection_deg", req.get("deflection_deg"),
                          "give exactly one of deflection_deg or deflection_rad "
                          "(deflection in each direction)")
    theta = (math.radians(_number(req, "deflection_deg", p, hi=3600)) if "deflection_deg" in req
             else float(_number(req, "deflection_rad", p, hi=20 * math.pi)))
    p = "envelope"
    env = data.get("envelope", {})
    _check_keys(env, p, {"max_outer_radius_mm", "max_axial_length_mm"})
    for key in ("max_outer_radius_mm", "max_axial_length_mm"):
        if key not in env:
            raise ConfigError(f"{p}.{key}", None, "is required (mm)")
    r_max = _number(env, "max_outer_radius_mm", p, lo=3.0, hi=1000.0)
    h_max = _number(env, "max_axial_length_mm", p, lo=0.5, hi=5000.0)
    materials, margin, kt, fatigue_margin = _materials(data.get("materials", {}))
    p = "objective"
    obj = data.get("objective", {})
    _check_keys(obj, p, {"minimise", "maximise"})
    if len(obj) > 1:
        raise ConfigError(p, obj, "give one of minimise or maximise")
    key, value = next(iter(obj.items())) if obj else ("minimise", "mass")
    allowed = [o for o, smaller in OBJECTIVES.items() if smaller == (key == "minimise")]
    if value not in allowed:
        raise ConfigError(f"{p}.{key}", value, f"must be one of {', '.join(allowed)}")
    search = _search(data.get("search", {}), r_max)
    mfg_t, hw_t = data.get("manufacturing", {}), data.get("hardware", {})
    # the job schema validates these tables: same keys, same messages as a job config
    duty_t = data.get("duty")
    probe = job_from_dict({"springs": {"probe": {"target_stiffness_Nm_per_rad": 1.0,
                                                 "max_deflection_rad": 1.55,
                                                 "outer_radius_mm": 10.0, "thickness_mm": 1.0}},
                           "manufacturing": mfg_t, "hardware": hw_t,
                           **({"duty": duty_t} if duty_t is not None else {})})
    duty_spec = probe.material.duty if duty_t is not None else None
    if duty_spec is not None:
        if any(b.unit != "fraction" for b in duty_spec.blocks) or (
                duty_spec.series and duty_spec.series_unit != "fraction"):
            raise ConfigError("duty", duty_t, "in a requirements file the duty is given in "
                              "fractions of each disk's theta_max (a preset, amplitude_fraction "
                              "blocks or a file with file_unit = \"fraction\"): the disks' "
                              "deflections are what the synthesis chooses")
        missing = [m.name for m in materials if m.name not in fatigue.fatigue_table()]
        if missing:
            raise ConfigError("duty", duty_t, f"cannot be checked for {', '.join(missing)}: no "
                              f"fatigue data (springcad/data/fatigue.csv has "
                              f"{', '.join(fatigue.fatigue_table())})")
    for ball_key in ("min_tip_radius_mm", "tip_radius_mm"):
        ball_mm = getattr(search, ball_key)
        if ball_mm is not None and ball_mm < probe.manufacturing.min_inside_radius_mm:
            raise ConfigError(f"search.{ball_key}", ball_mm,
                              f"must be at least the wire radius + spark gap = "
                              f"{probe.manufacturing.min_inside_radius_mm:g} mm")
    return Requirements(
        name=str(req.get("name", name)), description=str(req.get("description", "")),
        target_stiffness_Nmm_per_rad=float(k) * NMM_PER_NM, stiffness_tolerance=float(tol) / 100.0,
        deflection_rad=float(theta), max_outer_radius_mm=float(r_max),
        max_axial_length_mm=float(h_max), materials=materials, yield_margin=margin,
        stress_concentration=kt, objective=value, search=search,
        manufacturing=probe.manufacturing, hardware=probe.hardware,
        manufacturing_table=dict(mfg_t), hardware_table=dict(hw_t), source=source,
        fatigue_margin=fatigue_margin, duty=duty_spec, surface=probe.material.duty.surface,
        duty_table=dict(duty_t) if duty_t is not None else {})


def load_requirements(path: Path | str) -> Requirements:
    """Read and validate a requirements TOML.

    Raises:
        ConfigError: unreadable file, TOML syntax error or a disallowed value.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise ConfigError("file", str(path), f"cannot be read: {err.strerror}") from err
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ConfigError("file", str(path), f"is not valid TOML: {err}") from err
    return requirements_from_dict(data, name=path.stem, source=str(path))
