"""The job config schema: every key declared once, with type, unit, range, default and doc.

:data:`SECTIONS` is the single source of truth: loading (:mod:`springcad.config.load`)
checks every value against it, the spec dataclasses (:mod:`springcad.config.specs`)
take their defaults from it and the README's config table is generated from it
(``python -m springcad.config --readme README.md``; a test keeps the two equal).

Ranges are physical and deliberately bounded: every accepted config must design in
well under a second and build in bounded time, so sizes, counts and sample numbers
that only an error would produce (1e300 mm radii, 10^9 Monte Carlo samples) are
refused at load with the allowed range, before any work.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from springcad.connections import CONNECTIONS
from springcad.errors import ConfigError, show
from springcad.materials import material_table

#: marker of a key that must be given
REQUIRED = object()
#: marker of an optional key with no default (springcad chooses the value)
CHOSEN = None

#: spring names become file names, STEP labels and drawing titles: ASCII letters,
#: digits, "_" and "-", starting with a letter or digit
NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*\Z")
#: job and material names, heat treatment: printable ASCII without path separators
#: or quotes (they go into STEP headers, DXF/PDF title blocks and file names)
LABEL_RE = re.compile(r"[ -~]*\Z")
LABEL_FORBIDDEN = set('/\\"\'<>|:*?')
#: ISO 4762 screw sizes that also have an ISO 4032 nut (bd_warehouse), mm
BOLT_DIAMETERS_MM = (1.6, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0)

def _num(x: float) -> str:
    """A bound as written in messages: whole numbers in full, others with %g."""
    if float(x).is_integer() and abs(x) < 1e10:
        return str(int(x))
    return f"{x:g}"


def _toml_type(value) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    return f"a {type(value).__name__}"


@dataclass(frozen=True)
class Key:
    """One config key.

    Attributes:
        name: key name inside its table (units are part of the name).
        kind: "float", "int", "str", "choice" or "names" (a list of spring names).
        unit: unit of the value as written in the config ("-" for none).
        lo: smallest allowed value (numbers) or length (strings, lists).
        hi: largest allowed value or length.
        default: value when the key is absent; :data:`REQUIRED` or ``None``
            (springcad chooses it; see ``doc``).
        doc: one line for the README table.
        choices: allowed strings of a "choice" key.
        text: "name" (spring-name characters), "label" (printable ASCII, no path
            separators or quotes) or "text" (any printable text) for "str" keys.
        lo_open: the lower bound itself is not allowed.
    """

    name: str
    kind: str
    unit: str
    lo: float | None = None
    hi: float | None = None
    default: Any = REQUIRED
    doc: str = ""
    choices: Sequence[str] = ()
    text: str = "text"
    lo_open: bool = False

    # ----------------------------------------------------------------- text
    @property
    def allowed(self) -> str:
        """What is allowed, as the error message and the README say it."""
        unit = "" if self.unit == "-" else f" {self.unit}"
        if self.kind == "choice":
            return "one of " + ", ".join(f'"{c}"' for c in self.choices)
        if self.kind == "names":
            return f"a list of {_num(self.lo)} to {_num(self.hi)} spring names"
        if self.kind == "str":
            what = {"name": "letters, digits, _ and - (ASCII)",
                    "label": "printable ASCII without / \\ \" ' < > | : * ?",
                    "text": "printable text"}[self.text]
            return f"a string of {_num(self.lo)} to {_num(self.hi)} characters: {what}"
        whole = "a whole number" if self.kind == "int" else "a number"
        if self.lo_open:
            return f"{whole} greater than {_num(self.lo)} and at most {_num(self.hi)}{unit}"
        return f"{whole} from {_num(self.lo)} to {_num(self.hi)}{unit}"

    @property
    def default_text(self) -> str:
        if self.default is REQUIRED:
            return "required"
        if self.default is None:
            return "-"
        if isinstance(self.default, str):
            return f'"{self.default}"'
        if isinstance(self.default, float):
            return f"{self.default:g}"
        return str(self.default)

    # ----------------------------------------------------------------- check
    def check(self, value, full: str):
        """The value if it is allowed, else :class:`ConfigError` naming ``full``."""
        kind = self.kind
        if kind in ("float", "int"):
            return self._number(value, full)
        if kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise ConfigError(full, value, f"must be {self.allowed}")
            return value
        if kind == "str":
            return self._string(value, full)
        if kind == "names":
            if not isinstance(value, list):
                raise ConfigError(full, value, f"must be {self.allowed}, got "
                                  f"{_toml_type(value)}")
            if not self.lo <= len(value) <= self.hi:
                raise ConfigError(full, value, f"must be {self.allowed}; it has "
                                  f"{len(value)}")
            for item in value:
                if not isinstance(item, str):
                    raise ConfigError(full, value, f"must be {self.allowed}; "
                                      f"{show(item)} is {_toml_type(item)}")
            return list(value)
        raise AssertionError(kind)

    def _number(self, value, full: str):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(full, value, f"must be {self.allowed}, got "
                              f"{_toml_type(value)}")
        if self.kind == "int" and not isinstance(value, int):
            raise ConfigError(full, value, f"must be {self.allowed}")
        if isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(full, value, f"must be {self.allowed}")
        too_low = value <= self.lo if self.lo_open else value < self.lo
        if too_low or value > self.hi:
            raise ConfigError(full, value, f"must be {self.allowed}")
        return value

    def _string(self, value, full: str) -> str:
        if not isinstance(value, str):
            raise ConfigError(full, value, f"must be {self.allowed}, got "
                              f"{_toml_type(value)}")
        if not self.lo <= len(value) <= self.hi:
            raise ConfigError(full, value, f"must be {self.allowed}; it has "
                              f"{len(value)}")
        if self.text == "name":
            ok = NAME_RE.match(value) is not None
        elif self.text == "label":
            ok = LABEL_RE.match(value) is not None and not (set(value) & LABEL_FORBIDDEN) \
                and value == value.strip()
        else:
            ok = value.isprintable()
        if not ok:
            raise ConfigError(full, value, f"must be {self.allowed}")
        return value


def _f(name, unit, lo, hi, default, doc, lo_open=False):
    return Key(name, "float", unit, lo, hi, default, doc, lo_open=lo_open)


def _i(name, lo, hi, default, doc):
    return Key(name, "int", "-", lo, hi, default, doc)


def _c(name, choices, default, doc):
    return Key(name, "choice", "-", default=default, doc=doc, choices=choices)


def _s(name, text, hi, default, doc, lo=1):
    return Key(name, "str", "-", lo, hi, default, doc, text=text)


class Registered(Sequence):
    """The allowed strings of a choice key whose values a higher layer registers.

    The schema sits below the design layer, so it cannot import what the design defines;
    the design's registry adds each name here when it registers it (a flexure shape:
    :func:`springcad.design.shapes.registry.register`), and the key's check and message
    read the list as it stands. Hashed and compared by identity, like a registry.
    """

    def __init__(self, fixed: tuple[str, ...] = ()):
        self._names: list[str] = list(fixed)

    def add(self, name: str) -> None:
        if name not in self._names:
            self._names.append(name)

    def discard(self, name: str) -> None:
        if name in self._names:
            self._names.remove(name)

    def __getitem__(self, i):
        return self._names[i]

    def __len__(self) -> int:
        return len(self._names)

    def __repr__(self) -> str:
        return f"Registered({tuple(self._names)!r})"


#: "auto" and every flexure shape of the registry (:mod:`springcad.design.shapes`)
FLEXURE_SHAPES = Registered(("auto",))
PROCESSES = ("wire_edm",)
FASTENER_KINDS = ("bolt", "dowel")
TOLERANCE_DISTRIBUTIONS = ("uniform", "normal")
#: surface conditions of the cut faces (springcad/data/surface.csv, kept equal by a test)
SURFACES = ("edm_main_cut", "edm_skim_cuts", "polished", "shot_peened")
#: named duties (springcad.design.duty.PRESETS, kept equal by a test)
DUTY_PRESETS = ("static", "robot_joint", "series_elastic_actuator", "prosthesis")
SERIES_UNITS = ("deg", "rad", "fraction")
#: most springs in one stack, and most spring tables in one job (run time of build/verify)
MAX_SPRINGS = 8

SECTIONS: dict[str, tuple[Key, ...]] = {
    "job": (
        _s("name", "label", 64, CHOSEN, "job name (STEP header, drawings); default: the config "
           "file name"),
        _s("description", "text", 500, "", "free text for design.json", lo=0),
    ),
    "material": (
        _s("name", "label", 40, "420_ht", "a name in springcad/data/materials.csv (420_ht, "
           "17-4ph_h900, maraging_300, ti6al4v, 7075_t6, 6061_t6, 301_shim, pom); any other "
           "name needs the four properties below"),
        _f("youngs_modulus_GPa", "GPa", 1.0, 1000.0, CHOSEN, "Young's modulus E (overrides the "
           "table)"),
        _f("poisson_ratio", "-", 0.0, 0.49, CHOSEN, "Poisson's ratio"),
        _f("yield_strength_MPa", "MPa", 10.0, 5000.0, CHOSEN, "0.2 % proof stress"),
        _f("density_kg_per_m3", "kg/m^3", 500.0, 25000.0, CHOSEN, "density of the springs, "
           "camshafts and shafts"),
        _s("heat_treatment", "label", 200, CHOSEN, "as written on the drawings", lo=0),
        _s("hardness", "label", 60, CHOSEN, "hardness to order, as written on the drawings "
           "(e.g. \"48-52 HRC\"); cleared when heat_treatment is overridden", lo=0),
        _s("heat_treatment_sequence", "label", 60, CHOSEN, "when the heat treatment happens "
           "relative to the cut (e.g. \"before EDM\")", lo=0),
        _f("design_stress_MPa", "MPa", 10.0, 5000.0, CHOSEN, "stress the flexures are sized to; "
           "default yield / safety_factor; below the yield strength"),
        _f("safety_factor", "-", 1.0, 10.0, CHOSEN, "required yield / FEA peak stress (1.5 "
           "without design_stress_MPa, else 1)"),
    ),
    "springs.<name>": (
        _f("target_stiffness_Nm_per_rad", "N*m/rad", 0.001, 1e5, REQUIRED, "target stiffness K "
           "(formerly stiffness_Nm_per_rad)"),
        _f("max_deflection_deg", "deg", 0.05, 89.0, REQUIRED, "deflection reached at the design "
           "stress (or max_deflection_rad)"),
        _f("max_deflection_rad", "rad", 0.000873, 1.553, REQUIRED, "the same in rad (give one of "
           "the two)"),
        _f("outer_radius_mm", "mm", 3.0, 250.0, REQUIRED, "disk outer radius R_o"),
        _f("thickness_mm", "mm", 0.2, 100.0, CHOSEN, "disk thickness z (chosen: the thinnest "
           "stock plate that carries the spring)"),
        _f("max_thickness_mm", "mm", 0.2, 100.0, CHOSEN, "thickest disk springcad may choose "
           "when thickness_mm is not given"),
        _f("contact_radius_mm", "mm", 0.5, 200.0, CHOSEN, "cam contact radius r_c (chosen to "
           "maximise the straight-flexure limit)"),
        _f("min_tip_radius_mm", "mm", 0.01, 10.0, 0.3, "smallest tip ball; the ball is sized "
           "for the peak load"),
        _f("tip_radius_mm", "mm", 0.01, 10.0, CHOSEN, "fixed tip ball (as-built parts); "
           "min_tip_radius_mm is then ignored"),
        _i("n_flexures", 2, 199, CHOSEN, "number of flexures N (chosen from the ball and "
           "cam-tooth fit)"),
        _f("root_radius_mm", "mm", 1.0, 249.0, CHOSEN, "flexure root radius R_r (rim rule "
           "otherwise)"),
        _c("flexure", FLEXURE_SHAPES, "auto", "flexure shape"),
    ),
    "stack": (
        Key("sequence", "names", "-", 1, MAX_SPRINGS, CHOSEN, "spring names from input to "
            "output; optional with one spring"),
        _c("input", CONNECTIONS, "shaft", "input connection (camshaft or rim)"),
        _c("output", CONNECTIONS, CHOSEN, "optional check: follows from input and the number "
           "of springs"),
    ),
    "manufacturing": (
        _c("process", PROCESSES, "wire_edm", "manufacturing process"),
        _f("t_spring_mm", "mm", 0.0, 0.5, 0.01, "machine tolerance of the spring profile "
           "(wire EDM with skim cuts)"),
        _f("t_shaft_mm", "mm", 0.0, 0.5, 0.01, "machine tolerance of the camshaft profile "
           "(wire EDM with skim cuts)"),
        _f("w_gap_mm", "mm", 0.005, 1.0, CHOSEN, "designed tip-to-cam gap per side; chosen: "
           "t_spring_mm + t_shaft_mm + 0.02, so the worst-case gap stays 0.02 mm"),
        _f("wire_diameter_mm", "mm", 0.02, 0.5, 0.25, "EDM wire diameter"),
        _f("spark_gap_mm", "mm", 0.0, 0.2, 0.025, "spark gap; min inside radius = wire radius + "
           "spark gap"),
        _f("min_slot_width_mm", "mm", 0.02, 2.0, 0.35, "narrowest slot between flexures; at "
           "least the kerf (wire + 2 spark gaps)"),
        _f("min_web_mm", "mm", 0.02, 5.0, 0.4, "thinnest web the wire may leave"),
        _f("min_hole_edge_mm", "mm", 0.02, 10.0, 0.4, "material between a rim hole and an edge"),
        _c("tolerance_distribution", TOLERANCE_DISTRIBUTIONS, "uniform", "Monte Carlo: uniform "
           "in +-t, or normal with t = 3 sigma"),
        _c("surface", SURFACES, "edm_skim_cuts", "surface of the flexures' cut faces: fatigue "
           "surface factor and the ring drawing's surface note (springcad/data/surface.csv)"),
    ),
    "hardware": (
        _c("fastener", FASTENER_KINDS, "dowel", "rim fastener"),
        _f("fastener_diameter_mm", "mm", 0.5, 12.0, 1.5, "fastener diameter (bolts: an ISO "
           "4762 size)"),
        _i("fastener_count", 0, 199, 7, "rim holes per spring, midway between flexures (at "
           "most one per flexure gap)"),
        _f("shaft_diameter_mm", "mm", 1.0, 100.0, 4.0, "camshaft bore / torque and alignment "
           "shaft; not given: 4, or the largest 0.5 mm step at least 0.5 mm below the "
           "smallest fixed contact_radius_mm"),
        _f("rim_spacer_thickness_mm", "mm", 0.1, 20.0, 0.4, "axial gap between springs: rim "
           "spacer, washer and centre spacer (sheet); the rim spacer's webs at its pin holes "
           "are at least this thick, so 0.5 needs a rim 0.2 mm wider (2.67 mm for 1.5 mm "
           "dowels)"),
        _f("bushing_wall_mm", "mm", 0.5, 20.0, 1.5, "outer bushing wall (stacks of 3+ springs)"),
        _f("camshaft_hub_length_mm", "mm", 0.5, 100.0, 6.0, "hub of an input/output camshaft"),
        _f("rim_spacer_density_kg_per_m3", "kg/m^3", 500.0, 25000.0, "301_shim",
           "rim spacer density (default: 301_shim in the material table, the stainless "
           "shim strip the spacer is cut from)"),
        _f("plastic_density_kg_per_m3", "kg/m^3", 500.0, 25000.0, "pom",
           "washer, centre spacer and bushing density (default: pom in the material table)"),
    ),
    "duty": (
        _c("preset", DUTY_PRESETS, CHOSEN, "a named duty (README: Duty); default robot_joint "
           "when the job gives no blocks or file"),
        _s("file", "text", 400, CHOSEN, "deflection time series (CSV/text, last column; path "
           "relative to the config), counted by rainflow (ASTM E1049)"),
        _c("file_unit", SERIES_UNITS, "deg", "unit of the file's deflection column (fraction: "
           "of each spring's theta_max)"),
        _f("file_repeats", "-", 1.0, 1e12, 1.0, "times the file's record is repeated over "
           "the life"),
        _f("safety_factor", "-", 1.0, 5.0, 1.2, "required fatigue safety factor on stress "
           "(Miner sum <= 1 with every block's stress x this factor)"),
        _f("reliability", "-", 0.5, 0.9999, 0.99, "survival probability of the endurance limit "
           "(Marin k_e = 1 - 0.08 z; handbook limits are mean values)"),
    ),
    "duty.blocks": (
        _f("cycles", "-", 1.0, 1e12, REQUIRED, "cycles of this block"),
        _f("amplitude_fraction", "-", 0.0, 1.0, CHOSEN, "half the deflection range, as a "
           "fraction of each spring's theta_max (or amplitude_deg)", lo_open=True),
        _f("amplitude_deg", "deg", 0.0, 89.0, CHOSEN, "half the deflection range in deg",
           lo_open=True),
        _f("mean_fraction", "-", -1.0, 1.0, 0.0, "mean deflection as a fraction of theta_max "
           "(or mean_deg)"),
        _f("mean_deg", "deg", -89.0, 89.0, 0.0, "mean deflection in deg"),
        _s("label", "text", 60, "", "name of the block in reports", lo=0),
    ),
    "analysis": (
        _i("monte_carlo_samples", 1, 1_000_000, 20000, "Monte Carlo stacks for the backlash "
           "statistics"),
        _i("seed", 0, 2 ** 32 - 1, 1, "random seed (results are reproducible)"),
    ),
}

#: keys that were renamed: (section, old name) -> new name. The old name is still read,
#: with a deprecation warning on the job (:func:`springcad.config.load.check_section`)
RENAMED = {
    ("springs.<name>", "stiffness_Nm_per_rad"): "target_stiffness_Nm_per_rad",
}

#: keys that were accepted once and had no effect: refused with the reason
REMOVED = {
    ("hardware", "centre_spacer_thickness_mm"):
        "was removed: the centre spacer fills the same gap as the rim spacer, so its thickness "
        "is hardware.rim_spacer_thickness_mm; delete this key",
    ("hardware", "centre_spacer_clearance_mm"):
        "was removed: the centre spacer overhangs the cam teeth by a fixed 0.5 mm and never "
        "used this value; delete this key",
}


def keys(section: str) -> dict[str, Key]:
    """The keys of a section by name (``"springs.<name>"`` for a spring table)."""
    return {k.name: k for k in SECTIONS[section]}


def default(section: str, name: str):
    """Default value of a key (material-table names resolve to their density)."""
    value = keys(section)[name].default
    if isinstance(value, str) and name.endswith("_kg_per_m3"):
        return material_table()[value].density_kg_per_m3
    return value


def markdown_table() -> str:
    """The README's config reference, one row per key."""
    rows = ["| key | allowed | default | meaning |", "|---|---|---|---|"]
    for section, ks in SECTIONS.items():
        for k in ks:
            dflt = k.default_text
            if isinstance(k.default, str) and k.name.endswith("_kg_per_m3"):
                dflt = f"{default(section, k.name):g} ({k.default})"
            rows.append(f"| `{section}.{k.name}` | {k.allowed.replace('|', '&#124;')} | {dflt} "
                        f"| {k.doc} |")
    return "\n".join(rows)


README_START = "<!-- config-table: generated by `python -m springcad.config --readme README.md` -->"
README_END = "<!-- config-table end -->"


def readme_with_table(text: str) -> str:
    """README text with the generated table between the markers."""
    start, end = text.index(README_START) + len(README_START), text.index(README_END)
    return text[:start] + "\n" + markdown_table() + "\n" + text[end:]
