"""Read a job config: bytes -> UTF-8 text -> TOML -> checked values -> :class:`Job`.

Every check is driven by :data:`springcad.config.schema.SECTIONS`; cross-key
consistency and plausibility warnings are in :mod:`springcad.config.consistency`.
The first problem found raises :class:`ConfigError` naming the key, the value
and what is allowed; nothing here is slower than a few milliseconds.
"""

from __future__ import annotations

import difflib
import math
import tomllib
from dataclasses import asdict
from pathlib import Path

from springcad.config import consistency
from springcad.config.schema import MAX_SPRINGS, REMOVED, REQUIRED, Key, _toml_type, keys
from springcad.config.specs import (AnalysisSpec, HardwareSpec, Job, ManufacturingSpec,
                                    MaterialSpec, SpringSpec, StackSpec)
from springcad.errors import ConfigError, ConfigFileError
from springcad.materials import DEFAULT_MATERIAL, Material, material_table
from springcad.textio import decode_utf8
from springcad.units import MPA_PER_GPA, NMM_PER_NM

#: a job config is a few hundred bytes; refuse anything absurdly large before parsing
MAX_CONFIG_BYTES = 1_000_000
TOP_LEVEL = ("job", "material", "springs", "stack", "manufacturing", "hardware", "analysis")
SPRING_NAME = Key("<name>", "str", "-", 1, 32, REQUIRED, text="name")


# --------------------------------------------------------------------------- text
def read_toml(path: Path | str) -> dict:
    """Parse a TOML file, every failure as :class:`ConfigFileError`."""
    path = Path(path)
    try:
        if path.is_dir():
            raise ConfigFileError(path, "is a folder; give the job's .toml file")
        with open(path, "rb") as fh:
            raw = fh.read(MAX_CONFIG_BYTES + 1)
    except OSError as err:
        raise ConfigFileError(path, f"cannot be read: {err.strerror or err}") from None
    if len(raw) > MAX_CONFIG_BYTES:
        raise ConfigFileError(path, f"is larger than {MAX_CONFIG_BYTES // 1000} kB; a job "
                                    "config is a few hundred bytes")
    text, problem = decode_utf8(raw)
    if text is None:
        raise ConfigFileError(path, problem)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ConfigFileError(path, f"is not valid TOML: {err}") from None
    except RecursionError:
        raise ConfigFileError(path, "nests arrays or tables too deeply to be read; a job config "
                                    "has two levels ([springs.<name>] keys)") from None


# --------------------------------------------------------------------------- values
def _table(value, full: str) -> dict:
    if not isinstance(value, dict):
        raise ConfigError(full, value, f"must be a table ([{full}] with keys), got "
                                       f"{_toml_type(value)}")
    return value


def _unknown(full: str, value, allowed: list[str]) -> ConfigError:
    name = full.rsplit(".", 1)[-1]
    stem = name.split("_")[0]
    similar = sorted(set(difflib.get_close_matches(name, allowed, n=2, cutoff=0.6))
                     | {k for k in allowed if k.split("_")[0] == stem})
    hint = (f"did you mean {' or '.join(similar)}? units are part of the key name"
            if similar else "")
    return ConfigError(full, value, f"is not a known key; allowed: {', '.join(sorted(allowed))}",
                       hint)


def check_section(table, section: str, prefix: str) -> dict:
    """Type- and range-check one table against the schema; unknown keys are errors.

    Args:
        table: the parsed TOML table.
        section: schema section (``"springs.<name>"`` for springs).
        prefix: the table's name in messages (``"springs.S1"``).

    Returns:
        The given values (absent keys are not filled in).
    """
    table = _table(table, prefix)
    declared = keys(section)
    values = {}
    for name, value in table.items():
        full = f"{prefix}.{name}"
        if (section, name) in REMOVED:
            raise ConfigError(full, value, REMOVED[(section, name)])
        if name not in declared:
            raise _unknown(full, value, list(declared))
        values[name] = declared[name].check(value, full)
    return values


def _required(values: dict, section: str, prefix: str, *names: str) -> None:
    for name in names:
        if name not in values:
            key = keys(section)[name]
            raise ConfigError(f"{prefix}.{name}", None, f"is required ({key.doc}; "
                                                        f"{key.allowed})")


# --------------------------------------------------------------------------- sections
def _material(v: dict) -> MaterialSpec:
    p = "material"
    name = v.get("name", DEFAULT_MATERIAL)
    known = material_table()
    props = ("youngs_modulus_GPa", "poisson_ratio", "yield_strength_MPa", "density_kg_per_m3")
    if name in known:
        base = known[name]
    else:
        missing = [k for k in props if k not in v]
        if missing:
            raise ConfigError(f"{p}.name", name,
                              f"is not a built-in material ({', '.join(known)}); a custom "
                              f"material needs {', '.join(missing)}")
        base = Material(name, 0, 0, 0, 0)
    over = {}
    if "youngs_modulus_GPa" in v:
        over["youngs_modulus_MPa"] = v["youngs_modulus_GPa"] * MPA_PER_GPA
    for key in ("poisson_ratio", "yield_strength_MPa", "density_kg_per_m3", "heat_treatment"):
        if key in v:
            over[key] = v[key]
    if "heat_treatment" in v:
        # another heat treatment: the table's hardness no longer applies unless restated
        over["hardness"] = ""
    for key in ("hardness", "heat_treatment_sequence"):
        if key in v:
            over[key] = str(v[key])
    mat = Material(**{**asdict(base), **over})
    sf = v.get("safety_factor")
    if "design_stress_MPa" in v:
        sigma = v["design_stress_MPa"]
        if sigma >= mat.yield_strength_MPa:
            raise ConfigError(f"{p}.design_stress_MPa", sigma,
                              f"must be below the yield strength {mat.yield_strength_MPa:g} MPa")
        sf = 1.0 if sf is None else sf
    else:
        sf = 1.5 if sf is None else sf
        sigma = mat.yield_strength_MPa / sf
    return MaterialSpec(mat, float(sigma), float(sf))


def _spring(name: str, v: dict) -> SpringSpec:
    p = f"springs.{name}"
    sec = "springs.<name>"
    _required(v, sec, p, "stiffness_Nm_per_rad", "outer_radius_mm", "thickness_mm")
    deg, rad = "max_deflection_deg" in v, "max_deflection_rad" in v
    if deg and rad:
        raise ConfigError(f"{p}.max_deflection_deg", v["max_deflection_deg"],
                          "give either max_deflection_deg or max_deflection_rad, not both")
    if not (deg or rad):
        raise ConfigError(f"{p}.max_deflection_deg", None,
                          "is required (max_deflection_deg or max_deflection_rad)")
    theta = math.radians(v["max_deflection_deg"]) if deg else float(v["max_deflection_rad"])
    return SpringSpec(
        name, v["stiffness_Nm_per_rad"] * NMM_PER_NM, theta, float(v["outer_radius_mm"]),
        float(v["thickness_mm"]), v.get("contact_radius_mm"),
        v.get("min_tip_radius_mm", SpringSpec.min_tip_radius_mm), v.get("tip_radius_mm"),
        v.get("n_flexures"), v.get("root_radius_mm"), v.get("flexure", SpringSpec.flexure))


def _stack(v: dict, springs: dict[str, SpringSpec]) -> StackSpec:
    p = "stack"
    inp = v.get("input", StackSpec.input)
    if "sequence" not in v:
        if len(springs) != 1:
            raise ConfigError(f"{p}.sequence", None,
                              "is required when more than one spring is defined "
                              f"(defined: {', '.join(springs)})")
        seq = [next(iter(springs))]
    else:
        seq = v["sequence"]
    for s in seq:
        if s not in springs:
            raise ConfigError(f"{p}.sequence", s,
                              f"is not a defined spring; defined: {', '.join(springs)}")
    if "output" in v:
        n = len(seq)
        expected = inp if n % 2 == 0 else ("rim" if inp == "shaft" else "shaft")
        if v["output"] != expected:
            raise ConfigError(f"{p}.output", v["output"],
                              f"must be '{expected}' for {n} spring(s) with input '{inp}' "
                              "(consecutive springs alternate rim-to-rim and shaft-to-shaft)")
    return StackSpec(tuple(seq), inp)


def _job_name(given: str | None, fallback: str) -> str:
    """The job name; a file-name fallback is made ASCII-safe (it goes into STEP headers)."""
    if given is not None:
        return given
    safe = "".join(c if c.isascii() and (c.isalnum() or c in "_-.+") else "_" for c in fallback)
    return safe.strip("_")[:64] or "job"


def job_from_dict(data, name: str = "job", source: str = "") -> Job:
    """Validate a parsed TOML document and build a :class:`Job`.

    Raises:
        ConfigError: the first key whose value is not allowed.
    """
    data = _table(data, "config")
    for key, value in data.items():
        if key not in TOP_LEVEL:
            raise _unknown(key, value, list(TOP_LEVEL))
    job_v = check_section(data.get("job", {}), "job", "job")
    material = _material(check_section(data.get("material", {}), "material", "material"))
    springs_t = _table(data.get("springs", {}), "springs")
    if not springs_t:
        raise ConfigError("springs", None, "at least one [springs.<name>] table is required")
    if len(springs_t) > MAX_SPRINGS:
        raise ConfigError("springs", f"{len(springs_t)} tables",
                          f"at most {MAX_SPRINGS} spring designs per job")
    spring_values = {}
    for sname, table in springs_t.items():
        SPRING_NAME.check(sname, "springs.<name>")
        spring_values[sname] = check_section(table, "springs.<name>", f"springs.{sname}")
    springs = {n: _spring(n, v) for n, v in spring_values.items()}
    stack_t = data.get("stack", {})
    if isinstance(stack_t, dict) and stack_t.get("sequence") == []:
        raise ConfigError("stack.sequence", [], f"must name at least one spring (defined: "
                                                f"{', '.join(springs)})")
    stack_v = check_section(stack_t, "stack", "stack")
    stack = _stack(stack_v, springs)
    mfg = ManufacturingSpec(**check_section(data.get("manufacturing", {}), "manufacturing",
                                            "manufacturing"))
    hw = HardwareSpec(**check_section(data.get("hardware", {}), "hardware", "hardware"))
    an = AnalysisSpec(**check_section(data.get("analysis", {}), "analysis", "analysis"))
    job = Job(name=_job_name(job_v.get("name"), name),
              description=job_v.get("description", keys("job")["description"].default),
              material=material, springs=springs, stack=stack, manufacturing=mfg, hardware=hw,
              analysis=an, source=source)
    return consistency.check(job, spring_values)


def load_job(path: Path | str) -> Job:
    """Read and validate a TOML job config.

    Raises:
        ConfigError: unreadable file, not UTF-8, TOML syntax error or a disallowed value.
    """
    path = Path(path)
    return job_from_dict(read_toml(path), name=path.stem, source=str(path))


