"""The changes a springcad refusal proposes, read from its message and applied to a copy of
the config exactly as printed (bench/spec_heldout.py applies the first one and runs it).

springcad writes a change as ``key = value (now old)`` with dotted keys
(``springs.A.thickness_mm = 6.6 (now 6)``, ``material.name = "maraging_300" with
material.design_stress_MPa = 1300``, ``hardware.fastener_count = 7 (now 6; ...)``), a freed
layout key as ``springs.A.n_flexures removed (now 39; springcad then chooses 51)``, a
change of disk count as ``'A' 1 times in stack.sequence where it is 3 times, each
springs.A.target_stiffness_Nm_per_rad = 323.3, max_deflection_deg = 18`` or ``2 disks in
series in its place (each springs.A.target_stiffness_Nm_per_rad = 1920, max_deflection_deg =
14.5, and each 'A' in stack.sequence written 2 times)``, and several keys at once as
``... = 7.6 (now 5.5) and ... = 38.5 (now 28) and springs.A.n_flexures removed (now 8), ...,
all together``. Alternatives are separated by a top-level ``or`` (outside parentheses);
clauses by ``;`` and sentence ends. A clause "with X it is feasible with Y or Z" gives X to
each of Y and Z.

Only what the message writes is applied: no value is guessed, a key springcad prints under
its current name (``target_stiffness_Nm_per_rad``) replaces the config's deprecated one
(``stiffness_Nm_per_rad``). When no clause of this strict form is found, the loose reading
of earlier harness versions (``raise thickness_mm to 9.07``, suggestion clauses only) is
used and said (``parser = "loose"``).
"""

from __future__ import annotations

import json
import re

#: spring keys a change may name (schema names; the deprecated one is mapped below)
SPRING_KEYS = ("target_stiffness_Nm_per_rad", "stiffness_Nm_per_rad", "max_deflection_deg",
               "max_deflection_rad", "outer_radius_mm", "thickness_mm", "contact_radius_mm",
               "min_tip_radius_mm", "tip_radius_mm", "n_flexures", "root_radius_mm",
               "flexure", "max_thickness_mm")
#: other keys and their section
OTHER_KEYS = {"name": "material", "design_stress_MPa": "material", "safety_factor": "material",
              "fastener": "hardware", "fastener_diameter_mm": "hardware",
              "fastener_count": "hardware", "shaft_diameter_mm": "hardware",
              "rim_spacer_thickness_mm": "hardware", "min_slot_width_mm": "manufacturing",
              "min_web_mm": "manufacturing", "min_hole_edge_mm": "manufacturing",
              "w_gap_mm": "manufacturing", "t_spring_mm": "manufacturing",
              "t_shaft_mm": "manufacturing", "surface": "manufacturing"}
INT_KEYS = ("n_flexures", "fastener_count")
#: the config's old key name -> the name springcad prints
RENAMED = {"stiffness_Nm_per_rad": "target_stiffness_Nm_per_rad"}
#: schema defaults of keys a config may leave out (a "change" to the default is none)
DEFAULTS = {"min_tip_radius_mm": 0.3, "fastener_diameter_mm": 1.5, "fastener_count": 7,
            "shaft_diameter_mm": 4.0, "min_slot_width_mm": 0.35, "min_web_mm": 0.4,
            "min_hole_edge_mm": 0.4, "w_gap_mm": 0.04, "t_spring_mm": 0.01,
            "t_shaft_mm": 0.01}

_ALL_KEYS = "|".join(sorted(set(SPRING_KEYS) | set(OTHER_KEYS), key=len, reverse=True))
_VALUE = r'(?P<val>"[^"]*"|-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)'
#: ``springs.A.thickness_mm = 6.6``, ``material.name = "x"``, ``max_deflection_deg = 18``
_SET = re.compile(r"(?<![\w.])(?:(?P<sec>springs\.(?P<spring>[A-Za-z0-9_-]+)|material|hardware|"
                  r"manufacturing)\.)?(?P<key>" + _ALL_KEYS + r")\s*=\s*" + _VALUE)
_REMOVED = re.compile(r"springs\.(?P<spring>[A-Za-z0-9_-]+)\.(?P<key>\w+) removed\b")
_FEWER = re.compile(r"'(?P<spring>[^']+)' (?P<k>\d+) times in stack\.sequence where it is "
                    r"(?P<n>\d+) times")
_SERIES = re.compile(r"each '(?P<spring>[^']+)' in stack\.sequence written (?P<m>\d+) times")


def _split_top(text: str, seps: re.Pattern) -> list[str]:
    """``text`` cut at every match of ``seps`` outside parentheses and quotes."""
    out, depth, start, i = [], 0, 0, 0
    quoted = False
    while i < len(text):
        c = text[i]
        if c == '"':
            quoted = not quoted
        elif not quoted and c == "(":
            depth += 1
        elif not quoted and c == ")":
            depth = max(0, depth - 1)
        elif depth == 0 and not quoted:
            m = seps.match(text, i)
            if m:
                out.append(text[start:i])
                start = i = m.end()
                continue
        i += 1
    out.append(text[start:])
    return out


_CLAUSE_SEP = re.compile(r";|\.\s+(?=[A-Z])|\n")
_OR = re.compile(r"\s+or\s+")


def _ops(text: str, default_spring: str | None) -> list[tuple]:
    """The operations written in one alternative, in order: ("set", sec, spring, key, value),
    ("remove", "springs", spring, key, None), ("fewer", spring, k, n), ("series", spring, m).
    Values inside ``(now ...)`` are the config's own and are not read (no ``=`` there)."""
    found = []
    spring = default_spring
    for m in _SET.finditer(text):
        key, raw = m["key"], m["val"]
        val = raw[1:-1] if raw.startswith('"') else float(raw)
        if key in INT_KEYS and not isinstance(val, str):
            val = int(round(val))
        if m["spring"]:
            spring = m["spring"]
        if key in SPRING_KEYS and (m["sec"] is None or m["spring"]):
            found.append((m.start(), ("set", "springs", m["spring"] or spring, key, val)))
        elif key in OTHER_KEYS and (m["sec"] is None or m["sec"] == OTHER_KEYS[key]):
            found.append((m.start(), ("set", OTHER_KEYS[key], None, key, val)))
    found += [(m.start(), ("remove", "springs", m["spring"], m["key"], None))
              for m in _REMOVED.finditer(text)]
    found += [(m.start(), ("fewer", m["spring"], int(m["k"]), int(m["n"])))
              for m in _FEWER.finditer(text)]
    found += [(m.start(), ("series", m["spring"], int(m["m"])))
              for m in _SERIES.finditer(text)]
    return [op for _, op in sorted(found, key=lambda t: t[0])]


def current(cfg: dict, sec: str, spring: str | None, key: str):
    """The config's value of a key (the schema default when left out)."""
    if sec == "springs":
        sp = cfg["springs"].get(spring, {})
        old = [o for o, new in RENAMED.items() if new == key]
        return sp.get(key, sp.get(old[0]) if old else DEFAULTS.get(key))
    return cfg.get(sec, {}).get(key, DEFAULTS.get(key))


def _is_change(cfg: dict, op: tuple) -> bool:
    if op[0] == "set":
        _, sec, spring, key, val = op
        return sec != "springs" or spring in cfg["springs"] \
            and current(cfg, sec, spring, key) != val
    if op[0] == "remove":
        return op[2] in cfg["springs"] and op[3] in cfg["springs"][op[2]]
    return op[1] in cfg["springs"]


def parse_strict(text: str, cfg: dict) -> list[list[tuple]]:
    """Every alternative change of the ``key = value`` form, first written first."""
    named = [n for n in re.findall(r"spring '([^']+)'", text) if n in cfg["springs"]]
    default = named[0] if named else (next(iter(cfg["springs"])) if len(cfg["springs"]) == 1
                                      else None)
    alts: list[list[tuple]] = []
    for clause in _split_top(text, _CLAUSE_SEP):
        common: list[tuple] = []
        for j, alt in enumerate(_split_top(clause, _OR)):
            at = alt.find("feasible with")
            if j == 0 and at > 0:     # "with X it is feasible with Y or Z": X goes with each
                common = _ops(alt[:at], default)
                alt = alt[at:]
            ops = _ops(alt, default)
            if not ops:
                continue
            ops = common + ops
            if any(_is_change(cfg, op) for op in ops) and ops not in alts:
                alts.append(ops)
    return alts


def apply_ops(cfg: dict, ops: list[tuple], tag: str) -> dict:
    """A copy of ``cfg`` with the operations applied, its job name tagged."""
    new = json.loads(json.dumps(cfg))
    for op in ops:
        if op[0] == "set":
            _, sec, spring, key, val = op
            if sec == "springs":
                sp = new["springs"][spring]
                for old, now in RENAMED.items():
                    if key == now:
                        sp.pop(old, None)
                if key.startswith("max_deflection_"):
                    sp.pop("max_deflection_rad" if key.endswith("deg") else
                           "max_deflection_deg", None)
                sp[key] = val
            else:
                new.setdefault(sec, {})[key] = val
        elif op[0] == "remove":
            new["springs"][op[2]].pop(op[3], None)
        else:
            stack = new.setdefault("stack", {})
            seq = list(stack.get("sequence", list(new["springs"])))
            if op[0] == "fewer":        # keep the first k of the spring's n copies
                _, name, k, n = op
                seen, out = 0, []
                for s in seq:
                    seen += s == name
                    if s != name or seen <= k:
                        out.append(s)
                seq = out
            else:                       # each copy written m times
                _, name, m = op
                seq = [x for s in seq for x in ([s] * m if s == name else [s])]
            stack["sequence"] = seq
    new.setdefault("job", {})["name"] = (new["job"].get("name", "spec") + tag)[:64]
    return new


def describe(ops: list[tuple]) -> str:
    """One line naming the operations, e.g. ``springs.A.thickness_mm=6.6; stack: 'A' x1``."""
    out = []
    for op in ops:
        if op[0] == "set":
            _, sec, spring, key, val = op
            out.append(f"{sec}.{spring + '.' if spring else ''}{key}={val}")
        elif op[0] == "remove":
            out.append(f"springs.{op[2]}.{op[3]} removed")
        elif op[0] == "fewer":
            out.append(f"'{op[1]}' {op[2]} times in stack.sequence (was {op[3]})")
        else:
            out.append(f"each '{op[1]}' in stack.sequence {op[2]} times")
    return "; ".join(out)


# -------------------------------------------------------------------- the loose reading
_LOOSE_KEY = re.compile(r"(?:springs\.(?P<spring>[A-Za-z0-9_-]+)\.)?(?:(?:material|hardware|"
                        r"manufacturing)\.)?(?P<key>" + _ALL_KEYS + r")\b\s*(?:=|:|to|>=|<=|"
                        r"≥|≤|of|at least|at most|below|above|about|~)?\s*"
                        r"(?P<val>-?\d+(?:\.\d+)?)")
_SUGGEST = re.compile(r"\b(use|raise|lower|increase|reduce|decrease|enlarge|allow|give|put|"
                      r"try|fix|feasible with|change|set|choose|add|remove|drop|widen|"
                      r"thicken|shorten)\b", re.I)


def parse_loose(text: str, cfg: dict) -> list[list[tuple]]:
    """Suggestion clauses naming a key and a number (``raise thickness_mm to 9.07``): the
    reading of earlier harness versions, for messages without a ``key = value`` change."""
    named = [n for n in re.findall(r"spring '([^']+)'", text) if n in cfg["springs"]]
    alts: list[list[tuple]] = []
    for clause in re.split(r";|(?<=\D)\.\s|\n", text):
        if not _SUGGEST.search(clause):
            continue
        last_end = None
        for m in _LOOSE_KEY.finditer(clause):
            key, val = m["key"], float(m["val"])
            val = int(round(val)) if key in INT_KEYS else val
            if key in SPRING_KEYS:
                names = [m["spring"]] if m["spring"] in cfg["springs"] \
                    else (named[:1] or list(cfg["springs"]))
                ops = [("set", "springs", n, key, val) for n in names]
            elif key in OTHER_KEYS:
                ops = [("set", OTHER_KEYS[key], None, key, val)]
            else:
                continue
            ops = [op for op in ops if _is_change(cfg, op)]
            if not ops:
                continue
            if last_end is None or re.search(r"\bor\b", clause[last_end:m.start()]) \
                    or not alts:
                alts.append(ops)
            else:
                alts[-1].extend(ops)
            last_end = m.end()
    return alts


def parse_fixes(text: str, cfg: dict) -> tuple[list[list[tuple]], str]:
    """The alternatives a refusal names, first written first, and a note: "strict",
    "loose" (the loose reading was needed) or why none was found."""
    alts = parse_strict(text, cfg)
    if alts:
        return alts, "strict"
    alts = parse_loose(text, cfg)
    if alts:
        return alts, "loose"
    numbers = re.search(r"(?<![A-Za-z_'])\d+(?:\.\d+)?", text)
    return [], ("names numbers, but no config key with a new value I could parse" if numbers
                else "no change in numbers named")
