"""Mutated job configs and bench CSVs: the families of issue 11, shared by the fuzz driver
(``bench/fuzz_cli.py``) and the property-based tests (``tests/test_fuzz_properties.py``).

Every generator takes a :class:`random.Random`, so a seeded driver and a hypothesis
strategy (``st.randoms(use_true_random=False)``) replay the same cases.
"""

from __future__ import annotations

import json
import math
import random
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: job configs only (the requirement files of `synthesize` and the title block are other formats)
TEMPLATES = sorted(p for p in (ROOT / "templates").glob("*.toml")
                   if "[springs." in p.read_text())

#: every numeric key a config can hold, by section (springs use the "S" placeholder)
NUMERIC_KEYS = {
    "material": ["youngs_modulus_GPa", "poisson_ratio", "yield_strength_MPa", "density_kg_per_m3",
                 "design_stress_MPa", "safety_factor"],
    "springs": ["target_stiffness_Nm_per_rad", "max_deflection_deg", "max_deflection_rad",
                "outer_radius_mm", "thickness_mm", "contact_radius_mm", "min_tip_radius_mm",
                "tip_radius_mm", "n_flexures", "root_radius_mm"],
    "manufacturing": ["t_spring_mm", "t_shaft_mm", "w_gap_mm", "wire_diameter_mm", "spark_gap_mm",
                      "min_slot_width_mm", "min_web_mm", "min_hole_edge_mm"],
    "hardware": ["fastener_diameter_mm", "fastener_count", "shaft_diameter_mm",
                 "rim_spacer_thickness_mm", "bushing_wall_mm", "camshaft_hub_length_mm",
                 "rim_spacer_density_kg_per_m3", "plastic_density_kg_per_m3"],
    "analysis": ["monte_carlo_samples", "seed"],
}
HUGE_INT = int("9" * 400)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def _key(k: str) -> str:
    return k if k and all(c.isalnum() and c.isascii() or c in "_-" for c in k) else json.dumps(k)


def toml_dumps(data: dict) -> str:
    """Tables of tables (two levels, as job configs are) and inline values below."""
    top, lines = [], []
    for k, v in data.items():
        if isinstance(v, dict) and v and all(isinstance(x, dict) for x in v.values()) and k == "springs":
            for name, t in v.items():
                lines.append(f"\n[{_key(k)}.{_key(name)}]")
                lines += [f"{_key(a)} = {_value(b)}" for a, b in t.items()]
        elif isinstance(v, dict):
            lines.append(f"\n[{_key(k)}]")
            lines += [f"{_key(a)} = {_value(b)}" for a, b in v.items()]
        else:
            top.append(f"{_key(k)} = {_value(v)}")
    return "\n".join(top + lines) + "\n"


def bad_values(rng: random.Random, current):
    """Mutations of one value: every class the issue lists."""
    x = current if isinstance(current, (int, float)) and not isinstance(current, bool) else 1.0
    if not (isinstance(x, float) or abs(x) < 1e15) or not math.isfinite(x) or abs(x) > 1e15:
        x = 1.0
    return rng.choice([
        0, -1, -x, 1e300, -1e300, 1e-300, 1e6, 1e-6, x * 10, x * 100, x / 100, x * 1.5, x * 0.7,
        float("inf"), float("nan"), "12", "abc", True, [1, 2], {"a": 1}, HUGE_INT, 2 ** 63 - 1,
        int(1e9), 0.001, 50, 1000, 2, 3, 0.5, 5.0, 20.0, x + 0.3])


def _schema_bounds() -> dict[str, dict[str, tuple]]:
    """(lo, hi, kind) of every numeric key, by section, from the config schema."""
    from springcad.config.schema import SECTIONS

    out = {sec.split(".")[0]: {k.name: (k.lo, k.hi, k.kind) for k in keys
                               if k.kind in ("float", "int")}
           for sec, keys in SECTIONS.items()}
    return {sec: ks for sec, ks in out.items() if ks}


#: values the issue names, by (section, key)
ISSUE_VALUES = [
    ("springs", "max_deflection_deg", 1e-6), ("manufacturing", "min_slot_width_mm", 50),
    ("hardware", "shaft_diameter_mm", 0.001), ("analysis", "monte_carlo_samples", int(1e9)),
    ("analysis", "monte_carlo_samples", 2 ** 63 - 1), ("hardware", "fastener_diameter_mm", 50),
    ("hardware", "fastener_count", 1000), ("springs", "target_stiffness_Nm_per_rad", 1e-6),
    ("springs", "outer_radius_mm", 1e6), ("hardware", "rim_spacer_thickness_mm", 1e6),
    ("springs", "min_tip_radius_mm", 2.0), ("analysis", "monte_carlo_samples", 1),
    ("analysis", "monte_carlo_samples", 2), ("hardware", "fastener_diameter_mm", 12.0),
    ("hardware", "fastener_count", 199), ("springs", "target_stiffness_Nm_per_rad", 0.001),
    ("springs", "target_stiffness_Nm_per_rad", 1e5), ("hardware", "rim_spacer_thickness_mm", 20.0),
    ("manufacturing", "min_web_mm", 0.02), ("manufacturing", "wire_diameter_mm", 0.5),
    ("springs", "thickness_mm", 0.2), ("springs", "thickness_mm", 100.0),
]


def _mutate_physics(rng: random.Random, fam: str, data: dict, springs: list[str]) -> dict:
    """Numbers that are legal one by one or that the issue names: every length at once
    (1e300, tiny), every key at a bound of its range, the issue's values, rad vs deg."""
    bounds = _schema_bounds()

    def table(sec):
        if sec == "springs":
            return data["springs"][rng.choice(springs)]
        return data.setdefault(sec, {})

    if fam == "every_length":
        v = rng.choice([1e300, 1e-300, 1e6, 1e-6, 0.001, 0.01, -1.0, 0.0, "hi", "lo"])
        for sec, ks in bounds.items():
            for t in ([data["springs"][s] for s in springs] if sec == "springs" else [table(sec)]):
                for k, (lo, hi, _) in ks.items():
                    if k.endswith("_mm") and (k in t or rng.random() < 0.3):
                        t[k] = hi if v == "hi" else lo if v == "lo" else v
    elif fam == "bounds":  # in range: the corners of the accepted space
        for _ in range(rng.randint(1, 4)):
            sec = rng.choice(list(bounds))
            k, (lo, hi, kind) = rng.choice(list(bounds[sec].items()))
            if k.startswith("max_deflection"):
                continue
            t = table(sec)
            x = rng.choice([lo, hi, lo * 1.01 + 1e-9, hi * 0.99])
            t[k] = int(round(x)) if kind == "int" else float(x)
    elif fam == "issue":
        for _ in range(rng.randint(1, 2)):
            sec, k, v = rng.choice(ISSUE_VALUES)
            t = table(sec)
            if k == "max_deflection_deg":
                t.pop("max_deflection_rad", None)
            t[k] = v
    else:  # rad written as deg and deg as rad
        t = table("springs")
        deg = t.pop("max_deflection_deg", None)
        rad = t.pop("max_deflection_rad", None)
        if deg is not None:
            t[rng.choice(["max_deflection_rad", "max_deflection_deg"])] = \
                rng.choice([deg, math.radians(deg)])
        else:
            t[rng.choice(["max_deflection_rad", "max_deflection_deg"])] = \
                rng.choice([rad, math.degrees(rad)])
        if rng.random() < 0.3:
            t["max_deflection_deg"], t["max_deflection_rad"] = 16.0, 0.28
    return data


def mutate_config(rng: random.Random, templates=None) -> tuple[str, bytes]:
    """One mutated config: (family, bytes)."""
    base = rng.choice(templates or TEMPLATES)
    text = base.read_text()
    data = tomllib.loads(text)
    springs = list(data.get("springs", {}))
    fam = rng.choices(["value", "value_new_key", "section", "names", "encoding", "structure",
                       "stack", "unknown", "multi", "every_length", "bounds", "issue", "rad_deg"],
                      [30, 20, 6, 8, 5, 5, 6, 4, 16, 6, 12, 8, 4])[0]
    if fam in ("every_length", "bounds", "issue", "rad_deg"):
        return fam, toml_dumps(_mutate_physics(rng, fam, data, springs)).encode()
    if fam in ("value", "value_new_key", "multi"):
        for _ in range(1 if fam != "multi" else rng.randint(2, 4)):
            sec = rng.choice(list(NUMERIC_KEYS))
            key = rng.choice(NUMERIC_KEYS[sec])
            table = (data.setdefault("springs", {}).setdefault(rng.choice(springs), {})
                     if sec == "springs" else data.setdefault(sec, {}))
            if sec == "springs" and key.startswith("max_deflection"):
                table.pop("max_deflection_deg", None), table.pop("max_deflection_rad", None)
            if fam == "value" and key not in table:
                present = [k for k in table if k in NUMERIC_KEYS[sec]]
                key = rng.choice(present) if present else key
            table[key] = bad_values(rng, table.get(key))
        return fam, toml_dumps(data).encode()
    if fam == "section":
        sec = rng.choice(["job", "material", "springs", "stack", "manufacturing", "hardware",
                          "analysis"])
        data[sec] = rng.choice(["x", 5, [1, 2], True, 1.5, {}])
        if sec == "springs" and rng.random() < 0.5:
            data[sec] = {springs[0]: rng.choice(["x", 5, [1, 2]])}
        return fam, toml_dumps(data).encode()
    if fam == "names":
        choice = rng.randrange(8)
        if choice == 0:
            data.setdefault("job", {})["name"] = rng.choice(
                [[1, 2], 5, True, {"a": 1}, "", "é-ünï", "a/b", "x" * 400, "CON", "a\nb", " ", "../up"])
        elif choice == 1:
            data.setdefault("job", {})["description"] = rng.choice(
                [[1, 2], 5, 1.5, "ü" * 10, "x" * 5000, "line\nbreak", "\x00"])
        elif choice in (2, 3):  # rename a spring
            new = rng.choice(["Sé", "S 1", "S/1", "", "ß", "S.1", "x" * 200, "1", "S-1", "s_1",
                              "Ω", "S\t1", "CON"])
            old = springs[0]
            data["springs"][new] = data["springs"].pop(old)
            if "stack" in data:
                data["stack"]["sequence"] = [new if s == old else s for s in data["stack"]["sequence"]]
        elif choice == 4:
            data.setdefault("material", {})["name"] = rng.choice([[1, 2], 5, "", "420_HT", "stéel"])
        elif choice == 5:
            data.setdefault("material", {})["heat_treatment"] = rng.choice([[1], 5, "ü", "x" * 3000])
        elif choice == 6:
            data.setdefault("springs", {})[springs[0]]["flexure"] = rng.choice([1, ["auto"], "curvy"])
        else:
            data.setdefault("manufacturing", {})["process"] = rng.choice([1, "laser", ["wire_edm"]])
        return fam, toml_dumps(data).encode()
    if fam == "encoding":
        raw = text.encode()
        choice = rng.randrange(5)
        if choice == 0:
            return fam, b"# caf\xe9 latin-1 comment\n" + raw
        if choice == 1:
            return fam, text.encode("utf-16")
        if choice == 2:
            i = rng.randrange(len(raw))
            return fam, raw[:i] + bytes([rng.choice([0xff, 0xfe, 0xc3, 0x80, 0x00])]) + raw[i:]
        if choice == 3:
            return fam, b"\xef\xbb\xbf" + raw
        return fam, raw.replace(b'name = "', b'name = "\xe9', 1)
    if fam == "structure":
        choice = rng.randrange(6)
        if choice == 0:
            return fam, (text + "\n[" + ".".join(["a"] * 1000) + "]\nx = 1\n").encode()
        if choice == 1:
            return fam, (text + "\nx = " + "[" * 1000 + "]" * 1000 + "\n").encode()
        if choice == 2:
            return fam, (text + "\nx = " + "{a = " * 1000 + "1" + "}" * 1000 + "\n").encode()
        if choice == 3:
            return fam, text[: rng.randrange(len(text))].encode()
        if choice == 4:
            return fam, b""
        return fam, bytes(rng.randrange(256) for _ in range(200))
    if fam == "stack":
        st = data.setdefault("stack", {"sequence": [springs[0]]})
        choice = rng.randrange(6)
        if choice == 0:
            st["sequence"] = [springs[0]] * rng.choice([9, 50, 1000])
        elif choice == 1:
            st["sequence"] = rng.choice([springs[0], [1, 2], [[springs[0]]], [], 5])
        elif choice == 2:
            st["input"] = rng.choice(["belt", 1, ["shaft"]])
        elif choice == 3:
            st["output"] = rng.choice(["rim", "shaft", 2])
        elif choice == 4:
            del data["stack"]
            data["springs"]["extra"] = dict(next(iter(data["springs"].values())))
        else:
            st["sequence"] = [springs[0], "nope"]
        return fam, toml_dumps(data).encode()
    # unknown keys
    sec = rng.choice(["job", "material", "stack", "manufacturing", "hardware", "analysis", "top"])
    key = rng.choice(["outer_radius_in", "foo", "centre_spacer_thickness_mm",
                      "centre_spacer_clearance_mm", "seed_", "Name"])
    if sec == "top":
        data[key] = 1
    else:
        data.setdefault(sec, {})[key] = 1.0
    return fam, toml_dumps(data).encode()


def mutate_csv(rng: random.Random, clean: str) -> tuple[str, bytes]:
    """One mutated bench CSV from a clean simulated record: (family, bytes)."""
    lines = clean.splitlines()
    header_i = next(i for i, l in enumerate(lines) if l and not l.startswith("#"))
    header = lines[header_i].split(",")
    body = lines[header_i + 1:]
    ti = header.index("torque_Nm")

    def scale(f):
        out = []
        for l in body:
            cells = l.split(",")
            cells[ti] = repr(f(float(cells[ti])))
            out.append(",".join(cells))
        return "\n".join(lines[:header_i + 1] + out) + "\n"

    fam = rng.choice(["negate", "scale_big", "scale_small", "latin1", "nan", "truncate",
                      "missing_col", "junk_cell", "few_rows", "constant", "utf16", "decreasing_time",
                      "inf", "empty", "dup_header", "semicolon", "latin1_cell", "deg_column",
                      "scale_rows", "offset", "huge_cell", "swap_columns"])
    di = header.index("deflection_rad")

    def column(i, f):
        out = []
        for l in body:
            cells = l.split(",")
            cells[i] = repr(f(float(cells[i])))
            out.append(",".join(cells))
        return "\n".join(lines[:header_i + 1] + out) + "\n"

    if fam == "latin1_cell":  # one Latin-1 byte inside the data
        raw = clean.encode()
        i = raw.index(b"\n", rng.randrange(len(raw) // 2, len(raw) - 2))
        return fam, raw[:i] + b" \xb0" + raw[i:]
    if fam == "deg_column":  # deflection written in degrees under the rad header
        return fam, column(di, math.degrees).encode()
    if fam == "scale_rows":
        f = rng.choice([1e300, 1e-300, -1e300, 1e20])
        return fam, column(ti, lambda t: t * f if rng.random() < 0.05 else t).encode()
    if fam == "offset":
        c = rng.choice([1e6, -1e6, 1e300])
        return fam, column(rng.choice([ti, di]), lambda t: t + c).encode()
    if fam == "huge_cell":
        i = rng.randrange(len(body))
        cells = body[i].split(",")
        cells[rng.choice([ti, di])] = rng.choice(["9" * 400, "1e999", "-1e400", "0x10", "1_0"])
        body[i] = ",".join(cells)
        return fam, ("\n".join(lines[:header_i + 1] + body) + "\n").encode()
    if fam == "swap_columns":
        hdr = lines[header_i].replace("torque_Nm", "TMP").replace("deflection_rad", "torque_Nm")
        return fam, ("\n".join(lines[:header_i] + [hdr.replace("TMP", "deflection_rad")] + body)
                     + "\n").encode()
    if fam == "negate":
        return fam, scale(lambda t: -t).encode()
    if fam == "scale_big":
        return fam, scale(lambda t: t * rng.choice([1e300, 1e30, 1e10])).encode()
    if fam == "scale_small":
        return fam, scale(lambda t: t * rng.choice([1e-300, 1e-30, 1e-12])).encode()
    if fam == "latin1":
        return fam, b"# caf\xe9\n" + clean.encode()
    if fam == "nan":
        i = rng.randrange(len(body))
        cells = body[i].split(",")
        cells[ti] = "nan"
        body[i] = ",".join(cells)
        return fam, "\n".join(lines[:header_i + 1] + body).encode()
    if fam == "truncate":
        return fam, clean[: rng.randrange(len(clean))].encode()
    if fam == "missing_col":
        return fam, clean.replace("torque_Nm", "torque_x", 1).encode()
    if fam == "junk_cell":
        i = rng.randrange(len(body))
        body[i] = body[i] + ",extra"
        return fam, "\n".join(lines[:header_i + 1] + body).encode()
    if fam == "few_rows":
        return fam, "\n".join(lines[:header_i + 1] + body[:rng.choice([0, 1, 3, 150])]).encode()
    if fam == "constant":
        return fam, scale(lambda t: 1.0).encode()
    if fam == "utf16":
        return fam, clean.encode("utf-16")
    if fam == "decreasing_time":
        return fam, "\n".join(lines[:header_i + 1] + body[::-1]).encode()
    if fam == "inf":
        return fam, scale(lambda t: float("inf") if rng.random() < 0.01 else t).encode()
    if fam == "empty":
        return fam, b""
    if fam == "dup_header":
        return fam, "\n".join(lines[:header_i + 1] + [lines[header_i]] + body).encode()
    return fam, clean.replace(",", ";").encode()
