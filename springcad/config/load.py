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
from dataclasses import asdict, replace
from pathlib import Path

from springcad.config import consistency
from springcad.config.schema import MAX_SPRINGS, REMOVED, RENAMED, REQUIRED, Key, _toml_type, keys
from springcad.config.specs import (AnalysisSpec, DutyBlock, DutySpec, HardwareSpec, Job,
                                    ManufacturingSpec, MaterialSpec, SpringSpec, StackSpec)
from springcad.connections import output_connection
from springcad.errors import ConfigError, ConfigFileError
from springcad.materials import DEFAULT_MATERIAL, Material, material_table
from springcad.textio import decode_utf8
from springcad.units import BYTES_PER_KB, BYTES_PER_MB, MPA_PER_GPA, NMM_PER_NM, RAD_PER_DEG

#: a job config is a few hundred bytes; refuse anything absurdly large before parsing
MAX_CONFIG_BYTES = 1_000_000
TOP_LEVEL = ("job", "material", "springs", "stack", "manufacturing", "hardware", "analysis",
             "duty")
#: a duty time series file: at most this many bytes and samples
MAX_SERIES_BYTES = 20_000_000
MAX_SERIES_SAMPLES = 2_000_000
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
        raise ConfigFileError(path, f"is larger than {MAX_CONFIG_BYTES // BYTES_PER_KB} kB; a job "
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
        if (section, name) in RENAMED:  # read under its new name (deprecations() warns)
            name = RENAMED[(section, name)]
            if name in table:
                raise ConfigError(full, value, f"is the old name of {prefix}.{name}, which is "
                                  "also given; delete this key")
        if name not in declared:
            raise _unknown(full, value, list(declared))
        values[name] = declared[name].check(value, full)
    return values


def deprecations(table, section: str, prefix: str) -> list[str]:
    """The deprecation warnings of one table's renamed keys (:data:`RENAMED`)."""
    return [f"{prefix}.{old} is deprecated: it is now {prefix}.{new} (same value and unit); "
            "rename the key" for (sec, old), new in RENAMED.items()
            if sec == section and isinstance(table, dict) and old in table]


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
    _required(v, sec, p, "target_stiffness_Nm_per_rad", "outer_radius_mm")
    deg, rad = "max_deflection_deg" in v, "max_deflection_rad" in v
    if deg and rad:
        raise ConfigError(f"{p}.max_deflection_deg", v["max_deflection_deg"],
                          "give either max_deflection_deg or max_deflection_rad, not both")
    if not (deg or rad):
        raise ConfigError(f"{p}.max_deflection_deg", None,
                          "is required (max_deflection_deg or max_deflection_rad)")
    theta = math.radians(v["max_deflection_deg"]) if deg else float(v["max_deflection_rad"])
    if "thickness_mm" in v and "max_thickness_mm" in v:
        raise ConfigError(f"{p}.max_thickness_mm", v["max_thickness_mm"],
                          "bounds the thickness springcad chooses, so it applies only when "
                          "thickness_mm is not given; delete one of the two")
    return SpringSpec(
        name, v["target_stiffness_Nm_per_rad"] * NMM_PER_NM, theta, float(v["outer_radius_mm"]),
        (float(v["thickness_mm"]) if "thickness_mm" in v else None), v.get("contact_radius_mm"),
        v.get("min_tip_radius_mm", SpringSpec.min_tip_radius_mm), v.get("tip_radius_mm"),
        v.get("n_flexures"), v.get("root_radius_mm"), v.get("flexure", SpringSpec.flexure),
        (float(v["max_thickness_mm"]) if "max_thickness_mm" in v else None))


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
        expected = output_connection(n, inp)
        if v["output"] != expected:
            raise ConfigError(f"{p}.output", v["output"],
                              f"must be '{expected}' for {n} spring(s) with input '{inp}' "
                              "(consecutive springs alternate rim-to-rim and shaft-to-shaft)")
    return StackSpec(tuple(seq), inp)


def _block(i: int, table, springs: dict[str, SpringSpec]) -> DutyBlock:
    p = f"duty.blocks[{i}]"
    v = check_section(table, "duty.blocks", p)
    _required(v, "duty.blocks", p, "cycles")
    frac, deg = "amplitude_fraction" in v, "amplitude_deg" in v
    if frac == deg:
        raise ConfigError(f"{p}.amplitude_fraction", v.get("amplitude_fraction"),
                          "give exactly one of amplitude_fraction (of theta_max) or "
                          "amplitude_deg")
    mean_key = "mean_fraction" if frac else "mean_deg"
    other = "mean_deg" if frac else "mean_fraction"
    if other in v:
        raise ConfigError(f"{p}.{other}", v[other], f"give the mean in the amplitude's unit "
                          f"({mean_key}), not {other}")
    label = v.get("label", "") or f"block {i + 1}"
    if frac:
        amp, mean = float(v["amplitude_fraction"]), float(v.get("mean_fraction", 0.0))
        if abs(mean) + amp > 1.0 + 1e-9:
            raise ConfigError(f"{p}.amplitude_fraction", amp,
                              f"with mean_fraction {mean:g} reaches {abs(mean) + amp:g} theta_max; "
                              "a block must stay within +-theta_max (|mean| + amplitude <= 1)")
        return DutyBlock(float(v["cycles"]), amp, mean, "fraction", label)
    amp, mean = math.radians(v["amplitude_deg"]), math.radians(v.get("mean_deg", 0.0))
    for name, s in springs.items():
        if abs(mean) + amp > s.max_deflection_rad * (1 + 1e-9):
            raise ConfigError(f"{p}.amplitude_deg", v["amplitude_deg"],
                              f"with mean_deg {v.get('mean_deg', 0.0):g} reaches "
                              f"{math.degrees(abs(mean) + amp):.4g} deg, beyond spring {name}'s "
                              f"max_deflection {math.degrees(s.max_deflection_rad):.4g} deg; "
                              "a block must stay within +-theta_max of every spring")
    return DutyBlock(float(v["cycles"]), amp, mean, "rad", label)


def _series(path: Path, unit: str, springs: dict[str, SpringSpec]) -> tuple[float, ...]:
    """The deflection samples of a duty file, in rad or fractions of theta_max."""
    full = "duty.file"
    try:
        raw = path.read_bytes()[:MAX_SERIES_BYTES + 1]
    except OSError as err:
        raise ConfigError(full, str(path), f"cannot be read: {err.strerror or err}") from None
    if len(raw) > MAX_SERIES_BYTES:
        raise ConfigError(full, str(path), f"is larger than {MAX_SERIES_BYTES // BYTES_PER_MB} MB")
    text, problem = decode_utf8(raw)
    if text is None:
        raise ConfigError(full, str(path), problem)
    values = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        field = line.replace(";", ",").replace("\t", ",").split(",")[-1].split()[-1:]
        try:
            x = float(field[0]) if field else math.nan
        except ValueError:
            if not values:  # a header line
                continue
            raise ConfigError(full, str(path), f"line {n}: {line[:60]!r} has no number in its "
                              "last column (one deflection per line, last column)") from None
        if not math.isfinite(x):
            raise ConfigError(full, str(path), f"line {n}: the deflection must be a finite "
                              "number")
        values.append(x)
        if len(values) > MAX_SERIES_SAMPLES:
            raise ConfigError(full, str(path), f"has more than {MAX_SERIES_SAMPLES} samples")
    if len(values) < 2:
        raise ConfigError(full, str(path), "needs at least two deflection samples (one a line, "
                          "last column)")
    scale = {"deg": RAD_PER_DEG, "rad": 1.0, "fraction": 1.0}[unit]
    series = tuple(x * scale for x in values)
    peak = max(abs(x) for x in series)
    limits = {"": 1.0} if unit == "fraction" else {
        name: s.max_deflection_rad for name, s in springs.items()}
    for name, lim in limits.items():
        if peak > lim * (1 + 1e-9):
            what = (f"{peak:g} theta_max" if unit == "fraction" else
                    f"{math.degrees(peak):.4g} deg, beyond spring {name}'s max_deflection "
                    f"{math.degrees(lim):.4g} deg")
            raise ConfigError(full, str(path), f"reaches {what}; the series must stay within "
                              "+-theta_max")
    return series


def _duty(table, springs: dict[str, SpringSpec], surface: str, base: Path) -> DutySpec:
    """The [duty] table (absent: springcad's default duty)."""
    if table is None:
        return DutySpec(surface=surface)
    table = dict(_table(table, "duty"))
    blocks_t = table.pop("blocks", None)
    v = check_section(table, "duty", "duty")
    given = [k for k, present in (("preset", "preset" in v), ("blocks", blocks_t is not None),
                                  ("file", "file" in v)) if present]
    if len(given) > 1:
        raise ConfigError(f"duty.{given[1]}", None, f"give one of preset, blocks or file, not "
                          f"{' and '.join(given)}")
    common = {k: v[k] for k in ("safety_factor", "reliability") if k in v}
    if blocks_t is not None:
        if not isinstance(blocks_t, list) or not blocks_t:
            raise ConfigError("duty.blocks", blocks_t, "must be an array of tables "
                              "([[duty.blocks]] with cycles and amplitude_fraction or "
                              "amplitude_deg), at least one")
        if len(blocks_t) > 1000:
            raise ConfigError("duty.blocks", f"{len(blocks_t)} blocks", "at most 1000 blocks")
        blocks = tuple(_block(i, b, springs) for i, b in enumerate(blocks_t))
        return DutySpec(preset=None, blocks=blocks, surface=surface, declared=True, **common)
    if "file" in v:
        path = Path(v["file"])
        path = path if path.is_absolute() else base / path
        unit = v.get("file_unit", keys("duty")["file_unit"].default)
        return DutySpec(preset=None, series=_series(path, unit, springs),
                        series_unit="fraction" if unit == "fraction" else "rad",
                        series_repeats=float(v.get("file_repeats", 1.0)),
                        series_file=v["file"], surface=surface, declared=True, **common)
    for k in ("file_unit", "file_repeats"):
        if k in v:
            raise ConfigError(f"duty.{k}", v[k], "applies only with duty.file")
    return DutySpec(preset=v.get("preset", DutySpec.preset), surface=surface, declared=True,
                    **common)


def _job_name(given: str | None, fallback: str) -> str:
    """The job name; a file-name fallback is made ASCII-safe (it goes into STEP headers)."""
    if given is not None:
        return given
    safe = "".join(c if c.isascii() and (c.isalnum() or c in "_-.+") else "_" for c in fallback)
    return safe.strip("_")[:64] or "job"


def _shaft_that_fits(hw_values: dict, springs: dict) -> dict:
    """The hardware values with springcad's camshaft bore where none is given: the default
    diameter, or, when a spring's fixed contact radius leaves no room for it,
    :func:`~springcad.config.consistency.shaft_diameter_below_mm` the smallest fixed
    contact radius (the design checks the cam's wall over it and names the largest bore
    that keeps it)."""
    if "shaft_diameter_mm" in hw_values:
        return hw_values
    fixed = [s.contact_radius_mm for s in springs.values() if s.contact_radius_mm is not None]
    key = keys("hardware")["shaft_diameter_mm"]
    if not fixed or key.default < min(fixed):
        return hw_values
    return {**hw_values, "shaft_diameter_mm": consistency.shaft_diameter_below_mm(min(fixed))}


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
    spring_values, deprecated = {}, []
    for sname, table in springs_t.items():
        SPRING_NAME.check(sname, "springs.<name>")
        spring_values[sname] = check_section(table, "springs.<name>", f"springs.{sname}")
        deprecated += deprecations(table, "springs.<name>", f"springs.{sname}")
    springs = {n: _spring(n, v) for n, v in spring_values.items()}
    stack_t = data.get("stack", {})
    if isinstance(stack_t, dict) and stack_t.get("sequence") == []:
        raise ConfigError("stack.sequence", [], f"must name at least one spring (defined: "
                                                f"{', '.join(springs)})")
    stack_v = check_section(stack_t, "stack", "stack")
    stack = _stack(stack_v, springs)
    mfg_v = check_section(data.get("manufacturing", {}), "manufacturing", "manufacturing")
    surface = mfg_v.pop("surface", keys("manufacturing")["surface"].default)
    mfg = ManufacturingSpec(**mfg_v)
    base = Path(source).parent if source else Path.cwd()
    material = replace(material, duty=_duty(data.get("duty"), springs, surface, base))
    hw_v = check_section(data.get("hardware", {}), "hardware", "hardware")
    hw = HardwareSpec(**_shaft_that_fits(hw_v, springs), given=tuple(sorted(hw_v)))
    an = AnalysisSpec(**check_section(data.get("analysis", {}), "analysis", "analysis"))
    job = Job(name=_job_name(job_v.get("name"), name),
              description=job_v.get("description", keys("job")["description"].default),
              material=material, springs=springs, stack=stack, manufacturing=mfg, hardware=hw,
              analysis=an, source=source)
    job = consistency.check(job, spring_values)
    return replace(job, warnings=tuple(deprecated) + job.warnings) if deprecated else job


def load_job(path: Path | str) -> Job:
    """Read and validate a TOML job config.

    Raises:
        ConfigError: unreadable file, not UTF-8, TOML syntax error or a disallowed value.
    """
    path = Path(path)
    return job_from_dict(read_toml(path), name=path.stem, source=str(path))


