"""Job configuration: one TOML file describes a job.

Sections (units in key names; see ``templates/`` and the README):

``[job]``            name, description
``[material]``       name (built-in table), overrides, design_stress_MPa or safety_factor
``[springs.<name>]`` one table per spring design
``[stack]``          sequence of spring names and the input connection
``[manufacturing]``  process, tolerances, tip-to-cam gap, wire EDM limits
``[hardware]``       fasteners, spacers, shaft, bushing
``[analysis]``       Monte Carlo samples and seed

Loading validates everything; a bad value raises :class:`ConfigError` naming the
key, the value and what is allowed. Internally lengths are mm, torques N*mm,
stresses MPa, angles rad.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from springcad.errors import ConfigError
from springcad.materials import DEFAULT_MATERIAL, Material, material_table
from springcad.units import MPA_PER_GPA, NMM_PER_NM

FLEXURE_SHAPES = ("auto", "straight", "serpentine")
CONNECTIONS = ("shaft", "rim")
PROCESSES = ("wire_edm",)
FASTENER_KINDS = ("bolt", "dowel")
TOLERANCE_DISTRIBUTIONS = ("uniform", "normal")


# --------------------------------------------------------------------------- specs
@dataclass(frozen=True)
class MaterialSpec:
    """Material with the stress the flexures are designed to (MPa)."""

    material: Material
    design_stress_MPa: float
    safety_factor: float
    """Required ratio yield strength / peak stress (checked by FEA)."""


@dataclass(frozen=True)
class SpringSpec:
    """What the user asks of one spring disk.

    Attributes:
        name: spring name used in the stack sequence.
        stiffness_Nmm_per_rad: target stiffness (N*mm/rad).
        max_deflection_rad: deflection the spring must reach at design stress (rad).
        outer_radius_mm: disk outer radius R_o (mm).
        thickness_mm: disk thickness z (mm).
        contact_radius_mm: r_c, or None to choose it.
        min_tip_radius_mm: smallest tip-ball radius allowed (mm).
        tip_radius_mm: exact tip-ball radius (as built), or None to size it for the peak load.
        n_flexures: N, or None to choose it.
        root_radius_mm: R_r, or None for the rim rule.
        flexure: "auto", "straight" or "serpentine".
    """

    name: str
    stiffness_Nmm_per_rad: float
    max_deflection_rad: float
    outer_radius_mm: float
    thickness_mm: float
    contact_radius_mm: float | None = None
    min_tip_radius_mm: float = 0.3
    tip_radius_mm: float | None = None
    n_flexures: int | None = None
    root_radius_mm: float | None = None
    flexure: str = "auto"


@dataclass(frozen=True)
class StackSpec:
    """Series stack: springs from input to output."""

    sequence: tuple[str, ...]
    input: str = "shaft"


@dataclass(frozen=True)
class ManufacturingSpec:
    """Process limits and tolerances (mm)."""

    process: str = "wire_edm"
    t_spring_mm: float = 0.03
    t_shaft_mm: float = 0.03
    w_gap_mm: float = 0.025
    wire_diameter_mm: float = 0.25
    spark_gap_mm: float = 0.025
    min_slot_width_mm: float = 0.35
    min_web_mm: float = 0.4
    min_hole_edge_mm: float = 0.4
    tolerance_distribution: str = "uniform"

    @property
    def min_inside_radius_mm(self) -> float:
        """Smallest inside corner radius the wire can cut (mm)."""
        return 0.5 * self.wire_diameter_mm + self.spark_gap_mm


@dataclass(frozen=True)
class HardwareSpec:
    """Fasteners, spacers and shafts (mm)."""

    fastener: str = "dowel"
    fastener_diameter_mm: float = 1.5
    fastener_count: int = 7
    shaft_diameter_mm: float = 4.0
    rim_spacer_thickness_mm: float = 0.5
    centre_spacer_thickness_mm: float = 0.5
    centre_spacer_clearance_mm: float = 0.5
    bushing_wall_mm: float = 1.5
    camshaft_hub_length_mm: float = 6.0
    rim_spacer_density_kg_per_m3: float = 2700.0
    plastic_density_kg_per_m3: float = 1420.0


@dataclass(frozen=True)
class AnalysisSpec:
    monte_carlo_samples: int = 20000
    seed: int = 1


@dataclass(frozen=True)
class Job:
    """A validated job: everything the pipeline needs, in internal units."""

    name: str
    description: str
    material: MaterialSpec
    springs: dict[str, SpringSpec]
    stack: StackSpec
    manufacturing: ManufacturingSpec
    hardware: HardwareSpec
    analysis: AnalysisSpec = field(default_factory=AnalysisSpec)
    source: str = ""

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        return d


# --------------------------------------------------------------------------- helpers
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


def _require(table: dict, key: str, prefix: str, what: str):
    if key not in table:
        raise ConfigError(f"{prefix}.{key}", None, f"is required ({what})")


def _angle(table: dict, stem: str, prefix: str, required=True) -> float | None:
    deg, rad = f"{stem}_deg", f"{stem}_rad"
    if deg in table and rad in table:
        raise ConfigError(f"{prefix}.{deg}", table[deg],
                          f"give either {deg} or {rad}, not both")
    if deg in table:
        return math.radians(_number(table, deg, prefix))
    if rad in table:
        return float(_number(table, rad, prefix))
    if required:
        raise ConfigError(f"{prefix}.{stem}_deg", None, f"is required ({stem}_deg or {stem}_rad)")
    return None


# --------------------------------------------------------------------------- sections
def _material(table: dict) -> MaterialSpec:
    p = "material"
    allowed = {"name", "youngs_modulus_GPa", "poisson_ratio", "yield_strength_MPa",
               "density_kg_per_m3", "heat_treatment", "hardness", "heat_treatment_sequence",
               "design_stress_MPa", "safety_factor"}
    _check_keys(table, p, allowed)
    name = table.get("name", DEFAULT_MATERIAL)
    known = material_table()
    if name in known:
        base = known[name]
    else:
        missing = [k for k in ("youngs_modulus_GPa", "poisson_ratio", "yield_strength_MPa",
                               "density_kg_per_m3") if k not in table]
        if missing:
            raise ConfigError(f"{p}.name", name,
                              f"is not a built-in material ({', '.join(known)}); a custom "
                              f"material needs {', '.join(missing)}")
        base = Material(name, 0, 0, 0, 0)
    over = {}
    if "youngs_modulus_GPa" in table:
        over["youngs_modulus_MPa"] = _number(table, "youngs_modulus_GPa", p) * MPA_PER_GPA
    if "poisson_ratio" in table:
        over["poisson_ratio"] = _number(table, "poisson_ratio", p, hi=0.4999)
    if "yield_strength_MPa" in table:
        over["yield_strength_MPa"] = _number(table, "yield_strength_MPa", p)
    if "density_kg_per_m3" in table:
        over["density_kg_per_m3"] = _number(table, "density_kg_per_m3", p)
    if "heat_treatment" in table:
        over["heat_treatment"] = str(table["heat_treatment"])
        # another heat treatment: the table's hardness no longer applies unless restated
        over["hardness"] = ""
    for key in ("hardness", "heat_treatment_sequence"):
        if key in table:
            over[key] = str(table[key])
    mat = Material(**{**asdict(base), **over})
    sf = _number(table, "safety_factor", p, lo=1.0) if "safety_factor" in table else None
    if "design_stress_MPa" in table:
        sigma = _number(table, "design_stress_MPa", p)
        if sigma >= mat.yield_strength_MPa:
            raise ConfigError(f"{p}.design_stress_MPa", sigma,
                              f"must be below the yield strength {mat.yield_strength_MPa:g} MPa")
        if sf is None:
            sf = 1.0
    else:
        sf = 1.5 if sf is None else sf
        sigma = mat.yield_strength_MPa / sf
    return MaterialSpec(mat, float(sigma), float(sf))


def _spring(name: str, table: dict) -> SpringSpec:
    p = f"springs.{name}"
    allowed = {"stiffness_Nm_per_rad", "max_deflection_deg", "max_deflection_rad",
               "outer_radius_mm", "thickness_mm", "contact_radius_mm", "min_tip_radius_mm",
               "tip_radius_mm", "n_flexures", "root_radius_mm", "flexure"}
    _check_keys(table, p, allowed)
    for key, what in (("stiffness_Nm_per_rad", "target stiffness in N*m/rad"),
                      ("outer_radius_mm", "disk outer radius in mm"),
                      ("thickness_mm", "disk thickness in mm")):
        _require(table, key, p, what)
    k = _number(table, "stiffness_Nm_per_rad", p)
    theta = _angle(table, "max_deflection", p)
    if theta >= math.pi / 2:
        raise ConfigError(f"{p}.max_deflection_rad", theta,
                          "must be below pi/2 rad (90 deg) for one disk; use a stack for more")
    ro = _number(table, "outer_radius_mm", p)
    z = _number(table, "thickness_mm", p)
    rc = _number(table, "contact_radius_mm", p) if "contact_radius_mm" in table else None
    if rc is not None and rc >= ro:
        raise ConfigError(f"{p}.contact_radius_mm", rc,
                          f"must be smaller than outer_radius_mm = {ro:g}")
    rbmin = _number(table, "min_tip_radius_mm", p) if "min_tip_radius_mm" in table else 0.3
    rb = _number(table, "tip_radius_mm", p) if "tip_radius_mm" in table else None
    n = _number(table, "n_flexures", p, integer=True, lo=2) if "n_flexures" in table else None
    rr = _number(table, "root_radius_mm", p) if "root_radius_mm" in table else None
    if rr is not None and rr >= ro:
        raise ConfigError(f"{p}.root_radius_mm", rr,
                          f"must be smaller than outer_radius_mm = {ro:g}")
    if rr is not None and rc is not None and rr <= rc:
        raise ConfigError(f"{p}.root_radius_mm", rr,
                          f"must be larger than contact_radius_mm = {rc:g}")
    shape = _choice(table, "flexure", p, FLEXURE_SHAPES) if "flexure" in table else "auto"
    return SpringSpec(name, k * NMM_PER_NM, theta, ro, z, rc, rbmin, rb, n, rr, shape)


def _stack(table: dict, springs: dict[str, SpringSpec]) -> StackSpec:
    p = "stack"
    _check_keys(table, p, {"sequence", "input", "output"})
    _require(table, "sequence", p, "list of spring names from input to output")
    seq = table["sequence"]
    if not isinstance(seq, list) or not all(isinstance(s, str) for s in seq):
        raise ConfigError(f"{p}.sequence", seq, "must be a list of spring names")
    if not seq:
        raise ConfigError(f"{p}.sequence", seq,
                          f"must name at least one spring (defined: {', '.join(springs)})")
    for s in seq:
        if s not in springs:
            raise ConfigError(f"{p}.sequence", s,
                              f"is not a defined spring; defined: {', '.join(springs) or 'none'}")
    inp = _choice(table, "input", p, CONNECTIONS) if "input" in table else "shaft"
    if "output" in table:
        out = _choice(table, "output", p, CONNECTIONS)
        n = len(seq)
        expected = inp if n % 2 == 0 else ("rim" if inp == "shaft" else "shaft")
        if out != expected:
            raise ConfigError(f"{p}.output", out,
                              f"must be '{expected}' for {n} spring(s) with input '{inp}' "
                              "(consecutive springs alternate rim-to-rim and shaft-to-shaft)")
    return StackSpec(tuple(seq), inp)


def _dataclass_section(cls, table: dict, prefix: str, choices: dict[str, tuple] = {},
                       integers: tuple[str, ...] = (), zero_ok: tuple[str, ...] = ()):
    defaults = cls()
    allowed = set(asdict(defaults))
    _check_keys(table, prefix, allowed)
    values = {}
    for key, value in table.items():
        if key in choices:
            values[key] = _choice(table, key, prefix, choices[key])
        else:
            values[key] = _number(table, key, prefix, integer=key in integers,
                                  allow_zero=key in zero_ok)
    return cls(**{**asdict(defaults), **values})


def job_from_dict(data: dict, name: str = "job", source: str = "") -> Job:
    """Validate a parsed TOML document and build a :class:`Job`.

    Raises:
        ConfigError: the first key whose value is not allowed.
    """
    _check_keys(data, "", {"job", "material", "springs", "stack", "manufacturing",
                           "hardware", "analysis"})
    job_t = data.get("job", {})
    _check_keys(job_t, "job", {"name", "description"})
    material = _material(data.get("material", {}))
    springs_t = data.get("springs", {})
    if not springs_t:
        raise ConfigError("springs", None, "at least one [springs.<name>] table is required")
    springs = {n: _spring(n, t) for n, t in springs_t.items()}
    if "stack" in data:
        stack = _stack(data["stack"], springs)
    elif len(springs) == 1:
        stack = StackSpec((next(iter(springs)),))
    else:
        raise ConfigError("stack", None, "is required when more than one spring is defined")
    mfg = _dataclass_section(ManufacturingSpec, data.get("manufacturing", {}), "manufacturing",
                             {"process": PROCESSES,
                              "tolerance_distribution": TOLERANCE_DISTRIBUTIONS},
                             zero_ok=("t_spring_mm", "t_shaft_mm", "spark_gap_mm"))
    hw = _dataclass_section(HardwareSpec, data.get("hardware", {}), "hardware",
                            {"fastener": FASTENER_KINDS}, integers=("fastener_count",),
                            zero_ok=("rim_spacer_thickness_mm", "centre_spacer_thickness_mm",
                                     "fastener_count", "bushing_wall_mm"))
    an = _dataclass_section(AnalysisSpec, data.get("analysis", {}), "analysis",
                            integers=("monte_carlo_samples", "seed"), zero_ok=("seed",))
    for s in springs.values():
        if s.tip_radius_mm is not None and s.tip_radius_mm < mfg.min_inside_radius_mm:
            raise ConfigError(f"springs.{s.name}.tip_radius_mm", s.tip_radius_mm,
                              f"must be at least the wire radius + spark gap = "
                              f"{mfg.min_inside_radius_mm:g} mm for wire EDM")
        if s.min_tip_radius_mm < mfg.min_inside_radius_mm:
            raise ConfigError(f"springs.{s.name}.min_tip_radius_mm", s.min_tip_radius_mm,
                              f"must be at least the wire radius + spark gap = "
                              f"{mfg.min_inside_radius_mm:g} mm for wire EDM")
    return Job(name=job_t.get("name", name), description=job_t.get("description", ""),
               material=material, springs=springs, stack=stack, manufacturing=mfg,
               hardware=hw, analysis=an, source=source)


def load_job(path: Path | str) -> Job:
    """Read and validate a TOML job config.

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
    return job_from_dict(data, name=path.stem, source=str(path))
